//! People in `mapc sim` (issue 19), through the binary: on the airport terminal demo map
//! (10 people in 5 groups, human lanes crossing the robots' lanes) with two tiny robots
//! looping through them, people walk tens of metres, never touch a robot, are published on
//! `/rmf_obstacles`, the trace is identical between runs, `crowd: {enabled: false}`
//! publishes no one, robots still complete their tasks, and `crowd: {scale: K}` multiplies
//! the groups.

mod support;

use std::path::{Path, PathBuf};

fn airport() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/maps/airport_terminal/airport_terminal.building.yaml");
    p.is_file().then_some(p)
}

fn scenario(dir: &Path, map: &Path, extra: &str) -> PathBuf {
    let text = format!(
        "map: {}\nseed: 1\nduration: 6min\n{extra}\nfleets:\n  - {{name: tiny, graph: 2, robot: TinyRobot, count: 2, spawn: [s10, s11]}}\ngenerators:\n  - {{every: 1min, start: 0, end: 2min, loop: {{start: s10, finish: s11, loops: 1}}}}\n",
        map.display()
    );
    let p = dir.join(format!("s{}.scenario.yaml", extra.len()));
    std::fs::write(&p, text).unwrap();
    p
}

fn run(s: &Path, trace: &Path, more: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "sim",
        s.to_str().unwrap(),
        "--format",
        "json",
        "--trace",
        trace.to_str().unwrap(),
    ];
    args.extend_from_slice(more);
    let (code, out, err) = support::mapc(&args);
    assert_eq!(code, 0, "{err}\n{out}");
    serde_json::from_str::<serde_json::Value>(out.trim()).unwrap()["report"].clone()
}

fn completed(r: &serde_json::Value) -> usize {
    r["tasks"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| t["result"] == "completed")
        .count()
}

#[test]
fn airport_people_walk_among_robots() {
    let Some(map) = airport() else {
        println!("skipped: ../shared not found");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let s = scenario(dir.path(), &map, "");
    let (t1, t2) = (dir.path().join("a.jsonl"), dir.path().join("b.jsonl"));
    let r = run(&s, &t1, &["--compare-crowd"]);
    run(&s, &t2, &[]);
    assert_eq!(std::fs::read(&t1).unwrap(), std::fs::read(&t2).unwrap());

    let c = &r["crowd"];
    assert_eq!(c["humans"], 10, "{c}");
    // 6 min at the profile's 2 m/s: tens of metres each, at most max_speed·t.
    let min = c["walked_m"]["min"].as_f64().unwrap();
    assert!(
        min > 20.0 && c["walked_m"]["max"].as_f64().unwrap() < 4.0 * 360.0,
        "{c}"
    );
    let v = c["speed_m_s"]["mean"].as_f64().unwrap();
    assert!(v > 1.0 && v <= 2.05, "{c}");
    assert!(c["speed_m_s"]["max"].as_f64().unwrap() <= 4.0 + 1e-9, "{c}");
    assert_eq!(c["contacts"], 0, "{c}");

    // The same run without people: robots complete at least 70 % as many tasks with them.
    let cmp = &c["compare"][0];
    let (with, without) = (
        cmp["completed"].as_u64().unwrap(),
        cmp["completed_without_crowd"].as_u64().unwrap(),
    );
    assert!(without > 0 && with * 10 >= without * 7, "{cmp}");
    assert_eq!(with as usize, completed(&r));

    // /rmf_obstacles at 2 Hz: one Obstacle per person, on the level, classified human.
    let trace = std::fs::read_to_string(&t1).unwrap();
    let msgs: Vec<serde_json::Value> = trace
        .lines()
        .filter(|l| l.contains("\"/rmf_obstacles\""))
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(msgs.len(), 720);
    assert_eq!(msgs[1]["t"], 0.5);
    let obs = msgs[100]["msg"]["obstacles"].as_array().unwrap();
    assert_eq!(obs.len(), 10);
    for (i, o) in obs.iter().enumerate() {
        assert_eq!(o["id"], i);
        assert_eq!(o["classification"], "human");
        assert_eq!(o["level_name"], "L1");
        assert_eq!(o["bbox"]["size"]["x"], 0.5);
        // Near the terminal's human lanes (map frame, metres).
        let x = o["bbox"]["center"]["position"]["x"].as_f64().unwrap();
        assert!((100.0..200.0).contains(&x), "{o}");
    }

    // Everyone stays on the navmesh of the human lanes (the polygons of L1_navmesh.nav),
    // within 5 cm, at every published moment.
    let parsed = mapc_frontend::parse_str("m", &std::fs::read_to_string(&map).unwrap());
    let b = parsed.building.unwrap();
    let (level, _) = b.levels.iter().next().unwrap();
    let mesh = mapc_ir::human_navmesh(&b, level, mapc_ir::Vec2::default()).unwrap();
    let on_mesh = |x: f64, y: f64| {
        mesh.nodes.iter().any(|ring| {
            (0..ring.len()).all(|k| {
                let (a, c) = (mesh.verts[ring[k]], mesh.verts[ring[(k + 1) % ring.len()]]);
                let (ex, ey) = (c.x - a.x, c.y - a.y);
                let len = (ex * ex + ey * ey).sqrt().max(1e-9);
                // Signed distance to the side's left (inside): at least -5 cm.
                (ex * (y - a.y) - ey * (x - a.x)) / len >= -0.05
            })
        })
    };
    for m in &msgs {
        for o in m["msg"]["obstacles"].as_array().unwrap() {
            let p = &o["bbox"]["center"]["position"];
            let (x, y) = (p["x"].as_f64().unwrap(), p["y"].as_f64().unwrap());
            assert!(on_mesh(x, y), "off the navmesh at t = {}: {o}", m["t"]);
        }
    }

    // Off: no one is published and the report has no crowd.
    let off = scenario(dir.path(), &map, "crowd: {enabled: false}");
    let t3 = dir.path().join("c.jsonl");
    let r = run(&off, &t3, &[]);
    assert!(r.get("crowd").is_none());
    assert!(!std::fs::read_to_string(&t3)
        .unwrap()
        .contains("/rmf_obstacles"));
}

#[test]
fn airport_scale_multiplies_the_groups() {
    let Some(map) = airport() else {
        println!("skipped: ../shared not found");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let s = scenario(dir.path(), &map, "crowd: {scale: 20}");
    let t = dir.path().join("a.jsonl");
    let r = run(&s, &t, &["--until", "30s", "--trace-topics", "task_events"]);
    assert_eq!(r["crowd"]["humans"], 200);
    assert_eq!(r["crowd"]["contacts"], 0);
}
