//! rmf_site's `.site.json` into the mapc IR.
//!
//! The file is read with the frontend's located tree reader (JSON is a subset of YAML
//! 1.2, and the reader keeps the line and column of every value), so every element of a
//! site has a span like the elements of a `.building.yaml`. `lower.rs` then maps the site
//! model (one site-wide id space, anchors, site-wide lanes, locations and graphs, lifts
//! on site anchors with cabin-frame anchors) onto the IR the rules and backends share.
//! docs/sites.md says what maps to what.

pub mod codes;
mod lower;

use mapc_ir::{Building, Diagnostic, FileId};

/// The major `format_version` mapc reads (rmf_site_format 0.0.2 writes "0.1").
pub const FORMAT_MAJOR: u32 = 0;
/// Key of mapc's own data in the site's `extensions.data`: what a `.building.yaml` says
/// and rmf_site has no field for (vertex parameters, door plugins, lift floor ranges, the
/// coordinate system), so that a conversion round trip keeps it.
pub const EXTENSION_KEY: &str = "mapc";

/// Is `name` a site file (by its extension)?
pub fn is_site_file(name: &str) -> bool {
    name.ends_with(".site.json")
}

pub(crate) fn parse_into(
    file: FileId,
    text: &str,
    diags: &mut Vec<Diagnostic>,
) -> Option<Building> {
    let root = match crate::yaml::parse(text, file) {
        Ok(r) => r,
        Err(mut d) => {
            if d.code == "E0001" {
                d.message = d.message.replace("YAML", "JSON");
            }
            diags.push(d);
            return None;
        }
    };
    lower::SiteLower::new(diags).site(&root)
}

#[cfg(test)]
mod tests {
    use crate::parse_site_str;
    use mapc_ir::*;

    /// Two anchors on L1 and one lane between them, with `lane` spliced into the lane and
    /// `graphs` as the site's graphs.
    fn site(graphs: &str, lane: &str) -> crate::Parsed {
        let text = format!(
            r#"{{"format_version": "0.1", "properties": {{"name": "s"}},
  "levels": {{"1": {{"properties": {{"name": "L1", "elevation": 0.0}},
    "anchors": {{"2": {{"Translate2D": [0.0, 0.0]}}, "3": {{"Translate2D": [3.0, 4.0]}}}}}}}},
  "navigation": {{"guided": {{"graphs": {{{graphs}}}, "ranking": [],
    "lanes": {{"9": {{"anchors": [2, 3], {lane}}}}}, "locations": {{}}}}}}}}"#
        );
        parse_site_str("t.site.json", &text)
    }

    fn lanes(b: &Building) -> Vec<(i64, bool, Option<f64>)> {
        b.lanes
            .iter()
            .map(|(_, l)| (l.graph, l.bidirectional, l.speed_limit))
            .collect()
    }

    #[test]
    fn integer_graph_names_keep_their_index_and_others_take_free_ones() {
        let p = site(
            r#""5": {"name": "3", "color": [1,1,1]}, "6": {"name": "x", "color": [1,1,1]}, "7": {"name": "0", "color": [1,1,1]}"#,
            r#""graphs": {"AllExcept": [5]}"#,
        );
        let b = p.building.unwrap();
        let g: Vec<(i64, &str)> = b
            .graphs
            .iter()
            .map(|g| (g.index, g.name.as_str()))
            .collect();
        assert_eq!(g, vec![(0, "0"), (1, "x"), (3, "3")]);
        assert_eq!(lanes(&b), vec![(0, true, None), (1, true, None)]);
        assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
    }

    #[test]
    fn a_reverse_motion_with_another_speed_is_two_one_way_lanes() {
        let p = site(
            r#""1": {"name": "0", "color": [1,1,1]}"#,
            r#""forward": {"speed_limit": 0.5}, "reverse": {"Different": {"speed_limit": 1.5}}, "graphs": "All""#,
        );
        let b = p.building.unwrap();
        assert_eq!(
            lanes(&b),
            vec![(0, false, Some(0.5)), (0, false, Some(1.5))]
        );
        let l: Vec<(Handle<Vertex>, Handle<Vertex>)> =
            b.lanes.iter().map(|(_, l)| (l.start, l.end)).collect();
        assert_eq!((l[0].0, l[0].1), (l[1].1, l[1].0));
    }

    #[test]
    fn a_dangling_graph_is_located_and_the_lane_stays_on_the_others() {
        let p = site(
            r#""1": {"name": "0", "color": [1,1,1]}"#,
            r#""graphs": {"Only": [1, 44]}"#,
        );
        let d = &p.diagnostics;
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].code, "E0121");
        assert_eq!((d[0].span.line, d[0].span.col), (5, 63), "on the id 44");
        assert_eq!(lanes(p.building.as_ref().unwrap()), vec![(0, true, None)]);
    }

    /// Site anchor 1 is used by a wall and a floor of L1 and a wall of L2: one vertex on
    /// each level, shared by the elements of that level, at the anchor.
    #[test]
    fn a_site_anchor_is_one_vertex_per_level_that_uses_it() {
        let text = r#"{"format_version": "0.1", "properties": {"name": "s"},
  "anchors": {"1": {"Translate2D": [2.0, 3.0]}},
  "levels": {
    "10": {"properties": {"name": "L1", "elevation": 0.0},
      "anchors": {"11": {"Translate2D": [0.0, 0.0]}, "12": {"Translate2D": [4.0, 0.0]}},
      "walls": {"13": {"anchors": [11, 1]}},
      "floors": {"14": {"anchors": [11, 12, 1]}}},
    "20": {"properties": {"name": "L2", "elevation": 3.0},
      "anchors": {"21": {"Translate2D": [0.0, 0.0]}},
      "walls": {"22": {"anchors": [1, 21]}}}},
  "navigation": {"guided": {"graphs": {"5": {"name": "g", "color": [1,1,1]}}, "ranking": [],
    "lanes": {"30": {"anchors": [12, 1], "graphs": "All"}}, "locations": {}}}}"#;
        let p = parse_site_str("t.site.json", text);
        let codes: Vec<(&str, u32, u32)> = p
            .diagnostics
            .iter()
            .map(|d| (d.code, d.span.line, d.span.col))
            .collect();
        assert_eq!(codes, vec![("W0123", 12, 38)], "the lane's site anchor");
        let b = p.building.unwrap();
        assert!(b.lanes.is_empty());
        let on_site_anchor: Vec<(&str, Handle<Vertex>)> = b
            .vertices
            .iter()
            .filter(|(_, v)| (v.pos.x, v.pos.y) == (2.0, 3.0))
            .map(|(h, v)| (b.levels[v.level].name.as_str(), h))
            .collect();
        assert_eq!(on_site_anchor.len(), 2);
        assert_eq!((on_site_anchor[0].0, on_site_anchor[1].0), ("L1", "L2"));
        let (l1, l2) = (on_site_anchor[0].1, on_site_anchor[1].1);
        let walls: Vec<Handle<Vertex>> = b.walls.iter().map(|(_, w)| w.end).collect();
        assert_eq!(walls[0], l1);
        assert_eq!(b.walls.iter().nth(1).unwrap().1.start, l2);
        assert_eq!(b.floors.iter().next().unwrap().1.vertices[2], l1);
    }

    #[test]
    fn broken_json_is_a_json_syntax_error() {
        let p = parse_site_str("t.site.json", "{\"format_version\": \"0.1\", ");
        assert!(p.building.is_none());
        assert_eq!(p.diagnostics[0].code, "E0001");
        assert!(
            p.diagnostics[0].message.contains("JSON"),
            "{}",
            p.diagnostics[0].message
        );
    }
}
