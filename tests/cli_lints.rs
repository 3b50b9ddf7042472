//! Lint levels through the real binary: `--allow`, `--warn`, `--deny` (codes, names,
//! `warnings`), `mapc.toml` discovery and `--config`, command line over file, codes that
//! cannot be allowed, errors that block only the outputs they break, and `mapc build`'s
//! per-map warning summary.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn invalid(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/invalid");
    std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.file_name().unwrap().to_string_lossy().starts_with(name))
        .unwrap_or_else(|| panic!("no fixture {name}"))
}

fn mapc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mapc"))
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn code(o: &Output) -> i32 {
    o.status.code().unwrap()
}

/// A copy of fixture `name` at `dir/rel` (so a mapc.toml can be put around it).
fn copy_to(name: &str, dir: &Path, rel: &str) -> String {
    let to = dir.join(rel);
    std::fs::create_dir_all(to.parent().unwrap()).unwrap();
    std::fs::copy(invalid(name), &to).unwrap();
    to.to_string_lossy().into_owned()
}

fn s(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

#[test]
fn allow_by_code_and_by_name() {
    let m = s(&invalid("E0302"));
    assert_eq!(code(&mapc(&["check", &m])), 1);
    for what in ["E0302", "duplicate-door-name"] {
        let o = mapc(&["check", &m, "--allow", what]);
        assert_eq!(code(&o), 0, "{}", stderr(&o));
        // `[E0302]`: the file name (in "no problems found") holds the code too.
        assert!(!stderr(&o).contains("[E0302]"), "{}", stderr(&o));
    }
}

#[test]
fn warn_lowers_an_error_so_outputs_are_written() {
    let m = s(&invalid("E0302"));
    let out = tempfile::tempdir().unwrap();
    let world = s(&out.path().join("w.world"));
    let models = s(&out.path().join("models"));
    let o = mapc(&["gazebo", &m, &world, &models]);
    assert_eq!(code(&o), 1);
    assert!(!out.path().join("w.world").exists());
    let o = mapc(&["gazebo", &m, &world, &models, "--warn", "E0302"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("warning[E0302]"), "{}", stderr(&o));
    assert!(out.path().join("w.world").exists());
}

#[test]
fn deny_a_warning_by_code_name_or_group() {
    let m = s(&invalid("W0204"));
    let out = tempfile::tempdir().unwrap();
    let dir = s(out.path());
    assert_eq!(code(&mapc(&["nav", &m, &dir])), 0);
    for args in [
        &["--deny", "W0204"][..],
        &["--deny", "lane-crosses-wall"],
        &["--deny", "warnings"],
        &["--deny-warnings"],
    ] {
        let empty = tempfile::tempdir().unwrap();
        let mut a = vec!["nav", &m, empty.path().to_str().unwrap()];
        a.extend_from_slice(args);
        let o = mapc(&a);
        assert_eq!(code(&o), 1, "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("error[W0204]"), "{}", stderr(&o));
        assert_eq!(
            std::fs::read_dir(empty.path()).unwrap().count(),
            0,
            "{args:?}"
        );
    }
}

#[test]
fn codes_that_cannot_be_allowed_are_usage_errors() {
    let m = s(&invalid("E0103"));
    for args in [
        ["--allow", "E0103"],
        ["--warn", "vertex-index-out-of-range"],
        ["--allow", "E0001"],
    ] {
        let mut a = vec!["check", &m];
        a.extend_from_slice(&args);
        let o = mapc(&a);
        assert_eq!(code(&o), 2, "{args:?}");
        assert!(stderr(&o).contains("cannot be"), "{}", stderr(&o));
    }
    // The same in a mapc.toml, named in the message.
    let dir = tempfile::tempdir().unwrap();
    let map = copy_to("E0103", dir.path(), "m.building.yaml");
    std::fs::write(dir.path().join("mapc.toml"), "[lints]\nE0103 = \"allow\"\n").unwrap();
    let o = mapc(&["check", &map]);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("mapc.toml") && stderr(&o).contains("cannot be allowed"));
    // Unknown codes and levels are usage errors too.
    assert_eq!(code(&mapc(&["check", &m, "--deny", "E9999"])), 2);
    std::fs::write(dir.path().join("mapc.toml"), "[lints]\nW0204 = \"off\"\n").unwrap();
    assert_eq!(code(&mapc(&["check", &map])), 2);
}

#[test]
fn mapc_toml_is_found_beside_the_map_or_above_it() {
    let dir = tempfile::tempdir().unwrap();
    let map = copy_to("E0302", dir.path(), "site/maps/m.building.yaml");
    assert_eq!(code(&mapc(&["check", &map])), 1);
    // In a parent directory.
    std::fs::write(dir.path().join("mapc.toml"), "[lints]\nE0302 = \"allow\"\n").unwrap();
    let o = mapc(&["check", &map]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    // The nearest one wins (files are not merged).
    std::fs::write(
        dir.path().join("site/maps/mapc.toml"),
        "[lints]\nduplicate-door-name = \"deny\"\n",
    )
    .unwrap();
    assert_eq!(code(&mapc(&["check", &map])), 1);
    // --config replaces discovery.
    let cfg = dir.path().join("other.toml");
    std::fs::write(&cfg, "[lints]\nE0302 = \"warn\"\n").unwrap();
    let o = mapc(&["check", &map, "--config", &s(&cfg)]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("warning[E0302]"));
}

#[test]
fn command_line_wins_over_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let e0302 = copy_to("E0302", dir.path(), "a/m.building.yaml");
    std::fs::write(
        dir.path().join("a/mapc.toml"),
        "[lints]\nE0302 = \"allow\"\n",
    )
    .unwrap();
    assert_eq!(code(&mapc(&["check", &e0302])), 0);
    assert_eq!(code(&mapc(&["check", &e0302, "--deny", "E0302"])), 1);

    let w0204 = copy_to("W0204", dir.path(), "b/m.building.yaml");
    std::fs::write(
        dir.path().join("b/mapc.toml"),
        "[lints]\nW0204 = \"deny\"\n",
    )
    .unwrap();
    assert_eq!(code(&mapc(&["check", &w0204])), 1);
    assert_eq!(code(&mapc(&["check", &w0204, "--warn", "W0204"])), 0);
    // `--deny warnings` turns what is still a warning into an error; an allowed code stays
    // allowed (as rustc's -D warnings).
    std::fs::write(
        dir.path().join("b/mapc.toml"),
        "[lints]\nW0204 = \"allow\"\n",
    )
    .unwrap();
    let o = mapc(&["check", &w0204, "--deny", "warnings"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
}

#[test]
fn an_error_blocks_only_the_outputs_it_breaks() {
    // E0407 (lift waypoints misaligned) breaks the nav graph, not the worlds.
    let m = s(&invalid("E0407"));
    let out = tempfile::tempdir().unwrap();
    let o = mapc(&[
        "build",
        &m,
        "-o",
        &s(out.path()),
        "--targets",
        "nav,gz,gltf",
    ]);
    assert_eq!(code(&o), 1);
    assert!(
        stderr(&o).contains("nav not written (E0407)"),
        "{}",
        stderr(&o)
    );
    let map_dir = std::fs::read_dir(out.path())
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let names: Vec<String> = std::fs::read_dir(&map_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(!names.contains(&"nav_graphs".to_string()), "{names:?}");
    assert!(names.iter().any(|n| n.ends_with(".world")), "{names:?}");
    assert!(names.iter().any(|n| n.ends_with(".glb")), "{names:?}");
    let world = out.path().join("w.world");
    let o = mapc(&["gazebo", &m, &s(&world), &s(&out.path().join("models"))]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(world.exists());
    let nav = tempfile::tempdir().unwrap();
    assert_eq!(code(&mapc(&["nav", &m, &s(nav.path())])), 1);

    // E0302 (two doors named alike) breaks worlds, and nav only when the map has lanes.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(invalid("E0302")).unwrap();
    let no_lanes: String = text
        .lines()
        .filter(|l| !l.contains("lanes:") && !l.contains("graph_idx"))
        .map(|l| format!("{l}\n"))
        .collect();
    let map = dir.path().join("doors.building.yaml");
    std::fs::write(&map, no_lanes).unwrap();
    let o = mapc(&[
        "build",
        &s(&map),
        "-o",
        &s(&dir.path().join("out")),
        "--targets",
        "nav",
    ]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let o = mapc(&[
        "build",
        &s(&map),
        "-o",
        &s(&dir.path().join("out")),
        "--targets",
        "gz",
    ]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    let with_lanes = s(&invalid("E0302"));
    let o = mapc(&[
        "build",
        &with_lanes,
        "-o",
        &s(&dir.path().join("o2")),
        "--targets",
        "nav",
    ]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
}

#[test]
fn build_counts_warnings_per_map_unless_verbose() {
    let m = s(&invalid("W0204"));
    let out = tempfile::tempdir().unwrap();
    let o = mapc(&["build", &m, "-o", &s(out.path()), "--targets", "nav"]);
    assert_eq!(code(&o), 0);
    let e = stderr(&o);
    assert!(e.contains("warnings: W0204 lane-crosses-wall ×1"), "{e}");
    assert!(!e.contains("warning[W0204]"), "{e}");
    let o = mapc(&[
        "build",
        &m,
        "-o",
        &s(out.path()),
        "--targets",
        "nav",
        "--verbose",
    ]);
    assert!(stderr(&o).contains("warning[W0204]"), "{}", stderr(&o));
}

/// Allowing a rule's error must leave every backend working on what the rule found
/// (degenerate polygons, duplicate names, misaligned lifts, ...): all targets written.
#[test]
fn every_rule_error_can_be_allowed_and_every_target_is_written() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/invalid");
    let mut seen = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let lint = &name[..5];
        if !lint.starts_with('E') || lint < "E0200" {
            continue;
        }
        seen += 1;
        let out = tempfile::tempdir().unwrap();
        let o = mapc(&["build", &s(&path), "-o", &s(out.path()), "--allow", lint]);
        if lint == "E0509" {
            // Control or bidi characters in a name that becomes a path: never allowed.
            assert_eq!(code(&o), 2, "{name}: {}", stderr(&o));
            assert!(stderr(&o).contains("cannot be allowed"), "{}", stderr(&o));
            continue;
        }
        assert_eq!(code(&o), 0, "{name}: {}", stderr(&o));
        let map_dir = std::fs::read_dir(out.path())
            .unwrap()
            .next()
            .unwrap()
            .unwrap()
            .path();
        let files: Vec<String> = std::fs::read_dir(&map_dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(
            files.iter().any(|f| f.ends_with(".glb")),
            "{name}: {files:?}"
        );
        assert_eq!(
            files.iter().filter(|f| f.ends_with(".world")).count(),
            3,
            "{name}"
        );
    }
    assert!(seen >= 20, "only {seen} rule fixtures");
}

#[test]
fn sim_takes_the_lint_options() {
    let scenario =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/two_level_clinic.scenario.yaml");
    let o = mapc(&[
        "sim",
        &s(&scenario),
        "--until",
        "1s",
        "--deny",
        "no-such-lint",
    ]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("unknown diagnostic `no-such-lint`"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn allow_warnings_silences_what_is_still_a_warning() {
    let m = s(&invalid("W0204"));
    let o = mapc(&["check", &m, "--allow", "warnings"]);
    assert_eq!(code(&o), 0);
    assert!(!stderr(&o).contains("[W0204]"), "{}", stderr(&o));
    // A code denied by name stays denied: the group applies only to warnings.
    let o = mapc(&["check", &m, "--allow", "warnings", "--deny", "W0204"]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    // Errors are not warnings.
    let e = s(&invalid("E0302"));
    assert_eq!(code(&mapc(&["check", &e, "--allow", "warnings"])), 1);
}

#[test]
fn a_likely_typo_can_be_allowed_or_lowered() {
    // E0112 ignores a key as W0103 does, so unlike the other E01xx codes it takes a level.
    let m = s(&invalid("E0112"));
    assert_eq!(code(&mapc(&["check", &m])), 1);
    let o = mapc(&["check", &m, "--allow", "E0112"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let o = mapc(&["check", &m, "--warn", "likely-typo"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("warning[E0112]"), "{}", stderr(&o));
    // Lowered to a warning it still counts as something ignored: no nav graph from a map
    // whose `lane` key was dropped is a failure, not an empty success.
    let out = tempfile::tempdir().unwrap();
    let o = mapc(&["nav", &m, &s(out.path()), "--warn", "E0112"]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("keys were ignored"), "{}", stderr(&o));
}

#[test]
fn a_blocked_target_keeps_its_earlier_files_and_the_rest_report_success() {
    // First with E0407 allowed: every target written. Then at the default level: nav is
    // blocked, its earlier graphs are not pruned as stale (the run does not own them), and
    // the targets written still get their success line.
    let m = s(&invalid("E0407"));
    let out = tempfile::tempdir().unwrap();
    let build = |extra: &[&str]| {
        let mut args = vec!["build", &m, "-o"];
        let o = s(out.path());
        args.push(&o);
        args.extend_from_slice(&["--targets", "nav,gltf"]);
        args.extend_from_slice(extra);
        mapc(&args)
    };
    let o = build(&["--allow", "E0407"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let map_dir = std::fs::read_dir(out.path())
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let graphs = map_dir.join("nav_graphs");
    assert!(graphs.is_dir());
    let o = build(&[]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("nav not written (E0407)"), "{err}");
    assert!(err.contains("written to"), "{err}");
    assert!(!err.contains("stale removed"), "{err}");
    assert!(graphs.is_dir(), "{err}");
    // --quiet drops the success line, not the error.
    let o = build(&["--quiet"]);
    assert_eq!(code(&o), 1);
    assert!(!stderr(&o).contains("written to"), "{}", stderr(&o));
    assert!(stderr(&o).contains("nav not written"), "{}", stderr(&o));
}

/// A fork's warehouse map: no lanes, its own extension keys (`aisles`, `rack_bays`) on the
/// level. `mapc nav` refuses it (the lanes may have been under a key it ignored), and the
/// refusal names both ways on: the flag, and the setting in the mapc.toml that applies.
/// Each is then taken as written and the map is accepted with no nav graph.
#[test]
fn the_ignored_keys_refusal_names_the_flag_and_the_mapc_toml_setting() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("maps/rack.building.yaml");
    std::fs::create_dir_all(map.parent().unwrap()).unwrap();
    std::fs::write(
        &map,
        "name: rack\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    elevation: 0\n    \
         vertices:\n      - [0, 0, 0, a]\n      - [4, 0, 0, b]\n      - [4, 3, 0, c]\n    \
         walls:\n      - [0, 1, {}]\n      - [1, 2, {}]\n    \
         aisles: [{from: a, to: b}]\n    rack_bays: [{at: c, depth: 1.2}]\n",
    )
    .unwrap();
    let m = s(&map);
    let out = dir.path().join("nav");
    let o = mapc(&["nav", &m, &s(&out)]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(err.matches("[W0103]").count(), 2, "{err}");
    let toml = dir.path().join("maps/mapc.toml");
    let expected = format!(
        "if those keys are meant to be ignored, pass `--allow W0103` on the command line, \
         or add `W0103 = \"allow\"` under `[lints]` in {}",
        toml.display()
    );
    assert!(err.contains(&expected), "{err}");
    assert!(!out.exists(), "nothing written");

    // The first way: the flag as the message spells it.
    let o = mapc(&["nav", &m, &s(&out), "--allow", "W0103"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("no nav graph written"),
        "{}",
        stderr(&o)
    );

    // The second way: the setting, in the file the message names; that file is then the
    // one found beside the map, and a second refusal would name it again.
    std::fs::write(&toml, "[lints]\nW0103 = \"allow\"\n").unwrap();
    let o = mapc(&["nav", &m, &s(&dir.path().join("nav2"))]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(!stderr(&o).contains("W0103"), "{}", stderr(&o));
    std::fs::write(&toml, "[lints]\nW0204 = \"allow\"\n").unwrap();
    let o = mapc(&["nav", &m, &s(&dir.path().join("nav3"))]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains(&expected), "{}", stderr(&o));
    // With `--config FILE`, that file is the one to edit.
    let other = dir.path().join("team.toml");
    std::fs::write(&other, "[lints]\nW0204 = \"allow\"\n").unwrap();
    let o = mapc(&[
        "nav",
        &m,
        &s(&dir.path().join("nav4")),
        "--config",
        &s(&other),
    ]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(
        stderr(&o).contains(&format!("under `[lints]` in {}", other.display())),
        "{}",
        stderr(&o)
    );
}
