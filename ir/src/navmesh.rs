//! The navigation mesh of a level's human lanes: the polygons Menge walks on (runtime.md
//! §6.3). The backends write it as a Menge `.nav` file and the runtime's crowd walks on the
//! very same polygons, so what `mapc sim` simulates is what Gazebo would load.
//!
//! A simple construction, not the editor's: every human lane is a rectangle of its `width`
//! (default 1 m) along the lane, and every vertex where two or more lanes meet is a
//! junction polygon through the lanes' end corners, which the lane rectangles share (so
//! A* can cross from lane to junction). The lane ends are pulled back from the
//! vertex far enough that neighbouring lanes do not overlap (half the wider lane over
//! `tan(α/2)`, α the angle to the angular neighbour; at least half the lane width, at most
//! 45 % of the shortest lane at the vertex). A dead end (one lane) is the lane rectangle's
//! end, an obstacle. Every polygon side that is not shared is an obstacle, wound clockwise
//! around its node (walkable space on its right, RVO2's convention).
//!
//! Limits: lanes that cross without a shared vertex overlap instead of joining; junction
//! polygons of lanes of very different widths may be slightly non-convex.

use crate::{Building, Handle, Level, Vec2, Vertex};
use std::collections::BTreeMap;

/// The default human lane width, metres, when the lane has none.
pub const DEFAULT_HUMAN_LANE_WIDTH: f64 = 1.0;

/// A level's walkable polygons.
#[derive(Debug, Clone, PartialEq)]
pub struct NavMesh {
    pub verts: Vec<Vec2>,
    /// Counter-clockwise vertex rings: one per lane, then one per junction.
    pub nodes: Vec<Vec<usize>>,
    /// Sides two nodes share: `(v0, v1, node0, node1)`.
    pub edges: Vec<(usize, usize, usize, usize)>,
    /// Sides no other node shares: `(v0, v1, node)`, walkable space on the right.
    pub obstacles: Vec<(usize, usize, usize)>,
}

struct Lane {
    a: Handle<Vertex>,
    b: Handle<Vertex>,
    half: f64,
}

/// The navmesh of `level`'s human lanes with `origin` subtracted from every position (a
/// world's `Building::offset`, or zero for the map frame), or `None` when it has none
/// usable (zero-length lanes are skipped).
pub fn human_navmesh(b: &Building, level: Handle<Level>, origin: Vec2) -> Option<NavMesh> {
    let lvl = &b.levels[level];
    let pos = |v: Handle<Vertex>| b.vertices[v].pos.minus(origin);
    // Lanes, one per unordered vertex pair (document order of the first).
    let mut lanes: Vec<Lane> = Vec::new();
    let mut pairs = std::collections::BTreeSet::new();
    for &h in &lvl.human_lanes {
        let l = &b.human_lanes[h];
        let w = l
            .params
            .f64("width")
            .filter(|w| w.is_finite() && *w > 0.0)
            .unwrap_or(DEFAULT_HUMAN_LANE_WIDTH);
        let len = pos(l.end).minus(pos(l.start)).norm();
        let pair = (l.start.min(l.end), l.start.max(l.end));
        if len.is_finite() && len > 1e-9 && pairs.insert(pair) {
            lanes.push(Lane {
                a: l.start,
                b: l.end,
                half: w / 2.0,
            });
        }
    }
    if lanes.is_empty() {
        return None;
    }

    // Lane ends at each vertex: (angle of the lane leaving the vertex, lane index, is the
    // lane's start), sorted counter-clockwise.
    let mut ends: BTreeMap<Handle<Vertex>, Vec<(f64, usize, bool)>> = BTreeMap::new();
    for (i, l) in lanes.iter().enumerate() {
        let d = pos(l.b).minus(pos(l.a));
        ends.entry(l.a).or_default().push((d.y.atan2(d.x), i, true));
        ends.entry(l.b)
            .or_default()
            .push(((-d.y).atan2(-d.x), i, false));
    }
    for e in ends.values_mut() {
        e.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    }
    // Pull-back of each lane end: (lane, is start) → distance from the vertex.
    let mut pull: BTreeMap<(usize, bool), f64> = BTreeMap::new();
    for e in ends.values() {
        let n = e.len();
        let shortest = e
            .iter()
            .map(|&(_, i, _)| pos(lanes[i].b).minus(pos(lanes[i].a)).norm())
            .fold(f64::INFINITY, f64::min);
        for (k, &(theta, i, start)) in e.iter().enumerate() {
            let p = if n < 2 {
                0.0
            } else {
                let mut p = lanes[i].half;
                // The angular neighbours on both sides.
                for j in [(k + 1) % n, (k + n - 1) % n] {
                    let (t2, i2, _) = e[j];
                    let mut a = (t2 - theta).abs() % std::f64::consts::TAU;
                    if a > std::f64::consts::PI {
                        a = std::f64::consts::TAU - a;
                    }
                    let h = lanes[i].half.max(lanes[i2].half);
                    let t = (a / 2.0).tan();
                    p = p.max(if t > 1e-6 { h / t } else { f64::INFINITY });
                }
                p.min(0.45 * shortest)
            };
            pull.insert((i, start), p);
        }
    }

    // Corner vertices: (lane, is start, left side) → index.
    let mut verts: Vec<Vec2> = Vec::new();
    let mut corner: BTreeMap<(usize, bool, bool), usize> = BTreeMap::new();
    // Corners that coincide (neighbouring lanes at a right angle meet at one corner) are
    // one vertex, so that no zero-length side becomes an obstacle (Menge normalises each
    // obstacle's direction). Micrometre grid: the corners come from the same formulas.
    let mut at: BTreeMap<(i64, i64), usize> = BTreeMap::new();
    for (i, l) in lanes.iter().enumerate() {
        let (pa, pb) = (pos(l.a), pos(l.b));
        let len = pb.minus(pa).norm();
        let d = pb.minus(pa).scale(1.0 / len);
        let nrm = Vec2::new(-d.y, d.x);
        for start in [true, false] {
            // Seen from the vertex the lane leaves: direction and its left normal.
            let (v, dir, left) = if start {
                (pa, d, nrm)
            } else {
                (pb, d.scale(-1.0), nrm.scale(-1.0))
            };
            let p = pull.get(&(i, start)).copied().unwrap_or(0.0);
            let base = v.plus(dir.scale(p));
            for is_left in [false, true] {
                let s = if is_left { l.half } else { -l.half };
                let p = base.plus(left.scale(s));
                let key = ((p.x * 1e6).round() as i64, (p.y * 1e6).round() as i64);
                let idx = *at.entry(key).or_insert_with(|| {
                    verts.push(p);
                    verts.len() - 1
                });
                corner.insert((i, start, is_left), idx);
            }
        }
    }

    // Nodes as counter-clockwise vertex rings: lanes, then junctions (vertex order).
    let mut nodes: Vec<Vec<usize>> = Vec::new();
    for i in 0..lanes.len() {
        let c = |s, l| corner[&(i, s, l)];
        // Start right, end left (= the lane's right side), end right, start left.
        nodes.push(vec![
            c(true, false),
            c(false, true),
            c(false, false),
            c(true, true),
        ]);
    }
    for e in ends.values().filter(|e| e.len() >= 2) {
        let ring = e
            .iter()
            .flat_map(|&(_, i, s)| [corner[&(i, s, false)], corner[&(i, s, true)]])
            .collect();
        nodes.push(ring);
    }

    // Merged corners repeat in a ring: keep one; a ring left with fewer than 3 vertices
    // encloses nothing.
    for ring in &mut nodes {
        ring.dedup();
        while ring.len() > 1 && ring.first() == ring.last() {
            ring.pop();
        }
    }
    nodes.retain(|r| r.len() >= 3);

    // Edges: sides two nodes share; obstacles: every other side.
    let mut sides: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    for (n, ring) in nodes.iter().enumerate() {
        for k in 0..ring.len() {
            let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
            sides.entry((a.min(b), a.max(b))).or_default().push(n);
        }
    }
    let mut edges: Vec<(usize, usize, usize, usize)> = Vec::new();
    let mut obstacles: Vec<(usize, usize, usize)> = Vec::new();
    for (n, ring) in nodes.iter().enumerate() {
        for k in 0..ring.len() {
            let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
            let users = &sides[&(a.min(b), a.max(b))];
            if users.len() >= 2 {
                // Once, from the first node that has it.
                if users[0] == n {
                    let other = users[1];
                    edges.push((a, b, n, other));
                }
            } else {
                // Reversed (clockwise around the walkable node): ORCA, as in RVO2, takes
                // an obstacle into account only for agents on its right.
                obstacles.push((b, a, n));
            }
        }
    }
    Some(NavMesh {
        verts,
        nodes,
        edges,
        obstacles,
    })
}
