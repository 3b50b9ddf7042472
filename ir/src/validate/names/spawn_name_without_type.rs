//! # W0505 spawn-name-without-type
//!
//! **What:** a vertex has `spawn_robot_name` but no (non-empty) `spawn_robot_type`.
//!
//! **Why it matters:** a robot is spawned only where `spawn_robot_type` says which model to
//! use; the name alone is ignored, so the robot the author expected never appears in the
//! simulation.
//!
//! **Fix:** add `spawn_robot_type: [1, <robot model>]`, or remove `spawn_robot_name`.
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, start, {spawn_robot_name: [1, tiny_1]}]   # W0505
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0505",
    name: "spawn-name-without-type",
    summary: "spawn_robot_name without spawn_robot_type (ignored)",
    group: Group::Spawns,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, v) in ctx.b.vertices.iter() {
        let (Some(name), None) = (&v.roles.spawn_robot_name, &v.roles.spawn_robot_type) else {
            continue;
        };
        let span = v
            .params
            .param("spawn_robot_name")
            .map_or(ctx.vertex_span(h), |p| p.span);
        out.push(
            Diagnostic::warning(
                RULE.code,
                span,
                format!(
                    "{} has `spawn_robot_name` `{name}` but no `spawn_robot_type`, so no robot \
                     is spawned and the name is ignored",
                    ctx.vertex_label(h)
                ),
            )
            .with_help("add `spawn_robot_type: [1, <robot model>]`, or remove the name"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{param, params, TestMap};
    use crate::ParamValue;

    fn count(list: Vec<(&str, &str)>) -> usize {
        let mut m = TestMap::new();
        m.vertex_with(
            "s",
            0.0,
            0.0,
            params(
                list.into_iter()
                    .map(|(k, v)| param(k, ParamValue::String(v.into())))
                    .collect(),
            ),
        );
        crate::validate(&m.b)
            .iter()
            .filter(|d| d.code == "W0505")
            .count()
    }

    #[test]
    fn type_required() {
        assert_eq!(count(vec![("spawn_robot_name", "t1")]), 1);
        assert_eq!(
            count(vec![("spawn_robot_name", "t1"), ("spawn_robot_type", "")]),
            1
        );
        assert_eq!(
            count(vec![
                ("spawn_robot_name", "t1"),
                ("spawn_robot_type", "Tiny")
            ]),
            0
        );
        assert_eq!(count(vec![("spawn_robot_name", "")]), 0);
    }
}
