//! `mapc nav INPUT OUTPUT_DIR`: the navigation graph of each fleet, a drop-in for
//! `building_map_generator nav`.

use crate::driver::{self, CliError, DiagOpts, Outcome, Product, Spec};
use crate::ui::report::Style;
use mapc_ir::lints::Outputs;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub(crate) struct NavArgs {
    /// The .building.yaml (or legacy .project.yaml) to read.
    input: PathBuf,
    #[command(flatten)]
    output: super::OutputDir,
    #[command(flatten)]
    diag: DiagOpts,
}

pub(crate) fn run(args: &NavArgs) -> Result<Outcome, CliError> {
    let spec = Spec {
        name: "nav",
        role: "OUTPUT_DIR",
        kind: "nav graph",
        none: Some("the map has no lanes"),
        outputs: Outputs::NAV,
        // A drop-in for `building_map_generator nav`: one line per diagnostic in build logs.
        style: Style::OneLine,
    };
    let out = args.output.path()?;
    driver::compile_into(&args.input, out, &args.diag, &spec, |r| {
        let files = driver::nav_files(r);
        Product {
            count: files.len(),
            files,
            diagnostics: Vec::new(),
        }
    })
}
