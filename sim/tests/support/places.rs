//! Named places of a map's nav graph, for tests that make task streams on real maps.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// ../shared beside the checkout, when it is there with its `sub` folder.
pub fn shared(sub: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared");
    p.join(sub).is_dir().then_some(p)
}

/// Named waypoints of graph `g` outside lift cabins (a task cannot be sent into a cabin),
/// sorted.
pub fn places(b: &mapc_ir::Building, g: i64) -> Vec<String> {
    let mut out = BTreeSet::new();
    for (_, l) in b.lanes.iter().filter(|(_, l)| l.graph == g) {
        for v in [l.start, l.end] {
            let w = &b.vertices[v];
            let n = &w.name;
            let in_cabin = w.roles.lift_cabin.is_some()
                || b.lifts_on_level(w.level)
                    .any(|lh| b.lifts[lh].shaft_contains(w.pos));
            if !n.is_empty() && !in_cabin {
                out.insert(n.clone());
            }
        }
    }
    out.into_iter().collect()
}
