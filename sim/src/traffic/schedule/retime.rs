//! Retiming the schedule: every traversal's estimated times from now on, keeping every
//! queue's order (a longest-path pass over the action dependency graph, Kahn's algorithm),
//! and writing them back into the itineraries and spans.
//!
//! A saturated warehouse retimes thousands of times an hour over 100,000 traversals, so
//! both halves remember what they read: the dependencies between neighbours in the
//! queues are kept between retimes and read again only for the queues that changed, and
//! spans are written only in the queues whose traversals' times moved, that changed, or
//! whose robot began to wait for its turn. Debug builds check both against a full pass.

use super::{new_stamp, Cycle, Schedule, Span, FOREVER};
use crate::traffic::conflicts::Res;
use std::collections::VecDeque;

/// Buffers [`Schedule::retime`] reuses: a saturated run retimes thousands of times, and
/// with 1,000 robots each retime allocated ten arrays as long as all itineraries (page
/// faults and allocator time every time). Not copied with the schedule.
#[derive(Debug, Default)]
pub(super) struct Bufs {
    offs: Vec<usize>,
    /// Per traversal (node), in robot order: its robot and what the times are made of.
    owner: Vec<u32>,
    nodes: Vec<Node>,
    edges: Vec<(u32, u32)>,
    indeg: Vec<u32>,
    first: Vec<u32>,
    users: Vec<u32>,
    at: Vec<u32>,
    ready: Vec<usize>,
    end: Vec<f64>,
    start: Vec<f64>,
    after: Vec<f64>,
    /// `start` and `end` hold a successful compute's times.
    pub(super) computed: bool,
    /// Per robot: whether the compute gave any of its traversals other times than they
    /// have (the apply passes the others by: in a saturated warehouse most robots'
    /// estimates hold from one retime to the next).
    moved: Vec<bool>,
    /// Per robot, what the loops over every span read of its itinerary, side by side
    /// (reading the itineraries themselves was half of writing the times back).
    robots: Vec<Brief>,
    /// The dependencies between neighbours in the queues as of the last
    /// [`Schedule::apply`] (when `known`), and as of the last compute: only the queues
    /// changed since are read again (reading all 40,000 queues of a warehouse, each in
    /// its own allocation, was a third of a retime).
    known: bool,
    deps: Vec<Dep>,
    cur: Vec<Dep>,
    /// The queues changed since the last apply (their order, spans, or what their spans'
    /// times are made of, other than the times of the traversals).
    dirty: Vec<Res>,
    is_dirty: Vec<bool>,
    /// Per robot: the running number of its first traversal if it waited for its turn
    /// at the last apply (else `u64::MAX`). Its spans from there were written busy from
    /// then, and stay so.
    waited: Vec<u64>,
}

/// What [`Schedule::compute`] reads of a traversal.
#[derive(Debug, Clone, Copy)]
struct Node {
    dur: f64,
    hold: f64,
    /// `Trav::start` and `Trav::end` as they are.
    was: (f64, f64),
    /// `Trav::start`, read when it has begun.
    start: f64,
    begun: bool,
}

/// In queue `q`, robot `p`'s span ending at its traversal `last` comes just before robot
/// `s`'s span starting at its traversal `first`.
#[derive(Debug, Clone, Copy)]
struct Dep {
    q: Res,
    p: u32,
    s: u32,
    last: u64,
    first: u64,
}

/// What [`Schedule::compute`] and [`Schedule::apply`] read of an itinerary.
#[derive(Debug, Clone, Copy)]
struct Brief {
    /// `Itinerary::base`, its traversals and the node of its first one.
    base: u64,
    len: u32,
    off: u32,
    /// How many of its first traversals it was sent along (they are a prefix).
    begun: u32,
    /// Ready to go on and waiting for its turn now (its first traversal not begun).
    waiting: bool,
    /// `Itinerary::ready`.
    ready: f64,
}

impl Brief {
    /// The node of its traversal `seq`, when that is still in the itinerary.
    fn node(&self, seq: u64) -> Option<usize> {
        let k = seq.checked_sub(self.base)?;
        (k < u64::from(self.len)).then(|| (u64::from(self.off) + k) as usize)
    }
}

impl Clone for Bufs {
    fn clone(&self) -> Bufs {
        Bufs::default()
    }
}

impl Bufs {
    /// Queue `x` changed (see `Bufs::dirty`).
    pub(super) fn touch(&mut self, x: Res) {
        let x = x as usize;
        if self.is_dirty.len() <= x {
            self.is_dirty.resize(x + 1, false);
        }
        if !self.is_dirty[x] {
            self.is_dirty[x] = true;
            self.dirty.push(x as Res);
        }
    }

    /// No queue changed since now.
    fn clean(&mut self) {
        for &x in &self.dirty {
            self.is_dirty[x as usize] = false;
        }
        self.dirty.clear();
    }
}

/// `v` as `n` copies of `x`, keeping its allocation.
fn refill<T: Clone>(v: &mut Vec<T>, n: usize, x: T) {
    v.clear();
    v.resize(n, x);
}

impl Schedule {
    /// Re-estimates every traversal's times from `now` on, keeping every queue's order:
    /// a traversal starts when its robot is ready and every span before its own in the
    /// queues it needs has ended. Fails when the dependencies form a cycle.
    pub fn retime(&mut self, now: f64) -> Result<(), Cycle> {
        self.compute(now)?;
        self.apply(now);
        Ok(())
    }

    /// The times [`Schedule::retime`] would set, into its buffers (read them with
    /// [`Schedule::computed_end`]); nothing else changes. Fails on a cycle.
    pub fn compute(&mut self, now: f64) -> Result<(), Cycle> {
        self.bufs.computed = false;
        let nr = self.its.len();
        let Bufs {
            offs,
            owner,
            nodes,
            edges,
            indeg,
            first,
            users,
            at,
            ready,
            end,
            start,
            after,
            robots,
            moved,
            known,
            deps,
            cur,
            dirty,
            is_dirty,
            ..
        } = &mut self.bufs;
        // What the times are made of, side by side (the itineraries' traversals are read
        // once, in order).
        offs.clear();
        robots.clear();
        owner.clear();
        nodes.clear();
        for (r, it) in self.its.iter().enumerate() {
            let off = nodes.len();
            offs.push(off);
            nodes.extend(it.travs.iter().map(|t| Node {
                dur: t.dur,
                hold: t.hold,
                was: (t.start, t.end),
                start: t.start,
                begun: t.begun,
            }));
            owner.resize(nodes.len(), r as u32);
            robots.push(Brief {
                base: it.base,
                len: it.travs.len() as u32,
                off: off as u32,
                begun: it.travs.iter().take_while(|t| t.begun).count() as u32,
                waiting: it.travs.front().is_some_and(|t| !t.begun) && it.ready <= now,
                ready: it.ready,
            });
        }
        offs.push(nodes.len());
        let offs = &*offs;
        let total = offs[nr];
        let robots = &*robots;
        // The dependencies between neighbours in the queues: those of the queues that did
        // not change since the last apply, and those of the others read again.
        cur.clear();
        let changed = |x: Res| is_dirty.get(x as usize).is_some_and(|&d| d);
        if *known {
            cur.extend(deps.iter().filter(|d| !changed(d.q)));
        }
        let mut read = |x: Res, q: &VecDeque<Span>| -> Result<(), Cycle> {
            for w in 1..q.len() {
                let (p, s) = (&q[w - 1], &q[w]);
                if p.last == FOREVER {
                    // A span after one held for good can never start (the callers say
                    // whether that may happen on the way: robots set aside).
                    return Err(Cycle {
                        robots: vec![p.robot as usize, s.robot as usize],
                    });
                }
                cur.push(Dep {
                    q: x,
                    p: p.robot,
                    s: s.robot,
                    last: p.last,
                    first: s.first,
                });
            }
            Ok(())
        };
        if *known {
            for &x in dirty.iter() {
                read(x, &self.queues[x as usize])?;
            }
        } else {
            for (x, q) in self.queues.iter().enumerate() {
                read(x as Res, q)?;
            }
        }
        #[cfg(debug_assertions)]
        {
            // The queues left unread give what reading them would.
            let key = |d: &Dep| (d.q, d.p, d.s, d.last, d.first);
            let mut all: Vec<_> = self
                .queues
                .iter()
                .enumerate()
                .flat_map(|(x, q)| {
                    q.iter()
                        .zip(q.iter().skip(1))
                        .map(move |(p, s)| (x as Res, p.robot, s.robot, p.last, s.first))
                })
                .collect();
            let mut have: Vec<_> = cur.iter().map(key).collect();
            all.sort_unstable();
            have.sort_unstable();
            assert!(all == have, "the dependencies kept are not the queues'");
        }
        // Dependencies of each traversal on the last traversal of the span before its own,
        // as one list of users per traversal (CSR: a saturated run retimes thousands of
        // times, and a vector per traversal cost most of it).
        edges.clear();
        edges.extend(cur.iter().filter_map(|d| {
            let a = robots[d.p as usize].node(d.last)?;
            let b = robots[d.s as usize].node(d.first)?;
            Some((a as u32, b as u32))
        }));
        refill(indeg, total, 0);
        refill(first, total + 1, 0);
        for &(a, b) in edges.iter() {
            first[a as usize + 1] += 1;
            indeg[b as usize] += 1;
        }
        for k in 0..total {
            first[k + 1] += first[k];
        }
        refill(users, edges.len(), 0);
        at.clear();
        at.extend_from_slice(first);
        for &(a, b) in edges.iter() {
            users[at[a as usize] as usize] = b;
            at[a as usize] += 1;
        }
        // Each robot's own order: a traversal after the one before it.
        for it_off in offs.windows(2) {
            for d in indeg.iter_mut().take(it_off[1]).skip(it_off[0] + 1) {
                *d += 1;
            }
        }
        // Kahn's algorithm: a node whose dependencies are all timed is timed.
        ready.clear();
        ready.extend((0..total).filter(|&b| indeg[b] == 0));
        refill(end, total, 0.0);
        refill(start, total, 0.0);
        // The latest end of the other robots' traversals each waits for.
        refill(after, total, f64::NEG_INFINITY);
        refill(moved, nr, false);
        let mut done = 0;
        while let Some(b) = ready.pop() {
            done += 1;
            let r = owner[b] as usize;
            let first_of_robot = b == offs[r];
            let nd = nodes[b];
            if nd.begun {
                // Driven now (the first), or next after it (sent together): the estimate
                // from when it was sent may lie ahead of now if the one before ended early.
                let s = if first_of_robot {
                    nd.start.min(now)
                } else {
                    end[b - 1]
                };
                start[b] = s;
                end[b] = (s + nd.dur).max(now);
            } else {
                let own = if first_of_robot {
                    robots[r].ready
                } else {
                    end[b - 1] + nd.hold
                };
                let s = now.max(own).max(after[b]);
                start[b] = s;
                end[b] = s + nd.dur;
            }
            // As `apply` compares them (NaN differs from itself).
            if start[b] != nd.was.0 || end[b] != nd.was.1 {
                moved[r] = true;
            }
            for &u in &users[first[b] as usize..first[b + 1] as usize] {
                let u = u as usize;
                after[u] = after[u].max(end[b]);
                indeg[u] -= 1;
                if indeg[u] == 0 {
                    ready.push(u);
                }
            }
            if b + 1 < offs[r + 1] {
                indeg[b + 1] -= 1;
                if indeg[b + 1] == 0 {
                    ready.push(b + 1);
                }
            }
        }
        if done < total {
            let mut robots: Vec<usize> = (0..total)
                .filter(|&b| indeg[b] > 0)
                .map(|b| owner[b] as usize)
                .collect();
            robots.dedup();
            // As before: a failed retime leaves the estimates and marks them fresh.
            self.stale = false;
            self.stamp = new_stamp();
            return Err(Cycle { robots });
        }
        self.bufs.computed = true;
        Ok(())
    }

    /// The end of robot `r`'s `k`-th remaining traversal by the last
    /// [`Schedule::compute`], if it succeeded and the traversal exists.
    pub fn computed_end(&self, r: usize, k: usize) -> Option<f64> {
        let b = &self.bufs;
        if !b.computed || k >= self.its[r].travs.len() {
            return None;
        }
        b.end.get(b.offs[r] + k).copied()
    }

    /// Writes the times of the last successful [`Schedule::compute`] (at `now`, on the
    /// schedule as it is still).
    pub fn apply(&mut self, now: f64) {
        debug_assert!(self.bufs.computed, "apply after a successful compute");
        debug_assert!(self.tx.is_none(), "a rollback would not undo the times");
        self.stale = false;
        self.stamp = new_stamp();
        // The traversals' times; the queues whose spans may move with them become dirty:
        // those of the traversals whose times moved, and those of a robot that began to
        // wait for its turn (its spans are held from now on). Setting off, arriving and
        // planning made theirs dirty already.
        let known = self.bufs.known;
        self.bufs.waited.resize(self.its.len(), u64::MAX);
        for (r, it) in self.its.iter_mut().enumerate() {
            let b = &mut self.bufs;
            let off = b.offs[r];
            let br = b.robots[r];
            let began_to_wait = br.waiting && b.waited[r] != br.base;
            b.waited[r] = if br.waiting { br.base } else { u64::MAX };
            if !(b.moved[r] || (known && began_to_wait)) {
                // Nothing to write, nothing touched.
                continue;
            }
            for (k, tr) in it.travs.iter_mut().enumerate() {
                let (s, e) = (b.start[off + k], b.end[off + k]);
                if known && ((k == 0 && began_to_wait) || tr.start != s || tr.end != e) {
                    for &x in &self.conf.trav[tr.edge] {
                        b.touch(x);
                    }
                }
                tr.start = s;
                tr.end = e;
            }
        }
        if !known {
            for x in 0..self.queues.len() as Res {
                self.bufs.touch(x);
            }
        }
        let dirty = std::mem::take(&mut self.bufs.dirty);
        for &x in &dirty {
            if self.respan(x as usize, now) {
                self.changed[x as usize] = self.stamp;
            }
        }
        self.bufs.dirty = dirty;
        self.bufs.clean();
        let b = &mut self.bufs;
        std::mem::swap(&mut b.deps, &mut b.cur);
        b.known = true;
        #[cfg(debug_assertions)]
        for x in 0..self.queues.len() {
            let before = self.queues[x].clone();
            assert!(
                !self.respan(x, now),
                "queue {x} was left with times to write: {before:?} -> {:?}",
                self.queues[x]
            );
        }
    }

    /// Writes the times of queue `x`'s spans from the last compute's; whether any moved.
    fn respan(&mut self, x: usize, now: f64) -> bool {
        let Bufs {
            start, end, robots, ..
        } = &self.bufs;
        let mut moved = false;
        for s in self.queues[x].iter_mut() {
            let was = (s.start, s.end);
            let br = &robots[s.robot as usize];
            // A span held now is busy from now (or from any time before: nobody plans
            // for the past, and a start that stays keeps the planner's intervals). Held:
            // its first traversal is done (an estimate from before would hide the span
            // from the planner), or the robot was sent along it (`install` never puts a
            // span before it), or the robot is ready to go on and waits for its turn
            // (nobody planned later goes before it, else a waiting robot could be
            // overtaken for ever).
            let held = br.node(s.first).is_none_or(|b| {
                s.first < br.base + u64::from(br.begun) || (b == br.off as usize && br.waiting)
            });
            s.start = match br.node(s.first) {
                Some(b) if !held => start[b],
                _ => s.start.min(now),
            };
            s.end = if s.last == FOREVER {
                f64::INFINITY
            } else if let Some(b) = br.node(s.last) {
                end[b]
            } else {
                s.end
            };
            moved |= (s.start, s.end) != was;
        }
        moved
    }
}
