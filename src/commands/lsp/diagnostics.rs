//! mapc diagnostics as LSP diagnostics, and the documentation of a code.

use super::document::Document;
use lsp_types::{
    CodeDescription, DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString,
    Uri,
};
use mapc_ir::{Diagnostic, Severity};
use std::str::FromStr;

/// The generated reference of every code, embedded so that hover shows the same text as
/// docs/diagnostics.md for the mapc that runs.
const DOCS: &str = include_str!("../../../docs/diagnostics.md");

pub(crate) fn to_lsp(doc: &Document, uri: &Uri, d: &Diagnostic) -> lsp_types::Diagnostic {
    let mut message = d.message.clone();
    if let Some(help) = &d.help {
        message.push_str("\nhelp: ");
        message.push_str(help);
    }
    let related: Vec<DiagnosticRelatedInformation> = d
        .labels
        .iter()
        .filter(|l| l.span.file == d.span.file && l.span.is_known())
        .map(|l| DiagnosticRelatedInformation {
            location: Location::new(uri.clone(), doc.range(l.span)),
            message: l.message.clone(),
        })
        .collect();
    lsp_types::Diagnostic {
        range: doc.range(d.span),
        severity: Some(match d.severity {
            Severity::Error => DiagnosticSeverity::ERROR,
            Severity::Warning => DiagnosticSeverity::WARNING,
        }),
        code: Some(NumberOrString::String(d.code.to_string())),
        code_description: Uri::from_str(&crate::ui::json::help_uri(d.code))
            .ok()
            .map(|href| CodeDescription { href }),
        source: Some("mapc".into()),
        message,
        related_information: (!related.is_empty()).then_some(related),
        tags: None,
        data: None,
    }
}

/// The section of docs/diagnostics.md about `code` (What, Why it matters, Fix, Example),
/// without its heading.
pub(crate) fn code_doc(code: &str) -> Option<&'static str> {
    let heading = format!("\n## {code} ");
    let start = DOCS.find(&heading)? + 1;
    let body = &DOCS[start..];
    let body = &body[body.find('\n')? + 1..];
    let end = body.find("\n## ").unwrap_or(body.len());
    Some(body[..end].trim())
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_rule_has_its_section() {
        for r in mapc_ir::rules() {
            let doc = super::code_doc(r.code).unwrap_or_else(|| panic!("{} undocumented", r.code));
            assert!(doc.contains("**What:**"), "{}", r.code);
        }
        assert!(super::code_doc("E0201")
            .unwrap()
            .contains("starts and ends at the same vertex"));
    }
}
