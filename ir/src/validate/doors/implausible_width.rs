//! # W0305 implausible-door-width
//!
//! **What:** a door is narrower than 0.5 m or wider than 6 m (measured between its two
//! vertices, in metres, after the map's scale is applied).
//!
//! **Why it matters:** real doors are between about 0.7 m (a single office door) and a
//! few metres (a double sliding entrance or a roller shutter). A width outside that range
//! usually means the door was drawn between the wrong vertices, or that the map's scale
//! is wrong (a missing or mistyped measurement on a `reference_image` map). Robots also
//! need a door clearly wider than themselves.
//!
//! **Fix:** check the door's vertices and the map scale; if the door really is that
//! size, ignore the warning.
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, ""]
//!   - [0.3, 0, 0, ""]
//! doors:
//!   - [0, 1, {name: [1, d1], type: [1, hinged]}]   # W0305: 0.3 m
//! ```

use super::zero_width::MIN_DOOR_WIDTH;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

const MIN_WIDTH: f64 = 0.5;
const MAX_WIDTH: f64 = 6.0;

pub(crate) static RULE: Rule = Rule {
    code: "W0305",
    name: "implausible-door-width",
    summary: "a door is narrower than 0.5 m or wider than 6 m",
    group: Group::Doors,
    metric: true,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, door) in ctx.b.doors.iter() {
        let w = ctx.b.vertices[door.start]
            .pos
            .minus(ctx.b.vertices[door.end].pos)
            .norm();
        if w < MIN_DOOR_WIDTH {
            continue; // E0304
        }
        let bound = if w < MIN_WIDTH {
            format!("narrower than {MIN_WIDTH} m")
        } else if w > MAX_WIDTH {
            format!("wider than {MAX_WIDTH} m")
        } else {
            continue;
        };
        out.push(
            Diagnostic::warning(
                RULE.code,
                ctx.b.doors.span(h),
                format!(
                    "door `{}` on level `{}` is {w:.2} m wide, {bound}",
                    door.name,
                    ctx.level_name(door.level)
                ),
            )
            .with_help("check the door's vertices and the map scale (measurements)"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::DoorKind;

    #[test]
    fn finds_narrow_and_wide_doors() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 0.3, 0.0);
        let c = m.vertex("", 1.0, 0.0);
        let d = m.vertex("", 0.0, 7.0);
        m.door("narrow", DoorKind::Hinged, a, b);
        m.door("ok", DoorKind::Hinged, a, c);
        m.door("wide", DoorKind::Sliding, a, d);
        m.door("zero", DoorKind::Sliding, a, a);
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "W0305").count(), 2);
    }
}
