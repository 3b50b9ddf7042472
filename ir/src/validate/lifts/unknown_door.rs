//! # E0403 unknown-lift-door
//!
//! **What:** a `level_doors` list names a door that is not among the lift's `doors`.
//!
//! **Why it matters:** the reference generator silently ignores the name. If it was the
//! level's only door, the lift plugin gets a floor without a door pair: the lift stops at
//! that level but never opens a door there, and a robot riding it never gets out. It is
//! almost always a typo, or a door that was renamed or deleted.
//!
//! **Fix:** use the name of one of the lift's `doors`, or add the missing door.
//!
//! **Example:**
//! ```yaml
//! lifts:
//!   LA:
//!     doors:
//!       door1: {door_type: 2, x: 0, y: -1, width: 1.2, motion_axis_orientation: 0}
//!     level_doors:
//!       L1: [door_1]   # E0403
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0403",
    name: "unknown-lift-door",
    summary: "level_doors names a door the lift does not have",
    group: Group::Lifts,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (_, lift) in ctx.b.lifts.iter() {
        for ld in &lift.level_doors {
            for (name, span) in &ld.doors {
                if lift.doors.iter().any(|d| &d.name == name) {
                    continue;
                }
                let known: Vec<String> =
                    lift.doors.iter().map(|d| format!("`{}`", d.name)).collect();
                let help = if known.is_empty() {
                    "the lift has no doors; add one under `doors`".to_string()
                } else {
                    format!("the lift's doors are {}", known.join(", "))
                };
                out.push(
                    Diagnostic::error(
                        RULE.code,
                        *span,
                        format!(
                            "lift `{}` has no door `{name}` (listed for level `{}`)",
                            lift.name,
                            ctx.level_name(ld.level)
                        ),
                    )
                    .with_help(help),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::Vec2;

    #[test]
    fn finds_unknown_names() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let l2 = m.level("L2", 3.0);
        let lift = m.lift("LA", Vec2::new(0.0, 0.0), 2.0, 2.0, &[l1, l2]);
        assert!(!codes_of(&m.b).contains(&"E0403"));
        let span = m.b.lifts[lift].level_doors[1].span;
        m.b.lifts[lift].level_doors[1]
            .doors
            .push(("typo".into(), span));
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "E0403").count(), 1);
    }
}
