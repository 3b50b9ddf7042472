//! # W0408 lift-initial-floor-not-served
//!
//! **What:** a lift's `initial_floor_name` is not one of the levels in its
//! `level_doors`.
//!
//! **Why it matters:** the lift's floors are its `level_doors` levels. The simulated
//! lift's plugin finds the initial floor missing from them, logs "Initial floor ... is
//! not available" and starts at the first `level_doors` level instead, so the setting
//! has no effect; usually a level was dropped from `level_doors` or the initial floor
//! was mistyped.
//!
//! **Fix:** set `initial_floor_name` to a level in `level_doors` (or leave it out: the
//! first `level_doors` level is then used).
//!
//! **Example:**
//! ```yaml
//! lifts:
//!   LA:   # W0408
//!     initial_floor_name: L3
//!     level_doors:
//!       L1: [door1]
//!       L2: [door1]
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0408",
    name: "lift-initial-floor-not-served",
    summary: "a lift's initial_floor_name is not one of its level_doors levels",
    group: Group::Lifts,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, lift) in ctx.b.lifts.iter() {
        let Some(init) = lift.initial_level else {
            continue;
        };
        if lift.level_doors.iter().any(|ld| ld.level == init) {
            continue;
        }
        let served: Vec<String> = lift
            .level_doors
            .iter()
            .map(|ld| format!("`{}`", ctx.level_name(ld.level)))
            .collect();
        let served = if served.is_empty() {
            "no level (its `level_doors` is empty)".to_string()
        } else {
            served.join(", ")
        };
        out.push(
            Diagnostic::warning(
                RULE.code,
                ctx.b.lifts.span(h),
                format!(
                    "lift `{}` starts at level `{}`, which it does not serve; it serves {served}",
                    lift.name,
                    ctx.level_name(init)
                ),
            )
            .with_help("set `initial_floor_name` to a level listed in `level_doors`"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::Vec2;

    #[test]
    fn initial_floor_must_be_served() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let l2 = m.level("L2", 3.0);
        let lift = m.lift("LA", Vec2::new(0.0, 0.0), 2.0, 2.0, &[l1]);
        assert!(!codes_of(&m.b).contains(&"W0408"));
        m.b.lifts[lift].initial_level = Some(l1);
        assert!(!codes_of(&m.b).contains(&"W0408"));
        m.b.lifts[lift].initial_level = Some(l2);
        assert_eq!(codes_of(&m.b).iter().filter(|c| **c == "W0408").count(), 1);
    }
}
