//! Generated buildings and saturating task streams for traffic tests and benchmarks.
//!
//! A building has one to three levels. Each level is a corridor with junctions every few
//! metres; off the junctions go side corridors to dead-end rooms (some behind doors) and
//! parking bays; some levels have a second, parallel corridor driven one way (a loop with
//! the first, one way round); levels are joined by a lift at the west end. Task places are
//! the rooms, and, in the buildings that are meant not to be well-formed, some junctions of
//! the main corridor too (a robot working there cuts the corridor).
//!
//! [`grid`] makes warehouses instead: aisles joined by cross aisles, no dead ends.
//!
//! Everything follows from the seed (fastrand), so a failing case is reproduced by its
//! seed alone.
#![allow(dead_code)] // each test binary uses a part

use std::fmt::Write;

/// A generated building: its `.building.yaml` text and the named places tasks may use.
pub struct Building {
    pub seed: u64,
    pub yaml: String,
    pub places: Vec<String>,
    pub levels: usize,
    pub well_formed: bool,
    /// Waypoints in all.
    pub waypoints: usize,
    /// Its doors and lifts, by name.
    pub doors: Vec<String>,
    pub lifts: Vec<String>,
    /// When not empty, every task of [`scenario`] ends at one of these (a hotspot) and
    /// starts at one of `places`.
    pub sinks: Vec<String>,
}

struct Level {
    name: String,
    verts: Vec<(f64, f64, String, String)>,
    lanes: Vec<(usize, usize, bool)>,
    doors: Vec<(usize, usize, String)>,
}

impl Level {
    fn v(&mut self, x: f64, y: f64, name: &str, params: &str) -> usize {
        self.verts
            .push((x, y, name.to_string(), params.to_string()));
        self.verts.len() - 1
    }
}

/// Options of [`building_with`].
pub struct Shape {
    pub levels: usize,
    /// Junctions on each level's main corridor.
    pub junctions: usize,
    /// Side corridors per junction (0 to 2: north and south).
    pub sides: usize,
    /// Rooms at the end of each side corridor.
    pub rooms: usize,
    pub one_way_loop: bool,
    pub doors: bool,
    pub well_formed: bool,
    /// The whole building turned by this angle (rad) about the origin: lanes, doors and the
    /// lift cabin off the axes (a rotated cabin's payload box reaches past it).
    pub yaw: f64,
}

/// A random building from `seed`.
pub fn building(seed: u64) -> Building {
    let mut rng = fastrand::Rng::with_seed(seed);
    let levels = [1, 1, 2, 2, 3][rng.usize(0..5)];
    let shape = Shape {
        levels,
        junctions: rng.usize(2..7),
        sides: rng.usize(1..3),
        rooms: rng.usize(1..3),
        one_way_loop: rng.bool(),
        doors: rng.bool(),
        well_formed: rng.usize(0..3) != 0,
        yaw: if rng.bool() {
            0.0
        } else {
            rng.f64() * std::f64::consts::TAU
        },
    };
    building_with(seed, &shape)
}

/// A building of the given shape; `seed` picks which junctions get side corridors, doors
/// and parking bays.
pub fn building_with(seed: u64, s: &Shape) -> Building {
    let mut rng = fastrand::Rng::with_seed(seed ^ 0x9e37_79b9_7f4a_7c15);
    let mut places = Vec::new();
    let mut out = String::new();
    let _ = writeln!(out, "coordinate_system: cartesian_meters");
    let _ = writeln!(out, "name: gen_{seed}");
    let _ = writeln!(out, "graphs:\n  0: {{name: fleet, default_lane_width: 1}}");
    let mut lvls = Vec::new();
    let gap = 4.0;
    for l in 0..s.levels {
        let mut lv = Level {
            name: format!("L{}", l + 1),
            verts: Vec::new(),
            lanes: Vec::new(),
            doors: Vec::new(),
        };
        // The lift lobby and, with several levels, the cabin west of it.
        let lobby = lv.v(-3.0, 0.0, &format!("lobby_{l}"), "");
        let mut prev = lobby;
        let mut main = Vec::new();
        for j in 0..s.junctions {
            let x = j as f64 * gap;
            let name = format!("j_{l}_{j}");
            let v = lv.v(x, 0.0, &name, "");
            lv.lanes.push((prev, v, true));
            prev = v;
            main.push(v);
            if !s.well_formed && j > 0 && j + 1 < s.junctions && rng.usize(0..3) == 0 {
                // A task place on the corridor itself: robots working there cut it.
                places.push(name);
            }
            for side in 0..s.sides {
                if rng.usize(0..4) == 0 && j > 0 {
                    continue;
                }
                let dir = if side == 0 { 1.0 } else { -1.0 };
                let a = lv.v(x, dir * 3.0, "", "");
                lv.lanes.push((v, a, true));
                for r in 0..s.rooms {
                    let room = format!("room_{l}_{j}_{side}_{r}");
                    let rx = x + (r as f64 - (s.rooms as f64 - 1.0) / 2.0) * 1.8;
                    let rv = lv.v(rx, dir * 6.0, &room, "");
                    lv.lanes.push((a, rv, true));
                    if s.doors && r == 0 && rng.bool() {
                        // A door across the lane, half way.
                        let my = dir * 4.5;
                        let (dx, dy) = (a_x_towards(x, rx), my);
                        let d1 = lv.v(dx - 0.45, dy, "", "");
                        let d2 = lv.v(dx + 0.45, dy, "", "");
                        lv.doors.push((d1, d2, format!("door_{l}_{j}_{side}")));
                    }
                    places.push(room);
                }
            }
            // Parking bays: dead ends a little off the corridor, every other junction.
            if j % 2 == 1 || s.junctions <= 2 {
                let p = lv.v(
                    x + gap / 2.0,
                    2.0,
                    &format!("park_{l}_{j}"),
                    "{is_parking_spot: [4, true]}",
                );
                let m = lv.v(x + gap / 2.0, 0.0, "", "");
                lv.lanes.push((m, p, true));
                // The next junction's lane will start from m.
                lv.lanes.push((v, m, true));
                prev = m;
            }
        }
        if s.one_way_loop && s.junctions >= 2 {
            // A parallel corridor 3 m south of... north sides are rooms; use y = -9, far
            // from the side corridors, joined at both ends: east-bound on the main
            // corridor's side lanes is not changed, the loop runs west-bound.
            let first = main[0];
            let last = *main.last().unwrap_or(&first);
            let mut chain = Vec::new();
            for j in 0..s.junctions {
                chain.push(lv.v(j as f64 * gap, -9.0, "", ""));
            }
            let down_w = lv.v(-1.5, -4.5, "", "");
            let down_e = lv.v((s.junctions - 1) as f64 * gap + 1.5, -4.5, "", "");
            // last -> down_e -> chain east end -> ... -> chain west end -> down_w -> first
            lv.lanes.push((last, down_e, false));
            lv.lanes
                .push((down_e, *chain.last().unwrap_or(&last), false));
            for w in chain.windows(2).rev() {
                lv.lanes.push((w[1], w[0], false));
            }
            lv.lanes.push((chain[0], down_w, false));
            lv.lanes.push((down_w, first, false));
            places.push(format!("loop_{l}"));
            let mid = chain[chain.len() / 2];
            lv.verts[mid].2 = format!("loop_{l}");
        }
        lvls.push(lv);
    }
    let cabin_x = -5.5;
    let _ = writeln!(out, "levels:");
    let mut waypoints = 0;
    for (l, lv) in lvls.iter_mut().enumerate() {
        let lobby = 0;
        if s.levels > 1 {
            let c = lv.v(
                cabin_x,
                0.0,
                &format!("cabin_{l}"),
                "{lift_cabin: [1, lift_1]}",
            );
            lv.lanes.push((lobby, c, true));
        }
        waypoints += lv.verts.len();
        let _ = writeln!(out, "  {}:", lv.name);
        let _ = writeln!(out, "    elevation: {}", l as f64 * 4.0);
        if !lv.doors.is_empty() {
            let _ = writeln!(out, "    doors:");
            for (a, b, name) in &lv.doors {
                let _ = writeln!(
                    out,
                    "      - [{a}, {b}, {{motion_axis: [1, start], motion_degrees: [3, 90], motion_direction: [2, 1], name: [1, {name}], plugin: [1, normal], right_left_ratio: [3, 1], type: [1, sliding]}}]"
                );
            }
        }
        let _ = writeln!(out, "    lanes:");
        for (a, b, bi) in &lv.lanes {
            let _ = writeln!(
                out,
                "      - [{a}, {b}, {{bidirectional: [4, {bi}], graph_idx: [2, 0], orientation: [1, \"\"]}}]"
            );
        }
        let _ = writeln!(out, "    vertices:");
        let (sin, cos) = s.yaw.sin_cos();
        for (x, y, name, params) in &lv.verts {
            let (x, y) = (x * cos - y * sin, x * sin + y * cos);
            if params.is_empty() {
                let _ = writeln!(out, "      - [{x}, {y}, 0, \"{name}\"]");
            } else {
                let _ = writeln!(out, "      - [{x}, {y}, 0, \"{name}\", {params}]");
            }
        }
    }
    if s.levels > 1 {
        let names: Vec<String> = (0..s.levels).map(|l| format!("L{}", l + 1)).collect();
        let _ = writeln!(out, "lifts:\n  lift_1:");
        let (sin, cos) = s.yaw.sin_cos();
        let _ = writeln!(
            out,
            "    depth: 1.6\n    width: 1.6\n    x: {}\n    y: {}\n    yaw: {}",
            cabin_x * cos,
            cabin_x * sin,
            s.yaw
        );
        let _ = writeln!(out, "    doors:\n      lift_1_door: {{door_type: 2, motion_axis_orientation: 1.5708, width: 1.2, x: 0.8, y: 0}}");
        let _ = writeln!(out, "    level_doors:");
        for n in &names {
            let _ = writeln!(out, "      {n}: [lift_1_door]");
        }
        let _ = writeln!(
            out,
            "    lowest_floor: L1\n    highest_floor: {}\n    initial_floor_name: L1\n    reference_floor_name: L1\n    plugins: true",
            names[names.len() - 1]
        );
    }
    let _ = writeln!(out, "reference_level_name: L1");
    let doors = lvls
        .iter()
        .flat_map(|lv| lv.doors.iter().map(|d| d.2.clone()))
        .collect();
    let lifts = if s.levels > 1 {
        vec!["lift_1".to_string()]
    } else {
        Vec::new()
    };
    Building {
        seed,
        yaml: out,
        places,
        levels: s.levels,
        well_formed: s.well_formed,
        waypoints,
        doors,
        lifts,
        sinks: Vec::new(),
    }
}

/// A warehouse from `seed`: 3 to 12 aisles of two-way lanes (waypoints 2 m apart, aisles 3
/// m apart), joined by a cross aisle every 10 waypoints (2 to 4 segments): a grid without
/// dead ends, where robots parked in the aisles leave single-file stretches. Each aisle's
/// west end is a station (`station_<row>`), each segment's middle a rack
/// (`rack_<row>_<segment>`); tasks go between any of them.
pub fn grid(seed: u64) -> Building {
    let mut rng = fastrand::Rng::with_seed(seed ^ 0x6a1d_5eed);
    let rows = rng.usize(3..13);
    let cols = 10 * rng.usize(2..5) + 1;
    let (yaml, places) = super::warehouse::map(rows, cols, &format!("grid_{seed}"));
    Building {
        seed,
        yaml,
        places,
        levels: 1,
        well_formed: true,
        waypoints: rows * cols,
        doors: Vec::new(),
        lifts: Vec::new(),
        sinks: Vec::new(),
    }
}

/// A warehouse of one-way aisles with bays from `seed` (`warehouse::bays`): 2 to 8 aisles
/// of 13 or 29 waypoints, a bay off every other waypoint, every other bay a rack; tasks
/// go between racks. Idle robots stand in bays, out of the aisles.
pub fn grid_bays(seed: u64) -> Building {
    let mut rng = fastrand::Rng::with_seed(seed ^ 0xba75_5eed);
    let rows = 2 * rng.usize(1..5);
    let cols = if rng.bool() { 13 } else { 29 };
    let (yaml, places) = super::warehouse::bays(rows, cols, &format!("bays_{seed}"));
    Building {
        seed,
        yaml,
        waypoints: rows * cols + rows * (cols / 2),
        places,
        levels: 1,
        well_formed: true,
        doors: Vec::new(),
        lifts: Vec::new(),
        sinks: Vec::new(),
    }
}

/// [`grid`]`(seed)` with a hotspot: every task goes from a rack to a station (the west
/// end of an aisle), as where goods are packed.
pub fn grid_to_stations(seed: u64) -> Building {
    let mut b = grid(seed);
    let (sinks, racks) = b
        .places
        .iter()
        .cloned()
        .partition(|p| p.starts_with("station_"));
    (b.sinks, b.places) = (sinks, racks);
    b
}

fn a_x_towards(x: f64, rx: f64) -> f64 {
    (x + rx) / 2.0
}

/// The tasks of a stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mix {
    /// Loops between two places (a robot parks after each).
    Loops,
    /// Go-to-place tasks: the robot stays at the place until another task or a robot
    /// that needs the place sends it on.
    GoTo,
    /// Either, drawn for each task.
    Mixed,
    /// Deliveries from the first place to the second, with a dispenser and an ingestor
    /// of the scenario's at every place (each dispenser holds one item, back home a few
    /// seconds after it was delivered).
    Deliveries,
}

/// A saturating stream of loops between random places of `b`: a task every `every` s for
/// the whole run, each between two places drawn from the seed, for `robots` robots placed
/// by `spawn: auto`: TinyRobots, and in one building in three half of them DeliveryRobots.
pub fn scenario(b: &Building, robots: usize, duration_s: f64, every: f64, seed: u64) -> String {
    scenario_mix(b, robots, duration_s, every, seed, Mix::Loops)
}

/// [`scenario`] with the tasks of `mix` (a go-to-place goes to the second place drawn).
pub fn scenario_mix(
    b: &Building,
    robots: usize,
    duration_s: f64,
    every: f64,
    seed: u64,
    mix: Mix,
) -> String {
    let mut rng = fastrand::Rng::with_seed(seed);
    // Drawn from a stream of its own, so that the places drawn are those of `Loops`.
    let mut kinds = fastrand::Rng::with_seed(seed ^ 0x0009_0709_1ace);
    let go = |kinds: &mut fastrand::Rng| match mix {
        Mix::Loops | Mix::Deliveries => false,
        Mix::GoTo => true,
        Mix::Mixed => kinds.bool(),
    };
    let caps = match mix {
        Mix::Loops => "loop",
        Mix::GoTo => "go_to_place",
        Mix::Mixed => "loop, go_to_place",
        Mix::Deliveries => "delivery",
    };
    let mut out = String::new();
    let _ = writeln!(out, "seed: {seed}");
    let _ = writeln!(out, "duration: {duration_s}s");
    let _ = writeln!(out, "crowd: {{enabled: false}}");
    // One building in three has a second fleet of bigger, slower robots on the same lanes
    // (footprints and kinematics differ; the tasks go to whichever fleet is there first).
    let big = if seed % 3 == 2 { robots / 2 } else { 0 };
    let _ = writeln!(
        out,
        "fleets:\n  - {{name: fleet, graph: 0, robot: TinyRobot, count: {}, spawn: auto, tasks: [{caps}]}}",
        robots - big
    );
    if big > 0 {
        let _ = writeln!(
            out,
            "  - {{name: big, graph: 0, robot: DeliveryRobot, count: {big}, spawn: auto, tasks: [{caps}]}}"
        );
    }
    if mix == Mix::Deliveries {
        let _ = writeln!(out, "workcells:");
        for p in b.places.iter().chain(&b.sinks) {
            let _ = writeln!(
                out,
                "  - {{name: {p}_dispenser, kind: dispenser, waypoint: {p}}}"
            );
            let _ = writeln!(
                out,
                "  - {{name: {p}_ingestor, kind: ingestor, waypoint: {p}}}"
            );
        }
    }
    let task = |at: f64, a: &str, c: &str, go: bool| {
        if mix == Mix::Deliveries {
            format!("  - {{at: {at}s, delivery: {{pickup: {a}, dropoff: {c}, dispenser: {a}_dispenser, ingestor: {c}_ingestor}}}}")
        } else if go {
            format!("  - {{at: {at}s, go_to_place: {{place: {c}}}}}")
        } else {
            format!("  - {{at: {at}s, loop: {{start: {a}, finish: {c}, loops: 1}}}}")
        }
    };
    let _ = writeln!(out, "tasks:");
    let n = (duration_s / every) as usize;
    for k in 0..n {
        let a = &b.places[rng.usize(0..b.places.len())];
        if !b.sinks.is_empty() {
            let c = &b.sinks[rng.usize(0..b.sinks.len())];
            let _ = writeln!(out, "{}", task(k as f64 * every, a, c, go(&mut kinds)));
            continue;
        }
        let mut c = &b.places[rng.usize(0..b.places.len())];
        if c == a {
            c = &b.places[(rng.usize(0..b.places.len()) + 1) % b.places.len()];
        }
        if a == c {
            continue;
        }
        let _ = writeln!(out, "{}", task(k as f64 * every, a, c, go(&mut kinds)));
    }
    out
}

/// Random faults for `b`'s runs with `robots` robots (of [`scenario`]): each a robot
/// paused, a door or the lift out of service, for 30 to 200 s, all starting in
/// `[0, before)`. A door or lift is never out of service twice at once: two overlapping
/// faults would make one outage longer than the 300 s a robot waits for it (a lift out
/// from 348 s to 547 s and from 544 s to 686 s failed a task, as it should); the
/// second becomes a robot's pause. Scenario lines to append to [`scenario`]'s text.
pub fn faults(b: &Building, robots: usize, before: f64, n: usize, seed: u64) -> String {
    let mut rng = fastrand::Rng::with_seed(seed ^ 0x5eed_fa17);
    let mut out = String::from("faults:\n");
    let big = if seed % 3 == 2 { robots / 2 } else { 0 };
    // Doors and lifts out of service: (target, from, to).
    let mut out_of_service: Vec<(String, f64, f64)> = Vec::new();
    for _ in 0..n {
        let at = (rng.f64() * before).floor();
        let len = 30.0 + (rng.f64() * 170.0).floor();
        let device = match rng.usize(0..3) {
            1 if !b.doors.is_empty() => {
                Some(format!("door: {}", b.doors[rng.usize(0..b.doors.len())]))
            }
            2 if !b.lifts.is_empty() => Some(format!("lift: {}", b.lifts[0])),
            _ => None,
        };
        let free = |d: &String| {
            !out_of_service
                .iter()
                .any(|(o, from, to)| o == d && at <= *to && *from <= at + len)
        };
        let target = match device.filter(free) {
            Some(d) => {
                out_of_service.push((d.clone(), at, at + len));
                d
            }
            // The first robot of a fleet: `spawn: auto` may keep the others off the floor.
            None if big > 0 && rng.bool() => "robot: big_0".to_string(),
            None => "robot: fleet_0".to_string(),
        };
        let _ = writeln!(out, "  - {{at: {at}s, for: {len}s, {target}}}");
    }
    out
}
