//! builtin_interfaces

use super::{ros_msg, Definition};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Time {
    pub sec: i32,
    pub nanosec: u32,
}
pub(crate) const TIME: Definition = ("builtin_interfaces/msg/Time", "int32 sec\nuint32 nanosec\n");
ros_msg!(Time, TIME);

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Duration {
    pub sec: i32,
    pub nanosec: u32,
}
pub(crate) const DURATION: Definition = (
    "builtin_interfaces/msg/Duration",
    "int32 sec\nuint32 nanosec\n",
);
ros_msg!(Duration, DURATION);
