//! The options every command that reads a map shares: lint levels and how to report.

use crate::ui::{limit::MaxDiagnostics, Format};
use std::path::PathBuf;

#[derive(clap::Args, Clone, Debug)]
pub(crate) struct DiagOpts {
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value = "human")]
    pub format: Format,
    /// Do not print the success line (what was written) on stderr.
    #[arg(short, long)]
    pub quiet: bool,
    /// Show at most N diagnostics per code, then one line with the number found (`all`:
    /// show every one).
    #[arg(long, value_name = "N|all", default_value = "20")]
    pub max_diagnostics: MaxDiagnostics,
    /// Show source snippets in `nav`, `gazebo`, `ignition` and `classic` too (they print
    /// one `file:line:col` line per diagnostic otherwise); in `build`, every warning with
    /// its snippet (by default: errors in full, warnings counted by code per map).
    #[arg(short = 'v', long)]
    pub verbose: bool,
    #[command(flatten)]
    pub lints: LintOpts,
}

/// Lint levels, on every command that reads a map.
#[derive(clap::Args, Clone, Debug)]
pub(crate) struct LintOpts {
    /// Treat warnings as errors (the same as `--deny warnings`).
    #[arg(long)]
    pub deny_warnings: bool,
    /// Do not report CODE (a code such as W0204 or a name such as lane-crosses-wall);
    /// repeatable. Errors after which no correct output can be written cannot be allowed.
    #[arg(long, value_name = "CODE")]
    pub allow: Vec<String>,
    /// Report CODE as a warning (repeatable); an error lowered so no longer blocks output.
    #[arg(long, value_name = "CODE")]
    pub warn: Vec<String>,
    /// Report CODE as an error (repeatable); `--deny warnings` makes every warning an error.
    #[arg(long, value_name = "CODE")]
    pub deny: Vec<String>,
    /// Lint levels from FILE (a `[lints]` table) instead of the mapc.toml found beside the
    /// map or in a parent directory. The command line wins over the file.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}
