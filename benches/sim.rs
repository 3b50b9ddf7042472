//! Throughput of the reference runtime (`mapc_sim::simulate`).
//!
//! `hotel_8h`: 20 robots of three fleets doing loops, deliveries (through doors and both
//! lifts) and cleaning for 8 simulated hours on the hotel demo map (read from
//! `../shared/maps`; skipped when absent). Real-time factor = 28 800 s / measured time.
//!
//! `grid_10min/<n>`: n robots looping on a synthetic square grid with 5 vertices per robot
//! (constant density), 10 simulated minutes: the cost per simulated second against the
//! number of robots (5, 20, 80).
//!
//! Run with `cargo bench --bench sim`. The map and scenario are parsed before timing.

use divan::Bencher;
use mapc_sim::{parse_scenario, simulate, RunOptions};
use std::path::Path;

fn main() {
    if !Path::new(HOTEL).is_file() {
        eprintln!("skipped: ../shared not found (hotel_8h not benchmarked)");
    }
    divan::main();
}

const HOTEL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/maps/hotel/hotel.building.yaml"
);

/// The hotel scenario of BENCHMARKS.md.
pub const HOTEL_SCENARIO: &str = include_str!("../fixtures/bench/hotel_20_robots.scenario.yaml");

fn load(map_text: &str, scenario_text: &str) -> (mapc_ir::Building, mapc_sim::Scenario) {
    let parsed = mapc_frontend::parse_str("map", map_text);
    let building = parsed.valid_building().expect("valid map").clone();
    let (scenario, diags) = parse_scenario(
        mapc_ir::FileId(0),
        scenario_text,
        Path::new(env!("CARGO_MANIFEST_DIR")),
    );
    let scenario = scenario.unwrap_or_else(|| panic!("scenario: {diags:?}"));
    (building, scenario)
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn hotel_8h(bencher: Bencher) {
    let Ok(map) = std::fs::read_to_string(HOTEL) else {
        return;
    };
    let (building, scenario) = load(&map, HOTEL_SCENARIO);
    bencher.bench_local(|| {
        let opts = RunOptions {
            until: None,
            trace: None,
            progress: None,
        };
        simulate(&building, &scenario, opts).expect("runs")
    });
}

/// A square grid of `side × side` vertices 3 m apart, bidirectional lanes between
/// neighbours, in cartesian metres.
fn grid_map(side: usize) -> String {
    let mut s = String::from(
        "coordinate_system: cartesian_meters\nname: grid\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n",
    );
    for j in 0..side {
        for i in 0..side {
            s += &format!("      - [{}, {}, 0, g_{i}_{j}]\n", 3 * i, 3 * j);
        }
    }
    s += "    lanes:\n";
    for j in 0..side {
        for i in 0..side {
            let k = j * side + i;
            if i + 1 < side {
                s += &format!(
                    "      - [{k}, {}, {{bidirectional: [4, true], graph_idx: [2, 0]}}]\n",
                    k + 1
                );
            }
            if j + 1 < side {
                s += &format!(
                    "      - [{k}, {}, {{bidirectional: [4, true], graph_idx: [2, 0]}}]\n",
                    k + side
                );
            }
        }
    }
    s
}

/// n robots, each with a loop along its own row or column (spread so that every row and
/// column is used about equally).
fn grid_scenario(n: usize, side: usize) -> String {
    let mut s = format!(
        "seed: 1\nduration: 10min\nfleets:\n  - {{name: grid, robot: TinyRobot, count: {n}, spawn: auto}}\ntasks:\n"
    );
    for r in 0..n {
        let line = r % side;
        let (a, b) = if r / side % 2 == 0 {
            (format!("g_0_{line}"), format!("g_{}_{line}", side - 1))
        } else {
            (format!("g_{line}_0"), format!("g_{line}_{}", side - 1))
        };
        s += &format!("  - {{at: 0, loop: {{start: {a}, finish: {b}, loops: 1000}}}}\n");
    }
    s
}

#[divan::bench(args = [5, 20, 80], sample_count = 3, sample_size = 1)]
fn grid_10min(bencher: Bencher, n: usize) {
    let side = ((5 * n) as f64).sqrt().ceil() as usize;
    let (building, scenario) = load(&grid_map(side), &grid_scenario(n, side));
    bencher.bench_local(|| {
        let opts = RunOptions {
            until: None,
            trace: None,
            progress: None,
        };
        simulate(&building, &scenario, opts).expect("runs")
    });
}
