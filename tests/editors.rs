//! Maps written by other editors and other traffic_editor versions (`fixtures/editors/`):
//! each must be read without errors or warnings, and its nav graphs must hold the values the
//! file means (numbers worked out by hand from the file, not taken from mapc).

use saphyr::{LoadableYamlNode, YamlOwned};
use std::path::{Path, PathBuf};
use std::process::Command;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/editors")
        .join(format!("{name}.building.yaml"))
}

/// Runs `mapc nav` on the fixture: no diagnostic at all, and the graph files it wrote.
fn nav(name: &str) -> Vec<(String, YamlOwned)> {
    let out = tempfile::tempdir().unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .arg("nav")
        .arg(fixture(name))
        .arg(out.path())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{name}: {stderr}");
    assert!(
        !stderr.contains("warning[") && !stderr.contains("error["),
        "{name}: {stderr}"
    );
    // The graphs only, not the output manifest (`.mapc-manifest-nav-<map>`).
    let mut files: Vec<(String, YamlOwned)> = std::fs::read_dir(out.path())
        .unwrap()
        .filter(|e| {
            let e = e.as_ref().unwrap();
            !e.file_name().to_string_lossy().starts_with('.')
        })
        .map(|e| {
            let p = e.unwrap().path();
            let text = std::fs::read_to_string(&p).unwrap();
            let doc = YamlOwned::load_from_str(&text).unwrap().remove(0);
            (p.file_name().unwrap().to_string_lossy().into_owned(), doc)
        })
        .collect();
    files.sort_by(|a, b| a.0.cmp(&b.0));
    files
}

/// `(x, y, name)` of every vertex of `level` in a nav graph document.
fn vertices(doc: &YamlOwned, level: &str) -> Vec<(f64, f64, String)> {
    let level = &doc["levels"][level];
    level["vertices"]
        .as_vec()
        .unwrap()
        .iter()
        .map(|v| {
            let num = |y: &YamlOwned| y.as_floating_point().unwrap();
            let name = v[2]["name"].as_str().unwrap_or("").to_string();
            (num(&v[0]), num(&v[1]), name)
        })
        .collect()
}

#[test]
fn traffic_editor_js_string_graph_keys() {
    // `graphs: {'0': ..., '1': ...}`: both fleets' lanes are written.
    let files = nav("traffic_editor_js");
    let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
    assert_eq!(names, ["0.yaml", "1.yaml"]);
    let v = vertices(&files[1].1, "L1");
    assert_eq!(
        v,
        [(2.0, 2.0, "dock_a".into()), (18.0, 8.0, "store".into())]
    );
    // The library reads the same graph table the file declares.
    let parsed = mapc_frontend::load(&fixture("traffic_editor_js")).unwrap();
    let b = parsed.building.unwrap();
    let graphs: Vec<(i64, &str, f64)> = b
        .graphs
        .iter()
        .map(|g| (g.index, g.name.as_str(), g.default_lane_width))
        .collect();
    assert_eq!(graphs, [(0, "cleaners", 1.0), (1, "carts", 0.5)]);
}

#[test]
fn rmf_site_legacy_export() {
    // Block-style nested sequences, full vertex parameters, lift `lowest_floor` etc.
    let files = nav("rmf_site_legacy");
    assert_eq!(files.len(), 1);
    let doc = &files[0].1;
    assert_eq!(
        vertices(doc, "L1"),
        [
            (2.0, 2.0, "charger_1".into()),
            (6.0, 4.0, "hall".into()),
            (10.0, 4.0, "lift_L1".into())
        ]
    );
    assert_eq!(
        doc["levels"]["L1"]["vertices"][0][2]["is_charger"].as_bool(),
        Some(true)
    );
    assert_eq!(
        doc["levels"]["L1"]["vertices"][2][2]["lift"].as_str(),
        Some("lift_a")
    );
    assert_eq!(vertices(doc, "L2")[1], (4.0, 4.0, "office".into()));
    assert_eq!(
        doc["lifts"]["lift_a"]["dims"][0].as_floating_point(),
        Some(2.0)
    );

    // Its block-style model (with `static` and `z`) and spawn reach the world.
    let out = tempfile::tempdir().unwrap();
    let world = out.path().join("w.world");
    let run = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .arg("gazebo")
        .arg(fixture("rmf_site_legacy"))
        .arg(&world)
        .arg(out.path().join("models"))
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = std::fs::read_to_string(&world).unwrap();
    assert!(
        text.contains("<name>chair_1</name>\n      <uri>model://OfficeChairBlack</uri>\n      <pose>4.0 6.0 0.0 0 0 1.5707963267948966</pose>\n      <static>true</static>"),
        "{text}"
    );
    assert!(text.contains("<name>bot_1</name>"), "{text}");
}

#[test]
fn traffic_editor_2021_layers_features_integer_level_names() {
    // Scale from the measurement: 20 m over 400 px = 0.05 m/px, y flipped; level `2` is
    // aligned to level `1` by its two fiducials, which sit on the same pixels.
    let files = nav("traffic_editor_2021");
    let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
    assert_eq!(names, ["0.yaml", "1.yaml"]);
    assert_eq!(
        vertices(&files[0].1, "1"),
        [
            (7.5, -7.5, "entrance".into()),
            (15.0, -10.0, "junction".into()),
            (22.5, -12.5, "bay".into())
        ]
    );
    assert_eq!(
        vertices(&files[1].1, "2"),
        [
            (7.5, -7.5, "upper_stairs".into()),
            (22.5, -12.5, "upper_bay".into())
        ]
    );
}
