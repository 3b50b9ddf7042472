//! `mapc gltf`: every GLB mapc writes passes the Khronos glTF-Validator (../shared/tools/
//! gltf-validate, when `node` is installed), has the promised structure (node names, extras,
//! level translations, vertex and index counts equal to the meshes'), and is deterministic.
//! Textures come from ../shared/textures when it exists; they are never copied into the repo.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn shared() -> Option<PathBuf> {
    let p = root().join("../shared");
    if p.is_dir() {
        Some(p)
    } else {
        println!("skipped: ../shared not found");
        None
    }
}

fn fixtures() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("fixtures"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".building.yaml"))
        .collect();
    v.sort();
    v
}

fn demo_maps(shared: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(shared.join("maps"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|d| {
            let name = d.file_name().unwrap().to_string_lossy().to_string();
            d.join(format!("{name}.building.yaml"))
        })
        .collect();
    v.sort();
    v
}

/// Runs `mapc gltf` with a clean environment for textures.
fn mapc_gltf(input: &Path, out: &Path, extra: &[&str], env_path: Option<&Path>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mapc"));
    cmd.arg("gltf").arg(input).arg(out).args(extra);
    cmd.env_remove("MAPC_TEXTURE_PATH");
    if let Some(p) = env_path {
        cmd.env("MAPC_TEXTURE_PATH", p);
    }
    cmd.output().unwrap()
}

fn texture_args(shared: Option<&Path>) -> Vec<String> {
    match shared {
        Some(s) => vec![
            "--texture-path".into(),
            s.join("textures").to_string_lossy().into(),
        ],
        None => Vec::new(),
    }
}

/// Every .glb under `dir`, sorted.
fn glbs(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "glb"))
        .collect();
    v.sort();
    v
}

fn glb_json(path: &Path) -> (Value, Vec<u8>) {
    let bytes = std::fs::read(path).unwrap();
    let (json, bin) =
        mapc_backends::glb_split(&bytes).unwrap_or_else(|| panic!("{}: not a GLB", path.display()));
    (serde_json::from_slice(json).unwrap(), bin.to_vec())
}

fn node_available() -> bool {
    Command::new("node")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Writes every GLB for the fixtures and demo maps and runs the validator on all of them.
#[test]
fn every_glb_passes_the_khronos_validator() {
    let shared = shared();
    let mut inputs = fixtures();
    if let Some(s) = &shared {
        inputs.extend(demo_maps(s));
    }
    let tmp = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for (i, input) in inputs.iter().enumerate() {
        let out = tmp.path().join(format!("{i}"));
        let mut args = texture_args(shared.as_deref());
        args.push("--per-level".into());
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = mapc_gltf(input, &out, &args, None);
        assert!(
            o.status.success(),
            "{}: {}",
            input.display(),
            String::from_utf8_lossy(&o.stderr)
        );
        let written = glbs(&out);
        assert!(written.len() >= 2, "{}: {written:?}", input.display());
        files.extend(written);
    }
    // A map with a translucent wall carrying a normal map, and textures beside it.
    let dir = tmp.path().join("textured");
    std::fs::create_dir_all(&dir).unwrap();
    let map = textured_map(&dir, "floor_tex", "wall_tex");
    for t in ["floor_tex", "wall_tex"] {
        std::fs::write(
            dir.join(format!("{t}.png")),
            mapc_backends::placeholder_png(),
        )
        .unwrap();
    }
    let o = mapc_gltf(&map, &dir.join("out"), &["--per-level"], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (doc, _) = glb_json(&dir.join("out/tex.glb"));
    assert!(doc["materials"]
        .as_array()
        .unwrap()
        .iter()
        .any(|m| m["normalTexture"].is_object()));
    files.extend(glbs(&dir.join("out")));
    let Some(shared) = shared else {
        return;
    };
    if !node_available() {
        // CI installs node (.ci/run); there a missing node is a failure, not a skip.
        assert!(
            std::env::var_os("CI").is_none(),
            "`node` not found in CI: .ci/run should have installed it"
        );
        println!("skipped: `node` not found; the glTF validator was not run");
        return;
    }
    let o = Command::new(shared.join("tools/gltf-validate"))
        .args(&files)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    println!("{stdout}");
    assert!(
        o.status.success(),
        "validator failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let summaries = stdout.lines().filter(|l| l.ends_with(" warnings")).count();
    assert_eq!(summaries, files.len(), "one summary line per file");
    assert!(!stdout.contains(": error "));
}

/// Index of the node named `name` among `ids`.
fn find_child<'a>(nodes: &'a [Value], ids: &Value, name: &str) -> Option<&'a Value> {
    ids.as_array()?
        .iter()
        .map(|i| &nodes[i.as_u64().unwrap() as usize])
        .find(|n| n["name"] == name)
}

#[test]
fn building_scene_structure() {
    let input = root().join("fixtures/two_level_clinic.building.yaml");
    let tmp = tempfile::tempdir().unwrap();
    let o = mapc_gltf(&input, tmp.path(), &[], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (doc, bin) = glb_json(&tmp.path().join("two_level_clinic.glb"));

    let b = mapc_frontend::load(&input).unwrap().building.unwrap();
    let nodes = doc["nodes"].as_array().unwrap();
    let accessors = doc["accessors"].as_array().unwrap();
    let meshes = doc["meshes"].as_array().unwrap();
    assert_eq!(doc["asset"]["version"], "2.0");
    assert_eq!(
        doc["buffers"][0]["byteLength"].as_u64().unwrap() as usize,
        bin.len()
    );

    let scene_root = &nodes[doc["scenes"][0]["nodes"][0].as_u64().unwrap() as usize];
    assert_eq!(scene_root["name"], "two_level_clinic");
    assert_eq!(scene_root["extras"]["building"], "two_level_clinic");
    let r: Vec<f64> = scene_root["rotation"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!((r[0] + h).abs() < 1e-6 && r[1] == 0.0 && r[2] == 0.0 && (r[3] - h).abs() < 1e-6);

    let level_ids = scene_root["children"].as_array().unwrap();
    assert_eq!(level_ids.len(), b.levels.len());
    for ((h, level), id) in b.levels.iter().zip(level_ids) {
        let ln = &nodes[id.as_u64().unwrap() as usize];
        assert_eq!(ln["name"], level.name.as_str());
        assert_eq!(ln["extras"]["level"], level.name.as_str());
        let t: Vec<f64> = ln["translation"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(t, [0.0, 0.0, level.elevation]);

        // Mesh nodes: counts equal the meshes'.
        let lm = mapc_backends::level_meshes(&b, h);
        for m in lm.all() {
            let node = find_child(nodes, &ln["children"], &m.name)
                .unwrap_or_else(|| panic!("{}: no node {}", level.name, m.name));
            assert_eq!(node["extras"]["level"], level.name.as_str());
            if m.triangles.is_empty() {
                continue;
            }
            let prim = &meshes[node["mesh"].as_u64().unwrap() as usize]["primitives"][0];
            let pos = &accessors[prim["attributes"]["POSITION"].as_u64().unwrap() as usize];
            let idx = &accessors[prim["indices"].as_u64().unwrap() as usize];
            assert_eq!(pos["count"].as_u64().unwrap() as usize, m.positions.len());
            assert_eq!(
                idx["count"].as_u64().unwrap() as usize,
                3 * m.triangles.len()
            );
        }

        // Doors: one node each, named and tagged.
        for &d in &level.doors {
            let door = &b.doors[d];
            let node = find_child(nodes, &ln["children"], &door.name)
                .unwrap_or_else(|| panic!("no door node {}", door.name));
            assert_eq!(node["extras"]["door"], door.name.as_str());
            assert_eq!(node["extras"]["type"], door.kind.as_str());
            assert_eq!(node["extras"]["level"], level.name.as_str());
            let prim = &meshes[node["mesh"].as_u64().unwrap() as usize]["primitives"][0];
            let pos = &accessors[prim["attributes"]["POSITION"].as_u64().unwrap() as usize];
            let leaves = if door.kind.as_str().starts_with("double") {
                2
            } else {
                1
            };
            assert_eq!(pos["count"].as_u64().unwrap(), 24 * leaves);
            // Panels stand 1 cm above the floor, DOOR_HEIGHT high.
            assert!((pos["min"][2].as_f64().unwrap() - 0.01).abs() < 1e-6);
            assert!((pos["max"][2].as_f64().unwrap() - 2.21).abs() < 1e-6);
            // Centred on the door segment (leaves of equal width in the fixture), offset
            // subtracted.
            let (ps, pe) = (b.vertices[door.start].pos, b.vertices[door.end].pos);
            let mid = [
                (ps.x + pe.x) / 2.0 - b.offset.x,
                (ps.y + pe.y) / 2.0 - b.offset.y,
            ];
            for k in 0..2 {
                let c = (pos["min"][k].as_f64().unwrap() + pos["max"][k].as_f64().unwrap()) / 2.0;
                assert!(
                    (c - mid[k]).abs() < 1e-3,
                    "{}: {c} vs {}",
                    door.name,
                    mid[k]
                );
            }
        }
    }
    // Lift cabins: under their initial floor.
    for (_, lift) in b.lifts.iter() {
        let home = &b.levels[lift.initial_floor().unwrap()];
        let ln = level_ids
            .iter()
            .map(|i| &nodes[i.as_u64().unwrap() as usize])
            .find(|n| n["name"] == home.name.as_str())
            .unwrap();
        let node = find_child(nodes, &ln["children"], &lift.name).unwrap();
        assert_eq!(node["extras"]["lift"], lift.name.as_str());
        let prim = &meshes[node["mesh"].as_u64().unwrap() as usize]["primitives"][0];
        let pos = &accessors[prim["attributes"]["POSITION"].as_u64().unwrap() as usize];
        let (lo, hi) = (&pos["min"], &pos["max"]);
        let dx = hi[0].as_f64().unwrap() - lo[0].as_f64().unwrap();
        let dz = hi[2].as_f64().unwrap() - lo[2].as_f64().unwrap();
        // yaw 0 in the fixture: the box's x extent is the width.
        assert!((dx - lift.width).abs() < 1e-4, "{dx} vs {}", lift.width);
        assert!((dz - mapc_backends::CABIN_HEIGHT).abs() < 1e-6);
    }
    // Every door material is BLEND (alpha 0.6); textured materials embed their texture.
    for m in doc["materials"].as_array().unwrap() {
        if m["name"] == "door" {
            assert_eq!(m["alphaMode"], "BLEND");
        }
    }
    for img in doc["images"].as_array().unwrap() {
        assert_eq!(img["mimeType"], "image/png");
        assert!(img["bufferView"].is_u64());
    }
}

#[test]
fn per_level_glbs_name_their_meshes() {
    let input = root().join("fixtures/two_level_clinic.building.yaml");
    let tmp = tempfile::tempdir().unwrap();
    let o = mapc_gltf(&input, tmp.path(), &["--per-level"], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let b = mapc_frontend::load(&input).unwrap().building.unwrap();
    for (h, level) in b.levels.iter() {
        let (doc, _) = glb_json(
            &tmp.path()
                .join(format!("two_level_clinic_{}.glb", level.name)),
        );
        let nodes = doc["nodes"].as_array().unwrap();
        let root_node = &nodes[doc["scenes"][0]["nodes"][0].as_u64().unwrap() as usize];
        assert_eq!(
            root_node["name"],
            format!("two_level_clinic_{}", level.name)
        );
        let names: Vec<&str> = root_node["children"]
            .as_array()
            .map(|c| {
                c.iter()
                    .map(|i| {
                        nodes[i.as_u64().unwrap() as usize]["name"]
                            .as_str()
                            .unwrap()
                    })
                    .collect()
            })
            .unwrap_or_default();
        let want: Vec<String> = mapc_backends::level_meshes(&b, h)
            .all()
            .map(|m| m.name.clone())
            .collect();
        assert_eq!(names, want);
    }
}

#[test]
fn output_is_deterministic() {
    let shared = shared();
    let args = texture_args(shared.as_deref());
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let mut inputs = fixtures();
    if let Some(s) = &shared {
        inputs.push(s.join("maps/office/office.building.yaml"));
    }
    for input in inputs {
        let a = tempfile::tempdir().unwrap();
        let b = tempfile::tempdir().unwrap();
        let mut args = args.clone();
        args.push("--per-level");
        assert!(mapc_gltf(&input, a.path(), &args, None).status.success());
        assert!(mapc_gltf(&input, b.path(), &args, None).status.success());
        let fa = glbs(a.path());
        assert_eq!(fa.len(), glbs(b.path()).len());
        for f in fa {
            let other = b.path().join(f.file_name().unwrap());
            assert!(
                std::fs::read(&f).unwrap() == std::fs::read(&other).unwrap(),
                "{}: {} differs between runs",
                input.display(),
                f.display()
            );
        }
    }
}

/// A one-level map with a floor and a wall using the given textures.
fn textured_map(dir: &Path, floor_texture: &str, wall_texture: &str) -> PathBuf {
    let text = format!(
        "coordinate_system: cartesian_meters\n\
         name: tex\n\
         levels:\n  L1:\n    elevation: 0\n\
         \x20   vertices:\n      - [0, 0, 0, a]\n      - [4, 0, 0, b]\n      - [4, 3, 0, c]\n      - [0, 3, 0, d]\n\
         \x20   floors:\n      - parameters: {{texture_name: [1, \"{floor_texture}\"]}}\n        vertices: [0, 1, 2, 3]\n\
         \x20   walls:\n      - [0, 1, {{texture_name: [1, \"{wall_texture}\"], alpha: [3, 0.5], normal_map: [1, \"{wall_texture}\"]}}]\n"
    );
    let p = dir.join("tex.building.yaml");
    std::fs::write(&p, text).unwrap();
    p
}

fn codes(o: &Output) -> Vec<String> {
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| {
            serde_json::from_str::<Value>(l).unwrap()["code"]
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect()
}

#[test]
fn missing_and_url_textures_are_warnings_with_placeholders() {
    let tmp = tempfile::tempdir().unwrap();
    let map = textured_map(
        tmp.path(),
        "no_such_texture",
        "https://example.com/wall.png",
    );
    let out = tmp.path().join("out");
    let o = mapc_gltf(&map, &out, &["--format", "json"], None);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let mut got = codes(&o);
    got.sort();
    assert_eq!(got, ["W0701", "W0702"]);
    let (doc, _) = glb_json(&out.join("tex.glb"));
    assert_eq!(doc["images"].as_array().unwrap().len(), 2);
    // The wall's alpha 0.5 makes its material BLEND.
    let wall = doc["materials"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["extras"]["texture"] == "https://example.com/wall.png")
        .unwrap();
    assert_eq!(wall["alphaMode"], "BLEND");
    assert_eq!(wall["pbrMetallicRoughness"]["baseColorFactor"][3], 0.5);
    // --deny-warnings: exit 1, nothing written.
    let out2 = tmp.path().join("out2");
    let o = mapc_gltf(&map, &out2, &["--deny-warnings"], None);
    assert_eq!(o.status.code(), Some(1));
    assert!(!out2.exists());
}

#[test]
fn texture_search_order() {
    let tmp = tempfile::tempdir().unwrap();
    let map = textured_map(tmp.path(), "floor_tex", "wall_tex");
    let cli = tmp.path().join("cli");
    let env = tmp.path().join("env");
    std::fs::create_dir_all(&cli).unwrap();
    std::fs::create_dir_all(&env).unwrap();
    let png = mapc_backends::placeholder_png();
    // floor_tex: only on the env path; wall_tex: beside the map.
    std::fs::write(env.join("floor_tex.png"), &png).unwrap();
    std::fs::write(tmp.path().join("wall_tex.png"), &png).unwrap();
    let out = tmp.path().join("out");
    let cli_arg = cli.to_string_lossy().to_string();
    let args = ["--format", "json", "--texture-path", cli_arg.as_str()];
    let o = mapc_gltf(&map, &out, &args, Some(&env));
    assert!(o.status.success());
    assert!(codes(&o).is_empty(), "{:?}", codes(&o));
    // Without the env path the floor texture is missing.
    let o = mapc_gltf(&map, &out, &args, None);
    assert_eq!(codes(&o), ["W0701"]);
    // A broken file earlier on the path is found first and reported, not skipped.
    // (--texture-path before the map's directory.)
    std::fs::write(cli.join("wall_tex.png"), b"not a png").unwrap();
    let o = mapc_gltf(&map, &out, &args, Some(&env));
    assert_eq!(codes(&o), ["W0701"]);
    // --texture-path before MAPC_TEXTURE_PATH.
    std::fs::write(cli.join("floor_tex.png"), b"not a png").unwrap();
    let o = mapc_gltf(&map, &out, &args, Some(&env));
    assert_eq!(codes(&o), ["W0701", "W0701"]);
    // MAPC_TEXTURE_PATH before the map's directory.
    std::fs::remove_file(cli.join("floor_tex.png")).unwrap();
    std::fs::remove_file(cli.join("wall_tex.png")).unwrap();
    std::fs::write(env.join("wall_tex.png"), b"not a png").unwrap();
    let o = mapc_gltf(&map, &out, &args, Some(&env));
    assert_eq!(codes(&o), ["W0701"]);
}

#[test]
fn invalid_map_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let input = root().join("fixtures/invalid/E0110-no-levels.building.yaml");
    let out = tmp.path().join("out");
    let o = mapc_gltf(&input, &out, &[], None);
    assert_eq!(o.status.code(), Some(1));
    assert!(!out.exists());
    let o = mapc_gltf(&tmp.path().join("missing.building.yaml"), &out, &[], None);
    assert_eq!(o.status.code(), Some(2));
}
