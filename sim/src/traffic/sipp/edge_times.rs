//! Edge traversal times for one [`Kinematics`], in flat arrays. The search reads an edge's
//! time at every state it expands, and the distance tables read every edge's bound; read
//! from the graph's edge and vertex records (large, and far apart in memory) they were a
//! third of the search's own time on a 10,000-waypoint warehouse. The values are those of
//! [`Kinematics::edge_time_with`] bit for bit (the sums are made in the same order; debug builds
//! compare them).

use super::{heading, Kinematics, STOP_S};
use crate::graph::{EdgeKind, Nav};

pub(super) struct EdgeTimes {
    pub(super) kin: Kinematics,
    pub(super) from: Vec<usize>,
    pub(super) to: Vec<usize>,
    /// Lanes take a turn and settle at their end; lift rides do not.
    lane: Vec<bool>,
    /// Lanes long enough to turn towards (see [`Kinematics::edge_time_with`]).
    turns: Vec<bool>,
    heading: Vec<f64>,
    /// The time without the turn and the settling (a lift ride: all of it).
    base: Vec<f64>,
    /// The time with no turn: the search's lower bound ([`Kinematics::edge_bound`]).
    bound: Vec<f64>,
}

impl EdgeTimes {
    pub(super) fn new(nav: &Nav, kin: Kinematics) -> EdgeTimes {
        let n = nav.edges.len();
        let mut t = EdgeTimes {
            kin,
            from: Vec::with_capacity(n),
            to: Vec::with_capacity(n),
            lane: Vec::with_capacity(n),
            turns: Vec::with_capacity(n),
            heading: Vec::with_capacity(n),
            base: Vec::with_capacity(n),
            bound: Vec::with_capacity(n),
        };
        for (e, edge) in nav.edges.iter().enumerate() {
            t.from.push(edge.from);
            t.to.push(edge.to);
            t.lane.push(edge.kind == EdgeKind::Lane);
            t.turns.push(edge.length >= 1e-6);
            t.heading.push(heading(nav, e));
            t.base.push(kin.edge_base(nav, e));
            t.bound.push(kin.edge_bound(nav, e));
        }
        t
    }

    /// Time to drive edge `e` after arriving along `prev` (None: no turn counted).
    #[inline]
    pub(super) fn time(&self, e: usize, prev: Option<usize>) -> f64 {
        if !self.lane[e] {
            return self.base[e];
        }
        let turn = prev.map_or(0.0, |p| {
            if !self.lane[p] || !self.turns[e] {
                return 0.0;
            }
            let mut a = (self.heading[e] - self.heading[p]).abs() % std::f64::consts::TAU;
            if a > std::f64::consts::PI {
                a = std::f64::consts::TAU - a;
            }
            a / self.kin.turn.max(0.05)
        });
        self.base[e] + turn + STOP_S
    }

    /// [`Kinematics::edge_bound`] of edge `e`.
    #[inline]
    pub(super) fn bound(&self, e: usize) -> f64 {
        self.bound[e]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traffic::test_map;

    /// Every edge after every edge into its start (and after none), on random maps and
    /// the corridor map: the same bits as [`Kinematics::edge_time_with`] and `edge_bound`.
    #[test]
    fn flat_times_are_the_kinematics_times() {
        let kins = [
            Kinematics {
                speed: 0.5,
                accel: 0.25,
                turn: 0.5,
            },
            Kinematics {
                speed: 1.3,
                accel: 0.7,
                turn: 0.02,
            },
        ];
        let navs = (0..20u64)
            .map(|seed| test_map::random_nav(seed, 10 + seed as usize))
            .chain([test_map::nav()]);
        let mut pairs = 0;
        for nav in navs {
            for kin in kins {
                let et = EdgeTimes::new(&nav, kin);
                for e in 0..nav.edges.len() {
                    assert_eq!(et.bound(e).to_bits(), kin.edge_bound(&nav, e).to_bits());
                    assert_eq!(
                        et.time(e, None).to_bits(),
                        kin.edge_time(&nav, e, None).to_bits()
                    );
                    for p in (0..nav.edges.len()).filter(|&p| nav.edges[p].to == nav.edges[e].from)
                    {
                        pairs += 1;
                        assert_eq!(
                            et.time(e, Some(p)).to_bits(),
                            kin.edge_time(&nav, e, Some(p)).to_bits(),
                            "edge {p} then {e}"
                        );
                    }
                }
            }
        }
        assert!(pairs > 200, "only {pairs} turns compared");
    }
}
