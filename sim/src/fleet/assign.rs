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
//! counted once more, waits for that robot, when it would also have the task done first
//! (at each fleet's speed, from the first place on); a robot given a task in a round bids so for
//! the tasks after it in that round. Only free robots were looked at before, so a bigger
//! fleet sent a robot parked far away where a smaller one's robot, about to finish next
//! door, would have taken the task: on the demo maps and generated buildings, fleets
//! completed 22-24 % more with the bids (BENCHMARKS.md). A free robot
//! that gets there sooner still yields to the busy one when it gains the task less time
//! than the longer drive it makes: under a saturating stream the fleet's throughput is its
//! robot-time, and a drive across the building also loads its corridors (of the 95 %
//! rule's breaches on the generated buildings and warehouses, all but one went).

mod round;
use super::steps::first_goal;
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
pub(super) const DISPATCH_EVERY: f64 = 5.0;
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
pub(super) type Free = (usize, usize, f64);

/// A busy robot: its index, the last place of its task, and how long until it is done
/// there (s).
pub(super) type Busy = (usize, usize, f64);

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
    /// may first succeed (see [`Dispatcher::round`]).
    backoff: Vec<(usize, f64)>,
    /// Every robot it was looked at for is in `backoff`: until when, and
    /// [`Dispatcher::freed`] then. Rounds pass it by until then unless a robot became free
    /// since (without looking for its nearest robots: with thousands of tasks queued,
    /// that was most of a round).
    asleep: Option<(f64, u64)>,
    /// Its plans keep clear of the others' ways to parking too (one that went before them
    /// was undone: see [`Floor::install`]).
    hard: bool,
    /// It waits for a busy robot that gets there before the free robots' plans did: see
    /// [`Deferred`].
    deferred: Option<Deferred>,
    /// A go-to-place: done the moment a robot standing at its place takes it
    /// ([`Dispatcher::done_where_they_stand`]).
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
    /// When the best plan would have had the task done (`beat` and its robot's free-flow
    /// time from the first place on).
    beat_done: f64,
    planned: Vec<usize>,
}

impl Deferred {
    /// At `t`, with the busy robot's bid `after` s away (`done`, s until it would have
    /// the task done) and `near` the free robots (free flow time, robot, fleet), nearest
    /// first: the bid still beats the best plan made, there and done, and no robot among
    /// those a round would plan for that was not planned for could.
    fn holds(&self, t: f64, (after, done): (f64, f64), near: &[(f64, usize, usize)]) -> bool {
        t + after < self.beat
            && t + done < self.beat_done
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
/// last round when one comes to a queue with tasks waiting). Guarantees (with [`Dispatcher::round`]):
/// tasks are looked at oldest first, each goes to the free robot whose whole-task plan
/// arrives first, a plan that would wait long for traffic is never taken, and a robot
/// whose plan for a task waited too long (or found no way) is not planned for it, nor for
/// the same places from the same start, again until its backoff ends (its excess wait, at
/// most `MAX_BACKOFF`; `NO_WAY_BACKOFF`), nor is a robot of a slower fleet given the task
/// meanwhile ([`Dispatcher::yield_to_faster`]).
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
    /// Per robot, until when its plans were last refused for waiting too long (cleared
    /// when it takes a task; read only for free robots): see
    /// [`Dispatcher::yield_to_faster`].
    late_until: Vec<f64>,
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
            late_until: Vec::new(),
        }
    }

    /// A round starts at `t` with robots `free` (of `robots`): refusals that ended are
    /// dropped, a robot free now that was not in the last round counts (`freed`), and the
    /// work budget is refilled.
    fn start_round(&mut self, t: f64, free: &[Free], robots: usize) {
        self.same.retain(|_, v| v.0 > t);
        self.was_free.resize(robots, false);
        if free.iter().any(|f| !self.was_free[f.0]) {
            self.freed += 1;
        }
        self.was_free.fill(false);
        for f in free {
            self.was_free[f.0] = true;
        }
        self.work = (self.work + (t - self.work_at) * WORK_PER_S).min(WORK_MAX);
        self.work_at = t;
        self.late_until.resize(robots, f64::NEG_INFINITY);
    }

    /// Whether robot `i` was free in the last round.
    fn was_free(&self, i: usize) -> bool {
        self.was_free.get(i).copied().unwrap_or(false)
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

impl Dispatcher {
    /// Task `new`, requested at `t`: queued, or failed at once when no robot of the
    /// task's fleets can do it.
    pub(super) fn request(
        &mut self,
        fl: &mut Floor,
        t: f64,
        new: NewTask,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let NewTask {
            kind,
            fleet,
            robot,
            priority,
        } = new;
        let category = kind.category();
        let id = self.new_id(category);
        let ti = fl.tasks.len();
        fl.tasks.push(Task {
            id,
            category,
            kind,
            fleet: fleet.clone(),
            ended: false,
        });
        fl.event(t, ti, "queued", None, String::new(), out);
        // A robot task: that robot of the task's fleet, or nobody.
        let only = robot.as_ref().map(|name| {
            fl.by_name.get(name).copied().filter(|&i| {
                fleet
                    .as_ref()
                    .is_none_or(|f| fl.fleets[fl.robots[i].fleet].name == *f)
            })
        });
        if let (Some(None), Some(name)) = (only, &robot) {
            fl.tasks[ti].ended = true;
            let detail = format!("no robot named `{name}` in the task's fleet");
            fl.event(t, ti, "failed", None, detail, out);
            return;
        }
        let steps: Vec<(usize, Vec<Step>)> = fl
            .fleets_for(ti)
            .into_iter()
            .filter(|(fi, _)| only.flatten().is_none_or(|i| fl.robots[i].fleet == *fi))
            .collect();
        if steps.is_empty() {
            fl.tasks[ti].ended = true;
            fl.event(
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
            go_to: matches!(fl.tasks[ti].kind, TaskKind::GoToPlace { .. }),
        };
        self.enqueue(p, t);
    }

    /// Pending task `k` waits for a busy robot that gets there first (`eta` s from `t`):
    /// rounds pass it by until that robot should be done or a robot becomes free.
    pub(super) fn wait_for_busy(&mut self, k: usize, eta: f64, t: f64) {
        self.pending[k].asleep = Some((t + eta, self.freed));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The best free plan made at 0 s got there at 100 s; robots 1 and 2 were planned.
    fn deferred() -> Deferred {
        Deferred {
            beat: 100.0,
            beat_done: 150.0,
            planned: vec![1, 2],
        }
    }

    #[test]
    fn a_deferred_task_is_not_planned_again_while_its_bid_holds() {
        let d = deferred();
        // The same robots free, the busy robot still first: nothing to plan.
        assert!(d.holds(10.0, (50.0, 90.0), &[(20.0, 1, 0), (30.0, 2, 0)]));
        // A robot that became free but cannot get there before the best plan did.
        assert!(d.holds(10.0, (50.0, 90.0), &[(20.0, 1, 0), (95.0, 7, 0)]));
        // Only the nearest `CANDIDATES` are planned for: a near robot further down the
        // list is not a reason.
        let far = [(1.0, 1, 0), (2.0, 2, 0), (3.0, 1, 0), (4.0, 9, 0)];
        assert!(d.holds(10.0, (50.0, 90.0), &far));
    }

    #[test]
    fn a_deferred_task_is_planned_again_when_its_bid_or_the_robots_change() {
        let d = deferred();
        // The busy robot was delayed: its bid no longer beats the best plan.
        assert!(!d.holds(10.0, (90.0, 130.0), &[(20.0, 1, 0)]));
        // A robot not planned for became free and could get there before it.
        assert!(!d.holds(10.0, (50.0, 90.0), &[(20.0, 1, 0), (60.0, 7, 0)]));
        // Still there first, but slower: it would have the task done after the best
        // plan would (at 155 s against 150 s).
        assert!(!d.holds(10.0, (50.0, 145.0), &[(20.0, 1, 0)]));
    }
}
