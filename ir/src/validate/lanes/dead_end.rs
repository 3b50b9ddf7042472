//! # W0209 one-way-dead-end
//!
//! **What:** in one graph, a waypoint that robots can enter but not leave (lanes lead into
//! it, none lead out), or leave but never reach (lanes lead out of it, none lead in).
//! Two-way lanes count in both directions. Waypoints inside the same lift shaft on
//! different levels are taken together (a robot may enter the lift on one level and leave
//! it on another).
//!
//! **Why it matters:** a robot sent to a trap waypoint stays there for ever: the planner
//! finds no way out, so every later task of that robot fails. A waypoint that cannot be
//! reached is useless as a goal (charger, parking spot, pickup) and strands the robot that
//! starts there once it has left. It is almost always a one-way lane drawn the wrong way,
//! or a lane left one-way where it should be two-way.
//!
//! **Fix:** make one of the waypoint's lanes two-way, reverse a one-way lane, or add a lane
//! in the missing direction.
//!
//! **Example:**
//! ```yaml
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]
//!   - [1, 2, {graph_idx: [2, 0], bidirectional: [4, false]}]   # vertex 2: W0209
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Handle, Lane, Lift, Vertex};
use std::collections::{BTreeMap, HashMap};

pub(crate) static RULE: Rule = Rule {
    code: "W0209",
    name: "one-way-dead-end",
    summary: "a waypoint robots can enter but not leave, or leave but not reach",
    group: Group::Lanes,
    metric: false,
    check,
};

#[derive(Clone, Copy)]
struct Ways {
    into: bool,
    out_of: bool,
    /// A lane at the waypoint, for the label.
    lane: Handle<Lane>,
}

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    for (&graph, lanes) in &ctx.lanes_by_graph {
        let mut ways: HashMap<Handle<Vertex>, Ways> = HashMap::new();
        let mut order = Vec::new();
        for &l in lanes {
            let lane = &b.lanes[l];
            if lane.start == lane.end {
                continue; // E0201
            }
            for (v, into, out_of) in [
                (lane.start, lane.bidirectional, true),
                (lane.end, true, lane.bidirectional),
            ] {
                let w = ways.entry(v).or_insert_with(|| {
                    order.push(v);
                    Ways {
                        into: false,
                        out_of: false,
                        lane: l,
                    }
                });
                w.into |= into;
                w.out_of |= out_of;
            }
        }
        // Lift waypoints on 2+ levels share their ways in and out.
        let mut by_lift: BTreeMap<Handle<Lift>, Vec<Handle<Vertex>>> = BTreeMap::new();
        for &v in &order {
            if let Some(lift) = ctx.lift_of(v) {
                by_lift.entry(lift).or_default().push(v);
            }
        }
        let mut shared: HashMap<Handle<Vertex>, (bool, bool)> = HashMap::new();
        for members in by_lift.values() {
            let level = b.vertices[members[0]].level;
            if members.iter().all(|&v| b.vertices[v].level == level) {
                continue;
            }
            let into = members.iter().any(|v| ways[v].into);
            let out_of = members.iter().any(|v| ways[v].out_of);
            for &v in members {
                shared.insert(v, (into, out_of));
            }
        }
        for &v in &order {
            let w = ways[&v];
            let (into, out_of) = shared.get(&v).copied().unwrap_or((w.into, w.out_of));
            let (what, help) = match (into, out_of) {
                (true, false) => (
                    "robots can enter it but never leave: every lane there leads into it",
                    "make one of its lanes two-way, or add a lane leading out of it",
                ),
                (false, true) => (
                    "robots can leave it but never reach it: every lane there leads away from it",
                    "make one of its lanes two-way, or add a lane leading into it",
                ),
                _ => continue,
            };
            out.push(
                Diagnostic::warning(
                    RULE.code,
                    ctx.vertex_span(v),
                    format!("{} in graph {graph}: {what}", ctx.vertex_label(v)),
                )
                .with_label(ctx.lane_span(w.lane), "a one-way lane here")
                .with_help(help),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{lanes_map, TestMap};
    use crate::Vec2;

    fn run(b: &crate::Building) -> Vec<String> {
        crate::validate(b)
            .into_iter()
            .filter(|d| d.code == "W0209")
            .map(|d| d.message)
            .collect()
    }

    #[test]
    fn traps_and_sources() {
        let r = run(&lanes_map(&[(0, 1, 0, true), (1, 2, 0, false)]));
        assert_eq!(r.len(), 1);
        assert!(
            r[0].starts_with("vertex `v2`") && r[0].contains("never leave"),
            "{r:?}"
        );
        let r = run(&lanes_map(&[(0, 1, 0, true), (2, 1, 0, false)]));
        assert_eq!(r.len(), 1);
        assert!(
            r[0].starts_with("vertex `v2`") && r[0].contains("never reach"),
            "{r:?}"
        );
    }

    #[test]
    fn cycles_and_two_way_lanes_are_fine() {
        assert!(run(&lanes_map(&[
            (0, 1, 0, false),
            (1, 2, 0, false),
            (2, 0, 0, false)
        ]))
        .is_empty());
        assert!(run(&lanes_map(&[(0, 1, 0, true)])).is_empty());
        // Per graph: a one-way lane of graph 1 is not excused by graph 0.
        assert_eq!(
            run(&lanes_map(&[(0, 1, 0, true), (0, 1, 1, false)])).len(),
            2
        );
    }

    #[test]
    fn lifts_join_levels() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let a = m.vertex("a", 0.0, 0.0);
        let la = m.vertex("lift_L1", 5.0, 0.0);
        m.lane(a, la, 0, false);
        let l2 = m.level("L2", 4.0);
        let lb = m.vertex("lift_L2", 5.0, 0.0);
        let c = m.vertex("c", 0.0, 0.0);
        m.lane(lb, c, 0, false);
        // a -> lift_L1 and lift_L2 -> c: without a lift, both lift waypoints are dead ends.
        assert_eq!(run(&m.b).len(), 4);
        m.lift("lift", Vec2::new(5.0, 0.0), 2.0, 2.0, &[l1, l2]);
        let r = run(&m.b);
        assert_eq!(r.len(), 2, "{r:?}");
        assert!(r.iter().all(|d| !d.contains("lift_")), "{r:?}");
    }
}
