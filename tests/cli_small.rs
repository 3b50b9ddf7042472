//! Issue 11, the small ones: textures found where an RMF install keeps them
//! (AMENT_PREFIX_PATH), SARIF with absolute help URIs and normalized artifact URIs.

use std::process::Command;

fn mapc_env(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mapc"));
    cmd.current_dir(env!("CARGO_MANIFEST_DIR")).args(args);
    cmd.env_remove("MAPC_TEXTURE_PATH")
        .env_remove("AMENT_PREFIX_PATH");
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A 1 × 1 RGB PNG.
const PNG: &[u8] = &[
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x90, 0x77, 0x53,
    0xde, 0x00, 0x00, 0x00, 0x0c, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x10, 0x50, 0x30, 0x00,
    0x00, 0x00, 0xa4, 0x00, 0x61, 0x34, 0x66, 0x7d, 0x72, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e,
    0x44, 0xae, 0x42, 0x60, 0x82,
];

#[test]
fn textures_from_every_ament_prefix() {
    let dir = tempfile::tempdir().unwrap();
    // Two prefixes, each with one of the clinic's textures, as colcon workspaces overlay.
    let mut prefixes = Vec::new();
    for (prefix, name) in [("ws", "blue_linoleum"), ("opt", "default")] {
        let textures = dir
            .path()
            .join(prefix)
            .join("share/rmf_building_map_tools/textures");
        std::fs::create_dir_all(&textures).unwrap();
        std::fs::write(textures.join(format!("{name}.png")), PNG).unwrap();
        prefixes.push(dir.path().join(prefix).to_str().unwrap().to_string());
    }
    let out = dir.path().join("models");
    let args = [
        "meshes",
        "fixtures/two_level_clinic.building.yaml",
        out.to_str().unwrap(),
    ];
    let (code, _, err) = mapc_env(&args, &[]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("W0701"),
        "without the prefixes the textures are missing: {err}"
    );
    let (code, _, err) = mapc_env(&args, &[("AMENT_PREFIX_PATH", &prefixes.join(":"))]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("W0701"), "{err}");
}

#[test]
fn sarif_uris_are_absolute_or_normalized() {
    let (code, out, err) = mapc_env(
        &[
            "check",
            "--format",
            "sarif",
            "./fixtures/invalid/E0201-lane-self-loop.building.yaml",
        ],
        &[],
    );
    assert_eq!(code, 1, "{err}");
    let log: serde_json::Value = serde_json::from_str(&out).unwrap();
    let run = &log["runs"][0];
    for rule in run["tool"]["driver"]["rules"].as_array().unwrap() {
        let uri = rule["helpUri"].as_str().unwrap();
        assert!(
            uri.starts_with("file:///") || uri.starts_with("https://"),
            "{uri}"
        );
        assert!(uri.ends_with("#e0201-lane-self-loop"), "{uri}");
    }
    let loc = &run["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"];
    assert_eq!(
        loc["uri"],
        "fixtures/invalid/E0201-lane-self-loop.building.yaml"
    );
    assert_eq!(loc["uriBaseId"], "%SRCROOT%");
    let base = run["originalUriBaseIds"]["%SRCROOT%"]["uri"]
        .as_str()
        .unwrap();
    assert!(
        base.starts_with("file:///") && base.ends_with('/'),
        "{base}"
    );
}

#[test]
fn readme_says_how_to_install_and_quick_start_shows_texture_path() {
    let readme =
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md"))
            .unwrap();
    let quick = readme
        .split("## Quick start")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .unwrap();
    assert!(quick.contains("cargo install --path ."), "{quick}");
    assert!(quick.contains("--texture-path"), "{quick}");
    assert!(quick.contains("AMENT_PREFIX_PATH"), "{quick}");
    // Every subcommand the quick start runs exists.
    let (_, help, _) = mapc_env(&["--help"], &[]);
    for line in quick.lines().filter(|l| l.starts_with("mapc ")) {
        let sub = line.split_whitespace().nth(1).unwrap();
        assert!(
            help.contains(&format!("  {sub} ")),
            "`mapc {sub}` not in --help:\n{help}"
        );
    }
}
