//! A checked map's report, as every command prints it: its diagnostics in the chosen
//! format, the count line, what was not written and why, and the success line.

use super::check::{load_and_check, Checked};
use super::opts::{DiagOpts, LintOpts};
use super::output::Written;
use super::CliError;
use crate::codes::policy;
use crate::ui::{self, json, limit, report, say, shown, Format};
use mapc_ir::lints::Outputs;
use std::path::Path;

/// Prints the diagnostics of `c` in the chosen format, at most `--max-diagnostics` per
/// code (SARIF is printed by the caller, once for all maps). `style` is the command's
/// human style; `--verbose` always gives snippets.
pub(crate) fn emit(c: &Checked, opts: &DiagOpts, style: report::Style) {
    let (shown, cut) = limit::select(&c.diagnostics, opts.max_diagnostics);
    let style = if opts.verbose {
        report::Style::Snippets
    } else {
        style
    };
    match opts.format {
        Format::Human => report::emit(&c.parsed.sources, &shown, &cut, style),
        Format::Json => {
            let mut out = std::io::BufWriter::new(std::io::stdout().lock());
            // Nothing useful to do if stdout is gone (e.g. a closed pipe).
            let _ = json::write_json_lines(&mut out, &c.parsed.sources, &shown, &cut);
        }
        Format::Sarif => print!("{}", json::sarif(&c.parsed.sources, &shown, &cut)),
    }
}

/// `error: MAP: nothing written` (or which outputs were not), with the codes to blame.
pub(crate) fn not_written(input: &Path, c: &Checked, blocked: Outputs, wanted: Outputs) {
    // The codes that break what was not written (not every error of the map).
    let mut codes: Vec<&str> = c
        .diagnostics
        .iter()
        .filter(|d| {
            let p = policy(d.code);
            d.is_error() && (!p.can_allow || p.blocks.intersects(blocked))
        })
        .map(|d| d.code)
        .collect();
    codes.sort();
    codes.dedup();
    let what = if blocked == wanted {
        "nothing written".to_string()
    } else {
        format!("{} not written", blocked.names().join(", "))
    };
    let why = if codes.is_empty() {
        String::new()
    } else {
        format!(" ({})", codes.join(", "))
    };
    eprintln!("error: {}: {what}{why}", shown(input));
}

/// `MAP: n error(s), m warning(s)`, when there is any.
pub(crate) fn summary_line(input: &Path, c: &Checked) {
    let errors = c.errors();
    let warnings = c.diagnostics.len() - errors;
    if errors + warnings > 0 {
        say(format!(
            "{}: {errors} error(s), {warnings} warning(s)",
            shown(input)
        ));
    }
}

/// The success line on stderr: what was written where, and how many warnings.
pub(crate) fn success_line(label: &str, what: &str, dir: &Path, w: Written, warnings: usize) {
    let removed = if w.removed > 0 {
        format!(", {} stale removed", w.removed)
    } else {
        String::new()
    };
    let warn = if warnings > 0 {
        format!(", {}", ui::plural(warnings, "warning"))
    } else {
        String::new()
    };
    say(format!(
        "{label}: {what}, {} written to {} ({} unchanged{removed}){warn}",
        ui::plural(w.files, "file"),
        shown(dir),
        w.unchanged
    ));
}

/// One SARIF log for several maps: sources merged, file ids re-based, at most `max`
/// diagnostics per code over all maps.
pub(crate) fn print_sarif<'a>(
    all: impl IntoIterator<Item = &'a Checked>,
    max: limit::MaxDiagnostics,
) {
    let mut sources = Vec::new();
    let mut diags = Vec::new();
    for c in all {
        let base = sources.len() as u32;
        sources.extend(c.parsed.sources.iter().cloned());
        for d in &c.diagnostics {
            let mut d = d.clone();
            d.span.file.0 += base;
            for l in &mut d.labels {
                l.span.file.0 += base;
            }
            diags.push(d);
        }
    }
    let (shown, cut) = limit::select(&diags, max);
    print!("{}", json::sarif(&sources, &shown, &cut));
}

/// How to go on when ignored keys (`codes`) are meant to be ignored (a fork's extension
/// keys): the flag, or the mapc.toml setting in the file that applies to `input` (the
/// `--config` file, else the one found beside the map or above it, else one beside it).
pub(crate) fn ways_out(input: &Path, opts: &LintOpts, codes: &[&str]) -> String {
    let flags: Vec<String> = codes.iter().map(|c| format!("--allow {c}")).collect();
    let keys: Vec<String> = codes.iter().map(|c| format!("{c} = \"allow\"")).collect();
    let toml = opts
        .config
        .clone()
        .or_else(|| super::lints::discover(input))
        .unwrap_or_else(|| input.parent().unwrap_or(Path::new(".")).join("mapc.toml"));
    format!(
        "if those keys are meant to be ignored, pass `{}` on the command line, or add `{}` under `[lints]` in {}",
        flags.join(" "),
        keys.join("` and `"),
        toml.display()
    )
}

/// For commands that only read a map (`info`, `models`): loads and checks it, prints its
/// errors (warnings are `mapc check`'s business), and gives the checked map when a
/// building could be read.
pub(crate) fn load_readable(input: &Path, opts: &LintOpts) -> Result<Checked, CliError> {
    let checked = load_and_check(input, opts)?;
    let errors: Vec<&mapc_ir::Diagnostic> = checked
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .collect();
    report::emit(
        &checked.parsed.sources,
        &errors,
        &[],
        report::Style::Snippets,
    );
    if !errors.is_empty() {
        summary_line(input, &checked);
    }
    if checked.parsed.building.is_none() {
        return Err(CliError::Invalid(format!(
            "{}: the map could not be read",
            shown(input)
        )));
    }
    Ok(checked)
}
