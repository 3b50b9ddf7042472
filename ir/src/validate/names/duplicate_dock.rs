//! # E0502 duplicate-dock-name
//!
//! **What:** two different waypoints of one navigation graph have the same `dock_name`.
//!
//! **Why it matters:** the nav graph turns `dock_name` into the `dock_name` of the lanes
//! entering the waypoint (and `undock_name` of the lanes leaving it); the fleet adapter
//! runs the docking procedure of that name when a robot drives such a lane. A dock name is
//! meant to identify one docking spot: with two waypoints sharing it, a request to dock
//! there (a charger, a workcell) is ambiguous and the robot may dock at the wrong place.
//!
//! **Fix:** give each dock waypoint its own `dock_name`.
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, a, {dock_name: [1, charger_dock]}]
//!   - [4, 0, 0, b, {dock_name: [1, charger_dock]}]   # E0502
//! ```

use super::{duplicates_per_graph, graphs_text};
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0502",
    name: "duplicate-dock-name",
    summary: "two waypoints of one graph have the same dock_name",
    group: Group::Names,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    let dups = duplicates_per_graph(ctx, |v| b.vertices[v].roles.dock_name.as_deref());
    for ((v, earlier), graphs) in dups {
        let span = b.vertices[v]
            .params
            .param("dock_name")
            .map_or(ctx.vertex_span(v), |p| p.span);
        out.push(
            Diagnostic::error(
                RULE.code,
                span,
                format!(
                    "dock name `{}` is given to two waypoints of {}: {} and {}",
                    b.vertices[v].roles.dock_name.as_deref().unwrap_or(""),
                    graphs_text(&graphs),
                    ctx.vertex_label(earlier),
                    ctx.vertex_label(v),
                ),
            )
            .with_label(
                ctx.vertex_span(earlier),
                "the other waypoint with this dock",
            )
            .with_help("give each dock waypoint its own dock_name"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{param, params, TestMap};
    use crate::ParamValue;

    fn dock(name: &str) -> crate::Params {
        params(vec![param("dock_name", ParamValue::String(name.into()))])
    }

    fn count(m: &TestMap) -> usize {
        crate::validate(&m.b)
            .iter()
            .filter(|d| d.code == "E0502")
            .count()
    }

    #[test]
    fn same_dock_twice() {
        let mut m = TestMap::new();
        let a = m.vertex_with("a", 0.0, 0.0, dock("d1"));
        let b = m.vertex_with("b", 4.0, 0.0, dock("d1"));
        let c = m.vertex_with("c", 8.0, 0.0, dock("d2"));
        m.lane(a, b, 0, true);
        m.lane(b, c, 0, true);
        assert_eq!(count(&m), 1);
    }

    #[test]
    fn different_graphs_are_fine() {
        let mut m = TestMap::new();
        let a = m.vertex_with("a", 0.0, 0.0, dock("d1"));
        let b = m.vertex("b", 4.0, 0.0);
        let c = m.vertex_with("c", 8.0, 0.0, dock("d1"));
        m.lane(a, b, 0, true);
        m.lane(b, c, 1, true);
        assert_eq!(count(&m), 0);
    }
}
