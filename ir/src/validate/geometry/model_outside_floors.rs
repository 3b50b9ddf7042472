//! # W0608 model-outside-floors
//!
//! **What:** a model's position is outside every floor polygon of its level (checked
//! only on levels that have floors).
//!
//! **Why it matters:** the model stands on nothing: in simulation it falls (if dynamic)
//! or floats beside the building, and a dispensable item placed there cannot be reached
//! by robots. It usually means the model was placed on the wrong level, or its
//! coordinates are in the wrong units.
//!
//! **Fix:** move the model onto a floor, put it on the right level, or extend the floor
//! polygon under it. Outdoor scenery outside the building's floors can keep the warning.
//!
//! **Example:**
//! ```yaml
//! floors:
//!   - {vertices: [0, 1, 2, 3], parameters: {}}   # a 10 m square at the origin
//! models:
//!   - {name: chair, model_name: OpenRobotics/Chair, x: 25, y: 3, yaw: 0, z: 0, static: true}   # W0608
//! ```

use super::shapes::{bbox, distinct_vertices, point_in_polygon, ring};
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Vec2};

pub(crate) static RULE: Rule = Rule {
    code: "W0608",
    name: "model-outside-floors",
    summary: "a model stands outside every floor of its level",
    group: Group::WorldGeometry,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    for (_, level) in b.levels.iter() {
        if level.floors.is_empty() || level.models.is_empty() {
            continue;
        }
        let floors: Vec<(Vec<Vec2>, (Vec2, Vec2))> = level
            .floors
            .iter()
            .map(|&f| &b.floors[f])
            .filter(|f| distinct_vertices(f) >= 3)
            .map(|f| {
                let pts = ring(b, f).0;
                let bb = bbox(&pts);
                (pts, bb)
            })
            .collect();
        if floors.is_empty() {
            continue;
        }
        let mut grid =
            crate::validate::grid::BoxGrid::new(&floors.iter().map(|f| f.1).collect::<Vec<_>>());
        for &mh in &level.models {
            let model = &b.models[mh];
            let p = model.pos;
            let on_floor = grid.candidates(p, p).into_iter().any(|i| {
                let (pts, (lo, hi)) = &floors[i as usize];
                p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && point_in_polygon(p, pts)
            });
            if !on_floor {
                out.push(
                    Diagnostic::warning(
                        RULE.code,
                        b.models.span(mh),
                        format!(
                            "model `{}` ({}) at ({}, {}) on level `{}` is outside every floor of the level",
                            model.name, model.model_name, model.raw.x, model.raw.y, level.name
                        ),
                    )
                    .with_help("move the model onto a floor or onto the right level, or extend the floor under it"),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::{Model, Span, Vec2};

    fn model(m: &mut TestMap, x: f64, y: f64) {
        let level = m.level;
        let h = m.b.models.append(
            Model {
                level,
                name: "chair".into(),
                model_name: "OpenRobotics/Chair".into(),
                pos: Vec2::new(x, y),
                raw: Vec2::new(x, y),
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
    fn models_must_stand_on_a_floor() {
        let mut m = TestMap::new();
        model(&mut m, 25.0, 3.0); // no floors yet: not checked
        assert!(!codes_of(&m.b).contains(&"W0608"));
        let f =
            [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)].map(|(x, y)| m.vertex("", x, y));
        m.floor(&f);
        model(&mut m, 5.0, 5.0);
        model(&mut m, 10.0, 5.0); // on the edge
        assert_eq!(codes_of(&m.b).iter().filter(|c| **c == "W0608").count(), 1);
    }
}
