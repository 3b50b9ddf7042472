//! # E0601 polygon-too-few-vertices
//!
//! **What:** a floor or hole lists fewer than three different vertices.
//!
//! **Why it matters:** a polygon needs at least three corners to enclose any area. The
//! reference generator skips such a floor with a message, and crashes on such a hole
//! (a `ValueError` from its polygon library).
//!
//! **Fix:** delete the polygon, or redraw it through at least three distinct vertices.
//!
//! **Example:**
//! ```yaml
//! floors:
//!   - {vertices: [0, 1, 0], parameters: {}}   # E0601: only vertices 0 and 1
//! ```

use super::shapes::{distinct_vertices, polygons};
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0601",
    name: "polygon-too-few-vertices",
    summary: "a floor or hole has fewer than three distinct vertices",
    group: Group::Geometry,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for p in polygons(ctx.b) {
        let n = distinct_vertices(p.poly);
        if n < 3 {
            out.push(
                Diagnostic::error(
                    RULE.code,
                    p.span,
                    format!(
                        "{} on level `{}` has {n} distinct {}; a polygon needs at least 3",
                        p.kind,
                        ctx.level_name(p.poly.level),
                        if n == 1 { "vertex" } else { "vertices" }
                    ),
                )
                .with_help(format!(
                    "delete the {} or draw it through at least three vertices",
                    p.kind
                )),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};

    #[test]
    fn finds_small_polygons() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 1.0, 0.0);
        let c = m.vertex("", 1.0, 1.0);
        m.floor(&[a, b, c]);
        m.floor(&[a, b, a]);
        m.hole(&[a, b]);
        m.hole(&[]);
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "E0601").count(), 3);
    }
}
