//! `spawn: auto`: where the robots of fleets without named spawn points start.
//!
//! Every robot asked is put on the floor, each on a parking vertex of its fleet's graph
//! (`crate::traffic::parks`: a waypoint where a standing robot blocks no route, away from
//! task waypoints, chargers and lift cabins; chargers themselves only when the others are
//! taken), so that a robot without work never stands in
//! the way of one with work, and every robot has a parking vertex of its own to end its
//! plans on (Token Passing's condition). Only on a graph with no parking vertex off the
//! task places do robots start on task places that cut nothing, on at most half of them (a
//! robot parked there holds up the tasks going there until it takes one or is sent away;
//! with every place held, no task could end). Fewer robots only when the building has too
//! few parking vertices; the report says so (S0211) and counts the others as `reserve`.
//!
//! Fleets share the parking vertices in proportion to their sizes: robots are placed one at
//! a time, always for the fleet with the smallest share placed so far, on the level with
//! the fewest robots so far; of those, on parking spots first, and nearest the scenario's
//! task places (by the sum of the drives to them), so that robots start where the work is.
//! (By waypoint order, the ninth robot on a generated three-level building started in a
//! far corner, 96 s from every task, and stood idle for the first 20 minutes of a saturating
//! stream, each task waiting for a nearer busy robot instead.)

use super::*;
use crate::traffic::parks::{PARK, PARK_ON_PLACE};

/// A fleet to place: its index in the scenario, graph slot and robot count.
pub(super) struct AutoFleet {
    pub fleet: usize,
    pub slot: usize,
    pub count: usize,
}

/// Task places [`reach`] measures from, at most: one search of the graph each (a
/// warehouse's 1,692 racks would be seconds of set-up; every so many of them, in waypoint
/// order, stand for the others).
const REACH_PLACES: usize = 64;

/// Per graph slot, per vertex: how far the task places `places` (per slot) are from it,
/// as (how many it cannot reach, the sum of the drive times to those it can).
pub(super) fn reach(nav: &Nav, places: &[Vec<bool>]) -> Vec<Vec<(usize, f64)>> {
    let n = nav.vertices.len();
    (0..nav.graphs.len())
        .map(|slot| {
            let mut out = vec![(0usize, 0.0); n];
            let here: Vec<usize> = places
                .get(slot)
                .map_or(&[][..], |p| p.as_slice())
                .iter()
                .enumerate()
                .filter_map(|(v, &is)| is.then_some(v))
                .collect();
            let every = here.len().div_ceil(REACH_PLACES).max(1);
            for &p in here.iter().step_by(every) {
                // Speed 1: distances, the same order for every fleet's speed.
                for (o, t) in out.iter_mut().zip(nav.times_to(slot, p, 1.0)) {
                    if t.is_finite() {
                        o.1 += t;
                    } else {
                        o.0 += 1;
                    }
                }
            }
            out
        })
        .collect()
}

/// The vertices chosen for each of `fleets` (same order), at most `count` each, on
/// parking vertices whose standing sets meet no other robot's (`taken`: robots placed
/// already), nearest the task places first (`reach`, from [`reach`]).
pub(super) fn auto_spawn(
    nav: &Nav,
    conf: &Conflicts,
    parks: &Parks,
    reach: &[Vec<(usize, f64)>],
    fleets: &[AutoFleet],
    taken: &[usize],
) -> Vec<Vec<usize>> {
    let mut held = vec![false; conf.n_res];
    let mut on_level: BTreeMap<mapc_ir::Handle<mapc_ir::Level>, usize> = BTreeMap::new();
    for &v in taken {
        for &x in &conf.vertex[v] {
            held[x as usize] = true;
        }
        *on_level.entry(nav.vertices[v].level).or_default() += 1;
    }
    let mut chosen: Vec<Vec<usize>> = vec![Vec::new(); fleets.len()];
    let mut full = vec![false; fleets.len()];
    // Per slot: robots placed on task places.
    let mut on_places = vec![0usize; nav.graphs.len()];
    loop {
        let next = (0..fleets.len())
            .filter(|&k| !full[k] && chosen[k].len() < fleets[k].count)
            .min_by(|&a, &b| {
                let share = |k: usize| chosen[k].len() as f64 / fleets[k].count as f64;
                share(a).total_cmp(&share(b)).then(a.cmp(&b))
            });
        let Some(k) = next else { break };
        let slot = fleets[k].slot;
        // Task places only on a graph without any other parking vertex, and on at most
        // half of them (at least one): a robot parked on a place holds up the tasks going
        // there, and with every place held no task could end.
        let free_on = |tier: u8| {
            nav.members[slot]
                .iter()
                .copied()
                .filter(move |&v| parks.per_slot[slot][v] == tier)
                .filter(|&v| conf.vertex[v].iter().all(|&x| !held[x as usize]))
        };
        let count = |tier: u8| {
            nav.members[slot]
                .iter()
                .filter(|&&v| parks.per_slot[slot][v] == tier)
                .count()
        };
        let tier = if count(PARK) > 0 {
            PARK
        } else if on_places[slot] < (count(PARK_ON_PLACE) / 2).max(1) {
            PARK_ON_PLACE
        } else {
            full[k] = true;
            continue;
        };
        let pick = free_on(tier).min_by(|&a, &b| {
            let key = |v: usize| {
                let ro = &nav.vertices[v].roles;
                let class = if ro.is_parking_spot {
                    0
                } else if ro.is_holding_point {
                    1
                } else {
                    2
                };
                let tier = parks.per_slot[slot][v];
                let (cut_off, far) = reach[slot][v];
                (
                    (
                        tier,
                        // Chargers last: they are parking too, but for robots that need them.
                        ro.is_charger,
                        on_level.get(&nav.vertices[v].level).copied().unwrap_or(0),
                        class,
                        cut_off,
                    ),
                    far,
                    v,
                )
            };
            let (ka, kb) = (key(a), key(b));
            ka.0.cmp(&kb.0)
                .then(ka.1.total_cmp(&kb.1))
                .then(ka.2.cmp(&kb.2))
        });
        match pick {
            Some(v) => {
                for &x in &conf.vertex[v] {
                    held[x as usize] = true;
                }
                *on_level.entry(nav.vertices[v].level).or_default() += 1;
                chosen[k].push(v);
                if tier == PARK_ON_PLACE {
                    on_places[slot] += 1;
                }
            }
            None => full[k] = true,
        }
    }
    chosen
}
