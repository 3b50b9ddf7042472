//! rmf_obstacle_msgs (rmf_internal_msgs 4.1.0): what a human detector publishes on
//! `/rmf_obstacles`, and mapc's crowd too. Constants (`ACTION_ADD = 1`, ...) are not part
//! of the wire format and are left out of the definitions, as for the other packages.

use super::builtin_interfaces::Duration;
use super::geometry_msgs::{Pose, Vector3};
use super::std_msgs::Header;
use super::{ros_msg, Definition};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct BoundingBox3D {
    pub center: Pose,
    pub size: Vector3,
}
pub(crate) const BOUNDING_BOX_3D: Definition = (
    "rmf_obstacle_msgs/msg/BoundingBox3D",
    "geometry_msgs/Pose center\ngeometry_msgs/Vector3 size\n",
);
ros_msg!(BoundingBox3D, BOUNDING_BOX_3D);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Obstacle {
    pub header: Header,
    pub id: i32,
    pub source: String,
    pub level_name: String,
    pub classification: String,
    pub bbox: BoundingBox3D,
    pub data_resolution: f64,
    pub data: Vec<i8>,
    pub lifetime: Duration,
    pub action: i32,
}
pub(crate) const OBSTACLE: Definition = (
    "rmf_obstacle_msgs/msg/Obstacle",
    "std_msgs/Header header\nint32 id\nstring source\nstring level_name\n\
     string classification\nrmf_obstacle_msgs/BoundingBox3D bbox\nfloat64 data_resolution\n\
     int8[] data\nbuiltin_interfaces/Duration lifetime\nint32 action\n",
);
ros_msg!(Obstacle, OBSTACLE);

/// `action` of an obstacle added or updated.
pub const ACTION_ADD: i32 = 1;

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Obstacles {
    pub header: Header,
    pub obstacles: Vec<Obstacle>,
}
pub(crate) const OBSTACLES: Definition = (
    "rmf_obstacle_msgs/msg/Obstacles",
    "std_msgs/Header header\nrmf_obstacle_msgs/Obstacle[] obstacles\n",
);
ros_msg!(Obstacles, OBSTACLES);
