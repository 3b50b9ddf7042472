//! Catching likely argument mistakes before any work: a directory where a map must be, a
//! scenario passed as a map, a world and a model directory swapped. Each error names what
//! is wrong and what was probably meant (exit 2, as any usage error).

use crate::ui::shown;
use std::path::Path;

fn has_ext(p: &Path, exts: &[&str]) -> bool {
    let name = p.file_name().map(|n| n.to_string_lossy().to_lowercase());
    name.is_some_and(|n| exts.iter().any(|e| n.ends_with(e)))
}

/// A map input: a file, and not a scenario or a world.
pub fn map_input(p: &Path) -> Result<(), String> {
    if p.is_dir() {
        return Err(format!(
            "`{}` is a directory; INPUT must be a .building.yaml file",
            shown(p)
        ));
    }
    if has_ext(p, &[".scenario.yaml", ".scenario.yml"]) {
        return Err(format!(
            "`{}` is a scenario, not a building map; run it with `mapc sim {}`",
            shown(p),
            shown(p)
        ));
    }
    if has_ext(p, &[".world", ".sdf"]) {
        return Err(format!(
            "`{}` is a world file, which mapc writes; INPUT must be a .building.yaml file \
             (were the arguments swapped?)",
            shown(p)
        ));
    }
    Ok(())
}

/// An output directory argument: not an existing file, and not a map (swapped arguments).
pub fn output_dir(p: &Path, role: &str) -> Result<(), String> {
    if p.exists() && !p.is_dir() {
        let hint = if has_ext(p, &[".yaml", ".yml"]) {
            " (were INPUT and the output swapped?)"
        } else {
            ""
        };
        return Err(format!(
            "`{}` is a file; {role} must be a directory{hint}",
            shown(p)
        ));
    }
    Ok(())
}

/// `mapc gazebo MAP OUTPUT_WORLD OUTPUT_MODEL_DIR`: the world is a file, the models a
/// directory. Writing a world named `models` and a directory `out.world/` is never meant.
pub fn world_outputs(world: &Path, models: &Path) -> Result<(), String> {
    let usage = "usage: mapc gazebo INPUT OUTPUT_WORLD OUTPUT_MODEL_DIR";
    let world_like = |p: &Path| has_ext(p, &[".world", ".sdf"]);
    if world.is_dir() && !world_like(world) {
        return Err(format!(
            "`{}` is a directory; OUTPUT_WORLD must be the world file to write (.world or \
             .sdf): were OUTPUT_WORLD and OUTPUT_MODEL_DIR swapped? {usage}",
            shown(world)
        ));
    }
    if world_like(models) && !world_like(world) {
        return Err(format!(
            "OUTPUT_MODEL_DIR `{}` looks like a world file and OUTPUT_WORLD `{}` does not: \
             were they swapped? {usage}",
            shown(models),
            shown(world)
        ));
    }
    if world.is_dir() {
        return Err(format!(
            "`{}` is a directory; OUTPUT_WORLD must be a file",
            shown(world)
        ));
    }
    output_dir(models, "OUTPUT_MODEL_DIR")
}
