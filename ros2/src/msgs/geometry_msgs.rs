//! geometry_msgs (the parts rmf_obstacle_msgs uses).

use super::{ros_msg, Definition};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}
pub(crate) const POINT: Definition = (
    "geometry_msgs/msg/Point",
    "float64 x\nfloat64 y\nfloat64 z\n",
);
ros_msg!(Point, POINT);

#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Vector3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}
pub(crate) const VECTOR3: Definition = (
    "geometry_msgs/msg/Vector3",
    "float64 x\nfloat64 y\nfloat64 z\n",
);
ros_msg!(Vector3, VECTOR3);

#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Quaternion {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}
pub(crate) const QUATERNION: Definition = (
    "geometry_msgs/msg/Quaternion",
    "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n",
);
ros_msg!(Quaternion, QUATERNION);

#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose {
    pub position: Point,
    pub orientation: Quaternion,
}
pub(crate) const POSE: Definition = (
    "geometry_msgs/msg/Pose",
    "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
);
ros_msg!(Pose, POSE);
