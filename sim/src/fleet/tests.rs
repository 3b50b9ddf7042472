//! Tests of the fleet layer: graphs, conflict sets, the wait-for cycle detector, spawn
//! placement, and runs against a small kinematic stand-in of the world (robots drive
//! straight lines at constant speed and stop at every waypoint; the door and lift
//! supervisors' session rules; instant workcells) until the real World is merged.

use super::*;
use crate::graph::{segment_segment, Nav};
use crate::msgs::*;
use crate::scenario::{FleetSpec, GeneratorSpec, SimOptions, TaskCategory, TaskSpec, WorkcellSpec};
use crate::traffic::schedule::{Schedule, Step as SchedStep};
use crate::traffic::{Clearance, Conflicts};
use mapc_ir::{Building, Span, Vec2};

fn clinic() -> Building {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/two_level_clinic.building.yaml"
    );
    let text = std::fs::read_to_string(path).expect("fixture");
    let parsed = mapc_frontend::parse_str("clinic", &text);
    parsed.building.expect("clinic parses")
}

fn fleet(name: &str, count: usize, spawn: SpawnSpec) -> FleetSpec {
    FleetSpec {
        name: name.into(),
        graph: 0,
        robot: RobotParams::preset("TinyRobot").expect("preset"),
        count,
        spawn,
        recharge_threshold: 0.2,
        recharge_soc: 0.9,
        task_kinds: Vec::new(),
        span: Span::UNKNOWN,
        rmf: None,
    }
}

fn scenario(fleets: Vec<FleetSpec>, tasks: Vec<TaskSpec>) -> Scenario {
    Scenario {
        map: None,
        seed: 1,
        duration: 600.0,
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

/// A loop from `start` to `finish`, once, requested at `at`.
fn one_loop(at: f64, start: &str, finish: &str) -> TaskSpec {
    task(
        at,
        TaskKind::Loop {
            start: start.into(),
            finish: finish.into(),
            loops: 1,
        },
    )
}

fn task(at: f64, kind: TaskKind) -> TaskSpec {
    TaskSpec {
        at,
        kind,
        fleet: None,
        robot: None,
        priority: 0,
        span: Span::UNKNOWN,
    }
}

fn vertex(nav: &Nav, name: &str) -> usize {
    nav.find(0, name).unwrap_or_else(|| panic!("vertex {name}"))
}

use crate::params::RobotParams;

#[test]
fn routes_respect_directions_doors_and_lifts() {
    let b = clinic();
    let nav = Nav::build(&b, &[0]);
    let (charger, pharmacy, ward_a) = (
        vertex(&nav, "tinyRobot1_charger"),
        vertex(&nav, "pharmacy"),
        vertex(&nav, "ward_a"),
    );
    let (cost, route) = nav.plan(0, charger, pharmacy, 0.5).expect("route");
    let doors: Vec<&str> = route
        .iter()
        .filter_map(|&e| nav.edges[e].door)
        .map(|d| nav.doors[d].name.as_str())
        .collect();
    assert_eq!(doors, ["L1_lobby_door", "L1_pharmacy_door"]);
    // Cost = sum of lengths / speed + stops + doors.
    let len: f64 = route.iter().map(|&e| nav.edges[e].length).sum();
    let expect =
        len / 0.5 + route.len() as f64 * crate::graph::STOP_COST + 2.0 * crate::graph::DOOR_COST;
    assert!((cost - expect).abs() < 1e-9, "{cost} vs {expect}");
    // Contiguous.
    for w in route.windows(2) {
        assert_eq!(nav.edges[w[0]].to, nav.edges[w[1]].from);
    }
    // Between levels: through the lift, exactly one ride.
    let (_, route) = nav.plan(0, charger, ward_a, 0.5).expect("lift route");
    let rides: Vec<usize> = route
        .iter()
        .filter(|&&e| matches!(nav.edges[e].kind, EdgeKind::Lift(_)))
        .copied()
        .collect();
    assert_eq!(rides.len(), 1);
    let ride = &nav.edges[rides[0]];
    assert_eq!(nav.vertices[ride.from].level_name, "L1");
    assert_eq!(nav.vertices[ride.to].level_name, "L2");
    assert_eq!(
        nav.vertices[*route.last().map(|e| &nav.edges[*e].to).unwrap()].name,
        "ward_a"
    );
}

#[test]
fn one_way_lanes_are_not_driven_backwards() {
    let mut b = clinic();
    // Make lobby→corridor one way (from lobby to corridor).
    let (lh, _) = b
        .lanes
        .iter()
        .find(|(_, l)| b.vertices[l.start].name == "lobby" && b.vertices[l.end].name == "corridor")
        .expect("lane");
    b.lanes[lh].bidirectional = false;
    let nav = Nav::build(&b, &[0]);
    let (lobby, corridor) = (vertex(&nav, "lobby"), vertex(&nav, "corridor"));
    assert!(nav.plan(0, lobby, corridor, 0.5).is_some());
    assert!(nav.plan(0, corridor, lobby, 0.5).is_none());
}

/// Two lanes crossing in an X, and one far away.
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
      - [0, 30, 0, far_w]
      - [10, 30, 0, far_e]
      - [0, 8, 0, park_w, {is_parking_spot: [4, true]}]
      - [10, 8, 0, park_e, {is_parking_spot: [4, true]}]
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [4, 5, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [0, 6, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [1, 7, {bidirectional: [4, true], graph_idx: [2, 0]}]
"#;

fn cross() -> Building {
    parse_map("cross", CROSS)
}

#[test]
fn crossing_lanes_conflict_and_far_ones_do_not() {
    let b = cross();
    let nav = Nav::build(&b, &[0]);
    let c = Clearance {
        footprint: 0.3,
        vicinity: 0.0,
        stop_distance: 0.75,
        stop_radius: 0.75,
    };
    let conf = Conflicts::build(&nav, c);
    let edge = |a: &str, z: &str| {
        let (a, z) = (vertex(&nav, a), vertex(&nav, z));
        nav.edges
            .iter()
            .position(|e| e.from == a && e.to == z)
            .expect("edge")
    };
    let (we, sn, far) = (edge("w", "e"), edge("s", "n"), edge("far_w", "far_e"));
    let shares = |x: usize, y: usize| conf.trav[x].iter().any(|r| conf.trav[y].contains(r));
    assert!(shares(we, sn));
    assert!(!shares(we, far));
    // The geometric reason: the segments cross (distance 0), the far one is 25 m away.
    let p = |n: &str| nav.vertices[vertex(&nav, n)].pos;
    assert_eq!(segment_segment(p("w"), p("e"), p("s"), p("n")), 0.0);
    assert!((segment_segment(p("w"), p("e"), p("far_w"), p("far_e")) - 25.0).abs() < 1e-9);
    // The schedule orders them: robot 0 planned w→e over [0, 10), robot 1 s→n over
    // [10, 20): robot 1 is granted its crossing only once robot 0 has crossed.
    let step = |e: usize, a: f64| SchedStep {
        edge: e,
        from: nav.edges[e].from,
        to: nav.edges[e].to,
        dur: 10.0,
        hold: 0.0,
        start: a,
        end: a + 10.0,
    };
    let starts = [nav.edges[we].from, nav.edges[sn].from];
    let mut sched = Schedule::new(conf, &starts, 0.0);
    sched.install(0, 0, &[step(we, 0.0)], 0.0, None);
    sched.install(1, 0, &[step(sn, 10.0)], 0.0, None);
    assert!(sched.check(0.0).is_ok());
    assert!(sched.granted(0, 0));
    assert!(!sched.granted(1, 0));
    assert_eq!(sched.waits_for(1, 0), vec![0]);
    sched.begin(0, 1, 0.0);
    sched.complete_front(0, 9.0);
    assert!(sched.granted(1, 0));
}

#[test]
fn auto_spawn_starts_robots_nearest_the_task_places() {
    // The traffic tests' corridor a - b - c - d (4 m apart), parking spots p1 off b and
    // p2 off c (3 m off the corridor).
    let parsed = mapc_frontend::parse_str("t.building.yaml", crate::traffic::test_map::YAML);
    let b = parsed.building.expect("test map parses");
    let go_to = |place: &str| {
        task(
            0.0,
            TaskKind::GoToPlace {
                place: place.into(),
            },
        )
    };
    let start = |tasks: Vec<TaskSpec>| {
        let p = Fleets::place(&b, &scenario(vec![fleet("f", 1, SpawnSpec::Auto)], tasks))
            .expect("placement");
        (p.robots[0].x, p.robots[0].y)
    };
    // Work at d: the robot starts on p2 (7 m from d), though p1 (11 m) comes first in
    // waypoint order.
    assert_eq!(start(vec![go_to("d")]), (8.0, 3.0));
    assert_eq!(start(vec![go_to("a")]), (4.0, 3.0));
    // Work at both ends: the drives from either spot sum to 18 m, a tie broken by
    // waypoint order.
    assert_eq!(start(vec![go_to("a"), go_to("d")]), (4.0, 3.0));
}

#[test]
fn spawn_placement() {
    let b = clinic();
    // Map spawn points: the one named in the map.
    let p = Fleets::place(
        &b,
        &scenario(vec![fleet("tiny", 1, SpawnSpec::MapSpawnPoints)], vec![]),
    )
    .expect("placement");
    assert_eq!(p.robots[0].name, "tinyRobot1");
    // Not enough spawn points.
    let e = Fleets::place(
        &b,
        &scenario(vec![fleet("tiny", 2, SpawnSpec::MapSpawnPoints)], vec![]),
    )
    .err()
    .expect("error");
    assert!(
        e.iter().any(|d| d.code == codes::NOT_ENOUGH_SPAWNS),
        "{e:?}"
    );
    // Unknown waypoint, with a suggestion.
    let e = Fleets::place(
        &b,
        &scenario(
            vec![fleet(
                "tiny",
                1,
                SpawnSpec::Waypoints(vec!["lobbby".into()]),
            )],
            vec![],
        ),
    )
    .err()
    .expect("error");
    assert_eq!(e[0].code, codes::UNKNOWN_WAYPOINT);
    // Auto: on parking vertices off the chargers and task places (where a standing robot
    // blocks nobody), never closer than the footprints + 0.5 m.
    let p = Fleets::place(
        &b,
        &scenario(vec![fleet("tiny", 3, SpawnSpec::Auto)], vec![]),
    )
    .expect("auto");
    assert_eq!(p.robots.len(), 3);
    assert_eq!(p.robots[0].name, "tiny_0");
    let nav = Nav::build(&b, &[0]);
    for r in &p.robots {
        let v = (0..nav.vertices.len())
            .find(|&v| {
                let q = nav.vertices[v].pos;
                nav.vertices[v].level == r.level && (q.x - r.x).hypot(q.y - r.y) < 1e-9
            })
            .expect("on a waypoint");
        assert_eq!(
            p.parks.per_slot[0][v],
            crate::traffic::parks::PARK,
            "{}",
            r.name
        );
        assert!(!nav.vertices[v].roles.is_charger, "{}", r.name);
    }
    for (i, a) in p.robots.iter().enumerate() {
        for c in &p.robots[i + 1..] {
            if a.level == c.level {
                assert!((a.x - c.x).hypot(a.y - c.y) >= 2.0 * 0.3 + 0.5);
            }
        }
    }
    // A task naming an unknown waypoint is refused by `new`.
    let s = scenario(
        vec![fleet("tiny", 1, SpawnSpec::MapSpawnPoints)],
        vec![task(
            0.0,
            TaskKind::GoToPlace {
                place: "nowhere".into(),
            },
        )],
    );
    let p = Fleets::place(&b, &s).expect("placement");
    let e = Fleets::new(&b, &s, &p).err().expect("error");
    assert_eq!(e[0].code, codes::UNKNOWN_WAYPOINT);
}

// ----- a kinematic stand-in of the world -----

struct MockRobot {
    name: String,
    pos: Vec2,
    yaw: f64,
    level: String,
    path: Vec<Location>,
    task_id: String,
    speed: f64,
    footprint: f64,
    seq: u64,
}

struct Mock {
    t: f64,
    robots: Vec<MockRobot>,
    levels: Vec<(String, f64)>,
    door_sessions: BTreeMap<String, Vec<String>>,
    door_open_at: BTreeMap<String, f64>,
    /// lift name → (floor, session, busy until, destination)
    lifts: BTreeMap<String, (String, String, f64, String)>,
    lift_cabins: Vec<(String, Vec2, f64)>,
    pending: Vec<Published>,
    min_gap: f64,
    door_open_log: Vec<(f64, String, usize)>,
    paths: Vec<PathRequest>,
}

impl Mock {
    fn new(b: &Building, placement: &Placement) -> Mock {
        let levels = b
            .levels
            .iter()
            .map(|(_, l)| (l.name.clone(), l.elevation))
            .collect();
        let robots = placement
            .robots
            .iter()
            .map(|r| MockRobot {
                name: r.name.clone(),
                pos: Vec2::new(r.x, r.y),
                yaw: r.yaw,
                level: b.levels[r.level].name.clone(),
                path: Vec::new(),
                task_id: String::new(),
                speed: r.params.nominal_drive_speed,
                footprint: r.params.footprint,
                seq: 0,
            })
            .collect();
        let mut lifts = BTreeMap::new();
        let mut lift_cabins = Vec::new();
        for (_, l) in b.lifts.iter() {
            let floor = l
                .initial_floor()
                .map(|h| b.levels[h].name.clone())
                .unwrap_or_default();
            lifts.insert(l.name.clone(), (floor, String::new(), 0.0, String::new()));
            lift_cabins.push((l.name.clone(), l.pos, l.width.max(l.depth)));
        }
        Mock {
            t: 0.0,
            robots,
            levels,
            door_sessions: BTreeMap::new(),
            door_open_at: BTreeMap::new(),
            lifts,
            lift_cabins,
            pending: Vec::new(),
            min_gap: f64::INFINITY,
            door_open_log: Vec::new(),
            paths: Vec::new(),
        }
    }

    fn publish(&mut self, topic: Topic, msg: Msg) {
        self.pending.push(Published {
            t: self.t,
            topic,
            msg,
        });
    }

    fn deliver(&mut self, topic: Topic, msg: Msg) {
        match (topic, msg) {
            (Topic::RobotPathRequests, Msg::PathRequest(p)) => {
                self.paths.push(p.clone());
                let Some(r) = self.robots.iter_mut().find(|r| r.name == p.robot_name) else {
                    return;
                };
                if p.task_id == r.task_id || p.path.is_empty() {
                    return;
                }
                r.task_id = p.task_id.clone();
                let d0 = (p.path[0].x - r.pos.x).hypot(p.path[0].y - r.pos.y);
                assert!(d0 <= 1.0, "path starts {d0} m from {}", r.name);
                r.path = p.path[1..].to_vec();
            }
            (Topic::AdapterDoorRequests, Msg::DoorRequest(d)) => {
                let s = self.door_sessions.entry(d.door_name.clone()).or_default();
                if d.requested_mode.value == door_mode::OPEN {
                    if !s.contains(&d.requester_id) {
                        s.push(d.requester_id.clone());
                    }
                    self.door_open_at
                        .entry(d.door_name.clone())
                        .or_insert(self.t + 1.0);
                } else {
                    s.retain(|x| *x != d.requester_id);
                    if s.is_empty() {
                        self.door_open_at.remove(&d.door_name);
                    }
                }
                let all_sessions = self
                    .door_sessions
                    .iter()
                    .map(|(k, v)| DoorSessions {
                        door_name: k.clone(),
                        sessions: v
                            .iter()
                            .map(|r| Session {
                                request_time: Time::default(),
                                requester_id: r.clone(),
                            })
                            .collect(),
                    })
                    .collect();
                self.publish(
                    Topic::DoorSupervisorHeartbeat,
                    Msg::DoorHeartbeat(SupervisorHeartbeat { all_sessions }),
                );
            }
            (Topic::AdapterLiftRequests, Msg::LiftRequest(l)) => {
                let t = self.t;
                let Some(lift) = self.lifts.get_mut(&l.lift_name) else {
                    return;
                };
                if l.request_type == lift_request::END_SESSION {
                    if lift.1 == l.session_id {
                        lift.1.clear();
                    }
                    return;
                }
                // First come owns the lift; others are ignored (the adapter retries).
                if !lift.1.is_empty() && lift.1 != l.session_id {
                    return;
                }
                lift.1 = l.session_id.clone();
                if lift.3 != l.destination_floor {
                    lift.3 = l.destination_floor.clone();
                    lift.2 = t + if lift.0 == l.destination_floor {
                        0.5
                    } else {
                        4.0
                    };
                }
            }
            (Topic::DispenserRequests, Msg::WorkcellRequest(w)) => self.publish(
                Topic::DispenserResults,
                Msg::WorkcellResult(WorkcellResult {
                    time: Time::whole(self.t),
                    request_guid: w.request_guid,
                    status: if w.target_guid == "broken" {
                        workcell_result::FAILED
                    } else {
                        workcell_result::SUCCESS
                    },
                    source_guid: w.target_guid,
                }),
            ),
            (Topic::IngestorRequests, Msg::WorkcellRequest(w)) => self.publish(
                Topic::IngestorResults,
                Msg::WorkcellResult(WorkcellResult {
                    time: Time::whole(self.t),
                    request_guid: w.request_guid,
                    source_guid: w.target_guid,
                    status: workcell_result::SUCCESS,
                }),
            ),
            _ => {}
        }
    }

    fn step(&mut self, dt: f64, out: &mut Vec<Published>) {
        self.t += dt;
        let t = self.t;
        let open_doors: Vec<String> = self
            .door_open_at
            .iter()
            .filter(|(_, &at)| at <= t)
            .map(|(k, _)| k.clone())
            .collect();
        for r in &mut self.robots {
            if let Some(target) = r.path.first() {
                let d = Vec2::new(target.x - r.pos.x, target.y - r.pos.y);
                let n = d.norm();
                let v = if target.obey_approach_speed_limit {
                    r.speed.min(target.approach_speed_limit)
                } else {
                    r.speed
                };
                if n <= v * dt {
                    r.pos = Vec2::new(target.x, target.y);
                    r.yaw = target.yaw;
                    r.path.remove(0);
                } else {
                    r.pos = r.pos.plus(d.scale(v * dt / n));
                }
            }
        }
        // Lifts: move after their delay; carry the robots in the cabin.
        let names: Vec<String> = self.lifts.keys().cloned().collect();
        for name in names {
            let (floor, session, until, dest) = self.lifts[&name].clone();
            if !dest.is_empty() && t >= until && floor != dest {
                let cabin = self
                    .lift_cabins
                    .iter()
                    .find(|c| c.0 == name)
                    .map(|c| (c.1, c.2));
                if let Some((p, size)) = cabin {
                    for r in &mut self.robots {
                        if r.level == floor && r.pos.minus(p).norm() < size / 2.0 {
                            r.level = dest.clone();
                        }
                    }
                }
                if let Some(l) = self.lifts.get_mut(&name) {
                    l.0 = dest.clone();
                }
            }
            let (floor, ..) = self.lifts[&name].clone();
            if (t * 100.0).round() as i64 % 50 == 0 {
                let arrived = !dest.is_empty() && t >= until && floor == dest;
                self.publish(
                    Topic::LiftStates,
                    Msg::LiftState(LiftState {
                        lift_name: name.clone(),
                        current_floor: floor.clone(),
                        destination_floor: dest.clone(),
                        door_state: if arrived {
                            lift_state::DOOR_OPEN
                        } else {
                            lift_state::DOOR_CLOSED
                        },
                        session_id: session.clone(),
                        ..LiftState::default()
                    }),
                );
            }
        }
        let tick = (t * 100.0).round() as i64;
        if tick % 100 == 0 {
            let doors: Vec<String> = self.door_sessions.keys().cloned().collect();
            for d in doors {
                let open = open_doors.contains(&d);
                if open {
                    let users = self.door_sessions.get(&d).map_or(0, |s| s.len());
                    self.door_open_log.push((t, d.clone(), users));
                }
                self.publish(
                    Topic::DoorStates,
                    Msg::DoorState(DoorState {
                        door_time: Time::from_secs(t),
                        door_name: d,
                        current_mode: DoorMode {
                            value: if open {
                                door_mode::OPEN
                            } else {
                                door_mode::CLOSED
                            },
                        },
                    }),
                );
            }
        }
        if tick % 50 == 0 {
            let states: Vec<RobotState> = self
                .robots
                .iter_mut()
                .map(|r| {
                    r.seq += 1;
                    RobotState {
                        name: r.name.clone(),
                        seq: r.seq,
                        task_id: r.task_id.clone(),
                        battery_percent: 100.0,
                        mode: RobotMode {
                            mode: if r.path.is_empty() {
                                robot_mode::IDLE
                            } else {
                                robot_mode::MOVING
                            },
                            ..RobotMode::default()
                        },
                        location: Location {
                            x: r.pos.x,
                            y: r.pos.y,
                            yaw: r.yaw,
                            level_name: r.level.clone(),
                            ..Location::default()
                        },
                        path: r.path.clone(),
                        ..RobotState::default()
                    }
                })
                .collect();
            for s in states {
                self.publish(Topic::RobotState, Msg::RobotState(s));
            }
        }
        for (i, a) in self.robots.iter().enumerate() {
            for c in &self.robots[i + 1..] {
                if a.level == c.level {
                    let gap = a.pos.minus(c.pos).norm() - (a.footprint + c.footprint);
                    self.min_gap = self.min_gap.min(gap);
                }
            }
        }
        let _ = &self.levels;
        out.append(&mut self.pending);
    }
}

/// Runs `s` on `b` against the mock for `seconds`; returns the task events and the mock.
fn run(b: &Building, s: &Scenario, seconds: f64) -> (Vec<TaskEvent>, Mock, Fleets) {
    let placement = Fleets::place(b, s).expect("placement");
    let mut fleets = Fleets::new(b, s, &placement).expect("fleets");
    let mut mock = Mock::new(b, &placement);
    let mut inbox = Vec::new();
    let mut out = Vec::new();
    let mut events = Vec::new();
    let steps = (seconds / s.step).round() as u64;
    for _ in 0..steps {
        let t = mock.t;
        out.clear();
        fleets.update(t, &inbox, &mut out);
        inbox.clear();
        for (topic, msg) in out.drain(..) {
            if let Msg::TaskEvent(e) = &msg {
                events.push(e.clone());
            } else {
                mock.deliver(topic, msg);
            }
        }
        mock.step(s.step, &mut inbox);
        if fleets.all_done(mock.t) && !events.is_empty() {
            break;
        }
    }
    (events, mock, fleets)
}

/// Goes on for `seconds` more after `run` (robots drive to park); returns the events.
fn settle(fleets: &mut Fleets, mock: &mut Mock, s: &Scenario, seconds: f64) -> Vec<TaskEvent> {
    let (mut inbox, mut out, mut events) = (Vec::new(), Vec::new(), Vec::new());
    let end = mock.t + seconds;
    while mock.t < end {
        out.clear();
        fleets.update(mock.t, &inbox, &mut out);
        inbox.clear();
        for (topic, msg) in out.drain(..) {
            if let Msg::TaskEvent(e) = &msg {
                events.push(e.clone());
            } else {
                mock.deliver(topic, msg);
            }
        }
        mock.step(s.step, &mut inbox);
    }
    events
}

fn ended(events: &[TaskEvent]) -> Vec<(String, String)> {
    events
        .iter()
        .filter(|e| e.event == "completed" || e.event == "failed")
        .map(|e| (e.task_id.clone(), e.event.clone()))
        .collect()
}

#[test]
fn delivery_through_doors_and_lift_completes() {
    let b = clinic();
    let mut s = scenario(
        vec![fleet("tiny", 1, SpawnSpec::MapSpawnPoints)],
        vec![task(
            1.0,
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
    let (events, mut mock, mut f) = run(&b, &s, 600.0);
    assert_eq!(
        ended(&events),
        vec![("delivery_0".to_string(), "completed".to_string())],
        "{events:#?}"
    );
    // It ended the task at the drop-off, on L2.
    let r = &mock.robots[0];
    assert_eq!(r.level, "L2");
    let nav = Nav::build(&b, &[0]);
    let goal = nav.vertices[vertex(&nav, "ward_a")].pos;
    assert!(r.pos.minus(goal).norm() < 1e-6);
    // Then it parks off the task places (its itinerary ends on a parking vertex).
    settle(&mut f, &mut mock, &s, 300.0);
    let end = f.floor.traffic.sched.end_vertex(0);
    assert_eq!(f.floor.traffic.parks(0)[end], crate::traffic::parks::PARK);
    assert_eq!(f.floor.robots[0].at, end);
    // Every door that was opened was opened for the robot, and all are closed again.
    assert!(mock
        .door_open_log
        .iter()
        .any(|(_, d, _)| d == "L1_lobby_door"));
    assert!(mock.door_sessions.values().all(|s| s.is_empty()));
    // The lift session was ended.
    assert!(mock.lifts.values().all(|l| l.1.is_empty()));
}

/// A scenario workcell named like one of the map's dispensers is refused (S0308): both
/// would answer its requests, and a robot was handed two items.
#[test]
fn a_workcell_named_like_one_of_the_maps_is_refused() {
    let b = clinic();
    let mut s = scenario(
        vec![fleet("tiny", 1, SpawnSpec::MapSpawnPoints)],
        Vec::new(),
    );
    s.workcells.push(WorkcellSpec {
        name: "pharmacy_dispenser".into(),
        kind: crate::scenario::WorkcellKind::Dispenser,
        waypoint: "ward_a".into(),
        span: Span::UNKNOWN,
    });
    let Err(diags) = Fleets::place(&b, &s) else {
        panic!("placed a workcell named like the map's `pharmacy_dispenser`");
    };
    assert!(
        diags
            .iter()
            .any(|d| d.code == "S0308" && d.message.contains("pharmacy_dispenser")),
        "{diags:#?}"
    );
}

#[test]
fn crossing_robots_keep_apart() {
    let b = cross();
    let s = scenario(
        vec![
            fleet("a", 1, SpawnSpec::Waypoints(vec!["w".into()])),
            fleet("b", 1, SpawnSpec::Waypoints(vec!["s".into()])),
        ],
        vec![
            TaskSpec {
                fleet: Some("a".into()),
                ..task(0.5, TaskKind::GoToPlace { place: "e".into() })
            },
            TaskSpec {
                fleet: Some("b".into()),
                ..task(0.5, TaskKind::GoToPlace { place: "n".into() })
            },
        ],
    );
    let (events, mock, _) = run(&b, &s, 200.0);
    assert_eq!(ended(&events).len(), 2, "{events:#?}");
    assert!(ended(&events).iter().all(|e| e.1 == "completed"));
    // Without reservations the two would meet at (5, 5) at the same time (same speed,
    // same distance); with them they never touch.
    assert!(mock.min_gap > 0.0, "min gap {}", mock.min_gap);
}

#[test]
fn head_on_on_a_single_lane_both_arrive() {
    let b = cross();
    // a: w → e, b: e → w on the same lane: the younger move makes room (a parking spot
    // beside the lane), the older drives; nobody fails, nobody touches.
    let s = scenario(
        vec![
            fleet("a", 1, SpawnSpec::Waypoints(vec!["w".into()])),
            fleet("b", 1, SpawnSpec::Waypoints(vec!["e".into()])),
        ],
        vec![
            TaskSpec {
                fleet: Some("a".into()),
                ..task(0.5, TaskKind::GoToPlace { place: "e".into() })
            },
            TaskSpec {
                fleet: Some("b".into()),
                ..task(0.5, TaskKind::GoToPlace { place: "w".into() })
            },
        ],
    );
    let (events, mock, _) = run(&b, &s, 400.0);
    let done = ended(&events);
    assert_eq!(done.len(), 2, "{events:#?}");
    assert!(done.iter().all(|e| e.1 == "completed"), "{events:#?}");
    assert!(!events.iter().any(|e| e.event == "stuck"), "{events:#?}");
    assert!(mock.min_gap > 0.0, "min gap {}", mock.min_gap);
}

#[test]
fn generator_ids_and_idle_update_is_cheap() {
    let b = clinic();
    let mut s = scenario(vec![fleet("tiny", 1, SpawnSpec::MapSpawnPoints)], vec![]);
    s.duration = 100.0;
    s.generators.push(GeneratorSpec {
        every: 30.0,
        start: 0.0,
        end: Some(70.0),
        kind: TaskKind::Loop {
            start: "lobby".into(),
            finish: "tinyRobot1_charger".into(),
            loops: 1,
        },
        fleet: None,
        span: Span::UNKNOWN,
    });
    let (events, _, fleets) = run(&b, &s, 300.0);
    let queued: Vec<&str> = events
        .iter()
        .filter(|e| e.event == "queued")
        .map(|e| e.task_id.as_str())
        .collect();
    // Requests at 0, 30, 60 (70 excluded: 90 > 70).
    assert_eq!(queued, ["loop_0", "loop_1", "loop_2"]);
    assert!(fleets.all_done(300.0));
    assert_eq!(
        ended(&events).iter().filter(|e| e.1 == "completed").count(),
        3,
        "{events:#?}"
    );
}

#[test]
fn clean_without_dock_waits_clean_duration() {
    let b = cross();
    let mut s = scenario(
        vec![fleet("a", 1, SpawnSpec::Waypoints(vec!["w".into()]))],
        vec![task(0.5, TaskKind::Clean { zone: "e".into() })],
    );
    s.options.clean_duration = 30.0;
    let (events, _, f) = run(&b, &s, 300.0);
    let done: Vec<&TaskEvent> = events.iter().filter(|e| e.event == "completed").collect();
    assert_eq!(done.len(), 1, "{events:#?}");
    // w is no parking vertex: at t = 0 the robot is sent to park_w (3 m at 0.5 m/s). The
    // task (t = 0.5) is planned from where that traversal ends: back to w and on to e
    // (3 + 10 m), then 30 s of cleaning; the fleet sees arrival through RobotState (2 Hz)
    // and acts on the next update.
    let t = done[0].time.as_secs();
    let expect = 3.0 / 0.5 + 13.0 / 0.5 + 30.0;
    assert!(t >= expect - 1e-6 && t <= expect + 1.0, "{t} vs {expect}");
    // Two phases: to the zone, then the clean (its 30 s), which ends with the task.
    let phases: Vec<(&str, f64)> = events
        .iter()
        .filter(|e| e.event == "phase")
        .map(|e| (e.detail.as_str(), e.time.as_secs()))
        .collect();
    assert_eq!(phases.len(), 2, "{events:#?}");
    assert_eq!((phases[0].0, phases[1].0), ("go_to_place e", "clean e"));
    assert!((phases[1].1 - phases[0].1 - 30.0).abs() < 1.0, "{phases:?}");
    assert_eq!(phases[1].1, t);
    // Then it parks on the nearest parking vertex off the task places: park_e, beside e.
    assert_eq!(
        f.floor.traffic.sched.end_vertex(0),
        vertex(&f.floor.nav, "park_e")
    );
    assert_eq!(
        f.floor.traffic.parks(0)[vertex(&f.floor.nav, "park_e")],
        crate::traffic::parks::PARK
    );
}

/// A clean with a docking lane: two phases, to the zone and the clean (into the dock and
/// back, one phase), which ends with the task.
#[test]
fn clean_with_dock_is_two_phases() {
    let text = CROSS.replace(
        "    lanes:\n",
        "      - [10, 2, 0, e_dock, {dock_name: [1, e_dock]}]\n    lanes:\n      - [1, 8, {bidirectional: [4, true], graph_idx: [2, 0]}]\n",
    );
    let b = parse_map("cross_dock", &text);
    let s = scenario(
        vec![fleet("a", 1, SpawnSpec::Waypoints(vec!["park_w".into()]))],
        vec![task(0.5, TaskKind::Clean { zone: "e".into() })],
    );
    let (events, _, f) = run(&b, &s, 300.0);
    let steps = f
        .floor
        .expand(0, &TaskKind::Clean { zone: "e".into() })
        .expect("on the graph");
    let (e, d) = (vertex(&f.floor.nav, "e"), vertex(&f.floor.nav, "e_dock"));
    assert_eq!(steps, [Step::GoTo(e), Step::GoTo(d), Step::GoTo(e)]);
    let names = ["go_to_place e", "clean e"];
    let started = events
        .iter()
        .find(|e| e.event == "started")
        .expect("started");
    assert_eq!(started.phases, Some(names.map(String::from).to_vec()));
    let phases: Vec<(&str, f64)> = events
        .iter()
        .filter(|e| e.event == "phase")
        .map(|e| (e.detail.as_str(), e.time.as_secs()))
        .collect();
    assert_eq!(phases.iter().map(|p| p.0).collect::<Vec<_>>(), names);
    // Into the dock and back: 3 m each way.
    assert!(phases[1].1 - phases[0].1 > 6.0 / 0.5, "{phases:?}");
    let done = events
        .iter()
        .find(|e| e.event == "completed")
        .expect("done");
    assert_eq!(phases[1].1, done.time.as_secs());
}

#[test]
fn robots_spawned_too_close_can_drive_apart() {
    let text = r#"
coordinate_system: cartesian_meters
name: close
levels:
  L1:
    elevation: 0
    vertices:
      - [0, 0, 0, a]
      - [0.7, 0, 0, b]
      - [-10, 0, 0, far_a]
      - [10.7, 0, 0, far_b]
    lanes:
      - [0, 2, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [1, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
"#;
    let b = mapc_frontend::parse_str("close", text)
        .building
        .expect("parses");
    let s = scenario(
        vec![
            fleet("a", 1, SpawnSpec::Waypoints(vec!["a".into()])),
            fleet("b", 1, SpawnSpec::Waypoints(vec!["b".into()])),
        ],
        vec![
            TaskSpec {
                fleet: Some("a".into()),
                ..task(
                    0.5,
                    TaskKind::GoToPlace {
                        place: "far_a".into(),
                    },
                )
            },
            TaskSpec {
                fleet: Some("b".into()),
                ..task(
                    0.5,
                    TaskKind::GoToPlace {
                        place: "far_b".into(),
                    },
                )
            },
        ],
    );
    let (events, _, _) = run(&b, &s, 200.0);
    let done = ended(&events);
    assert_eq!(done.len(), 2, "{events:#?}");
    assert!(done.iter().all(|e| e.1 == "completed"), "{events:#?}");
}

#[test]
fn assignment_by_category_and_soonest_start() {
    let b = cross();
    let mut a = fleet("a", 1, SpawnSpec::Waypoints(vec!["w".into()]));
    a.task_kinds = vec![TaskCategory::Loop];
    let c = fleet(
        "c",
        2,
        SpawnSpec::Waypoints(vec!["far_w".into(), "far_e".into()]),
    );
    let s = scenario(
        vec![a, c],
        vec![
            // c_1 stands at far_e: no travel, c_0 would drive 10 m.
            task(
                0.5,
                TaskKind::GoToPlace {
                    place: "far_e".into(),
                },
            ),
            // c_1 is busy now; c_0 stands at the pickup. The dispenser fails (every
            // time it is asked, for ITEM_WAIT).
            task(
                0.6,
                TaskKind::Delivery {
                    pickup: "far_w".into(),
                    dropoff: "far_e".into(),
                    dispenser: Some("broken".into()),
                    ingestor: Some("sink".into()),
                },
            ),
            // Only fleet a reaches e, and it takes loops only.
            task(0.7, TaskKind::GoToPlace { place: "e".into() }),
        ],
    );
    let (events, _, _) = run(&b, &s, ITEM_WAIT + 60.0);
    let assigned: Vec<(&str, &str)> = events
        .iter()
        .filter(|e| e.event == "assigned")
        .map(|e| (e.task_id.as_str(), e.robot.as_str()))
        .collect();
    // The delivery is planned whole when a robot takes it: its drop-off, far_e, is where
    // c_1 stays after its go-to-place, and the two-waypoint graph leaves c_1 nowhere to
    // make room to. So no robot can take it: it waits in the queue (neither assigned nor
    // failed), and c_0 is not sent to a pickup it could not leave.
    assert_eq!(assigned, [("go_to_place_0", "c_1")]);
    let mut done: Vec<(String, String)> = ended(&events);
    done.sort();
    let expect = [("go_to_place_0", "completed"), ("go_to_place_1", "failed")];
    assert_eq!(
        done,
        expect.map(|(a, b)| (a.to_string(), b.to_string())).to_vec()
    );
    let detail = |id: &str| {
        events
            .iter()
            .find(|e| e.task_id == id && e.event == "failed")
            .map(|e| e.detail.clone())
    };
    assert_eq!(detail("delivery_0"), None);
    assert_eq!(
        detail("go_to_place_1").as_deref(),
        Some("no robot can reach the task")
    );
}

/// Who was assigned which task, in order.
fn assignments(events: &[TaskEvent]) -> Vec<(&str, &str)> {
    events
        .iter()
        .filter(|e| e.event == "assigned")
        .map(|e| (e.task_id.as_str(), e.robot.as_str()))
        .collect()
}

/// A go-to-place task at `at` to `place`, for `robot` only when named.
fn go(at: f64, place: &str, robot: Option<&str>) -> TaskSpec {
    TaskSpec {
        robot: robot.map(str::to_string),
        ..task(
            at,
            TaskKind::GoToPlace {
                place: place.into(),
            },
        )
    }
}

#[test]
fn a_robot_task_goes_to_its_robot_only() {
    let b = cross();
    let c = fleet(
        "c",
        2,
        SpawnSpec::Waypoints(vec!["park_w".into(), "park_e".into()]),
    );
    // c_1 stands 3 m from e, c_0 13 m: without its robot named, c_1 would take it.
    let s = scenario(
        vec![c],
        vec![go(0.5, "e", Some("c_0")), go(0.6, "w", Some("nobody"))],
    );
    let (events, _, _) = run(&b, &s, 120.0);
    assert_eq!(assignments(&events), [("go_to_place_0", "c_0")]);
    let mut done = ended(&events);
    done.sort();
    let expect = [("go_to_place_0", "completed"), ("go_to_place_1", "failed")];
    assert_eq!(done, expect.map(|(a, b)| (a.to_string(), b.to_string())));
    let failed = events.iter().find(|e| e.event == "failed").expect("failed");
    assert_eq!(failed.detail, "no robot named `nobody` in the task's fleet");
}

#[test]
fn a_higher_priority_task_goes_before_older_ones() {
    let b = cross();
    let c = fleet("c", 1, SpawnSpec::Waypoints(vec!["park_w".into()]));
    let go = |at: f64, place: &str, priority: u64| TaskSpec {
        priority,
        ..task(
            at,
            TaskKind::GoToPlace {
                place: place.into(),
            },
        )
    };
    // The robot drives to e; meanwhile w (priority 0), then park_e (priority 1) come.
    let s = scenario(
        vec![c],
        vec![go(0.5, "e", 0), go(0.6, "w", 0), go(0.7, "park_e", 1)],
    );
    let (events, _, _) = run(&b, &s, 300.0);
    assert_eq!(
        assignments(&events),
        [
            ("go_to_place_0", "c_0"),
            ("go_to_place_2", "c_0"),
            ("go_to_place_1", "c_0")
        ]
    );
}

#[test]
fn speed_limits_reach_the_path() {
    let text = r#"
coordinate_system: cartesian_meters
name: slow
levels:
  L1:
    elevation: 0
    vertices:
      - [0, 0, 0, a]
      - [10, 0, 0, b]
      - [20, 0, 0, c]
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0], speed_limit: [3, 0.2]}]
      - [1, 2, {bidirectional: [4, true], graph_idx: [2, 0]}]
"#;
    let b = mapc_frontend::parse_str("slow", text)
        .building
        .expect("parses");
    let s = scenario(
        vec![fleet("a", 1, SpawnSpec::Waypoints(vec!["a".into()]))],
        vec![task(0.5, TaskKind::GoToPlace { place: "c".into() })],
    );
    let (events, mock, _) = run(&b, &s, 200.0);
    let done = events
        .iter()
        .find(|e| e.event == "completed")
        .expect("completed");
    // 10 m at 0.2 m/s, then 10 m at 0.5 m/s (TinyRobot), plus up to one RobotState period.
    let expect = 0.5 + 10.0 / 0.2 + 10.0 / 0.5;
    let t = done.time.as_secs();
    assert!(t >= expect - 1e-6 && t <= expect + 1.0, "{t} vs {expect}");
    let first = &mock.paths[0];
    assert_eq!((first.path[0].x, first.path[0].y), (0.0, 0.0));
    assert!(first.path[1].obey_approach_speed_limit);
    assert_eq!(first.path[1].approach_speed_limit, 0.2);
    assert!(!first.path[2].obey_approach_speed_limit);
    assert_eq!(first.path[2].level_name, "L1");
}

#[test]
fn task_waypoint_in_a_lift_cabin_is_refused() {
    let mut b = clinic();
    let cabin = b
        .vertices
        .iter()
        .find(|(_, v)| v.roles.lift_cabin.is_some())
        .map(|(h, _)| h)
        .expect("cabin vertex");
    b.vertices[cabin].name = "cabin".into();
    let s = scenario(
        vec![fleet("tiny", 1, SpawnSpec::MapSpawnPoints)],
        vec![task(
            0.0,
            TaskKind::GoToPlace {
                place: "cabin".into(),
            },
        )],
    );
    let p = Fleets::place(&b, &s).expect("placement");
    let e = Fleets::new(&b, &s, &p).err().expect("error");
    assert_eq!(e[0].code, codes::IN_LIFT);
}

#[test]
fn an_empty_dispensers_item_is_coming_while_its_carrier_is_on_its_way() {
    // c_0 drives to far_e (a GoTo under way): pretend it carries `disp`'s item. A robot
    // waiting at `disp` then keeps asking past ITEM_WAIT; once the carrier has nothing
    // left to do (its return trip dropped), the item is not coming and the wait is bounded.
    let b = cross();
    let s = scenario(
        vec![fleet("c", 1, SpawnSpec::Waypoints(vec!["far_w".into()]))],
        vec![task(
            0.5,
            TaskKind::GoToPlace {
                place: "far_e".into(),
            },
        )],
    );
    let (_, _, mut f) = run(&b, &s, 2.0);
    assert!(matches!(f.floor.robots[0].cur, Cur::GoTo { .. }));
    assert!(!f.floor.item_coming("disp", 2.0), "nothing carried yet");
    f.floor.robots[0].item_from = Some("disp".into());
    assert!(f.floor.item_coming("disp", 2.0));
    assert!(!f.floor.item_coming("other", 2.0));
    f.floor.robots[0].cur = Cur::None;
    f.floor.robots[0].steps.clear();
    assert!(
        !f.floor.item_coming("disp", 2.0),
        "a carrier with nothing to do brings nothing back"
    );
    // Ingested: the plugin sends it home after a few seconds, so it is still coming then.
    f.floor.devices.ingested("disp".into(), 2.0);
    assert!(f.floor.item_coming("disp", 2.0 + ITEM_HOME - 1.0));
    assert!(!f.floor.item_coming("disp", 2.0 + ITEM_HOME + 1.0));
}

#[test]
fn a_robot_waiting_at_an_empty_dispenser_makes_room() {
    // park_w - w - e - park_e in a line. a_0 waits at e for a dispenser's item (asked,
    // answered empty, asks again much later); b_0 must pass e to reach w. The item could
    // be the one b_0 brings back, so a_0 must make room (to park_w) and come back.
    let b = cross();
    let s = scenario(
        vec![
            fleet("a", 1, SpawnSpec::Waypoints(vec!["e".into()])),
            fleet("b", 1, SpawnSpec::Waypoints(vec!["park_e".into()])),
        ],
        vec![TaskSpec {
            fleet: Some("b".into()),
            ..task(0.5, TaskKind::GoToPlace { place: "w".into() })
        }],
    );
    let placement = Fleets::place(&b, &s).expect("placement");
    let mut f = Fleets::new(&b, &s, &placement).expect("fleets");
    let mut mock = Mock::new(&b, &placement);
    let a = f.floor.by_name["a_0"];
    let e = f.floor.robots[a].at;
    f.floor.robots[a].cur = Cur::Workcell {
        guid: "x_pickup_retry1".into(),
        target: "disp".into(),
        dispenser: true,
        next_send: 1e9,
        deadline: 1e9,
        tries: 1,
        since: 0.0,
        sent: false,
    };
    let (mut inbox, mut out, mut events) = (Vec::new(), Vec::new(), Vec::new());
    let mut asked_again = false;
    while mock.t < 120.0 {
        out.clear();
        f.update(mock.t, &inbox, &mut out);
        inbox.clear();
        for (topic, msg) in out.drain(..) {
            match &msg {
                Msg::TaskEvent(ev) => events.push(ev.clone()),
                Msg::WorkcellRequest(w) if w.target_guid == "disp" => asked_again = true,
                _ => {}
            }
            if !matches!(msg, Msg::TaskEvent(_)) {
                mock.deliver(topic, msg);
            }
        }
        mock.step(s.step, &mut inbox);
    }
    assert_eq!(
        ended(&events),
        vec![("go_to_place_0".to_string(), "completed".to_string())],
        "{events:#?}"
    );
    // a_0 came back to its dispenser and asked for the item again.
    assert!(asked_again);
    assert_eq!(f.floor.robots[a].at, e);
}

fn parse_map(name: &str, text: &str) -> Building {
    let parsed = mapc_frontend::parse_str(name, text);
    assert!(!parsed.has_errors(), "{:?}", parsed.diagnostics);
    parsed.building.expect("map parses")
}

/// RMF's patrol of three places: each place in order, every round; and done end to end.
#[test]
fn a_patrol_of_three_places_visits_them_in_order_each_round() {
    let b = clinic();
    let kind = TaskKind::Patrol {
        places: vec!["lobby".into(), "pharmacy".into(), "corridor".into()],
        rounds: 2,
    };
    let mut s = scenario(vec![fleet("tiny", 1, SpawnSpec::MapSpawnPoints)], vec![]);
    s.tasks.push(TaskSpec {
        at: 0.0,
        kind: kind.clone(),
        fleet: None,
        robot: None,
        priority: 0,
        span: Span::UNKNOWN,
    });
    let (events, _, fleets) = run(&b, &s, 900.0);
    let v = |n: &str| {
        Step::GoTo(
            fleets
                .floor
                .nav
                .find(fleets.floor.fleets[0].slot, n)
                .expect(n),
        )
    };
    let steps = fleets.floor.expand(0, &kind).expect("on the graph");
    let round = [v("lobby"), v("pharmacy"), v("corridor")];
    assert_eq!(steps, [round.clone(), round].concat());
    let off = TaskKind::Patrol {
        places: vec!["lobby".into(), "nowhere".into(), "corridor".into()],
        rounds: 1,
    };
    assert_eq!(fleets.floor.expand(0, &off), None);
    let done: Vec<(&str, &str)> = events
        .iter()
        .filter(|e| e.event == "completed" || e.event == "failed")
        .map(|e| (e.task_id.as_str(), e.event.as_str()))
        .collect();
    assert_eq!(done, [("loop_0", "completed")], "{events:?}");
    // A `phase` event per place reached, in order; the `started` event names them all.
    let names: Vec<String> = ["lobby", "pharmacy", "corridor"]
        .iter()
        .cycle()
        .take(6)
        .map(|p| format!("go_to_place {p}"))
        .collect();
    let at = |ev: &str| {
        let e = events.iter().find(|e| e.event == ev).expect(ev);
        (e.time.as_secs(), e)
    };
    let (started, e) = at("started");
    assert_eq!(e.phases.as_ref(), Some(&names));
    let phases: Vec<&TaskEvent> = events.iter().filter(|e| e.event == "phase").collect();
    let details: Vec<&str> = phases.iter().map(|e| e.detail.as_str()).collect();
    assert_eq!(details, names, "{events:#?}");
    assert!(phases
        .iter()
        .all(|p| p.task_id == "loop_0" && p.robot == e.robot && !p.robot.is_empty()));
    // Each place after the one before (they are apart), the last when the task ends.
    let times: Vec<f64> = phases.iter().map(|e| e.time.as_secs()).collect();
    assert!(started <= times[0], "{started} {times:?}");
    assert!(times.windows(2).all(|w| w[0] < w[1]), "{times:?}");
    assert_eq!(times.last().copied(), Some(at("completed").0));
}

/// More robots than parking vertices (a fleet config's start waypoints): a robot standing
/// off the parking vertices, with every parking vertex taken for good, plans its task to end
/// back where it stands. Before, no plan could end anywhere and it never moved.
#[test]
fn a_robot_with_no_parking_vertex_left_ends_its_plan_where_it_stands() {
    let b = cross();
    let s = scenario(
        vec![fleet(
            "a",
            3,
            SpawnSpec::Waypoints(vec!["park_w".into(), "park_e".into(), "w".into()]),
        )],
        vec![TaskSpec {
            robot: Some("a_2".into()),
            ..one_loop(0.5, "e", "w")
        }],
    );
    let (events, _, f) = run(&b, &s, 300.0);
    assert_eq!(
        ended(&events),
        vec![("loop_0".to_string(), "completed".to_string())],
        "{events:#?}"
    );
    let i = f.floor.by_name["a_2"];
    assert_eq!(
        f.floor.nav.vertices[f.floor.traffic.sched.end_vertex(i)].name,
        "w"
    );
}

#[test]
fn tasks_no_free_robot_may_take_do_not_hold_up_those_behind_them() {
    let b = cross();
    let c = fleet(
        "c",
        2,
        SpawnSpec::Waypoints(vec!["park_w".into(), "park_e".into()]),
    );
    // c_0 is sent back and forth by 100 tasks of its own (more than a round looks at);
    // a task any robot may do comes after them: to park_e, where c_1 stands free.
    let mut tasks: Vec<TaskSpec> = (0..100)
        .map(|k| go(0.5, if k % 2 == 0 { "e" } else { "w" }, Some("c_0")))
        .collect();
    tasks.push(go(1.0, "park_e", None));
    let s = scenario(vec![c], tasks);
    let (events, _, _) = run(&b, &s, 30.0);
    let last = events
        .iter()
        .find(|e| e.event == "assigned" && e.task_id == "go_to_place_100")
        .unwrap_or_else(|| panic!("not assigned in 30 s: {:?}", assignments(&events)));
    assert_eq!(last.robot, "c_1");
}

/// A robot on its way to its go-to-place, where it will stay, is not planned again to make
/// room for a second task to the same place: its new plan would end there again. The
/// second task waits until the first is done, then its robot, already there, takes it.
#[test]
fn a_robot_going_to_stay_at_a_place_is_not_moved_for_the_same_place() {
    let text = r#"
coordinate_system: cartesian_meters
name: corridor
levels:
  L1:
    elevation: 0
    vertices:
      - [0, 0, 0, park_a, {is_parking_spot: [4, true]}]
      - [0, 5, 0, park_b, {is_parking_spot: [4, true]}]
      - [10, 0, 0, x1]
      - [20, 0, 0, x2]
      - [30, 0, 0, room]
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [0, 2, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [3, 4, {bidirectional: [4, true], graph_idx: [2, 0]}]
"#;
    let b = parse_map("corridor", text);
    let c = fleet(
        "c",
        2,
        SpawnSpec::Waypoints(vec!["park_a".into(), "park_b".into()]),
    );
    let s = scenario(vec![c], vec![go(0.5, "room", None), go(1.0, "room", None)]);
    let (events, _, fleets) = run(&b, &s, 300.0);
    assert_eq!(
        assignments(&events),
        [("go_to_place_0", "c_0"), ("go_to_place_1", "c_0")]
    );
    let done: Vec<&str> = events
        .iter()
        .filter(|e| e.event == "completed")
        .map(|e| e.task_id.as_str())
        .collect();
    assert_eq!(done, ["go_to_place_0", "go_to_place_1"]);
    // c_0's plan at the start and one per task: nothing planned again on the way (15
    // plans when it was moved for the second task every 5 s).
    assert_eq!(fleets.traffic_report().plans_taken, 3);
}

/// A corridor a-b-c-d with a parking spot off each end.
const CORRIDOR: &str = r#"
coordinate_system: cartesian_meters
name: corridor
levels:
  L1:
    elevation: 0
    vertices:
      - [0, 0, 0, a]
      - [10, 0, 0, b]
      - [20, 0, 0, c]
      - [40, 0, 0, d]
      - [0, 3, 0, park_a, {is_parking_spot: [4, true]}]
      - [40, 3, 0, park_d, {is_parking_spot: [4, true]}]
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [1, 2, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [0, 4, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [3, 5, {bidirectional: [4, true], graph_idx: [2, 0]}]
"#;

/// A task goes to the robot that gets there first, busy ones included: c_1's loop ends at
/// b, 13 m from where it starts, while c_0 stands free 33 m from b. The go-to-place to b
/// waits for c_1 (RMF queues it after c_1's loop) rather than sending c_0 the length of
/// the corridor; a task where the free robot is first still goes to it.
#[test]
fn a_task_waits_for_a_busy_robot_that_gets_there_first() {
    let b = parse_map("corridor", CORRIDOR);
    let c = fleet(
        "c",
        2,
        SpawnSpec::Waypoints(vec!["park_d".into(), "park_a".into()]),
    );
    let s = scenario(
        vec![c],
        vec![
            one_loop(0.5, "a", "b"),
            go(1.0, "b", None),
            go(1.5, "d", None),
        ],
    );
    let (events, _, _) = run(&b, &s, 200.0);
    assert_eq!(
        assignments(&events),
        [
            ("loop_0", "c_1"),
            ("go_to_place_1", "c_0"),
            ("go_to_place_0", "c_1")
        ]
    );
    let at = |id: &str, what: &str| {
        events
            .iter()
            .find(|e| e.task_id == id && e.event == what)
            .map(|e| e.time.as_secs())
            .expect("event")
    };
    // Taken the moment c_1's loop is done, where c_1 stands (it did not set off to park
    // first): done a step later.
    assert_eq!(at("go_to_place_0", "assigned"), at("loop_0", "completed"));
    let took = at("go_to_place_0", "completed") - at("go_to_place_0", "assigned");
    assert!(took < 0.05, "{took}");
}

/// Busy robots bid across fleets: c_0's loop ends at b while the only robot of another
/// fleet, e_0, stands free 33 m from b. The go-to-place to b waits for c_0, although its
/// fleet has no robot free (only fleets with a free robot bid before, and two fleets on a
/// corridor between two rooms then completed half what one robot alone did).
#[test]
fn a_busy_robot_of_another_fleet_that_gets_there_first_is_waited_for() {
    let b = parse_map("corridor", CORRIDOR);
    let c = fleet("c", 1, SpawnSpec::Waypoints(vec!["park_a".into()]));
    let e = fleet("e", 1, SpawnSpec::Waypoints(vec!["park_d".into()]));
    let s = scenario(
        vec![c, e],
        vec![one_loop(0.5, "a", "b"), go(1.0, "b", None)],
    );
    let (events, _, _) = run(&b, &s, 200.0);
    assert_eq!(
        assignments(&events),
        [("loop_0", "c_0"), ("go_to_place_0", "c_0")]
    );
}

/// Two rooms, `a` and `b`, joined by a main way through `m` and a second, longer one
/// through `p`, `q` and `r`; `c` and `d` are corners of triangles of lanes (out of the way:
/// the ways around them are shorter than through them); `q`, a parking spot too, is the
/// middle of the second way (around it from `p` to `r` is 36 m against 20 m through it).
const TWO_WAYS: &str = r#"
coordinate_system: cartesian_meters
name: two_ways
levels:
  L1:
    elevation: 0
    vertices:
      - [0, 0, 0, a]
      - [10, 0, 0, m]
      - [20, 0, 0, b]
      - [0, -8, 0, p]
      - [10, -8, 0, q, {is_parking_spot: [4, true]}]
      - [20, -8, 0, r]
      - [4, 4, 0, c, {is_parking_spot: [4, true]}]
      - [16, 4, 0, d, {is_parking_spot: [4, true]}]
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [1, 2, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [0, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [3, 4, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [4, 5, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [5, 2, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [0, 6, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [6, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 7, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [7, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
"#;

/// A robot left idle while tasks wait, on the second way between two rooms, goes to a
/// parking vertex out of the way; with no task waiting it stays where it is.
#[test]
fn an_idle_robot_in_the_way_while_tasks_wait_goes_out_of_the_way() {
    let b = parse_map("two_ways", TWO_WAYS);
    let c = fleet("c", 2, SpawnSpec::Waypoints(vec!["c".into(), "q".into()]));
    // Tasks for c_0 only: c_1 is free while they wait.
    let tasks: Vec<TaskSpec> = (0..6)
        .map(|k| TaskSpec {
            robot: Some("c_0".into()),
            ..one_loop(k as f64, "a", "b")
        })
        .collect();
    let s = scenario(vec![c.clone()], tasks);
    let placement = Fleets::place(&b, &s).expect("placement");
    let mut fleets = Fleets::new(&b, &s, &placement).expect("fleets");
    let v = |f: &Fleets, n: &str| f.floor.nav.find(f.floor.fleets[0].slot, n).expect(n);
    let (q, corners) = (v(&fleets, "q"), [v(&fleets, "c"), v(&fleets, "d")]);
    let slot = fleets.floor.fleets[0].slot;
    assert_eq!(
        fleets.floor.traffic.parks(slot)[q],
        crate::traffic::parks::PARK
    );
    // q is in the way, with both corners nearby; the corners are out of the way.
    let mut out = fleets.floor.ways_out[slot][q].clone();
    out.sort_unstable();
    assert_eq!(out, corners);
    assert!(corners
        .iter()
        .all(|&x| fleets.floor.ways_out[slot][x].is_empty()));
    assert_eq!(fleets.floor.robots[1].at, q);
    let mut mock = Mock::new(&b, &placement);
    let events = settle(&mut fleets, &mut mock, &s, 60.0);
    let assigned: Vec<&str> = events
        .iter()
        .filter(|e| e.event == "assigned")
        .map(|e| e.robot.as_str())
        .collect();
    assert!(assigned.iter().all(|&r| r == "c_0"), "{assigned:?}");
    // Left q within a few rounds of `RETREAT_AFTER`, for a corner (d: c_0 parks on c).
    let end = fleets.floor.traffic.sched.end_vertex(1);
    assert!(corners.contains(&end), "c_1 ends at {end}, q is {q}");
    assert_eq!(fleets.floor.robots[1].retreat, Some(end));

    // The same tasks requested only at 300 s: nothing waits for the first minute, and
    // c_1 stays on q.
    let later = s
        .tasks
        .iter()
        .map(|t| TaskSpec {
            at: t.at + 300.0,
            ..t.clone()
        })
        .collect();
    let s = scenario(vec![c], later);
    let placement = Fleets::place(&b, &s).expect("placement");
    let mut fleets = Fleets::new(&b, &s, &placement).expect("fleets");
    assert_eq!(
        fleets.floor.traffic.parks(slot)[q],
        crate::traffic::parks::PARK
    );
    let mut mock = Mock::new(&b, &placement);
    settle(&mut fleets, &mut mock, &s, 60.0);
    assert_eq!(fleets.floor.traffic.sched.end_vertex(1), q);
    assert_eq!(fleets.floor.robots[1].retreat, None);
}
