//! # E0401 lift-dimensions
//!
//! **What:** a lift's `width` or `depth` is zero or negative.
//!
//! **Why it matters:** the cabin would be a box of zero or negative size, which no robot
//! fits in and no physics engine can simulate, and the shaft cut out of each floor (the
//! cabin plus 5 cm on each side) shrinks to a sliver or turns inside out. It is always a
//! typo or a value lost in an edit.
//!
//! **Fix:** set `width` (along the cabin's x axis) and `depth` (along its y axis) to the
//! cabin's inside size in metres.
//!
//! **Example:**
//! ```yaml
//! lifts:
//!   LA:   # E0401
//!     width: 0
//!     depth: 2.0
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0401",
    name: "lift-dimensions",
    summary: "a lift's width or depth is not positive",
    group: Group::Lifts,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, lift) in ctx.b.lifts.iter() {
        let bad: Vec<String> = [("width", lift.width), ("depth", lift.depth)]
            .iter()
            .filter(|(_, v)| *v <= 0.0)
            .map(|(k, v)| format!("`{k}` is {v}"))
            .collect();
        if !bad.is_empty() {
            out.push(
                Diagnostic::error(
                    RULE.code,
                    ctx.b.lifts.span(h),
                    format!("lift `{}` has no size: {}", lift.name, bad.join(" and ")),
                )
                .with_help("set `width` and `depth` to the cabin's inside size in metres"),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::Vec2;

    #[test]
    fn finds_flat_lifts() {
        let mut m = TestMap::new();
        let l1 = m.level;
        m.lift("ok", Vec2::new(0.0, 0.0), 2.0, 2.0, &[l1]);
        let bad = m.lift("bad", Vec2::new(10.0, 0.0), 2.0, 2.0, &[l1]);
        m.b.lifts[bad].width = 0.0;
        m.b.lifts[bad].depth = -1.0;
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "E0401").count(), 1);
    }
}
