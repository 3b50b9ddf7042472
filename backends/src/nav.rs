//! Navigation graphs for RMF fleet adapters (generator.md §4), one document per graph.

use crate::yaml::{self, Yaml};
use crate::OutputFile;
use mapc_ir::*;
use std::collections::BTreeMap;

/// One `<graph>.yaml` per graph index that has at least one lane (any index >= 0, not
/// only 0..8 as in the reference generator).
/// A site's graphs have names, and the file takes the graph's name (made safe as one file
/// name) instead of the index.
pub fn nav_graphs(b: &Building) -> Vec<OutputFile> {
    b.graph_indices()
        .into_iter()
        .map(|g| OutputFile {
            path: format!("{}.yaml", graph_file_stem(b, g)).into(),
            contents: nav_graph_text(b, g).into_bytes(),
        })
        .collect()
}

/// The file name (less `.yaml`) of graph `g`: its index, or for a site its name with path
/// separators, control characters and leading dots made `_` (never empty, never `..`);
/// the index when two graphs would share a name.
pub fn graph_file_stem(b: &Building, g: i64) -> String {
    if b.format != SourceFormat::Site {
        return g.to_string();
    }
    let safe = |name: &str| -> String {
        let s: String = name
            .chars()
            .enumerate()
            .map(|(i, c)| {
                if c == '/' || c == '\\' || c == ':' || c.is_control() || (i == 0 && c == '.') {
                    '_'
                } else {
                    c
                }
            })
            .collect();
        if s.is_empty() {
            g.to_string()
        } else {
            s
        }
    };
    let Some(info) = b.graphs.iter().find(|i| i.index == g) else {
        return g.to_string();
    };
    let stem = safe(&info.name);
    let clash = b
        .graphs
        .iter()
        .any(|o| o.index != g && safe(&o.name) == stem);
    if clash {
        g.to_string()
    } else {
        stem
    }
}

/// The YAML document of graph `graph`. Written entry by entry: a waypoint or lane entry is
/// built, rendered and dropped before the next, so a map of 10^5 waypoints never holds
/// its graph as a tree (that tree took several times the map file's size).
pub fn nav_graph_text(b: &Building, graph: i64) -> String {
    let mut root = vec![("building_name".to_string(), Yaml::str(&b.name))];
    if let Some(crs) = &b.crs_name {
        root.push(("crs_name".into(), Yaml::str(crs)));
    }

    // Every door of every level, sorted by name; a later duplicate replaces an earlier one.
    let mut doors = BTreeMap::new();
    for (_, d) in b.doors.iter() {
        let p = |v: Handle<Vertex>| {
            let pos = b.vertices[v].pos;
            Yaml::Seq(vec![Yaml::Float(pos.x), Yaml::Float(pos.y)])
        };
        doors.insert(
            d.name.clone(),
            Yaml::Map(vec![
                ("endpoints".into(), Yaml::Seq(vec![p(d.start), p(d.end)])),
                ("map".into(), Yaml::str(&b.levels[d.level].name)),
            ]),
        );
    }
    root.push(("doors".into(), Yaml::Map(doors.into_iter().collect())));
    let mut out = String::new();
    yaml::write_entries(&mut out, &root, 0);

    // Levels by name; a later level of the same name replaces an earlier one.
    let mut levels = BTreeMap::new();
    for (lh, level) in b.levels.iter() {
        levels.insert(level.name.as_str(), lh);
    }
    if levels.is_empty() {
        yaml::write_entries(&mut out, &[("levels".into(), Yaml::Map(Vec::new()))], 0);
    } else {
        yaml::write_key(&mut out, "levels", 0);
        for (name, lh) in levels {
            yaml::write_key(&mut out, name, 2);
            nav_level(&mut out, b, lh, graph, 4);
        }
    }

    let mut root = Vec::new();
    let mut lifts = BTreeMap::new();
    for (_, l) in b.lifts.iter() {
        lifts.insert(
            l.name.clone(),
            Yaml::Map(vec![
                (
                    "dims".into(),
                    Yaml::Seq(vec![Yaml::Float(l.width), Yaml::Float(l.depth)]),
                ),
                (
                    "position".into(),
                    Yaml::Seq(vec![
                        Yaml::Float(l.pos.x),
                        Yaml::Float(l.pos.y),
                        Yaml::Float(l.yaw),
                    ]),
                ),
            ]),
        );
    }
    root.push(("lifts".into(), Yaml::Map(lifts.into_iter().collect())));

    if matches!(
        b.coordinate_system,
        CoordinateSystem::Wgs84 | CoordinateSystem::CartesianMeters | CoordinateSystem::WebMercator
    ) {
        root.push((
            "offset".into(),
            Yaml::Seq(vec![Yaml::Float(b.offset.x), Yaml::Float(b.offset.y)]),
        ));
    }
    yaml::write_entries(&mut out, &root, 0);
    out
}

fn param_yaml(v: &ParamValue) -> Yaml {
    match v {
        ParamValue::String(s) => Yaml::str(s),
        ParamValue::Int(i) => Yaml::Int(*i),
        ParamValue::Double(d) => Yaml::Float(*d),
        ParamValue::Bool(x) => Yaml::Bool(*x),
    }
}

/// Writes level `lh`'s `lanes` and `vertices` of graph `graph` at indent `ind`.
fn nav_level(out: &mut String, b: &Building, lh: Handle<Level>, graph: i64, ind: usize) {
    let level = &b.levels[lh];
    let lanes = || {
        level
            .lanes
            .iter()
            .map(|&h| &b.lanes[h])
            .filter(|l| l.graph == graph)
    };

    // Only vertices used by this graph's lanes, numbered by first appearance (by arena
    // index: a table of the level's size rather than a tree of the graph's).
    const NONE: u32 = u32::MAX;
    let mut index = vec![NONE; b.vertices.len()];
    let mut order = Vec::new();
    for lane in lanes() {
        for v in [lane.start, lane.end] {
            if index[v.index()] == NONE {
                index[v.index()] = order.len() as u32;
                order.push(v);
            }
        }
    }
    let lifts_here: Vec<&Lift> = b.lifts_on_level(lh).map(|h| &b.lifts[h]).collect();
    let unnamed: &[Handle<Vertex>] = b
        .graphs
        .iter()
        .find(|g| g.index == graph)
        .map_or(&[], |g| &g.unnamed);

    let lane_entries = lanes().flat_map(|lane| {
        let (s, e) = (
            index[lane.start.index()] as usize,
            index[lane.end.index()] as usize,
        );
        let dock = |v: Handle<Vertex>| b.vertices[v].roles.dock_name.clone();
        let (begin_dock, end_dock) = (dock(lane.start), dock(lane.end));
        let forward = lane_params(b, lh, lane, false, end_dock.clone(), begin_dock.clone());
        let backward = lane
            .bidirectional
            .then(|| lane_yaml(e, s, lane_params(b, lh, lane, true, begin_dock, end_dock)));
        std::iter::once(lane_yaml(s, e, forward)).chain(backward)
    });
    yaml::write_key_seq(out, "lanes", ind, lane_entries);

    let vertices = order.iter().map(|&vh| {
        let v = &b.vertices[vh];
        let mut p: BTreeMap<String, Yaml> = v
            .params
            .iter()
            .map(|p| (p.name.clone(), param_yaml(&p.value)))
            .collect();
        // The vertex's own name wins over a parameter called `name`.
        p.insert("name".into(), Yaml::str(&v.name));
        if unnamed.binary_search(&vh).is_ok() {
            // A site location of other graphs: here the waypoint is not that place, as in
            // rmf_site's export (no name, none of the location's tags or mutex).
            p.insert("name".into(), Yaml::str(""));
            for k in ["is_charger", "is_parking_spot", "is_holding_point", "mutex"] {
                p.remove(k);
            }
        }
        if let Some(lift) = lifts_here.iter().find(|l| l.shaft_contains(v.pos)) {
            p.insert("lift".into(), Yaml::str(&lift.name));
        }
        Yaml::Flow(Box::new(Yaml::Seq(vec![
            Yaml::Float(v.pos.x),
            Yaml::Float(v.pos.y),
            Yaml::Map(p.into_iter().collect()),
        ])))
    });
    yaml::write_key_seq(out, "vertices", ind, vertices);
}

fn lane_yaml(s: usize, e: usize, params: BTreeMap<String, Yaml>) -> Yaml {
    Yaml::Flow(Box::new(Yaml::Seq(vec![
        Yaml::Int(s as i64),
        Yaml::Int(e as i64),
        Yaml::Map(params.into_iter().collect()),
    ])))
}

fn lane_params(
    b: &Building,
    lh: Handle<Level>,
    lane: &Lane,
    reverse: bool,
    dock_name: Option<String>,
    undock_name: Option<String>,
) -> BTreeMap<String, Yaml> {
    let mut p = BTreeMap::new();
    let (from, to) = if reverse {
        (lane.end, lane.start)
    } else {
        (lane.start, lane.end)
    };
    if let Some(door) = b.crossed_door(lh, b.vertices[from].pos, b.vertices[to].pos) {
        p.insert("door_name".into(), Yaml::str(&b.doors[door].name));
    }
    let orientation = if reverse {
        lane.orientation.reversed()
    } else {
        lane.orientation.clone()
    };
    if orientation != Orientation::Any {
        p.insert(
            "orientation_constraint".into(),
            Yaml::str(orientation.as_str()),
        );
    }
    if let Some(v) = lane.speed_limit {
        p.insert("speed_limit".into(), Yaml::Float(v));
    }
    for (k, v) in [
        ("mutex", &lane.mutex),
        ("demo_mock_floor_name", &lane.demo_mock_floor_name),
        ("demo_mock_lift_name", &lane.demo_mock_lift_name),
    ] {
        if let Some(v) = v {
            p.insert(k.into(), Yaml::str(v));
        }
    }
    if !lane.bidirectional {
        p.insert("is_bidirectional".into(), Yaml::Bool(false));
    }
    if let Some(d) = dock_name {
        p.insert("dock_name".into(), Yaml::str(d));
    }
    if let Some(d) = undock_name {
        p.insert("undock_name".into(), Yaml::str(d));
    }
    p
}
