//! # W0206 lane-crosses-several-doors
//!
//! **What:** a lane intersects more than one door of its level.
//!
//! **Why it matters:** a nav-graph lane carries at most one `door_name`, and the fleet
//! adapter opens only that door before the lane and closes it after. With two doors on one
//! lane, the other door is never opened and the robot drives into it. mapc names the door
//! met first in the direction of travel (so the two directions of a two-way lane may name
//! different doors); the reference generator names the last one in file order.
//!
//! **Fix:** put a waypoint between the doors and split the lane there, so that each lane
//! passes through one door.
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, a]
//!   - [6, 0, 0, b]
//!   - [2, -0.5, 0, ""]
//!   - [2, 0.5, 0, ""]
//!   - [4, -0.5, 0, ""]
//!   - [4, 0.5, 0, ""]
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]   # W0206: d1 and d2
//! doors:
//!   - [2, 3, {name: [1, d1], type: [1, sliding]}]
//!   - [4, 5, {name: [1, d2], type: [1, sliding]}]
//! ```

use super::geom::{segment_intersection, Bbox, TOUCH};
use crate::lints::Group;
use crate::validate::grid::BoxGrid;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Door, Handle, Vertex};

pub(crate) static RULE: Rule = Rule {
    code: "W0206",
    name: "lane-crosses-several-doors",
    summary: "a lane crosses more than one door",
    group: Group::Lanes,
    metric: true,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    let pos = |v: Handle<Vertex>| b.vertices[v].pos;
    for (_, level) in b.levels.iter() {
        if level.doors.len() < 2 {
            continue;
        }
        let doors: Vec<_> = level
            .doors
            .iter()
            .map(|&d| (d, pos(b.doors[d].start), pos(b.doors[d].end)))
            .map(|(d, p, q)| (d, p, q, Bbox::of(p, q)))
            .collect();
        let mut grid = BoxGrid::new(&doors.iter().map(|d| (d.3.lo, d.3.hi)).collect::<Vec<_>>());
        for &lh in &level.lanes {
            let lane = &b.lanes[lh];
            let (a, z) = (pos(lane.start), pos(lane.end));
            if z.minus(a).norm() < TOUCH {
                continue; // E0201, W0202
            }
            let bbox = Bbox::of(a, z);
            // (parameter along the lane, door), the test mapc's nav backend uses.
            let mut hits: Vec<(f64, Handle<Door>)> = grid
                .candidates(bbox.lo, bbox.hi)
                .into_iter()
                .map(|i| doors[i as usize])
                .filter(|d| bbox.overlaps(&d.3))
                .filter_map(|(d, p, q, _)| segment_intersection(a, z, p, q).map(|t| (t, d)))
                .collect();
            if hits.len() < 2 {
                continue;
            }
            hits.sort_by(|x, y| x.0.total_cmp(&y.0));
            let names: Vec<String> = hits
                .iter()
                .map(|&(_, d)| format!("`{}`", b.doors[d].name))
                .collect();
            let first = &b.doors[hits[0].1].name;
            let last = &b.doors[hits[hits.len() - 1].1].name;
            let named = if lane.bidirectional && first != last {
                format!(
                    "the nav graph names only `{first}` going forward and only `{last}` going back"
                )
            } else {
                format!("the nav graph names only `{first}`")
            };
            let mut d = Diagnostic::warning(
                RULE.code,
                ctx.lane_span(lh),
                format!(
                    "lane of graph {} from {} to {} crosses {} doors ({}); {named}",
                    lane.graph,
                    ctx.vertex_label(lane.start),
                    ctx.vertex_label(lane.end),
                    hits.len(),
                    names.join(", "),
                ),
            );
            for &(_, dh) in &hits {
                d = d.with_label(b.doors.span(dh), format!("door `{}`", b.doors[dh].name));
            }
            out.push(d.with_help(
                "add a waypoint between the doors and split the lane so each lane passes one door",
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::TestMap;
    use crate::DoorKind;

    fn run(xs: &[f64], bidirectional: bool) -> Vec<String> {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 10.0, 0.0);
        m.lane(a, b, 0, bidirectional);
        for (i, &x) in xs.iter().enumerate() {
            let p = m.vertex("", x, -0.5);
            let q = m.vertex("", x, 0.5);
            m.door(&format!("d{i}"), DoorKind::Hinged, p, q);
        }
        crate::validate(&m.b)
            .into_iter()
            .filter(|d| d.code == "W0206")
            .map(|d| d.message)
            .collect()
    }

    #[test]
    fn one_door_is_fine() {
        assert!(run(&[5.0], true).is_empty());
        assert!(run(&[5.0, 12.0], true).is_empty());
    }

    #[test]
    fn two_doors() {
        // Doors listed in the file in the opposite order of travel.
        let m = run(&[7.0, 3.0], false);
        assert_eq!(m.len(), 1);
        assert!(m[0].contains("2 doors (`d1`, `d0`)"), "{m:?}");
        assert!(m[0].contains("names only `d1`"), "{m:?}");
        let m = run(&[7.0, 3.0], true);
        assert!(
            m[0].contains("only `d1` going forward and only `d0` going back"),
            "{m:?}"
        );
    }
}
