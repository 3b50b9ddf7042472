//! `mapc render`: one picture per level (SVG, PNG or both) in an output directory.
//! Exit codes: 0 ok, 1 invalid map (with `--diagnostics` the pictures are still written,
//! since showing the problems is their point), 2 usage or I/O error.

use crate::{emit, load_and_check, output, summary_line, Format};
use clap::ValueEnum;
use mapc_backends::render::{self, RenderOptions};
use mapc_backends::OutputFile;
use std::path::PathBuf;
use std::process::ExitCode;

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
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    output_dir: PathBuf,
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
    max_diagnostics: crate::limit::MaxDiagnostics,
    #[command(flatten)]
    lints: crate::LintOpts,
}

pub(crate) fn run(args: &RenderArgs) -> ExitCode {
    let checked = match load_and_check(&args.input, &args.lints) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let opts = crate::DiagOpts {
        format: Format::Human,
        quiet: args.quiet,
        max_diagnostics: args.max_diagnostics,
        verbose: true,
        lints: args.lints.clone(),
    };
    emit(&checked, &opts, crate::report::Style::Snippets);
    summary_line(&args.input, &checked);
    // At the user's lint levels: an allowed or lowered code no longer counts.
    let has_errors = checked.diagnostics.iter().any(|d| d.is_error());
    let Some(b) = checked.parsed.building.as_ref() else {
        eprintln!("error: {}: nothing written", args.input.display());
        return ExitCode::from(1);
    };
    if has_errors && !args.diagnostics {
        eprintln!(
            "error: {}: nothing written (pass --diagnostics to draw the map with its problems)",
            args.input.display()
        );
        return ExitCode::from(1);
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
                    eprintln!(
                        "error: {} has no level `{name}` (levels: {})",
                        args.input.display(),
                        known.join(", ")
                    );
                    return ExitCode::from(2);
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
                Err(e) => {
                    eprintln!("error: {}: {e}", f.path.display());
                    return ExitCode::from(2);
                }
            }
        }
        if args.format.contains(&PictureFormat::Svg) {
            files.push(f);
        }
    }
    let label = crate::build::map_name(&args.input);
    let pictures = files.len();
    // A full render replaces the last one (stale pictures removed); `--level` adds to it.
    let written = if args.levels.is_empty() {
        output::single_write(&args.output_dir, "DIR", &files, "render", &label)
    } else {
        output::write_all(&args.output_dir, "DIR", &files)
    };
    match written {
        Ok(w) if !args.quiet => {
            let what = crate::plural(pictures, "picture");
            crate::success_line(
                &label,
                &what,
                &args.output_dir,
                w,
                checked.diagnostics.len(),
            );
        }
        Ok(_) => {}
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    }
    if has_errors {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
