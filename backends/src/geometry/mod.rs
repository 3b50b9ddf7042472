//! Level geometry shared by every mesh backend (OBJ, glTF/GLB): wall boxes, floor slabs with
//! holes and lift shafts cut out, ceilings (generator.md §0.3, §2.3.2-2.3.4).
//!
//! Everything is in the map frame, metres, z up, z = 0 at the level's floor; writers place
//! levels at their elevation and apply any per-mesh origin shift or site offset themselves.
//! Differences from the reference generator, on purpose:
//! - every wall face has its outward normal (the reference swaps the two end faces');
//! - floor UVs apply `texture_rotation` (degrees, counter-clockwise, as rmf_site reads it):
//!   `uv = R(−θ)·(x, y) / texture_scale`, identical to the reference when θ = 0;
//! - floors are triangulated by ear clipping after an exact-enough boolean difference, not by
//!   clipped Delaunay triangles; the covered region is the same.
//!
//! Degenerate input (polygons with fewer than 3 vertices or no area, reported by E0601-E0603)
//! is skipped, never a panic.

mod floors;
mod walls;

use crate::mesh::Mesh;
use mapc_ir::{Building, Handle, Level, ParamValue, Params};

pub use floors::{floor_region, FloorRegion};
pub use walls::{wall_groups, WallGroup};

/// Wall height, metres (fixed in the reference generator).
pub const WALL_HEIGHT: f64 = 2.5;
/// Wall thickness, metres.
pub const WALL_THICKNESS: f64 = 0.1;
/// Floor slab thickness, metres: the top face at z = 0, the bottom at −FLOOR_THICKNESS.
pub const FLOOR_THICKNESS: f64 = 0.1;
/// Ceiling height, metres (the wall height).
pub const CEILING_HEIGHT: f64 = WALL_HEIGHT;

/// The meshes of one level.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LevelMeshes {
    /// `floor_<n>`, n = position of the floor in the level + 1 (skipped floors leave gaps).
    pub floors: Vec<Mesh>,
    /// `ceiling_<n>` for floors with `indoor` ≠ 0, same n as their floor.
    pub ceilings: Vec<Mesh>,
    /// `wall_<k>`, one per distinct wall parameter map, in order of first appearance.
    pub walls: Vec<Mesh>,
}

impl LevelMeshes {
    /// Every mesh: floors and their ceilings interleaved in floor order, then walls (the
    /// order of the links in the reference's `model.sdf`).
    pub fn all(&self) -> impl Iterator<Item = &Mesh> + '_ {
        let mut ceilings = self.ceilings.iter().peekable();
        let mut out = Vec::with_capacity(self.floors.len() + self.ceilings.len());
        for f in &self.floors {
            out.push(f);
            let n = f.name.trim_start_matches("floor_");
            if let Some(c) = ceilings.next_if(|c| c.name.trim_start_matches("ceiling_") == n) {
                out.push(c);
            }
        }
        out.extend(ceilings);
        out.into_iter().chain(self.walls.iter())
    }

    pub fn is_empty(&self) -> bool {
        self.floors.is_empty() && self.ceilings.is_empty() && self.walls.is_empty()
    }
}

/// Meshes of `level`: floors (holes and lift shafts cut out), ceilings, walls grouped by
/// parameter map. Pure; never panics on a building whose handles are valid.
pub fn level_meshes(b: &Building, level: Handle<Level>) -> LevelMeshes {
    let lvl = &b.levels[level];
    let mut out = LevelMeshes::default();
    if !lvl.floors.is_empty() {
        let cutters = floors::cutters(b, level);
        for (i, &fh) in lvl.floors.iter().enumerate() {
            let floor = &b.floors[fh];
            let n = i + 1;
            let Some(region) = floors::region_with_cutters(b, floor, &cutters) else {
                continue;
            };
            out.floors
                .push(floors::floor_mesh(&region, &floor.params, n));
            if is_indoor(&floor.params) {
                out.ceilings
                    .push(floors::ceiling_mesh(&region, &floor.params, n));
            }
        }
    }
    out.walls = walls::wall_meshes(b, level);
    out
}

/// The mesh of a level's first floor (`floor_1`), as [`level_meshes`] makes it: `None`
/// when the level has no floor or the first one has no area. The world's camera is placed
/// by it, without the cost of every other mesh of the level.
pub fn first_floor_mesh(b: &Building, level: Handle<Level>) -> Option<Mesh> {
    let lvl = &b.levels[level];
    let &fh = lvl.floors.first()?;
    let floor = &b.floors[fh];
    let region = floors::region_with_cutters(b, floor, &floors::cutters(b, level))?;
    Some(floors::floor_mesh(&region, &floor.params, 1))
}

/// Meshes of every level, in document order.
pub fn building_meshes(b: &Building) -> Vec<(Handle<Level>, LevelMeshes)> {
    b.levels
        .iter()
        .map(|(h, _)| (h, level_meshes(b, h)))
        .collect()
}

fn is_indoor(p: &Params) -> bool {
    match p.get("indoor") {
        Some(ParamValue::Bool(v)) => *v,
        Some(v) => v.as_f64().is_some_and(|x| x != 0.0),
        None => false,
    }
}

/// A positive finite parameter, else `default`.
fn positive(p: &Params, name: &str, default: f64) -> f64 {
    match p.f64(name) {
        Some(v) if v.is_finite() && v > 0.0 => v,
        _ => default,
    }
}

/// Extra PBR maps `(kind, texture)` in the params' order: `names` are the param names,
/// `strip` a prefix removed from the kind (`ceiling_`).
fn pbr_maps<'a>(
    params: impl Iterator<Item = (&'a str, &'a ParamValue)>,
    names: &[&str],
    strip: &str,
) -> Vec<(String, String)> {
    params
        .filter(|(name, _)| names.contains(name))
        .filter_map(|(name, value)| {
            let tex = value.as_str()?;
            (!tex.is_empty()).then(|| {
                (
                    name.strip_prefix(strip).unwrap_or(name).to_string(),
                    tex.to_string(),
                )
            })
        })
        .collect()
}

fn params_iter(p: &Params) -> impl Iterator<Item = (&str, &ParamValue)> {
    p.iter().map(|q| (q.name.as_str(), &q.value))
}

/// `a × b`.
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
pub(crate) mod tests;
