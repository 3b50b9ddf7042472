//! Human rendering of diagnostics with source snippets (codespan-reporting).

use codespan_reporting::diagnostic::{
    Diagnostic as CsDiagnostic, Label as CsLabel, Severity as CsSeverity,
};
use codespan_reporting::files::SimpleFiles;
use codespan_reporting::term::{
    self,
    termcolor::{ColorChoice, StandardStream},
};
use mapc_frontend::SourceFile;
use mapc_ir::{Diagnostic, Severity};
use std::io::IsTerminal;

/// Renders diagnostics to stderr, colour only on a terminal.
pub fn emit(sources: &[SourceFile], diags: &[Diagnostic]) {
    let mut files = SimpleFiles::new();
    for s in sources {
        files.add(s.name.as_str(), s.text.as_str());
    }
    let choice = if std::io::stderr().is_terminal() {
        ColorChoice::Auto
    } else {
        ColorChoice::Never
    };
    let mut out = StandardStream::stderr(choice);
    let config = term::Config::default();
    for d in diags {
        let cs = to_codespan(sources, d);
        if term::emit_to_write_style(&mut out, &config, &files, &cs).is_err() {
            // A span that does not fit its file (should not happen): plain fallback.
            eprintln!("{}", one_line(sources, d));
        }
    }
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
