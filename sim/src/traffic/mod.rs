//! Traffic by planning: one schedule of itineraries shared by all fleets, a planner per
//! robot against it, and the order in which robots pass each resource kept at execution.
//!
//! - `conflicts`: which resources (vertices, lanes, lifts, doors, mutex groups) a robot
//!   holds while it stands on a vertex or drives an edge, from geometry;
//! - `schedule`: the itineraries and, per resource, the order of its holders (an action
//!   dependency graph), retimed as robots are delayed; execution grants a traversal only
//!   in that order;
//! - `sipp`: Safe Interval Path Planning against the schedule, to goals and then to a
//!   parking vertex;
//! - `parks`: the parking vertices, chosen so that the building stays well-formed.
//!
//! Guarantee (tested on generated buildings, `sim/tests/traffic_props.rs`): the dependency
//! graph is acyclic whenever it changes, so while every traversal that starts also ends
//! (robots drive, doors open, lifts come), every robot with an itinerary finishes it; a
//! robot whose plan fails keeps its old itinerary, which ends on a parking vertex.

mod conflicts;
pub mod parks;
pub mod schedule;
pub mod sipp;
#[cfg(test)]
pub(crate) mod test_map;

pub use conflicts::{Clearance, Conflicts, Res};
