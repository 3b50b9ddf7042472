//! # E0602 polygon-self-intersecting
//!
//! **What:** two edges of a floor or hole cross or touch (other than neighbouring edges
//! at their shared corner), or an edge folds straight back over the previous one.
//!
//! **Why it matters:** the polygon is not simple, so its inside is not well defined. The
//! reference generator's polygon library (GEOS) raises a `TopologyException` while
//! building the floor mesh, so no world can be generated. It usually comes from vertices
//! listed in the wrong order, or from a vertex that was snapped to the wrong point.
//!
//! Polygons so large and convoluted that the check would need more than a million
//! segment tests are skipped (real floors have tens of corners).
//!
//! **Fix:** list the vertices in order around the outline, or split the shape into
//! several floors.
//!
//! **Example:**
//! ```yaml
//! vertices: [[0, 0, 0, ""], [4, 0, 0, ""], [4, 4, 0, ""], [0, 4, 0, ""]]
//! floors:
//!   - {vertices: [0, 2, 1, 3], parameters: {}}   # E0602: a bow tie
//! ```

use super::shapes::{
    distinct_vertices, fan_extent, level_index, polygons, ring, self_intersection, Simplicity,
};
use super::zero_area::MIN_AREA;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0602",
    name: "polygon-self-intersecting",
    summary: "a floor or hole has crossing edges",
    group: Group::Geometry,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    for p in polygons(b) {
        if distinct_vertices(p.poly) < 3 {
            continue; // E0601
        }
        let (pts, hs) = ring(b, p.poly);
        if pts.len() < 3 || fan_extent(&pts) < MIN_AREA {
            continue; // E0603: flat
        }
        let Simplicity::Crossing(i, j) = self_intersection(&pts) else {
            continue;
        };
        let n = pts.len();
        let edge = |k: usize| (hs[k], hs[(k + 1) % n]);
        let (e1, e2) = (edge(i), edge(j));
        let name = |e: (crate::Handle<crate::Vertex>, crate::Handle<crate::Vertex>)| {
            format!("{}-{}", level_index(b, e.0), level_index(b, e.1))
        };
        let how = if (i + 1) % n == j || (j + 1) % n == i {
            "folds back over"
        } else {
            "crosses"
        };
        out.push(
            Diagnostic::error(
                RULE.code,
                p.span,
                format!(
                    "{} on level `{}` intersects itself: edge {} {how} edge {}",
                    p.kind,
                    ctx.level_name(p.poly.level),
                    name(e1),
                    name(e2)
                ),
            )
            .with_label(
                ctx.vertex_span(e1.0),
                format!("edge {} starts here", name(e1)),
            )
            .with_label(
                ctx.vertex_span(e2.0),
                format!("edge {} starts here", name(e2)),
            )
            .with_help("list the vertices in order around the outline, or split the polygon"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};

    #[test]
    fn finds_bow_ties_and_touching_rings() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 4.0, 0.0);
        let c = m.vertex("", 4.0, 4.0);
        let d = m.vertex("", 0.0, 4.0);
        let e = m.vertex("", 2.0, 0.0);
        m.floor(&[a, b, c, d]);
        m.floor(&[a, e, b, c, d]); // colinear corner: still simple
        assert!(!codes_of(&m.b).contains(&"E0602"));
        m.floor(&[a, c, b, d]); // bow tie
        m.hole(&[a, b, c, a, d]); // touches itself at a
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "E0602").count(), 2);
    }

    #[test]
    fn flat_polygons_are_left_to_e0603() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 4.0, 0.0);
        let c = m.vertex("", 2.0, 0.0);
        m.floor(&[a, b, c]);
        let d = codes_of(&m.b);
        assert!(!d.contains(&"E0602"));
        assert!(d.contains(&"E0603"));
    }
}
