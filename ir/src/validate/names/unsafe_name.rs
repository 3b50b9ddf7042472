//! # W0508 unsafe-name
//!
//! **What:** a level, lift, door or model name that is empty (levels and lifts; empty door
//! and model names are E0301 and E0609), contains `/` or `\` (model names may contain `/`,
//! as in the usual `OpenRobotics/Chair`), is `.` or has `..` as a path component, or starts
//! or ends with whitespace. (Control and bidi characters are error E0509.)
//!
//! **Why it matters:** these names become file, directory and model names in the generated
//! output: one directory and mesh files per level, one model per lift and door and their
//! controller topics, model instance names in the world. A `/` creates unexpected
//! sub-directories or model scopes, `..` can point outside the output directory (mapc
//! refuses to write there), and leading or trailing spaces and control characters make
//! names that look identical but differ, and that shells and ROS tools mangle.
//!
//! **Fix:** use letters, digits, `_` and `-` (for example `L1`, `lift_1`, `main_door`).
//!
//! **Example:**
//! ```yaml
//! levels:
//!   "L1/east":        # W0508
//!     elevation: 0
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Span};

pub(crate) static RULE: Rule = Rule {
    code: "W0508",
    name: "unsafe-name",
    summary: "a level, lift, door or model name unsafe as a file or model name",
    group: Group::FileNames,
    metric: false,
    check,
};

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Level,
    Lift,
    Door,
    Model,
}

/// Why `name` is unsafe, if it is.
fn problem(name: &str, kind: Kind) -> Option<&'static str> {
    let is_model = kind == Kind::Model;
    if name.is_empty() {
        // Empty door and model names are errors of their own (E0301, E0609).
        return matches!(kind, Kind::Level | Kind::Lift).then_some("is empty");
    }
    if name
        .chars()
        .any(|c| c.is_control() || super::unsafe_characters::is_bidi_control(c))
    {
        return None; // E0509
    }
    if name.starts_with(char::is_whitespace) || name.ends_with(char::is_whitespace) {
        return Some("starts or ends with whitespace");
    }
    if name.contains('\\') {
        return Some("contains `\\`");
    }
    if !is_model && name.contains('/') {
        return Some("contains `/`");
    }
    if name == "." || name.split('/').any(|c| c == "..") {
        return Some("is or contains the path component `.` or `..`");
    }
    None
}

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    let mut report = |kind: Kind, name: &str, span: Span| {
        let Some(why) = problem(name, kind) else {
            return;
        };
        let (what, becomes) = match kind {
            Kind::Level => (
                "level",
                "level names become directory, file and model names",
            ),
            Kind::Lift => (
                "lift",
                "lift names become model names and controller topics",
            ),
            Kind::Door => (
                "door",
                "door names become model names and controller topics",
            ),
            Kind::Model => (
                "model",
                "model names become model instance names in the world",
            ),
        };
        out.push(
            Diagnostic::warning(
                RULE.code,
                span,
                format!("{what} name \"{}\" {why}; {becomes}", name.escape_debug()),
            )
            .with_help("use letters, digits, `_` and `-`, e.g. `L1`, `lift_1`, `main_door`"),
        );
    };
    for (h, level) in b.levels.iter() {
        report(Kind::Level, &level.name, b.levels.span(h));
    }
    for (h, lift) in b.lifts.iter() {
        report(Kind::Lift, &lift.name, b.lifts.span(h));
    }
    for (h, door) in b.doors.iter() {
        let span = door
            .params
            .param("name")
            .map_or(b.doors.span(h), |p| p.span);
        report(Kind::Door, &door.name, span);
    }
    for (h, model) in b.models.iter() {
        report(Kind::Model, &model.name, b.models.span(h));
    }
}

#[cfg(test)]
mod tests {
    use super::{problem, Kind};

    #[test]
    fn safe_names() {
        for n in [
            "L1",
            "lift_1",
            "main-door",
            "Pine Tree",
            "ground floor",
            "a.b",
            "..x",
        ] {
            assert_eq!(problem(n, Kind::Level), None, "{n}");
        }
        assert_eq!(problem("OpenRobotics/Chair", Kind::Model), None);
        assert_eq!(problem("", Kind::Door), None); // E0301
        assert_eq!(problem("", Kind::Model), None); // E0609
    }

    #[test]
    fn unsafe_names() {
        for n in ["", "L1/east", "a\\b", "..", ".", " L1", "L1 ", "a/../b"] {
            assert!(problem(n, Kind::Level).is_some(), "{n:?}");
        }
        assert!(problem("", Kind::Lift).is_some());
        assert!(problem("../Chair", Kind::Model).is_some());
        assert!(problem("Open\\Chair", Kind::Model).is_some());
        assert!(problem("Chair ", Kind::Model).is_some());
    }

    #[test]
    fn checks_every_kind() {
        use crate::validate::tests::TestMap;
        use crate::{DoorKind, Vec2};
        let mut m = TestMap::new();
        m.b.levels[m.level].name = "L1 ".into();
        let l1 = m.level;
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 1.0, 0.0);
        m.door("d/1", DoorKind::Hinged, a, b);
        m.lift("lift ", Vec2::new(5.0, 5.0), 2.0, 2.0, &[l1]);
        let n = crate::validate(&m.b)
            .iter()
            .filter(|d| d.code == "W0508")
            .count();
        assert_eq!(n, 3);
    }
}
