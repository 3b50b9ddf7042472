//! Every RMF fleet adapter config of rmf_demos (../shared/fleet_configs) on its demo map:
//! the fleet runs an hour of a generated requests file (RMF task API, checked against
//! rmf_api_msgs' schemas), its robots start at their chargers with the
//! config's names, and drive within its limits with its footprint (issue 38).

use mapc_sim::{parse_scenario, simulate, RunOptions, SimError};
#[path = "support/places.rs"]
mod places;
#[path = "support/rmf_schemas.rs"]
mod rmf_schemas;
use places::places;
use rmf_schemas::validator;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The demo map a config directory goes with.
fn map_of(dir: &str) -> &str {
    match dir {
        "office_mock_traffic_light" => "office",
        d => d,
    }
}

/// The nav graph on which every robot's start waypoint has a lane.
fn graph_of(b: &mapc_ir::Building, starts: &[String]) -> Option<i64> {
    b.graph_indices().into_iter().find(|&g| {
        starts.iter().all(|s| {
            b.lanes.iter().any(|(_, l)| {
                l.graph == g && [l.start, l.end].iter().any(|&v| b.vertices[v].name == *s)
            })
        })
    })
}

struct Motion {
    first: [f64; 2],
    top_speed: f64,
    top_accel: f64,
}

/// From RobotState messages (2 Hz): first position, top speed (distance between
/// consecutive states on one level), top acceleration along straight stretches.
fn motion(trace: &[u8]) -> BTreeMap<String, Motion> {
    type Last = (f64, f64, f64, String, Option<f64>, Option<(f64, f64)>);
    let mut last: BTreeMap<String, Last> = BTreeMap::new();
    let mut out: BTreeMap<String, Motion> = BTreeMap::new();
    for line in std::str::from_utf8(trace).unwrap().lines() {
        let v: Value = serde_json::from_str(line).unwrap();
        let m = &v["msg"];
        let name = m["name"].as_str().unwrap().to_string();
        let t = v["t"].as_f64().unwrap();
        let l = &m["location"];
        let (x, y) = (l["x"].as_f64().unwrap(), l["y"].as_f64().unwrap());
        let level = l["level_name"].as_str().unwrap_or("").to_string();
        let e = out.entry(name.clone()).or_insert(Motion {
            first: [x, y],
            top_speed: 0.0,
            top_accel: 0.0,
        });
        let mut next = (t, x, y, level.clone(), None, None);
        if let Some((t0, x0, y0, lv, v0, dir0)) = last.get(&name) {
            let dt = t - t0;
            if dt > 0.2 && *lv == level {
                let dist = (x - x0).hypot(y - y0);
                let speed = dist / dt;
                e.top_speed = e.top_speed.max(speed);
                let dir = (dist > 1e-6).then(|| ((x - x0) / dist, (y - y0) / dist));
                let straight = match (dir, dir0) {
                    (Some(a), Some(b)) => a.0 * b.0 + a.1 * b.1 > 0.9999,
                    _ => true,
                };
                if let (true, Some(v0)) = (straight, v0) {
                    e.top_accel = e.top_accel.max((speed - v0).abs() / dt);
                }
                next = (t, x, y, level, Some(speed), dir);
            }
        }
        last.insert(name, next);
    }
    out
}

#[test]
fn every_demo_config_runs_an_hour_on_its_map() {
    let Some(shared) = places::shared("fleet_configs") else {
        eprintln!("skipped: ../shared not found");
        return;
    };
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(shared.join("fleet_configs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    // rmf_api_msgs' request schemas, when they are there.
    let validators =
        validator("dispatch_task_request.json").zip(validator("robot_task_request.json"));
    let tmp = tempfile::tempdir().unwrap();
    let mut ran = 0;
    for dir in dirs {
        let dname = dir.file_name().unwrap().to_str().unwrap().to_string();
        let map = shared
            .join("maps")
            .join(map_of(&dname))
            .join(format!("{}.building.yaml", map_of(&dname)));
        let loaded = mapc_frontend::load(&map).expect("map");
        let b = loaded.valid_building().expect("valid demo map");
        let mut configs: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
            .collect();
        configs.sort();
        for config in configs {
            let cname = config.file_name().unwrap().to_str().unwrap();
            let what = format!("{dname}/{cname}");
            // The config alone first: its robots and where they start.
            let probe = format!("duration: 1h\nfleets:\n  - {{config: {cname}}}\n");
            let (s, d) = parse_scenario(mapc_ir::FileId(0), &probe, &dir);
            let s = s.unwrap_or_else(|| panic!("{what}: {d:#?}"));
            assert!(d.is_empty(), "{what}: {d:#?}");
            let f = &s.fleets[0];
            let rmf = f.rmf.as_ref().expect("from a config");
            let starts: Vec<String> = rmf.robots.iter().map(|r| r.start.clone()).collect();
            let g = graph_of(b, &starts).unwrap_or_else(|| panic!("{what}: no graph"));
            // A generated requests file, as rmf_demos_tasks would send: go_to_place
            // (compose) to the graph's named places in turn every 3 minutes, and patrols
            // between two chargers when the fleet patrols.
            let others: Vec<String> = places(b, g)
                .into_iter()
                .filter(|p| !starts.contains(p))
                .collect();
            let step = (others.len() / 20).max(1);
            let mut lines = String::new();
            for (k, p) in others.iter().step_by(step).cycle().take(20).enumerate() {
                let go = serde_json::json!({"at": format!("{}s", 30 + 180 * k), "request": {
                    "type": "dispatch_task_request",
                    "request": {"category": "compose", "description": {
                        "category": "go_to_place",
                        "phases": [{"activity": {"category": "go_to_place", "description": p}}]
                    }}
                }});
                lines.push_str(&format!("{go}\n"));
            }
            if f.task_kinds.contains(&mapc_sim::TaskCategory::Loop) && starts.len() >= 2 {
                for k in 0..3 {
                    let patrol = serde_json::json!({"at": format!("{}min", 5 + 20 * k), "request": {
                        "type": "robot_task_request", "robot": rmf.robots[1].name, "fleet": f.name,
                        "request": {"category": "patrol", "description": {
                            "places": [starts[0], starts[1]], "rounds": 1
                        }}
                    }});
                    lines.push_str(&format!("{patrol}\n"));
                }
            }
            if let Some(v) = &validators {
                for l in lines.lines() {
                    let r: Value = serde_json::from_str(l).unwrap();
                    let which = if r["request"]["type"] == "robot_task_request" {
                        &v.1
                    } else {
                        &v.0
                    };
                    let errs: Vec<String> = which
                        .iter_errors(&r["request"])
                        .map(|e| e.to_string())
                        .collect();
                    assert!(errs.is_empty(), "{what}: {errs:?} in {l}");
                }
            }
            let req = tmp.path().join(format!("{dname}_{cname}.jsonl"));
            std::fs::write(&req, &lines).unwrap();
            let text = format!(
                "duration: 1h\nseed: 1\nfleets:\n  - {{config: {cname}, graph: {g}}}\nrequests: '{}'\n",
                req.display()
            );
            let (s, d) = parse_scenario(mapc_ir::FileId(0), &text, &dir);
            let s = s.unwrap_or_else(|| panic!("{what}: {d:#?}\n{text}"));
            let mut trace = Vec::new();
            let report = match simulate(
                b,
                &s,
                RunOptions {
                    trace: Some(&mut trace),
                    trace_filter: mapc_sim::TraceFilter::new(
                        Some([mapc_sim::msgs::Topic::RobotState].into_iter().collect()),
                        0.0,
                    ),
                    ..Default::default()
                },
            ) {
                Ok(r) => r,
                Err(SimError::Invalid(d)) => panic!("{what}: {d:#?}"),
                Err(e) => panic!("{what}: {e:?}"),
            };
            let p = &f.robot;
            // Names and start places as in the config.
            let names: Vec<&str> = report.robots.iter().map(|r| r.name.as_str()).collect();
            let want: Vec<&str> = rmf.robots.iter().map(|r| r.name.as_str()).collect();
            assert_eq!(names, want, "{what}");
            let m = motion(&trace);
            for r in &rmf.robots {
                // (Names repeat across graphs: the vertex of graph g.)
                let at = b
                    .lanes
                    .iter()
                    .filter(|(_, l)| l.graph == g)
                    .flat_map(|(_, l)| [l.start, l.end])
                    .map(|v| &b.vertices[v])
                    .find(|v| v.name == r.start)
                    .expect("start waypoint");
                let first = m[&r.name].first;
                let off = (first[0] - at.pos.x).hypot(first[1] - at.pos.y);
                // The first state is at 0.5 s: at most a·t²/2 away.
                let slack = p.max_drive_acceleration * 0.125 + 0.01;
                assert!(
                    off <= slack,
                    "{what}: {} starts {off} m from {}",
                    r.name,
                    r.start
                );
            }
            let top = m.values().map(|x| x.top_speed).fold(0.0, f64::max);
            let acc = m.values().map(|x| x.top_accel).fold(0.0, f64::max);
            let v = p.nominal_drive_speed;
            assert!(top <= v + 1e-6, "{what}: top speed {top} > {v}");
            assert!(top > 0.8 * v, "{what}: top speed {top}, limit {v}");
            let a = p.max_drive_acceleration;
            assert!(acc <= a + 0.02, "{what}: top acceleration {acc} > {a}");
            // Footprints in the contact check: the config's, for every pair.
            for e in report.near_misses.iter().chain(&report.contacts) {
                assert!(
                    (e.contact_distance_m - 2.0 * p.footprint).abs() < 1e-9,
                    "{what}: {e:?}"
                );
            }
            let done = report
                .tasks
                .iter()
                .filter(|t| t.result == "completed")
                .count();
            assert!(
                done >= 3,
                "{what}: {done} tasks completed: {:#?}",
                report.tasks
            );
            eprintln!(
                "{what}: graph {g}, {} robots, {done}/{} tasks completed, top speed {top:.3}/{v}, top acceleration {acc:.3}/{a}",
                names.len(),
                report.tasks.len()
            );
            ran += 1;
        }
    }
    assert_eq!(ran, 13, "configs run");
}
