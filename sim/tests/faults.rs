//! `faults:` (issue 35): a lift out of service answers no request until the fault ends, a
//! paused robot stands still and then goes on, and a fault naming nothing is an error.

use mapc_sim::{parse_scenario, simulate, Report, RunOptions, SimError};
use std::path::Path;

/// The two-level clinic's delivery (pharmacy on L1 to ward A on L2 through `lift_1`) with
/// `faults` added; its trace and report.
fn clinic(faults: &str) -> Result<(Report, Vec<serde_json::Value>), SimError> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let text = std::fs::read_to_string(dir.join("two_level_clinic.scenario.yaml")).unwrap();
    let text = format!("{text}\n{faults}");
    let (scenario, diags) = parse_scenario(mapc_ir::FileId(0), &text, &dir);
    let scenario = scenario.unwrap_or_else(|| panic!("{diags:?}"));
    let map = mapc_frontend::load(&dir.join("two_level_clinic.building.yaml")).unwrap();
    let building = map.valid_building().expect("valid fixture");
    let mut trace = Vec::new();
    let report = simulate(
        building,
        &scenario,
        RunOptions {
            until: Some(900.0),
            trace: Some(&mut trace),
            ..Default::default()
        },
    )?;
    let lines = String::from_utf8(trace)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    Ok((report, lines))
}

/// When the delivery's robot first reaches floor L2 (its RobotState level), if it does.
fn on_l2(trace: &[serde_json::Value]) -> Option<f64> {
    trace
        .iter()
        .find(|v| v["topic"] == "/robot_state" && v["msg"]["location"]["level_name"] == "L2")
        .and_then(|v| v["t"].as_f64())
}

fn delivered(r: &Report) -> Option<f64> {
    r.tasks
        .iter()
        .find(|t| t.category == "delivery" && t.result == "completed")
        .and_then(|t| t.finished)
}

#[test]
fn a_lift_out_of_service_holds_the_ride_until_it_is_back() {
    let (clean, trace) = clinic("").expect("runs");
    let up = on_l2(&trace).expect("the robot rides up without faults");
    let done = delivered(&clean).expect("delivered without faults");
    // lift_1 out of service from 0 to 200 s: it answers nothing, the robot waits at the
    // lift (less than the 300 s after which a task fails), then rides once it is back.
    let (r, trace) = clinic("faults:\n  - {at: 0, for: 200s, lift: lift_1}").expect("runs");
    let up_late = on_l2(&trace).expect("the robot rides up after the fault");
    assert!(up < 200.0, "without the fault it is up at {up} s");
    assert!(
        up_late >= 200.0,
        "up at {up_late} s, while the lift was out of service"
    );
    let late = delivered(&r).expect("delivered after the fault");
    assert!(late > done, "{late} vs {done}");
    assert!(r.contacts.is_empty());
}

#[test]
fn a_paused_robot_stands_still_then_goes_on() {
    let (clean, _) = clinic("").expect("runs");
    let done = delivered(&clean).expect("delivered without faults");
    // Paused from 20 s for 100 s: it delivers about 100 s later.
    let (r, trace) = clinic("faults:\n  - {at: 20s, for: 100s, robot: tinyRobot1}").expect("runs");
    let late = delivered(&r).expect("delivered after the pause");
    assert!(late >= done + 80.0, "{late} vs {done}");
    // Standing still while paused: the reported position does not change in (25, 115) s.
    let at = |t0: f64| {
        trace
            .iter()
            .find(|v| v["topic"] == "/robot_state" && v["t"].as_f64().unwrap() >= t0)
            .map(|v| {
                let l = &v["msg"]["location"];
                (l["x"].as_f64().unwrap(), l["y"].as_f64().unwrap())
            })
            .unwrap()
    };
    let (a, z) = (at(25.0), at(115.0));
    assert!((a.0 - z.0).hypot(a.1 - z.1) < 0.01, "{a:?} -> {z:?}");
}

#[test]
fn a_fault_naming_nothing_is_an_error() {
    let err = clinic("faults:\n  - {at: 0, for: 1min, lift: LIFT_9}").unwrap_err();
    let SimError::Invalid(diags) = err else {
        panic!("{err:?}")
    };
    assert_eq!(diags.len(), 1);
    assert_eq!(diags[0].code, "S0212");
    assert!(diags[0].message.contains("LIFT_9"), "{}", diags[0].message);
    // Located on the fault's line (the fixture's text, then a blank line, `faults:`).
    assert!(diags[0].span.line > 20, "{:?}", diags[0].span);
}

#[test]
fn a_fault_needs_exactly_one_target() {
    let dir = Path::new(".");
    let base = "duration: 1h\nfleets:\n  - {name: f, robot: TinyRobot, count: 1}\n";
    for (faults, code) in [
        ("faults:\n  - {at: 0, for: 1min}", "S0311"),
        ("faults:\n  - {for: 1min, lift: a, door: b}", "S0311"),
        ("faults:\n  - {at: 0, lift: a}", "S0102"),
        ("faults:\n  - {at: 0, for: 1min, lift: a, when: 3}", "S0103"),
    ] {
        let (s, diags) = parse_scenario(mapc_ir::FileId(0), &format!("{base}{faults}"), dir);
        assert!(diags.iter().any(|d| d.code == code), "{faults}: {diags:?}");
        if code != "S0103" {
            assert!(s.is_none(), "{faults}");
        }
    }
    let (s, diags) = parse_scenario(
        mapc_ir::FileId(0),
        &format!("{base}faults:\n  - {{at: 10min, for: 90s, door: d1}}"),
        dir,
    );
    let s = s.unwrap_or_else(|| panic!("{diags:?}"));
    assert_eq!(s.faults.len(), 1);
    assert_eq!((s.faults[0].at, s.faults[0].duration), (600.0, 90.0));
    assert_eq!(s.faults[0].target.kind(), "door");
    assert_eq!(s.faults[0].target.name(), "d1");
}

/// The report's per-task `planned_finish` and `delay`: alone and without faults a robot is
/// never later than its plan (plans drive each lane from rest to rest and count doors and
/// lift calls at their longest); paused for 100 s, it is about 100 s later than that.
#[test]
fn a_pause_shows_as_the_tasks_delay_over_its_plan() {
    let delivery = |r: &Report| {
        let t = r
            .tasks
            .iter()
            .find(|t| t.category == "delivery" && t.result == "completed")
            .expect("delivered")
            .clone();
        let planned = t.planned_finish.expect("a planned finish");
        assert!(planned > t.assigned.expect("assigned"), "{t:?}");
        assert_eq!(t.delay, Some(t.finished.expect("finished") - planned));
        t.delay.expect("a delay")
    };
    let (clean, _) = clinic("").expect("runs");
    let (paused, _) = clinic("faults:\n  - {at: 20s, for: 100s, robot: tinyRobot1}").expect("runs");
    let (on_time, late) = (delivery(&clean), delivery(&paused));
    eprintln!("delay without the fault {on_time:.1} s, with it {late:.1} s");
    assert!(on_time <= 0.0, "{on_time}");
    assert!((late - on_time - 100.0).abs() < 20.0, "{late} vs {on_time}");
}
