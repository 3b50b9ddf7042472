//! Conflict sets: the resources a robot holds while it drives an edge or stands on a vertex.
//! Two robots may hold the same resource only at different times (the schedule orders
//! them, `schedule.rs`). Conflict sets are
//! precomputed from geometry: standing sets with the largest footprint of all fleets (anyone
//! may come close), edge sets with the stop zone of the fleets driving that graph (the
//! slotcar only probes a disc of `stop_radius` around the point `stop_distance` ahead of
//! itself), so a small robot is not reserved as much room as the largest one.

use crate::graph::{point_segment, segment_segment, EdgeKind, Nav};
use mapc_ir::{BoxGrid, Vec2};
use std::collections::BTreeMap;

/// Clearance added to the footprint sum (m).
pub const MARGIN: f64 = 0.25;

/// Geometry that sizes the conflict sets (the largest over all fleets).
#[derive(Debug, Clone, Copy)]
pub struct Clearance {
    pub footprint: f64,
    /// RMF's `profile.vicinity` (m, 0 when not given): another robot's footprint keeps out
    /// of it, as in rmf_traffic's conflict check (footprint against vicinity).
    pub vicinity: f64,
    pub stop_distance: f64,
    pub stop_radius: f64,
}

pub type Res = u32;

#[derive(Debug, Clone, Default)]
pub struct Conflicts {
    /// Per vertex: sorted resources a robot standing there holds.
    pub vertex: Vec<Vec<Res>>,
    /// Per edge: everything a robot holds while it drives the edge: the edge's set and the
    /// standing sets of both ends (it leaves one and arrives at the other), sorted.
    pub trav: Vec<Vec<Res>>,
    pub n_res: usize,
}

impl Conflicts {
    /// One clearance for every graph.
    #[cfg(test)]
    pub fn build(nav: &Nav, c: Clearance) -> Conflicts {
        Conflicts::build_per_slot(nav, c.footprint, &vec![c; nav.graphs.len()])
    }

    /// `footprint`: the largest footprint of all robots; `per_slot[s]`: the clearance of
    /// the robots driving graph slot `s` (largest over the fleets sharing it).
    pub fn build_per_slot(nav: &Nav, footprint: f64, per_slot: &[Clearance]) -> Conflicts {
        let nv = nav.vertices.len();
        let lane_base = nv;
        let lift_base = lane_base + nav.ir_lanes;
        let mut mutexes: BTreeMap<&str, usize> = BTreeMap::new();
        for e in &nav.edges {
            if let Some(m) = &e.mutex {
                let n = mutexes.len();
                mutexes.entry(m).or_insert(n);
            }
        }
        for v in &nav.vertices {
            if let Some(m) = &v.roles.mutex {
                let n = mutexes.len();
                mutexes.entry(m).or_insert(n);
            }
        }
        let mutex_base = lift_base + nav.lifts.len();
        // One robot passes a door at a time: the door opens and closes for each.
        let door_base = mutex_base + mutexes.len();
        let pair_base = door_base + nav.doors.len();
        // The vicinity of the robots with the largest one (RMF: another's footprint keeps
        // out of it); with none given, the footprint sum and margin decide alone.
        let vicinity = per_slot.iter().map(|c| c.vicinity).fold(0.0, f64::max);
        let separation = |c: &Clearance| {
            (footprint + c.footprint.min(footprint) + MARGIN)
                .max(footprint + c.vicinity)
                .max(c.footprint.min(footprint) + vicinity)
        };
        let body = (2.0 * footprint + MARGIN).max(footprint + vicinity);
        let same_level = |a: usize, b: usize| nav.vertices[a].level == nav.vertices[b].level;
        let clearance = |graph: usize| {
            per_slot.get(graph).copied().unwrap_or(Clearance {
                footprint,
                vicinity: 0.0,
                stop_distance: 0.0,
                stop_radius: 0.0,
            })
        };
        // Lanes closer than this interact (contact, or a stop zone reaching the other's
        // centre), per IR lane: (one end, the other, its gap).
        let mut lanes: BTreeMap<usize, (usize, usize, f64)> = BTreeMap::new();
        for e in &nav.edges {
            if let (Some(l), EdgeKind::Lane) = (e.lane, e.kind) {
                let c = clearance(e.graph);
                let gap = separation(&c).max(c.stop_radius);
                lanes.entry(l).or_insert((e.from, e.to, gap));
            }
        }
        // Two lanes that interact share a resource of their own, so that two lanes near a
        // third do not exclude each other through it (on a corridor of short lanes, a robot
        // would otherwise keep the lanes two junctions away free).
        let lane_list: Vec<(usize, (usize, usize, f64))> =
            lanes.iter().map(|(&l, &g)| (l, g)).collect();
        // Candidate pairs from a grid of the lanes' boxes grown by half the largest gap:
        // two lanes closer than a gap have boxes that overlap then (setup stays linear in
        // the lanes of a large warehouse, not quadratic).
        let grow = lane_list.iter().map(|l| l.1 .2).fold(0.0, f64::max) / 2.0;
        let lane_box = |a: usize, z: usize, r: f64| {
            let (pa, pz) = (nav.vertices[a].pos, nav.vertices[z].pos);
            (
                Vec2::new(pa.x.min(pz.x) - r, pa.y.min(pz.y) - r),
                Vec2::new(pa.x.max(pz.x) + r, pa.y.max(pz.y) + r),
            )
        };
        let boxes: Vec<(Vec2, Vec2)> = lane_list
            .iter()
            .map(|&(_, (a, z, _))| lane_box(a, z, grow))
            .collect();
        let mut lane_grid = BoxGrid::new(&boxes);
        let mut near: BTreeMap<usize, Vec<Res>> = BTreeMap::new();
        let mut n_pairs = 0;
        for (i, &(li, (a, z, gi))) in lane_list.iter().enumerate() {
            let (lo, hi) = boxes[i];
            for j in lane_grid.candidates(lo, hi) {
                let j = j as usize;
                if j <= i {
                    continue;
                }
                let (lj, (p, q, gj)) = lane_list[j];
                if !same_level(a, p) {
                    continue;
                }
                let (pa, pz) = (nav.vertices[a].pos, nav.vertices[z].pos);
                let (pp, pq) = (nav.vertices[p].pos, nav.vertices[q].pos);
                if segment_segment(pa, pz, pp, pq) < gi.max(gj) {
                    let x = (pair_base + n_pairs) as Res;
                    n_pairs += 1;
                    near.entry(li).or_default().push(x);
                    near.entry(lj).or_default().push(x);
                }
            }
        }
        let n_res = pair_base + n_pairs;

        // Vertices near a point or a lane, from a grid of the vertices' boxes grown by half
        // the largest reach of any test below.
        let reach = per_slot
            .iter()
            .map(|c| c.stop_radius + 0.05)
            .fold(body, f64::max);
        let vertex_boxes: Vec<(Vec2, Vec2)> = nav
            .vertices
            .iter()
            .map(|v| {
                let r = Vec2::new(reach / 2.0, reach / 2.0);
                (v.pos.minus(r), v.pos.plus(r))
            })
            .collect();
        let mut vertex_grid = BoxGrid::new(&vertex_boxes);
        let mut vertex = Vec::with_capacity(nv);
        for (i, v) in nav.vertices.iter().enumerate() {
            let mut set = vec![i as Res];
            let (lo, hi) = vertex_boxes[i];
            for j in vertex_grid.candidates(lo, hi) {
                let (j, w) = (j as usize, &nav.vertices[j as usize]);
                if j != i && same_level(i, j) && w.pos.minus(v.pos).norm() < body {
                    set.push(j as Res);
                }
            }
            if let Some(m) = v.roles.mutex.as_deref().and_then(|m| mutexes.get(m)) {
                set.push((mutex_base + m) as Res);
            }
            // Standing where the lift would carry the robot (in the cabin, or close to a
            // rotated one) owns the lift: nobody else may move it meanwhile.
            if let Some(l) = v.lift {
                set.push((lift_base + l) as Res);
            }
            set.sort_unstable();
            set.dedup();
            vertex.push(set);
        }

        let mut edge = Vec::with_capacity(nav.edges.len());
        for e in &nav.edges {
            let mut set: Vec<Res> = vertex[e.to].clone();
            set.push(e.from as Res);
            match e.kind {
                EdgeKind::Lift(l) => set.push((lift_base + l) as Res),
                EdgeKind::Lane => {
                    let c = clearance(e.graph);
                    let body = separation(&c);
                    let (a, z) = (nav.vertices[e.from].pos, nav.vertices[e.to].pos);
                    let d = z.minus(a);
                    let len = d.norm();
                    let h = if len > 1e-9 { d.scale(1.0 / len) } else { d };
                    // Where the slotcar probes for obstacles while driving this lane.
                    let (pa, pz) = (
                        a.plus(h.scale(c.stop_distance)),
                        z.plus(h.scale(c.stop_distance)),
                    );
                    let (lo, hi) = (
                        Vec2::new(
                            a.x.min(z.x).min(pa.x).min(pz.x) - reach / 2.0,
                            a.y.min(z.y).min(pa.y).min(pz.y) - reach / 2.0,
                        ),
                        Vec2::new(
                            a.x.max(z.x).max(pa.x).max(pz.x) + reach / 2.0,
                            a.y.max(z.y).max(pa.y).max(pz.y) + reach / 2.0,
                        ),
                    );
                    for j in vertex_grid.candidates(lo, hi) {
                        let (j, w) = (j as usize, &nav.vertices[j as usize]);
                        if !same_level(j, e.from) {
                            continue;
                        }
                        if point_segment(w.pos, a, z) < body
                            || point_segment(w.pos, pa, pz) < c.stop_radius + 0.05
                        {
                            set.push(j as Res);
                        }
                    }
                    if let Some(lane) = e.lane {
                        set.push((lane_base + lane) as Res);
                        set.extend(near.get(&lane).into_iter().flatten().copied());
                    }
                    if let Some(m) = e.mutex.as_deref().and_then(|m| mutexes.get(m)) {
                        set.push((mutex_base + m) as Res);
                    }
                    if let Some(d) = e.door.filter(|&d| nav.doors[d].controlled) {
                        set.push((door_base + d) as Res);
                    }
                }
            }
            // A lift ride, or a lane where the lift would carry the robot, needs the lift.
            if let Some(l) = e.carried_by {
                set.push((lift_base + l) as Res);
            }
            set.sort_unstable();
            set.dedup();
            edge.push(set);
        }
        let trav = nav
            .edges
            .iter()
            .zip(&edge)
            .map(|(e, set)| {
                let mut t = [set.as_slice(), &vertex[e.from], &vertex[e.to]].concat();
                t.sort_unstable();
                t.dedup();
                t
            })
            .collect();
        Conflicts {
            vertex,
            trav,
            n_res,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Clearance, Conflicts, MARGIN};
    use crate::graph::{point_segment, segment_segment, EdgeKind};
    use crate::traffic::test_map::{conflicts, e, nav, random_nav};

    /// The sets hold exactly what the geometry says, however many elements the grid puts
    /// in a cell: vertices closer than the body, and for a lane, the vertices near the
    /// lane or its probe and the lanes closer than their gap (the grid only narrows the
    /// candidates; it must never drop one).
    #[test]
    fn conflict_sets_are_the_geometric_ones() {
        for seed in 0..40 {
            let nav = random_nav(seed, 12 + seed as usize * 3);
            let c = Clearance {
                footprint: 0.2 + (seed % 5) as f64 * 0.2,
                // None, one within the footprint and margin, one beyond them.
                vicinity: [0.0, 0.5, 2.5][(seed / 2 % 3) as usize],
                stop_distance: (seed % 3) as f64 * 0.5,
                stop_radius: (seed % 4) as f64 * 0.6,
            };
            let conf = Conflicts::build(&nav, c);
            // RMF: one's footprint keeps out of the other's vicinity.
            let body = (2.0 * c.footprint + MARGIN).max(c.footprint + c.vicinity);
            let level = |v: usize| nav.vertices[v].level;
            for i in 0..nav.vertices.len() {
                for j in 0..nav.vertices.len() {
                    let near = i == j
                        || level(i) == level(j)
                            && nav.vertices[i].pos.minus(nav.vertices[j].pos).norm() < body;
                    let has = conf.vertex[i].binary_search(&(j as u32)).is_ok();
                    assert_eq!(near, has, "seed {seed}: vertex {i} and {j}");
                }
            }
            let gap = body.max(c.stop_radius);
            let lane = |e: usize| (nav.edges[e].from, nav.edges[e].to);
            for (k, ek) in nav.edges.iter().enumerate() {
                if ek.kind != EdgeKind::Lane {
                    continue;
                }
                let (a, z) = lane(k);
                let (pa, pz) = (nav.vertices[a].pos, nav.vertices[z].pos);
                let d = pz.minus(pa);
                let h = d.scale(1.0 / d.norm().max(1e-9));
                let (qa, qz) = (
                    pa.plus(h.scale(c.stop_distance)),
                    pz.plus(h.scale(c.stop_distance)),
                );
                for j in 0..nav.vertices.len() {
                    let w = nav.vertices[j].pos;
                    let near = level(j) == level(a)
                        && (point_segment(w, pa, pz) < body
                            || point_segment(w, qa, qz) < c.stop_radius + 0.05);
                    // Its own ends' standing sets are in a traversal set anyway.
                    let end = conf.vertex[a].contains(&(j as u32))
                        || conf.vertex[z].contains(&(j as u32));
                    let has = conf.trav[k].binary_search(&(j as u32)).is_ok();
                    assert!(
                        near || end || !has,
                        "seed {seed}: lane {k} holds vertex {j}"
                    );
                    assert!(!near || has, "seed {seed}: lane {k} misses vertex {j}");
                }
                for (m, em) in nav.edges.iter().enumerate() {
                    let (p, q) = lane(m);
                    if em.kind != EdgeKind::Lane || ek.lane == em.lane || level(p) != level(a) {
                        continue;
                    }
                    let close =
                        segment_segment(pa, pz, nav.vertices[p].pos, nav.vertices[q].pos) < gap;
                    let shared = conf.trav[k].iter().any(|x| {
                        *x as usize >= nav.vertices.len() && conf.trav[m].binary_search(x).is_ok()
                    });
                    assert!(
                        !close || shared,
                        "seed {seed}: lanes {k} and {m} share nothing"
                    );
                }
            }
        }
    }

    #[test]
    fn lanes_conflict_with_their_neighbours_only() {
        let nav = nav();
        let conf = conflicts(&nav);
        let shared = |x: usize, y: usize| {
            conf.trav[x]
                .iter()
                .any(|r| conf.trav[y].binary_search(r).is_ok())
        };
        // The corridor a - b - c - d, 4 m lanes: lanes that meet conflict (head-on, or at
        // the junction); a-b and c-d, 4 m apart, do not, though both meet b-c.
        assert!(shared(e(&nav, "a", "b"), e(&nav, "b", "a")));
        assert!(shared(e(&nav, "a", "b"), e(&nav, "c", "b")));
        assert!(shared(e(&nav, "a", "b"), e(&nav, "b", "c")));
        assert!(!shared(e(&nav, "a", "b"), e(&nav, "c", "d")));
        assert!(!shared(e(&nav, "a", "b"), e(&nav, "d", "c")));
        // The parking bays off b and c, 4 m apart, are as independent.
        assert!(!shared(e(&nav, "b", "p1"), e(&nav, "c", "p2")));
    }

    #[test]
    fn a_vicinity_wider_than_the_footprints_keeps_other_robots_out() {
        let nav = nav();
        let (b, c) = (
            crate::traffic::test_map::v(&nav, "b"),
            crate::traffic::test_map::v(&nav, "c"),
        );
        let with = |vicinity: f64| {
            Conflicts::build(
                &nav,
                Clearance {
                    footprint: 0.3,
                    vicinity,
                    stop_distance: 0.0,
                    stop_radius: 0.0,
                },
            )
        };
        // b and c are 4 m apart: far for 0.3 m robots, within a 4 m vicinity (0.3 + 4 m).
        let apart = |conf: &Conflicts| conf.vertex[b].binary_search(&(c as u32)).is_err();
        assert!(apart(&with(0.0)));
        assert!(apart(&with(3.6)), "0.3 + 3.6 m is under 4 m");
        assert!(!apart(&with(4.0)));
        // Driving b→c then holds what stands at d, 4 m past c, too.
        let d = crate::traffic::test_map::v(&nav, "d");
        let bc = e(&nav, "b", "c");
        assert!(with(0.0).trav[bc].binary_search(&(d as u32)).is_err());
        assert!(with(4.0).trav[bc].binary_search(&(d as u32)).is_ok());
    }
}
