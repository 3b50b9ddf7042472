//! End-to-end runs of the fleet layer against the real World (slotcars, doors, lifts,
//! supervisors, workcells), checking ground truth every step.

use super::*;
use crate::msgs::{LiftRequest, Msg, Published, TaskEvent};
use crate::params::RobotParams;
use crate::scenario::{FleetSpec, SimOptions, TaskSpec, WorkcellSpec};
use crate::world::{World, WorldSetup};
use mapc_ir::{Building, Span};

fn load(name: &str, text: Option<&str>) -> Building {
    let owned;
    let text = match text {
        Some(t) => t,
        None => {
            let path = format!(
                "{}/../fixtures/{name}.building.yaml",
                env!("CARGO_MANIFEST_DIR")
            );
            owned = std::fs::read_to_string(path).expect("fixture");
            &owned
        }
    };
    let parsed = mapc_frontend::parse_str(name, text);
    assert!(!parsed.has_errors(), "{:?}", parsed.diagnostics);
    parsed.building.expect("map parses")
}

fn fleet(name: &str, count: usize, spawn: SpawnSpec) -> FleetSpec {
    FleetSpec {
        name: name.into(),
        graph: 0,
        robot: RobotParams::preset("TinyRobot").expect("preset"),
        count,
        spawn,
        recharge_threshold: 0.1,
        recharge_soc: 0.9,
        task_kinds: Vec::new(),
        span: Span::UNKNOWN,
        rmf: None,
    }
}

fn scenario(fleets: Vec<FleetSpec>, tasks: Vec<TaskSpec>) -> Scenario {
    Scenario {
        map: None,
        seed: 7,
        duration: 1200.0,
        step: 0.01,
        fleets,
        workcells: Vec::new(),
        tasks,
        generators: Vec::new(),
        faults: Vec::new(),
        options: SimOptions::default(),
        requests: Vec::new(),
        cancels: Vec::new(),
    }
}

/// A go_to_place task for any fleet.
fn go_to(at: f64, place: &str) -> TaskSpec {
    task(
        at,
        None,
        TaskKind::GoToPlace {
            place: place.into(),
        },
    )
}

fn task(at: f64, fleet: Option<&str>, kind: TaskKind) -> TaskSpec {
    TaskSpec {
        at,
        kind,
        fleet: fleet.map(str::to_string),
        robot: None,
        priority: 0,
        span: Span::UNKNOWN,
    }
}

struct Run {
    events: Vec<TaskEvent>,
    published: Vec<Published>,
    /// Smallest (centre distance − footprint sum) between robots on one floor.
    min_gap: f64,
    world: World,
}

fn run(b: &Building, s: &Scenario, seconds: f64) -> Run {
    run_checked(b, s, seconds, &mut |_, _| {})
}

thread_local! {
    /// Keep running after every task ended (to watch charging).
    static RUN_TO_END: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// The fleets and the world of scenario `s` on `b`, lifts at their initial floors.
fn start(b: &Building, s: &Scenario) -> (Fleets, World) {
    let placement = Fleets::place(b, s).expect("placement");
    let fleets = Fleets::new(b, s, &placement).expect("fleets");
    let setup = WorldSetup {
        dt: s.step,
        seed: s.seed,
        robots: placement.robots.clone(),
        workcells: placement.workcells.clone(),
        lifts_start_at_initial_floor: true,
    };
    (fleets, World::new(b, &setup))
}

/// Like `run`, calling `check(world, published this step)` after every step.
fn run_checked(
    b: &Building,
    s: &Scenario,
    seconds: f64,
    check: &mut dyn FnMut(&mut World, &[Published]),
) -> Run {
    let (mut fleets, mut world) = start(b, s);
    let mut inbox = Vec::new();
    let mut out = Vec::new();
    let mut events = Vec::new();
    let mut published = Vec::new();
    let mut min_gap = f64::INFINITY;
    let steps = (seconds / s.step).round() as u64;
    for _ in 0..steps {
        let t = world.time();
        out.clear();
        fleets.update(t, &inbox, &mut out);
        inbox.clear();
        for (topic, msg) in out.drain(..) {
            if let Msg::TaskEvent(e) = &msg {
                events.push(e.clone());
            } else {
                published.push(Published {
                    t,
                    topic,
                    msg: msg.clone(),
                });
                world.deliver(topic, msg);
            }
        }
        world.step(&mut inbox);
        check(&mut world, &inbox);
        published.extend(inbox.iter().cloned());
        let robots = world.robots();
        for (i, a) in robots.iter().enumerate() {
            for c in &robots[i + 1..] {
                if (a.z - c.z).abs() < 0.5 {
                    let gap = (a.x - c.x).hypot(a.y - c.y) - (a.footprint + c.footprint);
                    min_gap = min_gap.min(gap);
                }
            }
        }
        if fleets.all_done(world.time()) && !events.is_empty() && !RUN_TO_END.with(|c| c.get()) {
            break;
        }
    }
    Run {
        events,
        published,
        min_gap,
        world,
    }
}

fn ended(events: &[TaskEvent]) -> Vec<(String, String, String)> {
    events
        .iter()
        .filter(|e| e.event == "completed" || e.event == "failed")
        .map(|e| (e.task_id.clone(), e.event.clone(), e.detail.clone()))
        .collect()
}

fn dump(events: &[TaskEvent]) -> String {
    events
        .iter()
        .map(|e| {
            format!(
                "{:.1} {} {} {} {}",
                e.time.as_secs(),
                e.task_id,
                e.event,
                e.robot,
                e.detail
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn world_delivery_through_doors_and_lift_completes() {
    let b = load("two_level_clinic", None);
    let mut s = scenario(
        vec![fleet("tiny", 1, SpawnSpec::MapSpawnPoints)],
        vec![task(
            1.0,
            None,
            TaskKind::Delivery {
                pickup: "pharmacy".into(),
                dropoff: "ward_a".into(),
                dispenser: None,
                ingestor: None,
            },
        )],
    );
    s.workcells.push(WorkcellSpec {
        name: "ward_a_ingestor".into(),
        kind: crate::scenario::WorkcellKind::Ingestor,
        waypoint: "ward_a".into(),
        span: Span::UNKNOWN,
    });
    let r = run(&b, &s, 1200.0);
    eprintln!("{}\nt={}", dump(&r.events), r.world.time());
    assert_eq!(
        ended(&r.events),
        vec![("delivery_0".into(), "completed".into(), String::new())],
        "{}",
        dump(&r.events)
    );
    // The robot ends at ward_a on L2 (elevation 4 m).
    let truth = r.world.robots()[0];
    let ward_a = b
        .vertices
        .iter()
        .find(|(_, v)| v.name == "ward_a")
        .map(|(_, v)| v.pos)
        .expect("ward_a");
    assert!(
        (truth.x - ward_a.x).hypot(truth.y - ward_a.y) < 0.1,
        "{truth:?}"
    );
    assert!((truth.z - 4.0).abs() < 0.05, "{truth:?}");
    // The lift was released: the last adapter lift request is END_SESSION.
    let last_lift = r.published.iter().rev().find_map(|p| match &p.msg {
        Msg::LiftRequest(l) if p.topic == Topic::AdapterLiftRequests => Some(l.request_type),
        _ => None,
    });
    assert_eq!(last_lift, Some(lift_request::END_SESSION));
}

/// Two lanes crossing in an X (w→e and s→n), parking spots off the crossing.
const CROSS: &str = r#"
coordinate_system: cartesian_meters
name: cross
levels:
  L1:
    elevation: 0
    vertices:
      - [0, 5, 0, w]
      - [10, 5, 0, e]
      - [5, 0, 0, s]
      - [5, 10, 0, n]
      - [0, 8, 0, park_w, {is_parking_spot: [4, true]}]
      - [8, 0, 0, park_s, {is_parking_spot: [4, true]}]
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [0, 4, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 5, {bidirectional: [4, true], graph_idx: [2, 0]}]
"#;

#[test]
fn world_crossing_robots_never_touch() {
    let b = load("cross", Some(CROSS));
    let s = scenario(
        vec![
            fleet("a", 1, SpawnSpec::Waypoints(vec!["w".into()])),
            fleet("b", 1, SpawnSpec::Waypoints(vec!["s".into()])),
        ],
        vec![
            task(0.5, Some("a"), TaskKind::GoToPlace { place: "e".into() }),
            task(0.5, Some("b"), TaskKind::GoToPlace { place: "n".into() }),
        ],
    );
    let r = run(&b, &s, 300.0);
    let done = ended(&r.events);
    assert_eq!(done.len(), 2, "{}", dump(&r.events));
    assert!(
        done.iter().all(|e| e.1 == "completed"),
        "{}",
        dump(&r.events)
    );
    // Same speed, same distance to the crossing: unmanaged they would collide there.
    assert!(r.min_gap > 0.0, "min gap {}", r.min_gap);
}

/// A 3 m wide door at x = 5 crossed by two parallel lanes 1.2 m apart.
const WIDE_DOOR: &str = r#"
coordinate_system: cartesian_meters
name: wide_door
levels:
  L1:
    elevation: 0
    vertices:
      - [0, 4.4, 0, a0]
      - [10, 4.4, 0, a1]
      - [0, 5.6, 0, b0]
      - [16, 5.6, 0, b1]
      - [5, 3.5, 0, d0]
      - [5, 6.5, 0, d1]
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
    doors:
      - [4, 5, {motion_axis: [1, start], motion_degrees: [3, 90], motion_direction: [2, 1], name: [1, wide], plugin: [1, normal], right_left_ratio: [3, 1], type: [1, double_sliding]}]
"#;

#[test]
fn world_door_is_passed_one_robot_at_a_time_and_only_open() {
    let b = load("wide_door", Some(WIDE_DOOR));
    let s = scenario(
        vec![
            fleet("a", 1, SpawnSpec::Waypoints(vec!["a0".into()])),
            fleet("b", 1, SpawnSpec::Waypoints(vec!["b0".into()])),
        ],
        vec![
            task(0.5, Some("a"), TaskKind::GoToPlace { place: "a1".into() }),
            task(0.5, Some("b"), TaskKind::GoToPlace { place: "b1".into() }),
        ],
    );
    let mut door_mode = door_mode::CLOSED;
    let mut violations = Vec::new();
    let mut both_requested = false;
    let mut sessions_max = 0;
    let r = run_checked(&b, &s, 300.0, &mut |w, published| {
        for p in published {
            match &p.msg {
                Msg::DoorState(d) if d.door_name == "wide" => door_mode = d.current_mode.value,
                Msg::DoorHeartbeat(h) => {
                    for ds in &h.all_sessions {
                        sessions_max = sessions_max.max(ds.sessions.len());
                    }
                }
                _ => {}
            }
        }
        both_requested |= sessions_max == 2;
        for (i, rb) in w.robots().iter().enumerate() {
            // In the doorway (centre within a footprint of the door line).
            if (rb.x - 5.0).abs() < rb.footprint && door_mode != door_mode::OPEN {
                violations.push((w.time(), i, door_mode));
            }
        }
    });
    let done = ended(&r.events);
    assert_eq!(done.len(), 2, "{}", dump(&r.events));
    assert!(
        done.iter().all(|e| e.1 == "completed"),
        "{}",
        dump(&r.events)
    );
    // The schedule passes a door one robot at a time (the door is a resource of its own):
    // never two sessions at once, and nobody in the doorway while it is not open.
    assert!(!both_requested, "two robots held the door at once");
    assert!(
        violations.is_empty(),
        "robot in the doorway while the door was not open: {violations:?}"
    );
}

/// One tiny robot at the clinic's `tinyRobot1_charger`, sent to `ward_a` on the floor
/// above, with its fleets and world.
fn clinic_rider() -> (Fleets, World) {
    let b = load("two_level_clinic", None);
    let s = scenario(
        vec![fleet(
            "tiny",
            1,
            SpawnSpec::Waypoints(vec!["tinyRobot1_charger".into()]),
        )],
        vec![go_to(0.5, "ward_a")],
    );
    start(&b, &s)
}

/// One step at `t`: the fleets' messages (each shown to `seen` first, task events not
/// delivered) go to the world, which steps.
fn step_once(
    (fleets, world): (&mut Fleets, &mut World),
    t: f64,
    inbox: &mut Vec<Published>,
    seen: &mut dyn FnMut(&Msg),
) {
    let mut out = Vec::new();
    fleets.update(t, inbox, &mut out);
    inbox.clear();
    for (topic, msg) in out {
        seen(&msg);
        if !matches!(msg, Msg::TaskEvent(_)) {
            world.deliver(topic, msg);
        }
    }
    world.step(inbox);
}

/// A robot waiting for a lift whose itinerary is planned again off the lift (as its way
/// to parking is when another robot's task plan goes through it) gives the lift back and
/// counts as free. It kept the lift it had asked for before: neither free nor working, it
/// stood where it was for good, and on a public map with lifts (lift_test) the
/// dispatcher took no task for the last 74 minutes of two hours (BENCHMARKS.md).
#[test]
fn world_a_robot_planned_off_its_lift_gives_it_back() {
    let (mut fleets, mut world) = clinic_rider();
    let mut inbox = Vec::new();
    let mut replanned_at: Option<f64> = None;
    let mut released = false;
    for _ in 0..60_000 {
        let t = world.time();
        let ended = replanned_at.is_some();
        step_once((&mut fleets, &mut world), t, &mut inbox, &mut |msg| {
            if let Msg::LiftRequest(l) = msg {
                released |= ended
                    && l.session_id == "tiny_0"
                    && l.request_type == crate::msgs::lift_request::END_SESSION;
            }
        });
        let r = &fleets.floor.robots[0];
        match replanned_at {
            None if matches!(r.gate, Gate::Lift { .. }) && r.n_sent == 0 => {
                // Its task ends here and its itinerary now stays where it stands.
                let r = &mut fleets.floor.robots[0];
                r.task = None;
                r.steps.clear();
                r.cur = Cur::None;
                r.leg = None;
                r.legs.clear();
                r.dirty = true;
                fleets.floor.traffic.sched.install(0, 0, &[], t, None);
                replanned_at = Some(t);
            }
            Some(at) if t > at + 5.0 => break,
            _ => {}
        }
    }
    assert!(
        replanned_at.is_some(),
        "the robot never waited for the lift"
    );
    assert_eq!(fleets.floor.robots[0].gate, Gate::None);
    assert!(fleets.floor.robots[0].idle(), "the robot is not idle");
    assert!(released, "the lift was not given back");
}

/// A robot in a cabin that has called it to a floor rides it, whatever it is planned to
/// next: planned again from the cabin with nothing kept (on a public map, a go-to-place
/// started without its plan), a robot drove out of a climbing cabin and stood there for
/// good.
#[test]
fn world_a_robot_planned_again_mid_ride_keeps_its_ride() {
    let (mut fleets, mut world) = clinic_rider();
    let mut inbox = Vec::new();
    let home = fleets.floor.robots[0].at;
    let mut rode = None;
    for _ in 0..60_000 {
        let t = world.time();
        step_once((&mut fleets, &mut world), t, &mut inbox, &mut |_| {});
        let r = &fleets.floor.robots[0];
        let front = fleets
            .floor
            .traffic
            .sched
            .itinerary(0)
            .travs
            .front()
            .map(|tr| tr.edge);
        let riding = matches!(r.gate, Gate::Lift { .. })
            && fleets.floor.nav.vertices[r.at].lift.is_some()
            && front.is_some_and(|e| matches!(fleets.floor.nav.edges[e].kind, EdgeKind::Lift(_)));
        if riding {
            // Back to where it came from, planned from the cabin.
            assert!(fleets.floor.plan_to(0, &[(home, 0.0)], t).is_ok());
            rode = front;
            break;
        }
    }
    let ride = rode.expect("the robot never rode the lift");
    let it = fleets.floor.traffic.sched.itinerary(0);
    assert_eq!(
        it.travs.front().map(|tr| tr.edge),
        Some(ride),
        "the ride was dropped"
    );
    assert_eq!(fleets.floor.traffic.sched.end_vertex(0), home);
}

#[test]
fn world_two_robots_share_the_lift() {
    let b = load("two_level_clinic", None);
    let s = scenario(
        vec![fleet(
            "tiny",
            2,
            SpawnSpec::Waypoints(vec!["tinyRobot1_charger".into(), "pharmacy".into()]),
        )],
        // One for each robot: left to the dispatcher, the robot that gets upstairs first
        // does both (the other's plan waits for the lift), done 8 s sooner.
        vec![
            TaskSpec {
                robot: Some("tiny_1".into()),
                ..go_to(0.5, "ward_a")
            },
            TaskSpec {
                robot: Some("tiny_0".into()),
                ..go_to(0.5, "ward_b")
            },
        ],
    );
    let r = run(&b, &s, 1200.0);
    let done = ended(&r.events);
    assert_eq!(done.len(), 2, "{}", dump(&r.events));
    assert!(
        done.iter().all(|e| e.1 == "completed"),
        "{}",
        dump(&r.events)
    );
    assert!(r.min_gap > 0.0, "min gap {}", r.min_gap);
    // Both rode: two AGV sessions, one after the other (never two owners at once).
    let mut owners: Vec<String> = r
        .published
        .iter()
        .filter_map(|p| match &p.msg {
            Msg::LiftState(l) if !l.session_id.is_empty() => Some(l.session_id.clone()),
            _ => None,
        })
        .collect();
    owners.dedup();
    assert_eq!(owners.len(), 2, "{owners:?}");
    for rb in r.world.robots() {
        assert!((rb.z - 4.0).abs() < 0.05, "{rb:?}");
    }
}

#[test]
fn world_idle_robot_in_the_way_moves_aside() {
    let b = load("two_level_clinic", None);
    // `b_0` idles at the lobby, on the only way from the charger to the pharmacy.
    let s = scenario(
        vec![
            fleet(
                "a",
                1,
                SpawnSpec::Waypoints(vec!["tinyRobot1_charger".into()]),
            ),
            fleet("b", 1, SpawnSpec::Waypoints(vec!["lobby".into()])),
        ],
        vec![task(
            0.5,
            Some("a"),
            TaskKind::GoToPlace {
                place: "pharmacy".into(),
            },
        )],
    );
    let lobby = b
        .vertices
        .iter()
        .find(|(_, v)| v.name == "lobby")
        .map(|(_, v)| v.pos)
        .expect("lobby");
    let r = run(&b, &s, 1200.0);
    let done = ended(&r.events);
    assert_eq!(done.len(), 1, "{}", dump(&r.events));
    assert_eq!(done[0].1, "completed", "{}", dump(&r.events));
    assert!(r.min_gap > 0.0, "min gap {}", r.min_gap);
    let idle = r.world.robots()[1];
    assert!(
        (idle.x - lobby.x).hypot(idle.y - lobby.y) > 1.0,
        "b_0 did not move: {idle:?}"
    );
}

#[test]
fn world_low_battery_goes_charging() {
    let b = load("two_level_clinic", None);
    let mut f = fleet("tiny", 1, SpawnSpec::MapSpawnPoints);
    // Charge as soon as the reported battery drops below 100 %, back to 100 %.
    f.recharge_threshold = 0.999;
    f.recharge_soc = 1.0;
    let s = scenario(
        vec![f],
        vec![task(
            0.5,
            None,
            TaskKind::Loop {
                start: "corridor".into(),
                finish: "lobby".into(),
                loops: 2,
            },
        )],
    );
    RUN_TO_END.with(|c| c.set(true));
    let r = run(&b, &s, 1500.0);
    RUN_TO_END.with(|c| c.set(false));
    assert_eq!(ended(&r.events)[0].1, "completed", "{}", dump(&r.events));
    // Back on the charger, charged again (battery_percent = ceil(100·soc)).
    let charger = b
        .vertices
        .iter()
        .find(|(_, v)| v.roles.is_charger)
        .map(|(_, v)| v.pos)
        .expect("charger");
    let truth = r.world.robots()[0];
    assert!(
        (truth.x - charger.x).hypot(truth.y - charger.y) < 0.05,
        "{truth:?}"
    );
    let went = r.published.iter().any(|p| match &p.msg {
        Msg::PathRequest(pr) => pr
            .path
            .last()
            .is_some_and(|l| (l.x - charger.x).hypot(l.y - charger.y) < 1e-9),
        _ => false,
    });
    assert!(went);
    // It reported CHARGING after the task.
    let done_t = r
        .events
        .iter()
        .find(|e| e.event == "completed")
        .map(|e| e.time.as_secs())
        .expect("done");
    let charging = r.published.iter().any(|p| {
        p.t > done_t
            && matches!(&p.msg, Msg::RobotState(rs) if rs.mode.mode == crate::msgs::robot_mode::CHARGING)
    });
    assert!(charging);
    // It stays there, parked on its charger (a parking vertex), charged.
    let last = r.published.iter().rev().find_map(|p| match &p.msg {
        Msg::RobotState(rs) => Some(rs.battery_percent),
        _ => None,
    });
    assert_eq!(last, Some(100.0));
}

#[test]
fn world_a_robot_going_to_charge_leaves_the_next_task_to_another() {
    // a_0 starts on the L1 charger, b_0 on L2. The first task (the lobby, next to the
    // charger) goes to a_0. Tasks wait in the dispatcher's queue until a robot is free
    // (none is queued behind a busy robot): the second (the corridor) goes to b_0, free
    // at once, and a_0, whose battery drains fast (20 kW), goes back to charge after its
    // task.
    let b = load("two_level_clinic", None);
    let mut a = fleet(
        "a",
        1,
        SpawnSpec::Waypoints(vec!["tinyRobot1_charger".into()]),
    );
    a.robot.nominal_power = 20_000.0;
    a.recharge_threshold = 0.9;
    a.recharge_soc = 1.0;
    let other = fleet("b", 1, SpawnSpec::Waypoints(vec!["ward_b".into()]));
    let s = scenario(
        vec![a, other],
        vec![go_to(0.5, "lobby"), go_to(1.0, "corridor")],
    );
    let r = run(&b, &s, 600.0);
    let assigned: Vec<(&str, &str)> = r
        .events
        .iter()
        .filter(|e| e.event == "assigned")
        .map(|e| (e.task_id.as_str(), e.robot.as_str()))
        .collect();
    assert_eq!(
        assigned,
        [("go_to_place_0", "a_0"), ("go_to_place_1", "b_0")],
        "{}",
        dump(&r.events)
    );
    let done: Vec<(&str, &str, &str)> = r
        .events
        .iter()
        .filter(|e| e.event == "completed")
        .map(|e| (e.task_id.as_str(), e.robot.as_str(), e.event.as_str()))
        .collect();
    assert_eq!(
        done,
        [
            ("go_to_place_0", "a_0", "completed"),
            ("go_to_place_1", "b_0", "completed")
        ],
        "{}",
        dump(&r.events)
    );
    // a_0 went back to its charger and charges.
    let charging = r.published.iter().any(|p| {
        matches!(&p.msg, Msg::RobotState(rs) if rs.name == "a_0"
            && rs.mode.mode == crate::msgs::robot_mode::CHARGING)
    });
    assert!(charging);
}

/// Timing of `update` with many robots on a demo map (run with `--release --ignored`).
#[test]
#[ignore]
fn perf_many_robots_on_a_demo_map() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shared/maps/airport_terminal/airport_terminal.building.yaml"
    );
    let Ok(text) = std::fs::read_to_string(path) else {
        eprintln!("skipped: ../shared not found");
        return;
    };
    let b = load("airport_terminal", Some(&text));
    let nav = crate::graph::Nav::build(&b, &[2]);
    let mut names: Vec<String> = nav.members[0]
        .iter()
        .map(|&v| nav.vertices[v].name.clone())
        .filter(|n| !n.is_empty())
        .collect();
    names.sort();
    names.dedup();
    let mut f = fleet("tiny", 24, SpawnSpec::Auto);
    f.graph = 2;
    let mut s = scenario(vec![f], Vec::new());
    // Busy: a task every second, waypoints in a scrambled but fixed order.
    for k in 0..150usize {
        let n = &names[(k * 37) % names.len()];
        s.tasks.push(task(
            1.0 + k as f64,
            None,
            TaskKind::GoToPlace { place: n.clone() },
        ));
    }
    let (mut fleets, mut world) = start(&b, &s);
    let (mut inbox, mut out, mut events) = (Vec::new(), Vec::new(), Vec::new());
    let (mut t_fleet, mut t_world) = (std::time::Duration::ZERO, std::time::Duration::ZERO);
    let (mut idle_calls, mut t_idle) = (0u64, std::time::Duration::ZERO);
    let mut min_gap = f64::INFINITY;
    let steps = (1200.0 / s.step) as u64;
    for _ in 0..steps {
        let t = world.time();
        out.clear();
        let empty = inbox.is_empty();
        let c = std::time::Instant::now();
        fleets.update(t, &inbox, &mut out);
        let d = c.elapsed();
        t_fleet += d;
        if empty {
            idle_calls += 1;
            t_idle += d;
        }
        inbox.clear();
        for (topic, msg) in out.drain(..) {
            if let Msg::TaskEvent(e) = &msg {
                events.push(e.clone());
            } else {
                world.deliver(topic, msg);
            }
        }
        let c = std::time::Instant::now();
        world.step(&mut inbox);
        t_world += c.elapsed();
        let robots = world.robots();
        for (i, a) in robots.iter().enumerate() {
            for c in &robots[i + 1..] {
                if (a.z - c.z).abs() < 0.5 {
                    min_gap =
                        min_gap.min((a.x - c.x).hypot(a.y - c.y) - (a.footprint + c.footprint));
                }
            }
        }
    }
    let done = ended(&events);
    let ok = done.iter().filter(|e| e.1 == "completed").count();
    eprintln!(
        "{} named waypoints, {} tasks: {} completed, {} failed; fleet {:?} ({:.2} µs/step, idle {:.3} µs over {} calls), world {:?}, min gap {:.3} m",
        names.len(),
        s.tasks.len(),
        ok,
        done.len() - ok,
        t_fleet,
        t_fleet.as_secs_f64() * 1e6 / steps as f64,
        t_idle.as_secs_f64() * 1e6 / idle_calls.max(1) as f64,
        idle_calls,
        t_world,
        min_gap
    );
    for e in events
        .iter()
        .filter(|e| e.event == "failed" || e.event == "stuck" || e.event == "deadlock")
    {
        eprintln!(
            "{:.1} {} {} {} {}",
            e.time.as_secs(),
            e.task_id,
            e.event,
            e.robot,
            e.detail
        );
    }
}

#[test]
fn world_lift_busy_with_someone_else_is_waited_for() {
    let b = load("two_level_clinic", None);
    let s = scenario(
        vec![fleet("tiny", 1, SpawnSpec::MapSpawnPoints)],
        vec![go_to(0.5, "ward_a")],
    );
    let request = |kind: u8, floor: &str| LiftRequest {
        lift_name: "lift_1".into(),
        session_id: "visitor".into(),
        request_type: kind,
        destination_floor: floor.into(),
        door_state: lift_request::DOOR_OPEN,
        ..LiftRequest::default()
    };
    let release_at = 120.0;
    let mut sent = (false, false);
    let r = run_checked(&b, &s, 1200.0, &mut |w, _| {
        // A visitor takes the lift to L2 at once and keeps it for two minutes.
        if !sent.0 {
            sent.0 = true;
            w.deliver(
                Topic::AdapterLiftRequests,
                Msg::LiftRequest(request(lift_request::AGV_MODE, "L2")),
            );
        }
        if !sent.1 && w.time() >= release_at {
            sent.1 = true;
            w.deliver(
                Topic::AdapterLiftRequests,
                Msg::LiftRequest(request(lift_request::END_SESSION, "L2")),
            );
        }
    });
    let done = ended(&r.events);
    assert_eq!(done.len(), 1, "{}", dump(&r.events));
    assert_eq!(done[0].1, "completed", "{}", dump(&r.events));
    // The robot asked before the visitor left, and got the lift only after.
    let first_ask = r.published.iter().find_map(|p| match &p.msg {
        Msg::LiftRequest(l)
            if p.topic == Topic::AdapterLiftRequests && l.session_id == "tinyRobot1" =>
        {
            Some(p.t)
        }
        _ => None,
    });
    let first_owned = r.published.iter().find_map(|p| match &p.msg {
        Msg::LiftState(l) if l.session_id == "tinyRobot1" => Some(p.t),
        _ => None,
    });
    let (ask, owned) = (first_ask.expect("asked"), first_owned.expect("owned"));
    assert!(
        ask < release_at && owned >= release_at,
        "asked {ask}, owned {owned}"
    );
    assert!((r.world.robots()[0].z - 4.0).abs() < 0.05);
}

/// Every demo map and graph: robots spawned automatically drive to named waypoints; no
/// contact, and report how many tasks ended (run with `--release --ignored`).
#[test]
#[ignore]
fn demo_maps_all_graphs() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/maps");
    let Ok(dir) = std::fs::read_dir(root) else {
        eprintln!("skipped: ../shared not found");
        return;
    };
    let mut maps: Vec<_> = dir
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().to_string())
        .collect();
    maps.sort();
    for m in maps {
        let Ok(text) = std::fs::read_to_string(format!("{root}/{m}/{m}.building.yaml")) else {
            continue;
        };
        let parsed = mapc_frontend::parse_str(&m, &text);
        let Some(b) = parsed.valid_building().cloned() else {
            eprintln!("{m}: map has errors");
            continue;
        };
        for g in b.graph_indices() {
            let nav = crate::graph::Nav::build(&b, &[g]);
            let mut names: Vec<String> = nav.members[0]
                .iter()
                .map(|&v| nav.vertices[v].name.clone())
                .filter(|n| !n.is_empty())
                .collect();
            names.sort();
            names.dedup();
            if names.is_empty() {
                continue;
            }
            let mut f = fleet("f", 12, SpawnSpec::Auto);
            f.graph = g;
            let mut s = scenario(vec![f], Vec::new());
            for k in 0..24usize {
                let n = &names[(k * 7) % names.len()];
                s.tasks.push(task(
                    1.0 + 2.0 * k as f64,
                    None,
                    TaskKind::GoToPlace { place: n.clone() },
                ));
            }
            if Fleets::place(&b, &s).is_err() {
                eprintln!("{m} graph {g}: not enough spawn points for 6 robots");
                continue;
            }
            let c = std::time::Instant::now();
            let r = run(&b, &s, 1500.0);
            let done = ended(&r.events);
            let ok = done.iter().filter(|e| e.1 == "completed").count();
            let fails: Vec<String> = done
                .iter()
                .filter(|e| e.1 == "failed")
                .map(|e| e.2.clone())
                .collect();
            eprintln!(
                "{m} graph {g}: {} tasks, {ok} completed, {} failed {:?}, min gap {:.2} m, {:.0} s simulated in {:?}",
                s.tasks.len(),
                fails.len(),
                fails.iter().take(3).collect::<Vec<_>>(),
                r.min_gap,
                r.world.time(),
                c.elapsed()
            );
            assert!(r.min_gap > 0.0, "{m} graph {g}: robots touched");
        }
        // All graphs at once: fleets of different graphs share the floor space.
        let graphs = b.graph_indices();
        if graphs.len() < 2 {
            continue;
        }
        let mut s = scenario(Vec::new(), Vec::new());
        for &g in &graphs {
            let nav = crate::graph::Nav::build(&b, &[g]);
            let mut names: Vec<String> = nav.members[0]
                .iter()
                .map(|&v| nav.vertices[v].name.clone())
                .filter(|n| !n.is_empty())
                .collect();
            names.sort();
            names.dedup();
            let name = format!("g{g}");
            let mut f = fleet(&name, 4, SpawnSpec::Auto);
            f.graph = g;
            s.fleets.push(f);
            for k in 0..8usize {
                if let Some(n) = names.get((k * 7) % names.len().max(1)) {
                    s.tasks.push(task(
                        1.0 + 3.0 * k as f64,
                        Some(&name),
                        TaskKind::GoToPlace { place: n.clone() },
                    ));
                }
            }
        }
        if Fleets::place(&b, &s).is_err() {
            eprintln!("{m} all graphs: not enough spawn points");
            continue;
        }
        let r = run(&b, &s, 1500.0);
        let done = ended(&r.events);
        let ok = done.iter().filter(|e| e.1 == "completed").count();
        eprintln!(
            "{m} all graphs {graphs:?}: {} tasks, {ok} completed, {} failed, min gap {:.2} m, {:.0} s",
            s.tasks.len(),
            done.len() - ok,
            r.min_gap,
            r.world.time()
        );
        for e in r
            .events
            .iter()
            .filter(|e| matches!(e.event.as_str(), "stuck" | "deadlock"))
        {
            eprintln!(
                "  {:.1} {} {} {} {}",
                e.time.as_secs(),
                e.task_id,
                e.event,
                e.robot,
                e.detail
            );
        }
        assert!(r.min_gap > 0.0, "{m} all graphs: robots touched");
    }
}

#[test]
fn world_runs_are_deterministic() {
    let b = load("two_level_clinic", None);
    let s = scenario(
        vec![fleet(
            "tiny",
            2,
            SpawnSpec::Waypoints(vec!["tinyRobot1_charger".into(), "pharmacy".into()]),
        )],
        vec![
            go_to(0.5, "ward_a"),
            go_to(0.5, "lobby"),
            go_to(3.0, "ward_b"),
        ],
    );
    let (a, c) = (run(&b, &s, 900.0), run(&b, &s, 900.0));
    assert_eq!(a.events, c.events);
    assert_eq!(a.published, c.published);
}

/// A corridor with a dead end at the west, a junction with two bays in the middle and a
/// bay near the east end; vertices 3 m apart (more than a TinyRobot's stop zone reaches).
const COMB: &str = r#"
coordinate_system: cartesian_meters
name: comb
levels:
  L1:
    elevation: 0
    vertices:
      - [0, 0, 0, dead_end]
      - [3, 0, 0, c1]
      - [6, 0, 0, c2]
      - [9, 0, 0, j]
      - [9, 3, 0, bay_n]
      - [9, -3, 0, bay_s]
      - [12, 0, 0, c4]
      - [15, 0, 0, c5]
      - [18, 0, 0, far_end]
      - [15, 3, 0, bay_e]
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [1, 2, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [3, 4, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [3, 5, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [3, 6, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [6, 7, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [7, 8, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [7, 9, {bidirectional: [4, true], graph_idx: [2, 0]}]
"#;

fn comb_pos(b: &Building, name: &str) -> mapc_ir::Vec2 {
    b.vertices
        .iter()
        .find(|(_, v)| v.name == name)
        .map(|(_, v)| v.pos)
        .expect("comb vertex")
}

fn spawn(names: &[&str]) -> SpawnSpec {
    SpawnSpec::Waypoints(names.iter().map(|n| n.to_string()).collect())
}

fn go(at: f64, fleet: &str, place: &str) -> TaskSpec {
    task(
        at,
        Some(fleet),
        TaskKind::GoToPlace {
            place: place.into(),
        },
    )
}

/// Every task completed, and no two robots ever closer than their footprints.
fn assert_all_completed(r: &Run, n: usize) {
    let done = ended(&r.events);
    assert_eq!(done.len(), n, "{}", dump(&r.events));
    assert!(
        done.iter().all(|e| e.1 == "completed"),
        "{}",
        dump(&r.events)
    );
    assert!(r.min_gap >= 0.0, "min gap {}", r.min_gap);
}

#[test]
fn world_idle_robots_in_a_row_make_way_out_of_a_dead_end() {
    // `a_0` starts at the dead end behind two idle robots standing in the corridor: the
    // first can only move once the second has (it used to find no free spot, and `a_0`
    // failed stuck in traffic).
    let b = load("comb", Some(COMB));
    let s = scenario(
        vec![
            fleet("a", 1, spawn(&["dead_end"])),
            fleet("idle", 2, spawn(&["c1", "c2"])),
        ],
        vec![go(0.5, "a", "far_end")],
    );
    let r = run(&b, &s, 1200.0);
    assert_all_completed(&r, 1);
    let robots = r.world.robots();
    let far = comb_pos(&b, "far_end");
    assert!((robots[0].x - far.x).hypot(robots[0].y - far.y) < 0.1);
    // The idle robots ended off the corridor's straight line or out of its way.
    for rb in &robots[1..] {
        assert!(rb.y.abs() > 1.0 || rb.x > 9.5, "{rb:?}");
    }
}

#[test]
fn world_head_on_in_a_corridor_and_a_crossing_robot_all_complete() {
    // Two robots swap ends of the corridor while a third crosses the junction between
    // the bays: they meet head-on unless one waits or backs off into a bay.
    let b = load("comb", Some(COMB));
    let s = scenario(
        vec![
            fleet("w", 1, spawn(&["dead_end"])),
            fleet("e", 1, spawn(&["far_end"])),
            fleet("n", 1, spawn(&["bay_n"])),
        ],
        vec![
            go(0.5, "w", "far_end"),
            go(0.5, "e", "dead_end"),
            go(0.5, "n", "bay_s"),
            go(200.0, "w", "dead_end"),
            go(200.0, "e", "far_end"),
            go(200.0, "n", "bay_n"),
        ],
    );
    let r = run(&b, &s, 2400.0);
    assert_all_completed(&r, 6);
    for (rb, home) in r
        .world
        .robots()
        .iter()
        .zip(["dead_end", "far_end", "bay_n"])
    {
        let p = comb_pos(&b, home);
        assert!((rb.x - p.x).hypot(rb.y - p.y) < 0.1, "{rb:?} not at {home}");
    }
}

/// One leg of triple_H: a corridor with a dead end at each end (top, bottom), joined
/// half way (j) to a cross corridor (x1) and a second corridor (ct-x2-cb).
const LEG: &str = r#"
coordinate_system: cartesian_meters
name: leg
levels:
  L1:
    elevation: 0
    vertices:
      - [0, 10, 0, top]
      - [0, 7.5, 0, u]
      - [0, 5, 0, j]
      - [0, 2.5, 0, d]
      - [0, 0, 0, bottom]
      - [3, 5, 0, x1]
      - [6, 5, 0, x2]
      - [6, 10, 0, ct]
      - [6, 0, 0, cb]
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [1, 2, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [3, 4, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 5, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [5, 6, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [6, 7, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [6, 8, {bidirectional: [4, true], graph_idx: [2, 0]}]
"#;

#[test]
fn world_robots_into_and_out_of_a_dead_end_leg_all_arrive() {
    // triple_H with 8 robots: one robot in the bottom dead end wants out to the top, two
    // in the corridor want into the bottom, one from the cross corridor wants the top.
    // The claimant bound for the bottom used to push the robot coming out back into the
    // dead end (its own goal: off the claimed lane but on its way), then make room for it
    // again, for hours.
    let b = load("leg", Some(LEG));
    let s = scenario(
        vec![
            fleet("a", 1, spawn(&["bottom"])),
            fleet("b", 1, spawn(&["j"])),
            fleet("c", 1, spawn(&["u"])),
            fleet("e", 1, spawn(&["x2"])),
        ],
        vec![
            go(0.5, "a", "top"),
            go(0.5, "b", "bottom"),
            go(0.5, "c", "d"),
            go(0.5, "e", "u"),
        ],
    );
    let r = run(&b, &s, 1800.0);
    assert_all_completed(&r, 4);
}

#[test]
fn world_second_delivery_waits_for_the_dispensers_item() {
    // One dispenser (at the junction) holds one item; two deliveries to the dead end come
    // at once. The second waits in the queue while the first carries the item down the
    // corridor, and is assigned once it has been ingested (it used to fail with `disp
    // failed`, and later had a robot stand at the empty dispenser meanwhile).
    let b = load("comb", Some(COMB));
    let delivery = |at: f64| {
        task(
            at,
            None,
            TaskKind::Delivery {
                pickup: "j".into(),
                dropoff: "dead_end".into(),
                dispenser: Some("disp".into()),
                ingestor: Some("sink".into()),
            },
        )
    };
    let mut s = scenario(
        vec![fleet("d", 2, spawn(&["bay_n", "far_end"]))],
        vec![delivery(0.5), delivery(0.6)],
    );
    for (name, kind, at) in [
        ("disp", crate::scenario::WorkcellKind::Dispenser, "j"),
        ("sink", crate::scenario::WorkcellKind::Ingestor, "dead_end"),
    ] {
        s.workcells.push(WorkcellSpec {
            name: name.into(),
            kind,
            waypoint: at.into(),
            span: Span::UNKNOWN,
        });
    }
    let r = run(&b, &s, 2400.0);
    assert_all_completed(&r, 2);
    let at = |task: &str, event: &str| {
        r.events
            .iter()
            .find(|e| e.task_id == task && e.event == event)
            .map(|e| e.time.sec as f64 + e.time.nanosec as f64 * 1e-9)
            .unwrap_or_else(|| panic!("no {event} of {task}: {}", dump(&r.events)))
    };
    // The first delivered (its item ingested) before the second was given a robot.
    assert!(
        at("delivery_1", "assigned") >= at("delivery_0", "completed"),
        "{}",
        dump(&r.events)
    );
}

#[test]
fn world_idle_robot_parks_off_the_task_routes() {
    // After a loop dead_end → far_end the robot does not stay on far_end (the next loop's
    // waypoint) but parks on the nearest vertex no task route uses: bay_e is 3 + 3 m from
    // far_end, bay_n and bay_s 9 + 3 m. It used to stay on far_end, in the next task's way.
    let b = load("comb", Some(COMB));
    let s = scenario(
        vec![fleet("t", 1, spawn(&["c2"]))],
        vec![task(
            0.5,
            Some("t"),
            TaskKind::Loop {
                start: "dead_end".into(),
                finish: "far_end".into(),
                loops: 1,
            },
        )],
    );
    RUN_TO_END.with(|c| c.set(true));
    let r = run(&b, &s, 400.0);
    RUN_TO_END.with(|c| c.set(false));
    assert_all_completed(&r, 1);
    let rb = r.world.robots()[0];
    let bay = comb_pos(&b, "bay_e");
    assert!(
        (rb.x - bay.x).hypot(rb.y - bay.y) < 0.1,
        "{rb:?} not at bay_e"
    );
}

// ----- the traffic planner's guarantees (ARCHITECTURE.md): every robot reaches its goal -----

#[test]
fn guarantee_dead_end_room_robots_in_and_out() {
    // `dead_end` is a room with one way in: one robot inside wants out while two outside
    // want in, over and over; the corridor holds one robot abreast.
    let b = load("comb", Some(COMB));
    let s = scenario(
        vec![
            fleet("in", 1, spawn(&["dead_end"])),
            fleet("out", 2, spawn(&["bay_n", "far_end"])),
        ],
        vec![
            go(0.5, "in", "far_end"),
            go(0.5, "out", "dead_end"),
            go(150.0, "out", "dead_end"),
            go(300.0, "in", "dead_end"),
            go(300.0, "out", "bay_s"),
            go(450.0, "out", "dead_end"),
        ],
    );
    let r = run(&b, &s, 3600.0);
    assert_all_completed(&r, 6);
    assert!(
        !r.events.iter().any(|e| e.event == "failed"),
        "{}",
        dump(&r.events)
    );
}

const RING: &str = r#"
coordinate_system: cartesian_meters
name: ring
levels:
  L1:
    elevation: 0
    vertices:
      - [0, 0, 0, r0]
      - [4, 0, 0, r1]
      - [8, 0, 0, r2]
      - [8, 4, 0, r3]
      - [4, 4, 0, r4]
      - [0, 4, 0, r5]
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [1, 2, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [3, 4, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [4, 5, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [5, 0, {bidirectional: [4, true], graph_idx: [2, 0]}]
"#;

#[test]
fn guarantee_ring_of_robots_each_wanting_the_next_spot() {
    // Five robots on a ring of six spots, each sent to the spot of the robot ahead of it
    // (the last one to the free spot): they must move one after the other, in the right
    // order, or swap round each other.
    let b = load("ring", Some(RING));
    let names = ["r0", "r1", "r2", "r3", "r4", "r5"];
    let fleets: Vec<FleetSpec> = (0..5)
        .map(|k| fleet(&format!("f{k}"), 1, spawn(&[names[k]])))
        .collect();
    let tasks: Vec<TaskSpec> = (0..5)
        .map(|k| go(0.5, &format!("f{k}"), names[k + 1]))
        .collect();
    let s = scenario(fleets, tasks);
    let r = run(&b, &s, 1800.0);
    assert_all_completed(&r, 5);
    for (k, rb) in r.world.robots().iter().enumerate() {
        let p = comb_pos(&b, names[k + 1]);
        assert!(
            (rb.x - p.x).hypot(rb.y - p.y) < 0.1,
            "{rb:?} not at {}",
            names[k + 1]
        );
    }
}

#[test]
fn guarantee_two_robots_need_the_lift_in_opposite_directions() {
    // One robot rides up while the other rides down, each starting where the other wants
    // to end up near the lift: the lift and its lobby are taken one at a time.
    let b = load("two_level_clinic", None);
    let s = scenario(
        vec![
            fleet("up", 1, spawn(&["corridor"])),
            fleet("down", 1, spawn(&["ward_a"])),
        ],
        vec![go(0.5, "up", "ward_a"), go(0.5, "down", "corridor")],
    );
    let r = run(&b, &s, 1800.0);
    assert_all_completed(&r, 2);
    // Each reached the other's start (the completions); "up" stays at ward_a. "down"
    // stays at the corridor only until "up" needs its way through: then it makes room.
    let robots = r.world.robots();
    assert!((robots[0].z - 4.0).abs() < 0.05, "{:?}", robots[0]);
}

#[test]
fn guarantee_three_fleets_cross_in_a_lift_lobby() {
    // The hotel demo map: three fleets on their own graphs share the ground floor's lift
    // lobby. Tiny robots ride up, delivery robots ride down, cleaners cross the lobby; two
    // of each, all at once.
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shared/maps/hotel/hotel.building.yaml"
    );
    let Ok(text) = std::fs::read_to_string(path) else {
        eprintln!("skipped: ../shared not found");
        return;
    };
    let b = load("hotel", Some(&text));
    let on = |name: &str, graph: i64, preset: &str, at: &[&str]| FleetSpec {
        graph,
        robot: RobotParams::preset(preset).expect("preset"),
        ..fleet(name, at.len(), spawn(at))
    };
    let s = scenario(
        vec![
            on("tiny", 0, "TinyRobot", &["lobby", "shop"]),
            on("delivery", 2, "DeliveryRobot", &["L3_room15", "L2_room1"]),
            on(
                "cleaner",
                1,
                "CleanerBotA",
                &["clean_lobby", "clean_restaurant"],
            ),
        ],
        vec![
            go(0.5, "tiny", "L3_room15"),
            go(0.5, "tiny", "L2_room1"),
            go(0.5, "delivery", "restaurant"),
            go(0.5, "delivery", "kitchen"),
            go(0.5, "cleaner", "clean_restaurant"),
            go(0.5, "cleaner", "clean_lobby"),
        ],
    );
    let r = run(&b, &s, 3600.0);
    assert_all_completed(&r, 6);
}

#[test]
fn world_a_robot_does_the_task_where_it_stands_first() {
    // One robot goes to r2 and stays there. Then two go-to-places come at once: the older
    // to r5 (across the ring), the younger to r2. The one at r2 takes no robot time, so
    // it goes first and the older one waits for nothing (the older one used to be done
    // first: a round trip before a task that was already done, which on a public map
    // left hundreds waiting).
    let b = load("ring", Some(RING));
    let s = scenario(
        vec![fleet("f", 1, spawn(&["r0"]))],
        vec![go(0.5, "f", "r2"), go(60.0, "f", "r5"), go(60.0, "f", "r2")],
    );
    let r = run(&b, &s, 300.0);
    assert_all_completed(&r, 3);
    let done: Vec<String> = ended(&r.events).into_iter().map(|e| e.0).collect();
    assert_eq!(
        done,
        ["go_to_place_0", "go_to_place_2", "go_to_place_1"],
        "{}",
        dump(&r.events)
    );
}

#[test]
fn world_a_robot_given_a_task_and_made_to_make_room_keeps_its_task() {
    // Robot x, standing in the corridor at c2, takes a go-to-place to c2 in a dispatch
    // round; before it starts the task, robot y's plan to far_end (through c2) asks it to
    // make room. x's new plan still goes to its task's place (it used to be planned to
    // park without it, then sent back there with no plan: on a public map with a lift, it
    // was planned again mid-ride and drove out of a climbing cabin).
    let b = load("comb", Some(COMB));
    let s = scenario(
        vec![
            fleet("x", 1, spawn(&["c2"])),
            fleet("y", 1, spawn(&["dead_end"])),
        ],
        vec![go(0.0, "x", "c2"), go(10.0, "y", "far_end")],
    );
    let (mut fleets, _world) = start(&b, &s);
    let mut out = Vec::new();
    while let Some(new) = fleets.dispatcher.take_request(0.0) {
        fleets
            .dispatcher
            .request(&mut fleets.floor, 0.0, new, &mut out);
    }
    fleets.dispatch(0.0, &mut out);
    let slot = fleets.floor.robots[0].slot;
    let (c2, far) = (
        fleets.floor.nav.find(slot, "c2").expect("c2"),
        fleets.floor.nav.find(slot, "far_end").expect("far_end"),
    );
    let x = &fleets.floor.robots[0];
    assert!(x.task.is_some() && x.cur == Cur::None && !x.steps.is_empty());
    fleets.floor.displace_for(1, &[(far, 0.0)], 0.0);
    let x = &fleets.floor.robots[0];
    let leg = *x.legs.front().expect("x keeps the leg to its task's place");
    let it = fleets.floor.traffic.sched.itinerary(0);
    let at = leg.checked_sub(1).map_or(it.at, |k| it.travs[k].to);
    assert_eq!(at, c2, "x's first leg ends at its task's place");
}

#[test]
fn world_a_charging_robot_made_to_make_room_charges_until_full_in_its_plan() {
    // Robot x charges at c2 (its battery at 10 %, to 100 %) when robot y's plan to far_end
    // (through c2) asks it to make room. It charges on until full, so its new plan holds
    // it at c2 for the whole charge, and robots planned later see it there that long (it
    // used to be planned to leave after a minute; on a public map the robots planned
    // behind it waited for hours).
    let b = load("comb", Some(COMB));
    let s = scenario(
        vec![
            fleet("x", 1, spawn(&["c2"])),
            fleet("y", 1, spawn(&["dead_end"])),
        ],
        vec![],
    );
    let (mut fleets, _world) = start(&b, &s);
    let slot = fleets.floor.robots[0].slot;
    let far = fleets.floor.nav.find(slot, "far_end").expect("far_end");
    let x = &mut fleets.floor.robots[0];
    x.state = Some(crate::msgs::RobotState {
        battery_percent: 10.0,
        ..Default::default()
    });
    x.cur = Cur::Charge {
        pct: 100.0,
        best: 10.0,
        best_t: 0.0,
    };
    let left = fleets.floor.charge_left(0, 100.0);
    assert!(left > 600.0, "a charge of {left} s");
    fleets.floor.displace_for(1, &[(far, 0.0)], 0.0);
    let it = fleets.floor.traffic.sched.itinerary(0);
    assert!(
        it.ready >= left - 1e-6,
        "x leaves at {} s, with {left} s of charge left",
        it.ready
    );
}
