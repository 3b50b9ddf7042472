//! # E0501 duplicate-waypoint-name
//!
//! **What:** two different vertices with the same non-empty name are both waypoints of one
//! navigation graph (both used by its lanes), on the same level or on different levels.
//!
//! **Why it matters:** the fleet adapter uses waypoint names as keys across the whole graph
//! (all levels together) and refuses to load a graph with a repeated name, so the fleet
//! fails to start. Tasks name their goals by waypoint name too: with two `pantry`
//! waypoints, "go to pantry" would be ambiguous.
//!
//! **Fix:** rename one of the vertices (names only need to be unique among the waypoints of
//! one graph; a name per level, like `lift_L1`, `lift_L2`, is a common scheme).
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, pantry]
//!   - [4, 0, 0, pantry]     # E0501
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]
//! ```

use super::{duplicates_per_graph, graphs_text};
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0501",
    name: "duplicate-waypoint-name",
    summary: "two waypoints of one graph have the same name",
    group: Group::Names,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    let dups = duplicates_per_graph(ctx, |v| {
        let name = b.vertices[v].name.as_str();
        (!name.is_empty()).then_some(name)
    });
    for ((v, earlier), graphs) in dups {
        out.push(
            Diagnostic::error(
                RULE.code,
                ctx.vertex_span(v),
                format!(
                    "waypoint name `{}` is used twice in {}: by {} and by {}; the fleet \
                     adapter rejects the graph",
                    b.vertices[v].name,
                    graphs_text(&graphs),
                    ctx.vertex_label(earlier),
                    ctx.vertex_label(v),
                ),
            )
            .with_label(
                ctx.vertex_span(earlier),
                "the other waypoint with this name",
            )
            .with_help("rename one of the two vertices"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::TestMap;

    fn count(m: &TestMap) -> usize {
        crate::validate(&m.b)
            .iter()
            .filter(|d| d.code == "E0501")
            .count()
    }

    #[test]
    fn same_graph_same_name() {
        let mut m = TestMap::new();
        let a = m.vertex("pantry", 0.0, 0.0);
        let b = m.vertex("pantry", 4.0, 0.0);
        m.lane(a, b, 0, true);
        assert_eq!(count(&m), 1);
        // Shared by two graphs: still one report.
        m.lane(a, b, 1, true);
        assert_eq!(count(&m), 1);
    }

    #[test]
    fn across_levels() {
        let mut m = TestMap::new();
        let a = m.vertex("lift", 0.0, 0.0);
        let b = m.vertex("x", 4.0, 0.0);
        m.lane(a, b, 0, true);
        m.level("L2", 4.0);
        let c = m.vertex("lift", 0.0, 0.0);
        let d = m.vertex("y", 4.0, 0.0);
        m.lane(c, d, 0, true);
        assert_eq!(count(&m), 1);
    }

    #[test]
    fn not_duplicates() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 4.0, 0.0);
        let c = m.vertex("c", 8.0, 0.0);
        let d = m.vertex("c", 12.0, 0.0);
        let _unused = m.vertex("c", 16.0, 0.0);
        m.lane(a, b, 0, true); // unnamed waypoints
        m.lane(b, c, 0, true);
        m.lane(d, a, 1, true); // other graph
        assert_eq!(count(&m), 0);
    }
}
