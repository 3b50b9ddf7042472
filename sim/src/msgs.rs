//! RMF messages (rmf_internal_msgs 4.1.0): the one set of types the runtime, the trace, MCAP
//! and DDS share. Each struct is its ROS message: field names and field order are the
//! `.msg`'s (CDR writes fields in declaration order; mapc-ros2 holds the `.msg` texts and
//! checks the order). Floats are f64 here, also where RMF says float32 (x, y, yaw, ...):
//! those fields carry `#[serde(with = "float32")]`, so the trace (JSON) keeps every f64
//! digit while CDR writes the float32 ROS expects.

use serde::{Deserialize, Serialize};

/// A float32 field of a ROS message held as f64: f64 for human-readable formats (the JSON
/// trace), f32 for binary ones (CDR, whose serde codec reports `is_human_readable() ==
/// false`): rounded to the nearest f32 on the way out, exact on the way in.
pub mod float32 {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        if s.is_human_readable() {
            s.serialize_f64(*v)
        } else {
            s.serialize_f32(*v as f32)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        if d.is_human_readable() {
            f64::deserialize(d)
        } else {
            f32::deserialize(d).map(f64::from)
        }
    }
}

/// builtin_interfaces/Time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Time {
    pub sec: i32,
    pub nanosec: u32,
}

impl Time {
    /// `(trunc(t), frac(t)·1e9)`, as the plugins stamp their messages.
    pub fn from_secs(t: f64) -> Time {
        let sec = t.trunc();
        let nanosec = ((t - sec) * 1e9).round().clamp(0.0, 999_999_999.0) as u32;
        Time {
            sec: sec as i32,
            nanosec,
        }
    }
    /// Whole seconds only (dispensers and ingestors use integer sim seconds).
    pub fn whole(t: f64) -> Time {
        Time {
            sec: t.floor() as i32,
            nanosec: 0,
        }
    }
    pub fn as_secs(self) -> f64 {
        self.sec as f64 + self.nanosec as f64 * 1e-9
    }
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Location {
    pub t: Time,
    #[serde(with = "float32")]
    pub x: f64,
    #[serde(with = "float32")]
    pub y: f64,
    #[serde(with = "float32")]
    pub yaw: f64,
    pub obey_approach_speed_limit: bool,
    #[serde(with = "float32")]
    pub approach_speed_limit: f64,
    pub level_name: String,
    pub index: u64,
}

pub mod robot_mode {
    pub const IDLE: u32 = 0;
    pub const CHARGING: u32 = 1;
    pub const MOVING: u32 = 2;
    pub const PAUSED: u32 = 3;
    pub const WAITING: u32 = 4;
    pub const EMERGENCY: u32 = 5;
    pub const GOING_HOME: u32 = 6;
    pub const DOCKING: u32 = 7;
    pub const ADAPTER_ERROR: u32 = 8;
    pub const CLEANING: u32 = 9;
    pub const PERFORMING_ACTION: u32 = 10;
    pub const ACTION_COMPLETED: u32 = 11;
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RobotMode {
    pub mode: u32,
    pub mode_request_id: u64,
    pub performing_action: String,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RobotState {
    pub name: String,
    pub model: String,
    pub task_id: String,
    pub seq: u64,
    pub mode: RobotMode,
    #[serde(with = "float32")]
    pub battery_percent: f64,
    pub location: Location,
    pub path: Vec<Location>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FleetState {
    pub name: String,
    pub robots: Vec<RobotState>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PathRequest {
    pub fleet_name: String,
    pub robot_name: String,
    pub path: Vec<Location>,
    pub task_id: String,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ModeParameter {
    pub name: String,
    pub value: String,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ModeRequest {
    pub fleet_name: String,
    pub robot_name: String,
    pub mode: RobotMode,
    pub task_id: String,
    pub parameters: Vec<ModeParameter>,
}

pub mod pause_type {
    pub const PAUSE_IMMEDIATELY: u32 = 0;
    pub const PAUSE_AT_CHECKPOINT: u32 = 1;
    pub const RESUME: u32 = 2;
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PauseRequest {
    pub fleet_name: String,
    pub robot_name: String,
    pub mode_request_id: u64,
    #[serde(rename = "type")]
    pub kind: u32,
    pub at_checkpoint: u32,
}

pub mod door_mode {
    pub const CLOSED: u32 = 0;
    pub const MOVING: u32 = 1;
    pub const OPEN: u32 = 2;
    pub const OFFLINE: u32 = 3;
    pub const UNKNOWN: u32 = 4;
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct DoorMode {
    pub value: u32,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DoorRequest {
    pub request_time: Time,
    pub requester_id: String,
    pub door_name: String,
    pub requested_mode: DoorMode,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DoorState {
    pub door_time: Time,
    pub door_name: String,
    pub current_mode: DoorMode,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Session {
    pub request_time: Time,
    pub requester_id: String,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DoorSessions {
    pub door_name: String,
    pub sessions: Vec<Session>,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct SupervisorHeartbeat {
    pub all_sessions: Vec<DoorSessions>,
}

pub mod lift_request {
    pub const END_SESSION: u8 = 0;
    pub const AGV_MODE: u8 = 1;
    pub const HUMAN_MODE: u8 = 2;
    pub const DOOR_CLOSED: u8 = 0;
    pub const DOOR_OPEN: u8 = 2;
}

pub mod lift_state {
    pub const DOOR_CLOSED: u8 = 0;
    pub const DOOR_MOVING: u8 = 1;
    pub const DOOR_OPEN: u8 = 2;
    pub const MOTION_STOPPED: u8 = 0;
    pub const MOTION_UP: u8 = 1;
    pub const MOTION_DOWN: u8 = 2;
    pub const MOTION_UNKNOWN: u8 = 3;
    pub const MODE_UNKNOWN: u8 = 0;
    pub const MODE_HUMAN: u8 = 1;
    pub const MODE_AGV: u8 = 2;
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct LiftRequest {
    pub lift_name: String,
    pub request_time: Time,
    pub session_id: String,
    pub request_type: u8,
    pub destination_floor: String,
    pub door_state: u8,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct LiftState {
    pub lift_time: Time,
    pub lift_name: String,
    pub available_floors: Vec<String>,
    pub current_floor: String,
    pub destination_floor: String,
    pub door_state: u8,
    pub motion_state: u8,
    pub available_modes: Vec<u8>,
    pub current_mode: u8,
    pub session_id: String,
}

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ItemType {
    pub type_guid: String,
    pub quantity: i32,
    pub compartment_name: String,
}

/// `rmf_dispenser_msgs/DispenserRequest` and `rmf_ingestor_msgs/IngestorRequest` have the
/// same fields.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct WorkcellRequest {
    pub time: Time,
    pub request_guid: String,
    pub target_guid: String,
    pub transporter_type: String,
    pub items: Vec<ItemType>,
}

pub mod workcell_result {
    pub const ACKNOWLEDGED: u8 = 0;
    pub const SUCCESS: u8 = 1;
    pub const FAILED: u8 = 2;
}

/// `DispenserResult` / `IngestorResult`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct WorkcellResult {
    pub time: Time,
    pub request_guid: String,
    pub source_guid: String,
    pub status: u8,
}

pub mod workcell_mode {
    pub const IDLE: i32 = 0;
    pub const BUSY: i32 = 1;
    pub const OFFLINE: i32 = 2;
}

/// `DispenserState` / `IngestorState`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct WorkcellState {
    pub time: Time,
    pub guid: String,
    pub mode: i32,
    pub request_guid_queue: Vec<String>,
    #[serde(with = "float32")]
    pub seconds_remaining: f64,
}

/// A task event of the fleet layer (not an RMF message; RMF reports task progress through
/// its task API). `event` is one of `queued`, `assigned`, `started`, `phase` (a step of the
/// task done; `detail` names it), `completed`, `failed`, `cancelled`, `stuck`.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct TaskEvent {
    pub time: Time,
    pub task_id: String,
    pub category: String,
    pub event: String,
    pub fleet: String,
    pub robot: String,
    pub detail: String,
    /// On `completed` and `failed`: where the task's robot waited, by cause.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub waits: Option<TaskWaits>,
    /// On `assigned`: when the plan it was assigned with ends the task (sim time, s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub planned_finish: Option<f64>,
    /// On `started`: the task's phases in order, named as their `phase` events name them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phases: Option<Vec<String>>,
}

/// Time (s) a task's robot spent waiting, by cause, and where (`places`: "lift Lift2",
/// "door L1_door2", "dispenser kitchen_dispenser", "traffic at lobby", ...). Charging counts
/// while a task waits for its robot to charge.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct TaskWaits {
    pub traffic_s: f64,
    pub lift_s: f64,
    pub door_s: f64,
    pub workcell_s: f64,
    pub charging_s: f64,
    pub places: std::collections::BTreeMap<String, f64>,
}

impl TaskWaits {
    /// Adds `dt` seconds of waiting for `cause` at `place`.
    pub fn add(&mut self, cause: WaitCause, place: &str, dt: f64) {
        if dt <= 0.0 {
            return;
        }
        *match cause {
            WaitCause::Traffic => &mut self.traffic_s,
            WaitCause::Lift => &mut self.lift_s,
            WaitCause::Door => &mut self.door_s,
            WaitCause::Workcell => &mut self.workcell_s,
            WaitCause::Charging => &mut self.charging_s,
        } += dt;
        *self.places.entry(place.to_string()).or_insert(0.0) += dt;
    }

    pub fn total(&self) -> f64 {
        self.traffic_s + self.lift_s + self.door_s + self.workcell_s + self.charging_s
    }
}

/// Why a robot with a task is not moving.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WaitCause {
    Traffic,
    Lift,
    Door,
    Workcell,
    Charging,
}

/// A message on a topic: what the runtime publishes, what the trace records. Untagged, so it
/// serialises as the message itself (a trace line's `msg`, a CDR payload).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Msg {
    RobotState(RobotState),
    FleetState(FleetState),
    PathRequest(PathRequest),
    ModeRequest(ModeRequest),
    PauseRequest(PauseRequest),
    DoorRequest(DoorRequest),
    DoorState(DoorState),
    DoorHeartbeat(SupervisorHeartbeat),
    LiftRequest(LiftRequest),
    LiftState(LiftState),
    WorkcellRequest(WorkcellRequest),
    WorkcellResult(WorkcellResult),
    WorkcellState(WorkcellState),
    TaskEvent(TaskEvent),
    Obstacles(Obstacles),
}

/// rmf_obstacle_msgs/Obstacles (rmf_internal_msgs 4.1.0): what rmf_human_detector
/// publishes on `/rmf_obstacles` and RMF's lane blocker reads; the crowd publishes one
/// `Obstacle` per person.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Obstacles {
    pub header: Header,
    pub obstacles: Vec<Obstacle>,
}

/// rmf_obstacle_msgs/Obstacle (the fields the crowd fills; `data` is empty).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Obstacle {
    pub header: Header,
    pub id: i32,
    pub source: String,
    pub level_name: String,
    pub classification: String,
    pub bbox: BoundingBox3D,
    pub data_resolution: f64,
    /// An octree's serialisation (`int8[]`); empty: a person is its bounding box.
    pub data: Vec<i8>,
    /// A `builtin_interfaces/Duration` (same fields as a time).
    pub lifetime: Time,
    /// ACTION_ADD = 1 (add or modify), ACTION_DELETE = 2, ACTION_DELETEALL = 3.
    pub action: i32,
}

/// rmf_obstacle_msgs/Obstacle's `action` for an obstacle added or updated.
pub const OBSTACLE_ACTION_ADD: i32 = 1;

/// std_msgs/Header.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Header {
    pub stamp: Time,
    pub frame_id: String,
}

/// rmf_obstacle_msgs/BoundingBox3D: centre pose and size (m).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct BoundingBox3D {
    pub center: Pose,
    pub size: Vector3,
}

/// geometry_msgs/Pose.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose {
    pub position: Vector3,
    pub orientation: Quaternion,
}

/// geometry_msgs/Point and Vector3 (same fields).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Vector3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// geometry_msgs/Quaternion.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Quaternion {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

/// Topic names as RMF sees them (§0.1 of the runtime spec), plus `/task_events`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Topic {
    RobotState,
    FleetStates,
    RobotPathRequests,
    RobotModeRequests,
    RobotPauseRequests,
    AdapterDoorRequests,
    DoorRequests,
    DoorStates,
    DoorSupervisorHeartbeat,
    AdapterLiftRequests,
    LiftRequests,
    LiftStates,
    DispenserRequests,
    DispenserResults,
    DispenserStates,
    IngestorRequests,
    IngestorResults,
    IngestorStates,
    TaskEvents,
    RmfObstacles,
}

impl Topic {
    pub const ALL: [Topic; 20] = [
        Topic::RobotState,
        Topic::FleetStates,
        Topic::RobotPathRequests,
        Topic::RobotModeRequests,
        Topic::RobotPauseRequests,
        Topic::AdapterDoorRequests,
        Topic::DoorRequests,
        Topic::DoorStates,
        Topic::DoorSupervisorHeartbeat,
        Topic::AdapterLiftRequests,
        Topic::LiftRequests,
        Topic::LiftStates,
        Topic::DispenserRequests,
        Topic::DispenserResults,
        Topic::DispenserStates,
        Topic::IngestorRequests,
        Topic::IngestorResults,
        Topic::IngestorStates,
        Topic::TaskEvents,
        Topic::RmfObstacles,
    ];

    /// The topic of a name, with or without the leading `/`.
    pub fn from_name(name: &str) -> Option<Topic> {
        let name = name.strip_prefix('/').unwrap_or(name);
        Topic::ALL.into_iter().find(|t| &t.name()[1..] == name)
    }

    /// Periodic state topics (what `--trace-state-period` thins out).
    pub fn is_state(self) -> bool {
        matches!(
            self,
            Topic::RobotState
                | Topic::FleetStates
                | Topic::DoorStates
                | Topic::DoorSupervisorHeartbeat
                | Topic::LiftStates
                | Topic::DispenserStates
                | Topic::IngestorStates
                | Topic::RmfObstacles
        )
    }

    pub fn name(self) -> &'static str {
        match self {
            Topic::RobotState => "/robot_state",
            Topic::FleetStates => "/fleet_states",
            Topic::RobotPathRequests => "/robot_path_requests",
            Topic::RobotModeRequests => "/robot_mode_requests",
            Topic::RobotPauseRequests => "/robot_pause_requests",
            Topic::AdapterDoorRequests => "/adapter_door_requests",
            Topic::DoorRequests => "/door_requests",
            Topic::DoorStates => "/door_states",
            Topic::DoorSupervisorHeartbeat => "/door_supervisor_heartbeat",
            Topic::AdapterLiftRequests => "/adapter_lift_requests",
            Topic::LiftRequests => "/lift_requests",
            Topic::LiftStates => "/lift_states",
            Topic::DispenserRequests => "/dispenser_requests",
            Topic::DispenserResults => "/dispenser_results",
            Topic::DispenserStates => "/dispenser_states",
            Topic::IngestorRequests => "/ingestor_requests",
            Topic::IngestorResults => "/ingestor_results",
            Topic::IngestorStates => "/ingestor_states",
            Topic::TaskEvents => "/task_events",
            Topic::RmfObstacles => "/rmf_obstacles",
        }
    }
}

/// One published message with its topic and the sim time it was published at.
#[derive(Debug, Clone, PartialEq)]
pub struct Published {
    pub t: f64,
    pub topic: Topic,
    pub msg: Msg,
}
