//! rmf_lift_msgs (rmf_internal_msgs 4.1.0).

use super::builtin_interfaces::Time;
use super::{ros_msg, Definition};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct LiftRequest {
    pub lift_name: String,
    pub request_time: Time,
    pub session_id: String,
    pub request_type: u8,
    pub destination_floor: String,
    pub door_state: u8,
}
pub(crate) const LIFT_REQUEST: Definition = (
    "rmf_lift_msgs/msg/LiftRequest",
    "string lift_name\nbuiltin_interfaces/Time request_time\nstring session_id\nuint8 request_type\n\
     string destination_floor\nuint8 door_state\n",
);
ros_msg!(LiftRequest, LIFT_REQUEST);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct LiftState {
    pub lift_time: Time,
    pub lift_name: String,
    pub available_floors: Vec<String>,
    pub current_floor: String,
    pub destination_floor: String,
    pub door_state: u8,
    pub motion_state: u8,
    pub available_modes: Vec<u8>,
    pub current_mode: u8,
    pub session_id: String,
}
pub(crate) const LIFT_STATE: Definition = (
    "rmf_lift_msgs/msg/LiftState",
    "builtin_interfaces/Time lift_time\nstring lift_name\nstring[] available_floors\n\
     string current_floor\nstring destination_floor\nuint8 door_state\nuint8 motion_state\n\
     uint8[] available_modes\nuint8 current_mode\nstring session_id\n",
);
ros_msg!(LiftState, LIFT_STATE);
