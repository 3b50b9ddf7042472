//! # W0207 unconnected-near-waypoints
//!
//! **What:** vertices of one level, all used by lanes of the same graph, lie closer than
//! 0.1 m to each other, and no lane of that graph joins them. A spot where k such
//! waypoints sit is one warning (naming the first few), not one per pair: the warning is
//! on the second waypoint of the spot in document order and the spot is the waypoints
//! within 0.1 m of the first.
//!
//! **Why it matters:** on screen the lanes seem to meet, but in the navigation graph they
//! end at two separate waypoints, so robots cannot get from one set of lanes to the other
//! (or only by a long detour). This is the classic "looks connected but is not" mistake:
//! a lane was drawn to a new vertex dropped on top of an existing one instead of to the
//! existing vertex itself.
//!
//! **Fix:** merge the two vertices: reconnect the lanes of one to the other and delete it.
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, a]
//!   - [4, 0, 0, b]
//!   - [4.03, 0, 0, c]     # W0207: 3 cm from b
//!   - [8, 0, 0, d]
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]
//!   - [2, 3, {graph_idx: [2, 0], bidirectional: [4, true]}]
//! ```

use crate::lints::Group;
use crate::validate::grid::PointGrid;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Handle, Vertex};
use std::collections::{BTreeMap, HashSet};

pub(crate) static RULE: Rule = Rule {
    code: "W0207",
    name: "unconnected-near-waypoints",
    summary: "two waypoints of one graph are closer than 0.1 m but not joined",
    group: Group::Lanes,
    metric: true,
    check,
};

/// Waypoints of one graph closer than this (metres) should be one waypoint.
pub const NEAR_TOLERANCE: f64 = 0.1;

/// Labels for at most this many other waypoints of a spot.
const MAX_LABELS: usize = 4;

/// A spot: `center` and the waypoints (document order) near it that no lane joins to it.
struct Spot {
    center: Handle<Vertex>,
    others: Vec<Handle<Vertex>>,
}

/// The spots of one graph on one level. Each waypoint belongs to at most one spot:
/// waypoints are visited in document order, and one that is not yet in a spot takes the
/// unclaimed waypoints near it. A grid with cells of the tolerance finds them; claimed
/// waypoints leave the grid, so a spot of k waypoints costs O(k), not O(k²).
fn spots(ctx: &Context, graph: i64, waypoints: &[Handle<Vertex>]) -> Vec<Spot> {
    let b = ctx.b;
    let mut claimed: HashSet<Handle<Vertex>> = HashSet::with_capacity(waypoints.len());
    let mut grid = PointGrid::new(
        NEAR_TOLERANCE,
        waypoints
            .iter()
            .enumerate()
            .map(|(i, &v)| (i as u32, b.vertices[v].pos)),
    );
    let mut out = Vec::new();
    for &v in waypoints {
        if claimed.contains(&v) {
            continue;
        }
        let pv = b.vertices[v].pos;
        // The vertices a lane of this graph joins to v, sorted for binary search (a set per
        // waypoint, grown and hashed, was most of this rule's time).
        let mut joined: Vec<Handle<Vertex>> = ctx.lanes_at_vertex[v.index()]
            .iter()
            .map(|&l| &b.lanes[l])
            .filter(|l| l.graph == graph)
            .flat_map(|l| [l.start, l.end])
            .collect();
        joined.sort_unstable();
        let mut others = Vec::new();
        grid.near(
            pv,
            |i| !claimed.contains(&waypoints[i as usize]),
            |i| {
                let w = waypoints[i as usize];
                if w != v
                    && joined.binary_search(&w).is_err()
                    && b.vertices[w].pos.minus(pv).norm() < NEAR_TOLERANCE
                {
                    others.push(w);
                }
            },
        );
        claimed.insert(v);
        if others.is_empty() {
            continue;
        }
        others.sort_unstable();
        claimed.extend(others.iter().copied());
        out.push(Spot { center: v, others });
    }
    out
}

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    // (center, others) -> graphs, so a spot that several graphs share is one warning.
    type SpotKey = (Handle<Vertex>, Vec<Handle<Vertex>>);
    let mut found: BTreeMap<SpotKey, Vec<i64>> = BTreeMap::new();
    for (&graph, lanes) in &ctx.lanes_by_graph {
        // The graph's waypoints, per level, in document order.
        let mut by_level: BTreeMap<_, Vec<Handle<Vertex>>> = BTreeMap::new();
        let mut seen: HashSet<Handle<Vertex>> = HashSet::new();
        for &l in lanes {
            for v in [b.lanes[l].start, b.lanes[l].end] {
                if seen.insert(v) {
                    by_level.entry(b.vertices[v].level).or_default().push(v);
                }
            }
        }
        for waypoints in by_level.values_mut() {
            waypoints.sort_unstable();
            for s in spots(ctx, graph, waypoints) {
                found.entry((s.center, s.others)).or_default().push(graph);
            }
        }
    }
    for ((center, others), graphs) in found {
        let gword = if graphs.len() == 1 { "graph" } else { "graphs" };
        let graphs = graphs
            .iter()
            .map(|g| g.to_string())
            .collect::<Vec<_>>()
            .join(", ");
        // Reported at the second waypoint of the spot in document order.
        let at = others[0];
        let pc = b.vertices[center].pos;
        let d = if others.len() == 1 {
            Diagnostic::warning(
                RULE.code,
                ctx.vertex_span(at),
                format!(
                    "{} is {:.3} m from {}; both are waypoints of {gword} {graphs} but \
                     no lane joins them, so the lanes that seem to meet here do not",
                    ctx.vertex_label(at),
                    b.vertices[at].pos.minus(pc).norm(),
                    ctx.vertex_label(center)
                ),
            )
            .with_label(ctx.vertex_span(center), "the other waypoint")
            .with_help("merge the two vertices: reconnect the lanes of one to the other")
        } else {
            let mut d = Diagnostic::warning(
                RULE.code,
                ctx.vertex_span(at),
                format!(
                    "{} waypoints of {gword} {graphs} lie within {NEAR_TOLERANCE} m of {} \
                     but no lane joins them to it, so the lanes that seem to meet here do not",
                    others.len() + 1,
                    ctx.vertex_label(center)
                ),
            )
            .with_label(ctx.vertex_span(center), "the first waypoint of this spot");
            for &w in others.iter().skip(1).take(MAX_LABELS - 1) {
                d = d.with_label(ctx.vertex_span(w), "another waypoint of this spot");
            }
            if others.len() > MAX_LABELS {
                d = d.with_label(
                    ctx.vertex_span(*others.last().unwrap_or(&at)),
                    format!(
                        "the last of {} more waypoints of this spot",
                        others.len() - MAX_LABELS
                    ),
                );
            }
            d.with_help(
                "merge the waypoints of the spot: reconnect the lanes of each to one of them",
            )
        };
        out.push(d);
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::TestMap;

    fn run(m: &TestMap) -> Vec<String> {
        crate::validate(&m.b)
            .into_iter()
            .filter(|d| d.code == "W0207")
            .map(|d| d.message)
            .collect()
    }

    #[test]
    fn near_unjoined_waypoints() {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 4.0, 0.0);
        let c = m.vertex("c", 4.03, 0.05);
        let d = m.vertex("d", 8.0, 0.0);
        m.lane(a, b, 0, true);
        m.lane(c, d, 0, true);
        let r = run(&m);
        assert_eq!(r.len(), 1);
        assert!(r[0].starts_with("vertex `c`"), "{r:?}");
        assert!(r[0].contains("0.058 m from vertex `b`"), "{r:?}");
    }

    #[test]
    fn not_reported() {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 4.0, 0.0);
        let c = m.vertex("c", 4.05, 0.0);
        let d = m.vertex("d", 8.0, 0.0);
        let e = m.vertex("e", 4.0, 0.09); // same x window, different graph
        let f = m.vertex("f", 4.0, 0.2); // 0.2 m away
        m.lane(a, b, 0, true);
        m.lane(b, c, 0, true); // joined by a (short) lane
        m.lane(c, d, 0, true);
        m.lane(e, a, 1, true);
        m.lane(f, a, 0, true);
        let _unused = m.vertex("g", 4.0, 0.01); // no lane at all
        assert!(run(&m).is_empty(), "{:?}", run(&m));
    }

    #[test]
    fn a_spot_is_one_warning() {
        // k waypoints on one spot: one warning, not k(k-1)/2.
        let mut m = TestMap::new();
        let hub = m.vertex("hub", 10.0, 0.0);
        for i in 0..300 {
            let v = m.vertex(&format!("s{i}"), 1.0 + (i % 7) as f64 * 0.001, 0.0);
            m.lane(v, hub, 0, true);
        }
        let r = run(&m);
        assert_eq!(r.len(), 1, "{r:?}");
        assert!(
            r[0].starts_with("300 waypoints of graph 0 lie within 0.1 m of vertex `s0`"),
            "{r:?}"
        );
        let d: Vec<_> = crate::validate(&m.b)
            .into_iter()
            .filter(|d| d.code == "W0207")
            .collect();
        assert_eq!(d[0].labels.len(), 5, "{:?}", d[0].labels);
    }

    #[test]
    fn shared_spot_is_one_warning_naming_the_graphs() {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 4.0, 0.0);
        let c = m.vertex("c", 4.03, 0.0);
        let d = m.vertex("d", 8.0, 0.0);
        for g in [0, 1] {
            m.lane(a, b, g, true);
            m.lane(c, d, g, true);
        }
        let r = run(&m);
        assert_eq!(r.len(), 1, "{r:?}");
        assert!(r[0].contains("waypoints of graphs 0, 1"), "{r:?}");
    }

    #[test]
    fn sweep_is_not_fooled_by_order() {
        // Many vertices on one vertical line: the x window holds them all, y decides.
        let mut m = TestMap::new();
        let hub = m.vertex("hub", 10.0, 0.0);
        for i in 0..50 {
            let v = m.vertex("", 0.0, i as f64);
            m.lane(v, hub, 0, true);
        }
        assert!(run(&m).is_empty());
    }
}
