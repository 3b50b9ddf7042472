//! One module per subcommand, each the same shape: an `Args` struct (clap) and
//! `run(&Args) -> Result<Outcome, CliError>` that turns the arguments into calls of the
//! driver and the library crates. A new subcommand is a new file here, one line below and
//! one variant in main.rs's `Command`.
//!
//! Invariants: a command imports the driver, `ui` and the library crates, never another
//! command (what two commands share lives in the driver) and never `main.rs`.

pub(crate) mod build;
pub(crate) mod check;
pub(crate) mod convert;
pub(crate) mod crowdsim;
pub(crate) mod diff;
pub(crate) mod gltf;
pub(crate) mod info;
pub(crate) mod lsp;
pub(crate) mod meshes;
pub(crate) mod models;
pub(crate) mod nav;
pub(crate) mod render;
pub(crate) mod sim;
pub(crate) mod sweep;
pub(crate) mod world;

use crate::driver::CliError;
use std::path::{Path, PathBuf};

/// The one argument convention for outputs: positional after the input, as the reference
/// generator's drop-ins take it (`mapc nav MAP DIR`), or `-o`/`--output` as every other
/// tool does (`mapc nav MAP -o DIR`).
#[derive(clap::Args, Debug)]
pub(crate) struct OutputDir {
    /// Directory for the output files; created if missing.
    #[arg(
        value_name = "OUTPUT_DIR",
        required_unless_present = "output",
        conflicts_with = "output"
    )]
    output_dir: Option<PathBuf>,
    /// The same as OUTPUT_DIR.
    #[arg(short = 'o', long = "output", value_name = "OUTPUT_DIR")]
    output: Option<PathBuf>,
}

impl OutputDir {
    pub(crate) fn path(&self) -> Result<&Path, CliError> {
        given(&self.output_dir, &self.output, "OUTPUT_DIR")
    }
}

/// [`OutputDir`] for a model directory (`mapc meshes`).
#[derive(clap::Args, Debug)]
pub(crate) struct OutputModelDir {
    /// Model directory; created if missing.
    #[arg(
        value_name = "OUTPUT_MODEL_DIR",
        required_unless_present = "output",
        conflicts_with = "output"
    )]
    output_model_dir: Option<PathBuf>,
    /// The same as OUTPUT_MODEL_DIR.
    #[arg(short = 'o', long = "output", value_name = "OUTPUT_MODEL_DIR")]
    output: Option<PathBuf>,
}

impl OutputModelDir {
    pub(crate) fn path(&self) -> Result<&Path, CliError> {
        given(&self.output_model_dir, &self.output, "OUTPUT_MODEL_DIR")
    }
}

/// [`OutputDir`] for a single output file (`mapc convert`).
#[derive(clap::Args, Debug)]
pub(crate) struct OutputFile {
    /// The file to write.
    #[arg(
        value_name = "OUTPUT",
        required_unless_present = "output",
        conflicts_with = "output"
    )]
    output_file: Option<PathBuf>,
    /// The same as OUTPUT.
    #[arg(short = 'o', long = "output", value_name = "OUTPUT")]
    output: Option<PathBuf>,
}

impl OutputFile {
    pub(crate) fn path(&self) -> Result<&Path, CliError> {
        given(&self.output_file, &self.output, "OUTPUT")
    }
}

/// The output given either way (clap makes sure it is exactly one).
fn given<'a>(
    positional: &'a Option<PathBuf>,
    flag: &'a Option<PathBuf>,
    role: &str,
) -> Result<&'a Path, CliError> {
    positional
        .as_deref()
        .or(flag.as_deref())
        .ok_or_else(|| CliError::Usage(format!("{role} is required")))
}
