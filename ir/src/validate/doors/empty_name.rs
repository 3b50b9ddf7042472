//! # E0301 empty-door-name
//!
//! **What:** a door's `name` parameter is the empty string.
//!
//! **Why it matters:** the door name is the door's identity everywhere downstream: nav
//! graph lanes refer to it in `door_name`, the door controller and the fleet adapter
//! exchange open/close requests by name, and the simulation world names the door model
//! after it. With an empty name the world gets a nameless model and robots ask to open a
//! door called `""`.
//!
//! **Fix:** give the door a unique, non-empty name.
//!
//! **Example:**
//! ```yaml
//! doors:
//!   - [4, 5, {name: [1, ""], type: [1, hinged], motion_direction: [2, 1], motion_degrees: [3, 90]}]   # E0301
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0301",
    name: "empty-door-name",
    summary: "a door has an empty name",
    group: Group::Doors,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, door) in ctx.b.doors.iter() {
        if door.name.is_empty() {
            let span = door
                .params
                .param("name")
                .map_or(ctx.b.doors.span(h), |p| p.span);
            out.push(
                Diagnostic::error(
                    RULE.code,
                    span,
                    format!(
                        "a {} door on level `{}` has an empty name",
                        door.kind.as_str(),
                        ctx.level_name(door.level)
                    ),
                )
                .with_help("give the door a unique name, e.g. `name: [1, main_entrance]`"),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::DoorKind;

    #[test]
    fn finds_empty_names_only() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 1.0, 0.0);
        m.door("", DoorKind::Hinged, a, b);
        m.door("d1", DoorKind::Hinged, a, b);
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "E0301").count(), 1);
    }
}
