//! The pipeline every command shares: read a map (`check`: frontend, validation passes,
//! lint levels), the gate that backends require (`Ready`: only a map no error blocks
//! reaches a file producer), the file producers several commands share (`produce`), the
//! one shape of a single-map command (`compile`), writing files (`output`, the only place
//! that writes), signals, the texture search path, argument sanity, and how a command ends
//! (`CliError`, `Outcome`, mapped to exit codes in `error`).
//!
//! Invariant: the driver never imports a command (`crate::commands`) or `main.rs`.

mod check;
mod compile;
mod error;
pub(crate) mod lints;
mod opts;
pub(crate) mod output;
mod produce;
mod report;
pub(crate) mod sanity;
pub(crate) mod signals;
pub(crate) mod texture;

pub(crate) use check::{all_diagnostics, lints_for, load_and_check, Checked, Ready};
pub(crate) use compile::{compile, compile_into, finished, Product, Spec};
pub(crate) use error::{exit_code, CliError, Outcome};
pub(crate) use opts::{DiagOpts, LintOpts};
pub(crate) use produce::{
    all_level_meshes, gltf_files, gltf_texture_names, map_name, mesh_count, mesh_files,
    mesh_texture_names, nav_files, read_template, textures_for,
};
pub(crate) use report::{
    emit, load_readable, not_written, print_sarif, success_line, summary_line, ways_out,
};
