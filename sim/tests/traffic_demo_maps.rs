//! Acceptance 3 of issue 35: the demo maps (../shared/maps) and the scaling scenarios
//! (fixtures/scaling) at fleet sizes from 2 to 64 robots, under the rule of the generated
//! buildings (traffic_props.rs): no task fails, no contact, no dependency cycle, no robot with
//! a task stands still for more than 300 s, a bigger fleet completes at least 95 % of what
//! any smaller one did, and every robot asked is on the floor unless the report says the
//! building has no room for it (S0211, `reserve`).
//!
//! On each graph of each demo map, TinyRobots get a stream of loops between random named
//! places of that graph, one every few seconds: more than any fleet serves, so every robot
//! on the floor has work (the kind of run a planner asks "how many robots can it take?"
//! with). The scaling scenarios keep their own task mixes, with their fleets scaled together.
//!
//! Briefly in CI: the demo maps at 2, 8 and 32 robots for 15 simulated minutes, the
//! scaling scenarios at 2 and 8 robots for 4 minutes, and the airport terminal's at 32 and
//! 64 for an hour. As of 2026-12-04 (BENCHMARKS.md) the demo maps hold the rule at 2-64
//! robots for 120 minutes, with four seeds and four task mixes, and the scaling scenarios
//! at 2-64 robots for 60 minutes. Long on
//! demand: `MAPC_DEMO_SIZES=2,4,8,16,32,64 MAPC_DEMO_MINUTES=120 cargo test -p mapc-sim
//! --release --test traffic_demo_maps -- --nocapture` (`MAPC_DEMO_ONLY=clinic` picks runs
//! by name, `MAPC_DEMO_DUMP=DIR` writes each run's scenario and report there,
//! `MAPC_DEMO_MAPS=DIR` takes the maps from DIR/<name>/<name>.building.yaml instead,
//! skipping invalid ones: your
//! own buildings under the same rule; `MAPC_DEMO_SEED=N` draws the demo maps' task streams
//! from another seed: other task mixes on the same maps; `MAPC_DEMO_TASKS=go_to_place` or
//! `mixed` sends robots to places where they stay, or mixes those with loops, and
//! `delivery` makes deliveries between the places, with a dispenser and an ingestor at each,
//! and `rounds` loops of one to three rounds;
//! `MAPC_DEMO_EVERY=S` sends a task every S seconds instead of 3: a stream some fleets
//! keep up with).

#[path = "support/places.rs"]
mod places;

use mapc_sim::{parse_scenario, simulate, Report, RunOptions};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// `MAPC_DEMO_SIZES`, or `default`.
fn sizes(default: &[usize]) -> Vec<usize> {
    std::env::var("MAPC_DEMO_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| default.to_vec())
}

/// `MAPC_DEMO_MINUTES`, or `default`.
fn minutes(default: f64) -> f64 {
    env_or("MAPC_DEMO_MINUTES", default)
}

/// Whether the run called `name` is one to do (`MAPC_DEMO_ONLY`: a part of the name).
fn wanted(name: &str) -> bool {
    std::env::var("MAPC_DEMO_ONLY").map_or(true, |only| name.contains(&only))
}

/// One run: robots asked, and its report.
struct Run {
    asked: usize,
    report: Report,
}

fn run(name: &str, building: &mapc_ir::Building, text: &str, dir: &Path) -> Report {
    try_run(name, building, text, dir).unwrap_or_else(|e| panic!("{name}: {e:?}"))
}

/// [`run`], or why the runtime refused the scenario.
fn try_run(
    name: &str,
    building: &mapc_ir::Building,
    text: &str,
    dir: &Path,
) -> Result<Report, mapc_sim::SimError> {
    let file: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let dump = std::env::var_os("MAPC_DEMO_DUMP").map(PathBuf::from);
    if let Some(out) = &dump {
        // For a look with `mapc sim` (add the `map:` line): each run's scenario.
        let _ = std::fs::create_dir_all(out);
        let _ = std::fs::write(out.join(format!("{file}.scenario.yaml")), text);
    }
    let (scenario, diags) = parse_scenario(mapc_ir::FileId(1), text, dir);
    let scenario = scenario.unwrap_or_else(|| panic!("{name}: {diags:#?}\n{text}"));
    let started = std::time::Instant::now();
    let r = simulate(building, &scenario, RunOptions::default())?;
    if std::env::var_os("MAPC_DEMO_VERBOSE").is_some() {
        eprintln!(
            "{name}: {} completed, {} on the floor, {:.1} s",
            completed(&r),
            r.robots.len(),
            started.elapsed().as_secs_f64()
        );
    }
    if let Some(out) = &dump {
        // And what `mapc sim --report` would write of it.
        let path = out.join(format!("{file}.report.json"));
        let _ = std::fs::write(path, serde_json::to_string(&r).unwrap_or_default());
    }
    Ok(r)
}

fn completed(r: &Report) -> usize {
    r.tasks.iter().filter(|t| t.result == "completed").count()
}

/// Everything that breaks the rule in the runs of one map or scenario (sizes ascending).
fn problems(name: &str, runs: &[Run]) -> Vec<String> {
    let mut out = Vec::new();
    for run in runs {
        let r = &run.report;
        let what = format!("{name}, {} robots", run.asked);
        let failed: Vec<_> = r.tasks.iter().filter(|t| t.result == "failed").collect();
        if let Some(t) = failed.first() {
            out.push(format!(
                "{what}: {} tasks failed, first {} ({})",
                failed.len(),
                t.id,
                t.detail
            ));
        }
        if let Some(c) = r.contacts.first() {
            out.push(format!(
                "{what}: {} contacts, first {c:?}",
                r.contacts.len()
            ));
        }
        if r.traffic.cycles > 0 {
            out.push(format!("{what}: {} dependency cycles", r.traffic.cycles));
        }
        // The throughput bound's demands are lower bounds (sim/src/report/bound.rs).
        for x in r.throughput.iter().flat_map(|b| &b.resources) {
            if x.used > 1.0 + 1e-9 {
                out.push(format!(
                    "{what}: the completed tasks needed {:.3} of {}'s capacity",
                    x.used, x.resource
                ));
            }
        }
        let still: Vec<_> = r.stuck.iter().filter(|s| s.reason == "no_motion").collect();
        if let Some(s) = still.first() {
            out.push(format!(
                "{what}: {} robots stood still, first {s:?}",
                still.len()
            ));
        }
        let reserve: usize = r.fleets.iter().map(|f| f.reserve).sum();
        let said = r.warnings.iter().any(|w| w.code == "S0211");
        if r.robots.len() + reserve != run.asked || (reserve > 0 && !said) {
            out.push(format!(
                "{what}: {} on the floor and {reserve} in reserve{}",
                r.robots.len(),
                if said { "" } else { " without S0211" }
            ));
        }
    }
    for (i, small) in runs.iter().enumerate() {
        for big in &runs[i + 1..] {
            let (a, b) = (completed(&small.report), completed(&big.report));
            // Asking more robots than the building holds changes nothing.
            let placed = |r: &Report| {
                let capped = r.fleets.iter().any(|f| f.reserve > 0);
                capped.then(|| r.fleets.iter().map(|f| f.robots).collect::<Vec<_>>())
            };
            if placed(&small.report).is_some()
                && placed(&small.report) == placed(&big.report)
                && a != b
            {
                out.push(format!(
                    "{name}: {} and {} robots asked, {} on the floor each, completed {a} and {b}",
                    small.asked,
                    big.asked,
                    big.report.robots.len()
                ));
            }
            if (b as f64) < 0.95 * a as f64 - 1.0 {
                out.push(format!(
                    "{name}: {} robots ({} on the floor) completed {b}, fewer than {} robots ({} on the floor) with {a}",
                    big.asked,
                    big.report.robots.len(),
                    small.asked,
                    small.report.robots.len()
                ));
            }
        }
    }
    out
}

/// A saturating stream on graph `graph`: `robots` TinyRobots and a task every 3 s
/// (`MAPC_DEMO_EVERY`): a loop between two random places, or
/// (`MAPC_DEMO_TASKS=go_to_place`) a go-to-place to a random place, after which the robot
/// stays there until it is sent elsewhere or the place is needed, or (`mixed`) either, at
/// random, or (`delivery`) a delivery between two random places, each with a dispenser and
/// an ingestor of the scenario's, or (`rounds`) loops of one to three rounds.
fn stream(places: &[String], graph: i64, robots: usize, minutes: f64, seed: u64) -> String {
    let mix = std::env::var("MAPC_DEMO_TASKS").unwrap_or_else(|_| "loop".into());
    let kinds = match mix.as_str() {
        "go_to_place" => "go_to_place",
        "mixed" => "loop, go_to_place",
        "delivery" => "delivery",
        _ => "loop",
    };
    let every = env_or("MAPC_DEMO_EVERY", 3.0_f64).max(0.1);
    let mut rng = fastrand::Rng::with_seed(seed);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "seed: {seed}\nduration: {}s\nstep: 0.05",
        minutes * 60.0
    );
    let _ = writeln!(out, "crowd: {{enabled: false}}");
    let _ = writeln!(
        out,
        "fleets:\n  - {{name: tiny, graph: {graph}, robot: TinyRobot, count: {robots}, spawn: auto, tasks: [{kinds}]}}"
    );
    if mix == "delivery" {
        // Names no map has (the map's own dispensers and ingestors keep theirs: S0308).
        let _ = writeln!(out, "workcells:");
        for p in places {
            let (d, i) = (
                q(&format!("stream_{p}_dispenser")),
                q(&format!("stream_{p}_ingestor")),
            );
            let p = q(p);
            let _ = writeln!(out, "  - {{name: {d}, kind: dispenser, waypoint: {p}}}");
            let _ = writeln!(out, "  - {{name: {i}, kind: ingestor, waypoint: {p}}}");
        }
    }
    let _ = writeln!(out, "tasks:");
    for k in 0..(minutes * 60.0 / every) as usize {
        let a = rng.usize(0..places.len());
        let c = (a + 1 + rng.usize(0..places.len() - 1)) % places.len();
        if mix == "delivery" {
            let (a, c) = (&places[a], &places[c]);
            let _ = writeln!(
                out,
                "  - {{at: {}s, delivery: {{pickup: {}, dropoff: {}, dispenser: {}, ingestor: {}}}}}",
                k as f64 * every,
                q(a),
                q(c),
                q(&format!("stream_{a}_dispenser")),
                q(&format!("stream_{c}_ingestor"))
            );
            continue;
        }
        let go = match mix.as_str() {
            "go_to_place" => true,
            "mixed" => rng.bool(),
            _ => false,
        };
        if go {
            let _ = writeln!(
                out,
                "  - {{at: {}s, go_to_place: {{place: {}}}}}",
                k as f64 * every,
                q(&places[c])
            );
            continue;
        }
        // `rounds`: loops of one to three rounds (a longer task, back and forth).
        let loops = if mix == "rounds" {
            1 + rng.usize(0..3)
        } else {
            1
        };
        let _ = writeln!(
            out,
            "  - {{at: {}s, loop: {{start: {}, finish: {}, loops: {loops}}}}}",
            k as f64 * every,
            q(&places[a]),
            q(&places[c])
        );
    }
    out
}

/// `s` as a YAML scalar: double-quoted, so that names with spaces, colons or quotes
/// (public maps have ` ingestor_bay1`) reach the scenario as the map spells them.
fn q(s: &str) -> String {
    serde_json::to_string(s).expect("a string")
}

/// The maps in `dir`: each `<name>/<name>.building.yaml`.
fn demo_maps(dir: &Path) -> Vec<PathBuf> {
    let mut maps: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("maps")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter_map(|d| {
            let name = d.file_name()?.to_str()?.to_string();
            Some(d.join(format!("{name}.building.yaml")))
        })
        .filter(|p| p.is_file())
        .collect();
    maps.sort();
    maps
}

#[test]
fn demo_maps_take_every_fleet_size() {
    let own = std::env::var_os("MAPC_DEMO_MAPS").map(PathBuf::from);
    let Some(dir) = own
        .clone()
        .or_else(|| places::shared("maps").map(|s| s.join("maps")))
    else {
        eprintln!("skipped: ../shared not found");
        return;
    };
    let mut all = Vec::new();
    let mut runs_done = 0;
    for path in demo_maps(&dir) {
        let map = match (mapc_frontend::load(&path), &own) {
            (Ok(m), _) => m,
            (Err(e), Some(_)) => {
                eprintln!("{}: {e:?}, skipped", path.display());
                continue;
            }
            (Err(e), None) => panic!("{}: {e:?}", path.display()),
        };
        let building = match (map.valid_building(), &own) {
            (Some(b), _) => b,
            (None, Some(_)) => {
                eprintln!("{}: not a valid map, skipped", path.display());
                continue;
            }
            (None, None) => panic!("{}: not a valid demo map", path.display()),
        };
        let stem = path
            .file_stem()
            .unwrap()
            .to_string_lossy()
            .replace(".building", "");
        for g in building.graph_indices() {
            let name = format!("{stem} graph {g}");
            let places = places::places(building, g);
            if places.len() < 2 || !wanted(&name) {
                continue;
            }
            let mut runs = Vec::new();
            for n in sizes(&[2, 8, 32]) {
                let seed = env_or("MAPC_DEMO_SEED", 35u64) + g as u64;
                let text = stream(&places, g, n, minutes(15.0), seed);
                let what = format!("{name}, {n} robots");
                let report = match try_run(&what, building, &text, Path::new(".")) {
                    Ok(r) => r,
                    // A map of your own whose graph cannot hold the smallest fleet (the
                    // runtime says why, S0202: one-way lanes only, say) is not a fleet map.
                    Err(mapc_sim::SimError::Invalid(d))
                        if own.is_some()
                            && runs.is_empty()
                            && d.iter().all(|x| x.code == "S0202") =>
                    {
                        eprintln!("{what}: {}, skipped", d[0].message);
                        break;
                    }
                    Err(e) => panic!("{what}: {e:?}"),
                };
                runs.push(Run { asked: n, report });
                runs_done += 1;
            }
            all.extend(problems(&name, &runs));
        }
    }
    assert!(runs_done > 0 || std::env::var_os("MAPC_DEMO_ONLY").is_some());
    assert!(
        all.is_empty(),
        "{} problems:\n{}",
        all.len(),
        all.join("\n")
    );
}

/// `text` with its fleets' `count`s scaled together to `n` robots (each at least 1, the
/// remainders to the first fleets) and its duration set; and the robots it asks for.
fn scaled(text: &str, n: usize, minutes: f64) -> (String, usize) {
    let count = |line: &str| -> Option<usize> {
        let at = line.find("count: ")? + "count: ".len();
        line[at..]
            .split(|c: char| !c.is_ascii_digit())
            .next()?
            .parse()
            .ok()
    };
    let counts: Vec<usize> = text.lines().filter_map(count).collect();
    let total: usize = counts.iter().sum();
    let mut new: Vec<usize> = counts.iter().map(|c| (c * n / total).max(1)).collect();
    let mut k = 0;
    while new.iter().sum::<usize>() < n {
        let at = k % new.len();
        new[at] += 1;
        k += 1;
    }
    let mut out = String::new();
    let mut fleet = 0;
    for line in text.lines() {
        if let Some(c) = count(line) {
            let _ = writeln!(
                out,
                "{}",
                line.replacen(&format!("count: {c}"), &format!("count: {}", new[fleet]), 1)
            );
            fleet += 1;
        } else if line.starts_with("duration:") {
            let _ = writeln!(out, "duration: {}s", minutes * 60.0);
        } else {
            let _ = writeln!(out, "{line}");
        }
    }
    (out, new.iter().sum())
}

#[test]
fn scaling_scenarios_take_every_fleet_size() {
    if places::shared("maps").is_none() {
        eprintln!("skipped: ../shared not found");
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scaling");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("fixtures/scaling")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .collect();
    files.sort();
    let mut all = Vec::new();
    for file in files {
        let name = file.file_name().unwrap().to_string_lossy().to_string();
        if !wanted(&name) {
            continue;
        }
        all.extend(scaling_problems(&file, &sizes(&[2, 8]), minutes(4.0)));
    }
    assert!(
        all.is_empty(),
        "{} problems:\n{}",
        all.len(),
        all.join("\n")
    );
}

/// What breaks the rule in the runs of scaling scenario `file` at `sizes` robots for
/// `minutes`.
fn scaling_problems(file: &Path, sizes: &[usize], minutes: f64) -> Vec<String> {
    let name = file.file_name().unwrap().to_string_lossy().to_string();
    let dir = file.parent().expect("fixtures/scaling");
    let text = std::fs::read_to_string(file).expect("scenario");
    let map = text
        .lines()
        .find_map(|l| l.strip_prefix("map: "))
        .expect("map line");
    let map = mapc_frontend::load(&dir.join(map.trim())).expect("map");
    let building = map.valid_building().expect("valid demo map");
    let mut runs = Vec::new();
    for &n in sizes {
        let (text, asked) = scaled(&text, n, minutes);
        let report = run(&format!("{name}, {asked} robots"), building, &text, dir);
        runs.push(Run { asked, report });
    }
    problems(&name, &runs)
}

/// The airport terminal's scaling scenario for an hour at 32 and 64 robots: its tasks are
/// few (about 55 an hour), and with 45 robots on the floor they waited in the queue for
/// minutes, every free robot's plan refused for waiting at its parking spot for others to
/// pass (45 tasks at 64 robots, 49 at 32; `Fleets::dispatch`).
#[test]
fn the_airport_terminal_takes_64_robots_for_an_hour() {
    if places::shared("maps").is_none() {
        eprintln!("skipped: ../shared not found");
        return;
    }
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/scaling/airport_terminal.scenario.yaml");
    let all = scaling_problems(&file, &[32, 64], 60.0);
    assert!(all.is_empty(), "{}", all.join("\n"));
}

#[test]
fn scaling_keeps_the_proportions_and_the_total() {
    let text = "duration: 4h\nfleets:\n  - {name: a, count: 3}\n  - {name: b, count: 1}\n";
    let (out, asked) = scaled(text, 8, 2.0);
    assert!(out.contains("{name: a, count: 6}"), "{out}");
    assert!(out.contains("{name: b, count: 2}"), "{out}");
    assert!(out.contains("duration: 120s"), "{out}");
    assert_eq!(asked, 8);
    let (out, asked) = scaled(text, 2, 2.0);
    assert!(out.contains("{name: a, count: 1}") && out.contains("{name: b, count: 1}"));
    assert_eq!(asked, 2);
    // Every fleet keeps a robot, so three fleets ask for three at least.
    let three = format!("{text}  - {{name: c, count: 1}}\n");
    assert_eq!(scaled(&three, 2, 2.0).1, 3);
}
