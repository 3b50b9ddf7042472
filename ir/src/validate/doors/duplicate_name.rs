//! # E0302 duplicate-door-name
//!
//! **What:** two doors, on the same level or on different levels, have the same name.
//!
//! **Why it matters:** doors are keyed by name. Nav graph lanes carry only the door name,
//! so the fleet adapter cannot tell which of the two doors to open; the reference
//! generator keeps the last one in the nav graph's door list; and the simulation world
//! gets two models with the same name, where Gazebo requires model names to be unique.
//!
//! **Fix:** rename one of the doors. Prefixing the level name (`L2_lobby_door`) keeps
//! names unique across levels.
//!
//! **Example:**
//! ```yaml
//! levels:
//!   L1:
//!     doors:
//!       - [0, 1, {name: [1, lobby], type: [1, sliding]}]
//!   L2:
//!     doors:
//!       - [3, 4, {name: [1, lobby], type: [1, sliding]}]   # E0302
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Door, Handle};
use std::collections::HashMap;

pub(crate) static RULE: Rule = Rule {
    code: "E0302",
    name: "duplicate-door-name",
    summary: "two doors have the same name",
    group: Group::Doors,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let mut first: HashMap<&str, Handle<Door>> = HashMap::new();
    for (h, door) in ctx.b.doors.iter() {
        if door.name.is_empty() {
            continue; // E0301
        }
        let Some(&prev) = first.get(door.name.as_str()) else {
            first.insert(&door.name, h);
            continue;
        };
        let other = &ctx.b.doors[prev];
        let where_ = if other.level == door.level {
            "also on this level".to_string()
        } else {
            format!("on level `{}`", ctx.level_name(other.level))
        };
        out.push(
            Diagnostic::error(
                RULE.code,
                ctx.b.doors.span(h),
                format!(
                    "door `{}` on level `{}` has the same name as a door {where_}",
                    door.name,
                    ctx.level_name(door.level)
                ),
            )
            .with_label(ctx.b.doors.span(prev), "the other door of that name")
            .with_help("door names must be unique across the whole building; rename one"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::DoorKind;

    #[test]
    fn finds_duplicates_across_levels() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 1.0, 0.0);
        m.door("d1", DoorKind::Hinged, a, b);
        m.door("d2", DoorKind::Hinged, a, b);
        m.level("L2", 3.0);
        let c = m.vertex("", 0.0, 0.0);
        let d = m.vertex("", 1.0, 0.0);
        m.door("d1", DoorKind::Sliding, c, d);
        m.door("d1", DoorKind::Sliding, c, d);
        let diags = crate::validate(&m.b);
        let dup: Vec<_> = diags.iter().filter(|d| d.code == "E0302").collect();
        assert_eq!(dup.len(), 2);
        assert!(dup[0].message.contains("on level `L1`"));
        assert!(dup[1].message.contains("also on this level") || dup[1].message.contains("L1"));
        assert_eq!(codes_of(&m.b).iter().filter(|c| **c == "E0302").count(), 2);
    }

    #[test]
    fn empty_names_are_not_duplicates() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 1.0, 0.0);
        m.door("", DoorKind::Hinged, a, b);
        m.door("", DoorKind::Hinged, a, b);
        assert!(!codes_of(&m.b).contains(&"E0302"));
    }
}
