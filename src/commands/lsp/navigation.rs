//! Go to definition (an index to its vertex's entry; a project file's `building.filename`
//! to that file) and find references (every lane, wall, door, measurement, human lane,
//! floor and hole using a vertex).

use super::analysis;
use super::document::{Document, Kind};
use super::outline;
use lsp_types::{Location, Position, Range, Uri};
use std::str::FromStr;

pub(crate) fn definition(doc: &Document, uri: &Uri, pos: Position) -> Option<Location> {
    let off = doc.offset(pos);
    let root = outline::parse(&doc.text)?;
    if doc.kind == Kind::Project {
        let span = analysis::project_filename_span(&doc.text)?;
        if span.start <= off && off <= span.end {
            let path = std::path::absolute(analysis::project_target(doc, &root)?).ok()?;
            let target = Uri::from_str(&crate::ui::json::file_uri(&path)).ok()?;
            return Some(Location::new(target, Range::default()));
        }
        return None;
    }
    let at = outline::at(&root, off)?;
    let levels = outline::levels(&root);
    match outline::vertex_at(&levels, &at)? {
        outline::VertexAt::Ref(l, v, _) => {
            let (entry, _) = *levels[l].vertices.get(v)?;
            Some(Location::new(uri.clone(), doc.range(entry)))
        }
        // On the vertex itself: the definition is where it is.
        outline::VertexAt::Entry(l, v) => Some(Location::new(
            uri.clone(),
            doc.range(levels[l].vertices[v].0),
        )),
    }
}

pub(crate) fn references(
    doc: &Document,
    uri: &Uri,
    pos: Position,
    include_declaration: bool,
) -> Vec<Location> {
    let off = doc.offset(pos);
    let Some(root) = outline::parse(&doc.text) else {
        return Vec::new();
    };
    let Some(at) = outline::at(&root, off) else {
        return Vec::new();
    };
    let levels = outline::levels(&root);
    let Some(va) = outline::vertex_at(&levels, &at) else {
        return Vec::new();
    };
    let (l, v) = va.level_and_vertex();
    let level = &levels[l];
    let mut out = Vec::new();
    if include_declaration {
        if let Some((entry, _)) = level.vertices.get(v) {
            out.push(Location::new(uri.clone(), doc.range(*entry)));
        }
    }
    out.extend(
        level
            .refs_to(v)
            .map(|r| Location::new(uri.clone(), doc.range(r.span))),
    );
    out
}
