//! Site tree → IR. Positions are metres, y up, in the site frame, which becomes the map
//! frame (plus the offset mapc's extension records, for maps converted from wgs84 or
//! offset cartesian maps). Problems become diagnostics and the element is dropped;
//! lowering always continues.

use super::{EXTENSION_KEY, FORMAT_MAJOR};
use crate::lower::Lower;
use crate::yaml::{Kind, Node};
use mapc_ir::*;
use std::collections::{BTreeMap, HashMap};

const ROOT_KEYS: &[&str] = &[
    "format_version",
    "anchors",
    "properties",
    "levels",
    "textures",
    "fiducial_groups",
    "fiducials",
    "lifts",
    "navigation",
    "scenarios",
    "model_descriptions",
    "robots",
    "model_instances",
    "tasks",
    "extensions",
];
/// Site elements mapc reads without using: reported once each when not empty. (`robots`
/// holds the fleet properties of model descriptions, whose instances are placed as
/// models; site-wide `fiducials` only align drawings in rmf_site's editor, whose poses
/// mapc reads as they are.)
const UNUSED_ROOT: &[&str] = &["tasks"];
const LEVEL_KEYS: &[&str] = &[
    "properties",
    "anchors",
    "doors",
    "drawings",
    "floors",
    "lights",
    "physical_cameras",
    "walls",
    "rankings",
    "user_camera_poses",
];
const UNUSED_LEVEL: &[&str] = &["lights", "physical_cameras"];
/// rmf_site_format's defaults for a cabin without `wall_thickness`, `gap` or a door
/// `thickness` (metres), which place its centre and doors.
const CABIN_WALL: f64 = 0.1;
const CABIN_GAP: f64 = 0.01;
const CABIN_DOOR: f64 = 0.05;
const LANE_KEYS: &[&str] = &["anchors", "forward", "reverse", "mutex", "graphs"];
const LOCATION_KEYS: &[&str] = &["anchor", "tags", "name", "mutex", "graphs"];
const MOTION_KEYS: &[&str] = &["orientation_constraint", "speed_limit", "dock"];

/// Where an anchor id lives.
#[derive(Clone, Copy)]
enum Anchor {
    /// A level anchor and the IR vertex made of it.
    Level(Handle<Level>, Handle<Vertex>),
    /// A site-wide anchor (shared by every level: lift reference anchors, and whatever
    /// walls, floors or doors of any level snap to), with the span of its definition.
    Site(Vec2, Span),
    /// A lift cabin anchor: lift index (in `lifts`), position in the cabin frame.
    Cabin(usize, Vec2),
}

pub(crate) struct SiteLower<'d, 'n, 's> {
    l: Lower<'d>,
    /// mapc's extension data, when the site was written by mapc.
    ext: Option<&'n Node<'s>>,
    anchors: HashMap<u32, Anchor>,
    /// Cabin anchor id and level → the vertex made for it on that level.
    cabin_vertices: HashMap<(u32, Handle<Level>), Handle<Vertex>>,
    /// Site anchor id and level → the vertex made for it on that level (the IR's
    /// elements join vertices of their own level).
    site_vertices: HashMap<(u32, Handle<Level>), Handle<Vertex>>,
    /// Site level id → handle.
    levels: HashMap<u32, Handle<Level>>,
    /// Graph id → IR graph index.
    graphs: BTreeMap<u32, i64>,
    /// Mutex group id → name.
    mutexes: HashMap<u32, String>,
    /// Texture id → texture name (file stem).
    textures: HashMap<u32, String>,
    /// Lift index → handle, for cabin anchors.
    lift_handles: Vec<Option<Handle<Lift>>>,
    /// Level handle → site level id (mapc's extension data is keyed by it).
    level_ids: HashMap<Handle<Level>, u32>,
    /// Fiducial group id → name.
    fiducial_groups: HashMap<u32, String>,
}

fn flip(p: Vec2) -> Vec2 {
    Vec2::new(p.x, -p.y)
}

fn ext_point(n: Option<&Node>) -> Option<Vec2> {
    let s = n?.as_seq()?;
    Some(Vec2::new(s.first()?.as_f64()?, s.get(1)?.as_f64()?))
}

fn id_of(k: &Node) -> Option<u32> {
    k.key_text().and_then(|t| t.trim().parse::<u32>().ok())
}

fn ref_of(n: &Node) -> Option<u32> {
    n.as_i64().and_then(|i| u32::try_from(i).ok())
}

/// `{"Variant": value}` or `"Variant"`: the variant name and its value.
fn variant<'n, 's>(n: &'n Node<'s>) -> Option<(&'n str, Option<&'n Node<'s>>)> {
    match &n.kind {
        Kind::Scalar { .. } => n.key_text().map(|t| (t, None)),
        Kind::Map(m) if m.len() == 1 => m[0].0.key_text().map(|t| (t, Some(&m[0].1))),
        _ => None,
    }
}

/// Texture name from an asset source path: the file stem, as the editor names textures.
fn stem(path: &str) -> String {
    let file = path.rsplit(['/', '\\']).next().unwrap_or(path);
    file.strip_suffix(".png")
        .or_else(|| file.rsplit_once('.').map(|(s, _)| s))
        .unwrap_or(file)
        .to_string()
}

fn angle_rad(n: &Node) -> Option<f64> {
    match variant(n)? {
        ("deg", Some(v)) => v.as_f64().map(f64::to_radians),
        ("rad", Some(v)) => v.as_f64(),
        _ => None,
    }
}

impl<'d, 'n, 's> SiteLower<'d, 'n, 's> {
    pub fn new(diags: &'d mut Vec<Diagnostic>) -> Self {
        SiteLower {
            l: Lower { diags },
            ext: None,
            anchors: HashMap::new(),
            cabin_vertices: HashMap::new(),
            site_vertices: HashMap::new(),
            levels: HashMap::new(),
            graphs: BTreeMap::new(),
            mutexes: HashMap::new(),
            textures: HashMap::new(),
            lift_handles: Vec::new(),
            level_ids: HashMap::new(),
            fiducial_groups: HashMap::new(),
        }
    }

    fn entries<'a, 'b>(
        &mut self,
        parent: &'a Node<'b>,
        key: &str,
        what: &str,
    ) -> Vec<(u32, &'a Node<'b>, Span)> {
        let Some(n) = parent.get(key) else {
            return Vec::new();
        };
        let Some(m) = self.l.map(n, format_args!("{what} `{key}`")) else {
            return Vec::new();
        };
        let mut out = Vec::with_capacity(m.len());
        for (k, v) in m {
            match id_of(k) {
                Some(id) => out.push((id, v, k.span)),
                None => self
                    .l
                    .wrong_type(k, "a site id", "an unsigned integer in quotes"),
            }
        }
        // rmf_site keeps every map as a BTreeMap<u32, _>: numeric id order.
        out.sort_by_key(|(id, _, _)| *id);
        out
    }

    fn unknown(&mut self, node: &Node, known: &[&str], what: &str) {
        let Some(m) = node.as_map() else { return };
        for (k, _) in m {
            let Some(t) = k.key_text() else { continue };
            if !known.contains(&t) {
                self.l.warn(
                    "W0121",
                    k.span,
                    format!("unknown field `{t}` in {what}; it is ignored"),
                    "rmf_site_format 0.0.2 has no such field; check the spelling",
                );
            }
        }
    }

    fn unused(&mut self, node: &Node, keys: &[&str], what: &str) {
        for key in keys {
            if let Some(v) = node.get(key) {
                let non_empty = v.as_map().is_some_and(|m| !m.is_empty())
                    || v.as_seq().is_some_and(|s| !s.is_empty());
                if non_empty {
                    self.l.warn(
                        "W0121",
                        v.span,
                        format!("mapc does not use the `{key}` of {what}; they are ignored"),
                        "nothing to do unless an output should have them",
                    );
                }
            }
        }
    }

    fn name(&mut self, n: &Node, what: &str) -> String {
        match n.get("name") {
            Some(v) => self
                .l
                .string(v, format_args!("the name of {what}"))
                .unwrap_or_default(),
            None => String::new(),
        }
    }

    fn point(&mut self, n: &Node, what: &str) -> Option<Vec2> {
        let s = n.as_seq().filter(|s| s.len() >= 2);
        let Some(s) = s else {
            self.l.wrong_type(n, what, "a list [x, y]");
            return None;
        };
        let x = self.l.f64(&s[0], format_args!("the x of {what}"))?;
        let y = self.l.f64(&s[1], format_args!("the y of {what}"))?;
        Some(Vec2::new(x, y))
    }

    /// An anchor value: `Translate2D`, `CategorizedTranslate2D` (its `General` point) or
    /// `Pose3D` (its x, y).
    fn anchor_pos(&mut self, n: &Node) -> Option<Vec2> {
        match variant(n) {
            Some(("Translate2D", Some(v))) => self.point(v, "an anchor"),
            Some(("CategorizedTranslate2D", Some(v))) => match v.get("General") {
                Some(g) => self.point(g, "an anchor"),
                None => {
                    self.l.err(
                        "E0102",
                        v.span,
                        "categorized anchor has no `General` point",
                        "add `General: [x, y]`",
                    );
                    None
                }
            },
            Some(("Pose3D", Some(v))) => v.get("trans").and_then(|t| self.point(t, "an anchor")),
            _ => {
                self.l.wrong_type(
                    n,
                    "an anchor",
                    "Translate2D, CategorizedTranslate2D or Pose3D",
                );
                None
            }
        }
    }

    /// The file coordinates (pixels, y down) of map position `pos` on level `lh` of a
    /// reference_image map: those mapc's extension kept, while they still land on `pos`
    /// (an element moved in rmf_site gets them from the level's drawing instead).
    fn pixel_raw(&self, b: &Building, lh: Handle<Level>, pos: Vec2, kept: Option<Vec2>) -> Vec2 {
        let t = b.levels[lh].transform;
        match kept {
            Some(r) if t.apply(flip(r)).minus(pos).norm() < 1e-6 => r,
            _ => flip(t.invert(pos)),
        }
    }

    /// What mapc's extension keeps under `key` for element `id` of level `lh`.
    fn ext_level_point(&self, key: &str, lh: Handle<Level>, id: u32) -> Option<Vec2> {
        let level = self.level_ids.get(&lh)?;
        ext_point(
            self.ext?
                .get(key)?
                .get(&level.to_string())?
                .get(&id.to_string()),
        )
    }

    fn dangling(&mut self, span: Span, what: &str, id: u32) {
        self.l.err(
            "E0121",
            span,
            format!("{what} refers to id {id}, which the site does not have"),
            "point it at an existing element, or delete it",
        );
    }

    pub fn site(mut self, root: &'n Node<'s>) -> Option<Building> {
        self.l.map(root, "the site")?;
        self.unknown(root, ROOT_KEYS, "the site");
        self.unused(root, UNUSED_ROOT, "the site");
        // Scenarios holding tasks say something the outputs do not; those that move or
        // hide instances are checked with the models.
        for (_, sc, _) in self.entries(root, "scenarios", "the site") {
            let name = self.name(sc, "a scenario");
            self.unused(sc, &["tasks"], &format!("scenario `{name}`"));
        }
        if !self.format_version(root) {
            return None;
        }
        let ext = root
            .get("extensions")
            .and_then(|e| e.get("data"))
            .and_then(|d| d.get(EXTENSION_KEY));
        self.ext = ext;

        let props = root.get("properties");
        let name = props.map(|p| self.name(p, "the site")).unwrap_or_default();
        if props.is_none() {
            self.l.err(
                "E0102",
                root.span,
                "the site has no `properties`",
                "add `properties: {name: ...}`",
            );
        }
        let coordinate_system = match ext
            .and_then(|e| e.get("coordinate_system"))
            .and_then(|c| c.key_text())
        {
            Some("reference_image") => CoordinateSystem::ReferenceImage,
            Some("wgs84") => CoordinateSystem::Wgs84,
            Some("web_mercator") => CoordinateSystem::WebMercator,
            _ => CoordinateSystem::CartesianMeters,
        };
        let params = ext
            .and_then(|e| e.get("parameters"))
            .map(|p| self.l.params(p, "the building"))
            .unwrap_or_default();
        let mut b = Building::new(name, coordinate_system, params);
        b.format = SourceFormat::Site;
        b.spans = BuildingSpans {
            root: root.span,
            name: props
                .and_then(|p| p.get("name"))
                .map_or(root.span, |n| n.span),
            coordinate_system: root.span,
            parameters: ext
                .and_then(|e| e.get("parameters"))
                .map_or(root.span, |n| n.span),
        };
        if let Some(e) = ext {
            if let Some(o) = e.get("offset") {
                b.offset = self.point(o, "the mapc offset").unwrap_or_default();
            }
            b.crs_name = e
                .get("crs_name")
                .and_then(|c| c.key_text())
                .map(str::to_string);
        }
        let shift = b.offset;

        for (id, v, _) in self.entries(root, "textures", "the site") {
            let src = v
                .get("texture")
                .and_then(|t| t.get("source"))
                .and_then(variant);
            if let Some((_, Some(path))) = src {
                if let Some(p) = path.key_text() {
                    self.textures.insert(id, stem(p));
                }
            }
        }
        if let Some(g) = root.get("navigation").and_then(|n| n.get("guided")) {
            for (id, v, _) in self.entries(g, "mutex_groups", "`navigation.guided`") {
                let n = self.name(v, "a mutex group");
                self.mutexes.insert(id, n);
            }
        }
        for (id, v, _) in self.entries(root, "fiducial_groups", "the site") {
            let n = self.name(v, "a fiducial group");
            self.fiducial_groups.insert(id, n);
        }
        for (id, v, span) in self.entries(root, "anchors", "the site") {
            if let Some(p) = self.anchor_pos(v) {
                self.anchors.insert(id, Anchor::Site(p.plus(shift), span));
            }
        }

        let level_entries = self.entries(root, "levels", "the site");
        if level_entries.is_empty() {
            self.l.err(
                "E0110",
                root.span,
                "the site has no levels",
                "add a level in rmf_site",
            );
            return None;
        }
        let ext_vertices = ext.and_then(|e| e.get("vertices"));
        for (id, v, span) in &level_entries {
            self.level(&mut b, *id, v, *span, shift, ext_vertices);
        }
        b.reference_level = b.levels.iter().next().map(|(h, _)| h)?;
        if let Some(r) = ext
            .and_then(|e| e.get("reference_level"))
            .and_then(|n| n.key_text())
            .and_then(|n| b.level_by_name(n))
        {
            b.reference_level = r;
        }

        self.graphs(root, &mut b);
        self.lifts(root, &mut b, shift, ext);
        if let Some(g) = root.get("navigation").and_then(|n| n.get("guided")) {
            self.unknown(
                g,
                &["graphs", "ranking", "lanes", "locations", "mutex_groups"],
                "`navigation.guided`",
            );
            let ext_lanes = ext.and_then(|e| e.get("lanes"));
            for (id, v, span) in self.entries(g, "lanes", "`navigation.guided`") {
                self.lane(&mut b, id, v, span, ext_lanes);
            }
            for (_, v, span) in self.entries(g, "locations", "`navigation.guided`") {
                self.location(&mut b, v, span);
            }
        }
        self.models(root, &mut b, shift);
        // rmf_site has no crowd simulation; mapc's extension keeps a map's crowd_sim in
        // the building format's own shape, read by the same code.
        if let Some(c) = ext.and_then(|e| e.get("crowd_sim")) {
            b.crowd_sim = self.l.crowd_sim(c);
        }
        // Roles follow the final parameters (locations and extension data both set them).
        for (_, v) in b.vertices.iter_mut() {
            v.roles = WaypointRoles::from_params(&v.params).into();
        }
        Some(b)
    }

    fn format_version(&mut self, root: &Node) -> bool {
        let Some(v) = root.get("format_version") else {
            self.l.err(
                "E0120",
                root.span,
                "the site has no `format_version`",
                "rmf_site writes `\"format_version\": \"0.1\"`",
            );
            return false;
        };
        let major = v
            .key_text()
            .and_then(|t| t.split('.').next())
            .and_then(|m| m.trim().parse::<u32>().ok());
        match major {
            Some(m) if m == FORMAT_MAJOR => true,
            Some(m) => {
                self.l.err(
                    "E0120",
                    v.span,
                    format!("site format_version major {m} is newer than the {FORMAT_MAJOR}.x mapc reads"),
                    "save the site with an rmf_site that writes format 0.x, or update mapc",
                );
                false
            }
            None => {
                self.l.err(
                    "E0120",
                    v.span,
                    "`format_version` must be \"MAJOR.MINOR\"",
                    "write `\"format_version\": \"0.1\"`",
                );
                false
            }
        }
    }

    fn level(
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
    fn measurements(&mut self, b: &mut Building, lh: Handle<Level>, id: u32) {
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
    fn holes_and_human_lanes(&mut self, b: &mut Building, lh: Handle<Level>, id: u32) {
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

    /// Translation and yaw of a `Pose` (`rot` as yaw, or a quaternion's yaw).
    /// The two anchor ids of an edge (`anchors: [start, end]`), or E0102 on `span`.
    fn anchor_pair<'a, 't>(
        &mut self,
        n: &'a Node<'t>,
        span: Span,
        what: &str,
    ) -> Option<&'a [Node<'t>]> {
        let a = n
            .get("anchors")
            .and_then(|a| a.as_seq())
            .filter(|s| s.len() == 2);
        if a.is_none() {
            self.l.err(
                "E0102",
                span,
                format!("{what} needs `anchors: [start, end]`"),
                "give the two anchor ids",
            );
        }
        a
    }

    /// A wall's or floor's `texture` reference as the `texture_name` param the backends
    /// read (empty when it has none or it dangles).
    fn texture_params(&mut self, n: &Node, span: Span, id: u32) -> Params {
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

    fn pose(&mut self, pose: Option<&Node>) -> (Vec2, f64) {
        let Some(p) = pose else {
            return (Vec2::default(), 0.0);
        };
        let t = p
            .get("trans")
            .and_then(|t| self.point(t, "a pose translation"))
            .unwrap_or_default();
        let yaw = match p.get("rot").and_then(variant) {
            Some(("yaw", Some(a))) => angle_rad(a).unwrap_or(0.0),
            Some(("quat", Some(q))) => {
                let q: Vec<f64> = q
                    .as_seq()
                    .unwrap_or(&[])
                    .iter()
                    .filter_map(|v| v.as_f64())
                    .collect();
                if let [x, y, z, w] = q[..] {
                    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
                } else {
                    0.0
                }
            }
            _ => 0.0,
        };
        (t, yaw)
    }

    /// The two anchors of a wall or door on level `lh` (its own anchors or site anchors).
    fn edge(
        &mut self,
        b: &mut Building,
        n: &Node,
        span: Span,
        lh: Handle<Level>,
        what: &str,
    ) -> Option<(Handle<Vertex>, Handle<Vertex>)> {
        let a = self.anchor_pair(n, span, what)?;
        let mut out = [None, None];
        for (i, node) in a.iter().enumerate() {
            let Some(id) = ref_of(node) else {
                self.l
                    .wrong_type(node, "an anchor id", "an unsigned integer");
                return None;
            };
            out[i] = Some(self.level_anchor(b, id, lh, node.span, what)?);
        }
        Some((out[0]?, out[1]?))
    }

    /// The vertex on level `lh` of anchor `id`, named by an element of that level (`what`,
    /// the reference at `at`). rmf_site's loader resolves a level's walls, floors and doors
    /// against the site's anchors and the level's own (site anchors first, then each
    /// level's anchors before its elements), so both are accepted; a site anchor is where
    /// the site says, on every level that uses it. Another level's anchor or a lift's cabin
    /// anchor is an error: rmf_site's loader finds the first only when that level's id is
    /// lower (it reads levels in id order) and the second never (lifts come after levels),
    /// so a site using them opens in rmf_site by accident of numbering, or not at all.
    fn level_anchor(
        &mut self,
        b: &mut Building,
        id: u32,
        lh: Handle<Level>,
        at: Span,
        what: &str,
    ) -> Option<Handle<Vertex>> {
        let level = |b: &Building, l: Handle<Level>| b.levels[l].name.clone();
        match self.anchors.get(&id).copied() {
            Some(Anchor::Level(l2, v)) if l2 == lh => Some(v),
            Some(Anchor::Site(p, def)) => Some(self.site_vertex(b, id, p, lh, def)),
            Some(Anchor::Level(l2, _)) => {
                self.l.err(
                    "E0121",
                    at,
                    format!(
                        "{what} of level `{}` uses anchor {id}, which is an anchor of level `{}`",
                        level(b, lh),
                        level(b, l2)
                    ),
                    &format!(
                        "use an anchor of level `{}` or a site anchor (the site's `anchors`, shared by all levels)",
                        level(b, lh)
                    ),
                );
                None
            }
            Some(Anchor::Cabin(..)) => {
                self.l.err(
                    "E0121",
                    at,
                    format!("{what} uses anchor {id}, which is a lift's cabin anchor"),
                    &format!(
                        "use an anchor of level `{}` or a site anchor; cabin anchors are for lanes and locations",
                        level(b, lh)
                    ),
                );
                None
            }
            None => {
                self.dangling(at, what, id);
                None
            }
        }
    }

    /// The vertex of site anchor `id` (at map position `pos`, defined at `span`) on level
    /// `lh`, made on first use: one per level, as the IR's elements join vertices of their
    /// own level.
    fn site_vertex(
        &mut self,
        b: &mut Building,
        id: u32,
        pos: Vec2,
        lh: Handle<Level>,
        span: Span,
    ) -> Handle<Vertex> {
        if let Some(v) = self.site_vertices.get(&(id, lh)) {
            return *v;
        }
        let raw = if b.coordinate_system == CoordinateSystem::ReferenceImage {
            let kept = self.ext_level_point("raw_vertices", lh, id);
            self.pixel_raw(b, lh, pos, kept)
        } else {
            pos.minus(b.offset)
        };
        let vh = b.vertices.append(
            Vertex {
                level: lh,
                name: String::new(),
                pos,
                raw,
                params: Params::default(),
                roles: Default::default(),
            },
            span,
        );
        b.levels[lh].vertices.push(vh);
        self.site_vertices.insert((id, lh), vh);
        vh
    }

    fn door(
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

    fn graphs(&mut self, root: &Node, b: &mut Building) {
        let Some(g) = root.get("navigation").and_then(|n| n.get("guided")) else {
            return;
        };
        let list: Vec<(u32, String, Span)> = self
            .entries(g, "graphs", "`navigation.guided`")
            .into_iter()
            .map(|(id, v, s)| (id, self.name(v, "a graph"), s))
            .collect();
        // A graph named by an integer keeps it as its index (what `mapc convert` writes
        // for a `.building.yaml`'s graph_idx); the others take the next free ones.
        let mut taken = std::collections::BTreeSet::new();
        for (id, name, _) in &list {
            if let Ok(i) = name.trim().parse::<i64>() {
                if i >= 0 && taken.insert(i) {
                    self.graphs.insert(*id, i);
                }
            }
        }
        let mut next = 0;
        for (id, _, _) in &list {
            if self.graphs.contains_key(id) {
                continue;
            }
            while taken.contains(&next) {
                next += 1;
            }
            taken.insert(next);
            self.graphs.insert(*id, next);
        }
        for (id, name, _) in list {
            b.graphs.push(GraphInfo {
                index: self.graphs[&id],
                name,
                default_lane_width: 1.0,
                unnamed: Vec::new(),
            });
        }
        b.graphs.sort_by_key(|g| g.index);
    }

    fn lifts(&mut self, root: &Node, b: &mut Building, shift: Vec2, ext: Option<&Node>) {
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
    fn cabin_vertex(
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

    fn motion(&mut self, n: Option<&Node>) -> (Orientation, Option<f64>, Option<String>) {
        let Some(n) = n else {
            return (Orientation::Any, None, None);
        };
        self.unknown(n, MOTION_KEYS, "a lane motion");
        let orientation = match n.get("orientation_constraint").and_then(variant) {
            Some(("Forwards", _)) => Orientation::Forward,
            Some(("Backwards", _)) => Orientation::Backward,
            Some(("None", _)) | None => Orientation::Any,
            Some((other, _)) => {
                let span = n.get("orientation_constraint").map_or(n.span, |c| c.span);
                self.l.warn(
                    "W0121",
                    span,
                    format!("orientation constraint `{other}` has no equivalent in RMF nav graphs; it is ignored"),
                    "use Forwards, Backwards or None",
                );
                Orientation::Any
            }
        };
        let speed = n
            .get("speed_limit")
            .and_then(|s| s.as_f64())
            .filter(|s| *s > 0.0);
        let dock = n
            .get("dock")
            .and_then(|d| d.get("name"))
            .and_then(|d| d.key_text())
            .filter(|d| !d.is_empty())
            .map(str::to_string);
        (orientation, speed, dock)
    }

    fn lane(&mut self, b: &mut Building, id: u32, n: &Node, span: Span, ext_lanes: Option<&Node>) {
        if self.l.map(n, "a lane").is_none() {
            return;
        }
        self.unknown(n, LANE_KEYS, "a lane");
        let Some(a) = self.anchor_pair(n, span, "a lane") else {
            return;
        };
        let mut ends = [None, None];
        for (i, node) in a.iter().enumerate() {
            let Some(aid) = ref_of(node) else {
                self.l
                    .wrong_type(node, "an anchor id", "an unsigned integer");
                return;
            };
            match self.anchors.get(&aid) {
                Some(x) => ends[i] = Some((aid, *x, node.span)),
                None => {
                    self.l.err(
                        "E0121",
                        node.span,
                        format!("lane {id} refers to anchor {aid}, which the site does not have"),
                        "point the lane at an existing anchor, or delete the lane",
                    );
                    return;
                }
            }
        }
        let [Some(s), Some(e)] = ends else { return };
        // rmf_site's nav export (`NavGraph::from_site`) makes waypoints of level anchors
        // and cabin anchors only, and leaves out a lane on a site anchor ("not
        // supported"); mapc's nav graphs are the same, and say so.
        if let Some((aid, _, aspan)) = [s, e]
            .into_iter()
            .find(|(_, x, _)| matches!(x, Anchor::Site(..)))
        {
            self.l.warn(
                "W0123",
                aspan,
                format!("lane {id} uses site anchor {aid}; it is left out of the nav graphs, as rmf_site's own nav export leaves it out"),
                "in rmf_site, draw the lane to an anchor of the level (a new anchor at the same place), not to the site anchor",
            );
            return;
        }
        let level_of = |x: &Anchor| match x {
            Anchor::Level(l, _) => Some(*l),
            _ => None,
        };
        let lh = match (level_of(&s.1), level_of(&e.1)) {
            (Some(l1), Some(l2)) if l1 != l2 => {
                self.l.err(
                    "E0122",
                    span,
                    format!(
                        "lane {id} joins level `{}` and level `{}`",
                        b.levels[l1].name, b.levels[l2].name
                    ),
                    "a lane lies on one level; use a lift to change levels",
                );
                return;
            }
            (Some(l), _) | (None, Some(l)) => l,
            (None, None) => {
                self.l.err(
                    "E0122",
                    span,
                    format!("lane {id} has no end on a level anchor"),
                    "draw the lane from an anchor of a level",
                );
                return;
            }
        };
        let mut vs = [None, None];
        for (i, (aid, x, aspan)) in [s, e].into_iter().enumerate() {
            vs[i] = match x {
                Anchor::Level(_, v) => Some(v),
                Anchor::Cabin(lift, p) => self.cabin_vertex(b, aid, lift, p, lh, aspan),
                Anchor::Site(..) => None,
            };
        }
        let [Some(sv), Some(ev)] = vs else { return };

        let (orientation, speed_limit, fdock) = self.motion(n.get("forward"));
        let reverse = n.get("reverse");
        let (bidirectional, back) = match reverse.and_then(variant) {
            None | Some(("Same", _)) => (true, None),
            Some(("Disable", _)) => (false, None),
            Some(("Different", m)) => (true, Some(self.motion(m))),
            Some((other, _)) => {
                self.l.wrong_type(
                    reverse.unwrap_or(n),
                    &format!("lane reverse `{other}`"),
                    "Same, Disable or Different",
                );
                (true, None)
            }
        };
        let mutex = n
            .get("mutex")
            .and_then(ref_of)
            .and_then(|m| self.mutexes.get(&m).cloned())
            .filter(|m| !m.is_empty());
        let graphs = self.graph_set(n, &format!("lane {id}"));
        let lext = ext_lanes.and_then(|e| e.get(&id.to_string()));
        let ext_str = |k: &str| {
            lext.and_then(|e| e.get(k))
                .and_then(|v| v.key_text())
                .map(str::to_string)
        };
        let (demo_floor, demo_lift) = (
            ext_str("demo_mock_floor_name"),
            ext_str("demo_mock_lift_name"),
        );
        let orientation = match ext_str("orientation") {
            Some(o) if !o.is_empty() => Orientation::Other(o),
            _ => orientation,
        };

        // Docks are vertex properties in RMF nav graphs: a lane into a vertex docks there.
        let set_dock = |b: &mut Building, v: Handle<Vertex>, d: &str| {
            b.vertices[v].params.insert(Param {
                name: "dock_name".into(),
                value: ParamValue::String(d.to_string()),
                span,
            });
        };
        if let Some(d) = &fdock {
            set_dock(b, ev, d);
        }
        // A reverse motion that differs in more than its dock: two one-way lanes.
        let split = match &back {
            Some((o, sl, d)) => {
                if let Some(d) = d {
                    set_dock(b, sv, d);
                }
                *o != orientation.reversed() || *sl != speed_limit
            }
            None => false,
        };
        let push = |b: &mut Building, s, e, bidi, o: Orientation, sl| {
            for &g in &graphs {
                let h = b.lanes.append(
                    Lane {
                        level: lh,
                        start: s,
                        end: e,
                        graph: g,
                        bidirectional: bidi,
                        orientation: o.clone(),
                        speed_limit: sl,
                        mutex: mutex.clone(),
                        demo_mock_floor_name: demo_floor.clone(),
                        demo_mock_lift_name: demo_lift.clone(),
                        params: Params::default(),
                    },
                    span,
                );
                b.levels[lh].lanes.push(h);
            }
        };
        if split {
            push(b, sv, ev, false, orientation, speed_limit);
            let (o, sl, _) = back.unwrap_or((Orientation::Any, None, None));
            push(b, ev, sv, false, o, sl);
        } else {
            push(b, sv, ev, bidirectional, orientation, speed_limit);
        }
    }

    /// The IR graph indices of a lane's or location's `graphs` (`what` names it).
    fn graph_set(&mut self, n: &Node, what: &str) -> Vec<i64> {
        let all: Vec<(u32, i64)> = self.graphs.iter().map(|(k, v)| (*k, *v)).collect();
        let set = |s: &mut Self, v: Option<&Node>| -> Vec<u32> {
            let mut out = Vec::new();
            for g in v.and_then(|v| v.as_seq()).unwrap_or(&[]) {
                match ref_of(g) {
                    Some(gid) if s.graphs.contains_key(&gid) => out.push(gid),
                    Some(gid) => s.l.err(
                        "E0121",
                        g.span,
                        format!("{what} refers to graph {gid}, which the site does not have"),
                        "point it at an existing graph",
                    ),
                    None => s.l.wrong_type(g, "a graph id", "an unsigned integer"),
                }
            }
            out
        };
        let mut out: Vec<i64> = match n.get("graphs").and_then(variant) {
            Some(("All", _)) | None => all.iter().map(|(_, i)| *i).collect(),
            Some(("Only", v)) => set(self, v).iter().map(|g| self.graphs[g]).collect(),
            Some(("AllExcept", v)) => {
                let ex = set(self, v);
                all.iter()
                    .filter(|(g, _)| !ex.contains(g))
                    .map(|(_, i)| *i)
                    .collect()
            }
            Some((other, _)) => {
                let span = n.get("graphs").map_or(n.span, |g| g.span);
                self.l.err(
                    "E0101",
                    span,
                    format!("unknown graphs `{other}` of {what}"),
                    "use All, Only or AllExcept",
                );
                Vec::new()
            }
        };
        out.sort_unstable();
        out.dedup();
        out
    }

    fn location(&mut self, b: &mut Building, n: &Node, span: Span) {
        if self.l.map(n, "a location").is_none() {
            return;
        }
        self.unknown(n, LOCATION_KEYS, "a location");
        let name = self.name(n, "a location");
        let aid = n.get("anchor").and_then(ref_of);
        let targets: Vec<Handle<Vertex>> = match aid.and_then(|a| self.anchors.get(&a).copied()) {
            Some(Anchor::Level(_, v)) => vec![v],
            // A cabin anchor has one vertex per level a lane uses it from.
            Some(Anchor::Cabin(..)) => self
                .cabin_vertices
                .iter()
                .filter(|((a, _), _)| Some(*a) == aid)
                .map(|(_, v)| *v)
                .collect(),
            Some(Anchor::Site(..)) => {
                let at = n.get("anchor").map_or(span, |a| a.span);
                self.l.warn(
                    "W0123",
                    at,
                    format!(
                        "location `{name}` is on site anchor {}; no nav graph has a waypoint there, as rmf_site's own nav export has none",
                        aid.map_or("?".into(), |a| a.to_string())
                    ),
                    "in rmf_site, put the location on an anchor of a level",
                );
                return;
            }
            _ => {
                let at = n.get("anchor").map_or(span, |a| a.span);
                self.l.err(
                    "E0123",
                    at,
                    format!(
                        "location `{name}` is on anchor {}, which the site does not have on a level or lift",
                        aid.map_or("?".into(), |a| a.to_string())
                    ),
                    "move the location onto an anchor of a level",
                );
                return;
            }
        };
        let mut flags = Vec::new();
        for t in n.get("tags").and_then(|t| t.as_seq()).unwrap_or(&[]) {
            // Warnings point at the variant's name.
            let at = t
                .as_map()
                .and_then(|m| m.first())
                .map_or(t.span, |(k, _)| k.span);
            match variant(t) {
                Some(("Charger", _)) => flags.push(("is_charger", t.span)),
                Some(("ParkingSpot", _)) => flags.push(("is_parking_spot", t.span)),
                Some(("HoldingPoint", _)) => flags.push(("is_holding_point", t.span)),
                Some(("Workcell", w)) => {
                    // mapc's extension says which dispenser or ingestor a workcell it
                    // wrote is; a workcell drawn in rmf_site says neither.
                    let role = |v: &Handle<Vertex>| {
                        let p = &b.vertices[*v].params;
                        p.param("pickup_dispenser").is_some()
                            || p.param("dropoff_ingestor").is_some()
                    };
                    if !targets.iter().any(role) {
                        let cell = w
                            .and_then(|w| w.get("name"))
                            .and_then(|n| n.key_text())
                            .unwrap_or("");
                        self.l.warn(
                            "W0121",
                            at,
                            format!("workcell `{cell}` at location `{name}` is kept as a named place only: rmf_site does not say whether it is a dispenser or an ingestor"),
                            "give the waypoint `pickup_dispenser` or `dropoff_ingestor` in the converted .building.yaml if tasks use it",
                        );
                    }
                }
                _ => {
                    let tag = variant(t).map_or("?", |(v, _)| v);
                    self.l.warn(
                        "W0121",
                        at,
                        format!("location tag `{tag}` of `{name}` is not one rmf_site_format 0.0.2 defines; it is ignored"),
                        "use Charger, ParkingSpot, HoldingPoint or Workcell",
                    );
                }
            }
        }
        let mutex = n
            .get("mutex")
            .and_then(ref_of)
            .and_then(|m| self.mutexes.get(&m))
            .filter(|m| !m.is_empty())
            .cloned();
        // The graphs the location is not in keep the waypoint, unnamed.
        let graphs = self.graph_set(n, &format!("location `{name}`"));
        for g in b.graphs.iter_mut().filter(|g| !graphs.contains(&g.index)) {
            g.unnamed.extend(&targets);
            g.unnamed.sort_unstable();
            g.unnamed.dedup();
        }
        for v in targets {
            let vx = &mut b.vertices[v];
            vx.name = name.clone();
            for (flag, at) in &flags {
                vx.params.insert(Param {
                    name: (*flag).into(),
                    value: ParamValue::Bool(true),
                    span: *at,
                });
            }
            if let Some(m) = &mutex {
                vx.params.insert(Param {
                    name: "mutex".into(),
                    value: ParamValue::String(m.clone()),
                    span,
                });
            }
        }
    }

    fn models(&mut self, root: &Node, b: &mut Building, shift: Vec2) {
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
