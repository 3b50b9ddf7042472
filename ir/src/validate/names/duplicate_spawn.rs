//! # W0506 duplicate-spawn-name
//!
//! **What:** two spawn vertices (with `spawn_robot_type`) have the same `spawn_robot_name`,
//! anywhere in the building.
//!
//! **Why it matters:** the spawn name becomes the robot's model name in the simulation
//! world and its name in its fleet. Model names in a Gazebo world must be unique, so one of
//! the two robots fails to load, and fleet adapters and dashboards that identify robots by
//! name would confuse them.
//!
//! **Fix:** give every spawned robot its own name (`tiny_1`, `tiny_2`, ...).
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, a, {spawn_robot_type: [1, TinyRobot], spawn_robot_name: [1, tiny]}]
//!   - [4, 0, 0, b, {spawn_robot_type: [1, TinyRobot], spawn_robot_name: [1, tiny]}]   # W0506
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Handle, Vertex};
use std::collections::HashMap;

pub(crate) static RULE: Rule = Rule {
    code: "W0506",
    name: "duplicate-spawn-name",
    summary: "two spawn vertices have the same spawn_robot_name",
    group: Group::Spawns,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let mut first: HashMap<&str, Handle<Vertex>> = HashMap::new();
    for (h, v) in ctx.b.vertices.iter() {
        let (Some(_), Some(name)) = (&v.roles.spawn_robot_type, &v.roles.spawn_robot_name) else {
            continue;
        };
        let Some(&earlier) = first.get(name.as_str()) else {
            first.insert(name, h);
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
                    "robot name `{name}` is spawned twice: at {} and at {}",
                    ctx.vertex_label(earlier),
                    ctx.vertex_label(h)
                ),
            )
            .with_label(ctx.vertex_span(earlier), "the other robot with this name")
            .with_help("give every spawned robot its own spawn_robot_name"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{param, params, TestMap};
    use crate::ParamValue;

    fn spawn(ty: &str, name: &str) -> crate::Params {
        params(vec![
            param("spawn_robot_type", ParamValue::String(ty.into())),
            param("spawn_robot_name", ParamValue::String(name.into())),
        ])
    }

    #[test]
    fn duplicates() {
        let mut m = TestMap::new();
        m.vertex_with("a", 0.0, 0.0, spawn("Tiny", "t1"));
        m.vertex_with("b", 4.0, 0.0, spawn("Tiny", "t2"));
        m.level("L2", 4.0);
        m.vertex_with("c", 0.0, 0.0, spawn("Other", "t1"));
        // A name without a type spawns nothing (W0505), so it cannot collide.
        m.vertex_with("d", 4.0, 0.0, spawn("", "t2"));
        let n = crate::validate(&m.b)
            .iter()
            .filter(|d| d.code == "W0506")
            .count();
        assert_eq!(n, 1);
    }
}
