//! Scenario files: what to simulate on a map (fleets, workcells, tasks, duration, seed).
//! Read with the frontend's located YAML tree so that every problem gets file:line:col.

use crate::params::RobotParams;
use mapc_ir::{Diagnostic, Span};
use std::path::PathBuf;

#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The map, resolved against the scenario file's directory (None if the scenario does
    /// not name one; then `--map` must).
    pub map: Option<PathBuf>,
    pub seed: u64,
    /// Simulated time to run (s).
    pub duration: f64,
    /// Physics step (s), default 0.01 as in generated worlds.
    pub step: f64,
    pub fleets: Vec<FleetSpec>,
    pub workcells: Vec<WorkcellSpec>,
    pub tasks: Vec<TaskSpec>,
    pub generators: Vec<GeneratorSpec>,
    pub options: SimOptions,
}

#[derive(Debug, Clone, PartialEq)]
pub struct FleetSpec {
    pub name: String,
    /// Nav graph index the fleet drives on.
    pub graph: i64,
    pub robot: RobotParams,
    pub count: usize,
    pub spawn: SpawnSpec,
    /// Go charging when the state of charge falls below this (0..1).
    pub recharge_threshold: f64,
    /// Leave the charger when charged to this (0..1).
    pub recharge_soc: f64,
    /// Task categories this fleet accepts (empty: all).
    pub task_kinds: Vec<TaskCategory>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum SpawnSpec {
    /// The map's spawn waypoints (`spawn_robot_type` params); with a robot type filter
    /// when the fleet names one of the map's robot types.
    MapSpawnPoints,
    /// Named waypoints, one per robot (cycled if fewer than `count`? no: must be enough).
    Waypoints(Vec<String>),
    /// Free waypoints chosen by the runtime: chargers, parking spots, holding points, then
    /// any vertex, in graph order, never two robots on one.
    Auto,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TaskCategory {
    Loop,
    Delivery,
    Clean,
    GoToPlace,
}

impl TaskCategory {
    pub fn as_str(self) -> &'static str {
        match self {
            TaskCategory::Loop => "loop",
            TaskCategory::Delivery => "delivery",
            TaskCategory::Clean => "clean",
            TaskCategory::GoToPlace => "go_to_place",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WorkcellKind {
    Dispenser,
    Ingestor,
}

/// A teleport dispenser or ingestor placed at a waypoint (in addition to the map's
/// `TeleportDispenser`/`TeleportIngestor` models).
#[derive(Debug, Clone, PartialEq)]
pub struct WorkcellSpec {
    pub name: String,
    pub kind: WorkcellKind,
    pub waypoint: String,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum TaskKind {
    Loop {
        start: String,
        finish: String,
        loops: u32,
    },
    Delivery {
        pickup: String,
        dropoff: String,
        /// Defaults: the waypoint's `pickup_dispenser` / `dropoff_ingestor` param.
        dispenser: Option<String>,
        ingestor: Option<String>,
    },
    Clean {
        zone: String,
    },
    GoToPlace {
        place: String,
    },
}

impl TaskKind {
    pub fn category(&self) -> TaskCategory {
        match self {
            TaskKind::Loop { .. } => TaskCategory::Loop,
            TaskKind::Delivery { .. } => TaskCategory::Delivery,
            TaskKind::Clean { .. } => TaskCategory::Clean,
            TaskKind::GoToPlace { .. } => TaskCategory::GoToPlace,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct TaskSpec {
    /// Request time (s).
    pub at: f64,
    pub kind: TaskKind,
    /// Restrict to one fleet (default: any fleet that accepts the category).
    pub fleet: Option<String>,
    pub span: Span,
}

/// "A task every `every` seconds from `start` until `end`".
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratorSpec {
    pub every: f64,
    pub start: f64,
    pub end: Option<f64>,
    pub kind: TaskKind,
    pub fleet: Option<String>,
    pub span: Span,
}

/// Switches for behaviours of the upstream plugins flagged as quirks in the runtime spec.
/// The defaults are the intended behaviour.
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    /// Start lift cabins at their initial floor (true) or, like Gazebo, at z = 0 and drive
    /// there first (false; runtime spec §4.2).
    pub lifts_start_at_initial_floor: bool,
    /// Cleaning time at a cleaning zone when the map has no cleaning path (s).
    pub clean_duration: f64,
    /// End the run as soon as every task has ended (instead of running to `duration`).
    pub stop_when_done: bool,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            lifts_start_at_initial_floor: true,
            clean_duration: 60.0,
            stop_when_done: false,
        }
    }
}

/// Reads a scenario. `base` is the scenario file's directory (for `map`). Returns the
/// scenario when there are no errors, and all diagnostics (warnings too).
pub fn parse(
    _file: mapc_ir::FileId,
    _text: &str,
    _base: &std::path::Path,
) -> (Option<Scenario>, Vec<Diagnostic>) {
    todo!("scenario parser")
}
