//! rmf_site `.site.json`: the frontend, `mapc convert` both ways, and rmf_site_format 0.0.2
//! (rmf_site's own format crate) as the oracle: it reads every site mapc writes, and its
//! `NavGraph::from_site` agrees with mapc's nav graphs by meaning on maps without lifts.

mod support;

use mapc_ir::{Handle, Vertex};
use rmf_site_format::legacy::building_map::BuildingMap;
use rmf_site_format::legacy::nav_graph::NavGraph;
use rmf_site_format::Site;
use serde_json::Value;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn mapc(args: &[&str]) -> support::Run {
    support::run(args, Duration::from_secs(120))
}

fn ok(args: &[&str]) {
    let r = mapc(args);
    assert_eq!(
        r.code,
        0,
        "mapc {args:?}:\n{}",
        String::from_utf8_lossy(&r.stderr)
    );
}

fn demo_maps() -> Option<Vec<(String, PathBuf)>> {
    let dir = Path::new(ROOT).join("../shared/maps");
    if !dir.is_dir() {
        println!("skipped: ../shared not found");
        return None;
    }
    let mut v: Vec<(String, PathBuf)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| {
            let d = e.unwrap().path();
            let n = d.file_name().unwrap().to_string_lossy().into_owned();
            (n.clone(), d.join(format!("{n}.building.yaml")))
        })
        .collect();
    v.sort();
    Some(v)
}

fn nav_dir(map: &Path, out: &Path) -> Vec<(String, String)> {
    ok(&["nav", map.to_str().unwrap(), out.to_str().unwrap(), "-q"]);
    let mut files: Vec<(String, String)> = std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read_to_string(&p).unwrap(),
            )
        })
        .collect();
    files.sort();
    files
}

type Lane = ((i64, i64), (i64, i64), i64, String, String);
type Place = ((i64, i64), String, bool, bool, bool);

/// A nav graph document (mapc's YAML or rmf_site's, as JSON values) by meaning, per level:
/// directed lanes between positions with speed limit, dock and orientation, and the named
/// places with their roles. Door names are left out: rmf_site's crossing test differs at
/// the door ends (it skips near-parallel segments) and mapc's is checked on its own.
/// mapc's documents are in the map frame and publish the `offset` rmf_site's site frame
/// is less; positions are compared in the site frame.
fn meaning(doc: &Value) -> Vec<(String, BTreeSet<Lane>, BTreeSet<Place>)> {
    meaning_off_lifts(doc, false)
}

/// `meaning`, leaving out (when `skip_lifts`) the lift waypoints and the lanes to them,
/// which rmf_site places differently (docs/sites.md).
fn meaning_off_lifts(
    doc: &Value,
    skip_lifts: bool,
) -> Vec<(String, BTreeSet<Lane>, BTreeSet<Place>)> {
    let off = |i: usize| doc["offset"][i].as_f64().unwrap_or(0.0);
    let (ox, oy) = (off(0), off(1));
    let mm = |v: &Value, o: f64| ((v.as_f64().unwrap() - o) * 1000.0).round() as i64;
    let mut out = Vec::new();
    for (level, l) in doc["levels"].as_object().unwrap() {
        let verts = l["vertices"].as_array().unwrap();
        let pos = |i: &Value| {
            let v = &verts[i.as_u64().unwrap() as usize];
            (mm(&v[0], ox), mm(&v[1], oy))
        };
        let text = |v: &Value, k: &str| v[k].as_str().unwrap_or("").to_string();
        let on_lift = |i: &Value| verts[i.as_u64().unwrap() as usize][2]["lift"].is_string();
        let lanes: BTreeSet<Lane> = l["lanes"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|lane| !skip_lifts || !(on_lift(&lane[0]) || on_lift(&lane[1])))
            .map(|lane| {
                let p = &lane[2];
                let speed = p["speed_limit"]
                    .as_f64()
                    .map_or(0, |s| (s * 1000.0).round() as i64);
                (
                    pos(&lane[0]),
                    pos(&lane[1]),
                    speed,
                    text(p, "dock_name"),
                    text(p, "orientation_constraint"),
                )
            })
            .collect();
        let flag = |p: &Value, k: &str| p[k].as_bool().unwrap_or(false);
        let places: BTreeSet<Place> = verts
            .iter()
            .filter(|v| !text(&v[2], "name").is_empty())
            .filter(|v| !skip_lifts || !v[2]["lift"].is_string())
            .map(|v| {
                let p = &v[2];
                (
                    (mm(&v[0], ox), mm(&v[1], oy)),
                    text(p, "name"),
                    flag(p, "is_charger"),
                    flag(p, "is_parking_spot"),
                    flag(p, "is_holding_point"),
                )
            })
            .collect();
        if !lanes.is_empty() {
            out.push((level.clone(), lanes, places));
        }
    }
    out
}

fn yaml_value(text: &str) -> Value {
    serde_yaml::from_str(text).unwrap()
}

/// rmf_site's nav graphs of `site` against mapc's nav files of `map_for_mapc` (named after
/// the graphs), by meaning.
fn assert_rmf_site_nav_equal(site: &Site, mapc_nav: &[(String, String)], what: &str) {
    let skip_lifts = !site.lifts.is_empty();
    let theirs = NavGraph::from_site(site);
    assert_eq!(theirs.len(), mapc_nav.len(), "{what}: number of graphs");
    for (name, graph) in theirs {
        let doc = serde_json::to_value(&graph).unwrap();
        let file = format!("{name}.yaml");
        let ours = &mapc_nav
            .iter()
            .find(|(f, _)| *f == file)
            .unwrap_or_else(|| panic!("{what}: mapc wrote no {file}"))
            .1;
        let (a, b) = (
            meaning_off_lifts(&doc, skip_lifts),
            meaning_off_lifts(&yaml_value(ours), skip_lifts),
        );
        assert_eq!(a, b, "{what}: graph {name}");
        assert!(!a.is_empty(), "{what}: graph {name} has lanes");
    }
}

/// `mapc gazebo` of `map` into `dir`: every file written (the world, the level models,
/// the crowd files), by path.
fn world(map: &Path, dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let w = dir.join("world.sdf");
    let m = dir.join("models");
    ok(&[
        "gazebo",
        map.to_str().unwrap(),
        w.to_str().unwrap(),
        m.to_str().unwrap(),
        "-q",
    ]);
    let mut files: Vec<(PathBuf, Vec<u8>)> = walk(dir)
        .into_iter()
        .filter(|p| {
            !p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with(".mapc")
        })
        .map(|p| {
            (
                p.strip_prefix(dir).unwrap().to_path_buf(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect();
    files.sort();
    assert!(files.iter().any(|(p, _)| p.ends_with("world.sdf")));
    files
}

/// Every demo map: `mapc convert` to a site that rmf_site_format reads with the same
/// levels, lifts and graphs; without lifts its nav graphs equal mapc's of the map; and
/// building -> site -> building gives the same nav files, world and level models, byte
/// for byte (a reference_image map comes back in its pixels, with its measurements).
#[test]
fn demo_maps_convert_both_ways() {
    let Some(maps) = demo_maps() else { return };
    assert_eq!(maps.len(), 7);
    let tmp = tempfile::tempdir().unwrap();
    let mut compared = 0;
    for (name, map) in &maps {
        let site_path = tmp.path().join(format!("{name}.site.json"));
        let back = tmp.path().join(format!("{name}.building.yaml"));
        ok(&[
            "convert",
            map.to_str().unwrap(),
            site_path.to_str().unwrap(),
            "-q",
        ]);
        ok(&[
            "convert",
            site_path.to_str().unwrap(),
            back.to_str().unwrap(),
            "-q",
        ]);

        let site = Site::from_bytes_json(&std::fs::read(&site_path).unwrap())
            .unwrap_or_else(|e| panic!("{name}: rmf_site_format cannot read it: {e}"));
        let parsed = mapc_frontend::load(map).unwrap();
        let b = parsed.building.unwrap();
        let levels: BTreeSet<String> = site
            .levels
            .values()
            .map(|l| l.properties.name.0.clone())
            .collect();
        let ours: BTreeSet<String> = b.levels.iter().map(|(_, l)| l.name.clone()).collect();
        assert_eq!(levels, ours, "{name}: levels");
        let lifts: BTreeSet<String> = site
            .lifts
            .values()
            .map(|l| l.properties.name.0.clone())
            .collect();
        let ours: BTreeSet<String> = b.lifts.iter().map(|(_, l)| l.name.clone()).collect();
        assert_eq!(lifts, ours, "{name}: lifts");
        let graphs: BTreeSet<String> = site
            .navigation
            .guided
            .graphs
            .values()
            .map(|g| g.name.0.clone())
            .collect();
        let ours: BTreeSet<String> = b.graph_indices().iter().map(|g| g.to_string()).collect();
        assert!(
            ours.is_subset(&graphs),
            "{name}: graphs {graphs:?} vs {ours:?}"
        );

        if b.coordinate_system == mapc_ir::CoordinateSystem::Wgs84 {
            // The geographic offset is the site origin (the map's offset): projected to the
            // map's CRS again, it lands within 2 m of it.
            let (lat, lon) = site
                .properties
                .geographic_offset
                .0
                .expect("geographic offset")
                .anchor;
            let code: u32 = b
                .crs_name
                .as_deref()
                .unwrap()
                .trim_start_matches("EPSG:")
                .parse()
                .unwrap();
            let mapc_frontend::crs::Lookup::Crs(crs) = mapc_frontend::crs::lookup(code) else {
                panic!("{name}: CRS");
            };
            let (e, n) = crs.project(lon as f64, lat as f64).unwrap();
            let d = (e - b.offset.x).hypot(n - b.offset.y);
            // rmf_site keeps f32 degrees: 0.85 m steps of longitude near 100°.
            assert!(
                d < 2.0,
                "{name}: geographic offset is {d} m from the map offset"
            );
            println!("{name}: geographic offset {d:.3} m from the map offset");
        }
        let original = nav_dir(map, &tmp.path().join(format!("{name}_nav_a")));
        let from_site = nav_dir(&site_path, &tmp.path().join(format!("{name}_nav_b")));
        let round = nav_dir(&back, &tmp.path().join(format!("{name}_nav_c")));
        assert_eq!(original, from_site, "{name}: nav of the site");
        assert_eq!(
            original, round,
            "{name}: nav after building -> site -> building"
        );
        // The world, every level model file and the crowd files too (a reference_image
        // map comes back in its pixels; crowd_sim, human lanes and holes travel in mapc's
        // extension data).
        let world_a = world(map, &tmp.path().join(format!("{name}_world_a")));
        let world_c = world(&back, &tmp.path().join(format!("{name}_world_c")));
        assert!(
            world_a == world_c,
            "{name}: world files after the round trip differ"
        );
        if b.crowd_sim.as_ref().is_some_and(|c| c.enable) {
            assert!(world_a
                .iter()
                .any(|(p, _)| p.starts_with("config_resource")));
        }
        if b.coordinate_system == mapc_ir::CoordinateSystem::ReferenceImage {
            // The reference level's drawing has the map's scale (the legacy generator's,
            // which the nav graphs use). rmf_site's own import fits its alignment to the
            // measurements and fiducials of all levels at once: on a map of one level it
            // gives the same scale (f32 there), on others it may not (hotel: 18.11 px/m
            // against the generator's 17.96).
            let ppm = |s: &Site| -> Vec<(String, f32)> {
                s.levels
                    .values()
                    .filter(|l| l.properties.name.0 == b.levels[b.reference_level].name)
                    .flat_map(|l| l.drawings.values())
                    .map(|d| (d.properties.name.0.clone(), d.properties.pixels_per_meter.0))
                    .collect()
            };
            let theirs = BuildingMap::from_bytes(&std::fs::read(map).unwrap())
                .ok()
                .and_then(|l| l.to_site().ok());
            if let Some(theirs) = theirs.filter(|t| !ppm(t).is_empty()) {
                let (a, t) = (ppm(&site), ppm(&theirs));
                assert_eq!(a.len(), 1, "{name}: one drawing on the reference level");
                println!("{name}: {} px/m, rmf_site's import {}", a[0].1, t[0].1);
                if b.levels.len() == 1 {
                    assert!(
                        (a[0].1 / t[0].1 - 1.0).abs() < 1e-6,
                        "{name}: pixels per metre {a:?} vs rmf_site's {t:?}"
                    );
                }
            }
            let text = std::fs::read_to_string(&back).unwrap();
            assert!(
                text.contains("coordinate_system: reference_image"),
                "{name}"
            );
            assert!(text.contains("measurements:"), "{name}");
        }

        if site.lifts.is_empty() {
            assert_rmf_site_nav_equal(&site, &original, name);
            compared += 1;
        }
    }
    println!("rmf_site nav graphs compared on {compared} maps without lifts");
    assert!(compared >= 3);
}

/// Sites written by rmf_site itself (its legacy import, rmf_site_format's `to_site`, of each
/// demo map it can import): mapc reads them, its nav graphs equal rmf_site's own by meaning
/// (lift waypoints and the lanes to them aside), and `mapc gazebo` writes a world that
/// libsdformat loads. tests/sites_editor.rs checks lifts of sites built as the editor does.
#[test]
fn sites_written_by_rmf_site() {
    let Some(maps) = demo_maps() else { return };
    let tmp = tempfile::tempdir().unwrap();
    let mut read = 0;
    for (name, map) in &maps {
        // rmf_site refuses wgs84 maps and telescope lift doors (the reasons mapc converts
        // itself); those are skipped here.
        let legacy = BuildingMap::from_bytes(&std::fs::read(map).unwrap());
        let Ok(site) = legacy
            .map_err(|e| e.to_string())
            .and_then(|l| l.to_site().map_err(|e| format!("{e:?}")))
        else {
            println!("{name}: rmf_site_format cannot import it, skipped");
            continue;
        };
        let path = tmp.path().join(format!("{name}.site.json"));
        std::fs::write(&path, site.to_bytes_json().unwrap()).unwrap();
        // Everything rmf_site wrote is a field mapc knows and uses (its import's default
        // scenario repeats each instance's pose; its robots are placed as models).
        let unknown: Vec<String> = mapc_frontend::load(&path)
            .unwrap()
            .diagnostics
            .iter()
            .filter(|d| d.code == "W0121")
            .map(|d| format!("{}:{}: {}", d.span.line, d.span.col, d.message))
            .collect();
        assert!(unknown.is_empty(), "{name}: {unknown:#?}");
        let nav = nav_dir(&path, &tmp.path().join(format!("{name}_nav")));
        // With lifts, lift waypoints and the lanes to them aside.
        assert_rmf_site_nav_equal(&site, &nav, &format!("{name} (rmf_site import)"));
        let world = tmp.path().join(format!("{name}.world"));
        let models = tmp.path().join(format!("{name}_models"));
        ok(&[
            "gazebo",
            path.to_str().unwrap(),
            world.to_str().unwrap(),
            models.to_str().unwrap(),
            "-q",
        ]);
        let text = std::fs::read_to_string(&world).unwrap();
        let level_model = format!("{}_", site.properties.name.0);
        assert!(
            text.contains("<world") && text.contains(&level_model),
            "{name}"
        );
        sdf_check(&path, &world, &models);
        read += 1;
    }
    assert!(read >= 4, "{read} rmf_site sites read");
}

/// The world and its level models load in libsdformat (`../shared/tools/sdf-check`) with
/// no error but Fuel models absent here; skipped when the tool cannot run.
fn sdf_check(map: &Path, world: &Path, models: &Path) {
    let tool = Path::new(ROOT).join("../shared/tools/sdf-check");
    let b = mapc_frontend::load(map).unwrap().building.unwrap();
    let levels: Vec<String> = b
        .levels
        .iter()
        .map(|(h, _)| mapc_backends::sdf::level::level_model_name(&b, h))
        .collect();
    let mut files = vec![world.to_path_buf()];
    files.extend(levels.iter().map(|l| models.join(l).join("model.sdf")));
    let Ok(out) = Command::new(&tool)
        .env("SDF_PATH", models)
        .args(&files)
        .output()
    else {
        println!("skipped: sdf-check not found");
        return;
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    if !stdout.contains(" errors (") {
        println!("skipped: sdf-check could not run");
        return;
    }
    let errors: Vec<&str> = stdout
        .lines()
        .filter(|l| l.contains(": error: "))
        .filter(|l| {
            l.split_once("Unable to find uri[model://")
                .is_none_or(|(_, m)| levels.iter().any(|lv| *lv == m.trim_end_matches(']')))
        })
        .collect();
    assert!(
        errors.is_empty(),
        "{}:\n{}",
        map.display(),
        errors.join("\n")
    );
}

fn fixture() -> PathBuf {
    Path::new(ROOT).join("fixtures/sites/lift_two_levels.site.json")
}

/// The hand-written fixture: two levels, a lift with a cabin anchor and a door visiting
/// both, a drawing with fiducials, a dock, a one-way speed-limited lane, locations.
#[test]
fn fixture_nav_graph_values() {
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read(fixture()).unwrap();
    Site::from_bytes_json(&text).expect("rmf_site_format reads the fixture");
    let nav = nav_dir(&fixture(), tmp.path());
    assert_eq!(nav.len(), 1);
    assert_eq!(nav[0].0, "fleet_a.yaml", "named after the graph");
    let doc = yaml_value(&nav[0].1);
    // Lift: reference anchors (6, ±1); the legacy cabin is 1 m (site depth) by 2 m (site
    // width), and rmf_site's editor puts its centre half the depth, the 0.1 m wall, the
    // 0.01 m gap and half the 0.05 m front door behind the anchors: x = 6 - 0.635.
    let centre = 6.0 - (0.5 + 0.1 + 0.01 + 0.025);
    let p = doc["lifts"]["lift1"]["position"].as_array().unwrap();
    assert!((p[0].as_f64().unwrap() - centre).abs() < 1e-12, "{p:?}");
    assert_eq!((p[1].as_f64(), p[2].as_f64()), (Some(0.0), Some(0.0)));
    assert_eq!(doc["lifts"]["lift1"]["dims"], serde_json::json!([1.0, 2.0]));
    let l1 = &doc["levels"]["L1"];
    let cabin: Vec<&Value> = l1["vertices"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|v| v[2]["lift"] == "lift1")
        .collect();
    assert_eq!(cabin.len(), 1);
    assert!((cabin[0][0].as_f64().unwrap() - centre).abs() < 1e-12);
    assert_eq!(cabin[0][1].as_f64(), Some(0.0));
    let lanes = l1["lanes"].as_array().unwrap();
    assert_eq!(lanes.len(), 6, "three two-way lanes on L1");
    assert_eq!(
        lanes.iter().filter(|l| l[2]["door_name"] == "d1").count(),
        2
    );
    assert_eq!(
        lanes
            .iter()
            .filter(|l| l[2]["dock_name"] == "dock1")
            .count(),
        1
    );
    let l2 = doc["levels"]["L2"]["lanes"].as_array().unwrap();
    let one_way: Vec<&Value> = l2
        .iter()
        .filter(|l| l[2]["is_bidirectional"] == false)
        .collect();
    assert_eq!(one_way.len(), 1);
    assert_eq!(one_way[0][2]["speed_limit"], 0.5);

    // Fiducials in metres: drawing at (1, 2), 10 px/m: pixel (10, 20) is (2, 4).
    let parsed = mapc_frontend::load(&fixture()).unwrap();
    let b = parsed.building.unwrap();
    let f: Vec<(f64, f64)> = b
        .fiducials
        .iter()
        .map(|(_, f)| (f.pos.x, f.pos.y))
        .collect();
    assert_eq!(f, vec![(2.0, 4.0), (4.0, 4.0)]);
    assert_eq!(
        b.levels.iter().next().unwrap().1.drawing.as_deref(),
        Some("L1_plan.png")
    );
    let lift = b.lifts.iter().next().unwrap().1;
    assert_eq!(
        lift.level_doors.len(),
        2,
        "the cabin door visits both levels"
    );
    // The back door (custom gap 0) is past the 0.1 m wall and half the 0.05 m door.
    assert!((lift.doors[0].pos.x + (0.5 + 0.1 + 0.025)).abs() < 1e-12);
    // Fiducials keep their group's name.
    assert_eq!(b.fiducials.iter().next().unwrap().1.name, "corner");

    // Converted back and forth, the nav graph stays the same.
    let bpath = tmp.path().join("x.building.yaml");
    let spath = tmp.path().join("x.site.json");
    ok(&[
        "convert",
        fixture().to_str().unwrap(),
        bpath.to_str().unwrap(),
        "-q",
    ]);
    ok(&[
        "convert",
        bpath.to_str().unwrap(),
        spath.to_str().unwrap(),
        "-q",
    ]);
    Site::from_bytes_json(&std::fs::read(&spath).unwrap()).expect("rmf_site_format reads it");
    let again = nav_dir(&spath, &tmp.path().join("again"));
    let b_nav = nav_dir(&bpath, &tmp.path().join("b"));
    assert_eq!(meaning(&yaml_value(&again[0].1)), meaning(&doc));
    assert_eq!(meaning(&yaml_value(&b_nav[0].1)), meaning(&doc));
}

/// Problems of a site, located: (code, line, column) of each diagnostic.
fn diagnostics(text: &str) -> Vec<(String, u64, u64)> {
    let tmp = tempfile::tempdir().unwrap();
    let p = tmp.path().join("bad.site.json");
    std::fs::write(&p, text).unwrap();
    let r = mapc(&["check", p.to_str().unwrap(), "--format", "json"]);
    String::from_utf8_lossy(&r.stdout)
        .lines()
        .map(|l| {
            let v: Value = serde_json::from_str(l).unwrap();
            (
                v["code"].as_str().unwrap().to_string(),
                v["location"]["line"].as_u64().unwrap_or(0),
                v["location"]["column"].as_u64().unwrap_or(0),
            )
        })
        .collect()
}

fn line_col(text: &str, needle: &str) -> (u64, u64) {
    let at = text.find(needle).unwrap();
    let line = text[..at].matches('\n').count() as u64 + 1;
    let col = (at - text[..at].rfind('\n').map_or(0, |i| i + 1)) as u64 + 1;
    (line, col)
}

#[test]
fn site_errors_are_located() {
    let good = std::fs::read_to_string(fixture()).unwrap();
    // A lane pointing at a missing anchor: E0121 on that anchor id of that lane.
    let bad = good.replace(
        r#""52": {"anchors": [21, 41]"#,
        r#""52": {"anchors": [21, 999]"#,
    );
    let d = diagnostics(&bad);
    let (line, col) = line_col(&bad, "999");
    assert!(d.contains(&("E0121".into(), line, col)), "{d:?}");
    // A lane between levels.
    let bad = good.replace(
        r#""51": {"anchors": [10, 11]"#,
        r#""51": {"anchors": [10, 21]"#,
    );
    let d = diagnostics(&bad);
    let (line, col) = line_col(&bad, r#""51": {"anchors": [10, 21]"#);
    assert!(d.contains(&("E0122".into(), line, col)), "{d:?}");
    // A location on a missing anchor.
    let bad = good.replace(r#""anchor": 20, "tags""#, r#""anchor": 77, "tags""#);
    let d = diagnostics(&bad);
    let (line, col) = line_col(&bad, "77, \"tags\"");
    assert!(d.contains(&("E0123".into(), line, col)), "{d:?}");
    // A cabin anchor outside the cabin (1 m x 2 m).
    let bad = good.replace(
        r#""41": {"Translate2D": [0.0, 0.0]}"#,
        r#""41": {"Translate2D": [3.0, 0.0]}"#,
    );
    let d = diagnostics(&bad);
    assert!(d.iter().any(|x| x.0 == "W0120"), "{d:?}");
    // A newer major format version is refused.
    let bad = good.replace(r#""format_version": "0.1""#, r#""format_version": "1.0""#);
    let d = diagnostics(&bad);
    let (line, col) = line_col(&bad, r#""1.0""#);
    assert_eq!(d, vec![("E0120".into(), line, col)]);
    // A scenario hiding or moving a model instance is reported on that instance's entry;
    // one repeating the instance's own pose (as rmf_site's import writes) is not.
    let scenario = |modifier: &str| {
        good.replacen(
            r#""model_descriptions""#,
            &format!(r#""scenarios": {{"7": {{"name": "s", "parent_scenario": null, "instances": {{"101": {modifier}}}}}}},
  "model_descriptions""#),
            1,
        )
    };
    let bad = scenario(r#"{"inclusion": "Hidden"}"#);
    let d = diagnostics(&bad);
    let (line, col) = line_col(&bad, r#""101": {"inclusion""#);
    assert!(d.contains(&("W0121".into(), line, col)), "{d:?}");
    let same = scenario(
        r#"{"pose": {"trans": [1.0, 2.0, 0.0], "rot": {"yaw": {"deg": 90.0}}}, "inclusion": "Included"}"#,
    );
    assert!(!diagnostics(&same).iter().any(|x| x.0 == "W0121"));
    let moved = scenario(r#"{"pose": {"trans": [3.0, 2.0, 0.0], "rot": {"yaw": {"deg": 90.0}}}}"#);
    assert!(diagnostics(&moved).iter().any(|x| x.0 == "W0121"));
    // An unknown field is reported, not dropped silently.
    let bad = good.replace(
        r#""name": "L2", "elevation": 4.0"#,
        r#""name": "L2", "elevaton": 4.0"#,
    );
    let d = diagnostics(&bad);
    let (line, col) = line_col(&bad, "\"elevaton\"");
    assert!(d.contains(&("W0121".into(), line, col)), "{d:?}");
}

/// `mapc build` with a `.site.json` from CMake, through cmake/mapc.cmake.
#[test]
fn cmake_builds_a_site() {
    if Command::new("cmake").arg("--version").output().is_err() {
        println!("skipped: cmake not found");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let src = tmp.path().join("src");
    std::fs::create_dir_all(&src).unwrap();
    std::fs::copy(fixture(), src.join("lift_two_levels.site.json")).unwrap();
    std::fs::write(
        src.join("CMakeLists.txt"),
        format!(
            "cmake_minimum_required(VERSION 3.16)\nproject(site_demo NONE)\n\
             list(APPEND CMAKE_MODULE_PATH \"{ROOT}/cmake\")\ninclude(mapc)\n\
             mapc_generate_maps(TARGET maps MAPS lift_two_levels.site.json TARGETS nav gltf)\n"
        ),
    )
    .unwrap();
    let build = tmp.path().join("build");
    let run = |args: &[&str]| {
        let out = Command::new("cmake").args(args).output().unwrap();
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(out.status.success(), "cmake {args:?}:\n{text}");
        text
    };
    run(&[
        "-S",
        src.to_str().unwrap(),
        "-B",
        build.to_str().unwrap(),
        &format!("-DMAPC_EXECUTABLE={}", env!("CARGO_BIN_EXE_mapc")),
    ]);
    let log = run(&["--build", build.to_str().unwrap()]);
    assert!(
        log.contains("mapc: generating map lift_two_levels"),
        "{log}"
    );
    let out = std::fs::read_dir(&build)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.join("lift_two_levels").is_dir())
        .map(|p| p.join("lift_two_levels"))
        .or_else(|| {
            let p = build.join("maps/lift_two_levels");
            p.is_dir().then_some(p)
        });
    let found = walk(&build);
    assert!(
        found
            .iter()
            .any(|p| p.ends_with("lift_two_levels/nav_graphs/fleet_a.yaml")),
        "{out:?} {found:?}"
    );
    assert!(found
        .iter()
        .any(|p| p.ends_with("lift_two_levels/lift_two_levels.glb")));
    // The depfile names the site, so a second build regenerates nothing.
    let log = run(&["--build", build.to_str().unwrap()]);
    assert!(!log.contains("mapc: generating map"), "{log}");
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}

/// A site as the simulation's map: the clinic fixture converted to a site runs the same
/// scenario to the same outcome as the `.building.yaml`.
#[test]
fn sim_on_a_site() {
    let tmp = tempfile::tempdir().unwrap();
    let site = tmp.path().join("two_level_clinic.site.json");
    let map = format!("{ROOT}/fixtures/two_level_clinic.building.yaml");
    let scenario = format!("{ROOT}/fixtures/two_level_clinic.scenario.yaml");
    ok(&["convert", &map, site.to_str().unwrap(), "-q"]);
    let outcome = |map: &str| -> Vec<String> {
        let r = mapc(&["sim", &scenario, "--map", map, "--until", "30min"]);
        assert_eq!(r.code, 0, "{}", String::from_utf8_lossy(&r.stderr));
        let text =
            String::from_utf8_lossy(&r.stdout).into_owned() + &String::from_utf8_lossy(&r.stderr);
        text.lines()
            .filter(|l| {
                l.contains("simulated") || l.contains("bottleneck") || l.starts_with("tasks")
            })
            .map(str::to_string)
            .collect()
    };
    let a = outcome(&map);
    assert!(a.iter().any(|l| l.contains("simulated")), "{a:?}");
    assert_eq!(a, outcome(site.to_str().unwrap()));
}

/// Bad input never panics: every truncation of the fixture (every 7th byte) and the
/// fixture with each number or id replaced by an out-of-range, negative or non-finite
/// value goes through the frontend, the rules and every writer a site feeds.
#[test]
fn mangled_sites_never_panic() {
    let good = std::fs::read_to_string(fixture()).unwrap();
    let mut inputs: Vec<String> = (0..good.len())
        .step_by(7)
        .filter(|&i| good.is_char_boundary(i))
        .map(|i| good[..i].to_string())
        .collect();
    for (i, _) in good.match_indices(|c: char| c.is_ascii_digit()) {
        for r in ["999999", "-1", "1e400", "\"x\"", "null", "[]"] {
            let end = good[i..]
                .find(|c: char| !c.is_ascii_digit() && c != '.')
                .map_or(good.len(), |e| i + e);
            inputs.push(format!("{}{r}{}", &good[..i], &good[end..]));
        }
    }
    for text in &inputs {
        let parsed = mapc_frontend::parse_site_str("x.site.json", text);
        if let Some(b) = parsed.valid_building() {
            let _ = mapc_ir::validate(b);
            let _ = mapc_backends::nav_graphs(b);
            let _ = mapc_backends::site_json(b);
            let _ = mapc_backends::building_yaml(b);
        }
    }
    assert!(inputs.len() > 1000);
}

fn shared_fixture() -> PathBuf {
    Path::new(ROOT).join("fixtures/sites/shared_anchors.site.json")
}

/// Positions in millimetres, for comparisons free of f32 rounding.
fn mm2(x: f64, y: f64) -> (i64, i64) {
    ((x * 1000.0).round() as i64, (y * 1000.0).round() as i64)
}

/// A directed lane: start and end (mm) and its door name.
type DoorLane = ((i64, i64), (i64, i64), String);

/// A nav level's lanes as (start, end, door name), sorted.
fn lanes_with_doors(level: &Value) -> Vec<DoorLane> {
    let verts = level["vertices"].as_array().unwrap();
    let at = |i: &Value| {
        let v = &verts[i.as_u64().unwrap() as usize];
        mm2(v[0].as_f64().unwrap(), v[1].as_f64().unwrap())
    };
    let mut out: Vec<_> = level["lanes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| {
            let door = l[2]["door_name"].as_str().unwrap_or("").to_string();
            (at(&l[0]), at(&l[1]), door)
        })
        .collect();
    out.sort();
    out
}

/// fixtures/sites/shared_anchors.site.json: two levels whose lift-core walls end on the
/// lift's reference anchors (site anchors 1 and 2, as in rmf_site's own demo sites),
/// whose floors are drawn through those anchors, and whose stacked lab doors share site
/// anchor 3; lane 42 runs from a level anchor to site anchor 3.
///
/// What rmf_site's nav export (`NavGraph::from_site`, rmf_site_format's legacy
/// nav_graph.rs, the code behind the editor's "export nav graphs") gives for it, reasoned
/// from that code:
/// - per level, its vertices are first the lift cabin anchors that lanes of the graph use
///   (anchor 90, at the lift's `center()`: the middle (8, 0) of the reference anchors, yaw
///   `atan2(0, 2)` = 0, plus (-(1.0/2 + 0.1 wall + 0.01 gap + 0.05/2 door), 0), so
///   (7.365, 0), marked `lift: core_lift`), then the level's own anchors that such lanes
///   use, by id; site anchors never become vertices;
/// - a lane whose two ends are not both among that level's vertices is skipped ("Lane .. is
///   using a site anchor ... skipped"): lane 42 (to site anchor 3) on both levels, and
///   each level's lane to the cabin anchor on the other level;
/// - each remaining lane is two directed entries (`reverse: Same`), with the `door_name`
///   of the level's door it crosses; doors are found with `site.get_anchor`, which knows
///   site anchors, so the lab doors on (12, ±0.8) count;
/// - locations name the vertex of their anchor.
///
/// So `ground` has (9,0)<->(14,0) through `lab_door`, (9,0)<->(7.365,0) and
/// (14,0)<->(14,3) with `ground_charger` a charger at (14,3); `upper` has (9,0)<->(14,0)
/// through `upper_lab_door` and (9,0)<->(7.365,0), with `upper_desk` a holding point at
/// (14,0). mapc's graph must be that (its lift waypoint agrees for a lift of yaw 0), and
/// rmf_site_format's own function, run here, must agree too.
#[test]
fn site_anchors_nav_graph_equals_rmf_sites_export() {
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read(shared_fixture()).unwrap();
    let site = Site::from_bytes_json(&text).expect("rmf_site_format reads the fixture");
    let nav = nav_dir(&shared_fixture(), tmp.path());
    assert_eq!(nav.len(), 1);
    assert_eq!(nav[0].0, "patrol.yaml");
    let doc = yaml_value(&nav[0].1);

    let both = |a: (i64, i64), b: (i64, i64), door: &str| {
        [(a, b, door.to_string()), (b, a, door.to_string())]
    };
    let lift = mm2(7.365, 0.0);
    let mut ground: Vec<_> = [
        both(mm2(9.0, 0.0), mm2(14.0, 0.0), "lab_door"),
        both(mm2(9.0, 0.0), lift, ""),
        both(mm2(14.0, 0.0), mm2(14.0, 3.0), ""),
    ]
    .concat();
    ground.sort();
    let mut upper: Vec<_> = [
        both(mm2(9.0, 0.0), mm2(14.0, 0.0), "upper_lab_door"),
        both(mm2(9.0, 0.0), lift, ""),
    ]
    .concat();
    upper.sort();
    assert_eq!(lanes_with_doors(&doc["levels"]["ground"]), ground);
    assert_eq!(lanes_with_doors(&doc["levels"]["upper"]), upper);
    // The lift waypoint on each level, and the named places.
    for level in ["ground", "upper"] {
        let cabin: Vec<(i64, i64)> = doc["levels"][level]["vertices"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|v| v[2]["lift"] == "core_lift")
            .map(|v| mm2(v[0].as_f64().unwrap(), v[1].as_f64().unwrap()))
            .collect();
        assert_eq!(cabin, vec![lift], "{level}");
    }
    let places = meaning_off_lifts(&doc, false);
    let named: Vec<(String, Vec<Place>)> = places
        .iter()
        .map(|(l, _, p)| (l.clone(), p.iter().cloned().collect()))
        .collect();
    assert_eq!(
        named,
        vec![
            (
                "ground".to_string(),
                vec![(mm2(14.0, 3.0), "ground_charger".into(), true, false, false)]
            ),
            (
                "upper".to_string(),
                vec![(mm2(14.0, 0.0), "upper_desk".into(), false, false, true)]
            ),
        ]
    );

    // rmf_site_format's export of the same file, run: the same graph, lift waypoints
    // included (yaw 0), door names included (no lane runs near-parallel to a door).
    let theirs = NavGraph::from_site(&site);
    assert_eq!(theirs.len(), 1);
    assert_eq!(theirs[0].0, "patrol");
    let theirs = serde_json::to_value(&theirs[0].1).unwrap();
    assert_eq!(meaning_off_lifts(&theirs, false), places);
    for level in ["ground", "upper"] {
        assert_eq!(
            lanes_with_doors(&theirs["levels"][level]),
            lanes_with_doors(&doc["levels"][level]),
            "{level}"
        );
    }
}

/// The same fixture in the IR, the worlds and `mapc convert` both ways: every wall, floor
/// and door on a site anchor is placed, on each level that uses it.
#[test]
fn site_anchors_in_walls_floors_and_doors() {
    let parsed = mapc_frontend::load(&shared_fixture()).unwrap();
    let d: Vec<(&str, u32, u32)> = parsed
        .diagnostics
        .iter()
        .map(|d| (d.code, d.span.line, d.span.col))
        .collect();
    let text = std::fs::read_to_string(shared_fixture()).unwrap();
    let lane = r#""42": {"anchors": [15, "#;
    let (line, col) = line_col(&text, lane);
    let col = col + lane.len() as u64;
    assert_eq!(
        d,
        vec![("W0123", line as u32, col as u32)],
        "lane 42's site anchor"
    );
    let b = parsed.building.unwrap();
    let at = |v: Handle<Vertex>| mm2(b.vertices[v].pos.x, b.vertices[v].pos.y);
    for (lh, level) in b.levels.iter() {
        assert_eq!(level.walls.len(), 9, "{}", level.name);
        // The lift-core walls start on the reference anchors (8, ±1).
        let starts: Vec<(i64, i64)> = level.walls[..2]
            .iter()
            .map(|w| at(b.walls[*w].start))
            .collect();
        assert_eq!(
            starts,
            vec![mm2(8.0, 1.0), mm2(8.0, -1.0)],
            "{}",
            level.name
        );
        assert!(level
            .walls
            .iter()
            .all(|w| b.vertices[b.walls[*w].start].level == lh
                && b.vertices[b.walls[*w].end].level == lh));
        assert_eq!(level.floors.len(), 1);
        let floor: Vec<(i64, i64)> = b.floors[level.floors[0]]
            .vertices
            .iter()
            .map(|v| at(*v))
            .collect();
        assert_eq!(
            floor,
            [
                (8.0, -1.0),
                (8.0, -4.0),
                (16.0, -4.0),
                (16.0, 4.0),
                (8.0, 4.0),
                (8.0, 1.0)
            ]
            .map(|(x, y)| mm2(x, y))
        );
        assert_eq!(level.doors.len(), 1);
        let door = &b.doors[level.doors[0]];
        assert_eq!(
            (at(door.start), at(door.end)),
            (mm2(12.0, 0.8), mm2(12.0, -0.8))
        );
    }
    // One vertex per level for each site anchor used there: (8, 1) on both levels.
    let on_anchor_2 = b
        .vertices
        .iter()
        .filter(|(_, v)| mm2(v.pos.x, v.pos.y) == mm2(8.0, 1.0))
        .map(|(_, v)| b.levels[v.level].name.as_str())
        .collect::<Vec<_>>();
    assert_eq!(on_anchor_2, ["ground", "upper"]);

    // The world: both lab doors (door models named after the doors, at the middle (12, 0)
    // of their anchors, turned to their x = 12 line, at their level's elevation), and a
    // level model per level.
    let tmp = tempfile::tempdir().unwrap();
    let files = world(&shared_fixture(), &tmp.path().join("w"));
    let sdf = String::from_utf8(
        files
            .iter()
            .find(|(p, _)| p.ends_with("world.sdf"))
            .unwrap()
            .1
            .clone(),
    )
    .unwrap();
    for (door, z) in [("lab_door", "0.0"), ("upper_lab_door", "3.5")] {
        let model = format!(
            "<model name=\"{door}\">\n      <pose>12.0 0.0 {z} 0 0 1.5707963267948966</pose>"
        );
        assert!(sdf.contains(&model), "{door}");
    }
    let level_models = files
        .iter()
        .filter(|(p, _)| p.ends_with("model.sdf"))
        .filter(|(p, _)| p.to_string_lossy().contains("shared_anchors_"))
        .count();
    assert_eq!(level_models, 2);
    sdf_check(
        &shared_fixture(),
        &tmp.path().join("w/world.sdf"),
        &tmp.path().join("w/models"),
    );
    // The other world flavours place the same doors.
    for flavour in ["ignition", "classic"] {
        let w = tmp.path().join(format!("{flavour}.world"));
        let m = tmp.path().join(format!("{flavour}_models"));
        let f = shared_fixture();
        ok(&[
            flavour,
            f.to_str().unwrap(),
            w.to_str().unwrap(),
            m.to_str().unwrap(),
            "-q",
        ]);
        let text = std::fs::read_to_string(&w).unwrap();
        assert!(
            text.contains("<pose>12.0 0.0 3.5 0 0 1.5707963267948966</pose>"),
            "{flavour}"
        );
    }

    // Converted to a .building.yaml and back to a site: the same walls per level and the
    // same nav graph, and rmf_site_format reads the site.
    let nav = nav_dir(&shared_fixture(), &tmp.path().join("nav"));
    let bpath = tmp.path().join("x.building.yaml");
    let spath = tmp.path().join("x.site.json");
    ok(&[
        "convert",
        shared_fixture().to_str().unwrap(),
        bpath.to_str().unwrap(),
        "-q",
    ]);
    ok(&[
        "convert",
        bpath.to_str().unwrap(),
        spath.to_str().unwrap(),
        "-q",
    ]);
    Site::from_bytes_json(&std::fs::read(&spath).unwrap()).expect("rmf_site_format reads it");
    for p in [&bpath, &spath] {
        let again = mapc_frontend::load(p).unwrap().building.unwrap();
        let walls: Vec<usize> = again.levels.iter().map(|(_, l)| l.walls.len()).collect();
        assert_eq!(walls, [9, 9], "{}", p.display());
        let n = nav_dir(
            p,
            &tmp.path()
                .join(format!("nav_{}", p.extension().unwrap().to_string_lossy())),
        );
        assert_eq!(
            meaning(&yaml_value(&n[0].1)),
            meaning(&yaml_value(&nav[0].1))
        );
        assert_eq!(
            lanes_with_doors(&yaml_value(&n[0].1)["levels"]["ground"]),
            lanes_with_doors(&yaml_value(&nav[0].1)["levels"]["ground"])
        );
    }
}

/// Anchors a level element may not use, and a lane on a missing anchor: located errors.
#[test]
fn site_anchor_scoping_errors_are_located() {
    let good = std::fs::read_to_string(shared_fixture()).unwrap();
    let case = |from: &str, to: &str, needle: &str, code: &str| {
        let bad = good.replace(from, to);
        assert_ne!(bad, good, "{from}");
        let d = diagnostics(&bad);
        let (line, col) = line_col(&bad, needle);
        assert!(d.contains(&(code.into(), line, col)), "{to}: {d:?}");
        d
    };
    // A lane on a missing anchor.
    case(
        r#""40": {"anchors": [14, 15]"#,
        r#""40": {"anchors": [14, 999]"#,
        "999",
        "E0121",
    );
    // A wall of `ground` on an anchor of `upper`.
    case(
        r#""21": {"anchors": [1, 13]"#,
        r#""21": {"anchors": [1, 53]"#,
        "53]",
        "E0121",
    );
    // A floor on a lift's cabin anchor.
    case(
        r#""31": {"anchors": [1, 13,"#,
        r#""31": {"anchors": [90, 13,"#,
        "90, 13,",
        "E0121",
    );
    // A door on a missing anchor.
    case(
        r#""30": {"anchors": [3, 17]"#,
        r#""30": {"anchors": [3, 77]"#,
        "77]",
        "E0121",
    );
    // A location on a site anchor: a warning, as rmf_site's export names no waypoint.
    let d = case(
        r#""anchor": 16, "tags""#,
        r#""anchor": 2, "tags""#,
        r#"2, "tags""#,
        "W0123",
    );
    assert!(d.iter().all(|x| x.0.starts_with('W')), "{d:?}");
}

/// rmf_site's own demo sites (its `assets/demo_maps/*.site.json`, not kept in this
/// repository), when `MAPC_RMF_SITE_DEMOS` names a directory holding them: each compiles
/// with no error, and `mapc nav` equals rmf_site_format's `NavGraph::from_site` of it by
/// meaning (lift waypoints and the lanes to them aside).
#[test]
fn rmf_site_demo_sites_when_given() {
    let Some(dir) = std::env::var_os("MAPC_RMF_SITE_DEMOS") else {
        println!("skipped: MAPC_RMF_SITE_DEMOS not set");
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let mut sites: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".site.json"))
        .collect();
    sites.sort();
    assert!(
        !sites.is_empty(),
        "no .site.json in {}",
        Path::new(&dir).display()
    );
    for (i, path) in sites.iter().enumerate() {
        let errors: Vec<String> = mapc_frontend::load(path)
            .unwrap()
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| format!("{}:{}: {}", d.span.line, d.span.col, d.message))
            .collect();
        assert!(errors.is_empty(), "{}: {errors:#?}", path.display());
        let site = Site::from_bytes_json(&std::fs::read(path).unwrap()).unwrap();
        let nav = nav_dir(path, &tmp.path().join(format!("nav{i}")));
        assert_rmf_site_nav_equal(&site, &nav, &path.display().to_string());
    }
}

/// A location in some graphs only (rmf_site's location `graphs`): rmf_site's export names
/// the waypoint in those graphs and leaves it unnamed, with no tags, in the others; so
/// does `mapc nav`. Converting to a `.building.yaml`, which names a waypoint in every
/// graph, says so (W0122).
#[test]
fn a_location_names_its_waypoint_only_in_its_graphs() {
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(shared_fixture())
        .unwrap()
        .replace(
            r#""95": {"name": "patrol", "color": [0.2, 0.6, 1.0]}"#,
            r#""95": {"name": "patrol", "color": [0.2, 0.6, 1.0]}, "96": {"name": "night", "color": [0.1, 0.1, 0.4]}"#,
        )
        .replace(
            r#""name": "ground_charger", "graphs": "All""#,
            r#""name": "ground_charger", "graphs": {"Only": [95]}"#,
        );
    let path = tmp.path().join("two_graphs.site.json");
    std::fs::write(&path, &text).unwrap();
    let nav = nav_dir(&path, &tmp.path().join("nav"));
    let names: Vec<&str> = nav.iter().map(|(f, _)| f.as_str()).collect();
    assert_eq!(names, ["night.yaml", "patrol.yaml"]);
    let charger_at = |doc: &Value| -> Vec<Value> {
        doc["levels"]["ground"]["vertices"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|v| mm2(v[0].as_f64().unwrap(), v[1].as_f64().unwrap()) == mm2(14.0, 3.0))
            .map(|v| v[2].clone())
            .collect()
    };
    let night = yaml_value(&nav[0].1);
    let patrol = yaml_value(&nav[1].1);
    assert_eq!(charger_at(&night), [serde_json::json!({"name": ""})]);
    assert_eq!(
        charger_at(&patrol),
        [serde_json::json!({"name": "ground_charger", "is_charger": true})]
    );
    let site = Site::from_bytes_json(text.as_bytes()).unwrap();
    for (name, graph) in NavGraph::from_site(&site) {
        let theirs = serde_json::to_value(&graph).unwrap();
        let ours = if name == "night" { &night } else { &patrol };
        assert_eq!(
            meaning_off_lifts(&theirs, false),
            meaning_off_lifts(ours, false),
            "{name}"
        );
    }
    let r = mapc(&[
        "convert",
        path.to_str().unwrap(),
        tmp.path().join("x.building.yaml").to_str().unwrap(),
    ]);
    assert_eq!(r.code, 0);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains(
            "warning[W0122]: waypoint `ground_charger` is a named place in some graphs only"
        ),
        "{err}"
    );
}
