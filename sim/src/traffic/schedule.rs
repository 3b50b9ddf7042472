//! The shared schedule: every robot's itinerary (the edges it will drive, in order, with
//! estimated times) and, per resource, the order in which robots hold it: one schedule for
//! all fleets, as in rmf_traffic.
//!
//! Execution keeps that order (an action dependency graph, Hönig et al. 2019): a robot may
//! drive a traversal only when, for every resource the traversal needs, its own span is the
//! first unfinished one in that resource's queue. Delays then slow robots down but cannot
//! deadlock them.
//!
//! Invariant (checked by [`Schedule::retime`], which fails on a cycle): the order of every
//! queue agrees with the robots' own order of traversals, so the dependency graph is
//! acyclic. It holds because spans are only ever appended or inserted where their estimated
//! times fit between their neighbours' (the planner plans against retimed estimates), never
//! before a span its robot holds (it drives, or was sent along, the span's first traversal;
//! such spans are busy from no later than now for the planner), and removing spans removes
//! dependencies.
//! Hence at any time the unfinished traversal with the earliest estimated start has every
//! dependency met: some robot can always go on.
//!
//! Every itinerary ends where its robot may stand for good (a span with `last ==
//! FOREVER`); the planner never plans through such a span, so a robot that has nothing to do
//! blocks nobody's plan.
//!
//! The part of an itinerary after a task's last place (its way to parking) may be *soft*
//! (`Itinerary::soft`): until the task is done, another robot's task plan may ignore those
//! spans and go before them in the queues ([`Schedule::install`] says whose it went
//! before); the fleet then plans those robots' ways to parking again behind it. A robot
//! rarely drives that way while tasks wait (it takes the next task first), so it should not
//! hold up the plans of tasks.

use super::conflicts::{Conflicts, Res};
use std::collections::VecDeque;

/// `Span::last` of a robot that stays where its itinerary ends.
pub const FOREVER: u64 = u64::MAX;

/// One edge of an itinerary.
#[derive(Debug, Clone)]
pub struct Trav {
    /// The robot's running number of its traversals (0 is its arrival at its start).
    pub seq: u64,
    pub edge: usize,
    pub to: usize,
    /// Nominal duration (s).
    pub dur: f64,
    /// Least time (s) the robot stays where the traversal starts after it got there before it leaves (the
    /// work of a task step there).
    pub hold: f64,
    /// Estimated start and end (the planner's, then retimed).
    pub start: f64,
    pub end: f64,
    /// The robot has been sent along it, and when.
    pub begun: bool,
    pub begun_at: f64,
}

/// A robot's hold on one resource, over its traversals `first..=last`.
#[derive(Debug, Clone)]
struct Span {
    robot: u32,
    first: u64,
    last: u64,
    start: f64,
    end: f64,
}

/// One robot's plan.
#[derive(Debug, Clone)]
pub struct Itinerary {
    /// Where the robot stands, or where its first remaining traversal starts.
    pub at: usize,
    /// The earliest its first remaining traversal may start (s).
    pub ready: f64,
    /// Traversals still to drive or being driven; `travs[k].seq == base + k`.
    pub travs: VecDeque<Trav>,
    base: u64,
    /// The running number of its first soft traversal (see the module's doc), if any.
    soft: Option<u64>,
}

impl Itinerary {
    /// Whether a span of this robot from its traversal `first` on is soft: it lies after
    /// the soft mark, and the robot has not set off on its soft traversals (`begin`
    /// removes the mark then).
    fn soft_in(&self, first: u64) -> bool {
        let soft = self
            .soft
            .is_some_and(|mark| first >= mark && mark >= self.base);
        debug_assert_eq!(
            soft,
            self.soft.is_some_and(|mark| first >= mark
                && mark
                    .checked_sub(self.base)
                    .is_some_and(|k| self.travs.get(k as usize).is_none_or(|t| !t.begun))),
            "a soft mark left on a traversal set off on"
        );
        soft
    }

    /// Whether the robot holds a span from its traversal `first` on now: it has driven,
    /// is driving, or was sent along the traversal (traversals sent together are driven
    /// one after the other, without asking again: the next one's resources are as good as
    /// held).
    fn held_in(&self, first: u64) -> bool {
        first < self.base
            || self
                .travs
                .get((first - self.base) as usize)
                .is_some_and(|t| t.begun)
    }
}

/// What a plan hands to [`Schedule::install`].
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub edge: usize,
    pub from: usize,
    pub to: usize,
    pub dur: f64,
    pub hold: f64,
    pub start: f64,
    pub end: f64,
}

/// The dependency graph has a cycle (a bug: the invariant above is broken).
#[derive(Debug, Clone, PartialEq)]
pub struct Cycle {
    pub robots: Vec<usize>,
}

#[derive(Debug)]
pub struct Schedule {
    /// Shared by the copies (fixed once built; a copy per soft plan copied it whole).
    conf: std::sync::Arc<Conflicts>,
    queues: Vec<VecDeque<Span>>,
    its: Vec<Itinerary>,
    /// Per robot: its soft mark (`Itinerary::soft`), or `u64::MAX` when it has none. The
    /// planner asks whether a span is soft of every span it reads; one look-up in this
    /// small array beats a cache miss on the robot's itinerary.
    soft_from: Vec<u64>,
    /// A traversal began or ended since the last retime: the estimates are stale.
    stale: bool,
    /// Changes with every change of the schedule, and no two schedules share one (see
    /// [`Schedule::stamp`]).
    stamp: u64,
    /// Per resource: the stamp of the last change of what [`Schedule::busy`] says of it.
    changed: Vec<u64>,
    /// New for every copy: what was computed from one copy says nothing of another (see
    /// [`Schedule::lineage`]).
    lineage: u64,
    /// What [`Schedule::retime`] reuses.
    bufs: retime::Bufs,
    /// The open transaction's undo log ([`Schedule::open_tx`]).
    tx: Option<Box<Tx>>,
}

/// What a transaction changed, as it was before: the queues and itineraries it changed
/// (a plan touches a few hundred resources; copying a 1,000-robot schedule whole to undo
/// one, and freeing the copy, was a fifth of a warehouse run).
#[derive(Debug, Default)]
struct Tx {
    queues: std::collections::BTreeMap<Res, VecDeque<Span>>,
    its: std::collections::BTreeMap<usize, Itinerary>,
    stale: bool,
}

impl Clone for Schedule {
    fn clone(&self) -> Schedule {
        Schedule {
            conf: self.conf.clone(),
            queues: self.queues.clone(),
            its: self.its.clone(),
            soft_from: self.soft_from.clone(),
            stale: self.stale,
            stamp: self.stamp,
            changed: self.changed.clone(),
            lineage: new_stamp(),
            bufs: retime::Bufs::default(),
            tx: None,
        }
    }
}

/// The next stamp any schedule takes.
static STAMPS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

fn new_stamp() -> u64 {
    STAMPS.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl Schedule {
    /// Robots standing at `starts` from `t0` on, for good.
    pub fn new(conf: Conflicts, starts: &[usize], t0: f64) -> Schedule {
        let mut queues = vec![VecDeque::new(); conf.n_res];
        let mut its = Vec::with_capacity(starts.len());
        for (r, &at) in starts.iter().enumerate() {
            for &x in &conf.vertex[at] {
                let q: &mut VecDeque<Span> = &mut queues[x as usize];
                // Robots placed closer than their clearance share a resource: only the first
                // holds it (a span after one held for good could never be reached).
                if q.is_empty() {
                    q.push_back(Span {
                        robot: r as u32,
                        first: 0,
                        last: FOREVER,
                        start: f64::NEG_INFINITY,
                        end: f64::INFINITY,
                    });
                }
            }
            its.push(Itinerary {
                at,
                ready: t0,
                travs: VecDeque::new(),
                base: 1,
                soft: None,
            });
        }
        let stamp = new_stamp();
        Schedule {
            changed: vec![stamp; conf.n_res],
            conf: std::sync::Arc::new(conf),
            queues,
            soft_from: vec![u64::MAX; its.len()],
            its,
            stale: true,
            stamp,
            lineage: new_stamp(),
            bufs: retime::Bufs::default(),
            tx: None,
        }
    }

    /// Opens a transaction: [`Schedule::rollback`] puts back every queue and itinerary
    /// as they are now; [`Schedule::commit`] keeps the changes. Retimes within it must be
    /// [`Schedule::compute`] only (its times are not written until [`Schedule::apply`]).
    pub fn open_tx(&mut self) {
        debug_assert!(self.tx.is_none(), "transactions do not nest");
        self.tx = Some(Box::new(Tx {
            stale: self.stale,
            ..Tx::default()
        }));
    }

    /// Keeps what the open transaction changed.
    pub fn commit(&mut self) {
        self.tx = None;
    }

    /// Undoes what the open transaction changed. Intervals computed from the restored
    /// queues are stale ([`Schedule::changed_since`]); the others hold.
    pub fn rollback(&mut self) {
        let Some(tx) = self.tx.take() else { return };
        self.bufs.computed = false;
        self.stamp = new_stamp();
        self.stale = tx.stale;
        for (x, q) in tx.queues {
            self.queues[x as usize] = q;
            self.changed[x as usize] = self.stamp;
            self.bufs.touch_with(x, &self.queues[x as usize]);
        }
        for (r, it) in tx.its {
            self.soft_from[r] = it.soft.unwrap_or(u64::MAX);
            self.its[r] = it;
            self.bufs.seed(r);
        }
    }

    /// Saves queues `set` and itinerary `r` in the open transaction, if not saved yet.
    fn save(&mut self, set: &[Res], r: usize) {
        if let Some(tx) = self.tx.as_mut() {
            for &x in set {
                tx.queues
                    .entry(x)
                    .or_insert_with(|| self.queues[x as usize].clone());
            }
            tx.its.entry(r).or_insert_with(|| self.its[r].clone());
        }
    }

    /// Identifies the schedule as it is: equal stamps, equal schedules (a clone shares
    /// its original's until either changes). What is computed from a schedule may be
    /// kept while its stamp stays.
    pub fn stamp(&self) -> u64 {
        self.stamp
    }

    /// Identifies this copy of the schedule: while it stays, intervals computed from
    /// resources at one stamp hold for as long as [`Schedule::changed_since`] says none of
    /// them changed.
    pub fn lineage(&self) -> u64 {
        self.lineage
    }

    /// Whether what [`Schedule::busy`] says of any of `set` changed after stamp `at`.
    pub fn changed_since(&self, set: &[Res], at: u64) -> bool {
        set.iter().any(|&x| self.changed[x as usize] > at)
    }

    /// Every resource robot `r` may hold a span on: its standing set and its traversals'.
    fn resources_of(&self, r: usize) -> Vec<Res> {
        let it = &self.its[r];
        let mut out: Vec<Res> = self.conf.vertex[it.at].clone();
        for t in &it.travs {
            out.extend_from_slice(&self.conf.trav[t.edge]);
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Marks `set` changed now.
    fn mark(&mut self, set: &[Res]) {
        for &x in set {
            self.changed[x as usize] = self.stamp;
            self.bufs.touch_with(x, &self.queues[x as usize]);
        }
    }

    pub fn conf(&self) -> &Conflicts {
        &self.conf
    }

    pub fn itinerary(&self, r: usize) -> &Itinerary {
        &self.its[r]
    }

    /// Where robot `r`'s itinerary ends (where it will stand for good).
    pub fn end_vertex(&self, r: usize) -> usize {
        let it = &self.its[r];
        it.travs.back().map_or(it.at, |t| t.to)
    }

    /// The resources traversal `t` holds.
    fn set(&self, t: &Trav) -> &[Res] {
        &self.conf.trav[t.edge]
    }

    /// Whether robot `r` may drive its `k`-th remaining traversal: for every resource, its
    /// own span is the first unfinished one.
    pub fn granted(&self, r: usize, k: usize) -> bool {
        let Some(t) = self.its[r].travs.get(k) else {
            return false;
        };
        self.set(t).iter().all(|&x| {
            self.queues[x as usize]
                .front()
                .is_some_and(|s| s.robot as usize == r && s.first <= t.seq && t.seq <= s.last)
        })
    }

    /// The robots whose spans come before robot `r`'s in the queues its `k`-th remaining
    /// traversal needs (whom it waits for), ascending.
    pub fn waits_for(&self, r: usize, k: usize) -> Vec<usize> {
        let Some(t) = self.its[r].travs.get(k) else {
            return Vec::new();
        };
        let mut who: Vec<usize> = Vec::new();
        for &x in self.set(t) {
            for s in &self.queues[x as usize] {
                if s.robot as usize == r {
                    break;
                }
                who.push(s.robot as usize);
            }
        }
        who.sort_unstable();
        who.dedup();
        who
    }

    /// Robot `r` starts driving its first `n` remaining traversals (they are granted).
    /// Traversals sent together are driven one after the other.
    pub fn begin(&mut self, r: usize, n: usize, t: f64) {
        debug_assert!(self.tx.is_none(), "robots drive outside transactions");
        self.stale = true;
        self.stamp = new_stamp();
        // Setting off on its soft traversals makes them hard, for good: the mark goes, so
        // that `soft_in` need not look at the traversal (the planner asks it of every
        // span it reads).
        let it = &self.its[r];
        if let Some(k) = it.soft.and_then(|m| m.checked_sub(it.base)) {
            if (k as usize) < n {
                if it.travs.get(k as usize).is_some_and(|t| !t.begun) {
                    let set = self.resources_of(r);
                    self.mark(&set);
                }
                self.its[r].soft = None;
                self.soft_from[r] = u64::MAX;
            }
        }
        let mut prev = t;
        for tr in self.its[r].travs.iter_mut().take(n) {
            if !tr.begun {
                self.bufs.seed_at(r, tr.seq);
                // Its spans are held from now on.
                for &x in &self.conf.trav[tr.edge] {
                    self.bufs.touch_with(x, &self.queues[x as usize]);
                }
                tr.begun = true;
                tr.begun_at = t;
                tr.start = prev.max(t);
                tr.end = tr.start + tr.dur;
            }
            prev = tr.end;
        }
    }

    /// Robot `r` reached the end of its first remaining traversal at `t`: what it no
    /// longer needs is released.
    pub fn complete_front(&mut self, r: usize, t: f64) {
        debug_assert!(self.tx.is_none(), "robots drive outside transactions");
        let Some(tr) = self.its[r].travs.pop_front() else {
            return;
        };
        self.stale = true;
        self.stamp = new_stamp();
        // Its next traversal starts when it is ready now.
        self.bufs.seed_at(r, tr.seq + 1);
        for &x in &self.conf.trav[tr.edge] {
            // Spans from it on start at a traversal that is gone.
            self.bufs.touch_with(x, &self.queues[x as usize]);
            let q = &mut self.queues[x as usize];
            if q.front()
                .is_some_and(|s| s.robot as usize == r && s.last == tr.seq)
            {
                q.pop_front();
                self.changed[x as usize] = self.stamp;
            }
        }
        let it = &mut self.its[r];
        it.base = tr.seq + 1;
        it.at = tr.to;
        it.ready = t + it.travs.front().map_or(0.0, |n| n.hold);
    }

    /// Replaces robot `r`'s traversals after the first `keep` with `steps` (which start
    /// where the kept ones end); `ready`: when the plan starts (with nothing kept, the
    /// first step's hold, the work where the robot stands, comes after it). The
    /// steps' times must fit the others' spans (the planner's result against this
    /// schedule as it is), or overlap only soft ones (a plan that ignored them). The
    /// steps from `soft` on are soft.
    ///
    /// Returns the robots whose soft spans the new spans went before where they overlap
    /// them: their soft traversals no longer fit, and must be planned again.
    pub fn install(
        &mut self,
        r: usize,
        keep: usize,
        steps: &[Step],
        ready: f64,
        soft: Option<usize>,
    ) -> Vec<usize> {
        self.stamp = new_stamp();
        let mut jumped: Vec<usize> = Vec::new();
        let keep = keep.min(self.its[r].travs.len());
        let s0 = self.its[r].base + keep as u64;
        // Every resource robot `r` may hold a span on: its traversals' and its standing set.
        let mut touched: Vec<Res> = self.conf.vertex[self.its[r].at].clone();
        for t in &self.its[r].travs {
            touched.extend_from_slice(&self.conf.trav[t.edge]);
        }
        for st in steps {
            touched.extend_from_slice(&self.conf.trav[st.edge]);
        }
        touched.sort_unstable();
        touched.dedup();
        self.save(&touched, r);
        self.mark(&touched);
        self.bufs.seed(r);
        // 1. Cut the itinerary after `keep`: spans wholly after go, spans reaching past end
        //    at the last kept traversal (they are extended below where the new steps need
        //    the resource straight on).
        for &x in &touched {
            let q = &mut self.queues[x as usize];
            q.retain(|s| !(s.robot as usize == r && s.first >= s0));
            for s in q.iter_mut() {
                if s.robot as usize == r && s.last >= s0 {
                    s.last = s0 - 1;
                }
            }
        }
        let it = &mut self.its[r];
        it.travs.truncate(keep);
        it.soft = soft.map(|k| s0 + k as u64);
        self.soft_from[r] = it.soft.unwrap_or(u64::MAX);
        if keep == 0 {
            // The work where the robot stands comes before its first traversal, as after
            // any other arrival ([`Schedule::complete_front`]). (Without it the retime let
            // a robot charging where it stood leave at once: others were planned behind it
            // and waited for hours.)
            it.ready = ready + steps.first().map_or(0.0, |st| st.hold);
        }
        for (k, st) in steps.iter().enumerate() {
            it.travs.push_back(Trav {
                seq: s0 + k as u64,
                edge: st.edge,
                to: st.to,
                dur: st.dur,
                hold: st.hold,
                start: st.start,
                end: st.end,
                begun: false,
                begun_at: 0.0,
            });
        }
        // 2. Spans of the new steps: runs of consecutive steps needing a resource.
        let end_v = self.end_vertex(r);
        let n = steps.len();
        let mut runs: Vec<(Res, usize, usize)> = Vec::new();
        {
            let mut open: std::collections::BTreeMap<Res, usize> = Default::default();
            for (k, st) in steps.iter().enumerate() {
                let set = &self.conf.trav[st.edge];
                let next: &[Res] = steps.get(k + 1).map_or(&[], |n| &self.conf.trav[n.edge]);
                // Between two traversals the robot holds only its standing set: where it
                // waits there, what the traversals alone need is released and taken again.
                let waits = steps.get(k + 1).is_some_and(|n| n.start > st.end + 1e-9);
                let stand = &self.conf.vertex[st.to];
                for &x in set {
                    open.entry(x).or_insert(k);
                    let goes_on = next.binary_search(&x).is_ok()
                        && (!waits || stand.binary_search(&x).is_ok());
                    if !goes_on {
                        let a = open.remove(&x).unwrap_or(k);
                        runs.push((x, a, k));
                    }
                }
            }
        }
        for (x, a, b) in runs {
            let forever = b + 1 == n && self.conf.vertex[end_v].binary_search(&x).is_ok();
            let last = if forever { FOREVER } else { s0 + b as u64 };
            let (start, end) = (
                steps[a].start,
                if forever { f64::INFINITY } else { steps[b].end },
            );
            let q = &mut self.queues[x as usize];
            // Straight on from what the robot holds now (the standing set, or a kept
            // traversal's set): the same span goes on.
            let straight_on = steps.first().is_some_and(|f| {
                f.start <= ready + 1e-9 || self.conf.vertex[f.from].binary_search(&x).is_ok()
            });
            if a == 0 && straight_on {
                if let Some(w) = q
                    .iter()
                    .position(|s| s.robot as usize == r && s.last == s0 - 1)
                {
                    q[w].last = last;
                    q[w].end = end;
                    // Soft spans after it that it now overlaps go after it.
                    for s in q.iter().skip(w + 1) {
                        let o = s.robot as usize;
                        if s.start < end && self.its[o].soft_in(s.first) && !jumped.contains(&o) {
                            jumped.push(o);
                        }
                    }
                    continue;
                }
            }
            // Elsewhere: before the first span of another robot that starts after it ends
            // (queues are in time order; the planner kept clear of the others' hard
            // spans) or is soft and overlaps it, but never before a span whose robot holds
            // the resource now.
            let its = &self.its;
            let soft_span = |s: &Span| its[s.robot as usize].soft_in(s.first);
            let pos = q
                .iter()
                .position(|s| {
                    s.robot as usize != r
                        && !its[s.robot as usize].held_in(s.first)
                        && (s.start >= end || soft_span(s) && s.end > start)
                })
                .unwrap_or(q.len());
            for s in q.iter().skip(pos) {
                if s.start < end && soft_span(s) && !jumped.contains(&(s.robot as usize)) {
                    jumped.push(s.robot as usize);
                }
            }
            q.insert(
                pos,
                Span {
                    robot: r as u32,
                    first: s0 + a as u64,
                    last,
                    start,
                    end,
                },
            );
        }
        // 3. Nothing new: the robot stays where its kept traversals end, for good.
        if n == 0 {
            let at = self.end_vertex(r);
            let last_kept = s0 - 1;
            for &x in &self.conf.vertex[at] {
                self.bufs.touch_with(x, &self.queues[x as usize]);
                for s in self.queues[x as usize].iter_mut() {
                    if s.robot as usize == r && s.last == last_kept {
                        s.last = FOREVER;
                        s.end = f64::INFINITY;
                    }
                }
            }
        }
        // 4. Standing (nothing kept): what it held up to the cut and does not hold straight
        //    on is released now (its last traversal is done).
        if keep == 0 {
            for &x in &touched {
                self.queues[x as usize].retain(|s| !(s.robot as usize == r && s.last == s0 - 1));
            }
        }
        jumped.sort_unstable();
        jumped
    }

    /// How many of robot `r`'s remaining traversals come before its soft ones, when it has
    /// soft ones it has not set off on.
    pub fn soft_keep(&self, r: usize) -> Option<usize> {
        let it = &self.its[r];
        let mark = it.soft?;
        it.soft_in(mark).then(|| (mark - it.base) as usize)
    }

    /// Robot `r`'s soft traversals become hard (its task is done: its way to parking is
    /// what it drives next).
    pub fn harden(&mut self, r: usize) {
        if self.its[r].soft.is_some() {
            self.stamp = new_stamp();
            let set = self.resources_of(r);
            self.save(&[], r);
            self.mark(&set);
            self.its[r].soft = None;
            self.soft_from[r] = u64::MAX;
        }
    }

    /// Whether robot `r`'s span from its traversal `first` on is soft
    /// (`Itinerary::soft_in`, from `soft_from`).
    fn soft_span(&self, r: u32, first: u64) -> bool {
        let soft = first >= self.soft_from[r as usize];
        debug_assert_eq!(
            soft,
            self.its[r as usize].soft_in(first),
            "soft_from of robot {r}"
        );
        soft
    }

    /// Whether a robot other than `r` has a soft span on resource `x` that does not end
    /// there for good (its way to parking passes there).
    pub fn soft_passing(&self, x: Res, r: usize) -> bool {
        self.queues[x as usize]
            .iter()
            .any(|s| s.robot as usize != r && s.last != FOREVER && self.soft_span(s.robot, s.first))
    }

    /// The robot other than `r` that holds resource `x` for good (stays there), if any;
    /// when `soft`, not one that would stay there only at the end of soft traversals.
    pub fn held_for_good(&self, x: Res, r: usize, soft: bool) -> Option<usize> {
        self.queues[x as usize]
            .back()
            .filter(|s| s.last == FOREVER && s.robot as usize != r)
            .filter(|s| !(soft && self.soft_span(s.robot, s.first)))
            .map(|s| s.robot as usize)
    }

    /// The robots with a span on resource `x` (in queue order, a robot as often as it has
    /// spans there).
    pub fn holders(&self, x: Res) -> impl Iterator<Item = usize> + '_ {
        self.queues[x as usize].iter().map(|s| s.robot as usize)
    }

    /// Busy intervals `[start, end)` of resource `x` for anybody but robot `r`; when
    /// `soft`, without the others' soft spans.
    pub fn busy(&self, x: Res, r: usize, soft: bool) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.queues[x as usize]
            .iter()
            .filter(move |s| s.robot as usize != r)
            .filter(move |s| !(soft && self.soft_span(s.robot, s.first)))
            .map(|s| (s.start, s.end))
    }

    /// Whether a traversal began or ended since the last [`Schedule::retime`].
    pub fn stale(&self) -> bool {
        self.stale
    }

    /// Checks the schedule's invariants: spans name traversals that exist, every queue's
    /// spans of one robot are in its order, and the whole is acyclic (by retiming a copy).
    pub fn check(&self, now: f64) -> Result<(), String> {
        for (x, q) in self.queues.iter().enumerate() {
            for (w, s) in q.iter().enumerate() {
                if s.last != FOREVER && s.last < s.first {
                    return Err(format!("resource {x}: span {w} ends before it starts"));
                }
                // A span whose traversals are all done was not released: nobody behind it
                // would ever be granted the resource.
                let it = &self.its[s.robot as usize];
                if s.last != FOREVER && s.last < it.base {
                    return Err(format!(
                        "resource {x}: span {w} of robot {} ends at traversal {}, done before {}: {q:?}",
                        s.robot, s.last, it.base
                    ));
                }
                if s.last == FOREVER && w + 1 != q.len() {
                    return Err(format!(
                        "resource {x}: a span after one held for good: {q:?}"
                    ));
                }
            }
        }
        self.clone().retime(now).map_err(|c| {
            let mut dump = String::new();
            for (x, q) in self.queues.iter().enumerate() {
                if q.len() > 1 {
                    dump.push_str(&format!("\n  res {x}: {q:?}"));
                }
            }
            for (r, it) in self.its.iter().enumerate() {
                dump.push_str(&format!(
                    "\n  robot {r} base {} at {}: {:?}",
                    it.base,
                    it.at,
                    it.travs
                        .iter()
                        .map(|t| (t.seq, t.edge, t.start, t.end))
                        .collect::<Vec<_>>()
                ));
            }
            format!("cycle among robots {:?}{dump}", c.robots)
        })
    }
}

mod retime;
pub(super) use retime::HEADWAY;
#[cfg(test)]
mod tests;
