//! ROS 2 message types mapc speaks, one module per ROS package, with their ROS names and
//! `.msg` definitions. Field order and widths are the wire format (CDR serialises fields in
//! declaration order), so each struct mirrors its `.msg` exactly; the `.msg` text beside it
//! is what MCAP files carry as schema and what `tests/ros2_cdr.rs` checks against Cyclone DDS.

pub mod builtin_interfaces;
pub mod geometry_msgs;
pub mod rmf_building_map_msgs;
pub mod rmf_dispenser_msgs;
pub mod rmf_door_msgs;
pub mod rmf_fleet_msgs;
pub mod rmf_ingestor_msgs;
pub mod rmf_lift_msgs;
pub mod rmf_obstacle_msgs;
pub mod rosgraph_msgs;
pub mod std_msgs;

use serde::{de::DeserializeOwned, Serialize};

/// A ROS 2 message type.
pub trait RosMsg: Serialize + DeserializeOwned {
    /// `package/msg/Name`, as rosbag2 and `ros2 topic` name it.
    const NAME: &'static str;
}

/// A type's name and `.msg` text.
pub type Definition = (&'static str, &'static str);

/// Ties a struct to its definition constant.
macro_rules! ros_msg {
    ($ty:ty, $def:expr) => {
        impl $crate::msgs::RosMsg for $ty {
            const NAME: &'static str = $def.0;
        }
    };
}
pub(crate) use ros_msg;

/// Every message definition: (`package/msg/Name`, `.msg` text with fully qualified field
/// types). Kept as one table so that schema text can follow dependencies.
pub fn definitions() -> &'static [Definition] {
    &[
        builtin_interfaces::TIME,
        builtin_interfaces::DURATION,
        std_msgs::STRING,
        std_msgs::HEADER,
        geometry_msgs::POINT,
        geometry_msgs::VECTOR3,
        geometry_msgs::QUATERNION,
        geometry_msgs::POSE,
        rosgraph_msgs::CLOCK,
        rmf_fleet_msgs::LOCATION,
        rmf_fleet_msgs::ROBOT_MODE,
        rmf_fleet_msgs::ROBOT_STATE,
        rmf_fleet_msgs::FLEET_STATE,
        rmf_fleet_msgs::PATH_REQUEST,
        rmf_fleet_msgs::MODE_PARAMETER,
        rmf_fleet_msgs::MODE_REQUEST,
        rmf_fleet_msgs::PAUSE_REQUEST,
        rmf_door_msgs::DOOR_MODE,
        rmf_door_msgs::DOOR_REQUEST,
        rmf_door_msgs::DOOR_STATE,
        rmf_door_msgs::SESSION,
        rmf_door_msgs::DOOR_SESSIONS,
        rmf_door_msgs::SUPERVISOR_HEARTBEAT,
        rmf_lift_msgs::LIFT_REQUEST,
        rmf_lift_msgs::LIFT_STATE,
        rmf_dispenser_msgs::REQUEST_ITEM,
        rmf_dispenser_msgs::REQUEST,
        rmf_dispenser_msgs::RESULT,
        rmf_dispenser_msgs::STATE,
        rmf_ingestor_msgs::REQUEST_ITEM,
        rmf_ingestor_msgs::REQUEST,
        rmf_ingestor_msgs::RESULT,
        rmf_ingestor_msgs::STATE,
        rmf_obstacle_msgs::BOUNDING_BOX_3D,
        rmf_obstacle_msgs::OBSTACLE,
        rmf_obstacle_msgs::OBSTACLES,
        rmf_building_map_msgs::PARAM,
        rmf_building_map_msgs::GRAPH_NODE,
        rmf_building_map_msgs::GRAPH_EDGE,
        rmf_building_map_msgs::GRAPH,
        rmf_building_map_msgs::AFFINE_IMAGE,
        rmf_building_map_msgs::PLACE,
        rmf_building_map_msgs::DOOR,
        rmf_building_map_msgs::LEVEL,
        rmf_building_map_msgs::LIFT,
        rmf_building_map_msgs::BUILDING_MAP,
    ]
}

/// The `.msg` text of `name` (`package/msg/Name`).
pub fn definition(name: &str) -> Option<&'static str> {
    definitions().iter().find(|(n, _)| *n == name).map(|d| d.1)
}

/// The schema text rosbag2 stores for a type (`ros2msg` encoding): its own definition, then
/// each type it uses, depth first, once, after a line of 80 `=` and `MSG: package/Name`.
pub fn schema_text(name: &str) -> Option<String> {
    let mut out = definition(name)?.to_string();
    let mut seen = vec![name.to_string()];
    let mut stack: Vec<String> = field_types(definition(name)?);
    stack.reverse();
    while let Some(t) = stack.pop() {
        if seen.contains(&t) {
            continue;
        }
        let def = definition(&t)?;
        out.push_str(&"=".repeat(80));
        out.push_str("\nMSG: ");
        out.push_str(&t.replace("/msg/", "/"));
        out.push('\n');
        out.push_str(def);
        let mut more = field_types(def);
        more.reverse();
        stack.extend(more);
        seen.push(t);
    }
    Some(out)
}

/// The complex field types of a definition, as `package/msg/Name`.
fn field_types(def: &str) -> Vec<String> {
    def.lines()
        .filter_map(|l| l.split_whitespace().next())
        .filter(|t| t.contains('/'))
        .map(|t| {
            let t = t.split('[').next().unwrap_or(t);
            let (pkg, name) = t.split_once('/').unwrap_or((t, ""));
            format!("{pkg}/msg/{name}")
        })
        .collect()
}

/// The DDS type name of a ROS type: `pkg/msg/Name` → `pkg::msg::dds_::Name_`.
pub fn dds_type_name(name: &str) -> String {
    let mut parts: Vec<&str> = name.split('/').collect();
    let last = parts.pop().unwrap_or("");
    format!("{}::dds_::{last}_", parts.join("::"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schema_follows_dependencies_once() {
        let s = schema_text("rmf_fleet_msgs/msg/RobotState").unwrap();
        assert!(s.starts_with("string name\n"));
        // Location is used twice (location, path[]) but appears once.
        assert_eq!(s.matches("MSG: rmf_fleet_msgs/Location\n").count(), 1);
        assert_eq!(s.matches("MSG: builtin_interfaces/Time\n").count(), 1);
        assert_eq!(s.matches("MSG: rmf_fleet_msgs/RobotMode\n").count(), 1);
        for (name, _) in definitions() {
            assert!(schema_text(name).is_some(), "{name}");
        }
    }

    #[test]
    fn definitions_are_one_field_per_line() {
        for (name, def) in definitions() {
            for line in def.lines() {
                let words: Vec<&str> = line.split(' ').collect();
                assert_eq!(words.len(), 2, "{name}: `{line}`");
                assert!(
                    !words[0].is_empty() && !words[1].is_empty(),
                    "{name}: `{line}`"
                );
            }
        }
    }

    #[test]
    fn dds_names() {
        assert_eq!(
            dds_type_name("rmf_door_msgs/msg/DoorState"),
            "rmf_door_msgs::msg::dds_::DoorState_"
        );
    }
}
