//! The user's lint levels: `--allow`, `--warn`, `--deny` (a code, a name, or `warnings`)
//! and the `[lints]` table of a `mapc.toml` (`--config FILE`, or the first one found beside
//! the map or in a parent directory).
//!
//! Precedence: a code's level on the command line, else its level in the file, else its
//! default (the letter of the code). Then whatever is still a warning takes the level of
//! the `warnings` group (command line, else file; `--deny-warnings` is `--deny warnings`):
//! an allowed code stays allowed under `--deny warnings`, as with rustc's `-D warnings`.

use crate::codes::{self, Source};
use mapc_ir::{Diagnostic, Severity};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Level {
    Allow,
    Warn,
    Deny,
}

impl Level {
    fn parse(s: &str) -> Option<Level> {
        match s {
            "allow" => Some(Level::Allow),
            "warn" => Some(Level::Warn),
            "deny" => Some(Level::Deny),
            _ => None,
        }
    }
    fn flag(self) -> &'static str {
        match self {
            Level::Allow => "allow",
            Level::Warn => "warn",
            Level::Deny => "deny",
        }
    }
}

/// One source of levels (the command line or one file).
#[derive(Default, Clone, Debug)]
pub(crate) struct LevelSet {
    codes: BTreeMap<&'static str, Level>,
    /// The level of the `warnings` group, if set.
    warnings: Option<Level>,
}

/// Every code a map can get, with its name: frontends, validation rules, backends.
fn known_codes() -> impl Iterator<Item = (&'static str, &'static str)> {
    codes::all()
        .iter()
        .filter(|e| e.source != Source::Scenario)
        .map(|e| (e.code.code, e.code.name))
}

impl LevelSet {
    /// Adds `level` for `what` (a code, a name or `warnings`); `origin` names where it
    /// came from for messages.
    fn set(&mut self, what: &str, level: Level, origin: &str) -> Result<(), String> {
        if what == "warnings" {
            if let Some(old) = self.warnings.replace(level) {
                if old != level {
                    return Err(format!(
                        "{origin}: `warnings` is given both `{}` and `{}`",
                        old.flag(),
                        level.flag()
                    ));
                }
            }
            return Ok(());
        }
        let Some((code, name)) = known_codes().find(|(c, n)| *c == what || *n == what) else {
            return Err(format!(
                "{origin}: unknown diagnostic `{what}` (use a code such as E0302 or a name such as duplicate-door-name; docs/diagnostics.md lists them)"
            ));
        };
        if level != Level::Deny && code.starts_with('E') && !codes::policy(code).can_allow {
            return Err(format!(
                "{origin}: {code} {name} cannot be {}: no correct output can be written after it (docs/diagnostics.md marks the codes that can)",
                if level == Level::Allow { "allowed" } else { "lowered to a warning" }
            ));
        }
        if let Some(old) = self.codes.insert(code, level) {
            if old != level {
                return Err(format!(
                    "{origin}: {code} {name} is given both `{}` and `{}`",
                    old.flag(),
                    level.flag()
                ));
            }
        }
        Ok(())
    }
}

/// The command line's levels, from `--allow`, `--warn`, `--deny` and `--deny-warnings`.
pub(crate) fn from_flags(
    allow: &[String],
    warn: &[String],
    deny: &[String],
    deny_warnings: bool,
) -> Result<LevelSet, String> {
    let mut set = LevelSet::default();
    for (list, level) in [
        (allow, Level::Allow),
        (warn, Level::Warn),
        (deny, Level::Deny),
    ] {
        for what in list {
            set.set(what, level, &format!("--{}", level.flag()))?;
        }
    }
    if deny_warnings {
        set.set("warnings", Level::Deny, "--deny-warnings")?;
    }
    Ok(set)
}

/// Reads the `[lints]` table of a mapc.toml.
pub(crate) fn from_file(path: &Path) -> Result<LevelSet, String> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{origin}: {e}"))?;
    let table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| format!("{origin}: {}", e.to_string().trim_end()))?;
    let mut set = LevelSet::default();
    for (key, value) in &table {
        if key != "lints" {
            return Err(format!(
                "{origin}: unknown table `{key}` (mapc.toml has `[lints]`)"
            ));
        }
        let Some(lints) = value.as_table() else {
            return Err(format!("{origin}: `lints` must be a table"));
        };
        for (what, level) in lints {
            let level = level.as_str().and_then(Level::parse).ok_or_else(|| {
                format!("{origin}: [lints] {what} must be \"allow\", \"warn\" or \"deny\"")
            })?;
            set.set(what, level, &origin)?;
        }
    }
    Ok(set)
}

/// The mapc.toml that applies to `input`: beside it or in the nearest parent directory.
pub(crate) fn discover(input: &Path) -> Option<PathBuf> {
    let abs = std::path::absolute(input).ok()?;
    abs.parent()?
        .ancestors()
        .map(|d| d.join("mapc.toml"))
        .find(|p| p.is_file())
}

/// The levels for one map: command line over file.
#[derive(Clone, Debug, Default)]
pub(crate) struct Lints {
    cli: LevelSet,
    file: LevelSet,
}

impl Lints {
    pub(crate) fn new(cli: LevelSet, file: Option<LevelSet>) -> Lints {
        Lints {
            cli,
            file: file.unwrap_or_default(),
        }
    }

    fn level(&self, code: &str) -> Level {
        let default = if code.starts_with('E') {
            Level::Deny
        } else {
            Level::Warn
        };
        let level = self
            .cli
            .codes
            .get(code)
            .or_else(|| self.file.codes.get(code))
            .copied()
            .unwrap_or(default);
        match (level, self.cli.warnings.or(self.file.warnings)) {
            (Level::Warn, Some(group)) => group,
            _ => level,
        }
    }

    /// Applies the levels: allowed diagnostics are removed, the others get their severity.
    pub(crate) fn apply(&self, diags: &mut Vec<Diagnostic>) {
        diags.retain_mut(|d| match self.level(d.code) {
            Level::Allow => false,
            Level::Warn => {
                d.severity = Severity::Warning;
                true
            }
            Level::Deny => {
                d.severity = Severity::Error;
                true
            }
        });
    }
}
