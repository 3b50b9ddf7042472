//! glTF 2.0 output: a GLB per level mesh set (for gz-sim) and the whole building as one GLB
//! scene (for viewers, Blender, web pages).
//!
//! **Axes.** mapc's map frame is z-up (x east, y north, metres). glTF is y-up. Vertex data
//! stays in the map frame and the scene's root node carries the rotation (−90° about x:
//! glTF `(x, y, z) = (x, z, −y)`), so level nodes keep `translation = [0, 0, elevation]` in
//! map terms and a z-up consumer can simply drop the root rotation.
//!
//! **Origin.** Positions are written as `f32`, so the building's `offset` (the wgs84
//! `suggested_offset`, or the cartesian `offset`) is subtracted first, as simulation worlds
//! do; the root node's extras record it (`"offset": [x, y]`). UVs are shifted per mesh by
//! whole texture repeats (which changes nothing on screen) to keep them small, and flipped
//! vertically (glTF's texture origin is the top-left corner, OBJ's the bottom-left).
//!
//! Output is deterministic: the same input gives the same bytes.

mod glb;
pub use glb::split as glb_split;

use crate::texture::Textures;
use crate::{Material, Mesh, MeshKind};
use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use mapc_ir::{Building, DoorKind, Handle, Level, Vec2};
use serde_json::json;
use std::collections::BTreeMap;

/// Door panels: height and thickness of a closed door's leaves (generator.md §2.7).
pub const DOOR_HEIGHT: f64 = 2.2;
pub const DOOR_THICKNESS: f64 = 0.03;
/// Lift cabins are drawn as a closed box this high (generator.md §2.8 cabin height).
pub const CABIN_HEIGHT: f64 = 2.5;

const DOOR_RGBA: [f32; 4] = [0.5, 0.25, 0.0, 0.6];
const CABIN_RGBA: [f32; 4] = [0.7, 0.7, 0.7, 1.0];

/// z-up → y-up: −90° about x, as `[x, y, z, w]`.
const ROOT_ROTATION: [f32; 4] = [
    -std::f32::consts::FRAC_1_SQRT_2,
    0.0,
    0.0,
    std::f32::consts::FRAC_1_SQRT_2,
];

/// A level's meshes as [`building_gltf`] takes them: the level and its floors, ceilings and
/// walls (in that order or any other: nodes follow the slice order).
pub struct LevelMeshSet<'a> {
    pub level: Handle<Level>,
    pub meshes: Vec<&'a Mesh>,
}

/// The GLB of one level's meshes (floors, ceilings, walls), for a gz-sim level model: a
/// root node `<building>_<level>` (carrying the z-up → y-up rotation) with one child node
/// and one glTF mesh per [`Mesh`], named as the mesh (`floor_1`, `wall_2`, ...), so an SDF
/// `<submesh>` can select one. Geometry is relative to the level's floor (z = 0) and to
/// the building offset; the world places the model at `(0, 0, elevation)`.
pub fn level_glb<'m>(
    b: &Building,
    level: Handle<Level>,
    meshes: impl IntoIterator<Item = &'m Mesh>,
    textures: &Textures,
) -> Vec<u8> {
    let mut w = Writer::new(textures, b.offset);
    let lname = &b.levels[level].name;
    let mut children = Vec::new();
    for m in meshes {
        children.push(w.mesh_node(m, mesh_extras(lname, m)));
    }
    let root = w.node(json::Node {
        name: Some(format!("{}_{}", b.name, lname)),
        rotation: Some(json::scene::UnitQuaternion(ROOT_ROTATION)),
        children: non_empty(children),
        extras: raw(json!({
            "building": b.name,
            "level": lname,
            "elevation": b.levels[level].elevation,
            "offset": [b.offset.x, b.offset.y],
        })),
        ..Default::default()
    });
    w.finish(root)
}

/// The whole building as one GLB scene: a root node named after the building (carrying the
/// z-up → y-up rotation), a child node per level at `translation = [0, 0, elevation]`, and
/// under each level named nodes for its meshes (`floor_<n>`, `ceiling_<n>`, `wall_<k>`),
/// its door panels (node named as the door) and the lift cabins whose initial floor it is
/// (node named as the lift). Every node's `extras` carry the map names, e.g.
/// `{"door": "coe_door", "type": "hinged", "level": "L1"}`.
///
/// Doors are drawn closed: one box per leaf (two for double doors, split by
/// `right_left_ratio`), as wide as the leaf less 1 cm, [`DOOR_THICKNESS`] thick and
/// [`DOOR_HEIGHT`] high, 1 cm above the floor, as the reference's door links. Lift cabins
/// are a `width × depth ×` [`CABIN_HEIGHT`] box at the lift's pose.
pub fn building_gltf(b: &Building, levels: &[LevelMeshSet<'_>], textures: &Textures) -> Vec<u8> {
    let mut w = Writer::new(textures, b.offset);
    let mut level_nodes = Vec::new();
    for set in levels {
        let level = &b.levels[set.level];
        let mut children = Vec::new();
        for &m in &set.meshes {
            children.push(w.mesh_node(m, mesh_extras(&level.name, m)));
        }
        for &d in &level.doors {
            let door = &b.doors[d];
            let mesh = door_mesh(b, d);
            let extras =
                json!({"door": door.name, "type": door.kind.as_str(), "level": level.name});
            children.push(w.mesh_node(&mesh, extras));
        }
        for (_, lift) in b.lifts.iter() {
            let home = lift.initial_floor().unwrap_or(lift.reference_level);
            if home != set.level {
                continue;
            }
            let served: Vec<&str> = lift
                .level_doors
                .iter()
                .map(|ld| b.levels[ld.level].name.as_str())
                .collect();
            let mesh = cabin_mesh(&lift.name, lift.pos, lift.yaw, lift.width, lift.depth);
            let extras = json!({"lift": lift.name, "level": level.name, "levels": served});
            children.push(w.mesh_node(&mesh, extras));
        }
        level_nodes.push(w.node(json::Node {
            name: Some(level.name.clone()),
            translation: Some([0.0, 0.0, level.elevation as f32]),
            children: non_empty(children),
            extras: raw(json!({"level": level.name, "elevation": level.elevation})),
            ..Default::default()
        }));
    }
    let root = w.node(json::Node {
        name: Some(b.name.clone()),
        rotation: Some(json::scene::UnitQuaternion(ROOT_ROTATION)),
        children: non_empty(level_nodes),
        extras: raw(json!({
            "building": b.name,
            "coordinate_system": b.coordinate_system.as_str(),
            "crs": b.crs_name,
            "offset": [b.offset.x, b.offset.y],
            "up": "map frame is z-up; this node rotates it to glTF's y-up",
        })),
        ..Default::default()
    });
    w.finish(root)
}

/// PBR map kinds (as in [`Material::pbr_maps`]) that glTF can carry as they are: a normal
/// map becomes `normalTexture`, an emissive map `emissiveTexture`. Metalness, roughness,
/// environment and light maps have no direct glTF slot (glTF packs metalness and roughness
/// into the channels of one image) and are left out.
pub const GLTF_PBR_MAPS: [&str; 2] = ["normal_map", "emissive_map"];

/// The texture names a glTF of these meshes embeds: base colours plus [`GLTF_PBR_MAPS`].
pub fn gltf_texture_names<'a>(
    meshes: impl IntoIterator<Item = &'a Mesh>,
) -> std::collections::BTreeSet<String> {
    let mut names = std::collections::BTreeSet::new();
    for m in meshes {
        let maps = m
            .material
            .pbr_maps
            .iter()
            .filter(|(k, _)| GLTF_PBR_MAPS.contains(&k.as_str()))
            .map(|(_, t)| t);
        for t in std::iter::once(&m.material.texture).chain(maps) {
            if !t.is_empty() {
                names.insert(t.clone());
            }
        }
    }
    names
}

fn mesh_extras(level: &str, m: &Mesh) -> serde_json::Value {
    let kind = match m.kind {
        MeshKind::Floor => "floor",
        MeshKind::Ceiling => "ceiling",
        MeshKind::Walls => "walls",
    };
    json!({"level": level, "kind": kind, "mesh": m.name, "texture": m.material.texture})
}

fn raw(v: serde_json::Value) -> json::Extras {
    Some(serde_json::value::to_raw_value(&v).expect("a JSON value serialises"))
}

fn non_empty<T>(v: Vec<T>) -> Option<Vec<T>> {
    (!v.is_empty()).then_some(v)
}

/// Adds a box, axis-aligned in the local frame `f`, to `m`: 4 vertices per face with the face normal,
/// triangles counter-clockwise seen from outside.
fn push_box(m: &mut Mesh, f: &Frame, centre: [f64; 3], half: [f64; 3]) {
    // (normal axis, sign, u axis, v axis) with u × v = sign · normal.
    const FACES: [(usize, f64, usize, usize); 6] = [
        (0, 1.0, 1, 2),
        (0, -1.0, 2, 1),
        (1, 1.0, 2, 0),
        (1, -1.0, 0, 2),
        (2, 1.0, 0, 1),
        (2, -1.0, 1, 0),
    ];
    for (n, s, u, v) in FACES {
        let base = m.positions.len() as u32;
        let mut normal = [0.0; 3];
        normal[n] = s;
        for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let mut p = centre;
            p[n] += s * half[n];
            p[u] += su * half[u];
            p[v] += sv * half[v];
            m.positions.push(f.point(p));
            m.normals.push(f.dir(normal));
            m.uvs.push([(su + 1.0) / 2.0, (sv + 1.0) / 2.0]);
        }
        m.triangles.push([base, base + 1, base + 2]);
        m.triangles.push([base, base + 2, base + 3]);
    }
}

fn colour_mesh(name: &str, material: &str) -> Mesh {
    Mesh {
        name: name.to_string(),
        kind: MeshKind::Walls,
        positions: Vec::new(),
        normals: Vec::new(),
        uvs: Vec::new(),
        triangles: Vec::new(),
        material: Material {
            name: material.to_string(),
            texture: String::new(),
            alpha: 1.0,
            pbr_maps: Vec::new(),
        },
    }
}

/// A placed frame in the map: origin `c`, rotated by yaw about z.
struct Frame {
    c: Vec2,
    sin: f64,
    cos: f64,
}

impl Frame {
    fn new(c: Vec2, yaw: f64) -> Self {
        let (sin, cos) = yaw.sin_cos();
        Frame { c, sin, cos }
    }
    fn dir(&self, p: [f64; 3]) -> [f64; 3] {
        [
            self.cos * p[0] - self.sin * p[1],
            self.sin * p[0] + self.cos * p[1],
            p[2],
        ]
    }
    fn point(&self, p: [f64; 3]) -> [f64; 3] {
        let r = self.dir(p);
        [r[0] + self.c.x, r[1] + self.c.y, r[2]]
    }
}

/// The closed leaves of a door (generator.md §2.7): the door frame's +x points from the end
/// vertex to the start vertex.
pub fn door_mesh(b: &Building, d: Handle<mapc_ir::Door>) -> Mesh {
    let door = &b.doors[d];
    let ps = b.vertices[door.start].pos;
    let pe = b.vertices[door.end].pos;
    let len = ps.minus(pe).norm();
    let c = ps.plus(pe).scale(0.5);
    let phi = (ps.y - pe.y).atan2(ps.x - pe.x);
    let r = if door.right_left_ratio.is_finite() && door.right_left_ratio > 0.0 {
        door.right_left_ratio
    } else {
        1.0
    };
    let lr = r / (1.0 + r) * len;
    let ll = len - lr;
    let leaves: Vec<(f64, f64)> = match door.kind {
        DoorKind::DoubleHinged | DoorKind::DoubleSliding => {
            vec![
                (lr - 0.01, len / 2.0 - lr / 2.0),
                (ll - 0.01, -len / 2.0 + ll / 2.0),
            ]
        }
        _ => vec![(len - 0.01, 0.0)],
    };
    let f = Frame::new(c, phi);
    let mut m = colour_mesh(&door.name, "door");
    for (width, x0) in leaves {
        let half = [
            width.max(0.001) / 2.0,
            DOOR_THICKNESS / 2.0,
            DOOR_HEIGHT / 2.0,
        ];
        push_box(&mut m, &f, [x0, 0.0, DOOR_HEIGHT / 2.0 + 0.01], half);
    }
    m
}

/// A lift cabin as a closed box at the lift's pose.
pub fn cabin_mesh(name: &str, pos: Vec2, yaw: f64, width: f64, depth: f64) -> Mesh {
    let f = Frame::new(pos, yaw);
    let mut m = colour_mesh(name, "lift_cabin");
    let half = [
        width.max(0.001) / 2.0,
        depth.max(0.001) / 2.0,
        CABIN_HEIGHT / 2.0,
    ];
    push_box(&mut m, &f, [0.0, 0.0, CABIN_HEIGHT / 2.0], half);
    m
}

/// Builds the JSON document and the binary buffer together.
struct Writer<'t> {
    root: json::Root,
    bin: Vec<u8>,
    textures: &'t Textures,
    offset: Vec2,
    texture_index: BTreeMap<String, json::Index<json::Texture>>,
    material_index: BTreeMap<String, json::Index<json::Material>>,
    sampler: Option<json::Index<json::texture::Sampler>>,
}

impl<'t> Writer<'t> {
    fn new(textures: &'t Textures, offset: Vec2) -> Self {
        let root = json::Root {
            asset: json::Asset {
                generator: Some(format!("mapc {}", env!("CARGO_PKG_VERSION"))),
                ..Default::default()
            },
            ..Default::default()
        };
        Writer {
            root,
            bin: Vec::new(),
            textures,
            offset,
            texture_index: BTreeMap::new(),
            material_index: BTreeMap::new(),
            sampler: None,
        }
    }

    fn node(&mut self, n: json::Node) -> json::Index<json::Node> {
        self.root.push(n)
    }

    /// Appends `bytes` (4-byte aligned) as a buffer view.
    fn view(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: None,
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        target: json::buffer::Target,
        min: Option<serde_json::Value>,
        max: Option<serde_json::Value>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(bytes, Some(target));
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: None,
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    fn texture(&mut self, name: &str) -> Option<json::Index<json::Texture>> {
        if let Some(&i) = self.texture_index.get(name) {
            return Some(i);
        }
        let image = self.textures.get(name)?;
        // Only the chunks that define the pixels (glTF §3.8.4.3; see `strip_png`).
        let png = crate::texture::strip_png(&image.png);
        let view = self.view(&png, None);
        let image = self.root.push(json::Image {
            buffer_view: Some(view),
            mime_type: Some(json::image::MimeType("image/png".into())),
            name: Some(name.to_string()),
            uri: None,
            extensions: None,
            extras: None,
        });
        let sampler = match self.sampler {
            Some(s) => s,
            None => {
                let s = self.root.push(json::texture::Sampler {
                    mag_filter: Some(Valid(json::texture::MagFilter::Linear)),
                    min_filter: Some(Valid(json::texture::MinFilter::LinearMipmapLinear)),
                    ..Default::default()
                });
                self.sampler = Some(s);
                s
            }
        };
        let t = self.root.push(json::Texture {
            name: Some(name.to_string()),
            sampler: Some(sampler),
            source: image,
            extensions: None,
            extras: None,
        });
        self.texture_index.insert(name.to_string(), t);
        Some(t)
    }

    fn material(&mut self, m: &Material) -> json::Index<json::Material> {
        let alpha = if m.alpha.is_finite() {
            m.alpha.clamp(0.0, 1.0)
        } else {
            1.0
        };
        let key = format!(
            "{}\u{0}{}\u{0}{}\u{0}{:?}",
            m.name,
            m.texture,
            alpha.to_bits(),
            m.pbr_maps
        );
        if let Some(&i) = self.material_index.get(&key) {
            return i;
        }
        let mut rgba = match m.name.as_str() {
            "door" if m.texture.is_empty() => DOOR_RGBA,
            "lift_cabin" if m.texture.is_empty() => CABIN_RGBA,
            _ => [1.0, 1.0, 1.0, 1.0],
        };
        if !m.texture.is_empty() {
            rgba[3] = alpha as f32;
        }
        let base_color_texture = if m.texture.is_empty() {
            None
        } else {
            self.texture(&m.texture).map(|index| json::texture::Info {
                index,
                tex_coord: 0,
                extensions: None,
                extras: None,
            })
        };
        let map = |kind: &str| {
            m.pbr_maps
                .iter()
                .find(|(k, t)| k == kind && !t.is_empty())
                .map(|(_, t)| t.clone())
        };
        let normal_texture = map("normal_map")
            .and_then(|t| self.texture(&t))
            .map(|index| json::material::NormalTexture {
                index,
                scale: 1.0,
                tex_coord: 0,
                extensions: None,
                extras: None,
            });
        let emissive_texture = map("emissive_map")
            .and_then(|t| self.texture(&t))
            .map(|index| json::texture::Info {
                index,
                tex_coord: 0,
                extensions: None,
                extras: None,
            });
        let emissive_factor = if emissive_texture.is_some() {
            [1.0; 3]
        } else {
            [0.0; 3]
        };
        let blend = rgba[3] < 1.0;
        let i = self.root.push(json::Material {
            name: Some(m.name.clone()),
            alpha_mode: Valid(if blend {
                json::material::AlphaMode::Blend
            } else {
                json::material::AlphaMode::Opaque
            }),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(rgba),
                base_color_texture,
                metallic_factor: json::material::StrengthFactor(0.0),
                ..Default::default()
            },
            normal_texture,
            emissive_texture,
            emissive_factor: json::material::EmissiveFactor(emissive_factor),
            extras: if m.texture.is_empty() {
                None
            } else {
                raw(json!({"texture": m.texture}))
            },
            ..Default::default()
        });
        self.material_index.insert(key, i);
        i
    }

    /// A node named after the mesh, with the mesh unless it has no triangles.
    fn mesh_node(&mut self, m: &Mesh, extras: serde_json::Value) -> json::Index<json::Node> {
        let mesh = self.mesh(m);
        self.node(json::Node {
            name: Some(m.name.clone()),
            mesh,
            extras: raw(extras),
            ..Default::default()
        })
    }

    fn mesh(&mut self, m: &Mesh) -> Option<json::Index<json::Mesh>> {
        let n = m.positions.len();
        let tris: Vec<[u32; 3]> = m
            .triangles
            .iter()
            .copied()
            .filter(|t| t.iter().all(|&i| (i as usize) < n))
            .collect();
        if tris.is_empty() {
            return None;
        }
        let (ox, oy) = (self.offset.x, self.offset.y);
        let pos: Vec<[f32; 3]> = m
            .positions
            .iter()
            .map(|p| [(p[0] - ox) as f32, (p[1] - oy) as f32, p[2] as f32])
            .collect();
        let mut lo = pos[0];
        let mut hi = pos[0];
        for p in &pos {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let normals: Vec<[f32; 3]> = (0..n)
            .map(|i| {
                let v = m.normals.get(i).copied().unwrap_or([0.0, 0.0, 1.0]);
                let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                if len.is_finite() && len > 1e-12 {
                    [
                        (v[0] / len) as f32,
                        (v[1] / len) as f32,
                        (v[2] / len) as f32,
                    ]
                } else {
                    [0.0, 0.0, 1.0]
                }
            })
            .collect();
        let uv: Vec<[f64; 2]> = (0..n)
            .map(|i| {
                let t = m.uvs.get(i).copied().unwrap_or([0.0, 0.0]);
                let t = if t[0].is_finite() && t[1].is_finite() {
                    t
                } else {
                    [0.0, 0.0]
                };
                [t[0], 1.0 - t[1]]
            })
            .collect();
        let du = uv
            .iter()
            .map(|t| t[0])
            .fold(f64::INFINITY, f64::min)
            .floor();
        let dv = uv
            .iter()
            .map(|t| t[1])
            .fold(f64::INFINITY, f64::min)
            .floor();
        let uv: Vec<[f32; 2]> = uv
            .iter()
            .map(|t| [(t[0] - du) as f32, (t[1] - dv) as f32])
            .collect();

        use json::accessor::{ComponentType as C, Type as T};
        use json::buffer::Target::{ArrayBuffer, ElementArrayBuffer};
        let a_pos = self.accessor(
            &f32_bytes(pos.iter().flatten()),
            n,
            C::F32,
            T::Vec3,
            ArrayBuffer,
            Some(json!(lo)),
            Some(json!(hi)),
        );
        let a_nrm = self.accessor(
            &f32_bytes(normals.iter().flatten()),
            n,
            C::F32,
            T::Vec3,
            ArrayBuffer,
            None,
            None,
        );
        let a_uv = self.accessor(
            &f32_bytes(uv.iter().flatten()),
            n,
            C::F32,
            T::Vec2,
            ArrayBuffer,
            None,
            None,
        );
        let idx: Vec<u8> = tris
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let a_idx = self.accessor(
            &idx,
            tris.len() * 3,
            C::U32,
            T::Scalar,
            ElementArrayBuffer,
            None,
            None,
        );
        let material = self.material(&m.material);
        let mut attributes = BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), a_pos);
        attributes.insert(Valid(json::mesh::Semantic::Normals), a_nrm);
        attributes.insert(Valid(json::mesh::Semantic::TexCoords(0)), a_uv);
        let has_normal_map = m
            .material
            .pbr_maps
            .iter()
            .any(|(k, t)| k == "normal_map" && self.texture_index.contains_key(t));
        if has_normal_map {
            let t = tangents(&pos, &normals, &uv, &tris);
            let a_tan = self.accessor(
                &f32_bytes(t.iter().flatten()),
                n,
                C::F32,
                T::Vec4,
                ArrayBuffer,
                None,
                None,
            );
            attributes.insert(Valid(json::mesh::Semantic::Tangents), a_tan);
        }
        Some(self.root.push(json::Mesh {
            extensions: None,
            extras: None,
            name: Some(m.name.clone()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: None,
                indices: Some(a_idx),
                material: Some(material),
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        }))
    }

    fn finish(mut self, root_node: json::Index<json::Node>) -> Vec<u8> {
        let scene = self.root.push(json::Scene {
            extensions: None,
            extras: None,
            name: Some("scene".into()),
            nodes: vec![root_node],
        });
        self.root.scene = Some(scene);
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        if !self.bin.is_empty() {
            self.root.push(json::Buffer {
                byte_length: USize64::from(self.bin.len()),
                name: None,
                uri: None,
                extensions: None,
                extras: None,
            });
        }
        let text = self.root.to_vec().expect("a glTF document serialises");
        glb::assemble(&text, &self.bin)
    }
}

/// Per-vertex tangents for normal mapping (Lengyel's method): the direction of increasing
/// u in the surface, made orthogonal to the normal, with w = ±1 the handedness of the
/// (tangent, bitangent, normal) frame. Vertices whose UVs give no direction get any unit
/// vector perpendicular to their normal.
fn tangents(
    pos: &[[f32; 3]],
    normals: &[[f32; 3]],
    uv: &[[f32; 2]],
    tris: &[[u32; 3]],
) -> Vec<[f32; 4]> {
    let n = pos.len();
    let mut tan = vec![[0.0f64; 3]; n];
    let mut bit = vec![[0.0f64; 3]; n];
    let sub = |a: [f32; 3], b: [f32; 3]| {
        [
            f64::from(a[0]) - f64::from(b[0]),
            f64::from(a[1]) - f64::from(b[1]),
            f64::from(a[2]) - f64::from(b[2]),
        ]
    };
    for t in tris {
        let [i0, i1, i2] = t.map(|i| i as usize);
        let e1 = sub(pos[i1], pos[i0]);
        let e2 = sub(pos[i2], pos[i0]);
        let (du1, dv1) = (
            f64::from(uv[i1][0] - uv[i0][0]),
            f64::from(uv[i1][1] - uv[i0][1]),
        );
        let (du2, dv2) = (
            f64::from(uv[i2][0] - uv[i0][0]),
            f64::from(uv[i2][1] - uv[i0][1]),
        );
        let det = du1 * dv2 - du2 * dv1;
        if det.abs() < 1e-20 {
            continue;
        }
        let r = 1.0 / det;
        for k in 0..3 {
            let s = (e1[k] * dv2 - e2[k] * dv1) * r;
            let q = (e2[k] * du1 - e1[k] * du2) * r;
            for i in [i0, i1, i2] {
                tan[i][k] += s;
                bit[i][k] += q;
            }
        }
    }
    (0..n)
        .map(|i| {
            let nv = normals[i].map(f64::from);
            let t = tan[i];
            let d = nv[0] * t[0] + nv[1] * t[1] + nv[2] * t[2];
            let mut o = [t[0] - nv[0] * d, t[1] - nv[1] * d, t[2] - nv[2] * d];
            let mut len = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
            if !(len.is_finite() && len > 1e-12) {
                // Any perpendicular: cross the normal with the axis it is least aligned to.
                let a = if nv[0].abs() < 0.9 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                };
                o = [
                    nv[1] * a[2] - nv[2] * a[1],
                    nv[2] * a[0] - nv[0] * a[2],
                    nv[0] * a[1] - nv[1] * a[0],
                ];
                len = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
            }
            let o = o.map(|c| c / len);
            let c = [
                nv[1] * o[2] - nv[2] * o[1],
                nv[2] * o[0] - nv[0] * o[2],
                nv[0] * o[1] - nv[1] * o[0],
            ];
            let b = bit[i];
            let w = if c[0] * b[0] + c[1] * b[1] + c[2] * b[2] < 0.0 {
                -1.0
            } else {
                1.0
            };
            [o[0] as f32, o[1] as f32, o[2] as f32, w]
        })
        .collect()
}

fn f32_bytes<'a>(values: impl Iterator<Item = &'a f32>) -> Vec<u8> {
    values.flat_map(|v| v.to_le_bytes()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{placeholder_png, TextureImage};
    use mapc_ir::CoordinateSystem;

    fn quad(texture: &str, alpha: f64) -> Mesh {
        Mesh {
            name: "floor_1".into(),
            kind: MeshKind::Floor,
            positions: vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [2.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            normals: vec![[0.0, 0.0, 1.0]; 4],
            uvs: vec![[10.0, 20.0], [12.0, 20.0], [12.0, 21.0], [10.0, 21.0]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            material: Material {
                name: "floor_1".into(),
                texture: texture.into(),
                alpha,
                pbr_maps: Vec::new(),
            },
        }
    }

    fn building() -> Building {
        let mut b = Building::new(
            "b".into(),
            CoordinateSystem::CartesianMeters,
            Default::default(),
        );
        b.levels.append(
            mapc_ir::Level {
                name: "L1".into(),
                elevation: 3.0,
                ..Default::default()
            },
            mapc_ir::Span::default(),
        );
        b
    }

    fn textures() -> Textures {
        let mut t = Textures::default();
        t.images.insert(
            "tiles".into(),
            TextureImage {
                png: placeholder_png(),
                placeholder: true,
            },
        );
        t
    }

    fn parse(glb: &[u8]) -> (serde_json::Value, Vec<u8>) {
        let (j, bin) = glb::split(glb).expect("a GLB");
        (serde_json::from_slice(j).unwrap(), bin.to_vec())
    }

    #[test]
    fn level_glb_holds_the_mesh_and_its_texture() {
        let b = building();
        let h = b.levels.iter().next().unwrap().0;
        let m = quad("tiles", 0.5);
        let glb = level_glb(&b, h, [&m], &textures());
        assert_eq!(glb.len() % 4, 0);
        let (doc, bin) = parse(&glb);
        assert_eq!(doc["nodes"][1]["name"], "b_L1");
        assert_eq!(doc["nodes"][0]["name"], "floor_1");
        let prim = &doc["meshes"][0]["primitives"][0];
        let pos = &doc["accessors"][prim["attributes"]["POSITION"].as_u64().unwrap() as usize];
        assert_eq!(pos["count"], 4);
        assert_eq!(pos["max"], serde_json::json!([2.0, 1.0, 0.0]));
        let mat = &doc["materials"][0];
        assert_eq!(mat["alphaMode"], "BLEND");
        assert_eq!(mat["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
        // UVs are shifted by whole repeats and flipped: u 10..12 → 0..2, v 20..21 → 0..1.
        let uv = &doc["accessors"][prim["attributes"]["TEXCOORD_0"].as_u64().unwrap() as usize];
        let view = &doc["bufferViews"][uv["bufferView"].as_u64().unwrap() as usize];
        let off = view["byteOffset"].as_u64().unwrap() as usize;
        let f: Vec<f32> = bin[off..off + 32]
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(f, [0.0, 1.0, 2.0, 1.0, 2.0, 0.0, 0.0, 0.0]);
        // The image is embedded.
        let img = &doc["images"][0];
        let v = &doc["bufferViews"][img["bufferView"].as_u64().unwrap() as usize];
        let off = v["byteOffset"].as_u64().unwrap() as usize;
        let len = v["byteLength"].as_u64().unwrap() as usize;
        assert_eq!(&bin[off..off + len], placeholder_png().as_slice());
        // Deterministic.
        assert_eq!(glb, level_glb(&b, h, [&m], &textures()));
    }

    #[test]
    fn building_gltf_places_levels_and_offsets_positions() {
        let mut b = building();
        b.offset = Vec2::new(1000.0, 2000.0);
        let h = b.levels.iter().next().unwrap().0;
        let mut m = quad("tiles", 1.0);
        for p in &mut m.positions {
            p[0] += 1000.0;
            p[1] += 2000.0;
        }
        let sets = [LevelMeshSet {
            level: h,
            meshes: vec![&m],
        }];
        let (doc, _) = parse(&building_gltf(&b, &sets, &textures()));
        let root = doc["scenes"][0]["nodes"][0].as_u64().unwrap() as usize;
        assert_eq!(
            doc["nodes"][root]["extras"]["offset"],
            serde_json::json!([1000.0, 2000.0])
        );
        let level = doc["nodes"][root]["children"][0].as_u64().unwrap() as usize;
        assert_eq!(
            doc["nodes"][level]["translation"],
            serde_json::json!([0.0, 0.0, 3.0])
        );
        assert_eq!(doc["materials"][0]["alphaMode"], "OPAQUE");
        let pos = &doc["accessors"][0];
        assert_eq!(pos["min"], serde_json::json!([0.0, 0.0, 0.0]));
    }

    #[test]
    fn normal_and_emissive_maps_are_carried() {
        let b = building();
        let h = b.levels.iter().next().unwrap().0;
        let mut m = quad("tiles", 1.0);
        m.material.pbr_maps = vec![
            ("roughness_map".into(), "rough".into()),
            ("normal_map".into(), "tiles".into()),
            ("emissive_map".into(), "tiles".into()),
        ];
        let names: Vec<String> = gltf_texture_names([&m]).into_iter().collect();
        assert_eq!(names, ["tiles"]);
        let (doc, _) = parse(&level_glb(&b, h, [&m], &textures()));
        let mat = &doc["materials"][0];
        assert_eq!(mat["normalTexture"]["index"], 0);
        assert_eq!(mat["emissiveTexture"]["index"], 0);
        assert_eq!(mat["emissiveFactor"], serde_json::json!([1.0, 1.0, 1.0]));
        assert_eq!(doc["textures"].as_array().unwrap().len(), 1);
        // Normal mapping gets tangents: u grows along +x on this quad.
        let prim = &doc["meshes"][0]["primitives"][0];
        let t = &doc["accessors"][prim["attributes"]["TANGENT"].as_u64().unwrap() as usize];
        assert_eq!(t["type"], "VEC4");
        let pos: Vec<[f32; 3]> = m.positions.iter().map(|p| p.map(|c| c as f32)).collect();
        let nrm = vec![[0.0f32, 0.0, 1.0]; 4];
        let uv = [[0.0f32, 1.0], [2.0, 1.0], [2.0, 0.0], [0.0, 0.0]];
        for tan in tangents(&pos, &nrm, &uv, &m.triangles) {
            assert_eq!(tan, [1.0, 0.0, 0.0, -1.0]);
        }
    }

    #[test]
    fn empty_meshes_become_nodes_without_mesh() {
        let b = building();
        let h = b.levels.iter().next().unwrap().0;
        let mut m = quad("tiles", 1.0);
        m.triangles.clear();
        let (doc, _) = parse(&level_glb(&b, h, [&m], &textures()));
        assert!(doc["nodes"][0]["mesh"].is_null());
        assert!(doc.get("buffers").is_none());
    }

    #[test]
    fn box_faces_point_outwards() {
        let m = cabin_mesh("lift", Vec2::new(5.0, -3.0), 0.7, 2.0, 1.5);
        assert_eq!(m.positions.len(), 24);
        assert_eq!(m.triangles.len(), 12);
        let centre = [5.0, -3.0, CABIN_HEIGHT / 2.0];
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let out = [a[0] - centre[0], a[1] - centre[1], a[2] - centre[2]];
            let dot = n[0] * out[0] + n[1] * out[1] + n[2] * out[2];
            assert!(dot > 0.0, "triangle {t:?} faces inwards");
            let vn = m.normals[t[0] as usize];
            assert!(n[0] * vn[0] + n[1] * vn[1] + n[2] * vn[2] > 0.0);
        }
        let (lo, hi) = m.bounds().unwrap();
        assert!((hi[2] - lo[2] - CABIN_HEIGHT).abs() < 1e-12);
        assert!((m.area() - 2.0 * (2.0 * 1.5 + 2.0 * 2.5 + 1.5 * 2.5)).abs() < 1e-9);
    }
}
