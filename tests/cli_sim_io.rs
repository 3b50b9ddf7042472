//! Issue 11, runs that are lost: `mapc sim` checks its output paths before simulating,
//! stops cleanly on Ctrl-C (report marked interrupted, partial trace under its final name,
//! summary, exit 130), filters and rate-limits the trace, writes `.jsonl.zst`, keeps the
//! report's documented key order in JSON, and refuses a building map given as scenario.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn mapc(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(root())
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

const SCENARIO: &str = "fixtures/two_level_clinic.scenario.yaml";

/// The clinic scenario, running until `--until` instead of stopping when its tasks are done.
fn long_scenario(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join(SCENARIO)).unwrap();
    let map = root().join("fixtures/two_level_clinic.building.yaml");
    let text = text
        .replace(
            "map: two_level_clinic.building.yaml",
            &format!("map: {}", map.display()),
        )
        .replace("stop_when_done: true", "stop_when_done: false");
    let p = dir.join("long.scenario.yaml");
    std::fs::write(&p, text).unwrap();
    p
}

fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".mapc-tmp-"))
        .collect()
}

#[test]
fn unwritable_report_fails_before_simulating() {
    let dir = tempfile::tempdir().unwrap();
    let afile = dir.path().join("afile");
    std::fs::write(&afile, "x").unwrap();
    let report = afile.join("report.json");
    let scenario = long_scenario(dir.path());
    let start = std::time::Instant::now();
    // 1000 h would take minutes: failing fast proves nothing was simulated.
    let (code, out, err) = mapc(&[
        "sim",
        scenario.to_str().unwrap(),
        "--until",
        "1000h",
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--report"), "{err}");
    assert!(err.contains("afile` is a file"), "{err}");
    assert!(err.contains("nothing simulated"), "{err}");
    assert!(out.is_empty());
    assert!(start.elapsed().as_secs() < 20);
    // A directory as trace file.
    let (code, _, err) = mapc(&["sim", SCENARIO, "--trace", dir.path().to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("is a directory; --trace must be a file path"),
        "{err}"
    );
}

/// A report or trace sent to a FIFO (as `--report >(jq ...)` or `/dev/stdout` do) is written
/// into it, not replaced by a file renamed over it: run as root with `--report /dev/null`,
/// a rename had turned `/dev/null` itself into a regular file.
#[cfg(unix)]
#[test]
fn outputs_into_a_fifo_are_written_in_place() {
    use std::io::Read;
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let fifo = |name: &str| {
        let p = dir.path().join(name);
        assert!(Command::new("mkfifo").arg(&p).status().unwrap().success());
        p
    };
    let (report, trace) = (fifo("report"), fifo("trace"));
    let reader = |p: PathBuf| {
        std::thread::spawn(move || {
            let mut s = String::new();
            std::fs::File::open(&p)
                .unwrap()
                .read_to_string(&mut s)
                .unwrap();
            s
        })
    };
    let (r, t) = (reader(report.clone()), reader(trace.clone()));
    let scenario = long_scenario(dir.path());
    let (code, _, err) = mapc(&[
        "sim",
        scenario.to_str().unwrap(),
        "--until",
        "30s",
        "--report",
        report.to_str().unwrap(),
        "--trace",
        trace.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    // Checked before the readers are joined: a FIFO replaced by a file is never opened for
    // writing, and its reader would wait for ever.
    for p in [&report, &trace] {
        let kind = std::fs::symlink_metadata(p).unwrap().file_type();
        assert!(kind.is_fifo(), "{} is no longer a FIFO", p.display());
    }
    let report_text = r.join().unwrap();
    let json: serde_json::Value = serde_json::from_str(&report_text).unwrap();
    assert_eq!(json["end_time"], 30.0);
    let trace_text = t.join().unwrap();
    assert!(trace_text.lines().count() > 10, "{trace_text}");
    assert!(temporaries(dir.path()).is_empty());
}

/// Runs mapc, and once the run is under way (its temporary trace in `dir` holds data: at
/// least 1 MB has been buffered and flushed), sends `signals` SIGINTs.
#[cfg(unix)]
fn interrupt_after(dir: &Path, args: &[&str], signals: usize) -> (i32, String, String) {
    let child = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(root())
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    let running = || {
        std::fs::read_dir(dir).unwrap().any(|e| {
            let e = e.unwrap();
            e.file_name().to_string_lossy().contains(".mapc-tmp-")
                && e.metadata().is_ok_and(|m| m.len() > 0)
        })
    };
    while !running() {
        assert!(started.elapsed().as_secs() < 120, "the run never got going");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    for _ in 0..signals {
        let ok = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap()
            .success();
        assert!(ok);
        std::thread::sleep(std::time::Duration::from_millis(200));
    }
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[cfg(unix)]
#[test]
fn ctrl_c_writes_the_report_of_what_ran() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = long_scenario(dir.path());
    let report = dir.path().join("report.json");
    let trace = dir.path().join("trace.jsonl");
    let (code, out, err) = interrupt_after(
        dir.path(),
        &[
            "sim",
            scenario.to_str().unwrap(),
            "--until",
            "1000h",
            "--report",
            report.to_str().unwrap(),
            "--trace",
            trace.to_str().unwrap(),
        ],
        1,
    );
    assert_eq!(code, 130, "{err}");
    assert!(out.contains("interrupted"), "summary printed: {out}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(r["interrupted"], true);
    let end = r["end_time"].as_f64().unwrap();
    assert!(end > 0.0 && end < 3_600_000.0, "{end}");
    let text = std::fs::read_to_string(&trace).unwrap();
    assert!(text.ends_with('\n') && text.lines().count() > 10);
    assert!(
        temporaries(dir.path()).is_empty(),
        "{:?}",
        temporaries(dir.path())
    );
}

#[cfg(unix)]
#[test]
fn second_ctrl_c_exits_and_removes_the_temporary_trace() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = long_scenario(dir.path());
    // The second signal arrives while the first is handled or after the run stopped; it
    // must not leave a temporary behind either way.
    let trace = dir.path().join("trace.jsonl");
    let (code, _, err) = interrupt_after(
        dir.path(),
        &[
            "sim",
            scenario.to_str().unwrap(),
            "--until",
            "1000h",
            "--trace",
            trace.to_str().unwrap(),
        ],
        2,
    );
    assert_eq!(code, 130, "{err}");
    assert!(
        temporaries(dir.path()).is_empty(),
        "{:?}",
        temporaries(dir.path())
    );
}

#[test]
fn trace_topics_state_period_and_zstd() {
    let dir = tempfile::tempdir().unwrap();
    let all = dir.path().join("all.jsonl");
    let some = dir.path().join("some.jsonl");
    let thin = dir.path().join("thin.jsonl");
    let zst = dir.path().join("all.jsonl.zst");
    for (path, extra) in [
        (&all, vec![]),
        (&some, vec!["--trace-topics", "task_events,/door_states"]),
        (&thin, vec!["--trace-state-period", "5s"]),
        (&zst, vec![]),
    ] {
        let mut args = vec!["sim", "-q", SCENARIO, "--trace", path.to_str().unwrap()];
        args.extend(extra);
        let (code, _, err) = mapc(&args);
        assert_eq!(code, 0, "{err}");
    }
    let read = |p: &Path| std::fs::read_to_string(p).unwrap();
    let topics = |t: &str| -> std::collections::BTreeSet<String> {
        t.lines()
            .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap()["topic"].to_string())
            .collect()
    };
    let (a, s, t) = (read(&all), read(&some), read(&thin));
    assert_eq!(
        topics(&s),
        ["\"/door_states\"", "\"/task_events\""]
            .map(String::from)
            .into()
    );
    let count = |text: &str, topic: &str| text.lines().filter(|l| l.contains(topic)).count();
    assert_eq!(count(&s, "\"/task_events\""), count(&a, "\"/task_events\""));
    // Robot states are published at 2 Hz: at most one per 5 s remains.
    assert!(count(&t, "\"/robot_state\"") * 5 < count(&a, "\"/robot_state\""));
    assert_eq!(count(&t, "\"/task_events\""), count(&a, "\"/task_events\""));
    let bytes = std::fs::read(&zst).unwrap();
    assert_eq!(&bytes[..4], &[0x28, 0xb5, 0x2f, 0xfd], "zstd magic");
    let decoded = zstd::decode_all(&bytes[..]).unwrap();
    assert_eq!(String::from_utf8(decoded).unwrap(), a);
    assert!(bytes.len() * 5 < a.len());
    let (code, _, err) = mapc(&["sim", SCENARIO, "--trace-topics", "nope"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("unknown topic"), "{err}");
}

#[test]
fn json_report_keeps_the_documented_key_order() {
    let (code, out, err) = mapc(&["sim", "-q", "--format", "json", SCENARIO]);
    assert_eq!(code, 0, "{err}");
    let line = out.lines().last().unwrap();
    let keys = [
        "\"end_time\"",
        "\"tasks\"",
        "\"fleets\"",
        "\"robots\"",
        "\"doors\"",
        "\"lifts\"",
        "\"near_misses\"",
        "\"contacts\"",
        "\"stuck\"",
    ];
    let pos: Vec<usize> = keys.iter().map(|k| line.find(k).unwrap()).collect();
    assert!(pos.windows(2).all(|w| w[0] < w[1]), "{line}");
}

#[test]
fn building_map_as_scenario_says_use_map() {
    let (code, _, err) = mapc(&["sim", "fixtures/two_level_clinic.building.yaml"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("is a building map; use --map"), "{err}");
}

#[test]
fn robot_state_carries_the_model_name() {
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("t.jsonl");
    let (code, _, err) = mapc(&[
        "sim",
        "-q",
        SCENARIO,
        "--trace",
        trace.to_str().unwrap(),
        "--trace-topics",
        "robot_state",
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&trace).unwrap();
    let first: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    assert_eq!(first["msg"]["model"], "TinyRobot", "{first}");
}

#[test]
fn summary_separates_resolved_and_unresolved_stuck_episodes() {
    let (code, out, err) = mapc(&["sim", "-q", SCENARIO]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("stuck episodes: 0 (0 resolved, 0 unresolved at the end)"),
        "{out}"
    );
}

#[test]
fn rmf_config_requests_and_states_in_rmf_format() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = root().join("fixtures/rmf/warehouse_requests.scenario.yaml");
    // --requests replaces the scenario's requests file.
    let requests = dir.path().join("r.jsonl");
    std::fs::write(
        &requests,
        concat!(
            r#"{"at": "30s", "request": {"type": "dispatch_task_request", "request": {"category": "patrol", "description": {"places": ["hold_a", "pickup"], "rounds": 1}}}}"#,
            "\n",
            r#"{"at": "1min", "request": {"type": "dispatch_task_request", "request": {"category": "clean", "description": {"zone": "clean_zone"}}}}"#,
            "\n"
        ),
    )
    .unwrap();
    let (t, f) = (dir.path().join("t.jsonl"), dir.path().join("f.jsonl"));
    let (code, _, err) = mapc(&[
        "sim",
        scenario.to_str().unwrap(),
        "--requests",
        requests.to_str().unwrap(),
        "--task-states",
        t.to_str().unwrap(),
        "--fleet-states",
        f.to_str().unwrap(),
        "--until",
        "5min",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    let states: Vec<serde_json::Value> = std::fs::read_to_string(&t)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    // The patrol (done by one of the config's robots), then the refused clean.
    assert_eq!(states.len(), 2, "{states:#?}");
    assert_eq!(states[0]["booking"]["id"], "loop_0");
    assert_eq!(states[0]["category"], "patrol");
    assert_eq!(states[0]["status"], "completed");
    let robot = states[0]["assigned_to"]["name"].as_str().unwrap();
    assert!(robot == "mover_1" || robot == "mover_2", "{robot}");
    assert_eq!(states[1]["dispatch"]["status"], "failed_to_assign");
    let updates = std::fs::read_to_string(&f).unwrap();
    let first: serde_json::Value = serde_json::from_str(updates.lines().next().unwrap()).unwrap();
    assert_eq!(first["type"], "fleet_state_update");
    assert_eq!(first["data"]["name"], "movers");
    // About one a second for 5 minutes.
    assert!((290..=310).contains(&updates.lines().count()));

    // A broken fleet config: located in the config, exit 1, nothing run.
    std::fs::write(
        dir.path().join("bad.yaml"),
        "rmf_fleet:\n  name: f\n  limits:\n    linear: [-0.5, 0.75]\n  robots:\n    r: {charger: c}\n",
    )
    .unwrap();
    let s = dir.path().join("s.scenario.yaml");
    std::fs::write(&s, "duration: 1min\nfleets:\n  - {config: bad.yaml}\n").unwrap();
    let (code, _, err) = mapc(&[
        "sim",
        s.to_str().unwrap(),
        "--task-states",
        t.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("S0106") && err.contains("bad.yaml:4:14"),
        "{err}"
    );
}
