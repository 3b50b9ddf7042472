//! Traffic property test (issue 35): on generated buildings (corridors, dead-end rooms,
//! doors, one-way loops, one to three levels joined by a lift; some not well-formed), a
//! saturating stream of loops between random places at 1, 2, 4, 8, 16 and 32 robots:
//! no task fails, no contact, no robot with a task stands still for more than 300 s, no
//! dependency cycle, and a bigger fleet completes at least 95 % of what any smaller one did.
//!
//! Briefly in CI (`MAPC_TRAFFIC_CASES`, default 200 buildings of a few simulated minutes at
//! a few sizes each); long on demand:
//! `MAPC_TRAFFIC_CASES=200 MAPC_TRAFFIC_MINUTES=60 MAPC_TRAFFIC_SIZES=1,2,4,8,16,32 cargo test
//! -p mapc-sim --release --test traffic_props -- --nocapture`.

mod support;

use mapc_sim::{parse_scenario, simulate, Report, RunOptions};
use std::path::Path;
use support::gen;

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Runs `robots` robots on generated building `b` for `minutes` with a task every `every` s.
fn run(b: &gen::Building, robots: usize, minutes: f64, every: f64) -> Report {
    let parsed = mapc_frontend::parse_str("gen.building.yaml", &b.yaml);
    let building = parsed.valid_building().unwrap_or_else(|| {
        panic!(
            "generated building {} does not load: {:?}\n{}",
            b.seed,
            parsed
                .diagnostics
                .iter()
                .filter(|d| d.is_error())
                .collect::<Vec<_>>(),
            b.yaml
        )
    });
    let text = gen::scenario(b, robots, minutes * 60.0, every, b.seed);
    let text = format!("step: 0.05\n{text}");
    if let Some(dir) = std::env::var_os("MAPC_TRAFFIC_DUMP") {
        // For a look with `mapc sim`: the map and the scenario of each run.
        let dir = Path::new(&dir);
        let _ = std::fs::create_dir_all(dir);
        let _ = std::fs::write(dir.join(format!("gen_{}.building.yaml", b.seed)), &b.yaml);
        let _ = std::fs::write(
            dir.join(format!("gen_{}_{robots}.scenario.yaml", b.seed)),
            format!("map: gen_{}.building.yaml\n{text}", b.seed),
        );
    }
    let (scenario, diags) = parse_scenario(mapc_ir::FileId(1), &text, Path::new("."));
    let scenario = scenario.unwrap_or_else(|| panic!("scenario of {}: {diags:?}\n{text}", b.seed));
    match simulate(building, &scenario, RunOptions::default()) {
        Ok(r) => r,
        Err(e) => panic!("building {} with {robots} robots: {e:?}", b.seed),
    }
}

fn completed(r: &Report) -> usize {
    r.tasks.iter().filter(|t| t.result == "completed").count()
}

/// Checks one building at every size; returns the completed counts.
fn check_building(seed: u64, sizes: &[usize], minutes: f64) -> Vec<usize> {
    let b = gen::building(seed);
    let mut done: Vec<usize> = Vec::new();
    let mut robots_on_floor: Vec<usize> = Vec::new();
    for &n in sizes {
        let r = run(&b, n, minutes, 10.0);
        let failed: Vec<_> = r.tasks.iter().filter(|t| t.result == "failed").collect();
        assert!(
            failed.is_empty(),
            "building {seed}, {n} robots: failed tasks {failed:?}"
        );
        assert!(
            r.contacts.is_empty(),
            "building {seed}, {n} robots: contacts {:?}",
            r.contacts
        );
        let still: Vec<_> = r.stuck.iter().filter(|s| s.reason == "no_motion").collect();
        assert!(
            still.is_empty(),
            "building {seed}, {n} robots: robots stood still {still:?}"
        );
        assert_eq!(
            r.traffic.cycles, 0,
            "building {seed}, {n} robots: dependency cycles"
        );
        done.push(completed(&r));
        robots_on_floor.push(r.robots.len());
    }
    // A bigger fleet completes at least 95 % of what any smaller one did (same stream).
    for i in 0..sizes.len() {
        for j in i + 1..sizes.len() {
            assert!(
                done[j] as f64 >= 0.95 * done[i] as f64 - 1.0,
                "building {seed}: {} robots ({} on the floor) completed {}, fewer than {} robots ({} on the floor) with {}",
                sizes[j],
                robots_on_floor[j],
                done[j],
                sizes[i],
                robots_on_floor[i],
                done[i]
            );
        }
    }
    done
}

#[test]
fn generated_buildings_never_deadlock() {
    let cases: u64 = env_or("MAPC_TRAFFIC_CASES", 200);
    let minutes: f64 = env_or("MAPC_TRAFFIC_MINUTES", 4.0);
    let sizes: Vec<usize> = std::env::var("MAPC_TRAFFIC_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![1, 4, 16]);
    let first: u64 = env_or("MAPC_TRAFFIC_FIRST", 0);
    for seed in first..first + cases {
        let done = check_building(seed, &sizes, minutes);
        if std::env::var_os("MAPC_TRAFFIC_VERBOSE").is_some() {
            eprintln!("building {seed}: completed {done:?} at {sizes:?}");
        }
    }
}

#[test]
fn generator_makes_what_it_says() {
    // Real values: levels, places and waypoints follow the shape.
    let b = gen::building_with(
        7,
        &gen::Shape {
            levels: 2,
            junctions: 3,
            sides: 1,
            rooms: 1,
            one_way_loop: false,
            doors: false,
            well_formed: true,
            yaw: 1.0,
        },
    );
    assert_eq!(b.levels, 2);
    let parsed = mapc_frontend::parse_str("g.building.yaml", &b.yaml);
    let building = parsed.valid_building().expect("loads");
    assert_eq!(building.levels.len(), 2);
    assert_eq!(building.lifts.len(), 1);
    // Turned as a whole: the cabin waypoints stay in the (turned) cabin, the lobby 2.5 m
    // away along the building's x axis.
    let lift = building.lifts.iter().next().unwrap().1;
    assert!((lift.yaw.abs() - 1.0).abs() < 1e-9, "{}", lift.yaw);
    let find = |name: &str| {
        let (_, v) = building
            .vertices
            .iter()
            .find(|(_, v)| v.level.index() == 0 && v.name == name)
            .unwrap();
        v.pos
    };
    assert!(lift.shaft_contains(find("cabin_0")));
    assert!((find("lobby_0").minus(find("cabin_0")).norm() - 2.5).abs() < 1e-9);
    assert!(!lift.shaft_contains(find("lobby_0")));
    // Rooms: every junction has its side corridor (j = 0 always; others 3 in 4), one room each.
    assert!(b.places.iter().all(|p| p.starts_with("room_")));
    assert!(b.places.len() >= 2 && b.places.len() <= 6, "{:?}", b.places);
}
