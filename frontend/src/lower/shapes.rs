//! Floors, holes, walls' polygons, models and fiducials.

use super::*;

impl Lower<'_> {
    pub(super) fn polygon(
        &mut self,
        b: &Building,
        level: Handle<Level>,
        node: &Node,
        key: &str,
        slots: &VertexSlots,
    ) -> Option<Polygon> {
        if node.as_map().is_none() {
            self.wrong_type(
                node,
                &format!("an entry of `{key}`"),
                "a mapping `{vertices: [...], parameters: {...}}`",
            );
            return None;
        }
        let list = self.require(node, "vertices", &format!("an entry of `{key}`"))?;
        let mut vertices = Vec::new();
        let mut ok = true;
        for i in self.seq(list, "polygon `vertices`")? {
            match self.vertex_index(b, level, i, slots) {
                Some(h) => vertices.push(h),
                None => ok = false,
            }
        }
        let params = match node.get("parameters") {
            Some(p) => self.params(p, format_args!("an entry of `{key}`")),
            None => Params::default(),
        };
        ok.then_some(Polygon {
            level,
            vertices,
            params,
        })
    }

    pub(super) fn model(&mut self, level: Handle<Level>, node: &Node) -> Option<Model> {
        if node.as_map().is_none() {
            self.wrong_type(node, "a model", "a mapping");
            return None;
        }
        let what = "a model";
        let name = self.req_string(node, "name", what);
        let model_name = self.req_string(node, "model_name", what);
        let x = self.req_f64(node, "x", what);
        let y = self.req_f64(node, "y", what);
        let yaw = self.req_f64(node, "yaw", what);
        let raw = Vec2::new(x?, y?);
        Some(Model {
            level,
            name: name?,
            model_name: model_name?,
            pos: raw,
            raw,
            z: self.opt_f64(node, "z", what, 0.0),
            yaw: yaw?,
            is_static: self.opt_bool(node, "static", what, true),
            dispensable: self.opt_bool(node, "dispensable", what, false),
        })
    }

    pub(super) fn fiducial(&mut self, level: Handle<Level>, node: &Node) -> Option<Fiducial> {
        let Some(items) = node.as_seq().filter(|s| s.len() >= 3) else {
            self.wrong_type(node, "a fiducial", "a sequence `[x, y, name]`");
            return None;
        };
        let raw = self.coord_pair(&items[0], &items[1], "a fiducial")?;
        let name = self.string(&items[2], "a fiducial name")?;
        Some(Fiducial {
            level,
            name,
            raw,
            pos: raw,
        })
    }
}
