//! What keeps a task waiting: a busy robot's bid (where and when its task ends) and a
//! dispenser whose item is away.

use super::*;

impl Floor {
    /// Where busy robot `i`'s task ends and when it is done there (its itinerary's
    /// estimate and the work still to do): None without a task or between steps.
    pub(super) fn busy_end(&self, i: usize, t: f64) -> Option<(usize, f64)> {
        let r = &self.robots[i];
        r.task?;
        let (goals, working) = match r.cur {
            Cur::GoTo { goal, .. } => (self.remaining_goals(i, goal), false),
            Cur::Dwell { until } => (self.working_goals(i, (until - t).max(0.0)), true),
            Cur::Workcell { .. } => (self.working_goals(i, WORKCELL_ESTIMATE), true),
            Cur::Charge { pct, .. } => {
                let rate = self.fleets[r.fleet].charge_rate.max(1e-9);
                (
                    self.working_goals(i, (pct - r.battery()).max(0.0) / rate),
                    true,
                )
            }
            Cur::None => return None,
        };
        let &(last, work) = goals.last()?;
        let ahead = goals.len() - usize::from(working);
        let at = if ahead == 0 {
            t
        } else {
            self.arrival(i, ahead).max(t)
        };
        Some((last, at + work))
    }

    /// Whether `dispenser`'s item is away or promised: a robot carries it or brings it
    /// back ([`Floor::item_coming`]), or a robot's task will take it (before it did).
    pub(super) fn dispenser_taken(&self, dispenser: &str, t: f64) -> bool {
        let asks = |c: &Cur| matches!(c, Cur::Workcell { target, dispenser: true, .. } if target == dispenser);
        self.item_coming(dispenser, t)
            || self.robots.iter().any(|r| {
                r.task.is_some()
                    && (asks(&r.cur)
                        || r.steps.iter().any(|s| match s {
                            Step::Dispense(d) => d == dispenser,
                            // Making room while it waits to ask again.
                            Step::Resume(c) => asks(c),
                            _ => false,
                        }))
            })
    }
}
