//! Conflict sets: the resources a robot holds while it drives an edge or stands on a vertex.
//! Two robots may hold the same resource only at different times (the schedule orders
//! them, `schedule.rs`). Conflict sets are
//! precomputed from geometry: standing sets with the largest footprint of all fleets (anyone
//! may come close), edge sets with the stop zone of the fleets driving that graph (the
//! slotcar only probes a disc of `stop_radius` around the point `stop_distance` ahead of
//! itself), so a small robot is not reserved as much room as the largest one.

use crate::graph::{point_segment, segment_segment, EdgeKind, Nav};
use std::collections::BTreeMap;

/// Clearance added to the footprint sum (m).
pub const MARGIN: f64 = 0.25;

/// Geometry that sizes the conflict sets (the largest over all fleets).
#[derive(Debug, Clone, Copy)]
pub struct Clearance {
    pub footprint: f64,
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
        let body = 2.0 * footprint + MARGIN;
        let same_level = |a: usize, b: usize| nav.vertices[a].level == nav.vertices[b].level;
        let clearance = |graph: usize| {
            per_slot.get(graph).copied().unwrap_or(Clearance {
                footprint,
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
                let gap = (footprint + c.footprint.min(footprint) + MARGIN).max(c.stop_radius);
                lanes.entry(l).or_insert((e.from, e.to, gap));
            }
        }
        // Two lanes that interact share a resource of their own, so that two lanes near a
        // third do not exclude each other through it (on a corridor of short lanes, a robot
        // would otherwise keep the lanes two junctions away free).
        let lane_list: Vec<(usize, (usize, usize, f64))> =
            lanes.iter().map(|(&l, &g)| (l, g)).collect();
        let mut near: BTreeMap<usize, Vec<Res>> = BTreeMap::new();
        let mut n_pairs = 0;
        for (i, &(li, (a, z, gi))) in lane_list.iter().enumerate() {
            for &(lj, (p, q, gj)) in &lane_list[i + 1..] {
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

        let mut vertex = Vec::with_capacity(nv);
        for (i, v) in nav.vertices.iter().enumerate() {
            let mut set = vec![i as Res];
            for (j, w) in nav.vertices.iter().enumerate() {
                if j != i && same_level(i, j) && w.pos.minus(v.pos).norm() < body {
                    set.push(j as Res);
                }
            }
            if let Some(m) = v.roles.mutex.as_deref().and_then(|m| mutexes.get(m)) {
                set.push((mutex_base + m) as Res);
            }
            // Standing where the lift would carry the robot (in the cabin, or close to a
            // rotated one) owns the lift: nobody else may move it meanwhile.
            if let Some(l) = v.carried_by {
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
                    let body = footprint + c.footprint.min(footprint) + MARGIN;
                    let (a, z) = (nav.vertices[e.from].pos, nav.vertices[e.to].pos);
                    let d = z.minus(a);
                    let len = d.norm();
                    let h = if len > 1e-9 { d.scale(1.0 / len) } else { d };
                    // Where the slotcar probes for obstacles while driving this lane.
                    let (pa, pz) = (
                        a.plus(h.scale(c.stop_distance)),
                        z.plus(h.scale(c.stop_distance)),
                    );
                    for (j, w) in nav.vertices.iter().enumerate() {
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
    use crate::traffic::test_map::{conflicts, e, nav};

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
}
