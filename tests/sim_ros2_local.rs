//! `mapc sim --ros2` on one machine: in a private network namespace whose only interface is
//! loopback (no veth), as in a container without a network, a CI job or a laptop offline.
//! An Eclipse Cyclone DDS peer (its Python package, in the venv .ci/run makes) configured
//! the way ROS 2's rmw_cyclonedds_cpp configures it for each setting plays RMF's door
//! supervisor (ros2/tests/python/rmf_peer.py with `quick`): it sees every door's state, the
//! latched `/map` and `/clock`, and opens a door.
//!
//! - `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST` (Jazzy on): Cyclone without multicast,
//!   `localhost` as its peer, participant indexes up to 32 (rmw_cyclonedds_cpp's
//!   `check_create_domain`); mapc's `--domain-id` wins over `ROS_DOMAIN_ID`.
//! - `ROS_LOCALHOST_ONLY=1` (Humble): Cyclone on the interface 127.0.0.1 (Humble's
//!   rmw_cyclonedds_cpp); the domain from `ROS_DOMAIN_ID=7` alone.
//! - No setting at all: loopback is the only interface, so mapc uses it.
//! - Loopback down: no interface can carry DDS; mapc exits 2 naming the settings.
//!
//! Prints `skipped: ...` without unshare, ip or the venv.

mod support;
use std::path::Path;
use std::process::Command;
use support::ros2::{namespace, peer};

/// The namespace: `lo` up with multicast and the multicast route, nothing else; then mapc
/// and the peer, mapc stopped with SIGINT when the peer is done.
const SCRIPT: &str = r#"set -e
ip link set lo up multicast on
ip route add 224.0.0.0/4 dev lo
test "$(ip -o link show | wc -l)" = 1  # no interface but lo
"$MAPC" sim "$SCENARIO" --ros2 --plugins-only --rate 10 $MAPC_FLAGS --until 900 \
  -q > "$DIR/mapc.out" 2> "$DIR/mapc.err" &
pid=$!
CYCLONEDDS_URI="$PEER_URI" "$PY" "$PEER" "$DIR/config.json" > "$DIR/peer.json" 2> "$DIR/peer.err" \
  || echo "peer failed: $?" >&2
kill -INT $pid
rc=0; wait $pid || rc=$?
echo "mapc exit $rc" >&2
"#;

/// rmw_cyclonedds_cpp's configuration for `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`.
const CYCLONE_LOCALHOST: &str = "<CycloneDDS><Domain><General><AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>32</MaxAutoParticipantIndex><Peers><Peer address=\"localhost\"/></Peers></Discovery></Domain></CycloneDDS>";
/// Humble's rmw_cyclonedds_cpp configuration for `ROS_LOCALHOST_ONLY=1`.
const CYCLONE_LOCALHOST_ONLY: &str = "<CycloneDDS><Domain><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces></General></Domain></CycloneDDS>";

/// Runs mapc with `env` and `flags` and the peer in domain `peer_domain` with Cyclone
/// configured by `peer_uri`; returns the peer's results and mapc's stderr.
fn run(
    env: &[(&str, &str)],
    flags: &str,
    peer_domain: u16,
    peer_uri: &str,
) -> Option<(serde_json::Value, String)> {
    let py = peer("cyclonedds.domain")?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().expect("tempdir");
    let defs: serde_json::Map<String, serde_json::Value> = mapc_ros2::msgs::definitions()
        .iter()
        .map(|(n, d)| (n.to_string(), serde_json::json!(d)))
        .collect();
    let config = serde_json::json!({
        "definitions": defs,
        "domain_id": peer_domain,
        "doors": ["L1_lobby_door", "L1_pharmacy_door", "L2_ward_a_door"],
        "quick": true,
    });
    std::fs::write(dir.path().join("config.json"), config.to_string()).expect("config");
    let mut cmd = Command::new("unshare");
    cmd.args(["-rn", "sh", "-c", SCRIPT])
        .env("MAPC", env!("CARGO_BIN_EXE_mapc"))
        .env("DIR", dir.path())
        .env("PY", &py)
        .env("PEER", root.join("ros2/tests/python/rmf_peer.py"))
        .env("PEER_URI", peer_uri)
        .env("MAPC_FLAGS", flags)
        .env(
            "SCENARIO",
            root.join("fixtures/two_level_clinic.scenario.yaml"),
        );
    for k in [
        "ROS_DOMAIN_ID",
        "ROS_AUTOMATIC_DISCOVERY_RANGE",
        "ROS_LOCALHOST_ONLY",
        "ROS_STATIC_PEERS",
        "RMW_IMPLEMENTATION",
        "CYCLONEDDS_URI",
    ] {
        cmd.env_remove(k);
    }
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().expect("unshare runs");
    let read = |n: &str| std::fs::read_to_string(dir.path().join(n)).unwrap_or_default();
    let mapc_err = read("mapc.err");
    let context = format!(
        "script: {}\npeer: {}\nmapc: {mapc_err}",
        String::from_utf8_lossy(&out.stderr),
        read("peer.err"),
    );
    assert!(out.status.success(), "{context}");
    assert!(
        context.contains("mapc exit 130"),
        "mapc stops on SIGINT\n{context}"
    );
    let r: serde_json::Value = serde_json::from_str(&read("peer.json"))
        .unwrap_or_else(|e| panic!("peer output: {e}\n{context}"));
    assert_eq!(r["errors"], serde_json::json!([]), "{context}");
    Some((r, mapc_err))
}

/// What every run on loopback shows: every door's state, the latched map, `/clock`
/// advancing, and the door opened on request.
fn assert_linked(r: &serde_json::Value) {
    assert_eq!(
        r["doors_seen"],
        serde_json::json!(["L1_lobby_door", "L1_pharmacy_door", "L2_ward_a_door"])
    );
    assert_eq!(r["map"]["levels"], serde_json::json!(["L1", "L2"]));
    assert!(r["clock_samples"].as_u64().is_some_and(|n| n >= 10), "{r}");
    assert!(r["clock_rate"].as_f64().is_some_and(|x| x > 1.0), "{r}");
    assert_eq!(r["clock_monotonic"], true);
    assert!(
        r["door_open_after"].as_f64().is_some_and(|t| t > 0.0),
        "{r}"
    );
}

#[test]
fn localhost_discovery_range_on_loopback_only() {
    let Some((r, err)) = run(
        &[
            ("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST"),
            ("ROS_DOMAIN_ID", "9"),
        ],
        "--domain-id 5",
        5,
        CYCLONE_LOCALHOST,
    ) else {
        return;
    };
    assert_linked(&r);
    assert!(
        err.contains(
            "DDS: domain 5, ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST: loopback only (127.0.0.1)"
        ),
        "{err}"
    );
}

#[test]
fn localhost_only_and_domain_from_environment() {
    let Some((r, err)) = run(
        &[("ROS_LOCALHOST_ONLY", "1"), ("ROS_DOMAIN_ID", "7")],
        "",
        7,
        CYCLONE_LOCALHOST_ONLY,
    ) else {
        return;
    };
    assert_linked(&r);
    assert!(
        err.contains("DDS: domain 7, ROS_LOCALHOST_ONLY=1: loopback only"),
        "{err}"
    );
}

#[test]
fn loopback_alone_is_used_without_settings() {
    let Some((r, err)) = run(&[], "", 0, CYCLONE_LOCALHOST) else {
        return;
    };
    assert_linked(&r);
    assert!(
        err.contains("DDS: domain 0, no interface but loopback is up"),
        "{err}"
    );
}

#[test]
fn no_usable_interface_is_an_error_naming_the_settings() {
    if !namespace() {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for env in [None, Some(("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST"))] {
        // A fresh namespace's `lo` is down.
        let mut cmd = Command::new("unshare");
        cmd.args([
            "-rn",
            "sh",
            "-c",
            r#""$MAPC" sim "$SCENARIO" --ros2 --until 10 -q"#,
        ])
        .env("MAPC", env!("CARGO_BIN_EXE_mapc"))
        .env(
            "SCENARIO",
            root.join("fixtures/two_level_clinic.scenario.yaml"),
        )
        .env_remove("ROS_AUTOMATIC_DISCOVERY_RANGE")
        .env_remove("ROS_LOCALHOST_ONLY");
        if let Some((k, v)) = env {
            cmd.env(k, v);
        }
        let out = cmd.output().expect("unshare runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{env:?}: {err}");
        assert!(
            err.contains("error: DDS: no network interface can carry DDS"),
            "{err}"
        );
        assert!(err.contains("lo (down, loopback"), "{err}");
        assert!(err.contains("ip link set lo up"), "{err}");
        if env.is_none() {
            assert!(
                err.contains("ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST")
                    && err.contains("ROS_LOCALHOST_ONLY=1")
                    && err.contains("ROS_STATIC_PEERS"),
                "{err}"
            );
        }
    }
}
