//! Traffic planning for the fleets (see ARCHITECTURE.md).

use super::*;

impl Fleets {
    /// Holds the standing set of the current vertex plus the sets of reserved edges.
    pub(super) fn rehold(&mut self, i: usize) {
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
    pub(super) fn try_reserve(&mut self, i: usize, t: f64) -> bool {
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
    pub(super) fn admission(&self, i: usize, k: usize) -> Vec<usize> {
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
    pub(super) fn segment(&self, i: usize, from: usize) -> usize {
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

    pub(super) fn is_plain(&self, e: usize) -> bool {
        let edge = &self.nav.edges[e];
        edge.kind == EdgeKind::Lane
            && !edge.door.is_some_and(|d| self.nav.doors[d].controlled)
            && self.nav.vertices[edge.from].lift.is_none()
            && self.nav.vertices[edge.to].lift.is_none()
    }

    pub(super) fn traffic_check(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
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
    pub(super) fn can_back_off(&self, b: usize) -> bool {
        let rb = &self.robots[b];
        rb.gate == Gate::None
            && rb.n_sent == 0
            && rb.wait_since.is_some()
            && matches!(rb.cur, Cur::GoTo { .. })
    }

    /// Robot `b` drives to `v`, waits there, then resumes its GoTo from scratch.
    pub(super) fn back_off(
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
    pub(super) fn resolve_deadlock(
        &mut self,
        cycle: &[usize],
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) {
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
    pub(super) fn detour(&mut self, b: usize, avoid: &[Res]) -> bool {
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
    pub(super) fn needed(&self, who: &[usize], edges: &[usize], horizon: usize) -> Vec<Res> {
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
    pub(super) fn free_spot(
        &self,
        b: usize,
        needed: &[Res],
        ignore: Option<usize>,
    ) -> Option<usize> {
        self.free_spot_timed(b, needed, ignore, false).map(|x| x.0)
    }

    /// [`Fleets::free_spot`] with the travel time there.
    pub(super) fn free_spot_timed(
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
    pub(super) fn edge_free(&self, b: usize, e: usize, ignore: Option<usize>) -> bool {
        let standing = &self.conf.vertex[self.robots[b].at];
        let set: Vec<Res> = self.conf.edge[e]
            .iter()
            .copied()
            .filter(|x| standing.binary_search(x).is_err())
            .collect();
        self.res.is_free_ignoring(b, &set, ignore)
    }

    /// What robot `i` is doing, for stuck reports.
    pub(super) fn status(&self, i: usize) -> &'static str {
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
