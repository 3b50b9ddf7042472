//! Traffic planning: which robot may drive where next, and who makes room for whom.
//!
//! Robots reserve conflict sets (`crate::traffic`) all or nothing: through a corridor to the
//! next place where robots can pass (`segment`), into a lift through the ride and the lane
//! out at the destination. A reserved segment is always driven to its end, so robots that
//! move never block each other for good; the only waits that could last for ever are
//! between robots at rest. Those are ordered by priority (`Robot::prio`: when the robot
//! began the move it waits to make; moves made to make room keep the priority of the move
//! they interrupt, idle robots have none):
//!
//! - the waiting robot of highest priority, the *claimant*, claims the resources of its
//!   next segment: no other robot may reserve them (except to leave them), and every robot
//!   at rest on them is pushed to the nearest free spot off them (`push`);
//! - when none of the robots in its way can get out of it (a dead end behind them), the
//!   claimant makes room for one of them instead, which then claims in its place (`yield`).
//!
//! So the claimant's way empties in bounded time (nobody enters it, everyone on it moves
//! off or leaves), it drives, and it stays the claimant at every wait until its move is
//! done; then the next oldest waiter is served. Every waiting robot becomes the claimant
//! eventually, so no robot waits for ever and no set of robots can hold each other up: no
//! wait-for cycle is ever resolved by failing a task. Idle robots never block: they park
//! off the task routes (`park.rs`) and are pushed aside by any waiting robot.

use super::*;

/// Edges of the claimant's route ahead that a robot pushed out of its way avoids, when it
/// can (else it only avoids the claimed segment).
const ESCAPE_HORIZON: usize = 8;
/// A pushed robot that has not got going after this long (s) is pushed again.
const REPUSH_AFTER: f64 = 2.0;
/// How many robots deep a push may reach (robots waiting at rest in the way of a robot
/// that makes room are pushed first).
const PUSH_DEPTH: u32 = 3;
/// Most robots a jam is searched for (see `unjam`).
const JAM_MAX: usize = 32;
/// The claimant waits this long (s) for the robots in its way before it makes room for
/// one of them instead.
const YIELD_AFTER: f64 = 5.0;

/// The sorted union of two sorted resource lists.
fn union(a: &[Res], b: &[Res]) -> Vec<Res> {
    let mut u = [a, b].concat();
    u.sort_unstable();
    u.dedup();
    u
}

/// Whether two sorted resource lists share an element.
pub(super) fn meets(a: &[Res], b: &[Res]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => return true,
        }
    }
    false
}

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

    /// Robot `i`'s next reservation: the number of edges from `route[n_res]` and their
    /// resources (sorted), less what its standing set already holds. None at the route's end.
    pub(super) fn wanted(&self, i: usize) -> Option<(usize, Vec<Res>)> {
        let r = &self.robots[i];
        let k = self.segment(i, r.n_res);
        if k == 0 {
            return None;
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
        Some((k, set))
    }

    /// Tries to reserve robot `i`'s next segment ([`Fleets::wanted`]), all or nothing. On
    /// failure records the blockers.
    pub(super) fn try_reserve(&mut self, i: usize, t: f64) -> bool {
        let Some((k, set)) = self.wanted(i) else {
            return false;
        };
        let claimant = self.claim_blocks(i, k).or_else(|| self.holds_off(i, t));
        // The claimant is served before admission limits: its way is being cleared.
        let claims = self.claims.iter().any(|c| c.0 == i);
        let full = if claims {
            Vec::new()
        } else {
            self.admission(i, k)
        };
        if claimant.is_none() && full.is_empty() && self.res.is_free_for(i, &set) {
            if claims {
                self.claims.retain(|c| c.0 != i);
            }
            let r = &mut self.robots[i];
            r.n_res += k;
            r.wait_since = None;
            r.blockers.clear();
            self.rehold(i);
            true
        } else {
            let mut blockers = self.res.blockers(i, &set);
            blockers.extend(full);
            blockers.extend(claimant);
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

    /// The claimant whose claim keeps robot `i` from reserving its next `k` edges: a claim
    /// of higher priority than `i`'s own that the segment would stop on (its end vertex's
    /// standing set meets the claim). Driving through a claim is allowed: the robot is
    /// gone at the end of its segment, like any robot already driving. Robots making room
    /// are never held up by a claim: the spot they drive to is off the claims, and a robot
    /// stopped on its way would only block them longer.
    fn claim_blocks(&self, i: usize, k: usize) -> Option<usize> {
        let r = &self.robots[i];
        if r.escape.is_some() {
            return None;
        }
        let end = r
            .route
            .get(r.n_res + k - 1)
            .map_or(r.at, |&e| self.nav.edges[e].to);
        let stop = &self.conf.vertex[end];
        for (c, claimed) in &self.claims {
            if *c == i {
                return None;
            }
            if meets(stop, claimed) {
                return Some(*c);
            }
        }
        None
    }

    /// The robot that robot `i` made room for, while that one still waits at rest and
    /// `i` came out of its way less than `HOLD_OFF` s ago: `i` waits where it made room
    /// instead of driving straight back into the way it cleared (a livelock: pushed out,
    /// back in, pushed out again, while the robot it made room for never gets going).
    fn holds_off(&mut self, i: usize, t: f64) -> Option<usize> {
        let (c, since) = self.robots[i].made_room?;
        if t - since < HOLD_OFF && c != i && self.waits_at_rest(c) {
            return Some(c);
        }
        self.robots[i].made_room = None;
        None
    }

    /// Waiting for a reservation, at rest, in the middle of a move.
    fn waits_at_rest(&self, i: usize) -> bool {
        let r = &self.robots[i];
        r.wait_since.is_some()
            && r.n_sent == 0
            && r.gate == Gate::None
            && matches!(r.cur, Cur::GoTo { .. })
    }

    /// Standing still and free to be sent elsewhere: idle, waiting at rest in a move, or
    /// waiting at an empty dispenser for its item to come back.
    fn at_rest(&self, o: usize) -> bool {
        let x = &self.robots[o];
        x.n_sent == 0
            && x.gate == Gate::None
            && (x.idle() || self.waits_at_rest(o) || Self::waits_for_item(x))
    }

    /// Waiting at a dispenser that answered empty: the item comes back only when another
    /// delivery ends, which may need this very spot, so the wait is not bounded and the
    /// robot makes room like one at rest (it comes back and asks again). Not while a
    /// request is out: the item would be handed to nobody.
    fn waits_for_item(r: &Robot) -> bool {
        matches!(r.cur, Cur::Workcell { dispenser: true, tries, sent: false, .. } if tries > 0)
    }

    /// Once a second while robots wait: stall bookkeeping and stuck reports, idle robots
    /// out of the way, the claimant's way cleared, detours for long waits.
    pub(super) fn traffic_check(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        self.next_traffic = t + 1.0;
        self.watch_stalls(t, out);
        self.move_idle_blockers(t);
        self.serve_claimants(t);
        for i in 0..self.robots.len() {
            let r = &self.robots[i];
            let long = r.wait_since.is_some_and(|s| t - s >= DETOUR_AFTER);
            if long && t - r.last_detour >= DETOUR_AFTER && self.waits_at_rest(i) {
                self.robots[i].last_detour = t;
                if self.detour(i, &[]) {
                    self.robots[i].stall_since = t;
                }
            }
        }
    }

    /// Idle robots in a waiting robot's way move to a free spot off its way.
    fn move_idle_blockers(&mut self, t: f64) {
        for i in 0..self.robots.len() {
            if self.robots[i].wait_since.is_none() {
                continue;
            }
            for b in self.robots[i].blockers.clone() {
                if self.robots[b].idle() && self.robots[b].n_sent == 0 {
                    // Off the waiter's way ahead, or not at all: a spot on it would only
                    // be left again (hemmed-in robots are let out by the claimant).
                    let needed = self.needed(&[i], &[], ESCAPE_HORIZON);
                    if let Some(v) = self.free_spot(b, &needed) {
                        self.escape(b, i, v, t);
                    }
                }
            }
        }
    }

    /// Serves the robots waiting at rest in priority order: each whose next segment is
    /// disjoint from the claims before it claims that segment, and the robots at rest on
    /// it are pushed out of the way (off the claims before it too). A robot in the way
    /// that cannot get out of it (a dead end behind it) is let out instead: the claimant
    /// makes room for it, and a waiting one inherits a priority just above the claimant's
    /// until its move is done (priority inheritance, as in PIBT), so that the two cannot
    /// take turns pushing each other back.
    fn serve_claimants(&mut self, t: f64) {
        let mut order: Vec<usize> = (0..self.robots.len())
            .filter(|&i| self.waits_at_rest(i))
            .collect();
        let prio: Vec<f64> = (0..self.robots.len())
            .map(|i| self.served_prio(i))
            .collect();
        order.sort_by(|&a, &b| prio[a].total_cmp(&prio[b]).then(a.cmp(&b)));
        self.claims.clear();
        for c in order {
            if !self.waits_at_rest(c) {
                continue;
            }
            let Some((_, set)) = self.wanted(c) else {
                continue;
            };
            // A robot making room leaves the way of the robot it makes room for: that
            // claim does not hold it back (it would never get out), any other does.
            let for_whom = self.robots[c].escape.map(|e| e.0);
            let conflict = self
                .claims
                .iter()
                .any(|(o, s)| Some(*o) != for_whom && meets(&set, s));
            if conflict {
                continue;
            }
            // Robots pushed out of its way keep off every claim before it.
            let higher: Vec<Res> = self
                .claims
                .iter()
                .fold(Vec::new(), |acc, (_, s)| union(&acc, s));
            self.claims.push((c, set.clone()));
            self.clear_way(c, &set, &higher, t);
        }
    }

    /// The priority robot `i` is served with: a robot making room for another goes just
    /// before it (priority inheritance, as in PIBT), through chains of such robots, so
    /// that robots of lower priority cannot step back into its way out.
    fn served_prio(&self, i: usize) -> f64 {
        let mut p = self.robots[i].prio;
        let mut o = i;
        for depth in 1..=self.robots.len() {
            let Some((c, _)) = self.robots[o].escape else {
                break;
            };
            if c == i {
                break;
            }
            p = p.min(self.robots[c].prio - 1e-6 * depth as f64);
            o = c;
        }
        p
    }

    /// Pushes the robots at rest on claimant `c`'s claimed `set` out of it, never onto
    /// `higher` (the claims before it).
    fn clear_way(&mut self, c: usize, set: &[Res], higher: &[Res], t: f64) {
        let near = union(&union(set, &self.conf.vertex[self.robots[c].at]), higher);
        let far = union(&self.needed(&[c], &[], ESCAPE_HORIZON), &near);
        let mut cannot = Vec::new();
        for b in self.res.blockers(c, set) {
            // Others (driving, at a door or lift, busy at a task step) leave by
            // themselves in bounded time.
            if !self.at_rest(b) {
                continue;
            }
            let rb = &self.robots[b];
            let on_its_way = rb.escape.is_some_and(|(f, _)| f == c)
                && rb.wait_since.is_none_or(|s| t - s < REPUSH_AFTER);
            if on_its_way {
                continue;
            }
            // Off the claimant's way ahead if at all possible, even by pushing others first:
            // a robot pushed onto it (into the claimant's goal in a dead end, say) is only
            // pushed back out again, and the two take turns for ever.
            let pushed = self.push(b, c, &far, 0, c, t)
                || self.push(b, c, &far, PUSH_DEPTH, c, t)
                || self.push(b, c, &near, PUSH_DEPTH, c, t);
            if !pushed {
                cannot.push(b);
            }
        }
        if !self.robots[c]
            .wait_since
            .is_some_and(|s| t - s >= YIELD_AFTER)
        {
            return;
        }
        for &b in &cannot {
            // Let `b` out through the claimant's place: the claimant moves too.
            let waiting = self.waits_at_rest(b);
            let pushed = self.push(b, c, &far, PUSH_DEPTH, usize::MAX, t)
                || self.push(b, c, &near, PUSH_DEPTH, usize::MAX, t);
            if !pushed {
                continue;
            }
            // `b` goes first until its move is done, so that the claimant does not come
            // back into its way before it is out.
            let prio = self.robots[c].prio - 1e-3;
            let rb = &mut self.robots[b];
            rb.prio = if waiting { rb.prio.min(prio) } else { prio };
            self.claims.retain(|x| x.0 != c);
            return;
        }
        if !cannot.is_empty() {
            self.unjam(c, &far, t);
        }
    }

    /// A jam: the robots in the claimant's way can neither get out of it nor be let out.
    /// Dissolve it from its edges: every robot at rest that holds up the claimant,
    /// directly or through other robots at rest (the wait-for closure, at most `JAM_MAX`
    /// robots), and has a free spot off the claimant's way within reach, goes there. Each
    /// one that leaves makes room for the next; robots keep their priority, so they come
    /// back in the claimant order.
    fn unjam(&mut self, c: usize, avoid: &[Res], t: f64) {
        let mut seen = vec![c];
        let mut k = 0;
        while k < seen.len() && seen.len() < JAM_MAX {
            let o = seen[k];
            k += 1;
            let wanted = match self.wanted(o) {
                Some((_, set)) if o == c || self.waits_at_rest(o) => set,
                _ => continue,
            };
            for b in self.res.blockers(o, &wanted) {
                if !seen.contains(&b) && self.at_rest(b) {
                    seen.push(b);
                }
            }
        }
        for &b in &seen[1..] {
            if !self.at_rest(b) {
                continue;
            }
            if let Some((v, _)) = self.find_spot(b, avoid, false, c) {
                self.escape(b, c, v, t);
            }
        }
    }

    /// Sends robot `b` to spot `v` to make room for robot `c`; the move it was waiting to
    /// make (if any) follows, with its priority kept.
    fn escape(&mut self, b: usize, c: usize, v: usize, t: f64) {
        let r = &mut self.robots[b];
        match r.cur.clone() {
            Cur::GoTo { goal, .. } => {
                // Already making room (its spot turned out blocked): only the spot changes.
                if r.escape.map(|e| e.1) != Some(goal) {
                    r.steps.push_front(Step::GoTo(goal));
                    if r.prio_until.is_none() {
                        r.prio_until = Some(goal);
                    }
                }
                r.steps.push_front(Step::GoTo(v));
                r.cur = Cur::None;
            }
            Cur::Workcell { target, .. } if Self::waits_for_item(r) => {
                let here = r.at;
                r.steps.push_front(Step::Dispense(target));
                r.steps.push_front(Step::GoTo(here));
                r.steps.push_front(Step::GoTo(v));
                r.cur = Cur::None;
            }
            Cur::None if r.idle() => {
                r.steps.push_back(Step::GoTo(v));
                r.prio = f64::INFINITY;
                r.prio_until = Some(v);
            }
            _ => return,
        }
        r.escape = Some((c, v));
        r.route.clear();
        r.n_res = 0;
        r.wait_since = None;
        r.blockers.clear();
        r.dirty = true;
        r.wake = r.wake.min(t);
        self.rehold(b);
    }

    /// Stall bookkeeping: a waiting robot stalls only when nothing it waits for, directly
    /// or through other waiting robots, has moved lately (long lanes take minutes). A
    /// robot stalled for `STUCK_AFTER` is reported once (a `stuck` task event); the
    /// claimant order still serves it, so this is information, never a failure.
    fn watch_stalls(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let n = self.robots.len();
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
        for i in 0..n {
            let r = &self.robots[i];
            if r.wait_since.is_none() || r.stuck_reported || t - r.stall_since < STUCK_AFTER {
                continue;
            }
            self.robots[i].stuck_reported = true;
            let who: Vec<String> = self.robots[i]
                .blockers
                .iter()
                .map(|&b| format!("{} ({})", self.robots[b].name, self.status(b)))
                .collect();
            if let Some(ti) = self.robots[i].task {
                let detail = format!("waiting for {}", who.join(","));
                self.event(t, ti, "stuck", Some(i), detail, out);
            }
        }
    }

    /// A vertex robot `b` can go to where it is in nobody's way, nearest first, with the
    /// route there: nobody else holds its standing set, the set is disjoint from `needed`
    /// (sorted), it is not a lift cabin, and every lane of the way is free or held only by
    /// robots that are driving (they pass); with `through_waiting`, also by robots at rest
    /// (idle or waiting) other than `keep`, which the caller pushes first. Parking spots, holding points and chargers count `SPOT_PENALTY`
    /// nearer than other vertices, which are more likely to be on somebody's way.
    fn find_spot(
        &self,
        b: usize,
        needed: &[Res],
        through_waiting: bool,
        keep: usize,
    ) -> Option<(usize, Vec<usize>)> {
        self.find_spot_in(b, needed, through_waiting, false, keep)
    }

    /// [`Fleets::find_spot`]; with `onto_waiting`, the spot may also be where a robot at
    /// rest (other than `keep`) stands, which the caller pushes on first (a shift along a
    /// chain of robots, as PIBT pushes).
    fn find_spot_in(
        &self,
        b: usize,
        needed: &[Res],
        through_waiting: bool,
        onto_waiting: bool,
        keep: usize,
    ) -> Option<(usize, Vec<usize>)> {
        let r = &self.robots[b];
        let f = &self.fleets[r.fleet];
        let standing = &self.conf.vertex[r.at];
        let clear = |e: usize| {
            self.conf.edge[e]
                .iter()
                .filter(|x| standing.binary_search(x).is_err())
                .all(|&x| {
                    self.res.holders(x).iter().all(|&o| {
                        let o = o as usize;
                        let x = &self.robots[o];
                        o == b || x.n_sent > 0 || (through_waiting && o != keep && self.at_rest(o))
                    })
                })
        };
        let here = &self.nav.vertices[r.at];
        // From a cabin, not by riding on: the cabin is what the others wait for.
        let from_cabin = here.lift.is_some();
        let ride = |e: usize| !from_cabin || self.nav.edges[e].kind == EdgeKind::Lane;
        let (times, prev) = self
            .nav
            .tree_with(f.slot, r.at, f.speed, &|e| ride(e) && clear(e));
        let cost = |v: usize| {
            let ro = &self.nav.vertices[v].roles;
            let spot = ro.is_parking_spot || ro.is_holding_point || ro.is_charger;
            times[v] + if spot { 0.0 } else { SPOT_PENALTY }
        };
        let v = self.nav.members[f.slot]
            .iter()
            .copied()
            .filter(|&v| v != r.at && times[v].is_finite())
            .filter(|&v| self.nav.vertices[v].lift.is_none())
            .filter(|&v| {
                self.res.is_free_ignoring(b, &self.conf.vertex[v], None)
                    || (onto_waiting
                        && self.conf.vertex[v].iter().all(|&x| {
                            self.res.holders(x).iter().all(|&o| {
                                let o = o as usize;
                                o == b || (o != keep && self.at_rest(o))
                            })
                        }))
            })
            .filter(|&v| !meets(&self.conf.vertex[v], needed))
            .filter(|&v| {
                !self
                    .robots
                    .iter()
                    .any(|x| x.escape.is_some_and(|e| e.1 == v))
            })
            .min_by(|&a, &c| cost(a).total_cmp(&cost(c)).then(a.cmp(&c)))?;
        let mut path = Vec::new();
        let mut w = v;
        while w != r.at {
            let e = prev[w]?;
            path.push(e);
            w = self.nav.edges[e].from;
        }
        path.reverse();
        Some((v, path))
    }

    /// A free spot for robot `b` (see [`Fleets::find_spot`]).
    pub(super) fn free_spot(&self, b: usize, needed: &[Res]) -> Option<usize> {
        self.find_spot(b, needed, false, usize::MAX).map(|s| s.0)
    }

    /// Pushes robot `b` off `avoid` to make room for the claimant `c`: to a free spot, or,
    /// `depth` levels deep, to a spot behind robots waiting at rest (other than `keep`),
    /// which are pushed off its way first (they move for the claimant too). False when no
    /// such spot exists.
    fn push(&mut self, b: usize, c: usize, avoid: &[Res], depth: u32, keep: usize, t: f64) -> bool {
        if let Some((v, _)) = self.find_spot(b, avoid, false, keep) {
            self.escape(b, c, v, t);
            return true;
        }
        if depth == 0 {
            return false;
        }
        // A free spot behind robots at rest, else one where a robot at rest stands.
        for onto in [false, true] {
            let Some((v, path)) = self.find_spot_in(b, avoid, true, onto, keep) else {
                continue;
            };
            let standing = self.conf.vertex[self.robots[b].at].clone();
            let mut way: Vec<Res> = self.conf.vertex[v].clone();
            for &e in &path {
                way.extend(
                    self.conf.edge[e]
                        .iter()
                        .filter(|x| standing.binary_search(x).is_err()),
                );
            }
            way.sort_unstable();
            way.dedup();
            let deeper = union(avoid, &way);
            let moved = self.res.blockers(b, &way).into_iter().all(|o| {
                o == keep || !self.at_rest(o) || self.push(o, c, &deeper, depth - 1, keep, t)
            });
            if moved {
                self.escape(b, c, v, t);
                return true;
            }
        }
        false
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
