//! # E0409 lane-between-lifts
//!
//! **What:** a lane starts inside one lift and ends inside another (on the same level).
//!
//! **Why it matters:** a robot cannot drive from one cabin into another; the fleet
//! adapter refuses the graph ("two connected waypoints ... that are in different
//! lifts"). It usually happens when two lifts' shafts are drawn too close together, or
//! when a lane was snapped to the wrong lift's waypoint.
//!
//! **Fix:** connect each lift's waypoint to a waypoint outside the lifts (in front of its
//! door), not to another lift's waypoint.
//!
//! **Example:**
//! ```yaml
//! vertices: [[0, 0, 0, LA_L1], [3, 0, 0, LB_L1]]   # cabins of lifts LA at (0, 0), LB at (3, 0)
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]   # E0409
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0409",
    name: "lane-between-lifts",
    summary: "a lane joins waypoints inside two different lifts",
    group: Group::LiftWaypoints,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    if b.lifts.len() < 2 {
        return;
    }
    for (h, lane) in b.lanes.iter() {
        let (Some(a), Some(c)) = (ctx.lift_of(lane.start), ctx.lift_of(lane.end)) else {
            continue;
        };
        if a == c {
            continue;
        }
        out.push(
            Diagnostic::error(
                RULE.code,
                ctx.lane_span(h),
                format!(
                    "lane of graph {} joins {} inside lift `{}` to {} inside lift `{}`",
                    lane.graph,
                    ctx.vertex_label(lane.start),
                    b.lifts[a].name,
                    ctx.vertex_label(lane.end),
                    b.lifts[c].name
                ),
            )
            .with_label(
                ctx.vertex_span(lane.start),
                format!("inside lift `{}`", b.lifts[a].name),
            )
            .with_label(
                ctx.vertex_span(lane.end),
                format!("inside lift `{}`", b.lifts[c].name),
            )
            .with_help("connect each lift's waypoint to a waypoint outside the lifts"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::Vec2;

    #[test]
    fn finds_lanes_between_lifts() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let a = m.vertex("in_a", 0.0, 0.0);
        let b = m.vertex("in_b", 3.0, 0.0);
        let c = m.vertex("out", 1.5, -3.0);
        let a2 = m.vertex("in_a2", 0.5, 0.5);
        m.lane(a, c, 0, true);
        m.lane(c, b, 0, true);
        m.lane(a, a2, 0, true);
        assert!(!codes_of(&m.b).contains(&"E0409"));
        m.lane(a, b, 0, true);
        m.lift("LA", Vec2::new(0.0, 0.0), 2.0, 2.0, &[l1]);
        m.lift("LB", Vec2::new(3.0, 0.0), 2.0, 2.0, &[l1]);
        assert_eq!(codes_of(&m.b).iter().filter(|c| **c == "E0409").count(), 1);
    }
}
