//! rmf_obstacle_msgs (rmf_internal_msgs 4.1.0): what a human detector publishes on
//! `/rmf_obstacles`, and mapc's crowd too. Constants (`ACTION_ADD = 1`, ...) are not part
//! of the wire format and are left out of the definitions, as for the other packages
//! (the runtime's is `mapc_sim::msgs::OBSTACLE_ACTION_ADD`).

use super::{ros_msg, Definition};
pub use mapc_sim::msgs::{BoundingBox3D, Obstacle, Obstacles};

pub(crate) const BOUNDING_BOX_3D: Definition = (
    "rmf_obstacle_msgs/msg/BoundingBox3D",
    "geometry_msgs/Pose center\ngeometry_msgs/Vector3 size\n",
);
ros_msg!(BoundingBox3D, BOUNDING_BOX_3D);

pub(crate) const OBSTACLE: Definition = (
    "rmf_obstacle_msgs/msg/Obstacle",
    "std_msgs/Header header\nint32 id\nstring source\nstring level_name\n\
     string classification\nrmf_obstacle_msgs/BoundingBox3D bbox\nfloat64 data_resolution\n\
     int8[] data\nbuiltin_interfaces/Duration lifetime\nint32 action\n",
);
ros_msg!(Obstacle, OBSTACLE);

pub(crate) const OBSTACLES: Definition = (
    "rmf_obstacle_msgs/msg/Obstacles",
    "std_msgs/Header header\nrmf_obstacle_msgs/Obstacle[] obstacles\n",
);
ros_msg!(Obstacles, OBSTACLES);
