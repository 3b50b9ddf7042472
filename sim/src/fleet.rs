//! The fleet layer: what a minimal RMF fleet adapter does (task assignment, routes on the
//! fleet's nav graph, traffic reservations, doors, lifts, workcells, charging).

use crate::msgs::{Msg, Published, Topic};
use crate::scenario::Scenario;
use crate::world::{RobotSpawn, WorkcellSpawn};
use mapc_ir::{Building, Diagnostic};

pub struct Fleets {}

/// Where robots and workcells start, resolved from the scenario against the map.
pub struct Placement {
    pub robots: Vec<RobotSpawn>,
    pub workcells: Vec<WorkcellSpawn>,
}

impl Fleets {
    /// Resolves spawns and workcells (named waypoints must exist on the fleet's graph).
    pub fn place(_building: &Building, _scenario: &Scenario) -> Result<Placement, Vec<Diagnostic>> {
        todo!()
    }
    pub fn new(
        _building: &Building,
        _scenario: &Scenario,
        _placement: &Placement,
    ) -> Result<Fleets, Vec<Diagnostic>> {
        todo!()
    }
    /// Reads what the world published in the last step (`inbox`) and appends the fleet's
    /// requests and task events to `out`.
    pub fn update(&mut self, _t: f64, _inbox: &[Published], _out: &mut Vec<(Topic, Msg)>) {
        todo!()
    }
    /// True when every task has ended (completed or failed) and no generator is pending.
    pub fn all_done(&self, _t: f64) -> bool {
        todo!()
    }
}
