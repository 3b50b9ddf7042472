//! Which ROS type and QoS each topic of the runtime has (runtime spec §0.1), and the
//! conversion between the runtime's messages and their ROS 2 form.

use crate::cdr;
use crate::msgs::{
    builtin_interfaces, geometry_msgs as geo, rmf_dispenser_msgs as disp, rmf_door_msgs as door,
    rmf_fleet_msgs as fleet, rmf_ingestor_msgs as ing, rmf_lift_msgs as lift,
    rmf_obstacle_msgs as obst, std_msgs, RosMsg,
};
use mapc_sim::msgs::{self as sim, Msg, Topic};

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

/// The ROS 2 type (`package/msg/Name`) of a runtime topic.
pub fn ros_type(topic: Topic) -> &'static str {
    match topic {
        Topic::RobotState => fleet::RobotState::NAME,
        Topic::FleetStates => fleet::FleetState::NAME,
        Topic::RobotPathRequests => fleet::PathRequest::NAME,
        Topic::RobotModeRequests => fleet::ModeRequest::NAME,
        Topic::RobotPauseRequests => fleet::PauseRequest::NAME,
        Topic::AdapterDoorRequests | Topic::DoorRequests => door::DoorRequest::NAME,
        Topic::DoorStates => door::DoorState::NAME,
        Topic::DoorSupervisorHeartbeat => door::SupervisorHeartbeat::NAME,
        Topic::AdapterLiftRequests | Topic::LiftRequests => lift::LiftRequest::NAME,
        Topic::LiftStates => lift::LiftState::NAME,
        Topic::DispenserRequests => disp::DispenserRequest::NAME,
        Topic::DispenserResults => disp::DispenserResult::NAME,
        Topic::DispenserStates => disp::DispenserState::NAME,
        Topic::IngestorRequests => ing::IngestorRequest::NAME,
        Topic::IngestorResults => ing::IngestorResult::NAME,
        Topic::IngestorStates => ing::IngestorState::NAME,
        Topic::TaskEvents => std_msgs::String::NAME,
        Topic::RmfObstacles => obst::Obstacles::NAME,
    }
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

fn time(t: sim::Time) -> builtin_interfaces::Time {
    builtin_interfaces::Time {
        sec: t.sec,
        nanosec: t.nanosec,
    }
}

fn sim_time(t: builtin_interfaces::Time) -> sim::Time {
    sim::Time {
        sec: t.sec,
        nanosec: t.nanosec,
    }
}

fn location(l: &sim::Location) -> fleet::Location {
    fleet::Location {
        t: time(l.t),
        x: l.x as f32,
        y: l.y as f32,
        yaw: l.yaw as f32,
        obey_approach_speed_limit: l.obey_approach_speed_limit,
        approach_speed_limit: l.approach_speed_limit as f32,
        level_name: l.level_name.clone(),
        index: l.index,
    }
}

fn sim_location(l: fleet::Location) -> sim::Location {
    sim::Location {
        t: sim_time(l.t),
        x: l.x as f64,
        y: l.y as f64,
        yaw: l.yaw as f64,
        obey_approach_speed_limit: l.obey_approach_speed_limit,
        approach_speed_limit: l.approach_speed_limit as f64,
        level_name: l.level_name,
        index: l.index,
    }
}

fn mode(m: &sim::RobotMode) -> fleet::RobotMode {
    fleet::RobotMode {
        mode: m.mode,
        mode_request_id: m.mode_request_id,
        performing_action: m.performing_action.clone(),
    }
}

fn robot_state(r: &sim::RobotState) -> fleet::RobotState {
    fleet::RobotState {
        name: r.name.clone(),
        model: r.model.clone(),
        task_id: r.task_id.clone(),
        seq: r.seq,
        mode: mode(&r.mode),
        battery_percent: r.battery_percent as f32,
        location: location(&r.location),
        path: r.path.iter().map(location).collect(),
    }
}

fn door_request(m: &sim::DoorRequest) -> door::DoorRequest {
    door::DoorRequest {
        request_time: time(m.request_time),
        requester_id: m.requester_id.clone(),
        door_name: m.door_name.clone(),
        requested_mode: door::DoorMode {
            value: m.requested_mode.value,
        },
    }
}

fn lift_request(m: &sim::LiftRequest) -> lift::LiftRequest {
    lift::LiftRequest {
        lift_name: m.lift_name.clone(),
        request_time: time(m.request_time),
        session_id: m.session_id.clone(),
        request_type: m.request_type,
        destination_floor: m.destination_floor.clone(),
        door_state: m.door_state,
    }
}

fn header(h: &sim::Header) -> std_msgs::Header {
    std_msgs::Header {
        stamp: time(h.stamp),
        frame_id: h.frame_id.clone(),
    }
}

fn obstacles(m: &sim::Obstacles) -> obst::Obstacles {
    let v = |v: &sim::Vector3| (v.x, v.y, v.z);
    obst::Obstacles {
        header: header(&m.header),
        obstacles: m
            .obstacles
            .iter()
            .map(|o| {
                let (px, py, pz) = v(&o.bbox.center.position);
                let (sx, sy, sz) = v(&o.bbox.size);
                let q = &o.bbox.center.orientation;
                obst::Obstacle {
                    header: header(&o.header),
                    id: o.id,
                    source: o.source.clone(),
                    level_name: o.level_name.clone(),
                    classification: o.classification.clone(),
                    bbox: obst::BoundingBox3D {
                        center: geo::Pose {
                            position: geo::Point {
                                x: px,
                                y: py,
                                z: pz,
                            },
                            orientation: geo::Quaternion {
                                x: q.x,
                                y: q.y,
                                z: q.z,
                                w: q.w,
                            },
                        },
                        size: geo::Vector3 {
                            x: sx,
                            y: sy,
                            z: sz,
                        },
                    },
                    data_resolution: o.data_resolution,
                    data: o.data.clone(),
                    lifetime: builtin_interfaces::Duration {
                        sec: o.lifetime.sec,
                        nanosec: o.lifetime.nanosec,
                    },
                    action: o.action,
                }
            })
            .collect(),
    }
}

macro_rules! workcell_request {
    ($m:expr, $req:ident, $item:ident) => {
        $req {
            time: time($m.time),
            request_guid: $m.request_guid.clone(),
            target_guid: $m.target_guid.clone(),
            transporter_type: $m.transporter_type.clone(),
            items: $m
                .items
                .iter()
                .map(|i| $item {
                    type_guid: i.type_guid.clone(),
                    quantity: i.quantity,
                    compartment_name: i.compartment_name.clone(),
                })
                .collect(),
        }
    };
}

/// A runtime message in its ROS 2 form, CDR-encoded with the header (as rosbag2 stores it).
/// `None` when the message does not belong on the topic.
pub fn encode(topic: Topic, msg: &Msg) -> Option<Vec<u8>> {
    Some(match (topic, msg) {
        (Topic::RobotState, Msg::RobotState(r)) => cdr::encode(&robot_state(r)),
        (Topic::FleetStates, Msg::FleetState(f)) => cdr::encode(&fleet::FleetState {
            name: f.name.clone(),
            robots: f.robots.iter().map(robot_state).collect(),
        }),
        (Topic::RobotPathRequests, Msg::PathRequest(m)) => cdr::encode(&fleet::PathRequest {
            fleet_name: m.fleet_name.clone(),
            robot_name: m.robot_name.clone(),
            path: m.path.iter().map(location).collect(),
            task_id: m.task_id.clone(),
        }),
        (Topic::RobotModeRequests, Msg::ModeRequest(m)) => cdr::encode(&fleet::ModeRequest {
            fleet_name: m.fleet_name.clone(),
            robot_name: m.robot_name.clone(),
            mode: mode(&m.mode),
            task_id: m.task_id.clone(),
            parameters: m
                .parameters
                .iter()
                .map(|p| fleet::ModeParameter {
                    name: p.name.clone(),
                    value: p.value.clone(),
                })
                .collect(),
        }),
        (Topic::RobotPauseRequests, Msg::PauseRequest(m)) => cdr::encode(&fleet::PauseRequest {
            fleet_name: m.fleet_name.clone(),
            robot_name: m.robot_name.clone(),
            mode_request_id: m.mode_request_id,
            kind: m.kind,
            at_checkpoint: m.at_checkpoint,
        }),
        (Topic::AdapterDoorRequests | Topic::DoorRequests, Msg::DoorRequest(m)) => {
            cdr::encode(&door_request(m))
        }
        (Topic::DoorStates, Msg::DoorState(m)) => cdr::encode(&door::DoorState {
            door_time: time(m.door_time),
            door_name: m.door_name.clone(),
            current_mode: door::DoorMode {
                value: m.current_mode.value,
            },
        }),
        (Topic::DoorSupervisorHeartbeat, Msg::DoorHeartbeat(m)) => {
            cdr::encode(&door::SupervisorHeartbeat {
                all_sessions: m
                    .all_sessions
                    .iter()
                    .map(|d| door::DoorSessions {
                        door_name: d.door_name.clone(),
                        sessions: d
                            .sessions
                            .iter()
                            .map(|s| door::Session {
                                request_time: time(s.request_time),
                                requester_id: s.requester_id.clone(),
                            })
                            .collect(),
                    })
                    .collect(),
            })
        }
        (Topic::AdapterLiftRequests | Topic::LiftRequests, Msg::LiftRequest(m)) => {
            cdr::encode(&lift_request(m))
        }
        (Topic::LiftStates, Msg::LiftState(m)) => cdr::encode(&lift::LiftState {
            lift_time: time(m.lift_time),
            lift_name: m.lift_name.clone(),
            available_floors: m.available_floors.clone(),
            current_floor: m.current_floor.clone(),
            destination_floor: m.destination_floor.clone(),
            door_state: m.door_state,
            motion_state: m.motion_state,
            available_modes: m.available_modes.clone(),
            current_mode: m.current_mode,
            session_id: m.session_id.clone(),
        }),
        (Topic::DispenserRequests, Msg::WorkcellRequest(m)) => {
            use disp::{DispenserRequest, DispenserRequestItem};
            cdr::encode(&workcell_request!(
                m,
                DispenserRequest,
                DispenserRequestItem
            ))
        }
        (Topic::IngestorRequests, Msg::WorkcellRequest(m)) => {
            use ing::{IngestorRequest, IngestorRequestItem};
            cdr::encode(&workcell_request!(m, IngestorRequest, IngestorRequestItem))
        }
        (Topic::DispenserResults, Msg::WorkcellResult(m)) => cdr::encode(&disp::DispenserResult {
            time: time(m.time),
            request_guid: m.request_guid.clone(),
            source_guid: m.source_guid.clone(),
            status: m.status,
        }),
        (Topic::IngestorResults, Msg::WorkcellResult(m)) => cdr::encode(&ing::IngestorResult {
            time: time(m.time),
            request_guid: m.request_guid.clone(),
            source_guid: m.source_guid.clone(),
            status: m.status,
        }),
        (Topic::DispenserStates, Msg::WorkcellState(m)) => cdr::encode(&disp::DispenserState {
            time: time(m.time),
            guid: m.guid.clone(),
            mode: m.mode,
            request_guid_queue: m.request_guid_queue.clone(),
            seconds_remaining: m.seconds_remaining as f32,
        }),
        (Topic::IngestorStates, Msg::WorkcellState(m)) => cdr::encode(&ing::IngestorState {
            time: time(m.time),
            guid: m.guid.clone(),
            mode: m.mode,
            request_guid_queue: m.request_guid_queue.clone(),
            seconds_remaining: m.seconds_remaining as f32,
        }),
        (Topic::RmfObstacles, Msg::Obstacles(m)) => cdr::encode(&obstacles(m)),
        (Topic::TaskEvents, Msg::TaskEvent(e)) => cdr::encode(&std_msgs::String {
            data: serde_json::to_string(e).ok()?,
        }),
        _ => return None,
    })
}

/// A request another node sent (CDR with header) as the runtime's message. Only the topics
/// the runtime subscribes to are read.
pub fn decode(topic: Topic, bytes: &[u8]) -> Result<Msg, String> {
    Ok(match topic {
        Topic::RobotPathRequests => {
            let m: fleet::PathRequest = cdr::decode(bytes)?;
            Msg::PathRequest(sim::PathRequest {
                fleet_name: m.fleet_name,
                robot_name: m.robot_name,
                path: m.path.into_iter().map(sim_location).collect(),
                task_id: m.task_id,
            })
        }
        Topic::RobotModeRequests => {
            let m: fleet::ModeRequest = cdr::decode(bytes)?;
            Msg::ModeRequest(sim::ModeRequest {
                fleet_name: m.fleet_name,
                robot_name: m.robot_name,
                mode: sim::RobotMode {
                    mode: m.mode.mode,
                    mode_request_id: m.mode.mode_request_id,
                    performing_action: m.mode.performing_action,
                },
                task_id: m.task_id,
                parameters: m
                    .parameters
                    .into_iter()
                    .map(|p| sim::ModeParameter {
                        name: p.name,
                        value: p.value,
                    })
                    .collect(),
            })
        }
        Topic::RobotPauseRequests => {
            let m: fleet::PauseRequest = cdr::decode(bytes)?;
            Msg::PauseRequest(sim::PauseRequest {
                fleet_name: m.fleet_name,
                robot_name: m.robot_name,
                mode_request_id: m.mode_request_id,
                kind: m.kind,
                at_checkpoint: m.at_checkpoint,
            })
        }
        Topic::FleetStates => {
            let m: fleet::FleetState = cdr::decode(bytes)?;
            Msg::FleetState(sim::FleetState {
                name: m.name,
                robots: m
                    .robots
                    .into_iter()
                    .map(|r| sim::RobotState {
                        name: r.name,
                        model: r.model,
                        task_id: r.task_id,
                        seq: r.seq,
                        mode: sim::RobotMode {
                            mode: r.mode.mode,
                            mode_request_id: r.mode.mode_request_id,
                            performing_action: r.mode.performing_action,
                        },
                        battery_percent: r.battery_percent as f64,
                        location: sim_location(r.location),
                        path: r.path.into_iter().map(sim_location).collect(),
                    })
                    .collect(),
            })
        }
        Topic::AdapterDoorRequests | Topic::DoorRequests => {
            let m: door::DoorRequest = cdr::decode(bytes)?;
            Msg::DoorRequest(sim::DoorRequest {
                request_time: sim_time(m.request_time),
                requester_id: m.requester_id,
                door_name: m.door_name,
                requested_mode: sim::DoorMode {
                    value: m.requested_mode.value,
                },
            })
        }
        Topic::AdapterLiftRequests | Topic::LiftRequests => {
            let m: lift::LiftRequest = cdr::decode(bytes)?;
            Msg::LiftRequest(sim::LiftRequest {
                lift_name: m.lift_name,
                request_time: sim_time(m.request_time),
                session_id: m.session_id,
                request_type: m.request_type,
                destination_floor: m.destination_floor,
                door_state: m.door_state,
            })
        }
        Topic::DispenserRequests => {
            let m: disp::DispenserRequest = cdr::decode(bytes)?;
            let items = m
                .items
                .into_iter()
                .map(|i| (i.type_guid, i.quantity, i.compartment_name));
            workcell(
                m.time,
                m.request_guid,
                m.target_guid,
                m.transporter_type,
                items,
            )
        }
        Topic::IngestorRequests => {
            let m: ing::IngestorRequest = cdr::decode(bytes)?;
            let items = m
                .items
                .into_iter()
                .map(|i| (i.type_guid, i.quantity, i.compartment_name));
            workcell(
                m.time,
                m.request_guid,
                m.target_guid,
                m.transporter_type,
                items,
            )
        }
        _ => return Err(format!("mapc does not subscribe to {}", topic.name())),
    })
}

fn workcell(
    t: builtin_interfaces::Time,
    request_guid: String,
    target_guid: String,
    transporter_type: String,
    items: impl Iterator<Item = (String, i32, String)>,
) -> Msg {
    Msg::WorkcellRequest(sim::WorkcellRequest {
        time: sim_time(t),
        request_guid,
        target_guid,
        transporter_type,
        items: items
            .map(|(type_guid, quantity, compartment_name)| sim::ItemType {
                type_guid,
                quantity,
                compartment_name,
            })
            .collect(),
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
