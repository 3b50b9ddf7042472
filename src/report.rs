//! Human rendering of diagnostics with source snippets (codespan-reporting).

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

/// Renders diagnostics to stderr, colour only on a terminal.
///
/// Everything is rendered into one buffer and written at once: the renderer issues many
/// small writes (a colour change, a gutter, a fragment of a line), and stderr is
/// unbuffered, so writing straight to it costs thousands of system calls per map.
pub fn emit(sources: &[SourceFile], diags: &[Diagnostic]) {
    if diags.is_empty() {
        return;
    }
    let mut files = SimpleFiles::new();
    for s in sources {
        files.add(s.name.as_str(), s.text.as_str());
    }
    let choice = if std::io::stderr().is_terminal() {
        ColorChoice::Auto
    } else {
        ColorChoice::Never
    };
    let writer = BufferWriter::stderr(choice);
    let mut out = writer.buffer();
    let config = term::Config::default();
    for d in diags {
        let cs = to_codespan(sources, d);
        let mut one = writer.buffer();
        // Writes to a memory buffer do not fail.
        let _ = match term::emit_to_write_style(&mut one, &config, &files, &cs) {
            Ok(()) => out.write_all(one.as_slice()),
            // A span that does not fit its file (should not happen): plain fallback, in
            // place of whatever was rendered before the failure.
            Err(_) => writeln!(out, "{}", one_line(sources, d)),
        };
    }
    // Nothing useful to do if stderr is gone (e.g. a closed pipe).
    let _ = writer.print(&out);
}

fn to_codespan(sources: &[SourceFile], d: &Diagnostic) -> CsDiagnostic<usize> {
    let severity = match d.severity {
        Severity::Error => CsSeverity::Error,
        Severity::Warning => CsSeverity::Warning,
    };
    let file = d.span.file.0 as usize;
    let mut cs = CsDiagnostic::new(severity).with_code(d.code);
    if d.span.is_known() && file < sources.len() {
        cs = cs.with_message(&d.message);
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
                    .with_message(&l.message),
                );
            }
        }
        cs = cs.with_labels(labels);
    } else {
        // No position (a whole-file problem): name the file in the message.
        let name = sources.first().map_or("<input>", |s| s.name.as_str());
        cs = cs.with_message(format!("{name}: {}", d.message));
    }
    if let Some(h) = &d.help {
        cs = cs.with_notes(vec![format!("help: {h}")]);
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
            "{name}:{}:{}: {sev}[{}]: {}",
            d.span.line, d.span.col, d.code, d.message
        )
    } else {
        format!("{name}: {sev}[{}]: {}", d.code, d.message)
    }
}
