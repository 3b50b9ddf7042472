//! The run report, built by observing the published messages (and ground-truth positions
//! for distances, near misses and motionless robots), so that it sees exactly what RMF
//! would see. Every list is in a deterministic order (map order, first-seen order, or
//! sorted), and every struct serialises its fields in declaration order.

pub mod bound;
mod idle;
pub mod rmf_states;
pub mod timeline;
use crate::msgs::{door_mode, lift_request, lift_state, robot_mode, Msg, TaskWaits, Topic};
use crate::world::RobotTruth;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use timeline::{Buckets, Timeline};

/// Two robots closer than `footprint_a + footprint_b + NEAR_MISS_MARGIN` have a near miss.
pub const NEAR_MISS_MARGIN: f64 = 0.3;
/// An approach ends once the robots are this much farther apart than the near-miss
/// distance again, so that noise around the threshold does not count as several approaches.
pub const NEAR_MISS_HYSTERESIS: f64 = 0.1;
/// Robots whose centres differ in height by less than this are on the same level.
pub const SAME_LEVEL_DZ: f64 = 0.5;
/// A robot with a task that moves less than `STILL_TOLERANCE` for longer than
/// `STUCK_AFTER` seconds is reported as stuck.
pub const STUCK_AFTER: f64 = 300.0;
pub const STILL_TOLERANCE: f64 = 0.1;
/// Stuck or deadlock events of one robot with the same detail less than this apart (s) are
/// one episode.
pub const STUCK_EVENT_GAP: f64 = 30.0;

#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Report {
    /// Sim time at the end of the run (s).
    pub end_time: f64,
    /// In the order tasks were first seen on /task_events.
    pub tasks: Vec<TaskReport>,
    /// In scenario order.
    pub fleets: Vec<FleetReport>,
    /// In spawn order.
    pub robots: Vec<RobotReport>,
    /// The map's doors in map order, then doors only seen in messages (by name).
    pub doors: Vec<DoorReport>,
    /// Same order rule as doors.
    pub lifts: Vec<LiftReport>,
    /// Approaches closer than the near-miss distance but never in contact, by time.
    pub near_misses: Vec<Encounter>,
    /// Approaches closer than the sum of the footprints, by time.
    pub contacts: Vec<Encounter>,
    /// By time.
    pub stuck: Vec<StuckReport>,
    /// Task waits by cause, over every ended task.
    pub waits: WaitTotals,
    /// The place tasks waited at longest (none when no task waited).
    pub bottleneck: Option<Bottleneck>,
    /// An upper bound on the tasks per hour for this building, fleet and task mix, from its
    /// busiest resource, and how close the run came to it (`report::bound`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub throughput: Option<bound::ThroughputBound>,
    /// Utilisation over time of the fleets, doors, lifts and busiest lanes.
    pub timeline: Timeline,
    /// The run was stopped (Ctrl-C) before its end: everything above covers what ran.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub interrupted: bool,
    /// People (`crowd/`), when the map's crowd walked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crowd: Option<crate::crowd::CrowdReport>,
    /// The traffic planner's work.
    pub traffic: TrafficReport,
    /// Warnings about the scenario on this map (codes S0210, S0211), located.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<ScenarioWarning>,
    /// What became of each line of the `requests:` file, in file order.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub requests: Vec<RequestReport>,
}

/// One RMF task API request (`requests:`): the task it became, or why it was refused.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct RequestReport {
    /// Line in the requests file.
    pub line: usize,
    /// When it arrived or, later, its earliest start (s).
    pub at: f64,
    /// The task's id (in `tasks`), when it was accepted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub task_id: Option<String>,
    /// Why it was refused (as RMF would refuse it, or mapc cannot do it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refused: Option<String>,
}

/// What the traffic planner did (`crate::traffic`).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct TrafficReport {
    /// Plans made (SIPP searches), how many found no way at the time, and how many were
    /// taken (installed in the schedule; the others found a way that another robot's
    /// plan beat, or that waited too long).
    pub plans: u64,
    pub plans_failed: u64,
    pub plans_taken: u64,
    /// States the planner expanded per plan taken: median and 99th percentile.
    pub expanded_median: u64,
    pub expanded_p99: u64,
    /// Dependency cycles found in the schedule (the guarantee says 0).
    pub cycles: u64,
    /// Task plans undone because a robot they would have gone before on its way to
    /// parking found no way behind them (the task was then planned around it).
    pub soft_undone: u64,
}

/// A located warning about the scenario.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ScenarioWarning {
    pub code: String,
    pub message: String,
    pub line: u32,
    pub column: u32,
}

#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct TaskReport {
    pub id: String,
    pub category: String,
    pub fleet: String,
    pub robot: String,
    /// Sim times (s) of the `queued`, `assigned`, `started` and `completed`/`failed` events.
    pub requested: Option<f64>,
    pub assigned: Option<f64>,
    pub started: Option<f64>,
    pub finished: Option<f64>,
    /// `completed`, `failed`, `cancelled` or `unfinished` (no end event before the end).
    pub result: String,
    /// The `detail` of the last event that had one (the failure reason for failed tasks).
    pub detail: String,
    /// Where its robot waited, by cause (from the end event; null while unfinished).
    pub waits: Option<TaskWaits>,
    /// When the plan it was (last) assigned with would have finished it (sim time, s).
    pub planned_finish: Option<f64>,
    /// `finished` − `planned_finish` for a completed task (s): what the plan did not foresee
    /// (doors, lifts, workcells, people, replanning); `waits` says where the time went.
    pub delay: Option<f64>,
    /// Its phases in order, from its `started` event on (none for a task that never
    /// started): one per step of its robot, timed by the `phase` events.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub phases: Vec<PhaseReport>,
}

/// A phase of a task: a step its robot does (go to a place, pick up, drop off, clean).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct PhaseReport {
    /// `go_to_place <place>`, `pickup at <place> from <dispenser>`, `dropoff at <place>
    /// into <ingestor>` or `clean <zone>`, as its `phase` event names it.
    pub detail: String,
    /// Sim times (s): when the phase before it ended (the task's start for the first), and
    /// when it ended (the task's end for the phase a failure or cancel ended).
    pub started: Option<f64>,
    pub finished: Option<f64>,
    /// `completed`; `failed` or `cancelled` (the task ended during it); `unfinished` (under
    /// way when the run ended); `pending` (not reached).
    pub result: String,
}

impl TaskReport {
    /// The task's robot ended the phase `detail` at `t`; the next one starts.
    fn phase_done(&mut self, t: f64, detail: &str) {
        match self.phases.iter().position(|p| p.finished.is_none()) {
            Some(k) => {
                let p = &mut self.phases[k];
                if p.started.is_none() {
                    p.started = Some(t);
                }
                p.finished = Some(t);
                p.result = "completed".into();
                if p.detail != detail {
                    p.detail = detail.to_string();
                }
                if let Some(next) = self.phases.get_mut(k + 1) {
                    next.started = Some(t);
                    next.result = "unfinished".into();
                }
            }
            // Phases the `started` event did not name (or more of them).
            None => {
                let started = self.phases.last().and_then(|p| p.finished).or(self.started);
                self.phases.push(PhaseReport {
                    detail: detail.to_string(),
                    started,
                    finished: Some(t),
                    result: "completed".into(),
                });
            }
        }
    }

    /// The task ended at `t` with `result`: so did its phase under way.
    fn phases_end(&mut self, t: f64, result: &str) {
        if let Some(p) = self.phases.iter_mut().find(|p| p.result == "unfinished") {
            p.finished = Some(t);
            p.result = result.to_string();
        }
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct FleetReport {
    pub name: String,
    pub robots: usize,
    /// Robots of the fleet that auto spawn found no home for (a place off every task
    /// route): they stayed in the depot and are not in `robots`.
    #[serde(skip_serializing_if = "is_zero")]
    pub reserve: usize,
    pub tasks_completed: usize,
    pub tasks_failed: usize,
    pub tasks_unfinished: usize,
    /// Completed tasks per hour of simulated time.
    pub throughput_per_hour: f64,
    /// Fraction of robot-time during which a robot had an assigned task (0..1).
    pub utilisation: f64,
    /// Horizontal distance driven by all its robots (m), from ground truth every 0.1 s.
    pub distance_m: f64,
    /// Robot-time its robots stood without a task while a task waited that the fleet went
    /// on to do, or that no robot took (s): under a saturating stream, robots the
    /// building's traffic does not keep busy.
    pub idle_with_work_s: f64,
}

#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct RobotReport {
    pub name: String,
    pub fleet: String,
    pub distance_m: f64,
    /// Time with at least one assigned, unfinished task (s).
    pub busy_s: f64,
    /// Time without a task while a task waited that its fleet went on to do, or that no
    /// robot took (s).
    pub idle_with_work_s: f64,
    /// State of charge at the end of the run (0..1).
    pub battery_soc: f64,
}

/// Waiting times in seconds.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Waits {
    /// Waits that ended (the door opened, the lift arrived with open doors).
    pub count: usize,
    pub total_s: f64,
    pub mean_s: f64,
    pub max_s: f64,
    /// Requests still waiting at the end of the run, or given up before being served.
    pub unserved: usize,
}

impl Waits {
    fn add(&mut self, w: f64) {
        self.count += 1;
        self.total_s += w;
        self.max_s = self.max_s.max(w);
        self.mean_s = self.total_s / self.count as f64;
    }
}

#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct DoorReport {
    pub name: String,
    /// Open requests on /adapter_door_requests, counted once per requester session (from
    /// a requester's first OPEN to its CLOSED; repeated OPENs are one request).
    pub open_requests: usize,
    /// From the session's first OPEN request to the first DoorState OPEN after it.
    pub wait: Waits,
    /// Share of the run the door was not closed (DoorState).
    pub utilisation: f64,
}

#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct LiftReport {
    pub name: String,
    /// Sessions on /adapter_lift_requests (from a session id's first request to its
    /// END_SESSION).
    pub sessions: usize,
    /// Cabin runs: LiftState going from stopped to moving up or down.
    pub trips: usize,
    /// From a session's first request to a LiftState of that session at its destination
    /// floor with the doors open.
    pub wait: Waits,
    /// Share of the run the lift was in someone's session (LiftState `session_id`).
    pub utilisation: f64,
}

/// Task waits summed over every ended task, by cause (s).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct WaitTotals {
    pub traffic_s: f64,
    pub lift_s: f64,
    pub door_s: f64,
    pub workcell_s: f64,
    pub charging_s: f64,
}

/// The place where tasks waited longest in total: what the building saturates on.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Bottleneck {
    /// "lift Lift2", "door L1_door2", "workcell kitchen_dispenser", "traffic at lobby", ...
    pub place: String,
    /// `traffic`, `lift`, `door`, `workcell` or `charging`.
    pub cause: String,
    /// Seconds tasks waited there, and that as a share of all task waiting.
    pub wait_s: f64,
    pub share: f64,
}

#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Encounter {
    /// Spawn order.
    pub robots: [String; 2],
    /// Time of the closest distance (s).
    pub t: f64,
    /// Closest distance between the centres (m).
    pub min_distance_m: f64,
    /// The near-miss distance of this pair: footprints + 0.3 m.
    pub near_miss_distance_m: f64,
    /// The contact distance of this pair: the sum of the footprints.
    pub contact_distance_m: f64,
}

#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct StuckReport {
    pub robot: String,
    pub fleet: String,
    pub task_id: String,
    /// When it got stuck: the event time, or when the robot stopped moving.
    pub t: f64,
    /// The end of the episode as far as seen: the last of its repeated events (the fleet
    /// layer repeats them while the condition lasts), or the last sample without motion.
    pub until: f64,
    /// Events merged into this episode (1 for `no_motion`).
    pub events: usize,
    /// `stuck` or `deadlock` (task events), or `no_motion` (from ground truth).
    pub reason: String,
    pub detail: String,
}

struct RobotAcc {
    name: String,
    fleet: String,
    footprint: f64,
    distance: f64,
    last: Option<(f64, f64)>,
    open_tasks: BTreeSet<String>,
    busy_since: Option<f64>,
    busy: Buckets,
    /// Where and since when the robot has been still (within STILL_TOLERANCE).
    anchor: Option<(f64, f64, f64)>,
    /// The still-since time already reported as stuck, and its entry in `stuck`.
    flagged: Option<(f64, usize)>,
    /// It last reported CHARGING: standing still is then waiting for its battery (the
    /// task's `charging` wait), not being stuck.
    charging: bool,
}

#[derive(Default)]
struct DoorAcc {
    report: DoorReport,
    /// Since when the door has not been closed, and the time summed so far.
    open_since: Option<f64>,
    open: Buckets,
    /// Open sessions by requester: the request time while waiting for the door to open.
    sessions: BTreeMap<String, Option<f64>>,
}

#[derive(Default)]
struct LiftAcc {
    report: LiftReport,
    /// Since when the lift has been in a session, and the time summed so far.
    busy_since: Option<f64>,
    busy: Buckets,
    /// Open sessions: (request time, destination) while waiting, None once served.
    sessions: BTreeMap<String, Option<(f64, String)>>,
    moving: bool,
}

struct Approach {
    min_d: f64,
    t_min: f64,
}

pub struct ReportBuilder {
    fleets: Vec<String>,
    reserve: BTreeMap<String, usize>,
    robots: Vec<RobotAcc>,
    robot_index: BTreeMap<String, usize>,
    tasks: Vec<TaskReport>,
    task_index: BTreeMap<String, usize>,
    doors: Vec<DoorAcc>,
    door_index: BTreeMap<String, usize>,
    lifts: Vec<LiftAcc>,
    lift_index: BTreeMap<String, usize>,
    approaches: BTreeMap<(usize, usize), Approach>,
    near_misses: Vec<Encounter>,
    contacts: Vec<Encounter>,
    stuck: Vec<StuckReport>,
    /// The latest episode of each (robot, event, detail), as an index into `stuck`.
    episodes: BTreeMap<(String, String, String), usize>,
    last_sample: Option<f64>,
    /// Interval of the utilisation timeline (s).
    period: f64,
}

fn slot<T: Default>(
    list: &mut Vec<T>,
    index: &mut BTreeMap<String, usize>,
    name: &str,
    init: impl FnOnce(&mut T),
) -> usize {
    if let Some(&i) = index.get(name) {
        return i;
    }
    let mut v = T::default();
    init(&mut v);
    list.push(v);
    index.insert(name.to_string(), list.len() - 1);
    list.len() - 1
}

impl ReportBuilder {
    pub fn new(
        building: &mapc_ir::Building,
        scenario: &crate::Scenario,
        placement: &crate::fleet::Placement,
    ) -> Self {
        let mut b = ReportBuilder {
            fleets: scenario.fleets.iter().map(|f| f.name.clone()).collect(),
            reserve: placement.reserve.iter().cloned().collect(),
            robots: Vec::new(),
            robot_index: BTreeMap::new(),
            tasks: Vec::new(),
            task_index: BTreeMap::new(),
            doors: Vec::new(),
            door_index: BTreeMap::new(),
            lifts: Vec::new(),
            lift_index: BTreeMap::new(),
            approaches: BTreeMap::new(),
            near_misses: Vec::new(),
            contacts: Vec::new(),
            stuck: Vec::new(),
            episodes: BTreeMap::new(),
            last_sample: None,
            period: timeline::period_for(scenario.duration),
        };
        for r in &placement.robots {
            b.robot_index.insert(r.name.clone(), b.robots.len());
            b.robots.push(RobotAcc {
                name: r.name.clone(),
                fleet: r.fleet.clone(),
                footprint: r.params.footprint,
                distance: 0.0,
                last: None,
                open_tasks: BTreeSet::new(),
                busy_since: None,
                busy: Buckets::new(b.period),
                anchor: None,
                flagged: None,
                charging: false,
            });
        }
        for (_, d) in building.doors.iter() {
            b.door(&d.name);
        }
        for (_, l) in building.lifts.iter() {
            b.lift(&l.name);
        }
        b
    }

    fn door(&mut self, name: &str) -> usize {
        let period = self.period;
        slot(
            &mut self.doors,
            &mut self.door_index,
            name,
            |d: &mut DoorAcc| {
                d.report.name = name.to_string();
                d.open = Buckets::new(period);
            },
        )
    }

    fn lift(&mut self, name: &str) -> usize {
        let period = self.period;
        slot(
            &mut self.lifts,
            &mut self.lift_index,
            name,
            |l: &mut LiftAcc| {
                l.report.name = name.to_string();
                l.busy = Buckets::new(period);
            },
        )
    }

    pub fn observe(&mut self, p: &crate::msgs::Published) {
        match (&p.topic, &p.msg) {
            (_, Msg::RobotState(s)) => {
                if let Some(&i) = self.robot_index.get(&s.name) {
                    self.robots[i].charging = s.mode.mode == robot_mode::CHARGING;
                }
            }
            (Topic::AdapterDoorRequests, Msg::DoorRequest(r)) => {
                let i = self.door(&r.door_name);
                let d = &mut self.doors[i];
                if r.requested_mode.value == door_mode::OPEN {
                    if !d.sessions.contains_key(&r.requester_id) {
                        d.report.open_requests += 1;
                        d.sessions.insert(r.requester_id.clone(), Some(p.t));
                    }
                } else if let Some(pending) = d.sessions.remove(&r.requester_id) {
                    if pending.is_some() {
                        d.report.wait.unserved += 1;
                    }
                }
            }
            (Topic::DoorStates, Msg::DoorState(s)) => {
                let i = self.door(&s.door_name);
                let d = &mut self.doors[i];
                let closed = s.current_mode.value == door_mode::CLOSED;
                match (closed, d.open_since) {
                    (true, Some(t0)) => {
                        d.open.add(t0, p.t);
                        d.open_since = None;
                    }
                    (false, None) => d.open_since = Some(p.t),
                    _ => {}
                }
                if s.current_mode.value != door_mode::OPEN {
                    return;
                }
                for pending in d.sessions.values_mut() {
                    if let Some(t0) = pending.take() {
                        d.report.wait.add(p.t - t0);
                    }
                }
            }
            (Topic::AdapterLiftRequests, Msg::LiftRequest(r)) => {
                let i = self.lift(&r.lift_name);
                let l = &mut self.lifts[i];
                if r.request_type == lift_request::END_SESSION {
                    if let Some(Some(_)) = l.sessions.remove(&r.session_id) {
                        l.report.wait.unserved += 1;
                    }
                } else if !l.sessions.contains_key(&r.session_id) {
                    l.report.sessions += 1;
                    l.sessions.insert(
                        r.session_id.clone(),
                        Some((p.t, r.destination_floor.clone())),
                    );
                }
            }
            (Topic::LiftStates, Msg::LiftState(s)) => {
                let i = self.lift(&s.lift_name);
                let l = &mut self.lifts[i];
                let moving = matches!(
                    s.motion_state,
                    lift_state::MOTION_UP | lift_state::MOTION_DOWN
                );
                if moving && !l.moving {
                    l.report.trips += 1;
                }
                match (s.session_id.is_empty(), l.busy_since) {
                    (true, Some(t0)) => {
                        l.busy.add(t0, p.t);
                        l.busy_since = None;
                    }
                    (false, None) => l.busy_since = Some(p.t),
                    _ => {}
                }
                l.moving = moving;
                if s.door_state == lift_state::DOOR_OPEN {
                    if let Some(pending) = l.sessions.get_mut(&s.session_id) {
                        if pending.as_ref().is_some_and(|(_, f)| *f == s.current_floor) {
                            if let Some((t0, _)) = pending.take() {
                                l.report.wait.add(p.t - t0);
                            }
                        }
                    }
                }
            }
            (Topic::TaskEvents, Msg::TaskEvent(e)) => self.task_event(p.t, e),
            _ => {}
        }
    }

    fn task_event(&mut self, t: f64, e: &crate::msgs::TaskEvent) {
        if matches!(e.event.as_str(), "stuck" | "deadlock") {
            // One episode per robot and condition: repeats of the same event continue it.
            let key = (e.robot.clone(), e.event.clone(), e.detail.clone());
            let episode = self
                .episodes
                .get(&key)
                .and_then(|&i| self.stuck.get_mut(i))
                .filter(|s| t - s.until <= STUCK_EVENT_GAP);
            match episode {
                Some(s) => {
                    s.until = t;
                    s.events += 1;
                }
                None => {
                    self.episodes.insert(key, self.stuck.len());
                    self.stuck.push(StuckReport {
                        robot: e.robot.clone(),
                        fleet: e.fleet.clone(),
                        task_id: e.task_id.clone(),
                        t,
                        until: t,
                        events: 1,
                        reason: e.event.clone(),
                        detail: e.detail.clone(),
                    });
                }
            }
            return;
        }
        let i = slot(&mut self.tasks, &mut self.task_index, &e.task_id, |r| {
            r.id = e.task_id.clone();
            r.result = "unfinished".into();
        });
        if e.event == "phase" {
            self.tasks[i].phase_done(t, &e.detail);
            return;
        }
        let previous_robot = self.tasks[i].robot.clone();
        {
            let task = &mut self.tasks[i];
            if !e.category.is_empty() {
                task.category = e.category.clone();
            }
            if !e.fleet.is_empty() {
                task.fleet = e.fleet.clone();
            }
            if !e.robot.is_empty() {
                task.robot = e.robot.clone();
            }
            if !e.detail.is_empty() {
                task.detail = e.detail.clone();
            }
            if e.waits.is_some() {
                task.waits = e.waits.clone();
            }
            if e.planned_finish.is_some() {
                task.planned_finish = e.planned_finish;
            }
        }
        match e.event.as_str() {
            "queued" => {
                self.tasks[i].requested.get_or_insert(t);
            }
            "assigned" => {
                self.tasks[i].assigned = Some(t);
                // A reassignment frees the previous robot.
                if previous_robot != e.robot {
                    self.release(&previous_robot, &e.task_id, t);
                }
                if let Some(&r) = self.robot_index.get(&e.robot) {
                    let robot = &mut self.robots[r];
                    if robot.open_tasks.is_empty() {
                        robot.busy_since = Some(t);
                    }
                    robot.open_tasks.insert(e.task_id.clone());
                }
            }
            "started" => {
                let task = &mut self.tasks[i];
                task.started.get_or_insert(t);
                if let Some(names) = &e.phases {
                    task.phases = names
                        .iter()
                        .map(|d| PhaseReport {
                            detail: d.clone(),
                            result: "pending".into(),
                            ..PhaseReport::default()
                        })
                        .collect();
                    if let Some(p) = task.phases.first_mut() {
                        p.started = Some(t);
                        p.result = "unfinished".into();
                    }
                }
            }
            "completed" | "failed" | "cancelled" => {
                self.tasks[i].phases_end(t, &e.event);
                self.tasks[i].finished = Some(t);
                self.tasks[i].result = e.event.clone();
                if e.event == "completed" {
                    self.tasks[i].delay = self.tasks[i].planned_finish.map(|p| t - p);
                }
                let robot = self.tasks[i].robot.clone();
                self.release(&robot, &e.task_id, t);
            }
            _ => {}
        }
    }

    fn release(&mut self, robot: &str, task: &str, t: f64) {
        let Some(&r) = self.robot_index.get(robot) else {
            return;
        };
        let robot = &mut self.robots[r];
        if robot.open_tasks.remove(task) && robot.open_tasks.is_empty() {
            if let Some(since) = robot.busy_since.take() {
                robot.busy.add(since, t);
            }
        }
    }

    /// Ground-truth positions (spawn order), about every 0.1 s.
    pub fn sample(&mut self, t: f64, robots: &[RobotTruth]) {
        self.last_sample = Some(t);
        let n = robots.len().min(self.robots.len());
        for (acc, r) in self.robots.iter_mut().zip(robots) {
            if let Some((x, y)) = acc.last {
                acc.distance += (r.x - x).hypot(r.y - y);
            }
            acc.last = Some((r.x, r.y));
            // Motionless with a task for too long (charging does not count).
            match acc.anchor {
                Some((ax, ay, _))
                    if !acc.charging && (r.x - ax).hypot(r.y - ay) <= STILL_TOLERANCE => {}
                _ => acc.anchor = Some((r.x, r.y, t)),
            }
            if let (Some(busy), Some((_, _, still))) = (acc.busy_since, acc.anchor) {
                let since = still.max(busy);
                match acc.flagged {
                    Some((s, i)) if s == since => {
                        if let Some(entry) = self.stuck.get_mut(i) {
                            entry.until = t;
                        }
                    }
                    _ if t - since > STUCK_AFTER => {
                        acc.flagged = Some((since, self.stuck.len()));
                        let task = acc.open_tasks.iter().next().cloned().unwrap_or_default();
                        self.stuck.push(StuckReport {
                            robot: acc.name.clone(),
                            fleet: acc.fleet.clone(),
                            task_id: task.clone(),
                            t: since,
                            until: t,
                            events: 1,
                            reason: "no_motion".into(),
                            detail: format!(
                                "did not move for more than {STUCK_AFTER} s while assigned task `{task}`"
                            ),
                        });
                    }
                    _ => {}
                }
            }
        }
        self.encounters(t, &robots[..n]);
    }

    /// Near misses and contacts: pairs on one level closer than their near-miss distance,
    /// counted once per approach. A sweep over x finds candidate pairs in O(n log n + k).
    fn encounters(&mut self, t: f64, robots: &[RobotTruth]) {
        // Follow open approaches: update the minimum, or end them.
        let mut ended = Vec::new();
        for (&(a, b), ap) in self.approaches.iter_mut() {
            let (Some(ra), Some(rb)) = (robots.get(a), robots.get(b)) else {
                ended.push((a, b));
                continue;
            };
            let d = (ra.x - rb.x).hypot(ra.y - rb.y);
            let near = self.robots[a].footprint + self.robots[b].footprint + NEAR_MISS_MARGIN;
            if (ra.z - rb.z).abs() >= SAME_LEVEL_DZ || d >= near + NEAR_MISS_HYSTERESIS {
                ended.push((a, b));
            } else if d < ap.min_d {
                ap.min_d = d;
                ap.t_min = t;
            }
        }
        for k in ended {
            self.close(k);
        }
        // New approaches.
        let max_near =
            2.0 * self.robots.iter().map(|r| r.footprint).fold(0.0, f64::max) + NEAR_MISS_MARGIN;
        let mut order: Vec<usize> = (0..robots.len()).collect();
        order.sort_by(|&i, &j| robots[i].x.total_cmp(&robots[j].x).then(i.cmp(&j)));
        for (k, &i) in order.iter().enumerate() {
            for &j in &order[k + 1..] {
                let (ri, rj) = (&robots[i], &robots[j]);
                if rj.x - ri.x >= max_near {
                    break;
                }
                if (ri.z - rj.z).abs() >= SAME_LEVEL_DZ {
                    continue;
                }
                let d = (ri.x - rj.x).hypot(ri.y - rj.y);
                let key = (i.min(j), i.max(j));
                if d < self.robots[i].footprint + self.robots[j].footprint + NEAR_MISS_MARGIN
                    && !self.approaches.contains_key(&key)
                {
                    self.approaches.insert(key, Approach { min_d: d, t_min: t });
                }
            }
        }
    }

    fn close(&mut self, key: (usize, usize)) {
        let Some(ap) = self.approaches.remove(&key) else {
            return;
        };
        let (a, b) = (&self.robots[key.0], &self.robots[key.1]);
        let contact = a.footprint + b.footprint;
        let e = Encounter {
            robots: [a.name.clone(), b.name.clone()],
            t: ap.t_min,
            min_distance_m: ap.min_d,
            near_miss_distance_m: contact + NEAR_MISS_MARGIN,
            contact_distance_m: contact,
        };
        if ap.min_d < contact {
            self.contacts.push(e);
        } else {
            self.near_misses.push(e);
        }
    }

    pub fn finish(mut self, t: f64, robots: &[RobotTruth]) -> Report {
        if self.last_sample.is_none_or(|s| s < t) {
            self.sample(t, robots);
        }
        // What is still busy at the end is busy until the end.
        for r in &mut self.robots {
            if let Some(s) = r.busy_since.take() {
                r.busy.add(s, t);
            }
        }
        for d in &mut self.doors {
            if let Some(s) = d.open_since.take() {
                d.open.add(s, t);
            }
        }
        for l in &mut self.lifts {
            if let Some(s) = l.busy_since.take() {
                l.busy.add(s, t);
            }
        }
        let mut timeline = Timeline {
            period_s: self.period,
            series: Vec::new(),
        };
        for name in &self.fleets {
            let mut busy = Buckets::new(self.period);
            let mut n = 0;
            for r in self.robots.iter().filter(|r| &r.fleet == name) {
                busy.merge(&r.busy);
                n += 1;
            }
            timeline.series.push(timeline::Series {
                resource: format!("fleet {name}"),
                busy: busy.shares(t, n as f64),
            });
        }
        for d in &self.doors {
            timeline.series.push(timeline::Series {
                resource: format!("door {}", d.report.name),
                busy: d.open.shares(t, 1.0),
            });
        }
        for l in &self.lifts {
            timeline.series.push(timeline::Series {
                resource: format!("lift {}", l.report.name),
                busy: l.busy.shares(t, 1.0),
            });
        }
        let open: Vec<_> = self.approaches.keys().copied().collect();
        for k in open {
            self.close(k);
        }
        let by_time = |a: &Encounter, b: &Encounter| {
            a.t.total_cmp(&b.t).then_with(|| a.robots.cmp(&b.robots))
        };
        self.near_misses.sort_by(by_time);
        self.contacts.sort_by(by_time);
        self.stuck
            .sort_by(|a, b| a.t.total_cmp(&b.t).then_with(|| a.robot.cmp(&b.robot)));

        let names: Vec<(&str, &str)> = self
            .robots
            .iter()
            .map(|r| (r.name.as_str(), r.fleet.as_str()))
            .collect();
        let idle = idle::idle_with_work(&self.tasks, &names, t);
        let robots: Vec<RobotReport> = self
            .robots
            .iter()
            .map(|r| RobotReport {
                name: r.name.clone(),
                fleet: r.fleet.clone(),
                distance_m: r.distance,
                busy_s: r.busy.total(),
                idle_with_work_s: idle.get(&r.name).copied().unwrap_or(0.0),
                battery_soc: 1.0,
            })
            .collect();
        let fleets = self
            .fleets
            .iter()
            .map(|name| {
                let mine: Vec<&RobotReport> = robots.iter().filter(|r| &r.fleet == name).collect();
                let tasks = self.tasks.iter().filter(|k| &k.fleet == name);
                let count = |res: &str| tasks.clone().filter(|k| k.result == res).count();
                let completed = count("completed");
                let busy: f64 = mine.iter().map(|r| r.busy_s).sum();
                FleetReport {
                    name: name.clone(),
                    robots: mine.len(),
                    reserve: self.reserve.get(name).copied().unwrap_or(0),
                    tasks_completed: completed,
                    tasks_failed: count("failed"),
                    tasks_unfinished: count("unfinished"),
                    throughput_per_hour: if t > 0.0 {
                        completed as f64 / (t / 3600.0)
                    } else {
                        0.0
                    },
                    utilisation: if t > 0.0 && !mine.is_empty() {
                        busy / (t * mine.len() as f64)
                    } else {
                        0.0
                    },
                    distance_m: mine.iter().map(|r| r.distance_m).sum(),
                    idle_with_work_s: mine.iter().map(|r| r.idle_with_work_s).sum(),
                }
            })
            .collect();
        let share = |busy: f64| if t > 0.0 { busy / t } else { 0.0 };
        let doors = self
            .doors
            .into_iter()
            .map(|mut d| {
                d.report.wait.unserved += d.sessions.values().filter(|p| p.is_some()).count();
                d.report.utilisation = share(d.open.total());
                d.report
            })
            .collect();
        let lifts = self
            .lifts
            .into_iter()
            .map(|mut l| {
                l.report.wait.unserved += l.sessions.values().filter(|p| p.is_some()).count();
                l.report.utilisation = share(l.busy.total());
                l.report
            })
            .collect();
        let (waits, bottleneck) = bottleneck(&self.tasks);
        Report {
            end_time: t,
            tasks: self.tasks,
            fleets,
            robots,
            doors,
            lifts,
            near_misses: self.near_misses,
            contacts: self.contacts,
            stuck: self.stuck,
            waits,
            bottleneck,
            throughput: None,
            timeline,
            interrupted: false,
            crowd: None,
            traffic: TrafficReport::default(),
            warnings: Vec::new(),
            requests: Vec::new(),
        }
    }
}

/// Task waits by cause, and the place waited at longest over all tasks (ties by name).
fn bottleneck(tasks: &[TaskReport]) -> (WaitTotals, Option<Bottleneck>) {
    let mut totals = WaitTotals::default();
    let mut places: BTreeMap<&str, f64> = BTreeMap::new();
    for w in tasks.iter().filter_map(|k| k.waits.as_ref()) {
        totals.traffic_s += w.traffic_s;
        totals.lift_s += w.lift_s;
        totals.door_s += w.door_s;
        totals.workcell_s += w.workcell_s;
        totals.charging_s += w.charging_s;
        for (p, s) in &w.places {
            *places.entry(p).or_insert(0.0) += s;
        }
    }
    let all =
        totals.traffic_s + totals.lift_s + totals.door_s + totals.workcell_s + totals.charging_s;
    let top = places
        .iter()
        .max_by(|a, b| a.1.total_cmp(b.1).then_with(|| b.0.cmp(a.0)))
        .filter(|(_, &s)| s > 0.0)
        .map(|(p, &s)| Bottleneck {
            place: p.to_string(),
            cause: p.split(' ').next().unwrap_or_default().to_string(),
            wait_s: s,
            share: if all > 0.0 { s / all } else { 0.0 },
        });
    (totals, top)
}

fn hms(t: f64) -> String {
    let s = t.max(0.0).round() as u64;
    match (s / 3600, s / 60 % 60, s % 60) {
        (0, 0, s) => format!("{s}s"),
        (0, m, s) => format!("{m}min {s}s"),
        (h, m, s) => format!("{h}h {m}min {s}s"),
    }
}

impl Report {
    /// A short human-readable summary (a few lines, for the terminal).
    pub fn summary(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let count = |r: &str| self.tasks.iter().filter(|k| k.result == r).count();
        let _ = writeln!(
            s,
            "simulated {} ({:.2} s){}",
            hms(self.end_time),
            self.end_time,
            if self.interrupted {
                ", interrupted"
            } else {
                ""
            }
        );
        let _ = writeln!(
            s,
            "tasks: {} seen, {} completed, {} failed, {} unfinished",
            self.tasks.len(),
            count("completed"),
            count("failed") + count("cancelled"),
            count("unfinished")
        );
        for f in &self.fleets {
            let reserve = if f.reserve > 0 {
                format!(" (+{} in reserve: no home on the floor)", f.reserve)
            } else {
                String::new()
            };
            // Robots idle on average while work waited: the ones the traffic did not take.
            let idle = if self.end_time > 0.0 {
                f.idle_with_work_s / self.end_time
            } else {
                0.0
            };
            let idle = if idle >= 0.05 {
                format!(", {idle:.1} robot(s) idle on average while tasks waited")
            } else {
                String::new()
            };
            let _ = writeln!(
                s,
                "  fleet {}: {} robot(s){reserve}, {} completed, {} failed, {:.2} tasks/h, utilisation {:.1} %{idle}, {:.1} m driven",
                f.name,
                f.robots,
                f.tasks_completed,
                f.tasks_failed,
                f.throughput_per_hour,
                100.0 * f.utilisation,
                f.distance_m
            );
        }
        if let Some(c) = &self.crowd {
            let _ = writeln!(
                s,
                "crowd: {} people, {:.0} m walked on average at {:.2} m/s, {} near miss(es) and {} contact(s) with robots",
                c.humans, c.walked_m.mean, c.speed_m_s.mean, c.near_misses, c.contacts
            );
            for f in &c.compare {
                let _ = writeln!(
                    s,
                    "  fleet {}: {} task(s) completed ({} without people), mean task {} s ({} s without people)",
                    f.fleet,
                    f.completed,
                    f.completed_without_crowd,
                    f.mean_task_s.map_or("-".into(), |x| format!("{x:.1}")),
                    f.mean_task_s_without_crowd.map_or("-".into(), |x| format!("{x:.1}"))
                );
            }
        }
        let busy_doors: Vec<&DoorReport> =
            self.doors.iter().filter(|d| d.open_requests > 0).collect();
        let _ = writeln!(
            s,
            "doors: {} open request(s) at {} of {} door(s)",
            busy_doors.iter().map(|d| d.open_requests).sum::<usize>(),
            busy_doors.len(),
            self.doors.len()
        );
        for d in busy_doors {
            let _ = writeln!(
                s,
                "  door {}: {} request(s), wait mean {:.1} s, max {:.1} s, open {:.0} %{}",
                d.name,
                d.open_requests,
                d.wait.mean_s,
                d.wait.max_s,
                100.0 * d.utilisation,
                unserved(d.wait.unserved)
            );
        }
        for l in self.lifts.iter().filter(|l| l.sessions > 0 || l.trips > 0) {
            let _ = writeln!(
                s,
                "  lift {}: {} session(s), {} trip(s), wait mean {:.1} s, max {:.1} s, busy {:.0} %{}",
                l.name,
                l.sessions,
                l.trips,
                l.wait.mean_s,
                l.wait.max_s,
                100.0 * l.utilisation,
                unserved(l.wait.unserved)
            );
        }
        let w = &self.waits;
        let _ = writeln!(
            s,
            "task waits: traffic {}, lift {}, door {}, workcell {}, charging {}",
            hms(w.traffic_s),
            hms(w.lift_s),
            hms(w.door_s),
            hms(w.workcell_s),
            hms(w.charging_s)
        );
        if let Some(b) = &self.bottleneck {
            let _ = writeln!(
                s,
                "bottleneck: {} ({} of waiting there, {:.0} % of all task waits)",
                b.place,
                hms(b.wait_s),
                100.0 * b.share
            );
        }
        if let Some(b) = &self.throughput {
            let _ = write!(
                s,
                "throughput bound: {:.1} tasks/h, set by {}",
                b.tasks_per_hour, b.limited_by
            );
            if let Some(r) = b.resources.iter().find(|r| r.resource == b.limited_by) {
                let _ = write!(
                    s,
                    " ({} × 3600 s / {:.1} s a task at least)",
                    r.capacity, r.demand_s
                );
            }
            let _ = writeln!(
                s,
                "; this run {:.1} tasks/h ({:.0} % of it)",
                b.achieved_per_hour,
                100.0 * b.share
            );
        }
        let closest = self
            .near_misses
            .iter()
            .chain(&self.contacts)
            .min_by(|a, b| a.min_distance_m.total_cmp(&b.min_distance_m));
        let _ = write!(
            s,
            "near misses: {}, contacts: {}",
            self.near_misses.len(),
            self.contacts.len()
        );
        if let Some(c) = closest {
            let _ = write!(
                s,
                " (closest {:.2} m: {} and {} at {})",
                c.min_distance_m,
                c.robots[0],
                c.robots[1],
                hms(c.t)
            );
        }
        let _ = writeln!(s);
        // Resolved: the robot moved on (or the events stopped) well before the end.
        let unresolved = self
            .stuck
            .iter()
            .filter(|k| k.until >= self.end_time - STUCK_AFTER)
            .count();
        let _ = writeln!(
            s,
            "stuck episodes: {} ({} resolved, {unresolved} unresolved at the end)",
            self.stuck.len(),
            self.stuck.len() - unresolved
        );
        const SHOWN: usize = 10;
        for k in self.stuck.iter().take(SHOWN) {
            let _ = writeln!(
                s,
                "  {} {}..{}: {} ({})",
                k.robot,
                hms(k.t),
                hms(k.until),
                k.reason,
                k.detail
            );
        }
        if self.stuck.len() > SHOWN {
            let _ = writeln!(s, "  ... {} more in the report", self.stuck.len() - SHOWN);
        }
        s
    }
}

fn unserved(n: usize) -> String {
    if n == 0 {
        String::new()
    } else {
        format!(", {n} unserved")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fleet::Placement;
    use crate::msgs::{
        DoorMode, DoorRequest, DoorState, LiftRequest, LiftState, Published, RobotMode, RobotState,
        TaskEvent, Time, WaitCause,
    };
    use crate::params::RobotParams;
    use crate::world::RobotSpawn;

    const CLINIC: &str = include_str!("../../fixtures/two_level_clinic.building.yaml");

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
}

#[cfg(test)]
mod sweep_tests {
    use super::*;
    use crate::fleet::Placement;
    use crate::params::RobotParams;
    use crate::world::RobotSpawn;

    /// The sweep finds exactly the approaches that checking every pair finds: robots doing
    /// random walks in a small room, some on a second level, with mixed footprints.
    #[test]
    fn sweep_matches_all_pairs() {
        let parsed = mapc_frontend::parse_str(
            "clinic",
            include_str!("../../fixtures/two_level_clinic.building.yaml"),
        );
        let building = parsed.building.unwrap();
        let n = 30;
        let fps: Vec<f64> = (0..n).map(|i| 0.2 + 0.05 * (i % 5) as f64).collect();
        let text = format!("duration: 1h\nfleets: [{{name: f, robot: TinyRobot, count: {n}}}]\n");
        let (scenario, _) =
            crate::scenario::parse(mapc_ir::FileId(0), &text, std::path::Path::new("."));
        let placement = Placement {
            robots: (0..n)
                .map(|i| RobotSpawn {
                    name: format!("r{i:02}"),
                    fleet: "f".into(),
                    params: RobotParams {
                        footprint: fps[i],
                        ..RobotParams::default()
                    },
                    x: 0.0,
                    y: 0.0,
                    yaw: 0.0,
                    level: building.reference_level,
                })
                .collect(),
            workcells: Vec::new(),
            reserve: Vec::new(),
            warnings: Vec::new(),
            parks: Default::default(),
            finishes: Vec::new(),
        };
        let mut b = ReportBuilder::new(&building, &scenario.unwrap(), &placement);
        let mut rng = fastrand::Rng::with_seed(11);
        let mut pos: Vec<(f64, f64, f64)> = (0..n)
            .map(|i| {
                let z = if i % 7 == 0 { 4.0 } else { 0.0 };
                (rng.f64() * 8.0, rng.f64() * 8.0, z)
            })
            .collect();
        // Reference: every pair, same rules (open below the near distance, close at near +
        // hysteresis or on another level), min distance per approach.
        let mut open: BTreeMap<(usize, usize), f64> = BTreeMap::new();
        let mut closed: Vec<((usize, usize), f64)> = Vec::new();
        let mut t = 0.0;
        for _ in 0..600 {
            for p in pos.iter_mut() {
                p.0 = (p.0 + (rng.f64() - 0.5) * 0.3).clamp(0.0, 8.0);
                p.1 = (p.1 + (rng.f64() - 0.5) * 0.3).clamp(0.0, 8.0);
            }
            let truth: Vec<RobotTruth> = pos
                .iter()
                .map(|&(x, y, z)| RobotTruth {
                    x,
                    y,
                    z,
                    yaw: 0.0,
                    v: 0.0,
                    footprint: 0.0,
                })
                .collect();
            b.sample(t, &truth);
            for i in 0..n {
                for j in i + 1..n {
                    let (a, c) = (pos[i], pos[j]);
                    let d = (a.0 - c.0).hypot(a.1 - c.1);
                    let near = fps[i] + fps[j] + NEAR_MISS_MARGIN;
                    let level = (a.2 - c.2).abs() < SAME_LEVEL_DZ;
                    match open.get_mut(&(i, j)) {
                        Some(m) => {
                            if !level || d >= near + NEAR_MISS_HYSTERESIS {
                                closed.push(((i, j), *m));
                                open.remove(&(i, j));
                            } else if d < *m {
                                *m = d;
                            }
                        }
                        None if level && d < near => {
                            open.insert((i, j), d);
                        }
                        None => {}
                    }
                }
            }
            t += 0.1;
        }
        closed.extend(open);
        let report = b.finish(t - 0.1, &[]);
        let mut got: Vec<(String, String, f64)> = report
            .near_misses
            .iter()
            .chain(&report.contacts)
            .map(|e| (e.robots[0].clone(), e.robots[1].clone(), e.min_distance_m))
            .collect();
        let mut want: Vec<(String, String, f64)> = closed
            .iter()
            .map(|&((i, j), m)| (format!("r{i:02}"), format!("r{j:02}"), m))
            .collect();
        let order = |a: &(String, String, f64), b: &(String, String, f64)| {
            (&a.0, &a.1).cmp(&(&b.0, &b.1)).then(a.2.total_cmp(&b.2))
        };
        got.sort_by(order);
        want.sort_by(order);
        assert!(
            want.len() > 20,
            "too few approaches to test: {}",
            want.len()
        );
        assert_eq!(got, want);
        let contacts = closed
            .iter()
            .filter(|&&((i, j), m)| m < fps[i] + fps[j])
            .count();
        assert_eq!(report.contacts.len(), contacts);
    }
}
