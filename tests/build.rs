//! `mapc build`: several maps and targets in one run, unchanged files left alone, the
//! depfile, exit codes; and the CMake module (cmake/mapc.cmake) on tests/cmake_project.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::SystemTime;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn mapc(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(ROOT)
        .env_remove("MAPC_TEXTURE_PATH")
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Relative path → (inode, mtime) of every file below `dir`.
fn files(dir: &Path) -> std::collections::BTreeMap<String, (u64, SystemTime)> {
    use std::os::unix::fs::MetadataExt;
    let mut out = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let m = std::fs::metadata(&p).unwrap();
                let rel = p.strip_prefix(dir).unwrap().display().to_string();
                out.insert(rel, (m.ino(), m.modified().unwrap()));
            }
        }
    }
    out
}

/// The two fixture maps and a texture directory holding `blue_linoleum.png`, in `dir`.
fn setup(dir: &Path) -> (PathBuf, PathBuf, PathBuf) {
    let maps = dir.join("maps");
    let textures = maps.join("textures");
    std::fs::create_dir_all(&textures).unwrap();
    for m in ["two_level_clinic", "cartesian_warehouse"] {
        let name = format!("{m}.building.yaml");
        std::fs::copy(
            Path::new(ROOT).join("fixtures").join(&name),
            maps.join(&name),
        )
        .unwrap();
    }
    std::fs::write(
        textures.join("blue_linoleum.png"),
        mapc_backends::placeholder_png(),
    )
    .unwrap();
    (
        maps.join("two_level_clinic.building.yaml"),
        maps.join("cartesian_warehouse.building.yaml"),
        textures,
    )
}

#[test]
fn builds_every_target_of_several_maps() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, warehouse, textures) = setup(tmp.path());
    let out = tmp.path().join("out");
    let depfile = tmp.path().join("deps/maps.d");
    let args = [
        "build",
        clinic.to_str().unwrap(),
        warehouse.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--texture-path",
        textures.to_str().unwrap(),
        "--depfile",
        depfile.to_str().unwrap(),
        "--jobs",
        "2",
    ];
    let (code, err) = mapc(&args);
    assert_eq!(code, 0, "{err}");
    // Every map's diagnostics are reported, in input order.
    let c = err
        .find("two_level_clinic.building.yaml: 0 error(s)")
        .unwrap();
    let w = err
        .find("cartesian_warehouse.building.yaml: 0 error(s)")
        .unwrap();
    assert!(c < w, "{err}");

    let first = files(&out);
    let names: BTreeSet<&str> = first.keys().map(String::as_str).collect();
    for f in [
        "two_level_clinic/nav_graphs/0.yaml",
        "two_level_clinic/two_level_clinic.glb",
        "two_level_clinic/models/two_level_clinic_L1/meshes/floor_1.obj",
        "two_level_clinic/models/two_level_clinic_L1/meshes/blue_linoleum.png",
        "two_level_clinic/models/two_level_clinic_L2/meshes/wall_1.obj",
        "cartesian_warehouse/nav_graphs/0.yaml",
        "cartesian_warehouse/nav_graphs/1.yaml",
        "cartesian_warehouse/nav_graphs/9.yaml",
        "cartesian_warehouse/cartesian_warehouse.glb",
        "cartesian_warehouse/models/cartesian_warehouse_L1/meshes/model.material",
    ] {
        assert!(names.contains(f), "{f} missing from {names:?}");
    }
    // World targets write the worlds beside the level models.
    for w in [
        "two_level_clinic.world",
        "two_level_clinic_ignition.world",
        "two_level_clinic_classic.world",
        "models/two_level_clinic_L1/model.sdf",
        "models/two_level_clinic_L2/model.config",
    ] {
        let f = format!("two_level_clinic/{w}");
        assert!(names.contains(f.as_str()), "{f} missing from {names:?}");
    }
    // crowd_sim is enabled in the warehouse: its Menge files once, beside the worlds.
    for f in [
        "cartesian_warehouse/config_resource/scene_file.xml",
        "cartesian_warehouse/config_resource/behavior_file.xml",
    ] {
        assert!(names.contains(f), "{f} missing from {names:?}");
    }
    assert!(!names
        .iter()
        .any(|n| n.starts_with("two_level_clinic/config_resource")));
    // Same bytes as the single-target commands.
    let nav = tmp.path().join("nav");
    assert_eq!(
        mapc(&["nav", clinic.to_str().unwrap(), nav.to_str().unwrap()]).0,
        0
    );
    assert_eq!(
        std::fs::read(nav.join("0.yaml")).unwrap(),
        std::fs::read(out.join("two_level_clinic/nav_graphs/0.yaml")).unwrap()
    );
    let world = tmp.path().join("gz/clinic.world");
    let models = tmp.path().join("gz/models");
    let (code, err) = mapc(&[
        "gazebo",
        clinic.to_str().unwrap(),
        world.to_str().unwrap(),
        models.to_str().unwrap(),
        "--texture-path",
        textures.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read(&world).unwrap(),
        std::fs::read(out.join("two_level_clinic/two_level_clinic.world")).unwrap()
    );
    assert_eq!(
        std::fs::read(models.join("two_level_clinic_L1/model.sdf")).unwrap(),
        std::fs::read(out.join("two_level_clinic/models/two_level_clinic_L1/model.sdf")).unwrap()
    );

    // The depfile: every output, then the maps and the texture found (plus the search
    // directories, because the `default` texture is not found anywhere).
    let d = std::fs::read_to_string(&depfile).unwrap();
    let (targets, deps) = d.split_once(": \\\n").unwrap();
    let targets: BTreeSet<String> = targets
        .split(" \\\n  ")
        .map(|t| {
            Path::new(t)
                .strip_prefix(&out)
                .unwrap()
                .display()
                .to_string()
        })
        .collect();
    // Every file but mapc's manifests (bookkeeping for pruning, not outputs).
    let outputs: BTreeSet<String> = first
        .keys()
        .filter(|k| !k.contains(".mapc-manifest"))
        .cloned()
        .collect();
    assert_eq!(targets, outputs, "{d}");
    let deps: Vec<&str> = deps.trim_end().split(" \\\n").map(str::trim).collect();
    let maps_dir = clinic.parent().unwrap();
    assert_eq!(
        deps,
        [
            clinic.to_str().unwrap(),
            textures.join("blue_linoleum.png").to_str().unwrap(),
            textures.to_str().unwrap(),
            maps_dir.to_str().unwrap(),
            warehouse.to_str().unwrap(),
        ],
        "{d}"
    );

    // A second run rewrites nothing: same inodes and modification times.
    std::thread::sleep(std::time::Duration::from_millis(20));
    let (code, err) = mapc(&args);
    assert_eq!(code, 0, "{err}");
    assert_eq!(files(&out), first);
    assert_eq!(std::fs::read_to_string(&depfile).unwrap(), d);
}

/// `--TEMPLATE_WORLD_FILE` and `--SKIP_CAMERA_POSE` mean what they mean for `mapc gazebo`:
/// the same world bytes with the same options, and a bad template is a usage error.
#[test]
fn template_and_skip_camera_pose() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, _, textures) = setup(tmp.path());
    let template = tmp.path().join("template.sdf");
    std::fs::write(
        &template,
        "<sdf version=\"1.7\"><world name=\"mine\"><gui>\
         <plugin filename=\"MinimalScene\" name=\"3D View\"><camera_pose>1 2 3 0 0 0</camera_pose>\
         </plugin></gui></world></sdf>\n",
    )
    .unwrap();
    let t = template.to_str().unwrap();
    for extra in [
        &["--TEMPLATE_WORLD_FILE", t][..],
        &["--TEMPLATE_WORLD_FILE", t, "--SKIP_CAMERA_POSE"][..],
        &["--SKIP_CAMERA_POSE"][..],
    ] {
        let out = tmp.path().join("out");
        let mut args = vec![
            "build",
            clinic.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--targets",
            "gz",
            "--texture-path",
            textures.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, err) = mapc(&args);
        assert_eq!(code, 0, "{extra:?}: {err}");
        let built =
            std::fs::read_to_string(out.join("two_level_clinic/two_level_clinic.world")).unwrap();

        let world = tmp.path().join("gz/w.world");
        let models = tmp.path().join("gz/models");
        let mut args = vec![
            "gazebo",
            clinic.to_str().unwrap(),
            world.to_str().unwrap(),
            models.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, err) = mapc(&args);
        assert_eq!(code, 0, "{extra:?}: {err}");
        assert_eq!(built, std::fs::read_to_string(&world).unwrap(), "{extra:?}");

        let templated = extra.contains(&"--TEMPLATE_WORLD_FILE");
        assert_eq!(
            built.contains("<world name=\"mine\">"),
            templated,
            "{extra:?}"
        );
        // The template's camera pose stays only with --SKIP_CAMERA_POSE.
        let kept = built.contains("<camera_pose>1 2 3 0 0 0</camera_pose>");
        assert_eq!(kept, templated && extra.contains(&"--SKIP_CAMERA_POSE"));
        // Without a template, --SKIP_CAMERA_POSE keeps the default template's pose.
        if !templated {
            assert!(built.contains("<camera_pose>-6 0 6 0 0.5 0</camera_pose>"));
        }
        std::fs::remove_dir_all(&out).unwrap();
    }
    // A template without a camera pose to set is a usage error, and nothing is written.
    std::fs::write(&template, "<sdf><world name=\"w\"><gui/></world></sdf>").unwrap();
    let out = tmp.path().join("out");
    let (code, err) = mapc(&[
        "build",
        clinic.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--TEMPLATE_WORLD_FILE",
        t,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--SKIP_CAMERA_POSE"), "{err}");
    assert!(!out.exists());
}

#[test]
fn stamp_is_the_depfile_target_and_always_touched() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, _, _) = setup(tmp.path());
    let out = tmp.path().join("out dir");
    let stamp = tmp.path().join("b/clinic.stamp");
    let depfile = tmp.path().join("b/clinic.d");
    let args = [
        "build",
        clinic.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--targets",
        "nav",
        "--stamp",
        stamp.to_str().unwrap(),
        "--depfile",
        depfile.to_str().unwrap(),
    ];
    assert_eq!(mapc(&args).0, 0);
    let d = std::fs::read_to_string(&depfile).unwrap();
    assert_eq!(
        d,
        format!(
            "{}: \\\n  {}\n",
            stamp.display().to_string().replace(' ', "\\ "),
            clinic.display().to_string().replace(' ', "\\ ")
        )
    );
    // The stamp lists the outputs (spaces unescaped there).
    let listed = std::fs::read_to_string(&stamp).unwrap();
    assert_eq!(
        listed,
        format!(
            "{}\n",
            out.join("two_level_clinic/nav_graphs/0.yaml").display()
        )
    );
    let before = std::fs::metadata(&stamp).unwrap().modified().unwrap();
    std::thread::sleep(std::time::Duration::from_millis(20));
    assert_eq!(mapc(&args).0, 0);
    let after = std::fs::metadata(&stamp).unwrap().modified().unwrap();
    assert!(after > before);
}

#[test]
fn exit_code_is_the_worst_of_all_maps() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let depfile = tmp.path().join("x.d");
    let o = out.to_str().unwrap();
    let good = "fixtures/two_level_clinic.building.yaml";
    let bad = "fixtures/invalid/E0103-lane-index-out-of-range.building.yaml";
    let (code, err) = mapc(&[
        "build",
        bad,
        good,
        "-o",
        o,
        "--targets",
        "nav",
        "--depfile",
        depfile.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("E0103"), "{err}");
    assert!(err.contains("nothing written"), "{err}");
    // The valid map is still built; no depfile when a map failed.
    assert!(out.join("two_level_clinic/nav_graphs/0.yaml").is_file());
    assert!(!out.join("E0103-lane-index-out-of-range").exists());
    assert!(!depfile.exists());
    let (code, err) = mapc(&["build", bad, "fixtures/missing.building.yaml", "-o", o]);
    assert_eq!(code, 2, "{err}");
    // Two maps with the same name would write the same directory.
    let (code, err) = mapc(&["build", good, &format!("./{good}"), "-o", o]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("would both write"), "{err}");
    let (code, err) = mapc(&["build", good, "-o", o, "--targets", "nope"]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn json_diagnostics_of_all_maps() {
    let tmp = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(ROOT)
        .args([
            "build",
            "fixtures/cartesian_warehouse.building.yaml",
            "fixtures/wgs84_campus.building.yaml",
            "-o",
            tmp.path().to_str().unwrap(),
            "--targets",
            "nav",
            "--format",
            "json",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8(out.stdout).unwrap();
    let files: Vec<String> = text
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            v["location"]["file"]
                .as_str()
                .unwrap_or_default()
                .to_string()
        })
        .collect();
    assert!(files.iter().any(|f| f.contains("cartesian_warehouse")));
    assert!(files.iter().any(|f| f.contains("wgs84_campus")));
    // Input order.
    let first_campus = files.iter().position(|f| f.contains("wgs84")).unwrap();
    assert!(files[..first_campus]
        .iter()
        .all(|f| f.contains("cartesian_warehouse")));
}

#[test]
fn one_sarif_log_for_all_maps() {
    let tmp = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(ROOT)
        .args([
            "build",
            "fixtures/cartesian_warehouse.building.yaml",
            "fixtures/wgs84_campus.building.yaml",
            "-o",
            tmp.path().to_str().unwrap(),
            "--targets",
            "nav",
            "--format",
            "sarif",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let text = v.to_string();
    assert!(text.contains("cartesian_warehouse") && text.contains("wgs84_campus"));
}

/// Runs `cmake` with `args`, panicking with its output on failure; returns stdout + stderr.
fn cmake(args: &[&str]) -> String {
    let out = Command::new("cmake").args(args).output().unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "cmake {args:?} failed:\n{text}");
    text
}

fn has_program(name: &str, arg: &str) -> bool {
    Command::new(name).arg(arg).output().is_ok()
}

/// tests/cmake_project configured, built and installed with each generator available; a
/// second build regenerates nothing; touching a map or its texture regenerates that map only.
#[test]
fn cmake_module() {
    if !has_program("cmake", "--version") {
        println!("skipped: cmake not found");
        return;
    }
    let mut generators = vec!["Unix Makefiles"];
    if has_program("ninja", "--version") {
        generators.push("Ninja");
    } else {
        println!("ninja not found: testing the Makefile generator only");
    }
    for generator in generators {
        let tmp = tempfile::tempdir().unwrap();
        let (clinic, _, textures) = setup(tmp.path());
        let maps = clinic.parent().unwrap();
        let build = tmp.path().join("build");
        let prefix = tmp.path().join("install");
        let b = build.to_str().unwrap();
        cmake(&[
            "-S",
            &format!("{ROOT}/tests/cmake_project"),
            "-B",
            b,
            "-G",
            generator,
            &format!("-DMAPC_EXECUTABLE={}", env!("CARGO_BIN_EXE_mapc")),
            &format!("-DMAPS_DIR={}", maps.display()),
            &format!("-DCMAKE_INSTALL_PREFIX={}", prefix.display()),
        ]);
        let generated = |log: &str| -> BTreeSet<String> {
            log.lines()
                .filter_map(|l| l.split("mapc: generating map ").nth(1))
                .map(|m| m.trim().to_string())
                .collect()
        };
        let both: BTreeSet<String> = ["cartesian_warehouse", "two_level_clinic"]
            .map(String::from)
            .into();
        let log = cmake(&["--build", b]);
        assert_eq!(generated(&log), both, "{generator}:\n{log}");
        cmake(&["--install", b]);
        let share = prefix.join("share/mapc_cmake_demo/maps");
        for f in [
            "two_level_clinic/nav_graphs/0.yaml",
            "two_level_clinic/two_level_clinic.glb",
            "two_level_clinic/models/two_level_clinic_L1/meshes/floor_1.obj",
            "two_level_clinic/models/two_level_clinic_L1/meshes/blue_linoleum.png",
            "two_level_clinic/two_level_clinic.world",
            "two_level_clinic/models/two_level_clinic_L1/model.sdf",
            "cartesian_warehouse/nav_graphs/9.yaml",
            "cartesian_warehouse/cartesian_warehouse.glb",
            "cartesian_warehouse/cartesian_warehouse_classic.world",
        ] {
            assert!(share.join(f).is_file(), "{generator}: {f} not installed");
        }
        // Stamps and depfiles stay in the build tree.
        assert!(!share.join("two_level_clinic.stamp").exists());

        // Nothing changed: nothing regenerated.
        let log = cmake(&["--build", b]);
        assert!(generated(&log).is_empty(), "{generator}:\n{log}");

        // A touched map: that map only.
        std::thread::sleep(std::time::Duration::from_millis(1100));
        touch(&clinic);
        let log = cmake(&["--build", b]);
        assert_eq!(
            generated(&log),
            ["two_level_clinic".to_string()].into(),
            "{generator}:\n{log}"
        );
        let log = cmake(&["--build", b]);
        assert!(generated(&log).is_empty(), "{generator}:\n{log}");

        // A touched texture: every map using it.
        std::thread::sleep(std::time::Duration::from_millis(1100));
        touch(&textures.join("blue_linoleum.png"));
        let log = cmake(&["--build", b]);
        assert_eq!(generated(&log), both, "{generator}:\n{log}");
    }
}

fn touch(p: &Path) {
    let f = std::fs::File::options().append(true).open(p).unwrap();
    f.set_modified(SystemTime::now()).unwrap();
}

/// All seven demo maps, every target, one command (when ../shared is beside the checkout).
#[test]
fn demo_maps_in_one_command() {
    let shared = Path::new(ROOT).join("../shared");
    if !shared.join("maps").is_dir() {
        println!("skipped: ../shared not found");
        return;
    }
    let mut maps: Vec<PathBuf> = std::fs::read_dir(shared.join("maps"))
        .unwrap()
        .map(|e| {
            let d = e.unwrap().path();
            let name = d.file_name().unwrap().to_string_lossy().into_owned();
            d.join(format!("{name}.building.yaml"))
        })
        .collect();
    maps.sort();
    assert_eq!(maps.len(), 7);
    let tmp = tempfile::tempdir().unwrap();
    let mut args = vec!["build".to_string()];
    args.extend(maps.iter().map(|m| m.display().to_string()));
    args.extend(["-o".into(), tmp.path().display().to_string()]);
    let textures = shared.join("textures");
    if textures.is_dir() {
        args.extend(["--texture-path".into(), textures.display().to_string()]);
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, err) = mapc(&args);
    assert_eq!(code, 0, "{err}");
    for m in &maps {
        let name = m.parent().unwrap().file_name().unwrap().to_string_lossy();
        let dir = tmp.path().join(&*name);
        for f in [
            format!("{name}.world"),
            format!("{name}_classic.world"),
            format!("{name}_ignition.world"),
            "nav_graphs".to_string(),
            "models".to_string(),
        ] {
            assert!(dir.join(&f).exists(), "{name}: {f} missing");
        }
        assert!(std::fs::read_dir(dir.join("nav_graphs")).unwrap().count() > 0);
    }
}
