//! Wavefront OBJ + MTL level meshes and the OGRE material script Gazebo classic reads,
//! laid out as the reference lays them out (generator.md §2.1, §2.3.1-2.3.4), relative to
//! the model directory:
//!
//! ```text
//! <building>_<level>/meshes/floor_<n>.obj, floor_<n>.mtl, [ceiling_<n>.obj, ceiling_<n>.mtl]
//!                          wall_<k>.obj, wall_<k>.mtl, model.material
//! ```
//!
//! Numbers are written as the reference writes them: floors and ceilings with Python `str`,
//! walls with four decimals. Positions have `Building::offset` subtracted, as everything in
//! a world should be (generator.md quirk 1: the reference shifts level meshes only in wgs84
//! maps, so a cartesian map with an offset gets its meshes away from its models there); wall
//! meshes are further written relative to their origin [`wall_origin`], which the level's
//! `model.sdf` gives the wall link as its pose. Floor UVs are map-frame metres / scale as in
//! the reference, rotated by `texture_rotation` (see `geometry`).
//!
//! Layout: walls and floors are written line for line as the reference writes them (8 `v`
//! and `vt` per wall, the same faces; top/bottom `v` pairs and one `vt` per floor point, the
//! polygon's own points first when nothing cuts it), except that the end faces of walls get
//! their outward normals (the reference swaps them) and floor triangles come from our
//! triangulation. `tests/meshes.rs` checks our wall OBJ files against the reference's line
//! by line. `model.material` is written fresh rather than appended to.

use crate::fmt::{push_fixed, push_py_float};
use crate::geometry::{level_meshes, LevelMeshes};
use crate::mesh::{Mesh, MeshKind};
use crate::{py_float, OutputFile};
use mapc_ir::{Building, Handle, Level, ParamValue, Vec2};
use std::collections::HashMap;
use std::fmt::Write;
use std::path::PathBuf;

const HEADER: &str = "# The Great Editor v0.0.1\n";

/// OBJ/MTL files and `model.material` of `level`, under `<building>_<level>/meshes/`.
/// A level without floors and walls has no files (the reference creates no `meshes/`).
pub fn level_obj_files(b: &Building, level: Handle<Level>) -> Vec<OutputFile> {
    let meshes = level_meshes(b, level);
    level_obj_files_from(b, level, &meshes)
}

/// As [`level_obj_files`], from meshes already computed.
pub fn level_obj_files_from(
    b: &Building,
    level: Handle<Level>,
    meshes: &LevelMeshes,
) -> Vec<OutputFile> {
    let objs = meshes.all().map(|m| mesh_obj(m, b.offset)).collect();
    level_obj_files_with(b, level, meshes, objs)
}

/// As [`level_obj_files_from`], with the OBJ text of each mesh already made: `objs[i]` is
/// [`mesh_obj`] of the i-th mesh of `meshes.all()`.
pub(crate) fn level_obj_files_with(
    b: &Building,
    level: Handle<Level>,
    meshes: &LevelMeshes,
    objs: Vec<String>,
) -> Vec<OutputFile> {
    if meshes.is_empty() {
        return Vec::new();
    }
    let dir = PathBuf::from(format!("{}_{}", b.name, b.levels[level].name)).join("meshes");
    let alphas = wall_alpha_texts(b, level);
    let mut out = Vec::new();
    let ordered: Vec<&Mesh> = meshes.all().collect();
    debug_assert_eq!(ordered.len(), objs.len());
    for (m, obj) in ordered.iter().zip(objs) {
        out.push(OutputFile {
            path: dir.join(format!("{}.obj", m.name)),
            contents: obj.into_bytes(),
        });
        let d = match m.kind {
            MeshKind::Walls => alphas
                .get(&m.name)
                .cloned()
                .unwrap_or_else(|| py_float(m.material.alpha)),
            _ => "1.0".to_string(),
        };
        out.push(OutputFile {
            path: dir.join(format!("{}.mtl", m.name)),
            contents: mesh_mtl(m, &d).into_bytes(),
        });
    }
    out.push(OutputFile {
        path: dir.join("model.material"),
        contents: model_material(ordered.iter().copied()).into_bytes(),
    });
    out
}

/// The texture images the level's meshes refer to, once per level model, as
/// `<building>_<level>/meshes/<file>` (the file names the MTL files, `model.material` and
/// model.sdf use), including PBR maps. Images come from `textures` (see
/// [`crate::resolve_textures`]: a texture not found is the placeholder, with a warning). A
/// name that cannot be a plain file name is skipped: it has its own warning and writing it
/// could leave the output directory.
pub fn level_texture_files(
    b: &Building,
    level: Handle<Level>,
    meshes: &LevelMeshes,
    textures: &crate::Textures,
) -> Vec<OutputFile> {
    level_texture_paths(b, level, meshes)
        .into_iter()
        .filter_map(|(path, name)| {
            textures.get(name).map(|image| OutputFile {
                path,
                contents: image.png.clone(),
            })
        })
        .collect()
}

/// Where [`level_texture_files`] puts each texture of the level, without the images:
/// (path, texture name) for every plain name, in file-name order. A caller that has the
/// image on disk can link it there instead of copying its bytes.
pub fn level_texture_paths<'m>(
    b: &Building,
    level: Handle<Level>,
    meshes: &'m LevelMeshes,
) -> Vec<(PathBuf, &'m str)> {
    let dir = PathBuf::from(format!("{}_{}", b.name, b.levels[level].name)).join("meshes");
    let mut names = std::collections::BTreeSet::new();
    for m in meshes.all() {
        names.insert(m.material.texture.as_str());
        for (_, t) in &m.material.pbr_maps {
            names.insert(t.as_str());
        }
    }
    let mut out = Vec::new();
    for name in names {
        let file = obj_texture_file(name);
        let plain = !file.is_empty()
            && file != "."
            && file != ".."
            && !file.contains(['/', '\\', '\0', ':']);
        if plain {
            out.push((dir.join(file), name));
        }
    }
    out
}

/// `d` of each wall group's MTL: the alpha as the YAML wrote it (`1` for `[3, 1]`,
/// `0.8` for `[3, 0.80000000000000004]`).
fn wall_alpha_texts(b: &Building, level: Handle<Level>) -> HashMap<String, String> {
    crate::geometry::wall_groups(b, level)
        .iter()
        .enumerate()
        .map(|(i, g)| {
            // The group's map is its first wall's; without `alpha` the reference adds 1.0.
            let written = b.walls[g.walls[0]].params.get("alpha");
            let text = match written {
                Some(ParamValue::Int(i)) => i.to_string(),
                // The IR keeps `[3, 1]` as 1.0; YAML maps write integral alphas as ints.
                Some(ParamValue::Double(d)) if d.fract() == 0.0 && d.abs() < 1e15 => {
                    format!("{}", *d as i64)
                }
                Some(ParamValue::Double(d)) => py_float(*d),
                Some(ParamValue::String(s)) => s.clone(),
                Some(ParamValue::Bool(v)) => if *v { "True" } else { "False" }.to_string(),
                None => "1.0".to_string(),
            };
            (format!("wall_{}", i + 1), text)
        })
        .collect()
}

/// Origin of a wall mesh in the OBJ: the minimum x and y of its vertices after subtracting
/// `offset` (the link pose of `wall_<k>` in `model.sdf`).
pub fn wall_origin(mesh: &Mesh, offset: Vec2) -> [f64; 2] {
    match mesh.bounds() {
        Some((lo, _)) => [lo[0] - offset.x, lo[1] - offset.y],
        None => [0.0, 0.0],
    }
}

/// The OBJ text of `mesh`, positions minus `offset` (and, for walls, minus their origin).
/// Wall and floor meshes in the layout `geometry` builds are written in the reference's
/// layout (8 `v`/`vt` per wall, top/bottom `v` pairs per floor point); anything else
/// vertex by vertex.
pub fn mesh_obj(mesh: &Mesh, offset: Vec2) -> String {
    match mesh.kind {
        MeshKind::Walls if is_wall_layout(mesh) => walls_obj(mesh, offset),
        MeshKind::Floor if is_slab_layout(mesh) => floor_obj(mesh, offset),
        _ => generic_obj(mesh, offset),
    }
}

fn is_wall_layout(m: &Mesh) -> bool {
    let n = m.positions.len();
    n % 20 == 0 && m.normals.len() == n && m.uvs.len() == n && m.triangles.len() * 2 == n
}

/// Top points, then the same points below, top triangles then the bottom ones reversed.
fn is_slab_layout(m: &Mesh) -> bool {
    let n = m.positions.len();
    let t = m.triangles.len();
    if n % 2 != 0 || t % 2 != 0 || m.uvs.len() != n || m.normals.len() != n {
        return false;
    }
    let (np, nt) = (n / 2, t / 2);
    (0..np).all(|i| {
        let (a, b) = (m.positions[i], m.positions[np + i]);
        a[0] == b[0] && a[1] == b[1] && a[2] == 0.0
    }) && (0..nt).all(|i| {
        let [a, b, c] = m.triangles[i];
        let o = np as u32;
        m.triangles[nt + i] == [c + o, b + o, a + o]
    })
}

/// `{:.4}`, but a zero as `0.000` (the reference's literal for u = 0 and v = 0).
fn fixed4(out: &mut String, v: f64) {
    if v == 0.0 {
        out.push_str("0.000");
    } else {
        push_fixed(out, v, 4);
    }
}

/// `{:.4}` (see [`push_fixed`]).
fn f4(out: &mut String, v: f64) {
    push_fixed(out, v, 4);
}

/// `vn x y z` with four decimals.
fn vn4(out: &mut String, n: [f64; 3]) {
    out.push_str("vn ");
    f4(out, n[0]);
    out.push(' ');
    f4(out, n[1]);
    out.push(' ');
    f4(out, n[2]);
    out.push('\n');
}

/// An OBJ index (itoa: `Display` through `fmt::write` was a tenth of a mesh's time).
fn int(out: &mut String, v: usize) {
    out.push_str(itoa::Buffer::new().format(v));
}

/// `f a/a/n b/b/n c/c/n`, the face line of a wall triangle.
fn face_same(out: &mut String, v: [usize; 3], n: [usize; 3]) {
    out.push('f');
    for k in 0..3 {
        out.push(' ');
        int(out, v[k]);
        out.push('/');
        int(out, v[k]);
        out.push('/');
        int(out, n[k]);
    }
    out.push('\n');
}

/// Walls as the reference writes them (generator.md §2.3.4), with the correct normals on
/// the end faces: `vn` 1 is up, then per wall the outward normals of faces C0–C1, C1–C2,
/// C2–C3, C3–C0 (the reference lists R(ψ)·(−1,0) second and R(ψ)·(1,0) fourth).
fn walls_obj(mesh: &Mesh, offset: Vec2) -> String {
    let o = wall_origin(mesh, offset);
    let shift = [o[0] + offset.x, o[1] + offset.y];
    let walls = mesh.positions.len() / 20;
    let mut s = String::with_capacity(walls * 700 + 128);
    s.push_str(HEADER);
    let _ = writeln!(s, "mtllib {}.mtl", mesh.name);
    s.push_str("o walls\n");
    // (face, vertex) of C0b, C0t, C1b, C1t, C2b, C2t, C3b, C3t in the mesh layout.
    const CORNERS: [(usize, usize); 8] = [
        (0, 0),
        (0, 3),
        (0, 1),
        (0, 2),
        (1, 1),
        (1, 2),
        (2, 1),
        (2, 2),
    ];
    for w in 0..walls {
        for (face, k) in CORNERS {
            let p = mesh.positions[20 * w + 4 * face + k];
            v4(&mut s, p[0] - shift[0], p[1] - shift[1], p[2]);
        }
    }
    for w in 0..walls {
        for (face, k) in CORNERS {
            let t = mesh.uvs[20 * w + 4 * face + k];
            vt4(&mut s, t);
        }
    }
    s.push_str("vn 0.0000 0.0000 1.0000\n");
    for w in 0..walls {
        for face in 0..4 {
            vn4(&mut s, mesh.normals[20 * w + 4 * face]);
        }
    }
    let _ = writeln!(s, "usemtl {}", mesh.name);
    s.push_str("s off\ng walls\n");
    for w in 0..walls {
        let (b, n) = (8 * w, 4 * w);
        let faces: [([usize; 3], [usize; 3], usize); 4] = [
            ([1, 2, 3], [4, 3, 2], 2),
            ([3, 4, 5], [6, 5, 4], 3),
            ([5, 6, 7], [8, 7, 6], 4),
            ([7, 8, 1], [2, 1, 8], 5),
        ];
        for (t1, t2, vn) in faces {
            for t in [t1, t2] {
                let [x, y, z] = t.map(|i| b + i);
                face_same(&mut s, [x, y, z], [n + vn; 3]);
            }
        }
        for [x, y, z] in [[b + 2, b + 6, b + 4], [b + 2, b + 8, b + 6]] {
            s.push('f');
            for v in [x, y, z] {
                s.push(' ');
                int(&mut s, v);
                s.push_str("/1/1");
            }
            s.push('\n');
        }
    }
    s
}

/// A floor slab as the reference writes it (generator.md §2.3.2 step 5): per point a top
/// and a bottom `v`, one `vt`, normals 1 (up) and 2 (down), per triangle its top face and
/// its reversed bottom face.
fn floor_obj(mesh: &Mesh, offset: Vec2) -> String {
    let np = mesh.positions.len() / 2;
    let nt = mesh.triangles.len() / 2;
    let mut s = String::with_capacity(np * 120 + nt * 80 + 128);
    s.push_str(HEADER);
    let _ = writeln!(s, "mtllib {}.mtl", mesh.name);
    let _ = writeln!(s, "o {}", mesh.name);
    // Pushed piece by piece: `writeln!` of `py_float` texts was most of a floor's time.
    // `x y ` of a top vertex and the bottom one below it, formatted once.
    let mut xy = String::with_capacity(48);
    for i in 0..np {
        let (top, bottom) = (mesh.positions[i], mesh.positions[np + i]);
        xy.clear();
        push_py_float(&mut xy, top[0] - offset.x);
        xy.push(' ');
        push_py_float(&mut xy, top[1] - offset.y);
        xy.push(' ');
        for z in [top[2], bottom[2]] {
            s.push_str("v ");
            s.push_str(&xy);
            push_short(&mut s, z);
            s.push('\n');
        }
    }
    for t in &mesh.uvs[..np] {
        vt_py(&mut s, *t);
    }
    s.push_str("vn 0 0 1\nvn 0 0 -1\n");
    let _ = writeln!(s, "usemtl {}", mesh.name);
    s.push_str("s off\n");
    for t in &mesh.triangles[..nt] {
        let [a, b, c] = t.map(|i| i as usize);
        // `f v/vt/1 ...` (top, normal 1) and the bottom reversed (normal 2).
        for (k, side) in [(1, [a, b, c]), (2, [c, b, a])] {
            s.push('f');
            for i in side {
                s.push(' ');
                int(&mut s, 2 * i + k);
                s.push('/');
                int(&mut s, i + 1);
                s.push_str(if k == 1 { "/1" } else { "/2" });
            }
            s.push('\n');
        }
    }
    s
}

/// Any mesh, one `v`/`vt` per vertex and the distinct normals.
fn generic_obj(mesh: &Mesh, offset: Vec2) -> String {
    let walls = mesh.kind == MeshKind::Walls;
    // Written coordinate = map frame − offset − (for walls) the wall origin.
    let shift = if walls {
        let o = wall_origin(mesh, offset);
        [o[0] + offset.x, o[1] + offset.y]
    } else {
        [offset.x, offset.y]
    };
    let mut s = String::with_capacity(64 * mesh.positions.len() + 48 * mesh.triangles.len());
    s.push_str(HEADER);
    let _ = writeln!(s, "mtllib {}.mtl", mesh.name);
    let _ = writeln!(s, "o {}", if walls { "walls" } else { &mesh.name });
    for p in &mesh.positions {
        let (x, y) = (p[0] - shift[0], p[1] - shift[1]);
        if walls {
            v4(&mut s, x, y, p[2]);
        } else {
            s.push_str("v ");
            push_py_float(&mut s, x);
            s.push(' ');
            push_py_float(&mut s, y);
            s.push(' ');
            push_short(&mut s, p[2]);
            s.push('\n');
        }
    }
    for t in &mesh.uvs {
        if walls {
            vt4(&mut s, *t);
        } else {
            vt_py(&mut s, *t);
        }
    }
    // Distinct normals in order of first use.
    let mut normal_index: HashMap<[u64; 3], usize> = HashMap::new();
    let mut vn = Vec::with_capacity(mesh.normals.len());
    for n in &mesh.normals {
        let key = n.map(|c| (c + 0.0).to_bits());
        let next = normal_index.len() + 1;
        let i = *normal_index.entry(key).or_insert_with(|| {
            if walls {
                vn4(&mut s, *n);
            } else {
                s.push_str("vn");
                for c in n {
                    s.push(' ');
                    push_short(&mut s, *c);
                }
                s.push('\n');
            }
            next
        });
        vn.push(i);
    }
    let _ = writeln!(s, "usemtl {}", mesh.name);
    s.push_str("s off\n");
    if walls {
        s.push_str("g walls\n");
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i as usize);
        face_same(&mut s, [a + 1, b + 1, c + 1], [vn[a], vn[b], vn[c]]);
    }
    s
}

/// `v x y z` of a wall: x and y as `f4`, z to four places.
fn v4(out: &mut String, x: f64, y: f64, z: f64) {
    out.push_str("v ");
    f4(out, x);
    out.push(' ');
    f4(out, y);
    out.push(' ');
    fixed4(out, z);
    out.push('\n');
}

/// `vt u v` of a wall, to four places.
fn vt4(out: &mut String, t: [f64; 2]) {
    out.push_str("vt ");
    fixed4(out, t[0]);
    out.push(' ');
    fixed4(out, t[1]);
    out.push('\n');
}

/// `vt u v 0` of a floor or another mesh, as Python prints floats.
fn vt_py(out: &mut String, t: [f64; 2]) {
    out.push_str("vt ");
    push_py_float(out, t[0]);
    out.push(' ');
    push_py_float(out, t[1]);
    out.push_str(" 0\n");
}

/// Integral values without a fraction (`0`, `-1`, as the reference writes z and normals of
/// floors), others as Python `str`.
fn push_short(out: &mut String, x: f64) {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        out.push_str(itoa::Buffer::new().format(x as i64));
    } else {
        push_py_float(out, x);
    }
}

/// The MTL text of `mesh` with opacity text `d`.
pub fn mesh_mtl(mesh: &Mesh, d: &str) -> String {
    format!(
        "{HEADER}newmtl {}\nKa 1.0 1.0 1.0\nKd 1.0 1.0 1.0\nKe 0.0 0.0 0.0\nNs 50.0\nNi 1.0\nd {d}\nillum 2\nmap_Kd {}\n",
        mesh.name,
        obj_texture_file(&mesh.material.texture)
    )
}

/// The OGRE-1 material script: one `<name>_Diffuse` material per mesh.
pub fn model_material<'a>(meshes: impl IntoIterator<Item = &'a Mesh>) -> String {
    let mut s = String::new();
    for m in meshes {
        let _ = write!(
            s,
            "material {}_Diffuse\n{{\n\ttechnique\n\t{{\n\t\tpass\n\t\t{{\n\t\t\ttexture_unit\n\t\t\t{{\n\t\t\t\ttexture {}\n\t\t\t}}\n\t\t}}\n\t}}\n}}\n",
            m.name,
            obj_texture_file(&m.material.texture)
        );
    }
    s
}

/// File name of a texture as the meshes refer to it: `<name>.png`, or the last path segment
/// of a URL (as the reference names downloaded textures).
pub(crate) fn obj_texture_file(name: &str) -> String {
    if let Some(f) = crate::texture_file_name(name) {
        return f;
    }
    if crate::is_url(name) {
        if let Some(last) = name.rsplit('/').next().filter(|l| !l.is_empty()) {
            return last.to_string();
        }
    }
    format!("{name}.png")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Material;

    fn tri(kind: MeshKind, name: &str) -> Mesh {
        Mesh {
            name: name.into(),
            kind,
            positions: vec![[1.0, 2.0, 0.0], [3.0, 2.0, 0.0], [3.0, 4.5, 2.5]],
            normals: vec![[0.0, 0.0, 1.0]; 3],
            uvs: vec![[1.0, 2.0], [3.0, 2.0], [3.0, 4.5]],
            triangles: vec![[0, 1, 2]],
            material: Material {
                name: name.into(),
                texture: "blue_linoleum".into(),
                alpha: 1.0,
                pbr_maps: Vec::new(),
            },
        }
    }

    #[test]
    fn floor_obj_uses_python_numbers() {
        let s = mesh_obj(&tri(MeshKind::Floor, "floor_1"), Vec2::default());
        assert!(s.starts_with("# The Great Editor v0.0.1\nmtllib floor_1.mtl\no floor_1\n"));
        assert!(s.contains("\nv 1.0 2.0 0\n"));
        assert!(s.contains("\nv 3.0 4.5 2.5\n"));
        assert!(s.contains("\nvt 3.0 4.5 0\n"));
        assert!(s.contains("\nvn 0 0 1\nusemtl floor_1\ns off\nf 1/1/1 2/2/1 3/3/1\n"));
    }

    #[test]
    fn wall_obj_is_relative_to_its_origin() {
        let m = tri(MeshKind::Walls, "wall_2");
        assert_eq!(wall_origin(&m, Vec2::new(1.0, 0.0)), [0.0, 2.0]);
        let s = mesh_obj(&m, Vec2::new(1.0, 0.0));
        assert!(s.contains(
            "\no walls\nv 0.0000 0.0000 0.000\nv 2.0000 0.0000 0.000\nv 2.0000 2.5000 2.5000\n"
        ));
        assert!(s.contains("\nvt 1.0000 2.0000\n"));
        assert!(s.contains("\nvn 0.0000 0.0000 1.0000\nusemtl wall_2\ns off\ng walls\n"));
    }

    #[test]
    fn mtl_and_material_script() {
        let m = tri(MeshKind::Floor, "floor_1");
        assert_eq!(
            mesh_mtl(&m, "1.0"),
            "# The Great Editor v0.0.1\nnewmtl floor_1\nKa 1.0 1.0 1.0\nKd 1.0 1.0 1.0\nKe 0.0 0.0 0.0\nNs 50.0\nNi 1.0\nd 1.0\nillum 2\nmap_Kd blue_linoleum.png\n"
        );
        assert_eq!(
            model_material([&m]),
            "material floor_1_Diffuse\n{\n\ttechnique\n\t{\n\t\tpass\n\t\t{\n\t\t\ttexture_unit\n\t\t\t{\n\t\t\t\ttexture blue_linoleum.png\n\t\t\t}\n\t\t}\n\t}\n}\n"
        );
        assert_eq!(obj_texture_file("https://x.org/t/wood.png"), "wood.png");
    }

    #[test]
    fn textures_are_written_once_per_level_model_and_never_escape() {
        use crate::{TextureImage, Textures};
        let mut b = Building::new(
            "b".into(),
            mapc_ir::CoordinateSystem::CartesianMeters,
            mapc_ir::Params::default(),
        );
        let l = b.levels.append(
            mapc_ir::Level {
                name: "L1".into(),
                ..mapc_ir::Level::default()
            },
            mapc_ir::Span::UNKNOWN,
        );
        let mut floor = tri(MeshKind::Floor, "floor_1");
        floor.material.texture = "blue_linoleum".into();
        floor.material.pbr_maps = vec![("normal_map".into(), "bumps".into())];
        let mut wall = tri(MeshKind::Walls, "wall_1");
        wall.material.texture = "blue_linoleum".into();
        let mut bad = tri(MeshKind::Walls, "wall_2");
        bad.material.texture = "../../etc/x".into();
        let meshes = LevelMeshes {
            floors: vec![floor],
            ceilings: vec![],
            walls: vec![wall, bad],
        };
        let img = |n: u8| TextureImage {
            png: vec![n],
            placeholder: false,
        };
        let textures = Textures {
            images: [
                ("blue_linoleum".to_string(), img(1)),
                ("bumps".to_string(), img(2)),
                ("../../etc/x".to_string(), img(3)),
            ]
            .into_iter()
            .collect(),
        };
        let files = level_texture_files(&b, l, &meshes, &textures);
        let paths: Vec<String> = files.iter().map(|f| f.path.display().to_string()).collect();
        assert_eq!(
            paths,
            ["b_L1/meshes/blue_linoleum.png", "b_L1/meshes/bumps.png"]
        );
        assert_eq!(files[0].contents, vec![1]);
    }
}

#[cfg(test)]
mod layout_tests {
    use super::*;
    use crate::geometry::tests::{param, Map};
    use mapc_ir::ParamValue;

    #[test]
    fn wall_obj_in_the_reference_layout_with_outward_end_normals() {
        let mut m = Map::new();
        m.wall((0.0, 0.0), (4.0, 0.0), vec![]);
        let walls = m.meshes().walls;
        let s = mesh_obj(&walls[0], Vec2::default());
        let expected = "# The Great Editor v0.0.1
mtllib wall_1.mtl
o walls
v 0.0000 0.1000 0.000
v 0.0000 0.1000 2.5000
v 4.1000 0.1000 0.000
v 4.1000 0.1000 2.5000
v 4.1000 0.0000 0.000
v 4.1000 0.0000 2.5000
v 0.0000 0.0000 0.000
v 0.0000 0.0000 2.5000
vt 0.000 0.000
vt 0.000 1.0000
vt 4.0000 0.000
vt 4.0000 1.0000
vt 4.1000 0.000
vt 4.1000 1.0000
vt 8.1000 0.000
vt 8.1000 1.0000
vn 0.0000 0.0000 1.0000
vn -0.0000 1.0000 0.0000
vn 1.0000 0.0000 0.0000
vn 0.0000 -1.0000 0.0000
vn -1.0000 -0.0000 0.0000
usemtl wall_1
s off
g walls
f 1/1/2 2/2/2 3/3/2
f 4/4/2 3/3/2 2/2/2
f 3/3/3 4/4/3 5/5/3
f 6/6/3 5/5/3 4/4/3
f 5/5/4 6/6/4 7/7/4
f 8/8/4 7/7/4 6/6/4
f 7/7/5 8/8/5 1/1/5
f 2/2/5 1/1/5 8/8/5
f 2/1/1 6/1/1 4/1/1
f 2/1/1 8/1/1 6/1/1
";
        assert_eq!(s, expected);
        let mtl = level_obj_files(&m.b, m.level);
        let mtl = mtl.iter().find(|f| f.path.ends_with("wall_1.mtl")).unwrap();
        assert!(std::str::from_utf8(&mtl.contents)
            .unwrap()
            .contains("\nd 1.0\n"));
    }

    #[test]
    fn floor_obj_in_the_reference_layout() {
        let mut m = Map::new();
        m.floor(
            &[(0.0, 0.0), (2.0, 0.0), (2.0, 1.5)],
            vec![param("texture_scale", ParamValue::Double(2.0))],
        );
        let floors = m.meshes().floors;
        let s = mesh_obj(&floors[0], Vec2::new(1.0, 0.0));
        let expected = "# The Great Editor v0.0.1
mtllib floor_1.mtl
o floor_1
v -1.0 0.0 0
v -1.0 0.0 -0.1
v 1.0 0.0 0
v 1.0 0.0 -0.1
v 1.0 1.5 0
v 1.0 1.5 -0.1
vt 0.0 0.0 0
vt 1.0 0.0 0
vt 1.0 0.75 0
vn 0 0 1
vn 0 0 -1
usemtl floor_1
s off
";
        assert!(s.starts_with(expected), "{s}");
        let faces: Vec<&str> = s.lines().filter(|l| l.starts_with("f ")).collect();
        assert_eq!(faces.len(), 2);
        // Bottom face: the top's corners reversed, on the bottom vertices.
        let top: Vec<&str> = faces[0][2..].split(' ').collect();
        let bottom: Vec<&str> = faces[1][2..].split(' ').collect();
        for (t, b) in top.iter().zip(bottom.iter().rev()) {
            let t: Vec<usize> = t.split('/').map(|x| x.parse().unwrap()).collect();
            let b: Vec<usize> = b.split('/').map(|x| x.parse().unwrap()).collect();
            assert_eq!((t[0] + 1, t[1], t[2], b[2]), (b[0], b[1], 1, 2));
        }
    }
}
