//! mapc's typed building model.
//!
//! Invariants: every `Handle` stored in a [`Building`] is valid for its arenas; all
//! positions are finite metres in the map frame; every element has a span. The crate is
//! data and checks only: no I/O, no threads, no `unsafe` (forbidden below).

#![forbid(unsafe_code)]

mod arena;
mod building;
mod diag;
mod geom;
pub mod lints;
mod navmesh;
mod params;
mod span;
mod summary;
mod validate;

pub use arena::{Arena, Handle};
pub use building::*;
pub use diag::{count_text, doc_anchor, has_errors, Code, Diagnostic, Label, Severity};
pub use geom::segment_intersection;
pub use navmesh::{human_navmesh, NavMesh, DEFAULT_HUMAN_LANE_WIDTH};
pub use params::{Param, ParamValue, Params};
pub use span::{FileId, Span};
pub use summary::summary;
pub use validate::grid::BoxGrid;
pub use validate::{rule, rules, validate, Context, Rule};
