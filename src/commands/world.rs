//! `mapc gazebo` (gz-sim, alias `gz`), `mapc ignition` and `mapc classic`: a simulation
//! world and its level models, with `building_map_generator gazebo`'s arguments.

use crate::driver::{self, output, sanity, CliError, DiagOpts, Outcome, Product, Spec};
use crate::ui::{plural, report::Style, say, shown};
use mapc_backends::sdf::world::{WorldFiles, WorldOptions};
use mapc_backends::sdf::world_files_untextured;
use mapc_backends::sdf::Flavour;
use mapc_backends::OutputFile;
use mapc_ir::lints::Outputs;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub(crate) struct WorldArgs {
    /// The .building.yaml (or legacy .project.yaml) to read.
    input: PathBuf,
    /// The world file to write (its directory is created if missing). With crowd_sim
    /// enabled, the Menge files go to config_resource/ next to it: point
    /// MENGE_RESOURCE_PATH there.
    output_world: PathBuf,
    /// Directory for the level models, <building>_<level>/{model.sdf,model.config,meshes/};
    /// created if missing. Point GZ_SIM_RESOURCE_PATH (or GAZEBO_MODEL_PATH) at it.
    output_model_dir: PathBuf,
    /// Use this SDF as the world skeleton instead of mapc's default for the simulator: root
    /// <sdf> with a <world> child; unless --SKIP_CAMERA_POSE, its <gui> must hold a camera
    /// pose (a MinimalScene or GzScene3D plugin's <camera_pose>, or <camera><pose>).
    #[arg(long = "TEMPLATE_WORLD_FILE", value_name = "PATH")]
    template_world_file: Option<PathBuf>,
    /// Keep the template's camera pose instead of placing the camera over the first floor.
    #[arg(long = "SKIP_CAMERA_POSE")]
    skip_camera_pose: bool,
    /// Accepted and ignored: building_map_generator's free-form options (before 2024-05
    /// only the subcommand name was ever passed through them).
    #[arg(short = 'o', long = "options", value_name = "OPT", num_args = 0..)]
    _options: Vec<String>,
    /// Accepted and ignored: building_map_generator's old no-download flag (model download
    /// was removed in 2020; mapc never downloads models).
    #[arg(short = 'n', long = "no_download")]
    _no_download: bool,
    /// Accepted and ignored: building_map_generator's old model path for downloads.
    #[arg(short = 'm', long = "model_path", value_name = "PATH")]
    _model_path: Option<PathBuf>,
    /// Accepted and ignored: building_map_generator's old download cache.
    #[arg(short = 'c', long = "cache", value_name = "PATH")]
    _cache: Option<PathBuf>,
    /// A directory to search for `<texture>.png` (repeatable; searched in order, before
    /// MAPC_TEXTURE_PATH and the map's directory).
    #[arg(long = "texture-path", value_name = "DIR")]
    texture_path: Vec<PathBuf>,
    #[command(flatten)]
    diag: DiagOpts,
}

pub(crate) fn run(flavour: Flavour, args: &WorldArgs) -> Result<Outcome, CliError> {
    sanity::world_outputs(&args.output_world, &args.output_model_dir)?;
    let template = match &args.template_world_file {
        None => None,
        Some(p) => Some(driver::read_template(p, args.skip_camera_pose)?),
    };
    let Some(world_name) = args.output_world.file_name() else {
        return Err(CliError::Usage(format!(
            "OUTPUT_WORLD `{}` is not a file path",
            args.output_world.display()
        )));
    };
    let world_dir = args
        .output_world
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));

    let cmd = match flavour {
        Flavour::Gz => "gz",
        Flavour::Ignition => "ignition",
        Flavour::Classic => "classic",
    };
    let spec = Spec {
        name: cmd,
        role: "OUTPUT_MODEL_DIR",
        // A world without any level mesh shows nothing but its models: a failure unless
        // the map truly has no floors or walls (nothing was ignored on the way).
        kind: "level mesh",
        none: Some("the map has no floors or walls"),
        // A world includes its level models, so what breaks meshes breaks it too.
        outputs: Outputs::WORLDS.union(Outputs::MESHES),
        // A drop-in for `building_map_generator`: one line per diagnostic in build logs.
        style: Style::OneLine,
    };
    let opts = WorldOptions {
        template,
        skip_camera_pose: args.skip_camera_pose,
    };
    let c = driver::compile(&args.input, &args.diag, &spec, |r| {
        produce(r.require(spec.outputs), flavour, &opts, args)
    })?;
    let (out, links) = c.files;
    // Models first: the world refers to them. The crowd simulator's Menge files
    // (config_resource/, next to the world) go with the world, before it.
    let mut world = out.crowd;
    world.push(OutputFile {
        path: PathBuf::from(world_name),
        contents: out.world.into_bytes(),
    });
    let result = output::single_writes_linked(
        &[
            (
                &args.output_model_dir,
                "OUTPUT_MODEL_DIR",
                &out.models,
                &links,
            ),
            (world_dir, "the world's directory", &world, &[]),
        ],
        cmd,
        &c.label,
    )
    .map(|w| (w[0], w[1]));
    let diagnostics = c.checked.diagnostics.len();
    let (label, meshes) = (c.label, c.count);
    let (m, w) = result?;
    if !args.diag.quiet {
        let total = output::Written {
            files: m.files + w.files,
            unchanged: m.unchanged + w.unchanged,
            removed: m.removed + w.removed,
        };
        let what = format!("1 world, {}", plural(meshes, "level mesh"));
        driver::success_line(&label, &what, &args.output_model_dir, total, diagnostics);
        say(format!("  world: {}", shown(&args.output_world)));
    }
    Ok(Outcome::Done)
}

/// The world, its level models and crowd files; the textures found on disk as links to
/// them (nothing copied, in memory or on disk), placeholders as files.
fn produce(
    b: &mapc_ir::Building,
    flavour: Flavour,
    opts: &WorldOptions,
    args: &WorldArgs,
) -> Product<(WorldFiles, Vec<output::LinkedFile>)> {
    let (meshes, mut files) = world_files_untextured(b, flavour, opts);
    let names = mapc_backends::texture_names(meshes.iter().flat_map(|(_, m)| m.all()));
    // Found images are linked from where they are (below), so only their heads are
    // read, to tell a PNG from anything else; placeholders are whole.
    let search = driver::texture::SearchPath::from_env(&args.texture_path, &args.input);
    // Where each image was found, so that it is linked from there without a second
    // look along the search path.
    let mut found_at = std::collections::HashMap::new();
    let (textures, diagnostics) =
        mapc_backends::resolve_textures(b, names.iter().map(String::as_str), &mut |f| {
            let (path, head) = search.find_head(f)?;
            found_at.insert(f.to_string(), path);
            Some(head)
        });
    let images = meshes
        .iter()
        .flat_map(|(h, m)| mapc_backends::level_texture_paths(b, *h, m));
    let mut links = Vec::new();
    for (path, name) in images {
        let Some(image) = textures.get(name) else {
            continue;
        };
        let source = (!image.placeholder)
            .then(|| mapc_backends::texture_file_name(name))
            .flatten()
            .and_then(|f| found_at.get(&f).cloned());
        match source {
            Some(source) => links.push(output::LinkedFile { path, source }),
            None => files.models.push(OutputFile {
                path,
                contents: image.png.clone(),
            }),
        }
    }
    let count = files
        .models
        .iter()
        .filter(|f| f.path.extension().is_some_and(|e| e == "obj"))
        .count();
    Product {
        files: (files, links),
        diagnostics,
        count,
    }
}
