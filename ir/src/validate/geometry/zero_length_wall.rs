//! # E0605 zero-length-wall
//!
//! **What:** a wall's two vertices are the same vertex, or lie less than 1 mm apart.
//!
//! **Why it matters:** a wall without length has no direction: the wall mesh gets
//! degenerate faces without a defined normal, and the wall blocks nothing. It is always a
//! drawing mistake (a double click in the editor).
//!
//! **Fix:** delete the wall, or draw it between two distinct vertices.
//!
//! **Example:**
//! ```yaml
//! walls:
//!   - [2, 2, {texture_name: [1, default]}]   # E0605
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

const MIN_LENGTH: f64 = 1e-3;

pub(crate) static RULE: Rule = Rule {
    code: "E0605",
    name: "zero-length-wall",
    summary: "a wall's end points coincide",
    group: Group::Geometry,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    for (h, wall) in b.walls.iter() {
        let len = b.vertices[wall.start]
            .pos
            .minus(b.vertices[wall.end].pos)
            .norm();
        if wall.start != wall.end && len >= MIN_LENGTH {
            continue;
        }
        let how = if wall.start == wall.end {
            format!("starts and ends at {}", ctx.vertex_label(wall.start))
        } else {
            format!(
                "is only {len:.2e} m long, from {} to {}",
                ctx.vertex_label(wall.start),
                ctx.vertex_label(wall.end)
            )
        };
        out.push(
            Diagnostic::error(
                RULE.code,
                b.walls.span(h),
                format!("wall on level `{}` {how}", ctx.level_name(wall.level)),
            )
            .with_label(ctx.vertex_span(wall.start), "the vertex")
            .with_help("delete the wall or draw it between two distinct vertices"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};

    #[test]
    fn finds_zero_length_walls() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 0.0, 0.0001);
        let c = m.vertex("", 3.0, 0.0);
        m.wall(a, c);
        m.wall(a, a);
        m.wall(a, b);
        assert_eq!(codes_of(&m.b).iter().filter(|c| **c == "E0605").count(), 2);
    }
}
