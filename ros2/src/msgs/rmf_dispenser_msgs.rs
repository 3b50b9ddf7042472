//! rmf_dispenser_msgs (rmf_internal_msgs 4.1.0).

use super::builtin_interfaces::Time;
use super::{ros_msg, Definition};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DispenserRequestItem {
    pub type_guid: String,
    pub quantity: i32,
    pub compartment_name: String,
}
pub(crate) const REQUEST_ITEM: Definition = (
    "rmf_dispenser_msgs/msg/DispenserRequestItem",
    "string type_guid\nint32 quantity\nstring compartment_name\n",
);
ros_msg!(DispenserRequestItem, REQUEST_ITEM);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DispenserRequest {
    pub time: Time,
    pub request_guid: String,
    pub target_guid: String,
    pub transporter_type: String,
    pub items: Vec<DispenserRequestItem>,
}
pub(crate) const REQUEST: Definition = (
    "rmf_dispenser_msgs/msg/DispenserRequest",
    "builtin_interfaces/Time time\nstring request_guid\nstring target_guid\nstring transporter_type\nrmf_dispenser_msgs/DispenserRequestItem[] items\n",
);
ros_msg!(DispenserRequest, REQUEST);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DispenserResult {
    pub time: Time,
    pub request_guid: String,
    pub source_guid: String,
    pub status: u8,
}
pub(crate) const RESULT: Definition = (
    "rmf_dispenser_msgs/msg/DispenserResult",
    "builtin_interfaces/Time time\nstring request_guid\nstring source_guid\nuint8 status\n",
);
ros_msg!(DispenserResult, RESULT);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DispenserState {
    pub time: Time,
    pub guid: String,
    pub mode: i32,
    pub request_guid_queue: Vec<String>,
    pub seconds_remaining: f32,
}
pub(crate) const STATE: Definition = (
    "rmf_dispenser_msgs/msg/DispenserState",
    "builtin_interfaces/Time time\nstring guid\nint32 mode\nstring[] request_guid_queue\nfloat32 seconds_remaining\n",
);
ros_msg!(DispenserState, STATE);
