//! Backends: pure functions from a validated [`mapc_ir::Building`] to output files held in
//! memory. Writing them to disk (atomically, inside the output directory) is the caller's
//! job, so backends do no I/O and never see a path outside the output tree.

mod fmt;
mod mesh;
mod nav;
mod yaml;

pub use fmt::py_float;
pub use mesh::{Material, Mesh, MeshKind};
pub use nav::{nav_graph, nav_graphs};
pub use yaml::{to_string as yaml_to_string, Yaml};

use std::path::PathBuf;

/// A file to write, with a path relative to the output directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutputFile {
    pub path: PathBuf,
    pub contents: Vec<u8>,
}
