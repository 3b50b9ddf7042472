//! The dispatcher: a task goes to the robot that, planned against the schedule, gets to
//! its first place first.
//!
//! Tasks wait in one queue, oldest first, until a robot that stands idle takes one, as in
//! Token Passing (Ma et al. 2017): the robot's whole task (every place, the work there,
//! then a parking vertex) is planned when it is assigned, so a robot holding a task
//! always has a plan. The nearest idle robots (free-flow time) are planned for, and the
//! one whose plan arrives first takes the task. A plan that would wait long for traffic
//! is not taken, however long the task has waited: robots stay parked rather than queue
//! in the corridors, so a bigger fleet does not jam a building that a smaller one serves.
//! (A task that has waited long used to accept plans that wait longer: under a saturating
//! stream nearly every task had, so the bound was loosest where traffic was densest;
//! BENCHMARKS.md has the figures.)
//! Such a task is not planned again for the same robot until its plan could first fit
//! (its excess wait, at most `MAX_BACKOFF`), whatever the task's other candidates found:
//! with a saturating stream hundreds of tasks wait, and planning each again at every round
//! cost 95 % of a run. Nor is the same plan (robot, start, places) made for another task
//! meanwhile, and a task none of whose candidates may be planned for sleeps until one may
//! or a robot becomes free: rounds pass it by at no cost and look further down the queue.
//! (Rounds looked at the 64 oldest tasks only, and under a saturating stream those were the
//! tasks every robot had been refused for: robots stood idle while the tasks they could do
//! waited behind them.)
//!
//! Busy robots bid too, as RMF's dispatcher queues a task after a robot's current one,
//! those of every fleet that may do the task (a fleet with no robot free did not bid, and
//! two fleets on a corridor between two rooms completed half what one robot did): a
//! task that a busy robot gets to (when its itinerary has it done, then free flow) before
//! any free robot could, or before the best free robot's plan with its waits for traffic
//! counted once more, waits for that robot; a robot given a task in a round bids so for
//! the tasks after it in that round. Only free robots were looked at before, so a bigger
//! fleet sent a robot parked far away where a smaller one's robot, about to finish next
//! door, would have taken the task: on the demo maps and generated buildings, fleets
//! completed 22-24 % more with the bids (BENCHMARKS.md). A free robot
//! that gets there sooner still yields to the busy one when it gains the task less time
//! than the longer drive it makes: under a saturating stream the fleet's throughput is its
//! robot-time, and a drive across the building also loads its corridors (of the 95 %
//! rule's breaches on the generated buildings and warehouses, all but one went).

use super::*;
use crate::traffic::sipp::{Delay, Plan};

/// States the dispatcher's searches may expand per simulated second, and at most at once:
/// its computing budget, as a real dispatcher has one (the League of Robot Runners plans
/// once a second). The saturated airport never reaches it (its runs are the same without
/// it); in the 1,000-robot warehouse, where one search expands thousands of states (one
/// that finds no way, up to the planner's bound), it bounds the work: rounds come with
/// every task requested, and without it 10 simulated minutes took 593 s (41 s with it).
const WORK_PER_S: f64 = 50_000.0;
const WORK_MAX: f64 = 500_000.0;
/// Robots planned for per task (the nearest by free-flow time).
const CANDIDATES: usize = 3;
/// Plans tried per dispatch round, and tasks looked at (bound the work of a round).
const PLANS_PER_ROUND: usize = 32;
const SCAN_PER_ROUND: usize = 64;
/// A plan waiting longer than this for traffic (s, summed up to its last place, but for a
/// wait where the robot stands idle before it leaves) is not taken. (It was 50 s: on every
/// set of long runs, generated, demo and public buildings and other task streams, fleets
/// completed more with 25 s, 2-8 %, and a breach of the rule went: the waits are held
/// where the robot stands, often a task place on a corridor. The saturated airport
/// completes 5 % less, and with 10 s a scaling scenario broke the rule. BENCHMARKS.md.)
const MAX_PLANNED_WAIT: f64 = 25.0;
/// The share of a plan's length (to its last place) it may wait on top of that.
const WAIT_SHARE: f64 = 0.25;
/// How late a task plan may reach its last place for the search to look for it: twice the
/// delay over its free-flow time F that a plan on its free-flow route may wait (W ≤ M +
/// s (F + W) is W ≤ (M + s F) / (1 - s), with M = `MAX_PLANNED_WAIT`, s = `WAIT_SHARE`).
/// A plan later than that waits past its bound by at least M + s F unless it drives a
/// long detour (detours and turns count as delay here, not as waits): searched to its end
/// only to be refused, such plans were most of the saturated airport's searching. The
/// robot is then backed off that task for `MAX_BACKOFF`.
const SEARCH_DELAY: Delay = Delay {
    fixed: 2.0 * MAX_PLANNED_WAIT / (1.0 - WAIT_SHARE),
    share: 2.0 * WAIT_SHARE / (1.0 - WAIT_SHARE),
};
/// No plan a task takes stands still for longer than this in one place (s), well under
/// the 300 s after which a robot with a task counts as stuck (`report::STUCK_AFTER`):
/// the others' delays lengthen planned waits. (It was 180 s: with busy robots bidding,
/// the saturated airport's corridors were fuller, and a 180 s wait at a place grew to
/// 476 s behind four delayed robots.)
const LONGEST_WAIT: f64 = 120.0;
/// Dispatch is tried again this often (s) while tasks wait (and sooner when a robot
/// becomes free or a task comes).
const DISPATCH_EVERY: f64 = 5.0;
/// Least time (s) between a round and one that a task joining a queue with tasks
/// waiting brings forward (RMF's dispatcher waits 2 s for bids on every task).
const ROUND_GAP: f64 = 1.0;
/// Robots in a waiting task's way are asked to make room at most this often (s).
const DISPLACE_EVERY: f64 = 5.0;
/// A robot that found no way to a task is planned for it again after this long (s): others
/// may make room meanwhile (robots in the way are asked as often, `DISPLACE_EVERY`), and
/// planning it again at every round (each second while tasks come) was most of a run.
const NO_WAY_BACKOFF: f64 = 5.0;
/// A task whose plans all waited too long is planned for the same robots again after at
/// most this long (s), even if their excess wait was longer (the others may have got
/// ahead of their plans meanwhile).
const MAX_BACKOFF: f64 = 60.0;

/// A free robot: its index, the vertex it plans from, and how long until it may leave
/// (s).
type Free = (usize, usize, f64);

/// A busy robot: its index, the last place of its task, and how long until it is done
/// there (s).
type Busy = (usize, usize, f64);

/// Free-flow time tables to places kept (each a float per vertex): at least this many, and
/// as many as fit in `ETA_TABLE_FLOATS` (a warehouse's thousand racks each made again and
/// again when all were dropped at 512).
const ETA_TABLES: usize = 512;
const ETA_TABLE_FLOATS: usize = 16 << 20;

/// A task in the queue.
struct Pending {
    task: usize,
    /// (fleet, the task's steps for it) of every fleet that may do the task.
    steps: Vec<(usize, Vec<Step>)>,
    /// The only robot that may do it (a robot task).
    robot: Option<usize>,
    /// RMF's priority: the queue keeps higher ones first.
    priority: u64,
    /// When robots were last asked to make room for it.
    displaced_at: f64,
    /// Robots whose plans for it waited too long, each with when planning for it again
    /// may first succeed (see [`Fleets::dispatch`]).
    backoff: Vec<(usize, f64)>,
    /// Every robot it was looked at for is in `backoff`: until when, and
    /// [`Dispatcher::freed`] then. Rounds pass it by until then unless a robot became free
    /// since (without looking for its nearest robots: with thousands of tasks queued,
    /// that was most of a round).
    asleep: Option<(f64, u64)>,
    /// Its plans keep clear of the others' ways to parking too (one that went before them
    /// was undone: see [`Fleets::install`]).
    hard: bool,
    /// It waits for a busy robot that gets there before the free robots' plans did: see
    /// [`Deferred`].
    deferred: Option<Deferred>,
    /// A go-to-place: done the moment a robot standing at its place takes it
    /// ([`Fleets::done_where_they_stand`]).
    go_to: bool,
}

/// A task that waits for a busy robot, its free robots' plans made and beaten: when the
/// best of them would have got there (counting its waits for traffic once more), and
/// the robots planned for. Until the busy robot's bid stops beating that, or a robot not
/// planned for could (by free flow) beat it, planning the free robots again cannot change
/// the choice: their plans only got later as the schedule filled. (Planned again at every
/// round where some robot became free, then dropped, the saturated airport's free robots
/// cost 2.5 times as much planning per decision.)
struct Deferred {
    beat: f64,
    planned: Vec<usize>,
}

impl Deferred {
    /// At `t`, with the busy robot's bid `after` s away and `near` the free robots (free
    /// flow time, robot, fleet), nearest first: the bid still beats the best plan made,
    /// and no robot among those a round would plan for that was not planned for could.
    fn holds(&self, t: f64, after: f64, near: &[(f64, usize, usize)]) -> bool {
        t + after < self.beat
            && near
                .iter()
                .take(CANDIDATES)
                .all(|c| self.planned.contains(&c.1) || t + c.0 >= self.beat)
    }
}

/// The dispatcher's state: the tasks still to be requested, the queue of tasks no robot
/// has taken yet, and when it runs next.
///
/// Invariant: the queue keeps tasks oldest first within a priority and a higher priority
/// before every lower one; a task is in it from its request until a robot takes it or it
/// is cancelled; while it is not empty a round is due within `DISPATCH_EVERY` s (at once
/// when a robot becomes free or a task comes to an empty queue, within `ROUND_GAP` of the
/// last round when one comes to a queue with tasks waiting). Guarantees (with [`Fleets::dispatch`]):
/// tasks are looked at oldest first, each goes to the free robot whose whole-task plan
/// arrives first, a plan that would wait long for traffic is never taken, and a robot
/// whose plan for a task waited too long (or found no way) is not planned for it, nor for
/// the same places from the same start, again until its backoff ends (its excess wait, at
/// most `MAX_BACKOFF`; `NO_WAY_BACKOFF`).
pub(super) struct Dispatcher {
    /// (request time, source order, kind, fleet) of tasks not yet requested, sorted.
    upcoming: VecDeque<(f64, usize, NewTask)>,
    /// Tasks no robot has taken yet, oldest first.
    pending: VecDeque<Pending>,
    /// How many of them are go-to-places (`Pending::go_to`): with none, a round need not
    /// look through the queue for them (a saturating stream of loops queues tens of
    /// thousands, and that look was a twentieth of the saturated airport).
    go_tos: usize,
    /// When the dispatcher runs next, and when it last ran (a round).
    next_dispatch: f64,
    last_round: f64,
    /// Per category, the tasks requested so far (their ids count on).
    counters: BTreeMap<TaskCategory, usize>,
    /// Per (graph slot, speed, place): free-flow times to the place from every vertex.
    eta_tables: BTreeMap<(usize, u64, usize), Vec<f64>>,
    /// The robots free in the last round, and how many times a round found one free that
    /// was not in the round before.
    was_free: Vec<bool>,
    freed: u64,
    /// States the searches may still expand (refilled over simulated time: `WORK_PER_S`),
    /// and when it was last refilled.
    work: f64,
    work_at: f64,
    /// Plans refused (or that found no way, or were undone), by what they were a plan of:
    /// until when planning the same again cannot succeed, and why.
    same: BTreeMap<Same, (f64, Refused)>,
}

/// Why a plan was not taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Refused {
    /// It found no way at any time.
    NoWay,
    /// It would wait too long for traffic.
    Late,
    /// It went through another robot's way to parking, and that robot found no way behind
    /// it.
    Undone,
}

/// The best plan for a task so far: when it gets to the first place, its robot and the
/// task's steps for it, the plan and where it starts (after `keep` traversals, at `t0`),
/// whether it goes through soft spans, and what it is a plan of.
struct Best {
    arrive: f64,
    /// Its robot's free-flow time to the first place (s).
    eta: f64,
    robot: usize,
    steps: Vec<Step>,
    plan: Plan,
    keep: usize,
    t0: f64,
    soft: bool,
    same: Same,
}

/// What a plan is a plan of: the robot, where it starts, whether it may go through the
/// others' soft spans, where it stays, and its places with the work there (bits).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Same(usize, usize, bool, Option<usize>, Vec<(usize, u64)>);

impl Same {
    fn new(
        robot: usize,
        from: usize,
        soft: bool,
        stay: Option<usize>,
        goals: &[(usize, f64)],
    ) -> Same {
        let goals = goals.iter().map(|&(g, w)| (g, w.to_bits())).collect();
        Same(robot, from, soft, stay, goals)
    }
}

impl Dispatcher {
    /// The tasks to come, `upcoming` sorted by (request time, source order).
    pub(super) fn new(upcoming: Vec<(f64, usize, NewTask)>) -> Dispatcher {
        Dispatcher {
            upcoming: upcoming.into(),
            pending: VecDeque::new(),
            go_tos: 0,
            next_dispatch: f64::INFINITY,
            last_round: f64::NEG_INFINITY,
            counters: BTreeMap::new(),
            eta_tables: BTreeMap::new(),
            was_free: Vec::new(),
            freed: 0,
            work: WORK_MAX,
            work_at: 0.0,
            same: BTreeMap::new(),
        }
    }

    /// The next task requested by `t`, if any (in request order).
    pub(super) fn take_request(&mut self, t: f64) -> Option<NewTask> {
        if self.upcoming.front().is_some_and(|u| u.0 <= t) {
            self.upcoming.pop_front().map(|(_, _, new)| new)
        } else {
            None
        }
    }

    /// No task is still to be requested.
    pub(super) fn requested_all(&self) -> bool {
        self.upcoming.is_empty()
    }

    /// When the dispatcher runs next or the next task is requested, whichever is first.
    pub(super) fn next_at(&self) -> f64 {
        let mut next = self.next_dispatch;
        if let Some(u) = self.upcoming.front() {
            next = next.min(u.0);
        }
        next
    }

    /// A round is due at `t` (a robot became free).
    pub(super) fn wake(&mut self, t: f64) {
        self.next_dispatch = self.next_dispatch.min(t);
    }

    /// The id of a new task of `category`: its category and how many came before it.
    fn new_id(&mut self, category: TaskCategory) -> String {
        let n = self.counters.entry(category).or_insert(0);
        let id = format!("{}_{}", category.as_str(), *n);
        *n += 1;
        id
    }

    /// Queues `p` at `t`: oldest first within a priority; a higher priority before every
    /// lower one. A round is due at once (into an empty queue) or soon.
    fn enqueue(&mut self, p: Pending, t: f64) {
        // Into a queue with tasks waiting, a round comes `ROUND_GAP` after the last one
        // at the soonest: the robots free now were looked at for the tasks before it, and
        // a saturating stream would otherwise start a round (and retime the whole
        // schedule) for every task it brings.
        let due = if self.pending.is_empty() {
            t
        } else {
            t.max(self.last_round + ROUND_GAP)
        };
        // Sorted by priority (a saturating stream queues tens of thousands: a scan for
        // each request was a twentieth of the saturated airport).
        let at = self.pending.partition_point(|q| q.priority >= p.priority);
        self.insert(at, p);
        self.next_dispatch = self.next_dispatch.min(due);
    }

    /// Puts `p` at index `at` of the queue.
    fn insert(&mut self, at: usize, p: Pending) {
        self.go_tos += usize::from(p.go_to);
        self.pending.insert(at, p);
    }

    /// Takes the task at index `k` out of the queue.
    fn remove(&mut self, k: usize) -> Option<Pending> {
        let p = self.pending.remove(k)?;
        self.go_tos -= usize::from(p.go_to);
        Some(p)
    }

    /// Takes task `ti` out of the queue. False when it was not queued.
    pub(super) fn withdraw(&mut self, ti: usize) -> bool {
        match self.pending.iter().position(|p| p.task == ti) {
            Some(k) => {
                self.remove(k);
                true
            }
            None => false,
        }
    }

    /// Free-flow times (s) from every vertex to `goal` for `fleet`'s robots: one table per
    /// place, kept (a table per robot would cost a search of the whole graph per free robot
    /// and round: with 1,000 robots on 10,000 waypoints, most of a run).
    fn eta_table(&mut self, nav: &Nav, fleet: &FleetRt, goal: usize) -> &[f64] {
        let key = (fleet.slot, fleet.speed.to_bits(), goal);
        if !self.eta_tables.contains_key(&key)
            && self.eta_tables.len() >= ETA_TABLES.max(ETA_TABLE_FLOATS / nav.vertices.len().max(1))
        {
            self.eta_tables.clear();
        }
        self.eta_tables
            .entry(key)
            .or_insert_with(|| nav.times_to(fleet.slot, goal, fleet.speed))
    }
}

impl Fleets {
    pub(super) fn request_task(&mut self, t: f64, new: NewTask, out: &mut Vec<(Topic, Msg)>) {
        let NewTask {
            kind,
            fleet,
            robot,
            priority,
        } = new;
        let category = kind.category();
        let id = self.dispatcher.new_id(category);
        let ti = self.tasks.len();
        self.tasks.push(Task {
            id,
            category,
            kind,
            fleet: fleet.clone(),
            ended: false,
        });
        self.event(t, ti, "queued", None, String::new(), out);
        // A robot task: that robot of the task's fleet, or nobody.
        let only = robot.as_ref().map(|name| {
            self.by_name.get(name).copied().filter(|&i| {
                fleet
                    .as_ref()
                    .is_none_or(|f| self.fleets[self.robots[i].fleet].name == *f)
            })
        });
        if let (Some(None), Some(name)) = (only, &robot) {
            self.tasks[ti].ended = true;
            let detail = format!("no robot named `{name}` in the task's fleet");
            self.event(t, ti, "failed", None, detail, out);
            return;
        }
        let steps: Vec<(usize, Vec<Step>)> = self
            .fleets_for(ti)
            .into_iter()
            .filter(|(fi, _)| only.flatten().is_none_or(|i| self.robots[i].fleet == *fi))
            .collect();
        if steps.is_empty() {
            self.tasks[ti].ended = true;
            self.event(
                t,
                ti,
                "failed",
                None,
                "no robot can reach the task".into(),
                out,
            );
            return;
        }
        let p = Pending {
            task: ti,
            steps,
            robot: only.flatten(),
            priority,
            displaced_at: f64::NEG_INFINITY,
            backoff: Vec::new(),
            asleep: None,
            hard: false,
            deferred: None,
            go_to: matches!(self.tasks[ti].kind, TaskKind::GoToPlace { .. }),
        };
        self.dispatcher.enqueue(p, t);
    }

    /// (fleet, its steps for the task) of every fleet that may do task `ti` and has a
    /// robot that can reach the task's places in order.
    pub(super) fn fleets_for(&self, ti: usize) -> Vec<(usize, Vec<Step>)> {
        let task = &self.tasks[ti];
        let mut out = Vec::new();
        for (fi, f) in self.fleets.iter().enumerate() {
            if task.fleet.as_ref().is_some_and(|n| *n != f.name)
                || !(f.kinds.is_empty() || f.kinds.contains(&task.category))
            {
                continue;
            }
            let Some(steps) = self.expand(fi, &task.kind) else {
                continue;
            };
            // The first place from some robot, then each place from the one before.
            let starts: Vec<usize> = f
                .robots
                .iter()
                .map(|&ri| self.traffic.sched.itinerary(ri).at)
                .collect();
            let goals: Vec<usize> = steps
                .iter()
                .filter_map(|s| match s {
                    Step::GoTo(v) => Some(*v),
                    _ => None,
                })
                .collect();
            let reaches = goals
                .first()
                .is_some_and(|&g| self.nav.reachable_from_any(f.slot, &starts, g))
                && goals
                    .windows(2)
                    .all(|w| self.nav.times_reachable(f.slot, w[0], w[1]));
            if reaches {
                out.push((fi, steps));
            }
        }
        out
    }

    /// Whether robot `i` may take a task now: idle, and not at a door or lift.
    fn free(&self, i: usize) -> bool {
        let r = &self.robots[i];
        r.idle() && r.gate == Gate::None
    }

    /// Where robot `i` plans from: where the traversals it was sent along end, and when
    /// (its first traversals still to be kept).
    fn plan_start(&self, i: usize, t: f64) -> (usize, usize, f64) {
        let keep = self.kept(i);
        let it = self.traffic.sched.itinerary(i);
        match keep.checked_sub(1).and_then(|k| it.travs.get(k)) {
            Some(tr) => (keep, tr.to, tr.end.max(t)),
            None => (0, it.at, t),
        }
    }

    /// A go-to-place to where a free robot stands (and may stay) is done the moment that
    /// robot takes it, at no robot time and in nobody's way, so it delays no other task:
    /// for each such robot, the oldest such task goes first in its priority. (A robot
    /// standing at one of two places at the end of a long single track took the oldest
    /// task, for the other, a 200 s round trip, while the tasks for its own place waited
    /// behind it.)
    fn done_where_they_stand(&mut self, free: &[Free]) {
        let standing: BTreeMap<usize, usize> = free
            .iter()
            .filter(|f| f.2 <= 0.0 && self.robots[f.0].n_sent == 0)
            .map(|f| (f.1, f.0))
            .collect();
        debug_assert_eq!(
            self.dispatcher.go_tos,
            self.dispatcher.pending.iter().filter(|p| p.go_to).count()
        );
        if standing.is_empty() || self.dispatcher.go_tos == 0 {
            return;
        }
        let mut first: Vec<(usize, usize)> = Vec::new();
        let mut served: Vec<usize> = Vec::new();
        for (k, p) in self.dispatcher.pending.iter().enumerate() {
            if !p.go_to {
                continue;
            }
            let here = p.steps.iter().find_map(|(fi, st)| match st.as_slice() {
                [Step::GoTo(v)] => standing
                    .get(v)
                    .filter(|&&ri| self.robots[ri].fleet == *fi)
                    .filter(|&&ri| p.robot.is_none_or(|o| o == ri)),
                _ => None,
            });
            if let Some(&ri) = here.filter(|ri| !served.contains(ri)) {
                served.push(ri);
                first.push((k, ri));
                if served.len() == standing.len() {
                    break;
                }
            }
        }
        // Taken out youngest first (the older indices stay), put back youngest first at
        // the front of their priority: the oldest ends first.
        let moved: Vec<(Pending, usize)> = first
            .iter()
            .rev()
            .filter_map(|&(k, ri)| Some((self.dispatcher.remove(k)?, ri)))
            .collect();
        for (mut p, ri) in moved {
            // Whatever kept it waiting for this robot (asleep, backed off, deferred to a
            // busy one) was about getting there, and it is there.
            p.asleep = None;
            p.deferred = None;
            p.backoff.retain(|b| b.0 != ri);
            let at = self
                .dispatcher
                .pending
                .partition_point(|q| q.priority > p.priority);
            self.dispatcher.insert(at, p);
        }
    }

    /// One dispatch round: tasks oldest first, each to the free robot whose plan gets
    /// there first. Tasks no robot can take now stay queued. A round looks at no more
    /// than `SCAN_PER_ROUND` tasks and makes no more than `PLANS_PER_ROUND` plans.
    pub(super) fn dispatch(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        if t < self.dispatcher.next_dispatch || self.dispatcher.pending.is_empty() {
            return;
        }
        self.dispatcher.last_round = t;
        self.dispatcher.next_dispatch = f64::INFINITY;
        self.traffic.retime(t);
        // Free robots: where they plan from, and how long until they may leave.
        let mut free: Vec<Free> = (0..self.robots.len())
            .filter(|&i| self.free(i))
            .map(|i| {
                let (_, at, t0) = self.plan_start(i, t);
                (i, at, t0 - t)
            })
            .collect();
        self.done_where_they_stand(&free);
        // Busy robots: where their tasks end and when (s from now). Not needed when no
        // robot is free: no task is looked at then.
        let mut busy: Vec<Busy> = if free.is_empty() {
            Vec::new()
        } else {
            (0..self.robots.len())
                .filter(|&i| !self.free(i))
                .filter_map(|i| {
                    let (last, done) = self.busy_end(i, t)?;
                    Some((i, last, done - t))
                })
                .collect()
        };
        let d = &mut self.dispatcher;
        d.same.retain(|_, v| v.0 > t);
        d.was_free.resize(self.robots.len(), false);
        if free.iter().any(|f| !d.was_free[f.0]) {
            d.freed += 1;
        }
        d.was_free.fill(false);
        for f in &free {
            d.was_free[f.0] = true;
        }
        d.work = (d.work + (t - d.work_at) * WORK_PER_S).min(WORK_MAX);
        d.work_at = t;
        let work_before = self.traffic.expanded();
        let mut budget = PLANS_PER_ROUND;
        // Plans made this round, by what they are a plan of, with the schedule they were
        // made against: the same plan asked again (the next task between the same places)
        // is that plan while the schedule stays (a search is a function of the two).
        let mut made: BTreeMap<Same, (u64, Option<Plan>, bool)> = BTreeMap::new();
        let mut displaced = false;
        let mut k = 0;
        let mut scanned = 0;
        while k < self.dispatcher.pending.len()
            && budget > 0
            && (self.traffic.expanded() - work_before) as f64 <= self.dispatcher.work
            && !free.is_empty()
            && scanned < SCAN_PER_ROUND
        {
            // Asleep: nothing changed that could let it be taken.
            if let Some((until, freed)) = self.dispatcher.pending[k].asleep {
                if t < until && freed == self.dispatcher.freed {
                    k += 1;
                    continue;
                }
            }
            self.dispatcher.pending[k].asleep = None;
            scanned += 1;
            // A delivery whose dispenser's item is away (on a robot, on its way home, or
            // promised to a robot on its way there) waits in the queue: a robot sent now
            // would stand at the empty dispenser until the item is back (minutes, on a
            // large building), in others' way.
            let away = self.dispatcher.pending[k].steps.iter().any(|(_, st)| {
                st.iter()
                    .any(|s| matches!(s, Step::Dispense(d) if self.dispenser_taken(d, t)))
            });
            if away {
                k += 1;
                continue;
            }
            let ti = self.dispatcher.pending[k].task;
            // The nearest free robots by free-flow time to the task's first place.
            // (time, robot, which of the task's fleets): the steps are cloned for the few
            // kept only (with hundreds of robots free, cloning them for each was a tenth
            // of a warehouse run, in the allocator).
            let mut near: Vec<(f64, usize, usize)> = Vec::new();
            // How soon a busy robot could get there after its task (s from now).
            let mut after: Option<f64> = None;
            // That robot's free-flow time from its task's last place.
            let mut approach = 0.0;
            let only = self.dispatcher.pending[k].robot;
            let firsts: Vec<(usize, usize, usize)> = self.dispatcher.pending[k]
                .steps
                .iter()
                .enumerate()
                .filter_map(|(n, (fi, st))| first_goal(st).map(|g| (n, *fi, g)))
                .collect();
            for (n, fi, first) in firsts {
                // One table lookup per task, not per robot: with hundreds of robots free
                // and tasks queued, the lookups were a tenth of a warehouse run.
                // A fleet with no robot free still bids with its busy ones: a robot of
                // another fleet sent now would only get there after it.
                // (Busy robots looked up only then: with one fleet, never.)
                let bids = |r: usize| self.robots[r].fleet == fi;
                if !free.iter().any(|f| bids(f.0))
                    && (only.is_some() || !busy.iter().any(|b| bids(b.0)))
                {
                    continue;
                }
                let fleet = &self.fleets[fi];
                let table = self.dispatcher.eta_table(&self.nav, fleet, first);
                for f in &free {
                    if self.robots[f.0].fleet == fi && only.is_none_or(|o| o == f.0) {
                        let eta = table[f.1] + f.2;
                        if eta.is_finite() {
                            near.push((eta, f.0, n));
                        }
                    }
                }
                if only.is_some() {
                    continue;
                }
                for &(ri, last, done) in &busy {
                    if self.robots[ri].fleet == fi {
                        let eta = done + table[last];
                        if eta.is_finite() && after.is_none_or(|a| eta < a) {
                            after = Some(eta);
                            approach = table[last];
                        }
                    }
                }
            }
            near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            // Its free robots' plans lost to a busy robot that still gets there first, and
            // no robot that was not planned for could beat it.
            if let (Some(a), Some(d)) = (after, &self.dispatcher.pending[k].deferred) {
                if d.holds(t, a, &near) {
                    self.wait_for_busy(k, a, t);
                    k += 1;
                    continue;
                }
            }
            self.dispatcher.pending[k].deferred = None;
            // A busy robot gets there before any free one could (free flow is the
            // soonest a plan arrives): the task waits for it, as RMF queues a task after
            // a robot's current one. Not planned for the free robots now, so they stay
            // for tasks only they are first to.
            if let Some(eta) = after.filter(|&a| near.first().is_none_or(|n| a < n.0)) {
                self.wait_for_busy(k, eta, t);
                k += 1;
                continue;
            }
            // Free robots that stay for good on one of the task's places are candidates
            // too, however far: no other robot can get there while they stay, and doing
            // the task moves them off (as in Token Passing, a robot whose endpoint a task
            // needs takes the task or makes room).
            let holders = self.holders(k, &free);
            let near: Vec<_> = near
                .into_iter()
                .enumerate()
                .filter(|(n, c)| *n < CANDIDATES || holders.contains(&c.1))
                .map(|(_, (eta, ri, n))| (eta, ri, self.dispatcher.pending[k].steps[n].1.clone()))
                .collect();
            // Task plans go through the others' ways to parking (see `schedule`).
            let task_soft = !self.dispatcher.pending[k].hard;
            let mut best: Option<Best> = None;
            let mut failed = false;
            let looked_at = near.len();
            let planned: Vec<usize> = near.iter().map(|c| c.1).collect();
            // Robots whose plans for it waited too long now and will, planned again.
            let mut refused: Vec<(usize, f64)> = Vec::new();
            for (eta, ri, steps) in near {
                // Planning again for a robot before its backoff ends cannot succeed unless
                // the others got ahead of their plans: a later start shortens a plan's
                // waits by at most the delay, and the plans installed since only add spans.
                if let Some(&(_, until)) = self.dispatcher.pending[k]
                    .backoff
                    .iter()
                    .find(|b| b.0 == ri)
                {
                    if t < until {
                        refused.push((ri, until));
                        continue;
                    }
                }
                let goals = self.goals_of(ri, &steps);
                let stay = matches!(self.tasks[ti].kind, TaskKind::GoToPlace { .. })
                    .then(|| goals.last().map(|g| g.0))
                    .flatten();
                let (keep, from, t0) = self.plan_start(ri, t);
                // The same plan through soft spans was undone for another task (a robot it
                // went before found no way behind it): this one keeps clear of them. With
                // a few places and a saturating stream, one task after another was
                // planned, installed and undone while robots stood idle.
                let undone = Same::new(ri, from, true, stay, &goals);
                let soft = task_soft
                    && !matches!(self.dispatcher.same.get(&undone), Some(&(until, Refused::Undone)) if t < until);
                // The same plan (robot, start, places) was refused for another task: the
                // reason above holds for it too (a saturating stream queues many tasks
                // between the same places).
                let same = Same::new(ri, from, soft, stay, &goals);
                if let Some(&(until, why)) = self.dispatcher.same.get(&same) {
                    if t < until && why != Refused::Undone {
                        failed |= why == Refused::NoWay;
                        refused.push((ri, until));
                        continue;
                    }
                }
                budget = budget.saturating_sub(1);
                let stamp = self.traffic.sched.stamp();
                let (found, late) = match made.get(&same) {
                    Some((at, found, late)) if *at == stamp => (found.clone(), *late),
                    _ => {
                        let (found, late) = self.task_plan(ri, &goals, (from, t0), stay, soft);
                        made.insert(same.clone(), (stamp, found.clone(), late));
                        (found, late)
                    }
                };
                let over = match &found {
                    // Every way there is later than the search looks: refused for long.
                    None if late => MAX_BACKOFF,
                    None => {
                        failed = true;
                        refused.push((ri, t + NO_WAY_BACKOFF));
                        self.dispatcher
                            .same
                            .insert(same, (t + NO_WAY_BACKOFF, Refused::NoWay));
                        continue;
                    }
                    // Long tasks may wait longer in all: a share of their length. No single
                    // wait as long as the stand-still a report calls stuck, however long
                    // the task: a robot with a task keeps moving.
                    Some(plan) => {
                        let last = plan.goal_at.last().copied().unwrap_or(0);
                        let length = last.checked_sub(1).map_or(0.0, |k| plan.steps[k].end - t0);
                        // A robot standing idle where its itinerary ends, waiting there
                        // before it leaves, stands in nobody's way but as it stood: that
                        // wait is not counted against the bound (it counts as the plan's
                        // longest, and against a busy robot's bid). (Counted, tasks on the
                        // airport terminal waited in the queue for minutes while 45 robots
                        // stood idle, their plans refused for waiting at their parking
                        // spots for others to pass.)
                        let idle_here = keep == 0 && self.traffic.sched.end_vertex(ri) == from;
                        let waited: f64 = waits(plan, t0).skip(usize::from(idle_here)).sum();
                        (waited - (MAX_PLANNED_WAIT + WAIT_SHARE * length))
                            .max(longest_wait(plan, t0) - LONGEST_WAIT)
                    }
                };
                let Some(plan) = found.filter(|_| over <= 0.0) else {
                    let until = t + over.clamp(DISPATCH_EVERY, MAX_BACKOFF);
                    refused.push((ri, until));
                    self.dispatcher.same.insert(same, (until, Refused::Late));
                    continue;
                };
                let arrive = match plan.goal_at.first() {
                    Some(&0) | None => t0,
                    Some(&n) => plan.steps[n - 1].end,
                };
                if best.as_ref().is_none_or(|b| arrive < b.arrive) {
                    best = Some(Best {
                        arrive,
                        eta,
                        robot: ri,
                        steps,
                        plan,
                        keep,
                        t0,
                        soft,
                        same,
                    });
                }
            }
            let Some(best) = best else {
                // No free robot may do it (a robot task whose robot is busy), or every one
                // that may is backed off (those that found no way for `NO_WAY_BACKOFF`: they
                // may find one as soon as others make room): only time or a robot becoming
                // free changes that.
                if refused.len() == looked_at {
                    let until = refused.iter().map(|r| r.1).fold(f64::INFINITY, f64::min);
                    self.dispatcher.pending[k].asleep = Some((until, self.dispatcher.freed));
                }
                self.dispatcher.pending[k].backoff = refused;
                // Room is made for one task per round, the oldest that needs it: for two
                // tasks in turn, the same robot would be sent back and forth between them.
                if failed
                    && !displaced
                    && t >= self.dispatcher.pending[k].displaced_at + DISPLACE_EVERY
                {
                    displaced = true;
                    self.dispatcher.pending[k].displaced_at = t;
                    // Maybe a robot stays for good where the task must go: it makes room.
                    let found = self.dispatcher.pending[k]
                        .steps
                        .iter()
                        .find_map(|(fi, st)| {
                            free.iter()
                                .find(|f| self.robots[f.0].fleet == *fi)
                                .map(|f| (f.0, st.clone()))
                        });
                    if let Some((ri, steps)) = found {
                        let goals = self.goals_of(ri, &steps);
                        self.displace_for(ri, &goals, t);
                    }
                }
                k += 1;
                continue;
            };
            // A busy robot still gets there before the best plan does, counting that
            // plan's waits for traffic once more, all of them up to its last place (those
            // before the first place are in its arrival already): a plan that waits for
            // the others contends with them for the way, spends robot-time standing that
            // the busy robot would spend on the next task, and the plans made after it
            // wait for it in turn. (Counting only the waits after the first place, two
            // robots on one corridor between two rooms took turns waiting for each
            // other, and completed 8 % less than one robot alone.)
            let waited: f64 = waits(&best.plan, best.t0).sum();
            // And it gets there so little later that the free robot's longer drive costs
            // more (robot-time on the corridors, under a saturating stream the fleet's
            // throughput) than the task gains by starting sooner.
            let extra = (best.eta - approach).max(0.0);
            if let Some(eta) = after.filter(|&a| t + a < best.arrive + waited + extra) {
                let p = &mut self.dispatcher.pending[k];
                p.backoff = refused;
                p.deferred = Some(Deferred {
                    beat: best.arrive + waited + extra,
                    planned,
                });
                self.wait_for_busy(k, eta, t);
                k += 1;
                continue;
            }
            let ri = best.robot;
            // Where and when the task will end, for its robot's bid on the next tasks.
            let (last, done) = self.task_end(ri, &best.steps, &best.plan, best.t0);
            let start = (best.keep, best.t0, best.soft.then_some(t));
            if !self.start_task(ri, ti, best.steps, best.plan, start, t, out) {
                // A robot it went before on its way to parking found no way behind it.
                self.dispatcher.pending[k].hard = true;
                self.dispatcher
                    .same
                    .insert(best.same, (t + MAX_BACKOFF, Refused::Undone));
                k += 1;
                continue;
            }
            self.dispatcher.remove(k);
            free.retain(|f| f.0 != ri);
            // The robot bids for the tasks after it in this round as a busy robot, from
            // where this one ends. (Left out until the next round, robots free together
            // each took a task, the second's plan waiting long behind the first's, where
            // the first would have done both in turn.)
            if let Some(last) = last {
                busy.push((ri, last, done - t));
            }
        }
        self.dispatcher.work -= (self.traffic.expanded() - work_before) as f64;
        if !self.dispatcher.pending.is_empty() {
            self.dispatcher.next_dispatch = t + DISPATCH_EVERY;
        }
    }

    /// Robot `i`'s plan to `goals` from `from` at `t0` for a task, against the schedule as
    /// it is, with its ends in order of preference (`stay`: a go-to-place's place); or
    /// None, and whether some way was cut only by the delay bound.
    fn task_plan(
        &mut self,
        i: usize,
        goals: &[(usize, f64)],
        (from, t0): (usize, f64),
        stay: Option<usize>,
        soft: bool,
    ) -> (Option<Plan>, bool) {
        // A place where another robot stays for good: no plan can get there (a search
        // would only prove it, at length), that robot must make room.
        let conf = self.traffic.sched.conf();
        let held = goals.iter().any(|&(g, _)| {
            conf.vertex[g]
                .iter()
                .any(|&x| self.traffic.sched.held_for_good(x, i, soft).is_some())
        });
        if held {
            return (None, false);
        }
        let ends = self.ends(i, goals, from, stay);
        self.plan_over(
            i,
            &ends,
            (from, t0),
            goals,
            (soft, Some(SEARCH_DELAY)),
            None,
        )
    }

    /// Pending task `k` waits for a busy robot that gets there first (`eta` s from `t`):
    /// rounds pass it by until that robot should be done or a robot becomes free.
    fn wait_for_busy(&mut self, k: usize, eta: f64, t: f64) {
        let d = &mut self.dispatcher;
        d.pending[k].asleep = Some((t + eta, d.freed));
    }

    /// Where busy robot `i`'s task ends and when it is done there (its itinerary's
    /// estimate and the work still to do): None without a task or between steps.
    fn busy_end(&self, i: usize, t: f64) -> Option<(usize, f64)> {
        let r = &self.robots[i];
        r.task?;
        let (goals, working) = match r.cur {
            Cur::GoTo { goal, .. } => (self.remaining_goals(i, goal), false),
            Cur::Dwell { until } => (self.working_goals(i, (until - t).max(0.0)), true),
            Cur::Workcell { .. } => (self.working_goals(i, WORKCELL_ESTIMATE), true),
            Cur::Charge { pct, .. } => {
                let rate = self.fleets[r.fleet].charge_rate.max(1e-9);
                (
                    self.working_goals(i, (pct - r.battery()).max(0.0) / rate),
                    true,
                )
            }
            Cur::None => return None,
        };
        let &(last, work) = goals.last()?;
        let ahead = goals.len() - usize::from(working);
        let at = if ahead == 0 {
            t
        } else {
            self.arrival(i, ahead).max(t)
        };
        Some((last, at + work))
    }

    /// Whether `dispenser`'s item is away or promised: a robot carries it or brings it
    /// back ([`Fleets::item_coming`]), or a robot's task will take it (before it did).
    fn dispenser_taken(&self, dispenser: &str, t: f64) -> bool {
        let asks = |c: &Cur| matches!(c, Cur::Workcell { target, dispenser: true, .. } if target == dispenser);
        self.item_coming(dispenser, t)
            || self.robots.iter().any(|r| {
                r.task.is_some()
                    && (asks(&r.cur)
                        || r.steps.iter().any(|s| match s {
                            Step::Dispense(d) => d == dispenser,
                            // Making room while it waits to ask again.
                            Step::Resume(c) => asks(c),
                            _ => false,
                        }))
            })
    }

    /// The free robots (of `free`) that stay for good on a place of pending task `k`.
    fn holders(&self, k: usize, free: &[Free]) -> Vec<usize> {
        let conf = self.traffic.sched.conf();
        let mut out = Vec::new();
        for (_, steps) in &self.dispatcher.pending[k].steps {
            for s in steps {
                let Step::GoTo(g) = s else { continue };
                for &x in &conf.vertex[*g] {
                    if let Some(o) = self.traffic.sched.held_for_good(x, usize::MAX, false) {
                        if free.iter().any(|f| f.0 == o) && !out.contains(&o) {
                            out.push(o);
                        }
                    }
                }
            }
        }
        out
    }

    /// Robot `ri` takes task `ti` with its plan (against the schedule as it is now, after
    /// its first `keep` traversals, from `t0`; through soft spans when `soft_at`). False
    /// when the plan could not be installed (see [`Fleets::install`]): nothing changed.
    #[allow(clippy::too_many_arguments)]
    fn start_task(
        &mut self,
        ri: usize,
        ti: usize,
        steps: Vec<Step>,
        plan: Plan,
        (keep, t0, soft_at): (usize, f64, Option<f64>),
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) -> bool {
        let (_, planned) = self.task_end(ri, &steps, &plan, t0);
        // Its way to parking is soft from the start: the robot has the task.
        self.robots[ri].task = Some(ti);
        if !self.install(ri, keep, plan, t0, soft_at) {
            self.robots[ri].task = None;
            return false;
        }
        let r = &mut self.robots[ri];
        r.task_started = t;
        r.steps = steps.into();
        r.park_pending = false;
        r.dirty = true;
        r.wake = t;
        self.event(t, ti, "assigned", Some(ri), String::new(), out);
        if let Some((_, Msg::TaskEvent(e))) = out.last_mut() {
            e.planned_finish = Some(planned);
        }
        self.event(t, ti, "started", Some(ri), String::new(), out);
        true
    }

    /// Where robot `i`'s task of `steps` ends (its last place, None without one) and when,
    /// on `plan` from `t0`: at its last place, after the work there.
    fn task_end(&self, i: usize, steps: &[Step], plan: &Plan, t0: f64) -> (Option<usize>, f64) {
        let last = self.goals_of(i, steps).last().copied();
        let arrive = match plan.goal_at.last() {
            Some(&0) | None => t0,
            Some(&n) => plan.steps[n - 1].end,
        };
        (last.map(|g| g.0), arrive + last.map_or(0.0, |g| g.1))
    }

    /// The places of `steps` in order, each with how long robot `i` stays there (the
    /// work of the steps up to the next place).
    pub(super) fn goals_of(&self, i: usize, steps: &[Step]) -> Vec<(usize, f64)> {
        let r = &self.robots[i];
        let f = &self.fleets[r.fleet];
        let mut goals: Vec<(usize, f64)> = Vec::new();
        for s in steps {
            let dwell = match s {
                Step::GoTo(v) => {
                    goals.push((*v, 0.0));
                    continue;
                }
                Step::Dwell(x) => *x,
                Step::Dispense(_) | Step::Ingest(_) | Step::Resume(_) => WORKCELL_ESTIMATE,
                Step::Charge(pct) => (pct - r.battery()).max(0.0) / f.charge_rate.max(1e-9),
            };
            if let Some(g) = goals.last_mut() {
                g.1 = (g.1 + dwell).min(4.0 * 3600.0);
            }
        }
        goals
    }

    /// The steps of a task for fleet `fi`, or None if its waypoints are not on the graph.
    pub(super) fn expand(&self, fi: usize, kind: &TaskKind) -> Option<Vec<Step>> {
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
            TaskKind::Patrol { places, rounds } => {
                let vs = places.iter().map(|p| v(p)).collect::<Option<Vec<_>>>()?;
                let mut s = Vec::new();
                for _ in 0..(*rounds).max(1) {
                    s.extend(vs.iter().map(|&x| Step::GoTo(x)));
                }
                s
            }
        })
    }
}

/// The first place of `steps`.
fn first_goal(steps: &[Step]) -> Option<usize> {
    steps.iter().find_map(|s| match s {
        Step::GoTo(v) => Some(*v),
        _ => None,
    })
}

/// The longest of `plan`'s waits for traffic up to its last place (s).
fn longest_wait(plan: &Plan, t0: f64) -> f64 {
    waits(plan, t0).fold(0.0, f64::max)
}

/// Each wait of `plan` for traffic before a step, up to its last place (s).
fn waits(plan: &Plan, t0: f64) -> impl Iterator<Item = f64> + '_ {
    let last = plan.goal_at.last().copied().unwrap_or(0);
    let mut prev = t0;
    plan.steps[..last].iter().map(move |s| {
        let w = (s.start - prev - s.hold).max(0.0);
        prev = s.end;
        w
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The best free plan made at 0 s got there at 100 s; robots 1 and 2 were planned.
    fn deferred() -> Deferred {
        Deferred {
            beat: 100.0,
            planned: vec![1, 2],
        }
    }

    #[test]
    fn a_deferred_task_is_not_planned_again_while_its_bid_holds() {
        let d = deferred();
        // The same robots free, the busy robot still first: nothing to plan.
        assert!(d.holds(10.0, 50.0, &[(20.0, 1, 0), (30.0, 2, 0)]));
        // A robot that became free but cannot get there before the best plan did.
        assert!(d.holds(10.0, 50.0, &[(20.0, 1, 0), (95.0, 7, 0)]));
        // Only the nearest `CANDIDATES` are planned for: a near robot further down the
        // list is not a reason.
        let far = [(1.0, 1, 0), (2.0, 2, 0), (3.0, 1, 0), (4.0, 9, 0)];
        assert!(d.holds(10.0, 50.0, &far));
    }

    #[test]
    fn a_deferred_task_is_planned_again_when_its_bid_or_the_robots_change() {
        let d = deferred();
        // The busy robot was delayed: its bid no longer beats the best plan.
        assert!(!d.holds(10.0, 90.0, &[(20.0, 1, 0)]));
        // A robot not planned for became free and could get there before it.
        assert!(!d.holds(10.0, 50.0, &[(20.0, 1, 0), (60.0, 7, 0)]));
    }
}
