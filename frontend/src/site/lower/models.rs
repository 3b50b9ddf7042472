//! Model instances, placed as the IR's models.

use super::*;

impl<'d, 'n, 's> SiteLower<'d, 'n, 's> {
    pub(super) fn models(&mut self, root: &Node, b: &mut Building, shift: Vec2) {
        let mut descs: HashMap<u32, (String, bool)> = HashMap::new();
        for (id, d, _) in self.entries(root, "model_descriptions", "the site") {
            let src = d
                .get("source")
                .and_then(variant)
                .and_then(|(_, v)| v?.key_text().map(str::to_string));
            let is_static = d
                .get("is_static")
                .and_then(|s| s.as_bool())
                .unwrap_or(false);
            descs.insert(id, (src.unwrap_or_default(), is_static));
        }
        let mut poses: HashMap<u32, (Vec2, f64)> = HashMap::new();
        for (id, m, span) in self.entries(root, "model_instances", "the site") {
            self.unknown(
                m,
                &["parent", "name", "pose", "description"],
                "a model instance",
            );
            let Some(parent) = m.get("parent").and_then(ref_of) else {
                continue;
            };
            let Some(&lh) = self.levels.get(&parent) else {
                // Models on other parents (robots, workcells) are not level furniture.
                let at = m.get("parent").map_or(span, |p| p.span);
                self.l.warn(
                    "W0121",
                    at,
                    format!("model instance on parent {parent}, which is not a level; mapc places only the models of levels, it is ignored"),
                    "nothing to do unless a world should have it: put it on a level",
                );
                continue;
            };
            let name = self.name(m, "a model");
            let (t, yaw) = self.pose(m.get("pose"));
            poses.insert(id, (t, yaw));
            let z = m
                .get("pose")
                .and_then(|p| p.get("trans"))
                .and_then(|t| t.as_seq())
                .and_then(|s| s.get(2))
                .and_then(|z| z.as_f64())
                .unwrap_or(0.0);
            let (model_name, is_static) = m
                .get("description")
                .and_then(ref_of)
                .and_then(|d| descs.get(&d).cloned())
                .unwrap_or_else(|| (name.clone(), true));
            let pos = t.plus(shift);
            let raw = if b.coordinate_system == CoordinateSystem::ReferenceImage {
                let kept = ext_point(
                    self.ext
                        .and_then(|e| e.get("models"))
                        .and_then(|e| e.get(&id.to_string()))
                        .and_then(|e| e.get("raw")),
                );
                self.pixel_raw(b, lh, pos, kept)
            } else {
                t
            };
            let h = b.models.append(
                Model {
                    level: lh,
                    name,
                    model_name,
                    pos,
                    raw,
                    z,
                    yaw,
                    is_static,
                    dispensable: false,
                },
                span,
            );
            b.levels[lh].models.push(h);
        }
        // rmf_site's scenarios may move or hide instances (its import repeats every
        // instance's own pose there); mapc places each where the instance says.
        for (_, sc, _) in self.entries(root, "scenarios", "the site") {
            let sname = self.name(sc, "a scenario");
            for (iid, modifier, mspan) in self.entries(sc, "instances", "a scenario") {
                let hidden = modifier
                    .get("inclusion")
                    .and_then(|i| i.key_text())
                    .is_some_and(|i| i == "Hidden");
                let moved = match (modifier.get("pose"), poses.get(&iid)) {
                    (Some(p), Some(&(t, yaw))) => {
                        let (t2, yaw2) = self.pose(Some(p));
                        t2.minus(t).norm() > 1e-3 || (yaw2 - yaw).sin().abs() > 1e-4
                    }
                    _ => false,
                };
                if hidden || moved {
                    self.l.warn(
                        "W0121",
                        mspan,
                        format!(
                            "scenario `{sname}` {} model instance {iid}; mapc places it where the instance says",
                            if hidden { "hides" } else { "moves" }
                        ),
                        "nothing to do unless the world should follow the scenario",
                    );
                }
            }
        }
    }
}
