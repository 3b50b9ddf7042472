//! rmf_door_msgs (rmf_internal_msgs 4.1.0).

use super::builtin_interfaces::Time;
use super::{ros_msg, Definition};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct DoorMode {
    pub value: u32,
}
pub(crate) const DOOR_MODE: Definition = ("rmf_door_msgs/msg/DoorMode", "uint32 value\n");
ros_msg!(DoorMode, DOOR_MODE);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DoorRequest {
    pub request_time: Time,
    pub requester_id: String,
    pub door_name: String,
    pub requested_mode: DoorMode,
}
pub(crate) const DOOR_REQUEST: Definition = (
    "rmf_door_msgs/msg/DoorRequest",
    "builtin_interfaces/Time request_time\nstring requester_id\nstring door_name\n\
     rmf_door_msgs/DoorMode requested_mode\n",
);
ros_msg!(DoorRequest, DOOR_REQUEST);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DoorState {
    pub door_time: Time,
    pub door_name: String,
    pub current_mode: DoorMode,
}
pub(crate) const DOOR_STATE: Definition = (
    "rmf_door_msgs/msg/DoorState",
    "builtin_interfaces/Time door_time\nstring door_name\nrmf_door_msgs/DoorMode current_mode\n",
);
ros_msg!(DoorState, DOOR_STATE);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Session {
    pub request_time: Time,
    pub requester_id: String,
}
pub(crate) const SESSION: Definition = (
    "rmf_door_msgs/msg/Session",
    "builtin_interfaces/Time request_time\nstring requester_id\n",
);
ros_msg!(Session, SESSION);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DoorSessions {
    pub door_name: String,
    pub sessions: Vec<Session>,
}
pub(crate) const DOOR_SESSIONS: Definition = (
    "rmf_door_msgs/msg/DoorSessions",
    "string door_name\nrmf_door_msgs/Session[] sessions\n",
);
ros_msg!(DoorSessions, DOOR_SESSIONS);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct SupervisorHeartbeat {
    pub all_sessions: Vec<DoorSessions>,
}
pub(crate) const SUPERVISOR_HEARTBEAT: Definition = (
    "rmf_door_msgs/msg/SupervisorHeartbeat",
    "rmf_door_msgs/DoorSessions[] all_sessions\n",
);
ros_msg!(SupervisorHeartbeat, SUPERVISOR_HEARTBEAT);
