//! `mapc sim --mcap`: the rosbag2 MCAP of a fixture run, read back by the independent Python
//! readers (`mcap`, `mcap-ros2-support`, in the venv .ci/run makes): every schema is found,
//! every message decodes to the values of the JSON trace, `/map` holds the building and
//! `/clock` ticks every 20 ms of simulated time; people on `/rmf_obstacles` decode to the
//! trace's values. Also: recording changes nothing in the trace and the report, byte for
//! byte.

use std::path::{Path, PathBuf};
use std::process::Command;

mod support;

fn python() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("MAPC_ROS2_PYTHON") {
        return Some(p.into());
    }
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/ros2-venv/bin/python");
    let ok = Command::new(&p)
        .args(["-c", "import mcap_ros2.decoder"])
        .output()
        .is_ok_and(|o| o.status.success());
    ok.then_some(p)
}

fn run(args: &[&str]) {
    let (code, _, err) = support::mapc(args);
    assert_eq!(code, 0, "mapc {args:?}: {err}");
}

/// The Python mcap readers' view of `mcap` against the trace `jsonl` (no mismatches).
fn read_mcap(py: &Path, mcap: &str, jsonl: &str) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("ros2/tests/python/read_mcap.py");
    let out = Command::new(py)
        .arg(script)
        .arg(mcap)
        .arg(jsonl)
        .output()
        .expect("python runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(r["mismatches"], serde_json::json!([]), "{r:#}");
    r
}

#[test]
fn mcap_decodes_to_the_trace() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = |n: &str| dir.path().join(n).to_string_lossy().into_owned();
    let scenario = "fixtures/two_level_clinic.scenario.yaml";
    run(&[
        "sim",
        scenario,
        "--until",
        "5min",
        "-q",
        "--trace",
        &p("a.jsonl"),
        "--report",
        &p("a.json"),
        "--mcap",
        &p("run.mcap"),
    ]);
    run(&[
        "sim",
        scenario,
        "--until",
        "5min",
        "-q",
        "--trace",
        &p("b.jsonl"),
        "--report",
        &p("b.json"),
    ]);
    let read = |n: &str| std::fs::read(dir.path().join(n)).expect("written");
    assert!(
        read("a.jsonl") == read("b.jsonl"),
        "--mcap changed the trace"
    );
    assert!(
        read("a.json") == read("b.json"),
        "--mcap changed the report"
    );
    let mcap = read("run.mcap");
    assert_eq!(&mcap[..8], b"\x89MCAP0\r\n", "MCAP magic");

    let Some(py) = python() else {
        println!("skipped: mcap-ros2-support (Python) not found; .ci/run makes target/ros2-venv");
        return;
    };
    let r = read_mcap(&py, &p("run.mcap"), &p("a.jsonl"));
    assert_eq!(r["profile"], "ros2");

    // Every topic of the trace, with its number of messages, and its schema.
    let trace = String::from_utf8(read("a.jsonl")).expect("utf-8");
    let mut counts = std::collections::BTreeMap::<String, u64>::new();
    for line in trace.lines() {
        let v: serde_json::Value = serde_json::from_str(line).expect("trace line");
        *counts
            .entry(v["topic"].as_str().expect("topic").to_string())
            .or_default() += 1;
    }
    assert!(
        counts.len() >= 15,
        "the fixture run uses most topics: {counts:?}"
    );
    for (topic, n) in &counts {
        assert_eq!(r["topics"][topic].as_u64(), Some(*n), "{topic}");
    }
    // /clock: one per 20 ms of the 5 minutes, stamped with its log time (read_mcap.py checks
    // each), evenly spaced from 0.
    let clock = &r["clock"];
    let ticks = (300.0 / mapc_ros2::mcap::CLOCK_PERIOD).round() as u64;
    assert_eq!(clock["count"].as_u64(), Some(ticks), "{clock}");
    assert_eq!(clock["first_ns"].as_u64(), Some(0));
    let period_ns = (mapc_ros2::mcap::CLOCK_PERIOD * 1e9) as i64;
    assert_eq!(
        clock["last_ns"]
            .as_i64()
            .map(|l| (l - (ticks as i64 - 1) * period_ns).abs() < 1000),
        Some(true),
        "{clock}"
    );
    for gap in ["min_gap_ns", "max_gap_ns"] {
        let g = clock[gap].as_i64().expect("gap");
        assert!((g - period_ns).abs() < 1000, "{gap} {g}");
    }
    assert_eq!(
        r["messages"].as_u64(),
        Some(trace.lines().count() as u64 + 1 + ticks)
    );
    for schema in [
        "rmf_fleet_msgs/msg/RobotState",
        "rmf_fleet_msgs/msg/FleetState",
        "rmf_fleet_msgs/msg/PathRequest",
        "rmf_door_msgs/msg/DoorState",
        "rmf_door_msgs/msg/DoorRequest",
        "rmf_door_msgs/msg/SupervisorHeartbeat",
        "rmf_lift_msgs/msg/LiftState",
        "rmf_lift_msgs/msg/LiftRequest",
        "rmf_dispenser_msgs/msg/DispenserRequest",
        "rmf_dispenser_msgs/msg/DispenserResult",
        "rmf_dispenser_msgs/msg/DispenserState",
        "rmf_ingestor_msgs/msg/IngestorRequest",
        "rmf_ingestor_msgs/msg/IngestorResult",
        "rmf_ingestor_msgs/msg/IngestorState",
        "rmf_building_map_msgs/msg/BuildingMap",
        "std_msgs/msg/String",
        "rosgraph_msgs/msg/Clock",
    ] {
        assert_eq!(r["schemas"][schema], "ros2msg", "{schema}");
    }
    // Door and lift topics carry RMF's QoS for rosbag2 playback; /map is latched.
    assert!(r["qos"]["/door_states"]
        .as_str()
        .unwrap()
        .contains("depth: 100"));
    assert!(r["qos"]["/map"].as_str().unwrap().contains("durability: 1"));
    assert!(r["qos"]["/clock"].as_str().unwrap().contains("depth: 1"));

    // /map: both levels with their doors and one nav graph of the fixture's lanes, the lift.
    assert_eq!(
        r["map_levels"],
        serde_json::json!([
            {"name": "L1", "doors": ["L1_lobby_door", "L1_pharmacy_door"], "graphs": [[5, 4]]},
            {"name": "L2", "doors": ["L2_ward_a_door", "L2_ward_b_door"], "graphs": [[4, 3]]},
        ])
    );
    assert_eq!(r["map_lifts"], serde_json::json!(["lift_1"]));
}

/// The warehouse fixture's two people on `/rmf_obstacles` (rmf_obstacle_msgs/Obstacles), read
/// back by the Python readers: every message equals the trace's.
#[test]
fn mcap_people_decode_to_the_trace() {
    let Some(py) = python() else {
        println!("skipped: mcap-ros2-support (Python) not found; .ci/run makes target/ros2-venv");
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let p = |n: &str| dir.path().join(n).to_string_lossy().into_owned();
    run(&[
        "sim",
        "fixtures/cartesian_warehouse.scenario.yaml",
        "--until",
        "1min",
        "-q",
        "--trace",
        &p("a.jsonl"),
        "--mcap",
        &p("run.mcap"),
    ]);
    let r = read_mcap(&py, &p("run.mcap"), &p("a.jsonl"));
    assert_eq!(
        r["schemas"]["rmf_obstacle_msgs/msg/Obstacles"], "ros2msg",
        "{r:#}"
    );
    let trace = std::fs::read_to_string(p("a.jsonl")).expect("trace");
    let people: Vec<serde_json::Value> = trace
        .lines()
        .filter(|l| l.contains("\"/rmf_obstacles\""))
        .map(|l| serde_json::from_str(l).expect("json"))
        .collect();
    // 2 Hz for a minute, two people each.
    assert!(people.len() >= 100, "{}", people.len());
    assert_eq!(
        people[10]["msg"]["obstacles"].as_array().map(Vec::len),
        Some(2)
    );
    assert_eq!(
        r["topics"]["/rmf_obstacles"].as_u64(),
        Some(people.len() as u64)
    );
}
