//! ROS 2 messages as mapc speaks them, one module per ROS package: each type's `.msg` text
//! (what MCAP files carry as schema and type hashes are computed from) and its ROS name. The
//! RMF messages the runtime publishes and reads are `mapc_sim::msgs`'s structs, re-exported
//! here under their package, so there is one set of types and CDR is derived from them; the
//! ROS-only types (`/map`'s, `/clock`'s, the `String` that carries task events) are defined
//! here. Invariant: a struct's field order is its `.msg`'s (CDR writes fields in declaration
//! order; `field_order_is_the_msg_order` checks every type), and a float32 field held as f64
//! by the runtime goes through `mapc_sim::msgs::float32`; `ros2/tests/cyclone_cdr.rs` holds
//! the bytes of every type to Cyclone DDS's.

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

    /// The top-level keys of a JSON object, in order (for default values: no escapes).
    fn keys(json: &str) -> Vec<std::string::String> {
        let b = json.as_bytes();
        let (mut depth, mut i, mut out) = (0, 0, Vec::new());
        while i < b.len() {
            match b[i] {
                b'{' | b'[' => depth += 1,
                b'}' | b']' => depth -= 1,
                b'"' => {
                    let end = i + 1 + json[i + 1..].find('"').expect("closed string");
                    if depth == 1 && b.get(end + 1) == Some(&b':') {
                        out.push(json[i + 1..end].to_string());
                    }
                    i = end;
                }
                _ => {}
            }
            i += 1;
        }
        out
    }

    /// A type's serialised field names, in declaration order (serde keeps it).
    fn fields<T: Serialize + Default>() -> Vec<std::string::String> {
        keys(&serde_json::to_string(&T::default()).expect("json"))
    }

    /// CDR has no field names: a struct whose fields are out of the `.msg`'s order sends
    /// wrong values silently. Every definition is checked against the type sent for it.
    #[test]
    fn field_order_is_the_msg_order() {
        use mapc_sim::msgs as sim;
        use rmf_building_map_msgs as map;
        let types = [
            (builtin_interfaces::TIME, fields::<sim::Time>()),
            (builtin_interfaces::DURATION, fields::<sim::Time>()),
            (std_msgs::STRING, fields::<std_msgs::String>()),
            (std_msgs::HEADER, fields::<sim::Header>()),
            (geometry_msgs::POINT, fields::<sim::Vector3>()),
            (geometry_msgs::VECTOR3, fields::<sim::Vector3>()),
            (geometry_msgs::QUATERNION, fields::<sim::Quaternion>()),
            (geometry_msgs::POSE, fields::<sim::Pose>()),
            (rosgraph_msgs::CLOCK, fields::<rosgraph_msgs::Clock>()),
            (rmf_fleet_msgs::LOCATION, fields::<sim::Location>()),
            (rmf_fleet_msgs::ROBOT_MODE, fields::<sim::RobotMode>()),
            (rmf_fleet_msgs::ROBOT_STATE, fields::<sim::RobotState>()),
            (rmf_fleet_msgs::FLEET_STATE, fields::<sim::FleetState>()),
            (rmf_fleet_msgs::PATH_REQUEST, fields::<sim::PathRequest>()),
            (
                rmf_fleet_msgs::MODE_PARAMETER,
                fields::<sim::ModeParameter>(),
            ),
            (rmf_fleet_msgs::MODE_REQUEST, fields::<sim::ModeRequest>()),
            (rmf_fleet_msgs::PAUSE_REQUEST, fields::<sim::PauseRequest>()),
            (rmf_door_msgs::DOOR_MODE, fields::<sim::DoorMode>()),
            (rmf_door_msgs::DOOR_REQUEST, fields::<sim::DoorRequest>()),
            (rmf_door_msgs::DOOR_STATE, fields::<sim::DoorState>()),
            (rmf_door_msgs::SESSION, fields::<sim::Session>()),
            (rmf_door_msgs::DOOR_SESSIONS, fields::<sim::DoorSessions>()),
            (
                rmf_door_msgs::SUPERVISOR_HEARTBEAT,
                fields::<sim::SupervisorHeartbeat>(),
            ),
            (rmf_lift_msgs::LIFT_REQUEST, fields::<sim::LiftRequest>()),
            (rmf_lift_msgs::LIFT_STATE, fields::<sim::LiftState>()),
            (rmf_dispenser_msgs::REQUEST_ITEM, fields::<sim::ItemType>()),
            (
                rmf_dispenser_msgs::REQUEST,
                fields::<sim::WorkcellRequest>(),
            ),
            (rmf_dispenser_msgs::RESULT, fields::<sim::WorkcellResult>()),
            (rmf_dispenser_msgs::STATE, fields::<sim::WorkcellState>()),
            (rmf_ingestor_msgs::REQUEST_ITEM, fields::<sim::ItemType>()),
            (rmf_ingestor_msgs::REQUEST, fields::<sim::WorkcellRequest>()),
            (rmf_ingestor_msgs::RESULT, fields::<sim::WorkcellResult>()),
            (rmf_ingestor_msgs::STATE, fields::<sim::WorkcellState>()),
            (
                rmf_obstacle_msgs::BOUNDING_BOX_3D,
                fields::<sim::BoundingBox3D>(),
            ),
            (rmf_obstacle_msgs::OBSTACLE, fields::<sim::Obstacle>()),
            (rmf_obstacle_msgs::OBSTACLES, fields::<sim::Obstacles>()),
            (map::PARAM, fields::<map::Param>()),
            (map::GRAPH_NODE, fields::<map::GraphNode>()),
            (map::GRAPH_EDGE, fields::<map::GraphEdge>()),
            (map::GRAPH, fields::<map::Graph>()),
            (map::AFFINE_IMAGE, fields::<map::AffineImage>()),
            (map::PLACE, fields::<map::Place>()),
            (map::DOOR, fields::<map::Door>()),
            (map::LEVEL, fields::<map::Level>()),
            (map::LIFT, fields::<map::Lift>()),
            (map::BUILDING_MAP, fields::<map::BuildingMap>()),
        ];
        for ((name, def), fields) in &types {
            let msg: Vec<&str> = def.lines().filter_map(|l| l.split(' ').nth(1)).collect();
            assert_eq!(fields, &msg, "{name}");
        }
        for (name, _) in definitions() {
            assert!(
                types.iter().any(|((n, _), _)| n == name),
                "{name} unchecked"
            );
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
