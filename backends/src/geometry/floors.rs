//! Floors and ceilings: the floor polygon minus the level's holes and lift shafts
//! (generator.md §2.3.2 step 2), triangulated.
//!
//! The boolean difference runs only when a hole or shaft's bounding box meets the floor's,
//! through `i_overlay` (which snaps to an integer grid of about extent / 2²⁹); its output
//! points are snapped back to the input points they came from, so untouched corners keep their
//! exact coordinates. Each resulting shape (outer contour + holes) is ear-clipped by `earcutr`
//! and every triangle is made counter-clockwise (normal +z).

use super::{params_iter, pbr_maps, positive, CEILING_HEIGHT, FLOOR_THICKNESS};
use crate::mesh::{Material, Mesh, MeshKind};
use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::core::solver::Solver;
use i_overlay::float::overlay::{FloatOverlay, OverlayOptions};
use mapc_ir::{Building, Handle, Level, Params, Polygon};

/// PBR map params of floors, and of ceilings (whose kinds lose the `ceiling_` prefix).
const FLOOR_PBR: &[&str] = &[
    "metalness_map",
    "roughness_map",
    "normal_map",
    "environment_map",
    "light_map",
];
const CEILING_PBR: &[&str] = &[
    "ceiling_metalness_map",
    "ceiling_roughness_map",
    "ceiling_environment_map",
    "ceiling_normal_map",
    "ceiling_light_map",
    "ceiling_emissive_map",
];

/// The area a floor covers, triangulated.
#[derive(Debug, Clone, PartialEq)]
pub struct FloorRegion {
    /// Shapes of the region: the outer contour (counter-clockwise) then its holes
    /// (clockwise). Without cuts, the floor polygon itself, in input order and orientation.
    pub shapes: Vec<Vec<Vec<[f64; 2]>>>,
    /// Every contour point of `shapes`, in order.
    pub points: Vec<[f64; 2]>,
    /// Counter-clockwise triangles over `points`.
    pub triangles: Vec<[u32; 3]>,
}

impl FloorRegion {
    /// Area of the triangles, m².
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                signed_area2(
                    self.points[t[0] as usize],
                    self.points[t[1] as usize],
                    self.points[t[2] as usize],
                ) / 2.0
            })
            .sum()
    }
}

/// A polygon to subtract from floors: a hole or a lift shaft, counter-clockwise.
pub(super) struct Cutter {
    pts: Vec<[f64; 2]>,
    min: [f64; 2],
    max: [f64; 2],
}

/// The holes of `level` and the shaft rectangles of the lifts serving it.
pub(super) fn cutters(b: &Building, level: Handle<Level>) -> Vec<Cutter> {
    let lvl = &b.levels[level];
    let holes = lvl.holes.iter().map(|&h| polygon_points(b, &b.holes[h]));
    let shafts = b
        .lifts_on_level(level)
        .map(|l| b.lifts[l].shaft_corners().map(|c| [c.x, c.y]).to_vec());
    holes
        .chain(shafts)
        .filter_map(|mut pts| {
            let a = shoelace(&pts);
            if pts.len() < 3 || a == 0.0 || !a.is_finite() {
                return None;
            }
            if a < 0.0 {
                pts.reverse();
            }
            let (min, max) = bbox(&pts);
            Some(Cutter { pts, min, max })
        })
        .collect()
}

/// The region of floor `floor` of `level`: its polygon minus the level's holes and lift
/// shafts, triangulated. `None` for a degenerate polygon or an empty region.
pub fn floor_region(
    b: &Building,
    level: Handle<Level>,
    floor: Handle<Polygon>,
) -> Option<FloorRegion> {
    region_with_cutters(b, &b.floors[floor], &cutters(b, level))
}

pub(super) fn region_with_cutters(
    b: &Building,
    floor: &Polygon,
    cutters: &[Cutter],
) -> Option<FloorRegion> {
    let pts = polygon_points(b, floor);
    let a = shoelace(&pts);
    if pts.len() < 3 || a == 0.0 || !a.is_finite() {
        return None;
    }
    let (min, max) = bbox(&pts);
    let hits: Vec<&Cutter> = cutters
        .iter()
        .filter(|c| {
            c.min[0] < max[0] && c.max[0] > min[0] && c.min[1] < max[1] && c.max[1] > min[1]
        })
        .collect();
    let shapes = if hits.is_empty() {
        vec![vec![pts]]
    } else {
        let cut = difference(pts.clone(), &hits);
        // Bounding boxes met but nothing was cut: keep the polygon as written.
        let area: f64 = cut.iter().flatten().map(|c| shoelace(c)).sum();
        if cut.len() == 1 && cut[0].len() == 1 && (area - a.abs()).abs() <= 1e-12 * a.abs() {
            vec![vec![pts]]
        } else {
            cut
        }
    };
    let mut points = Vec::new();
    let mut triangles = Vec::new();
    for shape in &shapes {
        triangulate(shape, &mut points, &mut triangles);
    }
    (!triangles.is_empty()).then_some(FloorRegion {
        shapes,
        points,
        triangles,
    })
}

/// `floor` minus the cutters, as shapes (outer contour then holes).
fn difference(mut floor: Vec<[f64; 2]>, cutters: &[&Cutter]) -> Vec<Vec<Vec<[f64; 2]>>> {
    if shoelace(&floor) < 0.0 {
        floor.reverse();
    }
    let clip: Vec<Vec<[f64; 2]>> = cutters.iter().map(|c| c.pts.clone()).collect();
    let options = OverlayOptions {
        preserve_input_collinear: true,
        preserve_output_collinear: true,
        ..OverlayOptions::default()
    };
    // Every contour counter-clockwise, so non-zero winding is the union of the cutters.
    let shapes = FloatOverlay::with_subj_and_clip_custom(&floor, &clip, options, Solver::default())
        .overlay(OverlayRule::Difference, FillRule::NonZero);
    // Snap back to input points (the overlay rounds to its integer grid).
    let mut originals: Vec<[f64; 2]> = floor.clone();
    for c in cutters {
        originals.extend_from_slice(&c.pts);
    }
    originals.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let (lo, hi) = bbox(&originals);
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let tol = extent * 2f64.powi(-24);
    shapes
        .into_iter()
        .map(|shape| {
            shape
                .into_iter()
                .map(|contour| {
                    contour
                        .into_iter()
                        .map(|p| snap(p, &originals, tol))
                        .collect()
                })
                .collect()
        })
        .collect()
}

/// The input point within `tol` of `p` (sorted by x), or `p`.
fn snap(p: [f64; 2], sorted: &[[f64; 2]], tol: f64) -> [f64; 2] {
    let start = sorted.partition_point(|q| q[0] < p[0] - tol);
    sorted[start..]
        .iter()
        .take_while(|q| q[0] <= p[0] + tol)
        .find(|q| (q[1] - p[1]).abs() <= tol)
        .copied()
        .unwrap_or(p)
}

/// Ear-clips one shape, appending its points and counter-clockwise triangles.
fn triangulate(shape: &[Vec<[f64; 2]>], points: &mut Vec<[f64; 2]>, triangles: &mut Vec<[u32; 3]>) {
    let Some(outer) = shape.first() else { return };
    let Some(&origin) = outer.first() else { return };
    let base = points.len();
    let mut data = Vec::with_capacity(2 * shape.iter().map(Vec::len).sum::<usize>());
    let mut holes = Vec::with_capacity(shape.len().saturating_sub(1));
    for (i, contour) in shape.iter().enumerate() {
        if i > 0 {
            holes.push(data.len() / 2);
        }
        for p in contour {
            // Local coordinates keep precision in projected (wgs84) maps.
            data.push(p[0] - origin[0]);
            data.push(p[1] - origin[1]);
            points.push(*p);
        }
    }
    let Ok(idx) = earcutr::earcut(&data, &holes, 2) else {
        return;
    };
    for t in idx.chunks_exact(3) {
        let [a, b, c] = [t[0] + base, t[1] + base, t[2] + base];
        let s = signed_area2(points[a], points[b], points[c]);
        if s > 0.0 {
            triangles.push([a as u32, b as u32, c as u32]);
        } else if s < 0.0 {
            triangles.push([a as u32, c as u32, b as u32]);
        }
    }
}

/// Floor slab: top face at z = 0 (normal +z), bottom face at −FLOOR_THICKNESS (normal −z).
/// Vertices: the region's points on top, then the same points below.
pub(super) fn floor_mesh(region: &FloorRegion, params: &Params, n: usize) -> Mesh {
    let scale = positive(params, "texture_scale", 1.0);
    let rot = params
        .f64("texture_rotation")
        .filter(|r| r.is_finite())
        .unwrap_or(0.0)
        .to_radians();
    let (s, c) = (-rot).sin_cos();
    let uv = |p: [f64; 2]| [(c * p[0] - s * p[1]) / scale, (s * p[0] + c * p[1]) / scale];
    let np = region.points.len();
    let mut positions = Vec::with_capacity(2 * np);
    let mut normals = Vec::with_capacity(2 * np);
    let mut uvs = Vec::with_capacity(2 * np);
    for (z, nz) in [(0.0, 1.0), (-FLOOR_THICKNESS, -1.0)] {
        for &p in &region.points {
            positions.push([p[0], p[1], z]);
            normals.push([0.0, 0.0, nz]);
            uvs.push(uv(p));
        }
    }
    let off = np as u32;
    let mut triangles = region.triangles.clone();
    triangles.extend(
        region
            .triangles
            .iter()
            .map(|t| [t[2] + off, t[1] + off, t[0] + off]),
    );
    let name = format!("floor_{n}");
    Mesh {
        material: Material {
            name: name.clone(),
            texture: texture(params, "texture_name"),
            alpha: 1.0,
            pbr_maps: pbr_maps(params_iter(params), FLOOR_PBR, ""),
        },
        name,
        kind: MeshKind::Floor,
        positions,
        normals,
        uvs,
        triangles,
    }
}

/// Ceiling: the floor's region at CEILING_HEIGHT facing down (visible from below only).
pub(super) fn ceiling_mesh(region: &FloorRegion, params: &Params, n: usize) -> Mesh {
    let scale = positive(params, "ceiling_scale", 1.0);
    let name = format!("ceiling_{n}");
    Mesh {
        material: Material {
            name: name.clone(),
            texture: texture(params, "ceiling_texture"),
            alpha: 1.0,
            pbr_maps: pbr_maps(params_iter(params), CEILING_PBR, "ceiling_"),
        },
        name,
        kind: MeshKind::Ceiling,
        positions: region
            .points
            .iter()
            .map(|p| [p[0], p[1], CEILING_HEIGHT])
            .collect(),
        normals: vec![[0.0, 0.0, -1.0]; region.points.len()],
        uvs: region
            .points
            .iter()
            .map(|p| [p[0] / scale, p[1] / scale])
            .collect(),
        triangles: region
            .triangles
            .iter()
            .map(|t| [t[2], t[1], t[0]])
            .collect(),
    }
}

fn texture(params: &Params, key: &str) -> String {
    params
        .str(key)
        .filter(|s| !s.is_empty())
        .unwrap_or("blue_linoleum")
        .to_string()
}

fn polygon_points(b: &Building, poly: &Polygon) -> Vec<[f64; 2]> {
    poly.vertices
        .iter()
        .map(|&v| {
            let p = b.vertices[v].pos;
            [p.x, p.y]
        })
        .collect()
}

/// Signed area (positive counter-clockwise), relative to the first point for precision.
pub(crate) fn shoelace(pts: &[[f64; 2]]) -> f64 {
    let Some(&o) = pts.first() else { return 0.0 };
    let mut s = 0.0;
    for i in 0..pts.len() {
        let a = pts[i];
        let b = pts[(i + 1) % pts.len()];
        s += (a[0] - o[0]) * (b[1] - o[1]) - (b[0] - o[0]) * (a[1] - o[1]);
    }
    s / 2.0
}

/// Twice the signed area of triangle abc.
fn signed_area2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
}

fn bbox(pts: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    pts.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    )
}
