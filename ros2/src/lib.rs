//! mapc-ros2: the runtime's messages in their ROS 2 form (CDR, the types of
//! rmf_internal_msgs and rmf_building_map_msgs), rosbag2-compatible MCAP recording, and (with
//! the `dds` and `zenoh` features) the DDS and rmw_zenoh bridges behind `mapc sim --ros2`.
//!
//! Nothing here changes a run: the recorder and the bridge see what the runtime's observer
//! sees, and the bridge only adds the requests other nodes send.

#[cfg(feature = "dds")]
pub mod bridge;
pub mod building_map;
pub mod cdr;
#[cfg(feature = "dds")]
mod dds_log;
#[cfg(any(feature = "dds", feature = "zenoh"))]
pub mod link;
pub mod mcap;
pub mod msgs;
pub mod ros_env;
pub mod topics;
pub mod type_hash;
#[cfg(feature = "zenoh")]
pub mod zenoh_bridge;
