//! `mapc meshes`: the level model meshes in the reference layout, with their textures.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

fn mapc(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env_remove("MAPC_TEXTURE_PATH")
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Relative paths of every file below `dir`.
/// Every file below `dir`, except mapc's manifest (what it wrote, for pruning).
fn files(dir: &Path) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if !p.to_string_lossy().contains(".mapc-manifest") {
                out.insert(p.strip_prefix(dir).unwrap().display().to_string());
            }
        }
    }
    out
}

fn shared() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared");
    p.join("maps").is_dir().then_some(p)
}

#[test]
fn missing_textures_are_placeholders_with_a_warning() {
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().to_str().unwrap();
    // No texture path and no textures beside the fixture: every texture is a placeholder.
    let (code, err) = mapc(&["meshes", "fixtures/two_level_clinic.building.yaml", dir]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("W0701"), "{err}");
    let got = files(out.path());
    for f in [
        "two_level_clinic_L1/meshes/floor_1.obj",
        "two_level_clinic_L1/meshes/floor_1.mtl",
        "two_level_clinic_L1/meshes/wall_1.obj",
        "two_level_clinic_L1/meshes/model.material",
        "two_level_clinic_L1/meshes/blue_linoleum.png",
        "two_level_clinic_L2/meshes/floor_1.obj",
    ] {
        assert!(got.contains(f), "{f} missing from {got:?}");
    }
    let png = std::fs::read(
        out.path()
            .join("two_level_clinic_L1/meshes/blue_linoleum.png"),
    )
    .unwrap();
    assert_eq!(png, mapc_backends::placeholder_png());
    // With warnings denied nothing is written.
    let out2 = tempfile::tempdir().unwrap();
    let dir2 = out2.path().join("models");
    let (code, _) = mapc(&[
        "meshes",
        "--deny-warnings",
        "fixtures/two_level_clinic.building.yaml",
        dir2.to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert!(!dir2.exists());
}

#[test]
fn demo_maps_get_the_reference_file_layout_and_real_textures() {
    let Some(shared) = shared() else {
        println!("skipped: ../shared not found");
        return;
    };
    let textures = shared.join("textures");
    for map in ["office", "hotel", "clinic", "airport_terminal"] {
        let out = tempfile::tempdir().unwrap();
        let input = shared.join(format!("maps/{map}/{map}.building.yaml"));
        let (code, err) = mapc(&[
            "meshes",
            input.to_str().unwrap(),
            out.path().to_str().unwrap(),
            "--texture-path",
            textures.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{map}: {err}");
        assert!(
            !err.contains("W0701"),
            "{map}: every texture is in ../shared/textures: {err}"
        );
        let got = files(out.path());
        // The reference models hold model.sdf/model.config (world generation, not meshes)
        // and leave the copied textures out; the mesh files must be the same set.
        let want: BTreeSet<String> = files(&shared.join(format!("reference/{map}/models")))
            .into_iter()
            .filter(|f| f.contains("/meshes/"))
            .collect();
        let got_meshes: BTreeSet<String> = got
            .iter()
            .filter(|f| !f.ends_with(".png"))
            .cloned()
            .collect();
        assert_eq!(got_meshes, want, "{map}");
        // Each texture a level's MTL names is there, as a PNG.
        for f in got.iter().filter(|f| f.ends_with(".mtl")) {
            let mtl = std::fs::read_to_string(out.path().join(f)).unwrap();
            let tex = mtl.lines().find_map(|l| l.strip_prefix("map_Kd ")).unwrap();
            let dir = Path::new(f).parent().unwrap();
            let png = std::fs::read(out.path().join(dir).join(tex)).unwrap();
            assert!(mapc_backends::is_png(&png), "{map}: {tex}");
        }
    }
}
