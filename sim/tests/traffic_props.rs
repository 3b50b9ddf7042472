//! Traffic property test (issue 35): on generated buildings (corridors, dead-end rooms,
//! doors, one-way loops, one to three levels joined by a lift, half of them turned off the
//! axes, a third with a second fleet of bigger robots; some not well-formed), a
//! saturating stream of loops between random places at 1, 2, 4, 8, 16 and 32 robots:
//! no task fails, no contact, no robot with a task stands still for more than 300 s, no
//! dependency cycle, and a bigger fleet completes at least 95 % of what any smaller one did.
//! Where the building holds fewer robots than asked, asking more changes nothing: runs with
//! the same robots on the floor complete the same tasks. The same on generated warehouses
//! (aisles joined by cross aisles, no dead ends: `MAPC_TRAFFIC_GRIDS`, default 6), and
//! with other task mixes on the same buildings: go-to-place tasks, after which a robot
//! stays at its place, alone or mixed with loops, and deliveries (`MAPC_TRAFFIC_MIX_CASES`,
//! default 60).
//!
//! Briefly in CI (`MAPC_TRAFFIC_CASES`, default 200 buildings of 8 simulated minutes at 1,
//! 4 and 16 robots; shorter runs measure the start more than the traffic); long on demand:
//! `MAPC_TRAFFIC_CASES=200 MAPC_TRAFFIC_MINUTES=60 MAPC_TRAFFIC_SIZES=1,2,4,8,16,32 cargo test
//! -p mapc-sim --release --test traffic_props -- --nocapture`. `MAPC_TRAFFIC_VERBOSE=1`
//! prints each building's counts; `MAPC_TRAFFIC_DUMP=<dir>` writes each run's map,
//! scenario (for `mapc sim`) and report.

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

/// The fleet sizes of `MAPC_TRAFFIC_SIZES` (comma-separated), else `default`.
fn sizes_or(default: &[usize]) -> Vec<usize> {
    std::env::var("MAPC_TRAFFIC_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| default.to_vec())
}

/// Runs `robots` robots on generated building `b` for `minutes` with a task every `every` s.
fn run(b: &gen::Building, robots: usize, minutes: f64, every: f64) -> Report {
    run_with(b, robots, minutes, every, "", gen::Mix::Loops)
}

/// [`run`] with extra scenario lines (`faults:`) and the tasks of `mix`.
fn run_with(
    b: &gen::Building,
    robots: usize,
    minutes: f64,
    every: f64,
    extra: &str,
    mix: gen::Mix,
) -> Report {
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
    let text = gen::scenario_mix(b, robots, minutes * 60.0, every, b.seed, mix);
    let text = format!("step: 0.05\n{text}{extra}");
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
    let r = match simulate(building, &scenario, RunOptions::default()) {
        Ok(r) => r,
        Err(e) => panic!("building {} with {robots} robots: {e:?}", b.seed),
    };
    if let Some(dir) = std::env::var_os("MAPC_TRAFFIC_DUMP") {
        // And what `mapc sim --report` would write of it.
        let path = Path::new(&dir).join(format!("gen_{}_{robots}.report.json", b.seed));
        let _ = std::fs::write(path, serde_json::to_string(&r).unwrap_or_default());
    }
    r
}

fn completed(r: &Report) -> usize {
    r.tasks.iter().filter(|t| t.result == "completed").count()
}

/// No failed task, no contact, no dependency cycle.
fn check_safe(r: &Report, what: &str) {
    let failed: Vec<_> = r.tasks.iter().filter(|t| t.result == "failed").collect();
    assert!(failed.is_empty(), "{what}: failed tasks {failed:?}");
    assert!(r.contacts.is_empty(), "{what}: contacts {:?}", r.contacts);
    assert_eq!(r.traffic.cycles, 0, "{what}: dependency cycles");
    // The planner's counts add up: no plan both failed and was taken, and every task given
    // to a robot took a plan.
    let t = &r.traffic;
    assert!(t.plans_failed + t.plans_taken <= t.plans, "{what}: {t:?}");
    let assigned = r.tasks.iter().filter(|k| k.assigned.is_some()).count() as u64;
    assert!(
        t.plans_taken >= assigned,
        "{what}: {assigned} tasks assigned, {t:?}"
    );
    check_bound(r, what);
}

/// The throughput bound's demands are lower bounds: what the completed tasks needed of a
/// resource at least never exceeds its capacity over the run, and no run beats the rate
/// tasks arrived at.
fn check_bound(r: &Report, what: &str) {
    let Some(b) = &r.throughput else {
        return;
    };
    for x in &b.resources {
        assert!(
            x.used <= 1.0 + 1e-9,
            "{what}: the completed tasks needed {:.3} of {}'s capacity",
            x.used,
            x.resource
        );
    }
    assert!(
        b.achieved_per_hour <= b.arrivals_per_hour + 1e-9,
        "{what}: {b:?}"
    );
}

/// Checks one building at every size, with a task of `mix` every `every` s: the completed
/// counts, and what broke the rule: a robot with a task that stood still, a fleet that
/// completed less than 95 % of a smaller one's (a failed task, a contact or a cycle panics
/// at once).
fn check_building_every(
    b: &gen::Building,
    sizes: &[usize],
    minutes: f64,
    every: f64,
    mix: gen::Mix,
) -> (Vec<usize>, Vec<String>) {
    let seed = b.seed;
    let mut done: Vec<usize> = Vec::new();
    let mut robots_on_floor: Vec<usize> = Vec::new();
    let mut placed = Vec::new();
    let mut fewer = Vec::new();
    for &n in sizes {
        let r = run_with(b, n, minutes, every, "", mix);
        check_safe(&r, &format!("building {seed}, {n} robots"));
        let still: Vec<_> = r.stuck.iter().filter(|s| s.reason == "no_motion").collect();
        if !still.is_empty() {
            fewer.push(format!(
                "building {seed}, {n} robots: robots stood still {still:?}"
            ));
        }
        done.push(completed(&r));
        robots_on_floor.push(r.robots.len());
        // Robots on the floor per fleet, and whether the building held fewer than asked.
        placed.push((
            r.fleets.iter().map(|f| f.robots).collect::<Vec<_>>(),
            r.fleets.iter().any(|f| f.reserve > 0),
        ));
        if std::env::var_os("MAPC_TRAFFIC_VERBOSE").is_some() {
            if let Some(b) = &r.throughput {
                eprintln!(
                    "bound {seed} {n}: {:.1} tasks/h by {}, achieved {:.1} ({:.2})",
                    b.tasks_per_hour, b.limited_by, b.achieved_per_hour, b.share
                );
            }
        }
    }
    // A bigger fleet completes at least 95 % of what any smaller one did (same stream).
    for i in 0..sizes.len() {
        for j in i + 1..sizes.len() {
            // Asking more robots than the building holds changes nothing: the same robots
            // on the floor, the same run.
            let same = placed[i].1 && placed[j].1 && placed[i].0 == placed[j].0;
            if same && done[i] != done[j] {
                fewer.push(format!(
                    "building {seed}: {} and {} robots asked, {} on the floor each, completed {} and {}",
                    sizes[i], sizes[j], robots_on_floor[i], done[i], done[j]
                ));
            }
            if (done[j] as f64) < 0.95 * done[i] as f64 - 1.0 {
                fewer.push(format!(
                    "building {seed}: {} robots ({} on the floor) completed {}, fewer than {} robots ({} on the floor) with {}",
                    sizes[j],
                    robots_on_floor[j],
                    done[j],
                    sizes[i],
                    robots_on_floor[i],
                    done[i]
                ));
            }
        }
    }
    (done, fewer)
}

#[test]
fn generated_buildings_never_deadlock() {
    check_generated(env_or("MAPC_TRAFFIC_CASES", 200), |_| gen::Mix::Loops);
}

/// Other task mixes on the generated buildings, by building in turn: go-to-place tasks
/// (the robot stays at the place until another task, or a robot the place is needed for,
/// sends it on), those and loops at random, and deliveries between the places (a dispenser
/// and an ingestor at each, one item per dispenser); the same checks and rule. Briefly in
/// CI (`MAPC_TRAFFIC_MIX_CASES`, default 60 buildings of 8 minutes at 1, 4 and 16 robots),
/// long on demand with the sizes and minutes as above. Go-to-place streams on a public map
/// found a robot that stood at its place for good, its task never done: a task planned
/// after a traversal the robot had been sent along counted that traversal in its first
/// leg, and it ended before the task's first step began (`Fleets::reach_next`).
#[test]
fn other_task_mixes_never_deadlock() {
    check_generated(env_or("MAPC_TRAFFIC_MIX_CASES", 60), |seed| {
        match seed % 3 {
            0 => gen::Mix::GoTo,
            1 => gen::Mix::Mixed,
            _ => gen::Mix::Deliveries,
        }
    });
}

/// Two generated buildings where a bigger fleet completed less, each a corridor between
/// task places at its dead ends, with loops and go-to-places mixed, for an hour at 1 to 3
/// robots: robots free in one dispatch round each took a task, the second's plan waiting
/// behind the first's where the first would have done both in turn, and a free robot's
/// plan that waited for the others to reach the task's first place counted as no worse
/// than a busy robot about to be done there. Building 190 completed 193 tasks with one
/// robot, 178 with two; building 52, 217 with two robots, 205 with three (`Fleets::dispatch`).
#[test]
fn a_second_robot_on_one_corridor_does_not_hold_the_first_up() {
    for seed in [52, 190] {
        let b = gen::building(seed);
        let (done, fewer) = check_building_every(&b, &[1, 2, 3], 60.0, 10.0, gen::Mix::Mixed);
        assert!(
            fewer.is_empty(),
            "building {seed}: {done:?}\n{}",
            fewer.join("\n")
        );
    }
}

/// A generated building never run before the rule was written (a TinyRobot and a
/// DeliveryRobot fleet, deliveries between two rooms at the dead ends of one corridor):
/// with a second Tiny, the Tinies took the deliveries while the DeliveryRobot stood idle
/// for half the hour, its plans refused for waiting on them, and three robots completed 89
/// tasks where two completed 101. A slower robot now leaves a task to a faster one refused
/// it for traffic (`Dispatcher::yield_to_faster`).
#[test]
fn a_slower_robot_leaves_the_corridor_to_a_faster_one() {
    let b = gen::building(569);
    let (done, fewer) = check_building_every(&b, &[1, 2, 3], 60.0, 10.0, gen::Mix::Deliveries);
    assert!(fewer.is_empty(), "{done:?}\n{}", fewer.join("\n"));
}

/// Runs `cases` generated buildings from `MAPC_TRAFFIC_FIRST` (default 0), each with the
/// task mix `mix_of` gives its seed, for `MAPC_TRAFFIC_MINUTES` (default 8) at
/// `MAPC_TRAFFIC_SIZES` (default 1, 4, 16) robots, and asserts the rule on all of them:
/// every building runs, so one run names every building that breaks it.
fn check_generated(cases: u64, mix_of: impl Fn(u64) -> gen::Mix) {
    let minutes: f64 = env_or("MAPC_TRAFFIC_MINUTES", 8.0);
    let sizes = sizes_or(&[1, 4, 16]);
    let first: u64 = env_or("MAPC_TRAFFIC_FIRST", 0);
    let mut fewer = Vec::new();
    for seed in first..first + cases {
        let mix = mix_of(seed);
        let (done, f) = check_building_every(&gen::building(seed), &sizes, minutes, 10.0, mix);
        if std::env::var_os("MAPC_TRAFFIC_VERBOSE").is_some() {
            match mix {
                gen::Mix::Loops => eprintln!("building {seed}: completed {done:?} at {sizes:?}"),
                _ => eprintln!("building {seed} ({mix:?}): completed {done:?} at {sizes:?}"),
            }
        }
        fewer.extend(f);
    }
    assert!(
        fewer.is_empty(),
        "{} breaches of the rule in {cases} buildings:\n{}",
        fewer.len(),
        fewer.join("\n")
    );
}

/// Generated warehouses (`gen::grid`: aisles joined by cross aisles, no dead ends, tasks
/// between racks and stations): the same checks and rule as the generated buildings. In CI
/// 6 of them at 4 and 16 robots for 8 minutes, a task every 2 s. Long runs on demand
/// (`MAPC_TRAFFIC_GRIDS`, `MAPC_TRAFFIC_EVERY`, and the sizes and minutes as above) still
/// find breaches: with 60 minutes, a task every second and 8 to 128 robots, grids 2, 4
/// and 5 complete 92-94 % of what 32 robots did once every parking vertex is taken (grid
/// 4: 587 tasks with 54 robots on the floor against 638 with 32; BENCHMARKS.md).
/// `MAPC_TRAFFIC_HOTSPOT=1` sends every task to a station (`gen::grid_to_stations`); 4 of
/// the 6 break the rule then from 32 to 64 robots, a task a second, 60 minutes (grid 5:
/// 319 to 265 tasks): not fixed yet, so not in CI (BENCHMARKS.md).
#[test]
fn generated_warehouses_never_deadlock() {
    // `MAPC_TRAFFIC_HOTSPOT=1`: every task goes to a station.
    if std::env::var_os("MAPC_TRAFFIC_HOTSPOT").is_some() {
        check_warehouses("grid", gen::grid_to_stations, 6);
    } else {
        check_warehouses("grid", gen::grid, 6);
    }
}

/// Generated warehouses of one-way aisles with bays (`gen::grid_bays`, where idle robots
/// stand out of the aisles, as in the 1,000-robot benchmark): the same checks and rule. In
/// CI 4 of them (`MAPC_TRAFFIC_BAYS`), as above.
#[test]
fn generated_bay_warehouses_never_deadlock() {
    check_warehouses("bays", gen::grid_bays, 4);
}

/// The checks and rule on `MAPC_TRAFFIC_GRIDS` (for `bays`: `MAPC_TRAFFIC_BAYS`, else
/// `cases`) warehouses made by `make`.
fn check_warehouses(what: &str, make: fn(u64) -> gen::Building, cases: u64) {
    let var = if what == "bays" {
        "MAPC_TRAFFIC_BAYS"
    } else {
        "MAPC_TRAFFIC_GRIDS"
    };
    let cases: u64 = env_or(var, cases);
    let minutes: f64 = env_or("MAPC_TRAFFIC_MINUTES", 8.0);
    let sizes = sizes_or(&[4, 16]);
    let first: u64 = env_or("MAPC_TRAFFIC_FIRST", 0);
    // A task every 2 s: more than 32 robots serve in these warehouses.
    let every: f64 = env_or("MAPC_TRAFFIC_EVERY", 2.0);
    let mut fewer = Vec::new();
    for seed in first..first + cases {
        let b = make(seed);
        let (done, f) = check_building_every(&b, &sizes, minutes, every, gen::Mix::Loops);
        if std::env::var_os("MAPC_TRAFFIC_VERBOSE").is_some() {
            eprintln!(
                "{what} {seed} ({} waypoints): completed {done:?} at {sizes:?}",
                b.waypoints
            );
        }
        fewer.extend(f);
    }
    assert!(
        fewer.is_empty(),
        "{} breaches of the rule in {cases} warehouses:\n{}",
        fewer.len(),
        fewer.join("\n")
    );
}

/// Tasks completed in `[from, to)`.
fn completed_between(r: &Report, from: f64, to: f64) -> usize {
    r.tasks
        .iter()
        .filter(|t| t.result == "completed")
        .filter(|t| t.finished.is_some_and(|f| from <= f && f < to))
        .count()
}

/// Acceptance 2 of issue 35: the same runs with random faults (robots paused, doors and
/// the lift out of service, 30 to 200 s each, all within the first third of the run). No
/// contact, no cycle, no failed task (no fault outlasts the 300 s a robot waits for a door
/// or a lift); once the last fault has ended, nobody with a task stands still for 300 s;
/// and in the last half of the run throughput is back to the fault-free run's: over all
/// buildings at least 90 % of the fault-free runs' tasks in the same window (less three),
/// and in each at least half (less one).
///
/// Why summed: one building's last half holds about ten tasks, and which ten depends on
/// where the queue stood when the faults ended (a task between levels takes three times
/// one on a level). Pausing one robot of building 27 for 30 to 171 s alone moves its last
/// half between 9 and 11 tasks against 11, and the per-building rule of 75 % failed on
/// such draws while the forty buildings together completed 98.6 % of the fault-free
/// tasks. The sum measures the rate; the per-building floor still catches a building
/// whose robots do not recover.
#[test]
fn faults_delay_robots_but_never_deadlock() {
    let cases: u64 = env_or("MAPC_TRAFFIC_FAULT_CASES", 40);
    let first: u64 = env_or("MAPC_TRAFFIC_FIRST", 0);
    let minutes: f64 = env_or("MAPC_TRAFFIC_FAULT_MINUTES", 20.0);
    let robots: usize = env_or("MAPC_TRAFFIC_FAULT_ROBOTS", 4);
    let end = minutes * 60.0;
    let (mut with_all, mut without_all) = (0, 0);
    for seed in first..first + cases {
        let b = gen::building(seed);
        let faults = gen::faults(&b, robots, end / 3.0, 4, seed);
        let clean = run(&b, robots, minutes, 10.0);
        let r = run_with(&b, robots, minutes, 10.0, &faults, gen::Mix::Loops);
        check_safe(&r, &format!("building {seed} with\n{faults}"));
        // The faults all end by a third of the run plus 200 s.
        let over = end / 3.0 + 200.0;
        let still: Vec<_> = r
            .stuck
            .iter()
            .filter(|s| s.reason == "no_motion" && s.until - s.t.max(over) > 300.0)
            .collect();
        assert!(
            still.is_empty(),
            "building {seed}: robots stood still after the faults {still:?}\n{faults}"
        );
        let (a, z) = (end / 2.0, end);
        let (with, without) = (completed_between(&r, a, z), completed_between(&clean, a, z));
        assert!(
            with as f64 >= 0.5 * without as f64 - 1.0,
            "building {seed}: {with} tasks in the last half after faults, {without} without\n{faults}"
        );
        if std::env::var_os("MAPC_TRAFFIC_VERBOSE").is_some() {
            eprintln!("building {seed}: last half {with} with faults, {without} without");
        }
        with_all += with;
        without_all += without;
    }
    eprintln!("last halves: {with_all} tasks with faults, {without_all} without");
    assert!(
        with_all as f64 >= 0.9 * without_all as f64 - 3.0,
        "buildings {first}..{}: {with_all} tasks in the last halves after faults, {without_all} without",
        first + cases
    );
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
