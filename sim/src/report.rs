//! The run report, built by observing the published messages (and ground-truth positions
//! for distances, near misses and motionless robots), so that it sees exactly what RMF
//! would see. Every list is in a deterministic order (map order, first-seen order, or
//! sorted), and every struct serialises its fields in declaration order.

pub mod bound;
mod builder;
mod idle;
pub mod rmf_states;
mod summary;
pub mod timeline;
use crate::msgs::{door_mode, lift_request, lift_state, robot_mode, Msg, TaskWaits, Topic};
use crate::world::RobotTruth;
pub use builder::ReportBuilder;
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

#[cfg(test)]
mod tests;

#[cfg(test)]
mod sweep_tests;
