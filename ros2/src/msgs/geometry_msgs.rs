//! geometry_msgs (the parts rmf_obstacle_msgs uses). `Point` has `Vector3`'s fields, so the
//! runtime's `Vector3` stands for both (a pose's position is a Point on the wire).

use super::{ros_msg, Definition};
pub use mapc_sim::msgs::{Pose, Quaternion, Vector3};

pub(crate) const POINT: Definition = (
    "geometry_msgs/msg/Point",
    "float64 x\nfloat64 y\nfloat64 z\n",
);

pub(crate) const VECTOR3: Definition = (
    "geometry_msgs/msg/Vector3",
    "float64 x\nfloat64 y\nfloat64 z\n",
);
ros_msg!(Vector3, VECTOR3);

pub(crate) const QUATERNION: Definition = (
    "geometry_msgs/msg/Quaternion",
    "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n",
);
ros_msg!(Quaternion, QUATERNION);

pub(crate) const POSE: Definition = (
    "geometry_msgs/msg/Pose",
    "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
);
ros_msg!(Pose, POSE);
