//! # E0405 lift-range-inverted
//!
//! **What:** a lift's `lowest_floor` is a level with a higher elevation than its
//! `highest_floor`.
//!
//! **Why it matters:** the range `lowest_floor`..`highest_floor` decides on which levels
//! the shaft is cut out of the floor and which waypoints belong to the lift. An inverted
//! range contains no level at all, so the shaft exists nowhere and robots cannot use the
//! lift. traffic_editor refuses this in its lift dialog; it only happens in hand-edited
//! files or after a level's elevation was changed.
//!
//! **Fix:** swap the two names, or correct the levels' `elevation`.
//!
//! **Example:**
//! ```yaml
//! levels:
//!   L1: {elevation: 0}
//!   L2: {elevation: 4}
//! lifts:
//!   LA:   # E0405
//!     lowest_floor: L2
//!     highest_floor: L1
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Lift};

pub(crate) static RULE: Rule = Rule {
    code: "E0405",
    name: "lift-range-inverted",
    summary: "a lift's lowest_floor is above its highest_floor",
    group: Group::Lifts,
    metric: false,
    check,
};

/// Is the lift's elevation range inverted?
pub(crate) fn inverted(ctx: &Context, lift: &Lift) -> bool {
    match (lift.lowest_level, lift.highest_level) {
        (Some(lo), Some(hi)) => ctx.b.levels[lo].elevation > ctx.b.levels[hi].elevation,
        _ => false,
    }
}

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, lift) in ctx.b.lifts.iter() {
        if !inverted(ctx, lift) {
            continue;
        }
        let (Some(lo), Some(hi)) = (lift.lowest_level, lift.highest_level) else {
            continue;
        };
        out.push(
            Diagnostic::error(
                RULE.code,
                ctx.b.lifts.span(h),
                format!(
                    "lift `{}` has lowest_floor `{}` (elevation {}) above highest_floor `{}` (elevation {})",
                    lift.name,
                    ctx.level_name(lo),
                    ctx.b.levels[lo].elevation,
                    ctx.level_name(hi),
                    ctx.b.levels[hi].elevation
                ),
            )
            .with_help("swap `lowest_floor` and `highest_floor`, or fix the levels' elevations"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::Vec2;

    #[test]
    fn finds_inverted_ranges() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let l2 = m.level("L2", 4.0);
        let lift = m.lift("LA", Vec2::new(0.0, 0.0), 2.0, 2.0, &[l1, l2]);
        m.b.lifts[lift].lowest_level = Some(l1);
        m.b.lifts[lift].highest_level = Some(l2);
        assert!(!codes_of(&m.b).contains(&"E0405"));
        m.b.lifts[lift].lowest_level = Some(l2);
        m.b.lifts[lift].highest_level = Some(l1);
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "E0405").count(), 1);
        // The inverted range is not also reported level by level.
        assert!(!d.contains(&"W0406"));
    }
}
