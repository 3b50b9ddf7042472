//! Lifts: cabins, their doors and anchors, and the levels they serve.

use super::*;

impl<'d, 'n, 's> SiteLower<'d, 'n, 's> {
    pub(super) fn lifts(&mut self, root: &Node, b: &mut Building, shift: Vec2, ext: Option<&Node>) {
        for (id, v, span) in self.entries(root, "lifts", "the site") {
            self.unknown(v, &["cabin_doors", "properties", "cabin_anchors"], "a lift");
            if let Some(p) = v.get("properties") {
                self.unknown(
                    p,
                    &[
                        "name",
                        "reference_anchors",
                        "cabin",
                        "is_static",
                        "initial_level",
                    ],
                    "lift properties",
                );
            }
            let idx = self.lift_handles.len();
            self.lift_handles.push(None);
            let props = v.get("properties");
            let name = props.map(|p| self.name(p, "a lift")).unwrap_or_default();
            let what = format!("lift `{name}`");
            let refs: Vec<u32> = props
                .and_then(|p| p.get("reference_anchors"))
                .and_then(|r| r.as_seq())
                .map(|s| s.iter().filter_map(ref_of).collect())
                .unwrap_or_default();
            let cabin = props
                .and_then(|p| p.get("cabin"))
                .and_then(|c| c.get("Rect"));
            let (Some(cabin), &[l, r]) = (cabin, &refs[..]) else {
                self.l.err(
                    "E0102",
                    span,
                    format!("{what} needs `reference_anchors` and a `Rect` cabin"),
                    "rmf_site writes both for every lift",
                );
                continue;
            };
            let pos_of = |s: &Self, id: u32| match s.anchors.get(&id) {
                Some(Anchor::Site(p, _)) => Some(*p),
                Some(Anchor::Level(_, vh)) => Some(b.vertices[*vh].pos),
                _ => None,
            };
            let (Some(pl), Some(pr)) = (pos_of(self, l), pos_of(self, r)) else {
                let bad = if pos_of(self, l).is_none() { l } else { r };
                self.dangling(span, &format!("{what}'s reference_anchors"), bad);
                continue;
            };
            // Site cabin width is the legacy depth and vice versa (rmf_site turned the
            // cabin axes).
            let num =
                |n: Option<&Node>, default: f64| n.and_then(|v| v.as_f64()).unwrap_or(default);
            let site_w = num(cabin.get("width"), 1.5);
            let site_d = num(cabin.get("depth"), 1.65);
            let (width, depth) = (site_d, site_w);
            let wall = num(cabin.get("wall_thickness"), CABIN_WALL);
            let cabin_gap = num(cabin.get("gap"), CABIN_GAP);
            let front_door = num(
                cabin.get("front_door").and_then(|d| d.get("thickness")),
                CABIN_DOOR,
            );
            // The editor's lift frame: at the middle of the reference anchors, x towards
            // the front; the cabin centre is behind it by half the cabin, its wall, the
            // gap and half the front door, and `shift` to the side
            // (`RectangularLiftCabin::aabb`). Cabin anchors are in the cabin's frame.
            let lr = pl.minus(pr);
            let yaw: f64 = (-lr.x).atan2(lr.y) + 0.0;
            let mid = pl.plus(pr).scale(0.5);
            let behind = width / 2.0 + wall + cabin_gap + front_door / 2.0;
            let shift_y = num(cabin.get("shift"), 0.0);
            let mut pos = mid.plus(Vec2::new(-behind, shift_y).rotate(yaw));
            if !(pos.is_finite() && width.is_finite() && depth.is_finite()) {
                // Each number may be finite and their sum not (1e308 twice).
                self.l.err(
                    "E0102",
                    span,
                    format!("{what}'s cabin does not fit in numbers: its size, wall, gap or shift is too large"),
                    "give the cabin a size in metres",
                );
                continue;
            }
            let mut yaw = yaw;
            let lx = ext
                .and_then(|e| e.get("lifts"))
                .and_then(|l| l.get(&id.to_string()));
            if let (Some(x), Some(y), Some(w)) = (
                lx.and_then(|e| e.get("x")).and_then(|v| v.as_f64()),
                lx.and_then(|e| e.get("y")).and_then(|v| v.as_f64()),
                lx.and_then(|e| e.get("yaw")).and_then(|v| v.as_f64()),
            ) {
                // Written by mapc: the exact values, free of the anchors' rounding, unless
                // the lift has been moved or turned since (in rmf_site, which keeps f32).
                let exact = Vec2::new(x, y);
                let turned = (w - yaw).sin().abs() > 1e-4 || (w - yaw).cos() < 0.0;
                if exact.minus(pos).norm() < 1e-3 && !turned {
                    pos = exact;
                    yaw = w;
                }
            }
            let initial_level = props
                .and_then(|p| p.get("initial_level"))
                .and_then(ref_of)
                .and_then(|l| self.levels.get(&l).copied());
            let lext = ext
                .and_then(|e| e.get("lifts"))
                .and_then(|l| l.get(&id.to_string()));
            let level_opt = |s: &Self, key: &str| {
                lext.and_then(|e| e.get(key))
                    .and_then(|n| n.key_text())
                    .and_then(|n| b.level_by_name(n))
                    .or_else(|| {
                        let _ = s;
                        None
                    })
            };
            let lowest_level = level_opt(self, "lowest_floor");
            let highest_level = level_opt(self, "highest_floor");
            let plugins = lext
                .and_then(|e| e.get("plugins"))
                .and_then(|p| p.as_bool())
                .unwrap_or(true);
            let mut doors = Vec::new();
            let mut level_doors: BTreeMap<Handle<Level>, Vec<(String, Span)>> = BTreeMap::new();
            let hx = width / 2.0;
            let hy = depth / 2.0;
            for (did, d, dspan) in self.entries(v, "cabin_doors", &what) {
                let dext = lext
                    .and_then(|e| e.get("doors"))
                    .and_then(|e| e.get(&did.to_string()));
                let dname = dext
                    .and_then(|e| e.get("name"))
                    .and_then(|n| n.key_text())
                    .map_or_else(|| format!("{name}_door{}", doors.len() + 1), str::to_string);
                // Which face holds the door, and where on it.
                let mut placed = None;
                for face in ["front_door", "back_door", "left_door", "right_door"] {
                    let Some(p) = cabin.get(face) else { continue };
                    if p.get("door").and_then(ref_of) != Some(did) {
                        continue;
                    }
                    let w = num(p.get("width"), 1.0);
                    let sh = num(p.get("shifted"), 0.0);
                    // The door's centre is past the cabin wall, the gap and half the
                    // door (`level_door_anchors`).
                    let gap = num(p.get("custom_gap"), cabin_gap)
                        + wall
                        + num(p.get("thickness"), CABIN_DOOR) / 2.0;
                    let (dx, dy, mao) = match face {
                        "front_door" => (gap + hx, sh, std::f64::consts::FRAC_PI_2),
                        "back_door" => (-(gap + hx), -sh, std::f64::consts::FRAC_PI_2),
                        "left_door" => (-sh, gap + hy, 0.0),
                        _ => (sh, -(gap + hy), 0.0),
                    };
                    if !(dx.is_finite() && dy.is_finite() && w.is_finite()) {
                        self.l.err(
                            "E0102",
                            dspan,
                            format!("cabin door {did} of {what} does not fit in numbers: its width, gap or shift is too large"),
                            "give the door a width and gap in metres",
                        );
                        continue;
                    }
                    placed = Some((Vec2::new(dx, dy), w, mao));
                }
                let Some((dpos, dw, mao)) = placed else {
                    self.l.err(
                        "E0121",
                        dspan,
                        format!("cabin door {did} of {what} is on no face of the cabin"),
                        "place the door on a face of the cabin in rmf_site",
                    );
                    continue;
                };
                let door_type = match (
                    dext.and_then(|e| e.get("door_type"))
                        .and_then(|t| t.as_i64()),
                    d.get("kind").and_then(variant),
                ) {
                    (Some(t), _) => t,
                    (None, Some(("DoubleSliding", _))) => 2,
                    _ => 1,
                };
                let mao = dext
                    .and_then(|e| e.get("motion_axis_orientation"))
                    .and_then(|t| t.as_f64())
                    .unwrap_or(mao);
                // mapc's exact door position, free of the gap's rounding, while the door
                // has not been moved in rmf_site.
                let exact = |k: &str| dext.and_then(|e| e.get(k)).and_then(|v| v.as_f64());
                let dpos = match (exact("x"), exact("y")) {
                    (Some(x), Some(y)) if Vec2::new(x, y).minus(dpos).norm() < 1e-3 => {
                        Vec2::new(x, y)
                    }
                    _ => dpos,
                };
                for lv in d.get("visits").and_then(|v| v.as_seq()).unwrap_or(&[]) {
                    match ref_of(lv).and_then(|l| self.levels.get(&l).copied()) {
                        Some(lh) => level_doors
                            .entry(lh)
                            .or_default()
                            .push((dname.clone(), lv.span)),
                        None => self.dangling(
                            lv.span,
                            &format!("a cabin door of {what}"),
                            ref_of(lv).unwrap_or(0),
                        ),
                    }
                }
                doors.push(LiftDoor {
                    name: dname,
                    door_type,
                    pos: dpos,
                    width: dw,
                    motion_axis_orientation: mao,
                    span: dspan,
                });
            }
            let door_anchors: Vec<u32> = v
                .get("cabin_doors")
                .and_then(|d| d.as_map())
                .unwrap_or(&[])
                .iter()
                .flat_map(|(_, d)| {
                    d.get("reference_anchors")
                        .and_then(|r| r.as_seq())
                        .unwrap_or(&[])
                })
                .filter_map(ref_of)
                .collect();
            for (aid, a, aspan) in self.entries(v, "cabin_anchors", &what) {
                let Some(p) = self.anchor_pos(a) else {
                    continue;
                };
                if !door_anchors.contains(&aid)
                    && (p.x.abs() > width / 2.0 + 1e-6 || p.y.abs() > depth / 2.0 + 1e-6)
                {
                    self.l.warn(
                        "W0120",
                        aspan,
                        format!("cabin anchor {aid} of {what} at ({}, {}) is outside the {width} × {depth} m cabin", p.x, p.y),
                        "move the anchor into the cabin or make it a level anchor",
                    );
                }
                self.anchors.insert(aid, Anchor::Cabin(idx, p));
            }
            let reference_level = level_opt(self, "reference_floor")
                .or(initial_level)
                .or_else(|| level_doors.keys().next().copied())
                .unwrap_or(b.reference_level);
            let raw = if b.coordinate_system == CoordinateSystem::ReferenceImage {
                let kept = ext_point(lext.and_then(|e| e.get("raw")));
                self.pixel_raw(b, reference_level, pos, kept)
            } else {
                pos.minus(shift)
            };
            let lift = Lift {
                name,
                pos,
                raw,
                yaw,
                width,
                depth,
                reference_level,
                initial_level,
                lowest_level,
                highest_level,
                plugins,
                doors,
                level_doors: level_doors
                    .into_iter()
                    .map(|(level, doors)| LevelDoors { level, doors, span })
                    .collect(),
            };
            let h = b.lifts.append(lift, span);
            self.lift_handles[idx] = Some(h);
        }
    }

    /// The vertex of anchor `id` on level `lh` (for a cabin anchor: made on first use).
    pub(super) fn cabin_vertex(
        &mut self,
        b: &mut Building,
        id: u32,
        lift: usize,
        p: Vec2,
        lh: Handle<Level>,
        span: Span,
    ) -> Option<Handle<Vertex>> {
        if let Some(v) = self.cabin_vertices.get(&(id, lh)) {
            return Some(*v);
        }
        let l = &b.lifts[self.lift_handles.get(lift).copied().flatten()?];
        let exact = self
            .ext
            .and_then(|e| e.get("cabin_positions"))
            .and_then(|c| c.get(&id.to_string()))
            .and_then(|c| c.get(&b.levels[lh].name))
            .and_then(|p| p.as_seq())
            .and_then(|s| Some(Vec2::new(s.first()?.as_f64()?, s.get(1)?.as_f64()?)));
        let pos = exact.unwrap_or_else(|| p.rotate(l.yaw).plus(l.pos));
        let mut params = match self
            .ext
            .and_then(|e| e.get("vertices"))
            .and_then(|v| v.get(&id.to_string()))
        {
            Some(ps) => self.l.params(ps, "a vertex"),
            None => Params::default(),
        };
        let name = params.str("name").unwrap_or_default().to_string();
        params.0.retain(|p| p.name != "name");
        params.insert(Param {
            name: "lift_cabin".into(),
            value: ParamValue::String(l.name.clone()),
            span,
        });
        let raw = if b.coordinate_system == CoordinateSystem::ReferenceImage {
            let kept = self.ext_level_point("raw_vertices", lh, id);
            self.pixel_raw(b, lh, pos, kept)
        } else {
            p
        };
        let vh = b.vertices.append(
            Vertex {
                level: lh,
                name,
                pos,
                raw,
                params,
                roles: Default::default(),
            },
            span,
        );
        b.levels[lh].vertices.push(vh);
        self.cabin_vertices.insert((id, lh), vh);
        Some(vh)
    }
}
