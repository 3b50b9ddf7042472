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
//! always for the fleet with the smallest share placed so far.

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
