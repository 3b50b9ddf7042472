//! Triangle meshes of a level (walls, floors, ceilings), shared by every mesh format
//! (OBJ for Gazebo classic and Ignition, glTF/GLB for gz-sim and viewers). Geometry is in
//! the map frame, metres, z up, with z = 0 at the level's floor; writers place levels at
//! their elevation.

/// A material: a texture by name (resolved to a file by the caller) plus PBR maps.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Material name as written in MTL / glTF, e.g. `floor_1`, `wall_2`.
    pub name: String,
    /// Texture name as in the map (`blue_linoleum`, or an http(s) URL).
    pub texture: String,
    /// Opacity in [0, 1].
    pub alpha: f64,
    /// Extra PBR maps `(kind, texture name)`, e.g. `("roughness_map", "rough")`, in the
    /// params' order.
    pub pbr_maps: Vec<(String, String)>,
}

/// What a mesh is, for naming nodes and grouping.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshKind {
    Floor,
    Ceiling,
    Walls,
}

/// An indexed triangle mesh with per-vertex normals and UVs. Triangles are
/// counter-clockwise seen from the side their normals point to.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// `floor_<n>`, `ceiling_<n>` (n counts floor entries from 1), `wall_<k>` (k counts
    /// distinct wall parameter sets from 1).
    pub name: String,
    pub kind: MeshKind,
    pub positions: Vec<[f64; 3]>,
    pub normals: Vec<[f64; 3]>,
    pub uvs: Vec<[f64; 2]>,
    pub triangles: Vec<[u32; 3]>,
    pub material: Material,
}

impl Mesh {
    /// Total area of the triangles, m².
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
                let x = u[1] * v[2] - u[2] * v[1];
                let y = u[2] * v[0] - u[0] * v[2];
                let z = u[0] * v[1] - u[1] * v[0];
                0.5 * (x * x + y * y + z * z).sqrt()
            })
            .sum()
    }

    /// Area of the triangles whose geometric normal (from the winding) points along `dir`
    /// (positive dot product), m²: e.g. the top face of a floor slab with `[0, 0, 1]`.
    pub fn area_facing(&self, dir: [f64; 3]) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
                let n = [
                    u[1] * v[2] - u[2] * v[1],
                    u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0],
                ];
                let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                let d = n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2];
                if d > 1e-12 * len {
                    0.5 * len
                } else {
                    0.0
                }
            })
            .sum()
    }

    /// Axis-aligned bounds `(min, max)`, or `None` for an empty mesh.
    pub fn bounds(&self) -> Option<([f64; 3], [f64; 3])> {
        let first = *self.positions.first()?;
        Some(self.positions.iter().fold((first, first), |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            )
        }))
    }
}
