//! Wait accounting: why each robot with a task is not moving, and where, summed per task
//! and reported with its end event, so the report can say what a building saturates on.

use super::*;

/// Where a robot waits (named only when an interval closes: this runs on every update).
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Place {
    Vertex(usize),
    Door(usize),
    Lift(usize),
    Workcell(String),
    Charging,
}

impl Floor {
    /// What robot `i` waits for now, if anything: a reservation (traffic, at the vertex
    /// it stands on), a door, a lift, a workcell, or charging while a task waits for it.
    fn wait_cause(&self, i: usize) -> Option<(WaitCause, Place)> {
        let r = &self.robots[i];
        r.task?;
        match (&r.gate, &r.cur) {
            (Gate::Door { door, .. }, _) => Some((WaitCause::Door, Place::Door(*door))),
            (Gate::Lift { lift, .. }, _) => Some((WaitCause::Lift, Place::Lift(*lift))),
            (_, Cur::Workcell { target, .. }) => {
                Some((WaitCause::Workcell, Place::Workcell(target.clone())))
            }
            (_, Cur::Charge { .. }) => Some((WaitCause::Charging, Place::Charging)),
            _ if r.waiting.is_some() && r.n_sent == 0 => {
                Some((WaitCause::Traffic, Place::Vertex(r.at)))
            }
            _ => None,
        }
    }

    /// The name of a place in the report ("traffic at lobby", "lift Lift2", ...).
    fn place_name(&self, p: &Place) -> String {
        match p {
            Place::Vertex(v) => {
                let v = &self.nav.vertices[*v];
                if v.name.is_empty() {
                    format!(
                        "traffic at ({:.1}, {:.1}) on {}",
                        v.pos.x, v.pos.y, v.level_name
                    )
                } else {
                    format!("traffic at {}", v.name)
                }
            }
            Place::Door(d) => format!("door {}", self.nav.doors[*d].name),
            Place::Lift(l) => format!("lift {}", self.nav.lifts[*l].name),
            Place::Workcell(w) => format!("workcell {w}"),
            Place::Charging => "charging".to_string(),
        }
    }

    /// Closes robot `i`'s wait interval at `t` when its cause changed, and opens the new one.
    pub(super) fn account_wait(&mut self, i: usize, t: f64) {
        let now = self.wait_cause(i);
        let same = match (&self.robots[i].waiting_for, &now) {
            (Some((c, p, _)), Some((d, q))) => c == d && p == q,
            (None, None) => true,
            _ => false,
        };
        if same {
            return;
        }
        self.close_wait(i, t);
        self.robots[i].waiting_for = now.map(|(c, p)| (c, p, t));
    }

    /// Adds robot `i`'s open wait interval, up to `t`, to its task's waits.
    fn close_wait(&mut self, i: usize, t: f64) {
        if let Some((cause, place, since)) = self.robots[i].waiting_for.take() {
            let name = self.place_name(&place);
            self.robots[i].waits.add(cause, &name, t - since);
        }
    }

    /// The waits of robot `i`'s task up to `t`; the accumulator starts afresh.
    pub(super) fn take_waits(&mut self, i: usize, t: f64) -> TaskWaits {
        self.close_wait(i, t);
        std::mem::take(&mut self.robots[i].waits)
    }
}
