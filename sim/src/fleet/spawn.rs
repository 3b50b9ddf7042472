//! `spawn: auto`: where the robots of fleets without named spawn points start.
//!
//! Every robot on the floor gets a *home*: a vertex off every task route (see
//! `park_vertices`) or a charger, so that a robot without work never stands in the way of
//! one with work. A building has only so many homes; robots beyond them wait in the
//! fleet's depot and take no part in the run (the report counts them, `reserve`): a
//! robot that entered anyway would have nowhere to stand but the corridors, and every
//! extra robot in a corridor takes throughput away from the others. Graphs without any
//! home place robots on any free vertex, as before.
//!
//! Fleets share the homes in proportion to their sizes: robots are placed one at a time,
//! always for the fleet with the smallest share placed so far. No fleet places more
//! robots than its task stream keeps busy (`needed`).

use super::*;

/// A fleet to place: its index in the scenario, graph slot, robot count and footprint.
pub(super) struct AutoFleet {
    pub fleet: usize,
    pub slot: usize,
    pub count: usize,
    pub footprint: f64,
}

/// Per fleet: candidates in order of preference, each vertex's neighbours on the fleet's
/// graph, each vertex's class (lower first).
type Prep = (Vec<usize>, Vec<Vec<usize>>, Vec<u8>);

/// The vertices chosen for each of `fleets` (same order), at most `count` each, away
/// from `taken` ((vertex, footprint) of robots placed already) and from each other.
pub(super) fn auto_spawn(
    nav: &Nav,
    park: &[Vec<bool>],
    fleets: &[AutoFleet],
    taken: &[(usize, f64)],
) -> Vec<Vec<usize>> {
    // Per fleet: the candidates in order of preference, and each vertex's neighbours.
    let prep: Vec<Prep> = fleets
        .iter()
        .map(|f| {
            let slot = f.slot;
            let home = |v: usize| {
                park.get(slot)
                    .and_then(|p| p.get(v))
                    .copied()
                    .unwrap_or(false)
                    || nav.vertices[v].roles.is_charger
            };
            let any_home = nav.members[slot].iter().any(|&v| home(v));
            let mut nbrs: Vec<Vec<usize>> = vec![Vec::new(); nav.vertices.len()];
            for e in nav.edges.iter().filter(|e| e.graph == slot) {
                nbrs[e.from].push(e.to);
                nbrs[e.to].push(e.from);
            }
            for n in &mut nbrs {
                n.sort_unstable();
                n.dedup();
            }
            // Chargers, parking spots and holding points first, then dead ends (off
            // every through route), then the rest.
            let mut class = vec![u8::MAX; nav.vertices.len()];
            for &v in &nav.members[slot] {
                let r = &nav.vertices[v].roles;
                class[v] = if r.is_charger {
                    0
                } else if r.is_parking_spot {
                    1
                } else if r.is_holding_point {
                    2
                } else if nbrs[v].len() <= 1 {
                    3
                } else {
                    4
                };
            }
            let mut cands: Vec<usize> = nav.members[slot]
                .iter()
                .copied()
                .filter(|&v| nav.vertices[v].lift.is_none())
                .filter(|&v| !any_home || home(v))
                .collect();
            cands.sort_by_key(|&v| (class[v], v));
            (cands, nbrs, class)
        })
        .collect();
    let mut placed: Vec<(usize, f64)> = taken.to_vec();
    let mut chosen: Vec<Vec<usize>> = vec![Vec::new(); fleets.len()];
    // First pass: no robot next to another (each can drive off without the other
    // moving); second pass: only far enough apart. Spread over the levels the graph
    // reaches: the level with the fewest robots so far first.
    for strict in [true, false] {
        let mut full = vec![false; fleets.len()];
        loop {
            let next = (0..fleets.len())
                .filter(|&k| !full[k] && chosen[k].len() < fleets[k].count)
                .min_by(|&a, &b| {
                    let share = |k: usize| chosen[k].len() as f64 / fleets[k].count as f64;
                    share(a).total_cmp(&share(b)).then(a.cmp(&b))
                });
            let Some(k) = next else { break };
            let (cands, nbrs, class) = &prep[k];
            let fp = fleets[k].footprint;
            let ok = |v: usize| {
                let p = nav.vertices[v].pos;
                placed.iter().all(|&(w, wfp)| {
                    let vw = &nav.vertices[w];
                    w != v
                        && (!level_handle_eq(vw.level, nav.vertices[v].level)
                            || vw.pos.minus(p).norm() >= wfp + fp + 0.5)
                        && !(strict && nbrs[v].binary_search(&w).is_ok())
                })
            };
            let on_level = |v: usize| {
                placed
                    .iter()
                    .filter(|&&(w, _)| nav.vertices[w].level == nav.vertices[v].level)
                    .count()
            };
            let pick = cands
                .iter()
                .copied()
                .filter(|&v| ok(v))
                .min_by_key(|&v| (class[v], on_level(v), v));
            match pick {
                Some(v) => {
                    chosen[k].push(v);
                    placed.push((v, fp));
                }
                None => full[k] = true,
            }
        }
    }
    chosen
}

/// Target utilisation of a fleet's robots by its task stream (see `needed`).
const UTILISATION: f64 = 0.5;

/// Per scenario fleet: how many robots its task stream can keep busy at `UTILISATION`
/// (at least one): the work its tasks ask for over the scenario's duration (driving
/// between their waypoints at nominal speed, and from where the fleet's tasks end to
/// where they start; a clean's dwell), divided by the duration; and at least as many as
/// would be busy at once if every task started when requested (a burst of tasks). A task any of several
/// fleets takes counts for each in proportion to its robots. Robots beyond it would
/// have nothing to do but wait in the corridors: past a building's capacity they take
/// throughput away (clinic, 9 tiny robots: 49 loops in 4 h where 6 to 8 do 61 to 63),
/// so `spawn: auto` keeps them in the depot.
pub(super) fn needed(nav: &Nav, scenario: &Scenario) -> Vec<usize> {
    let horizon = scenario.duration.max(1.0);
    // (kind, fleet, how many over the horizon, request time of a single task)
    type Entry<'a> = (&'a TaskKind, Option<&'a str>, f64, Option<f64>);
    let mut stream: Vec<Entry> = scenario
        .tasks
        .iter()
        .filter(|t| t.at < horizon)
        .map(|t| (&t.kind, t.fleet.as_deref(), 1.0, Some(t.at)))
        .collect();
    for g in &scenario.generators {
        let end = g.end.unwrap_or(horizon).min(horizon);
        let n = if g.every > 0.0 && g.start < end {
            ((end - g.start) / g.every).ceil()
        } else {
            0.0
        };
        stream.push((&g.kind, g.fleet.as_deref(), n, None));
    }
    let takes = |fi: usize, kind: &TaskKind, fleet: Option<&str>| {
        let f = &scenario.fleets[fi];
        fleet.is_none_or(|n| n == f.name)
            && (f.task_kinds.is_empty() || f.task_kinds.contains(&kind.category()))
            && nav.slot(f.graph).is_some_and(|slot| {
                waypoint_names(kind)
                    .iter()
                    .all(|w| nav.find(slot, w).is_some())
            })
    };
    let mut work = vec![0.0; scenario.fleets.len()];
    // Robots busy at once if every task started on request (nominal speed): a burst of
    // tasks asks for more robots than its average over the run.
    let mut peak = vec![0.0; scenario.fleets.len()];
    for (fi, f) in scenario.fleets.iter().enumerate() {
        let Some(slot) = nav.slot(f.graph) else {
            continue;
        };
        let speed = f.robot.nominal_drive_speed.max(0.05);
        let mine: Vec<&Entry> = stream.iter().filter(|s| takes(fi, s.0, s.1)).collect();
        if mine.is_empty() {
            // Its tasks come from outside (RMF's task API over DDS): no stream to size by.
            work[fi] = f64::INFINITY;
            continue;
        }
        // Travel times from every waypoint the fleet's tasks use.
        let mut wps: Vec<usize> = mine
            .iter()
            .flat_map(|s| waypoint_names(s.0))
            .filter_map(|w| nav.find(slot, w))
            .collect();
        wps.sort_unstable();
        wps.dedup();
        let times: BTreeMap<usize, Vec<f64>> = wps
            .iter()
            .map(|&w| (w, nav.times_from(slot, w, speed)))
            .collect();
        let leg = |a: usize, b: usize| {
            times
                .get(&a)
                .and_then(|t| t.get(b))
                .copied()
                .filter(|x| x.is_finite())
                .unwrap_or(0.0)
        };
        // (time, change in robots busy) of the single tasks; the generators' steady load.
        let mut sweep: Vec<(f64, f64)> = Vec::new();
        let mut steady = 0.0;
        for (kind, fleet, n, at) in mine {
            let v: Vec<usize> = waypoint_names(kind)
                .iter()
                .filter_map(|w| nav.find(slot, w))
                .collect();
            let (Some(&first), Some(&last)) = (v.first(), v.last()) else {
                continue;
            };
            let sharing: usize = (0..scenario.fleets.len())
                .filter(|&o| takes(o, kind, *fleet))
                .map(|o| scenario.fleets[o].count)
                .sum();
            let share = f.count as f64 / sharing.max(1) as f64;
            // From where the fleet's tasks end, on average.
            let approach = wps.iter().map(|&w| leg(w, first)).sum::<f64>() / wps.len() as f64;
            let body = match kind {
                TaskKind::Loop { loops, .. } => {
                    let k = (*loops).max(1) as f64;
                    k * leg(first, last) + (k - 1.0) * leg(last, first)
                }
                TaskKind::Delivery { .. } => leg(first, last) + 10.0,
                TaskKind::Clean { .. } => scenario.options.clean_duration,
                TaskKind::GoToPlace { .. } => 0.0,
            };
            let w = approach + body;
            work[fi] += n * share * w;
            match at {
                Some(at) => {
                    sweep.push((*at, share));
                    sweep.push((at + w.max(1.0), -share));
                }
                None => steady += n * share * w / horizon,
            }
        }
        // Ends before starts at the same time.
        sweep.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let mut now: f64 = 0.0;
        let mut most: f64 = 0.0;
        for (_, d) in sweep {
            now += d;
            most = most.max(now);
        }
        peak[fi] = most + steady;
    }
    // Square-root staffing (Halfin–Whitt): the offered load and a spare of its square
    // root, for the tasks that arrive together.
    work.iter()
        .zip(&peak)
        .map(|(w, p)| {
            let load = w / horizon / UTILISATION;
            if load.is_finite() {
                ((load + load.sqrt()).ceil().max((p - 1e-9).ceil()) as usize).max(1)
            } else {
                usize::MAX
            }
        })
        .collect()
}
