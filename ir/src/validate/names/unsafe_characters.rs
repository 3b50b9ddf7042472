//! # E0509 unsafe-characters-in-name
//!
//! **What:** the building name, or a level, lift, door or model name, contains a control
//! character (a tab, a newline, an escape, ...) or a bidirectional control character
//! (U+202A–U+202E, U+2066–U+2069, U+200E, U+200F, U+061C).
//!
//! **Why it matters:** these names become file and directory names (`<building>.glb`,
//! `models/<building>_<level>/`), model names and controller topics in the generated
//! output, and they appear in build logs and depfiles. A tab or newline in a path breaks
//! Make and Ninja rules and shell scripts; a right-to-left override makes a name display
//! as different text than it is (the "Trojan Source" class of attacks, CVE-2021-42574).
//! mapc does not guess a safe replacement: the map is refused and nothing is written.
//! Messages and snippets show such characters escaped (`\t`, `\u{202e}`).
//!
//! **Fix:** retype the name with visible characters only: letters, digits, `_` and `-`
//! (for example `L1`, `lift_1`, `main_door`).
//!
//! **Example:**
//! ```yaml
//! levels:
//!   "L0_tab\there":        # E0509
//!     elevation: 0
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Span};

pub(crate) static RULE: Rule = Rule {
    code: "E0509",
    name: "unsafe-characters-in-name",
    summary: "a name that becomes a path or model name has control or bidi characters",
    group: Group::UnsafeNames,
    metric: false,
    check,
};

/// Bidirectional formatting characters: embeddings and overrides, isolates, marks.
pub(crate) fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}' | '\u{200e}' | '\u{200f}' | '\u{61c}')
}

/// What is wrong with `name`, if anything.
fn problem(name: &str) -> Option<&'static str> {
    if name.chars().any(is_bidi_control) {
        Some("a bidirectional control character")
    } else if name.chars().any(char::is_control) {
        Some("a control character")
    } else {
        None
    }
}

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    let mut report = |what: &str, name: &str, span: Span| {
        let Some(why) = problem(name) else {
            return;
        };
        out.push(
            Diagnostic::error(
                RULE.code,
                span,
                format!(
                    "{what} name \"{}\" contains {why}; names become file, directory and \
                     model names, so nothing is written",
                    name.escape_debug()
                ),
            )
            .with_help("retype the name with visible characters: letters, digits, `_` and `-`"),
        );
    };
    report("building", &b.name, b.spans.name);
    for (h, level) in b.levels.iter() {
        report("level", &level.name, b.levels.span(h));
    }
    for (h, lift) in b.lifts.iter() {
        report("lift", &lift.name, b.lifts.span(h));
    }
    for (h, door) in b.doors.iter() {
        let span = door
            .params
            .param("name")
            .map_or(b.doors.span(h), |p| p.span);
        report("door", &door.name, span);
    }
    for (h, model) in b.models.iter() {
        report("model", &model.name, b.models.span(h));
    }
}

#[cfg(test)]
mod tests {
    use super::problem;

    #[test]
    fn finds_controls_and_bidi() {
        for ok in ["L1", "Pine Tree", "étage 2", "OpenRobotics/Chair", ""] {
            assert_eq!(problem(ok), None, "{ok:?}");
        }
        for bad in [
            "L0_tab\there",
            "a\nb",
            "x\u{202e}y",
            "\u{2066}L1",
            "bell\u{7}",
            "\u{200f}",
        ] {
            assert!(problem(bad).is_some(), "{bad:?}");
        }
    }

    #[test]
    fn reports_every_kind_as_an_error() {
        use crate::validate::tests::TestMap;
        use crate::{DoorKind, Vec2};
        let mut m = TestMap::new();
        m.b.name = "site\u{202e}".into();
        m.b.levels[m.level].name = "L\t1".into();
        let l1 = m.level;
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 1.0, 0.0);
        m.door("d\n1", DoorKind::Hinged, a, b);
        m.lift("lift\u{2067}", Vec2::new(5.0, 5.0), 2.0, 2.0, &[l1]);
        let d: Vec<_> = crate::validate(&m.b)
            .into_iter()
            .filter(|d| d.code == "E0509")
            .collect();
        assert_eq!(d.len(), 4, "{d:?}");
        assert!(d.iter().all(|d| d.is_error()));
        // Messages never carry the raw characters.
        assert!(d.iter().all(|d| !d
            .message
            .chars()
            .any(|c| c.is_control() || super::is_bidi_control(c))));
        // W0508 leaves these names to E0509.
        assert!(!crate::validate(&m.b).iter().any(|d| d.code == "W0508"));
    }
}
