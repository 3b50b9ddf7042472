//! The least each task asks of the building's exclusive resources, for the report's
//! throughput bound (`report::bound`): a robot's time, the doors and lifts every route of a
//! leg must pass, and a dispenser's one item while it is carried.
//!
//! Every figure is a lower bound of what any run spends, so that the sum over the tasks a
//! run completed never exceeds a resource's capacity × the run's length (tested over the
//! generated buildings): lanes are driven from rest to rest at the top speed, speeding up
//! at the nominal acceleration and braking at the largest (the slotcar's profile never
//! does better: `profile::robot`), with no turn, settling, door or lift-call time; a lift
//! ride likewise at the cabin's limits (`profile::building`); a door or lift counts only
//! where no route of the leg avoids it.

use super::*;
use crate::report::bound::{Demands, Resource};
use std::collections::HashMap;

/// Least rest-to-rest time over `len` at top speed `v`, speeding up at `up` and braking at
/// `down` (a trapezoid, or a triangle on short stretches).
fn rest_to_rest(len: f64, v: f64, up: f64, down: f64) -> f64 {
    let ramps = 0.5 / up + 0.5 / down;
    if len >= v * v * ramps {
        len / v + v * ramps
    } else {
        // Peak speed p: p² · ramps = len; time p / up + p / down.
        2.0 * (len / ramps).sqrt() * ramps
    }
}

/// One leg of one task for one fleet: from a place to the next.
struct Leg {
    fleet: usize,
    from: usize,
    to: usize,
    /// (task, index of the fleet among the task's fleets, leg number).
    at: (usize, usize, usize),
}

/// A leg's least robot time and the doors and lifts it cannot avoid.
#[derive(Default, Clone)]
struct LegUse {
    time: f64,
    doors: Vec<usize>,
    lifts: Vec<usize>,
}

impl Floor {
    /// Lower bound of the time a robot of fleet `fi` takes over edge `e`.
    fn edge_floor(&self, fi: usize, e: usize) -> f64 {
        let f = &self.fleets[fi];
        let edge = &self.nav.edges[e];
        match edge.kind {
            EdgeKind::Lane => {
                // The slotcar drives a lane's limit, even above its own nominal speed.
                let v = edge
                    .speed_limit
                    .filter(|&l| l > 0.0)
                    .unwrap_or(f.speed)
                    .max(0.05);
                rest_to_rest(edge.length, v, f.accel, f.max_accel)
            }
            EdgeKind::Lift(_) => {
                let c = crate::lift::CABIN;
                rest_to_rest(edge.length, c.v_max, c.a_nom, c.a_max)
            }
        }
    }

    /// Per task that arrived (and was not refused): its least use of each exclusive
    /// resource, the least over the fleets that may do it. `broken_off`: some task ended
    /// half-way (failed or cancelled under way), so a robot may start its next task from
    /// anywhere.
    pub(super) fn demands(&self, broken_off: bool) -> Demands {
        let nav = &self.nav;
        // The steps of each task per fleet that may do it, and their legs.
        let mut per_task: Vec<Vec<(usize, Vec<Step>)>> = Vec::with_capacity(self.tasks.len());
        let mut legs: Vec<Leg> = Vec::new();
        for ti in 0..self.tasks.len() {
            let fleets = self.fleets_for(ti);
            for (k, (fi, steps)) in fleets.iter().enumerate() {
                let goals: Vec<usize> = steps
                    .iter()
                    .filter_map(|s| match s {
                        &Step::GoTo(v) => Some(v),
                        _ => None,
                    })
                    .collect();
                for (n, w) in goals.windows(2).enumerate() {
                    legs.push(Leg {
                        fleet: *fi,
                        from: w[0],
                        to: w[1],
                        at: (ti, k, n),
                    });
                }
            }
            per_task.push(fleets);
        }
        // One search per (fleet, start of a leg), then its legs.
        legs.sort_by_key(|l| (l.fleet, l.from));
        let mut uses: HashMap<(usize, usize, usize), LegUse> = HashMap::new();
        let mut mandatory: HashMap<(usize, usize, usize, Resource), bool> = HashMap::new();
        let mut i = 0;
        while i < legs.len() {
            let (fi, from) = (legs[i].fleet, legs[i].from);
            let slot = self.fleets[fi].slot;
            let (dist, prev) =
                nav.tree_costed(slot, &[from], &|e| self.edge_floor(fi, e), &|_| true);
            while i < legs.len() && legs[i].fleet == fi && legs[i].from == from {
                let to = legs[i].to;
                let mut u = LegUse {
                    time: if dist[to].is_finite() { dist[to] } else { 0.0 },
                    ..LegUse::default()
                };
                // A door or lift every route takes is on the fastest one.
                let mut v = to;
                while v != from {
                    let Some(e) = prev[v] else { break };
                    let edge = &nav.edges[e];
                    let x = match (edge.kind, edge.door) {
                        (EdgeKind::Lift(l), _) => Some(Resource::Lift(l)),
                        (EdgeKind::Lane, Some(d)) if nav.doors[d].controlled => {
                            Some(Resource::Door(d))
                        }
                        _ => None,
                    };
                    if let Some(x) = x {
                        let must = *mandatory.entry((slot, from, to, x)).or_insert_with(|| {
                            nav.plan_with(slot, from, to, 1.0, &|e| !uses_resource(nav, e, x))
                                .is_none()
                        });
                        match x {
                            Resource::Door(d) if must && !u.doors.contains(&d) => u.doors.push(d),
                            Resource::Lift(l) if must && !u.lifts.contains(&l) => u.lifts.push(l),
                            _ => {}
                        }
                    }
                    v = edge.from;
                }
                uses.insert(legs[i].at, u);
                i += 1;
            }
        }
        // The way to a task's first place: but for each robot's first task, a robot comes
        // from where an earlier task ended (anything in between, parking or charging, only
        // makes the way longer). `report::bound` allows for the first tasks.
        let fleets = self.fleets.len();
        let mut approach: Vec<Vec<f64>> = vec![Vec::new(); fleets];
        if !broken_off {
            for (fi, f) in self.fleets.iter().enumerate() {
                let mut ends: Vec<usize> = Vec::new();
                for tf in &per_task {
                    for (g, steps) in tf {
                        if *g == fi {
                            ends.extend(steps.iter().rev().find_map(|s| match s {
                                &Step::GoTo(v) => Some(v),
                                _ => None,
                            }));
                        }
                    }
                }
                ends.sort_unstable();
                ends.dedup();
                approach[fi] = nav
                    .tree_costed(f.slot, &ends, &|e| self.edge_floor(fi, e), &|_| true)
                    .0;
            }
        }
        // The least time a pass through each door, or a ride in each lift, takes a robot of
        // each fleet.
        let mut door_pass = vec![vec![f64::INFINITY; nav.doors.len()]; fleets];
        let mut lift_use = vec![vec![f64::INFINITY; nav.lifts.len()]; fleets];
        let mut lift_entry = vec![vec![f64::INFINITY; nav.lifts.len()]; fleets];
        for (fi, f) in self.fleets.iter().enumerate() {
            for (e, edge) in nav.edges.iter().enumerate() {
                if edge.graph != f.slot {
                    continue;
                }
                let t = self.edge_floor(fi, e);
                if let Some(d) = edge.door {
                    door_pass[fi][d] = door_pass[fi][d].min(t);
                }
                if let EdgeKind::Lift(l) = edge.kind {
                    lift_use[fi][l] = lift_use[fi][l].min(t);
                }
                if let Some(l) = nav.vertices[edge.to].lift {
                    if nav.vertices[edge.from].lift != Some(l) && edge.kind == EdgeKind::Lane {
                        lift_entry[fi][l] = lift_entry[fi][l].min(t);
                    }
                }
            }
        }
        let finite = |x: f64| if x.is_finite() { x } else { 0.0 };

        let mut out = Demands {
            robots: self.robots.len(),
            doors: nav.doors.iter().map(|d| d.name.clone()).collect(),
            lifts: nav.lifts.iter().map(|l| l.name.clone()).collect(),
            ..Demands::default()
        };
        for (ti, fleets) in per_task.iter().enumerate() {
            if fleets.is_empty() {
                continue;
            }
            // Per resource, the least over the task's fleets.
            let mut least: BTreeMap<Resource, f64> = BTreeMap::new();
            let mut least_approach = f64::INFINITY;
            for (k, (fi, steps)) in fleets.iter().enumerate() {
                let mut mine: BTreeMap<Resource, f64> = BTreeMap::new();
                let mut robot = 0.0;
                let mut leg = 0;
                let mut seen_goal = false;
                // The dispenser whose item the robot carries, until the ingest.
                let mut carried: Option<&str> = None;
                for s in steps {
                    match s {
                        &Step::GoTo(v) => {
                            if !seen_goal {
                                let a = approach[*fi].get(v).copied().map_or(0.0, finite);
                                least_approach = least_approach.min(a);
                                robot += a;
                            }
                            if seen_goal {
                                let u = &uses[&(ti, k, leg)];
                                robot += u.time;
                                for &d in &u.doors {
                                    *mine.entry(Resource::Door(d)).or_insert(0.0) +=
                                        finite(door_pass[*fi][d]);
                                }
                                for &l in &u.lifts {
                                    *mine.entry(Resource::Lift(l)).or_insert(0.0) +=
                                        finite(lift_entry[*fi][l]) + finite(lift_use[*fi][l]);
                                }
                                if let Some(d) = carried {
                                    let n = out.dispenser(d);
                                    *mine.entry(Resource::Dispenser(n)).or_insert(0.0) += u.time;
                                }
                                leg += 1;
                            }
                            seen_goal = true;
                        }
                        Step::Dwell(d) => robot += d.max(0.0),
                        Step::Dispense(d) => carried = Some(d),
                        Step::Ingest(_) => carried = None,
                        Step::Charge(_) | Step::Resume(_) => {}
                    }
                }
                mine.insert(Resource::Robots, robot);
                if k == 0 {
                    least = mine;
                } else {
                    // A resource this fleet does not need costs the task nothing.
                    least.retain(|x, v| match mine.get(x) {
                        Some(m) => {
                            *v = v.min(*m);
                            true
                        }
                        None => false,
                    });
                }
            }
            let id = &self.tasks[ti].id;
            out.approach.insert(id.clone(), finite(least_approach));
            out.tasks.insert(id.clone(), least.into_iter().collect());
        }
        out
    }
}

/// Whether edge `e` needs resource `x` (a ride in the lift, a lane through the door).
fn uses_resource(nav: &Nav, e: usize, x: Resource) -> bool {
    let edge = &nav.edges[e];
    match x {
        Resource::Door(d) => edge.door == Some(d),
        Resource::Lift(l) => edge.kind == EdgeKind::Lift(l),
        _ => false,
    }
}
