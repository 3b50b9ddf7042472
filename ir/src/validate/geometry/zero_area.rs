//! # E0603 polygon-zero-area
//!
//! **What:** a floor or hole encloses (almost) no area: less than 1e-6 m², for example
//! because all its vertices lie on one line or several of them coincide.
//!
//! **Why it matters:** a floor without area generates no surface, so the region it was
//! meant to cover has no ground, and a hole without area removes nothing. Such
//! degenerate rings are also invalid for the polygon library the reference generator
//! uses to build floor meshes.
//!
//! **Fix:** delete the polygon, or move its vertices so that it encloses the intended
//! region.
//!
//! **Example:**
//! ```yaml
//! vertices: [[0, 0, 0, ""], [2, 0, 0, ""], [4, 0, 0, ""]]
//! floors:
//!   - {vertices: [0, 1, 2], parameters: {}}   # E0603: all on y = 0
//! ```

use super::shapes::{
    distinct_vertices, fan_extent, polygons, ring, self_intersection, signed_area, Simplicity,
};
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

/// Polygons enclosing less than this, in square metres, have no area.
pub(crate) const MIN_AREA: f64 = 1e-6;

pub(crate) static RULE: Rule = Rule {
    code: "E0603",
    name: "polygon-zero-area",
    summary: "a floor or hole encloses no area",
    group: Group::Geometry,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for p in polygons(ctx.b) {
        if distinct_vertices(p.poly) < 3 {
            continue; // E0601
        }
        let (pts, _) = ring(ctx.b, p.poly);
        let area = signed_area(&pts).abs();
        if area >= MIN_AREA {
            continue;
        }
        // A crossing ring whose lobes cancel out (a symmetric bow tie) is E0602's.
        let flat = pts.len() < 3 || fan_extent(&pts) < MIN_AREA;
        if !flat && matches!(self_intersection(&pts), Simplicity::Crossing(..)) {
            continue;
        }
        out.push(
            Diagnostic::error(
                RULE.code,
                p.span,
                format!(
                    "{} on level `{}` encloses no area (less than {MIN_AREA:e} m²): its vertices coincide or lie (almost) on one line",
                    p.kind,
                    ctx.level_name(p.poly.level),
                ),
            )
            .with_help(format!("delete the {} or move its vertices apart", p.kind)),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};

    #[test]
    fn finds_flat_polygons() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 2.0, 0.0);
        let c = m.vertex("", 4.0, 0.0);
        let d = m.vertex("", 0.0, 0.0); // on top of a
        let e = m.vertex("", 0.0, 3.0);
        m.floor(&[a, b, e]);
        assert!(!codes_of(&m.b).contains(&"E0603"));
        m.floor(&[a, b, c]);
        m.hole(&[a, b, d]);
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "E0603").count(), 2);
    }

    #[test]
    fn symmetric_bow_tie_is_not_zero_area() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 1.0, 1.0);
        let c = m.vertex("", 1.0, 0.0);
        let d = m.vertex("", 0.0, 1.0);
        m.floor(&[a, b, c, d]);
        let d = codes_of(&m.b);
        assert!(!d.contains(&"E0603"));
        assert!(d.contains(&"E0602"));
    }
}
