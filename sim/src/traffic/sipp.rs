//! Safe Interval Path Planning (Phillips & Likhachev, ICRA 2011) against the shared
//! schedule: A* over (vertex, safe interval, goals reached) in continuous time, waiting only
//! where another robot's span makes it necessary.
//!
//! A plan visits its goals in order (staying at each for its dwell) and ends where the
//! robot may stay for good: a parking vertex whose standing set nobody needs after the
//! robot arrives. So every plan leaves the robot where it blocks nobody's plan.
//!
//! Complete for the schedule as it is: if the robot can reach its goals and a free parking
//! vertex by any timing of waits and moves that keeps clear of the others' spans, the search
//! finds the earliest such arrival (within `MAX_EXPANSIONS`).

use super::conflicts::Res;
use super::parks::{PARK, PARK_ON_PLACE};
use super::schedule::{Schedule, Step, HEADWAY};
use crate::graph::{EdgeKind, Nav, DOOR_COST};
use cache::Cache;
use edge_times::EdgeTimes;
use kinematics::heading;
pub use kinematics::Kinematics;
use std::cmp::Ordering;
use std::collections::hash_map::Entry as Slot;
use std::collections::BinaryHeap;

/// The search's maps are keyed by small integers and never iterated: a fast fixed hasher
/// keeps them deterministic and cheap.
type Map<K, V> = std::collections::HashMap<K, V, foldhash::fast::FixedState>;

/// Bound on the search (states expanded) of one plan.
const MAX_EXPANSIONS: usize = 200_000;
/// Distance tables to goals kept between plans (each a float per vertex): at least this
/// many, and as many as fit in `GOAL_TABLE_FLOATS` (a warehouse has a thousand racks, and
/// dropping them all each time 512 were kept made tables again and again).
const GOAL_TABLES: usize = 512;
const GOAL_TABLE_FLOATS: usize = 16 << 20;
/// Extra cost (s) of ending on a parking vertex that is a task place: another robot's task
/// may need it (and send the robot parked there away).
const PLACE_PENALTY: f64 = 60.0;

/// Settling at a waypoint (s): the slotcar stops within its tolerance, then reports.
const STOP_S: f64 = 0.5;

/// What to plan.
pub struct Query<'a> {
    pub robot: usize,
    pub slot: usize,
    pub kin: Kinematics,
    /// Where the robot is (or will be), and from when it may leave.
    pub from: usize,
    pub t0: f64,
    /// Goals in order, each with how long the robot stays there (s).
    pub goals: &'a [(usize, f64)],
    /// Per vertex: where the robot may stay for good (`parks::PARK`, or `PARK_ON_PLACE`
    /// at a cost of `PLACE_PENALTY`), 0 elsewhere.
    pub parks: &'a [u8],
    /// A vertex where the plan may end, at no penalty, even if it is not a parking vertex:
    /// the place a robot was sent to (it stays there, as after RMF's go-to-place; when it is
    /// in somebody's way later, it is sent on to a parking vertex).
    pub stay: Option<usize>,
    /// Plan through the others' soft spans (their ways to parking while their tasks go
    /// on: see `schedule`), but not to stay for good where one is.
    pub soft: bool,
    /// How late the plan may reach its last place (see [`Delay`]); None: any time.
    pub delay: Option<Delay>,
}

/// A bound on how late a plan reaches its last place: by `t0 + F + fixed + share · F`,
/// where F is its free-flow time there (the search's lower bound, dwells included). The
/// search keeps to it: it does not look at states that cannot arrive in time, so a task
/// that cannot be served soon costs only the states that could (searched to their end and
/// refused after, such plans were half of the saturated airport's searching).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Delay {
    pub fixed: f64,
    pub share: f64,
}

/// A plan: its steps, and after how many steps each goal is reached.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    pub steps: Vec<Step>,
    pub goal_at: Vec<usize>,
    /// When the robot is at its last vertex for good.
    pub done: f64,
    /// States expanded.
    pub expanded: usize,
}

#[derive(Clone, Copy)]
struct Node {
    v: usize,
    iv: usize,
    label: usize,
    /// When the robot is at `v` ready to leave (after a goal's dwell).
    t: f64,
    parent: usize,
    /// The edge driven to get here (None: a goal reached at `v`), its start and end.
    edge: Option<(usize, f64, f64)>,
    /// The end: the robot stays at `v` for good (its cost counts the parking's penalty).
    end: bool,
}

#[derive(PartialEq)]
struct Open(f64, f64, usize);
impl Eq for Open {}
impl Ord for Open {
    fn cmp(&self, o: &Self) -> Ordering {
        // Smallest f, then largest g (deeper first), then oldest node.
        o.0.total_cmp(&self.0)
            .then(self.1.total_cmp(&o.1))
            .then(o.2.cmp(&self.2))
    }
}
impl PartialOrd for Open {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// A search's buffers, kept between searches (cleared, not freed: a saturated run makes
/// tens of thousands of searches).
#[derive(Default)]
struct Scratch {
    nodes: Vec<Node>,
    best: Map<(usize, usize, usize), f64>,
    open: BinaryHeap<Open>,
}

/// Reverse graphs and heuristic tables, reused across plans.
pub struct Planner {
    /// Per slot, per vertex: incoming edges.
    inn: Vec<Vec<Vec<usize>>>,
    /// Edge times per kinematics met so far (a fleet's robots share theirs).
    edge_times: Vec<EdgeTimes>,
    /// Time to the nearest free parking vertex, per (slot, speed and acceleration bits,
    /// whether places count, whether busy robots' parks count: soft plans), repaired as
    /// parks are taken and left.
    park_dist: Map<(usize, (u64, u64), bool, bool), nearest::Nearest>,
    /// Time to a goal, per (slot, speed and acceleration bits, goal vertex): tasks go to
    /// the same places again and again.
    goal_dist: Map<(usize, (u64, u64), usize), Vec<f64>>,
    /// Busy and safe intervals computed from the schedule: the plans of one dispatch round
    /// (several robots per task, most refused) meet the same ones, and so do the next
    /// rounds' where the schedule did not change.
    cache: Cache,
    scratch: Scratch,
    /// Plans made, plans that found no way, and states expanded, for the report.
    pub plans: u64,
    pub failed: u64,
    pub expanded: u64,
    /// Why the last plan failed (for debugging).
    pub why: &'static str,
    /// The last plan failed for its [`Delay`]: ways later than it were not searched.
    pub late: bool,
    /// The last search may have failed for want of ends: it got past the last place, or
    /// could not tell. A search that did not fails the same way with more ends.
    ends_mattered: bool,
    /// When set, the wall-clock time (s) of every plan, for benchmarks.
    pub times: Option<Vec<f64>>,
}

impl Planner {
    pub fn new(nav: &Nav) -> Planner {
        let inn = (0..nav.graphs.len())
            .map(|slot| {
                let mut inn = vec![Vec::new(); nav.vertices.len()];
                for (i, e) in nav.edges.iter().enumerate() {
                    if e.graph == slot {
                        inn[e.to].push(i);
                    }
                }
                inn
            })
            .collect();
        Planner {
            inn,
            edge_times: Vec::new(),
            park_dist: Map::default(),
            goal_dist: Map::default(),
            cache: Cache::default(),
            scratch: Scratch::default(),
            plans: 0,
            failed: 0,
            expanded: 0,
            why: "",
            late: false,
            ends_mattered: false,
            times: None,
        }
    }

    /// Where in `edge_times` those of `kin` are (made when first asked).
    fn times_for(&mut self, nav: &Nav, kin: Kinematics) -> usize {
        let same = |k: &Kinematics| {
            (k.speed.to_bits(), k.accel.to_bits(), k.turn.to_bits())
                == (kin.speed.to_bits(), kin.accel.to_bits(), kin.turn.to_bits())
        };
        match self.edge_times.iter().position(|t| same(&t.kin)) {
            Some(i) => i,
            None => {
                self.edge_times.push(EdgeTimes::new(nav, kin));
                self.edge_times.len() - 1
            }
        }
    }

    /// Travel times to the nearest of `targets` from every vertex (reverse Dijkstra).
    fn dist_to(&self, slot: usize, et: &EdgeTimes, targets: &[usize]) -> Vec<f64> {
        let mut d = vec![f64::INFINITY; self.inn[slot].len()];
        let mut heap = BinaryHeap::new();
        for &g in targets {
            d[g] = 0.0;
            heap.push(Open(0.0, 0.0, g));
        }
        while let Some(Open(c, _, v)) = heap.pop() {
            if c > d[v] {
                continue;
            }
            for &e in &self.inn[slot][v] {
                let u = et.from[e];
                let nc = c + et.bound(e);
                if nc < d[u] {
                    d[u] = nc;
                    heap.push(Open(nc, 0.0, u));
                }
            }
        }
        d
    }

    /// The earliest plan for `q` against `sched` (ignoring the robot's own spans), or None.
    /// It ends on a parking vertex off the task places if it can, else on a place that may
    /// be parked on (a robot there blocks the tasks going there until it is sent away).
    pub fn plan(&mut self, nav: &Nav, sched: &Schedule, q: &Query) -> Option<Plan> {
        self.plans += 1;
        self.late = false;
        let started = self.times.is_some().then(std::time::Instant::now);
        let plan = self.search(nav, sched, q, false).or_else(|| {
            // Places as ends too: they matter only to a search that got past its last
            // place. One stopped before (by its delay bound, or by the others' spans) stops
            // at the same states with more ends: its states before the last place, the
            // bound on them and their order do not depend on the ends (half of the
            // saturated airport's searches were such second ones).
            let any_place = q.parks.contains(&PARK_ON_PLACE);
            if any_place && self.ends_mattered {
                self.search(nav, sched, q, true)
            } else {
                None
            }
        });
        if let (Some(t), Some(times)) = (started, self.times.as_mut()) {
            times.push(t.elapsed().as_secs_f64());
        }
        self.failed += u64::from(plan.is_none());
        plan
    }

    /// [`Planner::plan`], ending on places only when `places`.
    fn search(&mut self, nav: &Nav, sched: &Schedule, q: &Query, places: bool) -> Option<Plan> {
        self.cache.follow(sched);
        let mut cache = std::mem::take(&mut self.cache);
        let mut scratch = std::mem::take(&mut self.scratch);
        scratch.nodes.clear();
        scratch.best.clear();
        scratch.open.clear();
        let plan = self.search_with(nav, sched, q, places, &mut cache, &mut scratch);
        self.cache = cache;
        self.scratch = scratch;
        plan
    }

    fn search_with(
        &mut self,
        nav: &Nav,
        sched: &Schedule,
        q: &Query,
        places: bool,
        cache: &mut Cache,
        scratch: &mut Scratch,
    ) -> Option<Plan> {
        let conf = sched.conf();
        self.ends_mattered = true;
        // The parking vertices the plan may end on: those nobody else stays on for good
        // (a heuristic towards taken ones sends the search round every vertex of a large
        // building before it gives up on them). Those nobody stays on are the same for
        // every robot: their table of times is repaired from the last plan's set as robots
        // park and leave. The robot's own (where it stays for good itself) are added to a
        // copy, searched from only as far as they are nearer than the others. (Repaired
        // for each robot's set, which has its own park in it, the shared table cost a
        // tenth of the saturated airport.)
        let mut common = Vec::new();
        let mut own = Vec::new();
        // Through the others' soft spans, also the parks robots at work would go to after
        // their tasks: such a robot plans its way to parking again behind this plan, to
        // the park this one leaves or another (`Schedule::install` returns it as jumped).
        // Else, with every park held, a robot at work could only go back to its own: on
        // a full warehouse, every task ended with a drive back across the aisles.
        let claim = q.soft;
        for v in 0..nav.vertices.len() {
            if !(q.parks[v] == PARK || places && q.parks[v] == PARK_ON_PLACE) {
                continue;
            }
            let (mut mine, mut other) = (false, false);
            for &x in &conf.vertex[v] {
                match sched.held_for_good(x, usize::MAX, claim) {
                    Some(h) if h == q.robot => mine = true,
                    Some(_) => other = true,
                    None => {}
                }
            }
            match (mine, other) {
                (_, true) => {}
                (true, false) => own.push(v),
                (false, false) => common.push(v),
            }
        }
        let ti = self.times_for(nav, q.kin);
        let et = &self.edge_times[ti];
        // Tables are shared by the kinematics whose bounds are the same: the same top speed
        // and acceleration (the turning speed does not count in a bound).
        let drive = (q.kin.speed.to_bits(), q.kin.accel.to_bits());
        let key = (q.slot, drive, places, claim);
        self.park_dist
            .entry(key)
            .or_insert_with(|| nearest::Nearest::new(nav.vertices.len()))
            .update(&self.inn[q.slot], &nav.out[q.slot], et, &common);
        let nl = q.goals.len();
        // Bounded memory (`GOAL_TABLES`): dropped all at once when full.
        let most = GOAL_TABLES.max(GOAL_TABLE_FLOATS / nav.vertices.len().max(1));
        if self.goal_dist.len() + nl + 1 > most {
            self.goal_dist.clear();
        }
        for g in q.goals.iter().map(|g| g.0).chain(q.stay) {
            let gk = (q.slot, drive, g);
            if !self.goal_dist.contains_key(&gk) {
                let d = self.dist_to(q.slot, et, &[g]);
                self.goal_dist.insert(gk, d);
            }
        }
        let park_dist = &self.park_dist[&key].d;
        let table = |g: usize| &self.goal_dist[&(q.slot, drive, g)];
        // h(v, label): to the goal of `label`, then through the rest, then to a park.
        let dist: Vec<&Vec<f64>> = q.goals.iter().map(|&(g, _)| table(g)).collect();
        // After the last goal: to a parking vertex, or back to where the robot may stay.
        // (The nearest of a union is the least of the nearest of each: the same sums.)
        let end_dist: std::borrow::Cow<[f64]> = if own.is_empty() && q.stay.is_none() {
            std::borrow::Cow::Borrowed(park_dist)
        } else {
            let mut d = park_dist.clone();
            nearer(&self.inn[q.slot], et, &own, &mut d);
            if let Some(st) = q.stay {
                for (a, b) in d.iter_mut().zip(table(st)) {
                    *a = a.min(*b);
                }
            }
            std::borrow::Cow::Owned(d)
        };
        debug_assert!(
            {
                let mut all = common.clone();
                all.extend(&own);
                all.extend(q.stay);
                end_dist
                    .iter()
                    .zip(&self.dist_to(q.slot, et, &all))
                    .all(|(a, b)| a.to_bits() == b.to_bits())
            },
            "times to parking differ from those computed at once"
        );
        // Time from label `l`'s goal to arriving at the last place (its dwell there not
        // counted): the delay bound's measure, the same whatever the plan may end on.
        let mut goals_rest = vec![0.0; nl + 1];
        for l in (0..nl.saturating_sub(1)).rev() {
            let (g, dwell) = q.goals[l];
            goals_rest[l] = dwell + dist[l + 1][g] + goals_rest[l + 1];
        }
        let to_last = |v: usize, label: usize| dist[label][v] + goals_rest[label];
        let mut rest = vec![0.0; nl + 1];
        for l in (0..nl).rev() {
            let (g, dwell) = q.goals[l];
            let next = if l + 1 < nl {
                dist[l + 1][g]
            } else {
                end_dist[g]
            };
            rest[l] = dwell + next + rest[l + 1];
        }
        let h = |v: usize, label: usize| -> f64 {
            if label < nl {
                dist[label][v] + rest[label]
            } else {
                end_dist[v]
            }
        };
        if !h(q.from, 0).is_finite() {
            self.why = "unreachable";
            return None;
        }
        // The latest a state may reach the last place at (its dwell there done).
        let deadline = match (q.delay, nl) {
            (Some(d), 1..) => {
                let free = to_last(q.from, 0);
                q.t0 + free + d.fixed + d.share * free
            }
            _ => f64::INFINITY,
        };
        let mut late = false;
        let r = q.robot;
        let rs = (r, q.soft);
        let iv0 = cache.intervals(sched, rs, q.from);
        let Some(i0) = cache
            .get(iv0)
            .iter()
            .position(|&(a, b)| a <= q.t0 && q.t0 < b)
        else {
            self.why = "start busy";
            self.ends_mattered = false;
            return None;
        };
        let Scratch { nodes, best, open } = scratch;
        nodes.push(Node {
            v: q.from,
            iv: i0,
            label: 0,
            t: q.t0,
            parent: usize::MAX,
            edge: None,
            end: false,
        });
        open.push(Open(q.t0 + h(q.from, 0), q.t0, 0));
        let mut expanded = 0usize;
        self.ends_mattered = nl == 0;
        while let Some(Open(_, _, id)) = open.pop() {
            let n = nodes[id];
            if best.get(&(n.v, n.iv, n.label)).is_some_and(|&t| t < n.t) {
                continue;
            }
            if n.end {
                self.expanded += expanded as u64;
                let mut plan = unwind(nav, nodes, n.parent, nl, expanded);
                wait_early(sched, q, &mut plan, cache);
                return Some(plan);
            }
            let at = cache.intervals(sched, rs, n.v);
            let (_, hi) = cache.get(at)[n.iv];
            let may_stay = q.stay == Some(n.v)
                || q.parks[n.v] == PARK
                || (places && q.parks[n.v] == PARK_ON_PLACE);
            // Not for good where another robot's soft way to parking passes: it could not
            // be planned behind a stay for good. (Where it ends, it can: see `claim`.)
            let soft_here = || q.soft && conf.vertex[n.v].iter().any(|&x| sched.soft_passing(x, r));
            if n.label == nl && may_stay && hi == f64::INFINITY && !soft_here() {
                // Staying here for good: a candidate end, ranked with its penalty.
                let pen = if q.parks[n.v] == PARK_ON_PLACE && q.stay != Some(n.v) {
                    PLACE_PENALTY
                } else {
                    0.0
                };
                nodes.push(Node {
                    parent: id,
                    end: true,
                    ..n
                });
                open.push(Open(n.t + pen, n.t, nodes.len() - 1));
            }
            expanded += 1;
            if expanded > MAX_EXPANSIONS {
                break;
            }
            let mut push = |node: Node, nodes: &mut Vec<Node>, open: &mut BinaryHeap<Open>| {
                // One probe of the map for the look-up and the insert.
                let slot = best.entry((node.v, node.iv, node.label));
                if let Slot::Occupied(o) = &slot {
                    if *o.get() <= node.t {
                        return;
                    }
                }
                let hv = h(node.v, node.label);
                if !hv.is_finite() {
                    return;
                }
                if node.label < nl && node.t + to_last(node.v, node.label) > deadline {
                    late = true;
                    return;
                }
                slot.insert_entry(node.t);
                nodes.push(node);
                open.push(Open(node.t + hv, node.t, nodes.len() - 1));
            };
            // A goal reached: stay for its dwell.
            if n.label < nl && q.goals[n.label].0 == n.v {
                let t = n.t + q.goals[n.label].1;
                if t < hi {
                    self.ends_mattered |= n.label + 1 == nl;
                    push(
                        Node {
                            label: n.label + 1,
                            t,
                            parent: id,
                            edge: None,
                            end: false,
                            ..n
                        },
                        nodes,
                        open,
                    );
                }
            }
            for &e in &nav.out[q.slot][n.v] {
                let w = et.to[e];
                let prev = n.edge.map(|(p, _, _)| p);
                let dur = et.time(e, prev);
                debug_assert_eq!(
                    dur.to_bits(),
                    q.kin
                        .edge_time_with(nav, e, prev, |x| heading(nav, x))
                        .to_bits()
                );

                let busy_at = cache.busy(sched, rs, e);
                let wi_at = cache.intervals(sched, rs, w);
                let (busy, wivs) = (cache.get(busy_at), cache.get(wi_at));
                // Each gap of the edge's resources wide enough, left while still in this
                // vertex's safe interval; the first arrival in each of w's intervals.
                let mut from = n.t;
                let mut k = busy.partition_point(|&(_, b)| b <= from);
                loop {
                    let gap_end = busy.get(k).map_or(f64::INFINITY, |&(a, _)| a);
                    let d = from;
                    if d >= hi {
                        break;
                    }
                    if gap_end - d >= dur {
                        let a = d + dur;
                        if let Some(wi) = wivs.iter().position(|&(lo, up)| lo <= a && a < up) {
                            push(
                                Node {
                                    v: w,
                                    iv: wi,
                                    label: n.label,
                                    t: a,
                                    parent: id,
                                    edge: Some((e, d, a)),
                                    end: false,
                                },
                                nodes,
                                open,
                            );
                        }
                    }
                    let Some(&(_, b)) = busy.get(k) else { break };
                    // Behind another robot, as the schedule's retime would put it: the plan
                    // holds its times when installed, and those behind it keep their slack.
                    from = b + HEADWAY;
                    k += 1;
                }
            }
        }
        self.expanded += expanded as u64;
        self.ends_mattered |= expanded > MAX_EXPANSIONS;
        self.why = if expanded > MAX_EXPANSIONS {
            "search bound"
        } else if late && !blocked(nav, sched, q, &dist, &end_dist) {
            self.late = true;
            "late"
        } else {
            "no way"
        };
        None
    }
}

/// Lowers the times `d` (to the nearest of some targets) to those to the nearest of
/// `targets` too: a reverse search from them that goes only where they are nearer. Where
/// they are not, neither are they beyond (`d` is already a fixpoint of its edges).
fn nearer(inn: &[Vec<usize>], et: &EdgeTimes, targets: &[usize], d: &mut [f64]) {
    let mut heap = BinaryHeap::new();
    for &t in targets {
        if d[t] > 0.0 {
            d[t] = 0.0;
            heap.push(Open(0.0, 0.0, t));
        }
    }
    while let Some(Open(c, _, v)) = heap.pop() {
        if c > d[v] {
            continue;
        }
        for &e in &inn[v] {
            let u = et.from[e];
            let nc = c + et.bound(e);
            if nc < d[u] {
                d[u] = nc;
                heap.push(Open(nc, 0.0, u));
            }
        }
    }
}

/// Whether other robots' stays for good cut every way to one of `q`'s goals (in order),
/// or from the last to anywhere the robot may stay, whatever the timing. A search cut by
/// its [`Delay`] then failed for that, not for the cut: no later plan exists either, and
/// the robot staying in the way must make room (a robot held up by one for good was
/// otherwise refused as late, again and again, and never had it moved).
///
/// Best first by the free-flow times to each target (`to_goal`, then `to_end`): the same
/// answer as any search of the reachable vertices, found in a few steps when the way is
/// open (it runs after every search the cut stopped).
fn blocked(nav: &Nav, sched: &Schedule, q: &Query, to_goal: &[&Vec<f64>], to_end: &[f64]) -> bool {
    let conf = sched.conf();
    let open = |set: &[Res]| {
        set.iter()
            .all(|&x| sched.held_for_good(x, q.robot, q.soft).is_none())
    };
    let mut seen = vec![false; nav.vertices.len()];
    let mut heap = BinaryHeap::new();
    let mut reach = |from: usize, by: &[f64], to: &dyn Fn(usize) -> bool| {
        seen.fill(false);
        seen[from] = true;
        heap.clear();
        heap.push(Open(by[from], 0.0, from));
        while let Some(Open(_, _, v)) = heap.pop() {
            if to(v) {
                return true;
            }
            for &e in &nav.out[q.slot][v] {
                let w = nav.edges[e].to;
                if !seen[w] && open(&conf.trav[e]) && open(&conf.vertex[w]) {
                    seen[w] = true;
                    heap.push(Open(by[w], 0.0, w));
                }
            }
        }
        false
    };
    let mut at = q.from;
    for (&(g, _), by) in q.goals.iter().zip(to_goal) {
        if !reach(at, by, &|v| v == g) {
            return true;
        }
        at = g;
    }
    let may_stay = |v: usize| q.stay == Some(v) || q.parks[v] != 0;
    !reach(at, to_end, &may_stay)
}

/// Moves each leg's waits (from a place to the next, and to the parking vertex) to its
/// start, where they keep the same arrival: the robot waits where it stands or works (a
/// parking vertex, a task place) rather than in a corridor, and leaves when its way is
/// clear. A traversal is only delayed into a gap of the others' spans that fits it, while
/// the robot may still stand where it starts.
///
/// Not the way to parking after a task's last place: waiting early there would keep the
/// robot standing on a task place, in the way of the next tasks, when it could wait for
/// its parking vertex further on.
fn wait_early(sched: &Schedule, q: &Query, plan: &mut Plan, cache: &mut Cache) {
    let rs = (q.robot, q.soft);
    let mut bounds = plan.goal_at.clone();
    if q.goals.is_empty() {
        bounds.push(plan.steps.len());
    }
    let mut l0 = 0;
    for &l1 in &bounds {
        for k in (l0..l1.saturating_sub(1)).rev() {
            let latest_end = plan.steps[k + 1].start;
            let st = &plan.steps[k];
            if latest_end <= st.end + 1e-9 {
                continue;
            }
            let start = latest_end - st.dur;
            let (busy, free) = (
                cache.busy(sched, rs, st.edge),
                cache.intervals(sched, rs, st.from),
            );
            let clear = cache
                .get(busy)
                .iter()
                .all(|&(a, b)| b <= start || a >= latest_end);
            let stays = cache
                .get(free)
                .iter()
                .any(|&(a, b)| a <= st.start && start <= b);
            if clear && stays {
                let st = &mut plan.steps[k];
                st.start = start;
                st.end = latest_end;
            }
        }
        l0 = l1;
    }
}

fn unwind(nav: &Nav, nodes: &[Node], mut id: usize, nl: usize, expanded: usize) -> Plan {
    let done = nodes[id].t;
    let mut chain = Vec::new();
    while id != usize::MAX {
        chain.push(id);
        id = nodes[id].parent;
    }
    chain.reverse();
    let mut steps: Vec<Step> = Vec::new();
    let mut goal_at = Vec::with_capacity(nl);
    let mut hold = 0.0;
    for w in chain.windows(2) {
        let (p, n) = (&nodes[w[0]], &nodes[w[1]]);
        match n.edge {
            None => {
                goal_at.push(steps.len());
                hold = n.t - p.t;
            }
            Some((e, d, a)) => {
                let edge = &nav.edges[e];
                steps.push(Step {
                    edge: e,
                    from: edge.from,
                    to: edge.to,
                    dur: a - d,
                    hold,
                    start: d,
                    end: a,
                });
                hold = 0.0;
            }
        }
    }
    Plan {
        steps,
        goal_at,
        done,
        expanded,
    }
}

mod cache;
mod edge_times;
mod kinematics;
mod nearest;
#[cfg(test)]
mod tests;
