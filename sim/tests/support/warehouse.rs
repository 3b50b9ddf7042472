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

/// A warehouse of one-way aisles with bays, as robot warehouses are laid out: `rows`
/// aisles (even) of `cols` waypoints 2 m apart, 4 m apart, driven east on even rows and
/// west on odd ones; a one-way cross aisle every 4 waypoints (`cols - 1` a multiple of 4,
/// an even number of them), south on even ones and north on odd ones (so the outer ring
/// is a loop and every waypoint reaches every other); and off every odd waypoint a bay
/// 1.5 m to the north, reached by a two-way lane, where a robot stands out of the aisle's
/// way: a rack (`rack_<row>_<col>`) at columns 1, 5, 9, ..., a parking bay between them.
/// Cartesian metres.
///
/// The map's `.building.yaml` text, and the names of its racks.
pub fn bays(rows: usize, cols: usize, name: &str) -> (String, Vec<String>) {
    assert!(rows % 2 == 0 && cols % 4 == 1 && (cols / 4 + 1) % 2 == 0);
    let mut s = format!(
        "coordinate_system: cartesian_meters\nname: {name}\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n"
    );
    let aisle = |r: usize, c: usize| r * cols + c;
    for r in 0..rows {
        for c in 0..cols {
            s += &format!("      - [{}, {}, 0, \"\"]\n", 2 * c, 4 * r);
        }
    }
    let mut racks = Vec::new();
    let mut bays = rows * cols;
    let mut lanes = String::new();
    let two_way = "{bidirectional: [4, true], graph_idx: [2, 0]}";
    let one_way = "{bidirectional: [4, false], graph_idx: [2, 0]}";
    for r in 0..rows {
        for c in (1..cols).step_by(2) {
            let rack = if c % 4 == 1 {
                format!("rack_{r}_{c}")
            } else {
                String::new()
            };
            let y = (4 * r) as f64 + 1.5;
            s += &format!("      - [{}, {y}, 0, \"{rack}\"]\n", 2 * c);
            lanes += &format!("      - [{}, {bays}, {two_way}]\n", aisle(r, c));
            bays += 1;
            if !rack.is_empty() {
                racks.push(rack);
            }
        }
        for c in 0..cols - 1 {
            let (a, b) = (aisle(r, c), aisle(r, c + 1));
            let (a, b) = if r % 2 == 0 { (a, b) } else { (b, a) };
            lanes += &format!("      - [{a}, {b}, {one_way}]\n");
        }
    }
    for k in 0..=cols / 4 {
        for r in 0..rows - 1 {
            let (a, b) = (aisle(r, 4 * k), aisle(r + 1, 4 * k));
            let (a, b) = if k % 2 == 1 { (a, b) } else { (b, a) };
            lanes += &format!("      - [{a}, {b}, {one_way}]\n");
        }
    }
    s += "    lanes:\n";
    s += &lanes;
    (s, racks)
}
