//! Times to the nearest of a set of targets that changes a little between uses: the
//! parking vertices nobody stays on, the heuristic of a plan's way to parking (the
//! planning robot's own park is added to a copy: see `sipp::nearer`). Each plan's set
//! differs from the last one's by the robots that parked or left since, so the table is
//! repaired, not computed again: on a 10,000-waypoint warehouse a full reverse Dijkstra
//! per plan was a tenth of the run.
//!
//! Guarantee: after [`Nearest::update`] the table is bit for bit what a full reverse
//! Dijkstra to the new set gives (debug builds check it). Each time is the fixpoint
//! `d[u] = min over u→w of d[w] + bound(u→w)`, which does not depend on the order of
//! relaxation; `src[u]` is a target that a way of time `d[u]` reaches, so when targets go,
//! only the vertices whose `src` went can have got further.

use super::{EdgeTimes, Open};
use std::collections::BinaryHeap;

const NONE: u32 = u32::MAX;

/// Per vertex: the time to the nearest target, and that target.
#[derive(Debug, Clone)]
pub(super) struct Nearest {
    target: Vec<bool>,
    pub(super) d: Vec<f64>,
    src: Vec<u32>,
}

impl Nearest {
    /// No targets yet: every time infinite.
    pub(super) fn new(n: usize) -> Nearest {
        Nearest {
            target: vec![false; n],
            d: vec![f64::INFINITY; n],
            src: vec![NONE; n],
        }
    }

    /// Brings the table to `targets`, with `inn`/`out` the slot's incoming and outgoing
    /// edges per vertex.
    pub(super) fn update(
        &mut self,
        inn: &[Vec<usize>],
        out: &[Vec<usize>],
        et: &EdgeTimes,
        targets: &[usize],
    ) {
        let n = self.d.len();
        let mut now = vec![false; n];
        for &t in targets {
            now[t] = true;
        }
        let mut heap = BinaryHeap::new();
        // Targets gone: every vertex whose nearest target went is timed again from its
        // neighbours that kept theirs (then the search below).
        let gone: Vec<usize> = (0..n).filter(|&v| self.target[v] && !now[v]).collect();
        if !gone.is_empty() {
            let mut went = vec![false; n];
            for &g in &gone {
                went[g] = true;
            }
            let orphans: Vec<usize> = (0..n)
                .filter(|&u| self.src[u] != NONE && went[self.src[u] as usize])
                .collect();
            for &u in &orphans {
                self.d[u] = f64::INFINITY;
                self.src[u] = NONE;
            }
            for &u in &orphans {
                for &e in &out[u] {
                    let w = et.to[e];
                    let c = self.d[w] + et.bound(e);
                    if c < self.d[u] {
                        self.d[u] = c;
                        self.src[u] = self.src[w];
                    }
                }
                if self.d[u].is_finite() {
                    heap.push(Open(self.d[u], 0.0, u));
                }
            }
        }
        for &t in targets {
            if !self.target[t] {
                self.d[t] = 0.0;
                self.src[t] = t as u32;
                heap.push(Open(0.0, 0.0, t));
            }
        }
        self.target = now;
        // Label-correcting from the changed vertices: a vertex improved is searched again.
        while let Some(Open(c, _, v)) = heap.pop() {
            if c > self.d[v] {
                continue;
            }
            for &e in &inn[v] {
                let u = et.from[e];
                let nc = c + et.bound(e);
                if nc < self.d[u] {
                    self.d[u] = nc;
                    self.src[u] = self.src[v];
                    heap.push(Open(nc, 0.0, u));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traffic::sipp::{Kinematics, Planner};
    use crate::traffic::test_map::random_nav;

    const KIN: Kinematics = Kinematics {
        speed: 0.5,
        accel: 0.25,
        turn: 0.5,
    };

    /// Sets of targets that grow, shrink and change, on random maps (one-way lanes, parts
    /// cut off): every repaired table is bit for bit the one computed from scratch.
    #[test]
    fn repaired_times_are_the_computed_ones() {
        for seed in 0..40u64 {
            let nav = random_nav(seed, 10 + (seed as usize % 30));
            let planner = Planner::new(&nav);
            let et = EdgeTimes::new(&nav, KIN);
            let n = nav.vertices.len();
            let mut rng = fastrand::Rng::with_seed(seed);
            let mut table = Nearest::new(n);
            let mut set: Vec<bool> = (0..n).map(|_| rng.u8(..) < 40).collect();
            for step in 0..30 {
                // Mostly a few changes, sometimes a new set altogether.
                if step % 10 == 9 {
                    set = (0..n).map(|_| rng.u8(..) < 40).collect();
                } else {
                    for _ in 0..rng.usize(1..4) {
                        let v = rng.usize(..n);
                        set[v] = !set[v];
                    }
                }
                let targets: Vec<usize> = (0..n).filter(|&v| set[v]).collect();
                table.update(&planner.inn[0], &nav.out[0], &et, &targets);
                let full = planner.dist_to(0, &et, &targets);
                assert!(
                    table
                        .d
                        .iter()
                        .zip(&full)
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "seed {seed} step {step}: {:?} against {full:?}",
                    table.d
                );
            }
        }
    }
}
