//! Named places of a map's nav graph, for tests that make task streams on real maps.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// ../shared beside the checkout, when it is there with its `sub` folder.
pub fn shared(sub: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared");
    p.join(sub).is_dir().then_some(p)
}

/// Named waypoints of graph `g` outside lift cabins (a task cannot be sent into a cabin),
/// sorted, in the piece of the graph with the most of them: a graph that falls apart
/// (W0208) has places no robot of another piece can reach, and a task between two pieces
/// fails by design ("no robot can reach the task"), which is not what a stream of work
/// for the fleet asks. Lanes join their ends whatever their direction, and a lift's
/// shaft joins the waypoints in it on every level.
pub fn places(b: &mapc_ir::Building, g: i64) -> Vec<String> {
    let n = b.vertices.iter().count();
    let lifts = b.lifts.iter().count();
    let mut up: Vec<usize> = (0..n + lifts).collect();
    fn root(up: &mut [usize], mut x: usize) -> usize {
        while up[x] != x {
            up[x] = up[up[x]];
            x = up[x];
        }
        x
    }
    let join = |up: &mut Vec<usize>, a: usize, c: usize| {
        let (ra, rc) = (root(up, a), root(up, c));
        up[ra.max(rc)] = ra.min(rc);
    };
    let mut named: BTreeSet<(String, usize)> = BTreeSet::new();
    for (_, l) in b.lanes.iter().filter(|(_, l)| l.graph == g) {
        join(&mut up, l.start.index(), l.end.index());
        for v in [l.start, l.end] {
            let w = &b.vertices[v];
            let shaft = b
                .lifts_on_level(w.level)
                .find(|&lh| b.lifts[lh].shaft_contains(w.pos));
            if let Some(lh) = shaft {
                join(&mut up, v.index(), n + lh.index());
            }
            if !w.name.is_empty() && w.roles.lift_cabin.is_none() && shaft.is_none() {
                named.insert((w.name.clone(), v.index()));
            }
        }
    }
    let mut pieces: BTreeMap<usize, BTreeSet<String>> = BTreeMap::new();
    for (name, v) in named {
        let r = root(&mut up, v);
        pieces.entry(r).or_default().insert(name);
    }
    // The most places; among equals, the piece of the first name.
    pieces
        .into_values()
        .max_by(|a, c| {
            a.len()
                .cmp(&c.len())
                .then_with(|| c.first().cmp(&a.first()))
        })
        .map(|s| s.into_iter().collect())
        .unwrap_or_default()
}
