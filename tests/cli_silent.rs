//! Issue 11, silent failures: typos are errors with a suggestion, zero outputs of a
//! command's kind are said (and fail when something was ignored), OUTPUT_DIR is created for
//! a map without lanes, success is said on stderr (`--quiet` silences it), and rules whose
//! inputs a frontend error left unknown stay quiet.

mod support;
use std::path::Path;
use support::mapc;

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

const CLINIC: &str = "fixtures/two_level_clinic.building.yaml";

/// A square room with a lane; `lanes_key` and `charger_key` let tests misspell them.
fn room(lanes_key: &str, charger_key: &str, extra_level_key: &str) -> String {
    format!(
        "name: room\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    elevation: 0\n{extra_level_key}    vertices:\n      - [0, 0, 0, a, {{{charger_key}: [4, true]}}]\n      - [5, 0, 0, b]\n      - [5, 5, 0, c]\n      - [0, 5, 0, d]\n    {lanes_key}:\n      - [0, 1, {{bidirectional: [4, true], graph_idx: [2, 0]}}]\n    floors:\n      - vertices: [0, 1, 2, 3]\n        parameters: {{texture_name: [1, x]}}\n"
    )
}

#[test]
fn misspelled_lanes_key_is_an_error_with_a_suggestion() {
    let dir = tempfile::tempdir().unwrap();
    let map = write(
        dir.path(),
        "m.building.yaml",
        &room("lane", "is_charger", ""),
    );
    let out = dir.path().join("nav");
    let (code, _, err) = mapc(&["nav", &map, out.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("error[E0112]"), "{err}");
    assert!(err.contains("did you mean `lanes`?"), "{err}");
    // The world target too: no world without its nav graphs.
    let (code, _, err) = mapc(&["build", &map, "-o", dir.path().join("b").to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    // An unknown key far from every known one is an extension: it stays a warning.
    let map = write(
        dir.path(),
        "ext.building.yaml",
        &room("lanes", "is_charger", "    vendor_notes: x\n"),
    );
    let (code, _, err) = mapc(&["check", &map]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning[W0103]"), "{err}");
    assert!(!err.contains("E0112"), "{err}");
}

#[test]
fn misspelled_vertex_param_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let map = write(
        dir.path(),
        "m.building.yaml",
        &room("lanes", "is_chargr", ""),
    );
    let (code, _, err) = mapc(&["check", &map]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("unknown parameter `is_chargr` of vertex `a`; did you mean `is_charger`?"),
        "{err}"
    );
}

#[test]
fn no_graph_written_fails_when_keys_were_ignored() {
    // `lanes_of_robots` is too far from `lanes` to be a typo: a warning. The map then has
    // no lanes, but something was ignored: no silent success with zero graphs.
    let dir = tempfile::tempdir().unwrap();
    let map = write(
        dir.path(),
        "m.building.yaml",
        &room("lanes_of_robots", "is_charger", ""),
    );
    let out = dir.path().join("nav");
    let (code, _, err) = mapc(&["nav", &map, out.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("no nav graph written"), "{err}");
}

#[test]
fn nav_on_a_map_without_lanes_creates_output_dir_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let text = room("lanes", "is_charger", "").replace(
        "    lanes:\n      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]\n",
        "",
    );
    let map = write(dir.path(), "doors.building.yaml", &text);
    let out = dir.path().join("nav_graphs");
    let (code, _, err) = mapc(&["nav", &map, out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_dir(), "OUTPUT_DIR must be created");
    assert!(
        err.contains("no nav graph written: the map has no lanes"),
        "{err}"
    );
}

#[test]
fn success_line_and_quiet() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("nav");
    let o = out.to_str().unwrap();
    let (code, _, err) = mapc(&["nav", CLINIC, o]);
    assert_eq!(code, 0, "{err}");
    let want = format!("two_level_clinic: 1 nav graph, 1 file written to {o} (0 unchanged)\n");
    assert!(err.ends_with(&want), "{err}");
    // Second run: the file is unchanged.
    let (_, _, err) = mapc(&["nav", CLINIC, o]);
    assert!(err.contains("(1 unchanged)"), "{err}");
    let (code, _, err) = mapc(&["nav", "--quiet", CLINIC, o]);
    assert_eq!((code, err.as_str()), (0, ""));
    // Every command says it: build per map, a world command, sim.
    let (_, _, err) = mapc(&[
        "build",
        CLINIC,
        "-o",
        dir.path().join("b").to_str().unwrap(),
        "--targets",
        "nav,gltf",
    ]);
    assert!(
        err.contains("two_level_clinic: 1 graph, 4 level meshes, 2 files written to"),
        "{err}"
    );
    let (_, _, err) = mapc(&[
        "classic",
        CLINIC,
        dir.path().join("w/c.world").to_str().unwrap(),
        dir.path().join("models").to_str().unwrap(),
    ]);
    assert!(
        err.contains("two_level_clinic: 1 world, 4 level meshes, "),
        "{err}"
    );
    let (_, _, err) = mapc(&["sim", "fixtures/two_level_clinic.scenario.yaml"]);
    assert!(
        err.contains("fixtures/two_level_clinic.scenario.yaml: simulated "),
        "{err}"
    );
    let (_, _, err) = mapc(&["check", "fixtures/two_level_clinic.building.yaml"]);
    assert_eq!(
        err,
        "fixtures/two_level_clinic.building.yaml: no problems found\n"
    );
    let (_, _, err) = mapc(&["check", "-q", "fixtures/two_level_clinic.building.yaml"]);
    assert_eq!(err, "");
    let (_, _, err) = mapc(&["sim", "-q", "fixtures/two_level_clinic.scenario.yaml"]);
    assert!(!err.contains("simulated"), "{err}");
}

#[test]
fn no_metric_cascade_after_an_unknown_coordinate_system() {
    // A pixel map whose coordinate_system is misspelled: its door is 40 px wide. Read as
    // metres that would be a "40 m wide door" (W0305); the scale is unknown, so no W0305.
    let dir = tempfile::tempdir().unwrap();
    let map = write(
        dir.path(),
        "m.building.yaml",
        "name: px\ncoordinate_system: reference_imag\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n      - [0, 0, 0, a]\n      - [40, 0, 0, b]\n    doors:\n      - [0, 1, {name: [1, d1], type: [1, hinged], motion_axis: [1, start], motion_direction: [2, 1], motion_degrees: [3, 90], right_left_ratio: [3, 1]}]\n",
    );
    let (code, out, err) = mapc(&["check", "--format", "json", &map]);
    assert_eq!(code, 1, "{err}");
    assert!(out.contains("E0106"), "{out}");
    assert!(!out.contains("W0305"), "{out}");
}
