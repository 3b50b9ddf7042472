//! Site tree → IR. Positions are metres, y up, in the site frame, which becomes the map
//! frame (plus the offset mapc's extension records, for maps converted from wgs84 or
//! offset cartesian maps). Problems become diagnostics and the element is dropped;
//! lowering always continues.

mod anchors;
mod level;
mod lift;
mod models;
mod navigation;
mod read;
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
}
