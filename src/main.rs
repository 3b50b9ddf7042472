//! `mapc`: the command line. This file is clap's definition of the commands and the one
//! mapping from a command's result to the exit code (`driver::exit_code`: 0 ok, 1 invalid
//! map or scenario, 2 usage or I/O error). The layers below it, each importing only those
//! further down: `commands` (one module per subcommand), `driver` (load, check, gate,
//! produce, write), `ui` (what users read), `codes` (every diagnostic code).

mod codes;
mod commands;
mod driver;
mod ui;

use clap::{Parser, Subcommand};
use commands::{
    build, check, convert, crowdsim, diff, gltf, info, lsp, meshes, models, nav, render, sim,
    sweep, world,
};
use driver::{signals, CliError};
use std::process::ExitCode;

// Faster than glibc's malloc for the runtime's many small vectors (ARCHITECTURE.md).
#[global_allocator]
static ALLOC: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[derive(Parser)]
#[command(
    name = "mapc",
    version,
    about = "Compiles RMF .building.yaml maps into navigation graphs, simulation worlds and glTF scenes",
    long_about = "mapc reads traffic_editor .building.yaml maps, checks them, and writes the \
                  files RMF needs. `mapc nav` and `mapc gazebo` are drop-ins for \
                  `building_map_generator nav` and `gazebo`.\n\n\
                  Exit codes: 0 ok (warnings allowed), 1 invalid map or scenario, 2 usage or I/O error."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Write the navigation graph of each fleet: OUTPUT_DIR/<graph_idx>.yaml
    /// (same arguments as `building_map_generator nav`).
    Nav(nav::NavArgs),
    /// Write the whole building as one binary glTF scene, OUTPUT_DIR/<building>.glb: a node
    /// per level at its elevation with floors, ceilings, walls, door panels and lift cabins,
    /// textures embedded.
    Gltf(gltf::GltfArgs),
    /// Write each level's meshes as Gazebo level models use them (the reference layout):
    /// OUTPUT_MODEL_DIR/<building>_<level>/meshes/ with floor_<n>, ceiling_<n> and wall_<k>
    /// OBJ + MTL files, the OGRE model.material script and the textures they name.
    Meshes(meshes::MeshesArgs),
    /// Build many maps to several targets at once (nav, gltf, meshes, classic, ignition,
    /// gz): OUTDIR/<map>/nav_graphs/<graph_idx>.yaml, OUTDIR/<map>/<building>.glb,
    /// OUTDIR/<map>/models/<building>_<level>/, OUTDIR/<map>/<map>{_classic,_ignition,}.world.
    /// Maps are built in parallel; unchanged files are not rewritten, stale ones removed;
    /// `--depfile` tells Make or Ninja what was read.
    Build(build::BuildArgs),
    /// Write a gz-sim (Harmonic onwards) world and its level models, like today's
    /// `building_map_generator gazebo`: OUTPUT_WORLD and
    /// OUTPUT_MODEL_DIR/<building>_<level>/{model.sdf,model.config,meshes/}.
    #[command(visible_alias = "gz")]
    Gazebo(world::WorldArgs),
    /// Write an Ignition Gazebo (Fortress era) world and its level models, like
    /// `building_map_generator ignition` before 2024-05.
    Ignition(world::WorldArgs),
    /// Write a Gazebo classic world and its level models, like `building_map_generator
    /// gazebo` before 2024-05.
    Classic(world::WorldArgs),
    /// Write the crowd simulator's Menge files into CONFIG_DIR and make WORLD hold the
    /// crowd_simulation plugin (a drop-in for `building_crowdsim MAP CONFIG_DIR WORLD`).
    Crowdsim(crowdsim::CrowdsimArgs),
    /// List the models a map needs (Fuel names, the crowd's actors) where
    /// `building_map_model_downloader` would download them; mapc downloads nothing and names
    /// those missing from the export directory (`-e DIR`).
    Models(models::ModelsArgs),
    /// Run a scenario (robots, tasks, doors, lifts) on a map with the headless RMF runtime and
    /// report what happened: task times, throughput, door and lift waits, near misses.
    /// Scenario format, trace and report: docs/sim.md.
    Sim(sim::SimArgs),
    /// Run a capacity study: a base scenario varied along axes (fleet sizes, task rates,
    /// seeds...), every run on all cores, a Slurm cluster or Kubernetes; writes
    /// OUT/results.csv, OUT/results.json and OUT/capacity.svg. Format: docs/sweep.md.
    Sweep(sweep::SweepArgs),
    /// List what a map holds for scenario authors: levels, graphs, named waypoints by role,
    /// doors, lifts, dispensers and ingestors.
    Info(info::InfoArgs),
    /// Draw each level as a picture: OUTPUT/<building>_<level>.svg (or .png) with floors,
    /// walls, doors, lifts, the lanes of each graph, waypoints and their roles, models, a
    /// legend and a scale bar; `--diagnostics` draws the problems at their places.
    Render(render::RenderArgs),
    /// Convert a map between traffic_editor's .building.yaml and rmf_site's .site.json
    /// (formats from the file names); what the target cannot say is a warning (docs/sites.md).
    Convert(convert::ConvertArgs),
    /// Serve maps to editors: a language server on stdin/stdout (diagnostics as you type,
    /// hover, go to definition, references, symbols, fixes). Set-up: docs/editors.md.
    Lsp(lsp::LspArgs),
    /// What changed by meaning between two versions of a map: levels, waypoints, lanes,
    /// doors, lifts, walls, floors, connectivity, diagnostics. Exit 0 when nothing
    /// changed, 1 when something did, 2 on errors (like diff).
    Diff(diff::DiffArgs),
    /// Check maps and report every problem found, without writing anything.
    Check(check::CheckArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // `mapc sim` stops cooperatively on the first signal (it writes what ran); every other
    // command removes its temporaries and exits.
    signals::install(usize::from(matches!(cli.command, Command::Sim(_))));
    let result = match &cli.command {
        Command::Nav(args) => nav::run(args),
        Command::Gltf(args) => gltf::run(args),
        Command::Meshes(args) => meshes::run(args),
        Command::Build(args) => build::run(args),
        Command::Gazebo(args) => world::run(mapc_backends::sdf::Flavour::Gz, args),
        Command::Ignition(args) => world::run(mapc_backends::sdf::Flavour::Ignition, args),
        Command::Classic(args) => world::run(mapc_backends::sdf::Flavour::Classic, args),
        Command::Crowdsim(args) => crowdsim::run(args),
        Command::Models(args) => models::run(args),
        Command::Sim(args) => sim::run(args),
        Command::Sweep(args) => sweep::run(args),
        Command::Info(args) => info::run(args),
        Command::Render(args) => render::run(args),
        Command::Lsp(args) => lsp::run(args),
        Command::Diff(args) => diff::run(args),
        Command::Check(args) => check::run(args),
        Command::Convert(args) => convert::run(args),
    };
    if let Some(message) = result.as_ref().err().and_then(CliError::message) {
        ui::error(message);
    }
    ExitCode::from(driver::exit_code(&result))
}

#[cfg(test)]
mod cli_tests {
    use super::*;

    fn argv(s: &str) -> Vec<std::ffi::OsString> {
        std::iter::once("mapc")
            .chain(s.split_whitespace())
            .map(Into::into)
            .collect()
    }

    /// One argument convention: an output positional (the drop-ins' form) or `-o`, never
    /// both and never neither.
    #[test]
    fn outputs_positional_or_dash_o() {
        for line in [
            "nav m.building.yaml out",
            "nav m.building.yaml -o out",
            "nav m.building.yaml --output out",
            "gltf m.building.yaml -o out --per-level",
            "meshes m.building.yaml -o out",
            "render m.building.yaml out",
            "render m.building.yaml -o out",
            "convert m.building.yaml -o m.site.json",
            "convert m.building.yaml m.site.json",
        ] {
            assert!(Cli::try_parse_from(argv(line)).is_ok(), "{line}");
        }
        for line in [
            "nav m.building.yaml",
            "nav m.building.yaml out -o other",
            "render m.building.yaml",
        ] {
            assert!(Cli::try_parse_from(argv(line)).is_err(), "{line}");
        }
    }
}
