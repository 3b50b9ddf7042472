//! rosbag2-compatible MCAP recording: profile `ros2`, one `ros2msg` schema per message type
//! (the `.msg` text with its dependencies), one `cdr` channel per topic with the
//! `offered_qos_profiles` rosbag2 uses on playback, and each message at its sim time.

use crate::building_map::building_map;
use crate::cdr;
use crate::msgs::{self, rmf_building_map_msgs::BuildingMap, rosgraph_msgs::Clock, RosMsg};
use crate::topics::{self, Qos};
use mapc_sim::msgs::Published;
use std::collections::BTreeMap;
use std::io::{Seek, Write};

/// The topic of the building map.
pub const MAP_TOPIC: &str = "/map";
/// `/map` is latched: transient local, depth 1 (building_map_server's QoS).
pub const MAP_QOS: Qos = Qos {
    reliable: true,
    transient_local: true,
    depth: 1,
};

/// `/clock`: reliable, volatile, depth 1, as Gazebo's clock bridge publishes it.
pub const CLOCK_QOS: Qos = Qos {
    reliable: true,
    transient_local: false,
    depth: 1,
};

/// `/clock` in a recording: every 20 ms of simulated time (50 Hz; every second step at the
/// default 10 ms), so that nodes with `use_sim_time` follow a `ros2 bag play` without
/// `--clock`, and the file stays deterministic (a wall-clock rate would not be).
pub const CLOCK_PERIOD: f64 = 0.02;

/// The `/clock` message of simulated time `t` (its stamp is the log time MCAP gives it).
pub fn clock_msg(t: f64) -> Clock {
    let n = ns(t);
    Clock {
        clock: msgs::builtin_interfaces::Time {
            sec: (n / 1_000_000_000).min(i32::MAX as u64) as i32,
            nanosec: (n % 1_000_000_000) as u32,
        },
    }
}

pub struct Recorder<W: Write + Seek> {
    writer: mcap::Writer<W>,
    /// Channel id per topic name, created on first use.
    channels: BTreeMap<String, u16>,
    sequence: u32,
    /// The `CLOCK_PERIOD` tick of the last `/clock` written.
    clock_tick: Option<u64>,
}

fn ns(t: f64) -> u64 {
    (t.max(0.0) * 1e9).round() as u64
}

/// The YAML rosbag2 writes as a channel's `offered_qos_profiles` (Humble and later):
/// history keep-last (1), reliability reliable (1) / best effort (2), durability transient
/// local (1) / volatile (2), infinite deadline, lifespan and lease, automatic liveliness.
pub fn qos_yaml(q: Qos) -> String {
    let inf = "\n    sec: 2147483647\n    nsec: 4294967295";
    format!(
        "- history: 1\n  depth: {}\n  reliability: {}\n  durability: {}\n  deadline:{inf}\n  \
         lifespan:{inf}\n  liveliness: 1\n  liveliness_lease_duration:{inf}\n  \
         avoid_ros_namespace_conventions: false\n",
        q.depth,
        if q.reliable { 1 } else { 2 },
        if q.transient_local { 1 } else { 2 },
    )
}

impl<W: Write + Seek> Recorder<W> {
    pub fn new(w: W) -> Result<Recorder<W>, String> {
        let writer = mcap::WriteOptions::new()
            .profile("ros2")
            .library(concat!("mapc ", env!("CARGO_PKG_VERSION")))
            .compression(None)
            .create(w)
            .map_err(|e| e.to_string())?;
        Ok(Recorder {
            writer,
            channels: BTreeMap::new(),
            sequence: 0,
            clock_tick: None,
        })
    }

    fn channel(&mut self, topic: &str, ros_type: &str, qos: Qos) -> Result<u16, String> {
        if let Some(&c) = self.channels.get(topic) {
            return Ok(c);
        }
        let schema = msgs::schema_text(ros_type).ok_or_else(|| format!("no schema {ros_type}"))?;
        let err = |e: mcap::McapError| e.to_string();
        let sid = self
            .writer
            .add_schema(ros_type, "ros2msg", schema.as_bytes())
            .map_err(err)?;
        let meta = BTreeMap::from([("offered_qos_profiles".to_string(), qos_yaml(qos))]);
        let c = self
            .writer
            .add_channel(sid, topic, "cdr", &meta)
            .map_err(err)?;
        self.channels.insert(topic.to_string(), c);
        Ok(c)
    }

    fn write(&mut self, channel: u16, t: f64, data: &[u8]) -> Result<(), String> {
        self.sequence += 1;
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: self.sequence,
            log_time: ns(t),
            publish_time: ns(t),
        };
        self.writer
            .write_to_known_channel(&header, data)
            .map_err(|e| e.to_string())
    }

    /// The building map on `/map` at time 0 (what building_map_server latches).
    pub fn map(&mut self, map: &BuildingMap) -> Result<(), String> {
        let c = self.channel(MAP_TOPIC, BuildingMap::NAME, MAP_QOS)?;
        self.write(c, 0.0, &cdr::encode(map))
    }

    /// Convenience: the map of a building.
    pub fn building(&mut self, b: &mapc_ir::Building) -> Result<(), String> {
        self.map(&building_map(b))
    }

    /// `/clock` at step time `t`, if `t` starts a new `CLOCK_PERIOD` (the first step does).
    pub fn clock(&mut self, t: f64) -> Result<(), String> {
        // The tolerance keeps 0.06 (= 0.02 * 2.9999999) in tick 3.
        let tick = (t / CLOCK_PERIOD + 1e-6).floor().max(0.0) as u64;
        if self.clock_tick.is_some_and(|k| k >= tick) {
            return Ok(());
        }
        self.clock_tick = Some(tick);
        let c = self.channel("/clock", Clock::NAME, CLOCK_QOS)?;
        self.write(c, t, &cdr::encode(&clock_msg(t)))
    }

    /// One message of the run.
    pub fn record(&mut self, p: &Published) -> Result<(), String> {
        let Some(bytes) = topics::encode(p.topic, &p.msg) else {
            return Ok(());
        };
        let c = self.channel(
            p.topic.name(),
            topics::ros_type(p.topic),
            topics::qos(p.topic),
        )?;
        self.write(c, p.t, &bytes)
    }

    /// Writes the summary and footer; returns the underlying writer.
    pub fn finish(mut self) -> Result<W, String> {
        self.writer.finish().map_err(|e| e.to_string())?;
        Ok(self.writer.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Messages written for steps `0, dt, 2 dt, ...` up to `end` (exclusive).
    fn clocks(dt: f64, end: f64) -> u32 {
        let mut r = Recorder::new(std::io::Cursor::new(Vec::new())).unwrap();
        let steps = (end / dt).round() as u32;
        for i in 0..steps {
            r.clock(f64::from(i) * dt).unwrap();
        }
        r.sequence
    }

    #[test]
    fn clock_every_20_ms_of_sim_time() {
        // 10 ms steps: every other one; 50 ms steps: every one; 1 ms steps: every 20th.
        assert_eq!(clocks(0.01, 10.0), 500);
        assert_eq!(clocks(0.05, 10.0), 200);
        assert_eq!(clocks(0.001, 1.0), 50);
    }

    #[test]
    fn clock_stamp_is_the_log_time() {
        for t in [0.0, 0.02, 1.5, 299.98, 1e6 + 0.123] {
            let c = clock_msg(t).clock;
            assert_eq!(
                u64::from(c.sec as u32) * 1_000_000_000 + u64::from(c.nanosec),
                ns(t)
            );
        }
        assert_eq!(clock_msg(2.5).clock.nanosec, 500_000_000);
    }
}
