//! # E0303 unknown-door-type
//!
//! **What:** a door's `type` is not one of `hinged`, `double_hinged`, `sliding`,
//! `double_sliding`.
//!
//! **Why it matters:** the reference generator prints "not yet implemented" and emits no
//! door model, yet still lists the door in the nav graph and in the level's toggle-floors
//! plugin. Robots would then wait for a door that no controller will ever open.
//!
//! **Fix:** use one of the four supported types (the editor offers exactly these).
//!
//! **Example:**
//! ```yaml
//! doors:
//!   - [4, 5, {name: [1, d1], type: [1, revolving]}]   # E0303
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, DoorKind};

pub(crate) static RULE: Rule = Rule {
    code: "E0303",
    name: "unknown-door-type",
    summary: "a door's type is not hinged, double_hinged, sliding or double_sliding",
    group: Group::Doors,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, door) in ctx.b.doors.iter() {
        if let DoorKind::Other(t) = &door.kind {
            let span = door
                .params
                .param("type")
                .map_or(ctx.b.doors.span(h), |p| p.span);
            out.push(
                Diagnostic::error(
                    RULE.code,
                    span,
                    format!(
                        "door `{}` on level `{}` has the unknown type `{t}`",
                        door.name,
                        ctx.level_name(door.level)
                    ),
                )
                .with_help("use `hinged`, `double_hinged`, `sliding` or `double_sliding`"),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::DoorKind;

    #[test]
    fn finds_unknown_types_only() {
        let mut m = TestMap::new();
        let a = m.vertex("", 0.0, 0.0);
        let b = m.vertex("", 1.0, 0.0);
        m.door("d1", DoorKind::Other("revolving".into()), a, b);
        m.door("d2", DoorKind::DoubleSliding, a, b);
        m.door("d3", DoorKind::parse("Hinged"), a, b);
        let d = codes_of(&m.b);
        assert_eq!(d.iter().filter(|c| **c == "E0303").count(), 2);
    }
}
