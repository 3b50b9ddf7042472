//! The run report, built by observing the published messages (and ground-truth positions
//! for near misses), so that it sees exactly what RMF would see.

use serde::Serialize;

#[derive(Debug, Clone, Default, Serialize)]
pub struct Report {}

pub struct ReportBuilder {}

impl ReportBuilder {
    pub fn new(
        _building: &mapc_ir::Building,
        _scenario: &crate::Scenario,
        _placement: &crate::fleet::Placement,
    ) -> Self {
        todo!()
    }
    pub fn observe(&mut self, _p: &crate::msgs::Published) {
        todo!()
    }
    pub fn sample(&mut self, _t: f64, _robots: &[crate::world::RobotTruth]) {
        todo!()
    }
    pub fn finish(self, _t: f64, _robots: &[crate::world::RobotTruth]) -> Report {
        todo!()
    }
}
