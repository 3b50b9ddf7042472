//! `mapc`: the command line. Exit codes: 0 ok (warnings allowed), 1 invalid map,
//! 2 usage or I/O error.

mod output;
mod report;
mod report_json;

use clap::{Parser, Subcommand, ValueEnum};
use mapc_ir::Diagnostic;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "mapc",
    version,
    about = "Compiles RMF .building.yaml maps into navigation graphs (and more to come)",
    long_about = "mapc reads traffic_editor .building.yaml maps, checks them, and writes the \
                  files RMF needs. `mapc nav` is a drop-in for `building_map_generator nav`.\n\n\
                  Exit codes: 0 ok (warnings allowed), 1 invalid map, 2 usage or I/O error."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
enum Format {
    /// Source snippets with underlines (colour on a terminal).
    Human,
    /// JSON Lines on stdout: one object per diagnostic (schema in docs/diagnostics.md).
    Json,
    /// A SARIF 2.1.0 log on stdout, for code-scanning tools.
    Sarif,
}

#[derive(clap::Args)]
struct DiagOpts {
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value = "human")]
    format: Format,
    /// Treat warnings as errors (exit 1 and write nothing when there are any).
    #[arg(long)]
    deny_warnings: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Write the navigation graph of each fleet: OUTPUT_DIR/<graph_idx>.yaml
    /// (same arguments as `building_map_generator nav`).
    Nav {
        /// The .building.yaml (or legacy .project.yaml) to read.
        input: PathBuf,
        /// Directory for the graph files; created if missing.
        output_dir: PathBuf,
        #[command(flatten)]
        diag: DiagOpts,
    },
    /// Check maps and report every problem found, without writing anything.
    Check {
        /// The .building.yaml (or legacy .project.yaml) files to read.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        #[command(flatten)]
        diag: DiagOpts,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Nav {
            input,
            output_dir,
            diag,
        } => nav(&input, &output_dir, &diag),
        Command::Check { inputs, diag } => check(&inputs, &diag),
    }
}

/// Stable name of a diagnostic code, from the frontend's table or the rule registry.
pub(crate) fn code_name(code: &str) -> &'static str {
    mapc_frontend::CODES
        .iter()
        .find(|c| c.code == code)
        .map(|c| c.name)
        .or_else(|| mapc_ir::rule(code).map(|r| r.name))
        .unwrap_or("")
}

/// A map read and checked: frontend diagnostics plus validation passes.
struct Checked {
    parsed: mapc_frontend::Parsed,
    diagnostics: Vec<Diagnostic>,
}

impl Checked {
    fn failed(&self, deny_warnings: bool) -> bool {
        self.parsed.building.is_none()
            || self
                .diagnostics
                .iter()
                .any(|d| d.is_error() || deny_warnings)
    }
}

/// Reads a map and runs every validation pass. `Err` is an I/O problem (exit 2).
fn load_and_check(input: &Path) -> Result<Checked, String> {
    let parsed = mapc_frontend::load(input).map_err(|e| e.to_string())?;
    let mut diagnostics = parsed.diagnostics.clone();
    // Passes run even after frontend errors so one run reports everything it can.
    if let Some(b) = &parsed.building {
        diagnostics.extend(mapc_ir::validate(b));
    }
    Ok(Checked {
        parsed,
        diagnostics,
    })
}

fn emit(c: &Checked, format: Format) {
    match format {
        Format::Human => report::emit(&c.parsed.sources, &c.diagnostics),
        Format::Json => print!(
            "{}",
            report_json::json_lines(&c.parsed.sources, &c.diagnostics)
        ),
        Format::Sarif => print!("{}", report_json::sarif(&c.parsed.sources, &c.diagnostics)),
    }
}

fn summary_line(input: &Path, c: &Checked) {
    let errors = c.diagnostics.iter().filter(|d| d.is_error()).count();
    let warnings = c.diagnostics.len() - errors;
    if errors + warnings > 0 {
        eprintln!(
            "{}: {errors} error(s), {warnings} warning(s)",
            input.display()
        );
    }
}

fn nav(input: &Path, output_dir: &Path, opts: &DiagOpts) -> ExitCode {
    let checked = match load_and_check(input) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    emit(&checked, opts.format);
    if opts.format == Format::Human {
        summary_line(input, &checked);
    }
    if checked.failed(opts.deny_warnings) {
        eprintln!("error: {}: nothing written", input.display());
        return ExitCode::from(1);
    }
    let Some(building) = &checked.parsed.building else {
        return ExitCode::from(1);
    };
    let files = mapc_backends::nav_graphs(building);
    match output::write_all(output_dir, &files) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn check(inputs: &[PathBuf], opts: &DiagOpts) -> ExitCode {
    let mut code = 0u8;
    let mut all: Vec<Checked> = Vec::new();
    for input in inputs {
        match load_and_check(input) {
            Ok(c) => {
                if c.failed(opts.deny_warnings) {
                    code = code.max(1);
                }
                if opts.format != Format::Sarif {
                    emit(&c, opts.format);
                }
                if opts.format == Format::Human {
                    summary_line(input, &c);
                }
                all.push(c);
            }
            Err(e) => {
                eprintln!("error: {e}");
                code = 2;
            }
        }
    }
    if opts.format == Format::Sarif {
        // One log for all inputs: merge sources and re-base file ids.
        let mut sources = Vec::new();
        let mut diags = Vec::new();
        for c in all {
            let base = sources.len() as u32;
            sources.extend(c.parsed.sources);
            for mut d in c.diagnostics {
                d.span.file.0 += base;
                for l in &mut d.labels {
                    l.span.file.0 += base;
                }
                diags.push(d);
            }
        }
        print!("{}", report_json::sarif(&sources, &diags));
    }
    ExitCode::from(code)
}
