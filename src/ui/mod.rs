//! What users read: diagnostics as snippets or one-liners (`report`), JSON Lines and SARIF
//! (`json`), the excerpts and escaping that keep untrusted text readable and safe
//! (`snippet`, `escape`), the per-code limit (`limit`) and the progress bar (`progress`).
//! Invariant: `ui` knows text and diagnostics, not maps or commands: it imports only
//! `crate::codes` (for code names), never the driver or a command.

pub(crate) mod escape;
pub(crate) mod json;
pub(crate) mod limit;
pub(crate) mod progress;
pub(crate) mod report;
mod snippet;

use std::path::{Component, Path, PathBuf};

/// How diagnostics are printed (`--format`).
#[derive(Clone, Copy, Debug, clap::ValueEnum, PartialEq, Eq)]
pub(crate) enum Format {
    /// Source snippets with underlines (colour on a terminal).
    Human,
    /// JSON Lines on stdout: one object per diagnostic (schema in docs/diagnostics.md).
    Json,
    /// A SARIF 2.1.0 log on stdout, for code-scanning tools.
    Sarif,
}

/// One line on stderr in one write (`eprintln!` writes each piece of its format on its
/// own to unbuffered stderr: a log's reader wakes for each, and lines of processes sharing
/// a log can interleave).
pub(crate) fn say(mut line: String) {
    use std::io::Write;
    line.push('\n');
    // Nothing useful to do if stderr is gone (e.g. a closed pipe).
    let _ = std::io::stderr().write_all(line.as_bytes());
}

/// `error: MESSAGE` on stderr: how every failure is said, by `main` for the one that ends
/// a command, by a command for one it reports and carries on after (one map of several).
pub(crate) fn error(message: impl std::fmt::Display) {
    say(format!("error: {message}"));
}

/// `n thing` or `n things`.
pub(crate) fn plural(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else if thing.ends_with("sh") || thing.ends_with('s') {
        format!("{n} {thing}es")
    } else {
        format!("{n} {thing}s")
    }
}

/// A path as users wrote it, without `./` noise (`./../x` prints as `../x`).
pub(crate) fn shown(p: &Path) -> String {
    let mut out = PathBuf::new();
    for c in p.components() {
        if c != Component::CurDir {
            out.push(c);
        }
    }
    if out.as_os_str().is_empty() {
        ".".into()
    } else {
        out.display().to_string()
    }
}
