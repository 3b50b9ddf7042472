//! Lowering: located YAML tree -> IR with file coordinates. Positions are filled in by
//! `transform` afterwards, once every level's alignment is known.

mod crowd;
mod graph;
mod level;
mod lift;
mod read;
mod shapes;
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
}

#[cfg(test)]
mod tests;
