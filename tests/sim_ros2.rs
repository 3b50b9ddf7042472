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

mod support;
use std::path::Path;
use std::process::Command;
use support::ros2::peer;

const RATE: f64 = 10.0;

/// A temporary directory; with MAPC_KEEP_TEST_DIR set, one that stays (its path is printed)
/// for a look at the trace and the logs after a failure.
fn test_dir() -> tempfile::TempDir {
    let mut dir = tempfile::tempdir().expect("tempdir");
    if std::env::var_os("MAPC_KEEP_TEST_DIR").is_some() {
        dir.disable_cleanup(true);
        eprintln!("files in {}", dir.path().display());
    }
    dir
}

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

/// Runs `script` under `sh` in a private network namespace (`unshare -rn`) with MAPC, DIR,
/// PY and `env` set; asserts it succeeded. Returns the context for failure messages (the
/// script's stderr, `<peer>.err`, `mapc.err`) and a reader of the files the run left in `dir`.
fn in_namespace<'a>(
    script: &str,
    dir: &'a Path,
    py: &Path,
    env: &[(&str, std::ffi::OsString)],
    peer: &str,
) -> (String, impl Fn(&str) -> String + 'a) {
    let mut cmd = Command::new("unshare");
    cmd.args(["-rn", "sh", "-c", script])
        .env("MAPC", env!("CARGO_BIN_EXE_mapc"))
        .env("DIR", dir)
        .env("PY", py);
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().expect("unshare runs");
    let read = move |n: &str| std::fs::read_to_string(dir.join(n)).unwrap_or_default();
    let context = format!(
        "script: {}\n{peer}: {}\nmapc: {}",
        String::from_utf8_lossy(&out.stderr),
        read(&format!("{peer}.err")),
        read("mapc.err")
    );
    assert!(out.status.success(), "{context}");
    (context, read)
}

#[test]
fn rmf_side_drives_mapc_over_cyclone_dds() {
    let Some(py) = peer("cyclonedds.domain") else {
        return;
    };
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = test_dir();
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
    let (context, read) = in_namespace(
        SCRIPT,
        dir.path(),
        &py,
        &[
            (
                "SCENARIO",
                root.join("fixtures/two_level_clinic.scenario.yaml").into(),
            ),
            ("RATE", RATE.to_string().into()),
            ("PEER", root.join("ros2/tests/python/rmf_peer.py").into()),
        ],
        "peer",
    );
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

/// Without `--plugins-only` mapc's own fleet layer and supervisors run and everything is
/// published: a listener started before mapc (as rmf-web's dashboard or a recorder) gets
/// every message of every topic, in order, equal to the trace's. mapc waits for the
/// listener's discovery before its first step and for its acknowledgments before leaving.
const WATCH_SCRIPT: &str = r#"set -e
ip link set lo up
ip link add dds0 type veth peer name dds1
ip addr add 192.0.2.1/24 dev dds0
ip link set dds1 up
ip link set dds0 up multicast on
ip route add 224.0.0.0/4 dev dds0
export CYCLONEDDS_URI='<CycloneDDS><Domain><General><Interfaces><NetworkInterface name="dds0" multicast="true"/></Interfaces></General></Domain></CycloneDDS>'
"$PY" "$WATCH" "$DIR/config.json" "$DIR/done" > "$DIR/watch.json" 2> "$DIR/watch.err" &
pid=$!
# The listener's readers exist before mapc starts.
for i in $(seq 100); do grep -q listening "$DIR/watch.err" 2>/dev/null && break; sleep 0.1; done
"$MAPC" sim "$SCENARIO" --ros2 --rate 40 --domain-id "$DOMAIN" --until 300 \
  --trace "$DIR/trace.jsonl" --report "$DIR/report.json" -q > "$DIR/mapc.out" 2> "$DIR/mapc.err"
touch "$DIR/done"
wait $pid
"#;

/// Runs `WATCH_SCRIPT` on a fixture; returns what the listener saw per topic and the trace.
fn watch_full_run(
    fixture: &str,
    domain: u16,
) -> Option<(serde_json::Value, Vec<serde_json::Value>)> {
    let py = peer("cyclonedds.domain")?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = test_dir();
    let defs: serde_json::Map<String, serde_json::Value> = mapc_ros2::msgs::definitions()
        .iter()
        .map(|(n, d)| (n.to_string(), serde_json::json!(d)))
        .collect();
    let topics: serde_json::Map<String, serde_json::Value> = mapc_sim::msgs::Topic::ALL
        .iter()
        .map(|t| (t.name().to_string(), mapc_ros2::topics::ros_type(*t).into()))
        .collect();
    let config = serde_json::json!({"definitions": defs, "domain_id": domain, "topics": topics});
    std::fs::write(dir.path().join("config.json"), config.to_string()).expect("config");
    let (context, read) = in_namespace(
        WATCH_SCRIPT,
        dir.path(),
        &py,
        &[
            ("SCENARIO", root.join("fixtures").join(fixture).into()),
            ("DOMAIN", domain.to_string().into()),
            ("WATCH", root.join("ros2/tests/python/rmf_watch.py").into()),
        ],
        "watch",
    );
    let seen: serde_json::Value = serde_json::from_str(&read("watch.json"))
        .unwrap_or_else(|e| panic!("watch output: {e}\n{context}"));
    // Publishing changed nothing: the same run without --ros2 writes the same trace and
    // report, byte for byte.
    let alone = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .arg("sim")
        .arg(root.join("fixtures").join(fixture))
        .args(["--until", "300", "-q", "--trace"])
        .arg(dir.path().join("alone.jsonl"))
        .arg("--report")
        .arg(dir.path().join("alone.json"))
        .output()
        .expect("mapc runs");
    assert!(alone.status.success());
    assert!(
        read("trace.jsonl") == read("alone.jsonl"),
        "--ros2 changed the trace"
    );
    assert!(
        read("report.json") == read("alone.json"),
        "--ros2 changed the report"
    );
    let trace: Vec<serde_json::Value> = read("trace.jsonl")
        .lines()
        .map(|l| serde_json::from_str(l).expect("trace line"))
        .collect();
    Some((seen, trace))
}

/// Every traced message of every topic arrived over DDS, in order and equal (float32 fields
/// to their precision); returns the number per topic.
fn assert_all_arrived(
    seen: &serde_json::Value,
    trace: &[serde_json::Value],
) -> std::collections::BTreeMap<String, usize> {
    let mut counts = std::collections::BTreeMap::new();
    for t in mapc_sim::msgs::Topic::ALL {
        let topic = t.name();
        let got = seen[topic].as_array().expect("topic listened to");
        let traced: Vec<&serde_json::Value> = trace
            .iter()
            .filter(|l| l["topic"] == topic)
            .map(|l| &l["msg"])
            .collect();
        assert_eq!(
            got.len(),
            traced.len(),
            "{topic}: {} of {} traced messages received",
            got.len(),
            traced.len()
        );
        for (i, (m, want)) in got.iter().zip(&traced).enumerate() {
            let m = if topic == "/task_events" {
                serde_json::from_str(m["data"].as_str().expect("json text")).expect("json")
            } else {
                m.clone()
            };
            assert!(
                approx_eq(&m, want),
                "{topic} #{i}: got {m}\n  traced {want}"
            );
        }
        counts.insert(topic.to_string(), got.len());
    }
    println!("received over DDS: {counts:?}");
    counts
}

#[test]
fn full_run_publishes_what_the_trace_holds() {
    let Some((seen, trace)) = watch_full_run("two_level_clinic.scenario.yaml", 8) else {
        return;
    };
    let n = assert_all_arrived(&seen, &trace);
    // The clinic run's event streams (fleet layer, supervisors, tasks) are all there.
    for topic in [
        "/task_events",
        "/door_supervisor_heartbeat",
        "/adapter_door_requests",
        "/door_requests",
        "/adapter_lift_requests",
        "/lift_requests",
        "/robot_path_requests",
        "/dispenser_results",
    ] {
        assert!(n[topic] > 0, "{topic}: the fixture run publishes it");
    }
    // 1 Hz per fleet for the 300 s.
    assert_eq!(n["/fleet_states"], 300);
}

/// The warehouse fixture's people on `/rmf_obstacles` (rmf_obstacle_msgs/Obstacles) reach a
/// Cyclone DDS reader with the trace's values: two people, classified human, on L1, in the
/// map frame, ACTION_ADD.
#[test]
fn people_arrive_as_rmf_obstacles() {
    let Some((seen, trace)) = watch_full_run("cartesian_warehouse.scenario.yaml", 9) else {
        return;
    };
    let n = assert_all_arrived(&seen, &trace);
    // 2 Hz for 300 s.
    assert_eq!(n["/rmf_obstacles"], 600);
    let last = seen["/rmf_obstacles"].as_array().unwrap().last().unwrap();
    assert_eq!(last["header"]["stamp"]["sec"], 299);
    assert_eq!(last["header"]["frame_id"], "map");
    let people = last["obstacles"].as_array().unwrap();
    assert_eq!(people.len(), 2);
    for (i, p) in people.iter().enumerate() {
        assert_eq!(p["id"], i);
        assert_eq!(p["classification"], "human");
        assert_eq!(p["level_name"], "L1");
        assert_eq!(p["action"], 1, "ACTION_ADD");
        // The human profile's radius is 0.3 m: a 0.6 m box.
        assert_eq!(p["bbox"]["size"]["x"], 0.6);
        assert_eq!(p["bbox"]["size"]["y"], 0.6);
    }
}

/// JSON equality with float32 tolerance for numbers.
fn approx_eq(a: &serde_json::Value, b: &serde_json::Value) -> bool {
    use serde_json::Value as V;
    match (a, b) {
        (V::Number(x), V::Number(y)) => {
            let (x, y) = (
                x.as_f64().unwrap_or(f64::NAN),
                y.as_f64().unwrap_or(f64::NAN),
            );
            (x - y).abs() <= 1e-6 * x.abs().max(y.abs()).max(1.0)
        }
        (V::Array(x), V::Array(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(a, b)| approx_eq(a, b))
        }
        (V::Object(x), V::Object(y)) => {
            y.iter()
                .all(|(k, v)| x.get(k).is_some_and(|w| approx_eq(w, v)))
                && x.len() == y.len()
        }
        _ => a == b,
    }
}
