//! Which waypoints each graph connects: the ones a change cut off from, or joined to, the
//! graph's main piece.

use super::*;

/// Per graph, the waypoints in the largest connected piece (lanes as undirected edges,
/// across levels where lanes join them), by shared id.
pub(super) fn main_piece(
    b: &Building,
    new_side: bool,
    ids: &mut Ids,
) -> BTreeMap<i64, (BTreeSet<usize>, HashMap<usize, String>)> {
    let mut edges: BTreeMap<i64, Vec<(usize, usize)>> = BTreeMap::new();
    let mut names: HashMap<usize, String> = HashMap::new();
    for (_, l) in b.lanes.iter() {
        let (a, z) = (ids.id(new_side, l.start), ids.id(new_side, l.end));
        names.entry(a).or_insert_with(|| waypoint_name(b, l.start));
        names.entry(z).or_insert_with(|| waypoint_name(b, l.end));
        edges.entry(l.graph).or_default().push((a, z));
    }
    let mut out = BTreeMap::new();
    for (g, es) in edges {
        let mut adj: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        for &(a, z) in &es {
            adj.entry(a).or_default().push(z);
            adj.entry(z).or_default().push(a);
        }
        let mut seen: BTreeSet<usize> = BTreeSet::new();
        let mut best: BTreeSet<usize> = BTreeSet::new();
        for &start in adj.keys() {
            if seen.contains(&start) {
                continue;
            }
            let mut piece = BTreeSet::from([start]);
            let mut stack = vec![start];
            seen.insert(start);
            while let Some(v) = stack.pop() {
                for &w in &adj[&v] {
                    if seen.insert(w) {
                        piece.insert(w);
                        stack.push(w);
                    }
                }
            }
            if piece.len() > best.len() {
                best = piece;
            }
        }
        out.insert(g, (best, names.clone()));
    }
    out
}

pub(super) fn connectivity(old: &Building, new: &Building, ids: &Ids, out: &mut Vec<Change>) {
    let mut ids = Ids {
        old: ids.old.clone(),
        new: ids.new.clone(),
        next: ids.next,
    };
    let (o, n) = (
        main_piece(old, false, &mut ids),
        main_piece(new, true, &mut ids),
    );
    for (g, (a, names_a)) in &o {
        let Some((b, names_b)) = n.get(g) else {
            continue;
        };
        // Waypoints on both sides whose reachability from the main piece changed.
        let all_b: BTreeSet<&usize> = names_b.keys().collect();
        let all_a: BTreeSet<&usize> = names_a.keys().collect();
        for id in a.iter().filter(|id| !b.contains(id) && all_b.contains(id)) {
            out.push(change(
                Section::Connectivity,
                None,
                Kind::Removed,
                names_b[id].clone(),
                format!("no longer reachable from the main part of graph {g}"),
            ));
        }
        for id in b.iter().filter(|id| !a.contains(id) && all_a.contains(id)) {
            out.push(change(
                Section::Connectivity,
                None,
                Kind::Added,
                names_b[id].clone(),
                format!("now reachable from the main part of graph {g}"),
            ));
        }
    }
}
