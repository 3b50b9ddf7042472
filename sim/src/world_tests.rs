//! World tests: analytic timings of doors, lifts and slotcars, the battery model, the
//! supervisors, obstacle stops and the dispenser → robot → ingestor loop.

use super::*;
use crate::msgs::{
    door_mode, lift_request, pause_type, DoorMode, FleetState, Location, PathRequest, RobotState,
    Time, WorkcellRequest,
};
use crate::profile::{time_to_band, trapezoid_time};

/// One level, cartesian metres: a 1.5 m sliding door, a 90° hinged door of 1 m, a
/// charger far from everything, a dispenser and an ingestor.
const MAP: &str = r#"
coordinate_system: cartesian_meters
graphs: {}
levels:
  L1:
    doors:
      - [0, 1, {motion_axis: [1, start], motion_degrees: [3, 90], motion_direction: [2, 1], name: [1, slide], plugin: [1, normal], right_left_ratio: [3, 1], type: [1, sliding]}]
      - [2, 3, {motion_axis: [1, start], motion_degrees: [3, 90], motion_direction: [2, 1], name: [1, swing], plugin: [1, normal], right_left_ratio: [3, 1], type: [1, hinged]}]
    elevation: 0
    models:
      - {dispensable: false, model_name: TeleportDispenser, name: disp, static: true, x: 20, y: 0, yaw: 0, z: 0}
      - {dispensable: false, model_name: TeleportIngestor, name: ing, static: true, x: 30, y: 0, yaw: 0, z: 0}
    vertices:
      - [0, -50, 0, ""]
      - [1.5, -50, 0, ""]
      - [0, -60, 0, ""]
      - [1, -60, 0, ""]
      - [-100, -100, 0, charger, {is_charger: [4, true]}]
name: test
reference_level_name: L1
"#;

fn parse(text: &str) -> Building {
    let parsed = mapc_frontend::parse_str("test.building.yaml", text);
    assert!(!parsed.has_errors(), "{:?}", parsed.diagnostics);
    parsed.building.expect("building")
}

fn clinic() -> Building {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/two_level_clinic.building.yaml"
    );
    let text = std::fs::read_to_string(path).expect("fixture");
    parse(&text)
}

fn spawn(
    b: &Building,
    name: &str,
    params: RobotParams,
    x: f64,
    y: f64,
    yaw: f64,
    level: &str,
) -> RobotSpawn {
    RobotSpawn {
        name: name.into(),
        fleet: "f".into(),
        params,
        x,
        y,
        yaw,
        level: b.level_by_name(level).expect("level"),
    }
}

fn setup(robots: Vec<RobotSpawn>) -> WorldSetup {
    WorldSetup {
        dt: 0.01,
        seed: 7,
        robots,
        workcells: Vec::new(),
        lifts_start_at_initial_floor: true,
    }
}

fn loc(x: f64, y: f64, yaw: f64) -> Location {
    Location {
        x,
        y,
        yaw,
        level_name: "L1".into(),
        ..Location::default()
    }
}

fn path(w: &mut World, robot: &str, task: &str, pts: &[(f64, f64, f64)]) {
    w.deliver(
        Topic::RobotPathRequests,
        Msg::PathRequest(PathRequest {
            fleet_name: "f".into(),
            robot_name: robot.into(),
            path: pts.iter().map(|&(x, y, yaw)| loc(x, y, yaw)).collect(),
            task_id: task.into(),
        }),
    );
}

/// Steps until `done` or `limit` seconds; returns the time it became true.
fn run_until(
    w: &mut World,
    out: &mut Vec<Published>,
    limit: f64,
    mut done: impl FnMut(&World, &[Published]) -> bool,
) -> Option<f64> {
    let end = w.time() + limit;
    while w.time() < end {
        out.clear();
        w.step(out);
        if done(w, out) {
            return Some(w.time());
        }
    }
    None
}

fn door(w: &World, name: &str) -> u32 {
    let i = w.door_index[name];
    w.doors[i].mode
}

fn door_request(w: &mut World, topic: Topic, door: &str, who: &str, mode: u32, t: f64) {
    w.deliver(
        topic,
        Msg::DoorRequest(DoorRequest {
            request_time: Time::from_secs(t),
            requester_id: who.into(),
            door_name: door.into(),
            requested_mode: DoorMode { value: mode },
        }),
    );
}

#[test]
fn door_opening_times_match_the_trapezoid() {
    let b = parse(MAP);
    let mut w = World::new(&b, &setup(Vec::new()));
    let mut out = Vec::new();
    run_until(&mut w, &mut out, 0.5, |_, _| false);
    // Sliding 1.5 m at v 0.2, a_nom 0.08; hinged 90° = 1.57 rad (3.14·90/180) at 0.5, 0.15.
    // OPEN once every joint is within dx_min (0.001 m, 0.01 rad) of its open position.
    for (name, d, v, a, dx) in [
        ("slide", 1.5, 0.2, 0.08, 0.001),
        ("swing", 1.57, 0.5, 0.15, 0.01),
    ] {
        let t0 = w.time();
        door_request(
            &mut w,
            Topic::AdapterDoorRequests,
            name,
            "test",
            door_mode::OPEN,
            t0,
        );
        let t1 = run_until(&mut w, &mut out, 30.0, |w, _| {
            door(w, name) == door_mode::OPEN
        })
        .expect("opens");
        let want = time_to_band(d, v, a, dx);
        let got = t1 - t0;
        assert!(
            (got - want).abs() < 0.01 * want,
            "{name}: {got} s vs {want} s"
        );
        let t = w.time();
        door_request(
            &mut w,
            Topic::AdapterDoorRequests,
            name,
            "test",
            door_mode::CLOSED,
            t,
        );
        run_until(&mut w, &mut out, 30.0, |w, _| {
            door(w, name) == door_mode::CLOSED
        })
        .expect("closes");
    }
}

#[test]
fn door_states_are_published_at_1_hz() {
    let b = parse(MAP);
    let mut w = World::new(&b, &setup(Vec::new()));
    let mut out = Vec::new();
    let mut times = Vec::new();
    run_until(&mut w, &mut out, 10.0, |_, out| {
        times.extend(
            out.iter()
                .filter(|p| matches!(&p.msg, Msg::DoorState(s) if s.door_name == "slide"))
                .map(|p| p.t),
        );
        false
    });
    assert!(times.len() >= 9 && times.len() <= 10, "{times:?}");
    for pair in times.windows(2) {
        let gap = pair[1] - pair[0];
        assert!((1.0..1.0 + 0.011).contains(&gap), "{gap}");
    }
}

#[test]
fn door_supervisor_keeps_the_door_open_for_a_second_requester() {
    let b = parse(MAP);
    let mut w = World::new(&b, &setup(Vec::new()));
    let mut out = Vec::new();
    run_until(&mut w, &mut out, 0.5, |_, _| false);
    let t = w.time();
    door_request(
        &mut w,
        Topic::AdapterDoorRequests,
        "slide",
        "a",
        door_mode::OPEN,
        t,
    );
    door_request(
        &mut w,
        Topic::AdapterDoorRequests,
        "slide",
        "b",
        door_mode::OPEN,
        t,
    );
    run_until(&mut w, &mut out, 15.0, |w, _| {
        door(w, "slide") == door_mode::OPEN
    })
    .expect("opens");
    let t = w.time();
    door_request(
        &mut w,
        Topic::AdapterDoorRequests,
        "slide",
        "a",
        door_mode::CLOSED,
        t,
    );
    // The heartbeat still lists b's session.
    out.clear();
    w.step(&mut out);
    let hb = out
        .iter()
        .find_map(|p| match &p.msg {
            Msg::DoorHeartbeat(h) => Some(h.clone()),
            _ => None,
        })
        .expect("heartbeat");
    let sessions = &hb.all_sessions[0];
    assert_eq!(sessions.door_name, "slide");
    assert_eq!(sessions.sessions.len(), 1);
    assert_eq!(sessions.sessions[0].requester_id, "b");
    let closed = run_until(&mut w, &mut out, 20.0, |w, _| {
        door(w, "slide") != door_mode::OPEN
    });
    assert_eq!(closed, None, "door must stay open while b holds it");
    let t = w.time();
    door_request(
        &mut w,
        Topic::AdapterDoorRequests,
        "slide",
        "b",
        door_mode::CLOSED,
        t,
    );
    let t1 = run_until(&mut w, &mut out, 20.0, |w, _| {
        door(w, "slide") == door_mode::CLOSED
    })
    .expect("closes");
    assert!(t1 - t < trapezoid_time(1.5, 0.2, 0.08) + 0.2);
}

#[test]
fn door_supervisor_closes_doors_nobody_holds() {
    let b = parse(MAP);
    let mut w = World::new(&b, &setup(Vec::new()));
    let mut out = Vec::new();
    run_until(&mut w, &mut out, 0.5, |_, _| false);
    // Opened behind the supervisor's back: its reminder closes it again.
    let t = w.time();
    door_request(
        &mut w,
        Topic::DoorRequests,
        "slide",
        "rogue",
        door_mode::OPEN,
        t,
    );
    run_until(&mut w, &mut out, 15.0, |w, _| {
        door(w, "slide") == door_mode::MOVING
    })
    .expect("moves");
    run_until(&mut w, &mut out, 30.0, |w, _| {
        door(w, "slide") == door_mode::CLOSED
    })
    .expect("closed again");
}

/// Where the clinic's first lift cabin stands (x, y).
fn lift_xy(b: &Building) -> (f64, f64) {
    let l = b.lifts.iter().next().expect("lift").1;
    (l.pos.x, l.pos.y)
}

/// Asks lift_1 to `floor` with its doors open (session `s`) and steps until it is done,
/// within `limit` s; returns when.
fn lift_to(w: &mut World, out: &mut Vec<Published>, floor: &str, limit: f64) -> Option<f64> {
    let open = lift_request::DOOR_OPEN;
    w.deliver(
        Topic::AdapterLiftRequests,
        lift_req("lift_1", "s", lift_request::AGV_MODE, floor, open),
    );
    run_until(w, out, limit, |w, _| w.lifts[0].active_dest().is_none())
}

fn lift_req(lift: &str, session: &str, kind: u8, floor: &str, door: u8) -> Msg {
    Msg::LiftRequest(LiftRequest {
        lift_name: lift.into(),
        request_time: Time::default(),
        session_id: session.into(),
        request_type: kind,
        destination_floor: floor.into(),
        door_state: door,
    })
}

#[test]
fn lift_trip_time_is_doors_close_plus_cabin_plus_doors_open() {
    let b = clinic();
    let (lx, ly) = lift_xy(&b);
    let r = spawn(&b, "rider", RobotParams::default(), lx, ly, 0.0, "L1");
    let mut w = World::new(&b, &setup(vec![r]));
    let mut out = Vec::new();
    run_until(&mut w, &mut out, 0.5, |_, _| false);
    lift_to(&mut w, &mut out, "L1", 20.0).expect("doors open at L1");
    let t0 = w.time();
    let t1 = lift_to(&mut w, &mut out, "L2", 40.0).expect("arrives");
    // Each lift door leaf travels width/2 = 0.6 m at 0.3 m/s, 0.1 m/s²; the cabin 4 m at
    // 2 m/s, 1 m/s².
    // Doors count as closed/open within dx_min 1e-4 m; the cabin arrives within 0.001 m.
    let want = 2.0 * time_to_band(0.6, 0.3, 0.1, 1e-4) + time_to_band(4.0, 2.0, 1.0, 0.001);
    let got = t1 - t0;
    assert!((got - want).abs() < 0.01 * want, "{got} s vs {want} s");
    assert!((w.lifts[0].z - 4.0).abs() < 0.001);
    // The traffic planner's estimate of the ride (graph.rs) is this, plus the messages, and
    // a little more: it brakes at the nominal rate where the plugins brake harder.
    let nav = crate::graph::Nav::build(&b, &[0]);
    let ride = (0..nav.edges.len())
        .find(|&e| matches!(nav.edges[e].kind, crate::graph::EdgeKind::Lift(_)))
        .map(|e| nav.edge_cost(e, 1.0))
        .expect("a ride on graph 0");
    assert!(
        ride >= got && ride <= 1.05 * got + crate::graph::LIFT_MESSAGES,
        "{ride} s planned, {got} s ridden"
    );
    // The robot in the cabin rode along.
    let r = w.robots()[0];
    assert!((r.z - 4.0).abs() < 0.001, "robot z {}", r.z);
    let last_state = out.iter().rev().find_map(|p| match &p.msg {
        Msg::LiftState(s) => Some(s.clone()),
        _ => None,
    });
    let s = last_state.expect("state on change");
    assert_eq!(s.current_floor, "L2");
    assert_eq!(s.door_state, lift_state_open());
    assert_eq!(s.session_id, "s");
    // The rider now reports the upper level.
    let level = last_level(&mut w, &mut out);
    assert_eq!(level.as_deref(), Some("L2"));
}

#[test]
fn only_robots_on_the_cabin_floor_ride() {
    let b = clinic();
    let (lx, ly) = lift_xy(&b);
    let params = RobotParams::default;
    let rider = spawn(&b, "rider", params(), lx, ly, 0.0, "L1");
    // In the shaft on the floor above: the plugin's box (up to the cabin roof, 2.5 m)
    // would take it from 1.5 m on and leave it 2.5 m above its floor.
    let above = spawn(&b, "above", params(), lx, ly, 0.0, "L2");
    let mut w = World::new(&b, &setup(vec![rider, above]));
    let mut out = Vec::new();
    run_until(&mut w, &mut out, 0.5, |_, _| false);
    lift_to(&mut w, &mut out, "L2", 40.0).expect("arrives");
    let z: Vec<f64> = w.robots().iter().map(|r| r.z).collect();
    assert!((z[0] - 4.0).abs() < 0.001, "rider z {}", z[0]);
    // Taken along only for the last centimetres, as the cabin floor reached it.
    assert!((4.0..4.06).contains(&z[1]), "z of the robot above {}", z[1]);
}

/// The level named by the last RobotState published during the next second.
fn last_level(w: &mut World, out: &mut Vec<Published>) -> Option<String> {
    let mut level = None;
    run_until(w, out, 1.0, |_, out| {
        for p in out {
            if let Msg::RobotState(s) = &p.msg {
                level = Some(s.location.level_name.clone());
            }
        }
        false
    });
    level
}

#[test]
fn lift_start_floor_option() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/two_level_clinic.building.yaml"
    ))
    .expect("fixture")
    .replace("initial_floor_name: L1", "initial_floor_name: L2");
    let b = parse(&text);
    let mut s = setup(Vec::new());
    let w = World::new(&b, &s);
    assert_eq!(w.lifts[0].z, 4.0);
    // Gazebo's behaviour: the cabin starts at z = 0 and drives up, doors closed.
    s.lifts_start_at_initial_floor = false;
    let mut w = World::new(&b, &s);
    assert_eq!(w.lifts[0].z, 0.0);
    let mut out = Vec::new();
    let t = run_until(&mut w, &mut out, 20.0, |w, _| {
        w.lifts[0].active_dest().is_none()
    })
    .expect("arrives");
    // Two initialising updates, then the cabin trapezoid.
    let want = 0.02 + time_to_band(4.0, 2.0, 1.0, 0.001);
    assert!((t - want).abs() < 0.01 * want, "{t} vs {want}");
}

fn lift_state_open() -> u8 {
    crate::msgs::lift_state::DOOR_OPEN
}

#[test]
fn lift_supervisor_retries_a_request_the_busy_lift_dropped() {
    let b = clinic();
    let mut w = World::new(&b, &setup(Vec::new()));
    let mut out = Vec::new();
    run_until(&mut w, &mut out, 0.5, |_, _| false);
    let open = lift_request::DOOR_OPEN;
    w.deliver(
        Topic::AdapterLiftRequests,
        lift_req("lift_1", "a", lift_request::AGV_MODE, "L2", open),
    );
    run_until(&mut w, &mut out, 10.0, |w, _| w.lifts[0].v != 0.0).expect("departs");
    // While it moves, the session owner changes its mind: the plugin drops the request.
    w.deliver(
        Topic::AdapterLiftRequests,
        lift_req("lift_1", "a", lift_request::AGV_MODE, "L1", open),
    );
    out.clear();
    w.step(&mut out);
    assert_eq!(w.lifts[0].active_dest(), Some(1), "still bound for L2");
    // It reaches L2 first, then the supervisor's retry brings it back to L1.
    run_until(&mut w, &mut out, 30.0, |w, _| {
        (w.lifts[0].z - 4.0).abs() < 0.001
    })
    .expect("L2");
    run_until(&mut w, &mut out, 60.0, |w, out| {
        w.lifts[0].z.abs() < 0.001
            && out.iter().any(|p| matches!(&p.msg, Msg::LiftState(s)
                if s.current_floor == "L1" && s.door_state == lift_state_open() && s.session_id == "a"))
    })
    .expect("served at L1");
    // Another session is ignored while "a" owns the lift; END_SESSION releases it.
    w.deliver(
        Topic::AdapterLiftRequests,
        lift_req("lift_1", "b", lift_request::AGV_MODE, "L2", open),
    );
    run_until(&mut w, &mut out, 3.0, |_, _| false);
    assert!(w.lifts[0].z.abs() < 0.001);
    w.deliver(
        Topic::AdapterLiftRequests,
        lift_req("lift_1", "a", lift_request::END_SESSION, "L1", 0),
    );
    run_until(&mut w, &mut out, 10.0, |_, out| {
        out.iter().any(
            |p| matches!(&p.msg, Msg::LiftState(s) if s.session_id.is_empty() && s.door_state == 0),
        )
    })
    .expect("released, doors closed");
}

/// Time for a robot to drive `d` metres straight ahead from rest and stop.
fn straight_time(params: RobotParams, d: f64) -> (f64, f64, World) {
    let b = parse(MAP);
    let r = spawn(&b, "r", params, 0.0, 0.0, 0.0, "L1");
    let mut w = World::new(&b, &setup(vec![r]));
    let mut out = Vec::new();
    run_until(&mut w, &mut out, 1.0, |_, _| false);
    let t0 = w.time();
    path(&mut w, "r", "1", &[(0.0, 0.0, 0.0), (d, 0.0, 0.0)]);
    let mut moved = false;
    let t1 = run_until(&mut w, &mut out, 10.0 * d + 100.0, |w, _| {
        let r = w.robots()[0];
        moved |= r.v != 0.0;
        moved && r.v == 0.0
    })
    .expect("stops");
    (t0, t1, w)
}

#[test]
fn slotcar_straight_lane_time_matches_the_trapezoid() {
    for (params, d) in [
        (RobotParams::preset("TinyRobot").expect("preset"), 10.0),
        (RobotParams::default(), 20.0),
        (RobotParams::default(), 3.0),
    ] {
        let (v, a) = (
            params.nominal_drive_speed,
            params.nominal_drive_acceleration,
        );
        let (t0, t1, w) = straight_time(params.clone(), d);
        // The trapezoid, except that the waypoint counts as reached 0.02 m early, at
        // v_tol = sqrt(2·a·0.02), from where the robot brakes at a_max, not a_nom.
        let v_tol = (2.0 * a * 0.02).sqrt();
        let a_max = params.max_drive_acceleration;
        let want = trapezoid_time(d, v, a) - v_tol / a + v_tol / a_max;
        let got = t1 - t0;
        assert!(
            (got - want).abs() < 0.01 * want,
            "{}: {got} s vs {want} s",
            params.model
        );
        let r = w.robots()[0];
        assert!((r.x - d).abs() < 0.02 && r.y.abs() < 1e-9, "{r:?}");
    }
}

#[test]
fn battery_drain_over_a_straight_path() {
    for (params, d) in [
        (RobotParams::default(), 20.0),
        (RobotParams::preset("TinyRobot").expect("preset"), 10.0),
    ] {
        let b = parse(MAP);
        let r = spawn(&b, "r", params.clone(), 0.0, 0.0, 0.0, "L1");
        let mut w = World::new(&b, &setup(vec![r]));
        let mut out = Vec::new();
        run_until(&mut w, &mut out, 1.0, |_, _| false);
        let (t0, soc0) = (w.time(), w.soc(0).expect("robot"));
        path(&mut w, "r", "1", &[(0.0, 0.0, 0.0), (d, 0.0, 0.0)]);
        run_until(&mut w, &mut out, 200.0, |_, _| false);
        let (t1, soc1) = (w.time(), w.soc(0).expect("robot"));
        let p = &params;
        let v = p.nominal_drive_speed;
        // Device power over the whole window, friction over the distance, and the
        // acceleration term ∫ m·|a|·v dt = m·v²/2 speeding up plus m·v²/2 braking.
        let energy = p.nominal_power * (t1 - t0)
            + p.friction_coefficient * p.mass * 9.81 * d
            + p.mass * v * v;
        let want = energy / p.nominal_voltage / (p.nominal_capacity * 3600.0);
        let got = soc0 - soc1;
        assert!(
            (got - want).abs() < 0.01 * want,
            "{}: {got} vs {want}",
            p.model
        );
    }
}

#[test]
fn robot_state_is_published_at_2_hz_with_the_level_and_path() {
    let b = parse(MAP);
    let r = spawn(&b, "r", RobotParams::default(), 0.0, 0.0, 0.0, "L1");
    let mut w = World::new(&b, &setup(vec![r]));
    let mut out = Vec::new();
    path(
        &mut w,
        "r",
        "7",
        &[(0.0, 0.0, 0.0), (5.0, 0.0, 0.0), (5.0, 5.0, 0.0)],
    );
    let mut states: Vec<(f64, RobotState)> = Vec::new();
    run_until(&mut w, &mut out, 5.0, |_, out| {
        states.extend(out.iter().filter_map(|p| match &p.msg {
            Msg::RobotState(s) => Some((p.t, s.clone())),
            _ => None,
        }));
        false
    });
    assert!(states.len() >= 9 && states.len() <= 10, "{}", states.len());
    for (k, (_, s)) in states.iter().enumerate() {
        assert_eq!(s.seq, k as u64 + 1);
        assert_eq!(s.location.level_name, "L1");
        assert_eq!(s.task_id, "7");
        assert_eq!(s.path.len(), 2);
    }
    for pair in states.windows(2) {
        let gap = pair[1].0 - pair[0].0;
        assert!(gap > 0.5 && gap < 0.52, "{gap}");
    }
}

#[test]
fn slotcar_turns_more_than_90_degrees_to_the_final_yaw() {
    let b = parse(MAP);
    let r = spawn(&b, "r", RobotParams::default(), 0.0, 0.0, 0.0, "L1");
    let mut w = World::new(&b, &setup(vec![r]));
    let mut out = Vec::new();
    let target = 3.0;
    path(&mut w, "r", "1", &[(0.0, 0.0, target)]);
    // A one-point path is dropped whole (the first point is "where the robot is").
    run_until(&mut w, &mut out, 2.0, |_, _| false);
    assert_eq!(w.robots()[0].yaw, 0.0);
    path(&mut w, "r", "2", &[(0.0, 0.0, 0.0), (0.0, 0.0, target)]);
    run_until(&mut w, &mut out, 60.0, |_, _| false);
    let r = w.robots()[0];
    assert!((r.yaw - target).abs() < 0.01, "yaw {}", r.yaw);
}

#[test]
fn non_reversible_robot_turns_around_for_a_waypoint_behind() {
    let b = parse(MAP);
    let params = RobotParams::preset("HospitalRobot").expect("preset");
    let r = spawn(&b, "r", params, 0.0, 0.0, 0.0, "L1");
    let mut w = World::new(&b, &setup(vec![r]));
    let mut out = Vec::new();
    path(
        &mut w,
        "r",
        "1",
        &[(0.0, 0.0, 0.0), (-3.0, 0.0, std::f64::consts::PI)],
    );
    run_until(&mut w, &mut out, 60.0, |_, _| false);
    let r = w.robots()[0];
    assert!((r.x + 3.0).abs() < 0.02 && r.y.abs() < 0.05, "{r:?}");
}

#[test]
fn robot_stops_for_a_robot_ahead_and_resumes() {
    let b = parse(MAP);
    let tiny = RobotParams::preset("TinyRobot").expect("preset");
    let a = spawn(&b, "a", tiny.clone(), 0.0, 0.0, 0.0, "L1");
    let blocker = spawn(&b, "b", tiny.clone(), 4.0, 0.0, 0.0, "L1");
    let mut w = World::new(&b, &setup(vec![a, blocker]));
    let mut out = Vec::new();
    path(&mut w, "a", "1", &[(0.0, 0.0, 0.0), (10.0, 0.0, 0.0)]);
    let mut waiting = false;
    run_until(&mut w, &mut out, 30.0, |_, out| {
        waiting |= out.iter().any(|p| matches!(&p.msg, Msg::RobotState(s) if s.name == "a" && s.mode.mode == crate::msgs::robot_mode::WAITING));
        false
    });
    assert!(waiting, "a reports WAITING");
    let ra = w.robots()[0];
    assert_eq!(ra.v, 0.0);
    // It brakes (at a_max) from where its stop zone, stop_distance ahead, comes within
    // stop_radius of the blocker.
    let stop_x = 4.0 - tiny.stop_distance - tiny.stop_radius;
    let v = tiny.nominal_drive_speed;
    let braking = v * v / (2.0 * tiny.max_drive_acceleration);
    assert!((ra.x - (stop_x + braking)).abs() < 0.01, "a at {}", ra.x);
    // The blocker leaves sideways; a goes on to its goal.
    path(
        &mut w,
        "b",
        "1",
        &[(4.0, 0.0, 0.0), (4.0, 5.0, std::f64::consts::FRAC_PI_2)],
    );
    run_until(&mut w, &mut out, 60.0, |_, _| false);
    let ra = w.robots()[0];
    assert!((ra.x - 10.0).abs() < 0.02, "a at {}", ra.x);
}

#[test]
fn pause_immediately_stops_and_resume_continues() {
    let b = parse(MAP);
    let r = spawn(&b, "r", RobotParams::default(), 0.0, 0.0, 0.0, "L1");
    let mut w = World::new(&b, &setup(vec![r]));
    let mut out = Vec::new();
    path(&mut w, "r", "1", &[(0.0, 0.0, 0.0), (20.0, 0.0, 0.0)]);
    run_until(&mut w, &mut out, 10.0, |_, _| false);
    let pause = |kind| {
        Msg::PauseRequest(crate::msgs::PauseRequest {
            fleet_name: "f".into(),
            robot_name: "r".into(),
            mode_request_id: 3,
            kind,
            at_checkpoint: 0,
        })
    };
    w.deliver(
        Topic::RobotPauseRequests,
        pause(pause_type::PAUSE_IMMEDIATELY),
    );
    run_until(&mut w, &mut out, 10.0, |_, _| false);
    let x = w.robots()[0].x;
    assert_eq!(w.robots()[0].v, 0.0);
    assert_eq!(w.robots[0].mode(), crate::msgs::robot_mode::PAUSED);
    w.deliver(Topic::RobotPauseRequests, pause(pause_type::RESUME));
    run_until(&mut w, &mut out, 60.0, |_, _| false);
    assert!(w.robots()[0].x > x + 5.0);
    assert!((w.robots()[0].x - 20.0).abs() < 0.02);
}

#[test]
fn far_first_waypoint_is_an_adapter_error_and_the_robot_holds() {
    let b = parse(MAP);
    let r = spawn(&b, "r", RobotParams::default(), 0.0, 0.0, 0.0, "L1");
    let mut w = World::new(&b, &setup(vec![r]));
    let mut out = Vec::new();
    path(&mut w, "r", "1", &[(5.0, 0.0, 0.0), (10.0, 0.0, 0.0)]);
    let mut modes = Vec::new();
    run_until(&mut w, &mut out, 5.0, |_, out| {
        modes.extend(out.iter().filter_map(|p| match &p.msg {
            Msg::RobotState(s) => Some(s.mode.mode),
            _ => None,
        }));
        false
    });
    assert!(
        modes
            .iter()
            .all(|&m| m == crate::msgs::robot_mode::ADAPTER_ERROR),
        "{modes:?}"
    );
    let r = w.robots()[0];
    assert_eq!((r.x, r.y), (0.0, 0.0));
}

#[test]
fn unknown_targets_are_ignored() {
    let b = parse(MAP);
    let mut w = World::new(&b, &setup(Vec::new()));
    let mut out = Vec::new();
    path(&mut w, "nobody", "1", &[(0.0, 0.0, 0.0)]);
    door_request(
        &mut w,
        Topic::DoorRequests,
        "no_door",
        "x",
        door_mode::OPEN,
        0.0,
    );
    door_request(
        &mut w,
        Topic::AdapterDoorRequests,
        "no_door",
        "x",
        door_mode::OPEN,
        0.0,
    );
    w.deliver(Topic::LiftRequests, lift_req("no_lift", "s", 1, "L1", 2));
    w.deliver(
        Topic::AdapterLiftRequests,
        lift_req("no_lift", "s", 1, "L9", 2),
    );
    w.deliver(Topic::RobotPathRequests, Msg::TaskEvent(Default::default()));
    run_until(&mut w, &mut out, 2.0, |_, _| false);
}

fn workcell_req(kind: Topic, target: &str, guid: &str) -> (Topic, Msg) {
    (
        kind,
        Msg::WorkcellRequest(WorkcellRequest {
            time: Time::default(),
            request_guid: guid.into(),
            target_guid: target.into(),
            transporter_type: "f".into(),
            items: Vec::new(),
        }),
    )
}

fn results(out: &[Published], topic: Topic) -> Vec<u8> {
    out.iter()
        .filter(|p| p.topic == topic)
        .filter_map(|p| match &p.msg {
            Msg::WorkcellResult(r) => Some(r.status),
            _ => None,
        })
        .collect()
}

/// Asks workcell `target` (request `guid` on `topic`) and steps once: the statuses of the
/// results it sent (on the matching results topic).
fn ask(w: &mut World, out: &mut Vec<Published>, topic: Topic, target: &str, guid: &str) -> Vec<u8> {
    let (t, m) = workcell_req(topic, target, guid);
    w.deliver(t, m);
    out.clear();
    w.step(out);
    let results_topic = if topic == Topic::DispenserRequests {
        Topic::DispenserResults
    } else {
        Topic::IngestorResults
    };
    results(out, results_topic)
}

/// A world on `b` with one TinyRobot `r` of fleet `f` at the dispenser `disp` (20, 0),
/// which has just been asked (`d1`) for its item: served at the next step.
fn at_dispenser_asking(b: &Building) -> (World, Vec<Published>) {
    let r = spawn(
        b,
        "r",
        RobotParams::preset("TinyRobot").expect("preset"),
        20.0,
        0.0,
        0.0,
        "L1",
    );
    let mut w = World::new(b, &setup(vec![r]));
    w.deliver(
        Topic::FleetStates,
        Msg::FleetState(FleetState {
            name: "f".into(),
            robots: vec![RobotState {
                name: "r".into(),
                ..RobotState::default()
            }],
        }),
    );
    let (t, m) = workcell_req(Topic::DispenserRequests, "disp", "d1");
    w.deliver(t, m);
    (w, Vec::new())
}

#[test]
fn dispenser_robot_ingestor_item_loop() {
    let b = parse(MAP);
    let (mut w, mut out) = at_dispenser_asking(&b);
    out.clear();
    w.step(&mut out);
    assert_eq!(results(&out, Topic::DispenserResults), vec![0, 1]);
    let item = w
        .items
        .iter()
        .position(|i| i.name == "disp_item")
        .expect("item");
    assert_eq!(w.items[item].attached.map(|a| a.0), Some(0));
    // The item rides on the robot to the ingestor.
    path(&mut w, "r", "1", &[(20.0, 0.0, 0.0), (30.0, 0.0, 0.0)]);
    run_until(&mut w, &mut out, 40.0, |_, _| false);
    let p = w.items[item].pos;
    assert!(
        (p[0] - 30.0).abs() < 0.02 && (p[2] - 0.5).abs() < 1e-9,
        "{p:?}"
    );
    // A repeated dispenser request gets its recorded result, nothing more.
    assert_eq!(
        ask(&mut w, &mut out, Topic::DispenserRequests, "disp", "d1"),
        vec![1]
    );
    assert_eq!(
        ask(&mut w, &mut out, Topic::IngestorRequests, "ing", "i1"),
        vec![0, 1]
    );
    assert_eq!(w.items[item].pos, [30.0, 0.0, 0.0]);
    assert!(w.items[item].attached.is_none());
    // A request while the item is still held waits until it went home (five whole
    // seconds), then fails: nothing left near the robot.
    let t_ingest = w.time() - 0.01;
    let (t, m) = workcell_req(Topic::IngestorRequests, "ing", "i2");
    w.deliver(t, m);
    let mut answers = Vec::new();
    let mut states = 0;
    run_until(&mut w, &mut out, 9.0, |_, out| {
        for p in out {
            match &p.msg {
                Msg::WorkcellResult(r) if p.topic == Topic::IngestorResults => {
                    answers.push((p.t, r.status))
                }
                Msg::WorkcellState(_) if p.topic == Topic::IngestorStates => states += 1,
                _ => {}
            }
        }
        false
    });
    let back = t_ingest.floor() + 5.0;
    assert_eq!(answers.iter().map(|a| a.1).collect::<Vec<_>>(), vec![0, 2]);
    assert!(
        answers[0].0 >= back && answers[0].0 < back + 1.0,
        "{answers:?}"
    );
    assert!(states <= 6, "{states} ingestor states in 9 s");
    // Home again; the dispenser refills and serves again.
    assert_eq!(w.items[item].pos, [20.0, 0.0, 0.0]);
    path(&mut w, "r", "2", &[(30.0, 0.0, 0.0), (20.0, 0.0, 0.0)]);
    run_until(&mut w, &mut out, 40.0, |_, _| false);
    assert_eq!(
        ask(&mut w, &mut out, Topic::DispenserRequests, "disp", "d2"),
        vec![0, 1]
    );
    // Empty now: the next request fails.
    assert_eq!(
        ask(&mut w, &mut out, Topic::DispenserRequests, "disp", "d3"),
        vec![0, 2]
    );
}

/// An ingestor at a place where a dispenser's own item waits takes the item the robot
/// brings, not the one waiting (the nearest): else the delivered item stayed on the robot
/// and its dispenser never refilled, and every later delivery from it failed.
#[test]
fn an_ingestor_takes_the_carried_item_before_one_waiting_beside_it() {
    let map = MAP.replace(
        "      - {dispensable: false, model_name: TeleportIngestor",
        "      - {dispensable: false, model_name: TeleportDispenser, name: disp2, static: true, x: 30, y: 0, yaw: 0, z: 0}\n      - {dispensable: false, model_name: TeleportIngestor",
    );
    let b = parse(&map);
    let (mut w, mut out) = at_dispenser_asking(&b);
    w.step(&mut out);
    let item = |w: &World, name: &str| w.items.iter().position(|i| i.name == name).expect(name);
    let (carried, waiting) = (item(&w, "disp_item"), item(&w, "disp2_item"));
    assert_eq!(w.items[carried].attached.map(|a| a.0), Some(0));
    path(&mut w, "r", "1", &[(20.0, 0.0, 0.0), (30.0, 0.0, 0.0)]);
    run_until(&mut w, &mut out, 40.0, |_, _| false);
    // The waiting item is nearer the robot's origin (0 m against 0.5 m).
    let d = |i: usize| w.items[i].distance([30.0, 0.0, 0.0]);
    assert!(d(waiting) < d(carried), "{} {}", d(waiting), d(carried));
    assert_eq!(
        ask(&mut w, &mut out, Topic::IngestorRequests, "ing", "i1"),
        vec![0, 1]
    );
    assert!(w.items[carried].attached.is_none());
    assert_eq!(w.items[carried].pos, [30.0, 0.0, 0.0]);
    // Five whole seconds later it is home, and its dispenser serves again.
    run_until(&mut w, &mut out, 8.0, |_, _| false);
    assert_eq!(w.items[carried].pos, [20.0, 0.0, 0.0]);
    assert_eq!(w.items[waiting].pos, [30.0, 0.0, 0.0]);
    path(&mut w, "r", "2", &[(30.0, 0.0, 0.0), (20.0, 0.0, 0.0)]);
    run_until(&mut w, &mut out, 40.0, |_, _| false);
    assert_eq!(
        ask(&mut w, &mut out, Topic::DispenserRequests, "disp", "d2"),
        vec![0, 1]
    );
}

#[test]
fn robots_on_a_charger_charge_and_report_charging() {
    let b = parse(MAP);
    let r = spawn(&b, "r", RobotParams::default(), -100.0, -100.0, 0.0, "L1");
    let mut w = World::new(&b, &setup(vec![r]));
    w.robots[0].soc = 0.5;
    let mut out = Vec::new();
    let mut modes = Vec::new();
    run_until(&mut w, &mut out, 100.0, |_, out| {
        modes.extend(out.iter().filter_map(|p| match &p.msg {
            Msg::RobotState(s) => Some(s.mode.mode),
            _ => None,
        }));
        false
    });
    let p = RobotParams::default();
    // Charging starts with the second update (the first one initialises).
    let want = 0.5 + p.charging_current * (100.0 - 0.01) / (p.nominal_capacity * 3600.0);
    let got = w.soc(0).expect("robot");
    assert!((got - want).abs() < 1e-6, "{got} vs {want}");
    assert!(
        modes
            .iter()
            .skip(1)
            .all(|&m| m == crate::msgs::robot_mode::CHARGING),
        "{modes:?}"
    );
}

/// `n` robots shuttling along parallel 60 m lanes 2 m apart (staggered starts so some
/// pass within each other's stop zones' reach), stepped for `secs` simulated seconds.
/// Returns ns per step.
fn bench(n: usize, secs: f64) -> f64 {
    let b = parse(MAP);
    let tiny = RobotParams::preset("TinyRobot").expect("preset");
    let robots = (0..n)
        .map(|i| {
            spawn(
                &b,
                &format!("r{i}"),
                tiny.clone(),
                (i % 7) as f64,
                2.0 * i as f64,
                0.0,
                "L1",
            )
        })
        .collect();
    let mut w = World::new(&b, &setup(robots));
    let mut out = Vec::new();
    let mut task = 0u64;
    let steps = (secs / 0.01) as u64;
    let start = std::time::Instant::now();
    for k in 0..steps {
        if k % 100 == 0 {
            for i in 0..n {
                let r = &w.robots[i];
                if r.v == 0.0 && r.w == 0.0 {
                    let (x, y) = (r.x, r.y);
                    let gx = if x < 30.0 { 60.0 } else { 0.0 };
                    task += 1;
                    path(
                        &mut w,
                        &format!("r{i}"),
                        &task.to_string(),
                        &[(x, y, 0.0), (gx, y, 0.0)],
                    );
                }
            }
        }
        out.clear();
        w.step(&mut out);
    }
    start.elapsed().as_nanos() as f64 / steps as f64
}

/// `cargo test -p mapc-sim --release bench_world -- --ignored --nocapture`
#[test]
#[ignore]
fn bench_world() {
    // BENCH_ROBOTS=20 runs one size (e.g. under `perf stat`); the best of 3 runs is
    // reported since the machine is shared.
    let sizes: Vec<usize> = match std::env::var("BENCH_ROBOTS") {
        Ok(v) => v.split(',').filter_map(|s| s.trim().parse().ok()).collect(),
        Err(_) => vec![5, 20, 80],
    };
    for n in sizes {
        let secs = std::env::var("BENCH_SECS")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(2000.0);
        let ns = (0..3).map(|_| bench(n, secs)).fold(f64::INFINITY, f64::min);
        println!(
            "{n} robots: {ns:.0} ns/step ({:.0}x real time at dt 0.01)",
            1e7 / ns
        );
    }
}

#[test]
fn robot_reports_its_own_level_when_levels_share_an_elevation() {
    let text = MAP.replace(
        "name: test\n",
        "  L1b:\n    elevation: 0\n    vertices:\n      - [0, 0, 0, \"\"]\nname: test\n",
    );
    let b = parse(&text);
    let r = spawn(&b, "r", RobotParams::default(), 0.0, 0.0, 0.0, "L1b");
    let mut w = World::new(&b, &setup(vec![r]));
    let mut out = Vec::new();
    let level = last_level(&mut w, &mut out);
    assert_eq!(level.as_deref(), Some("L1b"));
}

#[test]
fn charge_toggles_apply_to_every_robot() {
    let b = parse(MAP);
    let on_charger = spawn(&b, "a", RobotParams::default(), -100.0, -100.0, 0.0, "L1");
    let away = spawn(&b, "b", RobotParams::default(), 0.0, 0.0, 0.0, "L1");
    let mut w = World::new(&b, &setup(vec![on_charger, away]));
    w.robots[0].soc = 0.5;
    w.set_charging(true, true, false);
    let mut out = Vec::new();
    run_until(&mut w, &mut out, 1.0, |_, _| false);
    assert_eq!(w.soc(0), Some(1.0), "instant charge");
    assert_eq!(w.soc(1), Some(1.0), "no drain");
    assert_eq!(w.soc(2), None);
}

/// Every demo map: a world with one robot per charger steps for a simulated minute
/// without panicking, every ROS door publishes its state and every lift its state.
#[test]
fn demo_maps_step() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/maps");
    let Ok(dirs) = std::fs::read_dir(&root) else {
        println!("skipped: ../shared not found");
        return;
    };
    let mut names: Vec<_> = dirs.filter_map(|d| d.ok()).map(|d| d.file_name()).collect();
    names.sort();
    for name in names {
        let name = name.to_string_lossy().to_string();
        let path = root.join(&name).join(format!("{name}.building.yaml"));
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue;
        };
        let parsed = mapc_frontend::parse_str(&name, &text);
        let Some(b) = parsed.building else {
            continue;
        };
        let robots = b
            .vertices
            .iter()
            .filter(|(_, v)| v.roles.is_charger)
            .enumerate()
            .map(|(i, (_, v))| RobotSpawn {
                name: format!("r{i}"),
                fleet: "f".into(),
                params: RobotParams::default(),
                x: v.pos.x,
                y: v.pos.y,
                yaw: 0.0,
                level: v.level,
            })
            .collect();
        let mut w = World::new(&b, &setup(robots));
        let mut out = Vec::new();
        let mut doors = std::collections::BTreeSet::new();
        let mut lifts = std::collections::BTreeSet::new();
        run_until(&mut w, &mut out, 60.0, |_, out| {
            for p in out {
                match &p.msg {
                    Msg::DoorState(s) => {
                        doors.insert(s.door_name.clone());
                    }
                    Msg::LiftState(s) => {
                        lifts.insert(s.lift_name.clone());
                    }
                    _ => {}
                }
            }
            false
        });
        assert_eq!(doors.len(), w.door_index.len(), "{name}");
        assert_eq!(lifts.len(), w.lifts.len(), "{name}");
        for r in w.robots() {
            assert!(
                r.x.is_finite() && r.y.is_finite() && r.z.is_finite(),
                "{name}"
            );
        }
    }
}

/// Idle cost on each demo map (robots parked on chargers, doors and lifts at rest):
/// `cargo test -p mapc-sim --release bench_demo_idle -- --ignored --nocapture`
#[test]
#[ignore]
fn bench_demo_idle() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/maps");
    let Ok(dirs) = std::fs::read_dir(&root) else {
        println!("skipped: ../shared not found");
        return;
    };
    let mut names: Vec<_> = dirs.filter_map(|d| d.ok()).map(|d| d.file_name()).collect();
    names.sort();
    for name in names {
        let name = name.to_string_lossy().to_string();
        let path = root.join(&name).join(format!("{name}.building.yaml"));
        let Some(b) = std::fs::read_to_string(&path)
            .ok()
            .and_then(|t| mapc_frontend::parse_str(&name, &t).building)
        else {
            continue;
        };
        let robots: Vec<RobotSpawn> = b
            .vertices
            .iter()
            .filter(|(_, v)| v.roles.is_charger)
            .enumerate()
            .map(|(i, (_, v))| RobotSpawn {
                name: format!("r{i}"),
                fleet: "f".into(),
                params: RobotParams::default(),
                x: v.pos.x,
                y: v.pos.y,
                yaw: 0.0,
                level: v.level,
            })
            .collect();
        let n = robots.len();
        let mut w = World::new(&b, &setup(robots));
        let mut out = Vec::new();
        let steps = 100_000;
        let start = std::time::Instant::now();
        for _ in 0..steps {
            out.clear();
            w.step(&mut out);
        }
        let ns = start.elapsed().as_nanos() as f64 / steps as f64;
        println!(
            "{name}: {n} robots, {} doors, {} lifts: {ns:.0} ns/step",
            w.doors.len(),
            w.lifts.len()
        );
    }
}

#[test]
fn a_lift_between_levels_at_one_elevation_gets_there() {
    // The clinic with L2 drawn at L1's elevation (a public map does this with eight
    // levels): the world stacks L2 a storey above L1 (`levels.rs`), so the cabin rides
    // there. With both floors at 0 m the cabin reported L1 for good, never arrived at L2,
    // and its riders waited for hours.
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/two_level_clinic.building.yaml"
    );
    let text = std::fs::read_to_string(path).expect("fixture");
    assert!(text.contains("elevation: 4"));
    let b = parse(&text.replace("elevation: 4", "elevation: 0"));
    let mut w = World::new(&b, &setup(Vec::new()));
    let mut out = Vec::new();
    run_until(&mut w, &mut out, 0.5, |_, _| false);
    lift_to(&mut w, &mut out, "L1", 20.0).expect("doors open at L1");
    lift_to(&mut w, &mut out, "L2", 40.0).expect("at L2");
    let s = out
        .iter()
        .rev()
        .find_map(|p| match &p.msg {
            Msg::LiftState(s) => Some(s.clone()),
            _ => None,
        })
        .expect("a state");
    assert_eq!(s.current_floor, "L2");
    assert_eq!(s.door_state, lift_state_open());
    assert!(
        (w.lifts[0].z - 4.0).abs() < 0.001,
        "cabin at {}",
        w.lifts[0].z
    );
}
