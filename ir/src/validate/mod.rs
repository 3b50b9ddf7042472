//! Validation passes: one rule per file, each with a stable code. A rule's `//!` doc
//! comment (what it means, why it matters, how to fix it, an example) is gathered into
//! docs/diagnostics.md by `cargo test --test docs` (MAPC_UPDATE_DOCS=1 rewrites it).
//!
//! Rules read a [`Building`] that the frontend produced (all handles valid) and never
//! panic; they may assume nothing else (degenerate geometry, duplicate names, ... are
//! exactly what they look for).

mod context;
mod crowd;
mod doors;
mod geometry;
pub(crate) mod grid;
mod lanes;
mod lifts;
mod names;
#[cfg(test)]
pub(crate) mod tests;

pub use context::Context;

use crate::{Building, Diagnostic, Severity};

/// A validation rule.
pub struct Rule {
    /// Stable code, e.g. `E0201`. The letter gives the default severity.
    pub code: &'static str,
    /// Stable kebab-case name, e.g. `lane-self-loop`.
    pub name: &'static str,
    /// One line: what the rule finds.
    pub summary: &'static str,
    /// What an error of this rule breaks, and whether it may be allowed.
    pub group: crate::lints::Group,
    /// The rule compares positions with thresholds in metres (a door's width, how close two
    /// waypoints are): meaningless, and not run, when the frontend could not tell the map's
    /// units.
    pub metric: bool,
    pub check: fn(&Context, &mut Vec<Diagnostic>),
}

impl Rule {
    /// The rule's facts as a [`crate::Code`], as the other crates declare theirs.
    pub fn code(&self) -> crate::Code {
        crate::Code {
            code: self.code,
            name: self.name,
            summary: self.summary,
            group: self.group,
        }
    }

    pub fn severity(&self) -> Severity {
        if self.code.starts_with('E') {
            Severity::Error
        } else {
            Severity::Warning
        }
    }
}

/// Every rule, grouped: lanes (E02xx), doors (E03xx), lifts (E04xx), names and roles
/// (E05xx), geometry and coordinates (E06xx), crowd simulation (E08xx).
pub fn rules() -> impl Iterator<Item = &'static Rule> {
    lanes::RULES
        .iter()
        .chain(doors::RULES)
        .chain(lifts::RULES)
        .chain(names::RULES)
        .chain(geometry::RULES)
        .chain(crowd::RULES)
        .copied()
}

/// Runs every rule; diagnostics come out sorted by position, then code.
pub fn validate(b: &Building) -> Vec<Diagnostic> {
    let ctx = Context::new(b);
    let mut out = Vec::new();
    for rule in rules() {
        (rule.check)(&ctx, &mut out);
    }
    out.sort_by(|a, b| {
        (a.span.file, a.span.start, a.code, &a.message).cmp(&(
            b.span.file,
            b.span.start,
            b.code,
            &b.message,
        ))
    });
    out
}

/// Looks up a rule by code.
pub fn rule(code: &str) -> Option<&'static Rule> {
    rules().find(|r| r.code == code)
}
