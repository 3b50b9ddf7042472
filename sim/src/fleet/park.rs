//! Parking and well-formedness on the scenario's terms: which vertices tasks, chargers and
//! spawns need (never parking), the parking vertices chosen around them
//! (`crate::traffic::parks`), and the warning for task waypoints that cut the graph.

use super::*;
use crate::traffic::parks::{self, Needs};

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
    // Task places, chargers and named spawns may be parking vertices of the second kind.
    let places = required_of(nav, scenario, spawns, true);
    let want: Vec<usize> = robots.iter().map(|&n| 2 * n + 4).collect();
    parks::choose(
        nav,
        conf,
        &Needs {
            required: &req,
            places: &places,
            want: &want,
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
                let cut = parks::cut_by(nav, conf, slot, v, &places);
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
