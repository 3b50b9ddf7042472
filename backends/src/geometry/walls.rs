//! Walls (generator.md §2.3.4): a box per wall segment, `WALL_THICKNESS` thick and
//! `WALL_HEIGHT` high, extended t/2 past each endpoint; four side faces and a top cap (no
//! bottom cap, as the reference), each face with its own vertices and outward normal.
//! Walls whose parameter maps are equal share one mesh.
//!
//! Mesh layout (the OBJ writer relies on it): 20 vertices and 10 triangles per wall, in the
//! group's order; per wall the faces C0–C1 (normal R(ψ)·(0,1)), C1–C2 (R(ψ)·(1,0)), C2–C3
//! (R(ψ)·(0,−1)), C3–C0 (R(ψ)·(−1,0)), each as [from bottom, to bottom, to top, from top],
//! then the top cap [C3, C2, C1, C0] at the wall height. UVs are the spec's: u = 0, L, L+t,
//! 2L+t at C0..C3 (C0 again 0 on the last face) over s, v = 0 or vt_h/s; (0, 0) on the cap.

use super::{cross, dot, pbr_maps, sub, WALL_HEIGHT, WALL_THICKNESS};
use crate::mesh::{Material, Mesh, MeshKind};
use mapc_ir::{Building, Handle, Level, ParamValue, Params, Wall};

const WALL_PBR: &[&str] = &[
    "metalness_map",
    "roughness_map",
    "normal_map",
    "environment_map",
    "light_map",
];

/// Walls sharing one parameter map.
#[derive(Debug, Clone, PartialEq)]
pub struct WallGroup {
    /// The normalised parameter map of the group's first wall, in its order, with
    /// `texture_name` and `alpha` appended when absent.
    pub params: Vec<(String, ParamValue)>,
    /// The group's walls in document order.
    pub walls: Vec<Handle<Wall>>,
}

impl WallGroup {
    fn get(&self, name: &str) -> Option<&ParamValue> {
        self.params.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
    fn f64(&self, name: &str) -> Option<f64> {
        self.get(name).and_then(ParamValue::as_f64)
    }
    /// `alpha` as a number (1.0 when not numeric).
    pub fn alpha(&self) -> f64 {
        self.f64("alpha").unwrap_or(1.0)
    }
    /// `texture_name` (`default` when absent or not a string).
    pub fn texture(&self) -> &str {
        self.get("texture_name")
            .and_then(ParamValue::as_str)
            .unwrap_or("default")
    }
}

/// Parameter maps compare as the reference's Python dicts do: by name, numbers by value.
fn same_value(a: &ParamValue, b: &ParamValue) -> bool {
    match (a, b) {
        (ParamValue::String(x), ParamValue::String(y)) => x == y,
        (ParamValue::Bool(x), ParamValue::Bool(y)) => x == y,
        (ParamValue::Bool(_), _) | (_, ParamValue::Bool(_)) => false,
        _ => match (a.as_f64(), b.as_f64()) {
            (Some(x), Some(y)) => x == y,
            _ => false,
        },
    }
}

fn normalised(p: &Params) -> Vec<(String, ParamValue)> {
    let mut v: Vec<(String, ParamValue)> = p
        .iter()
        .map(|q| (q.name.clone(), q.value.clone()))
        .collect();
    if p.get("texture_name").is_none() {
        v.push(("texture_name".into(), ParamValue::String("default".into())));
    }
    if p.get("alpha").is_none() {
        v.push(("alpha".into(), ParamValue::Double(1.0)));
    }
    v
}

/// The level's walls grouped by parameter map, groups in order of first appearance.
pub fn wall_groups(b: &Building, level: Handle<Level>) -> Vec<WallGroup> {
    let mut groups: Vec<WallGroup> = Vec::new();
    for &w in &b.levels[level].walls {
        let p = &b.walls[w].params;
        // The wall's `normalised` parameters, compared in place: a copy is made only for a
        // new group (copying every wall's was most of this function's allocations).
        let (no_texture, no_alpha) = (p.get("texture_name").is_none(), p.get("alpha").is_none());
        let len = p.0.len() + usize::from(no_texture) + usize::from(no_alpha);
        let has =
            |g: &WallGroup, n: &str, v: &ParamValue| g.get(n).is_some_and(|gv| same_value(gv, v));
        let found = groups.iter_mut().find(|g| {
            // Names are unique in a map, so equal lengths and inclusion mean equality.
            g.params.len() == len
                && p.iter().all(|q| has(g, &q.name, &q.value))
                && (!no_texture
                    || g.get("texture_name").and_then(ParamValue::as_str) == Some("default"))
                && (!no_alpha || has(g, "alpha", &ParamValue::Double(1.0)))
        });
        match found {
            Some(g) => g.walls.push(w),
            None => groups.push(WallGroup {
                params: normalised(p),
                walls: vec![w],
            }),
        }
    }
    groups
}

pub(super) fn wall_meshes(b: &Building, level: Handle<Level>) -> Vec<Mesh> {
    wall_groups(b, level)
        .iter()
        .enumerate()
        .map(|(i, g)| wall_mesh(b, g, i + 1))
        .collect()
}

/// `(vt_h, s)`: the texture's vertical extent and the scale that divides UVs (§2.3.4).
fn texture_extent(g: &WallGroup) -> (f64, f64) {
    let (th, tw, ts) = match g.f64("texture_height") {
        Some(th) => (
            th,
            g.f64("texture_width").unwrap_or(1.0),
            g.f64("texture_scale").unwrap_or(1.0),
        ),
        None => (2.5, 1.0, 1.0),
    };
    let mut vt_h = WALL_HEIGHT / (th / tw);
    if !vt_h.is_finite() || vt_h <= 0.0 {
        vt_h = 1.0;
    }
    let s = if ts == 0.0 || !ts.is_finite() {
        vt_h
    } else {
        ts
    };
    (vt_h, s)
}

fn wall_mesh(b: &Building, g: &WallGroup, k: usize) -> Mesh {
    let (vt_h, s) = texture_extent(g);
    let t = WALL_THICKNESS;
    let h = WALL_HEIGHT;
    let n = g.walls.len();
    let mut m = Mesh {
        name: format!("wall_{k}"),
        kind: MeshKind::Walls,
        positions: Vec::with_capacity(20 * n),
        normals: Vec::with_capacity(20 * n),
        uvs: Vec::with_capacity(20 * n),
        triangles: Vec::with_capacity(10 * n),
        material: Material {
            name: format!("wall_{k}"),
            texture: g.texture().to_string(),
            alpha: g.alpha().clamp(0.0, 1.0),
            pbr_maps: pbr_maps(g.params.iter().map(|(n, v)| (n.as_str(), v)), WALL_PBR, ""),
        },
    };
    for &w in &g.walls {
        let wall = &b.walls[w];
        let p1 = b.vertices[wall.start].pos;
        let p2 = b.vertices[wall.end].pos;
        let d = p2.minus(p1);
        let len = d.norm();
        let c = p1.plus(p2).scale(0.5);
        let psi = d.y.atan2(d.x);
        let (sn, cs) = psi.sin_cos();
        let world = |x: f64, y: f64| [c.x + cs * x - sn * y, c.y + sn * x + cs * y];
        let (hx, hy) = (len / 2.0 + t / 2.0, t / 2.0);
        let corners = [
            world(-hx, hy),
            world(hx, hy),
            world(hx, -hy),
            world(-hx, -hy),
        ];
        let dir = [cs, sn, 0.0];
        let left = [-sn, cs, 0.0];
        let neg = |v: [f64; 3]| [-v[0], -v[1], 0.0];
        // (from corner, to corner, outward normal, u at from, u at to)
        let sides = [
            (0, 1, left, 0.0, len),
            (1, 2, dir, len, len + t),
            (2, 3, neg(left), len + t, 2.0 * len + t),
            // The spec's UVs: C0 keeps u = 0 on this face too.
            (3, 0, neg(dir), 2.0 * len + t, 0.0),
        ];
        for (a, bb, normal, u0, u1) in sides {
            let (pa, pb) = (corners[a], corners[bb]);
            quad(
                &mut m,
                [
                    [pa[0], pa[1], 0.0],
                    [pb[0], pb[1], 0.0],
                    [pb[0], pb[1], h],
                    [pa[0], pa[1], h],
                ],
                [
                    [u0 / s, 0.0],
                    [u1 / s, 0.0],
                    [u1 / s, vt_h / s],
                    [u0 / s, vt_h / s],
                ],
                normal,
            );
        }
        // Top cap: UV (0, 0) at every corner, as the spec.
        let top = [3, 2, 1, 0].map(|i| [corners[i][0], corners[i][1], h]);
        quad(&mut m, top, [[0.0, 0.0]; 4], [0.0, 0.0, 1.0]);
    }
    m
}

/// Appends a planar quad `q` (4 corners in order around it) as two triangles facing
/// `normal` (the winding is chosen from the geometry, so it is right whatever the order).
fn quad(m: &mut Mesh, q: [[f64; 3]; 4], uv: [[f64; 2]; 4], normal: [f64; 3]) {
    let base = m.positions.len() as u32;
    m.positions.extend_from_slice(&q);
    m.uvs.extend_from_slice(&uv);
    m.normals.extend_from_slice(&[normal; 4]);
    let facing = dot(cross(sub(q[1], q[0]), sub(q[2], q[0])), normal) >= 0.0;
    if facing {
        m.triangles.push([base, base + 1, base + 2]);
        m.triangles.push([base, base + 2, base + 3]);
    } else {
        m.triangles.push([base, base + 2, base + 1]);
        m.triangles.push([base, base + 3, base + 2]);
    }
}
