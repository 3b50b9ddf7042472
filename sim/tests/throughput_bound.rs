//! The report's throughput bound (sim/src/report/bound.rs) on a corridor worked out by hand:
//! a - b - c - d, 4 m apart, a door across c - d, a parking bay p off b. One TinyRobot
//! (0.5 m/s, largest acceleration 0.75 m/s²) loops a → d, a task every 30 s (more than it
//! can serve).
//!
//! A lane from rest to rest takes at least 4 / 0.5 + 0.5 / 0.75 = 8.667 s. A task drives
//! a → d (3 lanes, 26 s) and, but for the first, first comes back from where a task ended
//! (d → a, 26 s): 52 s of the robot, so at most 3600 / 52 = 69.2 tasks per hour. Every
//! way from a to d passes the door: 8.667 s of it a task.

use mapc_sim::{parse_scenario, simulate, Report, RunOptions};
use std::path::Path;

fn corridor(bypass: bool) -> String {
    // The bypass: c - e - f - d around the door, 4 m north.
    let (lanes, vertices) = if bypass {
        (
            "      - [2, 7, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [7, 8, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [8, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
",
            "      - [8, 4, 0, e]
      - [12, 4, 0, f]
",
        )
    } else {
        ("", "")
    };
    format!(
        r#"coordinate_system: cartesian_meters
name: corridor
graphs:
  0: {{name: g, default_lane_width: 1}}
levels:
  L1:
    elevation: 0
    doors:
      - [5, 6, {{motion_axis: [1, start], motion_degrees: [3, 90], motion_direction: [2, 1], name: [1, d1], plugin: [1, normal], right_left_ratio: [3, 1], type: [1, sliding]}}]
    lanes:
      - [0, 1, {{bidirectional: [4, true], graph_idx: [2, 0]}}]
      - [1, 2, {{bidirectional: [4, true], graph_idx: [2, 0]}}]
      - [2, 3, {{bidirectional: [4, true], graph_idx: [2, 0]}}]
      - [1, 4, {{bidirectional: [4, true], graph_idx: [2, 0]}}]
{lanes}    vertices:
      - [0, 0, 0, a]
      - [4, 0, 0, b]
      - [8, 0, 0, c]
      - [12, 0, 0, d]
      - [4, 3, 0, p, {{is_parking_spot: [4, true]}}]
      - [10, -0.8, 0, ""]
      - [10, 0.8, 0, ""]
{vertices}reference_level_name: L1
"#
    )
}

const SCENARIO: &str = "seed: 1
duration: 1h
fleets:
  - {name: f, robot: TinyRobot, count: 1, spawn: [p]}
generators:
  - {every: 30s, start: 0, loop: {start: a, finish: d, loops: 1}}
";

fn run(bypass: bool) -> Report {
    let text = corridor(bypass);
    let parsed = mapc_frontend::parse_str("corridor.building.yaml", &text);
    let building = parsed.valid_building().expect("the corridor loads");
    let (scenario, diags) = parse_scenario(mapc_ir::FileId(0), SCENARIO, Path::new("."));
    let scenario = scenario.unwrap_or_else(|| panic!("{diags:?}"));
    simulate(building, &scenario, RunOptions::default()).expect("runs")
}

/// Length, top speed, speeding up, braking.
const LANE: f64 = {
    let (len, v, up, down) = (4.0, 0.5, 0.25, 0.75);
    len / v + v / (2.0 * up) + v / (2.0 * down)
};

#[test]
fn the_bound_is_the_robot_time_of_a_task_worked_out_by_hand() {
    let r = run(false);
    let b = r.throughput.as_ref().expect("a bound");
    let robots = &b.resources[0];
    assert_eq!(robots.resource, "robots");
    assert!((robots.demand_s - 6.0 * LANE).abs() < 1e-6, "{b:?}");
    assert!((b.tasks_per_hour - 3600.0 / (6.0 * LANE)).abs() < 1e-6);
    assert_eq!(b.limited_by, "robots");
    let door = b
        .resources
        .iter()
        .find(|x| x.resource == "door d1")
        .expect("the door is on every way");
    assert!((door.demand_s - LANE).abs() < 1e-6, "{door:?}");
    assert!((door.tasks_per_hour - 3600.0 / LANE).abs() < 1e-6);
    // The run cannot beat it; it comes within reach (turns, settling, the door and a
    // gentler acceleration than the largest are what it loses).
    let done = r.tasks.iter().filter(|t| t.result == "completed").count() as f64;
    assert!((b.achieved_per_hour - done).abs() < 1e-9);
    assert!(b.share <= 1.0 && b.share > 0.75, "{b:?}");
    assert!(robots.used <= 1.0 && door.used <= 1.0, "{b:?}");
    assert!(r
        .summary()
        .contains("throughput bound: 64.3 tasks/h, set by robots"));
}

#[test]
fn a_door_with_a_way_around_it_is_not_part_of_the_bound() {
    let r = run(true);
    let b = r.throughput.as_ref().expect("a bound");
    assert!(b.resources.iter().all(|x| x.resource != "door d1"), "{b:?}");
    assert!((b.resources[0].demand_s - 6.0 * LANE).abs() < 1e-6, "{b:?}");
}
