//! Retiming the schedule: every traversal's estimated times from now on, keeping every
//! queue's order (a longest-path pass over the action dependency graph, Kahn's algorithm),
//! and writing them back into the itineraries and spans.
//!
//! A saturated warehouse retimes thousands of times an hour over 100,000 traversals, so
//! both halves remember what they read. A full pass reads again only the queues whose
//! dependencies changed since it last read them; a retime at the time of the last one
//! (within a dispatch round) times only the traversals downstream of a change
//! (`follow.rs`); and spans are written only in the queues whose traversals' times moved,
//! that changed, or whose robot began to wait for its turn. Debug builds check all three
//! against a full pass.

use super::{new_stamp, Cycle, Itinerary, Schedule, Span, FOREVER};
use crate::traffic::conflicts::Res;
use std::collections::VecDeque;

mod follow;

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
    pub(super) robots: Vec<Brief>,
    /// The itineraries hold the times of the last [`Schedule::apply`], at `applied_at`,
    /// and `dirty` and `seeds` say what changed since: the next compute may follow the
    /// changes only.
    pub(super) known: bool,
    pub(super) applied_at: f64,
    /// The queues changed since the last apply (their order, spans, or what their spans'
    /// times are made of, other than the times of the traversals).
    pub(super) dirty: Vec<Res>,
    is_dirty: Vec<bool>,
    /// Per queue in `dirty`, where its dependencies as of the last apply begin in
    /// `before` (robot and traversal of each span's predecessor, and of the span).
    snap: Vec<u32>,
    before: Vec<(u32, u64, u32, u64)>,
    /// The robots whose itineraries changed since the last apply (other than by the
    /// apply's times), and single traversals that did (robot, running number).
    seeds: Vec<u32>,
    is_seed: Vec<bool>,
    seed_nodes: Vec<(u32, u64)>,
    /// Per node of the last compute: whether it waits in `follow`'s work list, and
    /// whether what waits for it is to be timed again whatever its own times.
    queued: Vec<bool>,
    forced: Vec<bool>,
    /// Per node: `start` and `end` hold its times (else they are its itinerary's).
    have: Vec<bool>,
    work: std::collections::VecDeque<(u32, u32)>,
    /// The spans just after the one `follow` times (robot, first traversal).
    next: Vec<(u32, u64)>,
    /// The dependencies between neighbours in the queues as of the last full compute that
    /// was applied (when `deps_known`), and as of the last full compute: the next full
    /// compute reads again only the queues changed since (`redo`; reading all 40,000
    /// queues of a warehouse, each in its own allocation, was a third of a retime).
    deps_known: bool,
    deps: Vec<Dep>,
    cur: Vec<Dep>,
    redo: Vec<Res>,
    is_redo: Vec<bool>,
    /// The last compute was a full one (its `cur` may become `deps`).
    last_full: bool,
    /// Computes that followed the changes, and full ones (for the tests).
    pub(super) followed: u64,
    pub(super) full: u64,
    /// Per robot: the running number of its first traversal if it waited for its turn
    /// at the last apply (else `u64::MAX`). Its spans from there were written busy from
    /// then, and stay so.
    waited: Vec<u64>,
}

/// What [`Schedule::compute`] reads of a traversal.
#[derive(Debug, Clone, Copy)]
pub(super) struct Node {
    dur: f64,
    hold: f64,
    /// `Trav::start` and `Trav::end` as they are.
    was: (f64, f64),
    /// `Trav::start`, read when it has begun.
    start: f64,
    begun: bool,
}

impl Node {
    pub(super) fn of(t: &super::Trav) -> Node {
        Node {
            dur: t.dur,
            hold: t.hold,
            was: (t.start, t.end),
            start: t.start,
            begun: t.begun,
        }
    }
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

/// `Brief::off` of a robot whose times the compute left as they are.
pub(super) const UNTOUCHED: u32 = u32::MAX;

/// What [`Schedule::compute`] and [`Schedule::apply`] read of an itinerary.
#[derive(Debug, Clone, Copy)]
pub(super) struct Brief {
    /// `Itinerary::base`, its traversals, and where the compute's times of its first one
    /// are in `Bufs::start` and `Bufs::end` (`UNTOUCHED`: they are the itinerary's).
    pub(super) base: u64,
    pub(super) len: u32,
    pub(super) off: u32,
    /// How many of its first traversals it was sent along (they are a prefix).
    begun: u32,
    /// Ready to go on and waiting for its turn now (its first traversal not begun).
    waiting: bool,
}

impl Brief {
    fn of(it: &Itinerary, now: f64) -> Brief {
        Brief {
            base: it.base,
            len: it.travs.len() as u32,
            off: UNTOUCHED,
            begun: it.travs.iter().take_while(|t| t.begun).count() as u32,
            waiting: it.travs.front().is_some_and(|t| !t.begun) && it.ready <= now,
        }
    }

    /// The index in the itinerary of its traversal `seq`, when that is still in it.
    pub(super) fn node(&self, seq: u64) -> Option<usize> {
        let k = seq.checked_sub(self.base)?;
        (k < u64::from(self.len)).then_some(k as usize)
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
            self.snap.push(self.before.len() as u32);
        }
    }

    /// Queue `x`, as it is (`q`), is about to change.
    pub(super) fn touch_with(&mut self, x: Res, q: &VecDeque<Span>) {
        let i = x as usize;
        if self.is_redo.len() <= i {
            self.is_redo.resize(i + 1, false);
        }
        if !self.is_redo[i] {
            self.is_redo[i] = true;
            self.redo.push(x);
        }
        if self.is_dirty.get(i).is_some_and(|&d| d) {
            return;
        }
        self.touch(x);
        if self.known {
            self.before.extend(neighbours(q));
        }
    }

    /// Robot `r`'s itinerary changed (see `Bufs::seeds`).
    pub(super) fn seed(&mut self, r: usize) {
        if self.is_seed.len() <= r {
            self.is_seed.resize(r + 1, false);
        }
        if !self.is_seed[r] {
            self.is_seed[r] = true;
            self.seeds.push(r as u32);
        }
    }

    /// Robot `r`'s traversal `seq` changed (see `Bufs::seeds`).
    pub(super) fn seed_at(&mut self, r: usize, seq: u64) {
        self.seed_nodes.push((r as u32, seq));
    }

    /// Nothing changed since now.
    fn clean(&mut self) {
        for &x in &self.dirty {
            self.is_dirty[x as usize] = false;
        }
        self.dirty.clear();
        self.snap.clear();
        self.before.clear();
        for &r in &self.seeds {
            self.is_seed[r as usize] = false;
        }
        self.seeds.clear();
        self.seed_nodes.clear();
    }

    /// The last compute's start and end of robot `r`'s `k`-th traversal (`its`: the
    /// itineraries it computed them for).
    pub(super) fn times(&self, its: &[Itinerary], r: usize, k: usize) -> (f64, f64) {
        let off = self.robots[r].off;
        let b = off as usize + k;
        if off == UNTOUCHED || !self.have[b] {
            let t = &its[r].travs[k];
            (t.start, t.end)
        } else {
            (self.start[b], self.end[b])
        }
    }
}

/// The dependencies between neighbours in queue `q`, in order: (the robot of a span, its
/// last traversal, the robot of the span after it, that span's first traversal).
fn neighbours(q: &VecDeque<Span>) -> impl Iterator<Item = (u32, u64, u32, u64)> + '_ {
    q.iter()
        .zip(q.iter().skip(1))
        .map(|(p, s)| (p.robot, p.last, s.robot, s.first))
}

/// `v` as `n` copies of `x`, keeping its allocation.
fn refill<T: Clone>(v: &mut Vec<T>, n: usize, x: T) {
    v.clear();
    v.resize(n, x);
}

/// How long after the others' traversals it waits for end a traversal starts (s). Retimed
/// to start the very instant they end, a robot's spans touched the others' on both sides,
/// and planning it again along its own way failed: the search's half-open intervals and
/// its floating-point sums do not fit a plan into a gap exactly its length (on a full
/// house, robots on their way to parking found no way to a task four times as often). Any
/// margin well above rounding does; this one costs a millisecond per robot followed.
pub(in crate::traffic) const HEADWAY: f64 = 1e-3;

/// A traversal's start and end: `prev_end`, the end of its robot's traversal before it
/// (none for the first); `ready`, when its robot may go on; `after`, the latest end of the
/// others' traversals it waits for (`NEG_INFINITY` for none).
pub(super) fn node_times(
    nd: Node,
    prev_end: Option<f64>,
    ready: f64,
    after: f64,
    now: f64,
) -> (f64, f64) {
    if nd.begun {
        // Driven now (the first), or next after it (sent together): the estimate from
        // when it was sent may lie ahead of now if the one before ended early.
        let s = prev_end.unwrap_or(nd.start.min(now));
        (s, (s + nd.dur).max(now))
    } else {
        let own = prev_end.map_or(ready, |e| e + nd.hold);
        let s = now.max(own).max(after + HEADWAY);
        (s, s + nd.dur)
    }
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
        let out = match self.follow(now) {
            Some(out) => {
                self.bufs.followed += 1;
                self.bufs.last_full = false;
                #[cfg(debug_assertions)]
                self.check_followed(now, &out);
                out
            }
            None => {
                self.bufs.full += 1;
                self.bufs.last_full = true;
                self.compute_all(now)
            }
        };
        match out {
            Ok(()) => self.bufs.computed = true,
            Err(_) => {
                // As before: a failed retime leaves the estimates and marks them fresh.
                self.stale = false;
                self.stamp = new_stamp();
            }
        }
        out
    }

    /// Debug builds: what followed the changes is what a full compute gives.
    #[cfg(debug_assertions)]
    fn check_followed(&self, now: f64, out: &Result<(), Cycle>) {
        let mut all = self.clone();
        let full = all.compute_all(now);
        assert_eq!(out.is_ok(), full.is_ok(), "followed {out:?}, full {full:?}");
        if full.is_err() {
            return;
        }
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
        for (r, it) in self.its.iter().enumerate() {
            for k in 0..it.travs.len() {
                let (a, b) = (
                    self.bufs.times(&self.its, r, k),
                    all.bufs.times(&all.its, r, k),
                );
                assert!(
                    same(a.0, b.0) && same(a.1, b.1),
                    "robot {r}'s traversal {k} at {now}: followed {a:?}, full {b:?}"
                );
            }
            assert_eq!(self.bufs.moved[r], all.bufs.moved[r], "robot {r} moved");
        }
    }

    /// [`Schedule::compute`] over every traversal: a longest-path pass over the whole
    /// dependency graph (Kahn's algorithm), which finds any cycle.
    fn compute_all(&mut self, now: f64) -> Result<(), Cycle> {
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
            have,
            deps_known,
            deps,
            cur,
            redo,
            is_redo,
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
            nodes.extend(it.travs.iter().map(Node::of));
            owner.resize(nodes.len(), r as u32);
            robots.push(Brief {
                off: off as u32,
                ..Brief::of(it, now)
            });
        }
        offs.push(nodes.len());
        let offs = &*offs;
        let total = offs[nr];
        let robots = &*robots;
        // The dependencies between neighbours in the queues: those of the queues that did
        // not change since they were read, and those of the others read again.
        cur.clear();
        let changed = |x: Res| is_redo.get(x as usize).is_some_and(|&d| d);
        if *deps_known {
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
        if *deps_known {
            for &x in redo.iter() {
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
                    neighbours(q).map(move |(p, last, s, first)| (x as Res, p, s, last, first))
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
            let node = |r: u32, seq: u64| {
                let br = &robots[r as usize];
                br.node(seq).map(|k| (br.off as usize + k) as u32)
            };
            Some((node(d.p, d.last)?, node(d.s, d.first)?))
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
        refill(have, total, true);
        // The latest end of the other robots' traversals each waits for.
        refill(after, total, f64::NEG_INFINITY);
        refill(moved, nr, false);
        let mut done = 0;
        while let Some(b) = ready.pop() {
            done += 1;
            let r = owner[b] as usize;
            let nd = nodes[b];
            let prev_end = (b > offs[r]).then(|| end[b - 1]);
            let (s, e) = node_times(nd, prev_end, self.its[r].ready, after[b], now);
            start[b] = s;
            end[b] = e;
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
            return Err(Cycle { robots });
        }
        Ok(())
    }

    /// The end of robot `r`'s `k`-th remaining traversal by the last
    /// [`Schedule::compute`], if it succeeded and the traversal exists.
    pub fn computed_end(&self, r: usize, k: usize) -> Option<f64> {
        if !self.bufs.computed || k >= self.its[r].travs.len() {
            return None;
        }
        Some(self.bufs.times(&self.its, r, k).1)
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
            let br = b.robots[r];
            let began_to_wait = br.waiting && b.waited[r] != br.base;
            b.waited[r] = if br.waiting { br.base } else { u64::MAX };
            if !(b.moved[r] || (known && began_to_wait)) {
                // Nothing to write, nothing touched.
                continue;
            }
            for (k, tr) in it.travs.iter_mut().enumerate() {
                let n = br.off as usize + k;
                let (s, e) = if br.off == UNTOUCHED || !b.have[n] {
                    (tr.start, tr.end)
                } else {
                    (b.start[n], b.end[n])
                };
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
        self.bufs.known = true;
        let b = &mut self.bufs;
        if b.last_full {
            // Its dependencies are the queues' now.
            std::mem::swap(&mut b.deps, &mut b.cur);
            b.deps_known = true;
            for &x in &b.redo {
                b.is_redo[x as usize] = false;
            }
            b.redo.clear();
        }
        self.bufs.applied_at = now;
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
        let b = &self.bufs;
        let mut moved = false;
        // When the span before in the queue ends (NEG_INFINITY when it is soft: see below).
        let mut before_ends = f64::NEG_INFINITY;
        for s in self.queues[x].iter_mut() {
            let was = (s.start, s.end);
            let r = s.robot as usize;
            let br = &b.robots[r];
            // A span held now is busy from now (or from any time before: nobody plans
            // for the past, and a start that stays keeps the planner's intervals). Held:
            // its first traversal is done (an estimate from before would hide the span
            // from the planner), or the robot was sent along it (`install` never puts a
            // span before it), or the robot is ready to go on and waits for its turn
            // (nobody planned later goes before it, else a waiting robot could be
            // overtaken for ever).
            let on_way = br
                .node(s.first)
                .is_none_or(|_| s.first < br.base + u64::from(br.begun));
            let waiting = !on_way && br.node(s.first) == Some(0) && br.waiting;
            s.start = match br.node(s.first) {
                Some(k) if !on_way && !waiting => b.times(&self.its, r, k).0,
                // A robot that waits for its turn behind another robot's span waits for
                // that span to end: its own is busy from then, not from now. When the
                // robot before it plans again (its own spans left out), a waiting span
                // busy from now took its place: standing where it stands, it found no
                // way at all ("start busy", on a full warehouse most of the free robots'
                // plans for tasks), or none out. The waiting robot cannot go before that
                // span anyway; robots planned later may use the time before it starts,
                // as without the waiting one. (Not behind a soft span, which a plan
                // through soft spans leaves out: it would go between the two.)
                _ if waiting && before_ends > now && before_ends.is_finite() => before_ends,
                _ => s.start.min(now),
            };
            s.end = if s.last == FOREVER {
                f64::INFINITY
            } else if let Some(k) = br.node(s.last) {
                b.times(&self.its, r, k).1
            } else {
                s.end
            };
            moved |= (s.start, s.end) != was;
            before_ends = if !self.its[r].soft_in(s.first) {
                s.end
            } else {
                f64::NEG_INFINITY
            };
        }
        moved
    }
}
