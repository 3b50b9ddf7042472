//! rmf_door_msgs (rmf_internal_msgs 4.1.0).

use super::{ros_msg, Definition};
pub use mapc_sim::msgs::{
    DoorMode, DoorRequest, DoorSessions, DoorState, Session, SupervisorHeartbeat,
};

pub(crate) const DOOR_MODE: Definition = ("rmf_door_msgs/msg/DoorMode", "uint32 value\n");
ros_msg!(DoorMode, DOOR_MODE);

pub(crate) const DOOR_REQUEST: Definition = (
    "rmf_door_msgs/msg/DoorRequest",
    "builtin_interfaces/Time request_time\nstring requester_id\nstring door_name\n\
     rmf_door_msgs/DoorMode requested_mode\n",
);
ros_msg!(DoorRequest, DOOR_REQUEST);

pub(crate) const DOOR_STATE: Definition = (
    "rmf_door_msgs/msg/DoorState",
    "builtin_interfaces/Time door_time\nstring door_name\nrmf_door_msgs/DoorMode current_mode\n",
);
ros_msg!(DoorState, DOOR_STATE);

pub(crate) const SESSION: Definition = (
    "rmf_door_msgs/msg/Session",
    "builtin_interfaces/Time request_time\nstring requester_id\n",
);
ros_msg!(Session, SESSION);

pub(crate) const DOOR_SESSIONS: Definition = (
    "rmf_door_msgs/msg/DoorSessions",
    "string door_name\nrmf_door_msgs/Session[] sessions\n",
);
ros_msg!(DoorSessions, DOOR_SESSIONS);

pub(crate) const SUPERVISOR_HEARTBEAT: Definition = (
    "rmf_door_msgs/msg/SupervisorHeartbeat",
    "rmf_door_msgs/DoorSessions[] all_sessions\n",
);
ros_msg!(SupervisorHeartbeat, SUPERVISOR_HEARTBEAT);
