//! Where each level's floor is in the simulated world.
//!
//! A level's floor is at its `elevation`, except where a map draws several levels at one
//! elevation (W0412 when a lift serves them): they would lie on top of each other, robots on
//! different floors would stop for each other and count as touching, and a cabin would
//! ride nowhere between them. Such a level is put `STACK` above the highest floor so far,
//! in the map's order, so each floor is a place of its own and a ride takes a storey's
//! time. Every part of the runtime (world, lifts, graph, crowd) reads floors from here.

use mapc_ir::Building;

/// The height of a storey given to a level drawn at another's elevation (m).
const STACK: f64 = 4.0;

/// Levels closer than this (m) are at one elevation (as W0412 counts them).
const SAME: f64 = 0.01;

/// Per level (by handle index), the elevation of its floor in the simulated world.
pub(crate) fn elevations(b: &Building) -> Vec<f64> {
    let drawn: Vec<f64> = b.levels.iter().map(|(_, l)| l.elevation).collect();
    let mut top = drawn.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut out: Vec<f64> = Vec::with_capacity(drawn.len());
    for &z in &drawn {
        if out.iter().any(|&o| (o - z).abs() < SAME) {
            top += STACK;
            out.push(top);
        } else {
            out.push(z);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use mapc_ir::{CoordinateSystem, Level, Params, Span};

    fn building(zs: &[f64]) -> Building {
        let mut b = Building::new(
            "b".into(),
            CoordinateSystem::CartesianMeters,
            Params::default(),
        );
        for (i, &z) in zs.iter().enumerate() {
            b.levels.append(
                Level {
                    name: format!("L{i}"),
                    elevation: z,
                    ..Level::default()
                },
                Span::default(),
            );
        }
        b
    }

    #[test]
    fn levels_at_one_elevation_are_stacked_above_the_top() {
        assert_eq!(elevations(&building(&[0.0, 4.0, 8.0])), [0.0, 4.0, 8.0]);
        assert_eq!(elevations(&building(&[0.0, 0.0, 0.0])), [0.0, 4.0, 8.0]);
        // L2 repeats L0's elevation: above the top (L1 at 5 m).
        assert_eq!(elevations(&building(&[0.0, 5.0, 0.0])), [0.0, 5.0, 9.0]);
    }
}
