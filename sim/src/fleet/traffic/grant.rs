//! Driving what the schedule grants: a robot is sent along its itinerary's traversals as
//! far as every robot planned to pass their resources before it has passed, doors and lifts
//! on the way waited for first.

use super::*;

impl Floor {
    /// Sends robot `i` along what the schedule grants it, up to `limit` traversals from
    /// its first (the end of its leg). Doors and lifts on the way are waited for first.
    pub(in crate::fleet) fn advance(
        &mut self,
        i: usize,
        limit: usize,
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        // A gate asked for on a way the robot was planned off since (its way to parking
        // moved for another robot's task while it waited at a door or lift) goes back. Kept,
        // the robot never counted as free again, and stood where it was for good.
        let front = self
            .traffic
            .sched
            .itinerary(i)
            .travs
            .front()
            .map(|tr| tr.edge);
        if self.robots[i].n_sent == 0 && !front.is_some_and(|e| self.gate_is_for(i, e)) {
            self.drop_gate(i, t, out);
        }
        if limit == 0 {
            self.robots[i].waiting = None;
            return;
        }
        let n_sent = self.robots[i].n_sent;
        if n_sent > 0 {
            // Moving: extend the path while the traversals stay plain and granted.
            let travs = &self.traffic.sched.itinerary(i).travs;
            let all_plain = travs.iter().take(n_sent).all(|tr| self.is_plain(tr.edge));
            if all_plain && n_sent < LOOKAHEAD && n_sent < limit {
                let next_plain = travs.get(n_sent).is_some_and(|tr| self.is_plain(tr.edge));
                if next_plain && self.traffic.sched.granted(i, n_sent) {
                    self.traffic.sched.begin(i, n_sent + 1, t);
                    self.send_path(i, n_sent + 1, t, out);
                }
            }
            return;
        }
        let Some(tr) = self.traffic.sched.itinerary(i).travs.front().cloned() else {
            self.robots[i].waiting = None;
            return;
        };
        if !self.traffic.sched.granted(i, 0) {
            let r = &mut self.robots[i];
            if r.waiting.is_none() {
                r.waiting = Some(t);
                r.stuck_reported = false;
            }
            return;
        }
        self.robots[i].waiting = None;
        let edge = self.nav.edges[tr.edge].clone();
        if let EdgeKind::Lift(l) = edge.kind {
            let floor = self.nav.vertices[edge.to].level_name.clone();
            if !self.lift_at(i, l, floor, t, out) {
                return;
            }
            // The cabin is at the destination floor: the robot is on its other vertex.
            self.traffic.sched.begin(i, 1, t);
            self.reach_next(i, t, out);
            self.robots[i].dirty = true;
            return;
        }
        let to_lift = self.nav.vertices[edge.to].lift;
        let from_lift = self.nav.vertices[edge.from].lift;
        let mut n = 1;
        if let Some(l) = to_lift.filter(|&l| from_lift != Some(l)) {
            let floor = self.nav.vertices[edge.from].level_name.clone();
            if !self.lift_at(i, l, floor, t, out) {
                return;
            }
        } else if let Some(d) = edge.door.filter(|&d| self.nav.doors[d].controlled) {
            if !self.gate(
                i,
                Gate::Door {
                    door: d,
                    next_send: t,
                    since: t,
                },
                t,
                out,
            ) {
                return;
            }
            self.robots[i].gate = Gate::None;
            self.robots[i].close_door = Some(d);
        } else {
            // Plain lanes: a few more in the same path while they stay plain and granted.
            let travs = &self.traffic.sched.itinerary(i).travs;
            while n < LOOKAHEAD.min(limit)
                && travs.get(n).is_some_and(|x| self.is_plain(x.edge))
                && self.traffic.sched.granted(i, n)
            {
                n += 1;
            }
        }
        self.traffic.sched.begin(i, n, t);
        self.send_path(i, n, t, out);
    }

    /// Waits for lift `l`'s cabin at `floor` with its doors open; once it is, the robot's
    /// gate is done and its leg ends in that lift. True when it is ready.
    fn lift_at(
        &mut self,
        i: usize,
        l: usize,
        floor: String,
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) -> bool {
        let want = Gate::Lift {
            lift: l,
            floor,
            next_send: t,
            since: t,
        };
        if !self.gate(i, want, t, out) {
            return false;
        }
        self.robots[i].gate = Gate::None;
        self.robots[i].end_lift = Some(l);
        true
    }

    /// Whether robot `i`'s gate (the door or lift it asked for, if any) is the one edge `e`
    /// goes through, as [`Floor::advance`] asks for it.
    pub(super) fn gate_is_for(&self, i: usize, e: usize) -> bool {
        let edge = &self.nav.edges[e];
        let lift_of = |v: usize| self.nav.vertices[v].lift;
        let level = |v: usize| self.nav.vertices[v].level_name.as_str();
        match &self.robots[i].gate {
            Gate::None => true,
            Gate::Door { door, .. } => edge.door == Some(*door),
            Gate::Lift { lift, floor, .. } => match edge.kind {
                EdgeKind::Lift(l) => l == *lift && level(edge.to) == floor,
                _ => {
                    lift_of(edge.to) == Some(*lift)
                        && lift_of(edge.from) != Some(*lift)
                        && level(edge.from) == floor
                }
            },
        }
    }

    /// How many of robot `i`'s first traversals a new plan keeps: those it was sent along,
    /// or the ride of a lift cabin it stands in and has called to a floor. (Planned again
    /// with none kept mid-ride, a robot drove out of a climbing cabin and stood between
    /// floors for good.)
    pub(in crate::fleet) fn kept(&self, i: usize) -> usize {
        let r = &self.robots[i];
        if r.n_sent > 0 {
            return r.n_sent;
        }
        let Gate::Lift { lift, .. } = &r.gate else {
            return 0;
        };
        let rides = self
            .traffic
            .sched
            .itinerary(i)
            .travs
            .front()
            .is_some_and(|tr| self.nav.edges[tr.edge].kind == EdgeKind::Lift(*lift));
        usize::from(rides && self.nav.vertices[r.at].lift == Some(*lift))
    }

    /// A lane without a controlled door, not into or out of a lift cabin.
    pub(in crate::fleet) fn is_plain(&self, e: usize) -> bool {
        let edge = &self.nav.edges[e];
        edge.kind == EdgeKind::Lane
            && !edge.door.is_some_and(|d| self.nav.doors[d].controlled)
            && self.nav.vertices[edge.from].lift.is_none()
            && self.nav.vertices[edge.to].lift.is_none()
    }
}
