//! The file producers several commands share, so that `mapc build` and the single-target
//! commands write the same bytes. Each takes a [`Ready`] building: the gate's proof that
//! no error breaks the output it makes.

use super::check::Ready;
use super::texture;
use mapc_backends::sdf::world::parse_template;
use mapc_backends::{LevelMeshes, OutputFile, Textures};
use mapc_ir::lints::Outputs;
use mapc_ir::{Diagnostic, Handle, Level};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Level meshes, per level in document order.
pub(crate) type Meshes = Vec<(Handle<Level>, LevelMeshes)>;

/// The navigation graphs: `<graph_idx>.yaml` each.
pub(crate) fn nav_files(r: Ready) -> Vec<OutputFile> {
    mapc_backends::nav_graphs(r.require(Outputs::NAV))
}

/// Every level's meshes, in document order (for the glTF, mesh and world outputs).
pub(crate) fn all_level_meshes(r: Ready) -> Meshes {
    let b = r.building();
    b.levels
        .iter()
        .map(|(h, _)| (h, mapc_backends::level_meshes(b, h)))
        .collect()
}

/// The number of level meshes (what the mesh-writing commands count).
pub(crate) fn mesh_count(meshes: &Meshes) -> usize {
    meshes.iter().map(|(_, m)| m.all().count()).sum()
}

/// The texture names the glTF target embeds.
pub(crate) fn gltf_texture_names(meshes: &Meshes) -> BTreeSet<String> {
    mapc_backends::gltf_texture_names(meshes.iter().flat_map(|(_, m)| m.all()))
}

/// The texture names the meshes target copies.
pub(crate) fn mesh_texture_names(meshes: &Meshes) -> BTreeSet<String> {
    mapc_backends::texture_names(meshes.iter().flat_map(|(_, m)| m.all()))
}

/// `<building>.glb` (and with `per_level`, `<building>_<level>.glb` per level).
pub(crate) fn gltf_files(
    r: Ready,
    meshes: &Meshes,
    textures: &Textures,
    per_level: bool,
) -> Vec<OutputFile> {
    let b = r.require(Outputs::GLTF);
    let stem = file_stem(&b.name);
    let sets: Vec<mapc_backends::LevelMeshSet> = meshes
        .iter()
        .map(|(h, m)| mapc_backends::LevelMeshSet {
            level: *h,
            meshes: m.all().collect(),
        })
        .collect();
    let mut files = vec![OutputFile {
        path: PathBuf::from(format!("{stem}.glb")),
        contents: mapc_backends::building_gltf(b, &sets, textures),
    }];
    if per_level {
        for (h, m) in meshes {
            let level = file_stem(&b.levels[*h].name);
            files.push(OutputFile {
                path: PathBuf::from(format!("{stem}_{level}.glb")),
                contents: mapc_backends::level_glb(b, *h, m.all(), textures),
            });
        }
    }
    files
}

/// `<building>_<level>/meshes/`: OBJ + MTL, model.material and textures, per level.
pub(crate) fn mesh_files(r: Ready, meshes: &Meshes, textures: &Textures) -> Vec<OutputFile> {
    let b = r.require(Outputs::MESHES);
    let mut files = Vec::new();
    for (h, m) in meshes {
        files.extend(mapc_backends::level_obj_files_from(b, *h, m));
        files.extend(mapc_backends::level_texture_files(b, *h, m, textures));
    }
    files
}

/// Texture images for `names`, searched on the texture path (`--texture-path` directories,
/// MAPC_TEXTURE_PATH, the map's directory), with warnings for those not found.
pub(crate) fn textures_for<'a>(
    r: Ready,
    names: impl IntoIterator<Item = &'a str>,
    texture_path: &[PathBuf],
    input: &Path,
) -> (Textures, Vec<Diagnostic>) {
    let search = texture::SearchPath::from_env(texture_path, input);
    mapc_backends::resolve_textures(r.building(), names, &mut |f| search.find(f))
}

/// Reads and parses a `--TEMPLATE_WORLD_FILE` (`mapc gazebo` and `mapc build`).
pub(crate) fn read_template(
    p: &Path,
    skip_camera_pose: bool,
) -> Result<mapc_backends::sdf::xml::Element, String> {
    std::fs::read_to_string(p)
        .map_err(|e| e.to_string())
        .and_then(|t| parse_template(&t, skip_camera_pose))
        .map_err(|e| format!("--TEMPLATE_WORLD_FILE {}: {e}", p.display()))
}

/// The directory name of a map's outputs: the file name less `.building.yaml` (or
/// `.project.yaml`, or its last extension), as rmf_demos_maps' CMake names maps.
pub(crate) fn map_name(input: &Path) -> String {
    let name = input
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = [".building.yaml", ".project.yaml", ".site.json"]
        .iter()
        .find_map(|suffix| name.strip_suffix(suffix))
        .map(str::to_owned)
        .or_else(|| input.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .unwrap_or_default();
    file_stem(&stem)
}

/// A name usable as one file name: path separators and control characters become `_`.
fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c == '/' || c == '\\' || c.is_control() {
                '_'
            } else {
                c
            }
        })
        .collect();
    if s.is_empty() || s == "." || s == ".." {
        "building".into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_names() {
        assert_eq!(map_name(Path::new("a/office.building.yaml")), "office");
        assert_eq!(map_name(Path::new("old.project.yaml")), "old");
        assert_eq!(map_name(Path::new("x/plain.yaml")), "plain");
        assert_eq!(map_name(Path::new("..building.yaml")), "building");
    }
}
