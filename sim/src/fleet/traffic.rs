//! The fleet side of traffic planning (`crate::traffic`): planning a robot's next leg into
//! the shared schedule, and driving what the schedule grants.
//!
//! A GoTo is planned once (SIPP against every robot's itinerary, to the goal, its work
//! there, then a parking vertex); the robot then drives each traversal when the schedule
//! grants it (every robot planned to pass the traversal's resources before it has passed).
//! A plan that fails (no way now) leaves the old itinerary, which ends on a parking vertex,
//! and is tried again `REPLAN_AFTER` s later. No robot ever waits on another except in the
//! schedule's order, and that order is acyclic: waits end.

mod grant;
mod room;
use super::*;
use crate::traffic::parks::{PARK, PARK_ON_PLACE};
use crate::traffic::sipp::{Delay, Plan, Query};
use crate::traffic::Res;

/// A failed plan is tried again after this long (s).
const REPLAN_AFTER: f64 = 2.0;
/// A waiting robot whose turn is put off by more than this (s) plans again.
const REPLAN_DELAY: f64 = 30.0;
/// A robot made to leave its home (`Finish::Home`) while idle tries to go back after this
/// long (s).
const HOME_AGAIN: f64 = 60.0;

/// Where a plan may end, tried in order by [`Floor::ends`]: parking vertices of the
/// robot's own (None: the graph's), and a vertex where it may stay.
pub(super) type End = (Option<Vec<u8>>, Option<usize>);

/// Why a leg could not be planned.
pub(super) enum NoPlan {
    /// The goal cannot be reached on the fleet's graph at all.
    Unreachable,
    /// Not now: the schedule leaves no way (try again later).
    Busy,
}

/// A query's `parks` when it ends on its graph's parking vertices (see [`Traffic::plan`]).
pub(super) const GRAPH_PARKS: &[u8] = &[];

/// A task plan through others' soft spans is undone when the order it was installed in
/// makes it reach its last place more than this much later than planned (s): well under
/// the 300 s a robot with a task may stand still.
const SOFT_ORDER_SLACK: f64 = 120.0;

/// The traffic side of the fleets: one schedule shared by all fleets, the planner that
/// plans legs into it, and where robots may stand for good.
///
/// Invariant: every robot has an itinerary in `sched` that ends on a vertex where it may
/// stand for good; every plan installed fits the schedule as it is (SIPP against every
/// robot's itinerary), and the order in which robots pass each resource is acyclic
/// (checked after every plan that goes through others' soft spans, and after every
/// arrival in debug builds; a cycle found is counted in `cycles`, never expected). A
/// plan that fails leaves the old itinerary. Guarantees that no robot ever waits on
/// another except in the schedule's order, so waits end.
pub(super) struct Traffic {
    /// Every robot's itinerary and the order robots pass each resource.
    pub(super) sched: Schedule,
    planner: Planner,
    /// Where robots may stand for good.
    parks: Parks,
    /// When the schedule was last retimed.
    retimed_at: f64,
    /// A traversal completed in this update (waiting robots may go on).
    released: bool,
    /// Dependency cycles found (never expected; counted for the tests).
    cycles: u64,
    /// Robots are being set aside ([`Floor::aside`]): the order may not hold until they
    /// have all planned again, and is checked then.
    pub(super) aside: bool,
    /// Task plans undone because a robot they went before on its way to parking could not
    /// plan again behind them.
    soft_undone: u64,
    /// States the planner expanded, per plan made.
    decisions: Vec<u32>,
}

impl Traffic {
    /// Robots standing at `starts` (vertices of `nav`), with the conflict sets `conf`.
    pub(super) fn new(nav: &Nav, conf: Conflicts, starts: &[usize], parks: Parks) -> Traffic {
        Traffic {
            sched: Schedule::new(conf, starts, 0.0),
            planner: Planner::new(nav),
            parks,
            retimed_at: f64::NAN,
            released: false,
            cycles: 0,
            aside: false,
            soft_undone: 0,
            decisions: Vec::new(),
        }
    }

    /// Brings the schedule's time estimates up to `t` (once per update).
    pub(super) fn retime(&mut self, t: f64) {
        if self.retimed_at == t && !self.sched.stale() {
            return;
        }
        self.retimed_at = t;
        if self.aside {
            if self.sched.retime(t).is_err() {
                self.retimed_at = f64::NAN;
            }
            return;
        }
        if let Err(c) = self.sched.retime(t) {
            // Never expected: the schedule's order is acyclic by construction. Counted so
            // that the tests see it.
            self.cycles += 1;
            debug_assert!(false, "traffic dependency cycle among {:?}", c.robots);
        }
    }

    /// Per vertex of graph slot `slot`: where robots may stand for good (0: nowhere).
    pub(super) fn parks(&self, slot: usize) -> &[u8] {
        &self.parks.per_slot[slot]
    }

    /// Plans `q` against the schedule as it is (a query whose `parks` is [`GRAPH_PARKS`]
    /// ends on its graph's parking vertices). Installs nothing.
    pub(super) fn plan(&mut self, nav: &Nav, q: Query) -> Option<Plan> {
        let q = if q.parks.is_empty() {
            Query {
                parks: &self.parks.per_slot[q.slot],
                ..q
            }
        } else {
            q
        };
        self.planner.plan(nav, &self.sched, &q)
    }

    /// Whether the last plan failed only for its delay bound (a later one may exist).
    pub(super) fn late(&self) -> bool {
        self.planner.late
    }

    /// States the planner expanded so far, in every search.
    pub(super) fn expanded(&self) -> u64 {
        self.planner.expanded
    }

    /// A plan that expanded `expanded` states was installed.
    fn planned(&mut self, expanded: usize) {
        self.decisions.push(expanded as u32);
    }

    /// Puts back the schedule as it was before a plan through soft spans that could not
    /// hold (the transaction it was installed in).
    fn undo(&mut self) {
        self.sched.rollback();
        self.soft_undone += 1;
    }

    /// In debug builds: checks the schedule at `t` (`what` says after what), counting a
    /// broken one as a cycle.
    pub(super) fn check(&mut self, t: f64, what: impl FnOnce() -> String) {
        if cfg!(debug_assertions) && !self.aside {
            if let Err(e) = self.sched.check(t) {
                self.cycles += 1;
                debug_assert!(false, "{}: {e}", what());
            }
        }
    }

    /// A new pass over the robots: no traversal completed in it yet.
    pub(super) fn begin_pass(&mut self) {
        self.released = false;
    }

    /// A traversal completed (waiting robots may go on).
    pub(super) fn release(&mut self) {
        self.released = true;
    }

    /// A traversal completed since [`Traffic::begin_pass`].
    pub(super) fn released(&self) -> bool {
        self.released
    }

    /// Records the wall-clock time of every plan from now on.
    pub(super) fn time_plans(&mut self) {
        self.planner.times = Some(Vec::new());
    }

    /// The wall-clock time (s) of every plan since [`Traffic::time_plans`].
    pub(super) fn plan_times(&mut self) -> Vec<f64> {
        self.planner.times.take().unwrap_or_default()
    }

    /// The traffic planner's work so far.
    pub(super) fn report(&self) -> crate::report::TrafficReport {
        let mut e = self.decisions.clone();
        e.sort_unstable();
        let pick = |q: f64| -> u64 {
            if e.is_empty() {
                0
            } else {
                e[((e.len() - 1) as f64 * q).round() as usize] as u64
            }
        };
        crate::report::TrafficReport {
            plans: self.planner.plans,
            plans_failed: self.planner.failed,
            plans_taken: e.len() as u64,
            expanded_median: pick(0.5),
            expanded_p99: pick(0.99),
            cycles: self.cycles,
            soft_undone: self.soft_undone,
        }
    }
}

impl Floor {
    /// The places robot `i` goes to from its current GoTo's `goal` on (its task's
    /// remaining places), each with the work there.
    pub(super) fn remaining_goals(&self, i: usize, goal: usize) -> Vec<(usize, f64)> {
        let mut steps = vec![Step::GoTo(goal)];
        steps.extend(self.robots[i].steps.iter().cloned());
        self.goals_of(i, &steps)
    }

    /// The places of robot `i`, working where it stands for `rest` s more, and then its
    /// task's remaining places.
    pub(super) fn working_goals(&self, i: usize, rest: f64) -> Vec<(usize, f64)> {
        let mut steps = vec![Step::GoTo(self.robots[i].at), Step::Dwell(rest)];
        steps.extend(self.robots[i].steps.iter().cloned());
        self.goals_of(i, &steps)
    }

    /// Where robot `i` stays after `goals` if it can: the place of a go-to-place task.
    fn stays_at(&self, i: usize, goals: &[(usize, f64)]) -> Option<usize> {
        let r = &self.robots[i];
        let last = goals.last()?.0;
        let go_to = r
            .task
            .and_then(|ti| self.tasks.get(ti))
            .is_some_and(|tk| matches!(tk.kind, TaskKind::GoToPlace { .. }));
        // The task's places left: none after the current leg's, or, before the task's
        // first step starts, its one place.
        let left = r
            .steps
            .iter()
            .filter(|s| matches!(s, Step::GoTo(_)))
            .count();
        let last_place = left == 0 || (r.cur == Cur::None && left == 1);
        (go_to && last_place).then_some(last)
    }

    /// Where robot `i`'s plan to `goals` from `from` may end, in order of preference:
    /// `stay` (a go-to-place's place) and the graph's parking vertices for robots without
    /// a config; its home first for a robot with one ([`Finish::Home`]); the vertex its
    /// last goal is (or `from`) when it stays where its task ends and that vertex is a
    /// parking vertex nobody has as a home ([`Finish::Stay`]).
    pub(super) fn ends(
        &self,
        i: usize,
        goals: &[(usize, f64)],
        from: usize,
        stay: Option<usize>,
    ) -> Vec<End> {
        let r = &self.robots[i];
        // Sent out of the way while idle: back there when planned again (made to make room).
        let mut ends = match r.finish {
            _ if r.retreat.is_some() && r.task.is_none() => {
                let mut only = vec![0u8; self.nav.vertices.len()];
                only[r.retreat.unwrap_or(0)] = PARK;
                vec![(Some(only), None), (None, stay)]
            }
            Finish::Park => vec![(None, stay)],
            Finish::Home(h) => {
                let mut only = vec![0u8; self.nav.vertices.len()];
                only[h] = PARK;
                vec![(Some(only), None), (None, stay)]
            }
            Finish::Stay => {
                let last = goals.last().map_or(from, |g| g.0);
                let free = self.traffic.parks(r.slot)[last] != 0
                    && !self.robots.iter().any(|o| o.finish == Finish::Home(last));
                vec![(None, if free { Some(last) } else { stay })]
            }
        };
        // Last: back where it stands for good now, when that is no parking vertex (a
        // config's start waypoint, or where it was sent to make room). With more robots
        // than parking vertices no plan could end otherwise, and it stands there already.
        let here = self.traffic.sched.end_vertex(i);
        if self.traffic.parks(r.slot)[here] == 0 && stay != Some(here) {
            ends.push((None, Some(here)));
        }
        ends
    }

    /// Installs `plan` as robot `i`'s itinerary after its first `keep` traversals, and
    /// remembers where each of its places is reached (`Robot::legs`). For a robot with a
    /// task, the way to parking after the last place is soft until the task is done.
    ///
    /// `soft_at`: the time now, when the plan was made through the others' soft spans
    /// (`Query::soft`). The robots it went before plan their ways to parking again behind
    /// it ([`Floor::park_again`]); when one cannot, or the order would have a cycle,
    /// nothing changes and this returns false.
    pub(super) fn install(
        &mut self,
        i: usize,
        keep: usize,
        plan: Plan,
        t0: f64,
        soft_at: Option<f64>,
    ) -> bool {
        if soft_at.is_some() {
            self.traffic.sched.open_tx();
        }
        let soft = self.robots[i]
            .task
            .and_then(|_| plan.goal_at.last().copied());
        let jumped = self.traffic.sched.install(i, keep, &plan.steps, t0, soft);
        if let Some(now) = soft_at {
            // Every robot it went before plans again behind it, the order stays acyclic,
            // and it does not put the plan far behind itself; else nothing changes.
            let kept = jumped.iter().all(|&o| self.park_again(o, now))
                && self.traffic.sched.compute(now).is_ok()
                && !self.later_than_planned(i, keep, &plan);
            if !kept {
                self.traffic.undo();
                return false;
            }
            self.traffic.sched.commit();
            self.traffic.sched.apply(now);
        }
        debug_assert!(jumped.is_empty() || soft_at.is_some(), "a hard plan jumped");
        self.traffic.planned(plan.expanded);
        self.traffic
            .check(t0, || format!("schedule broken after planning robot {i}"));
        let mut prev = 0;
        let r = &mut self.robots[i];
        r.legs = plan
            .goal_at
            .iter()
            .enumerate()
            .map(|(k, &at)| {
                let n = if k == 0 { keep + at } else { at - prev };
                prev = at;
                n
            })
            .collect();
        true
    }

    /// Whether robot `i`'s itinerary, just installed from `plan` after `keep` traversals and
    /// computed ([`Schedule::compute`]), reaches the plan's last place more than
    /// `SOFT_ORDER_SLACK` later than the plan did. A plan through others' soft spans goes after those the others hold now,
    /// whatever the plan assumed: on the airport a task planned to wait 51 s was put behind
    /// two robots' whole ways to parking, and its robot stood 513 s.
    fn later_than_planned(&self, i: usize, keep: usize, plan: &Plan) -> bool {
        let Some(&last) = plan.goal_at.last().filter(|&&n| n > 0) else {
            return false;
        };
        let planned = plan.steps[last - 1].end;
        self.traffic
            .sched
            .computed_end(i, keep + last - 1)
            .is_some_and(|end| end > planned + SOFT_ORDER_SLACK)
    }

    /// Plans robot `o`'s way to parking again after its task's last place (its soft
    /// traversals, which another robot's task plan went before), through nobody's spans.
    /// False when there is no way now.
    fn park_again(&mut self, o: usize, now: f64) -> bool {
        let Some(keep) = self.traffic.sched.soft_keep(o) else {
            return false;
        };
        let it = self.traffic.sched.itinerary(o);
        // From its last place, after the work there.
        let (from, t0, work) = match keep.checked_sub(1).and_then(|k| it.travs.get(k)) {
            Some(tr) => (
                tr.to,
                tr.end.max(now),
                it.travs.get(keep).map_or(0.0, |n| n.hold),
            ),
            None => (it.at, it.ready.max(now), 0.0),
        };
        let goals = [(from, work)];
        let f = &self.fleets[self.robots[o].fleet];
        let (slot, kin) = (f.slot, f.kin);
        let stay = self.stays_at(o, &goals);
        for (own, stay) in self.ends(o, &goals, from, stay) {
            let q = Query {
                robot: o,
                slot,
                kin,
                from,
                t0,
                goals: &goals,
                parks: own.as_deref().unwrap_or(GRAPH_PARKS),
                stay,
                soft: false,
                delay: None,
            };
            if let Some(plan) = self.traffic.plan(&self.nav, q) {
                let soft = plan.goal_at.last().copied();
                let jumped = self.traffic.sched.install(o, keep, &plan.steps, t0, soft);
                debug_assert!(jumped.is_empty(), "a hard plan jumped {jumped:?}");
                self.robots[o].dirty = true;
                return true;
            }
        }
        false
    }

    /// Plans robot `i` to `goals` (then a parking vertex) from where its committed
    /// traversals end, and installs the plan. Returns the traversals to the first goal.
    pub(super) fn plan_to(
        &mut self,
        i: usize,
        goals: &[(usize, f64)],
        t: f64,
    ) -> Result<usize, NoPlan> {
        let r = match self.plan_with(i, goals, None, t) {
            Err(NoPlan::Busy) if self.displace_for(i, goals, t) => {
                self.plan_with(i, goals, None, t)
            }
            r => r,
        };
        if r.is_err() {
            // Only the robot's own plans wait to be tried again (not the tries to make it
            // make room for others, which would put its own off for ever).
            self.robots[i].replan_at = t + REPLAN_AFTER;
        }
        r
    }

    /// Robot `i`'s plan from `from` at `t0` to `goals` with the first of `ends` (in order of
    /// preference) it can end on, through the others' soft spans or not and within a delay
    /// bound or not (`soft`, `delay`), ending where `parks` say when an end has none of its
    /// own (default: the graph's parking vertices); and whether a way was cut only by the
    /// delay bound.
    pub(super) fn plan_over(
        &mut self,
        i: usize,
        ends: &[End],
        (from, t0): (usize, f64),
        goals: &[(usize, f64)],
        (soft, delay): (bool, Option<Delay>),
        parks: Option<&[u8]>,
    ) -> (Option<Plan>, bool) {
        let f = &self.fleets[self.robots[i].fleet];
        let (slot, kin) = (f.slot, f.kin);
        let mut late = false;
        for (own, stay) in ends {
            let q = Query {
                robot: i,
                slot,
                kin,
                from,
                t0,
                goals,
                parks: own.as_deref().or(parks).unwrap_or(GRAPH_PARKS),
                stay: *stay,
                soft,
                delay,
            };
            let found = self.traffic.plan(&self.nav, q);
            if found.is_some() {
                return (found, late);
            }
            late |= self.traffic.late();
        }
        (None, late)
    }

    /// [`Floor::plan_to`] with the parking vertices `parks` (default: the graph's).
    fn plan_with(
        &mut self,
        i: usize,
        goals: &[(usize, f64)],
        parks: Option<&[u8]>,
        t: f64,
    ) -> Result<usize, NoPlan> {
        self.traffic.retime(t);
        let r = &self.robots[i];
        let slot = self.fleets[r.fleet].slot;
        let keep = self.kept(i);
        let it = self.traffic.sched.itinerary(i);
        let (from, t0) = match keep.checked_sub(1).and_then(|k| it.travs.get(k)) {
            Some(tr) => (tr.to, tr.end.max(t)),
            None => (it.at, t.max(it.ready.min(t))),
        };
        for &(g, _) in goals {
            if !self.nav.times_reachable(slot, from, g) {
                return Err(NoPlan::Unreachable);
            }
        }
        let stay = self.stays_at(i, goals);
        let ends = match parks {
            Some(_) => vec![(None, stay)],
            None => self.ends(i, goals, from, stay),
        };
        let (found, _) = self.plan_over(i, &ends, (from, t0), goals, (false, None), parks);
        let Some(plan) = found else {
            return Err(NoPlan::Busy);
        };
        let all = keep + plan.steps.len();
        self.install(i, keep, plan, t0, None);
        // The first place's leg is the current GoTo's; the others wait in `legs`.
        Ok(match self.robots[i].legs.pop_front() {
            Some(n) => n,
            None => all,
        })
    }

    /// Once a second while robots wait: a robot that stands waiting for its turn, whose
    /// turn the delays of those before it have put off by more than `REPLAN_DELAY`, plans
    /// again from where it stands (its old itinerary stays if no better one is found).
    /// The new plan fits the schedule as it is, so the order stays acyclic.
    pub(super) fn replan_delayed(&mut self, t: f64) {
        self.traffic.retime(t);
        for i in 0..self.robots.len() {
            let r = &self.robots[i];
            let Some(since) = r.waiting else { continue };
            if r.n_sent > 0 || r.gate != Gate::None || t - since < REPLAN_DELAY || t < r.replan_at {
                continue;
            }
            let Some(front) = self.traffic.sched.itinerary(i).travs.front() else {
                continue;
            };
            if front.start - t < REPLAN_DELAY {
                continue;
            }
            let before = self.traffic.sched.end_vertex(i);
            let goals = match r.cur {
                Cur::GoTo {
                    goal,
                    planned: true,
                } => self.remaining_goals(i, goal),
                Cur::None if r.idle() => Vec::new(),
                _ => continue,
            };
            let old_arrival = self.arrival(i, goals.len());
            // An undo log, not a copy: a copy is a new lineage, and putting it back
            // emptied the planner's cache of intervals every time.
            let snapshot = (self.robots[i].legs.clone(), self.robots[i].leg);
            self.traffic.sched.open_tx();
            let better = match self.plan_with(i, &goals, None, t) {
                Ok(leg) => {
                    if !goals.is_empty() {
                        self.robots[i].leg = Some(leg);
                    }
                    self.arrival(i, goals.len()) + 1.0 < old_arrival
                }
                Err(_) => false,
            };
            if better {
                self.traffic.sched.commit();
                self.robots[i].dirty = true;
            } else {
                // Not better: the old itinerary stays.
                self.traffic.sched.rollback();
                (self.robots[i].legs, self.robots[i].leg) = snapshot;
                debug_assert_eq!(before, self.traffic.sched.end_vertex(i));
            }
            self.robots[i].replan_at = t + REPLAN_DELAY;
        }
    }

    /// When robot `i`'s itinerary estimates it at its last place (of `n` goals), or at its
    /// end when it has none.
    pub(super) fn arrival(&self, i: usize, n: usize) -> f64 {
        let it = self.traffic.sched.itinerary(i);
        let legs: usize =
            self.robots[i].leg.unwrap_or(0) + self.robots[i].legs.iter().sum::<usize>();
        let k = if n == 0 {
            it.travs.len()
        } else {
            legs.min(it.travs.len())
        };
        match k.checked_sub(1).and_then(|k| it.travs.get(k)) {
            Some(tr) => tr.end,
            None => it.ready,
        }
    }

    /// Once a second while robots wait: a robot that has waited for the schedule for
    /// `STUCK_AFTER` s is reported once (a `stuck` task event naming whom it waits for).
    pub(super) fn watch_waits(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        for i in 0..self.robots.len() {
            let r = &self.robots[i];
            let Some(since) = r.waiting else { continue };
            if r.stuck_reported || t - since < STUCK_AFTER {
                continue;
            }
            self.robots[i].stuck_reported = true;
            let who: Vec<String> = self
                .traffic
                .sched
                .waits_for(i, 0)
                .into_iter()
                .map(|b| format!("{} ({})", self.robots[b].name, self.status(b)))
                .collect();
            if let Some(ti) = self.robots[i].task {
                let detail = format!("waiting for {}", who.join(","));
                self.event(t, ti, "stuck", Some(i), detail, out);
            }
        }
    }

    /// What robot `i` is doing, for stuck reports.
    pub(super) fn status(&self, i: usize) -> &'static str {
        let r = &self.robots[i];
        if r.n_sent > 0 {
            "moving"
        } else if r.waiting.is_some() {
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
