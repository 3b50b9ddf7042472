//! `mapc sim` through the binary: malformed scenarios give located diagnostics and exit 1
//! (never a panic), usage and I/O problems exit 2, the fixture scenarios run and write a
//! trace and a report that are identical between runs, and the scenarios in docs/sim.md
//! parse and name waypoints that exist in the demo maps (when ../shared is present).

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

struct Out {
    code: i32,
    stdout: String,
    stderr: String,
}

fn run(args: &[&str]) -> Out {
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(root())
        .arg("sim")
        .args(args)
        .output()
        .unwrap();
    Out {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// The JSON diagnostics of a run (`--format json`), as (code, line, column).
fn json_diags(stdout: &str) -> Vec<(String, u64, u64)> {
    stdout
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter(|v| v.get("severity").is_some())
        .map(|v| {
            let loc = &v["location"];
            (
                v["code"].as_str().unwrap_or("").to_string(),
                loc["line"].as_u64().unwrap_or(0),
                loc["column"].as_u64().unwrap_or(0),
            )
        })
        .collect()
}

#[test]
fn malformed_scenarios_exit_1_with_located_diagnostics() {
    let dir = tempfile::tempdir().unwrap();
    let bomb = "a: &a [x, x, x, x, x, x, x, x, x, x]\nb: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a, *a]\nc: &c [*b, *b, *b, *b, *b, *b, *b, *b, *b, *b]\nd: &d [*c, *c, *c, *c, *c, *c, *c, *c, *c, *c]\ne: &e [*d, *d, *d, *d, *d, *d, *d, *d, *d, *d]\nf: [*e, *e, *e, *e, *e, *e, *e, *e, *e, *e]\n";
    let mut garbage = vec![0u8; 4096];
    let mut x: u32 = 12345;
    for b in &mut garbage {
        x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
        *b = (x >> 16) as u8;
    }
    let cases: Vec<(&str, Vec<u8>, &str, u64)> = vec![
        ("empty", Vec::new(), "S0001", 1),
        ("wrong type", b"duration: 1h\nfleets: 3\n".to_vec(), "S0101", 2),
        (
            "missing key",
            b"duration: 1h\nfleets:\n  - {name: a, count: 1}\n".to_vec(),
            "S0102",
            3,
        ),
        ("alias bomb", bomb.as_bytes().to_vec(), "S0002", 0),
        (
            "deep nesting",
            format!("x: {}{}\n", "[".repeat(100), "]".repeat(100)).into_bytes(),
            "S0002",
            1,
        ),
        (
            "huge numbers",
            b"duration: 1e308\nfleets: [{name: a, robot: TinyRobot, count: 99999999999999999999}]\n"
                .to_vec(),
            "S0109",
            1,
        ),
        ("binary garbage", garbage, "", 0),
        (
            "bad duration",
            b"duration: 8 hours\nfleets: [{name: a, robot: TinyRobot, count: 1}]\n".to_vec(),
            "S0105",
            1,
        ),
        (
            "unknown preset",
            b"duration: 1h\nfleets: [{name: a, robot: TinyBot, count: 1}]\n".to_vec(),
            "S0301",
            2,
        ),
    ];
    for (name, bytes, code, line) in cases {
        let p = write(dir.path(), "s.scenario.yaml", &bytes);
        let p = p.to_str().unwrap();
        let human = run(&[p]);
        assert_eq!(human.code, 1, "{name}: {}", human.stderr);
        assert!(
            !human.stderr.contains("panicked"),
            "{name}: {}",
            human.stderr
        );
        assert!(
            human.stderr.contains("invalid scenario, nothing simulated"),
            "{name}: {}",
            human.stderr
        );
        let json = run(&[p, "--format", "json"]);
        assert_eq!(json.code, 1, "{name}");
        let diags = json_diags(&json.stdout);
        assert!(!diags.is_empty(), "{name}: {}", json.stdout);
        for (c, l, col) in &diags {
            assert!(c.starts_with('S'), "{name}: {c}");
            assert!(*l >= 1 && *col >= 1, "{name}: {c} has no position");
        }
        if !code.is_empty() {
            assert!(
                diags
                    .iter()
                    .any(|(c, l, _)| c == code && (line == 0 || *l == line)),
                "{name}: want {code} on line {line}, got {diags:?}"
            );
        }
    }
}

#[test]
fn usage_and_io_problems_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope.scenario.yaml");
    let r = run(&[missing.to_str().unwrap()]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    // No map in the scenario and no --map.
    let p = write(
        dir.path(),
        "nomap.scenario.yaml",
        b"duration: 1h\nfleets: [{name: a, robot: TinyRobot, count: 1}]\n",
    );
    let r = run(&[p.to_str().unwrap()]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(r.stderr.contains("--map"), "{}", r.stderr);
    // A map that does not exist.
    let r = run(&[p.to_str().unwrap(), "--map", "fixtures/none.building.yaml"]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    // A bad --until.
    let r = run(&["fixtures/legacy_2019.scenario.yaml", "--until", "5 parsecs"]);
    assert_eq!(r.code, 2, "{}", r.stderr);
}

#[test]
fn invalid_map_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "s.scenario.yaml",
        b"duration: 1min\nfleets: [{name: a, robot: TinyRobot, count: 1}]\n",
    );
    let map = root().join("fixtures/invalid/E0103-lane-index-out-of-range.building.yaml");
    let r = run(&[p.to_str().unwrap(), "--map", map.to_str().unwrap()]);
    assert_eq!(r.code, 1, "{}", r.stderr);
    assert!(r.stderr.contains("E0103"), "{}", r.stderr);
    assert!(
        r.stderr.contains("invalid map, nothing simulated"),
        "{}",
        r.stderr
    );
}

#[test]
fn scenario_not_fitting_the_map_exits_1_with_its_location() {
    let dir = tempfile::tempdir().unwrap();
    let map = root().join("fixtures/two_level_clinic.building.yaml");
    let text = format!(
        "map: {}\nduration: 1min\nfleets: [{{name: a, robot: TinyRobot, spawn: [no_such_waypoint]}}]\n",
        map.display()
    );
    let p = write(dir.path(), "s.scenario.yaml", text.as_bytes());
    let r = run(&[p.to_str().unwrap(), "--format", "json"]);
    assert_eq!(r.code, 1, "{}{}", r.stdout, r.stderr);
    let diags = json_diags(&r.stdout);
    // The fleet layer's diagnostic points into the scenario file, line 3.
    assert!(
        diags
            .iter()
            .any(|(c, l, _)| c.starts_with("S02") && *l == 3),
        "{diags:?}"
    );
    assert!(r.stdout.contains("s.scenario.yaml"), "{}", r.stdout);
}

#[test]
fn fixture_scenarios_run_and_are_deterministic() {
    let dir = tempfile::tempdir().unwrap();
    let mut any = false;
    for entry in std::fs::read_dir(root().join("fixtures")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        if !name.ends_with(".scenario.yaml") {
            continue;
        }
        any = true;
        let mut outputs = Vec::new();
        for k in 0..2 {
            let trace = dir.path().join(format!("{name}.{k}.jsonl"));
            let report = dir.path().join(format!("{name}.{k}.json"));
            let r = run(&[
                path.to_str().unwrap(),
                "--trace",
                trace.to_str().unwrap(),
                "--report",
                report.to_str().unwrap(),
            ]);
            assert_eq!(r.code, 0, "{name}: {}", r.stderr);
            assert!(r.stdout.contains("simulated "), "{name}: {}", r.stdout);
            outputs.push((
                std::fs::read(&trace).unwrap(),
                std::fs::read(&report).unwrap(),
            ));
        }
        assert!(outputs[0] == outputs[1], "{name}: two runs differ");
        let (trace, report) = &outputs[0];
        // Every trace line is {"t", "topic", "msg"} in that order, times never decrease.
        let text = std::str::from_utf8(trace).unwrap();
        let mut last = 0.0;
        let mut lines = 0;
        for line in text.lines() {
            assert!(line.starts_with("{\"t\":"), "{name}: {line}");
            let v: serde_json::Value = serde_json::from_str(line).unwrap();
            let t = v["t"].as_f64().unwrap();
            assert!(t >= last, "{name}: time goes back at {line}");
            last = t;
            assert!(v["topic"].as_str().unwrap().starts_with('/'));
            assert!(v["msg"].is_object());
            let topic_pos = line.find("\"topic\"").unwrap();
            assert!(topic_pos < line.find("\"msg\"").unwrap());
            lines += 1;
        }
        assert!(lines > 0, "{name}: empty trace");
        // The report's task list agrees with the task events of the trace.
        let report: serde_json::Value = serde_json::from_slice(report).unwrap();
        let completed_events = text
            .lines()
            .filter(|l| {
                l.contains("\"topic\":\"/task_events\"") && l.contains("\"event\":\"completed\"")
            })
            .count();
        let completed_tasks = report["tasks"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|t| t["result"] == "completed")
            .count();
        assert_eq!(completed_events, completed_tasks, "{name}");
        // Every example scenario is sized to finish: each task completes (a robot parked
        // past a one-way lane once left the warehouse's later tasks unreachable).
        let tasks = report["tasks"].as_array().unwrap();
        assert_eq!(completed_tasks, tasks.len(), "{name}: {tasks:?}");
        assert!(report["end_time"].as_f64().unwrap() <= last + 1.0);
    }
    assert!(any, "no fixtures/*.scenario.yaml");
}

#[test]
fn until_stops_early_and_json_format_ends_with_the_report() {
    let r = run(&[
        "fixtures/two_level_clinic.scenario.yaml",
        "--until",
        "90s",
        "--format",
        "json",
    ]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let last = r.stdout.lines().last().unwrap();
    let v: serde_json::Value = serde_json::from_str(last).unwrap();
    let end = v["report"]["end_time"].as_f64().unwrap();
    // 90 s in 0.01 s steps; the end time is the time after the last step.
    assert!((end - 90.0).abs() < 0.011, "{end}");
}

/// YAML code blocks of docs/sim.md that are whole scenarios (they have `fleets:`).
fn doc_scenarios() -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(root().join("docs/sim.md")).unwrap();
    let mut out = Vec::new();
    let mut block: Option<(usize, String)> = None;
    for (i, line) in text.lines().enumerate() {
        match &mut block {
            None if line.trim_start() == "```yaml" => block = Some((i + 2, String::new())),
            Some((start, b)) if line.trim_start() == "```" => {
                if b.contains("\nfleets:") || b.starts_with("fleets:") {
                    out.push((*start, std::mem::take(b)));
                }
                block = None;
            }
            Some((_, b)) => {
                b.push_str(line);
                b.push('\n');
            }
            None => {}
        }
    }
    out
}

#[test]
fn docs_scenarios_parse_and_name_real_waypoints() {
    let blocks = doc_scenarios();
    assert!(
        blocks.len() >= 4,
        "expected the format example and three demo scenarios"
    );
    let shared = root().join("../shared/maps");
    let tmp = tempfile::tempdir().unwrap();
    let mut checked = 0;
    for (line, text) in blocks {
        // A fleet from a config in ../shared (the RMF deployment example) needs it to read.
        if text.contains("config: ../shared/") && !shared.is_dir() {
            println!("skipped: ../shared not found");
            continue;
        }
        let (scenario, diags) = mapc_sim::parse_scenario(mapc_ir::FileId(0), &text, root());
        let errors: Vec<_> = diags.iter().filter(|d| d.is_error()).collect();
        assert!(errors.is_empty(), "docs/sim.md:{line}: {errors:#?}");
        assert!(diags.is_empty(), "docs/sim.md:{line}: warnings {diags:#?}");
        let scenario = scenario.unwrap();
        let Some(map) = &scenario.map else { continue };
        if !map.to_string_lossy().contains("../shared/maps/") {
            continue; // the format example names a made-up map
        }
        if !shared.is_dir() {
            println!("skipped: ../shared not found");
            continue;
        }
        let parsed = mapc_frontend::load(map).unwrap();
        let building = parsed.building.expect("demo map reads");
        let names: std::collections::BTreeSet<&str> = building
            .vertices
            .iter()
            .map(|(_, v)| v.name.as_str())
            .filter(|n| !n.is_empty())
            .collect();
        for w in waypoints(&scenario) {
            assert!(
                names.contains(w.as_str()),
                "docs/sim.md:{line}: waypoint `{w}` is not in {}",
                map.display()
            );
        }
        // A scenario naming files relative to itself (the RMF deployment example) is run
        // by sim/tests/rmf_shared_configs.rs and the docs' own commands, not from a copy.
        if text.contains("config: ") {
            continue;
        }
        // And the runtime accepts it on the map (graphs, spawn points): a short run.
        let r = run(&[
            "--map",
            map.to_str().unwrap(),
            "--until",
            "1min",
            &write_tmp(tmp.path(), &text),
        ]);
        assert_eq!(r.code, 0, "docs/sim.md:{line}: {}", r.stderr);
        checked += 1;
    }
    if shared.is_dir() {
        assert_eq!(checked, 3, "office, hotel and clinic");
    }
}

fn write_tmp(dir: &std::path::Path, text: &str) -> String {
    let n = text.len();
    let p = dir.join(format!("doc{n}.scenario.yaml"));
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

fn waypoints(s: &mapc_sim::Scenario) -> Vec<String> {
    use mapc_sim::{SpawnSpec, TaskKind};
    let mut out = Vec::new();
    for f in &s.fleets {
        if let SpawnSpec::Waypoints(w) = &f.spawn {
            out.extend(w.iter().cloned());
        }
    }
    out.extend(s.workcells.iter().map(|w| w.waypoint.clone()));
    let kinds = s
        .tasks
        .iter()
        .map(|t| &t.kind)
        .chain(s.generators.iter().map(|g| &g.kind));
    for k in kinds {
        match k {
            TaskKind::Loop { start, finish, .. } => out.extend([start.clone(), finish.clone()]),
            TaskKind::Delivery {
                pickup, dropoff, ..
            } => out.extend([pickup.clone(), dropoff.clone()]),
            TaskKind::Clean { zone } => out.push(zone.clone()),
            TaskKind::GoToPlace { place } => out.push(place.clone()),
            TaskKind::Patrol { places, .. } => out.extend(places.iter().cloned()),
        }
    }
    out
}

/// Truncations and byte mutations of every fixture scenario: the parser never panics, and
/// every diagnostic has a position in the file.
#[test]
fn mutated_scenarios_never_panic() {
    let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let mut cases = 0;
    for entry in std::fs::read_dir(root().join("fixtures")).unwrap() {
        let path = entry.unwrap().path();
        if !path.to_string_lossy().ends_with(".scenario.yaml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let mut inputs: Vec<String> = Vec::new();
        for cut in (0..text.len()).step_by(5) {
            if text.is_char_boundary(cut) {
                inputs.push(text[..cut].to_string());
            }
        }
        let pieces = [
            "", ":", "-", "[", "]", "{", "}", "&a", "*a", "!!str ", "\t", "\n", "1e999", "-1", "~",
            "0", "TinyBot", "\"", "'", "#", "?", ",",
        ];
        for _ in 0..400 {
            let mut bytes = text.clone().into_bytes();
            for _ in 0..(next() % 4 + 1) {
                let at = (next() as usize) % (bytes.len() + 1);
                let piece = pieces[(next() as usize) % pieces.len()].as_bytes();
                let del = ((next() % 6) as usize).min(bytes.len() - at.min(bytes.len()));
                bytes.splice(at..at + del, piece.iter().copied());
            }
            inputs.push(String::from_utf8_lossy(&bytes).into_owned());
        }
        for input in inputs {
            let (s, d) = mapc_sim::parse_scenario(mapc_ir::FileId(0), &input, root());
            for x in &d {
                assert!(
                    x.span.line >= 1 && x.span.col >= 1 && (x.span.end as usize) <= input.len(),
                    "{x:?} in {input:?}"
                );
            }
            assert_eq!(s.is_some(), !mapc_ir::has_errors(&d), "{input:?}");
            cases += 1;
        }
    }
    assert!(cases > 1000, "{cases}");
}

#[test]
fn outputs_are_all_or_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let trace = out.join("trace.jsonl");
    let report = out.join("report.json");
    // A scenario that does not fit the map: the run never starts, nothing is left behind
    // (the trace's temporary file is removed).
    let map = root().join("fixtures/two_level_clinic.building.yaml");
    let text = format!(
        "map: {}\nduration: 1min\nfleets: [{{name: a, robot: TinyRobot, spawn: [nowhere]}}]\n",
        map.display()
    );
    let p = write(dir.path(), "s.scenario.yaml", text.as_bytes());
    let args = [
        p.to_str().unwrap(),
        "--trace",
        trace.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ];
    let r = run(&args);
    assert_eq!(r.code, 1, "{}", r.stderr);
    let left: Vec<_> = std::fs::read_dir(&out).unwrap().collect();
    assert!(left.is_empty(), "{left:?}");
    // A trace path under a regular file cannot be created: I/O error, exit 2.
    let blocker = write(dir.path(), "file", b"x");
    let r = run(&[
        "fixtures/legacy_2019.scenario.yaml",
        "--trace",
        blocker.join("trace.jsonl").to_str().unwrap(),
    ]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    // A successful run leaves exactly the two files.
    let r = run(&[
        "fixtures/legacy_2019.scenario.yaml",
        "--trace",
        trace.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let mut left: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["report.json", "trace.jsonl"]);
}
