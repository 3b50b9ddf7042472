//! `mapc sim --ros2 --plugins-only` driven by an independent DDS implementation: Eclipse
//! Cyclone DDS (its Python package, in the venv .ci/run makes) plays RMF's supervisors, a
//! fleet adapter and a workcell client (ros2/tests/python/rmf_peer.py) on the two-level
//! clinic fixture.
//!
//! Everything runs in a private network namespace made here (`unshare -rn`): no DDS packet
//! can reach the machine's interfaces. Inside it, RustDDS needs a multicast-capable
//! non-loopback interface (it skips `lo`), so the namespace gets a veth pair of its own
//! with a TEST-NET-1 address (RFC 5737); both ends stay in the namespace and the 224.0.0.0/4
//! route points at it. Prints `skipped: ...` without unshare, ip or the venv.

use std::path::{Path, PathBuf};
use std::process::Command;

fn python() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("MAPC_ROS2_PYTHON") {
        return Some(p.into());
    }
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/ros2-venv/bin/python");
    let ok = Command::new(&p)
        .args(["-c", "import cyclonedds.domain"])
        .output()
        .is_ok_and(|o| o.status.success());
    ok.then_some(p)
}

fn namespace_works() -> bool {
    Command::new("unshare")
        .args([
            "-rn",
            "sh",
            "-c",
            "ip link set lo up && ip link add t0 type veth peer name t1",
        ])
        .output()
        .is_ok_and(|o| o.status.success())
}

const RATE: f64 = 10.0;

/// The namespace: `lo` up, the veth pair with multicast, the multicast route, Cyclone told
/// to use that interface; then mapc and the peer, mapc stopped with SIGINT when the peer is
/// done.
const SCRIPT: &str = r#"set -e
ip link set lo up
ip link add dds0 type veth peer name dds1
ip addr add 192.0.2.1/24 dev dds0
ip link set dds1 up
ip link set dds0 up multicast on
ip route add 224.0.0.0/4 dev dds0
export CYCLONEDDS_URI='<CycloneDDS><Domain><General><Interfaces><NetworkInterface name="dds0" multicast="true"/></Interfaces></General></Domain></CycloneDDS>'
"$MAPC" sim "$SCENARIO" --ros2 --plugins-only --rate "$RATE" --domain-id 7 --until 900 \
  --trace "$DIR/trace.jsonl" -q > "$DIR/mapc.out" 2> "$DIR/mapc.err" &
pid=$!
"$PY" "$PEER" "$DIR/config.json" > "$DIR/peer.json" 2> "$DIR/peer.err" || echo "peer failed: $?" >&2
kill -INT $pid
rc=0; wait $pid || rc=$?
echo "mapc exit $rc" >&2
"#;

#[test]
fn rmf_side_drives_mapc_over_cyclone_dds() {
    let Some(py) = python() else {
        println!("skipped: cyclonedds (Python) not found; .ci/run makes target/ros2-venv");
        return;
    };
    if !namespace_works() {
        println!("skipped: no private network namespace (unshare -rn, ip, veth) here");
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().expect("tempdir");
    // MAPC_KEEP_TEST_DIR=1 keeps the trace and logs for a look after a failure.
    let dir = if std::env::var_os("MAPC_KEEP_TEST_DIR").is_some() {
        let p = dir.keep();
        eprintln!("files in {}", p.display());
        tempfile::TempDir::new_in(p).expect("tempdir")
    } else {
        dir
    };
    let defs: serde_json::Map<String, serde_json::Value> = mapc_ros2::msgs::definitions()
        .iter()
        .map(|(n, d)| (n.to_string(), serde_json::json!(d)))
        .collect();
    let config = serde_json::json!({
        "definitions": defs,
        "domain_id": 7,
        // The map's doors that have a door plugin (L2_ward_b_door has `plugin: none`).
        "doors": ["L1_lobby_door", "L1_pharmacy_door", "L2_ward_a_door"],
        "lift": "lift_1",
        "lift_floor": "L2",
        "robot": "tinyRobot1",
        "fleet": "tinyRobot",
        "path": ["tinyRobot1_charger", "lobby", "corridor", "pharmacy"],
        "dispenser": "pharmacy_dispenser",
    });
    std::fs::write(dir.path().join("config.json"), config.to_string()).expect("config");
    let started = std::time::Instant::now();
    let out = Command::new("unshare")
        .args(["-rn", "sh", "-c", SCRIPT])
        .env("MAPC", env!("CARGO_BIN_EXE_mapc"))
        .env(
            "SCENARIO",
            root.join("fixtures/two_level_clinic.scenario.yaml"),
        )
        .env("RATE", RATE.to_string())
        .env("DIR", dir.path())
        .env("PY", &py)
        .env("PEER", root.join("ros2/tests/python/rmf_peer.py"))
        .output()
        .expect("unshare runs");
    let read = |n: &str| std::fs::read_to_string(dir.path().join(n)).unwrap_or_default();
    let context = format!(
        "script: {}\npeer: {}\nmapc: {}",
        String::from_utf8_lossy(&out.stderr),
        read("peer.err"),
        read("mapc.err")
    );
    assert!(out.status.success(), "{context}");
    assert!(
        context.contains("mapc exit 130"),
        "mapc stops on SIGINT\n{context}"
    );
    let r: serde_json::Value = serde_json::from_str(&read("peer.json"))
        .unwrap_or_else(|e| panic!("peer output: {e}\n{context}"));
    println!("{r:#}\nwall {:?}", started.elapsed());
    assert_eq!(r["errors"], serde_json::json!([]), "{context}");

    // Every door's state; the latched map with both levels and the lift.
    assert_eq!(r["doors_seen"], config["doors"]);
    assert_eq!(r["map"]["levels"], serde_json::json!(["L1", "L2"]));
    assert_eq!(r["map"]["lifts"], serde_json::json!(["lift_1"]));

    // /clock advances at the requested rate (within 5 %) and never backwards.
    let rate = r["clock_rate"].as_f64().expect("clock rate");
    assert!(
        (rate / RATE - 1.0).abs() < 0.05,
        "clock rate {rate}, asked {RATE}"
    );
    assert_eq!(r["clock_monotonic"], true);

    // The door opened and closed again; the lift arrived with its doors open.
    assert!(r["door_open_after"].as_f64().is_some_and(|t| t > 0.0));
    assert!(r["door_closed_after"].as_f64().is_some_and(|t| t > 0.0));
    assert_eq!(r["lift"]["floor"], "L2");
    assert_eq!(r["lift"]["door_state"], 2);

    // The robot drove the path to its end, reporting the task id and moving on the way.
    assert_eq!(r["path"]["task_id"], "mapc-test-7");
    assert!(r["path"]["distinct_positions"]
        .as_u64()
        .is_some_and(|n| n > 5));

    // The dispenser served the robot's fleet.
    assert_eq!(r["dispenser"]["status"], 1, "SUCCESS");
    assert_eq!(r["dispenser"]["source"], "pharmacy_dispenser");

    // mapc traced what came over DDS like any request.
    let trace = read("trace.jsonl");
    assert!(trace.contains(r#""requester_id":"door_supervisor""#));
    assert!(trace.contains(r#""task_id":"mapc-test-7""#));
}
