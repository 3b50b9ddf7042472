//! `spawn: auto`: where the robots of fleets without named spawn points start.
//!
//! Every robot asked is put on the floor, each on a parking vertex of its fleet's graph
//! (`crate::traffic::parks`: a waypoint where a standing robot blocks no route, away from
//! task waypoints, chargers and lift cabins), so that a robot without work never stands in
//! the way of one with work, and every robot has a parking vertex of its own to end its
//! plans on (Token Passing's condition). Only on a graph with no parking vertex off the
//! task places do robots start on task places that cut nothing (a robot parked there is
//! sent away when a task needs the place). Fewer robots only when the building has too few
//! parking vertices; the report says so (S0211) and counts the others as `reserve`.
//!
//! Fleets share the parking vertices in proportion to their sizes: robots are placed one at
//! a time, always for the fleet with the smallest share placed so far, on the level with
//! the fewest robots so far.

use super::*;
use crate::traffic::parks::{PARK, PARK_ON_PLACE};

/// A fleet to place: its index in the scenario, graph slot and robot count.
pub(super) struct AutoFleet {
    pub fleet: usize,
    pub slot: usize,
    pub count: usize,
}

/// The vertices chosen for each of `fleets` (same order), at most `count` each, on
/// parking vertices whose standing sets meet no other robot's (`taken`: robots placed
/// already).
pub(super) fn auto_spawn(
    nav: &Nav,
    conf: &Conflicts,
    parks: &Parks,
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
    loop {
        let next = (0..fleets.len())
            .filter(|&k| !full[k] && chosen[k].len() < fleets[k].count)
            .min_by(|&a, &b| {
                let share = |k: usize| chosen[k].len() as f64 / fleets[k].count as f64;
                share(a).total_cmp(&share(b)).then(a.cmp(&b))
            });
        let Some(k) = next else { break };
        let slot = fleets[k].slot;
        // Task places only on a graph without any other parking vertex: a robot parked
        // on a place holds up the tasks going there.
        let tier = if nav.members[slot]
            .iter()
            .any(|&v| parks.per_slot[slot][v] == PARK)
        {
            PARK
        } else {
            PARK_ON_PLACE
        };
        let pick = nav.members[slot]
            .iter()
            .copied()
            .filter(|&v| parks.per_slot[slot][v] == tier)
            .filter(|&v| conf.vertex[v].iter().all(|&x| !held[x as usize]))
            .min_by_key(|&v| {
                let ro = &nav.vertices[v].roles;
                let class = if ro.is_parking_spot {
                    0
                } else if ro.is_holding_point {
                    1
                } else {
                    2
                };
                let tier = parks.per_slot[slot][v];
                (
                    tier,
                    on_level.get(&nav.vertices[v].level).copied().unwrap_or(0),
                    class,
                    v,
                )
            });
        match pick {
            Some(v) => {
                for &x in &conf.vertex[v] {
                    held[x as usize] = true;
                }
                *on_level.entry(nav.vertices[v].level).or_default() += 1;
                chosen[k].push(v);
            }
            None => full[k] = true,
        }
    }
    chosen
}
