//! `mapc render`: one picture per level (SVG, PNG or both) in an output directory.
//! Exit codes: 0 ok, 1 invalid map (with `--diagnostics` the pictures are still written,
//! since showing the problems is their point), 2 usage or I/O error.

use crate::driver::{self, emit, load_and_check, output, summary_line, CliError, Outcome};
use crate::ui::{plural, report::Style, Format};
use clap::ValueEnum;
use mapc_backends::render::{self, RenderOptions};
use mapc_backends::OutputFile;
use std::path::PathBuf;

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum PictureFormat {
    /// SVG with real text (searchable, selectable).
    Svg,
    /// PNG rasterised in mapc (resvg), the same picture as the SVG.
    Png,
}

#[derive(clap::Args)]
pub(crate) struct RenderArgs {
    /// The .building.yaml (or legacy .project.yaml) to draw.
    input: PathBuf,
    /// Directory for the pictures (`<building>_<level>.svg` / `.png`); created if missing.
    #[command(flatten)]
    output: super::OutputDir,
    /// Picture formats, e.g. `--format png` or `--format svg,png`.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "svg")]
    format: Vec<PictureFormat>,
    /// Only these levels (by name; repeatable). Default: every level.
    #[arg(long = "level", value_name = "L")]
    levels: Vec<String>,
    /// Only the lanes of these graph indices (repeatable). Default: every graph.
    #[arg(long = "graph", value_name = "G")]
    graphs: Vec<i64>,
    /// Draw every diagnostic at its place (coloured by severity, with its code) and list
    /// them under the map.
    #[arg(long)]
    diagnostics: bool,
    /// No success line on stderr.
    #[arg(short, long)]
    quiet: bool,
    /// Show at most N diagnostics per code on stderr (`all`: every one); the pictures
    /// always draw every one.
    #[arg(long, value_name = "N|all", default_value = "20")]
    max_diagnostics: crate::ui::limit::MaxDiagnostics,
    #[command(flatten)]
    lints: driver::LintOpts,
}

pub(crate) fn run(args: &RenderArgs) -> Result<Outcome, CliError> {
    let output_dir = args.output.path()?;
    let checked = load_and_check(&args.input, &args.lints)?;
    let opts = driver::DiagOpts {
        format: Format::Human,
        quiet: args.quiet,
        max_diagnostics: args.max_diagnostics,
        verbose: true,
        lints: args.lints.clone(),
    };
    emit(&checked, &opts, Style::Snippets);
    summary_line(&args.input, &checked);
    // At the user's lint levels: an allowed or lowered code no longer counts.
    let has_errors = checked.diagnostics.iter().any(|d| d.is_error());
    let Some(b) = checked.parsed.building.as_ref() else {
        return Err(CliError::Invalid(format!(
            "{}: nothing written",
            args.input.display()
        )));
    };
    if has_errors && !args.diagnostics {
        return Err(CliError::Invalid(format!(
            "{}: nothing written (pass --diagnostics to draw the map with its problems)",
            args.input.display()
        )));
    }
    let mut levels = Vec::new();
    if args.levels.is_empty() {
        levels.extend(b.levels.iter().map(|(h, _)| h));
    } else {
        for name in &args.levels {
            match b.level_by_name(name) {
                Some(h) => levels.push(h),
                None => {
                    let known: Vec<&str> = b.levels.iter().map(|(_, l)| l.name.as_str()).collect();
                    return Err(CliError::Usage(format!(
                        "{} has no level `{name}` (levels: {})",
                        args.input.display(),
                        known.join(", ")
                    )));
                }
            }
        }
    }
    let opts = RenderOptions {
        graphs: (!args.graphs.is_empty()).then_some(args.graphs.as_slice()),
        diagnostics: args.diagnostics.then_some(checked.diagnostics.as_slice()),
    };
    let svgs = render::render_svgs(b, &levels, &opts);
    let mut files = Vec::new();
    for f in svgs {
        if args.format.contains(&PictureFormat::Png) {
            let text = String::from_utf8_lossy(&f.contents);
            match render::svg_to_png(&text) {
                Ok(png) => files.push(OutputFile {
                    path: f.path.with_extension("png"),
                    contents: png,
                }),
                Err(e) => return Err(CliError::Usage(format!("{}: {e}", f.path.display()))),
            }
        }
        if args.format.contains(&PictureFormat::Svg) {
            files.push(f);
        }
    }
    let label = driver::map_name(&args.input);
    let pictures = files.len();
    // A full render replaces the last one (stale pictures removed); `--level` adds to it.
    let written = if args.levels.is_empty() {
        output::single_write(output_dir, "DIR", &files, "render", &label)
    } else {
        output::write_all(output_dir, "DIR", &files)
    };
    let w = written?;
    if !args.quiet {
        let what = plural(pictures, "picture");
        driver::success_line(&label, &what, output_dir, w, checked.diagnostics.len());
    }
    if has_errors {
        // The pictures show the problems (`--diagnostics`); the map is still invalid.
        Err(CliError::InvalidReported)
    } else {
        Ok(Outcome::Done)
    }
}
