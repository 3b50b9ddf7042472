//! # W0406 lift-door-outside-range
//!
//! **What:** a level in a lift's `level_doors` lies outside the lift's range: its
//! elevation is below that of `lowest_floor` or above that of `highest_floor`.
//!
//! **Why it matters:** the shaft is only cut out of the levels in the range, and only
//! waypoints on those levels are tagged with the lift, yet the reference generator still
//! builds a shaft door on every level of `level_doors`, and the lift plugin still lists
//! the floor. The result is a shaft door standing in an uncut floor, and a lift that can
//! be sent to a floor its shaft does not reach.
//!
//! **Fix:** widen `lowest_floor`/`highest_floor` to include the level, or remove the
//! level from `level_doors`.
//!
//! **Example:**
//! ```yaml
//! lifts:
//!   LA:
//!     lowest_floor: L1
//!     highest_floor: L2
//!     level_doors:
//!       L1: [door1]
//!       L3: [door1]   # W0406: L3 is above L2
//! ```

use super::range_inverted::inverted;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0406",
    name: "lift-door-outside-range",
    summary: "level_doors lists a level outside the lift's lowest..highest floor range",
    group: Group::Lifts,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let levels = &ctx.b.levels;
    for (_, lift) in ctx.b.lifts.iter() {
        if inverted(ctx, lift) {
            continue; // E0405
        }
        for ld in &lift.level_doors {
            let z = levels[ld.level].elevation;
            let below = lift.lowest_level.filter(|&lo| z < levels[lo].elevation);
            let above = lift.highest_level.filter(|&hi| z > levels[hi].elevation);
            let (bound, which, dir) = match (below, above) {
                (Some(lo), _) => (lo, "lowest_floor", "below"),
                (_, Some(hi)) => (hi, "highest_floor", "above"),
                _ => continue,
            };
            out.push(
                Diagnostic::warning(
                    RULE.code,
                    ld.span,
                    format!(
                        "lift `{}` opens doors on level `{}` (elevation {z}), {dir} its {which} `{}` (elevation {})",
                        lift.name,
                        ctx.level_name(ld.level),
                        ctx.level_name(bound),
                        levels[bound].elevation
                    ),
                )
                .with_help(format!(
                    "include the level in the lift's range (`{which}`), or remove it from `level_doors`"
                )),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::Vec2;

    #[test]
    fn finds_levels_outside_the_range() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let l2 = m.level("L2", 4.0);
        let l3 = m.level("L3", 8.0);
        let lift = m.lift("LA", Vec2::new(0.0, 0.0), 2.0, 2.0, &[l1, l2, l3]);
        assert!(!codes_of(&m.b).contains(&"W0406"));
        m.b.lifts[lift].lowest_level = Some(l2);
        m.b.lifts[lift].highest_level = Some(l2);
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "W0406").count(), 2);
        m.b.lifts[lift].lowest_level = None;
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "W0406").count(), 1);
    }
}
