//! # E0201 lane-self-loop
//!
//! **What:** a lane starts and ends at the same vertex.
//!
//! **Why it matters:** a self loop has no direction and no length; the fleet adapter
//! plans over it as a zero-time edge, and the traffic schedule can never make progress
//! along it. It is always a drawing mistake (a double click in the editor).
//!
//! **Fix:** delete the lane, or redraw it between two different waypoints.
//!
//! **Example:**
//! ```yaml
//! lanes:
//!   - [3, 3, {graph_idx: [2, 0], bidirectional: [4, true]}]   # E0201
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0201",
    name: "lane-self-loop",
    summary: "a lane starts and ends at the same vertex",
    group: Group::Lanes,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, lane) in ctx.b.lanes.iter() {
        if lane.start == lane.end {
            out.push(
                Diagnostic::error(
                    RULE.code,
                    ctx.lane_span(h),
                    format!(
                        "lane of graph {} starts and ends at {}",
                        lane.graph,
                        ctx.vertex_label(lane.start)
                    ),
                )
                .with_label(ctx.vertex_span(lane.start), "the vertex")
                .with_help("delete the lane or connect two different waypoints"),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, lanes_map};

    #[test]
    fn finds_self_loops_only() {
        let d = codes_of(&lanes_map(&[(0, 0, 0, true), (0, 1, 0, true)]));
        assert_eq!(d.iter().filter(|c| **c == "E0201").count(), 1);
    }
}
