//! `mapc gltf INPUT OUTPUT_DIR`: the whole building as one binary glTF scene.

use crate::driver::{self, CliError, DiagOpts, Outcome, Product, Spec};
use crate::ui::report::Style;
use mapc_ir::lints::Outputs;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub(crate) struct GltfArgs {
    /// The .building.yaml (or legacy .project.yaml) to read.
    input: PathBuf,
    #[command(flatten)]
    output: super::OutputDir,
    /// A directory to search for `<texture>.png` (repeatable; searched in order, before
    /// MAPC_TEXTURE_PATH and the map's directory).
    #[arg(long = "texture-path", value_name = "DIR")]
    texture_path: Vec<PathBuf>,
    /// Also write each level's meshes as OUTPUT_DIR/<building>_<level>.glb (the gz-sim
    /// level model meshes, without doors and lifts).
    #[arg(long)]
    per_level: bool,
    #[command(flatten)]
    diag: DiagOpts,
}

pub(crate) fn run(args: &GltfArgs) -> Result<Outcome, CliError> {
    let spec = Spec {
        name: "gltf",
        role: "OUTPUT_DIR",
        kind: "level mesh",
        none: Some("the map has no floors or walls"),
        outputs: Outputs::GLTF,
        style: Style::Snippets,
    };
    let out = args.output.path()?;
    driver::compile_into(&args.input, out, &args.diag, &spec, |r| {
        let meshes = driver::all_level_meshes(r);
        let names = driver::gltf_texture_names(&meshes);
        let (textures, diagnostics) = driver::textures_for(
            r,
            names.iter().map(String::as_str),
            &args.texture_path,
            &args.input,
        );
        Product {
            count: driver::mesh_count(&meshes),
            files: driver::gltf_files(r, &meshes, &textures, args.per_level),
            diagnostics,
        }
    })
}
