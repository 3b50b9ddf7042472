//! A level: its keys, elements in file order (so later elements keep their file indices
//! when one is dropped), its layers and features.

use super::*;

impl Lower<'_> {
    pub(crate) fn level<'s>(
        &mut self,
        b: &mut Building,
        name: &str,
        node: &mut Node<'s>,
        span: Span,
        lists: &Lists<'s>,
    ) {
        let what = format!("level `{name}`");
        let Some(entries) = self.map(node, &what) else {
            return;
        };
        self.unknown_keys(entries, LEVEL_KEYS, &what);
        let level = Level {
            name: name.to_string(),
            elevation: self.opt_f64(node, "elevation", &what, 0.0),
            drawing: node.get("drawing").and_then(|d| match d.as_map() {
                Some(_) => self.req_string(d, "filename", "the drawing"),
                None if d.is_null() => None,
                None => {
                    self.wrong_type(d, "`drawing`", "a mapping with `filename`");
                    None
                }
            }),
            x_meters: node.get("x_meters").and_then(|n| self.f64(n, "`x_meters`")),
            y_meters: node.get("y_meters").and_then(|n| self.f64(n, "`y_meters`")),
            ..Level::default()
        };
        let lh = b.levels.append(level, span);

        // Vertices first: every other element indexes them, by position in the file.
        let mut slots: Vec<Option<Handle<Vertex>>> = Vec::new();
        if let Some(vs) = node.get_mut("vertices").map(Node::take) {
            let len = match self.seq(&vs, &format!("the vertices of {what}")) {
                Some(_) => lists.len(&vs),
                None => 0,
            };
            slots.reserve_exact(len);
            b.vertices.reserve(len);
            // By value: each vertex's subtree is freed once lowered.
            for v in lists.items(vs) {
                let h = self.vertex(lh, &v).map(|vx| {
                    let h = b.vertices.append(vx, v.span);
                    b.levels[lh].vertices.push(h);
                    h
                });
                slots.push(h);
            }
        }
        let slots = &slots[..];

        let len = |node: &Node<'s>, key: &str| node.get(key).map_or(0, |l| lists.len(l));
        b.lanes.reserve(len(node, "lanes"));
        let edges = EdgeList {
            level: lh,
            slots,
            what: &what,
            lists,
        };
        edges.each(self, b, node, "lanes", |l, b, e| {
            let span = e.span;
            if let Some(lane) = l.lane(lh, e) {
                let h = b.lanes.append(lane, span);
                b.levels[lh].lanes.push(h);
            }
        });
        edges.each(self, b, node, "walls", |_, b, e| {
            let h = b.walls.append(
                Wall {
                    level: lh,
                    start: e.start,
                    end: e.end,
                    params: e.params,
                },
                e.span,
            );
            b.levels[lh].walls.push(h);
        });
        edges.each(self, b, node, "measurements", |l, b, e| {
            let (params, span) = (&e.params, e.span);
            let distance = match params.get("distance") {
                Some(v) => match v.as_f64() {
                    Some(d) => d,
                    None => {
                        l.err(
                            "E0105",
                            params.param("distance").map_or(span, |p| p.span),
                            "measurement `distance` must be a number",
                            "write `distance: [3, <metres>]`",
                        );
                        return;
                    }
                },
                // Present but malformed: already reported.
                None if e.is_invalid("distance") => return,
                None => {
                    l.err(
                        "E0102",
                        span,
                        "measurement has no `distance` parameter",
                        "add `distance: [3, <metres>]` to the measurement",
                    );
                    return;
                }
            };
            let h = b.measurements.append(
                Measurement {
                    level: lh,
                    start: e.start,
                    end: e.end,
                    distance,
                    params: e.params,
                },
                span,
            );
            b.levels[lh].measurements.push(h);
        });
        edges.each(self, b, node, "doors", |l, b, e| {
            let span = e.span;
            if let Some(door) = l.door(lh, e) {
                let h = b.doors.append(door, span);
                b.levels[lh].doors.push(h);
            }
        });
        edges.each(self, b, node, "human_lanes", |_, b, e| {
            let h = b.human_lanes.append(
                HumanLane {
                    level: lh,
                    start: e.start,
                    end: e.end,
                    params: e.params,
                },
                e.span,
            );
            b.levels[lh].human_lanes.push(h);
        });

        for (key, is_floor) in [("floors", true), ("holes", false)] {
            let Some(list) = node.get(key) else { continue };
            for p in self
                .seq(list, &format!("the {key} of {what}"))
                .unwrap_or(&[])
            {
                let Some(poly) = self.polygon(b, lh, p, key, slots) else {
                    continue;
                };
                if is_floor {
                    let h = b.floors.append(poly, p.span);
                    b.levels[lh].floors.push(h);
                } else {
                    let h = b.holes.append(poly, p.span);
                    b.levels[lh].holes.push(h);
                }
            }
        }

        if let Some(list) = node.get("models") {
            for m in self
                .seq(list, &format!("the models of {what}"))
                .unwrap_or(&[])
            {
                if let Some(model) = self.model(lh, m) {
                    let h = b.models.append(model, m.span);
                    b.levels[lh].models.push(h);
                }
            }
        }
        if let Some(list) = node.get("fiducials") {
            for f in self
                .seq(list, &format!("the fiducials of {what}"))
                .unwrap_or(&[])
            {
                if let Some(fid) = self.fiducial(lh, f) {
                    let h = b.fiducials.append(fid, f.span);
                    b.levels[lh].fiducials.push(h);
                }
            }
        }
        if let Some(list) = node.get("features") {
            let feats = self.features(list, &what);
            b.levels[lh].features = feats;
        }
        if let Some(list) = node.get("constraints") {
            for c in self
                .seq(list, &format!("the constraints of {what}"))
                .unwrap_or(&[])
            {
                let ids = c
                    .get("ids")
                    .and_then(|i| self.seq(i, "constraint `ids`"))
                    .unwrap_or(&[])
                    .iter()
                    .filter_map(|i| self.string(i, "a constraint id"))
                    .collect();
                b.levels[lh]
                    .constraints
                    .push(Constraint { ids, span: c.span });
            }
        }
        if let Some(layers) = node.get("layers") {
            for (k, v) in self
                .map(layers, &format!("the layers of {what}"))
                .unwrap_or(&[])
            {
                let lname = k.key_text().unwrap_or_default().to_string();
                if let Some(layer) = self.layer(lname, v) {
                    b.levels[lh].layers.push(layer);
                }
            }
        }
    }

    pub(super) fn features(&mut self, list: &Node, what: &str) -> Vec<Feature> {
        let mut out = Vec::new();
        for f in self
            .seq(list, &format!("the features of {what}"))
            .unwrap_or(&[])
        {
            if f.as_map().is_none() {
                self.wrong_type(f, "a feature", "a mapping `{x, y, name, id}`");
                continue;
            }
            let x = self.req_f64(f, "x", "a feature");
            let y = self.req_f64(f, "y", "a feature");
            let (Some(x), Some(y)) = (x, y) else { continue };
            out.push(Feature {
                id: self.opt_string(f, "id", "a feature"),
                name: self.opt_string(f, "name", "a feature"),
                raw: Vec2::new(x, y),
                span: f.span,
            });
        }
        out
    }

    pub(super) fn layer(&mut self, name: String, node: &Node) -> Option<Layer> {
        if node.as_map().is_none() {
            self.wrong_type(node, "a layer", "a mapping");
            return None;
        }
        let what = "a layer";
        let t = node.get("transform");
        let (yaw, scale, translation) = match t {
            Some(t) => {
                let tx = t.get("translation_x").or(t.get("translation_lon"));
                let ty = t.get("translation_y").or(t.get("translation_lat"));
                (
                    self.opt_f64(t, "yaw", "the layer transform", 0.0),
                    self.opt_f64(t, "scale", "the layer transform", 1.0),
                    Vec2::new(
                        tx.and_then(|n| self.f64(n, "a layer translation"))
                            .unwrap_or(0.0),
                        ty.and_then(|n| self.f64(n, "a layer translation"))
                            .unwrap_or(0.0),
                    ),
                )
            }
            // Legacy keys (before 2021-02).
            None => (
                self.opt_f64(node, "rotation", what, 0.0),
                self.opt_f64(node, "meters_per_pixel", what, 1.0),
                Vec2::new(
                    self.opt_f64(node, "translation_x", what, 0.0),
                    self.opt_f64(node, "translation_y", what, 0.0),
                ),
            ),
        };
        let mut color = [0.0, 0.0, 1.0, 0.5];
        if let Some(c) = node.get("color") {
            if let Some(items) = self.seq(c, "layer `color`") {
                for (slot, item) in color.iter_mut().zip(items) {
                    if let Some(v) = self.f64(item, "a layer colour component") {
                        *slot = v;
                    }
                }
            }
        }
        Some(Layer {
            name,
            filename: self.opt_string(node, "filename", what),
            visible: self.opt_bool(node, "visible", what, true),
            color,
            yaw,
            scale,
            translation,
            features: node
                .get("features")
                .map(|f| self.features(f, what))
                .unwrap_or_default(),
            span: node.span,
        })
    }
}
