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
        let n_res = door_base + nav.doors.len();
        let body = 2.0 * footprint + MARGIN;
        let same_level = |a: usize, b: usize| nav.vertices[a].level == nav.vertices[b].level;

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
                    let c = per_slot.get(e.graph).copied().unwrap_or(Clearance {
                        footprint,
                        stop_distance: 0.0,
                        stop_radius: 0.0,
                    });
                    let body = footprint + c.footprint.min(footprint) + MARGIN;
                    // Lanes closer than this interact (contact, or our stop zone reaching
                    // the other's centre; the other lane's own set covers its stop zone).
                    let lane_gap = body.max(c.stop_radius);
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
                    }
                    for o in &nav.edges {
                        let (Some(ol), EdgeKind::Lane) = (o.lane, o.kind) else {
                            continue;
                        };
                        if !same_level(o.from, e.from) {
                            continue;
                        }
                        let (p, q) = (nav.vertices[o.from].pos, nav.vertices[o.to].pos);
                        if segment_segment(a, z, p, q) < lane_gap {
                            set.push((lane_base + ol) as Res);
                        }
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
