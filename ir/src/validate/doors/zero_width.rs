//! # E0304 zero-width-door
//!
//! **What:** a door's two vertices are the same vertex, or lie less than 1 mm apart.
//!
//! **Why it matters:** the door has no width: the generator builds leaves of negative
//! width (it subtracts a 1 cm clearance from the door's width), the door's orientation
//! is undefined, and robots cannot pass through it.
//!
//! **Fix:** draw the door between the two vertices at the edges of the door opening.
//!
//! **Example:**
//! ```yaml
//! doors:
//!   - [4, 4, {name: [1, d1], type: [1, sliding]}]   # E0304
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

/// Doors narrower than this, in metres, have no usable width.
pub(crate) const MIN_DOOR_WIDTH: f64 = 1e-3;

pub(crate) static RULE: Rule = Rule {
    code: "E0304",
    name: "zero-width-door",
    summary: "a door's end points coincide",
    group: Group::Doors,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, door) in ctx.b.doors.iter() {
        let w = ctx.b.vertices[door.start]
            .pos
            .minus(ctx.b.vertices[door.end].pos)
            .norm();
        if door.start == door.end || w < MIN_DOOR_WIDTH {
            let how = if door.start == door.end {
                format!("starts and ends at {}", ctx.vertex_label(door.start))
            } else {
                format!("is only {w:.2e} m wide")
            };
            let mut d = Diagnostic::error(
                RULE.code,
                ctx.b.doors.span(h),
                format!(
                    "door `{}` on level `{}` {how}",
                    door.name,
                    ctx.level_name(door.level)
                ),
            )
            .with_label(ctx.vertex_span(door.start), "start vertex");
            if door.end != door.start {
                d = d.with_label(ctx.vertex_span(door.end), "end vertex");
            }
            out.push(d.with_help(
                "draw the door across the whole opening, between two distinct vertices",
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::DoorKind;

    #[test]
    fn finds_zero_width_doors() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 0.0005, 0.0);
        let c = m.vertex("", 1.0, 0.0);
        m.door("same", DoorKind::Hinged, a, a);
        m.door("tiny", DoorKind::Hinged, a, b);
        m.door("ok", DoorKind::Hinged, a, c);
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "E0304").count(), 2);
    }
}
