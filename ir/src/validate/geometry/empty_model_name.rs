//! # E0609 empty-model-name
//!
//! **What:** a model's `name` or `model_name` is the empty string.
//!
//! **Why it matters:** `model_name` says which Gazebo model to include: an empty one is
//! an include of no model, which the simulator cannot resolve. `name` becomes the
//! instance's name in the world, and Gazebo requires every model to have a unique,
//! non-empty name.
//! traffic_editor refuses empty names in its model dialog.
//!
//! **Fix:** set `model_name` to the model to include (e.g. `OpenRobotics/Chair`) and
//! `name` to a unique instance name.
//!
//! **Example:**
//! ```yaml
//! models:
//!   - {name: "", model_name: OpenRobotics/Chair, x: 2, y: 3, yaw: 0, z: 0, static: true}   # E0609
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0609",
    name: "empty-model-name",
    summary: "a model's name or model_name is empty",
    group: Group::WorldGeometry,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    for (h, model) in b.models.iter() {
        let what = match (model.name.is_empty(), model.model_name.is_empty()) {
            (false, false) => continue,
            (true, true) => "both its `name` and its `model_name` are empty".to_string(),
            (true, false) => format!("its `name` is empty (model_name `{}`)", model.model_name),
            (false, true) => format!("its `model_name` is empty (name `{}`)", model.name),
        };
        out.push(
            Diagnostic::error(
                RULE.code,
                b.models.span(h),
                format!(
                    "model at ({}, {}) on level `{}`: {what}",
                    model.raw.x,
                    model.raw.y,
                    ctx.level_name(model.level)
                ),
            )
            .with_help("set `model_name` to the Gazebo model to include and `name` to a unique instance name"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::{Model, Span, Vec2};

    fn model(m: &mut TestMap, name: &str, model_name: &str) {
        let level = m.level;
        let h = m.b.models.append(
            Model {
                level,
                name: name.into(),
                model_name: model_name.into(),
                pos: Vec2::default(),
                raw: Vec2::default(),
                z: 0.0,
                yaw: 0.0,
                is_static: true,
                dispensable: false,
            },
            Span::UNKNOWN,
        );
        m.b.levels[level].models.push(h);
    }

    #[test]
    fn finds_empty_names() {
        let mut m = TestMap::new();
        model(&mut m, "chair", "OpenRobotics/Chair");
        model(&mut m, "", "OpenRobotics/Chair");
        model(&mut m, "chair2", "");
        model(&mut m, "", "");
        assert_eq!(codes_of(&m.b).iter().filter(|c| **c == "E0609").count(), 3);
    }
}
