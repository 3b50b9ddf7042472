//! Code actions where the fix is clear: remove a self-loop (E0201) or a duplicate lane
//! (W0203), rename a duplicate waypoint name (E0501), join near waypoints that look
//! connected but are not (W0207: the lanes of one are reconnected to the other).

use super::analysis::Analysis;
use super::diagnostics;
use super::document::Document;
use super::outline::{self, LevelOutline, RefKind};
use lsp_types::{CodeAction, CodeActionKind, Range, TextEdit, Uri, WorkspaceEdit};
use mapc_ir::{Diagnostic, Span};
use std::collections::HashMap;

pub(crate) fn code_actions(
    doc: &Document,
    uri: &Uri,
    analysis: &Analysis,
    range: Range,
) -> Vec<CodeAction> {
    let Some(root) = outline::parse(&doc.text) else {
        return Vec::new();
    };
    let levels = outline::levels(&root);
    let mut out = Vec::new();
    for d in &analysis.diagnostics {
        let r = doc.range(d.span);
        if r.end < range.start || range.end < r.start {
            continue;
        }
        let fix = match d.code {
            "E0201" => remove_line(doc, d.span)
                .map(|e| ("Remove this self-loop lane".to_string(), vec![e])),
            "W0203" => remove_line(doc, d.span)
                .map(|e| ("Remove this duplicate lane".to_string(), vec![e])),
            "E0501" => rename(doc, analysis, &levels, d),
            "W0207" => join(doc, &levels, d),
            _ => None,
        };
        let Some((title, edits)) = fix else { continue };
        out.push(CodeAction {
            title,
            kind: Some(CodeActionKind::QUICKFIX),
            diagnostics: Some(vec![diagnostics::to_lsp(doc, uri, d)]),
            edit: Some(WorkspaceEdit {
                changes: Some(HashMap::from([(uri.clone(), edits)])),
                ..WorkspaceEdit::default()
            }),
            command: None,
            is_preferred: Some(true),
            disabled: None,
            data: None,
        });
    }
    out
}

/// Deletes the whole line(s) of a block-sequence entry (`    - [3, 3, {...}]`); `None` when
/// the entry shares its line with anything else (a flow sequence).
fn remove_line(doc: &Document, span: Span) -> Option<TextEdit> {
    let text = &doc.text;
    let (start, end) = (span.start as usize, span.end as usize);
    let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    let prefix = text[line_start..start].trim_start();
    if prefix != "-" && !prefix.is_empty() && prefix.trim_end() != "-" {
        return None;
    }
    let rest = &text[end..];
    let line_end = rest.find('\n').map_or(text.len(), |i| end + i + 1);
    if !text[end..line_end].trim().is_empty() && !text[end..line_end].trim_start().starts_with('#')
    {
        return None;
    }
    Some(TextEdit::new(
        doc.lines.range(text, line_start as u32, line_end as u32),
        String::new(),
    ))
}

/// The vertex (level, file index) whose entry is at `span`.
fn vertex_of(levels: &[LevelOutline], span: Span) -> Option<(usize, usize)> {
    levels
        .iter()
        .enumerate()
        .find_map(|(l, lo)| lo.vertex_at(span.start).map(|v| (l, v)))
}

/// Renames the later of two waypoints with the same name to the first free `name_2`,
/// `name_3`, ...
fn rename(
    doc: &Document,
    analysis: &Analysis,
    levels: &[LevelOutline],
    d: &Diagnostic,
) -> Option<(String, Vec<TextEdit>)> {
    let b = analysis.building.as_ref()?;
    let (l, v) = vertex_of(levels, d.span)?;
    let name_span = levels[l].vertices[v].1?;
    let (_, vx) = b
        .vertices
        .iter()
        .find(|(h, _)| b.vertices.span(*h).start == d.span.start)?;
    let taken = |n: &str| b.vertices.iter().any(|(_, x)| x.name == n);
    let new = (2..)
        .map(|i| format!("{}_{i}", vx.name))
        .find(|n| !taken(n))?;
    let quoted = super::yaml_scalar(&new);
    Some((
        format!("Rename `{}` to `{new}`", vx.name),
        vec![TextEdit::new(doc.range(name_span), quoted)],
    ))
}

/// Reconnects the lanes of the reported waypoint to the waypoint it lies on (the
/// diagnostic's first label), leaving the emptied vertex in place so no index shifts.
fn join(
    doc: &Document,
    levels: &[LevelOutline],
    d: &Diagnostic,
) -> Option<(String, Vec<TextEdit>)> {
    let (l, from) = vertex_of(levels, d.span)?;
    let (l2, to) = vertex_of(levels, d.labels.first()?.span)?;
    if l != l2 || from == to {
        return None;
    }
    let edits: Vec<TextEdit> = levels[l]
        .refs_to(from)
        .filter(|r| r.kind == RefKind::Lane)
        .map(|r| TextEdit::new(doc.range(r.span), to.to_string()))
        .collect();
    if edits.is_empty() {
        return None;
    }
    Some((
        format!("Join vertex {from} to vertex {to}: reconnect its lanes to vertex {to}"),
        edits,
    ))
}
