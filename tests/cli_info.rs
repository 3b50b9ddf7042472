//! Issue 11: `mapc info MAP` lists what scenario authors refer to by name, and S0201 (no
//! waypoint named) names the nearest match and how many names it leaves out.

mod support;
use support::mapc;

const CLINIC: &str = "fixtures/two_level_clinic.building.yaml";

#[test]
fn info_human() {
    let (code, out, err) = mapc(&["info", CLINIC]);
    assert_eq!(code, 0, "{err}");
    for want in [
        "building two_level_clinic\n",
        "levels (2):\n  L1  elevation 0.0 m, 17 vertices, 4 lanes\n",
        "graphs (1):\n  0  7 lanes, 7 named waypoints\n",
        "  charger (1): tinyRobot1_charger@L1\n",
        "  pickup (1): pharmacy@L1 (dispenser pharmacy_dispenser)\n",
        "  spawn (1): tinyRobot1_charger@L1 (robot tinyRobot1)\n",
        "doors (4):\n  L1_lobby_door  hinged on L1\n",
        "lifts (1):\n  lift_1  serves L1, L2\n",
        "dispensers (1):\n  pharmacy_dispenser  at pharmacy@L1\n",
        "ingestors (1):\n  ward_a_ingestor  at ward_a@L2\n",
    ] {
        assert!(out.contains(want), "missing {want:?} in\n{out}");
    }
}

#[test]
fn info_json() {
    let (code, out, err) = mapc(&["info", "--format", "json", CLINIC]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["building"], "two_level_clinic");
    assert_eq!(v["levels"].as_array().unwrap().len(), 2);
    assert_eq!(v["graphs"][0]["index"], 0);
    assert_eq!(v["waypoints"]["charger"][0]["name"], "tinyRobot1_charger");
    assert_eq!(v["waypoints"]["spawn"][0]["model"], "TinyRobot");
    assert_eq!(v["doors"].as_array().unwrap().len(), 4);
    assert_eq!(v["lifts"][0]["name"], "lift_1");
    assert_eq!(v["dispensers"][0]["name"], "pharmacy_dispenser");
    assert_eq!(v["ingestors"][0]["waypoint"], "ward_a");
}

#[test]
fn info_on_an_invalid_map_exits_1() {
    let (code, _, err) = mapc(&[
        "info",
        "fixtures/invalid/E0201-lane-self-loop.building.yaml",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("E0201"), "{err}");
}

#[test]
fn unknown_waypoint_names_the_nearest_and_counts_the_rest() {
    // A corridor of 20 named waypoints: the help lists 12 others and says 7 are left out.
    let dir = tempfile::tempdir().unwrap();
    let mut map = String::from(
        "name: corridor\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n",
    );
    for i in 0..20 {
        let extra = if i == 0 {
            ", {is_charger: [4, true], spawn_robot_type: [1, TinyRobot], spawn_robot_name: [1, r1]}"
        } else {
            ""
        };
        map.push_str(&format!("      - [{}, 0, 0, room_{i:02}{extra}]\n", 3 * i));
    }
    map.push_str("    lanes:\n");
    for i in 0..19 {
        map.push_str(&format!(
            "      - [{i}, {}, {{bidirectional: [4, true], graph_idx: [2, 0]}}]\n",
            i + 1
        ));
    }
    let map_path = dir.path().join("corridor.building.yaml");
    std::fs::write(&map_path, map).unwrap();
    let scenario = dir.path().join("s.scenario.yaml");
    std::fs::write(
        &scenario,
        format!(
            "map: {}\nduration: 1min\nfleets:\n  - {{name: f, robot: TinyRobot, count: 1, spawn: spawn_points}}\ntasks:\n  - {{at: 0, go_to_place: {{place: room_1O}}}}\n",
            map_path.display()
        ),
    )
    .unwrap();
    let (code, _, err) = mapc(&["sim", scenario.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("no waypoint named `room_1O`"), "{err}");
    assert!(err.contains("nearest: `room_10`"), "{err}");
    assert!(err.contains("and 7 more"), "{err}");
}

#[test]
fn info_takes_the_lint_options() {
    let bad = "fixtures/invalid/E0201-lane-self-loop.building.yaml";
    let (code, _, err) = mapc(&["info", bad]);
    assert_eq!(code, 1, "{err}");
    let (code, out, err) = mapc(&["info", bad, "--allow", "lane-self-loop"]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.is_empty());
    let (code, _, err) = mapc(&["info", bad, "--deny", "no-such-lint"]);
    assert_eq!(code, 2, "{err}");
}
