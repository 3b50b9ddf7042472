//! # W0412 lift-floors-at-one-elevation
//!
//! **What:** a lift serves two or more levels drawn at the same `elevation`.
//!
//! **Why it matters:** a level's elevation is where its floor is in the world. Levels
//! at one elevation lie on top of each other: in a Gazebo world their walls and floors
//! overlap and robots on different levels meet in the same place, and a cabin "moving"
//! between them travels nowhere. The reference lift plugin tells floors apart by
//! elevation, so it always reports the first of them and a cabin sent to another never
//! arrives. This is usually a map whose levels were drawn without setting their
//! elevations. (`mapc sim` stacks such levels a storey apart, above the highest, so the
//! run goes on; the other outputs keep the elevations as drawn.)
//!
//! **Fix:** give each level the height of its floor, e.g. `elevation: 4` for a floor
//! 4 m above the first.
//!
//! **Example:**
//! ```yaml
//! levels:
//!   L1: {elevation: 0}
//!   L2: {elevation: 0}   # W0412 with a lift serving L1 and L2
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0412",
    name: "lift-floors-at-one-elevation",
    summary: "a lift serves levels drawn at the same elevation",
    group: Group::Lifts,
    metric: false,
    check,
};

/// Levels closer than this (m) are at one elevation: no cabin rides between them.
const SAME: f64 = 0.01;

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, lift) in ctx.b.lifts.iter() {
        let mut levels: Vec<_> = lift.level_doors.iter().map(|ld| ld.level).collect();
        levels.sort_by(|a, b| {
            ctx.b.levels[*a]
                .elevation
                .total_cmp(&ctx.b.levels[*b].elevation)
        });
        levels.dedup();
        // Runs of levels at one elevation, each reported once.
        let mut i = 0;
        while i < levels.len() {
            let z = ctx.b.levels[levels[i]].elevation;
            let mut j = i + 1;
            while j < levels.len() && (ctx.b.levels[levels[j]].elevation - z).abs() < SAME {
                j += 1;
            }
            if j - i > 1 {
                let names: Vec<String> = levels[i..j]
                    .iter()
                    .map(|&l| format!("`{}`", ctx.level_name(l)))
                    .collect();
                out.push(
                    Diagnostic::warning(
                        RULE.code,
                        ctx.b.lifts.span(h),
                        format!(
                            "lift `{}` serves levels {} all at elevation {z} m: they lie on top of each other, and the cabin cannot ride between them",
                            lift.name,
                            names.join(", ")
                        ),
                    )
                    .with_help("give each level the height of its floor in `elevation` (e.g. 4 for a floor 4 m up)"),
                );
            }
            i = j;
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::Vec2;

    #[test]
    fn finds_served_levels_at_one_elevation() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let l2 = m.level("L2", 4.0);
        m.lift("LA", Vec2::new(0.0, 0.0), 2.0, 2.0, &[l1, l2]);
        assert!(!codes_of(&m.b).contains(&"W0412"));
        let mut m = TestMap::new();
        let l1 = m.level;
        let l2 = m.level("L2", 0.0);
        let l3 = m.level("L3", 0.0);
        let l4 = m.level("L4", 4.0);
        m.lift("LA", Vec2::new(0.0, 0.0), 2.0, 2.0, &[l1, l2, l3, l4]);
        let d = codes_of(&m.b);
        // One warning for the three levels at 0 m, none for L4.
        assert_eq!(d.iter().filter(|c| **c == "W0412").count(), 1);
    }
}
