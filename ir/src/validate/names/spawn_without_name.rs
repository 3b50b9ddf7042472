//! # E0504 spawn-without-name
//!
//! **What:** a vertex has `spawn_robot_type` but no non-empty `spawn_robot_name`.
//!
//! **Why it matters:** a spawn vertex places a robot model in the simulation world, and the
//! name is the robot's model name in Gazebo and its name in its fleet. Without it the
//! reference generator crashes (`KeyError`) while writing the world, and an empty name
//! would make an unnamed model that no fleet adapter can identify.
//!
//! **Fix:** add `spawn_robot_name: [1, <unique robot name>]`, or remove
//! `spawn_robot_type` if no robot should start here.
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, start, {spawn_robot_type: [1, TinyRobot]}]   # E0504
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0504",
    name: "spawn-without-name",
    summary: "spawn_robot_type without a non-empty spawn_robot_name",
    group: Group::Spawns,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, v) in ctx.b.vertices.iter() {
        let Some(ty) = &v.roles.spawn_robot_type else {
            continue;
        };
        if v.roles.spawn_robot_name.is_some() {
            continue;
        }
        let span = v
            .params
            .param("spawn_robot_type")
            .map_or(ctx.vertex_span(h), |p| p.span);
        let mut d = Diagnostic::error(
            RULE.code,
            span,
            format!(
                "{} spawns a robot of type `{ty}` but has no `spawn_robot_name`",
                ctx.vertex_label(h)
            ),
        );
        if let Some(p) = v.params.param("spawn_robot_name") {
            d = d.with_label(p.span, "empty or not a string");
        }
        out.push(d.with_help("add `spawn_robot_name: [1, <unique robot name>]`"));
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{param, params, TestMap};
    use crate::ParamValue;

    fn count(list: Vec<(&str, ParamValue)>) -> usize {
        let mut m = TestMap::new();
        m.vertex_with(
            "s",
            0.0,
            0.0,
            params(list.into_iter().map(|(k, v)| param(k, v)).collect()),
        );
        crate::validate(&m.b)
            .iter()
            .filter(|d| d.code == "E0504")
            .count()
    }

    #[test]
    fn name_required() {
        let ty = || ("spawn_robot_type", ParamValue::String("TinyRobot".into()));
        assert_eq!(count(vec![ty()]), 1);
        assert_eq!(
            count(vec![
                ty(),
                ("spawn_robot_name", ParamValue::String("".into()))
            ]),
            1
        );
        assert_eq!(
            count(vec![ty(), ("spawn_robot_name", ParamValue::Int(3))]),
            1
        );
        assert_eq!(
            count(vec![
                ty(),
                ("spawn_robot_name", ParamValue::String("t1".into()))
            ]),
            0
        );
        assert_eq!(count(vec![]), 0);
    }
}
