//! Lowering: located YAML tree -> IR with file coordinates. Positions are filled in by
//! `transform` afterwards, once every level's alignment is known.

use crate::yaml::{Kind, Lists, Node, Scalar};
use mapc_ir::*;
use std::collections::HashSet;
use std::fmt::Display;

/// "<what> `<key>`", formatted only when a diagnostic needs it (lowering reads tens of
/// thousands of fields and almost never reports one).
struct Field<'a>(&'a str, &'a str);

impl Display for Field<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} `{}`", self.0, self.1)
    }
}

pub(crate) struct Lower<'d> {
    pub diags: &'d mut Vec<Diagnostic>,
}

/// One slot per entry of a level's `vertices` list, in file order: `None` for an entry
/// that did not lower (already reported). Edges and polygons index this table, so a bad
/// vertex neither shifts the indices of the ones after it nor enters the IR.
type VertexSlots = [Option<Handle<Vertex>>];

/// An entry of `lanes`, `walls`, `measurements`, `doors` or `human_lanes` whose two vertex
/// indices resolved.
struct Edge {
    start: Handle<Vertex>,
    end: Handle<Vertex>,
    params: Params,
    /// Names of parameters present in the file but malformed (already reported as E0105
    /// or E0104), so that a required one is not reported a second time as missing.
    invalid: Vec<String>,
    span: Span,
}

impl Edge {
    fn is_invalid(&self, name: &str) -> bool {
        self.invalid.iter().any(|n| n == name)
    }
}

/// What reading a level's edge lists (`lanes`, `walls`, ...) needs.
struct EdgeList<'e, 's> {
    level: Handle<Level>,
    slots: &'e VertexSlots,
    what: &'e str,
    lists: &'e Lists<'s>,
}

impl<'s> EdgeList<'_, 's> {
    /// Reads the level list `key` entry by entry and hands each edge whose indices resolved
    /// to `element`, so that an entry's tree is freed before the next is read and no list
    /// of edges is ever whole. Diagnostics of `element` follow those of reading the whole
    /// list (indices, parameters), in the order of a list read first and lowered after.
    fn each(
        &self,
        l: &mut Lower,
        b: &mut Building,
        node: &mut Node<'s>,
        key: &str,
        mut element: impl FnMut(&mut Lower, &mut Building, Edge),
    ) {
        let Some(list) = node.get_mut(key).map(Node::take) else {
            return;
        };
        if l.seq(&list, &format!("the {key} of {}", self.what))
            .is_none()
        {
            return;
        }
        let mut later = Vec::new();
        for e in self.lists.items(list) {
            if let Some(x) = l.edge(b, self.level, &e, key, self.slots) {
                drop(e);
                let n = l.diags.len();
                element(l, b, x);
                later.extend(l.diags.drain(n..));
            }
        }
        l.diags.append(&mut later);
    }
}

/// Keys each element may carry; anything else gets a typo warning.
const ROOT_KEYS: &[&str] = &[
    "name",
    "building_name",
    "coordinate_system",
    "reference_level_name",
    "levels",
    "lifts",
    "parameters",
    "graphs",
    "crowd_sim",
    "map_version",
];
const LEVEL_KEYS: &[&str] = &[
    "elevation",
    "drawing",
    "x_meters",
    "y_meters",
    "vertices",
    "fiducials",
    "measurements",
    "lanes",
    "walls",
    "doors",
    "human_lanes",
    "floors",
    "holes",
    "models",
    "features",
    "constraints",
    "layers",
    "flattened_x_offset",
    "flattened_y_offset",
    // rmf_site's legacy export writes it (always empty there); nothing generates from it.
    "physical_cameras",
];

/// Vertex parameters the format gives a meaning (waypoint roles).
const VERTEX_PARAMS: &[&str] = &[
    "is_charger",
    "is_parking_spot",
    "is_holding_point",
    "is_passthrough_point",
    "is_cleaning_zone",
    "dock_name",
    "pickup_dispenser",
    "dropoff_ingestor",
    "spawn_robot_type",
    "spawn_robot_name",
    "mutex",
    "lift_cabin",
    "merge_radius",
    "human_goal_set_name",
];

impl Lower<'_> {
    pub(crate) fn err(
        &mut self,
        code: &'static str,
        span: Span,
        msg: impl Into<String>,
        help: &str,
    ) {
        self.diags
            .push(Diagnostic::error(code, span, msg).with_help(help));
    }
    pub(crate) fn warn(
        &mut self,
        code: &'static str,
        span: Span,
        msg: impl Into<String>,
        help: &str,
    ) {
        self.diags
            .push(Diagnostic::warning(code, span, msg).with_help(help));
    }

    pub(crate) fn wrong_type(&mut self, node: &Node, what: &str, expected: &str) {
        self.err(
            "E0101",
            node.span,
            format!("{what} must be {expected}, found {}", node.type_name()),
            &format!("write {what} as {expected}"),
        );
    }

    /// Entries of a mapping, warning about duplicate keys. `null` is an empty mapping
    /// (with a warning); other types are an error.
    pub fn map<'n, 's>(
        &mut self,
        node: &'n Node<'s>,
        what: impl Display + Copy,
    ) -> Option<&'n [(Node<'s>, Node<'s>)]> {
        match &node.kind {
            Kind::Map(m) => {
                if m.len() > 1 {
                    // Most mappings are small parameter maps: compare pairwise there and
                    // hash only large ones.
                    let small = m.len() <= 16;
                    let mut seen = HashSet::new();
                    for (i, (k, _)) in m.iter().enumerate() {
                        if let Some(t) = k.key_text() {
                            let dup = if small {
                                m[..i].iter().any(|(p, _)| p.key_text() == Some(t))
                            } else {
                                !seen.insert(t)
                            };
                            if dup {
                                self.warn(
                                    "W0102",
                                    k.span,
                                    format!("duplicate key `{t}` in {what}; the last one is used"),
                                    "remove or rename one of the duplicates",
                                );
                            }
                        }
                    }
                }
                Some(m)
            }
            _ if node.is_null() => {
                self.warn(
                    "W0101",
                    node.span,
                    format!("{what} is null; treated as empty"),
                    "write `{}` for an empty mapping, or remove the key",
                );
                Some(&[])
            }
            _ => {
                self.wrong_type(node, &what.to_string(), "a mapping");
                None
            }
        }
    }

    pub fn seq<'n, 's>(
        &mut self,
        node: &'n Node<'s>,
        what: impl Display + Copy,
    ) -> Option<&'n [Node<'s>]> {
        match &node.kind {
            Kind::Seq(s) => Some(s),
            _ if node.is_null() => {
                self.warn(
                    "W0101",
                    node.span,
                    format!("{what} is null; treated as empty"),
                    "write `[]` for an empty list, or remove the key",
                );
                Some(&[])
            }
            // The reference iterates it as an empty list, and public maps have `walls: {}`.
            Kind::Map(m) if m.is_empty() => {
                self.warn(
                    "W0101",
                    node.span,
                    format!("{what} is an empty mapping `{{}}`; treated as an empty list"),
                    "write `[]` for an empty list, or remove the key",
                );
                Some(&[])
            }
            _ => {
                self.wrong_type(node, &what.to_string(), "a sequence");
                None
            }
        }
    }

    fn unknown_keys(&mut self, entries: &[(Node, Node)], known: &[&str], what: &str) {
        for (k, _) in entries {
            if let Some(t) = k.key_text() {
                if known.contains(&t) {
                    continue;
                }
                // Close to a known key: a typo whose value would be silently lost. Far from
                // every known key: a tool-specific extension, which maps may carry.
                match crate::spelling::closest(t, known) {
                    Some(m) => self.err(
                        "E0112",
                        k.span,
                        format!("unknown key `{t}` in {what}; did you mean `{m}`?"),
                        &format!("rename it to `{m}`; as written it is ignored"),
                    ),
                    None => self.warn(
                        "W0103",
                        k.span,
                        format!("unknown key `{t}` in {what}; it is ignored"),
                        "check the spelling against the .building.yaml format",
                    ),
                }
            }
        }
    }

    /// Vertex parameters close to a known one (`is_chargr`): errors, since the role would
    /// silently disappear. Others are free-form and stay quiet.
    fn misspelled_params(&mut self, node: &Node, what: impl Display) {
        let Some(entries) = node.as_map() else {
            return;
        };
        for (k, _) in entries {
            let Some(t) = k.key_text() else { continue };
            if VERTEX_PARAMS.contains(&t) {
                continue;
            }
            if let Some(m) = crate::spelling::closest(t, VERTEX_PARAMS) {
                self.err(
                    "E0112",
                    k.span,
                    format!("unknown parameter `{t}` of {what}; did you mean `{m}`?"),
                    &format!("rename it to `{m}`; as written it is ignored"),
                );
            }
        }
    }

    pub fn f64(&mut self, node: &Node, what: impl Display) -> Option<f64> {
        match node.as_f64() {
            Some(v) if v.is_finite() => Some(v),
            Some(_) => {
                self.err(
                    "E0104",
                    node.span,
                    format!("{what} is not a finite number"),
                    "use a finite number",
                );
                None
            }
            None => {
                self.wrong_type(node, &what.to_string(), "a number");
                None
            }
        }
    }

    pub fn i64(&mut self, node: &Node, what: impl Display) -> Option<i64> {
        let v = node.as_i64();
        if v.is_none() {
            self.wrong_type(node, &what.to_string(), "an integer");
        }
        v
    }

    /// A `graphs` key: an integer, or an integer written as a string (traffic-editor-js
    /// and serde-based exporters write `'0':`, which the reference's Python reads too).
    fn graph_key(&mut self, node: &Node) -> Option<i64> {
        if let Some(i) = node.as_i64() {
            return Some(i);
        }
        let text = node.key_text().map(str::trim);
        if let Some(i) = text.and_then(|t| t.parse::<i64>().ok()) {
            return Some(i);
        }
        self.wrong_type(
            node,
            "a graph index",
            "an integer (or an integer in quotes)",
        );
        None
    }

    pub fn bool(&mut self, node: &Node, what: impl Display) -> Option<bool> {
        // Old files and crowd_sim write 0/1 for booleans.
        match node.scalar() {
            Some(Scalar::Bool(b)) => Some(b),
            Some(Scalar::Int(i)) if i == 0 || i == 1 => Some(i == 1),
            _ => {
                self.wrong_type(node, &what.to_string(), "a boolean");
                None
            }
        }
    }

    pub fn string(&mut self, node: &Node, what: impl Display) -> Option<String> {
        match &node.kind {
            Kind::Scalar { text, .. } if !node.is_null() => Some(text.to_string()),
            _ if node.is_null() => Some(String::new()),
            _ => {
                self.wrong_type(node, &what.to_string(), "a string");
                None
            }
        }
    }

    fn require<'n, 's>(
        &mut self,
        parent: &'n Node<'s>,
        key: &str,
        what: &str,
    ) -> Option<&'n Node<'s>> {
        let v = parent.get(key);
        if v.is_none() {
            self.err(
                "E0102",
                parent.span,
                format!("{what} has no `{key}`"),
                &format!("add `{key}` to {what}"),
            );
        }
        v
    }

    fn opt_f64(&mut self, parent: &Node, key: &str, what: &str, default: f64) -> f64 {
        match parent.get(key) {
            Some(n) => self.f64(n, Field(what, key)).unwrap_or(default),
            None => default,
        }
    }
    fn opt_i64(&mut self, parent: &Node, key: &str, what: &str, default: i64) -> i64 {
        match parent.get(key) {
            Some(n) => self.i64(n, Field(what, key)).unwrap_or(default),
            None => default,
        }
    }
    fn opt_string(&mut self, parent: &Node, key: &str, what: &str) -> String {
        match parent.get(key) {
            Some(n) => self.string(n, Field(what, key)).unwrap_or_default(),
            None => String::new(),
        }
    }
    fn opt_bool(&mut self, parent: &Node, key: &str, what: &str, default: bool) -> bool {
        match parent.get(key) {
            Some(n) => self.bool(n, Field(what, key)).unwrap_or(default),
            None => default,
        }
    }
    fn req_f64(&mut self, parent: &Node, key: &str, what: &str) -> Option<f64> {
        let n = self.require(parent, key, what)?;
        self.f64(n, Field(what, key))
    }
    fn req_string(&mut self, parent: &Node, key: &str, what: &str) -> Option<String> {
        let n = self.require(parent, key, what)?;
        self.string(n, Field(what, key))
    }

    /// A `{name: [type_code, value], ...}` map.
    pub fn params(&mut self, node: &Node, what: impl Display + Copy) -> Params {
        self.params_checked(node, what).0
    }

    /// [`Self::params`], plus the names of the parameters that are present but malformed
    /// (reported here, and left out of the `Params`).
    fn params_checked(&mut self, node: &Node, what: impl Display + Copy) -> (Params, Vec<String>) {
        let mut out = Params::default();
        let mut invalid = Vec::new();
        let Some(entries) = self.map(node, format_args!("the parameters of {what}")) else {
            return (out, invalid);
        };
        // A later duplicate replaces the earlier one in place. Name -> position in `out`
        // for long lists, without a scan per parameter (maps are untrusted: a lane may have
        // 10^5 of them); the few of a usual element are scanned (a hash map per vertex was
        // a tenth of lowering).
        let mut position: Option<std::collections::HashMap<&str, usize>> =
            (entries.len() > 16).then(std::collections::HashMap::new);
        out.0.reserve_exact(entries.len());
        for (k, v) in entries {
            let Some(name) = k.key_text() else {
                self.wrong_type(k, "a parameter name", "a string");
                continue;
            };
            match self.param_value(v, name) {
                Some(value) => {
                    let p = Param {
                        name: name.to_string(),
                        value,
                        span: v.span,
                    };
                    let earlier = match &position {
                        Some(m) => m.get(name).copied(),
                        None => out.0.iter().position(|q| q.name == name),
                    };
                    match earlier {
                        Some(i) => out.0[i] = p,
                        None => {
                            if let Some(m) = &mut position {
                                m.insert(name, out.0.len());
                            }
                            out.0.push(p);
                        }
                    }
                }
                None => invalid.push(name.to_string()),
            }
        }
        out.0.shrink_to_fit();
        (out, invalid)
    }

    fn param_value(&mut self, v: &Node, name: &str) -> Option<ParamValue> {
        let help = "write parameters as `[type_code, value]` with type_code 1 string, 2 int, 3 double, 4 bool";
        let Some([code, value]) = v.as_seq() else {
            self.err(
                "E0105",
                v.span,
                format!(
                    "parameter `{name}` must be a `[type_code, value]` pair, found {}",
                    v.type_name()
                ),
                help,
            );
            return None;
        };
        let bad = |l: &mut Self, expected: &str| {
            l.err(
                "E0105",
                value.span,
                format!(
                    "parameter `{name}` has type code {} ({expected}) but its value is {}",
                    code.as_i64().unwrap_or(0),
                    value.type_name()
                ),
                help,
            );
            None
        };
        match code.as_i64() {
            Some(1) => match &value.kind {
                Kind::Scalar { text, .. } => Some(ParamValue::String(if value.is_null() {
                    String::new()
                } else {
                    text.to_string()
                })),
                _ => bad(self, "string"),
            },
            Some(2) => match value.scalar() {
                Some(Scalar::Int(i)) => Some(ParamValue::Int(i)),
                _ => bad(self, "int"),
            },
            Some(3) => match value.as_f64() {
                Some(f) if f.is_finite() => Some(ParamValue::Double(f)),
                Some(_) => {
                    self.err(
                        "E0104",
                        value.span,
                        format!("parameter `{name}` is not a finite number"),
                        "use a finite number",
                    );
                    None
                }
                None => bad(self, "double"),
            },
            Some(4) => match value.as_bool() {
                Some(b) => Some(ParamValue::Bool(b)),
                _ => bad(self, "bool"),
            },
            _ => {
                self.err(
                    "E0105",
                    code.span,
                    format!("parameter `{name}` has an unknown type code"),
                    help,
                );
                None
            }
        }
    }

    /// The whole document.
    /// The level lists may have been left out of the tree (`lists` reads them).
    pub fn building<'s>(&mut self, root: &mut Node<'s>, lists: &Lists<'s>) -> Option<Building> {
        let root_entries = self.map(root, "the document root")?;
        self.unknown_keys(root_entries, ROOT_KEYS, "the building");

        // `building_name` is the 2019 spelling; the generator prefers it.
        let name = match (root.get("building_name"), root.get("name")) {
            (Some(b), n) => {
                let b = self.string(b, "`building_name`");
                if let (Some(b), Some(n)) = (&b, n.and_then(|n| n.key_text())) {
                    if b != n {
                        self.warn(
                            "W0104",
                            root.get("name").map_or(root.span, |n| n.span),
                            format!("both `building_name: {b}` and `name: {n}` are set; `building_name` is used"),
                            "remove the legacy `building_name` key",
                        );
                    }
                }
                b
            }
            (None, Some(n)) => self.string(n, "`name`"),
            (None, None) => {
                self.err(
                    "E0102",
                    root.span,
                    "the building has no `name`",
                    "add `name: <building name>` at the top level",
                );
                None
            }
        }
        .unwrap_or_default();

        let coordinate_system = match root.get("coordinate_system") {
            None => CoordinateSystem::ReferenceImage,
            Some(n) => match n.key_text() {
                Some("reference_image") => CoordinateSystem::ReferenceImage,
                Some("cartesian_meters") => CoordinateSystem::CartesianMeters,
                Some("wgs84") => CoordinateSystem::Wgs84,
                Some("web_mercator") => CoordinateSystem::WebMercator,
                _ => {
                    self.err(
                        "E0106",
                        n.span,
                        "unknown `coordinate_system`",
                        "use one of reference_image, cartesian_meters, wgs84, web_mercator",
                    );
                    // Read positions as they are, without pixel-scale warnings that would
                    // only follow from this error.
                    CoordinateSystem::CartesianMeters
                }
            },
        };

        let params = match root.get("parameters") {
            Some(p) => self.params(p, "the building"),
            None => Params::default(),
        };

        let mut b = Building::new(name, coordinate_system, params);
        b.spans = BuildingSpans {
            root: root.span,
            name: root
                .get("building_name")
                .or(root.get("name"))
                .map_or(root.span, |n| n.span),
            coordinate_system: root.get("coordinate_system").map_or(root.span, |n| n.span),
            parameters: root.get("parameters").map_or(root.span, |n| n.span),
        };
        b.map_version = root
            .get("map_version")
            .and_then(|n| n.key_text())
            .map(str::to_string);

        let levels_node = self.require(root, "levels", "the building")?;
        let levels_span = levels_node.span;
        let level_entries = self.map(levels_node, "`levels`")?;
        // A duplicated level name (reported by `map`) keeps its last definition, as
        // everywhere else, at the position of that last definition.
        let mut last = std::collections::HashMap::new();
        for (i, (k, _)) in level_entries.iter().enumerate() {
            if let Some(name) = k.key_text() {
                last.insert(name, i);
            }
        }
        let mut chosen = Vec::new();
        for (i, (k, _)) in level_entries.iter().enumerate() {
            let Some(name) = k.key_text() else {
                self.wrong_type(k, "a level name", "a string");
                continue;
            };
            if last.get(name) == Some(&i) {
                chosen.push((i, name.to_string(), k.span));
            }
        }
        // Levels are lowered from the tree mutably: each frees its large lists once read.
        if let Some(entries) = root.get_mut("levels").and_then(Node::as_map_mut) {
            // `chosen` is in document order: each entry is taken once, as it comes.
            let mut chosen = chosen.into_iter().peekable();
            for (i, (_, node)) in entries.iter_mut().enumerate() {
                if let Some((_, name, span)) = chosen.next_if(|c| c.0 == i) {
                    self.level(&mut b, &name, node, span, lists);
                }
            }
        }
        if b.levels.is_empty() {
            self.err(
                "E0110",
                levels_span,
                "the building has no levels",
                "add at least one level under `levels`",
            );
            return None;
        }

        b.reference_level = match root.get("reference_level_name") {
            None => b.levels.handle(0)?,
            Some(n) => match self.level_ref(&b, n, "`reference_level_name`") {
                Some(h) => h,
                None => b.levels.handle(0)?,
            },
        };

        if let Some(lifts) = root.get("lifts") {
            if let Some(entries) = self.map(lifts, "`lifts`") {
                for (k, v) in entries {
                    let Some(name) = k.key_text() else {
                        self.wrong_type(k, "a lift name", "a string");
                        continue;
                    };
                    if let Some(lift) = self.lift(&b, name, v) {
                        b.lifts.append(lift, k.span);
                    }
                }
            }
        }

        if let Some(g) = root.get("graphs") {
            if let Some(entries) = self.map(g, "`graphs`") {
                for (k, v) in entries {
                    let Some(index) = self.graph_key(k) else {
                        continue;
                    };
                    b.graphs.push(GraphInfo {
                        index,
                        name: self.opt_string(v, "name", "the graph"),
                        default_lane_width: self.opt_f64(v, "default_lane_width", "the graph", 1.0),
                        unnamed: Vec::new(),
                    });
                }
            }
        }

        if let Some(c) = root.get("crowd_sim") {
            b.crowd_sim = self.crowd_sim(c);
        }
        Some(b)
    }

    pub fn level_ref(&mut self, b: &Building, n: &Node, what: &str) -> Option<Handle<Level>> {
        let name = self.string(n, what)?;
        let h = b.level_by_name(&name);
        if h.is_none() {
            let names: Vec<&str> = b.levels.iter().map(|(_, l)| l.name.as_str()).collect();
            self.err(
                "E0107",
                n.span,
                format!("{what} names level `{name}`, which does not exist"),
                &format!("use one of the levels: {}", names.join(", ")),
            );
        }
        h
    }

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

    fn coord_pair(&mut self, x: &Node, y: &Node, what: &str) -> Option<Vec2> {
        let x = self.f64(x, format_args!("the x coordinate of {what}"));
        let y = self.f64(y, format_args!("the y coordinate of {what}"));
        Some(Vec2::new(x?, y?))
    }

    fn vertex(&mut self, level: Handle<Level>, node: &Node) -> Option<Vertex> {
        let Some(items) = node.as_seq() else {
            self.wrong_type(node, "a vertex", "a sequence `[x, y, z, name, {params}]`");
            return None;
        };
        if items.len() < 4 {
            self.err(
                "E0101",
                node.span,
                format!(
                    "a vertex must have at least 4 elements `[x, y, z, name]`, found {}",
                    items.len()
                ),
                "write the vertex as `[x, y, z, name]` (name may be \"\")",
            );
            return None;
        }
        let raw = self.coord_pair(&items[0], &items[1], "a vertex")?;
        // items[2] (z) is a placeholder the generator ignores; check it is a number anyway.
        self.f64(&items[2], "the z of a vertex");
        let name = self.string(&items[3], "a vertex name")?;
        let params = match items.get(4) {
            Some(p) => {
                self.misspelled_params(p, format_args!("vertex `{name}`"));
                self.params(p, format_args!("vertex `{name}`"))
            }
            None => Params::default(),
        };
        if items.len() > 5 {
            self.warn(
                "W0103",
                items[5].span,
                "extra elements after the vertex parameters are ignored",
                "remove them",
            );
        }
        let roles = WaypointRoles::from_params(&params);
        Some(Vertex {
            level,
            name,
            pos: raw,
            raw,
            params,
            roles: roles.into(),
        })
    }

    fn edge(
        &mut self,
        b: &Building,
        level: Handle<Level>,
        node: &Node,
        key: &str,
        slots: &VertexSlots,
    ) -> Option<Edge> {
        let Some(items) = node.as_seq() else {
            self.wrong_type(
                node,
                &format!("an entry of `{key}`"),
                "a sequence `[start, end, {params}]`",
            );
            return None;
        };
        if items.len() < 2 {
            self.err(
                "E0101",
                node.span,
                format!(
                    "an entry of `{key}` needs two vertex indices, found {} elements",
                    items.len()
                ),
                "write it as `[start_index, end_index, {params}]`",
            );
            return None;
        }
        let s = self.vertex_index(b, level, &items[0], slots);
        let e = self.vertex_index(b, level, &items[1], slots);
        // Parameters are checked even when an index failed: their problems are their own.
        let (params, invalid) = match items.get(2) {
            Some(p) => self.params_checked(p, format_args!("an entry of `{key}`")),
            None => Default::default(),
        };
        Some(Edge {
            start: s?,
            end: e?,
            params,
            invalid,
            span: node.span,
        })
    }

    /// The vertex at file position `n` of the level. Out of range is E0103, counted against
    /// the file's `vertices` list; a vertex that failed to lower gives `None` without a
    /// further diagnostic (it has its own).
    fn vertex_index(
        &mut self,
        b: &Building,
        level: Handle<Level>,
        n: &Node,
        slots: &VertexSlots,
    ) -> Option<Handle<Vertex>> {
        let i = self.i64(n, "a vertex index")?;
        let nverts = slots.len();
        if i < 0 || i as u64 >= nverts as u64 {
            self.err(
                "E0103",
                n.span,
                format!(
                    "vertex index {i} is out of range: level `{}` has {nverts} vertices (0..{})",
                    b.levels[level].name,
                    nverts.saturating_sub(1)
                ),
                "use the 0-based index of a vertex in this level's `vertices` list",
            );
            return None;
        }
        slots[i as usize]
    }

    fn lane(&mut self, level: Handle<Level>, edge: Edge) -> Option<Lane> {
        let graph_idx_invalid = edge.is_invalid("graph_idx");
        let Edge {
            start,
            end,
            params,
            span,
            ..
        } = edge;
        let graph = match params.get("graph_idx") {
            // Present but malformed: already reported as E0105.
            None if graph_idx_invalid => return None,
            None => {
                self.err(
                    "E0102",
                    span,
                    "lane has no `graph_idx` parameter",
                    "add `graph_idx: [2, <fleet graph number>]` to the lane",
                );
                return None;
            }
            Some(ParamValue::Int(i)) if *i >= 0 => *i,
            Some(v) => {
                let span = params.param("graph_idx").map_or(span, |p| p.span);
                self.err(
                    "E0105",
                    span,
                    format!(
                        "lane `graph_idx` must be a non-negative int, found {}",
                        match v {
                            ParamValue::Int(i) => i.to_string(),
                            other => other.type_name().to_string(),
                        }
                    ),
                    "write `graph_idx: [2, 0]` (type code 2, a graph number from 0)",
                );
                return None;
            }
        };
        let bidirectional = match params.get("bidirectional") {
            None => false,
            Some(ParamValue::Bool(b)) => *b,
            Some(v) => {
                self.err(
                    "E0105",
                    params.param("bidirectional").map_or(span, |p| p.span),
                    format!(
                        "lane `bidirectional` must be a bool, found {}",
                        v.type_name()
                    ),
                    "write `bidirectional: [4, true]` or `[4, false]`",
                );
                return None;
            }
        };
        let orientation = match params.str("orientation").unwrap_or("") {
            "" => Orientation::Any,
            "forward" => Orientation::Forward,
            "backward" => Orientation::Backward,
            other => Orientation::Other(other.to_string()),
        };
        let speed_limit = match params.get("speed_limit") {
            None => None,
            Some(v) => match v.as_f64() {
                Some(s) => (s > 0.0).then_some(s),
                None => {
                    self.err(
                        "E0105",
                        params.param("speed_limit").map_or(span, |p| p.span),
                        "lane `speed_limit` must be a number",
                        "write `speed_limit: [3, <metres per second>]` (0 for none)",
                    );
                    None
                }
            },
        };
        let s = |k: &str| params.str(k).filter(|s| !s.is_empty()).map(str::to_string);
        let (mutex, demo_mock_floor_name, demo_mock_lift_name) = (
            s("mutex"),
            s("demo_mock_floor_name"),
            s("demo_mock_lift_name"),
        );
        // `graph_idx` and `bidirectional` are whole in their fields; nearly every lane has
        // both, and as parameters they took more memory than the rest of the lane.
        let mut params = params;
        params
            .0
            .retain(|p| p.name != "graph_idx" && p.name != "bidirectional");
        params.0.shrink_to_fit();
        Some(Lane {
            level,
            start,
            end,
            graph,
            bidirectional,
            orientation,
            speed_limit,
            mutex,
            demo_mock_floor_name,
            demo_mock_lift_name,
            params,
        })
    }

    fn door(&mut self, level: Handle<Level>, edge: Edge) -> Option<Door> {
        let (name_invalid, type_invalid) = (edge.is_invalid("name"), edge.is_invalid("type"));
        let Edge {
            start,
            end,
            params,
            span,
            ..
        } = edge;
        let Some(name) = params.str("name").map(str::to_string) else {
            // Present but malformed: already reported as E0105.
            if name_invalid {
                return None;
            }
            self.err(
                "E0102",
                span,
                "door has no `name` parameter of type string",
                "add `name: [1, <door name>]` to the door",
            );
            return None;
        };
        let kind = match params.str("type") {
            Some(t) => DoorKind::parse(t),
            None if type_invalid => return None,
            None => {
                self.err(
                    "E0102",
                    span,
                    format!("door `{name}` has no `type` parameter of type string"),
                    "add `type: [1, hinged]` (or double_hinged, sliding, double_sliding)",
                );
                return None;
            }
        };
        let motion_axis = match params.str("motion_axis") {
            Some("end") => MotionAxis::End,
            _ => MotionAxis::Start,
        };
        Some(Door {
            level,
            start,
            end,
            motion_axis,
            // Read as a number: files write both `[2, -1]` and `[3, -1.0]`.
            motion_direction: params
                .f64("motion_direction")
                .map_or(1, |v| v.round() as i64),
            motion_degrees: params.f64("motion_degrees").unwrap_or(90.0),
            right_left_ratio: params.f64("right_left_ratio").unwrap_or(1.0),
            plugin: params.str("plugin") != Some("none"),
            name,
            kind,
            params,
        })
    }

    fn polygon(
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

    fn model(&mut self, level: Handle<Level>, node: &Node) -> Option<Model> {
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

    fn fiducial(&mut self, level: Handle<Level>, node: &Node) -> Option<Fiducial> {
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

    fn features(&mut self, list: &Node, what: &str) -> Vec<Feature> {
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

    fn layer(&mut self, name: String, node: &Node) -> Option<Layer> {
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

    fn lift(&mut self, b: &Building, name: &str, node: &Node) -> Option<Lift> {
        let what = format!("lift `{name}`");
        self.map(node, &what)?;
        let x = self.req_f64(node, "x", &what);
        let y = self.req_f64(node, "y", &what);
        let yaw = self.req_f64(node, "yaw", &what);
        let width = self.req_f64(node, "width", &what);
        let depth = self.req_f64(node, "depth", &what);
        let level_opt = |l: &mut Self, key: &str| -> Option<Handle<Level>> {
            let n = node.get(key)?;
            if n.is_null() || n.key_text() == Some("") {
                return None;
            }
            l.level_ref(b, n, &format!("{what} `{key}`"))
        };
        let reference_level = level_opt(self, "reference_floor_name").unwrap_or(b.reference_level);
        let initial_level = level_opt(self, "initial_floor_name");
        let lowest_level = level_opt(self, "lowest_floor");
        let highest_level = level_opt(self, "highest_floor");
        let plugins = self.opt_bool(node, "plugins", &what, true);

        let mut doors = Vec::new();
        if let Some(d) = node.get("doors") {
            for (k, v) in self.map(d, &format!("the doors of {what}")).unwrap_or(&[]) {
                let dname = k.key_text().unwrap_or_default().to_string();
                let dwhat = format!("lift door `{dname}`");
                if self.map(v, &dwhat).is_none() {
                    continue;
                }
                let door_type = self
                    .require(v, "door_type", &dwhat)
                    .and_then(|n| self.i64(n, "`door_type`"));
                let dx = self.req_f64(v, "x", &dwhat);
                let dy = self.req_f64(v, "y", &dwhat);
                let dw = self.req_f64(v, "width", &dwhat);
                let mao = self.req_f64(v, "motion_axis_orientation", &dwhat);
                if let (Some(door_type), Some(dx), Some(dy), Some(width), Some(mao)) =
                    (door_type, dx, dy, dw, mao)
                {
                    doors.push(LiftDoor {
                        name: dname,
                        door_type,
                        pos: Vec2::new(dx, dy),
                        width,
                        motion_axis_orientation: mao,
                        span: k.span,
                    });
                }
            }
        }
        let mut level_doors = Vec::new();
        if let Some(ld) = node.get("level_doors") {
            for (k, v) in self
                .map(ld, &format!("the level_doors of {what}"))
                .unwrap_or(&[])
            {
                let Some(level) = self.level_ref(b, k, &format!("a level_doors key of {what}"))
                else {
                    continue;
                };
                let names = self
                    .seq(v, "a level_doors entry")
                    .unwrap_or(&[])
                    .iter()
                    .filter_map(|n| self.string(n, "a lift door name").map(|s| (s, n.span)))
                    .collect();
                level_doors.push(LevelDoors {
                    level,
                    doors: names,
                    span: k.span,
                });
            }
        }
        let raw = Vec2::new(x?, y?);
        Some(Lift {
            name: name.to_string(),
            pos: raw,
            raw,
            yaw: yaw?,
            width: width?,
            depth: depth?,
            reference_level,
            initial_level,
            lowest_level,
            highest_level,
            plugins,
            doors,
            level_doors,
        })
    }

    /// crowd_sim is read leniently: the generator ignores it and the editor resets it to
    /// defaults when it does not parse, so problems here are warnings.
    pub(crate) fn crowd_sim(&mut self, node: &Node) -> Option<CrowdSim> {
        node.as_map()?;
        let mut inner = Vec::new();
        let cs = {
            let mut l = Lower { diags: &mut inner };
            l.crowd_sim_inner(node)
        };
        for mut d in inner {
            d.severity = Severity::Warning;
            d.code = "W0105";
            d.message = format!("crowd_sim: {}", d.message);
            self.diags.push(d);
        }
        Some(cs)
    }

    fn crowd_sim_inner(&mut self, n: &Node) -> CrowdSim {
        let w = "crowd_sim";
        let list = |l: &mut Self, key: &str| -> Vec<Node> {
            n.get(key)
                .and_then(|s| l.seq(s, &format!("crowd_sim `{key}`")))
                .map(|s| s.to_vec())
                .unwrap_or_default()
        };
        let strings = |l: &mut Self, n: &Node, key: &str| -> Vec<String> {
            n.get(key)
                .and_then(|s| l.seq(s, key))
                .unwrap_or(&[])
                .iter()
                .filter_map(|s| l.string(s, key))
                .collect()
        };
        let mut cs = CrowdSim {
            enable: self.opt_bool(n, "enable", w, false),
            update_time_step: self.opt_f64(n, "update_time_step", w, 0.1),
            span: n.span,
            ..CrowdSim::default()
        };
        for s in list(self, "states") {
            cs.states.push(CrowdState {
                name: self.opt_string(&s, "name", "a state"),
                goal_set: self.opt_i64(&s, "goal_set", "a state", -1),
                navmesh_file_name: self.opt_string(&s, "navmesh_file_name", "a state"),
                is_final: self.opt_bool(&s, "final", "a state", false),
                span: s.span,
            });
        }
        for g in list(self, "goal_sets") {
            cs.goal_sets.push(GoalSet {
                set_id: self.opt_i64(&g, "set_id", "a goal set", 0),
                capacity: self.opt_i64(&g, "capacity", "a goal set", 0),
                set_area: strings(self, &g, "set_area"),
                span: g.span,
            });
        }
        for p in list(self, "agent_profiles") {
            let f = |l: &mut Self, k: &str| l.opt_f64(&p, k, "an agent profile", 0.0);
            cs.agent_profiles.push(AgentProfile {
                name: self.opt_string(&p, "name", "an agent profile"),
                class: self.opt_i64(&p, "class", "an agent profile", 1),
                max_accel: f(self, "max_accel"),
                max_angle_vel: f(self, "max_angle_vel"),
                max_neighbors: self.opt_i64(&p, "max_neighbors", "an agent profile", 10),
                max_speed: f(self, "max_speed"),
                neighbor_dist: f(self, "neighbor_dist"),
                obstacle_set: self.opt_i64(&p, "obstacle_set", "an agent profile", 1),
                pref_speed: f(self, "pref_speed"),
                r: f(self, "r"),
                orca_tau: f(self, "ORCA_tau"),
                orca_tau_obst: f(self, "ORCA_tauObst"),
                span: p.span,
            });
        }
        for t in list(self, "transitions") {
            let mut targets = Vec::new();
            if let Some(ts) = t.get("Target").and_then(|x| self.seq(x, "`Target`")) {
                for x in ts {
                    targets.push((
                        self.opt_string(x, "name", "a target"),
                        self.opt_f64(x, "weight", "a target", 1.0),
                        x.span,
                    ));
                }
            }
            cs.transitions.push(Transition {
                from: self.opt_string(&t, "from", "a transition"),
                to: self.opt_string(&t, "to", "a transition"),
                targets,
                condition: t.get("Condition").map(|c| self.condition(c, 0)),
                span: t.span,
            });
        }
        if let Some(o) = n.get("obstacle_set") {
            cs.obstacle_set = Some(ObstacleSet {
                class: self.opt_i64(o, "class", "the obstacle set", 1),
                file_name: self.opt_string(o, "file_name", "the obstacle set"),
                kind: self.opt_string(o, "type", "the obstacle set"),
            });
        }
        for g in list(self, "agent_groups") {
            cs.agent_groups.push(AgentGroup {
                group_id: self.opt_i64(&g, "group_id", "an agent group", 0),
                profile_selector: self.opt_string(&g, "profile_selector", "an agent group"),
                state_selector: self.opt_string(&g, "state_selector", "an agent group"),
                agents_number: self.opt_i64(&g, "agents_number", "an agent group", 0),
                agents_name: strings(self, &g, "agents_name"),
                pos: Vec2::new(
                    self.opt_f64(&g, "x", "an agent group", 0.0),
                    self.opt_f64(&g, "y", "an agent group", 0.0),
                ),
                span: g.span,
            });
        }
        for m in list(self, "model_types") {
            let init_pose = m
                .get("init_pose")
                .and_then(|p| self.seq(p, "`init_pose`"))
                .unwrap_or(&[])
                .iter()
                .filter_map(|v| self.f64(v, "an init_pose value"))
                .collect();
            cs.model_types.push(ModelType {
                typename: self.opt_string(&m, "typename", "a model type"),
                animation: self.opt_string(&m, "animation", "a model type"),
                animation_speed: self.opt_f64(&m, "animation_speed", "a model type", 0.0),
                model_uri: self.opt_string(&m, "model_uri", "a model type"),
                init_pose,
            });
        }
        cs
    }

    fn condition(&mut self, c: &Node, depth: usize) -> Condition {
        let kind = self.opt_string(c, "type", "a condition");
        // Depth is bounded by the YAML depth limit already; this is belt and braces.
        let sub = |l: &mut Self, key: &str| -> Box<Condition> {
            Box::new(match c.get(key) {
                Some(n) if depth < 32 => l.condition(n, depth + 1),
                _ => Condition::Other(String::new()),
            })
        };
        match kind.as_str() {
            "goal_reached" => Condition::GoalReached {
                distance: self.opt_f64(c, "distance", "a condition", 0.1),
            },
            "timer" => {
                // Menge's distributions: `c` constant (`value`), `u` uniform (`min`, `max`);
                // the editor writes `dist: c` and `per_agent: true`.
                let dist = self.opt_string(c, "dist", "a timer");
                let duration = if dist == "u" {
                    TimerDuration::Uniform {
                        min: self.opt_f64(c, "min", "a timer", 0.0),
                        max: self.opt_f64(c, "max", "a timer", 0.0),
                    }
                } else {
                    TimerDuration::Const(self.opt_f64(c, "value", "a condition", 0.0))
                };
                Condition::Timer(Timer {
                    duration,
                    per_agent: self.opt_bool(c, "per_agent", "a timer", true),
                })
            }
            "auto" => Condition::Auto,
            "and" => Condition::And(sub(self, "condition1"), sub(self, "condition2")),
            "or" => Condition::Or(sub(self, "condition1"), sub(self, "condition2")),
            "not" => Condition::Not(sub(self, "condition1")),
            other => Condition::Other(other.to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use mapc_ir::{Building, Diagnostic, Handle, Vertex};

    /// Lowers a cartesian map with level `L1` whose body is `level` (indented 4 spaces).
    fn lower(level: &str) -> (Building, Vec<Diagnostic>) {
        let text = format!("name: t\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n{level}");
        let parsed = crate::parse_str("t.building.yaml", &text);
        (parsed.building.expect("a building"), parsed.diagnostics)
    }

    fn codes(diags: &[Diagnostic]) -> Vec<&'static str> {
        diags.iter().map(|d| d.code).collect()
    }

    fn name(b: &Building, v: Handle<Vertex>) -> &str {
        &b.vertices[v].name
    }

    /// traffic-editor-js keys `graphs` by strings; an integer in quotes is an index, any
    /// other string is E0101 at the key.
    #[test]
    fn graph_keys_may_be_integers_in_quotes() {
        let text = "name: t\ncoordinate_system: cartesian_meters\nlevels:\n  L1: {}\ngraphs:\n  '0': {name: a}\n  \"12\": {name: b}\n  3: {name: c}\n  'x1': {name: d}\n";
        let parsed = crate::parse_str("t.building.yaml", text);
        let b = parsed.building.expect("a building");
        let got: Vec<(i64, &str)> = b
            .graphs
            .iter()
            .map(|g| (g.index, g.name.as_str()))
            .collect();
        assert_eq!(got, [(0, "a"), (12, "b"), (3, "c")]);
        assert_eq!(
            codes(&parsed.diagnostics),
            ["E0101"],
            "{:#?}",
            parsed.diagnostics
        );
        assert_eq!(parsed.diagnostics[0].span.line, 9);
    }

    /// `walls: {}` (a public map has it; the reference reads it as no walls) is an empty
    /// list with W0101 at the `{}`; a mapping with entries where a list belongs stays E0101.
    #[test]
    fn an_empty_mapping_is_an_empty_list() {
        let (b, diags) = lower(&format!("{OK_BAD_OK}    walls: {{}}\n"));
        assert_eq!(codes(&diags), ["E0101", "W0101"], "{diags:#?}");
        assert_eq!((diags[1].span.line, diags[1].span.col), (9, 12));
        assert_eq!((b.vertices.len(), b.walls.len()), (2, 0));
        let (_, diags) = lower("    walls: {a: 1}\n");
        assert_eq!(codes(&diags), ["E0101"], "{diags:#?}");
    }

    /// `[ok, bad, ok]`: the bad one (a string x) is E0101 and is not in the IR.
    const OK_BAD_OK: &str =
        "    vertices:\n      - [0, 0, 0, a]\n      - [x, 0, 0, b]\n      - [4, 0, 0, c]\n";

    #[test]
    fn bad_vertex_keeps_file_indices_of_later_vertices() {
        let (b, diags) = lower(&format!(
            "{OK_BAD_OK}    lanes:\n      - [0, 2, {{graph_idx: [2, 0]}}]\n    walls:\n      - [2, 0]\n"
        ));
        assert_eq!(codes(&diags), ["E0101"], "{diags:#?}");
        assert_eq!(b.vertices.len(), 2, "the bad vertex is not in the IR");
        let (_, lane) = b.lanes.iter().next().expect("the lane is kept");
        assert_eq!((name(&b, lane.start), name(&b, lane.end)), ("a", "c"));
        let (_, wall) = b.walls.iter().next().expect("the wall is kept");
        assert_eq!((name(&b, wall.start), name(&b, wall.end)), ("c", "a"));
    }

    #[test]
    fn out_of_range_counts_the_file_vertices() {
        let (b, diags) = lower(&format!(
            "{OK_BAD_OK}    lanes:\n      - [0, 3, {{graph_idx: [2, 0]}}]\n"
        ));
        assert_eq!(codes(&diags), ["E0101", "E0103"], "{diags:#?}");
        assert!(
            diags[1]
                .message
                .contains("level `L1` has 3 vertices (0..2)"),
            "{}",
            diags[1].message
        );
        assert_eq!(b.lanes.len(), 0);
    }

    #[test]
    fn elements_on_a_bad_vertex_are_dropped_silently() {
        let (b, diags) = lower(&format!(
            "{OK_BAD_OK}    lanes:\n      - [0, 1, {{graph_idx: [2, 0]}}]\n      - [1, 2]\n\
             \x20   walls:\n      - [1, 2]\n\
             \x20   doors:\n      - [0, 1, {{name: [1, d], type: [1, hinged]}}]\n\
             \x20   measurements:\n      - [1, 0, {{distance: [3, 1.0]}}]\n\
             \x20   human_lanes:\n      - [2, 1]\n\
             \x20   floors:\n      - vertices: [0, 1, 2]\n\
             \x20   holes:\n      - vertices: [2, 1, 0]\n"
        ));
        // Only the vertex's own error: no E0103, and no E0102 for the lane `[1, 2]` that
        // lacks a graph_idx, since it is dropped before its parameters are read as a lane's.
        assert_eq!(codes(&diags), ["E0101"], "{diags:#?}");
        assert_eq!(b.lanes.len(), 0);
        assert_eq!(b.walls.len(), 0);
        assert_eq!(b.doors.len(), 0);
        assert_eq!(b.measurements.len(), 0);
        assert_eq!(b.human_lanes.len(), 0);
        assert_eq!(b.floors.len(), 0);
        assert_eq!(b.holes.len(), 0);
    }

    #[test]
    fn every_kind_of_bad_vertex_keeps_its_slot() {
        // Not a sequence, too short, non-finite, bad name: four failures, then `e` at 4.
        let (b, diags) = lower(
            "    vertices:\n      - {x: 1}\n      - [0, 0]\n      - [.nan, 0, 0, c]\n      - [0, 0, 0, [n]]\n      - [1, 1, 0, e]\n      - [2, 2, 0, f]\n\
             \x20   lanes:\n      - [4, 5, {graph_idx: [2, 0]}]\n",
        );
        assert_eq!(
            codes(&diags),
            ["E0101", "E0101", "E0104", "E0101"],
            "{diags:#?}"
        );
        let (_, lane) = b.lanes.iter().next().expect("the lane is kept");
        assert_eq!((name(&b, lane.start), name(&b, lane.end)), ("e", "f"));
    }

    /// Two good vertices and one lane with the given parameters.
    fn lane_with(params: &str) -> Vec<Diagnostic> {
        lower(&format!(
            "    vertices:\n      - [0, 0, 0, a]\n      - [4, 0, 0, b]\n    lanes:\n      - [0, 1, {{{params}}}]\n"
        ))
        .1
    }

    #[test]
    fn malformed_graph_idx_is_only_e0105() {
        for p in [
            "graph_idx: 0",
            "graph_idx: [2, \"0\"]",
            "graph_idx: [7, 0]",
            "graph_idx: [2]",
            "graph_idx: [2, 0.5]",
            "graph_idx: [3, .nan]",
        ] {
            let diags = lane_with(p);
            assert_eq!(diags.len(), 1, "{p}: {diags:#?}");
            assert!(
                matches!(diags[0].code, "E0105" | "E0104"),
                "{p}: {diags:#?}"
            );
        }
        // Well-formed parameters of the wrong kind are still E0105 once.
        for p in ["graph_idx: [1, zero]", "graph_idx: [2, -1]"] {
            assert_eq!(codes(&lane_with(p)), ["E0105"], "{p}");
        }
        // Really absent: E0102, as before.
        assert_eq!(codes(&lane_with("bidirectional: [4, true]")), ["E0102"]);
    }

    #[test]
    fn malformed_required_door_and_measurement_params_are_only_e0105() {
        let two = "    vertices:\n      - [0, 0, 0, a]\n      - [4, 0, 0, b]\n";
        for (body, expect) in [
            (
                "    doors:\n      - [0, 1, {name: [1, [d]], type: [1, hinged]}]\n",
                "E0105",
            ),
            (
                "    doors:\n      - [0, 1, {name: [1, d], type: hinged}]\n",
                "E0105",
            ),
            ("    doors:\n      - [0, 1, {type: [1, hinged]}]\n", "E0102"),
            (
                "    measurements:\n      - [0, 1, {distance: [3, far]}]\n",
                "E0105",
            ),
            ("    measurements:\n      - [0, 1, {}]\n", "E0102"),
        ] {
            let (b, diags) = lower(&format!("{two}{body}"));
            assert_eq!(codes(&diags), [expect], "{body}: {diags:#?}");
            assert_eq!(b.doors.len() + b.measurements.len(), 0, "{body}");
        }
    }
}
