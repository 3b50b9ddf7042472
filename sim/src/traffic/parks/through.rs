//! How much of the traffic between places passes each vertex: the share of shortest routes
//! between places through it (betweenness restricted to places, Brandes 2001; with many
//! places, from a sample of them as sources, Brandes & Pich 2007). A robot parked where
//! little traffic passes makes few routes longer, so parking vertices are taken in that
//! order.

use crate::graph::Nav;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Places searched from, at most (the others are still targets).
pub(super) const SOURCES: usize = 48;

/// The routes to count: each source with the places routes go to from it. The places tasks
/// go between (`legs`, from → to, each task's places in order), else every place to every
/// other; at most [`SOURCES`] sources, spread evenly over them.
pub(super) fn flows(places: &[usize], legs: &[(usize, usize)]) -> Vec<(usize, Vec<usize>)> {
    let all: Vec<(usize, Vec<usize>)> = if legs.is_empty() {
        places.iter().map(|&p| (p, places.to_vec())).collect()
    } else {
        let mut by: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        for &(a, z) in legs {
            by.entry(a).or_default().push(z);
        }
        by.into_iter().collect()
    };
    let stride = all.len().div_ceil(SOURCES).max(1);
    all.into_iter().step_by(stride).collect()
}

/// Per vertex: the (fractional) number of shortest routes of `flows` (see [`flows`]) on graph
/// slot `s` that pass through it, on the edges `usable` accepts. `inn[v]`: the slot's edges
/// into `v`.
pub(super) fn through(
    nav: &Nav,
    s: usize,
    inn: &[Vec<usize>],
    flows: &[(usize, Vec<usize>)],
    usable: &dyn Fn(usize) -> bool,
) -> Vec<f64> {
    let n = nav.vertices.len();
    let mut out = vec![0.0; n];
    let mut target = vec![false; n];
    // Per edge, in flat arrays: its ends, its cost, whether it may be used. Read from the
    // graph's edge records (large, far apart) at every step, they were most of the time
    // of choosing a 10,000-waypoint warehouse's thousand parks.
    let from: Vec<usize> = nav.edges.iter().map(|e| e.from).collect();
    let to: Vec<usize> = nav.edges.iter().map(|e| e.to).collect();
    let costs: Vec<f64> = (0..nav.edges.len())
        .map(|e| nav.edge_cost(e, 1.0))
        .collect();
    let ok: Vec<bool> = (0..nav.edges.len()).map(usable).collect();
    let cost = |e: usize| costs[e];
    let mut dist = vec![f64::INFINITY; n];
    let mut sigma = vec![0.0f64; n];
    let mut delta = vec![0.0f64; n];
    let mut settled: Vec<usize> = Vec::new();
    let mut heap = BinaryHeap::new();
    for (src, targets) in flows {
        let src = *src;
        for &p in targets {
            target[p] = true;
        }
        for &v in &settled {
            (dist[v], sigma[v], delta[v]) = (f64::INFINITY, 0.0, 0.0);
        }
        settled.clear();
        dist[src] = 0.0;
        heap.push(Entry(0.0, src));
        while let Some(Entry(d, v)) = heap.pop() {
            if d > dist[v] || sigma[v] > 0.0 {
                continue;
            }
            // Routes to v: one from the source, else the sum over its shortest ways in.
            sigma[v] = if v == src {
                1.0
            } else {
                inn[v]
                    .iter()
                    .filter(|&&e| ok[e] && on_shortest(&dist, from[e], d, cost(e)))
                    .map(|&e| sigma[from[e]])
                    .sum()
            };
            settled.push(v);
            for &e in &nav.out[s][v] {
                if !ok[e] {
                    continue;
                }
                let w = to[e];
                let dw = d + cost(e);
                if dw < dist[w] - tol(dw) {
                    dist[w] = dw;
                    heap.push(Entry(dw, w));
                }
            }
        }
        // Back from the farthest: each vertex passes its share on to the ways into it.
        for &w in settled.iter().rev() {
            let pass = (if target[w] && w != src { 1.0 } else { 0.0 }) + delta[w];
            for &e in &inn[w] {
                let u = from[e];
                if ok[e] && on_shortest(&dist, u, dist[w], cost(e)) && sigma[w] > 0.0 {
                    delta[u] += sigma[u] / sigma[w] * pass;
                }
            }
            if w != src {
                out[w] += delta[w];
            }
        }
        for &p in targets {
            target[p] = false;
        }
    }
    out
}

/// Whether the edge from `u` (cost `c`) lies on a shortest route to a vertex at `d`.
fn on_shortest(dist: &[f64], u: usize, d: f64, c: f64) -> bool {
    dist[u].is_finite() && (dist[u] + c - d).abs() <= tol(d)
}

/// Equal costs within rounding.
fn tol(d: f64) -> f64 {
    1e-9 * d.abs().max(1.0)
}

/// A vertex and its distance, nearest first in a max-heap (ties: lower index first).
struct Entry(f64, usize);

impl PartialEq for Entry {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traffic::test_map::nav;

    #[test]
    fn a_corridor_carries_every_route_past_it_and_a_dead_end_none() {
        let nav = nav();
        let s = 0;
        let mut inn = vec![Vec::new(); nav.vertices.len()];
        for (i, e) in nav.edges.iter().enumerate() {
            if e.graph == s {
                inn[e.to].push(i);
            }
        }
        let v = |n: &str| nav.find(s, n).unwrap();
        let places = [v("a"), v("d")];
        let t = through(&nav, s, &inn, &flows(&places, &[]), &|_| true);
        // a ↔ d both ways, each through b and c only.
        assert_eq!(t[v("b")], 2.0);
        assert_eq!(t[v("c")], 2.0);
        assert_eq!(t[v("p1")], 0.0);
        assert_eq!(t[v("a")], 0.0);
    }
}
