//! `mapc crowdsim` as a drop-in for `building_crowdsim` in a map package's CMake build,
//! laid out like rmf_demos_maps: a `ros2` shim sends `ros2 run rmf_building_map_tools
//! building_map_generator|building_crowdsim|building_map_model_downloader ...` to
//! `mapc ...|mapc crowdsim ...|mapc models ...`, an ament_cmake stand-in provides
//! `ament_package()`, and the package configures, builds (Ninja, or Make without it) and
//! installs, once with `-DNO_DOWNLOAD_MODELS=ON` and once without (the downloader branch):
//! worlds with the crowd plugin, the Menge files in config_resource/ equal to what
//! `mapc gazebo` writes, nav graphs, the map sources. A map without a crowd builds too
//! (its crowdsim step writes nothing).
//!
//! The CMakeLists.txt is tests/demo_maps_package's (ours, in rmf_demos_maps' style), or
//! rmf_demos_maps' own, unchanged, when MAPC_RMF_DEMOS_MAPS_CMAKELISTS names it (upstream's
//! file is not part of this repository).

use std::path::{Path, PathBuf};
use std::process::Command;

fn have(tool: &str) -> bool {
    Command::new(tool).arg("--version").output().is_ok()
}

/// The package's CMakeLists.txt: upstream's when the variable names it, else ours.
fn cmakelists(root: &Path) -> PathBuf {
    match std::env::var_os("MAPC_RMF_DEMOS_MAPS_CMAKELISTS") {
        Some(p) if !p.is_empty() => {
            let p = PathBuf::from(p);
            assert!(
                p.is_file(),
                "MAPC_RMF_DEMOS_MAPS_CMAKELISTS: {} not found",
                p.display()
            );
            p
        }
        _ => root.join("tests/demo_maps_package/CMakeLists.txt"),
    }
}

/// The `project(NAME)` of a CMakeLists.txt: the install goes to share/NAME.
fn project_name(text: &str) -> String {
    let at = text.find("project(").expect("a project() call") + "project(".len();
    text[at..]
        .split(|c: char| c == ')' || c.is_whitespace())
        .next()
        .unwrap()
        .to_string()
}

fn run(c: &mut Command) -> String {
    let out = c.output().unwrap();
    let text = format!(
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{text}");
    text
}

#[test]
fn map_package_builds_and_installs_with_mapc_behind_ros2_run() {
    if !have("cmake") {
        println!("skipped: cmake not found");
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lists = cmakelists(root);
    println!("CMakeLists.txt: {}", lists.display());
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    // The package: the CMakeLists, unchanged, and two fixture maps (with and without a crowd).
    let pkg = t.join("pkg");
    for (name, crowd) in [("cartesian_warehouse", true), ("two_level_clinic", false)] {
        let src = root.join(format!("fixtures/{name}.building.yaml"));
        assert!(src.is_file(), "missing fixture {name} (crowd: {crowd})");
        let dir = pkg.join("maps").join(name);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::copy(&src, dir.join(format!("{name}.building.yaml"))).unwrap();
    }
    std::fs::copy(&lists, pkg.join("CMakeLists.txt")).unwrap();
    let project = project_name(&std::fs::read_to_string(&lists).unwrap());
    // `ros2 run rmf_building_map_tools TOOL ARGS` → mapc, each call logged.
    let bin = t.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let shim = bin.join("ros2");
    let log = t.join("ros2.log");
    std::fs::write(
        &shim,
        format!(
            "#!/bin/sh\necho \"$*\" >> '{log}'\n[ \"$1\" = run ] && [ \"$2\" = rmf_building_map_tools ] || exit 2\ntool=$3\nshift 3\ncase $tool in\n  building_map_generator) exec '{m}' \"$@\" ;;\n  building_crowdsim) exec '{m}' crowdsim \"$@\" ;;\n  building_map_model_downloader) exec '{m}' models \"$@\" ;;\n  *) exit 2 ;;\nesac\n",
            m = env!("CARGO_BIN_EXE_mapc"),
            log = log.display()
        ),
    )
    .unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&shim, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let ament = t.join("ament/share/ament_cmake/cmake");
    std::fs::create_dir_all(&ament).unwrap();
    std::fs::write(
        ament.join("ament_cmakeConfig.cmake"),
        "macro(ament_package)\nendmacro()\n",
    )
    .unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    // `~/.gazebo/models` in the downloader's command: a home of our own, left empty.
    let home = t.join("home");
    std::fs::create_dir_all(&home).unwrap();

    for download in [false, true] {
        let _ = std::fs::remove_file(&log);
        let tag = if download { "download" } else { "no_download" };
        let build = t.join(format!("build_{tag}"));
        let inst = t.join(format!("install_{tag}"));
        let cmake = || {
            let mut c = Command::new("cmake");
            c.env("PATH", &path).env("HOME", &home);
            c
        };
        let mut configure = cmake();
        configure
            .arg("-S")
            .arg(&pkg)
            .arg("-B")
            .arg(&build)
            .arg(format!("-DCMAKE_PREFIX_PATH={}", t.join("ament").display()))
            .arg(format!("-DCMAKE_INSTALL_PREFIX={}", inst.display()));
        if !download {
            configure.arg("-DNO_DOWNLOAD_MODELS=ON");
        }
        if have("ninja") {
            configure.args(["-G", "Ninja"]);
        }
        run(&mut configure);
        let built = run(cmake().arg("--build").arg(&build));
        run(cmake().arg("--install").arg(&build));
        let calls = std::fs::read_to_string(&log).unwrap();
        let downloads: Vec<&str> = calls
            .lines()
            .filter(|l| l.contains("building_map_model_downloader"))
            .collect();
        println!(
            "{tag}: {} ros2 calls, downloader: {downloads:?}",
            calls.lines().count()
        );
        if download {
            // Once per map, after its world; mapc names the models and fetches none.
            assert_eq!(downloads.len(), 2, "{calls}");
            assert!(built.contains("mapc downloads nothing"), "{built}");
            for model in ["TeleportDispenser", "MaleVisitorPhone"] {
                assert!(built.lines().any(|l| l.trim() == model), "{model}: {built}");
            }
        } else {
            assert!(downloads.is_empty(), "{calls}");
        }
        assert_eq!(
            std::fs::read_dir(&home).unwrap().count(),
            0,
            "nothing under HOME"
        );
        check_install(&inst.join("share").join(&project), &pkg, t, tag);
    }
}

/// What the package installs: sources, worlds, Menge files, graphs.
fn check_install(share: &Path, pkg: &Path, t: &Path, tag: &str) {
    for name in ["cartesian_warehouse", "two_level_clinic"] {
        let src = share.join(format!("{name}/{name}.building.yaml"));
        assert!(src.is_file(), "{tag}: {}", src.display());
    }
    let maps = share.join("maps");
    let w = maps.join("cartesian_warehouse");
    let world = std::fs::read_to_string(w.join("cartesian_warehouse.world")).unwrap();
    assert_eq!(world.matches("name=\"crowd_simulation\"").count(), 1);
    let ign =
        std::fs::read_to_string(maps.join("cartesian_warehouse_ign/cartesian_warehouse.world"))
            .unwrap();
    assert_eq!(ign.matches("name=\"crowd_simulation\"").count(), 1);
    let graph = std::fs::read_to_string(w.join("nav_graphs/0.yaml")).unwrap();
    assert!(
        graph.contains("lanes:") && graph.contains("vertices:"),
        "{graph}"
    );
    assert!(!w.join("nav_graphs/phony").exists());
    // The map without a crowd: world and graphs, no crowd plugin, no Menge files.
    let c = maps.join("two_level_clinic");
    let clinic = std::fs::read_to_string(c.join("two_level_clinic.world")).unwrap();
    assert!(!clinic.contains("crowd_simulation"));
    assert!(c.join("nav_graphs/0.yaml").is_file());
    assert!(!c.join("config_resource").exists());
    // The crowdsim files are the bytes `mapc gazebo` writes for the same map.
    let direct = t.join(format!("direct_{tag}"));
    let o = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .args(["gazebo", "-q"])
        .arg(pkg.join("maps/cartesian_warehouse/cartesian_warehouse.building.yaml"))
        .arg(direct.join("w.world"))
        .arg(direct.join("models"))
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    for f in ["behavior_file.xml", "scene_file.xml", "L1_navmesh.nav"] {
        assert_eq!(
            std::fs::read(w.join("config_resource").join(f)).unwrap(),
            std::fs::read(direct.join("config_resource").join(f)).unwrap(),
            "{f}"
        );
    }
}

/// `mapc models`, the downloader's stand-in: the map's models on stdout, those missing from
/// the export directory on stderr, nothing fetched, exit 0.
#[test]
fn models_lists_what_the_downloader_would_fetch() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let map = root.join("fixtures/cartesian_warehouse.building.yaml");
    let tmp = tempfile::tempdir().unwrap();
    let export = tmp.path().join("models");
    std::fs::create_dir_all(export.join("TeleportDispenser")).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .arg("models")
        .arg(&map)
        .args(["-f", "-e"])
        .arg(&export)
        .output()
        .unwrap();
    let (out, err) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert_eq!(out, "MaleVisitorPhone\nTeleportDispenser\n");
    assert!(
        err.contains("2 model(s) needed; mapc downloads nothing"),
        "{err}"
    );
    assert!(err.ends_with(": MaleVisitorPhone\n"), "{err}");
    assert_eq!(std::fs::read_dir(&export).unwrap().count(), 1);
}
