use super::*;
use crate::fleet::Placement;
use crate::msgs::{
    DoorMode, DoorRequest, DoorState, LiftRequest, LiftState, Published, RobotMode, RobotState,
    TaskEvent, Time, WaitCause,
};
use crate::params::RobotParams;
use crate::world::RobotSpawn;

const CLINIC: &str = include_str!("../../../fixtures/two_level_clinic.building.yaml");

/// The clinic fixture, a two-fleet scenario and robots `a0`, `a1` (fleet a, footprint
/// 0.3 and 0.4) and `b0` (fleet b, 0.5).
fn builder() -> ReportBuilder {
    let parsed = mapc_frontend::parse_str("clinic", CLINIC);
    let building = parsed.building.expect("fixture reads");
    let (scenario, d) = crate::scenario::parse(
            mapc_ir::FileId(0),
            "duration: 1h\nfleets:\n  - {name: a, robot: TinyRobot, count: 2}\n  - {name: b, robot: TinyRobot, count: 1}\n",
            std::path::Path::new("."),
        );
    let scenario = scenario.unwrap_or_else(|| panic!("{d:?}"));
    let spawn = |name: &str, fleet: &str, footprint: f64| RobotSpawn {
        name: name.into(),
        fleet: fleet.into(),
        params: RobotParams {
            footprint,
            ..RobotParams::default()
        },
        x: 0.0,
        y: 0.0,
        yaw: 0.0,
        level: building.reference_level,
    };
    let placement = Placement {
        robots: vec![
            spawn("a0", "a", 0.3),
            spawn("a1", "a", 0.4),
            spawn("b0", "b", 0.5),
        ],
        workcells: Vec::new(),
        reserve: Vec::new(),
        warnings: Vec::new(),
        parks: Default::default(),
        finishes: Vec::new(),
    };
    ReportBuilder::new(&building, &scenario, &placement)
}

fn at(x: f64, y: f64, z: f64) -> RobotTruth {
    RobotTruth {
        x,
        y,
        z,
        yaw: 0.0,
        v: 0.0,
        footprint: 0.0,
    }
}

fn door_req(t: f64, who: &str, door: &str, mode: u32) -> Published {
    Published {
        t,
        topic: Topic::AdapterDoorRequests,
        msg: Msg::DoorRequest(DoorRequest {
            request_time: Time::from_secs(t),
            requester_id: who.into(),
            door_name: door.into(),
            requested_mode: DoorMode { value: mode },
        }),
    }
}

fn door_state(t: f64, door: &str, mode: u32) -> Published {
    Published {
        t,
        topic: Topic::DoorStates,
        msg: Msg::DoorState(DoorState {
            door_time: Time::from_secs(t),
            door_name: door.into(),
            current_mode: DoorMode { value: mode },
        }),
    }
}

fn event(t: f64, id: &str, event: &str, robot: &str, fleet: &str) -> Published {
    Published {
        t,
        topic: Topic::TaskEvents,
        msg: Msg::TaskEvent(TaskEvent {
            time: Time::from_secs(t),
            task_id: id.into(),
            category: "delivery".into(),
            event: event.into(),
            fleet: fleet.into(),
            robot: robot.into(),
            detail: String::new(),
            ..TaskEvent::default()
        }),
    }
}

/// A task's phases: named by its `started` event, each ended by a `phase` event (which
/// leaves the task's detail alone); a failure ends the phase under way, the rest stay
/// pending.
#[test]
fn phases_are_timed_by_phase_events_and_end_with_the_task() {
    let mut b = builder();
    let names = ["go_to_place a", "pickup at a from d", "go_to_place b"];
    let mut send = |t: f64, ev: &str, detail: &str, phases: Option<&[&str]>| {
        let mut p = event(t, "delivery_0", ev, "a0", "a");
        if let Msg::TaskEvent(e) = &mut p.msg {
            e.detail = detail.into();
            e.phases = phases.map(|n| n.iter().map(|s| s.to_string()).collect());
        }
        b.observe(&p);
    };
    send(1.0, "queued", "", None);
    send(2.0, "assigned", "", None);
    send(2.0, "started", "", Some(&names));
    send(10.0, "phase", "go_to_place a", None);
    send(15.0, "failed", "d failed", None);
    let r = b.finish(20.0, &[]);
    let t = &r.tasks[0];
    assert_eq!(
        (t.result.as_str(), t.detail.as_str()),
        ("failed", "d failed")
    );
    let got: Vec<_> = t
        .phases
        .iter()
        .map(|p| (p.detail.as_str(), p.started, p.finished, p.result.as_str()))
        .collect();
    assert_eq!(
        got,
        [
            ("go_to_place a", Some(2.0), Some(10.0), "completed"),
            ("pickup at a from d", Some(10.0), Some(15.0), "failed"),
            ("go_to_place b", None, None, "pending"),
        ]
    );
    let j = serde_json::to_value(t).unwrap();
    assert_eq!(j["phases"][1]["result"], "failed");
}

#[test]
fn bottleneck_is_the_place_tasks_waited_at_longest() {
    let mut b = builder();
    let mut done = |t: f64, id: &str, waits: TaskWaits| {
        let mut p = event(t, id, "completed", "r0", "f");
        if let Msg::TaskEvent(e) = &mut p.msg {
            e.waits = Some(waits);
        }
        b.observe(&p);
    };
    let mut w1 = TaskWaits::default();
    w1.add(WaitCause::Lift, "lift Lift2", 30.0);
    w1.add(WaitCause::Traffic, "traffic at lobby", 20.0);
    let mut w2 = TaskWaits::default();
    w2.add(WaitCause::Lift, "lift Lift2", 40.0);
    w2.add(WaitCause::Door, "door d1", 10.0);
    done(100.0, "t1", w1);
    done(200.0, "t2", w2);
    let r = b.finish(300.0, &[]);
    assert_eq!(r.waits.lift_s, 70.0);
    assert_eq!(r.waits.traffic_s, 20.0);
    assert_eq!(r.waits.door_s, 10.0);
    let top = r.bottleneck.clone().expect("a bottleneck");
    assert_eq!(
        (top.place.as_str(), top.cause.as_str()),
        ("lift Lift2", "lift")
    );
    assert_eq!(top.wait_s, 70.0);
    assert!((top.share - 0.7).abs() < 1e-12);
    assert_eq!(r.tasks[0].waits.as_ref().map(TaskWaits::total), Some(50.0));
    assert!(r.summary().contains("bottleneck: lift Lift2"));
}

#[test]
fn door_waits_are_request_to_first_open() {
    let mut b = builder();
    let door = "L1_lobby_door";
    let seq = [
        door_req(10.0, "a0", door, door_mode::OPEN),
        door_state(10.5, door, door_mode::CLOSED),
        door_req(11.0, "a0", door, door_mode::OPEN), // repeated: same session
        door_state(11.5, door, door_mode::MOVING),
        door_state(13.25, door, door_mode::OPEN),
        door_state(14.0, door, door_mode::OPEN),
        door_req(20.0, "a0", door, door_mode::CLOSED),
        door_req(30.0, "a0", door, door_mode::OPEN), // a new session
        door_state(30.5, door, door_mode::OPEN),
        door_req(40.0, "a1", door, door_mode::OPEN), // never served
        // Other topics with door messages do not count as adapter requests.
        Published {
            topic: Topic::DoorRequests,
            ..door_req(41.0, "door_supervisor", door, door_mode::OPEN)
        },
    ];
    for p in &seq {
        b.observe(p);
    }
    let r = b.finish(60.0, &[]);
    let names: Vec<&str> = r.doors.iter().map(|d| d.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "L1_lobby_door",
            "L1_pharmacy_door",
            "L2_ward_a_door",
            "L2_ward_b_door"
        ]
    );
    let d = &r.doors[0];
    assert_eq!(d.open_requests, 3);
    let waits = [13.25 - 10.0, 30.5 - 30.0];
    assert_eq!(d.wait.count, 2);
    assert_eq!(d.wait.total_s, waits[0] + waits[1]);
    assert_eq!(d.wait.mean_s, (waits[0] + waits[1]) / 2.0);
    assert_eq!(d.wait.max_s, waits[0]);
    assert_eq!(d.wait.unserved, 1);
    assert_eq!(
        r.doors[1],
        DoorReport {
            name: "L1_pharmacy_door".into(),
            ..Default::default()
        }
    );
}

#[test]
fn lift_sessions_trips_and_waits() {
    let mut b = builder();
    let req = |t: f64, session: &str, kind: u8, floor: &str| Published {
        t,
        topic: Topic::AdapterLiftRequests,
        msg: Msg::LiftRequest(LiftRequest {
            lift_name: "lift_1".into(),
            request_time: Time::from_secs(t),
            session_id: session.into(),
            request_type: kind,
            destination_floor: floor.into(),
            door_state: lift_request::DOOR_OPEN,
        }),
    };
    let state = |t: f64, session: &str, floor: &str, door: u8, motion: u8| Published {
        t,
        topic: Topic::LiftStates,
        msg: Msg::LiftState(LiftState {
            lift_name: "lift_1".into(),
            current_floor: floor.into(),
            door_state: door,
            motion_state: motion,
            session_id: session.into(),
            ..Default::default()
        }),
    };
    use lift_state::{DOOR_CLOSED, DOOR_OPEN, MOTION_DOWN, MOTION_STOPPED, MOTION_UP};
    let seq = [
        state(99.0, "", "L1", DOOR_CLOSED, MOTION_STOPPED),
        req(100.0, "a0", lift_request::AGV_MODE, "L2"),
        req(100.5, "a0", lift_request::AGV_MODE, "L2"),
        state(101.0, "a0", "L1", DOOR_CLOSED, MOTION_UP),
        state(105.0, "a0", "L2", DOOR_CLOSED, MOTION_UP),
        // At the floor but the session does not match: not the end of the wait.
        state(109.0, "other", "L2", DOOR_OPEN, MOTION_STOPPED),
        state(110.0, "a0", "L2", DOOR_OPEN, MOTION_STOPPED),
        req(120.0, "a0", lift_request::AGV_MODE, "L1"),
        state(121.0, "a0", "L2", DOOR_CLOSED, MOTION_DOWN),
        state(122.0, "a0", "L1", DOOR_CLOSED, MOTION_DOWN),
        state(130.0, "a0", "L1", DOOR_OPEN, MOTION_STOPPED),
        req(131.0, "a0", lift_request::END_SESSION, ""),
        req(200.0, "b0", lift_request::AGV_MODE, "L2"),
    ];
    for p in &seq {
        b.observe(p);
    }
    let r = b.finish(300.0, &[]);
    assert_eq!(r.lifts.len(), 1);
    let l = &r.lifts[0];
    assert_eq!((l.name.as_str(), l.sessions, l.trips), ("lift_1", 2, 2));
    assert_eq!(l.wait.count, 1);
    assert_eq!(l.wait.total_s, 110.0 - 100.0);
    assert_eq!(l.wait.unserved, 1);
}

#[test]
fn near_misses_and_contacts_once_per_approach() {
    let mut b = builder();
    // a0 (0.3) still at the origin; a1 (0.4) passes at y = 0.8 (near-miss distance
    // 0.3 + 0.4 + 0.3 = 1.0, contact 0.7), then back at y = 0.5 (a contact); b0 stays
    // right above a0 but one level up.
    let mut t = 0.0;
    for pass in [0.8, 0.5] {
        for k in 0..=100 {
            let x = -5.0 + 0.1 * k as f64;
            let x = if pass == 0.5 { -x } else { x };
            b.sample(t, &[at(0.0, 0.0, 0.0), at(x, pass, 0.0), at(0.0, 0.1, 3.0)]);
            t += 0.1;
        }
    }
    // Hovering around the near-miss distance of a0/a1 is one approach (hysteresis).
    for k in 0..20 {
        let y = if k % 2 == 0 { 0.99 } else { 1.05 };
        b.sample(t, &[at(0.0, 0.0, 0.0), at(0.0, y, 0.0), at(0.0, 0.1, 3.0)]);
        t += 0.1;
    }
    let r = b.finish(
        t,
        &[at(0.0, 0.0, 0.0), at(0.0, 5.0, 0.0), at(0.0, 0.1, 3.0)],
    );
    assert_eq!(r.near_misses.len(), 2, "{:#?}", r.near_misses);
    assert_eq!(r.contacts.len(), 1, "{:#?}", r.contacts);
    let first = &r.near_misses[0];
    assert_eq!(first.robots, ["a0".to_string(), "a1".to_string()]);
    // Closest at x = 0 (k = 50): distance 0.8.
    assert!((first.min_distance_m - 0.8).abs() < 1e-9, "{first:?}");
    assert!((first.t - 5.0).abs() < 1e-9, "{first:?}");
    assert!((first.near_miss_distance_m - 1.0).abs() < 1e-12);
    assert!((first.contact_distance_m - 0.7).abs() < 1e-12);
    let c = &r.contacts[0];
    assert!((c.min_distance_m - 0.5).abs() < 1e-9, "{c:?}");
    assert!((r.near_misses[1].min_distance_m - 0.99).abs() < 1e-12);
    // a0 never moved.
    assert!(r.robots[0].distance_m == 0.0);
}

#[test]
fn distance_is_summed_from_samples() {
    let mut b = builder();
    // a0 drives a 3-4-5 triangle's legs in 0.1 s steps: 3 m along x, 4 m along y.
    let mut t = 0.0;
    for k in 0..=30 {
        b.sample(
            t,
            &[
                at(0.1 * k as f64, 0.0, 0.0),
                at(50.0, 0.0, 0.0),
                at(90.0, 0.0, 0.0),
            ],
        );
        t += 0.1;
    }
    for k in 1..=40 {
        b.sample(
            t,
            &[
                at(3.0, 0.1 * k as f64, 0.0),
                at(50.0, 0.0, 0.0),
                at(90.0, 0.0, 0.0),
            ],
        );
        t += 0.1;
    }
    let r = b.finish(
        t,
        &[at(3.0, 4.0, 0.0), at(50.0, 0.0, 0.0), at(90.0, 0.0, 0.0)],
    );
    assert!(
        (r.robots[0].distance_m - 7.0).abs() < 1e-9,
        "{:?}",
        r.robots[0]
    );
    assert!((r.fleets[0].distance_m - 7.0).abs() < 1e-9);
    assert_eq!(r.fleets[1].distance_m, 0.0);
}

#[test]
fn a_robot_charging_with_a_task_queued_is_not_stuck() {
    let mut b = builder();
    let still = [at(0.0, 0.0, 0.0), at(10.0, 0.0, 0.0), at(20.0, 0.0, 0.0)];
    b.observe(&event(0.0, "t1", "queued", "", ""));
    b.observe(&event(0.0, "t1", "assigned", "a0", "a"));
    let state = |t: f64, mode: u32| Published {
        t,
        topic: Topic::RobotState,
        msg: Msg::RobotState(RobotState {
            name: "a0".into(),
            mode: RobotMode {
                mode,
                ..Default::default()
            },
            ..Default::default()
        }),
    };
    // Charging for 1000 s, then waiting without charging for 400 s.
    b.observe(&state(0.0, robot_mode::CHARGING));
    let mut t = 0.0;
    while t < 1000.0 {
        b.sample(t, &still);
        t += 10.0;
    }
    b.observe(&state(1000.0, robot_mode::IDLE));
    while t <= 1400.0 {
        b.sample(t, &still);
        t += 10.0;
    }
    let r = b.finish(1400.0, &still);
    let stuck: Vec<(&str, f64)> = r.stuck.iter().map(|s| (s.robot.as_str(), s.t)).collect();
    // Still since the last sample while it charged (990 s), stuck 300 s later.
    assert_eq!(stuck, [("a0", 990.0)]);
}

#[test]
fn tasks_utilisation_throughput_and_stuck() {
    let mut b = builder();
    let still = [at(0.0, 0.0, 0.0), at(10.0, 0.0, 0.0), at(20.0, 0.0, 0.0)];
    let seq = [
        event(0.0, "t1", "queued", "", ""),
        event(10.0, "t1", "assigned", "a0", "a"),
        event(12.0, "t1", "started", "a0", "a"),
        event(100.0, "t1", "completed", "a0", "a"),
        event(20.0, "t2", "queued", "", ""),
        event(30.0, "t2", "assigned", "a1", "a"),
        event(50.0, "t2", "failed", "a1", "a"),
        event(60.0, "t3", "queued", "", ""),
        event(70.0, "t3", "assigned", "b0", "b"),
        event(80.0, "t3", "deadlock", "b0", "b"),
        // Repeats of the same condition continue the episode; after a gap, a new one.
        event(84.0, "t3", "deadlock", "b0", "b"),
        event(88.0, "t3", "deadlock", "b0", "b"),
        event(200.0, "t3", "deadlock", "b0", "b"),
    ];
    for p in &seq {
        b.observe(p);
    }
    // b0 never moves while t3 is assigned (from 70 s): stuck after 300 s.
    let mut t = 0.0;
    while t < 600.0 {
        b.sample(t, &still);
        t += 10.0;
    }
    let r = b.finish(600.0, &still);
    let t1 = &r.tasks[0];
    assert_eq!(
        (t1.requested, t1.assigned, t1.started, t1.finished),
        (Some(0.0), Some(10.0), Some(12.0), Some(100.0))
    );
    assert_eq!(
        (t1.robot.as_str(), t1.fleet.as_str(), t1.result.as_str()),
        ("a0", "a", "completed")
    );
    assert_eq!(r.tasks[1].result, "failed");
    assert_eq!(r.tasks[2].result, "unfinished");
    let a = &r.fleets[0];
    assert_eq!((a.robots, a.tasks_completed, a.tasks_failed), (2, 1, 1));
    assert_eq!(a.throughput_per_hour, 1.0 / (600.0 / 3600.0));
    // a0 busy 10..100, a1 busy 30..50: (90 + 20) / (2 robots × 600 s).
    assert_eq!(a.utilisation, (90.0 + 20.0) / (2.0 * 600.0));
    // b0 busy from 70 s to the end.
    assert_eq!(r.fleets[1].utilisation, 530.0 / 600.0);
    // Idle while work waited: t1 waits 0..10 and t2 20..30 for fleet a; a0 (busy from
    // 10 s) is idle through t1's wait, a1 (busy from 30 s) through both; b0 through
    // t3's (60..70).
    let idle: Vec<f64> = r.robots.iter().map(|x| x.idle_with_work_s).collect();
    assert_eq!(idle, [10.0, 20.0, 10.0]);
    assert_eq!(
        (a.idle_with_work_s, r.fleets[1].idle_with_work_s),
        (30.0, 10.0)
    );
    assert_eq!(r.fleets[1].tasks_unfinished, 1);
    let reasons: Vec<(&str, &str, f64)> = r
        .stuck
        .iter()
        .map(|s| (s.robot.as_str(), s.reason.as_str(), s.t))
        .collect();
    assert_eq!(
        reasons,
        [
            ("b0", "no_motion", 70.0),
            ("b0", "deadlock", 80.0),
            ("b0", "deadlock", 200.0)
        ]
    );
    assert_eq!(r.stuck[0].task_id, "t3");
    // Still motionless at the last sample (the end of the run).
    assert_eq!((r.stuck[0].until, r.stuck[0].events), (600.0, 1));
    assert_eq!((r.stuck[1].until, r.stuck[1].events), (88.0, 3));
    assert_eq!((r.stuck[2].until, r.stuck[2].events), (200.0, 1));
    // The summary names the numbers.
    let s = r.summary();
    assert!(
        s.contains("tasks: 3 seen, 1 completed, 1 failed, 1 unfinished"),
        "{s}"
    );
    // Run end 600 s: the no_motion episode lasts to the end; the deadlocks ended at 88 s
    // and 200 s, more than 300 s before it.
    assert!(
        s.contains("stuck episodes: 3 (2 resolved, 1 unresolved at the end)"),
        "{s}"
    );
}

#[test]
fn report_json_keys_are_in_declaration_order() {
    let r = builder().finish(1.0, &[]);
    let j = serde_json::to_string(&r).unwrap();
    let keys = [
        "end_time",
        "tasks",
        "fleets",
        "robots",
        "doors",
        "lifts",
        "near_misses",
        "contacts",
        "stuck",
    ];
    let pos: Vec<usize> = keys
        .iter()
        .map(|k| j.find(&format!("\"{k}\"")).unwrap())
        .collect();
    assert!(pos.windows(2).all(|w| w[0] < w[1]), "{j}");
}
