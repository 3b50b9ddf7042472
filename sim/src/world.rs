//! The simulated building: slotcars, doors, lifts, dispensers and ingestors, and the door
//! and lift supervisors, stepped in the order the Gazebo plugins run (runtime spec §0).

use crate::msgs::{Msg, Published, Topic};
use crate::params::RobotParams;
use mapc_ir::{Building, Handle, Level};

/// A robot placed in the world at start-up.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotSpawn {
    pub name: String,
    pub fleet: String,
    pub params: RobotParams,
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
    pub level: Handle<Level>,
}

/// A dispenser or ingestor placed in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkcellSpawn {
    pub name: String,
    pub kind: crate::scenario::WorkcellKind,
    pub x: f64,
    pub y: f64,
    pub level: Handle<Level>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct WorldSetup {
    pub dt: f64,
    pub seed: u64,
    pub robots: Vec<RobotSpawn>,
    /// Workcells from the scenario; the map's TeleportDispenser/TeleportIngestor models are
    /// added by `World::new`.
    pub workcells: Vec<WorkcellSpawn>,
    pub lifts_start_at_initial_floor: bool,
}

/// Ground truth of a robot, for the report (near misses) and tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotTruth {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub yaw: f64,
    /// Forward speed command (m/s).
    pub v: f64,
    pub footprint: f64,
}

pub struct World {}

impl World {
    pub fn new(_building: &Building, _setup: &WorldSetup) -> World {
        todo!()
    }
    /// Current sim time (s).
    pub fn time(&self) -> f64 {
        todo!()
    }
    /// A message from outside (fleet layer) on an input topic: handled like a ROS callback,
    /// i.e. before the next step.
    pub fn deliver(&mut self, _topic: Topic, _msg: Msg) {
        todo!()
    }
    /// Advances one step; appends everything published during it.
    pub fn step(&mut self, _out: &mut Vec<Published>) {
        todo!()
    }
    /// Robots in spawn order.
    pub fn robots(&self) -> Vec<RobotTruth> {
        todo!()
    }
}
