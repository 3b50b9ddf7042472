//! Parking: where idle robots stand out of everybody's way.

use super::*;

impl Fleets {
    /// The nearest parking vertex (`park`) on robot `i`'s level that nobody stands on,
    /// drives to or holds, with the travel time there; None when it is on one already.
    pub(super) fn park_spot(&self, i: usize) -> Option<(usize, f64)> {
        let r = &self.robots[i];
        let f = &self.fleets[r.fleet];
        let park = self.park.get(f.slot)?;
        if park.get(r.at).copied().unwrap_or(true) || self.nav.vertices[r.at].lift.is_some() {
            return None;
        }
        let level = &self.nav.vertices[r.at].level;
        let taken = |v: usize| {
            self.robots.iter().enumerate().any(|(o, x)| {
                o != i
                    && (x.at == v
                        || matches!(x.cur, Cur::GoTo { goal, .. } if goal == v)
                        || x.steps
                            .iter()
                            .any(|s| matches!(s, Step::GoTo(g) if *g == v)))
            })
        };
        let (times, prev) = self.nav.tree_from(f.slot, r.at, f.speed);
        // Not through a controlled door or a lift: parking must not keep them busy.
        let plain = |v: usize| {
            let mut w = v;
            for _ in 0..prev.len() {
                if w == r.at {
                    return true;
                }
                let Some(e) = prev.get(w).copied().flatten() else {
                    return false;
                };
                if !self.is_plain(e) {
                    return false;
                }
                w = self.nav.edges[e].from;
            }
            false
        };
        // Parking spots and holding points first (cf. `free_spot`).
        let cost = |v: usize| {
            let ro = &self.nav.vertices[v].roles;
            let spot = ro.is_parking_spot || ro.is_holding_point;
            times[v] + if spot { 0.0 } else { SPOT_PENALTY }
        };
        let mut spots: Vec<usize> = self.nav.members[f.slot]
            .iter()
            .copied()
            .filter(|&v| park.get(v).copied().unwrap_or(false) && times[v] <= PARK_REACH)
            .filter(|&v| self.nav.vertices[v].level == *level)
            .filter(|&v| self.res.is_free_ignoring(i, &self.conf.vertex[v], None))
            .filter(|&v| !taken(v) && plain(v))
            .collect();
        spots.sort_by(|&a, &b| cost(a).total_cmp(&cost(b)).then(a.cmp(&b)));
        // Past a one-way lane a spot may have no way back: the robot would be trapped there
        // for every later task. Parking is rare (after a task), so a tree per candidate
        // tried is affordable; usually the first one qualifies.
        spots
            .into_iter()
            .find(|&v| {
                self.nav
                    .tree_from(f.slot, v, f.speed)
                    .0
                    .get(r.at)
                    .is_some_and(|t| t.is_finite())
            })
            .map(|v| (v, times[v]))
    }
}

/// Per graph slot, per vertex: where an idle robot may park out of everybody's way. Not a
/// lift cabin or a charger, and neither the vertex nor anything its standing robot would hold is needed
/// by a shortest route between two task waypoints (the routes loops, deliveries and the
/// drives between tasks take), so a parked robot never has to be moved aside for them.
pub(super) fn park_vertices(nav: &Nav, conf: &Conflicts, scenario: &Scenario) -> Vec<Vec<bool>> {
    let kinds: Vec<&TaskKind> = scenario
        .tasks
        .iter()
        .map(|t| &t.kind)
        .chain(scenario.generators.iter().map(|g| &g.kind))
        .collect();
    // Resources any task route of any graph needs (vertices and lanes driven): fleets on
    // other graphs share the floor.
    let mut used = vec![false; conf.n_res];
    let mut mark = |set: &[Res]| {
        for &x in set {
            if let Some(u) = used.get_mut(x as usize) {
                *u = true;
            }
        }
    };
    for slot in 0..nav.graphs.len() {
        let mut wps: Vec<usize> = kinds
            .iter()
            .flat_map(|k| waypoint_names(k))
            .filter_map(|name| nav.find(slot, name))
            .collect();
        wps.sort_unstable();
        wps.dedup();
        for &a in &wps {
            if let Some(set) = conf.vertex.get(a) {
                mark(set);
            }
            let (times, prev) = nav.tree_from(slot, a, 1.0);
            for &b in &wps {
                if b == a || !times[b].is_finite() {
                    continue;
                }
                let mut v = b;
                for _ in 0..prev.len() {
                    let Some(e) = prev.get(v).copied().flatten() else {
                        break;
                    };
                    if let Some(set) = conf.edge.get(e) {
                        mark(set);
                    }
                    v = nav.edges[e].from;
                    if v == a {
                        break;
                    }
                }
            }
        }
    }
    (0..nav.graphs.len())
        .map(|slot| {
            let mut ok = vec![false; nav.vertices.len()];
            for &v in &nav.members[slot] {
                // Chargers are kept for robots that need to charge.
                ok[v] = nav.vertices[v].lift.is_none()
                    && !nav.vertices[v].roles.is_charger
                    && conf.vertex[v]
                        .iter()
                        .all(|&x| !used.get(x as usize).copied().unwrap_or(true));
            }
            // A robot parked where it cannot drive to the tasks, or back, is of no use.
            let wps: Vec<usize> = kinds
                .iter()
                .flat_map(|k| waypoint_names(k))
                .filter_map(|name| nav.find(slot, name))
                .collect();
            if let Some(&a) = wps.first() {
                let from_a = nav.tree_from(slot, a, 1.0).0;
                for &v in &nav.members[slot] {
                    if ok[v] {
                        ok[v] =
                            from_a[v].is_finite() && nav.tree_from(slot, v, 1.0).0[a].is_finite();
                    }
                }
            }
            keep_refuges(nav, slot, &mut ok);
            ok
        })
        .collect()
}

/// Leaves the entrance of every pocket of parking vertices (a connected set of them,
/// entered from the rest of the graph) free of parked robots: a robot making room needs
/// a place to step into, and a pocket filled up to its entrance offers none, so robots on
/// the corridors in front of it take turns pushing each other back and forth (a livelock
/// that held four robots for hours on the hotel map with 16 robots). A lone parking
/// vertex is its own entrance. When that would leave a graph with no parking vertex at
/// all, the graph keeps them all (a robot must stand somewhere), except in front of a
/// charger: a pocket that holds a charger always keeps its entrance free, or a robot
/// parked there would shut the one charging in (triple_H, 8 robots: four robots never
/// left their chargers).
fn keep_refuges(nav: &Nav, slot: usize, ok: &mut [bool]) {
    let mut nbrs: Vec<Vec<usize>> = vec![Vec::new(); nav.vertices.len()];
    for e in nav.edges.iter().filter(|e| e.graph == slot) {
        nbrs[e.from].push(e.to);
        nbrs[e.to].push(e.from);
    }
    let charger = |v: usize| nav.vertices[v].roles.is_charger && nav.vertices[v].lift.is_none();
    let inside = |v: usize| ok[v] || charger(v);
    // Pockets: connected sets of parking vertices and chargers; which hold a charger.
    let mut pocket = vec![usize::MAX; nav.vertices.len()];
    let mut powered: Vec<bool> = Vec::new();
    for &v0 in &nav.members[slot] {
        if !inside(v0) || pocket[v0] != usize::MAX {
            continue;
        }
        let id = powered.len();
        powered.push(false);
        let mut stack = vec![v0];
        pocket[v0] = id;
        while let Some(v) = stack.pop() {
            powered[id] |= charger(v);
            for &w in &nbrs[v] {
                if inside(w) && pocket[w] == usize::MAX {
                    pocket[w] = id;
                    stack.push(w);
                }
            }
        }
    }
    let entrance = |v: usize| ok[v] && nbrs[v].iter().any(|&w| !inside(w));
    let mut shut: Vec<usize> = Vec::new();
    let mut plain: Vec<usize> = Vec::new();
    let mut parked = 0;
    for &v in &nav.members[slot] {
        if !ok[v] {
            continue;
        }
        if powered[pocket[v]] {
            if entrance(v) {
                shut.push(v);
            }
        } else {
            parked += 1;
            if entrance(v) {
                plain.push(v);
            }
        }
    }
    if plain.len() < parked {
        shut.extend(plain);
    }
    for v in shut {
        ok[v] = false;
    }
}

/// Whether a robot parks (`Fleets::park_spot`) after a task of this kind.
pub(super) fn parks_after(kind: &TaskKind) -> bool {
    !matches!(kind, TaskKind::GoToPlace { .. })
}

pub(super) fn waypoint_names(kind: &TaskKind) -> Vec<&str> {
    match kind {
        TaskKind::Loop { start, finish, .. } => vec![start, finish],
        TaskKind::Delivery {
            pickup, dropoff, ..
        } => vec![pickup, dropoff],
        TaskKind::Clean { zone } => vec![zone],
        TaskKind::GoToPlace { place } => vec![place],
    }
}
