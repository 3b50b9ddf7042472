//! Which ROS type and QoS each topic of the runtime has (runtime spec §0.1), and the CDR of
//! its messages. The runtime's message structs are the ROS ones (`crate::msgs`), so encoding
//! and decoding are serde's, one line per topic.

use crate::cdr;
use crate::msgs::{
    rmf_dispenser_msgs as disp, rmf_door_msgs as door, rmf_fleet_msgs as fleet,
    rmf_ingestor_msgs as ing, rmf_lift_msgs as lift, rmf_obstacle_msgs as obst, std_msgs,
};
use mapc_sim::msgs::{Msg, Topic};

/// The QoS of a topic (history is always keep-last).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Qos {
    pub reliable: bool,
    pub transient_local: bool,
    pub depth: i32,
}

/// rclcpp's default: reliable, volatile, keep last 10.
pub const DEFAULT_QOS: Qos = Qos {
    reliable: true,
    transient_local: false,
    depth: 10,
};

/// The ROS 2 type (`package/msg/Name`) of a runtime topic. The topic decides it where one
/// runtime type stands for two ROS ones (a workcell's messages: dispenser or ingestor).
pub fn ros_type(topic: Topic) -> &'static str {
    let (name, _) = match topic {
        Topic::RobotState => fleet::ROBOT_STATE,
        Topic::FleetStates => fleet::FLEET_STATE,
        Topic::RobotPathRequests => fleet::PATH_REQUEST,
        Topic::RobotModeRequests => fleet::MODE_REQUEST,
        Topic::RobotPauseRequests => fleet::PAUSE_REQUEST,
        Topic::AdapterDoorRequests | Topic::DoorRequests => door::DOOR_REQUEST,
        Topic::DoorStates => door::DOOR_STATE,
        Topic::DoorSupervisorHeartbeat => door::SUPERVISOR_HEARTBEAT,
        Topic::AdapterLiftRequests | Topic::LiftRequests => lift::LIFT_REQUEST,
        Topic::LiftStates => lift::LIFT_STATE,
        Topic::DispenserRequests => disp::REQUEST,
        Topic::DispenserResults => disp::RESULT,
        Topic::DispenserStates => disp::STATE,
        Topic::IngestorRequests => ing::REQUEST,
        Topic::IngestorResults => ing::RESULT,
        Topic::IngestorStates => ing::STATE,
        Topic::TaskEvents => std_msgs::STRING,
        Topic::RmfObstacles => obst::OBSTACLES,
    };
    name
}

/// The QoS RMF uses on a topic (§0.1; rclcpp's default where the spec names none).
pub fn qos(topic: Topic) -> Qos {
    let reliable = |depth| Qos {
        reliable: true,
        transient_local: false,
        depth,
    };
    match topic {
        Topic::DoorStates | Topic::LiftStates => reliable(100),
        // The lift supervisor publishes /lift_requests transient local (§0.1), like the
        // adapters' requests.
        Topic::AdapterLiftRequests | Topic::LiftRequests => Qos {
            reliable: true,
            transient_local: true,
            depth: 100,
        },
        _ => DEFAULT_QOS,
    }
}

/// Whether the runtime message `msg` is what `topic` carries.
fn carries(topic: Topic, msg: &Msg) -> bool {
    matches!(
        (topic, msg),
        (Topic::RobotState, Msg::RobotState(_))
            | (Topic::FleetStates, Msg::FleetState(_))
            | (Topic::RobotPathRequests, Msg::PathRequest(_))
            | (Topic::RobotModeRequests, Msg::ModeRequest(_))
            | (Topic::RobotPauseRequests, Msg::PauseRequest(_))
            | (
                Topic::AdapterDoorRequests | Topic::DoorRequests,
                Msg::DoorRequest(_)
            )
            | (Topic::DoorStates, Msg::DoorState(_))
            | (Topic::DoorSupervisorHeartbeat, Msg::DoorHeartbeat(_))
            | (
                Topic::AdapterLiftRequests | Topic::LiftRequests,
                Msg::LiftRequest(_)
            )
            | (Topic::LiftStates, Msg::LiftState(_))
            | (
                Topic::DispenserRequests | Topic::IngestorRequests,
                Msg::WorkcellRequest(_)
            )
            | (
                Topic::DispenserResults | Topic::IngestorResults,
                Msg::WorkcellResult(_)
            )
            | (
                Topic::DispenserStates | Topic::IngestorStates,
                Msg::WorkcellState(_)
            )
            | (Topic::TaskEvents, Msg::TaskEvent(_))
            | (Topic::RmfObstacles, Msg::Obstacles(_))
    )
}

/// A runtime message in its ROS 2 form, CDR-encoded with the header (as rosbag2 stores it).
/// `None` when the message does not belong on the topic.
pub fn encode(topic: Topic, msg: &Msg) -> Option<Vec<u8>> {
    if !carries(topic, msg) {
        return None;
    }
    Some(match msg {
        // RMF has no task event message: the trace's JSON goes in a std_msgs/String.
        Msg::TaskEvent(e) => cdr::encode(&std_msgs::String {
            data: serde_json::to_string(e).ok()?,
        }),
        // `Msg` is untagged: it serialises as the message struct itself.
        _ => cdr::encode(msg),
    })
}

/// A request another node sent (CDR with header) as the runtime's message. Only the topics
/// the runtime subscribes to are read.
pub fn decode(topic: Topic, bytes: &[u8]) -> Result<Msg, String> {
    Ok(match topic {
        Topic::RobotPathRequests => Msg::PathRequest(cdr::decode(bytes)?),
        Topic::RobotModeRequests => Msg::ModeRequest(cdr::decode(bytes)?),
        Topic::RobotPauseRequests => Msg::PauseRequest(cdr::decode(bytes)?),
        Topic::FleetStates => Msg::FleetState(cdr::decode(bytes)?),
        Topic::AdapterDoorRequests | Topic::DoorRequests => Msg::DoorRequest(cdr::decode(bytes)?),
        Topic::AdapterLiftRequests | Topic::LiftRequests => Msg::LiftRequest(cdr::decode(bytes)?),
        Topic::DispenserRequests | Topic::IngestorRequests => {
            Msg::WorkcellRequest(cdr::decode(bytes)?)
        }
        _ => return Err(format!("mapc does not subscribe to {}", topic.name())),
    })
}

/// Topics mapc publishes when it plays only the Gazebo plugins (what rmf_demos' simulation
/// side publishes), plus the crowd's people as a human detector would publish them.
pub const PLUGIN_OUTPUTS: [Topic; 8] = [
    Topic::RobotState,
    Topic::DoorStates,
    Topic::LiftStates,
    Topic::DispenserResults,
    Topic::DispenserStates,
    Topic::IngestorResults,
    Topic::IngestorStates,
    Topic::RmfObstacles,
];

/// The topics mapc publishes: the plugins' alone, or all of its own.
pub(crate) fn outputs(plugins_only: bool) -> &'static [Topic] {
    if plugins_only {
        &PLUGIN_OUTPUTS
    } else {
        &Topic::ALL
    }
}

/// Topics the plugins answer: the slotcars', door and lift plugins', workcells' requests,
/// and the fleet states the workcells read to find the robot of a fleet.
pub const PLUGIN_INPUTS: [Topic; 8] = [
    Topic::RobotPathRequests,
    Topic::RobotModeRequests,
    Topic::RobotPauseRequests,
    Topic::DoorRequests,
    Topic::LiftRequests,
    Topic::DispenserRequests,
    Topic::IngestorRequests,
    Topic::FleetStates,
];

#[cfg(test)]
mod tests {
    use super::*;
    use mapc_sim::msgs::{Location, PathRequest};

    /// A float32 field goes to CDR as an f32 and comes back rounded to it; the JSON trace
    /// keeps the f64.
    #[test]
    fn float32_fields_are_f32_in_cdr_only() {
        let loc = Location {
            x: 0.1,
            ..Default::default()
        };
        let req = Msg::PathRequest(PathRequest {
            path: vec![loc.clone()],
            ..Default::default()
        });
        let bytes = encode(Topic::RobotPathRequests, &req).expect("fits the topic");
        let Ok(Msg::PathRequest(back)) = decode(Topic::RobotPathRequests, &bytes) else {
            panic!("decodes");
        };
        assert_eq!(back.path[0].x, f64::from(0.1f32));
        assert!(serde_json::to_string(&loc)
            .expect("json")
            .contains(r#""x":0.1,"#));
        assert_eq!(encode(Topic::DoorStates, &req), None, "not a door state");
    }
}
