//! The middleware behind `mapc sim --ros2`: DDS (`bridge.rs`, RustDDS) or rmw_zenoh's
//! Zenoh (`zenoh_bridge.rs`), chosen by `--rmw` or `RMW_IMPLEMENTATION` (`ros_env.rs`).
//! Both publish the same topics with the same types, QoS and CDR, and read the same
//! requests; the run sees no difference.

use crate::ros_env::{Rmw, RosEnv};
use mapc_sim::msgs::{Msg, Published, Topic};

pub enum Link {
    #[cfg(feature = "dds")]
    Dds(crate::bridge::Bridge),
    #[cfg(feature = "zenoh")]
    Zenoh(crate::zenoh_bridge::ZenohBridge),
}

impl Link {
    /// Joins ROS 2 as `env` says, the environment read through `get`.
    #[allow(unused_variables)]
    pub fn open(
        env: &RosEnv,
        get: &dyn Fn(&str) -> Option<String>,
        plugins_only: bool,
        building: &mapc_ir::Building,
    ) -> Result<Link, String> {
        match env.rmw {
            #[cfg(feature = "dds")]
            Rmw::Dds => crate::bridge::Bridge::new(env, plugins_only, building).map(Link::Dds),
            #[cfg(feature = "zenoh")]
            Rmw::Zenoh => crate::zenoh_bridge::ZenohBridge::new(env, get, plugins_only, building)
                .map(Link::Zenoh),
            #[allow(unreachable_patterns)]
            other => Err(format!(
                "--ros2 over {other:?}: this mapc was built without it (cargo feature `{}`)",
                if other == Rmw::Dds { "dds" } else { "zenoh" }
            )),
        }
    }

    /// A line saying where mapc talks.
    pub fn summary(&self) -> &str {
        match self {
            #[cfg(feature = "dds")]
            Link::Dds(b) => &b.summary,
            #[cfg(feature = "zenoh")]
            Link::Zenoh(b) => &b.summary,
        }
    }

    /// Before the first step: lets the peers already there learn of mapc.
    pub fn settle(&self) {
        match self {
            #[cfg(feature = "dds")]
            Link::Dds(b) => {
                b.settle();
            }
            #[cfg(feature = "zenoh")]
            Link::Zenoh(b) => b.settle(),
        }
    }

    /// After the last step: lets the last messages arrive, then leaves.
    pub fn finish(self) {
        match self {
            #[cfg(feature = "dds")]
            Link::Dds(b) => b.finish(),
            #[cfg(feature = "zenoh")]
            Link::Zenoh(b) => b.finish(),
        }
    }

    pub fn publish(&mut self, p: &Published) {
        match self {
            #[cfg(feature = "dds")]
            Link::Dds(b) => b.publish(p),
            #[cfg(feature = "zenoh")]
            Link::Zenoh(b) => b.publish(p),
        }
    }

    pub fn clock(&mut self, t: f64) {
        match self {
            #[cfg(feature = "dds")]
            Link::Dds(b) => b.clock(t),
            #[cfg(feature = "zenoh")]
            Link::Zenoh(b) => b.clock(t),
        }
    }

    pub fn take_requests(&mut self, out: &mut Vec<(Topic, Msg)>) {
        match self {
            #[cfg(feature = "dds")]
            Link::Dds(b) => b.take_requests(out),
            #[cfg(feature = "zenoh")]
            Link::Zenoh(b) => b.take_requests(out),
        }
    }
}
