//! # W0205 lane-grazes-door
//!
//! **What:** a lane meets a door segment but does not pass through the doorway: it crosses
//! the door at a shallow angle (|sin| of the angle between lane and door below 0.2, about
//! 11.5°), runs along the door, only touches the door line with one of its own endpoints (a
//! waypoint drawn on the door), or passes exactly through one end of the door (its jamb).
//!
//! **Why it matters:** the navigation graph gives a lane the `door_name` of the door it
//! intersects, and the fleet adapter opens that door before the lane and closes it after.
//! A lane that only grazes a door gets the door (or, running along it, does not) although
//! robots do not really pass through it: a waypoint on the door line leaves the robot
//! standing in the doorway when the door closes, a shallow crossing drives the robot into
//! the door leaf or the jamb, and a lane along a door gets no door events at all.
//!
//! **Fix:** make the lane cross the door near its middle and roughly at right angles, with
//! waypoints on both sides of the door, clear of the swing of its leaves.
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, a]
//!   - [2, 0, 0, b]        # on the door line
//!   - [2, -0.5, 0, ""]
//!   - [2, 0.5, 0, ""]
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]   # W0205: ends on the door
//! doors:
//!   - [2, 3, {name: [1, d1], type: [1, sliding]}]
//! ```

use super::geom::{
    abs_sin, colinear_overlap, point_segment_distance, segment_intersection, side, Bbox, TOUCH,
};
use crate::lints::Group;
use crate::validate::grid::BoxGrid;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Handle, Vertex};

pub(crate) static RULE: Rule = Rule {
    code: "W0205",
    name: "lane-grazes-door",
    summary: "a lane meets a door but does not pass through the doorway",
    group: Group::Lanes,
    metric: true,
    check,
};

/// Crossings with `|sin(angle)|` below this are too shallow to pass through the door.
pub(super) const MIN_SIN: f64 = 0.2;

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    let pos = |v: Handle<Vertex>| b.vertices[v].pos;
    for (_, level) in b.levels.iter() {
        let doors: Vec<_> = level
            .doors
            .iter()
            .map(|&d| (d, pos(b.doors[d].start), pos(b.doors[d].end)))
            .filter(|(_, p, q)| q.minus(*p).norm() >= TOUCH)
            .map(|(d, p, q)| (d, p, q, Bbox::of(p, q)))
            .collect();
        if doors.is_empty() {
            continue;
        }
        let mut grid = BoxGrid::new(&doors.iter().map(|d| (d.3.lo, d.3.hi)).collect::<Vec<_>>());
        for &lh in &level.lanes {
            let lane = &b.lanes[lh];
            let (a, z) = (pos(lane.start), pos(lane.end));
            if z.minus(a).norm() < TOUCH {
                continue; // E0201, W0202
            }
            let bbox = Bbox::of(a, z);
            for i in grid.candidates(bbox.lo, bbox.hi) {
                let (dh, p, q, db) = doors[i as usize];
                if !bbox.overlaps(&db) {
                    continue;
                }
                let how = if segment_intersection(a, z, p, q).is_some() {
                    let sin = abs_sin(a, z, p, q);
                    if sin < MIN_SIN {
                        format!(
                            "crosses door `{}` at a shallow angle of {:.1}°",
                            b.doors[dh].name,
                            sin.asin().to_degrees()
                        )
                    } else if side(p, q, a).abs() <= TOUCH || side(p, q, z).abs() <= TOUCH {
                        format!(
                            "ends on the line of door `{}` instead of passing through it",
                            b.doors[dh].name
                        )
                    } else if point_segment_distance(p, a, z) <= TOUCH
                        || point_segment_distance(q, a, z) <= TOUCH
                    {
                        format!(
                            "passes through an end (the jamb) of door `{}`, not through the \
                             doorway",
                            b.doors[dh].name
                        )
                    } else {
                        continue; // A clean crossing.
                    }
                } else if colinear_overlap(a, z, p, q) {
                    format!(
                        "runs along door `{}`, so it gets no `door_name`",
                        b.doors[dh].name
                    )
                } else {
                    continue;
                };
                out.push(
                    Diagnostic::warning(
                        RULE.code,
                        ctx.lane_span(lh),
                        format!(
                            "lane of graph {} from {} to {} {how}",
                            lane.graph,
                            ctx.vertex_label(lane.start),
                            ctx.vertex_label(lane.end),
                        ),
                    )
                    .with_label(b.doors.span(dh), "the door")
                    .with_help(
                        "make the lane cross the door near its middle, roughly at right angles, \
                         with a waypoint on each side",
                    ),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::TestMap;
    use crate::DoorKind;

    /// Messages of W0205 for a lane (ax, ay)→(bx, by) and a door from (2, -0.5) to (2, 0.5).
    fn run(ax: f64, ay: f64, bx: f64, by: f64) -> Vec<String> {
        let mut m = TestMap::new();
        let a = m.vertex("a", ax, ay);
        let b = m.vertex("b", bx, by);
        m.lane(a, b, 0, true);
        let p = m.vertex("", 2.0, -0.5);
        let q = m.vertex("", 2.0, 0.5);
        m.door("d", DoorKind::Hinged, p, q);
        crate::validate(&m.b)
            .into_iter()
            .filter(|d| d.code == "W0205")
            .map(|d| d.message)
            .collect()
    }

    #[test]
    fn clean_crossing_is_fine() {
        assert!(run(0.0, 0.0, 4.0, 0.0).is_empty());
        assert!(run(0.0, -1.0, 4.0, 1.0).is_empty()); // 45°
        assert!(run(0.0, 0.0, 1.9, 0.0).is_empty()); // stops short: no contact
    }

    #[test]
    fn shallow_crossing() {
        let m = run(1.95, -0.4, 2.05, 0.4);
        assert_eq!(m.len(), 1);
        assert!(m[0].contains("shallow angle of 7.1°"), "{m:?}");
        // Exactly along the door.
        let m = run(2.0, -1.0, 2.0, 0.0);
        assert_eq!(m.len(), 1);
        assert!(m[0].contains("runs along"), "{m:?}");
    }

    #[test]
    fn ends_on_the_door() {
        let m = run(0.0, 0.0, 2.0, 0.0);
        assert_eq!(m.len(), 1);
        assert!(m[0].contains("ends on the line"), "{m:?}");
    }

    #[test]
    fn through_the_jamb() {
        let m = run(0.0, 0.5, 4.0, 0.5);
        assert_eq!(m.len(), 1);
        assert!(m[0].contains("jamb"), "{m:?}");
    }
}
