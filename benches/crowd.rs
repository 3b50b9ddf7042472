//! Throughput of the runtime with people (issue 19), on a generated map: a 6 × 6 grid of
//! 20 m blocks whose streets are robot lanes (graph 0) and 4 m human lanes (graph 9), people
//! in 20 groups chasing the four corners round (goal reached within 2 m, then the next),
//! and 20 tiny robots looping between opposite corners through them.
//!
//! `people_20_robots_10min/<n>`: n people (250, 500, 1,000) and 20 robots for 10 simulated
//! minutes: real-time factor = 600 s / measured time, and the cost against the size of the
//! crowd (near linear: neighbour search on a uniform grid, at most 10 neighbours each).
//!
//! `people_1000_20_robots_1h`: the target, 1,000 people and 20 robots for one
//! simulated hour (one sample).
//!
//! Run with `cargo bench --bench crowd`.

use divan::Bencher;
use mapc_sim::{parse_scenario, simulate, RunOptions};
use std::fmt::Write;
use std::path::Path;

fn main() {
    divan::main();
}

const N: usize = 6;
const BLOCK: f64 = 20.0;

/// The grid map with `people` people.
fn map(people: usize) -> String {
    let mut y = String::from(
        "name: grid\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n",
    );
    let corner = |i: usize, j: usize| {
        [(0, 0), (N - 1, 0), (N - 1, N - 1), (0, N - 1)]
            .iter()
            .position(|&c| c == (i, j))
    };
    for j in 0..N {
        for i in 0..N {
            let goal = corner(i, j).map_or(String::new(), |k| {
                format!(", {{human_goal_set_name: [1, c{k}]}}")
            });
            let _ = writeln!(
                y,
                "      - [{}, {}, 0, v{i}_{j}{goal}]",
                i as f64 * BLOCK,
                j as f64 * BLOCK
            );
        }
    }
    let mut edges = Vec::new();
    for j in 0..N {
        for i in 0..N {
            let k = j * N + i;
            if i + 1 < N {
                edges.push((k, k + 1));
            }
            if j + 1 < N {
                edges.push((k, k + N));
            }
        }
    }
    y.push_str("    lanes:\n");
    for (a, b) in &edges {
        let _ = writeln!(
            y,
            "      - [{a}, {b}, {{bidirectional: [4, true], graph_idx: [2, 0]}}]"
        );
    }
    y.push_str("    human_lanes:\n");
    for (a, b) in &edges {
        let _ = writeln!(
            y,
            "      - [{a}, {b}, {{bidirectional: [4, true], graph_idx: [2, 9], width: [3, 4]}}]"
        );
    }
    y.push_str("crowd_sim:\n  enable: 1\n  update_time_step: 0.1\n");
    y.push_str("  obstacle_set: {class: 1, file_name: L1_navmesh.nav, type: nav_mesh}\n");
    y.push_str("  agent_profiles:\n    - {name: human, r: 0.25, pref_speed: 1.34, max_speed: 2, max_accel: 5, neighbor_dist: 5, max_neighbors: 10, ORCA_tau: 1, ORCA_tauObst: 0.4}\n");
    y.push_str("  goal_sets:\n");
    for k in 0..4 {
        let _ = writeln!(
            y,
            "    - {{set_id: {k}, capacity: 100000, set_area: [c{k}]}}"
        );
    }
    y.push_str("  states:\n");
    for k in 0..4 {
        let _ = writeln!(
            y,
            "    - {{name: s{k}, goal_set: {k}, final: 0, navmesh_file_name: L1_navmesh.nav}}"
        );
    }
    y.push_str("  transitions:\n");
    for k in 0..4 {
        let _ = writeln!(
            y,
            "    - {{from: s{k}, to: s{}, Condition: {{type: goal_reached, distance: 2}}}}",
            (k + 1) % 4
        );
    }
    y.push_str("  agent_groups:\n");
    // 20 groups at the street midpoints.
    for g in 0..20 {
        let (a, b) = edges[g * edges.len() / 20];
        let (ax, ay) = ((a % N) as f64 * BLOCK, (a / N) as f64 * BLOCK);
        let (bx, by) = ((b % N) as f64 * BLOCK, (b / N) as f64 * BLOCK);
        let count = people / 20 + usize::from(g < people % 20);
        let _ = writeln!(
            y,
            "    - {{group_id: {g}, profile_selector: human, state_selector: s{}, agents_number: {count}, agents_name: [], x: {}, y: {}}}",
            g % 4,
            (ax + bx) / 2.0,
            (ay + by) / 2.0
        );
    }
    y
}

/// 20 tiny robots looping corner to corner for `duration` (e.g. `10min`).
fn scenario(duration: &str) -> String {
    format!(
        "seed: 1\nduration: {duration}\nfleets:\n  - {{name: tiny, graph: 0, robot: TinyRobot, count: 20, spawn: auto}}\ngenerators:\n  - {{every: 30s, start: 0, end: {duration}, loop: {{start: v0_0, finish: v5_5, loops: 1}}}}\n  - {{every: 30s, start: 0, end: {duration}, loop: {{start: v5_0, finish: v0_5, loops: 1}}}}\n"
    )
}

fn load(people: usize, duration: &str) -> (mapc_ir::Building, mapc_sim::Scenario) {
    let parsed = mapc_frontend::parse_str("map", &map(people));
    let building = parsed.valid_building().expect("valid map").clone();
    let (scenario, diags) = parse_scenario(mapc_ir::FileId(0), &scenario(duration), Path::new("."));
    (building, scenario.unwrap_or_else(|| panic!("{diags:?}")))
}

#[divan::bench(args = [250, 500, 1000], sample_count = 2, sample_size = 1)]
fn people_20_robots_10min(bencher: Bencher, people: usize) {
    let (b, s) = load(people, "10min");
    bencher.bench_local(|| {
        let r = simulate(&b, &s, RunOptions::default()).expect("runs");
        assert_eq!(r.crowd.as_ref().map(|c| c.humans), Some(people));
        r
    });
}

/// The target run: 1,000 people and 20 robots for one simulated hour
/// (real-time factor = 3,600 s / measured time). One sample: it takes about 40 s.
#[divan::bench(sample_count = 1, sample_size = 1)]
fn people_1000_20_robots_1h(bencher: Bencher) {
    let (b, s) = load(1000, "1h");
    bencher.bench_local(|| {
        let r = simulate(&b, &s, RunOptions::default()).expect("runs");
        assert_eq!(r.crowd.as_ref().map(|c| c.humans), Some(1000));
        r
    });
}

const AIRPORT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/maps/airport_terminal/airport_terminal.building.yaml"
);

/// The acceptance run: the airport terminal's 10 people × 20 (200) with two tiny
/// robots looping through them, one simulated hour (skipped without ../shared).
#[divan::bench(sample_count = 2, sample_size = 1)]
fn airport_200_people_1h(bencher: Bencher) {
    let Ok(text) = std::fs::read_to_string(AIRPORT) else {
        eprintln!("skipped: ../shared not found");
        return;
    };
    let parsed = mapc_frontend::parse_str("map", &text);
    let b = parsed.valid_building().expect("valid map").clone();
    let s = "seed: 1\nduration: 1h\ncrowd: {scale: 20}\nfleets:\n  - {name: tiny, graph: 2, robot: TinyRobot, count: 2, spawn: [s10, s11]}\ngenerators:\n  - {every: 5min, start: 0, end: 1h, loop: {start: s10, finish: s11, loops: 1}}\n";
    let (s, d) = parse_scenario(mapc_ir::FileId(0), s, Path::new("."));
    let s = s.unwrap_or_else(|| panic!("{d:?}"));
    bencher.bench_local(|| {
        let r = simulate(&b, &s, RunOptions::default()).expect("runs");
        assert_eq!(r.crowd.as_ref().map(|c| c.humans), Some(200));
        r
    });
}
