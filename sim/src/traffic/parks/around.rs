//! How far around a parking vertex the ways through it go: for the worst pair of its
//! neighbours, the shortest way between them that avoids it, over the way through it. A
//! robot standing where that ratio is small (a dead end, the corner of a triangle of lanes)
//! costs the others almost nothing; one standing in the middle of the second corridor
//! between two halves of a building makes every way that corridor offered a detour.

use super::{Parks, PARK};
use crate::graph::{EdgeKind, Nav, NavEdge};
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// A parking vertex whose way around is at most this many times the way through it is one
/// where a robot standing idle is out of the way ([`out_of_the_way`]).
pub const SHORT_WAY_AROUND: f64 = 1.5;

/// Per slot, per vertex: for a [`PARK`] in the way (its way around is longer than
/// [`SHORT_WAY_AROUND`] times the way through it), the parks out of the way (no longer than
/// that) within its [`lookout`], nearest first; empty for every other vertex.
pub fn out_of_the_way(nav: &Nav, parks: &Parks) -> Vec<Vec<Vec<usize>>> {
    let n = nav.vertices.len();
    (0..parks.per_slot.len())
        .map(|s| {
            let adj = undirected(&nav.edges, s, n);
            let park = |v: usize| parks.per_slot[s][v] == PARK;
            let out: Vec<bool> = (0..n)
                .map(|v| park(v) && way_around(&adj, v) <= SHORT_WAY_AROUND)
                .collect();
            (0..n)
                .map(|v| {
                    if !park(v) || out[v] {
                        return Vec::new();
                    }
                    near(&adj, v, lookout(&adj, v))
                        .into_iter()
                        .filter(|&(w, _)| out[w])
                        .map(|(w, _)| w)
                        .collect()
                })
                .collect()
        })
        .collect()
}

/// Slot `s`'s lanes as undirected edges with their lengths (lift rides left out: a way
/// around through another floor is no way around), each neighbour once (the shortest).
fn undirected(edges: &[NavEdge], s: usize, n: usize) -> Vec<Vec<(usize, f64)>> {
    let mut adj: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for e in edges {
        if e.graph != s || e.from == e.to || matches!(e.kind, EdgeKind::Lift(_)) {
            continue;
        }
        adj[e.from].push((e.to, e.length));
        adj[e.to].push((e.from, e.length));
    }
    for a in &mut adj {
        a.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
        a.dedup_by(|x, y| x.0 == y.0);
    }
    adj
}

/// The longest way around `v` over the way through it, for any two of its neighbours: 0 at
/// a dead end, [`CAP`] when some way around is longer than that (or none: `v` cuts them).
fn way_around(adj: &[Vec<(usize, f64)>], v: usize) -> f64 {
    let nb = &adj[v];
    let far = nb.iter().map(|x| x.1).fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    let mut dist: HashMap<usize, f64> = HashMap::new();
    for (k, &(u, du)) in nb.iter().enumerate() {
        // Searched only as far as a way around could still count (a bounded search: on a
        // warehouse grid a few cells around `v`).
        let cutoff = CAP * (du + far);
        avoiding(adj, u, v, cutoff, &mut dist);
        for &(w, dw) in &nb[k + 1..] {
            let around = dist.get(&w).copied().unwrap_or(f64::INFINITY);
            worst = worst.max((around / (du + dw).max(1e-9)).min(CAP));
        }
    }
    worst
}

/// Ratios are counted up to this.
const CAP: f64 = 3.0;

/// The vertices within `radius` metres of `from` by the lanes `adj` (either way), with
/// their distances, nearest first.
fn near(adj: &[Vec<(usize, f64)>], from: usize, radius: f64) -> Vec<(usize, f64)> {
    let mut dist = HashMap::new();
    avoiding(adj, from, usize::MAX, radius, &mut dist);
    let mut out: Vec<(usize, f64)> = dist.into_iter().filter(|x| x.1 <= radius).collect();
    out.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    out
}

/// How far from `v` a robot standing there looks for a parking vertex out of the way: as
/// far as its way-around search may go ([`CAP`] times twice its longest lane).
fn lookout(adj: &[Vec<(usize, f64)>], v: usize) -> f64 {
    CAP * 2.0 * adj[v].iter().map(|x| x.1).fold(0.0, f64::max)
}

/// Shortest distances from `from` without passing `gone`, up to `cutoff`, into `dist`.
fn avoiding(
    adj: &[Vec<(usize, f64)>],
    from: usize,
    gone: usize,
    cutoff: f64,
    dist: &mut HashMap<usize, f64>,
) {
    dist.clear();
    dist.insert(from, 0.0);
    // Distances as integer micrometres: a total order for the heap.
    let key = |d: f64| (d * 1e6) as u64;
    let mut heap = BinaryHeap::from([(Reverse(0u64), from)]);
    while let Some((Reverse(k), x)) = heap.pop() {
        let d = dist[&x];
        if k > key(d) || d > cutoff {
            continue;
        }
        for &(y, l) in &adj[x] {
            let nd = d + l;
            if y != gone && nd < dist.get(&y).copied().unwrap_or(f64::INFINITY) {
                dist.insert(y, nd);
                heap.push((Reverse(key(nd)), y));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Undirected lanes of unit length but for the given ones.
    fn graph(n: usize, lanes: &[(usize, usize, f64)]) -> Vec<Vec<(usize, f64)>> {
        let mut adj = vec![Vec::new(); n];
        for &(a, b, l) in lanes {
            adj[a].push((b, l));
            adj[b].push((a, l));
        }
        adj
    }

    #[test]
    fn a_dead_end_and_a_corner_are_out_of_the_way() {
        // 0-1-2 a corridor, 3 a dead end off 1, 4 the corner of the triangle 0-4-1 (0-1
        // is 1 m, 0-4 and 4-1 are 1 m each).
        let adj = graph(
            5,
            &[
                (0, 1, 1.0),
                (1, 2, 1.0),
                (1, 3, 1.0),
                (0, 4, 1.0),
                (4, 1, 1.0),
            ],
        );
        assert_eq!(way_around(&adj, 3), 0.0);
        // Around the corner: 0-1 directly, 1 m against 2 m through it.
        assert!((way_around(&adj, 4) - 0.5).abs() < 1e-9);
        // 1 cuts 2 and 3 off: no way around.
        assert_eq!(way_around(&adj, 1), CAP);
    }

    #[test]
    fn the_second_corridor_between_two_halves_is_in_the_way() {
        // Halves {0, 1} and {2, 3}; ways between them: 0-2 (2 m) and 1-4-3 (1 + 1 m).
        // Around 4 from 1 to 3: 1-0-2-3, 1 + 2 + 1 = 4 m against 2 m through it.
        let adj = graph(
            5,
            &[
                (0, 1, 1.0),
                (2, 3, 1.0),
                (0, 2, 2.0),
                (1, 4, 1.0),
                (4, 3, 1.0),
            ],
        );
        assert!((way_around(&adj, 4) - 2.0).abs() < 1e-9);
        assert!(way_around(&adj, 4) > SHORT_WAY_AROUND);
    }

    #[test]
    fn nearby_vertices_are_found_nearest_first_within_the_radius() {
        // A line 0-1-2-3 of 2 m lanes, and 4 off 1 at 1 m.
        let adj = graph(5, &[(0, 1, 2.0), (1, 2, 2.0), (2, 3, 2.0), (1, 4, 1.0)]);
        assert_eq!(near(&adj, 0, 4.0), [(0, 0.0), (1, 2.0), (4, 3.0), (2, 4.0)]);
        assert_eq!(near(&adj, 3, 1.0), [(3, 0.0)]);
    }

    #[test]
    fn a_way_around_past_the_cutoff_counts_as_none() {
        // A ring of 8 unit lanes: around any vertex is 6 m against 2 m, 3 times.
        let lanes: Vec<_> = (0..8).map(|i| (i, (i + 1) % 8, 1.0)).collect();
        let adj = graph(8, &lanes);
        assert_eq!(way_around(&adj, 0), CAP);
        // A ring of 4: 2 m around against 2 m through.
        let lanes: Vec<_> = (0..4).map(|i| (i, (i + 1) % 4, 1.0)).collect();
        assert!((way_around(&graph(4, &lanes), 0) - 1.0).abs() < 1e-9);
    }
}
