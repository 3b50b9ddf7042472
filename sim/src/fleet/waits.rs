//! Wait accounting: why each robot with a task is not moving, and where, summed per task
//! and reported with its end event, so the report can say what a building saturates on.

use super::*;

impl Fleets {
    /// What robot `i` waits for now, if anything: a reservation (traffic, at the vertex
    /// it stands on), a door, a lift, a workcell, or charging while a task waits for it.
    fn wait_cause(&self, i: usize) -> Option<(WaitCause, String)> {
        let r = &self.robots[i];
        if r.task.is_none() && r.queue.is_empty() {
            return None;
        }
        match (&r.gate, &r.cur) {
            (Gate::Door { door, .. }, _) => Some((
                WaitCause::Door,
                format!("door {}", self.nav.doors[*door].name),
            )),
            (Gate::Lift { lift, .. }, _) => Some((
                WaitCause::Lift,
                format!("lift {}", self.nav.lifts[*lift].name),
            )),
            (_, Cur::Workcell { target, .. }) => {
                Some((WaitCause::Workcell, format!("workcell {target}")))
            }
            (_, Cur::Charge { .. }) => Some((WaitCause::Charging, "charging".to_string())),
            _ if r.wait_since.is_some() && r.n_sent == 0 => {
                let v = &self.nav.vertices[r.at];
                let place = if v.name.is_empty() {
                    format!("({:.1}, {:.1}) on {}", v.pos.x, v.pos.y, v.level_name)
                } else {
                    v.name.clone()
                };
                Some((WaitCause::Traffic, format!("traffic at {place}")))
            }
            _ => None,
        }
    }

    /// Closes robot `i`'s wait interval at `t` when its cause changed, and opens the new one.
    pub(super) fn account_wait(&mut self, i: usize, t: f64) {
        let now = self.wait_cause(i);
        let r = &mut self.robots[i];
        let same = match (&r.waiting_for, &now) {
            (Some((c, p, _)), Some((d, q))) => c == d && p == q,
            (None, None) => true,
            _ => false,
        };
        if same {
            return;
        }
        if let Some((cause, place, since)) = r.waiting_for.take() {
            r.waits.add(cause, &place, t - since);
        }
        r.waiting_for = now.map(|(c, p)| (c, p, t));
    }

    /// The waits of robot `i`'s task up to `t`; the accumulator starts afresh.
    pub(super) fn take_waits(&mut self, i: usize, t: f64) -> TaskWaits {
        let r = &mut self.robots[i];
        if let Some((cause, place, since)) = r.waiting_for.take() {
            r.waits.add(cause, &place, t - since);
        }
        std::mem::take(&mut r.waits)
    }
}
