//! # W0203 duplicate-lane
//!
//! **What:** after two-way lanes are expanded into their two directions, the same directed
//! edge (same start vertex, same end vertex) occurs twice in one graph: two lanes `a → b`,
//! two two-way lanes between `a` and `b`, or a two-way lane `a – b` plus a one-way lane
//! `b → a`.
//!
//! **Why it matters:** the navigation graph gets parallel edges that may disagree (one
//! with a speed limit or an orientation constraint, one without); which one a planner picks
//! is arbitrary, and later edits to one copy silently leave the other behind. A two-way
//! lane overlaid with a one-way lane usually means the one-way restriction was intended
//! but is not in effect.
//!
//! **Fix:** keep one lane per pair of waypoints: delete the copy, or delete the two-way lane
//! if the one-way lane is what you meant.
//!
//! **Example:**
//! ```yaml
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]
//!   - [1, 0, {graph_idx: [2, 0], bidirectional: [4, false]}]   # W0203: 1 → 0 exists
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Handle, Lane, Vertex};
use std::collections::HashMap;

pub(crate) static RULE: Rule = Rule {
    code: "W0203",
    name: "duplicate-lane",
    summary: "the same directed edge occurs twice in one graph",
    group: Group::Lanes,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let mut seen: HashMap<(i64, Handle<Vertex>, Handle<Vertex>), Handle<Lane>> =
        HashMap::with_capacity(ctx.b.lanes.len());
    for (h, lane) in ctx.b.lanes.iter() {
        if lane.start == lane.end {
            continue; // E0201
        }
        let (s, e) = (lane.start, lane.end);
        let edges = [(s, e), (e, s)];
        let mut first_dup: Option<(Handle<Lane>, Handle<Vertex>, Handle<Vertex>)> = None;
        for &(from, to) in &edges[..1 + usize::from(lane.bidirectional)] {
            match seen.get(&(lane.graph, from, to)) {
                Some(&other) => {
                    first_dup.get_or_insert((other, from, to));
                }
                None => {
                    seen.insert((lane.graph, from, to), h);
                }
            }
        }
        let Some((other, from, to)) = first_dup else {
            continue;
        };
        let kind = |l: &Lane| {
            if l.bidirectional {
                "two-way"
            } else {
                "one-way"
            }
        };
        out.push(
            Diagnostic::warning(
                RULE.code,
                ctx.lane_span(h),
                format!(
                    "duplicate lane in graph {}: the edge from {} to {} is already given by an \
                     earlier {} lane",
                    lane.graph,
                    ctx.vertex_label(from),
                    ctx.vertex_label(to),
                    kind(&ctx.b.lanes[other])
                ),
            )
            .with_label(ctx.lane_span(other), "the earlier lane")
            .with_help(format!(
                "keep one lane per pair of waypoints: delete this {} lane or the earlier one",
                kind(lane)
            )),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, lanes_map};

    fn count(lanes: &[(usize, usize, i64, bool)]) -> usize {
        codes_of(&lanes_map(lanes))
            .iter()
            .filter(|c| **c == "W0203")
            .count()
    }

    #[test]
    fn same_direction_twice() {
        assert_eq!(count(&[(0, 1, 0, false), (0, 1, 0, false)]), 1);
    }

    #[test]
    fn two_way_plus_one_way_back() {
        assert_eq!(count(&[(0, 1, 0, true), (1, 0, 0, false)]), 1);
        // Two two-way lanes, written in opposite directions: one report, not two.
        assert_eq!(count(&[(0, 1, 0, true), (1, 0, 0, true)]), 1);
    }

    #[test]
    fn distinct_edges_are_fine() {
        // Opposite one-way lanes form a two-way connection; other graphs are independent.
        assert_eq!(count(&[(0, 1, 0, false), (1, 0, 0, false)]), 0);
        assert_eq!(count(&[(0, 1, 0, true), (0, 1, 1, true)]), 0);
        assert_eq!(count(&[(0, 1, 0, true), (1, 2, 0, true)]), 0);
    }
}
