//! The registry: every diagnostic code mapc reports, in one list, each with the facts its
//! declaration gives (`mapc_ir::Code`: code, name, summary, lint group; rules add whether
//! they are metric). The declarations stay where the codes are reported (the frontends',
//! the validation rules', the backends', the scenario runtime's, the sweep's in `sweep`);
//! this module is the one place that gathers them, and every part of the CLI asks it:
//! names, policies (through the group), `--allow CODE`, help links.
//!
//! A new code is declared once, with its doc, beside its siblings (a rule: its own file
//! under ir/src/validate/); the registry and docs/diagnostics.md follow (`MAPC_UPDATE_DOCS=1
//! cargo test --test docs`). Nothing below this module imports from the rest of `src/`.

pub(crate) mod sweep;

use mapc_ir::lints::{Policy, UNKNOWN_CODE};
use mapc_ir::Code;
use std::collections::HashMap;
use std::sync::OnceLock;

/// Which input a code is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Source {
    /// A map: its reading, a validation rule, or producing output (the lints).
    Map,
    /// A `.site.json` file.
    Site,
    /// A scenario or sweep file (`mapc sim`, `mapc sweep`).
    Scenario,
}

/// One code, as the CLI knows it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Entry {
    pub code: Code,
    pub source: Source,
    /// A validation rule that compares positions with thresholds in metres.
    pub metric: bool,
}

impl Entry {
    pub(crate) fn policy(&self) -> Policy {
        self.code.group.policy()
    }
}

/// Every code, in docs order.
pub(crate) fn all() -> &'static [Entry] {
    static ALL: OnceLock<Vec<Entry>> = OnceLock::new();
    ALL.get_or_init(|| {
        let entry = |source, metric| {
            move |c: &Code| Entry {
                code: *c,
                source,
                metric,
            }
        };
        let mut all: Vec<Entry> = mapc_frontend::CODES
            .iter()
            .map(entry(Source::Map, false))
            .collect();
        all.extend(
            mapc_frontend::site::codes::CODES
                .iter()
                .map(entry(Source::Site, false)),
        );
        all.extend(mapc_ir::rules().map(|r| Entry {
            code: r.code(),
            source: Source::Map,
            metric: r.metric,
        }));
        all.extend(mapc_backends::CODES.iter().map(entry(Source::Map, false)));
        all.extend(
            mapc_sim::codes::CODES
                .iter()
                .chain(sweep::CODES)
                .map(entry(Source::Scenario, false)),
        );
        all
    })
}

/// The entry of `code` (a code such as `W0204`).
pub(crate) fn find(code: &str) -> Option<&'static Entry> {
    // A map can have tens of thousands of diagnostics, each asked about: a hash, not a scan.
    static BY_CODE: OnceLock<HashMap<&'static str, &'static Entry>> = OnceLock::new();
    BY_CODE
        .get_or_init(|| all().iter().map(|e| (e.code.code, e)).collect())
        .get(code)
        .copied()
}

/// Stable name of a diagnostic code (`""` for a code no table lists).
pub(crate) fn code_name(code: &str) -> &'static str {
    find(code).map_or("", |e| e.code.name)
}

/// How `code` may be treated: from its group (an unknown code may be allowed and blocks
/// everything).
pub(crate) fn policy(code: &str) -> Policy {
    find(code).map_or(UNKNOWN_CODE, Entry::policy)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn every_code_is_declared_once() {
        let mut seen = BTreeSet::new();
        for e in all() {
            assert!(seen.insert(e.code.code), "{} declared twice", e.code.code);
        }
    }

    /// docs/diagnostics.md documents exactly the registry's codes (its sections are
    /// generated from the declarations by tests/docs.rs; this keeps both in step).
    #[test]
    fn the_docs_document_exactly_the_registry() {
        let docs = include_str!("../../docs/diagnostics.md");
        let documented: BTreeSet<(String, String)> = docs
            .lines()
            .filter_map(|l| l.strip_prefix("## "))
            .filter_map(|h| h.split_once(' '))
            .filter(|(code, _)| code.len() == 5 && code[1..].chars().all(|c| c.is_ascii_digit()))
            .map(|(c, n)| (c.to_string(), n.to_string()))
            .collect();
        let registry: BTreeSet<(String, String)> = all()
            .iter()
            .map(|e| (e.code.code.to_string(), e.code.name.to_string()))
            .collect();
        let missing: Vec<_> = registry.difference(&documented).collect();
        let extra: Vec<_> = documented.difference(&registry).collect();
        assert!(
            missing.is_empty() && extra.is_empty(),
            "not documented: {missing:?}; documented but not declared: {extra:?}"
        );
    }

    #[test]
    fn policies_come_from_the_groups() {
        assert_eq!(policy("E0407").blocks, mapc_ir::lints::Outputs::NAV);
        assert!(policy("E0302").nav_only_with_lanes);
        assert!(!policy("E0001").can_allow && !policy("E0509").can_allow);
        assert!(policy("E0112").can_allow);
        assert!(find("W0204").is_some_and(|e| e.metric));
        assert!(find("W0203").is_some_and(|e| !e.metric));
        assert_eq!(code_name("W0701"), "texture-not-found");
    }
}
