//! rmf_fleet_msgs (rmf_internal_msgs 4.1.0): what fleet adapters and slotcars exchange.

use super::{ros_msg, Definition};
pub use mapc_sim::msgs::{
    FleetState, Location, ModeParameter, ModeRequest, PathRequest, PauseRequest, RobotMode,
    RobotState,
};

pub(crate) const LOCATION: Definition = (
    "rmf_fleet_msgs/msg/Location",
    "builtin_interfaces/Time t\nfloat32 x\nfloat32 y\nfloat32 yaw\n\
     bool obey_approach_speed_limit\nfloat32 approach_speed_limit\nstring level_name\nuint64 index\n",
);
ros_msg!(Location, LOCATION);

pub(crate) const ROBOT_MODE: Definition = (
    "rmf_fleet_msgs/msg/RobotMode",
    "uint32 mode\nuint64 mode_request_id\nstring performing_action\n",
);
ros_msg!(RobotMode, ROBOT_MODE);

pub(crate) const ROBOT_STATE: Definition = (
    "rmf_fleet_msgs/msg/RobotState",
    "string name\nstring model\nstring task_id\nuint64 seq\nrmf_fleet_msgs/RobotMode mode\n\
     float32 battery_percent\nrmf_fleet_msgs/Location location\nrmf_fleet_msgs/Location[] path\n",
);
ros_msg!(RobotState, ROBOT_STATE);

pub(crate) const FLEET_STATE: Definition = (
    "rmf_fleet_msgs/msg/FleetState",
    "string name\nrmf_fleet_msgs/RobotState[] robots\n",
);
ros_msg!(FleetState, FLEET_STATE);

pub(crate) const PATH_REQUEST: Definition = (
    "rmf_fleet_msgs/msg/PathRequest",
    "string fleet_name\nstring robot_name\nrmf_fleet_msgs/Location[] path\nstring task_id\n",
);
ros_msg!(PathRequest, PATH_REQUEST);

pub(crate) const MODE_PARAMETER: Definition = (
    "rmf_fleet_msgs/msg/ModeParameter",
    "string name\nstring value\n",
);
ros_msg!(ModeParameter, MODE_PARAMETER);

pub(crate) const MODE_REQUEST: Definition = (
    "rmf_fleet_msgs/msg/ModeRequest",
    "string fleet_name\nstring robot_name\nrmf_fleet_msgs/RobotMode mode\nstring task_id\n\
     rmf_fleet_msgs/ModeParameter[] parameters\n",
);
ros_msg!(ModeRequest, MODE_REQUEST);

pub(crate) const PAUSE_REQUEST: Definition = (
    "rmf_fleet_msgs/msg/PauseRequest",
    "string fleet_name\nstring robot_name\nuint64 mode_request_id\nuint32 type\nuint32 at_checkpoint\n",
);
ros_msg!(PauseRequest, PAUSE_REQUEST);
