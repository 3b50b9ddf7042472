//! rmf_building_map_msgs: the `/map` building_map_server publishes (images are not sent:
//! mapc has none of its own, and viewers draw the walls and lanes).

use super::{ros_msg, Definition};
use serde::{Deserialize, Serialize};

pub mod param_type {
    pub const STRING: u32 = 1;
    pub const INT: u32 = 2;
    pub const DOUBLE: u32 = 3;
    pub const BOOL: u32 = 4;
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Param {
    pub name: String,
    #[serde(rename = "type")]
    pub kind: u32,
    pub value_int: i32,
    pub value_float: f32,
    pub value_string: String,
    pub value_bool: bool,
}
pub(crate) const PARAM: Definition = (
    "rmf_building_map_msgs/msg/Param",
    "string name\nuint32 type\nint32 value_int\nfloat32 value_float\nstring value_string\nbool value_bool\n",
);
ros_msg!(Param, PARAM);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct GraphNode {
    pub x: f32,
    pub y: f32,
    pub name: String,
    pub params: Vec<Param>,
}
pub(crate) const GRAPH_NODE: Definition = (
    "rmf_building_map_msgs/msg/GraphNode",
    "float32 x\nfloat32 y\nstring name\nrmf_building_map_msgs/Param[] params\n",
);
ros_msg!(GraphNode, GRAPH_NODE);

pub const EDGE_TYPE_BIDIRECTIONAL: u8 = 0;
pub const EDGE_TYPE_UNIDIRECTIONAL: u8 = 1;

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct GraphEdge {
    pub v1_idx: u32,
    pub v2_idx: u32,
    pub params: Vec<Param>,
    pub edge_type: u8,
}
pub(crate) const GRAPH_EDGE: Definition = (
    "rmf_building_map_msgs/msg/GraphEdge",
    "uint32 v1_idx\nuint32 v2_idx\nrmf_building_map_msgs/Param[] params\nuint8 edge_type\n",
);
ros_msg!(GraphEdge, GRAPH_EDGE);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Graph {
    pub name: String,
    pub vertices: Vec<GraphNode>,
    pub edges: Vec<GraphEdge>,
    pub params: Vec<Param>,
}
pub(crate) const GRAPH: Definition = (
    "rmf_building_map_msgs/msg/Graph",
    "string name\nrmf_building_map_msgs/GraphNode[] vertices\nrmf_building_map_msgs/GraphEdge[] edges\n\
     rmf_building_map_msgs/Param[] params\n",
);
ros_msg!(Graph, GRAPH);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct AffineImage {
    pub name: String,
    pub x_offset: f32,
    pub y_offset: f32,
    pub yaw: f32,
    pub scale: f32,
    pub encoding: String,
    pub data: Vec<u8>,
}
pub(crate) const AFFINE_IMAGE: Definition = (
    "rmf_building_map_msgs/msg/AffineImage",
    "string name\nfloat32 x_offset\nfloat32 y_offset\nfloat32 yaw\nfloat32 scale\nstring encoding\nuint8[] data\n",
);
ros_msg!(AffineImage, AFFINE_IMAGE);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Place {
    pub name: String,
    pub x: f32,
    pub y: f32,
    pub yaw: f32,
    pub position_tolerance: f32,
    pub yaw_tolerance: f32,
}
pub(crate) const PLACE: Definition = (
    "rmf_building_map_msgs/msg/Place",
    "string name\nfloat32 x\nfloat32 y\nfloat32 yaw\nfloat32 position_tolerance\nfloat32 yaw_tolerance\n",
);
ros_msg!(Place, PLACE);

pub mod door_type {
    pub const SINGLE_SLIDING: u8 = 1;
    pub const DOUBLE_SLIDING: u8 = 2;
    pub const SINGLE_TELESCOPE: u8 = 3;
    pub const DOUBLE_TELESCOPE: u8 = 4;
    pub const SINGLE_SWING: u8 = 5;
    pub const DOUBLE_SWING: u8 = 6;
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Door {
    pub name: String,
    pub v1_x: f32,
    pub v1_y: f32,
    pub v2_x: f32,
    pub v2_y: f32,
    pub door_type: u8,
    pub motion_range: f32,
    pub motion_direction: i32,
}
pub(crate) const DOOR: Definition = (
    "rmf_building_map_msgs/msg/Door",
    "string name\nfloat32 v1_x\nfloat32 v1_y\nfloat32 v2_x\nfloat32 v2_y\nuint8 door_type\n\
     float32 motion_range\nint32 motion_direction\n",
);
ros_msg!(Door, DOOR);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Level {
    pub name: String,
    pub elevation: f32,
    pub images: Vec<AffineImage>,
    pub places: Vec<Place>,
    pub doors: Vec<Door>,
    pub nav_graphs: Vec<Graph>,
    pub wall_graph: Graph,
}
pub(crate) const LEVEL: Definition = (
    "rmf_building_map_msgs/msg/Level",
    "string name\nfloat32 elevation\nrmf_building_map_msgs/AffineImage[] images\n\
     rmf_building_map_msgs/Place[] places\nrmf_building_map_msgs/Door[] doors\n\
     rmf_building_map_msgs/Graph[] nav_graphs\nrmf_building_map_msgs/Graph wall_graph\n",
);
ros_msg!(Level, LEVEL);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Lift {
    pub name: String,
    pub levels: Vec<String>,
    pub doors: Vec<Door>,
    pub wall_graph: Graph,
    pub ref_x: f32,
    pub ref_y: f32,
    pub ref_yaw: f32,
    pub width: f32,
    pub depth: f32,
}
pub(crate) const LIFT: Definition = (
    "rmf_building_map_msgs/msg/Lift",
    "string name\nstring[] levels\nrmf_building_map_msgs/Door[] doors\n\
     rmf_building_map_msgs/Graph wall_graph\nfloat32 ref_x\nfloat32 ref_y\nfloat32 ref_yaw\n\
     float32 width\nfloat32 depth\n",
);
ros_msg!(Lift, LIFT);

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct BuildingMap {
    pub name: String,
    pub levels: Vec<Level>,
    pub lifts: Vec<Lift>,
}
pub(crate) const BUILDING_MAP: Definition = (
    "rmf_building_map_msgs/msg/BuildingMap",
    "string name\nrmf_building_map_msgs/Level[] levels\nrmf_building_map_msgs/Lift[] lifts\n",
);
ros_msg!(BuildingMap, BUILDING_MAP);
