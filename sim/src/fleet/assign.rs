//! Task assignment: a task goes to the robot that can start it soonest.

use super::*;

impl Fleets {
    pub(super) fn request_task(
        &mut self,
        t: f64,
        kind: TaskKind,
        fleet: Option<String>,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let category = kind.category();
        let n = self.counters.entry(category).or_insert(0);
        let id = format!("{}_{}", category.as_str(), *n);
        *n += 1;
        let ti = self.tasks.len();
        self.tasks.push(Task {
            id,
            category,
            kind,
            fleet,
            ended: false,
        });
        self.event(t, ti, "queued", None, String::new(), out);
        self.assign(ti, t, out);
    }

    /// Gives task `ti` to the robot that can start it soonest, or fails it when no robot
    /// can reach it.
    pub(super) fn assign(&mut self, ti: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let category = self.tasks[ti].category;
        // Pick the robot that can start soonest: (ready time + travel to the first
        // waypoint, robot index).
        let mut best: Option<(f64, usize, f64)> = None;
        for (fi, f) in self.fleets.iter().enumerate() {
            let task = &self.tasks[ti];
            if task.fleet.as_ref().is_some_and(|n| *n != f.name)
                || !(f.kinds.is_empty() || f.kinds.contains(&category))
            {
                continue;
            }
            let Some(steps) = self.expand(fi, &task.kind) else {
                continue;
            };
            let Some(first) = steps.iter().find_map(|s| match s {
                Step::GoTo(v) => Some(*v),
                _ => None,
            }) else {
                continue;
            };
            let dur = self.estimate(f.slot, f.speed, first, &steps);
            for &ri in &f.robots {
                let r = &self.robots[ri];
                let (ready, from) = if r.idle() {
                    (t, r.at)
                } else {
                    (r.free_at.max(t), r.end_vertex)
                };
                let Some((travel, _)) = self.nav.plan(f.slot, from, first, f.speed) else {
                    continue;
                };
                // An idle robot standing on one of the task's waypoints would have to be
                // moved aside for it anyway: it takes the task unless another robot is much
                // sooner.
                let on_task = r.idle()
                    && steps
                        .iter()
                        .any(|s| matches!(s, Step::GoTo(v) if *v == r.at));
                let bonus = if on_task { ON_TASK_BONUS } else { 0.0 };
                let score = ready + travel - bonus;
                if best.is_none_or(|b| score < b.0) {
                    best = Some((score, ri, dur));
                }
            }
        }
        match best {
            None => {
                self.tasks[ti].ended = true;
                self.event(
                    t,
                    ti,
                    "failed",
                    None,
                    "no robot can reach the task".into(),
                    out,
                );
            }
            Some((score, ri, dur)) => {
                let end = self
                    .expand(self.robots[ri].fleet, &self.tasks[ti].kind)
                    .and_then(|s| {
                        s.iter().rev().find_map(|s| match s {
                            Step::GoTo(v) => Some(*v),
                            _ => None,
                        })
                    });
                let r = &mut self.robots[ri];
                r.free_at = score.max(t) + dur;
                if let Some(e) = end {
                    r.end_vertex = e;
                }
                r.queue.push_back(ti);
                r.dirty = true;
                self.event(t, ti, "assigned", Some(ri), String::new(), out);
            }
        }
    }

    /// Rough duration of `steps` after arriving at `first`.
    pub(super) fn estimate(&self, slot: usize, speed: f64, first: usize, steps: &[Step]) -> f64 {
        let mut at = first;
        let mut d = 0.0;
        for s in steps {
            match s {
                Step::GoTo(v) => {
                    d += self.nav.plan(slot, at, *v, speed).map_or(0.0, |p| p.0);
                    at = *v;
                }
                Step::Dwell(x) => d += x,
                Step::Dispense(_) | Step::Ingest(_) => d += 5.0,
                Step::Charge(_) => {}
            }
        }
        d
    }

    /// The steps of a task for fleet `fi`, or None if its waypoints are not on the graph.
    pub(super) fn expand(&self, fi: usize, kind: &TaskKind) -> Option<Vec<Step>> {
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
        })
    }
}
