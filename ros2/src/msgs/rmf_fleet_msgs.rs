//! rmf_fleet_msgs (rmf_internal_msgs 4.1.0): what fleet adapters and slotcars exchange.

use super::builtin_interfaces::Time;
use super::{ros_msg, Definition};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Location {
    pub t: Time,
    pub x: f32,
    pub y: f32,
    pub yaw: f32,
    pub obey_approach_speed_limit: bool,
    pub approach_speed_limit: f32,
    pub level_name: String,
    pub index: u64,
}
pub(crate) const LOCATION: Definition = (
    "rmf_fleet_msgs/msg/Location",
    "builtin_interfaces/Time t\nfloat32 x\nfloat32 y\nfloat32 yaw\n\
     bool obey_approach_speed_limit\nfloat32 approach_speed_limit\nstring level_name\nuint64 index\n",
);
ros_msg!(Location, LOCATION);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RobotMode {
    pub mode: u32,
    pub mode_request_id: u64,
    pub performing_action: String,
}
pub(crate) const ROBOT_MODE: Definition = (
    "rmf_fleet_msgs/msg/RobotMode",
    "uint32 mode\nuint64 mode_request_id\nstring performing_action\n",
);
ros_msg!(RobotMode, ROBOT_MODE);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RobotState {
    pub name: String,
    pub model: String,
    pub task_id: String,
    pub seq: u64,
    pub mode: RobotMode,
    pub battery_percent: f32,
    pub location: Location,
    pub path: Vec<Location>,
}
pub(crate) const ROBOT_STATE: Definition = (
    "rmf_fleet_msgs/msg/RobotState",
    "string name\nstring model\nstring task_id\nuint64 seq\nrmf_fleet_msgs/RobotMode mode\n\
     float32 battery_percent\nrmf_fleet_msgs/Location location\nrmf_fleet_msgs/Location[] path\n",
);
ros_msg!(RobotState, ROBOT_STATE);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FleetState {
    pub name: String,
    pub robots: Vec<RobotState>,
}
pub(crate) const FLEET_STATE: Definition = (
    "rmf_fleet_msgs/msg/FleetState",
    "string name\nrmf_fleet_msgs/RobotState[] robots\n",
);
ros_msg!(FleetState, FLEET_STATE);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PathRequest {
    pub fleet_name: String,
    pub robot_name: String,
    pub path: Vec<Location>,
    pub task_id: String,
}
pub(crate) const PATH_REQUEST: Definition = (
    "rmf_fleet_msgs/msg/PathRequest",
    "string fleet_name\nstring robot_name\nrmf_fleet_msgs/Location[] path\nstring task_id\n",
);
ros_msg!(PathRequest, PATH_REQUEST);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ModeParameter {
    pub name: String,
    pub value: String,
}
pub(crate) const MODE_PARAMETER: Definition = (
    "rmf_fleet_msgs/msg/ModeParameter",
    "string name\nstring value\n",
);
ros_msg!(ModeParameter, MODE_PARAMETER);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ModeRequest {
    pub fleet_name: String,
    pub robot_name: String,
    pub mode: RobotMode,
    pub task_id: String,
    pub parameters: Vec<ModeParameter>,
}
pub(crate) const MODE_REQUEST: Definition = (
    "rmf_fleet_msgs/msg/ModeRequest",
    "string fleet_name\nstring robot_name\nrmf_fleet_msgs/RobotMode mode\nstring task_id\n\
     rmf_fleet_msgs/ModeParameter[] parameters\n",
);
ros_msg!(ModeRequest, MODE_REQUEST);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PauseRequest {
    pub fleet_name: String,
    pub robot_name: String,
    pub mode_request_id: u64,
    #[serde(rename = "type")]
    pub kind: u32,
    pub at_checkpoint: u32,
}
pub(crate) const PAUSE_REQUEST: Definition = (
    "rmf_fleet_msgs/msg/PauseRequest",
    "string fleet_name\nstring robot_name\nuint64 mode_request_id\nuint32 type\nuint32 at_checkpoint\n",
);
ros_msg!(PauseRequest, PAUSE_REQUEST);
