//! `mapc meshes INPUT OUTPUT_MODEL_DIR`: each level's meshes as Gazebo level models use
//! them (the reference layout).

use crate::driver::{self, CliError, DiagOpts, Outcome, Product, Spec};
use crate::ui::report::Style;
use mapc_ir::lints::Outputs;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub(crate) struct MeshesArgs {
    /// The .building.yaml (or legacy .project.yaml) to read.
    input: PathBuf,
    #[command(flatten)]
    output: super::OutputModelDir,
    /// A directory to search for `<texture>.png` (repeatable; searched in order, before
    /// MAPC_TEXTURE_PATH and the map's directory).
    #[arg(long = "texture-path", value_name = "DIR")]
    texture_path: Vec<PathBuf>,
    #[command(flatten)]
    diag: DiagOpts,
}

pub(crate) fn run(args: &MeshesArgs) -> Result<Outcome, CliError> {
    let spec = Spec {
        name: "meshes",
        role: "OUTPUT_MODEL_DIR",
        kind: "level mesh",
        none: Some("the map has no floors or walls"),
        outputs: Outputs::MESHES,
        style: Style::Snippets,
    };
    let out = args.output.path()?;
    driver::compile_into(&args.input, out, &args.diag, &spec, |r| {
        let meshes = driver::all_level_meshes(r);
        let names = driver::mesh_texture_names(&meshes);
        let (textures, diagnostics) = driver::textures_for(
            r,
            names.iter().map(String::as_str),
            &args.texture_path,
            &args.input,
        );
        Product {
            count: driver::mesh_count(&meshes),
            files: driver::mesh_files(r, &meshes, &textures),
            diagnostics,
        }
    })
}
