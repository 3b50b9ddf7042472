//! The changes as text for a terminal, JSON for tools, Markdown for a pull-request comment.

use super::compute::{Change, Kind, Section};
use serde_json::json;

fn mark(k: Kind) -> &'static str {
    match k {
        Kind::Added => "+",
        Kind::Removed => "-",
        Kind::Changed => "~",
    }
}

fn counts(changes: &[Change]) -> String {
    let n = |k: Kind| changes.iter().filter(|c| c.kind == k).count();
    format!(
        "{} added, {} removed, {} changed",
        n(Kind::Added),
        n(Kind::Removed),
        n(Kind::Changed)
    )
}

/// A section (on a level) and its changes.
type Group<'a> = ((Section, Option<&'a str>), Vec<&'a Change>);

/// Changes grouped by section then level, in order.
fn groups(changes: &[Change]) -> Vec<Group<'_>> {
    let mut out: Vec<Group<'_>> = Vec::new();
    for c in changes {
        let k = (c.section, c.level.as_deref());
        match out.last_mut() {
            Some((last, v)) if *last == k => v.push(c),
            _ => out.push((k, vec![c])),
        }
    }
    out
}

fn heading(section: Section, level: Option<&str>) -> String {
    match level {
        Some(l) => format!("{} on level `{l}`", section.title()),
        None => section.title().to_string(),
    }
}

pub(crate) fn human(old: &str, new: &str, changes: &[Change]) -> String {
    if changes.is_empty() {
        return String::new();
    }
    let mut s = format!("{old} → {new}: {}\n", counts(changes));
    for ((section, level), cs) in groups(changes) {
        s.push_str(&format!("\n{}:\n", heading(section, level)));
        for c in cs {
            s.push_str(&format!("  {} {}: {}\n", mark(c.kind), c.subject, c.detail));
        }
    }
    s
}

pub(crate) fn json(old: &str, new: &str, changes: &[Change]) -> String {
    let v = json!({"old": old, "new": new, "changed": !changes.is_empty(), "changes": changes});
    format!("{}\n", serde_json::to_string_pretty(&v).unwrap_or_default())
}

/// Markdown-safe text: backticks are kept (names are in code spans), table pipes escaped.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

pub(crate) fn markdown(old: &str, new: &str, changes: &[Change]) -> String {
    let mut s = format!("### Map changes: `{old}` → `{new}`\n\n");
    if changes.is_empty() {
        s.push_str("No changes by meaning.\n");
        return s;
    }
    s.push_str(&format!("{}.\n", counts(changes)));
    for ((section, level), cs) in groups(changes) {
        s.push_str(&format!(
            "\n#### {}\n\n| | what | change |\n|---|---|---|\n",
            heading(section, level)
        ));
        for c in cs {
            let m = match c.kind {
                Kind::Added => "➕",
                Kind::Removed => "➖",
                Kind::Changed => "✏️",
            };
            s.push_str(&format!(
                "| {m} | {} | {} |\n",
                cell(&c.subject),
                cell(&c.detail)
            ));
        }
    }
    s
}
