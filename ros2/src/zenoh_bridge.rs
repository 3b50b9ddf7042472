//! The Zenoh side of `mapc sim --ros2 --rmw zenoh`: mapc as a ROS 2 node on rmw_zenoh_cpp's
//! wire format, through the `zenoh` crate (Zenoh's own Rust implementation). Same topics,
//! types, QoS and CDR payloads as the DDS bridge (docs/ros2.md); what rmw_zenoh_cpp adds
//! on top of Zenoh, as its sources do it:
//!
//! - a topic's key expression is `<domain>/<topic without its leading slash>/<DDS type
//!   name>/RIHS01_<type hash>` (`type_hash.rs`), so only the same definition matches;
//! - every node, publisher and subscription has a liveliness token (`@ros2_lv/<domain>/
//!   <session id>/<node id>/<entity id>/<NN|MP|MS>/<enclave>/<namespace>/<node>[/<topic>/
//!   <type>/<hash>/<qos>]`, `/` in names written `%`), which `ros2 node list`, `ros2 topic
//!   info` and rmw_zenoh's graph cache read;
//! - every sample carries an attachment: sequence number (i64), source timestamp (i64,
//!   ns since the epoch) and the publisher's GID (16 bytes: XXH3-128 of its liveliness key
//!   expression), in zenoh-ext's serialization (little endian, the GID as a sequence of
//!   16 bytes with its length);
//! - publishers are zenoh-ext advanced publishers; a transient-local one (`/map`) keeps its
//!   last `depth` samples in a cache that late subscriptions query, and a reliable
//!   transient-local one sends sporadic heartbeats (500 ms) so they can detect misses.
//!
//! The session is a peer that connects to a router on `tcp/localhost:7447`, with multicast
//! scouting off and gossip on (rmw_zenoh_cpp's default session config), or the config file
//! of `ZENOH_SESSION_CONFIG_URI`, then `ZENOH_CONFIG_OVERRIDE`; it checks for a router
//! `ZENOH_ROUTER_CHECK_ATTEMPTS` times, one second apart (default 1; 0: until one answers;
//! negative: not at all), and like rmw_zenoh_cpp goes on with a warning if none answered.

use crate::building_map::building_map;
use crate::cdr;
use crate::msgs::{self, rmf_building_map_msgs::BuildingMap, rosgraph_msgs::Clock, RosMsg};
use crate::ros_env::RosEnv;
use crate::topics::{self, Qos, PLUGIN_INPUTS};
use crate::type_hash::type_hash;
use mapc_sim::msgs::{Msg, Published, Topic};
use std::collections::BTreeMap;
use std::time::{Duration, SystemTime, UNIX_EPOCH};
use zenoh::handlers::FifoChannelHandler;
use zenoh::liveliness::LivelinessToken;
use zenoh::pubsub::Subscriber;
use zenoh::qos::{CongestionControl, Reliability};
use zenoh::sample::Sample;
use zenoh::{Config, Session, Wait};
use zenoh_ext::{AdvancedPublisher, AdvancedPublisherBuilderExt, CacheConfig, MissDetectionConfig};

/// The ROS node mapc is, in the root namespace and enclave.
pub const NODE_NAME: &str = "mapc";

/// rmw_zenoh_cpp's default QoS, against which the liveliness token writes only differences:
/// reliable, volatile, keep last 42, infinite deadline, lifespan and lease, automatic.
const DEFAULT_DEPTH: i32 = 42;

/// rmw_zenoh_cpp's default session: a peer of the local router.
const DEFAULT_ROUTER: &str = "tcp/localhost:7447";

/// How long to let declarations reach the peers already there before the first step, and
/// the last samples leave before the session closes.
const SETTLE: Duration = Duration::from_millis(800);
const FINISH: Duration = Duration::from_millis(500);

/// The QoS part of a liveliness token: `reliability:durability:history,depth:deadline_s,
/// deadline_ns:lifespan_s,lifespan_ns:liveliness,lease_s,lease_ns`, each empty where it is
/// rmw_zenoh_cpp's default (rmw enum values: RELIABLE 1, BEST_EFFORT 2, TRANSIENT_LOCAL 1,
/// VOLATILE 2).
pub fn qos_keyexpr(q: Qos) -> String {
    let reliability = if q.reliable { "" } else { "2" };
    let durability = if q.transient_local { "1" } else { "" };
    let depth = if q.depth == DEFAULT_DEPTH {
        String::new()
    } else {
        q.depth.to_string()
    };
    format!("{reliability}:{durability}:,{depth}:,:,:,,")
}

/// A name in a liveliness token: `/` written `%` (key expressions cannot hold `//`).
pub fn mangle(name: &str) -> String {
    name.replace('/', "%")
}

/// A topic's data key expression.
pub fn topic_keyexpr(domain: u16, topic: &str, ros_type: &str) -> Result<String, String> {
    Ok(format!(
        "{domain}/{}/{}/{}",
        topic.trim_matches('/'),
        msgs::dds_type_name(ros_type),
        type_hash(ros_type)?
    ))
}

/// An entity's liveliness token; `topic` is (name, ROS type, QoS) for publishers ("MP") and
/// subscriptions ("MS"), `None` for the node ("NN").
pub fn liveliness_keyexpr(
    domain: u16,
    zid: &str,
    node_id: usize,
    entity_id: usize,
    kind: &str,
    topic: Option<(&str, &str, Qos)>,
) -> Result<String, String> {
    let mut ke = format!(
        "@ros2_lv/{domain}/{zid}/{node_id}/{entity_id}/{kind}/%/%/{}",
        mangle(NODE_NAME)
    );
    if let Some((name, ros_type, q)) = topic {
        ke += &format!(
            "/{}/{}/{}/{}",
            mangle(name),
            mangle(&msgs::dds_type_name(ros_type)),
            type_hash(ros_type)?,
            qos_keyexpr(q)
        );
    }
    Ok(ke)
}

/// The GID rmw_zenoh_cpp gives an entity: XXH3-128 of its liveliness key expression, low
/// 64 bits first, each little endian.
pub fn gid(liveliness_keyexpr: &str) -> [u8; 16] {
    xxhash_rust::xxh3::xxh3_128(liveliness_keyexpr.as_bytes()).to_le_bytes()
}

/// A sample's attachment: sequence number, source timestamp, GID.
pub fn attachment(sequence_number: i64, source_timestamp: i64, gid: &[u8; 16]) -> Vec<u8> {
    let mut a = Vec::with_capacity(33);
    a.extend(sequence_number.to_le_bytes());
    a.extend(source_timestamp.to_le_bytes());
    a.push(16); // the sequence length, a LEB128 varint
    a.extend(gid);
    a
}

struct Writer {
    publisher: AdvancedPublisher<'static>,
    gid: [u8; 16],
    sequence_number: i64,
}

impl Writer {
    fn put(&mut self, cdr: Vec<u8>) {
        self.sequence_number += 1;
        let now = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map(|d| d.as_nanos() as i64)
            .unwrap_or(0);
        // A full queue or no subscriber is not an error for a publisher.
        let _ = self
            .publisher
            .put(cdr)
            .attachment(attachment(self.sequence_number, now, &self.gid))
            .wait();
    }
}

pub struct ZenohBridge {
    // Fields drop in order: endpoints and tokens first, then the session.
    writers: BTreeMap<Topic, Writer>,
    readers: Vec<(Topic, Subscriber<FifoChannelHandler<Sample>>)>,
    clock: Writer,
    _map: Writer,
    _tokens: Vec<LivelinessToken>,
    session: Session,
    /// Requests that could not be decoded (wrong type on a topic).
    pub rejected: u64,
    /// Where mapc talks, for a line on stderr.
    pub summary: String,
}

/// The session configuration: `ZENOH_SESSION_CONFIG_URI`'s file or rmw_zenoh_cpp's
/// default, then `ZENOH_CONFIG_OVERRIDE` (`key=value;...`, values in JSON5).
fn config(get: &dyn Fn(&str) -> Option<String>) -> Result<(Config, String), String> {
    let (mut config, from) = match get("ZENOH_SESSION_CONFIG_URI").filter(|v| !v.is_empty()) {
        Some(path) => (
            Config::from_file(&path).map_err(|e| {
                format!("ZENOH_SESSION_CONFIG_URI={path}: not a Zenoh configuration ({e})")
            })?,
            format!("ZENOH_SESSION_CONFIG_URI={path}"),
        ),
        None => {
            let mut c = Config::default();
            for (k, v) in [
                ("mode", "\"peer\"".to_string()),
                ("connect/endpoints", format!("[\"{DEFAULT_ROUTER}\"]")),
                ("listen/endpoints", "[\"tcp/localhost:0\"]".into()),
                ("scouting/multicast/enabled", "false".into()),
                ("scouting/gossip/enabled", "true".into()),
                (
                    "timestamping/enabled",
                    "{router: true, peer: true, client: false}".into(),
                ),
            ] {
                c.insert_json5(k, &v)
                    .map_err(|e| format!("Zenoh: default configuration {k}: {e}"))?;
            }
            (c, format!("peer of the router on {DEFAULT_ROUTER}"))
        }
    };
    if let Some(over) = get("ZENOH_CONFIG_OVERRIDE").filter(|v| !v.is_empty()) {
        for pair in over.split(';').filter(|p| !p.trim().is_empty()) {
            let (k, v) = pair.split_once('=').ok_or_else(|| {
                format!("ZENOH_CONFIG_OVERRIDE: `{pair}` is not key=value (e.g. mode=\"client\")")
            })?;
            config
                .insert_json5(k.trim(), v.trim())
                .map_err(|e| format!("ZENOH_CONFIG_OVERRIDE: `{pair}`: {e}"))?;
        }
    }
    Ok((config, from))
}

/// `ZENOH_ROUTER_CHECK_ATTEMPTS`: how many times to look for a router (`None`: never,
/// `u64::MAX`: until one answers).
fn router_check_attempts(get: &dyn Fn(&str) -> Option<String>) -> Result<Option<u64>, String> {
    match get("ZENOH_ROUTER_CHECK_ATTEMPTS").filter(|v| !v.is_empty()) {
        None => Ok(Some(1)),
        Some(v) => match v.trim().parse::<i64>() {
            Ok(n) if n > 0 => Ok(Some(n as u64)),
            Ok(0) => Ok(Some(u64::MAX)),
            Ok(_) => Ok(None),
            Err(_) => Err(format!(
                "ZENOH_ROUTER_CHECK_ATTEMPTS={v}: use a number of attempts (0: until a router \
                 answers, negative: no check)"
            )),
        },
    }
}

impl ZenohBridge {
    /// Opens a Zenoh session as rmw_zenoh_cpp would for a node `mapc` in the domain of
    /// `env`, with the environment read through `get`; declares the publishers and (with
    /// `plugins_only`) the subscriptions of the DDS bridge, and publishes `/map`.
    pub fn new(
        env: &RosEnv,
        get: &dyn Fn(&str) -> Option<String>,
        plugins_only: bool,
        building: &mapc_ir::Building,
    ) -> Result<ZenohBridge, String> {
        let err = |e: &dyn std::fmt::Display| format!("Zenoh: {e}");
        let (config, from) = config(get)?;
        let attempts = router_check_attempts(get)?;
        let session = zenoh::open(config).wait().map_err(|e| err(&e))?;
        let zid = session.zid().to_string();
        let domain = env.domain_id;
        let mut summary = format!("Zenoh: domain {domain}, session {zid}, {from}");
        if let Some(attempts) = attempts {
            let mut found = 0;
            let mut tried = 0;
            while tried < attempts {
                found = session.info().routers_zid().wait().count();
                tried += 1;
                if found > 0 || tried >= attempts {
                    break;
                }
                std::thread::sleep(Duration::from_secs(1));
            }
            if found == 0 {
                eprintln!(
                    "warning: Zenoh: no router answered ({tried} attempt(s), \
                     ZENOH_ROUTER_CHECK_ATTEMPTS); other nodes will not find mapc until one \
                     runs: start one with `ros2 run rmw_zenoh_cpp rmw_zenohd`, or point \
                     ZENOH_SESSION_CONFIG_URI at a configuration that connects to yours"
                );
            } else {
                summary += &format!(", {found} router(s) connected");
            }
        }

        let mut next_id = 0usize;
        let mut id = || {
            next_id += 1;
            next_id - 1
        };
        let node_id = id();
        let mut tokens = Vec::new();
        let mut token = |ke: &str| -> Result<(), String> {
            tokens.push(
                session
                    .liveliness()
                    .declare_token(ke.to_string())
                    .wait()
                    .map_err(|e| err(&e))?,
            );
            Ok(())
        };
        token(&liveliness_keyexpr(
            domain, &zid, node_id, node_id, "NN", None,
        )?)?;

        let mut writer = |name: &str, ros_type: &str, q: Qos| -> Result<Writer, String> {
            let live =
                liveliness_keyexpr(domain, &zid, node_id, id(), "MP", Some((name, ros_type, q)))?;
            let builder = session
                .declare_publisher(topic_keyexpr(domain, name, ros_type)?)
                .reliability(if q.reliable {
                    Reliability::Reliable
                } else {
                    Reliability::BestEffort
                })
                .congestion_control(CongestionControl::Drop)
                .advanced();
            let builder = if q.transient_local {
                let b = builder
                    .cache(CacheConfig::default().max_samples(q.depth.max(1) as usize))
                    .publisher_detection();
                if q.reliable {
                    b.sample_miss_detection(
                        MissDetectionConfig::default()
                            .sporadic_heartbeat(Duration::from_millis(500)),
                    )
                } else {
                    b
                }
            } else {
                builder
            };
            let publisher = builder.wait().map_err(|e| err(&e))?;
            token(&live)?;
            Ok(Writer {
                publisher,
                gid: gid(&live),
                sequence_number: 0,
            })
        };
        let mut writers = BTreeMap::new();
        for &t in topics::outputs(plugins_only) {
            writers.insert(t, writer(t.name(), topics::ros_type(t), topics::qos(t))?);
        }
        let clock = writer("/clock", Clock::NAME, crate::mcap::CLOCK_QOS)?;
        let mut map = writer(
            crate::mcap::MAP_TOPIC,
            BuildingMap::NAME,
            crate::mcap::MAP_QOS,
        )?;
        map.put(cdr::encode(&building_map(building)));

        let mut readers = Vec::new();
        if plugins_only {
            for t in PLUGIN_INPUTS {
                // Volatile, as the DDS bridge's readers: what arrives from now on.
                let q = Qos {
                    transient_local: false,
                    ..topics::qos(t)
                };
                let name = t.name();
                let ros_type = topics::ros_type(t);
                let sub = session
                    .declare_subscriber(topic_keyexpr(domain, name, ros_type)?)
                    .wait()
                    .map_err(|e| err(&e))?;
                token(&liveliness_keyexpr(
                    domain,
                    &zid,
                    node_id,
                    id(),
                    "MS",
                    Some((name, ros_type, q)),
                )?)?;
                readers.push((t, sub));
            }
        }
        Ok(ZenohBridge {
            writers,
            readers,
            clock,
            _map: map,
            _tokens: tokens,
            session,
            rejected: 0,
            summary,
        })
    }

    /// Before the first step: lets the declarations reach the peers already there.
    pub fn settle(&self) {
        std::thread::sleep(SETTLE);
    }

    /// After the last step: lets the last samples leave, then closes the session.
    pub fn finish(self) {
        std::thread::sleep(FINISH);
        let ZenohBridge {
            writers,
            readers,
            clock,
            _map,
            _tokens,
            session,
            ..
        } = self;
        drop((writers, readers, clock, _map, _tokens));
        let _ = session.close().wait();
    }

    /// Publishes a message of the run, if mapc publishes its topic.
    pub fn publish(&mut self, p: &Published) {
        let Some(w) = self.writers.get_mut(&p.topic) else {
            return;
        };
        if let Some(bytes) = topics::encode(p.topic, &p.msg) {
            w.put(bytes);
        }
    }

    /// Publishes `/clock`.
    pub fn clock(&mut self, t: f64) {
        self.clock.put(cdr::encode(&crate::mcap::clock_msg(t)));
    }

    /// Appends the requests that arrived since the last call, topic by topic.
    pub fn take_requests(&mut self, out: &mut Vec<(Topic, Msg)>) {
        for (topic, sub) in &self.readers {
            while let Ok(Some(sample)) = sub.try_recv() {
                match topics::decode(*topic, &sample.payload().to_bytes()) {
                    Ok(m) => out.push((*topic, m)),
                    Err(_) => self.rejected += 1,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_expressions_as_rmw_zenoh() {
        assert_eq!(
            topic_keyexpr(0, "/door_states", "rmf_door_msgs/msg/DoorState").unwrap(),
            "0/door_states/rmf_door_msgs::msg::dds_::DoorState_/\
             RIHS01_1cb9d98f19c66cbc1f9acb16faaa90c63a7b65021bd26c69958d96f0a0388bb2"
        );
        let q = topics::DEFAULT_QOS;
        assert_eq!(qos_keyexpr(q), "::,10:,:,:,,");
        assert_eq!(qos_keyexpr(crate::mcap::MAP_QOS), ":1:,1:,:,:,,");
        assert_eq!(
            liveliness_keyexpr(7, "ab12", 0, 0, "NN", None).unwrap(),
            "@ros2_lv/7/ab12/0/0/NN/%/%/mapc"
        );
        let ke = liveliness_keyexpr(
            7,
            "ab12",
            0,
            3,
            "MS",
            Some(("/door_requests", "rmf_door_msgs/msg/DoorRequest", q)),
        )
        .unwrap();
        assert_eq!(
            ke,
            "@ros2_lv/7/ab12/0/3/MS/%/%/mapc/%door_requests/\
             rmf_door_msgs::msg::dds_::DoorRequest_/\
             RIHS01_3145b5d97064f89b0a0db953b8167ddeeefbc2914c24a603c3bdc51f122f143e/\
             ::,10:,:,:,,"
        );
    }

    #[test]
    fn attachment_is_zenoh_ext_serialization() {
        let gid: [u8; 16] = std::array::from_fn(|i| i as u8 + 1);
        let ours = attachment(5, -7, &gid);
        let theirs = zenoh_ext::z_serialize(&(5i64, -7i64, gid.to_vec()));
        assert_eq!(ours, theirs.to_bytes().to_vec());
        assert_eq!(ours.len(), 33);
    }

    #[test]
    fn router_check_attempts_as_rmw_zenoh() {
        let env = |v: &'static str| {
            move |k: &str| (k == "ZENOH_ROUTER_CHECK_ATTEMPTS").then(|| v.to_string())
        };
        assert_eq!(router_check_attempts(&|_| None).unwrap(), Some(1));
        assert_eq!(router_check_attempts(&env("3")).unwrap(), Some(3));
        assert_eq!(router_check_attempts(&env("0")).unwrap(), Some(u64::MAX));
        assert_eq!(router_check_attempts(&env("-1")).unwrap(), None);
        assert!(router_check_attempts(&env("x")).is_err());
    }
}
