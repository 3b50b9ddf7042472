//! rmf_lift_msgs (rmf_internal_msgs 4.1.0).

use super::{ros_msg, Definition};
pub use mapc_sim::msgs::{LiftRequest, LiftState};

pub(crate) const LIFT_REQUEST: Definition = (
    "rmf_lift_msgs/msg/LiftRequest",
    "string lift_name\nbuiltin_interfaces/Time request_time\nstring session_id\nuint8 request_type\n\
     string destination_floor\nuint8 door_state\n",
);
ros_msg!(LiftRequest, LIFT_REQUEST);

pub(crate) const LIFT_STATE: Definition = (
    "rmf_lift_msgs/msg/LiftState",
    "builtin_interfaces/Time lift_time\nstring lift_name\nstring[] available_floors\n\
     string current_floor\nstring destination_floor\nuint8 door_state\nuint8 motion_state\n\
     uint8[] available_modes\nuint8 current_mode\nstring session_id\n",
);
ros_msg!(LiftState, LIFT_STATE);
