//! # W0410 lift-door-never-opens
//!
//! **What:** a lift cabin door is not listed for any level in `level_doors`.
//!
//! **Why it matters:** the generator builds the door into the cabin, but no shaft door
//! pairs with it and the lift never opens it: on every level it stays shut. It is
//! usually left over from an edit (a door renamed in `doors` but not in `level_doors`,
//! or a level removed).
//!
//! **Fix:** list the door for the levels where it should open, or delete it.
//!
//! **Example:**
//! ```yaml
//! lifts:
//!   LA:
//!     doors:
//!       front: {door_type: 2, x: 0, y: -1, width: 1.2, motion_axis_orientation: 0}
//!       back: {door_type: 2, x: 0, y: 1, width: 1.2, motion_axis_orientation: 0}   # W0410
//!     level_doors:
//!       L1: [front]
//!       L2: [front]
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0410",
    name: "lift-door-never-opens",
    summary: "a lift door is not listed for any level in level_doors",
    group: Group::Lifts,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (_, lift) in ctx.b.lifts.iter() {
        for door in &lift.doors {
            let used = lift
                .level_doors
                .iter()
                .any(|ld| ld.doors.iter().any(|(n, _)| *n == door.name));
            if !used {
                out.push(
                    Diagnostic::warning(
                        RULE.code,
                        door.span,
                        format!(
                            "door `{}` of lift `{}` opens on no level: no `level_doors` entry lists it",
                            door.name, lift.name
                        ),
                    )
                    .with_help("list the door under `level_doors` for the levels where it opens, or delete it"),
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
    fn finds_unused_doors() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let lift = m.lift("LA", Vec2::new(0.0, 0.0), 2.0, 2.0, &[l1]);
        assert!(!codes_of(&m.b).contains(&"W0410"));
        let mut back = m.b.lifts[lift].doors[0].clone();
        back.name = "back".into();
        back.pos = Vec2::new(0.0, 1.0);
        m.b.lifts[lift].doors.push(back);
        assert_eq!(codes_of(&m.b).iter().filter(|c| **c == "W0410").count(), 1);
    }
}
