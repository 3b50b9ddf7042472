//! # E0407 lift-waypoints-misaligned
//!
//! **What:** two waypoints of one nav graph lie inside the same lift (on different
//! levels, or twice on one level) more than 0.1 m apart horizontally.
//!
//! **Why it matters:** the fleet adapter links every waypoint of a lift in a graph into
//! one vertical stack and rejects the whole graph ("Bad vertical alignment for the
//! waypoints in lift ...") when any two of them are more than 0.1 m apart. The fleet then
//! does not start. On `reference_image` maps the usual cause is a level whose fiducials
//! do not line up exactly with the reference level, so the same pixel lands at a
//! slightly different place; elsewhere it is a waypoint dragged off the lift centre.
//!
//! **Fix:** place one waypoint per level at the lift's centre (traffic_editor's
//! `lift_cabin` vertices), check the fiducials of misaligned levels, and do not put two
//! lane vertices of one graph inside the same lift on one level.
//!
//! **Example:**
//! ```yaml
//! L1:
//!   vertices: [[10, 5, 0, LA_L1], ...]   # lift LA is centred at (10, 5)
//! L2:
//!   vertices: [[10.4, 5, 0, LA_L2], ...]   # E0407: 0.4 m from LA_L1
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Handle, Lift, Vertex};
use std::collections::BTreeMap;

/// The fleet adapter's limit, metres.
const MAX_SPREAD: f64 = 0.1;

pub(crate) static RULE: Rule = Rule {
    code: "E0407",
    name: "lift-waypoints-misaligned",
    summary: "waypoints inside the same lift are more than 0.1 m apart",
    group: Group::LiftWaypoints,
    metric: true,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    if b.lifts.is_empty() {
        return;
    }
    // Farthest pair per (lift, graph), merged over graphs: pair -> graphs.
    type Pair = (Handle<Lift>, Handle<Vertex>, Handle<Vertex>);
    let mut bad: BTreeMap<Pair, Vec<i64>> = BTreeMap::new();
    for (&graph, lanes) in &ctx.lanes_by_graph {
        let mut by_lift: BTreeMap<Handle<Lift>, Vec<Handle<Vertex>>> = BTreeMap::new();
        let mut seen = std::collections::HashSet::new();
        for &l in lanes {
            let lane = &b.lanes[l];
            for v in [lane.start, lane.end] {
                if let Some(lift) = ctx.lift_of(v) {
                    if seen.insert(v) {
                        by_lift.entry(lift).or_default().push(v);
                    }
                }
            }
        }
        for (lift, vs) in by_lift {
            // The farthest pair is a pair of hull vertices: compare those only.
            let vs = hull(b, vs);
            let mut worst: Option<(f64, Handle<Vertex>, Handle<Vertex>)> = None;
            for (i, &a) in vs.iter().enumerate() {
                for &c in &vs[i + 1..] {
                    let d = b.vertices[a].pos.minus(b.vertices[c].pos).norm();
                    if d > MAX_SPREAD && worst.is_none_or(|w| d > w.0) {
                        worst = Some((d, a.min(c), a.max(c)));
                    }
                }
            }
            if let Some((_, a, c)) = worst {
                bad.entry((lift, a, c)).or_default().push(graph);
            }
        }
    }
    for ((lift, a, c), graphs) in bad {
        let (va, vc) = (&b.vertices[a], &b.vertices[c]);
        let d = va.pos.minus(vc.pos).norm();
        let graphs: Vec<String> = graphs.iter().map(i64::to_string).collect();
        let s = if graphs.len() > 1 { "s" } else { "" };
        out.push(
            Diagnostic::error(
                RULE.code,
                ctx.vertex_span(c),
                format!(
                    "{} and {} are both inside lift `{}` but {d:.3} m apart (more than {MAX_SPREAD} m); \
                     the fleet adapter rejects graph{s} {}",
                    ctx.vertex_label(c),
                    ctx.vertex_label(a),
                    b.lifts[lift].name,
                    graphs.join(", ")
                ),
            )
            .with_label(ctx.vertex_span(a), "the other waypoint in the lift")
            .with_help(
                "put one waypoint per level at the lift centre; if levels are misaligned, \
                 check their fiducials",
            ),
        );
    }
}

/// The vertices of `vs` on their convex hull (Andrew's monotone chain; collinear points
/// dropped), in document order. With duplicates or fewer than 3 points, all of them.
fn hull(b: &crate::Building, mut vs: Vec<Handle<Vertex>>) -> Vec<Handle<Vertex>> {
    if vs.len() <= 3 {
        return vs;
    }
    let pos = |v: Handle<Vertex>| b.vertices[v].pos;
    vs.sort_by(|&p, &q| {
        let (p, q) = (pos(p), pos(q));
        p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y))
    });
    let turn = |o: Handle<Vertex>, a: Handle<Vertex>, c: Handle<Vertex>| {
        pos(a).minus(pos(o)).cross(pos(c).minus(pos(o)))
    };
    let mut chain: Vec<Handle<Vertex>> = Vec::with_capacity(2 * vs.len());
    for pass in [vs.clone(), vs.iter().rev().copied().collect()] {
        let start = chain.len();
        for v in pass {
            while chain.len() >= start + 2
                && turn(chain[chain.len() - 2], chain[chain.len() - 1], v) <= 0.0
            {
                chain.pop();
            }
            chain.push(v);
        }
        chain.pop();
    }
    chain.sort_unstable();
    chain.dedup();
    chain
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::Vec2;

    fn map(dx: f64, graph2: i64) -> Vec<&'static str> {
        let mut m = TestMap::new();
        let l1 = m.level;
        let a = m.vertex("a1", 10.0, 5.0);
        let b = m.vertex("b1", 10.0, 2.0);
        m.lane(a, b, 0, true);
        let l2 = m.level("L2", 3.0);
        let c = m.vertex("a2", 10.0 + dx, 5.0);
        let d = m.vertex("b2", 10.0, 2.0);
        m.lane(c, d, graph2, true);
        m.lift("LA", Vec2::new(10.0, 5.0), 2.0, 2.0, &[l1, l2]);
        codes_of(&m.b)
    }

    #[test]
    fn aligned_waypoints_are_fine() {
        assert!(!map(0.05, 0).contains(&"E0407"));
    }

    #[test]
    fn misaligned_waypoints_of_one_graph() {
        let d = map(0.4, 0);
        assert_eq!(d.iter().filter(|c| **c == "E0407").count(), 1);
        // Different graphs are different files for the fleet adapter.
        assert!(!map(0.4, 1).contains(&"E0407"));
    }
}
