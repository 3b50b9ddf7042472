//! Making room: robots standing in a plan's way (idle, or with nothing but a way to go)
//! planned again aside, all or nothing, so that a robot whose goal another stays on for good
//! can get there.

use super::*;

/// The schedule, and the legs of the robots [`Floor::aside`] plans again.
type AsideSnapshot = (Schedule, Vec<(VecDeque<usize>, Option<usize>)>);

impl Floor {
    /// Robot `j` stands (not driving, at no door or lift) with nothing but a way to go:
    /// its itinerary may be dropped and planned again.
    pub(super) fn may_stand_aside(&self, j: usize) -> bool {
        let o = &self.robots[j];
        o.n_sent == 0 && o.gate == Gate::None && matches!(o.cur, Cur::GoTo { .. } | Cur::None)
    }

    /// What [`Self::aside`] changes, to put it back.
    pub(super) fn aside_snapshot(&self, who: &[usize]) -> AsideSnapshot {
        let legs = who
            .iter()
            .map(|&j| (self.robots[j].legs.clone(), self.robots[j].leg))
            .collect();
        (self.traffic.sched.clone(), legs)
    }

    pub(super) fn aside_restore(&mut self, who: &[usize], snap: AsideSnapshot) {
        self.traffic.sched = snap.0;
        for (&j, (legs, leg)) in who.iter().zip(snap.1) {
            (self.robots[j].legs, self.robots[j].leg) = (legs, leg);
        }
    }

    /// Robot `i` plans (`plan`) past robots `js` (each [`Self::may_stand_aside`]): they
    /// stand where they are while it plans, then each plans its way again at once, behind
    /// what is in the schedule by then. Every plan fits the schedule as it is, and the
    /// order is checked acyclic; when `plan` declines, a robot set aside finds no way, or
    /// the order would not hold, everything is put back. True when it went through.
    pub(super) fn aside(
        &mut self,
        i: usize,
        js: &[usize],
        t: f64,
        plan: impl FnOnce(&mut Self) -> bool,
    ) -> bool {
        let who: Vec<usize> = std::iter::once(i).chain(js.iter().copied()).collect();
        let snap = self.aside_snapshot(&who);
        // Until each has planned again, a robot set to stand may be ahead of a span of
        // another's that passes where it stands later: no order holds meanwhile, and the
        // retimes and checks on the way must not count that (a delivery robot making room
        // at an empty dispenser did). The order is checked once all have planned.
        self.traffic.aside = true;
        for &j in js {
            self.traffic.sched.install(j, 0, &[], t, None);
        }
        let mut ok = plan(self);
        for &j in js {
            if !ok {
                break;
            }
            let goals = match self.robots[j].cur {
                Cur::GoTo {
                    goal,
                    planned: true,
                } => self.remaining_goals(j, goal),
                _ => Vec::new(),
            };
            ok = match self.plan_with(j, &goals, None, t) {
                Ok(leg) => {
                    if !goals.is_empty() {
                        self.robots[j].leg = Some(leg);
                    }
                    true
                }
                Err(_) => false,
            };
        }
        self.traffic.aside = false;
        ok = ok && self.traffic.sched.retime(t).is_ok();
        if ok {
            for &j in &who {
                self.robots[j].dirty = true;
            }
        } else {
            self.aside_restore(&who, snap);
        }
        ok
    }

    /// Robot `i` waits to ask an empty dispenser again. When other robots wait for it to
    /// leave, it makes room: it drives to a parking vertex, stays there as long as it would
    /// have waited to ask, comes back and asks again (the item it waits for may be the one
    /// another robot brings back). Its request keeps its tries and time limit. The robots
    /// that waited for it plan again behind it ([`Self::aside`]). True when it set off.
    pub(in crate::fleet) fn make_room(&mut self, i: usize, t: f64) -> bool {
        let r = &self.robots[i];
        // Wherever it stands, a parking vertex too (a task place may be one): the robots
        // whose plans pass there after it wait for it, and the item it waits for may be on
        // one of them.
        if r.n_sent > 0 || r.gate != Gate::None {
            return false;
        }
        let waiters: Vec<usize> = (0..self.robots.len())
            .filter(|&j| {
                j != i
                    && self.robots[j].waiting.is_some()
                    && self.may_stand_aside(j)
                    && self.traffic.sched.waits_for(j, 0).contains(&i)
            })
            .collect();
        if waiters.is_empty() {
            return false;
        }
        let back = r.at;
        let mut leg = 0;
        let went = self.aside(i, &waiters, t, |f| {
            // The task's later legs were planned from this place: they are planned again
            // on the way.
            f.robots[i].legs.clear();
            // Anywhere but here (it may stand on a place that is a parking vertex).
            let mut elsewhere = f.traffic.parks(f.robots[i].slot).to_vec();
            elsewhere[back] = 0;
            match f.plan_with(i, &[], Some(&elsewhere), t) {
                Ok(n) if f.traffic.sched.end_vertex(i) != back => {
                    leg = n;
                    true
                }
                _ => false,
            }
        });
        if !went {
            return false;
        }
        let park = self.traffic.sched.end_vertex(i);
        let r = &mut self.robots[i];
        let cur = std::mem::replace(
            &mut r.cur,
            Cur::GoTo {
                goal: park,
                planned: true,
            },
        );
        r.leg = Some(leg);
        r.legs.clear();
        r.steps.push_front(Step::Resume(Box::new(cur)));
        r.steps.push_front(Step::GoTo(back));
        r.steps.push_front(Step::Dwell(ITEM_RETRY));
        // The way to park, the stay there and the way back are no phases.
        r.detour = 3;
        true
    }

    /// Robots whose itineraries end where one of robot `i`'s `goals` is (a task place that
    /// is also a parking vertex), idle robots that stay off the parking vertices, and idle
    /// robots parked on robot `i`'s shortest way are planned again to end on other parking
    /// vertices (off that way), keeping their own goal and its work: their stay for good
    /// there may be what keeps robot `i` from planning. A robot driving to its task's place
    /// keeps its plan when the new one would get there later. True when one moved.
    pub(in crate::fleet) fn displace_for(
        &mut self,
        i: usize,
        goals: &[(usize, f64)],
        t: f64,
    ) -> bool {
        let conf = self.traffic.sched.conf();
        let mut near: Vec<Res> = goals
            .iter()
            .flat_map(|&(g, _)| conf.vertex[g].iter().copied())
            .collect();
        near.sort_unstable();
        near.dedup();
        let off: Vec<bool> = conf
            .vertex
            .iter()
            .map(|set| set.iter().any(|x| near.binary_search(x).is_ok()))
            .collect();
        // The vertices robot `i`'s shortest way to its goals passes (and their neighbours
        // in conflict): where a robot made to make room should not stay.
        let mut on_way = off.clone();
        {
            let r = &self.robots[i];
            let f = &self.fleets[r.fleet];
            let mut at = self.traffic.sched.end_vertex(i);
            if r.n_sent == 0 {
                at = self.traffic.sched.itinerary(i).at;
            }
            let mut way: Vec<usize> = vec![at];
            for &(g, _) in goals {
                if let Some((_, es)) = self.nav.plan(f.slot, at, g, f.speed) {
                    way.extend(es.iter().map(|&e| self.nav.edges[e].to));
                }
                at = g;
            }
            let mut res: Vec<Res> = way
                .iter()
                .flat_map(|&v| conf.vertex[v].iter().copied())
                .collect();
            res.sort_unstable();
            res.dedup();
            for (v, set) in conf.vertex.iter().enumerate() {
                if set.iter().any(|x| res.binary_search(x).is_ok()) {
                    on_way[v] = true;
                }
            }
        }
        // Those whose stay for good is at a goal, standing robots staying anywhere but on a
        // parking vertex, and idle robots parked on robot `i`'s way: such a stay may cut
        // it (each parking vertex keeps the graph connected alone, not all of them
        // together).
        let blockers: Vec<usize> = (0..self.robots.len())
            .filter(|&o| o != i && self.robots[o].gate == Gate::None)
            .filter(|&o| {
                let r = &self.robots[o];
                let end = self.traffic.sched.end_vertex(o);
                off[end]
                    || (r.n_sent == 0 && self.traffic.parks(r.slot)[end] == 0)
                    || (r.n_sent == 0 && r.idle() && on_way[end])
            })
            .collect();
        let mut moved = false;
        for o in blockers {
            let r = &self.robots[o];
            // What it is doing stays: its leg's goal, the work at its place, or the task it
            // took this round and has not started (planned again without its places, it
            // went to park and started the task from there with no plan).
            let pending = r.cur == Cur::None && !r.steps.is_empty();
            let (own, leg): (Vec<(usize, f64)>, bool) = match r.cur {
                Cur::GoTo {
                    goal,
                    planned: true,
                } => (self.remaining_goals(o, goal), true),
                Cur::Dwell { until } => (self.working_goals(o, (until - t).max(0.0)), false),
                Cur::Workcell { .. } => (self.working_goals(o, WORKCELL_ESTIMATE), false),
                // It charges on where it stands until it is full (it used to be planned
                // to leave after a minute, and the robots planned behind it waited hours).
                Cur::Charge { pct, .. } => (self.working_goals(o, self.charge_left(o, pct)), false),
                Cur::None if pending => {
                    let steps: Vec<Step> = r.steps.iter().cloned().collect();
                    (self.goals_of(o, &steps), false)
                }
                _ => (Vec::new(), false),
            };
            if r.n_sent > 0 && !leg && !pending {
                continue;
            }
            // Its own task ends where it stays, at a place asked for (a go-to-place on its
            // way there): planned again, it would end there again, yet count as room made
            // (every `DISPLACE_EVERY` s while the task waits). It makes room once its task
            // is done.
            if self.stays_at(o, &own).is_some_and(|v| off[v]) {
                continue;
            }
            let slot = r.slot;
            let mask: Vec<u8> = self
                .traffic
                .parks(slot)
                .iter()
                .enumerate()
                .map(|(v, &p)| if off[v] { 0 } else { p })
                .collect();
            // No parking vertex left for it: any vertex off robot `i`'s way will do for a
            // while (a robot staying there is moved on again when it is in the way).
            let anywhere: Vec<u8> = (0..mask.len())
                .map(|v| {
                    if mask[v] != 0 {
                        mask[v]
                    } else if off[v] || on_way[v] || self.nav.vertices[v].lift.is_some() {
                        0
                    } else {
                        PARK_ON_PLACE
                    }
                })
                .collect();
            // Making room never delays a robot's own task: a new plan that reaches its
            // places later (it may have to wait out of the others' way, for minutes) is
            // undone, and the robot keeps its plan.
            let task = (leg || pending) && self.robots[o].task.is_some();
            let before = task.then(|| {
                let r = &self.robots[o];
                let snap = (self.traffic.sched.clone(), r.legs.clone(), r.leg);
                (snap, self.arrival(o, own.len()))
            });
            let end = self.traffic.sched.end_vertex(o);
            let mut res = if self.traffic.parks(slot)[end] != 0 && !off[end] {
                // Parked on the way: to a parking vertex off it, or it stays.
                let clear: Vec<u8> = (0..mask.len())
                    .map(|v| if on_way[v] { 0 } else { mask[v] })
                    .collect();
                self.plan_with(o, &own, Some(&clear), t)
            } else {
                match self.plan_with(o, &own, Some(&mask), t) {
                    Err(NoPlan::Busy) => self.plan_with(o, &own, Some(&anywhere), t),
                    r => r,
                }
            };
            if pending {
                // Its first leg is for the step it starts next, not a leg under way.
                if let Ok(l) = res {
                    self.robots[o].legs.push_front(l);
                }
            }
            if let (Ok(l), Some((snap, old))) = (&res, before) {
                let was = if pending {
                    self.robots[o].leg
                } else {
                    self.robots[o].leg.replace(*l)
                };
                if self.arrival(o, own.len()) > old + 1.0 {
                    (self.traffic.sched, self.robots[o].legs, self.robots[o].leg) = snap;
                    res = Err(NoPlan::Busy);
                } else {
                    self.robots[o].leg = was;
                }
            }
            if let Ok(l) = res {
                if leg {
                    self.robots[o].leg = Some(l);
                }
                let r = &mut self.robots[o];
                r.dirty = true;
                if matches!(r.finish, Finish::Home(_)) && r.idle() {
                    // Made to leave its home while idle: back there a while later.
                    r.park_pending = true;
                    r.replan_at = t + HOME_AGAIN;
                    r.wake = r.wake.min(r.replan_at);
                }
                moved = true;
            }
        }
        moved
    }
}
