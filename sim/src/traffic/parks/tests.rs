//! Parking vertices keep the building well-formed.

use super::*;
use crate::traffic::test_map::{conflicts, nav, v};

/// The parking vertices for `want` robots on graph 0, with `places` the task places (all
/// required to stay reachable) and `homes` asked for by name.
fn choose_for(
    nav: &crate::graph::Nav,
    conf: &crate::traffic::conflicts::Conflicts,
    places: &[Vec<bool>],
    want: usize,
    homes: &[(usize, usize)],
) -> Parks {
    choose_among(nav, conf, (places, places), want, homes)
}

/// [`choose_for`] where `tasks` are the task places among the `places` that must stay
/// reachable (the others: chargers, spawn points).
fn choose_among(
    nav: &crate::graph::Nav,
    conf: &crate::traffic::conflicts::Conflicts,
    (places, tasks): (&[Vec<bool>], &[Vec<bool>]),
    want: usize,
    homes: &[(usize, usize)],
) -> Parks {
    choose(
        nav,
        conf,
        &Needs {
            required: places,
            places,
            tasks,
            legs: &[],
            want: &[want],
            homes,
        },
    )
}

#[test]
fn dead_ends_are_parks_and_corridors_are_not() {
    let nav = nav();
    let conf = conflicts(&nav);
    let n = nav.vertices.len();
    let none = vec![vec![false; n]];
    let parks = choose_for(&nav, &conf, &none, 10, &[]);
    let names: Vec<&str> = (0..n)
        .filter(|&x| parks.per_slot[0][x] != 0)
        .map(|x| nav.vertices[x].name.as_str())
        .collect();
    // p1, p2 (parking spots), a and d (dead ends of the part that can be driven both
    // ways: e, past a one-way lane, has no way back); b and c cut the corridor.
    assert_eq!(names, ["a", "d", "p1", "p2"]);
}

#[test]
fn task_places_park_only_as_the_second_kind() {
    let nav = nav();
    let conf = conflicts(&nav);
    let n = nav.vertices.len();
    let mut places = vec![vec![false; n]];
    places[0][v(&nav, "a")] = true;
    let parks = choose_for(&nav, &conf, &places, 10, &[]);
    assert_eq!(parks.per_slot[0][v(&nav, "a")], PARK_ON_PLACE);
    assert_eq!(parks.per_slot[0][v(&nav, "p1")], PARK);
    // Wanting one: the best kind first.
    let one = choose_for(&nav, &conf, &places, 1, &[]);
    assert_eq!(one.per_slot[0].iter().filter(|&&p| p != 0).count(), 1);
    assert_eq!(one.per_slot[0][v(&nav, "p1")], PARK);
}

#[test]
fn a_robot_working_in_the_corridor_cuts_it() {
    let nav = nav();
    let conf = conflicts(&nav);
    let places = [v(&nav, "a"), v(&nav, "c"), v(&nav, "d")];
    // Working at c separates a from d.
    let cut = cut_by(&nav, &conf, 0, v(&nav, "c"), &places);
    assert!(!cut.is_empty());
    // Working at a (a dead end) cuts nothing.
    assert!(cut_by(&nav, &conf, 0, v(&nav, "a"), &places).is_empty());
}

/// [`Cuts`] asked about every vertex in turn, on 80 random graphs, says what a search
/// from scratch says: which vertices are no longer both reachable from and back to the
/// first one left, with every edge and vertex the standing robot holds taken out.
#[test]
fn cuts_asked_in_turn_are_each_a_fresh_search() {
    use crate::traffic::test_map::random_nav;
    for seed in 0..80 {
        let nav = random_nav(seed, 8 + (seed as usize % 24));
        let conf = conflicts(&nav);
        let n = nav.vertices.len();
        let of: Vec<usize> = (0..n).collect();
        let mut cuts = Cuts::new(&nav, &conf, 0);
        for v in 0..n {
            let set = &conf.vertex[v];
            let held = |xs: &[u32]| xs.iter().any(|x| set.contains(x));
            let gone: Vec<bool> = (0..n).map(|w| held(&conf.vertex[w])).collect();
            let open = |e: usize| {
                let ed = &nav.edges[e];
                ed.graph == 0 && !held(&conf.trav[e]) && !gone[ed.from] && !gone[ed.to]
            };
            let want: Vec<usize> = match (0..n).find(|&w| !gone[w]) {
                None => Vec::new(),
                Some(root) => {
                    // Fixed points of "reached, and one open edge further".
                    let close = |fwd: bool| {
                        let mut seen = vec![false; n];
                        seen[root] = true;
                        loop {
                            let before = seen.iter().filter(|&&b| b).count();
                            for (e, ed) in nav.edges.iter().enumerate() {
                                let (a, b) = if fwd {
                                    (ed.from, ed.to)
                                } else {
                                    (ed.to, ed.from)
                                };
                                if open(e) && seen[a] {
                                    seen[b] = true;
                                }
                            }
                            if seen.iter().filter(|&&b| b).count() == before {
                                return seen;
                            }
                        }
                    };
                    let (f, b) = (close(true), close(false));
                    (0..n).filter(|&w| !(gone[w] || f[w] && b[w])).collect()
                }
            };
            assert_eq!(cuts.cut_by(v, &of), want, "seed {seed}, vertex {v}");
        }
    }
}

#[test]
fn homes_are_taken_first_where_they_cut_nothing() {
    let nav = nav();
    let conf = conflicts(&nav);
    let n = nav.vertices.len();
    // a and p1 are task places (a charger, a robot's parking spot, ...), asked for as homes
    // with b (the corridor) and e (past a one-way lane: no way back).
    let mut places = vec![vec![false; n]];
    places[0][v(&nav, "a")] = true;
    places[0][v(&nav, "p1")] = true;
    let homes = [
        (0, v(&nav, "b")),
        (0, v(&nav, "a")),
        (0, v(&nav, "p1")),
        (0, v(&nav, "e")),
    ];
    let parks = choose_for(&nav, &conf, &places, 10, &homes);
    let kind = |x: &str| parks.per_slot[0][v(&nav, x)];
    assert_eq!(
        [kind("b"), kind("a"), kind("p1"), kind("e")],
        [0, PARK_HOME, PARK_HOME, 0]
    );
    // The others as without homes, around them: d and p2 (b and c cut the corridor).
    assert_eq!([kind("d"), kind("p2"), kind("c")], [PARK, PARK, 0]);
}

#[test]
fn a_charger_no_task_names_is_parking_and_a_task_place_of_the_second_kind() {
    let nav = nav();
    let conf = conflicts(&nav);
    let n = nav.vertices.len();
    // p1 is a charger (required, may be parked on), a a task place.
    let mut places = vec![vec![false; n]];
    places[0][v(&nav, "p1")] = true;
    places[0][v(&nav, "a")] = true;
    let mut tasks = vec![vec![false; n]];
    tasks[0][v(&nav, "a")] = true;
    let parks = choose_among(&nav, &conf, (&places, &tasks), 10, &[]);
    let kind = |name: &str| parks.per_slot[0][v(&nav, name)];
    assert_eq!(kind("p1"), PARK);
    assert_eq!(kind("a"), PARK_ON_PLACE);
    assert_eq!((kind("p2"), kind("d")), (PARK, PARK));
    // The charger is chosen after the other parking vertices: with room for two, not it.
    let two = choose_among(&nav, &conf, (&places, &tasks), 2, &[]);
    assert_eq!(two.per_slot[0][v(&nav, "p1")], 0);
}

/// With a robot on every other parking vertex, each parking vertex keeps a way out and a
/// way in: an edge to (and one from) a vertex clear of the others' standing room whose
/// traversal needs none of it. Over random maps; a park shut in by later ones once left a
/// robot unable to plan for a whole run (a corridor of parks, each between two others).
#[test]
fn every_park_keeps_a_way_out_and_in_with_all_parks_taken() {
    use crate::traffic::test_map::random_nav;
    for seed in 0..80 {
        let nav = random_nav(seed, 8 + (seed as usize % 24));
        let conf = conflicts(&nav);
        let n = nav.vertices.len();
        let none = vec![vec![false; n]];
        let parks = choose_for(&nav, &conf, &none, n, &[]);
        let taken: Vec<usize> = (0..n).filter(|&p| parks.per_slot[0][p] != 0).collect();
        for &p in &taken {
            let mut others: Vec<u32> = taken
                .iter()
                .filter(|&&q| q != p)
                .flat_map(|&q| conf.vertex[q].iter().copied())
                .collect();
            others.sort_unstable();
            let hit = |set: &[u32]| set.iter().any(|x| others.binary_search(x).is_ok());
            let clear = |e: usize| {
                let ed = &nav.edges[e];
                let w = if ed.from == p { ed.to } else { ed.from };
                !hit(&conf.vertex[w]) && !hit(&conf.trav[e])
            };
            let edges = || (0..nav.edges.len()).filter(|&e| nav.edges[e].graph == 0);
            let out = edges().any(|e| nav.edges[e].from == p && clear(e));
            let inn = edges().any(|e| nav.edges[e].to == p && clear(e));
            assert!(
                out && inn,
                "seed {seed}: park {p} shut in (out {out}, in {inn}) among {taken:?}"
            );
        }
    }
}

/// A ring of two aisles (11 waypoints each, 2 m apart, 3 m between the aisles, joined at
/// both ends) with a station at the west end of the south aisle and a rack 6 m east of it.
fn ring_nav() -> crate::graph::Nav {
    let mut y = String::from(
        "coordinate_system: cartesian_meters\nname: ring\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n",
    );
    for r in 0..2 {
        for c in 0..11 {
            let name = match (r, c) {
                (0, 0) => "station",
                (0, 3) => "rack",
                _ => "",
            };
            y += &format!("      - [{}, {}, 0, \"{name}\"]\n", 2 * c, 3 * r);
        }
    }
    y += "    lanes:\n";
    let lane = "{bidirectional: [4, true], graph_idx: [2, 0]}";
    for r in 0..2 {
        for c in 0..10 {
            y += &format!("      - [{}, {}, {lane}]\n", 11 * r + c, 11 * r + c + 1);
        }
    }
    y += &format!("      - [0, 11, {lane}]\n      - [10, 21, {lane}]\n");
    let parsed = mapc_frontend::parse_str("ring.building.yaml", &y);
    crate::graph::Nav::build(parsed.valid_building().expect("ring loads"), &[0])
}

#[test]
fn parks_go_where_the_fewest_routes_between_places_pass() {
    let nav = ring_nav();
    let conf = conflicts(&nav);
    let n = nav.vertices.len();
    let (station, rack) = (v(&nav, "station"), v(&nav, "rack"));
    let mut places = vec![vec![false; n]];
    places[0][station] = true;
    places[0][rack] = true;
    let parks = choose_for(&nav, &conf, &places, 2, &[]);
    let taken: Vec<(f64, f64)> = (0..n)
        .filter(|&x| parks.per_slot[0][x] != 0)
        .map(|x| (nav.vertices[x].pos.x, nav.vertices[x].pos.y))
        .collect();
    assert_eq!(taken.len(), 2, "{taken:?}");
    // The short way between the station and the rack (x 2 and 4 on the south aisle)
    // stays clear: a robot parked there would send every trip round the ring. The
    // waypoints first in the map's order are exactly those.
    for p in &taken {
        assert!(
            !(p.1 == 0.0 && p.0 > 0.0 && p.0 < 6.0),
            "parked on the short way: {taken:?}"
        );
    }
}

/// A floor of 4 × 12 waypoints (2 m × 3 m, each joined to its four neighbours) with a
/// station at the west end of every row and racks in its middle and at its east end.
fn floor_nav() -> crate::graph::Nav {
    let (rows, cols) = (4, 12);
    let mut y = String::from(
        "coordinate_system: cartesian_meters\nname: floor\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n",
    );
    for r in 0..rows {
        for c in 0..cols {
            let name = match c {
                0 => format!("station_{r}"),
                6 => format!("mid_{r}"),
                11 => format!("end_{r}"),
                _ => String::new(),
            };
            y += &format!("      - [{}, {}, 0, \"{name}\"]\n", 2 * c, 3 * r);
        }
    }
    y += "    lanes:\n";
    let lane = "{bidirectional: [4, true], graph_idx: [2, 0]}";
    for r in 0..rows {
        for c in 0..cols {
            let v = r * cols + c;
            if c + 1 < cols {
                y += &format!("      - [{v}, {}, {lane}]\n", v + 1);
            }
            if r + 1 < rows {
                y += &format!("      - [{v}, {}, {lane}]\n", v + cols);
            }
        }
    }
    let parsed = mapc_frontend::parse_str("floor.building.yaml", &y);
    crate::graph::Nav::build(parsed.valid_building().expect("floor loads"), &[0])
}

#[test]
fn parks_keep_off_the_routes_tasks_drive_not_only_those_between_places() {
    let nav = floor_nav();
    let conf = conflicts(&nav);
    let n = nav.vertices.len();
    let mut places = vec![vec![false; n]];
    let mut legs = vec![Vec::new()];
    for r in 0..4 {
        let station = v(&nav, &format!("station_{r}"));
        places[0][station] = true;
        for rack in [format!("mid_{r}"), format!("end_{r}")] {
            let rack = v(&nav, &rack);
            places[0][rack] = true;
            // Every rack to every station: the stream a warehouse's pickers drive.
            for s in 0..4 {
                legs[0].push((rack, v(&nav, &format!("station_{s}"))));
            }
        }
    }
    let parks = choose(
        &nav,
        &conf,
        &Needs {
            required: &places,
            places: &places,
            tasks: &places,
            legs: &legs,
            want: &[8],
            homes: &[],
        },
    );
    let taken: Vec<(f64, f64)> = (0..n)
        .filter(|&x| parks.per_slot[0][x] != 0)
        .map(|x| (nav.vertices[x].pos.x, nav.vertices[x].pos.y))
        .collect();
    assert_eq!(taken.len(), 8, "{taken:?}");
    // Every route from a rack to a station ends in the west columns. Counted between every
    // two places instead, the routes between racks fill the middle and the columns beside
    // the stations look free: parks there wall the stations in.
    for p in &taken {
        assert!(p.0 > 12.0, "parked on the way to the stations: {taken:?}");
    }
}
