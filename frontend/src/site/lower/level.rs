//! A level: its properties, drawings, floors, walls and doors, and what mapc's extension
//! keeps for it (measurements, floor holes, human lanes).

use super::*;

impl<'d, 'n, 's> SiteLower<'d, 'n, 's> {
    pub(super) fn level(
        &mut self,
        b: &mut Building,
        id: u32,
        node: &Node,
        span: Span,
        shift: Vec2,
        ext_vertices: Option<&Node>,
    ) {
        if self.l.map(node, "a level").is_none() {
            return;
        }
        self.unknown(node, LEVEL_KEYS, "a level");
        let props = node.get("properties");
        let name = props.map(|p| self.name(p, "a level")).unwrap_or_default();
        let elevation = props
            .and_then(|p| p.get("elevation"))
            .and_then(|e| self.l.f64(e, "the level elevation"))
            .unwrap_or(0.0);
        if let Some(p) = props {
            self.unknown(
                p,
                &[
                    "name",
                    "elevation",
                    "global_floor_visibility",
                    "global_drawing_visibility",
                ],
                "level properties",
            );
        }
        self.unused(node, UNUSED_LEVEL, &format!("level `{name}`"));
        let lh = b.levels.append(
            Level {
                name: name.clone(),
                elevation,
                ..Level::default()
            },
            span,
        );
        self.levels.insert(id, lh);
        self.level_ids.insert(lh, id);

        let mut level_anchors = Vec::new();
        for (aid, v, aspan) in self.entries(node, "anchors", "a level") {
            let Some(p) = self.anchor_pos(v) else {
                continue;
            };
            let mut params = Params::default();
            if let Some(ps) = ext_vertices.and_then(|e| e.get(&aid.to_string())) {
                params = self.l.params(ps, "a vertex");
            }
            let name = params.str("name").unwrap_or_default().to_string();
            params.0.retain(|p| p.name != "name");
            let vh = b.vertices.append(
                Vertex {
                    level: lh,
                    name,
                    pos: p.plus(shift),
                    raw: p,
                    params,
                    roles: Default::default(),
                },
                aspan,
            );
            b.levels[lh].vertices.push(vh);
            self.anchors.insert(aid, Anchor::Level(lh, vh));
            level_anchors.push((aid, vh));
        }

        // Drawings: the first names the level's drawing; their fiducials become the
        // level's fiducials, in metres.
        let mut first_drawing = true;
        for (_, d, _) in self.entries(node, "drawings", "a level") {
            self.unknown(
                d,
                &["properties", "anchors", "fiducials", "measurements"],
                "a drawing",
            );
            let dp = d.get("properties");
            if b.levels[lh].drawing.is_none() {
                let src = dp.and_then(|p| p.get("source")).and_then(variant);
                if let Some((_, Some(s))) = src {
                    b.levels[lh].drawing =
                        s.key_text().filter(|s| !s.is_empty()).map(str::to_string);
                }
            }
            let ppm = dp
                .and_then(|p| p.get("pixels_per_meter"))
                .and_then(|v| v.as_f64())
                .filter(|v| *v > 0.0)
                .unwrap_or(100.0);
            let pose = dp.and_then(|p| p.get("pose"));
            let (t, yaw) = self.pose(pose);
            let pixels = b.coordinate_system == CoordinateSystem::ReferenceImage;
            if pixels && first_drawing {
                // The level's reference image: its pose and scale are the level's
                // transform from pixels (y up) to the map frame.
                b.levels[lh].transform = LevelTransform {
                    scale: 1.0 / ppm,
                    rotation: yaw,
                    translation: t.plus(shift),
                };
            }
            first_drawing = false;
            let mut danchors = HashMap::new();
            for (aid, v, _) in self.entries(d, "anchors", "a drawing") {
                if let Some(p) = self.anchor_pos(v) {
                    danchors.insert(aid, p);
                }
            }
            for (_, f, fspan) in self.entries(d, "fiducials", "a drawing") {
                let Some(aid) = f.get("anchor").and_then(ref_of) else {
                    continue;
                };
                let Some(px) = danchors.get(&aid) else {
                    self.dangling(fspan, "a drawing fiducial", aid);
                    continue;
                };
                let fname = f
                    .get("affiliation")
                    .and_then(ref_of)
                    .map(|g| {
                        self.fiducial_groups
                            .get(&g)
                            .filter(|n| !n.is_empty())
                            .cloned()
                            .unwrap_or_else(|| format!("group_{g}"))
                    })
                    .unwrap_or_default();
                let pos = px.scale(1.0 / ppm).rotate(yaw).plus(t).plus(shift);
                let fh = b.fiducials.append(
                    Fiducial {
                        level: lh,
                        name: fname,
                        raw: if pixels { flip(*px) } else { *px },
                        pos,
                    },
                    fspan,
                );
                b.levels[lh].fiducials.push(fh);
            }
        }

        if b.coordinate_system == CoordinateSystem::ReferenceImage {
            for &(aid, vh) in &level_anchors {
                let kept = self.ext_level_point("raw_vertices", lh, aid);
                b.vertices[vh].raw = self.pixel_raw(b, lh, b.vertices[vh].pos, kept);
            }
        }
        self.measurements(b, lh, id);
        self.holes_and_human_lanes(b, lh, id);

        for (wid, w, wspan) in self.entries(node, "walls", "a level") {
            self.unknown(w, &["anchors", "texture"], "a wall");
            let Some((s, e)) = self.edge(b, w, wspan, lh, "a wall") else {
                continue;
            };
            let params = self.texture_params(w, wspan, wid);
            let h = b.walls.append(
                Wall {
                    level: lh,
                    start: s,
                    end: e,
                    params,
                },
                wspan,
            );
            b.levels[lh].walls.push(h);
        }
        for (did, d, dspan) in self.entries(node, "doors", "a level") {
            self.unknown(d, &["anchors", "name", "kind"], "a door");
            let Some((s, e)) = self.edge(b, d, dspan, lh, "a door") else {
                continue;
            };
            let dname = self.name(d, "a door");
            let mut door = self.door(d, lh, s, e, dname, did);
            if let Some(x) = self
                .ext
                .and_then(|e| e.get("doors"))
                .and_then(|m| m.get(&did.to_string()))
            {
                if let Some(t) = x.get("type").and_then(|t| t.key_text()) {
                    door.kind = DoorKind::parse(t);
                }
                if let Some(p) = x.get("plugin").and_then(|p| p.as_bool()) {
                    door.plugin = p;
                }
                if let Some(r) = x.get("right_left_ratio").and_then(|r| r.as_f64()) {
                    door.right_left_ratio = r;
                }
                if let Some(p) = x.get("params") {
                    door.params = self.l.params(p, "a door");
                }
            }
            let h = b.doors.append(door, dspan);
            b.levels[lh].doors.push(h);
        }
        for (fid, f, fspan) in self.entries(node, "floors", "a level") {
            self.unknown(
                f,
                &["anchors", "texture", "preferred_semi_transparency"],
                "a floor",
            );
            let Some(list) = f.get("anchors").and_then(|a| a.as_seq()) else {
                self.l
                    .wrong_type(f, "a floor's `anchors`", "a list of anchor ids");
                continue;
            };
            let mut vs = Vec::with_capacity(list.len());
            let mut ok = true;
            for a in list {
                let Some(id) = ref_of(a) else {
                    self.l.wrong_type(a, "an anchor id", "an unsigned integer");
                    ok = false;
                    continue;
                };
                match self.level_anchor(b, id, lh, a.span, "a floor") {
                    Some(v) => vs.push(v),
                    None => ok = false,
                }
            }
            if !ok {
                continue;
            }
            let params = self.texture_params(f, fspan, fid);
            let h = b.floors.append(
                Polygon {
                    level: lh,
                    vertices: vs,
                    params,
                },
                fspan,
            );
            b.levels[lh].floors.push(h);
        }
    }

    /// The measurements mapc's extension keeps for level `id`: `[start, end, params]`
    /// with anchors of that level (rmf_site's own are on drawing anchors, in f32, and
    /// only define the drawing's scale, which the level's transform already has).
    pub(super) fn measurements(&mut self, b: &mut Building, lh: Handle<Level>, id: u32) {
        let Some(list) = self
            .ext
            .and_then(|e| e.get("measurements"))
            .and_then(|m| m.get(&id.to_string()))
            .and_then(|m| m.as_seq())
        else {
            return;
        };
        for m in list {
            let s = m.as_seq().unwrap_or(&[]);
            let vertex =
                |n: Option<&Node>| match n.and_then(ref_of).and_then(|a| self.anchors.get(&a)) {
                    Some(Anchor::Level(l, v)) if *l == lh => Some(*v),
                    _ => None,
                };
            let (Some(start), Some(end), Some(p)) = (vertex(s.first()), vertex(s.get(1)), s.get(2))
            else {
                self.l.warn(
                    "W0121",
                    m.span,
                    "mapc's extension data has a measurement that is not [start anchor, end anchor, parameters] of this level; it is ignored",
                    "re-convert the site from its .building.yaml",
                );
                continue;
            };
            let params = self.l.params(p, "a measurement");
            let distance = params.f64("distance").unwrap_or(0.0);
            let h = b.measurements.append(
                Measurement {
                    level: lh,
                    start,
                    end,
                    distance,
                    params,
                },
                m.span,
            );
            b.levels[lh].measurements.push(h);
        }
    }

    /// The floor holes and human lanes mapc's extension keeps for level `id` (rmf_site has
    /// neither): `[[anchors...], params]` and `[start, end, params]`.
    pub(super) fn holes_and_human_lanes(&mut self, b: &mut Building, lh: Handle<Level>, id: u32) {
        let list = |key: &str| {
            self.ext
                .and_then(|e| e.get(key))
                .and_then(|m| m.get(&id.to_string()))
                .and_then(|m| m.as_seq())
                .unwrap_or(&[])
        };
        let vertex =
            |s: &Self, n: Option<&Node>| match n.and_then(ref_of).and_then(|a| s.anchors.get(&a)) {
                Some(Anchor::Level(l, v)) if *l == lh => Some(*v),
                _ => None,
            };
        for h in list("holes") {
            let s = h.as_seq().unwrap_or(&[]);
            let vs: Option<Vec<Handle<Vertex>>> = s
                .first()
                .and_then(|a| a.as_seq())
                .map(|a| a.iter().map(|n| vertex(self, Some(n))).collect())
                .unwrap_or(None);
            let (Some(vs), Some(p)) = (vs, s.get(1)) else {
                self.l.warn(
                    "W0121",
                    h.span,
                    "mapc's extension data has a hole that is not [[anchors of this level], parameters]; it is ignored",
                    "re-convert the site from its .building.yaml",
                );
                continue;
            };
            let params = self.l.params(p, "a hole");
            let hh = b.holes.append(
                Polygon {
                    level: lh,
                    vertices: vs,
                    params,
                },
                h.span,
            );
            b.levels[lh].holes.push(hh);
        }
        for h in list("human_lanes") {
            let s = h.as_seq().unwrap_or(&[]);
            let (Some(start), Some(end), Some(p)) =
                (vertex(self, s.first()), vertex(self, s.get(1)), s.get(2))
            else {
                self.l.warn(
                    "W0121",
                    h.span,
                    "mapc's extension data has a human lane that is not [start anchor, end anchor, parameters] of this level; it is ignored",
                    "re-convert the site from its .building.yaml",
                );
                continue;
            };
            let params = self.l.params(p, "a human lane");
            let hh = b.human_lanes.append(
                HumanLane {
                    level: lh,
                    start,
                    end,
                    params,
                },
                h.span,
            );
            b.levels[lh].human_lanes.push(hh);
        }
    }

    /// A wall's or floor's `texture` reference as the `texture_name` param the backends
    /// read (empty when it has none or it dangles).
    pub(super) fn texture_params(&mut self, n: &Node, span: Span, id: u32) -> Params {
        // mapc's extension keeps the rest of the parameters of a surface it wrote; the
        // texture is the site's (it may have been changed in rmf_site).
        let mut params = match self
            .ext
            .and_then(|e| e.get("surfaces"))
            .and_then(|e| e.get(&id.to_string()))
        {
            Some(p) => self.l.params(p, "a wall or floor"),
            None => Params::default(),
        };
        match n
            .get("texture")
            .and_then(ref_of)
            .and_then(|t| self.textures.get(&t))
        {
            Some(t) => params.insert(Param {
                name: "texture_name".into(),
                value: ParamValue::String(t.clone()),
                span,
            }),
            None => params.0.retain(|p| p.name != "texture_name"),
        }
        params
    }

    pub(super) fn door(
        &mut self,
        d: &Node,
        lh: Handle<Level>,
        s: Handle<Vertex>,
        e: Handle<Vertex>,
        name: String,
        did: u32,
    ) -> Door {
        let mut door = Door {
            level: lh,
            start: s,
            end: e,
            name,
            kind: DoorKind::Hinged,
            motion_axis: MotionAxis::Start,
            motion_direction: 1,
            motion_degrees: 90.0,
            right_left_ratio: 1.0,
            plugin: true,
            params: Params::default(),
        };
        let swing = |door: &mut Door, sw: Option<&Node>| {
            if let Some((dir, Some(a))) = sw.and_then(variant) {
                door.motion_direction = if dir == "Backward" { -1 } else { 1 };
                if let Some(r) = angle_rad(a) {
                    door.motion_degrees = r.to_degrees();
                }
            } else if let Some(("Both", Some(v))) = sw.and_then(variant) {
                if let Some(r) = v.get("forward").and_then(angle_rad) {
                    door.motion_degrees = r.to_degrees();
                }
            }
        };
        match d.get("kind").and_then(variant) {
            Some(("SingleSliding", v)) => {
                door.kind = DoorKind::Sliding;
                if v.and_then(|v| v.get("towards")).and_then(|t| t.key_text()) == Some("Right") {
                    door.motion_axis = MotionAxis::End;
                }
            }
            Some(("DoubleSliding", v)) => {
                door.kind = DoorKind::DoubleSliding;
                if let Some(r) = v
                    .and_then(|v| v.get("left_right_ratio"))
                    .and_then(|r| r.as_f64())
                {
                    door.right_left_ratio = if r > 0.0 { 1.0 / r } else { 1.0 };
                }
            }
            Some(("SingleSwing", v)) => {
                door.kind = DoorKind::Hinged;
                if v.and_then(|v| v.get("pivot_on")).and_then(|t| t.key_text()) == Some("Right") {
                    door.motion_axis = MotionAxis::End;
                }
                swing(&mut door, v.and_then(|v| v.get("swing")));
            }
            Some(("DoubleSwing", v)) => {
                door.kind = DoorKind::DoubleHinged;
                if let Some(r) = v
                    .and_then(|v| v.get("left_right_ratio"))
                    .and_then(|r| r.as_f64())
                {
                    door.right_left_ratio = if r > 0.0 { 1.0 / r } else { 1.0 };
                }
                swing(&mut door, v.and_then(|v| v.get("swing")));
            }
            Some((other, _)) => {
                door.kind = DoorKind::Other(other.to_string());
            }
            None => {
                self.l.err(
                    "E0102",
                    d.span,
                    "the door has no `kind`",
                    "give the door a kind such as SingleSwing",
                );
            }
        }
        let _ = did;
        door
    }
}
