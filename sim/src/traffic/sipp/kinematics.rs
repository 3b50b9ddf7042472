//! How a robot drives, for the planner's traversal times.

use super::*;

/// How a robot drives, for traversal times: the slotcar accelerates to its top speed,
/// brakes to a stop at every waypoint, and turns in place towards the next one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// Top speed (m/s) and acceleration (m/s²).
    pub speed: f64,
    pub accel: f64,
    /// Turning speed (rad/s).
    pub turn: f64,
}

impl Kinematics {
    /// Time to drive `len` metres from rest to rest at top speed `v` (a trapezoid, or a
    /// triangle on short lanes).
    fn drive(&self, len: f64, v: f64) -> f64 {
        let a = self.accel.max(1e-3);
        if len >= v * v / a {
            len / v + v / a
        } else {
            2.0 * (len / a).sqrt()
        }
    }

    /// Time to drive edge `e` after arriving along `prev` (None: no turn counted).
    #[cfg(test)]
    pub fn edge_time(&self, nav: &Nav, e: usize, prev: Option<usize>) -> f64 {
        self.edge_time_with(nav, e, prev, |x| heading(nav, x))
    }

    /// [`Kinematics::edge_time_with`] with the edges' headings from `h`.
    pub(super) fn edge_time_with(
        &self,
        nav: &Nav,
        e: usize,
        prev: Option<usize>,
        h: impl Fn(usize) -> f64,
    ) -> f64 {
        let edge = &nav.edges[e];
        match edge.kind {
            EdgeKind::Lift(_) => self.edge_base(nav, e),
            EdgeKind::Lane => {
                let turn = prev.map_or(0.0, |p| {
                    if nav.edges[p].kind != EdgeKind::Lane || edge.length < 1e-6 {
                        return 0.0;
                    }
                    let mut a = (h(e) - h(p)).abs() % std::f64::consts::TAU;
                    if a > std::f64::consts::PI {
                        a = std::f64::consts::TAU - a;
                    }
                    a / self.turn.max(0.05)
                });
                self.edge_base(nav, e) + turn + STOP_S
            }
        }
    }

    /// Edge `e`'s time without the turn towards it and the settling at its end (a lift
    /// ride: all of it).
    pub(super) fn edge_base(&self, nav: &Nav, e: usize) -> f64 {
        let edge = &nav.edges[e];
        match edge.kind {
            EdgeKind::Lift(_) => nav.edge_cost(e, self.speed),
            EdgeKind::Lane => {
                let v = edge
                    .speed_limit
                    .map_or(self.speed, |l| l.min(self.speed))
                    .max(0.05);
                let door = if edge.door.is_some_and(|d| nav.doors[d].controlled) {
                    DOOR_COST
                } else {
                    0.0
                };
                // Into a cabin: the cabin may first have to come from another floor.
                let call = match (nav.vertices[edge.to].lift, nav.vertices[edge.from].lift) {
                    (Some(l), from) if from != Some(l) => nav.lifts[l].call,
                    _ => 0.0,
                };
                self.drive(edge.length, v) + door + call
            }
        }
    }

    /// A lower bound of [`Kinematics::edge_time_with`] (for the search's heuristic): the same
    /// time without the turn, which depends on the edge before. Every lane is driven from
    /// rest to rest, so a bound without the braking and settling (a third of a tiny
    /// robot's 2 m lane) would let A* spread over most of a large building.
    pub(super) fn edge_bound(&self, nav: &Nav, e: usize) -> f64 {
        self.edge_time_with(nav, e, None, |_| 0.0)
    }
}

/// The heading of edge `e` (rad).
pub(super) fn heading(nav: &Nav, e: usize) -> f64 {
    let x = &nav.edges[e];
    let d = nav.vertices[x.to].pos.minus(nav.vertices[x.from].pos);
    d.y.atan2(d.x)
}
