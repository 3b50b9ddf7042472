//! rosgraph_msgs

use super::builtin_interfaces::Time;
use super::{ros_msg, Definition};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Clock {
    pub clock: Time,
}
pub(crate) const CLOCK: Definition = ("rosgraph_msgs/msg/Clock", "builtin_interfaces/Time clock\n");
ros_msg!(Clock, CLOCK);
