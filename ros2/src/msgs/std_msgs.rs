//! std_msgs (mapc's task events travel as JSON in a `String`: RMF has no message for them).

use super::{ros_msg, Definition};
pub use mapc_sim::msgs::Header;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct String {
    pub data: std::string::String,
}
pub(crate) const STRING: Definition = ("std_msgs/msg/String", "string data\n");
ros_msg!(String, STRING);

pub(crate) const HEADER: Definition = (
    "std_msgs/msg/Header",
    "builtin_interfaces/Time stamp\nstring frame_id\n",
);
ros_msg!(Header, HEADER);
