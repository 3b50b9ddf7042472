//! Throughput of the reference runtime (`mapc_sim::simulate`).
//!
//! `hotel_8h`: 20 robots of three fleets doing loops, deliveries (through doors and both
//! lifts) and cleaning for 8 simulated hours on the hotel demo map (read from
//! `../shared/maps`; skipped when absent). Real-time factor = 28 800 s / measured time.
//!
//! `hotel_8h_64`: the same with the fleets scaled to 64 robots.
//!
//! `airport_8h_64`: 64 tiny robots asked on the airport terminal (graph 2), loops between
//! 16 places arriving faster than any fleet serves them (every robot on the floor always
//! has work), 8 simulated hours: the planner's cost under saturation (issue 35 asks for
//! at least 1,000× real time, i.e. under 28.8 s).
//!
//! `rings_10min/<n>`: n robots, two per one-way ring of 8 vertices (constant density, every
//! robot always driving), 10 simulated minutes: the cost per simulated second against the
//! number of robots (5, 20, 80).
//!
//! `warehouse_1000/<minutes>`: 1,000 tiny robots on a generated warehouse of 10,188
//! waypoints (one-way aisles, a bay off every other waypoint), loops between random racks
//! faster than the fleet serves, for one simulated minute and for an hour (issue 35 asks
//! for an hour at least 10× real time with every robot busy; BENCHMARKS.md has the
//! figures).
//!
//! Run with `cargo bench --bench sim`. The map and scenario are parsed before timing. Each
//! bench also prints the planner's cost per decision (one robot's plan against the
//! schedule): median, 99th percentile and maximum over every decision of its samples.

// Shared with the traffic property test, which uses its single-file layout too.
#[allow(dead_code)]
#[path = "../sim/tests/support/warehouse.rs"]
mod warehouse;

use divan::Bencher;
use mapc_sim::{parse_scenario, simulate, RunOptions};
use std::path::Path;

// The `mapc` binary's allocator, so the runtime is timed as `mapc sim` runs it.
#[global_allocator]
static ALLOC: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    if !Path::new(HOTEL).is_file() {
        eprintln!("skipped: ../shared not found (hotel_8h, airport_8h_64 not benchmarked)");
    }
    divan::main();
}

const HOTEL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/maps/hotel/hotel.building.yaml"
);

const AIRPORT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/maps/airport_terminal/airport_terminal.building.yaml"
);

/// The saturating airport scenario of BENCHMARKS.md.
const AIRPORT_SCENARIO: &str = include_str!("../fixtures/bench/airport_64_robots.scenario.yaml");

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

/// Times whole runs of `scenario` (to its duration), and prints the planner's cost per
/// decision (one robot's plan against the schedule): median and 99th percentile over
/// every decision of every sample; and what the last run did (tasks, and how busy the
/// robots were: a fast run of idle robots proves little).
fn run_whole(bencher: Bencher, building: &mapc_ir::Building, scenario: &mapc_sim::Scenario) {
    let mut times: Vec<f64> = Vec::new();
    let mut last = None;
    bencher.bench_local(|| {
        let opts = RunOptions {
            plan_times: Some(&mut times),
            ..Default::default()
        };
        let report = simulate(building, scenario, opts).expect("runs");
        last = Some(
            report
                .fleets
                .iter()
                .map(|f| (f.tasks_completed, f.utilisation))
                .collect::<Vec<_>>(),
        );
    });
    if let Some(fleets) = last {
        for (done, busy) in fleets {
            eprintln!(
                "fleet: {done} tasks completed, robots with a task {:.1} %",
                100.0 * busy
            );
        }
    }
    if !times.is_empty() {
        times.sort_unstable_by(f64::total_cmp);
        let at = |q: f64| times[((times.len() - 1) as f64 * q).round() as usize] * 1e6;
        eprintln!(
            "planner per decision: median {:.0} µs, p99 {:.0} µs, max {:.0} µs ({} decisions)",
            at(0.5),
            at(0.99),
            at(1.0),
            times.len()
        );
    }
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn hotel_8h(bencher: Bencher) {
    let Ok(map) = std::fs::read_to_string(HOTEL) else {
        return;
    };
    let (building, scenario) = load(&map, HOTEL_SCENARIO);
    run_whole(bencher, &building, &scenario);
}

/// The hotel scenario with its fleets scaled together to 64 robots (32 / 19 / 13): the
/// planner's cost when most robots are idle and in the way.
#[divan::bench(sample_count = 2, sample_size = 1)]
fn hotel_8h_64(bencher: Bencher) {
    let Ok(map) = std::fs::read_to_string(HOTEL) else {
        return;
    };
    let scenario = HOTEL_SCENARIO
        .replace("count: 10,", "count: 32,")
        .replace("count: 6,", "count: 19,")
        .replace("count: 4,", "count: 13,");
    let (building, scenario) = load(&map, &scenario);
    assert_eq!(scenario.fleets.iter().map(|f| f.count).sum::<usize>(), 64);
    run_whole(bencher, &building, &scenario);
}

#[divan::bench(sample_count = 2, sample_size = 1)]
fn airport_8h_64(bencher: Bencher) {
    let Ok(map) = std::fs::read_to_string(AIRPORT) else {
        return;
    };
    let (building, scenario) = load(&map, AIRPORT_SCENARIO);
    run_whole(bencher, &building, &scenario);
}

/// `rings` one-way rings of 8 vertices 3 m apart (a 9 m × 3 m rectangle), 20 m apart, in
/// cartesian metres; each ring carries two robots (the last one, when n is odd, one).
fn rings_map(rings: usize) -> String {
    const RING: [(i32, i32); 8] = [
        (0, 0),
        (3, 0),
        (6, 0),
        (9, 0),
        (9, 3),
        (6, 3),
        (3, 3),
        (0, 3),
    ];
    let mut s = String::from(
        "coordinate_system: cartesian_meters\nname: rings\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n",
    );
    for r in 0..rings {
        let (ox, oy) = (20 * (r % 10) as i32, 10 * (r / 10) as i32);
        for (k, (x, y)) in RING.iter().enumerate() {
            s += &format!("      - [{}, {}, 0, r{r}_{k}]\n", x + ox, y + oy);
        }
    }
    s += "    lanes:\n";
    for r in 0..rings {
        for k in 0..8 {
            let (a, b) = (r * 8 + k, r * 8 + (k + 1) % 8);
            s += &format!("      - [{a}, {b}, {{bidirectional: [4, false], graph_idx: [2, 0]}}]\n");
        }
    }
    s
}

/// n robots, two per ring, starting on opposite corners, each looping between the corners
/// (the one-way ring makes them follow each other round).
fn rings_scenario(n: usize) -> String {
    let spawns: Vec<String> = (0..n)
        .map(|i| format!("r{}_{}", i / 2, 4 * (i % 2)))
        .collect();
    let mut s = format!(
        "seed: 1\nduration: 10min\nfleets:\n  - {{name: ring, robot: TinyRobot, count: {n}, spawn: [{}]}}\ntasks:\n",
        spawns.join(", ")
    );
    for i in 0..n {
        let r = i / 2;
        s += &format!("  - {{at: 0, loop: {{start: r{r}_0, finish: r{r}_4, loops: 1000}}}}\n");
    }
    s
}

#[divan::bench(args = [5, 20, 80], sample_count = 3, sample_size = 1)]
fn rings_10min(bencher: Bencher, n: usize) {
    let (building, scenario) = load(&rings_map(n.div_ceil(2)), &rings_scenario(n));
    run_whole(bencher, &building, &scenario);
}

/// `robots` tiny robots placed by `spawn: auto` on the warehouse with `racks`, and loops
/// between two random racks: one for every robot in the first ten seconds, then one every
/// 0.4 s for `minutes` (a robot takes about 9 minutes for one: more than the fleet serves).
fn warehouse_scenario(racks: &[String], robots: usize, minutes: usize) -> String {
    let mut s = format!(
        "seed: 1\nduration: {minutes}min\ncrowd: {{enabled: false}}\nfleets:\n  - {{name: pickers, graph: 0, robot: TinyRobot, count: {robots}, spawn: auto, tasks: [loop]}}\ntasks:\n"
    );
    // A fixed linear congruential sequence: the same tasks on every run.
    let mut x: u64 = 1;
    let mut next = |n: usize| {
        x = x
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((x >> 33) % n as u64) as usize
    };
    let times = (0..robots)
        .map(|k| k as f64 * 10.0 / robots as f64)
        .chain((0..minutes * 150).map(|k| 10.0 + k as f64 * 0.4));
    for at in times {
        let a = next(racks.len());
        let b = (a + 1 + next(racks.len() - 1)) % racks.len();
        s += &format!(
            "  - {{at: {at:.2}s, loop: {{start: {}, finish: {}, loops: 1}}}}\n",
            racks[a], racks[b]
        );
    }
    s
}

/// 1,000 robots on a generated warehouse of 10,188 waypoints (36 one-way aisles of 189,
/// 48 one-way cross aisles, 3,384 bays, half of them racks: `warehouse::bays`), tasks
/// arriving faster than the fleet serves them: issue 35 asks for at least 10× real time
/// over an hour with every robot busy (figures in BENCHMARKS.md). `args` are simulated
/// minutes: one, and the hour the issue asks for.
#[divan::bench(args = [1, 60], sample_count = 1, sample_size = 1)]
fn warehouse_1000(bencher: Bencher, minutes: usize) {
    let (map, racks) = warehouse::bays(36, 189, "warehouse");
    let (building, scenario) = load(&map, &warehouse_scenario(&racks, 1000, minutes));
    run_whole(bencher, &building, &scenario);
}
