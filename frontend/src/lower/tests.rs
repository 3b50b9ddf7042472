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
