//! Retiming only what changed, at the time of the last retime. Once the itineraries hold
//! the times of a retime at `Bufs::applied_at`, a retime at that same time can give other
//! times only downstream of a change: a robot whose itinerary changed (`Bufs::seeds`), or
//! a queue whose order changed (`Bufs::dirty`). Those traversals are timed again, and
//! each whose end moves has those that wait for it timed again, until nothing moves: a
//! work list over the dependency graph.
//!
//! Only at the same time: that is a dispatch round, where each plan that goes before
//! others' ways to parking is checked by a retime (more than half of a saturated
//! warehouse's retimes), and a few hundred of 90,000 traversals are timed again. At a
//! later time, every robot that arrived earlier or later than estimated shifts all it
//! waits behind, a sixth of the schedule, and following that cost more than the full
//! pass (BENCHMARKS.md).
//!
//! Guarantee: when it answers, it answers what [`Schedule::compute_all`] would (debug
//! builds check every answer). Every traversal left out satisfies its equation, since each
//! of its inputs is unchanged, so when the work list empties all do; on a directed acyclic
//! graph those times are the only solution. A new cycle passes through a traversal timed
//! again (the target of a changed dependency) and, when its traversals take any time, has
//! no solution, so the work never ends: it gives up after as much work as a full pass, and
//! the full pass finds the cycle. It also gives up where that argument does not hold: a
//! traversal of no duration, a dependency on a traversal already begun, or on a later one
//! of the same robot.

use super::{neighbours, node_times, Brief, Bufs, Node, UNTOUCHED};
use crate::traffic::schedule::{Cycle, Itinerary, Schedule, FOREVER};

/// Room for robot `r`'s times in `Bufs::start` and `Bufs::end` (empty: `Bufs::have`),
/// if it has none yet; where they begin.
fn room(b: &mut Bufs, its: &[Itinerary], r: usize) -> usize {
    let br = &mut b.robots[r];
    if br.off == UNTOUCHED {
        br.off = b.start.len() as u32;
        let n = b.start.len() + its[r].travs.len();
        b.start.resize(n, 0.0);
        b.end.resize(n, 0.0);
        b.queued.resize(n, false);
        b.forced.resize(n, false);
        b.have.resize(n, false);
    }
    br.off as usize
}

/// Robot `r`'s traversal `k` is to be timed again; when `forced`, so is what waits for
/// it, whatever its times (its own changed: what was timed from it may not hold).
fn push(b: &mut Bufs, its: &[Itinerary], r: usize, k: usize, forced: bool) {
    let n = room(b, its, r) + k;
    b.forced[n] |= forced;
    if !b.queued[n] {
        b.queued[n] = true;
        b.work.push_back((r as u32, k as u32));
    }
}

impl Schedule {
    /// [`Schedule::compute`] of the traversals downstream of what changed since the last
    /// apply; `None` where it cannot tell (the caller computes them all).
    pub(super) fn follow(&mut self, now: f64) -> Option<Result<(), Cycle>> {
        let b = &mut self.bufs;
        // Only at the time of the last apply (see the module's doc).
        if !b.known || now != b.applied_at {
            return None;
        }
        let its = &self.its[..];
        b.robots.clear();
        b.robots.extend(its.iter().map(|it| Brief::of(it, now)));
        let total: usize = its.iter().map(|it| it.travs.len()).sum();
        for &x in &b.dirty {
            let q = &self.queues[x as usize];
            for w in 1..q.len() {
                if q[w - 1].last == FOREVER {
                    // As `compute_all`: a span after one held for good never starts.
                    return Some(Err(Cycle {
                        robots: vec![q[w - 1].robot as usize, q[w].robot as usize],
                    }));
                }
            }
        }
        b.start.clear();
        b.end.clear();
        b.queued.clear();
        b.forced.clear();
        b.have.clear();
        b.work.clear();
        // What changed: the traversals of a changed itinerary, and what waits for them;
        // the first traversal of a span whose predecessor in a queue changed.
        for i in 0..b.seeds.len() {
            let r = b.seeds[i] as usize;
            for k in 0..its[r].travs.len() {
                push(b, its, r, k, true);
            }
        }
        for i in 0..b.seed_nodes.len() {
            let (r, seq) = b.seed_nodes[i];
            if let Some(k) = b.robots[r as usize].node(seq) {
                push(b, its, r as usize, k, true);
            }
        }
        // The spans whose predecessor in a queue changed (robot, first traversal).
        let mut seeds: Vec<(u32, u64)> = Vec::new();
        for i in 0..b.dirty.len() {
            let q = &self.queues[b.dirty[i] as usize];
            let from = b.snap[i] as usize;
            let to = b.snap.get(i + 1).map_or(b.before.len(), |&t| t as usize);
            seeds.clear();
            {
                let old = &b.before[from..to];
                let now_deps = || neighbours(q);
                seeds.extend(now_deps().filter(|d| !old.contains(d)).map(|d| (d.2, d.3)));
                seeds.extend(
                    old.iter()
                        .filter(|d| !now_deps().any(|n| n == **d))
                        .map(|d| (d.2, d.3)),
                );
            }
            for &(r, seq) in &seeds {
                if let Some(k) = b.robots[r as usize].node(seq) {
                    push(b, its, r as usize, k, false);
                }
            }
        }
        // Time again until nothing moves; as much work as a full pass at most.
        let mut budget = total + 64;
        while let Some((r, k)) = b.work.pop_front() {
            if budget == 0 {
                return None;
            }
            budget -= 1;
            let (r, k) = (r as usize, k as usize);
            let off = b.robots[r].off as usize;
            b.queued[off + k] = false;
            let forced = std::mem::take(&mut b.forced[off + k]);
            let it = &its[r];
            let tr = &it.travs[k];
            let seq = it.base + k as u64;
            if !tr.begun && (tr.dur <= 0.0 || tr.dur.is_nan()) {
                return None;
            }
            // In each queue it needs, the robot's span holding it: the span before, if
            // this one starts here, gives the latest end it waits for; the span after, if
            // this one ends here, waits for its end. (A robot's spans in a queue are in
            // its order: the first reaching this traversal is the one.)
            let mut after = f64::NEG_INFINITY;
            b.next.clear();
            for &x in &self.conf.trav[tr.edge] {
                let q = &self.queues[x as usize];
                let Some(w) = q
                    .iter()
                    .position(|s| s.robot as usize == r && s.last >= seq)
                else {
                    continue;
                };
                let span = &q[w];
                if span.last == seq {
                    if let Some(n) = q.get(w + 1) {
                        b.next.push((n.robot, n.first));
                    }
                }
                if span.first != seq {
                    continue;
                }
                let Some(p) = w.checked_sub(1).map(|w| &q[w]) else {
                    continue;
                };
                let Some(pk) = b.robots[p.robot as usize].node(p.last) else {
                    continue;
                };
                if tr.begun || (p.robot as usize == r && pk >= k) {
                    return None;
                }
                after = after.max(b.times(its, p.robot as usize, pk).1);
            }
            let prev_end = (k > 0).then(|| b.times(its, r, k - 1).1);
            let (s, e) = node_times(Node::of(tr), prev_end, it.ready, after, now);
            let was_end = b.times(its, r, k).1;
            b.start[off + k] = s;
            b.end[off + k] = e;
            b.have[off + k] = true;
            if !forced && e.to_bits() == was_end.to_bits() {
                continue;
            }
            // Those that wait for its end: its next traversal, and the spans just after
            // its own that end here.
            if k + 1 < it.travs.len() {
                push(b, its, r, k + 1, false);
            }
            for i in 0..b.next.len() {
                let (n, first) = b.next[i];
                if let Some(nk) = b.robots[n as usize].node(first) {
                    push(b, its, n as usize, nk, false);
                }
            }
        }
        b.moved.clear();
        b.moved.resize(its.len(), false);
        for (r, it) in its.iter().enumerate() {
            let off = b.robots[r].off;
            if off == UNTOUCHED {
                continue;
            }
            // As `apply` compares them (NaN differs from itself).
            b.moved[r] = it.travs.iter().enumerate().any(|(k, t)| {
                let n = off as usize + k;
                b.have[n] && (b.start[n] != t.start || b.end[n] != t.end)
            });
        }
        Some(Ok(()))
    }
}
