//! Backends: pure functions from a validated [`mapc_ir::Building`] to output files held in
//! memory. Writing them to disk (atomically, inside the output directory) is the caller's
//! job, so backends do no I/O and never see a path outside the output tree.

mod building_yaml;
pub mod codes;
mod crowd_doc;
mod fmt;
pub mod geometry;
mod gltf;
mod mesh;
mod nav;
mod obj;
pub mod render;
pub mod sdf;
mod site;
pub mod svg;
mod texture;
mod yaml;

pub use building_yaml::building_yaml;
pub use codes::CODES;
pub use fmt::py_float;
pub use geometry::{level_meshes, LevelMeshes};
pub use gltf::{
    building_gltf, cabin_mesh, door_mesh, glb_split, gltf_texture_names, level_glb, LevelMeshSet,
    CABIN_HEIGHT, DOOR_HEIGHT, DOOR_THICKNESS, GLTF_PBR_MAPS,
};
pub use mesh::{Material, Mesh, MeshKind};
pub use nav::{graph_file_stem, nav_graph_text, nav_graphs};
pub use obj::{
    level_obj_files, level_obj_files_from, level_texture_files, level_texture_paths, mesh_mtl,
    mesh_obj, model_material, wall_origin,
};
pub use site::site_json;
pub use texture::{
    is_png, is_url, placeholder_png, png_head_is_enough, resolve_textures, strip_png,
    texture_file_name, texture_names, TextureImage, Textures,
};
pub use yaml::{to_string as yaml_to_string, Yaml};

use std::path::PathBuf;

/// A file to write, with a path relative to the output directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutputFile {
    pub path: PathBuf,
    pub contents: Vec<u8>,
}
