//! Parking: the vertices where a robot may stand for good, chosen so that the building
//! stays *well-formed* (Ma et al., AAMAS 2017): with a robot standing on every parking
//! vertex at once, every other vertex the graphs connect is still connected (both ways, on
//! every graph, across fleets: standing sets are geometric), and every parking vertex can
//! still be left and reached. Then a robot can always wait at its parking vertex until the
//! others' finite plans are done and drive on: planning never fails for want of room.
//!
//! Not parking vertices: where a lift would carry a robot (its cabins, and around a rotated
//! cabin some vertices just outside), and vertices whose standing set reaches a task
//! waypoint, a charger or a spawn point (a robot there would be in their way). Chargers and
//! spawn points themselves are parking vertices, taken after the others (a robot parked on
//! a charger is sent elsewhere when another comes to charge, as RMF robots park at their
//! chargers); task waypoints are parking vertices of a second kind, taken only when the
//! others are too few: a plan ending there holds the place, and is sent elsewhere when a
//! task needs it.

use super::conflicts::{Conflicts, Res};
use crate::graph::Nav;
use petgraph::algo::tarjan_scc;
use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::visit::{EdgeFiltered, EdgeRef};

mod around;
mod through;

pub use around::out_of_the_way;

/// Per graph slot, per vertex: 0 not a parking vertex, [`PARK`], [`PARK_ON_PLACE`] or
/// [`PARK_HOME`].
#[derive(Debug, Clone, Default)]
pub struct Parks {
    pub per_slot: Vec<Vec<u8>>,
}

/// A parking vertex off every task place.
pub const PARK: u8 = 1;
/// A task place where a robot may also park (it cuts nothing), when the building has too
/// few others: a robot parked there is sent elsewhere when a task needs the place.
pub const PARK_ON_PLACE: u8 = 2;
/// A vertex asked for by name ([`Needs::homes`]: a robot's own charger or parking spot, or
/// a place where a robot may stay after its task) that keeps the building well-formed like
/// any parking vertex. Not in the common pool: only the robots it was asked for end their
/// plans there.
pub const PARK_HOME: u8 = 3;

/// Vertices a graph must keep reachable, and vertices that must not be parked on.
pub struct Needs<'a> {
    /// Per slot, per vertex: task waypoints, chargers, spawn points (not parking vertices,
    /// nor in a parking vertex's standing set).
    pub required: &'a [Vec<bool>],
    /// Per slot, per vertex: task waypoints, chargers and spawn points, which may still be
    /// parking vertices when there are too few others (chosen after them).
    pub places: &'a [Vec<bool>],
    /// Per slot, per vertex: the task waypoints among `places`: parking there is of the
    /// second kind ([`PARK_ON_PLACE`]); a charger or spawn point no task names is a
    /// [`PARK`] (a robot parked there is sent elsewhere when one comes to charge).
    pub tasks: &'a [Vec<bool>],
    /// Per slot: the legs tasks drive (from one place to the next, in a task's order),
    /// whose routes parks should keep clear of; empty: every place to every other.
    pub legs: &'a [Vec<(usize, usize)>],
    /// At most this many parking vertices per slot (enough for the robots and spares).
    pub want: &'a [usize],
    /// (slot, vertex) asked for as [`PARK_HOME`]s, tried in this order before the slot's
    /// other candidates (not counted in `want`). Empty for scenarios without fleet adapter
    /// configs: then the choice is exactly as without them.
    pub homes: &'a [(usize, usize)],
}

/// Undirected neighbours and the edges into each vertex, of one slot.
struct Slot {
    s: usize,
    nbrs: Vec<Vec<usize>>,
    /// Per vertex: the slot's edges that end there.
    inn: Vec<Vec<usize>>,
    /// The slot's edges as a directed graph over all vertices (weights: edge indices).
    graph: DiGraph<(), usize>,
}

/// The directed graph of slot `s`'s edges, one node per vertex of `nav`.
fn digraph(nav: &Nav, s: usize) -> DiGraph<(), usize> {
    let mut g = DiGraph::with_capacity(nav.vertices.len(), nav.edges.len());
    for _ in &nav.vertices {
        g.add_node(());
    }
    for (i, e) in nav.edges.iter().enumerate() {
        if e.graph == s {
            g.add_edge(NodeIndex::new(e.from), NodeIndex::new(e.to), i);
        }
    }
    g
}

/// Chooses the parking vertices (see the module doc). Greedy in order of preference:
/// parking spots, holding points, dead ends (leaves), then other vertices, and within each
/// where the fewest shortest routes between places pass (`through`, with the parks taken
/// so far in the way), not in the map's order (which put parks beside a warehouse's
/// stations, on every route to them); a candidate is taken when the graphs stay connected
/// with it taken too. Deterministic.
pub fn choose(nav: &Nav, conf: &Conflicts, needs: &Needs) -> Parks {
    let nv = nav.vertices.len();
    let slots: Vec<Slot> = (0..nav.graphs.len())
        .map(|s| {
            let mut nbrs = vec![Vec::new(); nv];
            let mut inn = vec![Vec::new(); nv];
            for (i, e) in nav.edges.iter().enumerate() {
                if e.graph == s {
                    nbrs[e.from].push(e.to);
                    nbrs[e.to].push(e.from);
                    inn[e.to].push(i);
                }
            }
            for n in &mut nbrs {
                n.sort_unstable();
                n.dedup();
            }
            Slot {
                s,
                nbrs,
                inn,
                graph: digraph(nav, s),
            }
        })
        .collect();
    // Per resource: the edges whose traversal needs it.
    let mut users: Vec<Vec<usize>> = vec![Vec::new(); conf.n_res];
    for (e, set) in conf.trav.iter().enumerate() {
        for &x in set {
            users[x as usize].push(e);
        }
    }
    // Per resource: the vertices whose standing set holds it.
    let mut standers: Vec<Vec<usize>> = vec![Vec::new(); conf.n_res];
    for (v, set) in conf.vertex.iter().enumerate() {
        for &x in set {
            standers[x as usize].push(v);
        }
    }
    let required = |s: usize, v: usize| {
        needs
            .required
            .get(s)
            .and_then(|r| r.get(v))
            .copied()
            .unwrap_or(false)
    };
    // Per slot: its strongly connected parts, which must stay connected.
    let full_block = vec![false; nav.edges.len()];
    let gone = vec![false; nv];
    let main: Vec<Vec<usize>> = (0..slots.len())
        .map(|s| parts(nav, &slots[s], &full_block, &gone))
        .collect();

    let mut parks = Parks {
        per_slot: vec![vec![0; nv]; slots.len()],
    };
    let mut blocked = vec![false; nav.edges.len()];
    // Vertices that cannot be used while the parks are taken (in a park's standing set).
    let mut absorbed = vec![false; nv];
    let mut held: Vec<bool> = vec![false; conf.n_res];
    let mut taken_parks: Vec<usize> = Vec::new();
    for s in 0..slots.len() {
        let want = needs.want.get(s).copied().unwrap_or(0);
        let place = |v: usize| {
            needs
                .places
                .get(s)
                .and_then(|r| r.get(v))
                .copied()
                .unwrap_or(false)
        };
        // Only in the largest strongly connected part: a robot parked past a one-way lane
        // could never come back to the places it is sent to.
        let mut size: std::collections::BTreeMap<usize, usize> = Default::default();
        for &v in &nav.members[s] {
            if main[s][v] != usize::MAX {
                *size.entry(main[s][v]).or_insert(0) += 1;
            }
        }
        let biggest = size
            .iter()
            .max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(a.0)))
            .map(|(&id, _)| id);
        let mut cands: Vec<usize> = nav.members[s]
            .iter()
            .copied()
            .filter(|&v| Some(main[s][v]) == biggest && nav.vertices[v].lift.is_none())
            .filter(|&v| !required(s, v) || place(v))
            .collect();
        let class = |v: usize| {
            let r = &nav.vertices[v].roles;
            if r.is_parking_spot {
                0
            } else if r.is_holding_point {
                1
            } else if slots[s].nbrs[v].len() <= 1 {
                2
            } else {
                3 + slots[s].nbrs[v].len()
            }
        };
        let task = |v: usize| {
            needs
                .tasks
                .get(s)
                .and_then(|r| r.get(v))
                .copied()
                .unwrap_or(false)
        };
        // Chargers and spawn points after the others, task places last, and only as many
        // as still wanted; within a class, where the least traffic between places passes
        // first (`through`), scored again as parks are taken (they send traffic round).
        let key = |v: usize| (task(v), place(v), class(v));
        cands.sort_by_key(|&v| (key(v), v));
        let targets: Vec<usize> = nav.members[s]
            .iter()
            .copied()
            .filter(|&v| required(s, v))
            .collect();
        let n_edges = nav.members[s]
            .iter()
            .map(|&v| nav.out[s][v].len())
            .sum::<usize>();
        // Routes counted: those of the legs tasks drive, else between every two places
        // (with a saturating stream between racks and stations, parks beside the stations
        // were on no route between racks, and walled the stations in).
        let legs: Vec<(usize, usize)> = needs
            .legs
            .get(s)
            .map(|l| {
                l.iter()
                    .copied()
                    .filter(|&(a, z)| required(s, a) && required(s, z))
                    .collect()
            })
            .unwrap_or_default();
        let flows = through::flows(&targets, &legs);
        let search_cost = flows.len() * n_edges.max(1);
        // Homes asked for first, on the same terms (but they may be required vertices).
        let homes: Vec<(usize, bool)> = needs
            .homes
            .iter()
            .filter(|&&(hs, v)| {
                hs == s
                    && Some(main[s][v]) == biggest
                    && nav.vertices[v].lift.is_none()
                    && nav.members[s].binary_search(&v).is_ok()
            })
            .map(|&(_, v)| (v, true))
            .collect();
        let n_homes = homes.len();
        let mut order: Vec<(usize, bool)> = homes
            .into_iter()
            .chain(cands.into_iter().map(|v| (v, false)))
            .collect();
        let mut taken = 0;
        // Parks taken since the scores were last computed (none yet).
        let mut since: Option<usize> = None;
        let mut i = 0;
        while i < order.len() {
            let (v, home) = order[i];
            if !home && taken >= want {
                break;
            }
            // Scores again after every park where that is cheap, else as the parks taken
            // grow by an eighth (a 10,000-waypoint warehouse takes a thousand).
            let every = if search_cost <= 200_000 {
                1
            } else {
                (taken / 8).max(1)
            };
            if i >= n_homes && !targets.is_empty() && since.is_none_or(|k| k >= every) {
                since = Some(0);
                let usable = |e: usize| {
                    let ed = &nav.edges[e];
                    !blocked[e] && !absorbed[ed.from] && !absorbed[ed.to]
                };
                let pass = through::through(nav, s, &slots[s].inn, &flows, &usable);
                // A robot standing on v blocks its standing room too.
                let score = |v: usize| -> f64 {
                    let mut room: Vec<usize> = conf.vertex[v]
                        .iter()
                        .flat_map(|&x| standers[x as usize].iter().copied())
                        .collect();
                    room.push(v);
                    room.sort_unstable();
                    room.dedup();
                    room.iter().map(|&w| pass[w]).sum()
                };
                let mut rest: Vec<(usize, f64)> =
                    order[i..].iter().map(|&(w, _)| (w, score(w))).collect();
                rest.sort_by(|a, b| {
                    key(a.0)
                        .cmp(&key(b.0))
                        .then(a.1.total_cmp(&b.1))
                        .then(a.0.cmp(&b.0))
                });
                for (k, (w, _)) in rest.into_iter().enumerate() {
                    order[i + k] = (w, false);
                }
                continue;
            }
            i += 1;
            let set: &[Res] = &conf.vertex[v];
            if set.iter().any(|&x| held[x as usize]) || absorbed[v] {
                continue;
            }
            // What a robot standing on v would absorb and block.
            let mut abs: Vec<usize> = set
                .iter()
                .flat_map(|&x| standers[x as usize].iter().copied())
                .filter(|&w| w != v)
                .collect();
            abs.sort_unstable();
            abs.dedup();
            let touches_need = abs.iter().any(|&w| {
                nav.vertices[w].lift.is_some()
                    || (0..slots.len()).any(|t| required(t, w) || parks.per_slot[t][w] != 0)
            });
            if touches_need {
                continue;
            }
            let mut blk: Vec<usize> = set
                .iter()
                .flat_map(|&x| users[x as usize].iter().copied())
                .filter(|&e| !blocked[e])
                .collect();
            blk.sort_unstable();
            blk.dedup();
            // Every park (this one too) keeps a way in and a way out that no park blocks.
            let access = |p: usize, blocked: &[bool], absorbed: &[bool]| {
                (0..slots.len()).all(|t| {
                    let outs = nav.out[t][p]
                        .iter()
                        .any(|&e| !blocked[e] && !absorbed[nav.edges[e].to]);
                    let ins = slots[t].inn[p]
                        .iter()
                        .any(|&e| !blocked[e] && !absorbed[nav.edges[e].from]);
                    nav.members[t].binary_search(&p).is_err() || (outs && ins)
                })
            };
            let own_ok = access(v, &blocked, &absorbed) && {
                // With v taken (and the lanes past it blocked), the others keep theirs.
                let past: Vec<usize> = blk
                    .iter()
                    .copied()
                    .filter(|&e| nav.edges[e].from != v && nav.edges[e].to != v)
                    .collect();
                for &e in &past {
                    blocked[e] = true;
                }
                absorbed[v] = true;
                let ok = taken_parks.iter().all(|&p| {
                    absorbed[p] = false;
                    let ok = access(p, &blocked, &absorbed);
                    absorbed[p] = true;
                    ok
                });
                absorbed[v] = false;
                for &e in &past {
                    blocked[e] = false;
                }
                ok
            };
            if !own_ok {
                continue;
            }
            // A leaf that blocks only its own lanes cannot cut anything.
            let own_only = blk
                .iter()
                .all(|&e| nav.edges[e].from == v || nav.edges[e].to == v);
            let leaf = own_only && slots[s].nbrs[v].len() <= 1;
            // Set for the check and undone after: only what is not set already (another
            // park's standing room stays absorbed).
            let fresh: Vec<usize> = abs.iter().copied().filter(|&w| !absorbed[w]).collect();
            let ok = leaf || {
                for &e in &blk {
                    blocked[e] = true;
                }
                for &w in &fresh {
                    absorbed[w] = true;
                }
                absorbed[v] = true;
                let ok = (0..slots.len()).all(|t| {
                    let m = parts(nav, &slots[t], &blocked, &absorbed);
                    // Every part keeps what parks do not take together.
                    kept_together(&main[t], &m, &absorbed)
                });
                for &e in &blk {
                    blocked[e] = false;
                }
                for &w in &fresh {
                    absorbed[w] = false;
                }
                absorbed[v] = false;
                ok
            };
            if !ok {
                continue;
            }
            for e in blk {
                // The park's own lanes stay usable by the robot parking there.
                if nav.edges[e].from != v && nav.edges[e].to != v {
                    blocked[e] = true;
                }
            }
            for w in abs {
                absorbed[w] = true;
            }
            for &x in set {
                held[x as usize] = true;
            }
            taken_parks.push(v);
            since = since.map(|k| k + 1);
            // A taken park is occupied for every later check (not only after a check
            // that happened to visit it: a later park must not shut it in).
            absorbed[v] = true;
            if home {
                parks.per_slot[s][v] = PARK_HOME;
                continue;
            }
            parks.per_slot[s][v] = if task(v) { PARK_ON_PLACE } else { PARK };
            taken += 1;
        }
    }
    parks
}

/// The strongly connected parts of slot `s` without the `blocked` edges and `gone`
/// vertices: per vertex, its part's id (its smallest member), or `usize::MAX` when it is
/// alone (it cannot be left and reached again). Linear in the slot (Tarjan), since it runs
/// once per parking candidate.
fn parts(nav: &Nav, slot: &Slot, blocked: &[bool], gone: &[bool]) -> Vec<usize> {
    // The edge's ends from the graph itself (its nodes are the vertices), not from the
    // nav's edge records: large and far apart, they were most of the time of this search.
    let g = EdgeFiltered::from_fn(&slot.graph, |e| {
        !blocked[*e.weight()] && !gone[e.source().index()] && !gone[e.target().index()]
    });
    let mut id = vec![usize::MAX; nav.vertices.len()];
    for part in tarjan_scc(&g) {
        if part.len() > 1 {
            let first = part.iter().map(|n| n.index()).min().unwrap_or(usize::MAX);
            for n in part {
                id[n.index()] = first;
            }
        }
    }
    id
}

/// Whether every part of `before` keeps its members (those not `gone`) together in `after`.
fn kept_together(before: &[usize], after: &[usize], gone: &[bool]) -> bool {
    // Part ids are vertex indices (a part's smallest member), so plain vectors index them.
    // A part left with one member has nothing to keep together (`parts` gives a lone
    // vertex no part).
    let mut left = vec![0usize; before.len()];
    for v in 0..before.len() {
        if before[v] != usize::MAX && !gone[v] {
            left[before[v]] += 1;
        }
    }
    let mut to = vec![usize::MAX; before.len()];
    for v in 0..before.len() {
        if before[v] == usize::MAX || gone[v] || left[before[v]] < 2 {
            continue;
        }
        if after[v] == usize::MAX {
            return false;
        }
        if to[before[v]] == usize::MAX {
            to[before[v]] = after[v];
        } else if to[before[v]] != after[v] {
            return false;
        }
    }
    true
}

/// The vertices `root` reaches (`forward`), or that reach it, on the edges `usable`
/// accepts; `out`/`inn` are the slot's edges per vertex, `ends` every edge's (from, to).
fn reach(
    (out, inn): (&[Vec<usize>], &[Vec<usize>]),
    ends: &[(u32, u32)],
    root: usize,
    forward: bool,
    usable: &dyn Fn(usize) -> bool,
) -> Vec<bool> {
    let mut seen = vec![false; out.len()];
    seen[root] = true;
    let mut stack = vec![root];
    while let Some(v) = stack.pop() {
        let es: &[usize] = if forward { &out[v] } else { &inn[v] };
        for &e in es {
            if !usable(e) {
                continue;
            }
            let w = if forward { ends[e].1 } else { ends[e].0 } as usize;
            if !seen[w] {
                seen[w] = true;
                stack.push(w);
            }
        }
    }
    seen
}

/// Whether a robot standing on `v` for a while (working there) cuts the graph of slot `s`:
/// the vertices of `of` it separates from the main part, if any (for the well-formedness
/// warning). Asking [`Cuts`] is the same, for many vertices.
pub fn cut_by(nav: &Nav, conf: &Conflicts, s: usize, v: usize, of: &[usize]) -> Vec<usize> {
    Cuts::new(nav, conf, s).cut_by(v, of)
}

/// [`cut_by`] for many vertices of one graph slot: what does not change from one vertex
/// to the next (the slot's incoming edges, and which edges and vertices hold each
/// resource) is built once. (Built again for every task place, it was a fifth of setting
/// up a 1,000-robot warehouse run.)
pub struct Cuts<'a> {
    nav: &'a Nav,
    conf: &'a Conflicts,
    slot: Slot,
    /// Per resource: the slot's edges whose traversal holds it, and the vertices whose
    /// standing set holds it.
    edges_of: Vec<Vec<u32>>,
    vertices_of: Vec<Vec<u32>>,
    /// Per edge and per vertex: held by the robot standing at the vertex asked about
    /// (false between asks).
    blocked: Vec<bool>,
    gone: Vec<bool>,
    /// Per edge: its (from, to), read at every step of the searches (the nav's edge
    /// records are large and far apart).
    ends: Vec<(u32, u32)>,
}

impl<'a> Cuts<'a> {
    pub fn new(nav: &'a Nav, conf: &'a Conflicts, s: usize) -> Cuts<'a> {
        let nv = nav.vertices.len();
        let mut inn = vec![Vec::new(); nv];
        let mut edges_of = vec![Vec::new(); conf.n_res];
        for (i, e) in nav.edges.iter().enumerate() {
            if e.graph == s {
                inn[e.to].push(i);
                for &x in &conf.trav[i] {
                    edges_of[x as usize].push(i as u32);
                }
            }
        }
        let mut vertices_of = vec![Vec::new(); conf.n_res];
        for (w, ws) in conf.vertex.iter().enumerate() {
            for &x in ws {
                vertices_of[x as usize].push(w as u32);
            }
        }
        Cuts {
            nav,
            conf,
            slot: Slot {
                s,
                nbrs: Vec::new(),
                inn,
                graph: DiGraph::new(),
            },
            edges_of,
            vertices_of,
            blocked: vec![false; nav.edges.len()],
            gone: vec![false; nv],
            ends: nav
                .edges
                .iter()
                .map(|e| (e.from as u32, e.to as u32))
                .collect(),
        }
    }

    /// The vertices of `of` that a robot working at `v` separates from the main part.
    pub fn cut_by(&mut self, v: usize, of: &[usize]) -> Vec<usize> {
        self.hold(v, true);
        let (nav, blocked, gone, ends) = (self.nav, &self.blocked, &self.gone, &self.ends);
        let usable = |e: usize| {
            let (a, z) = ends[e];
            !blocked[e] && !gone[a as usize] && !gone[z as usize]
        };
        let cut = match of.iter().find(|&&w| !gone[w]) {
            None => Vec::new(),
            Some(&root) => {
                let sides = (&nav.out[self.slot.s][..], &self.slot.inn[..]);
                let fwd = reach(sides, ends, root, true, &usable);
                let bwd = reach(sides, ends, root, false, &usable);
                of.iter()
                    .copied()
                    .filter(|&w| !(gone[w] || fwd[w] && bwd[w]))
                    .collect()
            }
        };
        self.hold(v, false);
        cut
    }

    /// Marks (or clears) what a robot standing at `v` holds: the edges and vertices that
    /// need a resource of its standing set.
    fn hold(&mut self, v: usize, held: bool) {
        for &x in &self.conf.vertex[v] {
            for &e in &self.edges_of[x as usize] {
                self.blocked[e as usize] = held;
            }
            for &w in &self.vertices_of[x as usize] {
                self.gone[w as usize] = held;
            }
        }
    }
}

#[cfg(test)]
mod tests;
