//! Fleets from RMF fleet adapter configs (issue 38): the robots start where the config
//! says with its names, drive within its limits, and their batteries drain as RMF's
//! rmf_battery computes it.

use mapc_sim::{parse_scenario, simulate, Report, RunOptions};
use serde_json::Value;
use std::path::Path;

/// Runs scenario `text` (read as if it were in `dir`) on `map`; the report and the trace.
fn run(dir: &Path, text: &str, map: &Path) -> (Report, Vec<Value>) {
    let (scenario, diags) = parse_scenario(mapc_ir::FileId(0), text, dir);
    let scenario = scenario.unwrap_or_else(|| panic!("{diags:#?}"));
    let map = mapc_frontend::load(map).expect("map");
    let building = map
        .valid_building()
        .unwrap_or_else(|| panic!("invalid map: {:#?}", map.diagnostics));
    let mut trace = Vec::new();
    let report = simulate(
        building,
        &scenario,
        RunOptions {
            trace: Some(&mut trace),
            trace_filter: mapc_sim::TraceFilter::new(
                Some([mapc_sim::msgs::Topic::RobotState].into_iter().collect()),
                0.0,
            ),
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e:?}"));
    let lines = String::from_utf8(trace)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    (report, lines)
}

fn fixtures() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

/// Per robot: (first position, top speed, top acceleration) from its RobotState messages
/// (2 Hz; speeds from the distance between consecutive positions on one level;
/// accelerations only along straight stretches, where a chord is the path).
fn motion(trace: &[Value]) -> std::collections::BTreeMap<String, ([f64; 2], f64, f64)> {
    // Per robot: (t, x, y, level, speed, direction of the last displacement).
    type Last = (f64, f64, f64, String, Option<f64>, Option<(f64, f64)>);
    let mut last: std::collections::BTreeMap<String, Last> = Default::default();
    let mut out: std::collections::BTreeMap<String, ([f64; 2], f64, f64)> = Default::default();
    for v in trace {
        let m = &v["msg"];
        let name = m["name"].as_str().unwrap().to_string();
        let t = v["t"].as_f64().unwrap();
        let l = &m["location"];
        let (x, y) = (l["x"].as_f64().unwrap(), l["y"].as_f64().unwrap());
        let level = l["level_name"].as_str().unwrap_or("").to_string();
        let e = out.entry(name.clone()).or_insert(([x, y], 0.0, 0.0));
        let mut next = (t, x, y, level.clone(), None, None);
        if let Some((t0, x0, y0, lv, v0, dir0)) = last.get(&name) {
            let dt = t - t0;
            if dt > 0.2 && *lv == level {
                let dist = (x - x0).hypot(y - y0);
                let speed = dist / dt;
                e.1 = e.1.max(speed);
                let dir = (dist > 1e-6).then(|| ((x - x0) / dist, (y - y0) / dist));
                let straight = match (dir, dir0) {
                    (Some(a), Some(b)) => a.0 * b.0 + a.1 * b.1 > 0.9999,
                    // Setting off from rest, or stopping.
                    (None, _) | (_, None) => true,
                };
                // (No speed before the first interval.)
                if let (true, Some(v0)) = (straight, v0) {
                    e.2 = e.2.max((speed - v0).abs() / dt);
                }
                next = (t, x, y, level, Some(speed), dir);
            }
        }
        last.insert(name, next);
    }
    out
}

#[test]
fn config_robots_start_at_their_chargers_and_drive_by_its_limits() {
    let dir = fixtures().join("rmf");
    let text = std::fs::read_to_string(dir.join("warehouse.scenario.yaml")).unwrap();
    let (report, trace) = run(
        &dir,
        &text,
        &fixtures().join("cartesian_warehouse.building.yaml"),
    );
    let names: Vec<&str> = report.robots.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, ["mover_1", "mover_2"]);
    let m = motion(&trace);
    // charger_a and dropoff of the warehouse (map metres).
    let start = |n: &str| m[n].0;
    // (The first state is at 0.5 s: a robot may have left by up to a·t²/2 = 0.05 m.)
    let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) < 0.06;
    assert!(
        near(start("mover_1"), [25002.0, 31002.0]),
        "{:?}",
        start("mover_1")
    );
    assert!(
        near(start("mover_2"), [25010.0, 31010.0]),
        "{:?}",
        start("mover_2")
    );
    let top = m.values().map(|x| x.1).fold(0.0, f64::max);
    let acc = m.values().map(|x| x.2).fold(0.0, f64::max);
    // limits.linear: [0.8, 0.4]. Both loops of aisle_1 <-> pickup drive at full speed.
    assert!(top <= 0.8 + 1e-6 && top > 0.75, "top speed {top}");
    assert!(acc <= 0.4 + 0.02 && acc > 0.3, "top acceleration {acc}");
    let done = report
        .tasks
        .iter()
        .filter(|t| t.result == "completed")
        .count();
    assert_eq!(done, 2, "{:#?}", report.tasks);
}

#[test]
fn the_older_template_runs_too() {
    let dir = fixtures().join("rmf");
    let text = "map: ../cartesian_warehouse.building.yaml\nduration: 5min\nfleets:\n  - {config: movers_legacy_config.yaml}\ntasks:\n  - {at: 0, go_to_place: dock_in}\n";
    let (report, trace) = run(
        &dir,
        text,
        &fixtures().join("cartesian_warehouse.building.yaml"),
    );
    assert_eq!(report.robots[0].name, "legacy_1");
    let m = motion(&trace);
    // hold_a, its start waypoint (its charger is charger_a).
    let s = m["legacy_1"].0;
    assert!(
        (s[0] - 25005.0).abs() < 0.06 && (s[1] - 31002.0).abs() < 0.06,
        "{s:?}"
    );
    assert!(m["legacy_1"].1 <= 0.6 + 1e-6 && m["legacy_1"].1 > 0.55);
    assert_eq!(report.tasks[0].result, "completed");
}

/// rmf_battery, worked out by hand for the movers' config: ambient 30 W + tool 10 W drain
/// all the time (SimpleDevicePowerSink: ΔE = P·t); driving adds, by SimpleMotionPowerSink,
/// friction μ·m·g·v·dt over the distance (μ·m·g·d) and m·a·v·dt while the speed changes
/// (m·v²/2 up to speed plus m·v²/2 braking, per stop); ΔSoC = ΔE / V / (Ah · 3600).
#[test]
fn battery_drain_follows_rmf_battery_by_hand() {
    let dir = fixtures().join("rmf");
    // One robot away from the charger: idle for 5 minutes, then 10 m along the aisle to
    // aisle_2 (through the pass-through point pass_1), and the run ends with the task.
    let text = "map: ../cartesian_warehouse.building.yaml\nduration: 1h\nfleets:\n  - {config: movers_config.yaml, count: 1, spawn: [aisle_1]}\ntasks:\n  - {at: 5min, go_to_place: aisle_2}\noptions: {stop_when_done: true}\n";
    let (report, trace) = run(
        &dir,
        text,
        &fixtures().join("cartesian_warehouse.building.yaml"),
    );
    let t = report.end_time;
    let r = &report.robots[0];
    let d = r.distance_m;
    // ∫ m·a·v dt = m·Δ(v²)/2 while the speed only rises or only falls: m/2 times the
    // total variation of v² (speeds between consecutive 2 Hz states, 0 at both ends).
    let mut speeds = vec![0.0];
    let mut last: Option<(f64, f64, f64)> = None;
    for v in &trace {
        let l = &v["msg"]["location"];
        let (tt, x, y) = (
            v["t"].as_f64().unwrap(),
            l["x"].as_f64().unwrap(),
            l["y"].as_f64().unwrap(),
        );
        if let Some((t0, x0, y0)) = last {
            speeds.push((x - x0).hypot(y - y0) / (tt - t0));
        }
        last = Some((tt, x, y));
    }
    speeds.push(0.0);
    let variation: f64 = speeds
        .windows(2)
        .map(|w| (w[1] * w[1] - w[0] * w[0]).abs())
        .sum();
    // Config: V = 24 V, 30 Ah, m = 50 kg, μ = 0.2, ambient 30 W + tool 10 W.
    let (volt, ah, m, mu, p) = (24.0, 30.0, 50.0, 0.2, 40.0);
    let accel = m / 2.0 * variation;
    let energy = p * t + mu * m * 9.81 * d + accel;
    let want = energy / volt / (ah * 3600.0);
    let got = 1.0 - r.battery_soc;
    // Turning in place (I·α·ω) adds I·ω² = 15 · 0.7² ≈ 7 J a turn, under 0.1 % here.
    eprintln!(
        "{t} s, {d} m: 40 W·{t} s + 0.2·50·9.81·{d} + {accel} J = {energy} J, ΔSoC {want} by hand, {got} simulated"
    );
    assert!(t > 300.0 && t < 400.0, "ran {t} s");
    assert!(d > 10.0, "drove {d} m");
    assert!(
        (got - want).abs() < 0.01 * want,
        "ΔSoC {got} vs {want} by hand ({t} s, {d} m)"
    );
}

/// Per robot, its last RobotState: (x, y, mode, battery percent).
fn last_states(trace: &[Value]) -> std::collections::BTreeMap<String, [f64; 4]> {
    let mut out = std::collections::BTreeMap::new();
    for v in trace {
        let m = &v["msg"];
        let l = &m["location"];
        let now = [
            l["x"].as_f64().unwrap(),
            l["y"].as_f64().unwrap(),
            m["mode"]["mode"].as_f64().unwrap(),
            m["battery_percent"].as_f64().unwrap(),
        ];
        out.insert(m["name"].as_str().unwrap().to_string(), now);
    }
    out
}

/// A scenario on fixtures/rmf/finishing.building.yaml with the fleet of `config` and
/// `tasks`, run for `duration`.
fn run_finishing(config: &str, count: usize, tasks: &str, duration: &str) -> (Report, Vec<Value>) {
    let dir = fixtures().join("rmf");
    let text = format!(
        "map: finishing.building.yaml\nseed: 1\nduration: {duration}\nfleets:\n  - {{config: {config}, graph: 0, count: {count}}}\ntasks:\n{tasks}"
    );
    run(&dir, &text, &dir.join("finishing.building.yaml"))
}

fn completed(report: &Report) -> usize {
    report
        .tasks
        .iter()
        .filter(|t| t.result == "completed")
        .count()
}

fn at(s: &[f64; 4], x: f64, y: f64) -> bool {
    (s[0] - x).hypot(s[1] - y) < 0.1
}

#[test]
fn charge_and_park_finishing_requests_end_at_the_robots_spots() {
    // bot_1 (`charge`, the fleet's) starts at charger_1 (5, -4), bot_2 (`park` at
    // park_spot, its own) at charger_2 (15, -4); one loop each to the far ends.
    let (report, trace) = run_finishing(
        "finishing_config.yaml",
        2,
        "  - {at: 0, loop: {start: east_end, finish: west_end, loops: 1}}\n  - {at: 0, loop: {start: west_end, finish: east_end, loops: 1}}\n",
        "10min",
    );
    assert_eq!(completed(&report), 2, "{:#?}", report.tasks);
    let s = last_states(&trace);
    let soc = |n: &str| {
        report
            .robots
            .iter()
            .find(|r| r.name == n)
            .unwrap()
            .battery_soc
    };
    let b1 = s["bot_1"];
    // Back on its charger, charging (robot_mode CHARGING = 1): its battery is full again
    // (20 W for 10 min alone is 1.2 % of its 288 Wh).
    assert!(at(&b1, 5.0, -4.0), "bot_1 ends at {b1:?}");
    assert_eq!(b1[2], 1.0, "bot_1's mode");
    assert!(soc("bot_1") > 0.9999, "bot_1's battery {}", soc("bot_1"));
    // On its parking spot (10, 4), which is no charger: idle, its battery drained.
    let b2 = s["bot_2"];
    assert!(at(&b2, 10.0, 4.0), "bot_2 ends at {b2:?}");
    assert_ne!(b2[2], 1.0, "bot_2's mode");
    assert!(soc("bot_2") < 0.99, "bot_2's battery {}", soc("bot_2"));
}

#[test]
fn nothing_stays_on_a_dead_end_place_no_route_needs() {
    // bay_e (15, 4) is a dead end beside the corridor: the robot stays there. (Without a
    // config it would drive on to the nearest parking vertex, east_end.)
    let (report, trace) = run_finishing(
        "nothing_config.yaml",
        1,
        "  - {at: 0, loop: {start: west_end, finish: bay_e, loops: 1}}\n",
        "10min",
    );
    assert_eq!(completed(&report), 1, "{:#?}", report.tasks);
    let b1 = last_states(&trace)["bot_1"];
    assert!(at(&b1, 15.0, 4.0), "bot_1 ends at {b1:?}");
}

#[test]
fn nothing_moves_off_a_corridor_place_others_need() {
    // `middle` (10, 0) is the only way between the corridor's halves: the robot whose
    // task ends there moves off, and the other's loops through it all complete.
    let (report, trace) = run_finishing(
        "nothing_config.yaml",
        2,
        "  - {at: 0, loop: {start: bay_w, finish: middle, loops: 1}}\n  - {at: 0, loop: {start: west_end, finish: east_end, loops: 3}}\n  - {at: 4min, loop: {start: east_end, finish: west_end, loops: 2}}\n",
        "20min",
    );
    assert_eq!(completed(&report), 3, "{:#?}", report.tasks);
    let s = last_states(&trace);
    for (name, b) in &s {
        assert!(!at(b, 10.0, 0.0), "{name} ends on `middle`: {b:?}");
    }
    assert!(report.stuck.is_empty(), "{:#?}", report.stuck);
}

#[test]
fn a_parking_spot_on_a_corridor_is_refused_with_a_warning() {
    // bot_1 asks to park on `middle`: a robot standing there would cut the corridor, so
    // it parks where no route needs it, and the report says why (S0210).
    let (report, trace) = run_finishing(
        "corridor_park_config.yaml",
        1,
        "  - {at: 0, loop: {start: west_end, finish: east_end, loops: 1}}\n",
        "10min",
    );
    assert_eq!(completed(&report), 1, "{:#?}", report.tasks);
    let w: Vec<_> = report
        .warnings
        .iter()
        .filter(|w| w.code == "S0210" && w.message.contains("`bot_1`"))
        .collect();
    assert_eq!(w.len(), 1, "{:#?}", report.warnings);
    assert!(
        w[0].message.contains("`middle`") && w[0].message.contains("only way to"),
        "{}",
        w[0].message
    );
    let b1 = last_states(&trace)["bot_1"];
    assert!(!at(&b1, 10.0, 0.0), "bot_1 ends on `middle`: {b1:?}");
}
