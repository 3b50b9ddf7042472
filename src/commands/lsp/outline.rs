//! Where things are in a map's text: the YAML path under the cursor, and per level the
//! vertex list and every place that refers to a vertex by index (lanes, walls, doors,
//! measurements, human lanes, floors, holes). Built from the frontend's located YAML tree on
//! request, so it always matches the text being edited (the IR keeps element spans but not
//! the span of each index inside an element).

use mapc_frontend::yaml_tree::{self, Node};
use mapc_ir::{FileId, Span};

/// One step of a YAML path.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Seg {
    Key(String),
    Index(usize),
}

/// The node under a byte offset: its path from the root, its span, and whether the offset
/// is on a mapping key (then the path ends with that key).
#[derive(Debug)]
pub(crate) struct At {
    pub(crate) path: Vec<Seg>,
    pub(crate) span: Span,
    pub(crate) on_key: bool,
}

impl At {
    /// The path as strings, indices as `#`, for matching: `levels L1 lanes # 0`.
    pub(crate) fn keys(&self) -> Vec<&str> {
        self.path
            .iter()
            .map(|s| match s {
                Seg::Key(k) => k.as_str(),
                Seg::Index(_) => "#",
            })
            .collect()
    }
    pub(crate) fn index(&self, i: usize) -> Option<usize> {
        match self.path.get(i) {
            Some(Seg::Index(n)) => Some(*n),
            _ => None,
        }
    }
}

fn contains(span: Span, off: u32) -> bool {
    span.start <= off && off <= span.end
}

/// The innermost node at `off`.
pub(crate) fn at(root: &Node, off: u32) -> Option<At> {
    if !contains(root.span, off) {
        return None;
    }
    let mut path = Vec::new();
    let mut node = root;
    'descend: loop {
        if let Some(map) = node.as_map() {
            for (k, v) in map {
                let name = k.key_text().unwrap_or("").to_string();
                if contains(k.span, off) && k.span.end > k.span.start {
                    path.push(Seg::Key(name));
                    return Some(At {
                        path,
                        span: k.span,
                        on_key: true,
                    });
                }
                if contains(v.span, off) {
                    path.push(Seg::Key(name));
                    node = v;
                    continue 'descend;
                }
            }
        } else if let Some(seq) = node.as_seq() {
            for (i, item) in seq.iter().enumerate() {
                if contains(item.span, off) {
                    path.push(Seg::Index(i));
                    node = item;
                    continue 'descend;
                }
            }
        }
        return Some(At {
            path,
            span: node.span,
            on_key: false,
        });
    }
}

/// Which list of a level an element is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RefKind {
    Lane,
    Wall,
    Door,
    Measurement,
    HumanLane,
    Floor,
    Hole,
}

impl RefKind {
    pub(crate) fn name(self) -> &'static str {
        match self {
            RefKind::Lane => "lane",
            RefKind::Wall => "wall",
            RefKind::Door => "door",
            RefKind::Measurement => "measurement",
            RefKind::HumanLane => "human lane",
            RefKind::Floor => "floor",
            RefKind::Hole => "hole",
        }
    }
}

/// An index that names a vertex.
#[derive(Debug, Clone)]
pub(crate) struct VertexRef {
    pub(crate) kind: RefKind,
    /// The vertex index as written (may be out of range or malformed: `None`).
    pub(crate) vertex: Option<usize>,
    pub(crate) span: Span,
}

#[derive(Debug, Clone)]
pub(crate) struct LevelOutline {
    pub(crate) name: String,
    pub(crate) name_span: Span,
    pub(crate) span: Span,
    /// The span of each entry of `vertices`, and of its name scalar when it has one.
    pub(crate) vertices: Vec<(Span, Option<Span>)>,
    pub(crate) refs: Vec<VertexRef>,
}

impl LevelOutline {
    /// Every reference to vertex `v`.
    pub(crate) fn refs_to(&self, v: usize) -> impl Iterator<Item = &VertexRef> {
        self.refs.iter().filter(move |r| r.vertex == Some(v))
    }
    /// The file index of the vertex whose entry starts at `start`.
    pub(crate) fn vertex_at(&self, start: u32) -> Option<usize> {
        self.vertices.iter().position(|(s, _)| s.start == start)
    }
}

/// The levels of a map, in document order.
pub(crate) fn levels(root: &Node) -> Vec<LevelOutline> {
    let Some(levels) = root.get("levels").and_then(Node::as_map) else {
        return Vec::new();
    };
    levels
        .iter()
        .map(|(name, level)| {
            let vertices = level
                .get("vertices")
                .and_then(Node::as_seq)
                .unwrap_or(&[])
                .iter()
                .map(|v| (v.span, v.as_seq().and_then(|s| s.get(3)).map(|n| n.span)))
                .collect();
            let mut refs = Vec::new();
            for (key, kind) in [
                ("lanes", RefKind::Lane),
                ("walls", RefKind::Wall),
                ("doors", RefKind::Door),
                ("measurements", RefKind::Measurement),
                ("human_lanes", RefKind::HumanLane),
            ] {
                for e in list(level, key) {
                    for n in e.as_seq().unwrap_or(&[]).iter().take(2) {
                        refs.push(vref(kind, n));
                    }
                }
            }
            for (key, kind) in [("floors", RefKind::Floor), ("holes", RefKind::Hole)] {
                for e in list(level, key) {
                    let Some(vs) = e.get("vertices").and_then(Node::as_seq) else {
                        continue;
                    };
                    for n in vs {
                        refs.push(vref(kind, n));
                    }
                }
            }
            LevelOutline {
                name: name.key_text().unwrap_or("").to_string(),
                name_span: name.span,
                span: level.span,
                vertices,
                refs,
            }
        })
        .collect()
}

fn list<'n, 'a>(level: &'n Node<'a>, key: &str) -> &'n [Node<'a>] {
    level.get(key).and_then(Node::as_seq).unwrap_or(&[])
}

fn vref(kind: RefKind, n: &Node) -> VertexRef {
    VertexRef {
        kind,
        vertex: n.as_i64().and_then(|i| usize::try_from(i).ok()),
        span: n.span,
    }
}

/// The YAML tree of `text` (file 0), or `None` when it does not parse.
pub(crate) fn parse(text: &str) -> Option<Node<'_>> {
    yaml_tree::parse(text, FileId(0)).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    const MAP: &str = "levels:\n  L1:\n    vertices:\n      - [0, 0, 0, a]\n      - [1, 0, 0]\n    lanes:\n      - [0, 1, {graph_idx: [2, 0]}]\n    floors:\n      - vertices: [1, 0]\n";

    #[test]
    fn path_under_the_cursor() {
        let root = parse(MAP).unwrap();
        let off = MAP.find("[0, 1,").unwrap() as u32 + 4;
        let at = at(&root, off).unwrap();
        assert_eq!(at.keys(), ["levels", "L1", "lanes", "#", "#"]);
        assert_eq!(at.index(4), Some(1));
        let key = MAP.find("graph_idx").unwrap() as u32 + 2;
        let at = super::at(&root, key).unwrap();
        assert!(at.on_key);
        assert_eq!(at.keys(), ["levels", "L1", "lanes", "#", "#", "graph_idx"]);
    }

    #[test]
    fn references_per_vertex() {
        let root = parse(MAP).unwrap();
        let levels = levels(&root);
        assert_eq!(levels.len(), 1);
        assert_eq!(levels[0].vertices.len(), 2);
        let kinds: Vec<_> = levels[0].refs_to(1).map(|r| r.kind).collect();
        assert_eq!(kinds, [RefKind::Lane, RefKind::Floor]);
        let name = levels[0].vertices[0].1.unwrap();
        assert_eq!(&MAP[name.start as usize..name.end as usize], "a");
    }
}

/// What the cursor is on, as far as vertices go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum VertexAt {
    /// The vertex's own entry in `vertices` (level, file index).
    Entry(usize, usize),
    /// An index naming the vertex (level, file index, the reference's span).
    Ref(usize, usize, Span),
}

impl VertexAt {
    pub(crate) fn level_and_vertex(self) -> (usize, usize) {
        match self {
            VertexAt::Entry(l, v) | VertexAt::Ref(l, v, _) => (l, v),
        }
    }
}

/// The vertex the cursor is on: a vertex entry (not one of its params) or an index.
pub(crate) fn vertex_at(levels: &[LevelOutline], at: &At) -> Option<VertexAt> {
    let keys = at.keys();
    if keys.first() != Some(&"levels") || keys.len() < 4 {
        return None;
    }
    let l = levels
        .iter()
        .position(|lv| lv.span.start <= at.span.start && at.span.end <= lv.span.end)?;
    if keys[2] == "vertices" {
        // The entry itself or its x, y, z, name; not its params mapping.
        if keys.len() <= 5 && !at.on_key {
            let v = at.index(3)?;
            return (v < levels[l].vertices.len()).then_some(VertexAt::Entry(l, v));
        }
        return None;
    }
    if at.on_key {
        return None;
    }
    let r = levels[l].refs.iter().find(|r| r.span == at.span)?;
    Some(VertexAt::Ref(l, r.vertex?, r.span))
}
