//! One dispatch round: tasks oldest first, each planned for its nearest free robots and
//! given to the one whose plan arrives first, unless a busy robot's bid beats it (gets
//! there and has it done first) or every plan waits too long; then the robot takes the
//! task with its plan installed.

use super::*;

/// A round's bounds and memo: plans it may still make, the plans made (by what they are a
/// plan of, with the schedule they were made against: the same plan asked again, the next
/// task between the same places, is that plan while the schedule stays, as a search is a
/// function of the two), and whether robots were asked to make room already.
struct Round {
    budget: usize,
    made: BTreeMap<Same, (u64, Option<Plan>, bool)>,
    displaced: bool,
}

/// A task's bids: its free robots (free-flow time, robot, which of the task's fleets),
/// nearest first; how soon a busy robot could get there after its task (s from now), and
/// that robot's free-flow time from its task's last place.
struct Bids {
    near: Vec<(f64, usize, usize)>,
    after: Option<f64>,
    approach: f64,
    /// Per fleet of the task's (by its robots' fleet): its free-flow time from the task's
    /// first place to its end, with the work at each place.
    rest: Vec<(usize, f64)>,
    /// The busy bid's robot's fleet.
    after_fleet: usize,
}

/// The time from the task's first place to its end for fleet `fi` (0 when unknown).
fn rest_for(rest: &[(usize, f64)], fi: usize) -> f64 {
    rest.iter().find(|r| r.0 == fi).map_or(0.0, |r| r.1)
}

/// A task's candidates planned: the best plan, the robots refused with until when, and
/// whether some found no way.
struct Tried {
    best: Option<Best>,
    refused: Vec<(usize, f64)>,
    failed: bool,
}

impl Dispatcher {
    /// A go-to-place to where a free robot stands (and may stay) is done the moment that
    /// robot takes it, at no robot time and in nobody's way, so it delays no other task:
    /// for each such robot, the oldest such task goes first in its priority. (A robot
    /// standing at one of two places at the end of a long single track took the oldest
    /// task, for the other, a 200 s round trip, while the tasks for its own place waited
    /// behind it.)
    pub(super) fn done_where_they_stand(&mut self, fl: &Floor, free: &[Free]) {
        let standing: BTreeMap<usize, usize> = free
            .iter()
            .filter(|f| f.2 <= 0.0 && fl.robots[f.0].n_sent == 0)
            .map(|f| (f.1, f.0))
            .collect();
        debug_assert_eq!(self.go_tos, self.pending.iter().filter(|p| p.go_to).count());
        if standing.is_empty() || self.go_tos == 0 {
            return;
        }
        let mut first: Vec<(usize, usize)> = Vec::new();
        let mut served: Vec<usize> = Vec::new();
        for (k, p) in self.pending.iter().enumerate() {
            if !p.go_to {
                continue;
            }
            let here = p.steps.iter().find_map(|(fi, st)| match st.as_slice() {
                [Step::GoTo(v)] => standing
                    .get(v)
                    .filter(|&&ri| fl.robots[ri].fleet == *fi)
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
            .filter_map(|&(k, ri)| Some((self.remove(k)?, ri)))
            .collect();
        for (mut p, ri) in moved {
            // Whatever kept it waiting for this robot (asleep, backed off, deferred to a
            // busy one) was about getting there, and it is there.
            p.asleep = None;
            p.deferred = None;
            p.backoff.retain(|b| b.0 != ri);
            let at = self.pending.partition_point(|q| q.priority > p.priority);
            self.insert(at, p);
        }
    }

    /// One dispatch round: tasks oldest first, each to the free robot whose plan gets
    /// there first. Tasks no robot can take now stay queued. A round looks at no more
    /// than `SCAN_PER_ROUND` tasks and makes no more than `PLANS_PER_ROUND` plans.
    pub(in crate::fleet) fn round(&mut self, fl: &mut Floor, t: f64, out: &mut Vec<(Topic, Msg)>) {
        if t < self.next_dispatch || self.pending.is_empty() {
            return;
        }
        self.last_round = t;
        self.next_dispatch = f64::INFINITY;
        fl.traffic.retime(t);
        let mut free = fl.free_robots(t);
        self.done_where_they_stand(fl, &free);
        // Not needed when no robot is free: no task is looked at then.
        let mut busy = if free.is_empty() {
            Vec::new()
        } else {
            fl.busy_robots(t)
        };
        for f in &free {
            let r = &mut fl.robots[f.0];
            if !self.was_free(f.0) || r.free_since == f64::INFINITY {
                r.free_since = t;
            }
        }
        self.start_round(t, &free, fl.robots.len());
        let work_before = fl.traffic.expanded();
        let mut round = Round {
            budget: PLANS_PER_ROUND,
            made: BTreeMap::new(),
            displaced: false,
        };
        let mut k = 0;
        let mut scanned = 0;
        while k < self.pending.len()
            && round.budget > 0
            && (fl.traffic.expanded() - work_before) as f64 <= self.work
            && !free.is_empty()
            && scanned < SCAN_PER_ROUND
        {
            // Asleep: nothing changed that could let it be taken.
            if let Some((until, freed)) = self.pending[k].asleep {
                if t < until && freed == self.freed {
                    k += 1;
                    continue;
                }
            }
            self.pending[k].asleep = None;
            scanned += 1;
            if self.item_away(fl, k, t) {
                k += 1;
                continue;
            }
            let ti = self.pending[k].task;
            let Bids {
                near,
                after,
                approach,
                rest,
                after_fleet,
            } = self.bids(fl, k, &free, &busy);
            let after_rest = rest_for(&rest, after_fleet);
            // Its free robots' plans lost to a busy robot that still gets there first, and
            // no robot that was not planned for could beat it.
            if let (Some(a), Some(d)) = (after, &self.pending[k].deferred) {
                if d.holds(t, (a, a + after_rest), &near) {
                    self.wait_for_busy(k, a, t);
                    k += 1;
                    continue;
                }
            }
            self.pending[k].deferred = None;
            // A busy robot gets there before any free one could (free flow is the
            // soonest a plan arrives): the task waits for it, as RMF queues a task after
            // a robot's current one. Not planned for the free robots now, so they stay
            // for tasks only they are first to. Only when it would also have the task
            // done first: a slower fleet's robot there first finishes later, while the
            // faster one stands idle (generated building 89, a Tiny and a DeliveryRobot
            // fleet: three robots completed 99 tasks where two completed 115, the
            // DeliveryRobot idle 2,768 s of the hour while the Tiny robots chained tasks).
            let free_done = near
                .iter()
                .map(|c| c.0 + rest_for(&rest, fl.robots[c.1].fleet))
                .fold(f64::INFINITY, f64::min);
            if let Some(eta) = after
                .filter(|&a| near.first().is_none_or(|n| a < n.0) && a + after_rest < free_done)
            {
                self.wait_for_busy(k, eta, t);
                k += 1;
                continue;
            }
            let near = self.candidates(fl, k, near, &free);
            let looked_at = near.len();
            let planned: Vec<usize> = near.iter().map(|c| c.1).collect();
            let Tried {
                best,
                refused,
                failed,
            } = self.plan_candidates(fl, k, ti, near, t, &mut round);
            let Some(best) = best else {
                self.no_taker(
                    fl,
                    k,
                    (refused, failed, looked_at),
                    &free,
                    &mut round.displaced,
                    t,
                );
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
            // throughput) than the task gains by starting sooner. And, as above, it would
            // have the task done first too.
            let extra = (best.eta - approach).max(0.0);
            let best_rest = rest_for(&rest, fl.robots[best.robot].fleet);
            let beat = best.arrive + waited + extra;
            if let Some(eta) =
                after.filter(|&a| t + a < beat && t + a + after_rest < beat + best_rest)
            {
                let p = &mut self.pending[k];
                p.backoff = refused;
                p.deferred = Some(Deferred {
                    beat,
                    beat_done: beat + best_rest,
                    planned,
                });
                self.wait_for_busy(k, eta, t);
                k += 1;
                continue;
            }
            let ri = best.robot;
            // Where and when the task will end, for its robot's bid on the next tasks.
            let (last, done) = fl.task_end(ri, &best.steps, &best.plan, best.t0);
            let start = (best.keep, best.t0, best.soft.then_some(t));
            if !fl.start_task(ri, ti, best.steps, best.plan, start, t, out) {
                // A robot it went before on its way to parking found no way behind it.
                self.pending[k].hard = true;
                self.same
                    .insert(best.same, (t + MAX_BACKOFF, Refused::Undone));
                k += 1;
                continue;
            }
            self.remove(k);
            self.late_until[ri] = f64::NEG_INFINITY;
            free.retain(|f| f.0 != ri);
            // The robot bids for the tasks after it in this round as a busy robot, from
            // where this one ends. (Left out until the next round, robots free together
            // each took a task, the second's plan waiting long behind the first's, where
            // the first would have done both in turn.)
            if let Some(last) = last {
                busy.push((ri, last, done - t));
            }
        }
        if !self.pending.is_empty() {
            fl.retreat(&free, t);
        }
        self.work -= (fl.traffic.expanded() - work_before) as f64;
        if !self.pending.is_empty() {
            self.next_dispatch = t + DISPATCH_EVERY;
        }
    }

    /// A delivery whose dispenser's item is away (on a robot, on its way home, or
    /// promised to a robot on its way there) waits in the queue: a robot sent now
    /// would stand at the empty dispenser until the item is back (minutes, on a
    /// large building), in others' way.
    fn item_away(&self, fl: &Floor, k: usize, t: f64) -> bool {
        self.pending[k].steps.iter().any(|(_, st)| {
            st.iter()
                .any(|s| matches!(s, Step::Dispense(d) if fl.dispenser_taken(d, t)))
        })
    }

    /// The bids for pending task `k`: its free robots (of `free`) by free-flow time to its
    /// first place, nearest first, and the soonest a busy robot (of `busy`) could get
    /// there after its task.
    fn bids(&mut self, fl: &Floor, k: usize, free: &[Free], busy: &[Busy]) -> Bids {
        // The nearest free robots by free-flow time to the task's first place.
        // (time, robot, which of the task's fleets): the steps are cloned for the few
        // kept only (with hundreds of robots free, cloning them for each was a tenth
        // of a warehouse run, in the allocator).
        let mut near: Vec<(f64, usize, usize)> = Vec::new();
        // How soon a busy robot could get there after its task (s from now).
        let mut after: Option<f64> = None;
        // That robot's free-flow time from its task's last place.
        let mut approach = 0.0;
        let mut after_fleet = usize::MAX;
        // The fleets that bid, by their steps.
        let mut bidding: Vec<(usize, usize)> = Vec::new();
        let only = self.pending[k].robot;
        let firsts: Vec<(usize, usize, usize)> = self.pending[k]
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
            let bids = |r: usize| fl.robots[r].fleet == fi;
            if !free.iter().any(|f| bids(f.0))
                && (only.is_some() || !busy.iter().any(|b| bids(b.0)))
            {
                continue;
            }
            bidding.push((n, fi));
            let fleet = &fl.fleets[fi];
            let table = self.eta_table(&fl.nav, fleet, first);
            for f in free {
                if fl.robots[f.0].fleet == fi && only.is_none_or(|o| o == f.0) {
                    let eta = table[f.1] + f.2;
                    if eta.is_finite() {
                        near.push((eta, f.0, n));
                    }
                }
            }
            if only.is_some() {
                continue;
            }
            for &(ri, last, done) in busy {
                if fl.robots[ri].fleet == fi {
                    let eta = done + table[last];
                    if eta.is_finite() && after.is_none_or(|a| eta < a) {
                        after = Some(eta);
                        approach = table[last];
                        after_fleet = fi;
                    }
                }
            }
        }
        near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        // Needed only against a busy robot's bid, and only with two fleets or more bidding
        // (with one, every bid's time from the first place on is the same).
        let rest: Vec<(usize, f64)> = if after.is_some() && bidding.len() > 1 {
            bidding
                .iter()
                .map(|&(n, fi)| (fi, self.rest_of(fl, k, n, free, busy)))
                .collect()
        } else {
            Vec::new()
        };
        Bids {
            near,
            after,
            approach,
            rest,
            after_fleet,
        }
    }

    /// The free-flow time of pending task `k` from its first place on, for its fleet of
    /// steps `n` (at that fleet's speed, with the work at each place; one of the fleet's
    /// robots, of `free` or `busy`, stands for it).
    fn rest_of(&mut self, fl: &Floor, k: usize, n: usize, free: &[Free], busy: &[Busy]) -> f64 {
        let fi = self.pending[k].steps[n].0;
        let robot = free.iter().map(|f| f.0).chain(busy.iter().map(|b| b.0));
        let Some(ri) = robot.into_iter().find(|&r| fl.robots[r].fleet == fi) else {
            return 0.0;
        };
        let goals = fl.goals_of(ri, &self.pending[k].steps[n].1);
        let mut rest = goals.first().map_or(0.0, |g| g.1);
        for w in goals.windows(2) {
            rest += self.eta_table(&fl.nav, &fl.fleets[fi], w[1].0)[w[0].0] + w[1].1;
        }
        rest
    }

    /// The robots pending task `k` is planned for, of its free robots `near` (nearest
    /// first): the `CANDIDATES` nearest, with the task's steps for each. Free robots that
    /// stay for good on one of the task's places are candidates too, however far: no other
    /// robot can get there while they stay, and doing the task moves them off (as in Token
    /// Passing, a robot whose endpoint a task needs takes the task or makes room).
    fn candidates(
        &self,
        fl: &Floor,
        k: usize,
        near: Vec<(f64, usize, usize)>,
        free: &[Free],
    ) -> Vec<(f64, usize, Vec<Step>)> {
        let holders = self.holders(fl, k, free);
        near.into_iter()
            .enumerate()
            .filter(|(n, c)| *n < CANDIDATES || holders.contains(&c.1))
            .map(|(_, (eta, ri, n))| (eta, ri, self.pending[k].steps[n].1.clone()))
            .collect()
    }

    /// Plans pending task `ti` (at `k`) for its candidates `near` (free-flow time, robot,
    /// the task's steps for it): the plan that arrives first among those not refused, the
    /// robots refused (backed off, or their plans waiting too long) with until when, and
    /// whether some found no way.
    fn plan_candidates(
        &mut self,
        fl: &mut Floor,
        k: usize,
        ti: usize,
        near: Vec<(f64, usize, Vec<Step>)>,
        t: f64,
        round: &mut Round,
    ) -> Tried {
        // Task plans go through the others' ways to parking (see `schedule`).
        let task_soft = !self.pending[k].hard;
        let mut best: Option<Best> = None;
        let mut failed = false;
        // Robots whose plans for it waited too long now and will, planned again.
        let mut refused: Vec<(usize, f64)> = Vec::new();
        for (eta, ri, steps) in near {
            // Planning again for a robot before its backoff ends cannot succeed unless
            // the others got ahead of their plans: a later start shortens a plan's
            // waits by at most the delay, and the plans installed since only add spans.
            if let Some(&(_, until)) = self.pending[k].backoff.iter().find(|b| b.0 == ri) {
                if t < until {
                    refused.push((ri, until));
                    continue;
                }
            }
            let goals = fl.goals_of(ri, &steps);
            let stay = matches!(fl.tasks[ti].kind, TaskKind::GoToPlace { .. })
                .then(|| goals.last().map(|g| g.0))
                .flatten();
            let (keep, from, t0) = fl.plan_start(ri, t);
            // The same plan through soft spans was undone for another task (a robot it
            // went before found no way behind it): this one keeps clear of them. With
            // a few places and a saturating stream, one task after another was
            // planned, installed and undone while robots stood idle.
            let undone = Same::new(ri, from, true, stay, &goals);
            let soft = task_soft
                && !matches!(self.same.get(&undone), Some(&(until, Refused::Undone)) if t < until);
            // The same plan (robot, start, places) was refused for another task: the
            // reason above holds for it too (a saturating stream queues many tasks
            // between the same places).
            let same = Same::new(ri, from, soft, stay, &goals);
            if let Some(&(until, why)) = self.same.get(&same) {
                if t < until && why != Refused::Undone {
                    failed |= why == Refused::NoWay;
                    if why == Refused::Late {
                        self.late(ri, until);
                    }
                    refused.push((ri, until));
                    continue;
                }
            }
            round.budget = round.budget.saturating_sub(1);
            let stamp = fl.traffic.sched.stamp();
            let (found, late) = match round.made.get(&same) {
                Some((at, found, late)) if *at == stamp => (found.clone(), *late),
                _ => {
                    let (found, late) =
                        fl.task_plan(ri, &goals, (from, t0), stay, (soft, SEARCH_DELAY));
                    round
                        .made
                        .insert(same.clone(), (stamp, found.clone(), late));
                    (found, late)
                }
            };
            let over = match &found {
                // Every way there is later than the search looks: refused for long.
                None if late => MAX_BACKOFF,
                None => {
                    failed = true;
                    refused.push((ri, t + NO_WAY_BACKOFF));
                    self.same.insert(same, (t + NO_WAY_BACKOFF, Refused::NoWay));
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
                    let idle_here = keep == 0 && fl.traffic.sched.end_vertex(ri) == from;
                    let waited: f64 = waits(plan, t0).skip(usize::from(idle_here)).sum();
                    (waited - (MAX_PLANNED_WAIT + WAIT_SHARE * length))
                        .max(longest_wait(plan, t0) - LONGEST_WAIT)
                }
            };
            let Some(plan) = found.filter(|_| over <= 0.0) else {
                let until = t + over.clamp(DISPATCH_EVERY, MAX_BACKOFF);
                refused.push((ri, until));
                self.late(ri, until);
                self.same.insert(same, (until, Refused::Late));
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
        let best = self.yield_to_faster(fl, best, &mut refused, t);
        Tried {
            best,
            refused,
            failed,
        }
    }

    /// Robot `ri`'s plan was refused for waiting too long, until `until`.
    fn late(&mut self, ri: usize, until: f64) {
        if let Some(l) = self.late_until.get_mut(ri) {
            *l = l.max(until);
        }
    }

    /// The best plan for a task, unless a faster robot among its candidates (`refused`)
    /// was refused it for waiting on traffic: then the slower robot does not take it
    /// either, and is backed off as long as the faster one. On a corridor the robots
    /// share, the way's time is what a saturating stream has too little of, and a faster
    /// robot spends less of it per task: a slower robot that takes the task keeps the way
    /// busy and the faster one idle. (Generated building 569, a TinyRobot and a
    /// DeliveryRobot fleet on one corridor: a second Tiny took the deliveries while the
    /// DeliveryRobot stood idle 1,731 s of the hour, and three robots completed 12 % less
    /// than two.) Robots of one speed are not held up by each other.
    fn yield_to_faster(
        &self,
        fl: &Floor,
        best: Option<Best>,
        refused: &mut Vec<(usize, f64)>,
        t: f64,
    ) -> Option<Best> {
        let b = best?;
        let speed = |r: usize| fl.fleets[fl.robots[r].fleet].speed;
        let faster = refused
            .iter()
            .filter(|&&(h, _)| speed(h) > speed(b.robot) && self.late_until[h] > t)
            .map(|&(h, _)| self.late_until[h])
            .fold(f64::NEG_INFINITY, f64::max);
        if faster > t {
            refused.push((b.robot, faster));
            None
        } else {
            Some(b)
        }
    }

    /// No free robot took pending task `k` (`refused`, whether some `failed` to find a
    /// way, of the `looked_at` candidates): it sleeps when every candidate is backed off,
    /// and a robot staying for good where it must go is asked to make room (one task per
    /// round: `displaced`).
    fn no_taker(
        &mut self,
        fl: &mut Floor,
        k: usize,
        (refused, failed, looked_at): (Vec<(usize, f64)>, bool, usize),
        free: &[Free],
        displaced: &mut bool,
        t: f64,
    ) {
        // No free robot may do it (a robot task whose robot is busy), or every one
        // that may is backed off (those that found no way for `NO_WAY_BACKOFF`: they
        // may find one as soon as others make room): only time or a robot becoming
        // free changes that.
        if refused.len() == looked_at {
            let until = refused.iter().map(|r| r.1).fold(f64::INFINITY, f64::min);
            self.pending[k].asleep = Some((until, self.freed));
        }
        self.pending[k].backoff = refused;
        // Room is made for one task per round, the oldest that needs it: for two
        // tasks in turn, the same robot would be sent back and forth between them.
        if failed && !*displaced && t >= self.pending[k].displaced_at + DISPLACE_EVERY {
            *displaced = true;
            self.pending[k].displaced_at = t;
            // Maybe a robot stays for good where the task must go: it makes room.
            let found = self.pending[k].steps.iter().find_map(|(fi, st)| {
                free.iter()
                    .find(|f| fl.robots[f.0].fleet == *fi)
                    .map(|f| (f.0, st.clone()))
            });
            if let Some((ri, steps)) = found {
                let goals = fl.goals_of(ri, &steps);
                fl.displace_for(ri, &goals, t);
            }
        }
    }

    /// The free robots (of `free`) that stay for good on a place of pending task `k`.
    pub(super) fn holders(&self, fl: &Floor, k: usize, free: &[Free]) -> Vec<usize> {
        let conf = fl.traffic.sched.conf();
        let mut out = Vec::new();
        for (_, steps) in &self.pending[k].steps {
            for s in steps {
                let Step::GoTo(g) = s else { continue };
                for &x in &conf.vertex[*g] {
                    if let Some(o) = fl.traffic.sched.held_for_good(x, usize::MAX, false) {
                        if free.iter().any(|f| f.0 == o) && !out.contains(&o) {
                            out.push(o);
                        }
                    }
                }
            }
        }
        out
    }
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
