//! Parking and well-formedness on the scenario's terms: which vertices tasks, chargers and
//! spawns need (never parking), the parking vertices chosen around them
//! (`crate::traffic::parks`), and the warning for task waypoints that cut the graph.

use super::*;
use crate::scenario::{Finishing, RequestKind};
use crate::traffic::parks::{self, Needs, PARK_HOME};

/// What a robot does when it has no more tasks: its fleet adapter config's
/// `finishing_request` (the robot's own, else its fleet's), as mapc can do it without
/// giving up that an idle robot blocks no route.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) enum Finish {
    /// Plans end on the nearest free parking vertex (fleets without a config, and robots
    /// whose requested spot would be in the way).
    #[default]
    Park,
    /// Plans end at this vertex (its charger, or its parking spot), a [`PARK_HOME`]; the
    /// nearest free parking vertex when another robot holds it or it cannot be reached.
    Home(usize),
    /// `nothing`: the robot stays where its last task ended when that vertex is a parking
    /// vertex of any kind (a task place that is a [`PARK_HOME`]: no route needs it), else as
    /// [`Finish::Park`].
    Stay,
}

/// What robot `k` of fleet `fi` asks for when it has no more tasks (unchecked: a home is
/// the vertex it names), and the name of the vertex.
pub(super) fn wanted_finish(
    nav: &Nav,
    scenario: &Scenario,
    fi: usize,
    k: usize,
) -> (Finish, Option<String>) {
    let f = &scenario.fleets[fi];
    let (Some(rmf), Some(slot)) = (f.rmf.as_ref(), nav.slot(f.graph)) else {
        return (Finish::Park, None);
    };
    let robot = rmf.robots.get(k);
    let request = robot
        .and_then(|r| r.finishing_request.clone())
        .unwrap_or_else(|| rmf.finishing_request.clone());
    let charger = robot.and_then(|r| r.charger.clone());
    // RMF's `park` without a waypoint (rmf_task's ParkRobotFactory) returns the robot to
    // its charging waypoint and leaves it idle there.
    let name = match request {
        Finishing::Nothing => return (Finish::Stay, None),
        Finishing::Charge | Finishing::Park(None) => charger,
        Finishing::Park(Some(wp)) => Some(wp),
    };
    match name.as_deref().and_then(|n| nav.find(slot, n)) {
        Some(v) => (Finish::Home(v), name),
        None => (Finish::Park, name),
    }
}

/// The vertices asked for as [`PARK_HOME`]s, in order: the homes of the config fleets'
/// robots, their chargers, then the task places on the graphs of fleets with robots that
/// stay where their tasks end. Empty without fleet adapter configs.
fn wanted_homes(nav: &Nav, scenario: &Scenario) -> Vec<(usize, usize)> {
    let mut homes = Vec::new();
    let mut stay_slots = Vec::new();
    for (fi, f) in scenario.fleets.iter().enumerate() {
        let (Some(_), Some(slot)) = (f.rmf.as_ref(), nav.slot(f.graph)) else {
            continue;
        };
        for k in 0..f.count {
            match wanted_finish(nav, scenario, fi, k).0 {
                Finish::Home(v) if !homes.contains(&(slot, v)) => homes.push((slot, v)),
                Finish::Stay if !stay_slots.contains(&slot) => stay_slots.push(slot),
                _ => {}
            }
        }
    }
    // Then their chargers, where they start: they wait there for their first task.
    for f in &scenario.fleets {
        let (Some(rmf), Some(slot)) = (f.rmf.as_ref(), nav.slot(f.graph)) else {
            continue;
        };
        for r in rmf.robots.iter().take(f.count) {
            if let Some(v) = r.charger.as_deref().and_then(|n| nav.find(slot, n)) {
                if !homes.contains(&(slot, v)) {
                    homes.push((slot, v));
                }
            }
        }
    }
    let requested = scenario.requests.iter().filter_map(|r| match &r.what {
        RequestKind::Task(t) => Some(&t.kind),
        _ => None,
    });
    let kinds: Vec<&TaskKind> = task_kinds(scenario).map(|k| k.0).chain(requested).collect();
    for &slot in &stay_slots {
        for kind in &kinds {
            for name in kind.places() {
                if let Some(v) = nav.find(slot, name) {
                    if !homes.contains(&(slot, v)) {
                        homes.push((slot, v));
                    }
                }
            }
        }
    }
    homes
}

/// Robot `k` of fleet `fi`'s finish once the parking vertices are chosen, and a warning
/// when the spot it asks for would be in the way (S0210): it then parks as robots without
/// a config do.
pub(super) fn finish_of(
    nav: &Nav,
    conf: &Conflicts,
    parks: &Parks,
    scenario: &Scenario,
    (fi, k): (usize, usize),
    robot: &str,
) -> (Finish, Option<Diagnostic>) {
    let (want, name) = wanted_finish(nav, scenario, fi, k);
    let f = &scenario.fleets[fi];
    let Finish::Home(v) = want else {
        return (want, None);
    };
    let Some(slot) = nav.slot(f.graph) else {
        return (Finish::Park, None);
    };
    if parks.per_slot[slot][v] == PARK_HOME {
        return (want, None);
    }
    let span = f
        .rmf
        .as_ref()
        .and_then(|r| r.robots.get(k))
        .map_or(f.span, |r| r.span);
    let name = name.unwrap_or_default();
    let mut of: Vec<usize> = nav.members[slot]
        .iter()
        .copied()
        .filter(|&w| parks.per_slot[slot][w] != 0 || nav.vertices[w].roles.is_charger)
        .collect();
    of.extend(
        task_kinds(scenario)
            .flat_map(|(k, _, _)| k.places())
            .filter_map(|n| nav.find(slot, n)),
    );
    of.sort_unstable();
    of.dedup();
    let cut = parks::cut_by(nav, conf, slot, v, &of);
    let why = if cut.is_empty() {
        "a robot standing there for good would be in the way of a task place, a charger, another robot's spot or a lift".to_string()
    } else {
        let names: Vec<String> = cut
            .iter()
            .take(5)
            .map(|&w| format!("`{}`", nav.vertices[w].name))
            .collect();
        format!(
            "it is the only way to {}{}",
            names.join(", "),
            if cut.len() > 5 {
                format!(" and {} more", cut.len() - 5)
            } else {
                String::new()
            }
        )
    };
    let d = Diagnostic::warning(
        codes::NOT_WELL_FORMED,
        span,
        format!(
            "robot `{robot}` would stay at `{name}` when it has no more tasks, but {why}: it parks where no route needs it instead"
        ),
    )
    .with_help("give it a charger or parking spot off the corridors (a dead end beside them)");
    (Finish::Park, Some(d))
}

/// Every task kind of the scenario (tasks and generators), with its fleet and span.
fn task_kinds(scenario: &Scenario) -> impl Iterator<Item = (&TaskKind, &Option<String>, Span)> {
    scenario
        .tasks
        .iter()
        .map(|t| (&t.kind, &t.fleet, t.span))
        .chain(
            scenario
                .generators
                .iter()
                .map(|g| (&g.kind, &g.fleet, g.span)),
        )
}

/// Per graph slot, per vertex: the waypoints tasks name, chargers, and `spawns`.
fn required(nav: &Nav, scenario: &Scenario, spawns: &[usize]) -> Vec<Vec<bool>> {
    required_of(nav, scenario, spawns, true)
}

/// Like [`required`]; without chargers when `chargers` is false.
fn required_of(nav: &Nav, scenario: &Scenario, spawns: &[usize], chargers: bool) -> Vec<Vec<bool>> {
    let mut req = vec![vec![false; nav.vertices.len()]; nav.graphs.len()];
    for (slot, r) in req.iter_mut().enumerate() {
        for (kind, _, _) in task_kinds(scenario) {
            for name in kind.places() {
                if let Some(v) = nav.find(slot, name) {
                    r[v] = true;
                }
            }
        }
        for &v in &nav.members[slot] {
            if chargers && nav.vertices[v].roles.is_charger {
                r[v] = true;
            }
        }
        for &v in spawns {
            r[v] = true;
        }
    }
    req
}

/// Per graph slot, per vertex: the waypoints tasks name.
pub(super) fn task_places(nav: &Nav, scenario: &Scenario) -> Vec<Vec<bool>> {
    required_of(nav, scenario, &[], false)
}

/// Per graph slot: the legs tasks drive, from each place to the next in the task's order
/// (and from the last back to the first when it goes round more than once), deduplicated.
fn task_legs(nav: &Nav, scenario: &Scenario) -> Vec<Vec<(usize, usize)>> {
    (0..nav.graphs.len())
        .map(|slot| {
            let mut legs = std::collections::BTreeSet::new();
            for (kind, _, _) in task_kinds(scenario) {
                let vs: Vec<usize> = kind
                    .places()
                    .into_iter()
                    .filter_map(|name| nav.find(slot, name))
                    .collect();
                for w in vs.windows(2) {
                    legs.insert((w[0], w[1]));
                }
                let again = match kind {
                    TaskKind::Loop { loops, .. } => *loops > 1,
                    TaskKind::Patrol { rounds, .. } => *rounds > 1,
                    _ => false,
                };
                if let (true, Some(&first), Some(&last)) = (again, vs.first(), vs.last()) {
                    legs.insert((last, first));
                }
            }
            legs.retain(|&(a, z)| a != z);
            legs.into_iter().collect()
        })
        .collect()
}

/// The parking vertices for `robots` robots per slot (and spares), around what the
/// scenario needs.
pub(super) fn choose_parks(
    nav: &Nav,
    conf: &Conflicts,
    scenario: &Scenario,
    spawns: &[usize],
    robots: &[usize],
) -> Parks {
    let req = required(nav, scenario, spawns);
    // Task places, chargers and named spawns may be parking vertices after the others;
    // task places of the second kind.
    let places = required_of(nav, scenario, spawns, true);
    let tasks = task_places(nav, scenario);
    let legs = task_legs(nav, scenario);
    let want: Vec<usize> = robots.iter().map(|&n| 2 * n + 4).collect();
    let homes = wanted_homes(nav, scenario);
    parks::choose(
        nav,
        conf,
        &Needs {
            required: &req,
            places: &places,
            tasks: &tasks,
            legs: &legs,
            want: &want,
            homes: &homes,
        },
    )
}

/// Warnings for task waypoints that cut their graph (S0210): a robot working there holds
/// up those going past. One per waypoint, at the first task naming it.
pub(super) fn well_formed_warnings(
    nav: &Nav,
    conf: &Conflicts,
    scenario: &Scenario,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let mut seen: Vec<(usize, usize)> = Vec::new();
    for slot in 0..nav.graphs.len() {
        let mut cuts = parks::Cuts::new(nav, conf, slot);
        let mut places: Vec<usize> = task_kinds(scenario)
            .flat_map(|(k, _, _)| k.places())
            .filter_map(|n| nav.find(slot, n))
            .collect();
        places.sort_unstable();
        places.dedup();
        for (kind, _, span) in task_kinds(scenario) {
            for name in kind.places() {
                let Some(v) = nav.find(slot, name) else {
                    continue;
                };
                if seen.contains(&(slot, v)) {
                    continue;
                }
                seen.push((slot, v));
                let cut = cuts.cut_by(v, &places);
                if cut.is_empty() {
                    continue;
                }
                let names: Vec<String> = cut
                    .iter()
                    .take(5)
                    .map(|&w| format!("`{}`", nav.vertices[w].name))
                    .collect();
                out.push(
                    Diagnostic::warning(
                        codes::NOT_WELL_FORMED,
                        span,
                        format!(
                            "waypoint `{name}` is the only way to {}{}: a robot working at `{name}` holds up every robot going there",
                            names.join(", "),
                            if cut.len() > 5 { format!(" and {} more", cut.len() - 5) } else { String::new() }
                        ),
                    )
                    .with_help("add a lane around it, or put the task on a dead end beside the corridor"),
                );
            }
        }
    }
    out
}
