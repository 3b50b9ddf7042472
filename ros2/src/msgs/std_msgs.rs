//! std_msgs (mapc's task events travel as JSON in a `String`: RMF has no message for them).

use super::{ros_msg, Definition};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct String {
    pub data: std::string::String,
}
pub(crate) const STRING: Definition = ("std_msgs/msg/String", "string data\n");
ros_msg!(String, STRING);
