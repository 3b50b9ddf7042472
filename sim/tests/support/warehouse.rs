//! A warehouse map: `rows` aisles of `cols` waypoints 2 m apart (two-way lanes), 3 m
//! apart and joined by a cross aisle every 10 waypoints, in cartesian metres. Racks are
//! named half way between cross aisles (`rack_<row>_<k>`), and each aisle's west end is a
//! station (`station_<row>`). Shared by the traffic property test (`gen::grid`) and the
//! simulation benchmark (`benches/sim.rs`, which includes this file by path).

/// The map's `.building.yaml` text, and the names of its racks and stations.
pub fn map(rows: usize, cols: usize, name: &str) -> (String, Vec<String>) {
    let mut s = format!(
        "coordinate_system: cartesian_meters\nname: {name}\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n"
    );
    let mut places = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            let place = if c == 0 {
                format!("station_{r}")
            } else if c % 10 == 5 {
                format!("rack_{r}_{}", c / 10)
            } else {
                String::new()
            };
            s += &format!("      - [{}, {}, 0, \"{place}\"]\n", 2 * c, 3 * r);
            if !place.is_empty() {
                places.push(place);
            }
        }
    }
    s += "    lanes:\n";
    let lane = "{bidirectional: [4, true], graph_idx: [2, 0]}";
    for r in 0..rows {
        for c in 0..cols {
            let v = r * cols + c;
            if c + 1 < cols {
                s += &format!("      - [{v}, {}, {lane}]\n", v + 1);
            }
            if c % 10 == 0 && r + 1 < rows {
                s += &format!("      - [{v}, {}, {lane}]\n", v + cols);
            }
        }
    }
    (s, places)
}
