//! # E0307 door-motion-params
//!
//! **What:** a door's motion parameter is out of range for its type:
//! - hinged and double hinged doors: `motion_direction` is not `1` or `-1`, or
//!   `motion_degrees` is not in (0, 180];
//! - double hinged and double sliding doors: `right_left_ratio` is not positive.
//!
//! A parameter of the wrong kind (a string where a number is expected) is reported too.
//! Parameters a door type does not use (`motion_degrees` on a sliding door) are not
//! checked.
//!
//! **Why it matters:** the generator builds the door's joints from these values.
//! `motion_direction` picks the swing side by its sign only, so `0` or `2` are silently
//! read as one side; a swing of 0° or less never opens and more than 180° swings into
//! the wall; a ratio of 0 or less gives a leaf of zero or negative width (or a division
//! by zero at -1). A string value crashes the reference generator.
//!
//! **Fix:** use `motion_direction: [2, 1]` or `[2, -1]`, `motion_degrees` between 1 and
//! 180 (usually 90), and a positive `right_left_ratio` (1.0 for equal leaves).
//!
//! **Example:**
//! ```yaml
//! doors:
//!   - [4, 5, {name: [1, d1], type: [1, hinged], motion_direction: [2, 0], motion_degrees: [3, 90]}]   # E0307
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Door, DoorKind, Span};

pub(crate) static RULE: Rule = Rule {
    code: "E0307",
    name: "door-motion-params",
    summary: "a door's motion_direction, motion_degrees or right_left_ratio is out of range",
    group: Group::Doors,
    metric: false,
    check,
};

/// The numeric value of parameter `name` (from the params, else the typed field) and the
/// span to point at; `Err` holds the type of a non-numeric value.
fn value(door: &Door, name: &str, field: f64, door_span: Span) -> (Result<f64, String>, Span) {
    match door.params.param(name) {
        Some(p) => match p.value.as_f64() {
            Some(v) => (Ok(v), p.span),
            None => (Err(p.value.type_name().to_string()), p.span),
        },
        None => (Ok(field), door_span),
    }
}

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, door) in ctx.b.doors.iter() {
        let span = ctx.b.doors.span(h);
        let hinged = matches!(door.kind, DoorKind::Hinged | DoorKind::DoubleHinged);
        let double = matches!(door.kind, DoorKind::DoubleHinged | DoorKind::DoubleSliding);
        let mut problems: Vec<(Span, String)> = Vec::new();
        let mut judge = |name: &str, field: f64, ok: fn(f64) -> bool, want: &str| {
            let (v, at) = value(door, name, field, span);
            match v {
                Ok(v) if ok(v) => {}
                Ok(v) => problems.push((at, format!("`{name}` is {v}, expected {want}"))),
                Err(t) => problems.push((at, format!("`{name}` is a {t}, expected {want}"))),
            }
        };
        if hinged {
            judge(
                "motion_direction",
                door.motion_direction as f64,
                |v| v == 1.0 || v == -1.0,
                "1 or -1",
            );
            judge(
                "motion_degrees",
                door.motion_degrees,
                |v| v > 0.0 && v <= 180.0,
                "a swing in (0, 180] degrees",
            );
        }
        if double {
            judge(
                "right_left_ratio",
                door.right_left_ratio,
                |v| v > 0.0,
                "a positive width ratio",
            );
        }
        for (at, what) in problems {
            out.push(
                Diagnostic::error(
                    RULE.code,
                    at,
                    format!(
                        "{} door `{}` on level `{}`: {what}",
                        door.kind.as_str(),
                        door.name,
                        ctx.level_name(door.level)
                    ),
                )
                .with_help(
                    "use motion_direction [2, 1] or [2, -1], motion_degrees in (0, 180] \
                     and a positive right_left_ratio",
                ),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, param, params, TestMap};
    use crate::{DoorKind, ParamValue};

    fn with(kind: DoorKind, p: Vec<crate::Param>) -> usize {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 1.0, 0.0);
        let d = m.door("d", kind, a, b);
        // Mirror what the frontend does with params.
        let ps = params(p);
        let door = &mut m.b.doors[d];
        door.motion_direction = ps.int("motion_direction").unwrap_or(1);
        door.motion_degrees = ps.f64("motion_degrees").unwrap_or(90.0);
        door.right_left_ratio = ps.f64("right_left_ratio").unwrap_or(1.0);
        door.params = ps;
        codes_of(&m.b).iter().filter(|c| **c == "E0307").count()
    }

    #[test]
    fn hinged_params() {
        use ParamValue::*;
        assert_eq!(with(DoorKind::Hinged, vec![]), 0);
        assert_eq!(
            with(DoorKind::Hinged, vec![param("motion_direction", Int(-1))]),
            0
        );
        assert_eq!(
            with(
                DoorKind::Hinged,
                vec![param("motion_direction", Double(-1.0))]
            ),
            0
        );
        assert_eq!(
            with(DoorKind::Hinged, vec![param("motion_direction", Int(0))]),
            1
        );
        assert_eq!(
            with(
                DoorKind::Hinged,
                vec![param("motion_direction", Double(0.5))]
            ),
            1
        );
        assert_eq!(
            with(
                DoorKind::Hinged,
                vec![param("motion_direction", String("1".into()))]
            ),
            1
        );
        assert_eq!(
            with(
                DoorKind::Hinged,
                vec![param("motion_degrees", Double(180.0))]
            ),
            0
        );
        assert_eq!(
            with(DoorKind::Hinged, vec![param("motion_degrees", Double(0.0))]),
            1
        );
        assert_eq!(
            with(
                DoorKind::Hinged,
                vec![param("motion_degrees", Double(270.0))]
            ),
            1
        );
        // Unused by single hinged doors.
        assert_eq!(
            with(
                DoorKind::Hinged,
                vec![param("right_left_ratio", Double(0.0))]
            ),
            0
        );
    }

    #[test]
    fn double_and_sliding_params() {
        use ParamValue::*;
        assert_eq!(
            with(
                DoorKind::DoubleSliding,
                vec![param("right_left_ratio", Double(0.0))]
            ),
            1
        );
        assert_eq!(
            with(
                DoorKind::DoubleHinged,
                vec![param("right_left_ratio", Double(-2.0))]
            ),
            1
        );
        assert_eq!(
            with(
                DoorKind::DoubleSliding,
                vec![param("right_left_ratio", Double(0.5))]
            ),
            0
        );
        // Sliding doors ignore the swing parameters.
        assert_eq!(
            with(
                DoorKind::Sliding,
                vec![
                    param("motion_direction", Int(0)),
                    param("motion_degrees", Double(0.0))
                ]
            ),
            0
        );
    }
}
