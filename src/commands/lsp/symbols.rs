//! Document symbols (levels with their doors and named waypoints, then lifts, then graphs)
//! and workspace symbols over the open maps.

use super::analysis::Analysis;
use super::document::{Document, Kind};
use super::outline;
use lsp_types::{DocumentSymbol, Location, OneOf, SymbolKind, Uri, WorkspaceSymbol};
use mapc_ir::{Building, Handle, Level, Span};

#[allow(deprecated)] // `DocumentSymbol::deprecated` must be written out.
fn symbol(
    doc: &Document,
    name: String,
    detail: Option<String>,
    kind: SymbolKind,
    span: Span,
    name_span: Span,
    children: Vec<DocumentSymbol>,
) -> DocumentSymbol {
    let range = doc.range(span);
    let mut selection = doc.range(name_span);
    // The selection must lie inside the range.
    if selection.start < range.start || selection.end > range.end {
        selection = range;
    }
    DocumentSymbol {
        name: if name.is_empty() {
            "(unnamed)".into()
        } else {
            name
        },
        detail,
        kind,
        tags: None,
        deprecated: None,
        range,
        selection_range: selection,
        children: (!children.is_empty()).then_some(children),
    }
}

/// A level's doors and named waypoints.
fn level_children(doc: &Document, b: &Building, lh: Handle<Level>) -> Vec<DocumentSymbol> {
    let mut children = Vec::new();
    let level = &b.levels[lh];
    for &d in &level.doors {
        let door = &b.doors[d];
        let span = b.doors.span(d);
        children.push(symbol(
            doc,
            door.name.clone(),
            Some(format!("{} door", door.kind.as_str())),
            SymbolKind::INTERFACE,
            span,
            span,
            Vec::new(),
        ));
    }
    for &v in &level.vertices {
        let vx = &b.vertices[v];
        if vx.name.is_empty() {
            continue;
        }
        let span = b.vertices.span(v);
        children.push(symbol(
            doc,
            vx.name.clone(),
            Some("waypoint".into()),
            SymbolKind::CONSTANT,
            span,
            span,
            Vec::new(),
        ));
    }
    children
}

pub(crate) fn document_symbols(doc: &Document, analysis: Option<&Analysis>) -> Vec<DocumentSymbol> {
    let b = analysis.and_then(|a| a.building.as_ref());
    let mut out = Vec::new();
    if let (Kind::Site, Some(b)) = (doc.kind, b) {
        // A site's levels are keyed by id: their names and places come from the building.
        for (lh, level) in b.levels.iter() {
            let span = b.levels.span(lh);
            out.push(symbol(
                doc,
                level.name.clone(),
                Some("level".into()),
                SymbolKind::NAMESPACE,
                span,
                span,
                level_children(doc, b, lh),
            ));
        }
    }
    let root = match doc.kind {
        Kind::Site => None,
        _ => match outline::parse(&doc.text) {
            Some(r) => Some(r),
            None => return Vec::new(),
        },
    };
    let levels = root.as_ref().map(outline::levels).unwrap_or_default();
    for lo in &levels {
        let mut children = Vec::new();
        if let Some(b) = b {
            if let Some((lh, _)) = b.levels.iter().find(|(h, _)| {
                b.levels.span(*h).start == lo.span.start || b.levels[*h].name == lo.name
            }) {
                children = level_children(doc, b, lh);
            }
        }
        out.push(symbol(
            doc,
            lo.name.clone(),
            Some("level".into()),
            SymbolKind::NAMESPACE,
            join(lo.name_span, lo.span),
            lo.name_span,
            children,
        ));
    }
    if let Some(b) = b {
        for (h, lift) in b.lifts.iter() {
            let span = b.lifts.span(h);
            out.push(symbol(
                doc,
                lift.name.clone(),
                Some("lift".into()),
                SymbolKind::CLASS,
                span,
                span,
                Vec::new(),
            ));
        }
    }
    if let Some(graphs) = root
        .as_ref()
        .and_then(|r| r.get("graphs"))
        .and_then(|g| g.as_map())
    {
        for (k, v) in graphs {
            let name = v.get("name").and_then(|n| n.key_text()).map_or_else(
                || format!("graph {}", k.key_text().unwrap_or("")),
                |n| format!("graph {}: {n}", k.key_text().unwrap_or("")),
            );
            out.push(symbol(
                doc,
                name,
                Some("graph".into()),
                SymbolKind::STRUCT,
                join(k.span, v.span),
                k.span,
                Vec::new(),
            ));
        }
    }
    out
}

/// Symbols of every open map whose name contains `query` (case-insensitive), flattened.
pub(crate) fn workspace_symbols<'a>(
    docs: impl Iterator<Item = (&'a Uri, &'a Document, Option<&'a Analysis>)>,
    query: &str,
) -> Vec<WorkspaceSymbol> {
    let q = query.to_lowercase();
    let mut out = Vec::new();
    for (uri, doc, analysis) in docs {
        let mut stack = document_symbols(doc, analysis);
        let mut container: Vec<(DocumentSymbol, Option<String>)> =
            stack.drain(..).map(|s| (s, None)).collect();
        while let Some((s, parent)) = container.pop() {
            if let Some(children) = &s.children {
                for c in children {
                    container.push((c.clone(), Some(s.name.clone())));
                }
            }
            if s.name.to_lowercase().contains(&q) {
                out.push(WorkspaceSymbol {
                    name: s.name.clone(),
                    kind: s.kind,
                    tags: None,
                    container_name: parent,
                    location: OneOf::Left(Location::new(uri.clone(), s.selection_range)),
                    data: None,
                });
            }
        }
    }
    out.sort_by(|a, b| a.name.cmp(&b.name));
    out
}

/// From the start of `a` to the end of `b`.
fn join(a: Span, b: Span) -> Span {
    Span {
        end: b.end.max(a.end),
        ..a
    }
}
