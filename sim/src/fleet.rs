//! The fleet layer: what a minimal RMF fleet adapter does (task assignment, routes on the
//! fleet's nav graph, traffic reservations, doors, lifts, workcells, charging), talking to
//! the world only through messages.
//!
//! Event driven: `update` returns at once unless a message arrived or a timer expired.
//!
//! A robot follows its route in PathRequests of the lanes it has reserved (see traffic.rs):
//! a corridor is reserved whole up to the next place where robots can pass (`segment`),
//! at least `LOOKAHEAD` plain lanes ahead; entering a lift reserves the ride and the lane
//! out at the destination. A lane through a controlled door, into a lift cabin, or a lift
//! ride is driven alone, after the door is open (DoorState OPEN and our heartbeat session)
//! or the lift is at the floor with its doors open in our session. Progress is read from
//! RobotState (`path` = waypoints not yet reached). Waiting robots are watched once a
//! second: idle robots in the way move aside (rows of them one after the other), wait-for
//! cycles are broken by backing one robot off (`resolve_deadlock`) or by a detour, a robot
//! whose wait chain has not moved for `STUCK_AFTER` is reported and looks for detours, and
//! after `STUCK_FAIL` its task fails. Empty dispensers are asked again (without limit while
//! their item is on its way back); a delivery that fails while carrying its item still takes
//! it to the ingestor.

use crate::graph::{EdgeKind, Nav, Regions};
use crate::msgs::{
    door_mode, lift_request, lift_state, robot_mode, workcell_result, DoorMode, DoorRequest,
    FleetState, ItemType, LiftRequest, Location, Msg, PathRequest, Published, RobotState,
    TaskEvent, Time, Topic, WorkcellRequest,
};
use crate::scenario::{Scenario, SpawnSpec, TaskCategory, TaskKind};
use crate::traffic::{find_cycle, Clearance, Conflicts, Res, Reservations};
use crate::world::{RobotSpawn, WorkcellSpawn};
use mapc_ir::{Building, Diagnostic, Span};
use std::collections::{BTreeMap, VecDeque};

/// Diagnostic codes of scenario/map mismatches.
pub mod codes {
    /// A named waypoint does not exist on the fleet's graph (or in the map for workcells).
    pub const UNKNOWN_WAYPOINT: &str = "S0201";
    /// Fewer spawn points than robots.
    pub const NOT_ENOUGH_SPAWNS: &str = "S0202";
    /// A fleet's graph has no lanes.
    pub const EMPTY_GRAPH: &str = "S0203";
    /// Two robots would start on the same waypoint or with the same name.
    pub const SPAWN_CLASH: &str = "S0204";
    /// A task names a fleet that does not exist or does not accept the task's category.
    pub const NO_FLEET: &str = "S0205";
    /// A delivery has no dispenser/ingestor (neither given nor a waypoint param).
    pub const NO_WORKCELL: &str = "S0206";
    /// A task waypoint lies inside a lift cabin.
    pub const IN_LIFT: &str = "S0207";
}

/// Seconds between re-sent door, lift and workcell requests.
const RESEND: f64 = 1.0;
/// Waiting this long for a door, lift or workcell fails the task.
const EXTERNAL_TIMEOUT: f64 = 300.0;
/// A robot stalled this long in another stalled robot's way backs off for it (s).
const YIELD_AFTER: f64 = 60.0;
/// A robot at an empty dispenser asks again this often (s), this long (s).
const ITEM_RETRY: f64 = 5.0;
const ITEM_WAIT: f64 = 1200.0;
/// A robot waiting for traffic this long is reported stuck.
const STUCK_AFTER: f64 = 120.0;
/// A stalled robot looks for a detour this often.
const DETOUR_AFTER: f64 = 30.0;
/// A robot stalled this long (no detour, no back-off helped) fails its task: traffic
/// that never clears is reported rather than waited for until the end of the run.
const STUCK_FAIL: f64 = 1800.0;
/// A wait-for cycle older than this is broken by backing a robot off.
const DEADLOCK_AFTER: f64 = 3.0;
/// Back-offs towards one goal before its task fails.
const MAX_BACKOFFS: u32 = 10;
/// How long a robot that backed off out of a deadlock waits before going on (s).
const BACKOFF_WAIT: f64 = 5.0;
/// Edges of the other robots' routes a robot backing off must keep off.
const DEADLOCK_HORIZON: usize = 8;
/// Extra cost (s) of a yield or back-off spot that is not a parking spot, holding point
/// or charger.
const SPOT_PENALTY: f64 = 10.0;
/// Head start (s) in task assignment of an idle robot standing on one of the task's
/// waypoints.
const ON_TASK_BONUS: f64 = 180.0;
/// Farthest (s) an idle robot drives to park: a long drive crosses the others' ways.
const PARK_REACH: f64 = 120.0;
/// Most edges reserved at once through a corridor.
const SEGMENT_MAX: usize = 12;
/// Edges reserved ahead of a moving robot.
const LOOKAHEAD: usize = 3;

/// Where robots and workcells start, resolved from the scenario against the map.
pub struct Placement {
    pub robots: Vec<RobotSpawn>,
    pub workcells: Vec<WorkcellSpawn>,
}

#[derive(Debug, Clone)]
enum Step {
    GoTo(usize),
    Dispense(String),
    Ingest(String),
    Dwell(f64),
    Charge(f64),
}

/// Runtime of the step in progress.
#[derive(Debug, Clone, PartialEq)]
enum Cur {
    None,
    GoTo {
        goal: usize,
        planned: bool,
    },
    Workcell {
        guid: String,
        target: String,
        dispenser: bool,
        next_send: f64,
        deadline: f64,
        /// Requests made after a FAILED, and when the first one was made.
        tries: u32,
        since: f64,
    },
    Dwell {
        until: f64,
    },
    Charge {
        pct: f64,
        best: f64,
        best_t: f64,
    },
}

/// What a GoTo waits for before the next edge.
#[derive(Debug, Clone, PartialEq)]
enum Gate {
    None,
    Door {
        door: usize,
        next_send: f64,
        since: f64,
    },
    Lift {
        lift: usize,
        floor: String,
        next_send: f64,
        since: f64,
    },
}

struct Robot {
    name: String,
    fleet: usize,
    slot: usize,
    at: usize,
    state: Option<RobotState>,
    route: VecDeque<usize>,
    /// Leading edges of `route` that are reserved / sent in the current PathRequest.
    n_res: usize,
    n_sent: usize,
    path_id: String,
    path_seq: u64,
    gate: Gate,
    /// Door to close / lift session to end after the edge being driven.
    close_door: Option<usize>,
    end_lift: Option<usize>,
    steps: VecDeque<Step>,
    cur: Cur,
    task: Option<usize>,
    queue: VecDeque<usize>,
    wake: f64,
    dirty: bool,
    /// Waiting for reservations since, and on whom.
    wait_since: Option<f64>,
    blockers: Vec<usize>,
    stuck_reported: bool,
    /// Back-offs on the way to `backoff_goal` (a livelock guard).
    backoffs: u32,
    backoff_goal: usize,
    /// Since when nothing this robot waits for (directly or through others) moved.
    stall_since: f64,
    /// When it last looked for a detour.
    last_detour: f64,
    /// Last reported position that differed by more than 5 cm, and when.
    last_pos: (f64, f64),
    last_moved: f64,
    free_at: f64,
    end_vertex: usize,
    charger: Option<usize>,
    /// (drop-off vertex, ingestor) of the item the robot carries.
    carrying: Option<(usize, String)>,
    /// The dispenser of the item aboard, until it is ingested (also on a return trip).
    item_from: Option<String>,
    /// Driving to a back-off spot (a Dwell and the GoTo it backed off from follow).
    backing_off: bool,
    last_backoff: f64,
    /// When the current task started.
    task_started: f64,
    /// Its task just ended: once idle, it drives to a parking vertex (`Fleets::park`).
    park_pending: bool,
}

impl Robot {
    fn idle(&self) -> bool {
        self.task.is_none()
            && self.queue.is_empty()
            && self.steps.is_empty()
            && self.cur == Cur::None
    }
    fn battery(&self) -> f64 {
        self.state.as_ref().map_or(100.0, |s| s.battery_percent)
    }
}

struct FleetRt {
    name: String,
    slot: usize,
    speed: f64,
    recharge_threshold: f64,
    recharge_soc: f64,
    kinds: Vec<TaskCategory>,
    robots: Vec<usize>,
}

struct Task {
    id: String,
    category: TaskCategory,
    kind: TaskKind,
    fleet: Option<String>,
    ended: bool,
}

#[derive(Default, Clone)]
struct DoorView {
    mode: u32,
    sessions: Vec<String>,
}

#[derive(Default, Clone)]
struct LiftView {
    current_floor: String,
    door_state: u8,
    session_id: String,
}

pub struct Fleets {
    nav: Nav,
    conf: Conflicts,
    /// Per graph slot, per vertex: robots can wait or pass each other there (junctions,
    /// leaves, holding points, lift cabins); corridors are the other vertices.
    passing: Vec<Vec<bool>>,
    /// Dead-end regions with their capacities (admission control, `Fleets::admission`).
    regions: Regions,
    /// Per graph slot, per vertex: where an idle robot parks out of everybody's way
    /// (see `park_vertices`).
    park: Vec<Vec<bool>>,
    res: Reservations,
    fleets: Vec<FleetRt>,
    robots: Vec<Robot>,
    by_name: BTreeMap<String, usize>,
    tasks: Vec<Task>,
    /// (request time, source order, kind, fleet) of tasks not yet requested, sorted.
    upcoming: VecDeque<(f64, usize, TaskKind, Option<String>)>,
    doors: Vec<DoorView>,
    door_index: BTreeMap<String, usize>,
    lifts: Vec<LiftView>,
    lift_index: BTreeMap<String, usize>,
    results: BTreeMap<String, u8>,
    counters: BTreeMap<TaskCategory, usize>,
    chargers: BTreeMap<usize, usize>,
    next_wake: f64,
    next_fleet_state: f64,
    next_traffic: f64,
    clean_duration: f64,
    released: bool,
}

fn level_handle_eq(a: mapc_ir::Handle<mapc_ir::Level>, b: mapc_ir::Handle<mapc_ir::Level>) -> bool {
    a == b
}

impl Fleets {
    /// Resolves spawns and workcells (named waypoints must exist on the fleet's graph).
    pub fn place(building: &Building, scenario: &Scenario) -> Result<Placement, Vec<Diagnostic>> {
        let graphs: Vec<i64> = scenario.fleets.iter().map(|f| f.graph).collect();
        let nav = Nav::build(building, &graphs);
        let mut diags = Vec::new();
        let mut robots: Vec<RobotSpawn> = Vec::new();
        // (vertex, footprint) of robots placed so far.
        let mut taken: Vec<(usize, f64)> = Vec::new();
        for f in &scenario.fleets {
            let Some(slot) = nav.slot(f.graph).filter(|&s| !nav.members[s].is_empty()) else {
                diags.push(
                    Diagnostic::error(
                        codes::EMPTY_GRAPH,
                        f.span,
                        format!(
                            "fleet `{}` drives on graph {}, which has no lanes",
                            f.name, f.graph
                        ),
                    )
                    .with_help(format!(
                        "graphs with lanes in this map: {:?}",
                        building.graph_indices()
                    )),
                );
                continue;
            };
            let mut chosen: Vec<(usize, Option<String>)> = Vec::new();
            match &f.spawn {
                SpawnSpec::MapSpawnPoints => {
                    let spawns: Vec<usize> = nav.members[slot]
                        .iter()
                        .copied()
                        .filter(|&v| nav.vertices[v].roles.spawn_robot_type.is_some())
                        .collect();
                    let matching: Vec<usize> = spawns
                        .iter()
                        .copied()
                        .filter(|&v| {
                            nav.vertices[v]
                                .roles
                                .spawn_robot_type
                                .as_deref()
                                .is_some_and(|t| {
                                    t.rsplit('/')
                                        .next()
                                        .unwrap_or(t)
                                        .eq_ignore_ascii_case(&f.robot.model)
                                })
                        })
                        .collect();
                    let pool = if matching.is_empty() {
                        spawns
                    } else {
                        matching
                    };
                    for v in pool {
                        if chosen.len() == f.count {
                            break;
                        }
                        if taken.iter().any(|&(w, _)| w == v) {
                            continue;
                        }
                        chosen.push((v, nav.vertices[v].roles.spawn_robot_name.clone()));
                    }
                }
                SpawnSpec::Waypoints(names) => {
                    for name in names.iter().take(f.count) {
                        match nav.find(slot, name) {
                            Some(v)
                                if taken.iter().any(|&(w, _)| w == v)
                                    || chosen.iter().any(|c| c.0 == v) =>
                            {
                                diags.push(
                                    Diagnostic::error(
                                        codes::SPAWN_CLASH,
                                        f.span,
                                        format!("two robots would start on waypoint `{name}`"),
                                    )
                                    .with_help("name a different waypoint for each robot"),
                                );
                            }
                            Some(v) => chosen.push((v, None)),
                            None => diags.push(unknown_waypoint(&nav, slot, name, f.span, &f.name)),
                        }
                    }
                }
                SpawnSpec::Auto => {
                    let mut cands: Vec<usize> = nav.members[slot]
                        .iter()
                        .copied()
                        .filter(|&v| nav.vertices[v].lift.is_none())
                        .collect();
                    // Neighbours (either direction) of each vertex on this graph.
                    let mut nbrs: Vec<Vec<usize>> = vec![Vec::new(); nav.vertices.len()];
                    for e in nav.edges.iter().filter(|e| e.graph == slot) {
                        nbrs[e.from].push(e.to);
                        nbrs[e.to].push(e.from);
                    }
                    for n in &mut nbrs {
                        n.sort_unstable();
                        n.dedup();
                    }
                    // Chargers, parking spots and holding points first, then dead ends
                    // (off every through route), then the rest.
                    let class = |v: usize| {
                        let r = &nav.vertices[v].roles;
                        if r.is_charger {
                            0
                        } else if r.is_parking_spot {
                            1
                        } else if r.is_holding_point {
                            2
                        } else if nbrs[v].len() <= 1 {
                            3
                        } else {
                            4
                        }
                    };
                    cands.sort_by_key(|&v| (class(v), v));
                    // First pass: no robot next to another (each can drive off without the
                    // other moving); second pass: only far enough apart.
                    // Spread over the levels the graph reaches: the level with the fewest
                    // robots so far first, so that a multi-level graph does not crowd one
                    // floor.
                    for strict in [true, false] {
                        while chosen.len() < f.count {
                            let mine: Vec<(usize, f64)> =
                                chosen.iter().map(|c| (c.0, f.robot.footprint)).collect();
                            let ok = |v: usize| {
                                let p = nav.vertices[v].pos;
                                let clear = |&(w, fp): &(usize, f64)| {
                                    let vw = &nav.vertices[w];
                                    w != v
                                        && (!level_handle_eq(vw.level, nav.vertices[v].level)
                                            || vw.pos.minus(p).norm()
                                                >= fp + f.robot.footprint + 0.5)
                                        && !(strict && nbrs[v].binary_search(&w).is_ok())
                                };
                                taken.iter().all(clear) && mine.iter().all(clear)
                            };
                            let on_level = |v: usize| {
                                taken
                                    .iter()
                                    .map(|x| x.0)
                                    .chain(mine.iter().map(|x| x.0))
                                    .filter(|&w| nav.vertices[w].level == nav.vertices[v].level)
                                    .count()
                            };
                            let pick = cands
                                .iter()
                                .copied()
                                .filter(|&v| ok(v))
                                .min_by_key(|&v| (class(v), on_level(v), v));
                            match pick {
                                Some(v) => chosen.push((v, None)),
                                None => break,
                            }
                        }
                    }
                }
            }
            if chosen.len() < f.count
                && !matches!(f.spawn, SpawnSpec::Waypoints(ref n) if n.len() >= f.count && chosen.len() + diags.len() >= f.count)
            {
                let what = match f.spawn {
                    SpawnSpec::MapSpawnPoints => "free spawn waypoints (`spawn_robot_type`)",
                    SpawnSpec::Waypoints(_) => "spawn waypoints listed",
                    SpawnSpec::Auto => "free waypoints far enough apart",
                };
                diags.push(
                    Diagnostic::error(
                        codes::NOT_ENOUGH_SPAWNS,
                        f.span,
                        format!(
                            "fleet `{}` has {} robots but only {} {what}",
                            f.name,
                            f.count,
                            chosen.len()
                        ),
                    )
                    .with_help(match f.spawn {
                        SpawnSpec::Auto => "lower `count` or add parking spots to the graph",
                        _ => "lower `count`, list more waypoints, or use `spawn: auto`",
                    }),
                );
            }
            for (i, (v, name)) in chosen.into_iter().enumerate() {
                let nv = &nav.vertices[v];
                let name = name.unwrap_or_else(|| format!("{}_{i}", f.name));
                if robots.iter().any(|r| r.name == name) {
                    diags.push(Diagnostic::error(
                        codes::SPAWN_CLASH,
                        f.span,
                        format!("two robots are named `{name}`"),
                    ));
                }
                // Face along the first lane leaving the spawn point, as a parked robot would.
                let yaw = nav.out[slot][v].first().map_or(0.0, |&e| {
                    let d = nav.vertices[nav.edges[e].to].pos.minus(nv.pos);
                    d.y.atan2(d.x)
                });
                robots.push(RobotSpawn {
                    name,
                    fleet: f.name.clone(),
                    params: f.robot.clone(),
                    x: nv.pos.x,
                    y: nv.pos.y,
                    yaw,
                    level: nv.level,
                });
                taken.push((v, f.robot.footprint));
            }
        }
        let mut workcells = Vec::new();
        for w in &scenario.workcells {
            match building
                .vertices
                .iter()
                .find(|(_, v)| v.name == w.waypoint && !w.waypoint.is_empty())
            {
                Some((_, v)) => workcells.push(WorkcellSpawn {
                    name: w.name.clone(),
                    kind: w.kind,
                    x: v.pos.x,
                    y: v.pos.y,
                    level: v.level,
                }),
                None => diags.push(
                    Diagnostic::error(
                        codes::UNKNOWN_WAYPOINT,
                        w.span,
                        format!("workcell `{}`: no waypoint named `{}`", w.name, w.waypoint),
                    )
                    .with_help("use the name of a vertex of the map"),
                ),
            }
        }
        if diags.iter().any(Diagnostic::is_error) {
            return Err(diags);
        }
        Ok(Placement { robots, workcells })
    }

    pub fn new(
        building: &Building,
        scenario: &Scenario,
        placement: &Placement,
    ) -> Result<Fleets, Vec<Diagnostic>> {
        let graphs: Vec<i64> = scenario.fleets.iter().map(|f| f.graph).collect();
        let nav = Nav::build(building, &graphs);
        let zero = Clearance {
            footprint: 0.0,
            stop_distance: 0.0,
            stop_radius: 0.0,
        };
        let mut per_slot = vec![zero; nav.graphs.len()];
        let mut footprint: f64 = 0.0;
        for f in &scenario.fleets {
            footprint = footprint.max(f.robot.footprint);
            if let Some(c) = nav.slot(f.graph).and_then(|s| per_slot.get_mut(s)) {
                c.footprint = c.footprint.max(f.robot.footprint);
                c.stop_distance = c.stop_distance.max(f.robot.stop_distance);
                c.stop_radius = c.stop_radius.max(f.robot.stop_radius);
            }
        }
        let conf = Conflicts::build_per_slot(&nav, footprint, &per_slot);
        let mut diags = Vec::new();
        let mut fleets = Vec::new();
        let mut robots = Vec::new();
        let mut by_name = BTreeMap::new();
        for f in &scenario.fleets {
            let Some(slot) = nav.slot(f.graph) else {
                continue;
            };
            let mut rt = FleetRt {
                name: f.name.clone(),
                slot,
                speed: f.robot.nominal_drive_speed.max(0.05),
                recharge_threshold: f.recharge_threshold,
                recharge_soc: f.recharge_soc,
                kinds: f.task_kinds.clone(),
                robots: Vec::new(),
            };
            for spawn in placement.robots.iter().filter(|s| s.fleet == f.name) {
                let at = nav.members[slot].iter().copied().find(|&v| {
                    let nv = &nav.vertices[v];
                    nv.level == spawn.level && (nv.pos.x - spawn.x).hypot(nv.pos.y - spawn.y) < 1e-6
                });
                let Some(at) = at else {
                    diags.push(Diagnostic::error(
                        codes::UNKNOWN_WAYPOINT,
                        f.span,
                        format!(
                            "robot `{}` does not start on a waypoint of graph {}",
                            spawn.name, f.graph
                        ),
                    ));
                    continue;
                };
                let i = robots.len();
                by_name.insert(spawn.name.clone(), i);
                rt.robots.push(i);
                robots.push(Robot {
                    name: spawn.name.clone(),
                    fleet: fleets.len(),
                    slot,
                    at,
                    state: None,
                    route: VecDeque::new(),
                    n_res: 0,
                    n_sent: 0,
                    path_id: String::new(),
                    path_seq: 0,
                    gate: Gate::None,
                    close_door: None,
                    end_lift: None,
                    steps: VecDeque::new(),
                    cur: Cur::None,
                    task: None,
                    queue: VecDeque::new(),
                    wake: f64::INFINITY,
                    dirty: true,
                    wait_since: None,
                    blockers: Vec::new(),
                    stuck_reported: false,
                    backoffs: 0,
                    backoff_goal: usize::MAX,
                    stall_since: 0.0,
                    last_detour: f64::NEG_INFINITY,
                    last_pos: (spawn.x, spawn.y),
                    last_moved: 0.0,
                    free_at: 0.0,
                    end_vertex: at,
                    charger: None,
                    carrying: None,
                    item_from: None,
                    backing_off: false,
                    last_backoff: f64::NEG_INFINITY,
                    task_started: 0.0,
                    park_pending: false,
                });
            }
            fleets.push(rt);
        }
        let mut res = Reservations::new(conf.n_res, robots.len());
        for (i, r) in robots.iter().enumerate() {
            res.set_held(i, conf.vertex[r.at].clone());
        }

        // Tasks: validate against the fleets, then order by request time (stable).
        let mut upcoming = Vec::new();
        let check = |kind: &TaskKind,
                     fleet: &Option<String>,
                     span: Span,
                     diags: &mut Vec<Diagnostic>| {
            let cat = kind.category();
            let cands: Vec<&FleetRt> = fleets
                .iter()
                .filter(|f| fleet.as_ref().is_none_or(|n| *n == f.name))
                .filter(|f| f.kinds.is_empty() || f.kinds.contains(&cat))
                .collect();
            if cands.is_empty() {
                diags.push(
                    Diagnostic::error(
                        codes::NO_FLEET,
                        span,
                        format!(
                            "no fleet{} accepts {} tasks",
                            fleet
                                .as_ref()
                                .map(|n| format!(" named `{n}`"))
                                .unwrap_or_default(),
                            cat.as_str()
                        ),
                    )
                    .with_help("add the category to a fleet's task kinds, or name another fleet"),
                );
                return;
            }
            for name in waypoint_names(kind) {
                let found: Vec<usize> = cands
                    .iter()
                    .filter_map(|f| nav.find(f.slot, name))
                    .collect();
                if found.is_empty() {
                    diags.push(unknown_waypoint(
                        &nav,
                        cands[0].slot,
                        name,
                        span,
                        &cands[0].name,
                    ));
                } else if found.iter().any(|&v| nav.vertices[v].lift.is_some()) {
                    // A robot parked in a cabin would keep the lift's session forever.
                    diags.push(
                        Diagnostic::error(
                            codes::IN_LIFT,
                            span,
                            format!("waypoint `{name}` is inside a lift cabin"),
                        )
                        .with_help("use a waypoint in front of the lift"),
                    );
                }
            }
            if let TaskKind::Delivery {
                pickup,
                dropoff,
                dispenser,
                ingestor,
            } = kind
            {
                let role = |name: &str, f: &dyn Fn(&mapc_ir::WaypointRoles) -> Option<String>| {
                    cands
                        .iter()
                        .find_map(|c| nav.find(c.slot, name))
                        .and_then(|v| f(&nav.vertices[v].roles))
                };
                if dispenser.is_none() && role(pickup, &|r| r.pickup_dispenser.clone()).is_none() {
                    diags.push(
                        Diagnostic::error(
                            codes::NO_WORKCELL,
                            span,
                            format!("delivery from `{pickup}`: no dispenser named and the waypoint has no `pickup_dispenser`"),
                        )
                        .with_help("add `dispenser: <name>` to the task"),
                    );
                }
                if ingestor.is_none() && role(dropoff, &|r| r.dropoff_ingestor.clone()).is_none() {
                    diags.push(
                        Diagnostic::error(
                            codes::NO_WORKCELL,
                            span,
                            format!("delivery to `{dropoff}`: no ingestor named and the waypoint has no `dropoff_ingestor`"),
                        )
                        .with_help("add `ingestor: <name>` to the task"),
                    );
                }
            }
        };
        for (i, t) in scenario.tasks.iter().enumerate() {
            check(&t.kind, &t.fleet, t.span, &mut diags);
            upcoming.push((t.at, i, t.kind.clone(), t.fleet.clone()));
        }
        let base = scenario.tasks.len();
        for (g, gen) in scenario.generators.iter().enumerate() {
            check(&gen.kind, &gen.fleet, gen.span, &mut diags);
            if !(gen.every.is_finite() && gen.start.is_finite()) || gen.every <= 0.0 {
                continue;
            }
            let end = gen.end.unwrap_or(scenario.duration).min(scenario.duration);
            let mut k = 0u64;
            loop {
                let at = gen.start + k as f64 * gen.every;
                if at > end || k > 1_000_000 {
                    break;
                }
                upcoming.push((at, base + g, gen.kind.clone(), gen.fleet.clone()));
                k += 1;
            }
        }
        if diags.iter().any(Diagnostic::is_error) {
            return Err(diags);
        }
        upcoming.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut door_index = BTreeMap::new();
        for (i, d) in nav.doors.iter().enumerate() {
            door_index.entry(d.name.clone()).or_insert(i);
        }
        let mut lift_index = BTreeMap::new();
        for (i, l) in nav.lifts.iter().enumerate() {
            lift_index.entry(l.name.clone()).or_insert(i);
        }
        let passing = (0..nav.graphs.len())
            .map(|slot| {
                let mut nbrs: Vec<Vec<usize>> = vec![Vec::new(); nav.vertices.len()];
                // Vertices touching a lane driven both ways: only there can two robots
                // meet head-on, so only there must a corridor be reserved whole. On
                // one-way corridors robots just follow each other.
                let mut two_way = vec![false; nav.vertices.len()];
                let directed: std::collections::BTreeSet<(usize, usize)> = nav
                    .edges
                    .iter()
                    .filter(|e| e.graph == slot && e.kind == EdgeKind::Lane)
                    .map(|e| (e.from, e.to))
                    .collect();
                for &(a, b) in &directed {
                    if directed.contains(&(b, a)) {
                        two_way[a] = true;
                        two_way[b] = true;
                    }
                }
                for e in nav.edges.iter().filter(|e| e.graph == slot) {
                    nbrs[e.from].push(e.to);
                    nbrs[e.to].push(e.from);
                }
                nbrs.iter_mut()
                    .enumerate()
                    .map(|(v, n)| {
                        n.sort_unstable();
                        n.dedup();
                        let x = &nav.vertices[v];
                        n.len() != 2 || !two_way[v] || x.roles.is_holding_point || x.lift.is_some()
                    })
                    .collect()
            })
            .collect();
        let park = park_vertices(&nav, &conf, scenario);
        // A robot that starts on a waypoint of a loop, delivery or cleaning parks first.
        for r in robots.iter_mut() {
            r.park_pending = scenario
                .tasks
                .iter()
                .map(|t| &t.kind)
                .chain(scenario.generators.iter().map(|g| &g.kind))
                .filter(|k| parks_after(k))
                .flat_map(|k| waypoint_names(k))
                .any(|name| nav.find(r.slot, name) == Some(r.at));
        }
        let regions = nav.regions();
        Ok(Fleets {
            park,
            passing,
            regions,
            doors: vec![DoorView::default(); nav.doors.len()],
            lifts: vec![LiftView::default(); nav.lifts.len()],
            nav,
            conf,
            res,
            fleets,
            robots,
            by_name,
            tasks: Vec::new(),
            upcoming: upcoming.into(),
            door_index,
            lift_index,
            results: BTreeMap::new(),
            counters: BTreeMap::new(),
            chargers: BTreeMap::new(),
            next_wake: 0.0,
            next_fleet_state: 0.0,
            next_traffic: f64::INFINITY,
            clean_duration: scenario.options.clean_duration,
            released: false,
        })
    }

    /// Reads what the world published in the last step (`inbox`) and appends the fleet's
    /// requests and task events to `out`.
    pub fn update(&mut self, t: f64, inbox: &[Published], out: &mut Vec<(Topic, Msg)>) {
        if inbox.is_empty() && t < self.next_wake {
            return;
        }
        let mut external = false;
        for p in inbox {
            match &p.msg {
                Msg::RobotState(s) => {
                    if let Some(&i) = self.by_name.get(&s.name) {
                        let r = &mut self.robots[i];
                        let (x, y) = (s.location.x, s.location.y);
                        if (x - r.last_pos.0).hypot(y - r.last_pos.1) > 0.05 {
                            r.last_pos = (x, y);
                            r.last_moved = t;
                        }
                        r.state = Some(s.clone());
                        r.dirty = true;
                    }
                }
                Msg::DoorState(s) => {
                    if let Some(&d) = self.door_index.get(&s.door_name) {
                        self.doors[d].mode = s.current_mode.value;
                        external = true;
                    }
                }
                Msg::DoorHeartbeat(h) => {
                    for v in self.doors.iter_mut() {
                        v.sessions.clear();
                    }
                    for ds in &h.all_sessions {
                        if let Some(&d) = self.door_index.get(&ds.door_name) {
                            self.doors[d].sessions =
                                ds.sessions.iter().map(|s| s.requester_id.clone()).collect();
                        }
                    }
                    external = true;
                }
                Msg::LiftState(s) => {
                    if let Some(&l) = self.lift_index.get(&s.lift_name) {
                        self.lifts[l] = LiftView {
                            current_floor: s.current_floor.clone(),
                            door_state: s.door_state,
                            session_id: s.session_id.clone(),
                        };
                        external = true;
                    }
                }
                Msg::WorkcellResult(res)
                    if matches!(p.topic, Topic::DispenserResults | Topic::IngestorResults)
                        && res.status != workcell_result::ACKNOWLEDGED =>
                {
                    self.results.insert(res.request_guid.clone(), res.status);
                    external = true;
                }
                _ => {}
            }
        }
        if external {
            for r in &mut self.robots {
                if r.gate != Gate::None || matches!(r.cur, Cur::Workcell { .. }) {
                    r.dirty = true;
                }
            }
        }
        // New tasks.
        while self.upcoming.front().is_some_and(|u| u.0 <= t) {
            if let Some((_, _, kind, fleet)) = self.upcoming.pop_front() {
                self.request_task(t, kind, fleet, out);
            }
        }
        // Robots with news or an expired timer; repeat while reservations were released
        // (a release can unblock robots that are waiting).
        for pass in 0..4 {
            self.released = false;
            for i in 0..self.robots.len() {
                let r = &self.robots[i];
                let due = r.dirty || r.wake <= t || (pass > 0 && r.wait_since.is_some());
                if due {
                    self.robots[i].dirty = false;
                    self.tick(i, t, out);
                }
            }
            if !self.released {
                break;
            }
        }
        if t >= self.next_traffic {
            self.traffic_check(t, out);
        }
        if t >= self.next_fleet_state {
            self.next_fleet_state = t + 1.0;
            for f in &self.fleets {
                let robots = f
                    .robots
                    .iter()
                    .filter_map(|&i| self.robots[i].state.clone())
                    .collect();
                out.push((
                    Topic::FleetStates,
                    Msg::FleetState(FleetState {
                        name: f.name.clone(),
                        robots,
                    }),
                ));
            }
        }
        let any_waiting = self.robots.iter().any(|r| r.wait_since.is_some());
        self.next_traffic = if any_waiting {
            self.next_traffic.min(t + 1.0).max(t + 1e-9)
        } else {
            f64::INFINITY
        };
        if self.next_traffic <= t {
            self.next_traffic = t + 1.0;
        }
        let mut next = self.next_fleet_state.min(self.next_traffic);
        if let Some(u) = self.upcoming.front() {
            next = next.min(u.0);
        }
        for r in &self.robots {
            next = next.min(r.wake);
        }
        self.next_wake = next;
    }

    /// True when every task has ended (completed or failed) and no generator is pending.
    pub fn all_done(&self, _t: f64) -> bool {
        self.upcoming.is_empty() && self.tasks.iter().all(|t| t.ended)
    }

    // ----- tasks -----

    fn event(
        &self,
        t: f64,
        task: usize,
        event: &str,
        robot: Option<usize>,
        detail: String,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let Some(tk) = self.tasks.get(task) else {
            return;
        };
        let (fleet, robot) = robot
            .and_then(|r| self.robots.get(r))
            .map(|r| (self.fleets[r.fleet].name.clone(), r.name.clone()))
            .unwrap_or_default();
        out.push((
            Topic::TaskEvents,
            Msg::TaskEvent(TaskEvent {
                time: Time::from_secs(t),
                task_id: tk.id.clone(),
                category: tk.category.as_str().to_string(),
                event: event.to_string(),
                fleet,
                robot,
                detail,
            }),
        ));
    }

    fn request_task(
        &mut self,
        t: f64,
        kind: TaskKind,
        fleet: Option<String>,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let category = kind.category();
        let n = self.counters.entry(category).or_insert(0);
        let id = format!("{}_{}", category.as_str(), *n);
        *n += 1;
        let ti = self.tasks.len();
        self.tasks.push(Task {
            id,
            category,
            kind,
            fleet,
            ended: false,
        });
        self.event(t, ti, "queued", None, String::new(), out);
        // Pick the robot that can start soonest: (ready time + travel to the first
        // waypoint, robot index).
        let mut best: Option<(f64, usize, f64)> = None;
        for (fi, f) in self.fleets.iter().enumerate() {
            let task = &self.tasks[ti];
            if task.fleet.as_ref().is_some_and(|n| *n != f.name)
                || !(f.kinds.is_empty() || f.kinds.contains(&category))
            {
                continue;
            }
            let Some(steps) = self.expand(fi, &task.kind) else {
                continue;
            };
            let Some(first) = steps.iter().find_map(|s| match s {
                Step::GoTo(v) => Some(*v),
                _ => None,
            }) else {
                continue;
            };
            let dur = self.estimate(f.slot, f.speed, first, &steps);
            for &ri in &f.robots {
                let r = &self.robots[ri];
                let (ready, from) = if r.idle() {
                    (t, r.at)
                } else {
                    (r.free_at.max(t), r.end_vertex)
                };
                let Some((travel, _)) = self.nav.plan(f.slot, from, first, f.speed) else {
                    continue;
                };
                // An idle robot standing on one of the task's waypoints would have to be
                // moved aside for it anyway: it takes the task unless another robot is much
                // sooner.
                let on_task = r.idle()
                    && steps
                        .iter()
                        .any(|s| matches!(s, Step::GoTo(v) if *v == r.at));
                let bonus = if on_task { ON_TASK_BONUS } else { 0.0 };
                let score = ready + travel - bonus;
                if best.is_none_or(|b| score < b.0) {
                    best = Some((score, ri, dur));
                }
            }
        }
        match best {
            None => {
                self.tasks[ti].ended = true;
                self.event(
                    t,
                    ti,
                    "failed",
                    None,
                    "no robot can reach the task".into(),
                    out,
                );
            }
            Some((score, ri, dur)) => {
                let end = self
                    .expand(self.robots[ri].fleet, &self.tasks[ti].kind)
                    .and_then(|s| {
                        s.iter().rev().find_map(|s| match s {
                            Step::GoTo(v) => Some(*v),
                            _ => None,
                        })
                    });
                let r = &mut self.robots[ri];
                r.free_at = score.max(t) + dur;
                if let Some(e) = end {
                    r.end_vertex = e;
                }
                r.queue.push_back(ti);
                r.dirty = true;
                self.event(t, ti, "assigned", Some(ri), String::new(), out);
            }
        }
    }

    /// Rough duration of `steps` after arriving at `first`.
    fn estimate(&self, slot: usize, speed: f64, first: usize, steps: &[Step]) -> f64 {
        let mut at = first;
        let mut d = 0.0;
        for s in steps {
            match s {
                Step::GoTo(v) => {
                    d += self.nav.plan(slot, at, *v, speed).map_or(0.0, |p| p.0);
                    at = *v;
                }
                Step::Dwell(x) => d += x,
                Step::Dispense(_) | Step::Ingest(_) => d += 5.0,
                Step::Charge(_) => {}
            }
        }
        d
    }

    /// The steps of a task for fleet `fi`, or None if its waypoints are not on the graph.
    fn expand(&self, fi: usize, kind: &TaskKind) -> Option<Vec<Step>> {
        let slot = self.fleets.get(fi)?.slot;
        let v = |n: &str| self.nav.find(slot, n);
        Some(match kind {
            TaskKind::Loop {
                start,
                finish,
                loops,
            } => {
                let (a, b) = (v(start)?, v(finish)?);
                let mut s = Vec::new();
                for _ in 0..(*loops).max(1) {
                    s.push(Step::GoTo(a));
                    s.push(Step::GoTo(b));
                }
                s
            }
            TaskKind::Delivery {
                pickup,
                dropoff,
                dispenser,
                ingestor,
            } => {
                let (a, b) = (v(pickup)?, v(dropoff)?);
                let d = dispenser
                    .clone()
                    .or_else(|| self.nav.vertices[a].roles.pickup_dispenser.clone())?;
                let i = ingestor
                    .clone()
                    .or_else(|| self.nav.vertices[b].roles.dropoff_ingestor.clone())?;
                vec![
                    Step::GoTo(a),
                    Step::Dispense(d),
                    Step::GoTo(b),
                    Step::Ingest(i),
                ]
            }
            TaskKind::Clean { zone } => {
                let z = v(zone)?;
                // A docking lane leaving the zone: drive it and come back; else clean in place.
                let dock = self.nav.out[slot][z]
                    .iter()
                    .map(|&e| self.nav.edges[e].to)
                    .find(|&w| {
                        self.nav.vertices[w].roles.dock_name.is_some()
                            && self.nav.vertices[w].lift.is_none()
                    });
                match dock {
                    Some(d) => vec![Step::GoTo(z), Step::GoTo(d), Step::GoTo(z)],
                    None => vec![Step::GoTo(z), Step::Dwell(self.clean_duration)],
                }
            }
            TaskKind::GoToPlace { place } => vec![Step::GoTo(v(place)?)],
        })
    }

    fn end_task(
        &mut self,
        i: usize,
        t: f64,
        ok: bool,
        detail: String,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let Some(ti) = self.robots[i].task.take() else {
            return;
        };
        // Like RMF's `finishing_request: park`, but a robot sent to a place stays there.
        self.robots[i].park_pending = self.tasks.get(ti).is_some_and(|tk| parks_after(&tk.kind));
        if let Some(tk) = self.tasks.get_mut(ti) {
            tk.ended = true;
        }
        self.event(
            t,
            ti,
            if ok { "completed" } else { "failed" },
            Some(i),
            detail,
            out,
        );
        let r = &mut self.robots[i];
        let ingesting = matches!(
            r.cur,
            Cur::Workcell {
                dispenser: false,
                ..
            }
        );
        r.steps.clear();
        r.cur = Cur::None;
        if !ok {
            self.abandon_route(i, t, out);
            // A failed delivery still takes the item it carries to the ingestor, so that
            // its dispenser gets it back (else the dispenser stays empty for good).
            let r = &mut self.robots[i];
            match r.carrying.take() {
                Some((v, ing)) if !ingesting => {
                    r.steps.push_back(Step::GoTo(v));
                    r.steps.push_back(Step::Ingest(ing));
                    r.dirty = true;
                }
                _ => {}
            }
        }
    }

    /// Drops the planned route (the robot stays where it is once the edges it is already
    /// driving are done) and gives back any door/lift it had asked for.
    fn abandon_route(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let r = &mut self.robots[i];
        let keep = r.n_sent;
        r.route.truncate(keep);
        r.n_res = keep;
        r.wait_since = None;
        r.blockers.clear();
        match std::mem::replace(&mut r.gate, Gate::None) {
            Gate::Door { door, .. } => self.door_request(i, door, false, t, out),
            Gate::Lift { lift, .. } if self.nav.vertices[self.robots[i].at].lift.is_none() => {
                self.lift_request(i, lift, None, t, out)
            }
            _ => {}
        }
        self.rehold(i);
    }

    // ----- per-robot state machine -----

    fn tick(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        self.robots[i].wake = f64::INFINITY;
        self.observe_progress(i, t, out);
        // Bounded: each pass either finishes a step or returns.
        for _ in 0..64 {
            let cur = self.robots[i].cur.clone();
            let done = match cur {
                Cur::None => {
                    if !self.next_step(i, t, out) {
                        return;
                    }
                    continue;
                }
                Cur::GoTo { goal, planned } => match self.drive(i, goal, planned, t, out) {
                    Some(true) => {
                        if goal == self.robots[i].backoff_goal {
                            self.robots[i].backoffs = 0;
                        }
                        true
                    }
                    Some(false) => return,
                    None => {
                        self.end_task(i, t, false, "no route".into(), out);
                        continue;
                    }
                },
                Cur::Workcell {
                    guid,
                    target,
                    dispenser,
                    next_send,
                    deadline,
                    tries,
                    since,
                } => match self.results.get(&guid).copied() {
                    Some(workcell_result::SUCCESS) => {
                        let r = &mut self.robots[i];
                        if dispenser {
                            // Carrying the item now: where it is to go, in case the task
                            // fails before it gets there.
                            let to = r.steps.iter().find_map(|s| match s {
                                Step::GoTo(v) => Some(*v),
                                _ => None,
                            });
                            let ing = r.steps.iter().find_map(|s| match s {
                                Step::Ingest(x) => Some(x.clone()),
                                _ => None,
                            });
                            r.carrying = to.zip(ing);
                            r.item_from = Some(target.clone());
                        } else {
                            r.carrying = None;
                            r.item_from = None;
                        }
                        true
                    }
                    // An empty dispenser: its item is still out with another delivery
                    // (it comes back once ingested). Ask again for a while.
                    Some(_)
                        if dispenser && (t - since < ITEM_WAIT || self.item_coming(&target)) =>
                    {
                        let base = guid.split("_retry").next().unwrap_or(&guid).to_string();
                        self.robots[i].cur = Cur::Workcell {
                            guid: format!("{base}_retry{}", tries + 1),
                            target,
                            dispenser,
                            next_send: t + ITEM_RETRY,
                            deadline: t + ITEM_RETRY + EXTERNAL_TIMEOUT,
                            tries: tries + 1,
                            since,
                        };
                        let r = &mut self.robots[i];
                        r.wake = r.wake.min(t + ITEM_RETRY);
                        return;
                    }
                    Some(_) => {
                        self.end_task(i, t, false, format!("{target} failed"), out);
                        continue;
                    }
                    None if t >= deadline => {
                        self.end_task(i, t, false, format!("{target} did not answer"), out);
                        continue;
                    }
                    None => {
                        if t >= next_send {
                            self.workcell_request(i, &guid, &target, dispenser, t, out);
                            if let Cur::Workcell { next_send, .. } = &mut self.robots[i].cur {
                                *next_send = t + 2.0 * RESEND;
                            }
                        }
                        let r = &mut self.robots[i];
                        r.wake = r.wake.min(t + 2.0 * RESEND);
                        return;
                    }
                },
                Cur::Dwell { until } => {
                    if t >= until {
                        true
                    } else {
                        self.robots[i].wake = until;
                        return;
                    }
                }
                Cur::Charge { pct, best, best_t } => {
                    let b = self.robots[i].battery();
                    if b >= pct {
                        true
                    } else if b > best {
                        self.robots[i].cur = Cur::Charge {
                            pct,
                            best: b,
                            best_t: t,
                        };
                        self.robots[i].wake = t + 10.0;
                        return;
                    } else if t - best_t > 900.0 {
                        // Not charging at all (charging disabled in the world?): give up.
                        true
                    } else {
                        self.robots[i].wake = t + 10.0;
                        return;
                    }
                }
            };
            if done {
                if matches!(self.robots[i].cur, Cur::Charge { .. }) {
                    let r = &mut self.robots[i];
                    if let Some(c) = r.charger.take() {
                        self.chargers.remove(&c);
                    }
                }
                self.robots[i].cur = Cur::None;
            }
        }
    }

    /// Starts the next step (or task). False when there is nothing to do.
    fn next_step(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) -> bool {
        if let Some(step) = self.robots[i].steps.pop_front() {
            // Requests outside a task (an item taken back) get their own ids.
            let task_id = self.robots[i]
                .task
                .and_then(|ti| self.tasks.get(ti))
                .map_or_else(
                    || format!("{}_return{}", self.robots[i].name, self.robots[i].path_seq),
                    |tk| tk.id.clone(),
                );
            let r = &mut self.robots[i];
            let workcell = |target: String, dispenser: bool| Cur::Workcell {
                guid: format!("{task_id}_{}", if dispenser { "pickup" } else { "dropoff" }),
                target,
                dispenser,
                next_send: t,
                deadline: t + EXTERNAL_TIMEOUT,
                tries: 0,
                since: t,
            };
            if matches!(step, Step::Dwell(_)) {
                r.backing_off = false;
            }
            r.cur = match step {
                Step::GoTo(goal) => Cur::GoTo {
                    goal,
                    planned: false,
                },
                Step::Dwell(d) => Cur::Dwell { until: t + d },
                Step::Charge(pct) => Cur::Charge {
                    pct,
                    best: r.battery(),
                    best_t: t,
                },
                Step::Dispense(target) => workcell(target, true),
                Step::Ingest(target) => workcell(target, false),
            };
            return true;
        }
        if self.robots[i].task.is_some() {
            self.end_task(i, t, true, String::new(), out);
        }
        // Charging comes before the next task when the battery is low.
        if self.robots[i].charger.is_none() && self.maybe_charge(i) {
            // The charger is where it stays afterwards.
            self.robots[i].park_pending = false;
            return true;
        }
        let Some(ti) = self.robots[i].queue.pop_front() else {
            // Once after a task: park off everybody's way rather than where the task ended
            // (task waypoints and corridors are what the next tasks need).
            if std::mem::take(&mut self.robots[i].park_pending) {
                if let Some((v, dt)) = self.park_spot(i) {
                    let r = &mut self.robots[i];
                    r.steps.push_back(Step::GoTo(v));
                    r.free_at = t + dt;
                    r.end_vertex = v;
                    return true;
                }
            }
            let r = &mut self.robots[i];
            r.free_at = t;
            r.end_vertex = r.at;
            return false;
        };
        let fi = self.robots[i].fleet;
        match self.expand(fi, &self.tasks[ti].kind.clone()) {
            Some(steps) => {
                let r = &mut self.robots[i];
                r.task = Some(ti);
                r.task_started = t;
                r.steps = steps.into();
                self.event(t, ti, "started", Some(i), String::new(), out);
            }
            None => {
                self.tasks[ti].ended = true;
                self.event(
                    t,
                    ti,
                    "failed",
                    Some(i),
                    "waypoints not on the fleet's graph".into(),
                    out,
                );
            }
        }
        true
    }

    fn maybe_charge(&mut self, i: usize) -> bool {
        let r = &self.robots[i];
        let f = &self.fleets[r.fleet];
        if r.state.is_none() || r.battery() >= f.recharge_threshold * 100.0 {
            return false;
        }
        let times = self.nav.times_from(f.slot, r.at, f.speed);
        let best = self.nav.members[f.slot]
            .iter()
            .copied()
            .filter(|&v| {
                self.nav.vertices[v].roles.is_charger && self.nav.vertices[v].lift.is_none()
            })
            .filter(|v| self.chargers.get(v).is_none_or(|&o| o == i))
            .filter(|&v| times[v].is_finite())
            .min_by(|&a, &b| times[a].total_cmp(&times[b]).then(a.cmp(&b)));
        let Some(c) = best else {
            return false;
        };
        let pct = f.recharge_soc * 100.0;
        self.chargers.insert(c, i);
        let r = &mut self.robots[i];
        r.charger = Some(c);
        r.steps.push_back(Step::GoTo(c));
        r.steps.push_back(Step::Charge(pct));
        true
    }

    fn workcell_request(
        &self,
        i: usize,
        guid: &str,
        target: &str,
        dispenser: bool,
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let r = &self.robots[i];
        let msg = Msg::WorkcellRequest(WorkcellRequest {
            time: Time::from_secs(t),
            request_guid: guid.to_string(),
            target_guid: target.to_string(),
            transporter_type: self.fleets[r.fleet].name.clone(),
            items: vec![ItemType {
                type_guid: "item".into(),
                quantity: 1,
                compartment_name: String::new(),
            }],
        });
        let topic = if dispenser {
            Topic::DispenserRequests
        } else {
            Topic::IngestorRequests
        };
        out.push((topic, msg));
    }

    /// Whether a robot still on its way (a delivery or the return trip of a failed one)
    /// carries `dispenser`'s item: it will come back, so waiting for it is not in vain.
    fn item_coming(&self, dispenser: &str) -> bool {
        self.robots.iter().any(|x| {
            x.item_from.as_deref() == Some(dispenser)
                && !(matches!(x.cur, Cur::None) && x.steps.is_empty())
        })
    }

    /// Reads the latest RobotState of the current PathRequest: pops the edges reached.
    fn observe_progress(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let r = &self.robots[i];
        if r.n_sent == 0 {
            return;
        }
        let Some(s) = &r.state else { return };
        if s.task_id != r.path_id {
            return;
        }
        if s.mode.mode == robot_mode::ADAPTER_ERROR {
            // The robot was too far from the path start: send it again from where it is.
            self.send_path(i, t, out);
            return;
        }
        let reached = r.n_sent.saturating_sub(s.path.len());
        for _ in 0..reached {
            self.reach_next(i, t, out);
        }
    }

    fn reach_next(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let r = &mut self.robots[i];
        let Some(e) = r.route.pop_front() else { return };
        r.n_sent = r.n_sent.saturating_sub(1);
        r.n_res = r.n_res.saturating_sub(1);
        r.at = self.nav.edges[e].to;
        r.stuck_reported = false;
        if let Some(d) = r.close_door.take() {
            self.door_request(i, d, false, t, out);
        }
        let r = &mut self.robots[i];
        if let Some(l) = r.end_lift {
            if self.nav.vertices[r.at].lift != Some(l) {
                r.end_lift = None;
                self.lift_request(i, l, None, t, out);
            }
        }
        self.rehold(i);
    }

    /// Holds the standing set of the current vertex plus the sets of reserved edges.
    fn rehold(&mut self, i: usize) {
        let r = &self.robots[i];
        let mut set: Vec<Res> = self.conf.vertex[r.at].clone();
        for &e in r.route.iter().take(r.n_res) {
            set.extend_from_slice(&self.conf.edge[e]);
        }
        let before = self.res.held(i).len();
        set.sort_unstable();
        set.dedup();
        if set.len() < before || set.as_slice() != self.res.held(i) {
            self.released = true;
        }
        self.res.set_held(i, set);
    }

    /// Tries to reserve the edges `route[n_res..]` up to the next place where robots can
    /// pass each other (see [`Fleets::segment`]), all or nothing. On failure records the
    /// blockers.
    fn try_reserve(&mut self, i: usize, t: f64) -> bool {
        let r = &self.robots[i];
        let k = self.segment(i, r.n_res);
        if k == 0 {
            return false;
        }
        // What the robot's standing set already shares (robots spawned closer than their
        // clearance) must not keep it from driving away.
        let standing = &self.conf.vertex[r.at];
        let mut set: Vec<Res> = Vec::new();
        for &e in r.route.iter().skip(r.n_res).take(k) {
            set.extend(
                self.conf.edge[e]
                    .iter()
                    .copied()
                    .filter(|x| standing.binary_search(x).is_err()),
            );
        }
        set.sort_unstable();
        set.dedup();
        let full = self.admission(i, k);
        if full.is_empty() && self.res.is_free_for(i, &set) {
            let r = &mut self.robots[i];
            r.n_res += k;
            r.wait_since = None;
            r.blockers.clear();
            self.rehold(i);
            true
        } else {
            let mut blockers = self.res.blockers(i, &set);
            blockers.extend(full);
            blockers.sort_unstable();
            blockers.dedup();
            let r = &mut self.robots[i];
            if r.wait_since.is_none() {
                r.wait_since = Some(t);
                r.stall_since = t;
                r.stuck_reported = false;
            }
            r.blockers = blockers;
            false
        }
    }

    /// Admission control: the robots that keep robot `i` out of a lift lobby (see
    /// [`Regions`]) that the next `k` unreserved edges of its route enter, or that the edge
    /// after them enters (so that it waits before the region's entrance, not on it). Empty
    /// when it may go on. A region admits `capacity` robots; robots inside it or with
    /// reserved edges into it count, idle ones do not (they are moved aside as usual).
    /// Robots arriving by lift enter without admission: they must get out of the cabin.
    fn admission(&self, i: usize, k: usize) -> Vec<usize> {
        let r = &self.robots[i];
        let mut full = Vec::new();
        for &e in r.route.iter().skip(r.n_res).take(k + 1) {
            let Some(g) = self.regions.entry.get(e).copied().flatten() else {
                continue;
            };
            if self.regions.contains(g, r.at) {
                continue;
            }
            let inside: Vec<usize> = self
                .robots
                .iter()
                .enumerate()
                .filter(|&(o, x)| {
                    o != i
                        && !x.idle()
                        && (self.regions.contains(g, x.at)
                            || x.route
                                .iter()
                                .take(x.n_res + 1)
                                .any(|&f| self.regions.contains(g, self.nav.edges[f].to)))
                })
                .map(|(o, _)| o)
                .collect();
            if inside.len() >= self.regions.capacity.get(g).copied().unwrap_or(1) {
                full.extend(inside);
            }
        }
        full
    }

    /// How many edges from `route[from]` on robot `i` must reserve at once: through a
    /// corridor (vertices with two neighbours) to the next junction, leaf, holding point,
    /// or the end of the route, so that two robots never meet head-on inside it. Only
    /// plain lanes are chained (doors and lifts are driven one edge at a time); at most
    /// `SEGMENT_MAX` edges.
    fn segment(&self, i: usize, from: usize) -> usize {
        let r = &self.robots[i];
        // Into a lift: the lane in, the ride and the lane out at the destination, so that
        // the robot never rides to a floor where somebody waits on the cabin's doorstep.
        if let Some(&first) = r.route.get(from) {
            let e = &self.nav.edges[first];
            let into_cabin = e.kind == EdgeKind::Lane
                && self.nav.vertices[e.to].lift.is_some()
                && self.nav.vertices[e.from].lift.is_none();
            if into_cabin {
                let mut k = 1;
                while let Some(&n) = r.route.get(from + k) {
                    k += 1;
                    if self.nav.edges[n].kind == EdgeKind::Lane {
                        break;
                    }
                }
                return k;
            }
        }
        let mut k = 0;
        for &e in r.route.iter().skip(from) {
            k += 1;
            if k >= SEGMENT_MAX || !self.is_plain(e) {
                break;
            }
            let v = self.nav.edges[e].to;
            if self.passing[r.slot].get(v).copied().unwrap_or(true) {
                break;
            }
            // The next edge must be plain too, else stop before it.
            match r.route.get(from + k) {
                Some(&n) if self.is_plain(n) => {}
                _ => break,
            }
        }
        k
    }

    fn is_plain(&self, e: usize) -> bool {
        let edge = &self.nav.edges[e];
        edge.kind == EdgeKind::Lane
            && !edge.door.is_some_and(|d| self.nav.doors[d].controlled)
            && self.nav.vertices[edge.from].lift.is_none()
            && self.nav.vertices[edge.to].lift.is_none()
    }

    /// Advances a GoTo. Some(true) arrived, Some(false) in progress, None no route.
    fn drive(
        &mut self,
        i: usize,
        goal: usize,
        planned: bool,
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) -> Option<bool> {
        if !planned {
            let r = &self.robots[i];
            if r.n_sent > 0 {
                return Some(false);
            }
            let speed = self.fleets[r.fleet].speed;
            // Around robots parked on the graph when there is a way, else through them
            // (they will be asked to move aside).
            let mut parked: Vec<Res> = Vec::new();
            for (o, x) in self.robots.iter().enumerate() {
                if o != i && x.idle() && x.n_sent == 0 {
                    parked.extend_from_slice(self.res.held(o));
                }
            }
            parked.sort_unstable();
            parked.dedup();
            let clear = |e: usize| {
                !self.conf.edge[e]
                    .iter()
                    .any(|x| parked.binary_search(x).is_ok())
            };
            let (_, edges) = if parked.is_empty() {
                None
            } else {
                self.nav.plan_with(r.slot, r.at, goal, speed, &clear)
            }
            .or_else(|| self.nav.plan(r.slot, r.at, goal, speed))?;
            let r = &mut self.robots[i];
            // Keep edges already reserved (they are a prefix only if the plan agrees).
            r.route = edges.into();
            r.n_res = 0;
            r.cur = Cur::GoTo {
                goal,
                planned: true,
            };
            self.rehold(i);
        }
        let r = &self.robots[i];
        if r.n_sent > 0 {
            // Moving: reserve ahead and extend the path while lanes stay plain.
            let all_plain = r.route.iter().take(r.n_sent).all(|&e| self.is_plain(e));
            if all_plain && r.n_res == r.n_sent && r.n_res < LOOKAHEAD {
                if let Some(&next) = r.route.get(r.n_res) {
                    if self.is_plain(next) && self.try_reserve(i, t) {
                        self.send_path(i, t, out);
                    } else {
                        // Retry on the next RobotState; traffic waits only count at rest.
                        self.robots[i].wait_since = None;
                    }
                }
            }
            return Some(false);
        }
        if r.route.is_empty() {
            return Some(r.at == goal).filter(|&b| b).or_else(|| {
                // Arrived somewhere else (route dropped): plan again next tick.
                if let Cur::GoTo { planned, .. } = &mut self.robots[i].cur {
                    *planned = false;
                }
                self.robots[i].dirty = true;
                Some(false)
            });
        }
        let Some(&e) = r.route.front() else {
            return Some(false);
        };
        let edge = self.nav.edges[e].clone();
        // 1. Reserve the next edge (all-or-nothing).
        if r.n_res == 0 && !self.try_reserve(i, t) {
            return Some(false);
        }
        // 2. Gates: lift ride, lift call, door.
        if let EdgeKind::Lift(l) = edge.kind {
            let floor = self.nav.vertices[edge.to].level_name.clone();
            if !self.gate(
                i,
                Gate::Lift {
                    lift: l,
                    floor: floor.clone(),
                    next_send: t,
                    since: t,
                },
                t,
                out,
            ) {
                return Some(false);
            }
            // Arrived at the destination floor: the robot is now on the other cabin vertex.
            let r = &mut self.robots[i];
            r.gate = Gate::None;
            r.end_lift = Some(l);
            self.reach_next_lift(i);
            self.robots[i].dirty = true;
            return Some(false);
        }
        let to_lift = self.nav.vertices[edge.to].lift;
        let from_lift = self.nav.vertices[edge.from].lift;
        if let Some(l) = to_lift.filter(|&l| from_lift != Some(l)) {
            let floor = self.nav.vertices[edge.from].level_name.clone();
            if !self.gate(
                i,
                Gate::Lift {
                    lift: l,
                    floor,
                    next_send: t,
                    since: t,
                },
                t,
                out,
            ) {
                return Some(false);
            }
            self.robots[i].gate = Gate::None;
            self.robots[i].end_lift = Some(l);
        } else if let Some(d) = edge.door.filter(|&d| self.nav.doors[d].controlled) {
            if !self.gate(
                i,
                Gate::Door {
                    door: d,
                    next_send: t,
                    since: t,
                },
                t,
                out,
            ) {
                return Some(false);
            }
            self.robots[i].gate = Gate::None;
            self.robots[i].close_door = Some(d);
        } else {
            // Plain lanes: reserve a few more while they stay plain.
            while self.robots[i].n_res < LOOKAHEAD {
                let r = &self.robots[i];
                let Some(&next) = r.route.get(r.n_res) else {
                    break;
                };
                if !(self.is_plain(e) && self.is_plain(next) && self.try_reserve(i, t)) {
                    self.robots[i].wait_since = None;
                    self.robots[i].blockers.clear();
                    break;
                }
            }
        }
        self.send_path(i, t, out);
        Some(false)
    }

    fn reach_next_lift(&mut self, i: usize) {
        let r = &mut self.robots[i];
        if let Some(e) = r.route.pop_front() {
            r.n_res = r.n_res.saturating_sub(1);
            r.at = self.nav.edges[e].to;
        }
        self.rehold(i);
    }

    /// Waits on a door or lift. True when it is ready (open / at the floor with doors open).
    fn gate(&mut self, i: usize, want: Gate, t: f64, out: &mut Vec<(Topic, Msg)>) -> bool {
        let same = match (&self.robots[i].gate, &want) {
            (Gate::Door { door: a, .. }, Gate::Door { door: b, .. }) => a == b,
            (
                Gate::Lift {
                    lift: a, floor: fa, ..
                },
                Gate::Lift {
                    lift: b, floor: fb, ..
                },
            ) => a == b && fa == fb,
            _ => false,
        };
        if !same {
            self.robots[i].gate = want;
        }
        let name = self.robots[i].name.clone();
        match self.robots[i].gate.clone() {
            Gate::None => true,
            Gate::Door {
                door,
                next_send,
                since,
            } => {
                let v = &self.doors[door];
                if v.mode == door_mode::OPEN && v.sessions.contains(&name) {
                    return true;
                }
                if t - since > EXTERNAL_TIMEOUT {
                    self.end_task(
                        i,
                        t,
                        false,
                        format!("door {} did not open", self.nav.doors[door].name),
                        out,
                    );
                    return false;
                }
                if t >= next_send {
                    self.door_request(i, door, true, t, out);
                    if let Gate::Door { next_send, .. } = &mut self.robots[i].gate {
                        *next_send = t + RESEND;
                    }
                }
                self.robots[i].wake = t + RESEND;
                false
            }
            Gate::Lift {
                lift,
                floor,
                next_send,
                since,
            } => {
                let v = &self.lifts[lift];
                if v.current_floor == floor
                    && v.door_state == lift_state::DOOR_OPEN
                    && v.session_id == name
                {
                    return true;
                }
                if t - since > EXTERNAL_TIMEOUT {
                    self.end_task(
                        i,
                        t,
                        false,
                        format!("lift {} did not come", self.nav.lifts[lift].name),
                        out,
                    );
                    return false;
                }
                if t >= next_send {
                    self.lift_request(i, lift, Some(floor), t, out);
                    if let Gate::Lift { next_send, .. } = &mut self.robots[i].gate {
                        *next_send = t + RESEND;
                    }
                }
                self.robots[i].wake = t + RESEND;
                false
            }
        }
    }

    fn door_request(&self, i: usize, door: usize, open: bool, t: f64, out: &mut Vec<(Topic, Msg)>) {
        out.push((
            Topic::AdapterDoorRequests,
            Msg::DoorRequest(DoorRequest {
                request_time: Time::from_secs(t),
                requester_id: self.robots[i].name.clone(),
                door_name: self.nav.doors[door].name.clone(),
                requested_mode: DoorMode {
                    value: if open {
                        door_mode::OPEN
                    } else {
                        door_mode::CLOSED
                    },
                },
            }),
        ));
    }

    /// AGV_MODE to `floor` with doors open, or END_SESSION at the current floor (None).
    fn lift_request(
        &self,
        i: usize,
        lift: usize,
        floor: Option<String>,
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let r = &self.robots[i];
        let (request_type, door_state, destination_floor) = match floor {
            Some(f) => (lift_request::AGV_MODE, lift_request::DOOR_OPEN, f),
            None => (
                lift_request::END_SESSION,
                lift_request::DOOR_CLOSED,
                self.lifts[lift].current_floor.clone(),
            ),
        };
        out.push((
            Topic::AdapterLiftRequests,
            Msg::LiftRequest(LiftRequest {
                lift_name: self.nav.lifts[lift].name.clone(),
                request_time: Time::from_secs(t),
                session_id: r.name.clone(),
                request_type,
                destination_floor,
                door_state,
            }),
        ));
    }

    /// PathRequest: where the robot is, then the targets of the reserved edges.
    fn send_path(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let r = &mut self.robots[i];
        r.path_seq += 1;
        r.path_id = format!("{}", r.path_seq);
        let at = &self.nav.vertices[r.at];
        let start = match &r.state {
            Some(s) => Location {
                t: Time::from_secs(t),
                x: s.location.x,
                y: s.location.y,
                yaw: s.location.yaw,
                level_name: at.level_name.clone(),
                ..Location::default()
            },
            None => Location {
                t: Time::from_secs(t),
                x: at.pos.x,
                y: at.pos.y,
                level_name: at.level_name.clone(),
                ..Location::default()
            },
        };
        let mut path = vec![start];
        let speed = self.fleets[r.fleet].speed;
        let mut eta = t;
        for (k, &e) in r.route.iter().take(r.n_res).enumerate() {
            let edge = &self.nav.edges[e];
            if edge.kind != EdgeKind::Lane {
                break;
            }
            let (a, z) = (&self.nav.vertices[edge.from], &self.nav.vertices[edge.to]);
            let d = z.pos.minus(a.pos);
            let mut yaw = d.y.atan2(d.x);
            if edge.orientation == mapc_ir::Orientation::Backward {
                yaw = (yaw + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI);
            }
            eta += self.nav.edge_cost(e, speed);
            path.push(Location {
                t: Time::from_secs(eta),
                x: z.pos.x,
                y: z.pos.y,
                yaw,
                obey_approach_speed_limit: edge.speed_limit.is_some(),
                approach_speed_limit: edge.speed_limit.unwrap_or(0.0),
                level_name: z.level_name.clone(),
                index: k as u64 + 1,
            });
        }
        r.n_sent = path.len() - 1;
        out.push((
            Topic::RobotPathRequests,
            Msg::PathRequest(PathRequest {
                fleet_name: self.fleets[r.fleet].name.clone(),
                robot_name: r.name.clone(),
                path,
                task_id: r.path_id.clone(),
            }),
        ));
    }

    // ----- traffic supervision -----

    fn traffic_check(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        self.next_traffic = t + 1.0;
        let n = self.robots.len();
        // Idle robots in the way move to a free spot off the waiting robot's route.
        for i in 0..n {
            if self.robots[i].wait_since.is_none() {
                continue;
            }
            for b in self.robots[i].blockers.clone() {
                // A blocker that has itself been stalled for long yields like an idle one
                // would (a gridlock dissolves from its edges).
                if self.robots[i].wait_since.is_some()
                    && self.can_back_off(b)
                    && t - self.robots[b].stall_since >= YIELD_AFTER
                    && t - self.robots[i].stall_since >= YIELD_AFTER
                {
                    let needed = self.needed(&[i], &[], DEADLOCK_HORIZON);
                    if let Some(v) = self.free_spot(b, &needed, None) {
                        let names = [self.robots[i].name.clone(), self.robots[b].name.clone()];
                        self.back_off(b, v, &names, t, out);
                    }
                    continue;
                }
                if self.robots[b].idle() && self.robots[b].n_sent == 0 {
                    // Out of the waiter's way if possible.
                    let needed = self.needed(&[i], &[], DEADLOCK_HORIZON);
                    if let Some(v) = self.free_spot(b, &needed, None) {
                        let r = &mut self.robots[b];
                        r.steps.push_back(Step::GoTo(v));
                        r.dirty = true;
                        continue;
                    }
                    // Hemmed in by the waiter itself (a dead end): choose the idle robot's
                    // spot off the waiter's way as if the waiter were gone, and back the
                    // waiter off. A spot on the waiter's way would only make the two swap
                    // places back and forth.
                    let hemmed = self
                        .free_spot(b, &needed, Some(i))
                        .or_else(|| self.free_spot(b, &[], Some(i)));
                    let Some(v) = hemmed.filter(|_| self.can_back_off(i)) else {
                        // Else anywhere it can go now.
                        if let Some(v) = self.free_spot(b, &[], None) {
                            let r = &mut self.robots[b];
                            r.steps.push_back(Step::GoTo(v));
                            r.dirty = true;
                        }
                        continue;
                    };
                    let rb = &self.robots[b];
                    let f = &self.fleets[rb.fleet];
                    let route = self
                        .nav
                        .plan(f.slot, rb.at, v, f.speed)
                        .map(|p| p.1)
                        .unwrap_or_default();
                    let needed = self.needed(&[b], &route, 0);
                    if let Some(w) = self.free_spot(i, &needed, None) {
                        let names = [self.robots[i].name.clone(), self.robots[b].name.clone()];
                        self.back_off(i, w, &names, t, out);
                        let r = &mut self.robots[b];
                        r.steps.push_back(Step::GoTo(v));
                        r.dirty = true;
                    } else if let Some(v) = self.free_spot(b, &[], None) {
                        let r = &mut self.robots[b];
                        r.steps.push_back(Step::GoTo(v));
                        r.dirty = true;
                    }
                }
            }
        }
        // Deadlocks: cycles of robots waiting for each other.
        let waits: Vec<Vec<usize>> = self
            .robots
            .iter()
            .map(|r| {
                if r.wait_since.is_some() {
                    r.blockers.clone()
                } else {
                    Vec::new()
                }
            })
            .collect();
        if let Some(cycle) = find_cycle(&waits) {
            let old = cycle.iter().all(|&r| {
                self.robots[r]
                    .wait_since
                    .is_some_and(|s| t - s >= DEADLOCK_AFTER)
            });
            if old {
                self.resolve_deadlock(&cycle, t, out);
            }
        }
        // A waiting robot stalls only when nothing it waits for, directly or through
        // other waiting robots, has moved lately (long lanes take minutes to drive).
        let mut live: Vec<bool> = self
            .robots
            .iter()
            .map(|r| r.wait_since.is_none() && t - r.last_moved < 2.0)
            .collect();
        for _ in 0..n {
            let mut changed = false;
            for i in 0..n {
                if !live[i]
                    && self.robots[i].wait_since.is_some()
                    && self.robots[i]
                        .blockers
                        .iter()
                        .any(|&b| live.get(b) == Some(&true))
                {
                    live[i] = true;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        for (i, r) in self.robots.iter_mut().enumerate() {
            if r.wait_since.is_none() || live[i] {
                r.stall_since = t;
            }
        }
        // No progress for too long: report, then give up the task.
        for i in 0..n {
            if self.robots[i].wait_since.is_none() {
                continue;
            }
            let waited = t - self.robots[i].stall_since;
            if waited >= STUCK_AFTER && !self.robots[i].stuck_reported {
                self.robots[i].stuck_reported = true;
                let who: Vec<String> = self.robots[i]
                    .blockers
                    .iter()
                    .map(|&b| format!("{} ({})", self.robots[b].name, self.status(b)))
                    .collect();
                if let Some(ti) = self.robots[i].task {
                    self.event(
                        t,
                        ti,
                        "stuck",
                        Some(i),
                        format!("waiting for {}", who.join(",")),
                        out,
                    );
                }
            }
            // Long stalled: look for a way around what the others hold now.
            if waited >= DETOUR_AFTER
                && t - self.robots[i].last_detour >= DETOUR_AFTER
                && self.can_back_off(i)
            {
                self.robots[i].last_detour = t;
                if self.detour(i, &[]) {
                    self.robots[i].stall_since = t;
                    continue;
                }
            }
            // Stalled, or not moved at all (back-offs that never start reset the stall).
            let r = &self.robots[i];
            let unmoved = t - r.last_moved.max(r.task_started);
            if waited >= STUCK_FAIL || (r.task.is_some() && unmoved >= STUCK_FAIL) {
                if self.robots[i].task.is_some() {
                    self.end_task(i, t, false, "stuck in traffic".into(), out);
                } else {
                    // A yield move that cannot happen: drop it.
                    let r = &mut self.robots[i];
                    r.steps.clear();
                    r.cur = Cur::None;
                    self.abandon_route(i, t, out);
                }
            }
        }
    }

    /// Only a robot waiting at rest in the middle of a GoTo can back off.
    fn can_back_off(&self, b: usize) -> bool {
        let rb = &self.robots[b];
        rb.gate == Gate::None
            && rb.n_sent == 0
            && rb.wait_since.is_some()
            && matches!(rb.cur, Cur::GoTo { .. })
    }

    /// Robot `b` drives to `v`, waits there, then resumes its GoTo from scratch.
    fn back_off(
        &mut self,
        b: usize,
        v: usize,
        names: &[String],
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        // Already backing off (its spot turned out blocked too): drop that back-off and
        // head for the goal it was for.
        {
            let r = &mut self.robots[b];
            if r.backing_off {
                if let (Some(Step::Dwell(_)), Some(&Step::GoTo(goal))) =
                    (r.steps.front(), r.steps.get(1))
                {
                    r.steps.pop_front();
                    r.steps.pop_front();
                    r.cur = Cur::GoTo {
                        goal,
                        planned: true,
                    };
                }
            }
        }
        if let Cur::GoTo { goal, .. } = self.robots[b].cur {
            let r = &mut self.robots[b];
            if r.backoff_goal != goal {
                r.backoff_goal = goal;
                r.backoffs = 0;
            }
            // Only back-offs after moving count: one that could not start is no livelock
            // (a robot that never moves fails by STUCK_FAIL instead).
            if r.last_moved > r.last_backoff {
                r.backoffs += 1;
            }
            r.last_backoff = t;
            if r.backoffs > MAX_BACKOFFS {
                // The same robots keep meeting: give up rather than loop forever.
                r.backoffs = 0;
                let detail = format!("deadlock with {} not resolved", names.join(","));
                if r.task.is_some() {
                    self.end_task(b, t, false, detail, out);
                } else {
                    r.cur = Cur::None;
                    r.steps.clear();
                    self.abandon_route(b, t, out);
                }
                return;
            }
        }
        let r = &mut self.robots[b];
        if let Cur::GoTo { goal, .. } = r.cur {
            r.steps.push_front(Step::GoTo(goal));
        }
        // Wait there long enough for the others to take the way.
        // Longer each time towards the same goal: the others may need long to pass.
        let wait = BACKOFF_WAIT * f64::from(1u32 << r.backoffs.clamp(1, 5).saturating_sub(1));
        r.steps.push_front(Step::Dwell(wait));
        r.steps.push_front(Step::GoTo(v));
        r.backing_off = true;
        r.cur = Cur::None;
        r.route.clear();
        r.n_res = 0;
        r.wait_since = None;
        r.blockers.clear();
        r.dirty = true;
        self.rehold(b);
        let spot = &self.nav.vertices[v];
        let spot = if spot.name.is_empty() {
            format!("({:.2}, {:.2})", spot.pos.x, spot.pos.y)
        } else {
            spot.name.clone()
        };
        let detail = format!(
            "{}: {} backs off to {spot}",
            names.join(","),
            self.robots[b].name
        );
        if let Some(ti) = self.robots[b].task {
            self.event(t, ti, "deadlock", Some(b), detail, out);
        }
    }

    /// Breaks a wait-for cycle. The victim is the robot that can get out of the others'
    /// way soonest (fewest back-offs lately first, so repeated cycles pick another one):
    /// to a spot off the others' next `horizon` edges, the far horizon first. Without any
    /// such spot, a robot of the cycle that has a detour around the others takes it; else
    /// the deadlock is reported (and retried every second).
    fn resolve_deadlock(&mut self, cycle: &[usize], t: f64, out: &mut Vec<(Topic, Msg)>) {
        let names: Vec<String> = cycle.iter().map(|&r| self.robots[r].name.clone()).collect();
        for horizon in [DEADLOCK_HORIZON, 2, 0] {
            // (in a cabin, back-offs, time, robot, spot)
            let mut best: Option<(bool, u32, f64, usize, usize)> = None;
            for &b in cycle.iter().rev() {
                if !self.can_back_off(b) {
                    continue;
                }
                let others: Vec<usize> = cycle.iter().copied().filter(|&o| o != b).collect();
                let needed = self.needed(&others, &[], horizon);
                if let Some((v, time)) = self.free_spot_timed(b, &needed, None, horizon == 0) {
                    // A robot in a lift cabin backs off last: the others wait for the
                    // cabin to empty.
                    let cabin = self.nav.vertices[self.robots[b].at].lift.is_some();
                    let k = (cabin, self.robots[b].backoffs, time);
                    if best.is_none_or(|(bc, bk, bt, _, _)| k < (bc, bk, bt)) {
                        best = Some((k.0, k.1, k.2, b, v));
                    }
                }
            }
            if let Some((_, _, _, b, v)) = best {
                self.back_off(b, v, &names, t, out);
                return;
            }
        }
        for &b in cycle {
            if self.can_back_off(b) && self.detour(b, &[]) {
                if let Some(ti) = self.robots[b].task {
                    let detail = format!("{}: {} detours", names.join(","), self.robots[b].name);
                    self.event(t, ti, "deadlock", Some(b), detail, out);
                }
                return;
            }
        }
        for &r in cycle {
            if let Some(ti) = self.robots[r].task {
                if !self.robots[r].stuck_reported {
                    self.event(t, ti, "deadlock", Some(r), names.join(","), out);
                }
            }
            self.robots[r].stuck_reported = true;
        }
    }

    /// Replans robot `b`'s GoTo (at rest, waiting) around what the other robots hold now
    /// (and `avoid`, more resources to keep off). True if a new route was taken.
    fn detour(&mut self, b: usize, avoid: &[Res]) -> bool {
        let r = &self.robots[b];
        let Cur::GoTo { goal, .. } = r.cur else {
            return false;
        };
        if r.n_sent > 0 || r.gate != Gate::None {
            return false;
        }
        let mut held: Vec<Res> = avoid.to_vec();
        for o in 0..self.robots.len() {
            if o != b {
                held.extend_from_slice(self.res.held(o));
            }
        }
        held.sort_unstable();
        held.dedup();
        let standing = &self.conf.vertex[r.at];
        let clear = |e: usize| {
            !self.conf.edge[e]
                .iter()
                .any(|x| standing.binary_search(x).is_err() && held.binary_search(x).is_ok())
        };
        let f = &self.fleets[r.fleet];
        let Some((_, edges)) = self.nav.plan_with(r.slot, r.at, goal, f.speed, &clear) else {
            return false;
        };
        if edges.is_empty() || edges.iter().eq(r.route.iter()) {
            return false;
        }
        let r = &mut self.robots[b];
        r.route = edges.into();
        r.n_res = 0;
        r.wait_since = None;
        r.blockers.clear();
        r.dirty = true;
        self.rehold(b);
        true
    }

    /// Resources robots `who` need: where they stand, the next `horizon` edges of their
    /// routes, and `edges`.
    fn needed(&self, who: &[usize], edges: &[usize], horizon: usize) -> Vec<Res> {
        let mut needed: Vec<Res> = Vec::new();
        for &o in who {
            let r = &self.robots[o];
            needed.extend_from_slice(&self.conf.vertex[r.at]);
            for &e in r.route.iter().take(horizon) {
                needed.extend_from_slice(&self.conf.edge[e]);
            }
        }
        for &e in edges {
            needed.extend_from_slice(&self.conf.edge[e]);
        }
        needed.sort_unstable();
        needed.dedup();
        needed
    }

    /// A vertex robot `b` can go to where it is in nobody's way: nobody (but `ignore`)
    /// holds its standing set, the set is disjoint from `needed` (sorted), and the first
    /// lane there is free now. Parking spots, holding points and chargers first, then any
    /// vertex; nearest first.
    fn free_spot(&self, b: usize, needed: &[Res], ignore: Option<usize>) -> Option<usize> {
        self.free_spot_timed(b, needed, ignore, false).map(|x| x.0)
    }

    /// The nearest parking vertex (`park`) on robot `i`'s level that nobody stands on,
    /// drives to or holds, with the travel time there; None when it is on one already.
    fn park_spot(&self, i: usize) -> Option<(usize, f64)> {
        let r = &self.robots[i];
        let f = &self.fleets[r.fleet];
        let park = self.park.get(f.slot)?;
        if park.get(r.at).copied().unwrap_or(true) || self.nav.vertices[r.at].lift.is_some() {
            return None;
        }
        let level = &self.nav.vertices[r.at].level;
        let taken = |v: usize| {
            self.robots.iter().enumerate().any(|(o, x)| {
                o != i
                    && (x.at == v
                        || matches!(x.cur, Cur::GoTo { goal, .. } if goal == v)
                        || x.steps
                            .iter()
                            .any(|s| matches!(s, Step::GoTo(g) if *g == v)))
            })
        };
        let (times, prev) = self.nav.tree_from(f.slot, r.at, f.speed);
        // Not through a controlled door or a lift: parking must not keep them busy.
        let plain = |v: usize| {
            let mut w = v;
            for _ in 0..prev.len() {
                if w == r.at {
                    return true;
                }
                let Some(e) = prev.get(w).copied().flatten() else {
                    return false;
                };
                if !self.is_plain(e) {
                    return false;
                }
                w = self.nav.edges[e].from;
            }
            false
        };
        // Parking spots and holding points first (cf. `free_spot`).
        let cost = |v: usize| {
            let ro = &self.nav.vertices[v].roles;
            let spot = ro.is_parking_spot || ro.is_holding_point;
            times[v] + if spot { 0.0 } else { SPOT_PENALTY }
        };
        let mut spots: Vec<usize> = self.nav.members[f.slot]
            .iter()
            .copied()
            .filter(|&v| park.get(v).copied().unwrap_or(false) && times[v] <= PARK_REACH)
            .filter(|&v| self.nav.vertices[v].level == *level)
            .filter(|&v| self.res.is_free_ignoring(i, &self.conf.vertex[v], None))
            .filter(|&v| !taken(v) && plain(v))
            .collect();
        spots.sort_by(|&a, &b| cost(a).total_cmp(&cost(b)).then(a.cmp(&b)));
        // Past a one-way lane a spot may have no way back: the robot would be trapped there
        // for every later task. Parking is rare (after a task), so a tree per candidate
        // tried is affordable; usually the first one qualifies.
        spots
            .into_iter()
            .find(|&v| {
                self.nav
                    .tree_from(f.slot, v, f.speed)
                    .0
                    .get(r.at)
                    .is_some_and(|t| t.is_finite())
            })
            .map(|v| (v, times[v]))
    }

    /// [`Fleets::free_spot`] with the travel time there.
    fn free_spot_timed(
        &self,
        b: usize,
        needed: &[Res],
        ignore: Option<usize>,
        push: bool,
    ) -> Option<(usize, f64)> {
        let r = &self.robots[b];
        let f = &self.fleets[r.fleet];
        let (times, prev) = self.nav.tree_from(f.slot, r.at, f.speed);
        let class = |v: usize| {
            let ro = &self.nav.vertices[v].roles;
            if ro.is_parking_spot || ro.is_holding_point || ro.is_charger {
                0u8
            } else {
                1
            }
        };
        let mut cands: Vec<usize> = self.nav.members[f.slot]
            .iter()
            .copied()
            .filter(|&v| v != r.at && times[v].is_finite())
            .filter(|&v| self.nav.vertices[v].lift.is_none())
            // From a cabin, not by riding on: the cabin is what the others wait for.
            .filter(|&v| {
                let here = &self.nav.vertices[r.at];
                here.lift.is_none() || self.nav.vertices[v].level == here.level
            })
            .filter(|&v| self.res.is_free_ignoring(b, &self.conf.vertex[v], ignore))
            .filter(|&v| {
                !self.conf.vertex[v]
                    .iter()
                    .any(|x| needed.binary_search(x).is_ok())
            })
            .collect();
        // Nearest first; a spot that is not a parking spot, holding point or charger
        // counts SPOT_PENALTY longer (it is more likely to be on somebody's way).
        let cost = |v: usize| times[v] + SPOT_PENALTY * f64::from(class(v));
        cands.sort_by(|&a, &c| cost(a).total_cmp(&cost(c)).then(a.cmp(&c)));
        // Only spots the robot can start driving to now (its first lane is free), else
        // whose first lane only idle robots block (they will be asked to move aside).
        let first: Vec<(usize, Option<usize>)> = cands
            .into_iter()
            .take(16)
            .map(|v| (v, self.nav.first_edge(&prev, r.at, v)))
            .collect();
        let found = first
            .iter()
            .find(|&&(_, e)| e.is_some_and(|e| self.edge_free(b, e, ignore)))
            .or_else(|| {
                first.iter().find(|&&(_, e)| {
                    e.is_some_and(|e| {
                        let standing = &self.conf.vertex[r.at];
                        let set: Vec<Res> = self.conf.edge[e]
                            .iter()
                            .copied()
                            .filter(|x| standing.binary_search(x).is_err())
                            .collect();
                        self.res.blockers(b, &set).iter().all(|&o| {
                            Some(o) == ignore
                                || (self.robots[o].idle() && self.robots[o].n_sent == 0)
                        })
                    })
                })
            })
            .or_else(|| {
                // Gridlock: a spot behind a robot that waits at rest (not one that needs
                // `needed`); waiting for it makes a new wait-for cycle, whose own victim
                // then makes room further out (robots pushed back one after the other).
                if !push {
                    return None;
                }
                first.iter().find(|&&(_, e)| {
                    e.is_some_and(|e| {
                        let standing = &self.conf.vertex[r.at];
                        let set: Vec<Res> = self.conf.edge[e]
                            .iter()
                            .copied()
                            .filter(|x| standing.binary_search(x).is_err())
                            .collect();
                        self.res.blockers(b, &set).iter().all(|&o| {
                            let x = &self.robots[o];
                            x.n_sent == 0
                                && !self
                                    .res
                                    .held(o)
                                    .iter()
                                    .any(|h| needed.binary_search(h).is_ok())
                        })
                    })
                })
            });
        found.map(|&(v, _)| (v, times[v]))
    }

    /// Whether robot `b` could reserve edge `e` now, not counting what `ignore` holds nor
    /// what its own standing set shares with others (as in `try_reserve`).
    fn edge_free(&self, b: usize, e: usize, ignore: Option<usize>) -> bool {
        let standing = &self.conf.vertex[self.robots[b].at];
        let set: Vec<Res> = self.conf.edge[e]
            .iter()
            .copied()
            .filter(|x| standing.binary_search(x).is_err())
            .collect();
        self.res.is_free_ignoring(b, &set, ignore)
    }

    /// What robot `i` is doing, for stuck reports.
    fn status(&self, i: usize) -> &'static str {
        let r = &self.robots[i];
        if r.n_sent > 0 {
            "moving"
        } else if r.wait_since.is_some() {
            "waiting"
        } else {
            match (&r.gate, &r.cur) {
                (Gate::Door { .. }, _) => "at a door",
                (Gate::Lift { .. }, _) => "at a lift",
                (_, Cur::Workcell { .. }) => "at a workcell",
                (_, Cur::Dwell { .. }) => "dwelling",
                (_, Cur::Charge { .. }) => "charging",
                _ if r.idle() => "idle",
                _ => "busy",
            }
        }
    }
}

/// Per graph slot, per vertex: where an idle robot may park out of everybody's way. Not a
/// lift cabin or a charger, and neither the vertex nor anything its standing robot would hold is needed
/// by a shortest route between two task waypoints (the routes loops, deliveries and the
/// drives between tasks take), so a parked robot never has to be moved aside for them.
fn park_vertices(nav: &Nav, conf: &Conflicts, scenario: &Scenario) -> Vec<Vec<bool>> {
    let kinds: Vec<&TaskKind> = scenario
        .tasks
        .iter()
        .map(|t| &t.kind)
        .chain(scenario.generators.iter().map(|g| &g.kind))
        .collect();
    // Resources any task route of any graph needs (vertices and lanes driven): fleets on
    // other graphs share the floor.
    let mut used = vec![false; conf.n_res];
    let mut mark = |set: &[Res]| {
        for &x in set {
            if let Some(u) = used.get_mut(x as usize) {
                *u = true;
            }
        }
    };
    for slot in 0..nav.graphs.len() {
        let mut wps: Vec<usize> = kinds
            .iter()
            .flat_map(|k| waypoint_names(k))
            .filter_map(|name| nav.find(slot, name))
            .collect();
        wps.sort_unstable();
        wps.dedup();
        for &a in &wps {
            if let Some(set) = conf.vertex.get(a) {
                mark(set);
            }
            let (times, prev) = nav.tree_from(slot, a, 1.0);
            for &b in &wps {
                if b == a || !times[b].is_finite() {
                    continue;
                }
                let mut v = b;
                for _ in 0..prev.len() {
                    let Some(e) = prev.get(v).copied().flatten() else {
                        break;
                    };
                    if let Some(set) = conf.edge.get(e) {
                        mark(set);
                    }
                    v = nav.edges[e].from;
                    if v == a {
                        break;
                    }
                }
            }
        }
    }
    (0..nav.graphs.len())
        .map(|slot| {
            let mut ok = vec![false; nav.vertices.len()];
            for &v in &nav.members[slot] {
                // Chargers are kept for robots that need to charge.
                ok[v] = nav.vertices[v].lift.is_none()
                    && !nav.vertices[v].roles.is_charger
                    && conf.vertex[v]
                        .iter()
                        .all(|&x| !used.get(x as usize).copied().unwrap_or(true));
            }
            ok
        })
        .collect()
}

/// Whether a robot parks (`Fleets::park_spot`) after a task of this kind.
fn parks_after(kind: &TaskKind) -> bool {
    !matches!(kind, TaskKind::GoToPlace { .. })
}

fn waypoint_names(kind: &TaskKind) -> Vec<&str> {
    match kind {
        TaskKind::Loop { start, finish, .. } => vec![start, finish],
        TaskKind::Delivery {
            pickup, dropoff, ..
        } => vec![pickup, dropoff],
        TaskKind::Clean { zone } => vec![zone],
        TaskKind::GoToPlace { place } => vec![place],
    }
}

fn unknown_waypoint(nav: &Nav, slot: usize, name: &str, span: Span, fleet: &str) -> Diagnostic {
    let mut names: Vec<&str> = nav.members[slot]
        .iter()
        .map(|&v| nav.vertices[v].name.as_str())
        .filter(|n| !n.is_empty())
        .collect();
    names.sort_unstable();
    names.dedup();
    // The nearest name first (a typo is the usual cause), then what else there is, saying
    // how many names the list leaves out.
    const LISTED: usize = 12;
    let nearest = mapc_frontend::spelling::nearest(name, names.iter().copied());
    let others: Vec<&str> = names
        .iter()
        .copied()
        .filter(|n| Some(*n) != nearest)
        .collect();
    let left_out = others.len().saturating_sub(LISTED);
    let mut help = match nearest {
        Some(n) => format!("nearest: `{n}`"),
        None => "this graph has no named waypoints".to_string(),
    };
    if !others.is_empty() {
        help.push_str(&format!(
            "; others: {}",
            others[..others.len().min(LISTED)].join(", ")
        ));
        if left_out > 0 {
            help.push_str(&format!(" and {left_out} more"));
        }
    }
    Diagnostic::error(
        codes::UNKNOWN_WAYPOINT,
        span,
        format!("no waypoint named `{name}` on the graph of fleet `{fleet}`"),
    )
    .with_help(help)
}

#[cfg(test)]
#[path = "fleet_tests.rs"]
mod tests;

#[cfg(test)]
#[path = "fleet_world_tests.rs"]
mod world_tests;
