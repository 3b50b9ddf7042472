//! Out of the way while idle: a robot that a dispatch round leaves without a task while
//! tasks wait (the bids went to busy robots, or its plans waited too long), on a parking
//! vertex whose way around is long, goes to a free one whose way around is short
//! (`traffic::parks::out_of_the_way`), and stays there until it takes a task.
//!
//! Why: a bigger fleet has more robots standing idle, and where a building's parking
//! vertices include a corridor that is the second way between two parts of it, the idle
//! ones stand there and every route that corridor offered becomes a detour. On the public
//! reroute_demo map six robots completed 91 % of what four did; six robots of which only
//! four ever worked, the other two standing on the building's corners, completed 96 %; with
//! this step six complete as much as four (BENCHMARKS.md).

use super::*;
use crate::traffic::parks::PARK;
use assign::{Free, DISPATCH_EVERY};

/// A robot left without a task this long (s) with tasks waiting goes out of the way: four
/// dispatch rounds, so a robot between two tasks of a stream does not drive off.
const RETREAT_AFTER: f64 = 4.0 * DISPATCH_EVERY;
/// Robots sent out of the way per round, at most (each is a plan).
const RETREATS_PER_ROUND: usize = 2;

impl Floor {
    /// Sends robots of `free` (those the round at `t` left without a task) that have stood
    /// idle `RETREAT_AFTER` on a parking vertex in the way to the nearest free one out of
    /// the way nearby. Each plan may go before others' ways to parking (they plan theirs
    /// again behind it, as for a task's plan); one that cannot changes nothing.
    pub(super) fn retreat(&mut self, free: &[Free], t: f64) {
        let ready: Vec<usize> = free
            .iter()
            .filter(|&&(i, from, wait)| self.in_the_way(i, from, wait, t))
            .map(|f| f.0)
            .take(RETREATS_PER_ROUND)
            .collect();
        let mut taken: Vec<usize> = Vec::new();
        for i in ready {
            let slot = self.robots[i].slot;
            let here = self.traffic.sched.end_vertex(i);
            // Nobody stays there for good (robots at work's ways to parking may be taken:
            // they plan theirs again), and not taken in this round.
            let conf = self.traffic.sched.conf();
            let free_park = |v: usize| {
                !taken.contains(&v)
                    && conf.vertex[v].iter().all(|&x| {
                        self.traffic
                            .sched
                            .held_for_good(x, usize::MAX, true)
                            .is_none()
                    })
            };
            let Some(to) = self.ways_out[slot][here]
                .iter()
                .copied()
                .find(|&v| free_park(v))
            else {
                continue;
            };
            taken.push(to);
            let mut only = vec![0u8; self.nav.vertices.len()];
            only[to] = PARK;
            let ends = [(Some(only), None)];
            let (keep, from, t0) = self.plan_start(i, t);
            let (plan, _) = self.plan_over(i, &ends, (from, t0), &[], (true, None), None);
            if plan.is_some_and(|plan| self.install(i, keep, plan, t0, Some(t))) {
                let r = &mut self.robots[i];
                r.retreat = Some(to);
                r.dirty = true;
                r.wake = t;
            }
        }
    }

    /// Whether free robot `i` (planning from `from`, after `wait` s) stands in the way with
    /// a way out: it parks where any robot may (a fleet config's homes and stays are the
    /// user's), stands where its itinerary ends, on a parking vertex in the way with parking
    /// vertices out of the way nearby, and has had no task for `RETREAT_AFTER`.
    fn in_the_way(&self, i: usize, from: usize, wait: f64, t: f64) -> bool {
        let r = &self.robots[i];
        let here = self.traffic.sched.end_vertex(i);
        r.finish == Finish::Park
            && wait <= 0.0
            && from == here
            && t - r.free_since >= RETREAT_AFTER
            && !self.ways_out[r.slot][here].is_empty()
    }
}
