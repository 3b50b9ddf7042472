//! A task's steps for a fleet (its places, the work there) and the places with the time
//! spent at each.

use super::*;

/// The longest work at one place a plan holds (s): a bound against absurd inputs (a
/// charging current near zero). It was 4 h, less than a TinyRobot's charge from 10 % (4.3
/// h): a plan that holds a charge short lets others be planned behind the charging robot.
const LONGEST_WORK: f64 = 48.0 * 3600.0;

impl Floor {
    /// The places of `steps` in order, each with how long robot `i` stays there (the
    /// work of the steps up to the next place).
    pub(in crate::fleet) fn goals_of(&self, i: usize, steps: &[Step]) -> Vec<(usize, f64)> {
        let mut goals: Vec<(usize, f64)> = Vec::new();
        for s in steps {
            let dwell = match s {
                Step::GoTo(v) => {
                    goals.push((*v, 0.0));
                    continue;
                }
                Step::Dwell(x) => *x,
                Step::Dispense(_) | Step::Ingest(_) | Step::Resume(_) => WORKCELL_ESTIMATE,
                Step::Charge(pct) => self.charge_left(i, *pct),
            };
            if let Some(g) = goals.last_mut() {
                g.1 = (g.1 + dwell).min(LONGEST_WORK);
            }
        }
        goals
    }

    /// How long robot `i` still charges to reach `pct` percent (s), at its fleet's rate.
    pub(in crate::fleet) fn charge_left(&self, i: usize, pct: f64) -> f64 {
        let r = &self.robots[i];
        (pct - r.battery()).max(0.0) / self.fleets[r.fleet].charge_rate.max(1e-9)
    }

    /// The steps of a task for fleet `fi`, or None if its waypoints are not on the graph.
    pub(in crate::fleet) fn expand(&self, fi: usize, kind: &TaskKind) -> Option<Vec<Step>> {
        let slot = self.fleets.get(fi)?.slot;
        let v = |n: &str| self.nav.find(slot, n);
        Some(match kind {
            TaskKind::Loop {
                start,
                finish,
                loops,
            } => {
                let (a, b) = (v(start)?, v(finish)?);
                let mut s = Vec::new();
                for _ in 0..(*loops).max(1) {
                    s.push(Step::GoTo(a));
                    s.push(Step::GoTo(b));
                }
                s
            }
            TaskKind::Delivery {
                pickup,
                dropoff,
                dispenser,
                ingestor,
            } => {
                let (a, b) = (v(pickup)?, v(dropoff)?);
                let d = dispenser
                    .clone()
                    .or_else(|| self.nav.vertices[a].roles.pickup_dispenser.clone())?;
                let i = ingestor
                    .clone()
                    .or_else(|| self.nav.vertices[b].roles.dropoff_ingestor.clone())?;
                vec![
                    Step::GoTo(a),
                    Step::Dispense(d),
                    Step::GoTo(b),
                    Step::Ingest(i),
                ]
            }
            TaskKind::Clean { zone } => {
                let z = v(zone)?;
                // A docking lane leaving the zone: drive it and come back; else clean in place.
                let dock = self.nav.out[slot][z]
                    .iter()
                    .map(|&e| self.nav.edges[e].to)
                    .find(|&w| {
                        self.nav.vertices[w].roles.dock_name.is_some()
                            && self.nav.vertices[w].lift.is_none()
                    });
                match dock {
                    Some(d) => vec![Step::GoTo(z), Step::GoTo(d), Step::GoTo(z)],
                    None => vec![Step::GoTo(z), Step::Dwell(self.clean_duration)],
                }
            }
            TaskKind::GoToPlace { place } => vec![Step::GoTo(v(place)?)],
            TaskKind::Patrol { places, rounds } => {
                let vs = places.iter().map(|p| v(p)).collect::<Option<Vec<_>>>()?;
                let mut s = Vec::new();
                for _ in 0..(*rounds).max(1) {
                    s.extend(vs.iter().map(|&x| Step::GoTo(x)));
                }
                s
            }
        })
    }
}

/// The first place of `steps`.
pub(super) fn first_goal(steps: &[Step]) -> Option<usize> {
    steps.iter().find_map(|s| match s {
        Step::GoTo(v) => Some(*v),
        _ => None,
    })
}
