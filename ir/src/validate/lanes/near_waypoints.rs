//! # W0207 unconnected-near-waypoints
//!
//! **What:** two different vertices of one level, both used by lanes of the same graph,
//! lie closer than 0.1 m to each other, and no lane of that graph joins them.
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

use crate::validate::{Context, Rule};
use crate::{Diagnostic, Handle, Vertex};

pub(crate) static RULE: Rule = Rule {
    code: "W0207",
    name: "unconnected-near-waypoints",
    summary: "two waypoints of one graph are closer than 0.1 m but not joined",
    check,
};

/// Waypoints of one graph closer than this (metres) should be one waypoint.
pub const NEAR_TOLERANCE: f64 = 0.1;

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    for (_, level) in b.levels.iter() {
        // The level's waypoints: vertices with lanes, with the sorted graphs they serve.
        let mut pts: Vec<(Handle<Vertex>, Vec<i64>)> = level
            .vertices
            .iter()
            .filter(|v| !ctx.lanes_at_vertex[v.index()].is_empty())
            .map(|&v| {
                let mut g: Vec<i64> = ctx.lanes_at_vertex[v.index()]
                    .iter()
                    .map(|&l| b.lanes[l].graph)
                    .collect();
                g.sort_unstable();
                g.dedup();
                (v, g)
            })
            .collect();
        // Sort by x and sweep a window NEAR_TOLERANCE wide.
        pts.sort_by(|p, q| b.vertices[p.0].pos.x.total_cmp(&b.vertices[q.0].pos.x));
        for (i, (v, gv)) in pts.iter().enumerate() {
            let pv = b.vertices[*v].pos;
            for (w, gw) in &pts[i + 1..] {
                let pw = b.vertices[*w].pos;
                if pw.x - pv.x >= NEAR_TOLERANCE {
                    break;
                }
                let dist = pw.minus(pv).norm();
                if dist >= NEAR_TOLERANCE {
                    continue;
                }
                // Graphs both serve, and in which no lane joins the two.
                let shared: Vec<i64> = gv
                    .iter()
                    .copied()
                    .filter(|g| gw.contains(g))
                    .filter(|&g| {
                        !ctx.lanes_at_vertex[v.index()].iter().any(|&l| {
                            let lane = &b.lanes[l];
                            lane.graph == g && (lane.start == *w || lane.end == *w)
                        })
                    })
                    .collect();
                if shared.is_empty() {
                    continue;
                }
                // Report at the later vertex of the document, pointing at the earlier.
                let (later, earlier) = if v > w { (*v, *w) } else { (*w, *v) };
                let graphs = shared
                    .iter()
                    .map(|g| g.to_string())
                    .collect::<Vec<_>>()
                    .join(", ");
                let gword = if shared.len() == 1 { "graph" } else { "graphs" };
                out.push(
                    Diagnostic::warning(
                        RULE.code,
                        ctx.vertex_span(later),
                        format!(
                            "{} is {:.3} m from {}; both are waypoints of {gword} {graphs} but \
                             no lane joins them, so the lanes that seem to meet here do not",
                            ctx.vertex_label(later),
                            dist,
                            ctx.vertex_label(earlier)
                        ),
                    )
                    .with_label(ctx.vertex_span(earlier), "the other waypoint")
                    .with_help("merge the two vertices: reconnect the lanes of one to the other"),
                );
            }
        }
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
