//! # E0212 demo-mock-incomplete
//!
//! **What:** a lane has `demo_mock_floor_name` without `demo_mock_lift_name`. (The reverse,
//! a lift without a floor, is the warning W0213.)
//!
//! **Why it matters:** the two parameters together turn a lane into a "mock lift" ride for
//! demos (the robot pretends to take the named lift to the named floor). The fleet adapter
//! refuses to load a graph with a mock floor but no mock lift, so the fleet fails to start.
//!
//! **Fix:** set both parameters on the lane, or neither.
//!
//! **Example:**
//! ```yaml
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], demo_mock_floor_name: [1, L2]}]   # E0212
//! ```

use super::label_lane;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0212",
    name: "demo-mock-incomplete",
    summary: "demo_mock_floor_name without demo_mock_lift_name",
    group: Group::Lanes,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, lane) in ctx.b.lanes.iter() {
        let span = |name: &str| lane.params.param(name).map_or(ctx.lane_span(h), |p| p.span);
        if let (Some(floor), None) = (&lane.demo_mock_floor_name, &lane.demo_mock_lift_name) {
            out.push(label_lane(
                Diagnostic::error(
                    RULE.code,
                    span("demo_mock_floor_name"),
                    format!(
                        "lane has `demo_mock_floor_name` `{floor}` but no \
                         `demo_mock_lift_name`; the fleet adapter rejects the graph"
                    ),
                )
                .with_help("add `demo_mock_lift_name: [1, <lift name>]`, or remove the floor"),
                ctx,
                h,
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::TestMap;
    use crate::Severity;

    fn run(floor: Option<&str>, lift: Option<&str>) -> Vec<Severity> {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 1.0, 0.0);
        let l = m.lane(a, b, 0, true);
        m.b.lanes[l].demo_mock_floor_name = floor.map(Into::into);
        m.b.lanes[l].demo_mock_lift_name = lift.map(Into::into);
        crate::validate(&m.b)
            .into_iter()
            .filter(|d| d.code == "E0212")
            .map(|d| d.severity)
            .collect()
    }

    #[test]
    fn pairs() {
        assert!(run(None, None).is_empty());
        assert!(run(Some("L2"), Some("lift1")).is_empty());
        assert_eq!(run(Some("L2"), None), vec![Severity::Error]);
        // Reported by W0213 instead.
        assert!(run(None, Some("lift1")).is_empty());
    }
}
