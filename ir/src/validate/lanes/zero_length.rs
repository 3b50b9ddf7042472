//! # W0202 zero-length-lane
//!
//! **What:** a lane joins two different vertices that lie less than 1 mm apart.
//!
//! **Why it matters:** the lane looks like a connection but has no length: the two
//! waypoints are really one place drawn twice. Planners treat it as a zero-time edge, the
//! lane's direction is meaningless, and any door or lift event on it happens "in place".
//! Usually one vertex was dropped on top of another while drawing.
//!
//! **Fix:** merge the two vertices (move every lane, wall and role of one onto the other
//! and delete it), then delete the lane.
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [10.0, 4.0, 0, a]
//!   - [10.0, 4.0, 0, b]
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]   # W0202: 0 m long
//! ```

use super::geom::TOUCH;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0202",
    name: "zero-length-lane",
    summary: "a lane joins two different vertices less than 1 mm apart",
    group: Group::Lanes,
    metric: true,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, lane) in ctx.b.lanes.iter() {
        if lane.start == lane.end {
            continue; // E0201
        }
        let (a, b) = (ctx.b.vertices[lane.start].pos, ctx.b.vertices[lane.end].pos);
        let len = b.minus(a).norm();
        if len < TOUCH {
            out.push(
                Diagnostic::warning(
                    RULE.code,
                    ctx.lane_span(h),
                    format!(
                        "lane of graph {} is {:.2} mm long: {} and {} are at the same place",
                        lane.graph,
                        len * 1000.0,
                        ctx.vertex_label(lane.start),
                        ctx.vertex_label(lane.end)
                    ),
                )
                .with_label(ctx.vertex_span(lane.start), "start")
                .with_label(ctx.vertex_span(lane.end), "end")
                .with_help("merge the two vertices and delete the lane"),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};

    fn count(b: &crate::Building) -> usize {
        codes_of(b).iter().filter(|c| **c == "W0202").count()
    }

    #[test]
    fn finds_coincident_endpoints() {
        let mut m = TestMap::new();
        let a = m.vertex("a", 1.0, 1.0);
        let b = m.vertex("b", 1.0005, 1.0);
        let c = m.vertex("c", 1.002, 1.0);
        m.lane(a, b, 0, true);
        m.lane(a, c, 0, true); // 2 mm: short but real
        m.lane(a, a, 0, true); // a self loop is E0201's business
        assert_eq!(count(&m.b), 1);
    }
}
