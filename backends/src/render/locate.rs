//! Where a diagnostic is on the map: the element whose source text holds the diagnostic's
//! span most tightly (a vertex, lane, wall, door, floor, hole, model, lift...), placed at
//! its position (a point) or its middle (a segment, a polygon).

use mapc_ir::{Building, Diagnostic, Handle, Level, Span, Vec2};

/// A diagnostic's place: the level and point of its primary span, and the points of its
/// labels on the same level.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Located {
    pub level: Option<Handle<Level>>,
    pub at: Option<Vec2>,
    pub labels: Vec<Vec2>,
}

struct Element {
    span: Span,
    level: Handle<Level>,
    at: Vec2,
}

fn mid(b: &Building, a: Handle<mapc_ir::Vertex>, z: Handle<mapc_ir::Vertex>) -> Vec2 {
    let (a, z) = (b.vertices[a].pos, b.vertices[z].pos);
    a.plus(z).scale(0.5)
}

fn centroid(b: &Building, vs: &[Handle<mapc_ir::Vertex>]) -> Vec2 {
    let n = vs.len().max(1) as f64;
    vs.iter()
        .fold(Vec2::default(), |acc, &v| acc.plus(b.vertices[v].pos))
        .scale(1.0 / n)
}

fn elements(b: &Building) -> Vec<Element> {
    let mut e = Vec::new();
    let mut add = |span: Span, level: Handle<Level>, at: Vec2| {
        if span.is_known() && at.is_finite() {
            e.push(Element { span, level, at });
        }
    };
    for (h, v) in b.vertices.iter() {
        add(b.vertices.span(h), v.level, v.pos);
    }
    for (h, l) in b.lanes.iter() {
        add(b.lanes.span(h), l.level, mid(b, l.start, l.end));
    }
    for (h, w) in b.walls.iter() {
        add(b.walls.span(h), w.level, mid(b, w.start, w.end));
    }
    for (h, m) in b.measurements.iter() {
        add(b.measurements.span(h), m.level, mid(b, m.start, m.end));
    }
    for (h, d) in b.doors.iter() {
        add(b.doors.span(h), d.level, mid(b, d.start, d.end));
    }
    for (h, f) in b.floors.iter() {
        add(b.floors.span(h), f.level, centroid(b, &f.vertices));
    }
    for (h, f) in b.holes.iter() {
        add(b.holes.span(h), f.level, centroid(b, &f.vertices));
    }
    for (h, m) in b.models.iter() {
        add(b.models.span(h), m.level, m.pos);
    }
    for (h, f) in b.fiducials.iter() {
        add(b.fiducials.span(h), f.level, f.pos);
    }
    for (h, l) in b.human_lanes.iter() {
        add(b.human_lanes.span(h), l.level, mid(b, l.start, l.end));
    }
    for (h, l) in b.lifts.iter() {
        let level = l.initial_floor().unwrap_or(l.reference_level);
        add(b.lifts.span(h), level, l.pos);
        // A lift's per-level door lists sit on their level.
        for ld in &l.level_doors {
            add(ld.span, ld.level, l.pos);
        }
    }
    e
}

fn find(elements: &[Element], s: Span) -> Option<&Element> {
    if !s.is_known() {
        return None;
    }
    elements
        .iter()
        .filter(|e| e.span.file == s.file && e.span.start <= s.start && s.end <= e.span.end)
        .min_by_key(|e| (e.span.end - e.span.start, e.span.start))
}

/// Places `d` on the map (see the module docs); `Located::default()` when its spans are in
/// no element.
pub fn locate(b: &Building, d: &Diagnostic) -> Located {
    let els = elements(b);
    let Some(primary) = find(&els, d.span) else {
        // Some diagnostics point at the key of a whole list; a label may still be placed.
        let mut labels = d.labels.iter().filter_map(|l| find(&els, l.span));
        return match labels.next() {
            Some(first) => Located {
                level: Some(first.level),
                at: Some(first.at),
                labels: labels
                    .filter(|e| e.level == first.level)
                    .map(|e| e.at)
                    .collect(),
            },
            None => Located::default(),
        };
    };
    let labels = d
        .labels
        .iter()
        .filter_map(|l| find(&els, l.span))
        .filter(|e| e.level == primary.level && e.at != primary.at)
        .map(|e| e.at)
        .collect();
    Located {
        level: Some(primary.level),
        at: Some(primary.at),
        labels,
    }
}
