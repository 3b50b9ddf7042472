//! Safe and busy intervals computed from the schedule, kept while the resources they come
//! from do not change.

use super::*;

/// Intervals computed from the schedule, kept while the resources they come from do not
/// change (`Schedule::changed_since`): a saturated run makes thousands of plans between
/// changes of most of the building. Kept for everybody (robot [`ANYBODY`]) with the robots
/// that have spans there; for a robot among those (its own spans do not count), kept for
/// it alone. Every list lives in one arena, so that starting again frees no small vectors.
#[derive(Default)]
pub(super) struct Cache {
    /// The copy of the schedule they come from (`Schedule::lineage`).
    lineage: u64,
    /// Per (robot, edge, without soft spans): the others' merged busy intervals on the
    /// edge's traversal set.
    edge_busy: Map<(usize, usize, bool), Entry>,
    /// Per (robot, vertex, without soft spans): the safe intervals of its standing set.
    vertex_free: Map<(usize, usize, bool), Entry>,
    arena: Vec<(f64, f64)>,
    /// The robots of the entries for [`ANYBODY`], sorted.
    who: Vec<u32>,
    /// The busy intervals being merged (a buffer).
    tmp: Vec<(f64, f64)>,
    /// What `kept` answered for (robot, soft) at the schedule's stamp `memo_for`, per
    /// vertex and per edge, valid where its generation is `memo_gen`: one search asks for
    /// the same vertex and edge again and again, and the answer cannot change until the
    /// schedule does.
    memo_for: (u64, u64, usize, bool),
    memo_gen: u32,
    vertex_memo: Vec<(u32, (u32, u32))>,
    edge_memo: Vec<(u32, (u32, u32))>,
}

/// The robot of the entries kept for everybody: no robot's spans are left out.
const ANYBODY: usize = usize::MAX;

/// Intervals kept: where in `Cache::arena` (start, length), the stamp they were computed
/// at, and the last stamp they were found to hold at.
#[derive(Clone, Copy)]
struct Entry {
    at: (u32, u32),
    /// For [`ANYBODY`]: where in `Cache::who` the robots with spans there are.
    who: (u32, u32),
    made: u64,
    checked: u64,
}

/// Entries of `Cache::arena` (16 bytes each) after which it starts again.
const ARENA_MAX: usize = 1 << 20;

impl Cache {
    /// Ready for `sched`: emptied when it is another copy, or the arena is full.
    pub(super) fn follow(&mut self, sched: &Schedule) {
        if self.lineage != sched.lineage() || self.arena.len() > ARENA_MAX {
            self.lineage = sched.lineage();
            self.edge_busy.clear();
            self.vertex_free.clear();
            self.arena.clear();
            self.who.clear();
            self.forget();
        }
    }

    /// Drops every memo (their arena ranges may be gone, or the question changed).
    fn forget(&mut self) {
        self.memo_gen = self.memo_gen.wrapping_add(1);
        if self.memo_gen == 0 {
            // Wrapped: no memo of an old generation may pass for a new one.
            self.vertex_memo.iter_mut().for_each(|m| m.0 = 0);
            self.edge_memo.iter_mut().for_each(|m| m.0 = 0);
            self.memo_gen = 1;
        }
    }

    /// The memo slot of `kind`, for the question (`sched`'s lineage and stamp, robot and
    /// soft) `key`: emptied first when the last question was another.
    fn memo(&mut self, sched: &Schedule, key: (usize, bool), kind: Kind) -> &mut (u32, (u32, u32)) {
        let now = (sched.lineage(), sched.stamp(), key.0, key.1);
        if self.memo_for != now || self.memo_gen == 0 {
            self.memo_for = now;
            self.forget();
        }
        let conf = sched.conf();
        let (memo, id, len) = match kind {
            Kind::Vertex(v) => (&mut self.vertex_memo, v, conf.vertex.len()),
            Kind::Edge(e) => (&mut self.edge_memo, e, conf.trav.len()),
        };
        if memo.len() < len {
            memo.resize(len, (0, (0, 0)));
        }
        &mut memo[id]
    }

    pub(super) fn get(&self, (a, n): (u32, u32)) -> &[(f64, f64)] {
        &self.arena[a as usize..(a + n) as usize]
    }

    /// Whether robot `r` has no span in the kept entry `e` for [`ANYBODY`]: it holds for
    /// `r` too.
    fn not_held_by(&self, e: Entry, r: usize) -> bool {
        let (a, n) = e.who;
        self.who[a as usize..(a + n) as usize]
            .binary_search(&(r as u32))
            .is_err()
    }

    /// The robots with spans on the resources of `set`, sorted, appended to `who`.
    fn robots_of(&mut self, sched: &Schedule, set: &[Res]) -> (u32, u32) {
        let start = self.who.len();
        self.who
            .extend(set.iter().flat_map(|&x| sched.holders(x)).map(|r| r as u32));
        self.who[start..].sort_unstable();
        // Duplicates out of the new entry's part only.
        let mut w = start;
        for i in start..self.who.len() {
            if w == start || self.who[i] != self.who[w - 1] {
                self.who[w] = self.who[i];
                w += 1;
            }
        }
        self.who.truncate(w);
        (start as u32, (w - start) as u32)
    }

    /// The safe intervals of vertex `v` for robot `r`.
    pub(super) fn intervals(
        &mut self,
        sched: &Schedule,
        rs: (usize, bool),
        v: usize,
    ) -> (u32, u32) {
        self.kept(sched, rs, Kind::Vertex(v))
    }

    /// The others' merged busy intervals on edge `e`'s traversal set for robot `r`.
    pub(super) fn busy(&mut self, sched: &Schedule, rs: (usize, bool), e: usize) -> (u32, u32) {
        self.kept(sched, rs, Kind::Edge(e))
    }

    /// The intervals of `kind` for robot `r`: those kept for everybody unless `r` has
    /// spans there, else those kept for `r`; computed and kept when none hold.
    fn kept(&mut self, sched: &Schedule, rs: (usize, bool), kind: Kind) -> (u32, u32) {
        let &mut (g, at) = self.memo(sched, rs, kind);
        if g == self.memo_gen {
            #[cfg(debug_assertions)]
            self.check_kept(sched, rs, kind, at);
            return at;
        }
        let at = self.kept_anew(sched, rs, kind);
        let gen = self.memo_gen;
        *self.memo(sched, rs, kind) = (gen, at);
        at
    }

    /// `kept` without the memo.
    fn kept_anew(&mut self, sched: &Schedule, (r, soft): (usize, bool), kind: Kind) -> (u32, u32) {
        let (set, id) = match kind {
            Kind::Vertex(v) => (&sched.conf().vertex[v], v),
            Kind::Edge(e) => (&sched.conf().trav[e], e),
        };
        let shared = match still(self.map(kind), (ANYBODY, id, soft), sched, set) {
            Some(x) => x,
            None => {
                let at = self.compute(sched, set, ANYBODY, soft, kind);
                let who = self.robots_of(sched, set);
                let x = made(at, who, sched);
                self.map(kind).insert((ANYBODY, id, soft), x);
                x
            }
        };
        let at = if self.not_held_by(shared, r) {
            shared.at
        } else if let Some(x) = still(self.map(kind), (r, id, soft), sched, set) {
            x.at
        } else {
            let at = self.compute(sched, set, r, soft, kind);
            self.map(kind)
                .insert((r, id, soft), made(at, (0, 0), sched));
            return at;
        };
        #[cfg(debug_assertions)]
        self.check_kept(sched, (r, soft), kind, at);
        at
    }

    /// Debug builds: the intervals at `at` are those computed from scratch.
    #[cfg(debug_assertions)]
    fn check_kept(&self, sched: &Schedule, (r, soft): (usize, bool), kind: Kind, at: (u32, u32)) {
        let set = match kind {
            Kind::Vertex(v) => &sched.conf().vertex[v],
            Kind::Edge(e) => &sched.conf().trav[e],
        };
        let (mut busy, mut fresh) = (Vec::new(), Vec::new());
        merge_busy(sched, set, r, soft, &mut busy);
        match kind {
            Kind::Vertex(_) => gaps(&busy, &mut fresh),
            Kind::Edge(_) => fresh = busy,
        }
        assert_eq!(self.get(at), &fresh[..], "intervals kept of {kind:?}");
    }

    /// The kept entries of `kind`'s intervals.
    fn map(&mut self, kind: Kind) -> &mut Map<(usize, usize, bool), Entry> {
        match kind {
            Kind::Vertex(_) => &mut self.vertex_free,
            Kind::Edge(_) => &mut self.edge_busy,
        }
    }

    /// Computes the intervals of `kind` on `set` for robot `r` into the arena.
    fn compute(
        &mut self,
        sched: &Schedule,
        set: &[Res],
        r: usize,
        soft: bool,
        kind: Kind,
    ) -> (u32, u32) {
        merge_busy(sched, set, r, soft, &mut self.tmp);
        let start = self.arena.len();
        match kind {
            Kind::Vertex(_) => gaps(&self.tmp, &mut self.arena),
            Kind::Edge(_) => self.arena.extend_from_slice(&self.tmp),
        }
        (start as u32, (self.arena.len() - start) as u32)
    }
}

/// What intervals are kept of: the safe intervals of a vertex's standing set, or the
/// busy intervals of an edge's traversal set.
#[derive(Debug, Clone, Copy)]
enum Kind {
    Vertex(usize),
    Edge(usize),
}

/// The gaps between sorted disjoint `busy` intervals, appended to `out`.
fn gaps(busy: &[(f64, f64)], out: &mut Vec<(f64, f64)>) {
    let mut from = f64::NEG_INFINITY;
    for &(a, b) in busy {
        if a > from {
            out.push((from, a));
        }
        from = b;
    }
    if from < f64::INFINITY {
        out.push((from, f64::INFINITY));
    }
}

fn made(at: (u32, u32), who: (u32, u32), sched: &Schedule) -> Entry {
    Entry {
        at,
        who,
        made: sched.stamp(),
        checked: sched.stamp(),
    }
}

/// The entry kept for `key` if none of `set` changed since it was computed.
fn still(
    map: &mut Map<(usize, usize, bool), Entry>,
    key: (usize, usize, bool),
    sched: &Schedule,
    set: &[Res],
) -> Option<Entry> {
    let e = map.get_mut(&key)?;
    if e.checked != sched.stamp() {
        if sched.changed_since(set, e.made) {
            return None;
        }
        e.checked = sched.stamp();
    }
    Some(*e)
}

/// The merged busy intervals of `set` for anybody but robot `r` (without soft spans when
/// `soft`), sorted, into `out`.
fn merge_busy(sched: &Schedule, set: &[Res], r: usize, soft: bool, out: &mut Vec<(f64, f64)>) {
    out.clear();
    out.extend(set.iter().flat_map(|&x| sched.busy(x, r, soft)));
    // Unstable: the union does not depend on the order of equal starts.
    out.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    // Merged in place: `w` intervals kept so far.
    let mut w = 0;
    for i in 0..out.len() {
        let (a, b) = out[i];
        if b <= a {
            continue;
        }
        if w > 0 && a <= out[w - 1].1 {
            out[w - 1].1 = out[w - 1].1.max(b);
        } else {
            out[w] = (a, b);
            w += 1;
        }
    }
    out.truncate(w);
}
