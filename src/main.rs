//! `mapc`: the command line. Exit codes: 0 ok (warnings allowed), 1 invalid map,
//! 2 usage or I/O error.

mod output;
mod report;

use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "mapc",
    version,
    about = "Compiles RMF .building.yaml maps into navigation graphs (and more to come)",
    long_about = "mapc reads traffic_editor .building.yaml maps, checks them, and writes the \
                  files RMF needs. `mapc nav` is a drop-in for `building_map_generator nav`."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
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
    },
    /// Read the map and report every problem found, without writing anything.
    Check {
        /// The .building.yaml (or legacy .project.yaml) to read.
        input: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Nav { input, output_dir } => nav(&input, &output_dir),
        Command::Check { input } => check(&input),
    }
}

/// Loads and reports. `Err(code)` when the command must stop.
fn load(input: &Path) -> Result<mapc_frontend::Parsed, ExitCode> {
    let parsed = match mapc_frontend::load(input) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return Err(ExitCode::from(2));
        }
    };
    report::emit(&parsed.sources, &parsed.diagnostics);
    if parsed.has_errors() || parsed.building.is_none() {
        let n = parsed.diagnostics.iter().filter(|d| d.is_error()).count();
        eprintln!(
            "error: {} has {n} error(s); nothing written",
            input.display()
        );
        return Err(ExitCode::from(1));
    }
    Ok(parsed)
}

fn nav(input: &Path, output_dir: &Path) -> ExitCode {
    let parsed = match load(input) {
        Ok(p) => p,
        Err(code) => return code,
    };
    let Some(building) = parsed.valid_building() else {
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

fn check(input: &Path) -> ExitCode {
    match load(input) {
        Ok(_) => ExitCode::SUCCESS,
        Err(code) => code,
    }
}
