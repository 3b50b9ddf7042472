//! builtin_interfaces. `Duration` has `Time`'s fields, so the runtime's `Time` stands for both
//! (`Obstacle::lifetime` is a Duration on the wire).

use super::{ros_msg, Definition};
pub use mapc_sim::msgs::Time;

pub(crate) const TIME: Definition = ("builtin_interfaces/msg/Time", "int32 sec\nuint32 nanosec\n");
ros_msg!(Time, TIME);

pub(crate) const DURATION: Definition = (
    "builtin_interfaces/msg/Duration",
    "int32 sec\nuint32 nanosec\n",
);
