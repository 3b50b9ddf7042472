//! # W0213 demo-mock-lift-without-floor
//!
//! **What:** a lane has `demo_mock_lift_name` but no `demo_mock_floor_name`.
//!
//! **Why it matters:** a mock lift ride needs both names; the lift name alone is ignored by
//! the fleet adapter, so the lane behaves as a plain lane, which is probably not what the
//! author meant.
//!
//! **Fix:** add `demo_mock_floor_name: [1, <level name>]`, or remove the lift name.
//!
//! **Example:**
//! ```yaml
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], demo_mock_lift_name: [1, lift1]}]   # W0213
//! ```

use super::label_lane;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0213",
    name: "demo-mock-lift-without-floor",
    summary: "demo_mock_lift_name without demo_mock_floor_name (ignored)",
    group: Group::Lanes,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, lane) in ctx.b.lanes.iter() {
        if let (None, Some(lift)) = (&lane.demo_mock_floor_name, &lane.demo_mock_lift_name) {
            let span = lane
                .params
                .param("demo_mock_lift_name")
                .map_or(ctx.lane_span(h), |p| p.span);
            out.push(label_lane(
                Diagnostic::warning(
                    RULE.code,
                    span,
                    format!(
                        "lane has `demo_mock_lift_name` `{lift}` but no \
                         `demo_mock_floor_name`; the lift name is ignored"
                    ),
                )
                .with_help("add `demo_mock_floor_name: [1, <level name>]`, or remove the lift"),
                ctx,
                h,
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::TestMap;

    fn count(floor: Option<&str>, lift: Option<&str>) -> usize {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 1.0, 0.0);
        let l = m.lane(a, b, 0, true);
        m.b.lanes[l].demo_mock_floor_name = floor.map(Into::into);
        m.b.lanes[l].demo_mock_lift_name = lift.map(Into::into);
        crate::validate(&m.b)
            .into_iter()
            .filter(|d| d.code == "W0213")
            .count()
    }

    #[test]
    fn lift_without_floor_only() {
        assert_eq!(count(None, Some("lift1")), 1);
        assert_eq!(count(Some("L2"), Some("lift1")), 0);
        assert_eq!(count(Some("L2"), None), 0);
        assert_eq!(count(None, None), 0);
    }
}
