//! The world file (generator.md §2.4-2.6 and §3) in the three flavours, and every file a
//! `gazebo`/`ignition`/`gz` run writes.
//!
//! The world starts from a template (mapc's default for the flavour, `templates/*.sdf`, or a
//! user's `--TEMPLATE_WORLD_FILE` parsed by [`parse_template`]) and gets, in the reference's
//! order: per level the model includes, the robot spawn includes, the door models and the
//! level model include; the lifts; the chargers; the crowd simulator plugin (when
//! crowd_sim is enabled; the reference generator ignores crowd_sim); the geo-reference; the GUI camera pose and
//! the toggle_floors (and, for classic, toggle_charging) GUI plugins.
//!
//! **Offset.** Everything in the world has `Building::offset` subtracted: models, robots,
//! doors, lifts, chargers, the camera pose; the level meshes are written less the offset, so
//! every level include is at `0 0 <elevation>`. The reference subtracts it from models and
//! robots only (generator.md §6.1), which puts walls, doors and chargers apart from models
//! in offset maps. The world still states the offset (`<offset>`) and the CRS for
//! geo-referenced maps, so a consumer can go back to map coordinates.
//!
//! Other deliberate differences: `<static>` of model includes is `true`/`false` (SDF's
//! spelling; the reference writes Python's `True`/`False`), a waypoint whose `is_charger` is
//! false is no charger (quirk 2), the classic world is named `sim_world` (libsdformat ≥ 1.8
//! reserves `world`; Gazebo classic accepts any name), and the camera pose of a first floor
//! that holes cut away completely is the no-floor pose rather than `nan`.

use super::xml::Element;
use super::Flavour;
use crate::fmt::cat;
use crate::py_float;
use mapc_ir::{Building, CoordinateSystem, Handle, Level, Vertex};
use std::collections::HashMap;

/// Options of a world run.
#[derive(Debug, Clone, Default)]
pub struct WorldOptions {
    /// A user template (`--TEMPLATE_WORLD_FILE`), already parsed; `None` for the flavour's.
    pub template: Option<Element>,
    /// Keep the template's camera pose (`--SKIP_CAMERA_POSE`).
    pub skip_camera_pose: bool,
}

/// The default world template of `flavour`: `templates/<flavour>.sdf` as [`parse_template`]
/// reads it, built from code made from that reading (`template_trees.rs`; a test keeps it
/// current). Why not parse at run time: the XML reader took 0.8 M instructions and 500
/// allocations of each world run, and its first search for a byte asks the CPU for its
/// features (a dozen `cpuid`, each a trap to the hypervisor on a VM, 3.6 µs here).
pub fn default_template(flavour: Flavour) -> Element {
    match flavour {
        Flavour::Gz => super::template_trees::gz(),
        Flavour::Ignition => super::template_trees::ignition(),
        Flavour::Classic => super::template_trees::classic(),
    }
}

/// Parses an SDF world template: root `<sdf>` with a `<world>` child. Unless
/// `skip_camera_pose`, the world's `<gui>` must hold a camera pose mapc can set: the
/// `camera_pose` of a `MinimalScene` (gz-sim) or `GzScene3D` (Ignition) plugin, or
/// `camera/pose` (classic). Comments, processing instructions and the declaration are
/// dropped; leaf elements keep their inner whitespace.
pub fn parse_template(text: &str, skip_camera_pose: bool) -> Result<Element, String> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(text);
    reader.config_mut().trim_text(false);
    let mut stack: Vec<Element> = Vec::new();
    let mut root: Option<Element> = None;
    let err = |reader: &quick_xml::Reader<&[u8]>, e: &dyn std::fmt::Display| {
        format!("at byte {}: {e}", reader.buffer_position())
    };
    fn open(e: &quick_xml::events::BytesStart) -> Result<Element, String> {
        let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
        let mut el = Element::new(name);
        for a in e.attributes() {
            let a = a.map_err(|e| e.to_string())?;
            let k = String::from_utf8_lossy(a.key.as_ref()).into_owned();
            let v = a.unescape_value().map_err(|e| e.to_string())?.into_owned();
            el.attrs.push((k.into(), v.into()));
        }
        Ok(el)
    }
    fn close(mut el: Element, stack: &mut [Element], root: &mut Option<Element>) {
        if !el.children.is_empty() && el.text.as_deref().is_some_and(|t| t.trim().is_empty()) {
            el.text = None;
        }
        match stack.last_mut() {
            Some(parent) => parent.push(el),
            None => *root = Some(el),
        }
    }
    let push_text = |stack: &mut Vec<Element>, s: &str| {
        if let Some(top) = stack.last_mut() {
            match &mut top.text {
                Some(t) => t.to_mut().push_str(s),
                None => top.text = Some(s.to_owned().into()),
            }
        }
    };
    loop {
        match reader.read_event() {
            Err(e) => return Err(err(&reader, &e)),
            Ok(Event::Eof) => break,
            Ok(Event::Start(e)) => {
                if root.is_some() {
                    return Err("more than one root element".into());
                }
                stack.push(open(&e)?);
            }
            Ok(Event::Empty(e)) => {
                if root.is_some() {
                    return Err("more than one root element".into());
                }
                let el = open(&e)?;
                close(el, &mut stack, &mut root);
            }
            Ok(Event::End(_)) => {
                let el = stack.pop().ok_or("unbalanced end tag")?;
                close(el, &mut stack, &mut root);
            }
            Ok(Event::Text(t)) => {
                let s = t.xml_content().map_err(|e| err(&reader, &e))?;
                push_text(&mut stack, &s);
            }
            Ok(Event::CData(t)) => {
                let s = t.decode().map_err(|e| err(&reader, &e))?;
                push_text(&mut stack, &s);
            }
            Ok(Event::GeneralRef(r)) => {
                let c = match r.resolve_char_ref().map_err(|e| err(&reader, &e))? {
                    Some(c) => c.to_string(),
                    None => {
                        let name = r.decode().map_err(|e| err(&reader, &e))?;
                        quick_xml::escape::resolve_predefined_entity(&name)
                            .ok_or_else(|| format!("unknown entity `&{name};`"))?
                            .to_string()
                    }
                };
                push_text(&mut stack, &c);
            }
            Ok(_) => {}
        }
    }
    if !stack.is_empty() {
        return Err("unexpected end of file: unclosed elements".into());
    }
    let root = root.ok_or("no root element")?;
    if root.name != "sdf" {
        return Err(format!("the root element is <{}>, not <sdf>", root.name));
    }
    let Some(world) = root.find("world") else {
        return Err("<sdf> has no <world> child".into());
    };
    if !skip_camera_pose {
        let ok = world.find("gui").is_some_and(|g| {
            let mut g = g.clone();
            camera_pose_mut(&mut g).is_some()
        });
        if !ok {
            return Err(
                "the world's <gui> has no camera pose to set (a `MinimalScene` or \
                        `GzScene3D` plugin with <camera_pose>, or <camera><pose>); add one \
                        or pass --SKIP_CAMERA_POSE"
                    .into(),
            );
        }
    }
    Ok(root)
}

fn child_mut<'a>(e: &'a mut Element, name: &str) -> Option<&'a mut Element> {
    e.children.iter_mut().find(|c| c.name == name)
}

fn attr<'a>(e: &'a Element, k: &str) -> Option<&'a str> {
    e.attrs
        .iter()
        .find(|(n, _)| n == k)
        .map(|(_, v)| v.as_ref())
}

/// The element whose text is the GUI camera pose, in any flavour's layout.
fn camera_pose_mut(gui: &mut Element) -> Option<&mut Element> {
    let idx = gui.children.iter().position(|c| {
        c.name == "plugin"
            && matches!(attr(c, "filename"), Some("MinimalScene" | "GzScene3D"))
            && c.find("camera_pose").is_some()
    });
    if let Some(i) = idx {
        return child_mut(&mut gui.children[i], "camera_pose");
    }
    child_mut(gui, "camera").and_then(|c| child_mut(c, "pose"))
}

/// World-frame position of a map-frame point: less the building offset.
fn world_xy(b: &Building, p: mapc_ir::Vec2) -> (String, String) {
    (py_float(p.x - b.offset.x), py_float(p.y - b.offset.y))
}

/// Instance names of every model (building-wide, document order): the first model with a
/// name keeps it, the k-th (k ≥ 2) becomes `<name>_<k>`.
fn instance_names(b: &Building) -> HashMap<Handle<mapc_ir::Model>, String> {
    let mut seen: HashMap<&str, usize> = HashMap::new();
    let mut out = HashMap::new();
    for (_, lvl) in b.levels.iter() {
        for &m in &lvl.models {
            let name = b.models[m].name.as_str();
            let k = seen.entry(name).or_insert(0);
            *k += 1;
            let inst = if *k == 1 {
                name.to_string()
            } else {
                cat(&[name, "_", &k.to_string()])
            };
            out.insert(m, inst);
        }
    }
    out
}

/// `model_name` less its first path segment (`OpenRobotics/Chair` → `Chair`).
fn strip_first_segment(name: &str) -> &str {
    name.split_once('/').map_or(name, |(_, rest)| rest)
}

/// Robot model type: an `open-rmf/` namespace (any case) is dropped for gz-sim (the
/// reference does so since 2025-01); older flavours keep the type verbatim.
fn robot_type(t: &str, flavour: Flavour) -> &str {
    if flavour == Flavour::Gz {
        if let Some((first, rest)) = t.split_once('/') {
            if first.eq_ignore_ascii_case("open-rmf") {
                return rest;
            }
        }
    }
    t
}

/// Yaw of a spawn waypoint: the direction of the first lane of its level touching it
/// (start → end, plus π when the lane is `backward`), `None` without one.
fn spawn_yaw(b: &Building, level: &Level, v: Handle<Vertex>) -> Option<f64> {
    let lane = level
        .lanes
        .iter()
        .map(|&l| &b.lanes[l])
        .find(|l| l.start == v || l.end == v)?;
    let s = b.vertices[lane.start].pos;
    let e = b.vertices[lane.end].pos;
    let mut yaw = (e.y - s.y).atan2(e.x - s.x);
    if lane.orientation == mapc_ir::Orientation::Backward {
        yaw += std::f64::consts::PI;
    }
    Some(yaw)
}

fn include(name: &str, uri: &str, pose: String) -> Element {
    Element::new("include")
        .leaf("name", name.to_owned())
        .leaf("uri", cat(&["model://", uri]))
        .leaf("pose", pose)
}

/// Centre of the bounding box of the first floor of the first level (holes and shafts cut
/// out), map frame; `None` when that floor is missing, degenerate or cut away.
fn first_floor_centre(b: &Building) -> Option<(f64, f64)> {
    let (h, _) = b.levels.iter().next()?;
    let f = crate::geometry::first_floor_mesh(b, h)?;
    let (lo, hi) = f.bounds()?;
    Some(((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0))
}

/// The GUI camera pose text: 20 m south of the first floor's centre, 10 m up, looking
/// north and down.
pub fn camera_pose(b: &Building) -> String {
    match first_floor_centre(b) {
        Some((cx, cy)) => format!(
            "{} {} 10 0 0.6 1.57",
            py_float(cx - b.offset.x),
            py_float(cy - 20.0 - b.offset.y)
        ),
        None => "0 -20 10 0 0.6 1.57".into(),
    }
}

/// The world document of `b` for `flavour` (root `<sdf>`).
pub fn world(b: &Building, flavour: Flavour, opts: &WorldOptions) -> Element {
    world_with(b, flavour, opts, &mut |p| part_elements(b, p, flavour))
}

/// A door's or a lift's models in the world.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Part {
    Door(Handle<mapc_ir::Door>),
    Lift(Handle<mapc_ir::Lift>),
}

/// The model elements of one part (a door without a model has none).
pub(crate) fn part_elements(b: &Building, part: Part, flavour: Flavour) -> Vec<Element> {
    match part {
        Part::Door(d) => super::doors::door_model(b, d, flavour)
            .into_iter()
            .collect(),
        Part::Lift(l) => super::lifts::lift_models(b, l, flavour),
    }
}

/// [`world`], with each part's elements from `part` (called in [`parts`] order).
pub(crate) fn world_with(
    b: &Building,
    flavour: Flavour,
    opts: &WorldOptions,
    part: &mut dyn FnMut(Part) -> Vec<Element>,
) -> Element {
    let mut root = opts
        .template
        .clone()
        .unwrap_or_else(|| default_template(flavour));
    let Some(wi) = root.children.iter().position(|c| c.name == "world") else {
        // parse_template guarantees a world; a hand-built template without one gets one.
        root.push(Element::new("world").attr("name", "sim_world"));
        return world_with(
            b,
            flavour,
            &WorldOptions {
                template: Some(root),
                skip_camera_pose: opts.skip_camera_pose,
            },
            part,
        );
    };
    let world = &mut root.children[wi];
    let names = instance_names(b);
    let mut toggle = Element::new("plugin").attr("name", "toggle_floors").attr(
        "filename",
        match flavour {
            Flavour::Classic => "libtoggle_floors.so",
            _ => "toggle_floors",
        },
    );

    for (lh, lvl) in b.levels.iter() {
        let elev = py_float(lvl.elevation);
        let model_name = super::level::level_model_name(b, lh);
        let mut floor = Element::new("floor")
            .attr("name", lvl.name.clone())
            .attr("model_name", model_name.clone());
        // 1. placed models
        for &mh in &lvl.models {
            let m = &b.models[mh];
            let inst = &names[&mh];
            let name = if m.dispensable {
                cat(&[inst, "_dispensable"])
            } else {
                inst.clone()
            };
            let is_static =
                m.is_static && !matches!(m.model_name.as_str(), "Sesto" | "MiR100" | "Magni");
            let (x, y) = world_xy(b, m.pos);
            let (z, yaw) = (py_float(m.z + lvl.elevation), py_float(m.yaw));
            let pose = cat(&[&x, " ", &y, " ", &z, " 0 0 ", &yaw]);
            world.push(
                include(&name, strip_first_segment(&m.model_name), pose)
                    .leaf("static", if is_static { "true" } else { "false" }),
            );
            if is_static {
                floor.push(Element::new("model").attr("name", inst.clone()));
            }
        }
        // 2. robot spawns
        for &vh in &lvl.vertices {
            let v = &b.vertices[vh];
            let (Some(t), Some(n)) = (&v.roles.spawn_robot_type, &v.roles.spawn_robot_name) else {
                continue;
            };
            let yaw = spawn_yaw(b, lvl, vh).map_or_else(|| "0".to_string(), py_float);
            let (x, y) = world_xy(b, v.pos);
            world.push(include(
                n,
                robot_type(t, flavour),
                cat(&[&x, " ", &y, " ", &elev, " 0 0 ", &yaw]),
            ));
        }
        // 3. doors
        for &dh in &lvl.doors {
            world.children.extend(part(Part::Door(dh)));
            floor.push(Element::new("model").attr("name", b.doors[dh].name.clone()));
        }
        // 4. the level model
        world.push(include(
            &model_name,
            &model_name,
            cat(&["0 0 ", &elev, " 0 0 0"]),
        ));
        // Shaft doors of the lifts that open on this level.
        for (lift, _) in b.lifts.iter() {
            for (level, name) in super::lifts::shaft_door_names(b, lift) {
                if level == lh {
                    floor.push(Element::new("model").attr("name", name));
                }
            }
        }
        toggle.push(floor);
    }

    // Lifts with level doors (others have no shaft and no cabin in the reference).
    for (lh, lift) in b.lifts.iter() {
        if !lift.level_doors.is_empty() {
            world.children.extend(part(Part::Lift(lh)));
        }
    }

    // Chargers.
    let chargers = b.levels.iter().flat_map(|(_, lvl)| {
        lvl.vertices
            .iter()
            .map(move |&vh| (lvl, &b.vertices[vh]))
            .filter(|(_, v)| v.roles.is_charger)
    });
    match flavour {
        Flavour::Gz => {
            let mut comp = Element::new("component").attr("name", "Chargers");
            for (lvl, v) in chargers {
                let (x, y) = world_xy(b, v.pos);
                comp.push(
                    Element::new("rmf_charger")
                        .attr("name", v.name.clone())
                        .attr("x", x)
                        .attr("y", y)
                        .attr("z", py_float(lvl.elevation)),
                );
            }
            world.push(
                Element::new("plugin")
                    .attr("name", "register_component")
                    .attr("filename", "libregister_component.so")
                    .child(comp),
            );
        }
        Flavour::Classic | Flavour::Ignition => {
            let mut wps = Element::new("rmf_charger_waypoints").attr("name", "charger_waypoints");
            for (lvl, v) in chargers {
                let (x, y) = world_xy(b, v.pos);
                wps.push(
                    Element::new("rmf_vertex")
                        .attr("name", v.name.clone())
                        .attr("x", x)
                        .attr("y", y)
                        .attr("level", lvl.name.clone()),
                );
            }
            world.push(wps);
        }
    }

    // The crowd simulator, when enabled (its Menge files are in `WorldFiles::crowd`).
    if let Some(p) = super::crowd::crowd_plugin(b) {
        world.push(p);
    }

    // Geo-reference.
    if b.coordinate_system != CoordinateSystem::ReferenceImage {
        world.push(Element::new("offset").text(format!(
            "{} {} 0 0 0 0",
            py_float(b.offset.x),
            py_float(b.offset.y)
        )));
        if let Some(crs) = &b.crs_name {
            world.push(Element::new("crs").text(crs.clone()));
        }
    }

    // GUI: camera pose, toggle plugins.
    if child_mut(world, "gui").is_none() {
        world.push(Element::new("gui"));
    }
    let gui = child_mut(world, "gui").expect("just ensured");
    if !opts.skip_camera_pose {
        if let Some(p) = camera_pose_mut(gui) {
            p.text = Some(camera_pose(b).into());
            p.children.clear();
        }
    }
    if flavour == Flavour::Classic {
        gui.push(
            Element::new("plugin")
                .attr("name", "toggle_charging")
                .attr("filename", "libtoggle_charging.so"),
        );
    }
    gui.push(toggle);
    root
}

/// The world file's text (no XML declaration, as the reference writes it).
pub fn world_text(b: &Building, flavour: Flavour, opts: &WorldOptions) -> String {
    world(b, flavour, opts).to_document(false)
}

/// What a world run writes: the world file's text, the level models (paths relative to
/// the model directory) and the crowd simulator's Menge files (paths relative to the
/// world's directory, `config_resource/...`; empty without an enabled crowd_sim).
#[derive(Debug, Clone)]
pub struct WorldFiles {
    pub world: String,
    pub models: Vec<crate::OutputFile>,
    pub crowd: Vec<crate::OutputFile>,
}

/// The world of `flavour` and every level model (model.sdf, model.config, meshes,
/// textures), from the level meshes already computed (one entry per level, document order).
pub fn world_files(
    b: &Building,
    flavour: Flavour,
    opts: &WorldOptions,
    meshes: &[(Handle<Level>, crate::LevelMeshes)],
    textures: &crate::Textures,
) -> WorldFiles {
    let mut models = Vec::new();
    for (h, m) in meshes {
        models.extend(super::level::level_model_files(b, *h, m, textures));
    }
    WorldFiles {
        world: world_text(b, flavour, opts),
        models,
        crowd: super::crowd::crowd_files(b),
    }
}

/// [`world_files`] without the texture images in `models` (see
/// [`crate::level_texture_paths`]: a caller that has the images on disk links them instead
/// of holding a copy of their bytes per level), and the level meshes it made for them (one
/// entry per level, document order).
pub fn world_files_untextured(
    b: &Building,
    flavour: Flavour,
    opts: &WorldOptions,
) -> (Vec<(Handle<Level>, crate::LevelMeshes)>, WorldFiles) {
    let meshes: Vec<(Handle<Level>, crate::LevelMeshes)> = b
        .levels
        .iter()
        .map(|(h, _)| (h, crate::level_meshes(b, h)))
        .collect();
    let mut models = Vec::new();
    for (h, m) in &meshes {
        models.extend(super::level::level_model_files_untextured(b, *h, m));
    }
    let files = WorldFiles {
        world: world_text(b, flavour, opts),
        models,
        crowd: super::crowd::crowd_files(b),
    };
    (meshes, files)
}

#[cfg(test)]
mod tests {
    use super::*;

    // The sources of `template_trees.rs`.
    const GZ_TEMPLATE: &str = include_str!("templates/gz.sdf");
    const IGNITION_TEMPLATE: &str = include_str!("templates/ignition.sdf");
    const CLASSIC_TEMPLATE: &str = include_str!("templates/classic.sdf");

    /// `template_trees.rs` is the code of the trees `parse_template` reads from
    /// `templates/*.sdf`: when a template changed, this test writes the new code and fails
    /// (run it again to see it pass; commit the file).
    #[test]
    fn template_trees_are_current() {
        fn emit(e: &Element, depth: usize, out: &mut String) {
            let pad = "    ".repeat(depth);
            let attrs: Vec<String> = e
                .attrs
                .iter()
                .map(|(k, v)| format!("({k:?}, {v:?})"))
                .collect();
            let head = format!(
                "{pad}e({:?}, &[{}], {:?}, vec![",
                e.name,
                attrs.join(", "),
                e.text.as_deref()
            );
            if e.children.is_empty() {
                out.push_str(&format!("{head}]),\n"));
            } else {
                out.push_str(&format!("{head}\n"));
                for c in &e.children {
                    emit(c, depth + 1, out);
                }
                out.push_str(&format!("{pad}]),\n"));
            }
        }
        let mut code = String::from(
            "//! The default world templates (`templates/*.sdf`) as trees: made by the test\n\
             //! `sdf::world::tests::template_trees_are_current` from `parse_template`'s reading\n\
             //! of them. Do not edit; change the template and run that test.\n\n\
             use super::xml::Element;\n\n\
             fn e(\n    name: &'static str,\n    attrs: &[(&'static str, &'static str)],\n    \
             text: Option<&'static str>,\n    children: Vec<Element>,\n) -> Element {\n    \
             Element {\n        name: name.into(),\n        \
             attrs: attrs.iter().map(|&(k, v)| (k.into(), v.into())).collect(),\n        \
             children,\n        text: text.map(Into::into),\n    }\n}\n",
        );
        let all = [
            (Flavour::Gz, "gz", GZ_TEMPLATE),
            (Flavour::Ignition, "ignition", IGNITION_TEMPLATE),
            (Flavour::Classic, "classic", CLASSIC_TEMPLATE),
        ];
        for (_, name, text) in all {
            let tree = parse_template(text, false).unwrap();
            code.push_str(&format!("\npub(super) fn {name}() -> Element {{\n"));
            let mut body = String::new();
            emit(&tree, 1, &mut body);
            // The root is the function's value, not an argument.
            code.push_str(body.trim_end().trim_end_matches(','));
            code.push_str("\n}\n");
        }
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/sdf/template_trees.rs");
        if std::fs::read_to_string(&path).ok().as_deref() != Some(code.as_str()) {
            std::fs::write(&path, &code).unwrap();
            panic!(
                "{} was out of date: written anew, run the test again",
                path.display()
            );
        }
        for (f, _, text) in all {
            assert_eq!(default_template(f), parse_template(text, false).unwrap());
        }
    }

    #[test]
    fn templates_parse() {
        for f in [Flavour::Gz, Flavour::Ignition, Flavour::Classic] {
            let t = default_template(f);
            let w = t.find("world").unwrap();
            assert_eq!(attr(w, "name"), Some("sim_world"));
            assert!(w.find("gui").is_some());
        }
        let gz = default_template(Flavour::Gz).to_document(false);
        assert!(gz.contains("<plugin filename=\"libdoor.so\" name=\"door\">\n    </plugin>"));
        assert!(gz.contains("<plugin filename=\"toggle_charging\" name=\"toggle_charging\" />"));
    }

    #[test]
    fn template_errors() {
        assert!(parse_template("<world/>", true).is_err());
        assert!(parse_template("<sdf><model/></sdf>", true).is_err());
        assert!(parse_template("<sdf><world name='w'/></sdf>", true).is_ok());
        let e = parse_template("<sdf><world name='w'><gui/></world></sdf>", false).unwrap_err();
        assert!(e.contains("--SKIP_CAMERA_POSE"), "{e}");
        assert!(parse_template("<sdf><world>", true).is_err());
        assert!(parse_template("<sdf><world></sdf>", true).is_err());
        let t = parse_template(
            "<!-- c --><sdf a=\"x &amp; y\"><world name=\"w\"><gui><camera><pose>1 2 3 0 0 0</pose></camera></gui><x>a &lt; b&#33;</x></world></sdf>",
            false,
        )
        .unwrap();
        assert_eq!(t.attrs[0].1, "x & y");
        let w = t.find("world").unwrap();
        assert_eq!(w.find("x").unwrap().text.as_deref(), Some("a < b!"));
    }

    #[test]
    fn names() {
        assert_eq!(strip_first_segment("OpenRobotics/Chair"), "Chair");
        assert_eq!(strip_first_segment("a/b/c"), "b/c");
        assert_eq!(strip_first_segment("Chair"), "Chair");
        assert_eq!(robot_type("Open-RMF/TinyRobot", Flavour::Gz), "TinyRobot");
        assert_eq!(
            robot_type("open-rmf/TinyRobot", Flavour::Classic),
            "open-rmf/TinyRobot"
        );
        assert_eq!(robot_type("acme/TinyRobot", Flavour::Gz), "acme/TinyRobot");
    }
}
