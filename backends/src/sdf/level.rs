//! Level models (generator.md §2.2-2.3): `<building>_<level>/model.sdf` with a static model
//! of `floor_<n>`, `ceiling_<n>` and `wall_<k>` links (visual with the material block, mesh
//! collision), `model.config`, and the meshes and textures the OBJ writer produces. The
//! files are identical for the three flavours (§3: `diff -r` of the reference model dirs is
//! empty).

use super::xml::Element;
use crate::geometry::LevelMeshes;
use crate::mesh::{Mesh, MeshKind};
use crate::obj::obj_texture_file;
use crate::{py_float, wall_origin, OutputFile, Textures};
use mapc_ir::{Building, Handle, Level};
use std::path::PathBuf;

/// `<building>_<level>`: the level model's name and directory.
pub fn level_model_name(b: &Building, level: Handle<Level>) -> String {
    format!("{}_{}", b.name, b.levels[level].name)
}

/// The level's `model.config` (§2.2).
pub fn level_model_config(b: &Building, level: Handle<Level>) -> Element {
    let name = level_model_name(b, level);
    Element::new("model")
        .leaf("name", name.clone())
        .leaf("version", "1.0.0")
        .child(Element::new("sdf").attr("version", "1.6").text("model.sdf"))
        .child(
            Element::new("author")
                .leaf("name", "automatically generated from the Great Editor")
                .leaf("email", "info@openrobotics.org"),
        )
        .leaf(
            "description",
            format!("level {name} (automatically generated)"),
        )
}

/// The level's `model.sdf` (§2.3): a static model with one link per mesh, floors and their
/// ceilings in floor order, then walls. A level without meshes has only `<static>`.
pub fn level_model_sdf(b: &Building, level: Handle<Level>, meshes: &LevelMeshes) -> Element {
    let name = level_model_name(b, level);
    let mut model = Element::new("model")
        .attr("name", name.clone())
        .leaf("static", "true");
    for m in meshes.all() {
        model.push(mesh_link(b, &name, m));
    }
    Element::new("sdf").attr("version", "1.7").child(model)
}

fn mesh_uri(model: &str, mesh: &Mesh) -> Element {
    Element::new("geometry").child(
        Element::new("mesh").leaf("uri", format!("model://{model}/meshes/{}.obj", mesh.name)),
    )
}

fn mesh_link(b: &Building, model: &str, m: &Mesh) -> Element {
    let wall = m.kind == MeshKind::Walls;
    let visual_name = if wall { m.name.as_str() } else { "visual" };
    let mut visual = Element::new("visual")
        .attr("name", visual_name.to_owned())
        .child(mesh_uri(model, m));
    if wall {
        visual = visual.leaf("transparency", py_float(1.0 - m.material.alpha));
    }
    let visual = visual.child(material(model, m));
    let collision = Element::new("collision")
        .attr("name", "collision")
        .child(mesh_uri(model, m))
        .child(
            Element::new("surface").child(Element::new("contact").leaf("collide_bitmask", "0x01")),
        );
    let mut link = Element::new("link")
        .attr("name", m.name.clone())
        .child(visual)
        .child(collision);
    if wall {
        let [x, y] = wall_origin(m, b.offset);
        link = link.leaf("pose", format!("{} {} 0 0 0 0", py_float(x), py_float(y)));
    }
    link
}

/// The material block (§2.3.1): diffuse/specular, PBR albedo and extra maps, OGRE script.
fn material(model: &str, m: &Mesh) -> Element {
    let tex = |name: &str| format!("model://{model}/meshes/{}", obj_texture_file(name));
    let mut metal = Element::new("metal")
        .leaf("metalness", "0.0")
        .leaf("albedo_map", tex(&m.material.texture));
    for (kind, t) in &m.material.pbr_maps {
        let mut e = Element::new(kind.clone()).text(tex(t));
        if kind == "light_map" {
            e = e.attr("uv_set", "1");
        }
        metal.push(e);
    }
    Element::new("material")
        .leaf("diffuse", "1.0 1.0 1.0")
        .leaf("specular", "0.1 0.1 0.1")
        .child(Element::new("pbr").child(metal))
        .child(
            Element::new("script")
                .leaf("uri", format!("model://{model}/meshes/"))
                .leaf("name", format!("{}_Diffuse", m.name)),
        )
}

/// Every file of the level model under `<building>_<level>/`: `model.sdf`, `model.config`,
/// the OBJ/MTL meshes, `model.material` and the textures.
pub fn level_model_files(
    b: &Building,
    level: Handle<Level>,
    meshes: &LevelMeshes,
    textures: &Textures,
) -> Vec<OutputFile> {
    let mut out = level_model_files_untextured(b, level, meshes);
    out.extend(crate::level_texture_files(b, level, meshes, textures));
    out
}

/// [`level_model_files`] without the texture images (see [`crate::level_texture_paths`]).
pub fn level_model_files_untextured(
    b: &Building,
    level: Handle<Level>,
    meshes: &LevelMeshes,
) -> Vec<OutputFile> {
    let objs = meshes.all().map(|m| crate::mesh_obj(m, b.offset)).collect();
    level_model_files_with(b, level, meshes, objs)
}

/// As [`level_model_files_untextured`], with the OBJ text of each mesh already made (see
/// [`crate::obj::level_obj_files_with`]).
pub(crate) fn level_model_files_with(
    b: &Building,
    level: Handle<Level>,
    meshes: &LevelMeshes,
    objs: Vec<String>,
) -> Vec<OutputFile> {
    let dir = PathBuf::from(level_model_name(b, level));
    let mut out = vec![
        OutputFile {
            path: dir.join("model.config"),
            contents: level_model_config(b, level).to_document(true).into_bytes(),
        },
        OutputFile {
            path: dir.join("model.sdf"),
            contents: level_model_sdf(b, level, meshes)
                .to_document(true)
                .into_bytes(),
        },
    ];
    out.extend(crate::obj::level_obj_files_with(b, level, meshes, objs));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use mapc_ir::{CoordinateSystem, Params, Span};

    #[test]
    fn config_and_empty_level() {
        let mut b = Building::new(
            "b".into(),
            CoordinateSystem::CartesianMeters,
            Params::default(),
        );
        let l = b.levels.append(
            Level {
                name: "L1".into(),
                ..Level::default()
            },
            Span::default(),
        );
        assert_eq!(
            level_model_config(&b, l).to_document(true),
            "<?xml version='1.0' encoding='utf-8'?>\n<model>\n  <name>b_L1</name>\n  \
             <version>1.0.0</version>\n  <sdf version=\"1.6\">model.sdf</sdf>\n  <author>\n    \
             <name>automatically generated from the Great Editor</name>\n    \
             <email>info@openrobotics.org</email>\n  </author>\n  \
             <description>level b_L1 (automatically generated)</description>\n</model>\n"
        );
        // A level without floors and walls: a model with only <static>, and no meshes.
        let meshes = crate::level_meshes(&b, l);
        assert_eq!(
            level_model_sdf(&b, l, &meshes).to_document(true),
            "<?xml version='1.0' encoding='utf-8'?>\n<sdf version=\"1.7\">\n  \
             <model name=\"b_L1\">\n    <static>true</static>\n  </model>\n</sdf>\n"
        );
        let files = level_model_files(&b, l, &meshes, &Textures::default());
        let paths: Vec<_> = files.iter().map(|f| f.path.clone()).collect();
        assert_eq!(
            paths,
            [
                PathBuf::from("b_L1/model.config"),
                PathBuf::from("b_L1/model.sdf")
            ]
        );
    }
}
