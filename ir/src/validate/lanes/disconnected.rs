//! # W0208 disconnected-graph
//!
//! **What:** the lanes of one graph form more than one connected piece (ignoring lane
//! directions). Waypoints inside the same lift shaft on different levels count as
//! connected, since robots ride the lift between them. One warning is given per graph, at
//! the first lane of the first piece other than the largest, listing the pieces by size
//! (the list is cut after a few: "… and 29,990 more pieces of 2").
//!
//! **Why it matters:** a fleet can only travel within one piece. Robots that start, charge
//! or receive tasks in a smaller piece can never reach the rest of the building, and tasks
//! between pieces fail at planning time. Usually a lane is missing, or two lanes that seem
//! to meet end at two separate vertices (see W0207), or a lift waypoint lies just outside
//! the shaft on one level.
//!
//! **Fix:** add the missing lane, merge the vertices that should be one waypoint, or move
//! the lift waypoints inside the shaft on every level. If the pieces really belong to
//! different fleets, give them different `graph_idx` values.
//!
//! **Example:**
//! ```yaml
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]
//!   - [2, 3, {graph_idx: [2, 0], bidirectional: [4, true]}]   # W0208: 2-3 is cut off
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{count_text, Diagnostic, Handle, Lane, Level, Lift};
use std::collections::BTreeMap;

pub(crate) static RULE: Rule = Rule {
    code: "W0208",
    name: "disconnected-graph",
    summary: "the lanes of a graph form more than one connected piece",
    group: Group::Lanes,
    metric: false,
    check,
};

struct UnionFind(Vec<usize>);

impl UnionFind {
    fn find(&mut self, mut x: usize) -> usize {
        while self.0[x] != x {
            self.0[x] = self.0[self.0[x]];
            x = self.0[x];
        }
        x
    }
    fn union(&mut self, a: usize, b: usize) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.0[a.max(b)] = a.min(b);
        }
    }
}

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    // Vertex arena index -> index among the current graph's waypoints.
    let mut local = vec![usize::MAX; b.vertices.len()];
    for (&graph, lanes) in &ctx.lanes_by_graph {
        let mut verts = Vec::new();
        for &l in lanes {
            for v in [b.lanes[l].start, b.lanes[l].end] {
                if local[v.index()] == usize::MAX {
                    local[v.index()] = verts.len();
                    verts.push(v);
                }
            }
        }
        let mut uf = UnionFind((0..verts.len()).collect());
        for &l in lanes {
            let lane = &b.lanes[l];
            uf.union(local[lane.start.index()], local[lane.end.index()]);
        }
        // Lift waypoints: those of one lift are connected when they are on 2+ levels.
        let mut by_lift: BTreeMap<Handle<Lift>, Vec<(Handle<Level>, usize)>> = BTreeMap::new();
        for (i, &v) in verts.iter().enumerate() {
            if let Some(lift) = ctx.lift_of(v) {
                by_lift
                    .entry(lift)
                    .or_default()
                    .push((b.vertices[v].level, i));
            }
        }
        for members in by_lift.values() {
            if members.iter().any(|m| m.0 != members[0].0) {
                for m in &members[1..] {
                    uf.union(members[0].1, m.1);
                }
            }
        }
        // Pieces in order of their first lane: (root, size, first lane).
        let mut size = vec![0usize; verts.len()];
        for i in 0..verts.len() {
            let r = uf.find(i);
            size[r] += 1;
        }
        let mut pieces: Vec<(usize, usize, Handle<Lane>)> = Vec::new();
        let mut listed = vec![false; verts.len()];
        for &l in lanes {
            let r = uf.find(local[b.lanes[l].start.index()]);
            if !std::mem::replace(&mut listed[r], true) {
                pieces.push((r, size[r], l));
            }
        }
        for &v in &verts {
            local[v.index()] = usize::MAX;
        }
        if pieces.len() < 2 {
            continue;
        }
        // The largest piece (the first of equals) is the main one.
        let main = pieces
            .iter()
            .enumerate()
            .max_by(|x, y| x.1 .1.cmp(&y.1 .1).then(y.0.cmp(&x.0)))
            .map_or(0, |(i, _)| i);
        let mut sizes: Vec<usize> = pieces.iter().map(|p| p.1).collect();
        sizes.sort_unstable_by(|x, y| y.cmp(x));
        let sizes = sizes_text(&sizes);
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        let mut small = pieces.iter().enumerate().filter(|(i, _)| *i != main);
        let Some((_, &(_, n, first))) = small.next() else {
            continue;
        };
        let message = if pieces.len() == 2 {
            format!(
                "graph {graph} falls apart into 2 pieces (of {sizes} waypoints); this lane \
                 belongs to a piece of {n} waypoint{} that robots cannot reach from the \
                 largest piece of {} waypoints",
                plural(n),
                pieces[main].1,
            )
        } else {
            format!(
                "graph {graph} falls apart into {} pieces (of {sizes} waypoints); robots \
                 cannot reach the largest piece of {} waypoints from this lane's piece of {n} \
                 waypoint{} nor from the {} other smaller pieces",
                count_text(pieces.len()),
                pieces[main].1,
                plural(n),
                count_text(pieces.len() - 2),
            )
        };
        let mut d = Diagnostic::warning(RULE.code, ctx.lane_span(first), message)
            .with_label(ctx.lane_span(pieces[main].2), "a lane of the largest piece");
        for (_, &(_, n, l)) in small.take(MAX_LABELS) {
            d = d.with_label(
                ctx.lane_span(l),
                format!("a lane of another piece of {n} waypoint{}", plural(n)),
            );
        }
        out.push(d.with_help(
            "add the missing lane, or merge vertices that should be one waypoint; use \
             another graph_idx if the pieces are meant for different fleets",
        ));
    }
}

/// Labels for at most this many other small pieces.
const MAX_LABELS: usize = 3;
/// Sizes listed one by one before the rest is summed up.
const MAX_SIZES: usize = 8;

/// "5, 3, 2" or, for many pieces (sizes sorted, largest first), "1000, 2, … and 29,990
/// more pieces of 2" (or "of 2 to 5").
fn sizes_text(sizes: &[usize]) -> String {
    let shown: Vec<String> = sizes
        .iter()
        .take(MAX_SIZES)
        .map(|s| s.to_string())
        .collect();
    let mut text = shown.join(", ");
    let rest = &sizes[shown.len()..];
    if let (Some(&hi), Some(&lo)) = (rest.first(), rest.last()) {
        let range = if hi == lo {
            hi.to_string()
        } else {
            format!("{lo} to {hi}")
        };
        text.push_str(&format!(
            " … and {} more piece{} of {range}",
            count_text(rest.len()),
            if rest.len() == 1 { "" } else { "s" }
        ));
    }
    text
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, lanes_map, TestMap};
    use crate::Vec2;

    fn count(b: &crate::Building) -> usize {
        codes_of(b).iter().filter(|c| **c == "W0208").count()
    }

    #[test]
    fn pieces() {
        assert_eq!(count(&lanes_map(&[(0, 1, 0, true), (1, 2, 0, false)])), 0);
        assert_eq!(count(&lanes_map(&[(0, 1, 0, true), (2, 3, 0, true)])), 1);
        assert_eq!(
            count(&lanes_map(&[
                (0, 1, 0, true),
                (2, 3, 0, true),
                (4, 5, 0, true)
            ])),
            1
        );
        // Different graphs are separate fleets.
        assert_eq!(count(&lanes_map(&[(0, 1, 0, true), (2, 3, 1, true)])), 0);
    }

    #[test]
    fn reports_the_smaller_piece() {
        let b = lanes_map(&[(0, 1, 0, true), (2, 3, 0, true), (3, 4, 0, true)]);
        let d: Vec<_> = crate::validate(&b)
            .into_iter()
            .filter(|d| d.code == "W0208")
            .collect();
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].span, b.lanes.span(b.lanes.handle(0).unwrap()));
        assert!(
            d[0].message.contains("2 pieces (of 3, 2 waypoints)"),
            "{}",
            d[0].message
        );
    }

    #[test]
    fn many_pieces_are_one_warning_with_a_cut_list() {
        let lanes: Vec<(usize, usize, i64, bool)> =
            (0..3000).map(|i| (2 * i, 2 * i + 1, 0, true)).collect();
        let b = lanes_map(&lanes);
        let d: Vec<_> = crate::validate(&b)
            .into_iter()
            .filter(|d| d.code == "W0208")
            .collect();
        assert_eq!(d.len(), 1);
        assert!(
            d[0].message.contains(
                "falls apart into 3,000 pieces (of 2, 2, 2, 2, 2, 2, 2, 2 … and 2,992 more \
                 pieces of 2 waypoints)"
            ),
            "{}",
            d[0].message
        );
        assert!(d[0].message.len() < 400);
        assert_eq!(d[0].labels.len(), 4);
    }

    #[test]
    fn sizes_text_cuts_ranges() {
        assert_eq!(super::sizes_text(&[3, 2]), "3, 2");
        let mut v = vec![9, 8, 7, 6, 5, 4, 3, 3];
        v.extend([3, 2, 1]);
        assert_eq!(
            super::sizes_text(&v),
            "9, 8, 7, 6, 5, 4, 3, 3 … and 3 more pieces of 1 to 3"
        );
    }

    #[test]
    fn lifts_connect_levels() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let a = m.vertex("a", 0.0, 0.0);
        let la = m.vertex("lift_L1", 5.0, 0.0);
        m.lane(a, la, 0, true);
        let l2 = m.level("L2", 4.0);
        let lb = m.vertex("lift_L2", 5.0, 0.0);
        let c = m.vertex("c", 0.0, 0.0);
        m.lane(lb, c, 0, true);
        assert_eq!(count(&m.b), 1);
        m.lift("lift", Vec2::new(5.0, 0.0), 2.0, 2.0, &[l1, l2]);
        assert_eq!(count(&m.b), 0);
    }
}
