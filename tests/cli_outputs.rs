//! Issue 11, outputs that lie and arguments that are mistaken: stale outputs of a previous
//! run are removed (only those mapc wrote), temporaries of killed runs are swept, I/O
//! errors say what is wrong, likely argument mistakes are caught with a hint.

mod support;
use std::path::Path;
use support::mapc;

const CLINIC: &str = "fixtures/two_level_clinic.building.yaml";

/// A map with lanes in graphs 0 and `second`.
fn two_graphs(second: i64) -> String {
    format!(
        "name: g\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n      - [0, 0, 0, a]\n      - [5, 0, 0, b]\n      - [5, 5, 0, c]\n    lanes:\n      - [0, 1, {{bidirectional: [4, true], graph_idx: [2, 0]}}]\n      - [1, 2, {{bidirectional: [4, true], graph_idx: [2, {second}]}}]\n"
    )
}

#[test]
fn stale_graphs_are_removed_by_nav_and_build() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("g.building.yaml");
    let m = map.to_str().unwrap();
    let nav = dir.path().join("nav");
    let n = nav.to_str().unwrap();
    let b = dir.path().join("out");
    std::fs::write(&map, two_graphs(1)).unwrap();
    assert_eq!(mapc(&["nav", m, n]).0, 0);
    assert_eq!(
        mapc(&["build", m, "-o", b.to_str().unwrap(), "--targets", "nav"]).0,
        0
    );
    assert!(nav.join("1.yaml").exists() && b.join("g/nav_graphs/1.yaml").exists());
    // A file the user put there is never touched.
    std::fs::write(nav.join("mine.txt"), "x").unwrap();
    // Graph 1's lane moves to graph 0: 1.yaml is stale.
    std::fs::write(&map, two_graphs(0)).unwrap();
    let (code, _, err) = mapc(&["nav", m, n]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("1 stale removed"), "{err}");
    assert!(!nav.join("1.yaml").exists(), "stale graph left behind");
    assert!(nav.join("0.yaml").exists() && nav.join("mine.txt").exists());
    let (code, _, err) = mapc(&["build", m, "-o", b.to_str().unwrap(), "--targets", "nav"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        !b.join("g/nav_graphs/1.yaml").exists(),
        "stale graph left behind"
    );
    // Building another target does not remove the nav graphs (not this run's group).
    let (code, _, err) = mapc(&["build", m, "-o", b.to_str().unwrap(), "--targets", "gltf"]);
    assert_eq!(code, 0, "{err}");
    assert!(b.join("g/nav_graphs/0.yaml").exists());
}

#[test]
fn stale_temporaries_are_swept_on_the_next_run() {
    let dir = tempfile::tempdir().unwrap();
    let nav = dir.path().join("nav");
    std::fs::create_dir_all(&nav).unwrap();
    // A temporary of a process that no longer exists (pid beyond the kernel's maximum).
    let stale = nav.join(".0.yaml.mapc-tmp-4194304999");
    std::fs::write(&stale, "half").unwrap();
    let (code, _, err) = mapc(&["nav", CLINIC, nav.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(!stale.exists(), "stale temporary not swept");
}

#[test]
fn io_errors_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let afile = dir.path().join("afile");
    std::fs::write(&afile, "x").unwrap();
    let (code, _, err) = mapc(&["nav", CLINIC, afile.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("is a file; OUTPUT_DIR must be a directory"),
        "{err}"
    );
    assert!(!err.contains("os error"), "{err}");
    // A file in the middle of the path.
    let (code, _, err) = mapc(&["nav", CLINIC, afile.join("sub").to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("afile` is a file"), "{err}");
    assert!(!err.contains("os error"), "{err}");
}

#[test]
fn swapped_world_arguments_are_caught() {
    let dir = tempfile::tempdir().unwrap();
    let models = dir.path().join("models");
    std::fs::create_dir_all(&models).unwrap();
    let world = dir.path().join("out.world");
    let (code, _, err) = mapc(&[
        "gazebo",
        CLINIC,
        models.to_str().unwrap(),
        world.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("swapped"), "{err}");
    assert!(!world.exists(), "nothing may be written");
    // The model directory not there yet: the .world name still gives it away.
    let fresh = dir.path().join("fresh");
    let (code, _, err) = mapc(&[
        "gazebo",
        CLINIC,
        fresh.to_str().unwrap(),
        world.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("swapped"), "{err}");
    assert!(!fresh.exists() && !world.exists());
}

#[test]
fn input_that_is_a_directory_or_a_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let (code, _, err) = mapc(&["nav", "fixtures", out.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("`fixtures` is a directory; INPUT must be a .building.yaml file"),
        "{err}"
    );
    let (code, _, err) = mapc(&["check", "fixtures/two_level_clinic.scenario.yaml"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("is a scenario, not a building map; run it with `mapc sim"),
        "{err}"
    );
}

#[test]
fn targets_gazebo_works_like_the_subcommand() {
    let dir = tempfile::tempdir().unwrap();
    let (code, _, err) = mapc(&[
        "build",
        CLINIC,
        "-o",
        dir.path().to_str().unwrap(),
        "--targets",
        "gazebo",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(Path::new(&dir.path().join("two_level_clinic/two_level_clinic.world")).exists());
}

#[test]
fn build_help_and_cmake_module_list_every_target() {
    let (_, help, _) = mapc(&["build", "--help"]);
    let cmake =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("cmake/mapc.cmake"))
            .unwrap();
    for t in ["nav", "gltf", "meshes", "classic", "ignition", "gz"] {
        assert!(help.contains(t), "build --help lacks {t}:\n{help}");
        let line = cmake.lines().find(|l| l.contains("[TARGETS")).unwrap();
        assert!(line.contains(t), "mapc.cmake's TARGETS lacks {t}: {line}");
    }
}

#[test]
fn paths_print_without_cur_dir() {
    let dir = tempfile::tempdir().unwrap();
    let (_, _, err) = mapc(&[
        "check",
        "./fixtures/invalid/W0213-demo-mock-lift-without-floor.building.yaml",
    ]);
    assert!(!err.contains("./fixtures"), "{err}");
    let out = dir.path().join("n");
    let (_, _, err) = mapc(&[
        "nav",
        "./../mapc/fixtures/nothing.building.yaml",
        out.to_str().unwrap(),
    ]);
    assert!(!err.contains("./.."), "{err}");
}

#[test]
fn renamed_level_model_is_removed_by_meshes() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(CLINIC)).unwrap();
    let map = dir.path().join("clinic.building.yaml");
    std::fs::write(&map, &text).unwrap();
    let models = dir.path().join("models");
    let (m, o) = (map.to_str().unwrap(), models.to_str().unwrap());
    assert_eq!(mapc(&["meshes", m, o]).0, 0);
    assert!(models.join("two_level_clinic_L2/meshes").is_dir());
    // L2 becomes L3 (the lift's level_doors refer to it by name too).
    std::fs::write(&map, text.replace("L2", "L3")).unwrap();
    let (code, _, err) = mapc(&["meshes", m, o]);
    assert_eq!(code, 0, "{err}");
    assert!(models.join("two_level_clinic_L3/meshes").is_dir());
    assert!(
        !models.join("two_level_clinic_L2").exists(),
        "the old level's model and its emptied directories must go"
    );
}

#[test]
fn outdir_that_is_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let afile = dir.path().join("afile");
    std::fs::write(&afile, "x").unwrap();
    let (code, _, err) = mapc(&["build", CLINIC, "-o", afile.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("is a file; OUTDIR must be a directory"),
        "{err}"
    );
}
