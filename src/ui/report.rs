//! Human rendering of diagnostics with source snippets (codespan-reporting).

use super::escape::display_safe;
use super::limit::CodeCount;
use super::snippet::{Excerpts, SourceLines};
use codespan_reporting::diagnostic::{
    Diagnostic as CsDiagnostic, Label as CsLabel, Severity as CsSeverity,
};
use codespan_reporting::files::SimpleFiles;
use codespan_reporting::term::{
    self,
    termcolor::{BufferWriter, ColorChoice},
};
use mapc_frontend::SourceFile;
use mapc_ir::{Diagnostic, Severity};
use std::io::{IsTerminal, Write};

/// How a diagnostic is printed in human form.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// With source snippets (`check`, `gltf`, `meshes`, `build`, and `--verbose`).
    Snippets,
    /// One `file:line:col: severity[code]: message` line (the drop-in commands).
    OneLine,
}

/// Renders `diags` to stderr as they come (one write per diagnostic, so memory holds one
/// rendered diagnostic, not the report), then one line per code in `cut` stating how many
/// were found. Colour only on a terminal.
///
/// Each diagnostic is rendered into a buffer first: the renderer issues many small writes
/// (a colour change, a gutter, a fragment of a line), and stderr is unbuffered. All of them
/// then go out in one write: a build log's reader (a pipe) wakes once, and the
/// diagnostics of processes writing to one log at once do not interleave.
pub fn emit(sources: &[SourceFile], diags: &[&Diagnostic], cut: &[CodeCount], style: Style) {
    if diags.is_empty() && cut.is_empty() {
        return;
    }
    let choice = if std::io::stderr().is_terminal() {
        ColorChoice::Auto
    } else {
        ColorChoice::Never
    };
    let writer = BufferWriter::stderr(choice);
    // The line index of every file only for snippets: one-line diagnostics carry their
    // line and column (a build log of a large map would index it for nothing).
    let snippets = (style != Style::OneLine).then(|| {
        let mut files = SimpleFiles::new();
        for s in sources {
            files.add(display_safe(&s.name), s.text.as_str());
        }
        (files, SourceLines::new(sources))
    });
    let config = term::Config::default();
    let mut all = writer.buffer();
    for d in diags {
        let mut one = writer.buffer();
        if let Some((files, lines)) = &snippets {
            let cs = to_codespan(sources, d);
            let labels: Vec<(usize, std::ops::Range<usize>)> = cs
                .labels
                .iter()
                .map(|l| (l.file_id, l.range.clone()))
                .collect();
            let rendered = if lines.needs_excerpt(&labels) {
                // Long lines cut, control and bidi characters escaped.
                let (excerpts, ranges) = Excerpts::new(lines, &labels);
                let mut cs = cs;
                for (l, r) in cs.labels.iter_mut().zip(ranges) {
                    l.range = r;
                }
                term::emit_to_write_style(&mut one, &config, &excerpts, &cs)
            } else {
                term::emit_to_write_style(&mut one, &config, files, &cs)
            };
            if rendered.is_err() {
                // A span that does not fit its file (should not happen): plain fallback,
                // in place of whatever was rendered before the failure.
                one = writer.buffer();
                let _ = writeln!(one, "{}", one_line(sources, d));
            }
        } else {
            let _ = writeln!(one, "{}", one_line(sources, d));
        }
        // In memory: cannot fail.
        let _ = all.write_all(one.as_slice());
    }
    for c in cut {
        let _ = writeln!(all, "{}", super::limit::summary_text(c));
    }
    // Nothing useful to do if stderr is gone (e.g. a closed pipe).
    let _ = writer.print(&all);
}

fn to_codespan(sources: &[SourceFile], d: &Diagnostic) -> CsDiagnostic<usize> {
    let severity = match d.severity {
        Severity::Error => CsSeverity::Error,
        Severity::Warning => CsSeverity::Warning,
    };
    let file = d.span.file.0 as usize;
    let mut cs = CsDiagnostic::new(severity).with_code(d.code);
    if d.span.is_known() && file < sources.len() {
        cs = cs.with_message(display_safe(&d.message));
        let mut labels = vec![CsLabel::primary(
            file,
            d.span.start as usize..d.span.end.max(d.span.start) as usize,
        )];
        for l in &d.labels {
            if l.span.is_known() && (l.span.file.0 as usize) < sources.len() {
                labels.push(
                    CsLabel::secondary(
                        l.span.file.0 as usize,
                        l.span.start as usize..l.span.end as usize,
                    )
                    .with_message(display_safe(&l.message)),
                );
            }
        }
        cs = cs.with_labels(labels);
    } else {
        // No position (a whole-file problem): name the file in the message.
        let name = sources.first().map_or("<input>", |s| s.name.as_str());
        cs = cs.with_message(format!(
            "{}: {}",
            display_safe(name),
            display_safe(&d.message)
        ));
    }
    if let Some(h) = &d.help {
        cs = cs.with_notes(vec![format!("help: {}", display_safe(h))]);
    }
    cs
}

/// `file:line:col: severity[code]: message`.
pub fn one_line(sources: &[SourceFile], d: &Diagnostic) -> String {
    let name = sources
        .get(d.span.file.0 as usize)
        .map_or("<input>", |s| s.name.as_str());
    let sev = match d.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
    };
    if d.span.is_known() {
        format!(
            "{}:{}:{}: {sev}[{}]: {}",
            display_safe(name),
            d.span.line,
            d.span.col,
            d.code,
            display_safe(&d.message)
        )
    } else {
        format!(
            "{}: {sev}[{}]: {}",
            display_safe(name),
            d.code,
            display_safe(&d.message)
        )
    }
}
