//! A small map for the traffic unit tests: a corridor a - b - c - d (4 m apart), parking
//! bays p1 off b and p2 off c (3 m off the corridor), and e past d on a one-way lane.

use super::{Clearance, Conflicts};
use crate::graph::Nav;

pub const YAML: &str = r#"coordinate_system: cartesian_meters
name: t
graphs:
  0: {name: g, default_lane_width: 1}
levels:
  L1:
    elevation: 0
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [1, 2, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [1, 4, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [2, 5, {bidirectional: [4, true], graph_idx: [2, 0]}]
      - [3, 6, {bidirectional: [4, false], graph_idx: [2, 0]}]
    vertices:
      - [0, 0, 0, a]
      - [4, 0, 0, b]
      - [8, 0, 0, c]
      - [12, 0, 0, d]
      - [4, 3, 0, p1, {is_parking_spot: [4, true]}]
      - [8, 3, 0, p2, {is_parking_spot: [4, true]}]
      - [16, 0, 0, e]
reference_level_name: L1
"#;

pub fn nav() -> Nav {
    let parsed = mapc_frontend::parse_str("t.building.yaml", YAML);
    let b = parsed.valid_building().expect("test map loads");
    Nav::build(b, &[0])
}

pub fn conflicts(nav: &Nav) -> Conflicts {
    Conflicts::build(
        nav,
        Clearance {
            footprint: 0.3,
            vicinity: 0.0,
            stop_distance: 0.75,
            stop_radius: 0.75,
        },
    )
}

pub fn v(nav: &Nav, name: &str) -> usize {
    nav.find(0, name).unwrap_or_else(|| panic!("vertex {name}"))
}

pub fn e(nav: &Nav, a: &str, z: &str) -> usize {
    let (a, z) = (v(nav, a), v(nav, z));
    nav.edges
        .iter()
        .position(|x| x.from == a && x.to == z)
        .unwrap_or_else(|| panic!("edge {a}->{z}"))
}

/// A random map: `n` vertices scattered over 30 m × 30 m on two levels, random lanes.
pub fn random_nav(seed: u64, n: usize) -> Nav {
    let mut rng = fastrand::Rng::with_seed(seed);
    let mut yaml = String::from(
        "coordinate_system: cartesian_meters\nname: r\nreference_level_name: L1\nlevels:\n",
    );
    for level in ["L1", "L2"] {
        yaml += &format!("  {level}:\n    elevation: 0\n    vertices:\n");
        for _ in 0..n {
            let (x, y) = (rng.f64() * 30.0, rng.f64() * 30.0);
            yaml += &format!("      - [{x:.3}, {y:.3}, 0, \"\"]\n");
        }
        yaml += "    lanes:\n";
        for _ in 0..n {
            let (a, z) = (rng.usize(0..n), rng.usize(0..n));
            if a != z {
                yaml += &format!(
                    "      - [{a}, {z}, {{bidirectional: [4, {}], graph_idx: [2, 0]}}]\n",
                    rng.bool()
                );
            }
        }
    }
    let parsed = mapc_frontend::parse_str("r.building.yaml", &yaml);
    Nav::build(parsed.valid_building().expect("random map loads"), &[0])
}
