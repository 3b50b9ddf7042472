//! Diagnostics shared by the frontend, the validation passes and the backends.

use crate::Span;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    Warning,
    Error,
}

/// A secondary location with a short message ("the other door is here").
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    pub span: Span,
    pub message: String,
}

/// A documented diagnostic code: each crate that reports diagnostics lists its codes as
/// `Code` constants whose doc comments are gathered into docs/diagnostics.md (validation
/// rules declare the same facts on their `Rule`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Code {
    /// Stable code; its letter is the default severity (`E` error, `W` warning; `S`
    /// scenario codes say theirs in their doc).
    pub code: &'static str,
    /// Stable kebab-case name, accepted wherever a code is (`--allow lane-self-loop`).
    pub name: &'static str,
    pub summary: &'static str,
    /// What an error of this code breaks, and whether it may be allowed.
    pub group: crate::lints::Group,
}

impl Code {
    /// Whether `d` is a diagnostic of this code.
    pub fn is(&self, d: &Diagnostic) -> bool {
        d.code == self.code
    }
}

/// The anchor of a code's section in docs/diagnostics.md: `e0201-lane-self-loop`.
pub fn doc_anchor(code: &str, name: &str) -> String {
    format!("{}-{name}", code.to_lowercase())
}

/// One problem found in a map. `code` is stable across releases (see docs/diagnostics.md).
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    pub severity: Severity,
    pub code: &'static str,
    pub message: String,
    pub span: Span,
    pub labels: Vec<Label>,
    pub help: Option<String>,
}

impl Diagnostic {
    pub fn error(code: &'static str, span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Error,
            code,
            message: message.into(),
            span,
            labels: Vec::new(),
            help: None,
        }
    }
    pub fn warning(code: &'static str, span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::error(code, span, message)
        }
    }
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }
    pub fn with_label(mut self, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label {
            span,
            message: message.into(),
        });
        self
    }
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// True if any diagnostic is an error.
pub fn has_errors(diags: &[Diagnostic]) -> bool {
    diags.iter().any(Diagnostic::is_error)
}

/// A count with thousands separators, as messages print them: `29,990`.
pub fn count_text(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn count_text() {
        assert_eq!(super::count_text(0), "0");
        assert_eq!(super::count_text(999), "999");
        assert_eq!(super::count_text(1000), "1,000");
        assert_eq!(super::count_text(24878), "24,878");
        assert_eq!(super::count_text(1234567), "1,234,567");
    }
}
