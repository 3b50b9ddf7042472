//! An upper bound on the building's throughput for the run's task mix, from its
//! bottleneck, and how close the run came to it.
//!
//! Each exclusive resource r (the robots, each controlled door and lift, each dispenser's
//! one item) has a capacity c_r (robots: how many; the others: one at a time). A task needs
//! at least d_r seconds of it (`fleet::bound`, always a lower bound). Over a long run the
//! tasks completed per hour X cannot exceed what the busiest resource can serve, whatever
//! the planning (the bottleneck law of operational analysis):
//!
//!   X ≤ min over r of c_r · 3600 / mean(d_r),  and  X ≤ the rate tasks arrived at,
//!
//! with the mean over the tasks that arrived (the mix). `used` is the share of each
//! resource the completed tasks needed at least: Σ d_r / (c_r · T) ≤ 1 always holds, and
//! the generated-buildings test checks it on every run.

use super::TaskReport;
use serde::Serialize;
use std::collections::BTreeMap;

/// An exclusive resource of the building.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Resource {
    Robots,
    /// Index into `Demands::doors`.
    Door(usize),
    /// Index into `Demands::lifts`.
    Lift(usize),
    /// Index into `Demands::dispensers`.
    Dispenser(usize),
}

/// Each task's least use of each resource (s), with the resources' names and the robots'
/// count.
#[derive(Debug, Clone, Default)]
pub struct Demands {
    pub robots: usize,
    pub doors: Vec<String>,
    pub lifts: Vec<String>,
    pub dispensers: Vec<String>,
    /// Per task id: (resource, seconds), only resources it needs.
    pub tasks: BTreeMap<String, Vec<(Resource, f64)>>,
    /// Per task id: the part of its robot time that is the way to its first place, from
    /// where another task ended. A robot's first task may come from its spawn instead, so
    /// the check of `used` allows for the largest of them once per robot.
    pub approach: BTreeMap<String, f64>,
}

impl Demands {
    /// The index of dispenser `name`, added when new.
    pub fn dispenser(&mut self, name: &str) -> usize {
        match self.dispensers.iter().position(|d| d == name) {
            Some(i) => i,
            None => {
                self.dispensers.push(name.to_string());
                self.dispensers.len() - 1
            }
        }
    }

    fn name(&self, r: Resource) -> String {
        match r {
            Resource::Robots => "robots".into(),
            Resource::Door(i) => format!("door {}", self.doors[i]),
            Resource::Lift(i) => format!("lift {}", self.lifts[i]),
            Resource::Dispenser(i) => format!("dispenser {}", self.dispensers[i]),
        }
    }

    fn capacity(&self, r: Resource) -> usize {
        match r {
            Resource::Robots => self.robots,
            _ => 1,
        }
    }
}

/// The report's throughput bound.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ThroughputBound {
    /// Tasks per hour that no planning can beat with this building, fleet and task mix.
    pub tasks_per_hour: f64,
    /// What sets it: a resource's name, or `arrivals` (tasks came no faster).
    pub limited_by: String,
    /// Tasks completed per hour in this run, and that as a share of the bound.
    pub achieved_per_hour: f64,
    pub share: f64,
    /// Tasks arrived per hour (those the fleets could do).
    pub arrivals_per_hour: f64,
    /// The resources, tightest first (at most ten).
    pub resources: Vec<ResourceBound>,
}

#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ResourceBound {
    /// `robots`, `door NAME`, `lift NAME`, `dispenser NAME`.
    pub resource: String,
    /// How many tasks may use it at once.
    pub capacity: usize,
    /// The least time a task of the mix needs it, on average (s).
    pub demand_s: f64,
    /// capacity · 3600 / demand_s.
    pub tasks_per_hour: f64,
    /// The least share of it the completed tasks needed (≤ 1; for the robots, less the
    /// way of each robot's first task, which may have started nearer).
    pub used: f64,
}

/// The bound for a run of length `end` (s) whose tasks are `tasks`. None when no task of
/// the mix needs any resource, or the run is empty.
pub fn throughput(d: &Demands, tasks: &[TaskReport], end: f64) -> Option<ThroughputBound> {
    if end <= 0.0 {
        return None;
    }
    let hours = end / 3600.0;
    let mut mix = 0usize;
    let mut completed = 0usize;
    // Per resource: Σ demand over the mix, and over the completed tasks.
    let mut sums: BTreeMap<Resource, (f64, f64)> = BTreeMap::new();
    let mut longest_approach: f64 = 0.0;
    for t in tasks {
        // Refused at arrival (no robot can do it) or called off: not part of the mix.
        let refused = t.result == "failed" && t.assigned.is_none();
        if refused || t.result == "cancelled" {
            continue;
        }
        let Some(uses) = d.tasks.get(&t.id) else {
            continue;
        };
        mix += 1;
        let done = t.result == "completed";
        completed += usize::from(done);
        if done {
            longest_approach = longest_approach.max(d.approach.get(&t.id).copied().unwrap_or(0.0));
        }
        for &(r, s) in uses {
            let e = sums.entry(r).or_insert((0.0, 0.0));
            e.0 += s;
            if done {
                e.1 += s;
            }
        }
    }
    if mix == 0 {
        return None;
    }
    let mut resources: Vec<ResourceBound> = sums
        .into_iter()
        .filter(|(r, (all, _))| *all > 0.0 && d.capacity(*r) > 0)
        .map(|(r, (all, done))| {
            let c = d.capacity(r) as f64;
            let demand = all / mix as f64;
            // Each robot's first task may have come from its spawn, nearer than any end.
            let done = match r {
                Resource::Robots => (done - c * longest_approach).max(0.0),
                _ => done,
            };
            ResourceBound {
                resource: d.name(r),
                capacity: d.capacity(r),
                demand_s: demand,
                tasks_per_hour: c * 3600.0 / demand,
                used: done / (c * end),
            }
        })
        .collect();
    resources.sort_by(|a, b| {
        a.tasks_per_hour
            .total_cmp(&b.tasks_per_hour)
            .then_with(|| a.resource.cmp(&b.resource))
    });
    resources.truncate(10);
    let arrivals = mix as f64 / hours;
    let (bound, by) = match resources.first() {
        Some(r) if r.tasks_per_hour < arrivals => (r.tasks_per_hour, r.resource.clone()),
        _ => (arrivals, "arrivals".to_string()),
    };
    let achieved = completed as f64 / hours;
    Some(ThroughputBound {
        tasks_per_hour: bound,
        limited_by: by,
        achieved_per_hour: achieved,
        share: if bound > 0.0 { achieved / bound } else { 0.0 },
        arrivals_per_hour: arrivals,
        resources,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn task(id: &str, result: &str) -> TaskReport {
        TaskReport {
            id: id.into(),
            result: result.into(),
            assigned: Some(0.0),
            ..TaskReport::default()
        }
    }

    /// Two robots, one lift: 4 tasks needing 600 s of a robot each and 2 of them 90 s of
    /// the lift. Robots: 2 · 3600 / 600 = 12 per hour; lift: 3600 / 45 = 80; the run of
    /// 1 h had 4 arrivals, so arrivals bind (4 per hour), and 3 were done.
    #[test]
    fn the_bound_is_the_least_of_the_resources_and_the_arrivals() {
        let mut d = Demands {
            robots: 2,
            lifts: vec!["L1".into()],
            ..Demands::default()
        };
        for (i, lift) in [(0, true), (1, false), (2, true), (3, false)] {
            let mut uses = vec![(Resource::Robots, 600.0)];
            if lift {
                uses.push((Resource::Lift(0), 90.0));
            }
            d.tasks.insert(format!("t{i}"), uses);
        }
        let tasks = [
            task("t0", "completed"),
            task("t1", "completed"),
            task("t2", "completed"),
            task("t3", "unfinished"),
        ];
        let b = throughput(&d, &tasks, 3600.0).unwrap();
        assert_eq!(b.limited_by, "arrivals");
        assert!((b.tasks_per_hour - 4.0).abs() < 1e-9);
        assert!((b.achieved_per_hour - 3.0).abs() < 1e-9);
        assert!((b.share - 0.75).abs() < 1e-9);
        assert_eq!(b.resources[0].resource, "robots");
        assert!((b.resources[0].tasks_per_hour - 12.0).abs() < 1e-9);
        // Completed: 3 · 600 s of 2 robots · 3600 s.
        assert!((b.resources[0].used - 1800.0 / 7200.0).abs() < 1e-9);
        assert_eq!(b.resources[1].resource, "lift L1");
        assert!((b.resources[1].tasks_per_hour - 80.0).abs() < 1e-9);
        assert!((b.resources[1].used - 180.0 / 3600.0).abs() < 1e-9);

        // Over a quarter of an hour the same 4 arrivals come at 16 per hour: the robots
        // (12 per hour) bind.
        let b = throughput(&d, &tasks, 900.0).unwrap();
        assert_eq!(b.limited_by, "robots");
        assert!((b.tasks_per_hour - 12.0).abs() < 1e-9);
    }

    #[test]
    fn refused_and_cancelled_tasks_are_not_in_the_mix() {
        let mut d = Demands {
            robots: 1,
            ..Demands::default()
        };
        for i in 0..3 {
            d.tasks.insert(
                format!("t{i}"),
                vec![(Resource::Robots, 100.0 * (i + 1) as f64)],
            );
        }
        let mut refused = task("t1", "failed");
        refused.assigned = None;
        let tasks = [task("t0", "completed"), refused, task("t2", "cancelled")];
        let b = throughput(&d, &tasks, 3600.0).unwrap();
        assert!((b.resources[0].demand_s - 100.0).abs() < 1e-9);
        assert!((b.arrivals_per_hour - 1.0).abs() < 1e-9);
    }
}
