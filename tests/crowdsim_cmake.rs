//! `mapc crowdsim` as a drop-in for `building_crowdsim` in a map package's CMake build
//! (tests/demo_maps_package, laid out like rmf_demos_maps): a `ros2` shim sends
//! `ros2 run rmf_building_map_tools building_map_generator|building_crowdsim ...` to mapc,
//! an ament_cmake stand-in provides `ament_package()`, and the package configures, builds
//! (Ninja, or Make without it) and installs: worlds with the crowd plugin, the Menge files
//! in config_resource/ equal to what `mapc gazebo` writes, nav graphs. A map without a crowd
//! builds too (its crowdsim step writes nothing).

use std::path::Path;
use std::process::Command;

fn have(tool: &str) -> bool {
    Command::new(tool).arg("--version").output().is_ok()
}

#[test]
fn map_package_builds_and_installs_with_mapc_behind_ros2_run() {
    if !have("cmake") {
        println!("skipped: cmake not found");
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    // The package: our CMakeLists and two fixture maps (with and without a crowd).
    let pkg = t.join("pkg");
    for (name, crowd) in [("cartesian_warehouse", true), ("two_level_clinic", false)] {
        let src = root.join(format!("fixtures/{name}.building.yaml"));
        assert!(src.is_file(), "missing fixture {name} (crowd: {crowd})");
        let dir = pkg.join("maps").join(name);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::copy(&src, dir.join(format!("{name}.building.yaml"))).unwrap();
    }
    std::fs::copy(
        root.join("tests/demo_maps_package/CMakeLists.txt"),
        pkg.join("CMakeLists.txt"),
    )
    .unwrap();
    // `ros2 run rmf_building_map_tools TOOL ARGS` → mapc.
    let bin = t.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let shim = bin.join("ros2");
    std::fs::write(
        &shim,
        format!(
            "#!/bin/sh\n[ \"$1\" = run ] && [ \"$2\" = rmf_building_map_tools ] || exit 2\ntool=$3\nshift 3\ncase $tool in\n  building_map_generator) exec '{m}' \"$@\" ;;\n  building_crowdsim) exec '{m}' crowdsim \"$@\" ;;\n  *) exit 2 ;;\nesac\n",
            m = env!("CARGO_BIN_EXE_mapc")
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
    let build = t.join("build");
    let inst = t.join("install");
    let mut configure = Command::new("cmake");
    configure
        .arg("-S")
        .arg(&pkg)
        .arg("-B")
        .arg(&build)
        .arg(format!("-DCMAKE_PREFIX_PATH={}", t.join("ament").display()))
        .arg(format!("-DCMAKE_INSTALL_PREFIX={}", inst.display()));
    if have("ninja") {
        configure.args(["-G", "Ninja"]);
    }
    let run = |c: &mut Command| {
        let out = c.env("PATH", &path).output().unwrap();
        assert!(
            out.status.success(),
            "{}\n{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    };
    run(&mut configure);
    run(Command::new("cmake").arg("--build").arg(&build));
    run(Command::new("cmake").arg("--install").arg(&build));

    let share = inst.join("share/demo_maps/maps");
    let w = share.join("cartesian_warehouse");
    let world = std::fs::read_to_string(w.join("cartesian_warehouse.world")).unwrap();
    assert_eq!(world.matches("name=\"crowd_simulation\"").count(), 1);
    let ign =
        std::fs::read_to_string(share.join("cartesian_warehouse_ign/cartesian_warehouse.world"))
            .unwrap();
    assert_eq!(ign.matches("name=\"crowd_simulation\"").count(), 1);
    assert!(w.join("nav_graphs/0.yaml").is_file());
    // The map without a crowd: world and graphs, no crowd plugin, no Menge files.
    let c = share.join("two_level_clinic");
    let clinic = std::fs::read_to_string(c.join("two_level_clinic.world")).unwrap();
    assert!(!clinic.contains("crowd_simulation"));
    assert!(!c.join("config_resource").exists());
    // The crowdsim files are the bytes `mapc gazebo` writes for the same map.
    let direct = t.join("direct");
    let (code, _, err) = {
        let o = Command::new(env!("CARGO_BIN_EXE_mapc"))
            .args(["gazebo", "-q"])
            .arg(pkg.join("maps/cartesian_warehouse/cartesian_warehouse.building.yaml"))
            .arg(direct.join("w.world"))
            .arg(direct.join("models"))
            .output()
            .unwrap();
        (
            o.status.code(),
            (),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    assert_eq!(code, Some(0), "{err}");
    for f in ["behavior_file.xml", "scene_file.xml", "L1_navmesh.nav"] {
        assert_eq!(
            std::fs::read(w.join("config_resource").join(f)).unwrap(),
            std::fs::read(direct.join("config_resource").join(f)).unwrap(),
            "{f}"
        );
    }
}
