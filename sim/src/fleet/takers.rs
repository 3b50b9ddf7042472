//! The floor's side of dispatch: which robots are free and which are busy (where and when
//! their tasks end), whether a dispenser's item is taken, which fleets can do a task, a
//! task's plan for a robot, and a robot taking its task. The dispatcher (`assign`) decides
//! with these; it reaches the robots through nothing else.

use super::assign::{Busy, Free};
use super::*;
use crate::traffic::sipp::{Delay, Plan};

impl Floor {
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
    pub(super) fn plan_start(&self, i: usize, t: f64) -> (usize, usize, f64) {
        let keep = self.kept(i);
        let it = self.traffic.sched.itinerary(i);
        match keep.checked_sub(1).and_then(|k| it.travs.get(k)) {
            Some(tr) => (keep, tr.to, tr.end.max(t)),
            None => (0, it.at, t),
        }
    }

    /// Where busy robot `i`'s task ends and when it is done there (its itinerary's
    /// estimate and the work still to do): None without a task or between steps.
    pub(super) fn busy_end(&self, i: usize, t: f64) -> Option<(usize, f64)> {
        let r = &self.robots[i];
        r.task?;
        let (goals, working) = match r.cur {
            Cur::GoTo { goal, .. } => (self.remaining_goals(i, goal), false),
            Cur::Dwell { until } => (self.working_goals(i, (until - t).max(0.0)), true),
            Cur::Workcell { .. } => (self.working_goals(i, WORKCELL_ESTIMATE), true),
            Cur::Charge { pct, .. } => (self.working_goals(i, self.charge_left(i, pct)), true),
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
    /// back ([`Floor::item_coming`]), or a robot's task will take it (before it did).
    pub(super) fn dispenser_taken(&self, dispenser: &str, t: f64) -> bool {
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

    /// The free robots: where they plan from, and how long until they may leave (s).
    pub(super) fn free_robots(&self, t: f64) -> Vec<Free> {
        (0..self.robots.len())
            .filter(|&i| self.free(i))
            .map(|i| {
                let (_, at, t0) = self.plan_start(i, t);
                (i, at, t0 - t)
            })
            .collect()
    }

    /// The busy robots: where their tasks end and when (s from now).
    pub(super) fn busy_robots(&self, t: f64) -> Vec<Busy> {
        (0..self.robots.len())
            .filter(|&i| !self.free(i))
            .filter_map(|i| {
                let (last, done) = self.busy_end(i, t)?;
                Some((i, last, done - t))
            })
            .collect()
    }

    /// Robot `i`'s plan to `goals` from `from` at `t0` for a task, against the schedule as
    /// it is, with its ends in order of preference (`stay`: a go-to-place's place), through
    /// the others' soft spans or not, searched within the dispatcher's `delay` bound; or
    /// None, and whether some way was cut only by that bound.
    pub(super) fn task_plan(
        &mut self,
        i: usize,
        goals: &[(usize, f64)],
        (from, t0): (usize, f64),
        stay: Option<usize>,
        (soft, delay): (bool, Delay),
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
        self.plan_over(i, &ends, (from, t0), goals, (soft, Some(delay)), None)
    }

    /// Robot `ri` takes task `ti` with its plan (against the schedule as it is now, after
    /// its first `keep` traversals, from `t0`; through soft spans when `soft_at`). False
    /// when the plan could not be installed (see [`Floor::install`]): nothing changed.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn start_task(
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
        self.robots[ri].retreat = None;
        self.robots[ri].free_since = f64::INFINITY;
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
    pub(super) fn task_end(
        &self,
        i: usize,
        steps: &[Step],
        plan: &Plan,
        t0: f64,
    ) -> (Option<usize>, f64) {
        let last = self.goals_of(i, steps).last().copied();
        let arrive = match plan.goal_at.last() {
            Some(&0) | None => t0,
            Some(&n) => plan.steps[n - 1].end,
        };
        (last.map(|g| g.0), arrive + last.map_or(0.0, |g| g.1))
    }
}
