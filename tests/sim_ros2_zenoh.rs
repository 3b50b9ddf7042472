//! `mapc sim --ros2` on rmw_zenoh's wire format (`RMW_IMPLEMENTATION=rmw_zenoh_cpp`), driven
//! by Zenoh's own Python package (eclipse-zenoh, in the venv .ci/run makes): a Zenoh router
//! (ros2/tests/python/zenoh_router.py, router mode on tcp/127.0.0.1:7447, as rmw_zenohd) and
//! a peer playing RMF's door supervisor (ros2/tests/python/zenoh_peer.py) whose key
//! expressions carry the type hashes ROS 2 published for DoorState, DoorRequest and Clock.
//! The peer joins after mapc published `/map`, so `/map` comes from the transient-local
//! cache.
//!
//! Everything runs in a private network namespace made here (`unshare -rn`, only `lo`).
//! Prints `skipped: ...` without unshare, ip or the venv.

mod support;
use std::path::Path;
use std::process::Command;
use support::ros2::{namespace, peer};

const SCRIPT: &str = r#"set -e
ip link set lo up multicast on
ip route add 224.0.0.0/4 dev lo
"$PY" "$ROUTER" "$DIR/done" > "$DIR/router.out" 2> "$DIR/router.err" &
router=$!
for i in $(seq 200); do grep -q "router up" "$DIR/router.out" 2>/dev/null && break; sleep 0.05; done
"$MAPC" sim "$SCENARIO" --ros2 --plugins-only --rate 10 --until 900 \
  -q > "$DIR/mapc.out" 2> "$DIR/mapc.err" &
pid=$!
# The peer joins once mapc has published /map.
for i in $(seq 200); do grep -q "^Zenoh: " "$DIR/mapc.err" 2>/dev/null && break; sleep 0.05; done
sleep 1
"$PY" "$PEER" "$DIR/config.json" > "$DIR/peer.json" 2> "$DIR/peer.err" || echo "peer failed: $?" >&2
kill -INT $pid
rc=0; wait $pid || rc=$?
echo "mapc exit $rc" >&2
touch "$DIR/done"
wait $router
"#;

#[test]
fn rmf_side_drives_mapc_over_rmw_zenoh() {
    let Some(py) = peer("zenoh.ext, xxhash, cyclonedds.idl") else {
        return;
    };
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().expect("tempdir");
    let defs: serde_json::Map<String, serde_json::Value> = mapc_ros2::msgs::definitions()
        .iter()
        .map(|(n, d)| (n.to_string(), serde_json::json!(d)))
        .collect();
    // The hashes rosidl generated for these types (ROS 2 Jazzy, rmf_internal_msgs):
    // `*__get_type_hash` in rosidl_generator_c's `*__description.c` (as in type_hash.rs).
    let hashes = serde_json::json!({
        "rmf_door_msgs/msg/DoorState":
            "RIHS01_1cb9d98f19c66cbc1f9acb16faaa90c63a7b65021bd26c69958d96f0a0388bb2",
        "rmf_door_msgs/msg/DoorRequest":
            "RIHS01_3145b5d97064f89b0a0db953b8167ddeeefbc2914c24a603c3bdc51f122f143e",
        "rosgraph_msgs/msg/Clock":
            "RIHS01_692f7a66e93a3c83e71765d033b60349ba68023a8c689a79e48078bcb5c58564",
    });
    let config = serde_json::json!({
        "definitions": defs,
        "domain_id": 7,
        "hashes": hashes,
        "doors": ["L1_lobby_door", "L1_pharmacy_door", "L2_ward_a_door"],
    });
    std::fs::write(dir.path().join("config.json"), config.to_string()).expect("config");
    let mut cmd = Command::new("unshare");
    cmd.args(["-rn", "sh", "-c", SCRIPT])
        .env("MAPC", env!("CARGO_BIN_EXE_mapc"))
        .env("DIR", dir.path())
        .env("PY", &py)
        .env("PEER", root.join("ros2/tests/python/zenoh_peer.py"))
        .env("ROUTER", root.join("ros2/tests/python/zenoh_router.py"))
        .env(
            "SCENARIO",
            root.join("fixtures/two_level_clinic.scenario.yaml"),
        )
        // The middleware and the domain from the environment, as every ROS 2 node.
        .env("RMW_IMPLEMENTATION", "rmw_zenoh_cpp")
        .env("ROS_DOMAIN_ID", "7")
        .env_remove("ZENOH_SESSION_CONFIG_URI")
        .env_remove("ZENOH_CONFIG_OVERRIDE")
        .env_remove("ZENOH_ROUTER_CHECK_ATTEMPTS");
    let out = cmd.output().expect("unshare runs");
    let read = |n: &str| std::fs::read_to_string(dir.path().join(n)).unwrap_or_default();
    let context = format!(
        "script: {}\npeer: {}\nmapc: {}\nrouter: {}",
        String::from_utf8_lossy(&out.stderr),
        read("peer.err"),
        read("mapc.err"),
        read("router.err"),
    );
    assert!(out.status.success(), "{context}");
    assert!(context.contains("mapc exit 130"), "{context}");
    let r: serde_json::Value = serde_json::from_str(&read("peer.json"))
        .unwrap_or_else(|e| panic!("peer output: {e}\n{context}"));
    println!("{r:#}");
    assert_eq!(r["errors"], serde_json::json!([]), "{context}");
    let mapc_err = read("mapc.err");
    assert!(
        mapc_err.contains("Zenoh: domain 7, session ")
            && mapc_err.contains("peer of the router on tcp/localhost:7447, 1 router(s)"),
        "{mapc_err}"
    );

    // Door states and /clock on the key expressions with ROS 2's own hashes; /map from the
    // cache of a transient-local publisher, its key naming BuildingMap's hash.
    assert_eq!(r["doors_seen"], config["doors"]);
    assert!(r["clock_rate"].as_f64().is_some_and(|x| x > 1.0), "{r}");
    assert_eq!(r["clock_monotonic"], true);
    assert_eq!(r["map"]["levels"], serde_json::json!(["L1", "L2"]));
    let map_hash =
        mapc_ros2::type_hash::type_hash("rmf_building_map_msgs/msg/BuildingMap").expect("hash");
    assert_eq!(
        r["map"]["key"],
        format!("7/map/rmf_building_map_msgs::msg::dds_::BuildingMap_/{map_hash}")
    );
    assert_eq!(r["door_opened"], true, "{r}");

    // Attachments: consecutive sequence numbers, a current timestamp, the publisher's GID
    // (XXH3-128 of its liveliness token, computed by the xxhash package).
    let a = &r["attachment"];
    assert_eq!(a["sequence_increasing"], true, "{a}");
    assert!(
        a["timestamp_age_s"]
            .as_f64()
            .is_some_and(|s| s.abs() < 60.0),
        "{a}"
    );
    assert_eq!(a["one_gid"], true, "{a}");
    assert_eq!(a["gid_is_xxh3_of_token"], true, "{a}");

    // Liveliness tokens as rmw_zenoh_cpp's: the node, then its publishers and subscriptions,
    // all of one session, with the entity ids of one context.
    let tokens: Vec<String> = r["tokens"]
        .as_array()
        .expect("tokens")
        .iter()
        .map(|t| t.as_str().unwrap().to_string())
        .collect();
    let parts = |t: &str| t.split('/').map(String::from).collect::<Vec<_>>();
    let node: Vec<&String> = tokens.iter().filter(|t| t.contains("/NN/")).collect();
    assert_eq!(node.len(), 1, "{tokens:#?}");
    let n = parts(node[0]);
    assert_eq!(n.len(), 9, "{node:?}");
    assert_eq!(&n[..2], ["@ros2_lv", "7"]);
    let zid = n[2].clone();
    assert!(zid.chars().all(|c| c.is_ascii_hexdigit()), "{zid}");
    assert_eq!(n[3], n[4], "a node's entity id is its node id");
    assert_eq!(&n[5..], ["NN", "%", "%", "mapc"]);
    let expect = |kind: &str, topic: &str, ros_type: &str, hash: &str, qos: &str| {
        let (pkg, name) = ros_type.split_once("/msg/").unwrap();
        let tail = format!("/{kind}/%/%/mapc/%{topic}/{pkg}::msg::dds_::{name}_/{hash}/{qos}");
        let t = tokens
            .iter()
            .find(|t| t.ends_with(&tail))
            .unwrap_or_else(|| panic!("no token ending {tail}: {tokens:#?}"));
        let p = parts(t);
        assert_eq!(p[2], zid, "{t}");
        assert_eq!(p[3], n[3], "{t}: node id");
        assert_ne!(p[4], n[4], "{t}: an entity id of its own");
    };
    let h = |k: &str| hashes[k].as_str().unwrap().to_string();
    expect(
        "MP",
        "door_states",
        "rmf_door_msgs/msg/DoorState",
        &h("rmf_door_msgs/msg/DoorState"),
        "::,100:,:,:,,",
    );
    expect(
        "MS",
        "door_requests",
        "rmf_door_msgs/msg/DoorRequest",
        &h("rmf_door_msgs/msg/DoorRequest"),
        "::,10:,:,:,,",
    );
    expect(
        "MP",
        "clock",
        "rosgraph_msgs/msg/Clock",
        &h("rosgraph_msgs/msg/Clock"),
        "::,1:,:,:,,",
    );
    expect(
        "MP",
        "map",
        "rmf_building_map_msgs/msg/BuildingMap",
        &map_hash,
        ":1:,1:,:,:,,",
    );
    // The plugins' topics: 8 publishers + /clock + /map, 8 subscriptions, 1 node.
    assert_eq!(tokens.iter().filter(|t| t.contains("/MP/")).count(), 10);
    assert_eq!(tokens.iter().filter(|t| t.contains("/MS/")).count(), 8);
}

/// Without a router, mapc warns (as rmw_zenoh_cpp does) and names the way out, and still
/// runs; a bad `ZENOH_ROUTER_CHECK_ATTEMPTS` or `ZENOH_SESSION_CONFIG_URI` is a usage error.
#[test]
fn zenoh_settings_without_a_router() {
    if !namespace() {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let run = |env: &[(&str, &str)]| {
        let mut cmd = Command::new("unshare");
        cmd.args([
            "-rn",
            "sh",
            "-c",
            r#"ip link set lo up && "$MAPC" sim "$SCENARIO" --ros2 --rmw zenoh --rate 100 --until 2 -q"#,
        ])
        .env("MAPC", env!("CARGO_BIN_EXE_mapc"))
        .env(
            "SCENARIO",
            root.join("fixtures/two_level_clinic.scenario.yaml"),
        )
        .env_remove("RMW_IMPLEMENTATION");
        for (k, v) in env {
            cmd.env(k, v);
        }
        let out = cmd.output().expect("unshare runs");
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let (code, err) = run(&[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("warning: Zenoh: no router answered (1 attempt(s)")
            && err.contains("ros2 run rmw_zenoh_cpp rmw_zenohd"),
        "{err}"
    );
    let (code, err) = run(&[("ZENOH_ROUTER_CHECK_ATTEMPTS", "-1")]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("no router answered"), "{err}");
    let (code, err) = run(&[("ZENOH_ROUTER_CHECK_ATTEMPTS", "often")]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("ZENOH_ROUTER_CHECK_ATTEMPTS=often"), "{err}");
    let (code, err) = run(&[("ZENOH_SESSION_CONFIG_URI", "/nonexistent/zenoh.json5")]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("ZENOH_SESSION_CONFIG_URI=/nonexistent/zenoh.json5"),
        "{err}"
    );
}
