//! The fleet layer: what a minimal RMF fleet adapter does (task assignment, routes on the
//! fleet's nav graph, traffic reservations, doors, lifts, workcells, charging), talking to
//! the world only through messages.
//!
//! Event driven: `update` returns at once unless a message arrived or a timer expired.
//!
//! Traffic is planned, not negotiated: every GoTo is planned into one schedule shared by
//! all fleets (`crate::traffic`), and a robot drives a traversal only when the schedule
//! grants it, in the order the plans fixed. A lane through a controlled door, into a lift
//! cabin, or a lift ride is driven alone, after the door is open (DoorState OPEN and our
//! heartbeat session) or the lift is at the floor with its doors open in our session.
//! Progress is read from RobotState (`path` = waypoints not yet reached). Empty
//! dispensers are asked again (without limit while their item is on its way back); a
//! delivery that fails while carrying its item still takes it to the ingestor.
//!
//! Three types share the work, each with its own state: [`Fleets`] runs the others in
//! turn; `assign::Dispatcher` keeps the task queue and runs the dispatch rounds (which robot
//! takes a task); [`Floor`] is the robots executing their tasks against the schedule.
//!
//! Modules: `setup` (placement, graphs, the schedule), `spawn` (where auto-spawned robots
//! start), `assign` (the dispatcher), `takers` (the floor's side of dispatch), `steps` (a
//! task's steps and places), `task` (the steps of a task and their sessions), `drive` (path
//! requests, doors and lifts on the way), `devices` (doors, lifts, workcells and chargers
//! as last heard of), `cancel` (cancel requests), `traffic` (planning legs into the
//! schedule and driving what it grants), `retreat` (out of the way while idle), `park`
//! (what a robot does with no task left), `waits` (why robots wait), `bound` (the
//! throughput bound's demands).

use crate::graph::{EdgeKind, Nav};
use crate::msgs::{
    door_mode, lift_request, lift_state, robot_mode, workcell_result, DoorMode, DoorRequest,
    FleetState, ItemType, LiftRequest, Location, Msg, PathRequest, Published, RobotState,
    TaskEvent, TaskWaits, Time, Topic, WaitCause, WorkcellRequest,
};
use crate::scenario::{Scenario, SpawnSpec, TaskCategory, TaskKind};
use crate::traffic::parks::Parks;
use crate::traffic::schedule::Schedule;
use crate::traffic::sipp::Planner;
use crate::traffic::{Clearance, Conflicts};
use crate::world::{RobotSpawn, WorkcellSpawn};
use mapc_ir::{Building, Diagnostic, Span};
use std::collections::{BTreeMap, VecDeque};

mod assign;
mod bound;
mod cancel;
mod devices;
mod drive;
mod park;
mod retreat;
mod setup;
mod spawn;
mod steps;
mod takers;
mod task;
mod traffic;
mod waits;

pub(crate) use park::Finish;
use park::{choose_parks, finish_of, well_formed_warnings};
use traffic::NoPlan;

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
    /// A scenario workcell has the name of one of the map's.
    pub const DUPLICATE_WORKCELL: &str = "S0308";
    /// A task waypoint lies inside a lift cabin.
    pub const IN_LIFT: &str = "S0207";
    /// A task waypoint cuts the graph (warning).
    pub const NOT_WELL_FORMED: &str = "S0210";
    /// Auto spawn found room for fewer robots than asked (warning).
    pub const NO_ROOM: &str = "S0211";
}

/// Seconds between re-sent door, lift and workcell requests.
const RESEND: f64 = 1.0;
/// Waiting this long for a door, lift or workcell fails the task.
const EXTERNAL_TIMEOUT: f64 = 300.0;
/// A robot at an empty dispenser asks again this often (s), this long (s).
const ITEM_RETRY: f64 = 5.0;
const ITEM_WAIT: f64 = 1200.0;
/// An ingested item is back in its dispenser within this long (s): the plugin sends it
/// home 5 s after the success, counted in whole seconds. (It was 30 s: in a building where
/// every task is a delivery from three dispensers, each delivery then kept its dispenser
/// 25 s longer than the item was away, and a third robot stood idle for it.)
const ITEM_HOME: f64 = 6.0;
/// A robot waiting for traffic this long is reported stuck.
const STUCK_AFTER: f64 = 120.0;
/// What a dispenser's or ingestor's work takes in plans (s); the plugins take 5 s.
const WORKCELL_ESTIMATE: f64 = 5.0;
/// Traversals sent at once along plain lanes.
const LOOKAHEAD: usize = 3;

/// Where robots and workcells start, resolved from the scenario against the map.
pub struct Placement {
    pub robots: Vec<RobotSpawn>,
    pub workcells: Vec<WorkcellSpawn>,
    /// Per fleet, robots that auto spawn found no room for: the building has fewer
    /// parking vertices (`crate::traffic::parks`) than robots asked.
    pub reserve: Vec<(String, usize)>,
    /// Warnings about the scenario on this map (not well-formed places, rooms short).
    pub warnings: Vec<Diagnostic>,
    /// Where robots may stand for good.
    pub(crate) parks: Parks,
    /// Per robot (as `robots`): what it does when it has no more tasks (default
    /// [`Finish::Park`]).
    pub(crate) finishes: Vec<Finish>,
}

#[derive(Debug, Clone, PartialEq)]
enum Step {
    GoTo(usize),
    Dispense(String),
    Ingest(String),
    Dwell(f64),
    Charge(f64),
    /// Back at a dispenser after making room: the wait for its item goes on as it was.
    Resume(Box<Cur>),
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
        /// The request under `guid` went out (an answer may still come).
        sent: bool,
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
    /// Leading traversals of the itinerary sent in the current PathRequest.
    n_sent: usize,
    /// Leading traversals of the itinerary up to the current GoTo's goal (None: no leg).
    leg: Option<usize>,
    /// The legs of the task's next GoTos, planned with it: traversals from one place to
    /// the next.
    legs: VecDeque<usize>,
    path_id: String,
    path_seq: u64,
    gate: Gate,
    /// Door to close / lift session to end after the edge being driven.
    close_door: Option<usize>,
    end_lift: Option<usize>,
    steps: VecDeque<Step>,
    cur: Cur,
    task: Option<usize>,
    wake: f64,
    dirty: bool,
    /// Waiting for the schedule to grant its next traversal (or for a plan) since.
    waiting: Option<f64>,
    /// When a failed plan is tried again.
    replan_at: f64,
    stuck_reported: bool,
    /// Last reported position that differed by more than 5 cm, and when.
    last_pos: (f64, f64),
    last_moved: f64,
    charger: Option<usize>,
    /// (drop-off vertex, ingestor) of the item the robot carries.
    carrying: Option<(usize, String)>,
    /// The dispenser of the item aboard, until it is ingested (also on a return trip).
    item_from: Option<String>,
    /// When the current task started.
    task_started: f64,
    /// When it reached the end of its last traversal.
    reached_at: f64,
    /// Not on a parking vertex yet (a spawn elsewhere): plans its way there when idle.
    park_pending: bool,
    /// Steps ahead that are a detour to make room, not phases of the task.
    detour: u8,
    /// What it does when it has no more tasks (its fleet adapter config's
    /// `finishing_request`).
    finish: Finish,
    /// What it waits for now (cause, place, since) and the waits of its current task.
    waiting_for: Option<(WaitCause, waits::Place, f64)>,
    waits: TaskWaits,
    /// The parking vertex out of the way it was sent to while idle with tasks waiting
    /// (`retreat.rs`), until it takes a task.
    retreat: Option<usize>,
    /// Since when it has had no task (the start of the dispatch round that first found it
    /// free; infinite from when it takes one).
    free_since: f64,
}

impl Robot {
    fn idle(&self) -> bool {
        self.task.is_none() && self.steps.is_empty() && self.cur == Cur::None
    }
    fn battery(&self) -> f64 {
        self.state.as_ref().map_or(100.0, |s| s.battery_percent)
    }
}

struct FleetRt {
    name: String,
    slot: usize,
    speed: f64,
    /// Its slotcars speed up at `accel` and brake at up to `max_accel` (m/s²): lower bounds
    /// of drive times.
    accel: f64,
    max_accel: f64,
    /// How its robots drive (traversal times in plans).
    kin: crate::traffic::sipp::Kinematics,
    recharge_threshold: f64,
    recharge_soc: f64,
    /// Battery percent gained per second on a charger.
    charge_rate: f64,
    kinds: Vec<TaskCategory>,
    robots: Vec<usize>,
}

/// A task as requested (from the scenario's tasks, generators or RMF requests), before it
/// is queued.
struct NewTask {
    kind: TaskKind,
    fleet: Option<String>,
    /// A robot task's robot, by name.
    robot: Option<String>,
    priority: u64,
}

struct Task {
    id: String,
    category: TaskCategory,
    kind: TaskKind,
    fleet: Option<String>,
    ended: bool,
}

/// The fleet adapter: the robots on the floor with their tasks ([`Floor`]), the task queue
/// and its rounds (`assign::Dispatcher`) and the scenario's cancels, run in turn by
/// [`Fleets::update`]. It owns no rule of its own: it hands each message, request and
/// timer to the component whose job it is.
pub struct Fleets {
    floor: Floor,
    /// The task queue and what is still to be requested.
    dispatcher: assign::Dispatcher,
    /// The scenario's cancels.
    cancels: cancel::Cancels,
    next_wake: f64,
    next_fleet_state: f64,
    next_traffic: f64,
}

/// The robots executing their tasks: the nav graphs, the fleets, their robots (each with
/// its task's steps, the step in progress and its itinerary in the schedule), the tasks and
/// the robots' names, with the components they execute against: `traffic::Traffic` (the
/// schedule shared by all fleets, the planner, the parking vertices), `devices::Devices`
/// (doors, lifts, workcells and chargers as last heard of) and `drive::LaneUse`. Its
/// `impl` is split by job: `task` (the steps of a task), `drive` (paths, doors and lifts),
/// `traffic` (plans into the schedule), `traffic/grant` (driving what the schedule
/// grants), `traffic/room` (making room), `retreat` (out of the way while idle), `takers`
/// (what the dispatcher asks of it), `steps` (a task's steps and places), `waits` (why
/// robots wait), `bound` (the throughput bound's demands).
///
/// Invariant: a robot with a task has a plan in the schedule to its next place (or is
/// planning one, waiting where it blocks nobody), and every itinerary ends on a vertex its
/// robot may stand on for good; a robot drives only what the schedule grants it.
struct Floor {
    nav: Nav,
    /// The schedule every robot's plan goes into, and the planner.
    traffic: traffic::Traffic,
    fleets: Vec<FleetRt>,
    robots: Vec<Robot>,
    by_name: BTreeMap<String, usize>,
    tasks: Vec<Task>,
    clean_duration: f64,
    /// Doors, lifts, workcells and chargers as last heard of.
    devices: devices::Devices,
    /// Per IR lane: when robots drove it (the report's timeline).
    lane_use: drive::LaneUse,
    /// Robots whose tasks ended in this update's ticks: they set off to park after its
    /// last dispatch round, if they took no task there.
    just_free: Vec<usize>,
    /// Per graph slot, per vertex: for a parking vertex in the way, the parking vertices out
    /// of the way nearby, nearest first (`traffic::parks::out_of_the_way`).
    ways_out: Vec<Vec<Vec<usize>>>,
    /// The earliest time a robot became free since the dispatcher last heard (a round is
    /// then due: [`Fleets::freed`]).
    freed_at: f64,
}

impl Fleets {
    /// Reads what the world published in the last step (`inbox`) and appends the fleet's
    /// requests and task events to `out`.
    pub fn update(&mut self, t: f64, inbox: &[Published], out: &mut Vec<(Topic, Msg)>) {
        if inbox.is_empty() && t < self.next_wake {
            return;
        }
        self.floor.hear(t, inbox);
        // New tasks.
        while let Some(new) = self.dispatcher.take_request(t) {
            self.dispatcher.request(&mut self.floor, t, new, out);
        }
        self.cancel_due(t, out);
        self.dispatch(t, out);
        self.floor.tick_due(t, out);
        // Robots that became free in this update take waiting tasks; those that took
        // none set off to park.
        self.dispatch(t, out);
        self.floor.set_off_to_park(t, out);
        if t >= self.next_traffic {
            self.next_traffic = t + 1.0;
            self.floor.replan_delayed(t);
            self.floor.watch_waits(t, out);
        }
        if t >= self.next_fleet_state {
            self.next_fleet_state = t + 1.0;
            self.floor.publish_states(out);
        }
        let any_waiting = self.floor.account_waits(t);
        self.next_traffic = if any_waiting {
            self.next_traffic.min(t + 1.0).max(t + 1e-9)
        } else {
            f64::INFINITY
        };
        if self.next_traffic <= t {
            self.next_traffic = t + 1.0;
        }
        self.freed();
        let mut next = self
            .next_fleet_state
            .min(self.next_traffic)
            .min(self.dispatcher.next_at());
        if let Some(c) = self.cancels.next_at() {
            next = next.min(c);
        }
        for r in &self.floor.robots {
            next = next.min(r.wake);
        }
        self.next_wake = next;
    }

    /// A dispatch round, if one is due (robots that became free since the last one make
    /// it due at once).
    fn dispatch(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        self.freed();
        self.dispatcher.round(&mut self.floor, t, out);
        debug_assert!(
            self.floor.freed_at.is_infinite(),
            "a robot became free in a round"
        );
    }

    /// Tells the dispatcher when robots became free on the floor.
    fn freed(&mut self) {
        let at = std::mem::replace(&mut self.floor.freed_at, f64::INFINITY);
        self.dispatcher.wake(at);
    }

    /// Records the wall-clock time of every plan from now on (see `RunOptions::plan_times`).
    pub fn time_plans(&mut self) {
        self.floor.traffic.time_plans();
    }

    /// The wall-clock time (s) of every plan since [`Fleets::time_plans`].
    pub fn plan_times(&mut self) -> Vec<f64> {
        self.floor.traffic.plan_times()
    }

    /// The ten lanes robots drove longest, each with its busy share per interval of a run
    /// of `end` seconds (the report's timeline).
    pub fn lane_series(&self, end: f64) -> Vec<crate::report::timeline::Series> {
        self.floor.lane_use.series(&self.floor.nav, end)
    }

    /// The traffic planner's work so far.
    pub fn traffic_report(&self) -> crate::report::TrafficReport {
        self.floor.traffic.report()
    }

    /// True when every task has ended (completed or failed) and no generator is pending.
    pub fn all_done(&self, _t: f64) -> bool {
        self.dispatcher.requested_all() && self.floor.tasks.iter().all(|t| t.ended)
    }

    /// Per task that arrived (and was not refused): its least use of each exclusive
    /// resource (see `bound`). `broken_off`: some task ended half-way.
    pub fn demands(&self, broken_off: bool) -> crate::report::bound::Demands {
        self.floor.demands(broken_off)
    }
}

impl Floor {
    /// Reads what the world published: robot states, and doors, lifts and workcells
    /// (robots waiting for one of them look again).
    fn hear(&mut self, t: f64, inbox: &[Published]) {
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
                _ => external |= self.devices.hear(p),
            }
        }
        if external {
            for r in &mut self.robots {
                if r.gate != Gate::None || matches!(r.cur, Cur::Workcell { .. }) {
                    r.dirty = true;
                }
            }
        }
    }

    /// Robots with news or an expired timer go on; repeated while reservations were
    /// released (a release can unblock robots that are waiting).
    fn tick_due(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        for pass in 0..4 {
            self.traffic.begin_pass();
            for i in 0..self.robots.len() {
                let r = &self.robots[i];
                let due = r.dirty || r.wake <= t || (pass > 0 && r.waiting.is_some());
                if due {
                    self.robots[i].dirty = false;
                    self.tick(i, t, out);
                }
            }
            if !self.traffic.released() {
                break;
            }
        }
    }

    /// Robots whose tasks ended in this update and that took no task set off to park.
    fn set_off_to_park(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        for i in std::mem::take(&mut self.just_free) {
            if self.robots[i].idle() {
                let n = self.traffic.sched.itinerary(i).travs.len();
                self.advance(i, n, t, out);
            }
        }
    }

    /// Each fleet's state (its robots' last states).
    fn publish_states(&self, out: &mut Vec<(Topic, Msg)>) {
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

    /// Counts each robot's wait so far; true when some robot waits for traffic.
    fn account_waits(&mut self, t: f64) -> bool {
        for i in 0..self.robots.len() {
            self.account_wait(i, t);
        }
        self.robots.iter().any(|r| r.waiting.is_some())
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
        // A task starting names its phases (the steps its robot was given).
        let phases = match robot.and_then(|r| self.robots.get(r)) {
            Some(r) if event == "started" => Some(self.phase_names(task, &r.steps)),
            _ => None,
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
                phases,
                ..TaskEvent::default()
            }),
        ));
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod world_tests;
