//! Hover: the vertex an index names (or a vertex entry), a parameter's meaning and type,
//! and the documentation of the diagnostics under the cursor.

use super::analysis::Analysis;
use super::document::Document;
use super::outline::{self, LevelOutline};
use super::params_doc;
use lsp_types::{Hover, HoverContents, MarkupContent, MarkupKind, Position};
use mapc_ir::{Building, Severity};

pub(crate) fn hover(doc: &Document, analysis: Option<&Analysis>, pos: Position) -> Option<Hover> {
    let off = doc.offset(pos);
    let mut parts: Vec<String> = Vec::new();
    let mut range = None;
    if let Some(root) = outline::parse(&doc.text) {
        if let Some(at) = outline::at(&root, off) {
            let levels = outline::levels(&root);
            let building = analysis.and_then(|a| a.building.as_ref());
            if let Some(va) = outline::vertex_at(&levels, &at) {
                let (l, v) = va.level_and_vertex();
                if let Some(text) = vertex_text(building, &levels[l], v) {
                    parts.push(text);
                    range = Some(doc.range(at.span));
                }
            } else if at.on_key || at.path.len() >= 2 {
                // A parameter key, or a value inside `name: [type, value]`.
                // A key of a params mapping: inside an entry (`[0, 1, {graph_idx: ...}]`)
                // or under `parameters` (the building's, a floor's); not e.g. the
                // building's own `name`.
                let name = at.path.iter().enumerate().rev().find_map(|(i, s)| {
                    match (s, i.checked_sub(1).map(|j| &at.path[j])) {
                        (outline::Seg::Key(k), Some(outline::Seg::Index(_))) => {
                            params_doc::param(k).map(|p| (k, p))
                        }
                        (outline::Seg::Key(k), Some(outline::Seg::Key(parent)))
                            if parent == "parameters" =>
                        {
                            params_doc::param(k).map(|p| (k, p))
                        }
                        _ => None,
                    }
                });
                if let Some((name, (ty, meaning))) = name {
                    parts.push(format!("**`{name}`** — {ty}\n\n{meaning}"));
                    range = Some(doc.range(at.span));
                }
            }
        }
    }
    if let Some(a) = analysis {
        let mut codes: Vec<&str> = Vec::new();
        for d in &a.diagnostics {
            let r = doc.range(d.span);
            if r.start <= pos && pos <= r.end && !codes.contains(&d.code) {
                codes.push(d.code);
                let sev = match d.severity {
                    Severity::Error => "error",
                    Severity::Warning => "warning",
                };
                let mut s = format!(
                    "**{}** {} ({sev}): {}",
                    d.code,
                    crate::codes::code_name(d.code),
                    d.message
                );
                if let Some(doc) = super::diagnostics::code_doc(d.code) {
                    s.push_str("\n\n");
                    s.push_str(doc);
                }
                s.push_str(&format!(
                    "\n\n[documentation]({})",
                    crate::ui::json::help_uri(d.code)
                ));
                parts.push(s);
            }
        }
    }
    if parts.is_empty() {
        return None;
    }
    Some(Hover {
        contents: HoverContents::Markup(MarkupContent {
            kind: MarkupKind::Markdown,
            value: parts.join("\n\n---\n\n"),
        }),
        range,
    })
}

/// `vertex 9 "lobby" on level L1`, its position in metres, file coordinates, roles and users.
fn vertex_text(b: Option<&Building>, level: &LevelOutline, v: usize) -> Option<String> {
    let (entry, _) = *level.vertices.get(v)?;
    let mut uses: Vec<(&str, usize)> = Vec::new();
    for r in level.refs_to(v) {
        match uses.iter_mut().find(|(k, _)| *k == r.kind.name()) {
            Some((_, n)) => *n += 1,
            None => uses.push((r.kind.name(), 1)),
        }
    }
    let uses = if uses.is_empty() {
        "used by nothing".to_string()
    } else {
        let list: Vec<String> = uses.iter().map(|(k, n)| crate::ui::plural(*n, k)).collect();
        format!("used by {}", list.join(", "))
    };
    let Some((_, vx)) = b.and_then(|b| {
        b.vertices
            .iter()
            .find(|(h, _)| b.vertices.span(*h).start == entry.start)
    }) else {
        return Some(format!(
            "**vertex {v}** on level `{}`\n\n{uses}",
            level.name
        ));
    };
    let name = if vx.name.is_empty() {
        String::new()
    } else {
        format!(" `{}`", vx.name)
    };
    let r = &vx.roles;
    let roles = r.describe();
    let roles = if roles.is_empty() {
        "no roles".to_string()
    } else {
        format!("roles: {}", roles.join(", "))
    };
    Some(format!(
        "**vertex {v}**{name} on level `{}`\n\nposition: ({:.3}, {:.3}) m (file: {}, {})\n\n{roles}\n\n{uses}",
        level.name, vx.pos.x, vx.pos.y, vx.raw.x, vx.raw.y
    ))
}
