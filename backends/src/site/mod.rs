//! The IR as an rmf_site `.site.json` (rmf_site_format 0.0.2, format "0.1").
//!
//! One site-wide id counter, assigned in IR order so that the numeric order of the ids is
//! the order of the map (rmf_site keeps its maps in `BTreeMap<u32, _>`). Positions are
//! the map frame less `Building::offset`, as rmf_site keeps sites near the origin. What a
//! site has no field for goes to `extensions.data.mapc` (read back by mapc's frontend, so a
//! round trip keeps it; rmf_site ignores it), and what cannot be said at all is a W0122
//! warning on the element. docs/sites.md lists both.

use mapc_ir::*;
use serde_json::{json, Map, Value};
use std::collections::{BTreeMap, HashMap};

/// Written `format_version`.
pub const FORMAT_VERSION: &str = "0.1";

/// rmf_site_format's defaults for a cabin with no `wall_thickness`, `gap` or door
/// `thickness`: its wall, the gap to the shaft and a door's thickness, metres.
const CABIN_WALL: f64 = 0.1;
const CABIN_GAP: f64 = 0.01;
const CABIN_DOOR: f64 = 0.05;
/// How far the reference anchors' line is in front of the cabin's front face.
const CABIN_FRONT: f64 = CABIN_WALL + CABIN_GAP + CABIN_DOOR / 2.0;

/// Graph colours, as rmf_site's `DEFAULT_NAV_GRAPH_COLORS`.
const COLORS: [[f64; 3]; 8] = [
    [1.0, 0.5, 0.3],
    [0.6, 1.0, 0.5],
    [0.6, 0.8, 1.0],
    [0.6, 0.2, 0.3],
    [0.1, 0.0, 1.0],
    [0.8, 0.4, 0.5],
    [0.9, 1.0, 0.0],
    [0.7, 0.5, 0.1],
];

struct Ids(u32);
impl Ids {
    fn next(&mut self) -> u32 {
        self.0 += 1;
        self.0
    }
}

fn key(id: u32) -> String {
    id.to_string()
}

fn param_json(v: &ParamValue) -> Value {
    match v {
        ParamValue::String(s) => json!([1, s]),
        ParamValue::Int(i) => json!([2, i]),
        ParamValue::Double(d) => json!([3, d]),
        ParamValue::Bool(b) => json!([4, b]),
    }
}

fn params_json(p: &Params) -> Value {
    Value::Object(
        p.iter()
            .map(|p| (p.name.clone(), param_json(&p.value)))
            .collect(),
    )
}

fn pt(p: Vec2) -> Value {
    json!([p.x, p.y])
}

fn warn(diags: &mut Vec<Diagnostic>, span: Span, msg: String) {
    diags.push(
        Diagnostic::warning("W0122", span, msg)
            .with_help("the .site.json written leaves this out; see docs/sites.md"),
    );
}

/// A wall's or floor's parameters besides its texture (alpha, texture scale, heights...):
/// rmf_site has a texture only, the level meshes need the rest.
fn surface_params(ext: &mut Map<String, Value>, id: u32, p: &Params) {
    if p.iter().any(|p| p.name != "texture_name") {
        ext.insert(key(id), params_json(p));
    }
}

/// The site document and the warnings about what it cannot hold.
pub fn site_json(b: &Building) -> (String, Vec<Diagnostic>) {
    let mut diags = Vec::new();
    let mut ids = Ids(0);
    let off = b.offset;
    let local = |p: Vec2| p.minus(off);

    let mut ext = Map::new();
    ext.insert(
        "coordinate_system".into(),
        json!(b.coordinate_system.as_str()),
    );
    if let Some(c) = &b.crs_name {
        ext.insert("crs_name".into(), json!(c));
    }
    ext.insert("offset".into(), pt(off));
    ext.insert(
        "reference_level".into(),
        json!(b.levels[b.reference_level].name),
    );
    // A reference_image map keeps its pixels: each level's drawing carries the level's
    // scale, rotation and translation (rmf_site's own reading of a reference image), and
    // the file coordinates of what was drawn on it go to the extension, so that the
    // `.building.yaml` written back is the original one, not a metre-for-pixel copy.
    let pixels = b.coordinate_system == CoordinateSystem::ReferenceImage;
    let flip = |p: Vec2| Vec2::new(p.x, -p.y);
    let mut ext_raw = Map::new();
    let mut ext_measurements = Map::new();
    let mut ext_surfaces = Map::new();
    let mut ext_holes = Map::new();
    let mut ext_human_lanes = Map::new();
    if !b.params.is_empty() {
        ext.insert("parameters".into(), params_json(&b.params));
    }
    if let Some(c) = &b.crowd_sim {
        warn(
            &mut diags,
            c.span,
            "rmf_site has no crowd simulation: only mapc's extension data keeps crowd_sim".into(),
        );
        ext.insert(
            "crowd_sim".into(),
            crate::crowd_doc::to_json(&crate::crowd_doc::crowd_sim(c)),
        );
    }
    for g in &b.graphs {
        if !g.name.is_empty() && g.name != g.index.to_string() {
            warn(
                &mut diags,
                b.spans.root,
                format!(
                    "graph {} is named `{}`; the site graph is named `{}` (its graph_idx)",
                    g.index, g.name, g.index
                ),
            );
        }
    }

    // Graphs: one per index used by a lane or declared, named by the index.
    let mut graph_idx: Vec<i64> = b.graph_indices();
    graph_idx.extend(b.graphs.iter().map(|g| g.index));
    graph_idx.sort_unstable();
    graph_idx.dedup();
    let mut graph_ids = BTreeMap::new();
    let mut graphs = Map::new();
    for (i, g) in graph_idx.iter().enumerate() {
        let id = ids.next();
        graph_ids.insert(*g, id);
        graphs.insert(
            key(id),
            json!({"name": g.to_string(), "color": COLORS[i % COLORS.len()]}),
        );
    }

    // Textures, by name.
    let mut textures = Map::new();
    let mut texture_ids: HashMap<String, u32> = HashMap::new();
    let mut texture = |name: Option<&str>, ids: &mut Ids| -> Value {
        let Some(name) = name.filter(|n| !n.is_empty()) else {
            return Value::Null;
        };
        let id = *texture_ids.entry(name.to_string()).or_insert_with(|| {
            let id = ids.next();
            textures.insert(
                key(id),
                json!({"name": name, "texture": {"source": {"Remote": format!("OpenRobotics/RMF_Materials/textures/{name}.png")}}}),
            );
            id
        });
        json!(id)
    };

    let mut mutex_ids: BTreeMap<String, u32> = BTreeMap::new();
    let mut mutex = |name: &Option<String>, ids: &mut Ids| -> Option<u32> {
        let n = name.as_ref().filter(|n| !n.is_empty())?;
        Some(*mutex_ids.entry(n.clone()).or_insert_with(|| ids.next()))
    };

    // Level ids first, so that lifts and models can name them.
    let level_ids: Vec<u32> = b.levels.iter().map(|_| ids.next()).collect();
    let mut anchor_of: HashMap<Handle<Vertex>, u32> = HashMap::new();
    let mut ext_vertices = Map::new();
    let mut cabin_positions: Map<String, Value> = Map::new();

    // Lift cabin vertices (the legacy `lift_cabin` parameter on a vertex inside the shaft)
    // become cabin anchors, one per lift and cabin position.
    let lift_by_name: HashMap<&str, Handle<Lift>> =
        b.lifts.iter().map(|(h, l)| (l.name.as_str(), h)).collect();
    let mut cabin_anchors: BTreeMap<Handle<Lift>, Vec<(u32, Vec2)>> = BTreeMap::new();
    let mut site_anchors = Map::new();
    let mut levels = Map::new();
    let mut fiducial_groups: BTreeMap<String, u32> = BTreeMap::new();
    for ((lh, level), &lid) in b.levels.iter().zip(&level_ids) {
        let mut anchors = Map::new();
        for &vh in &level.vertices {
            let v = &b.vertices[vh];
            let cabin = v
                .roles
                .lift_cabin
                .as_deref()
                .and_then(|n| lift_by_name.get(n).copied())
                .filter(|&l| b.lifts[l].shaft_contains(v.pos));
            let id = match cabin {
                Some(l) => {
                    let lift = &b.lifts[l];
                    let p = v.pos.minus(lift.pos).rotate(-lift.yaw);
                    let list = cabin_anchors.entry(l).or_default();
                    let id = match list.iter().find(|(_, q)| q.minus(p).norm() < 1e-6) {
                        Some((id, _)) => *id,
                        None => {
                            let id = ids.next();
                            list.push((id, p));
                            id
                        }
                    };
                    // The exact map position per level, so a round trip keeps it.
                    let e = cabin_positions
                        .entry(key(id))
                        .or_insert_with(|| Value::Object(Map::new()));
                    if let Value::Object(m) = e {
                        m.insert(level.name.clone(), pt(v.pos));
                    }
                    id
                }
                None => {
                    let id = ids.next();
                    anchors.insert(key(id), json!({"Translate2D": pt(local(v.pos))}));
                    id
                }
            };
            anchor_of.insert(vh, id);
            if pixels {
                let e = ext_raw
                    .entry(key(lid))
                    .or_insert_with(|| Value::Object(Map::new()));
                if let Value::Object(m) = e {
                    m.insert(key(id), pt(v.raw));
                }
            }
            let mut p = params_json(&v.params);
            if !v.name.is_empty() {
                if let Value::Object(m) = &mut p {
                    m.insert("name".into(), json!([1, v.name]));
                }
            }
            if p.as_object().is_some_and(|m| !m.is_empty()) {
                ext_vertices.insert(key(id), p);
            }
        }

        let mut walls = Map::new();
        for &wh in &level.walls {
            let w = &b.walls[wh];
            let t = texture(w.params.str("texture_name"), &mut ids);
            let mut o = json!({"anchors": [anchor_of[&w.start], anchor_of[&w.end]]});
            if !t.is_null() {
                o["texture"] = t;
            }
            let id = ids.next();
            surface_params(&mut ext_surfaces, id, &w.params);
            walls.insert(key(id), o);
        }
        // Measurements: rmf_site keeps them on drawing anchors in f32; the extension keeps
        // the vertices they join and their exact parameters.
        let ms: Vec<Value> = level
            .measurements
            .iter()
            .map(|&mh| {
                let m = &b.measurements[mh];
                json!([
                    anchor_of[&m.start],
                    anchor_of[&m.end],
                    params_json(&m.params)
                ])
            })
            .collect();
        if !ms.is_empty() {
            ext_measurements.insert(key(lid), Value::Array(ms));
        }
        // Holes and human lanes: rmf_site has neither; the extension keeps them.
        let holes: Vec<Value> = level
            .holes
            .iter()
            .map(|&h| {
                let p = &b.holes[h];
                let a: Vec<u32> = p.vertices.iter().map(|v| anchor_of[v]).collect();
                json!([a, params_json(&p.params)])
            })
            .collect();
        if !holes.is_empty() {
            ext_holes.insert(key(lid), Value::Array(holes));
        }
        let humans: Vec<Value> = level
            .human_lanes
            .iter()
            .map(|&h| {
                let l = &b.human_lanes[h];
                json!([
                    anchor_of[&l.start],
                    anchor_of[&l.end],
                    params_json(&l.params)
                ])
            })
            .collect();
        if !humans.is_empty() {
            ext_human_lanes.insert(key(lid), Value::Array(humans));
        }
        let mut floors = Map::new();
        let mut floor_rank = Vec::new();
        for &fh in &level.floors {
            let f = &b.floors[fh];
            let t = texture(f.params.str("texture_name"), &mut ids);
            let a: Vec<u32> = f.vertices.iter().map(|v| anchor_of[v]).collect();
            let mut o = json!({ "anchors": a });
            if !t.is_null() {
                o["texture"] = t;
            }
            let id = ids.next();
            surface_params(&mut ext_surfaces, id, &f.params);
            floor_rank.push(id);
            floors.insert(key(id), o);
        }
        if !level.holes.is_empty() {
            warn(
                &mut diags,
                b.levels.span(lh),
                format!(
                    "level `{}` has {} floor hole(s); rmf_site has no holes: only mapc's extension data keeps them",
                    level.name,
                    level.holes.len()
                ),
            );
        }
        if !level.human_lanes.is_empty() {
            warn(
                &mut diags,
                b.levels.span(lh),
                format!(
                    "level `{}` has {} human lane(s); rmf_site has none: only mapc's extension data keeps them",
                    level.name,
                    level.human_lanes.len()
                ),
            );
        }
        if !level.layers.is_empty() || !level.features.is_empty() {
            warn(
                &mut diags,
                b.levels.span(lh),
                format!(
                    "the layers and features of level `{}` are left out",
                    level.name
                ),
            );
        }
        let mut doors = Map::new();
        let mut ext_doors = Map::new();
        for &dh in &level.doors {
            let d = &b.doors[dh];
            let side = |a: MotionAxis| {
                if a == MotionAxis::Start {
                    "Left"
                } else {
                    "Right"
                }
            };
            let angle = json!({"deg": d.motion_degrees});
            let swing = if d.motion_direction < 0 {
                json!({ "Backward": angle })
            } else {
                json!({ "Forward": angle })
            };
            let ratio = if d.right_left_ratio > 0.0 {
                1.0 / d.right_left_ratio
            } else {
                1.0
            };
            let kind = match &d.kind {
                DoorKind::Hinged => {
                    json!({"SingleSwing": {"pivot_on": side(d.motion_axis), "swing": swing}})
                }
                DoorKind::DoubleHinged => {
                    json!({"DoubleSwing": {"swing": swing, "left_right_ratio": ratio}})
                }
                DoorKind::Sliding => json!({"SingleSliding": {"towards": side(d.motion_axis)}}),
                DoorKind::DoubleSliding => json!({"DoubleSliding": {"left_right_ratio": ratio}}),
                DoorKind::Other(t) => {
                    warn(
                        &mut diags,
                        b.doors.span(dh),
                        format!(
                            "door `{}` of type `{t}` has no rmf_site kind; written as a single swing door",
                            d.name
                        ),
                    );
                    json!({"SingleSwing": {"pivot_on": "Left", "swing": swing}})
                }
            };
            let id = ids.next();
            doors.insert(
                key(id),
                json!({"anchors": [anchor_of[&d.start], anchor_of[&d.end]], "name": d.name, "kind": kind}),
            );
            ext_doors.insert(
                key(id),
                json!({"type": d.kind.as_str(), "plugin": d.plugin, "right_left_ratio": d.right_left_ratio, "params": params_json(&d.params)}),
            );
        }
        if !ext_doors.is_empty() {
            let e = ext.entry("doors").or_insert_with(|| json!({}));
            if let Value::Object(m) = e {
                m.extend(ext_doors);
            }
        }

        let mut drawings = Map::new();
        let mut drawing_rank = Vec::new();
        if pixels || level.drawing.is_some() || !level.fiducials.is_empty() {
            let id = ids.next();
            drawing_rank.push(id);
            let file = level.drawing.clone().unwrap_or_default();
            let dname = std::path::Path::new(&file)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| format!("{}_fiducials", level.name));
            // A reference image sits where the level's transform puts it, its anchors in
            // (y up) pixels; any other drawing sits at the map frame with 1 pixel per
            // metre, so its anchors are map positions.
            let t = level.transform;
            let (dpose, dyaw, ppm) = if pixels {
                (local(t.translation), t.rotation, 1.0 / t.scale)
            } else {
                (Vec2::default(), 0.0, 1.0)
            };
            let mut danchors = Map::new();
            let mut dfids = Map::new();
            for &fh in &level.fiducials {
                let f = &b.fiducials[fh];
                let a = ids.next();
                let at = if pixels { flip(f.raw) } else { local(f.pos) };
                danchors.insert(key(a), json!({"Translate2D": pt(at)}));
                let group = if f.name.is_empty() {
                    Value::Null
                } else {
                    json!(*fiducial_groups
                        .entry(f.name.clone())
                        .or_insert_with(|| ids.next()))
                };
                dfids.insert(key(ids.next()), json!({"anchor": a, "affiliation": group}));
            }
            drawings.insert(
                key(id),
                json!({
                    "properties": {
                        "name": dname,
                        "source": {"Local": file},
                        "pose": {"trans": [dpose.x, dpose.y, 0.0], "rot": {"yaw": {"rad": dyaw}}},
                        "pixels_per_meter": ppm,
                    },
                    "anchors": danchors,
                    "fiducials": dfids,
                }),
            );
        }
        let mut o = json!({
            "properties": {"name": level.name, "elevation": level.elevation},
            "anchors": anchors,
        });
        for (k, m) in [
            ("doors", doors),
            ("walls", walls),
            ("floors", floors),
            ("drawings", drawings),
        ] {
            if !m.is_empty() {
                o[k] = Value::Object(m);
            }
        }
        if !floor_rank.is_empty() || !drawing_rank.is_empty() {
            o["rankings"] = json!({"floors": floor_rank, "drawings": drawing_rank});
        }
        levels.insert(key(lid), o);
    }

    // Lifts: reference anchors are the cabin's front corners (rmf_site_format's import).
    let level_id = |h: Handle<Level>| level_ids[h.index()];
    let mut lifts = Map::new();
    let mut ext_lifts = Map::new();
    for (lh, l) in b.lifts.iter() {
        let lift_id = ids.next();
        let (d, w) = (l.width / 2.0, l.depth / 2.0);
        let left = ids.next();
        let right = ids.next();
        // rmf_site's editor puts the cabin centre behind the line between the reference
        // anchors by half the cabin plus its wall, gap and half the front door
        // (`RectangularLiftCabin::aabb`); the anchors go there so that it shows the cabin
        // where the map has it (rmf_site_format's import puts them on the cabin corners,
        // which moves every imported cabin by that much).
        let front = d + CABIN_FRONT;
        site_anchors.insert(
            key(left),
            json!({"Translate2D": pt(local(l.pos.plus(Vec2::new(front, w).rotate(l.yaw))))}),
        );
        site_anchors.insert(
            key(right),
            json!({"Translate2D": pt(local(l.pos.plus(Vec2::new(front, -w).rotate(l.yaw))))}),
        );
        let mut cabin = json!({"width": l.depth, "depth": l.width});
        let mut cabin_doors = Map::new();
        let mut ext_doors = Map::new();
        let mut cabin_anchor_map = Map::new();
        for (id, p) in cabin_anchors.get(&lh).into_iter().flatten() {
            cabin_anchor_map.insert(key(*id), json!({"Translate2D": pt(*p)}));
        }
        for door in &l.doors {
            let did = ids.next();
            let (dx, dy) = (door.pos.x, door.pos.y);
            // The face the door is on, as rmf_site_format's import decides it.
            let face = if dx.abs() < 1e-3 {
                if dy >= 0.0 {
                    "left_door"
                } else {
                    "right_door"
                }
            } else if (dy / dx * d).abs() <= w {
                if dx >= 0.0 {
                    "front_door"
                } else {
                    "back_door"
                }
            } else if dy >= 0.0 {
                "left_door"
            } else {
                "right_door"
            };
            // The editor puts a door's centre past the cabin wall and half the door
            // (`level_door_anchors`); the gap is what is left to the map's position.
            let (shifted, gap) = match face {
                "front_door" => (dy, dx - d),
                "back_door" => (-dy, -dx - d),
                "left_door" => (-dx, dy - w),
                _ => (dx, -dy - w),
            };
            let gap = gap - CABIN_WALL - CABIN_DOOR / 2.0;
            if cabin.get(face).is_some() {
                warn(
                    &mut diags,
                    door.span,
                    format!(
                        "lift `{}` has two doors on one face; rmf_site holds one, `{}` is left out",
                        l.name, door.name
                    ),
                );
                continue;
            }
            cabin[face] =
                json!({"door": did, "width": door.width, "shifted": shifted, "custom_gap": gap});
            let kind = match door.door_type {
                2 | 4 => json!({"DoubleSliding": {"left_right_ratio": 1.0}}),
                _ => json!({"SingleSliding": {"towards": "Left"}}),
            };
            if door.door_type > 2 {
                warn(
                    &mut diags,
                    door.span,
                    format!(
                        "lift door `{}` is a telescope door; rmf_site has none, it is written as a sliding door",
                        door.name
                    ),
                );
            }
            let visits: Vec<u32> = l
                .level_doors
                .iter()
                .filter(|ld| ld.doors.iter().any(|(n, _)| *n == door.name))
                .map(|ld| level_id(ld.level))
                .collect();
            // rmf_site wants door anchors; both sit at the door's ends in the cabin frame.
            let a0 = ids.next();
            let a1 = ids.next();
            let half = door.width / 2.0;
            let along = Vec2::new(1.0, 0.0).rotate(door.motion_axis_orientation);
            cabin_anchor_map.insert(
                key(a0),
                json!({"Translate2D": pt(door.pos.plus(along.scale(half)))}),
            );
            cabin_anchor_map.insert(
                key(a1),
                json!({"Translate2D": pt(door.pos.minus(along.scale(half)))}),
            );
            cabin_doors.insert(
                key(did),
                json!({"kind": kind, "reference_anchors": [a0, a1], "visits": visits}),
            );
            ext_doors.insert(
                key(did),
                json!({"name": door.name, "door_type": door.door_type, "motion_axis_orientation": door.motion_axis_orientation, "x": door.pos.x, "y": door.pos.y}),
            );
        }
        let mut props = json!({
            "name": l.name,
            "reference_anchors": [left, right],
            "cabin": {"Rect": cabin},
            "is_static": !l.plugins,
        });
        if let Some(i) = l.initial_level {
            props["initial_level"] = json!(level_id(i));
        }
        lifts.insert(
            key(lift_id),
            json!({"cabin_doors": cabin_doors, "properties": props, "cabin_anchors": cabin_anchor_map}),
        );
        let name_of = |h: Option<Handle<Level>>| h.map(|h| b.levels[h].name.clone());
        ext_lifts.insert(
            key(lift_id),
            json!({
                "x": l.pos.x, "y": l.pos.y, "yaw": l.yaw,
                "lowest_floor": name_of(l.lowest_level),
                "highest_floor": name_of(l.highest_level),
                "plugins": l.plugins,
                "reference_floor": b.levels[l.reference_level].name,
                "doors": ext_doors,
            }),
        );
        if pixels {
            ext_lifts[&key(lift_id)]["raw"] = pt(l.raw);
        }
    }

    // Lanes, site-wide; a dock is the dock_name of the vertex a lane drives into.
    let mut lanes = Map::new();
    let mut ext_lanes = Map::new();
    for (lh, lane) in b.lanes.iter() {
        let dock = |v: Handle<Vertex>| {
            b.vertices[v]
                .roles
                .dock_name
                .as_ref()
                .map(|n| json!({ "name": n }))
        };
        let orient = |o: &Orientation| match o {
            Orientation::Forward => Some(json!("Forwards")),
            Orientation::Backward => Some(json!("Backwards")),
            _ => None,
        };
        let motion = |o: &Orientation, dock: Option<Value>| {
            let mut m = Map::new();
            if let Some(o) = orient(o) {
                m.insert("orientation_constraint".into(), o);
            }
            if let Some(s) = lane.speed_limit {
                m.insert("speed_limit".into(), json!(s));
            }
            if let Some(d) = dock {
                m.insert("dock".into(), d);
            }
            Value::Object(m)
        };
        let forward = motion(&lane.orientation, dock(lane.end));
        let back_dock = dock(lane.start);
        let reverse = if !lane.bidirectional {
            json!("Disable")
        } else if back_dock.is_some() || lane.orientation != Orientation::Any {
            json!({"Different": motion(&lane.orientation.reversed(), back_dock)})
        } else {
            json!("Same")
        };
        let mut o = json!({
            "anchors": [anchor_of[&lane.start], anchor_of[&lane.end]],
            "forward": forward,
            "reverse": reverse,
            "graphs": {"Only": [graph_ids[&lane.graph]]},
        });
        if let Some(m) = mutex(&lane.mutex, &mut ids) {
            o["mutex"] = json!(m);
        }
        let id = ids.next();
        lanes.insert(key(id), o);
        let mut e = Map::new();
        if let Orientation::Other(s) = &lane.orientation {
            warn(
                &mut diags,
                b.lanes.span(lh),
                format!("orientation constraint `{s}` has no rmf_site equivalent; kept only in mapc's extension data"),
            );
            e.insert("orientation".into(), json!(s));
        }
        for (k, v) in [
            ("demo_mock_floor_name", &lane.demo_mock_floor_name),
            ("demo_mock_lift_name", &lane.demo_mock_lift_name),
        ] {
            if let Some(v) = v {
                e.insert(k.into(), json!(v));
            }
        }
        if !e.is_empty() {
            ext_lanes.insert(key(id), Value::Object(e));
        }
    }

    // Locations: every named vertex or vertex with a role.
    let mut locations = Map::new();
    let mut seen = std::collections::HashSet::new();
    for (vh, v) in b.vertices.iter() {
        let r = &v.roles;
        let mut tags = Vec::new();
        if r.is_charger {
            tags.push(json!("Charger"));
        }
        if r.is_parking_spot {
            tags.push(json!("ParkingSpot"));
        }
        if r.is_holding_point {
            tags.push(json!("HoldingPoint"));
        }
        for n in [&r.pickup_dispenser, &r.dropoff_ingestor]
            .into_iter()
            .flatten()
        {
            tags.push(json!({"Workcell": {
                "name": n,
                "source": {"Local": ""},
                "pose": {"trans": [0.0, 0.0, 0.0], "rot": {"yaw": {"rad": 0.0}}},
            }}));
        }
        if v.name.is_empty() && tags.is_empty() {
            continue;
        }
        let Some(&a) = anchor_of.get(&vh) else {
            continue;
        };
        // One location per anchor (a cabin anchor is shared by the levels).
        if !seen.insert(a) {
            continue;
        }
        let mut o = json!({"anchor": a, "tags": tags, "name": v.name, "graphs": "All"});
        if let Some(m) = mutex(&r.mutex, &mut ids) {
            o["mutex"] = json!(m);
        }
        locations.insert(key(ids.next()), o);
    }

    // Models: a description per model name, an instance per model.
    let mut descriptions = Map::new();
    let mut desc_ids: BTreeMap<(String, bool), u32> = BTreeMap::new();
    let mut instances = Map::new();
    let mut ext_models = Map::new();
    for (_, m) in b.models.iter() {
        let d = *desc_ids
            .entry((m.model_name.clone(), m.is_static))
            .or_insert_with(|| {
                let id = ids.next();
                let short = m.model_name.rsplit('/').next().unwrap_or(&m.model_name);
                descriptions.insert(
                    key(id),
                    json!({"name": short, "source": {"Search": m.model_name}, "is_static": m.is_static}),
                );
                id
            });
        let p = local(m.pos);
        let id = ids.next();
        if pixels {
            ext_models.insert(key(id), json!({ "raw": pt(m.raw) }));
        }
        instances.insert(
            key(id),
            json!({
                "parent": level_id(m.level),
                "name": m.name,
                "pose": {"trans": [p.x, p.y, m.z], "rot": {"yaw": {"rad": m.yaw}}},
                "description": d,
            }),
        );
    }

    let mut mutex_groups = Map::new();
    for (n, id) in &mutex_ids {
        mutex_groups.insert(key(*id), json!({ "name": n }));
    }
    let mut groups = Map::new();
    for (n, id) in &fiducial_groups {
        groups.insert(key(*id), json!({ "name": n }));
    }

    if !ext_vertices.is_empty() {
        ext.insert("vertices".into(), Value::Object(ext_vertices));
    }
    if !cabin_positions.is_empty() {
        ext.insert("cabin_positions".into(), Value::Object(cabin_positions));
    }
    if !ext_lanes.is_empty() {
        ext.insert("lanes".into(), Value::Object(ext_lanes));
    }
    if !ext_lifts.is_empty() {
        ext.insert("lifts".into(), Value::Object(ext_lifts));
    }
    for (k, m) in [
        ("raw_vertices", ext_raw),
        ("measurements", ext_measurements),
        ("surfaces", ext_surfaces),
        ("holes", ext_holes),
        ("human_lanes", ext_human_lanes),
        ("models", ext_models),
    ] {
        if !m.is_empty() {
            ext.insert(k.into(), Value::Object(m));
        }
    }

    let mut props = json!({ "name": b.name });
    if let Some(latlon) = geographic_anchor(b) {
        props["geographic_offset"] = json!({"anchor": latlon, "zoom": 15, "visible": false});
    }
    let mut site = json!({
        "format_version": FORMAT_VERSION,
        "properties": props,
        "levels": levels,
        "navigation": {"guided": {
            "graphs": graphs,
            "ranking": graph_ids.values().collect::<Vec<_>>(),
            "lanes": lanes,
            "locations": locations,
        }},
        "extensions": {"data": {"mapc": ext}},
    });
    if !mutex_groups.is_empty() {
        site["navigation"]["guided"]["mutex_groups"] = Value::Object(mutex_groups);
    }
    for (k, m) in [
        ("anchors", site_anchors),
        ("textures", textures),
        ("fiducial_groups", groups),
        ("lifts", lifts),
        ("model_descriptions", descriptions),
        ("model_instances", instances),
    ] {
        if !m.is_empty() {
            site[k] = Value::Object(m);
        }
    }
    let mut text = serde_json::to_string_pretty(&site).unwrap_or_default();
    text.push('\n');
    (text, diags)
}

/// Latitude and longitude of the map-frame point `Building::offset` (the site origin) for
/// a wgs84 map: an affine fit of the vertices' file longitude/latitude to their projected
/// positions, inverted at the offset. Projections are close to affine over a site, which
/// is what rmf_site's geographic offset (an f32 latitude/longitude) can hold anyway.
fn geographic_anchor(b: &Building) -> Option<[f64; 2]> {
    if b.coordinate_system != CoordinateSystem::Wgs84 {
        return None;
    }
    let pts: Vec<(Vec2, Vec2)> = b.vertices.iter().map(|(_, v)| (v.pos, v.raw)).collect();
    if pts.len() < 3 {
        return None;
    }
    // Least squares raw = A * (pos - c) + r0, per output coordinate.
    let n = pts.len() as f64;
    let c = pts
        .iter()
        .fold(Vec2::default(), |s, (p, _)| s.plus(*p))
        .scale(1.0 / n);
    let r0 = pts
        .iter()
        .fold(Vec2::default(), |s, (_, r)| s.plus(*r))
        .scale(1.0 / n);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    let (mut bx, mut by) = ([0.0; 2], [0.0; 2]);
    for (p, r) in &pts {
        let d = p.minus(c);
        let e = r.minus(r0);
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
        bx[0] += d.x * e.x;
        bx[1] += d.y * e.x;
        by[0] += d.x * e.y;
        by[1] += d.y * e.y;
    }
    let det = sxx * syy - sxy * sxy;
    if det.abs() < 1e-12 {
        return None;
    }
    let solve = |v: [f64; 2]| {
        [
            (syy * v[0] - sxy * v[1]) / det,
            (sxx * v[1] - sxy * v[0]) / det,
        ]
    };
    let (ax, ay) = (solve(bx), solve(by));
    let d = b.offset.minus(c);
    let lon = r0.x + ax[0] * d.x + ax[1] * d.y;
    let lat = r0.y + ay[0] * d.x + ay[1] * d.y;
    (lon.is_finite() && lat.is_finite()).then_some([lat, lon])
}
