//! # W0204 lane-crosses-wall
//!
//! **What:** a lane crosses a wall of its level at a place where there is no door. A
//! crossing counts when the wall passes strictly from one side of the lane to the other,
//! away from the lane's endpoints (a waypoint drawn on a wall only touches it), or when
//! walls meeting at a corner on the lane reach to both of its sides. A crossing is excused
//! when the lane also crosses a door within 0.1 m of it (a wall drawn through a doorway,
//! under its door).
//!
//! **Why it matters:** robots follow lanes; a lane through a wall is a route the planner
//! believes is open but that is physically blocked, so robots get stuck or their paths are
//! rejected by local planners. It often means a door is missing or drawn a little off the
//! wall gap, so the lane gets no `door_name` and the door is never opened.
//!
//! **Fix:** route the lane through a doorway, add the missing door across the lane, or
//! move the door so that it lies on the wall gap the lane passes through.
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, a]
//!   - [4, 0, 0, b]
//!   - [2, -2, 0, ""]
//!   - [2, 2, 0, ""]
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]   # W0204
//! walls:
//!   - [2, 3, {}]
//! ```

use super::geom::{meet, point_segment_distance, segment_intersection, Bbox, Meet, TOUCH};
use crate::lints::Group;
use crate::validate::grid::BoxGrid;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Handle, Vec2, Vertex, Wall};

pub(crate) static RULE: Rule = Rule {
    code: "W0204",
    name: "lane-crosses-wall",
    summary: "a lane crosses a wall where there is no door",
    group: Group::Lanes,
    metric: true,
    check,
};

/// A wall crossing closer than this to a door the lane crosses is the doorway itself.
const DOOR_TOLERANCE: f64 = 0.1;

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    let pos = |v: Handle<Vertex>| b.vertices[v].pos;
    for (_, level) in b.levels.iter() {
        if level.walls.is_empty() {
            continue;
        }
        let walls: Vec<_> = level
            .walls
            .iter()
            .map(|&w| (w, pos(b.walls[w].start), pos(b.walls[w].end)))
            .filter(|(_, p, q)| q.minus(*p).norm() >= TOUCH)
            .map(|(w, p, q)| (w, p, q, Bbox::of(p, q)))
            .collect();
        let doors: Vec<_> = level
            .doors
            .iter()
            .map(|&d| (pos(b.doors[d].start), pos(b.doors[d].end)))
            .filter(|(p, q)| q.minus(*p).norm() >= TOUCH)
            .collect();
        // Spatial indexes: a lane is tested against the walls and doors near it only.
        let mut wall_grid =
            BoxGrid::new(&walls.iter().map(|w| (w.3.lo, w.3.hi)).collect::<Vec<_>>());
        let mut door_grid = BoxGrid::new(
            &doors
                .iter()
                .map(|&(p, q)| {
                    let bb = Bbox::of(p, q);
                    (bb.lo, bb.hi)
                })
                .collect::<Vec<_>>(),
        );
        for &lh in &level.lanes {
            let lane = &b.lanes[lh];
            let (a, z) = (pos(lane.start), pos(lane.end));
            let len = z.minus(a).norm();
            if len < TOUCH {
                continue; // E0201, W0202
            }
            let bbox = Bbox::of(a, z);
            // The doors this lane passes through, computed when first needed.
            let mut crossed_doors: Option<Vec<(Vec2, Vec2)>> = None;
            let mut in_doorway = |x: Vec2| {
                crossed_doors
                    .get_or_insert_with(|| {
                        door_grid
                            .candidates(bbox.lo, bbox.hi)
                            .into_iter()
                            .map(|i| doors[i as usize])
                            .filter(|&(p, q)| segment_intersection(a, z, p, q).is_some())
                            .collect()
                    })
                    .iter()
                    .any(|&(p, q)| point_segment_distance(x, p, q) <= DOOR_TOLERANCE)
            };
            // (distance along the lane, wall) of every crossing outside a doorway.
            let mut hits: Vec<(f64, Handle<Wall>)> = Vec::new();
            // Wall ends lying on the lane: (point, wall, side of the wall's other end).
            let mut ends: Vec<(Vec2, Handle<Wall>, i8)> = Vec::new();
            for i in wall_grid.candidates(bbox.lo, bbox.hi) {
                let (w, p, q, wb) = walls[i as usize];
                if !bbox.overlaps(&wb) {
                    continue;
                }
                match meet(a, z, p, q) {
                    Meet::Apart => {}
                    Meet::Cross(x) => {
                        if !in_doorway(x) {
                            hits.push((x.minus(a).norm(), w));
                        }
                    }
                    Meet::EndOnLane { end_is_start, side } => {
                        ends.push((if end_is_start { p } else { q }, w, side));
                    }
                }
            }
            // Walls meeting at one point of the lane cross it when they reach to both of
            // its sides. Each meeting point is judged once, at its first wall end.
            for (i, &(x, w, s)) in ends.iter().enumerate() {
                let same = |&&(y, _, _): &&(Vec2, Handle<Wall>, i8)| y.minus(x).norm() <= TOUCH;
                if ends[..i].iter().any(|e| same(&e)) {
                    continue;
                }
                let both_sides = ends[i + 1..].iter().filter(same).any(|&(_, _, t)| t != s);
                if both_sides && !in_doorway(x) {
                    hits.push((x.minus(a).norm(), w));
                }
            }
            if hits.is_empty() {
                continue;
            }
            hits.sort_by(|x, y| x.0.total_cmp(&y.0));
            let (d, w) = hits[0];
            let more = match hits.len() {
                1 => String::new(),
                2 => " (and 1 more wall further on)".to_string(),
                n => format!(" (and {} more walls further on)", n - 1),
            };
            out.push(
                Diagnostic::warning(
                    RULE.code,
                    ctx.lane_span(lh),
                    format!(
                        "lane of graph {} from {} to {} crosses a wall {:.2} m from its start, \
                         where there is no door{more}",
                        lane.graph,
                        ctx.vertex_label(lane.start),
                        ctx.vertex_label(lane.end),
                        d
                    ),
                )
                .with_label(b.walls.span(w), "the wall")
                .with_help(
                    "route the lane through a doorway, or add a door across the lane on this wall",
                ),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::DoorKind;

    fn count(b: &crate::Building) -> usize {
        codes_of(b).iter().filter(|c| **c == "W0204").count()
    }

    /// A lane from (0,0) to (4,0) and a vertical wall x = 2 from y0 to y1.
    fn setup(y0: f64, y1: f64) -> TestMap {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 4.0, 0.0);
        m.lane(a, b, 0, true);
        let p = m.vertex("", 2.0, y0);
        let q = m.vertex("", 2.0, y1);
        m.wall(p, q);
        m
    }

    #[test]
    fn crossing_a_wall() {
        assert_eq!(count(&setup(-2.0, 2.0).b), 1);
        // Passing beside the end of a wall, or the wall ending exactly on the lane.
        assert_eq!(count(&setup(0.5, 2.0).b), 0);
        assert_eq!(count(&setup(0.0, 2.0).b), 0);
    }

    #[test]
    fn walls_meeting_on_the_lane() {
        // Two walls meeting at (2, 0), one on each side: a crossing.
        let mut m = setup(0.0, 2.0);
        let c = m.b.levels[m.level].vertices[2];
        let d = m.vertex("", 2.0, -2.0);
        m.wall(c, d);
        assert_eq!(count(&m.b), 1);
        // Both on the same side: a corner touching the lane.
        let mut m = setup(0.0, 2.0);
        let c = m.b.levels[m.level].vertices[2];
        let d = m.vertex("", 3.0, 2.0);
        m.wall(c, d);
        assert_eq!(count(&m.b), 0);
    }

    #[test]
    fn lane_ending_on_a_wall() {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 2.0, 0.0);
        m.lane(a, b, 0, true);
        let p = m.vertex("", 2.0, -2.0);
        let q = m.vertex("", 2.0, 2.0);
        m.wall(p, q);
        assert_eq!(count(&m.b), 0);
    }

    #[test]
    fn door_drawn_over_the_wall() {
        let mut m = setup(-2.0, 2.0);
        let p = m.vertex("", 2.0, -0.5);
        let q = m.vertex("", 2.0, 0.5);
        m.door("d", DoorKind::Hinged, p, q);
        assert_eq!(count(&m.b), 0);
        // A door elsewhere on the level does not excuse the crossing.
        let mut m = setup(-2.0, 2.0);
        let p = m.vertex("", 3.0, -0.5);
        let q = m.vertex("", 3.0, -1.5);
        m.door("d", DoorKind::Hinged, p, q);
        assert_eq!(count(&m.b), 1);
    }

    #[test]
    fn several_walls_one_report() {
        let mut m = setup(-2.0, 2.0);
        let p = m.vertex("", 3.0, -2.0);
        let q = m.vertex("", 3.0, 2.0);
        m.wall(p, q);
        let d = crate::validate(&m.b);
        let w: Vec<_> = d.iter().filter(|d| d.code == "W0204").collect();
        assert_eq!(w.len(), 1);
        assert!(w[0].message.contains("2.00 m"), "{}", w[0].message);
        assert!(w[0].message.contains("1 more wall"), "{}", w[0].message);
    }
}
