//! Global paths for people: A* over the polygons of a level's human-lane navmesh (the
//! same polygons `mapc gazebo` writes to `<level>_navmesh.nav`), then the portals of the
//! polygon corridor pulled taut with the funnel algorithm, as Menge's `nav_mesh` velocity
//! component does (runtime.md §6.3).
//!
//! Coordinates are map-frame metres less `origin` (the mesh's centre), so that the f32
//! arithmetic of the avoidance crate stays accurate on maps far from the origin.

use mapc_ir::{NavMesh, Vec2};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

pub(crate) struct Mesh {
    pub origin: Vec2,
    pub verts: Vec<Vec2>,
    pub nodes: Vec<Vec<usize>>,
    centres: Vec<Vec2>,
    /// Per node: (neighbour node, left, right) with left/right the portal ends seen when
    /// leaving the node through it.
    adj: Vec<Vec<(usize, Vec2, Vec2)>>,
    /// Boundary segments (walkable on the right), the avoidance obstacles.
    pub walls: Vec<(Vec2, Vec2)>,
    bbox: Vec<[f64; 4]>,
}

#[derive(PartialEq)]
struct Open(f64, usize);
impl Eq for Open {}
impl Ord for Open {
    fn cmp(&self, o: &Self) -> Ordering {
        // Min-heap on cost, ties by node index: deterministic.
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}
impl PartialOrd for Open {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

impl Mesh {
    pub fn new(m: &NavMesh) -> Mesh {
        let n = m.verts.len().max(1) as f64;
        let sum = m.verts.iter().fold(Vec2::default(), |s, v| s.plus(*v));
        let origin = Vec2::new((sum.x / n).round(), (sum.y / n).round());
        let verts: Vec<Vec2> = m.verts.iter().map(|v| v.minus(origin)).collect();
        let centres = m
            .nodes
            .iter()
            .map(|r| {
                let s = r.iter().fold(Vec2::default(), |s, &i| s.plus(verts[i]));
                s.scale(1.0 / r.len().max(1) as f64)
            })
            .collect();
        let mut adj = vec![Vec::new(); m.nodes.len()];
        for &(a, b, n0, n1) in &m.edges {
            // (a, b) runs counter-clockwise around n0: leaving n0, a is on the right.
            adj[n0].push((n1, verts[b], verts[a]));
            adj[n1].push((n0, verts[a], verts[b]));
        }
        let walls = m
            .obstacles
            .iter()
            .map(|&(a, b, _)| (verts[a], verts[b]))
            .collect();
        let bbox = m
            .nodes
            .iter()
            .map(|r| {
                r.iter().fold(
                    [
                        f64::INFINITY,
                        f64::NEG_INFINITY,
                        f64::INFINITY,
                        f64::NEG_INFINITY,
                    ],
                    |b, &i| {
                        let v = verts[i];
                        [b[0].min(v.x), b[1].max(v.x), b[2].min(v.y), b[3].max(v.y)]
                    },
                )
            })
            .collect();
        Mesh {
            origin,
            verts,
            nodes: m.nodes.clone(),
            centres,
            adj,
            walls,
            bbox,
        }
    }

    /// Is `p` inside node `n` (boundary included, small tolerance)?
    pub fn node_contains(&self, n: usize, p: Vec2) -> bool {
        let b = self.bbox[n];
        let eps = 1e-6;
        if p.x < b[0] - eps || p.x > b[1] + eps || p.y < b[2] - eps || p.y > b[3] + eps {
            return false;
        }
        let r = &self.nodes[n];
        (0..r.len()).all(|k| {
            let (a, c) = (self.verts[r[k]], self.verts[r[(k + 1) % r.len()]]);
            cross(c.minus(a), p.minus(a)) >= -eps
        })
    }

    /// The node holding `p`, looking at `hint` and its neighbours first (a person moves
    /// at most a few centimetres per step), then everywhere.
    pub fn relocate(&self, hint: usize, p: Vec2) -> Option<usize> {
        if hint < self.nodes.len() {
            if self.node_contains(hint, p) {
                return Some(hint);
            }
            if let Some(&(n, _, _)) = self.adj[hint].iter().find(|a| self.node_contains(a.0, p)) {
                return Some(n);
            }
        }
        self.locate(p)
    }

    /// The node holding `p`, if any (lowest index).
    pub fn locate(&self, p: Vec2) -> Option<usize> {
        (0..self.nodes.len()).find(|&n| self.node_contains(n, p))
    }

    /// The node holding `p`, or the one whose boundary is nearest, with the nearest point
    /// of the mesh.
    pub fn snap(&self, p: Vec2) -> Option<(usize, Vec2)> {
        if let Some(n) = self.locate(p) {
            return Some((n, p));
        }
        let mut best: Option<(f64, usize, Vec2)> = None;
        for (n, r) in self.nodes.iter().enumerate() {
            for k in 0..r.len() {
                let (a, b) = (self.verts[r[k]], self.verts[r[(k + 1) % r.len()]]);
                let q = closest_on_segment(p, a, b);
                let d = q.minus(p).norm();
                if best.is_none_or(|(bd, _, _)| d < bd) {
                    // A little inside, towards the node's centre.
                    let inward = self.centres[n].minus(q);
                    let len = inward.norm();
                    let q = if len > 1e-9 {
                        q.plus(inward.scale(0.01_f64.min(len) / len))
                    } else {
                        q
                    };
                    best = Some((d, n, q));
                }
            }
        }
        best.map(|(_, n, q)| (n, q))
    }

    /// Waypoints from `from` (in node `a`) to `to` (in node `b`) for an agent of radius
    /// `r`: portals narrower than the agent are closed. `None` when no corridor exists.
    pub fn path(&self, from: Vec2, a: usize, to: Vec2, b: usize, r: f64) -> Option<Vec<Vec2>> {
        if a == b {
            return Some(vec![to]);
        }
        let n = self.nodes.len();
        let mut g = vec![f64::INFINITY; n];
        let mut prev: Vec<Option<(usize, usize)>> = vec![None; n];
        // Node positions: the start and goal for their nodes, portal midpoints on the way
        // (the first crossing found), centres otherwise.
        let mut at = vec![Vec2::default(); n];
        let mut heap = BinaryHeap::new();
        g[a] = 0.0;
        at[a] = from;
        heap.push(Open(to.minus(from).norm(), a));
        let mut closed = vec![false; n];
        while let Some(Open(_, u)) = heap.pop() {
            if closed[u] {
                continue;
            }
            closed[u] = true;
            if u == b {
                break;
            }
            for (k, &(v, l, rr)) in self.adj[u].iter().enumerate() {
                if closed[v] || l.minus(rr).norm() < 2.0 * r {
                    continue;
                }
                let mid = l.plus(rr).scale(0.5);
                let pos = if v == b { to } else { mid };
                let cost = g[u] + at[u].minus(mid).norm() + mid.minus(pos).norm();
                if cost < g[v] {
                    g[v] = cost;
                    at[v] = pos;
                    prev[v] = Some((u, k));
                    heap.push(Open(cost + to.minus(pos).norm(), v));
                }
            }
        }
        if !closed[b] {
            return None;
        }
        // Portals from a to b, shrunk by the radius at both ends.
        let mut portals = Vec::new();
        let mut v = b;
        while let Some((u, k)) = prev[v] {
            let (_, l, rr) = self.adj[u][k];
            let d = rr.minus(l);
            let w = d.norm();
            let s = if w > 2.0 * r { r / w } else { 0.5 };
            portals.push((l.plus(d.scale(s)), rr.minus(d.scale(s))));
            v = u;
        }
        portals.reverse();
        Some(funnel(from, to, &portals))
    }
}

fn closest_on_segment(p: Vec2, a: Vec2, b: Vec2) -> Vec2 {
    let d = b.minus(a);
    let l2 = d.x * d.x + d.y * d.y;
    if l2 <= 0.0 {
        return a;
    }
    let t = (p.minus(a).x * d.x + p.minus(a).y * d.y) / l2;
    a.plus(d.scale(t.clamp(0.0, 1.0)))
}

/// The simple stupid funnel algorithm (Mononen): the shortest path through the portals
/// (`(left, right)` seen in the direction of travel), as its corner points plus `to`.
pub(crate) fn funnel(from: Vec2, to: Vec2, portals: &[(Vec2, Vec2)]) -> Vec<Vec2> {
    let mut pts: Vec<(Vec2, Vec2)> = Vec::with_capacity(portals.len() + 1);
    pts.extend_from_slice(portals);
    pts.push((to, to));
    let mut out = Vec::new();
    let (mut apex, mut left, mut right) = (from, from, from);
    let (mut li, mut ri) = (0usize, 0usize);
    let mut i = 0;
    // Each restart moves the apex to a later portal, so this ends; the bound is a guard.
    let mut guard = 0usize;
    while i < pts.len() && guard < 4 * pts.len() + 16 {
        guard += 1;
        let (pl, pr) = pts[i];
        // Right side: tighten if the new right is inside the funnel.
        if cross(right.minus(apex), pr.minus(apex)) >= 0.0 {
            if apex == right || cross(left.minus(apex), pr.minus(apex)) < 0.0 {
                right = pr;
                ri = i;
            } else {
                // Crosses the left side: the left point is a corner.
                apex = left;
                out.push(apex);
                right = apex;
                i = li + 1;
                li = i;
                ri = i;
                continue;
            }
        }
        if cross(left.minus(apex), pl.minus(apex)) <= 0.0 {
            if apex == left || cross(right.minus(apex), pl.minus(apex)) > 0.0 {
                left = pl;
                li = i;
            } else {
                apex = right;
                out.push(apex);
                left = apex;
                i = ri + 1;
                li = i;
                ri = i;
                continue;
            }
        }
        i += 1;
    }
    if out.last() != Some(&to) {
        out.push(to);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn funnel_straight_and_around_a_corner() {
        // A straight corridor: no corners.
        let p = [(Vec2::new(1.0, 1.0), Vec2::new(1.0, -1.0))];
        assert_eq!(
            funnel(Vec2::new(0.0, 0.0), Vec2::new(2.0, 0.0), &p),
            vec![Vec2::new(2.0, 0.0)]
        );
        // An L: from (0,0) east to the corner, then north to (5,5); the portal at x = 4,
        // y from 0 (right) to... the inner corner (4, 1) is where the path bends.
        let p = [(Vec2::new(4.0, 1.0), Vec2::new(6.0, 1.0))];
        let path = funnel(Vec2::new(0.0, 0.0), Vec2::new(5.0, 5.0), &p);
        assert_eq!(path, vec![Vec2::new(4.0, 1.0), Vec2::new(5.0, 5.0)]);
    }
}
