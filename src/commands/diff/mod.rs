//! `mapc diff OLD NEW`: what changed by meaning between two versions of a map.
//! `compute.rs` matches the two buildings and lists the changes; `render.rs` prints them.
//! Also a git external diff driver (seven arguments: path, old file, hex, mode, new file,
//! hex, mode) and difftool.

mod compute;
mod render;

use crate::driver::{load_and_check, Checked, CliError, LintOpts, Outcome};
use clap::ValueEnum;
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
enum DiffFormat {
    /// Grouped lines for a terminal.
    Human,
    /// One JSON document: `{old, new, changed, changes: [{section, level, change, subject, detail}]}`.
    Json,
    /// Markdown tables, for a pull-request comment.
    Markdown,
}

#[derive(clap::Args)]
pub(crate) struct DiffArgs {
    /// The old map (.building.yaml or legacy .project.yaml).
    old: PathBuf,
    /// The new map.
    new: PathBuf,
    /// As a git diff driver git passes seven arguments: PATH OLD-FILE OLD-HEX OLD-MODE
    /// NEW-FILE NEW-HEX NEW-MODE. They are recognised here (docs/editors.md shows the
    /// .gitattributes line); the exit code is then 0, as git expects of drivers.
    #[arg(hide = true, num_args = 0..=5)]
    git: Vec<String>,
    #[arg(long, value_enum, default_value = "human")]
    format: DiffFormat,
    #[command(flatten)]
    lints: LintOpts,
}

/// A map read for comparison, or why it could not be.
fn read(path: &Path, lints: &LintOpts) -> Result<Checked, String> {
    let c = load_and_check(path, lints)?;
    if c.parsed.building.is_none() {
        let mut codes: Vec<&str> = c
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| d.code)
            .collect();
        codes.dedup();
        return Err(format!(
            "{}: the map could not be read ({}); `mapc check {}` shows why",
            crate::ui::shown(path),
            codes.join(", "),
            crate::ui::shown(path)
        ));
    }
    Ok(c)
}

pub(crate) fn run(args: &DiffArgs) -> Result<Outcome, CliError> {
    // git's external diff convention: PATH OLD OLD-HEX OLD-MODE NEW NEW-HEX NEW-MODE.
    let (old, new, label_old, label_new, as_git) = if args.git.len() == 5 {
        let path = args.old.display().to_string();
        let (o, n) = (args.new.clone(), PathBuf::from(&args.git[2]));
        (o, n, format!("a/{path}"), format!("b/{path}"), true)
    } else if args.git.is_empty() {
        let (o, n) = (args.old.clone(), args.new.clone());
        let (lo, ln) = (crate::ui::shown(&o), crate::ui::shown(&n));
        (o, n, lo, ln, false)
    } else {
        return Err(CliError::Usage(
            "mapc diff takes OLD NEW (or the seven arguments of a git diff driver)".into(),
        ));
    };
    // A file added or deleted in git is /dev/null on one side.
    let null = |p: &Path| p == Path::new("/dev/null");
    if null(&old) || null(&new) {
        let what = if null(&old) { "new map" } else { "map deleted" };
        println!("{label_new}: {what}");
        return Ok(if as_git {
            Outcome::Done
        } else {
            Outcome::Differs
        });
    }
    let (a, b) = match (read(&old, &args.lints), read(&new, &args.lints)) {
        (Ok(a), Ok(b)) => (a, b),
        (a, b) => {
            for e in [a.err(), b.err()].into_iter().flatten() {
                crate::ui::error(e);
            }
            return Err(CliError::UsageReported);
        }
    };
    let (Some(ba), Some(bb)) = (&a.parsed.building, &b.parsed.building) else {
        return Err(CliError::UsageReported); // `read` refused maps without a building.
    };
    let changes = compute::diff(
        &compute::Side {
            building: ba,
            diagnostics: &a.diagnostics,
        },
        &compute::Side {
            building: bb,
            diagnostics: &b.diagnostics,
        },
    );
    let text = match args.format {
        DiffFormat::Human => render::human(&label_old, &label_new, &changes),
        DiffFormat::Json => render::json(&label_old, &label_new, &changes),
        DiffFormat::Markdown => render::markdown(&label_old, &label_new, &changes),
    };
    print!("{text}");
    // As diff(1): 1 when the inputs differ (git's driver wants 0 for a shown diff).
    if changes.is_empty() || as_git {
        Ok(Outcome::Done)
    } else {
        Ok(Outcome::Differs)
    }
}
