//! Machine-readable diagnostics: JSON Lines for editors and scripts, SARIF 2.1.0 for
//! code-scanning tools. The JSON schema is documented in docs/diagnostics.md and is
//! stable: fields are only ever added. Messages, labels and help are display-safe (control
//! and bidi characters escaped), as editors and code-scanning pages show them to people.

use super::escape::display_safe;
use super::limit::CodeCount;
use mapc_frontend::SourceFile;
use mapc_ir::{Diagnostic, Severity, Span};
use serde_json::{json, Value};
use std::io::Write;

/// (line, column) of the end of a span, 1-based, column in characters.
fn end_position(sources: &[SourceFile], s: Span) -> (u32, u32) {
    let Some(src) = sources.get(s.file.0 as usize) else {
        return (s.line, s.col);
    };
    let end = (s.end as usize).min(src.text.len());
    let start = (s.start as usize).min(end);
    let Some(piece) = src.text.get(start..end) else {
        return (s.line, s.col);
    };
    let newlines = piece.matches('\n').count() as u32;
    if newlines == 0 {
        (s.line, s.col + piece.chars().count() as u32)
    } else {
        let tail = piece.rsplit('\n').next().unwrap_or("");
        (s.line + newlines, tail.chars().count() as u32 + 1)
    }
}

fn file_name(sources: &[SourceFile], s: Span) -> &str {
    sources
        .get(s.file.0 as usize)
        .or(sources.first())
        .map_or("", |f| f.name.as_str())
}

fn location(sources: &[SourceFile], s: Span) -> Value {
    if !s.is_known() {
        return json!({ "file": file_name(sources, s) });
    }
    let (end_line, end_column) = end_position(sources, s);
    json!({
        "file": file_name(sources, s),
        "line": s.line,
        "column": s.col,
        "end_line": end_line,
        "end_column": end_column,
        "byte_start": s.start,
        "byte_end": s.end,
    })
}

fn severity(d: &Diagnostic) -> &'static str {
    match d.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
    }
}

/// One JSON object per diagnostic.
pub fn diagnostic_json(sources: &[SourceFile], d: &Diagnostic) -> Value {
    let mut v = json!({
        "severity": severity(d),
        "code": d.code,
        "name": crate::codes::code_name(d.code),
        "message": display_safe(&d.message),
        "location": location(sources, d.span),
        "labels": d.labels.iter().map(|l| {
            let mut loc = location(sources, l.span);
            loc["message"] = json!(display_safe(&l.message));
            loc
        }).collect::<Vec<_>>(),
    });
    if let Some(h) = &d.help {
        v["help"] = json!(display_safe(h));
    }
    v
}

/// The summary record of a code whose diagnostics were not all shown (documented in
/// docs/diagnostics.md): `{"kind": "summary", "code", "name", "found", "shown", "message"}`.
pub fn summary_json(c: &CodeCount) -> Value {
    json!({
        "kind": "summary",
        "code": c.code,
        "name": crate::codes::code_name(c.code),
        "found": c.found,
        "shown": c.shown,
        "message": super::limit::summary_text(c),
    })
}

/// JSON Lines to `out`, one object per line as it is made, then one summary record per
/// code in `cut`.
pub fn write_json_lines(
    out: &mut impl Write,
    sources: &[SourceFile],
    diags: &[&Diagnostic],
    cut: &[CodeCount],
) -> std::io::Result<()> {
    for d in diags {
        writeln!(out, "{}", diagnostic_json(sources, d))?;
    }
    for c in cut {
        writeln!(out, "{}", summary_json(c))?;
    }
    out.flush()
}

/// Where a code's documentation is, as an absolute URI (SARIF viewers do not resolve
/// relative ones): the repository's page when the package names one, else the docs of the
/// source tree mapc was built from.
pub(crate) fn help_uri(code: &str) -> String {
    // The heading's anchor: `## W0213 demo-mock-lift-without-floor`.
    let anchor = match crate::codes::code_name(code) {
        "" => code.to_ascii_lowercase(),
        name => mapc_ir::doc_anchor(code, name),
    };
    match option_env!("CARGO_PKG_REPOSITORY").filter(|r| !r.is_empty()) {
        Some(repo) => format!("{repo}/blob/main/docs/diagnostics.md#{anchor}"),
        None => format!(
            "{}#{anchor}",
            file_uri(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/diagnostics.md"))
        ),
    }
}

/// Percent-encodes what may not appear in a URI path (RFC 3986 unreserved and `/` stay).
fn encode(path: &str) -> String {
    let mut out = String::new();
    for b in path.bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' | b'/' => {
                out.push(b as char)
            }
            _ => out.push_str(&format!("%{b:02X}")),
        }
    }
    out
}

/// `file:///abs/path`, with `\` as `/` (Windows).
pub(crate) fn file_uri(p: &std::path::Path) -> String {
    let s = p.to_string_lossy().replace('\\', "/");
    let s = if s.starts_with('/') {
        s
    } else {
        format!("/{s}")
    };
    format!("file://{}", encode(&s))
}

/// A SARIF artifact location: relative paths as normalized URI references against
/// `%SRCROOT%` (the working directory), absolute ones as `file://` URIs.
fn artifact_location(name: &str) -> Value {
    let p = std::path::Path::new(name);
    if p.is_absolute() {
        return json!({ "uri": file_uri(p) });
    }
    let parts: Vec<String> = p
        .components()
        .filter(|c| *c != std::path::Component::CurDir)
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    json!({ "uri": encode(&parts.join("/")), "uriBaseId": "%SRCROOT%" })
}

/// A SARIF 2.1.0 log with one run.
///
/// Codes in `cut` get a tool notification in the run's invocation (`level: note`, the
/// code as `descriptor.id`, `properties.found` and `properties.shown`).
pub fn sarif(sources: &[SourceFile], diags: &[&Diagnostic], cut: &[CodeCount]) -> String {
    let mut codes: Vec<&str> = diags.iter().map(|d| d.code).collect();
    codes.sort_unstable();
    codes.dedup();
    let rules: Vec<Value> = codes
        .iter()
        .map(|c| {
            json!({
                "id": c,
                "name": crate::codes::code_name(c),
                "helpUri": help_uri(c),
            })
        })
        .collect();
    let results: Vec<Value> = diags
        .iter()
        .map(|d| {
            let mut region = json!({});
            if d.span.is_known() {
                let (el, ec) = end_position(sources, d.span);
                region = json!({
                    "startLine": d.span.line,
                    "startColumn": d.span.col,
                    "endLine": el,
                    "endColumn": ec,
                });
            }
            let mut text = display_safe(&d.message).into_owned();
            if let Some(h) = &d.help {
                text.push_str("\nhelp: ");
                text.push_str(&display_safe(h));
            }
            json!({
                "ruleId": d.code,
                "level": severity(d),
                "message": { "text": text },
                "locations": [{
                    "physicalLocation": {
                        "artifactLocation": artifact_location(file_name(sources, d.span)),
                        "region": region,
                    }
                }],
            })
        })
        .collect();
    let mut log = json!({
        "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
        "version": "2.1.0",
        "runs": [{
            "tool": { "driver": {
                "name": "mapc",
                "version": env!("CARGO_PKG_VERSION"),
                "informationUri": "https://github.com/open-rmf",
                "rules": rules,
            }},
            "originalUriBaseIds": {
                "%SRCROOT%": {
                    "uri": std::env::current_dir()
                        .map(|d| format!("{}/", file_uri(&d).trim_end_matches('/')))
                        .unwrap_or_default(),
                },
            },
            "results": results,
        }],
    });
    if !cut.is_empty() {
        let notes: Vec<Value> = cut
            .iter()
            .map(|c| {
                json!({
                    "level": "note",
                    "descriptor": { "id": c.code },
                    "message": { "text": super::limit::summary_text(c) },
                    "properties": { "found": c.found, "shown": c.shown },
                })
            })
            .collect();
        log["runs"][0]["invocations"] = json!([{
            "executionSuccessful": true,
            "toolExecutionNotifications": notes,
        }]);
    }
    let mut s = serde_json::to_string_pretty(&log).unwrap_or_default();
    s.push('\n');
    s
}
