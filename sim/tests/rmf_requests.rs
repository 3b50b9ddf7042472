//! RMF task API requests as a scenario's `requests:` (issue 38): what they become, what is
//! refused, located problems, and the task and fleet states mapc writes in RMF's format,
//! validated against rmf_api_msgs' schemas (../shared) with the `jsonschema` crate.

use mapc_sim::{parse_scenario, parse_scenario_files, rmf_states, simulate, Report, RunOptions};
#[path = "support/rmf_schemas.rs"]
mod rmf_schemas;
use rmf_schemas::validator;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

/// Runs the warehouse requests scenario; its report, task states and fleet state updates.
fn run() -> (mapc_sim::Scenario, Report, Vec<Value>) {
    run_file("warehouse_requests.scenario.yaml")
}

/// Runs `fixtures/rmf/<name>` on the warehouse; its report and fleet state updates.
fn run_file(name: &str) -> (mapc_sim::Scenario, Report, Vec<Value>) {
    let dir = fixtures().join("rmf");
    let text = std::fs::read_to_string(dir.join(name)).unwrap();
    let (s, d) = parse_scenario(mapc_ir::FileId(0), &text, &dir);
    let s = s.unwrap_or_else(|| panic!("{d:#?}"));
    let map = mapc_frontend::load(&fixtures().join("cartesian_warehouse.building.yaml")).unwrap();
    let b = map.valid_building().unwrap();
    let start = rmf_states::start_unix_millis(&s);
    let mut fleet_states = Vec::new();
    let mut observe = |p: &mapc_sim::msgs::Published| {
        if let mapc_sim::msgs::Msg::FleetState(f) = &p.msg {
            fleet_states.push(rmf_states::fleet_state_update(f, p.t, start));
        }
    };
    let report = simulate(
        b,
        &s,
        RunOptions {
            observer: Some(&mut observe),
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e:?}"));
    (s, report, fleet_states)
}

/// Per request: its line, the task it names, and why it was refused.
fn outcomes(r: &Report) -> Vec<(usize, Option<&str>, Option<&str>)> {
    r.requests
        .iter()
        .map(|q| (q.line, q.task_id.as_deref(), q.refused.as_deref()))
        .collect()
}

#[test]
fn requests_become_tasks_or_are_refused() {
    let (_, r, fleet_states) = run();
    assert_eq!(
        outcomes(&r),
        [
            (1, Some("loop_0"), None),
            (2, Some("go_to_place_0"), None),
            (3, Some("delivery_0"), None),
            (4, Some("go_to_place_1"), None),
            (5, None, Some("no fleet is capable of clean tasks")),
            (6, None, Some("no fleet is named `cleaners`")),
            (
                7,
                Some("loop_0"),
                Some("cancel_task_request for `loop_0`: the task had already ended")
            ),
            (8, Some("delivery_1"), None),
            (
                9,
                None,
                Some("mapc cannot simulate the action `teleop` (its robots go to places, deliver and clean)")
            ),
            (10, Some("go_to_place_2"), None),
        ]
    );
    // The delivery may not start before its unix_millis_earliest_start_time (4 min after
    // the run's start), though it arrived at 2 min.
    let d = r.tasks.iter().find(|t| t.id == "delivery_0").unwrap();
    assert_eq!(d.requested, Some(240.0));
    assert_eq!(r.requests[2].at, 240.0);
    for t in &r.tasks {
        assert_eq!(t.result, "completed", "{t:?}");
    }
    // The robot task went to the robot's fleet.
    let g = r.tasks.iter().find(|t| t.id == "go_to_place_1").unwrap();
    assert_eq!(g.fleet, "movers");
    assert!(!fleet_states.is_empty());
}

fn check(v: &jsonschema::Validator, x: &Value, what: &str) {
    let errors: Vec<String> = v
        .iter_errors(x)
        .map(|e| format!("{e} at {}", e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{what}: {errors:#?}\n{x:#}");
}

#[test]
fn requests_and_states_follow_rmf_api_schemas() {
    let (Some(dispatch), Some(robot), Some(cancel), Some(task_state), Some(fleet_update)) = (
        validator("dispatch_task_request.json"),
        validator("robot_task_request.json"),
        validator("cancel_task_request.json"),
        validator("task_state.json"),
        validator("fleet_state_update.json"),
    ) else {
        eprintln!("skipped: ../shared not found");
        return;
    };
    let descriptions = |cat: &str| validator(&format!("task_description__{cat}.json"));
    // The warehouse's requests and the office example's (docs/sim.md).
    let text = ["warehouse_requests.jsonl", "office_requests.jsonl"]
        .map(|f| std::fs::read_to_string(fixtures().join("rmf").join(f)).unwrap())
        .concat();
    for (i, line) in text.lines().enumerate() {
        let v: Value = serde_json::from_str(line).unwrap();
        let req = &v["request"];
        let what = format!("request line {}", i + 1);
        match req["type"].as_str().unwrap() {
            "dispatch_task_request" => check(&dispatch, req, &what),
            "robot_task_request" => check(&robot, req, &what),
            "cancel_task_request" => check(&cancel, req, &what),
            t => panic!("{t}"),
        }
        // The description against the fleet adapter's schema of its category.
        if let Some(cat) = req["request"]["category"].as_str() {
            let d = descriptions(cat).expect("a schema for each category used");
            check(&d, &req["request"]["description"], &what);
        }
    }
    let (s, r, fleet_states) = run();
    let states = rmf_states::task_states(&s, &r);
    assert_eq!(
        states.len(),
        r.tasks.len() + 4,
        "tasks plus refused requests"
    );
    for st in &states {
        check(&task_state, st, "task_state");
    }
    // The delivery: booked with its request's fields, done by a mover, times in unix ms.
    let d = states
        .iter()
        .find(|s| s["booking"]["id"] == "delivery_0")
        .unwrap();
    let start = 1_767_225_600_000i64;
    assert_eq!(
        d["booking"]["unix_millis_earliest_start_time"],
        start + 240_000
    );
    assert_eq!(d["booking"]["priority"]["value"], 1);
    // The requester's time of the request (1.5 min), not when it reached mapc (2 min).
    assert_eq!(d["booking"]["unix_millis_request_time"], start + 90_000);
    // A request without one: when it arrived.
    let g = states
        .iter()
        .find(|s| s["booking"]["id"] == "go_to_place_0")
        .unwrap();
    assert_eq!(g["booking"]["unix_millis_request_time"], start + 60_000);
    assert_eq!(d["category"], "delivery");
    assert_eq!(d["status"], "completed");
    assert_eq!(d["assigned_to"]["group"], "movers");
    let t = r.tasks.iter().find(|t| t.id == "delivery_0").unwrap();
    assert_eq!(
        d["unix_millis_finish_time"],
        start + (t.finished.unwrap() * 1000.0).round() as i64
    );
    let p = states
        .iter()
        .find(|s| s["booking"]["id"] == "loop_0")
        .unwrap();
    assert_eq!(p["category"], "patrol");
    assert_eq!(p["booking"]["requester"], "rmf_demos_tasks");
    let refused = states.iter().filter(|s| s["status"] == "failed").count();
    assert_eq!(refused, 4);
    for f in &fleet_states {
        check(&fleet_update, f, "fleet_state_update");
    }
    let last = fleet_states.last().unwrap();
    let b = last["data"]["robots"]["mover_1"]["battery"]
        .as_f64()
        .unwrap();
    assert!(b > 0.9 && b <= 1.0, "{b}");
}

/// A requests file written next to a scenario in a scratch directory; the diagnostics.
fn broken(dir: &Path, lines: &str) -> Vec<(&'static str, u32, u32, u32)> {
    std::fs::write(dir.join("r.jsonl"), lines).unwrap();
    std::fs::copy(
        fixtures().join("rmf/movers_config.yaml"),
        dir.join("m.yaml"),
    )
    .unwrap();
    let text = "duration: 1h\nfleets: [{config: m.yaml}]\nrequests: r.jsonl\n";
    let p = parse_scenario_files(mapc_ir::FileId(0), text, dir);
    let mut out: Vec<_> = p
        .diagnostics
        .iter()
        .map(|d| (d.code, d.span.file.0, d.span.line, d.span.col))
        .collect();
    if let Some(s) = p.scenario {
        // Against the map: unknown places.
        let map =
            mapc_frontend::load(&fixtures().join("cartesian_warehouse.building.yaml")).unwrap();
        if let Err(mapc_sim::SimError::Invalid(d)) =
            simulate(map.valid_building().unwrap(), &s, RunOptions::default())
        {
            out.extend(
                d.iter()
                    .map(|d| (d.code, d.span.file.0, d.span.line, d.span.col)),
            );
        }
    }
    out
}

#[test]
fn broken_requests_are_located() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let ok = r#"{"at": 0, "request": {"type": "dispatch_task_request", "request": {"category": "patrol", "description": {"places": ["aisle_1"]}}}}"#;
    // A truncated line (file 2: the requests, after the fleet config).
    let d = broken(dir, &format!("{ok}\n{}\n", &ok[..60]));
    assert_eq!(d, [("S0313", 2, 2, 60)]);
    // A wrong type: `rounds` must be an integer.
    let d = broken(
        dir,
        &format!("{ok}\n{}\n", ok.replace("]}", "], \"rounds\": \"two\"}")),
    );
    assert_eq!(d, [("S0313", 2, 2, 139)], "{d:?}");
    // Missing `description` (required by task_request).
    let d = broken(
        dir,
        &ok.replace(r#", "description": {"places": ["aisle_1"]}"#, ""),
    );
    assert_eq!(d, [("S0313", 2, 1, 11)], "{d:?}");
    // A bad `at`.
    let d = broken(dir, &ok.replace(r#""at": 0"#, r#""at": "soon""#));
    assert_eq!(d, [("S0313", 2, 1, 2)], "{d:?}");
    // An unknown place: at the place, in the requests file.
    let d = broken(dir, &ok.replace("aisle_1", "aisle_7"));
    assert_eq!(d, [("S0201", 2, 1, 118)], "{d:?}");
    // A missing file.
    std::fs::remove_file(dir.join("r.jsonl")).unwrap();
    let p = parse_scenario_files(
        mapc_ir::FileId(0),
        "duration: 1h\nfleets: [{config: m.yaml}]\nrequests: r.jsonl\n",
        dir,
    );
    assert_eq!(p.diagnostics[0].code, "S0004");
    // Garbage never panics.
    for g in [
        "{",
        "[]",
        "null",
        "{\"at\": 1}",
        "\u{0}",
        "{\"at\": -5, \"request\": {}}",
    ] {
        let d = broken(dir, g);
        assert!(d.iter().any(|x| x.0 == "S0313"), "{g}: {d:?}");
    }
}

/// `cancel_task_request`: the queued go_to_place leaves the queue, the 10-round patrol under
/// way ends where its robot is at 1 min, and that robot takes the patrol asked at 2 min; a
/// second cancel of the patrol and a cancel of a task that never comes are refused, and
/// the task states say `canceled` (validated against RMF's schema).
#[test]
fn cancel_requests_stop_queued_and_running_tasks() {
    let (s, r, _) = run_file("cancel_requests.scenario.yaml");
    assert_eq!(
        outcomes(&r),
        [
            (1, Some("loop_0"), None),
            (2, Some("loop_1"), None),
            (3, Some("go_to_place_0"), None),
            (4, Some("go_to_place_0"), None),
            (5, Some("loop_0"), None),
            (
                6,
                Some("loop_0"),
                Some("cancel_task_request for `loop_0`: the task had already ended")
            ),
            (
                7,
                Some("loop_7"),
                Some("cancel_task_request for `loop_7`: no task of that id arrived before the run ended")
            ),
            (8, Some("loop_2"), None),
        ]
    );
    let task = |id: &str| r.tasks.iter().find(|t| t.id == id).unwrap();
    let queued = task("go_to_place_0");
    assert_eq!(
        (
            queued.result.as_str(),
            queued.robot.as_str(),
            queued.finished
        ),
        ("cancelled", "", Some(20.0))
    );
    assert_eq!(queued.assigned, None);
    let patrol = task("loop_0");
    assert_eq!(
        (patrol.result.as_str(), patrol.finished),
        ("cancelled", Some(60.0))
    );
    assert!(patrol.started.is_some_and(|t| t < 60.0), "{patrol:?}");
    // The robot it had is free again: the patrol asked at 2 min is done, by either mover.
    assert_eq!(task("loop_1").result, "completed", "{:#?}", r.tasks);
    assert_eq!(task("loop_2").result, "completed");
    assert!(r.contacts.is_empty());
    let states = rmf_states::task_states(&s, &r);
    let state = |id: &str| states.iter().find(|x| x["booking"]["id"] == id).unwrap();
    assert_eq!(state("loop_0")["status"], "canceled");
    assert_eq!(state("go_to_place_0")["status"], "canceled");
    // RMF's record of the cancel request: when it came (unix ms, the run's start plus
    // 1 min and 20 s) and its labels; a task that was not cancelled has none.
    let t0 = rmf_states::start_unix_millis(&s);
    assert_eq!(
        state("loop_0")["cancellation"],
        serde_json::json!({"unix_millis_request_time": t0 + 60_000, "labels": ["app=dashboard"]})
    );
    assert_eq!(
        state("go_to_place_0")["cancellation"],
        serde_json::json!({"unix_millis_request_time": t0 + 20_000, "labels": []})
    );
    assert!(state("loop_1").get("cancellation").is_none());
    // The patrol's booking is its own request's, not the cancel's.
    assert_eq!(state("loop_0")["category"], "patrol");
    if let Some(v) = validator("task_state.json") {
        for st in &states {
            check(&v, st, "task_state");
        }
    } else {
        eprintln!("skipped: ../shared not found (task_state schema)");
    }
}

/// An RMF phase: its category, the status of its event, its start and finish (unix ms).
type RmfPhase = (String, Option<String>, Option<i64>, Option<i64>);

/// The phases of a task state, in id order.
fn rmf_phases(st: &Value) -> Vec<RmfPhase> {
    let phases = st["phases"].as_object().expect("phases");
    (1..=phases.len())
        .map(|id| {
            let p = &phases[&id.to_string()];
            assert_eq!(p["id"], id);
            (
                p["category"].as_str().unwrap().to_string(),
                p["events"]["0"]["status"].as_str().map(str::to_string),
                p["unix_millis_start_time"].as_i64(),
                p["unix_millis_finish_time"].as_i64(),
            )
        })
        .collect()
}

/// A delivery's phases are its robot's steps (to the pickup, the pickup, to the drop-off,
/// the drop-off), as RMF's own delivery has them: each starts when the one before ends,
/// the first when the task starts and the last ends when the task does; in the task
/// state, each a completed phase with those times in unix ms.
#[test]
fn a_delivery_has_a_timed_phase_per_step() {
    let (s, r, _) = run();
    let t = r.tasks.iter().find(|t| t.id == "delivery_0").unwrap();
    let details: Vec<&str> = t.phases.iter().map(|p| p.detail.as_str()).collect();
    assert_eq!(
        details,
        [
            "go_to_place pickup",
            "pickup at pickup from dispenser_1",
            "go_to_place dropoff",
            "dropoff at dropoff into ingestor_1"
        ],
        "{t:#?}"
    );
    assert!(t.phases.iter().all(|p| p.result == "completed"), "{t:#?}");
    let (started, finished) = (t.started.unwrap(), t.finished.unwrap());
    assert_eq!(t.phases[0].started, Some(started));
    assert_eq!(t.phases.last().unwrap().finished, Some(finished));
    for w in t.phases.windows(2) {
        assert_eq!(w[1].started, w[0].finished, "{t:#?}");
    }
    // Each takes time: the drives several seconds, the workcells less than one (the
    // teleport plugins answer at once; the robot reads the answer in the next step).
    for (k, p) in t.phases.iter().enumerate() {
        let (a, b) = (p.started.unwrap(), p.finished.unwrap());
        assert!(started <= a && a < b && b <= finished, "{p:?} in {t:#?}");
        if k % 2 == 0 {
            assert!(b - a > 5.0, "{p:?}");
        } else {
            assert!(b - a < 1.0, "{p:?}");
        }
    }
    // In RMF's format.
    let states = rmf_states::task_states(&s, &r);
    let d = states
        .iter()
        .find(|x| x["booking"]["id"] == "delivery_0")
        .unwrap();
    let start = 1_767_225_600_000i64;
    let ms = |x: Option<f64>| x.map(|x| start + (x * 1000.0).round() as i64);
    let want: Vec<_> = [
        "Go to [place:pickup]",
        "Pick up",
        "Go to [place:dropoff]",
        "Drop Off",
    ]
    .iter()
    .zip(&t.phases)
    .map(|(c, p)| {
        (
            c.to_string(),
            Some("completed".to_string()),
            ms(p.started),
            ms(p.finished),
        )
    })
    .collect();
    assert_eq!(rmf_phases(d), want);
    assert_eq!(d["completed"], serde_json::json!([1, 2, 3, 4]));
    assert_eq!(d["pending"], serde_json::json!([]));
    assert!(d.get("active").is_none());
    assert_eq!(
        d["phases"]["1"]["unix_millis_start_time"],
        d["unix_millis_start_time"]
    );
    assert_eq!(
        d["phases"]["4"]["unix_millis_finish_time"],
        d["unix_millis_finish_time"]
    );
    assert_eq!(
        d["phases"]["2"]["detail"],
        "pickup at pickup from dispenser_1"
    );
    // The compose delivery (rmf_demos' perform_action pickup and dropoff) alike.
    let c = r.tasks.iter().find(|t| t.id == "delivery_1").unwrap();
    assert_eq!(c.phases.len(), 4, "{c:#?}");
    assert_eq!(c.phases[3].finished, c.finished);
}

/// A patrol cancelled under way: the places it reached are completed phases, the one it was
/// going to is canceled at the cancel's time, the rest are pending.
#[test]
fn a_cancelled_patrol_shows_its_completed_and_interrupted_phases() {
    let (s, r, _) = run_file("cancel_requests.scenario.yaml");
    let t = r.tasks.iter().find(|t| t.id == "loop_0").unwrap();
    // 10 rounds of hold_a, pickup.
    assert_eq!(t.phases.len(), 20, "{t:#?}");
    for (k, p) in t.phases.iter().enumerate() {
        let place = if k % 2 == 0 { "hold_a" } else { "pickup" };
        assert_eq!(p.detail, format!("go_to_place {place}"));
    }
    let done = t
        .phases
        .iter()
        .take_while(|p| p.result == "completed")
        .count();
    assert!(done >= 1, "{t:#?}");
    let cut = &t.phases[done];
    assert_eq!(cut.result, "cancelled");
    assert_eq!(cut.started, t.phases[done - 1].finished);
    assert_eq!(cut.finished, Some(60.0));
    assert!(t.phases[..done]
        .iter()
        .all(|p| p.finished.is_some_and(|f| f <= 60.0)));
    assert!(t.phases[done + 1..]
        .iter()
        .all(|p| p.result == "pending" && p.started.is_none() && p.finished.is_none()));
    let states = rmf_states::task_states(&s, &r);
    let st = states
        .iter()
        .find(|x| x["booking"]["id"] == "loop_0")
        .unwrap();
    let phases = rmf_phases(st);
    let start = 1_767_225_600_000i64;
    for (k, (category, status, a, b)) in phases.iter().enumerate() {
        let place = if k % 2 == 0 { "hold_a" } else { "pickup" };
        assert_eq!(*category, format!("Go to [place:{place}]"));
        let want = match k.cmp(&done) {
            std::cmp::Ordering::Less => Some("completed"),
            std::cmp::Ordering::Equal => Some("canceled"),
            std::cmp::Ordering::Greater => None,
        };
        assert_eq!(status.as_deref(), want, "phase {}", k + 1);
        assert_eq!(a.is_some(), k <= done);
        assert_eq!(b.is_some(), k <= done);
    }
    assert_eq!(phases[done].3, Some(start + 60_000));
    assert_eq!(
        st["completed"],
        serde_json::json!((1..=done + 1).collect::<Vec<_>>())
    );
    assert_eq!(
        st["pending"],
        serde_json::json!((done + 2..=20).collect::<Vec<_>>())
    );
    assert!(st.get("active").is_none());
    // The queued task it cancelled never started: no phases.
    let q = states
        .iter()
        .find(|x| x["booking"]["id"] == "go_to_place_0")
        .unwrap();
    assert!(q.get("phases").is_none(), "{q:#}");
}
