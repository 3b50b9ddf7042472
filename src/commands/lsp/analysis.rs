//! Checking one open document: the same frontend, validation passes and lint levels as
//! `mapc check`, on the editor's text instead of the file on disk.

use super::document::{Document, Kind};
use super::outline;
use crate::driver::lints::Lints;
use mapc_ir::{Building, Diagnostic, FileId, Span};
use std::path::Path;

/// The result of checking one version of a document.
pub(crate) struct Analysis {
    /// The building (maps only; `None` when nothing could be read).
    pub(crate) building: Option<Building>,
    /// Diagnostics located in this document (file 0), at the user's lint levels.
    pub(crate) diagnostics: Vec<Diagnostic>,
}

/// Checks `doc` with `lints` (the levels that apply to its path).
pub(crate) fn check(doc: &Document, lints: &Lints) -> Analysis {
    let name = doc
        .path
        .as_ref()
        .map_or_else(|| doc.uri.clone(), |p| p.display().to_string());
    let (building, mut diagnostics) = match doc.kind {
        Kind::Building => {
            let parsed = mapc_frontend::parse_str(&name, &doc.text);
            let mut diags = crate::driver::all_diagnostics(&parsed);
            lints.apply(&mut diags);
            (parsed.building, diags)
        }
        Kind::Site => {
            let parsed = mapc_frontend::parse_site_str(&name, &doc.text);
            let mut diags = crate::driver::all_diagnostics(&parsed);
            lints.apply(&mut diags);
            (parsed.building, diags)
        }
        Kind::Project => (None, check_project(doc, lints)),
        Kind::Scenario => {
            let base = doc
                .path
                .as_deref()
                .and_then(Path::parent)
                .unwrap_or(Path::new("."));
            // Scenario codes (S...) are not lints: their severities are fixed.
            (None, mapc_sim::parse_scenario(FileId(0), &doc.text, base).1)
        }
    };
    // Labels in other files cannot be shown as this document's ranges.
    diagnostics.retain(|d| d.span.file == FileId(0));
    Analysis {
        building,
        diagnostics,
    }
}

/// A legacy project file: its own problems, then the building it names, read from disk
/// and summarised at `building.filename` (its diagnostics belong to that file).
fn check_project(doc: &Document, lints: &Lints) -> Vec<Diagnostic> {
    let root = match mapc_frontend::yaml_tree::parse(&doc.text, FileId(0)) {
        Ok(r) => r,
        Err(d) => return vec![d],
    };
    let Some(target) = root.get("building").and_then(|b| b.get("filename")) else {
        return vec![Diagnostic::error(
            mapc_frontend::codes::BAD_PROJECT.code,
            root.span,
            "project file has no `building: {filename: ...}`",
        )
        .with_help("name the .building.yaml file under `building.filename`")];
    };
    let Some(bpath) = project_target(doc, &root) else {
        return Vec::new();
    };
    let span = target.span;
    let parsed = match mapc_frontend::load(&bpath) {
        Ok(p) => p,
        Err(e) => {
            return vec![Diagnostic::error(
                mapc_frontend::codes::BAD_PROJECT.code,
                span,
                e.to_string(),
            )
            .with_help("`building.filename` is read relative to the project file")]
        }
    };
    let mut diags = crate::driver::all_diagnostics(&parsed);
    lints.apply(&mut diags);
    let errors = diags.iter().filter(|d| d.is_error()).count();
    let warnings = diags.len() - errors;
    if diags.is_empty() {
        return Vec::new();
    }
    // The first error (the worst problem), else the first warning.
    let first = diags.iter().find(|d| d.is_error()).unwrap_or(&diags[0]);
    let message = format!(
        "{}: {errors} error(s), {warnings} warning(s); the first: {}[{}] at line {}",
        bpath.display(),
        if first.is_error() { "error" } else { "warning" },
        first.code,
        first.span.line
    );
    let d = Diagnostic {
        span: Span {
            file: FileId(0),
            ..span
        },
        ..first.clone()
    };
    vec![Diagnostic {
        message,
        labels: Vec::new(),
        help: Some("open the building file to see every problem".into()),
        ..d
    }]
}

/// The building file a project names, as a path.
pub(crate) fn project_target(
    doc: &Document,
    root: &mapc_frontend::yaml_tree::Node,
) -> Option<std::path::PathBuf> {
    let target = root.get("building")?.get("filename")?.key_text()?;
    let dir = doc.path.as_deref()?.parent()?;
    Some(dir.join(target))
}

/// The project file's `building.filename` value span, for go to definition.
pub(crate) fn project_filename_span(text: &str) -> Option<Span> {
    let root = outline::parse(text)?;
    Some(root.get("building")?.get("filename")?.span)
}
