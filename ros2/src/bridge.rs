//! The DDS side of `mapc sim --ros2`, on RustDDS (pure Rust, no ROS install): one writer per
//! topic mapc publishes, one reader per topic it answers, `/clock` and the latched `/map`.
//! Topic and type names follow ROS 2's DDS mapping (`rt/door_states`,
//! `rmf_door_msgs::msg::dds_::DoorState_`); payloads are the CDR of `topics::encode`.
//!
//! The bridge never blocks the run once it runs: writes are keep-last, reads take what has
//! arrived. It waits twice, bounded: before the first step, for the peers already on the
//! bus to discover mapc's endpoints (`settle`), and at the end, for reliable readers to
//! acknowledge the last messages (`finish`); without these, a peer that is listening from
//! the start would still miss what mapc publishes in its first and last instants.

use crate::building_map::building_map;
use crate::cdr;
use crate::msgs::{self, rmf_building_map_msgs::BuildingMap, rosgraph_msgs::Clock, RosMsg};
use crate::ros_env::{self, DdsNetwork, RosEnv};
use crate::topics::{self, Qos};
use mapc_sim::msgs::{Msg, Published, Topic};
use rustdds::no_key::{DataReader, DataWriter, DeserializerAdapter, SerializerAdapter};
use rustdds::policy::{Durability, History, Reliability};
use rustdds::{
    DomainParticipant, DomainParticipantBuilder, QosPolicies, QosPolicyBuilder,
    RepresentationIdentifier, TopicKind,
};
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// A serialised message: the CDR body, after the 4-byte encapsulation header.
#[derive(Debug, Clone)]
pub struct Raw(Vec<u8>);

/// Passes CDR bodies through unchanged: messages are encoded by `topics`, once.
pub struct RawAdapter;

#[derive(Debug)]
pub struct Never;
impl std::fmt::Display for Never {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("never")
    }
}
impl std::error::Error for Never {}

impl SerializerAdapter<Raw> for RawAdapter {
    type Error = Never;
    fn output_encoding() -> RepresentationIdentifier {
        RepresentationIdentifier::CDR_LE
    }
    fn to_bytes(value: &Raw) -> Result<bytes::Bytes, Never> {
        Ok(bytes::Bytes::copy_from_slice(&value.0))
    }
}

/// Decodes to header + body, so that `cdr::decode` sees the byte order.
#[derive(Clone)]
pub struct RawDecoder;

impl rustdds::no_key::Decode<Raw> for RawDecoder {
    type Error = Never;
    fn decode_bytes(self, input: &[u8], enc: RepresentationIdentifier) -> Result<Raw, Never> {
        let mut v = Vec::with_capacity(input.len() + 4);
        v.extend(enc.to_bytes());
        v.extend([0, 0]);
        v.extend(input);
        Ok(Raw(v))
    }
}

impl DeserializerAdapter<Raw> for RawAdapter {
    type Error = Never;
    type Decoded = Raw;
    fn supported_encodings() -> &'static [RepresentationIdentifier] {
        &[
            RepresentationIdentifier::CDR_LE,
            RepresentationIdentifier::CDR_BE,
        ]
    }
    fn transform_decoded(decoded: Raw) -> Raw {
        decoded
    }
}

impl rustdds::no_key::DefaultDecoder<Raw> for RawAdapter {
    type Decoder = RawDecoder;
    const DECODER: RawDecoder = RawDecoder;
}

pub use crate::topics::{PLUGIN_INPUTS, PLUGIN_OUTPUTS};

fn dds_qos(q: Qos) -> QosPolicies {
    QosPolicyBuilder::new()
        .reliability(if q.reliable {
            Reliability::Reliable {
                max_blocking_time: rustdds::Duration::from_millis(100),
            }
        } else {
            Reliability::BestEffort
        })
        .durability(if q.transient_local {
            Durability::TransientLocal
        } else {
            Durability::Volatile
        })
        .history(History::KeepLast { depth: q.depth })
        .build()
}

/// History kept by every writer for repairs.
const WRITER_DEPTH: i32 = 1000;

/// How long `settle` waits at most, and how long discovery must stay unchanged.
const SETTLE_MAX: Duration = Duration::from_secs(3);
const SETTLE_MIN: Duration = Duration::from_millis(500);
const SETTLE_QUIET: Duration = Duration::from_millis(500);
/// How long `finish` waits at most for reliable readers' acknowledgments.
const FINISH_MAX: Duration = Duration::from_secs(2);

pub struct Bridge {
    // Fields drop in order: endpoints first, then the participant (dropping the participant
    // first stops RustDDS's event loop, and the endpoints can no longer be disposed of).
    writers: BTreeMap<Topic, DataWriter<Raw, RawAdapter>>,
    readers: Vec<(Topic, DataReader<Raw, RawAdapter>)>,
    clock: DataWriter<Raw, RawAdapter>,
    map: DataWriter<Raw, RawAdapter>,
    _participant: DomainParticipant,
    /// Requests that could not be decoded (wrong type on a topic).
    pub rejected: u64,
    /// Where mapc talks, for a line on stderr: domain, loopback or network, and why.
    pub summary: String,
}

/// Participant ids (RTPS 2.5 section 9.6.2.3) whose discovery ports receive mapc's unicast
/// announcements on each static peer and, on loopback, on 127.0.0.1: 0 to 32, as
/// rmw_cyclonedds_cpp's `MaxAutoParticipantIndex` for LOCALHOST (one id per ROS 2 process).
pub const MAX_PARTICIPANT_INDEX: u16 = 32;

/// Where the participant talks, from ROS 2's settings and the host's interfaces.
pub fn network(env: &RosEnv) -> Result<DdsNetwork, String> {
    let interfaces: Vec<ros_env::Interface> = rustdds::local_interfaces()
        .into_iter()
        .map(|i| ros_env::Interface {
            has_ipv4: !i.ipv4.is_empty(),
            up: i.up,
            loopback: i.loopback,
            multicast: i.multicast,
            name: i.name,
        })
        .collect();
    ros_env::choose_network(env, &interfaces)
}

impl Bridge {
    /// Joins the DDS domain of `env` (ROS 2's settings: domain, discovery range, static
    /// peers), on loopback when the range asks for it or when loopback is the only
    /// interface up, as Cyclone DDS and Fast DDS do under ROS 2's LOCALHOST range. With
    /// `plugins_only`, mapc publishes only what the Gazebo plugins publish and answers
    /// their requests; otherwise it publishes every message of the run (its own fleet
    /// layer and supervisors included) and reads nothing.
    pub fn new(
        env: &RosEnv,
        plugins_only: bool,
        building: &mapc_ir::Building,
    ) -> Result<Bridge, String> {
        let err = |e: &dyn std::fmt::Display| format!("DDS: {e}");
        crate::dds_log::init();
        let net = network(env)?;
        let mut peers = env.static_peer_addresses()?;
        let localhost = std::net::IpAddr::from([127, 0, 0, 1]);
        if net.loopback_only && !peers.contains(&localhost) {
            // As rmw_cyclonedds_cpp's `<Peer address="localhost"/>` for LOCALHOST: peers
            // restricted to this machine may not use multicast at all.
            peers.insert(0, localhost);
        }
        let mut summary = format!("DDS: domain {}, {}", env.domain_id, net.reason);
        if !peers.is_empty() {
            let shown: Vec<String> = peers.iter().map(|p| p.to_string()).collect();
            summary += &format!("; announced to {}", shown.join(", "));
        }
        let participant = DomainParticipantBuilder::new(env.domain_id)
            .loopback_only(net.loopback_only)
            .initial_peers(peers, MAX_PARTICIPANT_INDEX)
            .build()
            .map_err(|e| err(&e))?;
        let default = dds_qos(topics::DEFAULT_QOS);
        let publisher = participant
            .create_publisher(&default)
            .map_err(|e| err(&e))?;
        let subscriber = participant
            .create_subscriber(&default)
            .map_err(|e| err(&e))?;
        let writer = |name: &str, ros_type: &str, q: Qos| {
            // Writers keep a deep history so that a reliable reader that missed a sample
            // gets it repaired instead of waiting for a gap (history does not affect
            // matching; readers keep their own depth).
            let qos = dds_qos(Qos {
                depth: q.depth.max(WRITER_DEPTH),
                ..q
            });
            let topic = participant
                .create_topic(
                    format!("rt{name}"),
                    msgs::dds_type_name(ros_type),
                    &qos,
                    TopicKind::NoKey,
                )
                .map_err(|e| err(&e))?;
            let w = publisher
                .create_datawriter_no_key::<Raw, RawAdapter>(&topic, Some(qos))
                .map_err(|e| err(&e));
            // RustDDS hands new writers to its event loop through a channel of 10; creating
            // more in one burst can block for good (seen with 21), so let it take each one.
            std::thread::sleep(std::time::Duration::from_millis(5));
            w
        };
        let mut writers = BTreeMap::new();
        for &t in topics::outputs(plugins_only) {
            writers.insert(t, writer(t.name(), topics::ros_type(t), topics::qos(t))?);
        }
        let clock = writer("/clock", Clock::NAME, crate::mcap::CLOCK_QOS)?;
        let map = writer(
            crate::mcap::MAP_TOPIC,
            BuildingMap::NAME,
            crate::mcap::MAP_QOS,
        )?;
        map.write(Raw(cdr::body(&building_map(building))), None)
            .map_err(|e| err(&e))?;
        let mut readers = Vec::new();
        if plugins_only {
            for t in PLUGIN_INPUTS {
                // Volatile readers: they match writers of any durability (a transient-local
                // reader would refuse a volatile writer).
                let qos = dds_qos(Qos {
                    transient_local: false,
                    ..topics::qos(t)
                });
                let topic = participant
                    .create_topic(
                        format!("rt{}", t.name()),
                        msgs::dds_type_name(topics::ros_type(t)),
                        &qos,
                        TopicKind::NoKey,
                    )
                    .map_err(|e| err(&e))?;
                let r = subscriber
                    .create_datareader_no_key::<Raw, RawAdapter>(&topic, Some(qos))
                    .map_err(|e| err(&e))?;
                readers.push((t, r));
            }
        }
        Ok(Bridge {
            writers,
            readers,
            clock,
            map,
            _participant: participant,
            rejected: 0,
            summary,
        })
    }

    fn all_writers(&self) -> impl Iterator<Item = &DataWriter<Raw, RawAdapter>> {
        self.writers.values().chain([&self.clock, &self.map])
    }

    /// Before the first step: lets the peers already on the bus discover mapc's endpoints,
    /// so that they hear its first messages (writers are volatile: a sample published
    /// before a reader matched is not for that reader). Waits until discovery has been
    /// quiet (no participant status event from RustDDS: participant, reader or writer
    /// detected, matched, lost) for `SETTLE_QUIET`, at least `SETTLE_MIN`, then until every
    /// matched reliable reader has acknowledged its writer (a reader does once it has
    /// matched the writer on its side), `SETTLE_MAX` in all. Returns the remote readers
    /// matched meanwhile.
    pub fn settle(&self) -> usize {
        use rustdds::{DomainParticipantStatusEvent as E, StatusEvented};
        let start = Instant::now();
        let status = self._participant.status_listener();
        let mut last_event = start;
        let mut matched = 0;
        loop {
            std::thread::sleep(Duration::from_millis(20));
            let now = Instant::now();
            while let Some(e) = status.try_recv_status() {
                last_event = now;
                if matches!(e, E::RemoteReaderMatched { .. }) {
                    matched += 1;
                }
            }
            let waited = now - start;
            if waited >= SETTLE_MAX || (waited >= SETTLE_MIN && now - last_event >= SETTLE_QUIET) {
                break;
            }
        }
        self.wait_acknowledged(start + SETTLE_MAX);
        matched
    }

    /// Waits until every reliable reader has acknowledged everything written, or `until`.
    fn wait_acknowledged(&self, until: Instant) {
        for w in self.all_writers() {
            let left = until.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return;
            }
            let _ = w.wait_for_acknowledgments(left);
        }
    }

    /// At the end of the run: gives reliable readers up to `FINISH_MAX` to acknowledge the
    /// last messages (a repair needs the writer alive), then leaves the domain.
    pub fn finish(self) {
        self.wait_acknowledged(Instant::now() + FINISH_MAX);
    }

    /// Publishes a message of the run, if mapc publishes its topic.
    pub fn publish(&mut self, p: &Published) {
        let Some(w) = self.writers.get(&p.topic) else {
            return;
        };
        if let Some(bytes) = topics::encode(p.topic, &p.msg) {
            // A full history or no reader is not an error for a publisher.
            let _ = w.write(Raw(bytes[cdr::HEADER.len()..].to_vec()), None);
        }
    }

    /// Publishes `/clock`.
    pub fn clock(&mut self, t: f64) {
        let clock = crate::mcap::clock_msg(t);
        let _ = self.clock.write(Raw(cdr::body(&clock)), None);
    }

    /// Appends the requests that arrived since the last call, topic by topic.
    pub fn take_requests(&mut self, out: &mut Vec<(Topic, Msg)>) {
        for (topic, reader) in &mut self.readers {
            while let Ok(Some(sample)) = reader.take_next_sample() {
                match topics::decode(*topic, &sample.value().0) {
                    Ok(m) => out.push((*topic, m)),
                    Err(_) => self.rejected += 1,
                }
            }
        }
    }
}
