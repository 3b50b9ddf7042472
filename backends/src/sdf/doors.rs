//! Door models (generator.md §2.7, flavour differences §3).
//!
//! **Offsets.** The reference generator does not subtract `Building::offset` from door
//! poses (generator.md §6.1), so in maps with a non-zero offset its doors end up away from
//! the walls they sit in. mapc subtracts the offset from everything it places in a world,
//! doors included, so doors stay in their walls. For maps with a zero offset (every demo
//! map that has doors) the poses are the reference's.

use super::xml::Element;
use super::Flavour;
use crate::fmt::cat;
use crate::py_float;
use mapc_ir::{Building, Door, DoorKind, Handle};

/// Door leaf height, metres.
pub const DOOR_HEIGHT: f64 = 2.2;
/// Door leaf thickness, metres.
pub const DOOR_THICKNESS: f64 = 0.03;
/// Mass of one door leaf, kg.
pub const DOOR_MASS: f64 = 50.0;

/// `<geometry><box><size>x y z</size></box></geometry>`.
pub(crate) fn box_geometry(size: &str) -> Element {
    Element::new("geometry").child(Element::new("box").leaf("size", size.to_owned()))
}

/// `<surface><contact><collide_bitmask>mask</collide_bitmask></contact></surface>`.
pub(crate) fn bitmask_surface(mask: &str) -> Element {
    Element::new("surface").child(Element::new("contact").leaf("collide_bitmask", mask.to_owned()))
}

/// Moment of inertia of a box of `mass` about the axis normal to the sides `a` and `b`:
/// `m/12 (a² + b²)`.
pub fn box_inertia(mass: f64, a: f64, b: f64) -> f64 {
    mass / 12.0 * (a * a + b * b)
}

/// Swing range in radians as the reference computes it: `3.14 · degrees / 180` (3.14, not
/// π; generator.md §6.5).
pub fn swing_limit(motion_degrees: f64) -> f64 {
    REFERENCE_PI * motion_degrees / 180.0
}

/// The reference's "π" in swing limits (generator.md §6.5); kept so limits match it.
#[allow(clippy::approx_constant)]
pub const REFERENCE_PI: f64 = 3.14;

/// Widths `(right, left)` of the leaves of a double door of length `l`:
/// `L_R = r/(1+r)·L`, `L_L = L − L_R`.
pub fn double_widths(l: f64, right_left_ratio: f64) -> (f64, f64) {
    let right = right_left_ratio / (1.0 + right_left_ratio) * l;
    (right, l - right)
}

/// Hinge axis from `motion_direction`: `0 0 1` when negative, else `0 0 -1`.
pub fn swing_axis(motion_direction: i64) -> &'static str {
    if motion_direction < 0 {
        "0 0 1"
    } else {
        "0 0 -1"
    }
}

/// A door leaf's joint.
enum JointKind {
    /// Prismatic along the door, limits `[lo, hi]`.
    Slide,
    /// Revolute about z, limits `[lo, hi]`, joint pose x relative to the leaf.
    Swing { axis: &'static str, pose_x: f64 },
}

/// One leaf: link name, width, centre along the door, limits (as text), joint.
struct Section {
    name: &'static str,
    width: f64,
    x0: Option<f64>,
    lower: String,
    upper: String,
    joint: JointKind,
}

fn section_elements(s: &Section, flavour: Flavour) -> [Element; 2] {
    let size = format!(
        "{} {} {}",
        py_float(s.width),
        DOOR_THICKNESS,
        py_float(DOOR_HEIGHT)
    );
    let mut material = Element::new("material")
        .leaf("ambient", "0.5 0.25 0 0.6")
        .leaf("diffuse", "0.5 0.25 0 0.6");
    if flavour != Flavour::Classic {
        material = material
            .child(Element::new("pbr").child(Element::new("metal").leaf("metalness", "0.0")));
    }
    let x0 = s.x0.map_or_else(|| "0".to_string(), py_float);
    let link = Element::new("link")
        .attr("name", s.name)
        .leaf("pose", format!("{x0} 0 {} 0 0 0", DOOR_HEIGHT / 2.0 + 0.01))
        .child(
            Element::new("visual")
                .attr("name", cat(&[s.name, "_visual"]))
                .child(box_geometry(&size))
                .child(material),
        )
        .child(
            Element::new("collision")
                .attr("name", cat(&[s.name, "_collision"]))
                .child(box_geometry(&size))
                .child(bitmask_surface("0x02")),
        )
        .child(
            Element::new("inertial")
                .leaf("mass", py_float(DOOR_MASS))
                .child(
                    Element::new("inertia")
                        .leaf(
                            "ixx",
                            py_float(box_inertia(DOOR_MASS, DOOR_THICKNESS, DOOR_HEIGHT)),
                        )
                        .leaf(
                            "iyy",
                            py_float(box_inertia(DOOR_MASS, s.width, DOOR_HEIGHT)),
                        )
                        .leaf(
                            "izz",
                            py_float(box_inertia(DOOR_MASS, DOOR_THICKNESS, s.width)),
                        ),
                ),
        );
    let limit = Element::new("limit")
        .leaf("lower", s.lower.clone())
        .leaf("upper", s.upper.clone());
    let joint = Element::new("joint").attr("name", cat(&[s.name, "_joint"]));
    let joint = match s.joint {
        JointKind::Slide => joint
            .attr("type", "prismatic")
            .leaf("parent", "world")
            .leaf("child", s.name)
            .child(
                Element::new("axis")
                    .leaf("xyz", "1 0 0")
                    .child(limit.leaf("effort", "500.0")),
            ),
        JointKind::Swing { axis, pose_x } => joint
            .attr("type", "revolute")
            .leaf("parent", "world")
            .leaf("child", s.name)
            .child(Element::new("axis").leaf("xyz", axis).child(limit))
            .leaf("pose", cat(&[&py_float(pose_x), " 0 0 0 0 0"])),
    };
    [link, joint]
}

/// The door's `<model>` in the world (generator.md §2.7), or `None` for a door type the
/// simulators do not know (the validator reports those).
///
/// The pose is the edge's centre less `Building::offset` (see the module docs; the
/// reference does not subtract the offset), at the level's elevation, yawed from the end
/// vertex towards the start vertex.
pub fn door_model(b: &Building, door: Handle<Door>, flavour: Flavour) -> Option<Element> {
    let d = &b.doors[door];
    let s = b.vertices[d.start].pos;
    let e = b.vertices[d.end].pos;
    let l = s.minus(e).norm();
    let c = s.plus(e).scale(0.5).minus(b.offset);
    let yaw = (s.y - e.y).atan2(s.x - e.x);
    let elevation = b.levels[d.level].elevation;
    let mu = swing_limit(d.motion_degrees);
    let (l_r, l_l) = double_widths(l, d.right_left_ratio);
    let f = py_float;
    let (sections, door_type, family_sliding) = match d.kind {
        DoorKind::Sliding => (
            vec![Section {
                name: "right",
                width: l - 0.01,
                x0: None,
                lower: "0.0".into(),
                upper: f(l),
                joint: JointKind::Slide,
            }],
            "SlidingDoor",
            true,
        ),
        DoorKind::DoubleSliding => (
            vec![
                Section {
                    name: "right",
                    width: l_r - 0.01,
                    x0: Some(l / 2.0 - l_r / 2.0),
                    lower: "0.0".into(),
                    upper: f(l_r),
                    joint: JointKind::Slide,
                },
                Section {
                    name: "left",
                    width: l_l - 0.01,
                    x0: Some(-l / 2.0 + l_l / 2.0),
                    lower: f(-l_l),
                    upper: "0.0".into(),
                    joint: JointKind::Slide,
                },
            ],
            "DoubleSlidingDoor",
            true,
        ),
        DoorKind::Hinged => (
            vec![Section {
                name: "right",
                width: l - 0.01,
                x0: None,
                lower: "0".into(),
                upper: f(mu),
                joint: JointKind::Swing {
                    axis: swing_axis(d.motion_direction),
                    pose_x: l / 2.0,
                },
            }],
            "SwingDoor",
            false,
        ),
        DoorKind::DoubleHinged => (
            vec![
                Section {
                    name: "right",
                    width: l_r - 0.01,
                    x0: Some(l / 2.0 - l_r / 2.0),
                    lower: "0".into(),
                    upper: f(mu),
                    joint: JointKind::Swing {
                        axis: swing_axis(d.motion_direction),
                        pose_x: l_r / 2.0,
                    },
                },
                Section {
                    name: "left",
                    width: l_l - 0.01,
                    x0: Some(-l / 2.0 + l_l / 2.0),
                    lower: f(-mu),
                    upper: "0".into(),
                    joint: JointKind::Swing {
                        axis: swing_axis(d.motion_direction),
                        pose_x: -l_l / 2.0,
                    },
                },
            ],
            "DoubleSwingDoor",
            false,
        ),
        DoorKind::Other(_) => return None,
    };
    let mut model = Element::new("model").attr("name", d.name.clone()).leaf(
        "pose",
        cat(&[&f(c.x), " ", &f(c.y), " ", &f(elevation), " 0 0 ", &f(yaw)]),
    );
    if !d.plugin {
        model = model.leaf("static", "true");
    }
    for s in &sections {
        for e in section_elements(s, flavour) {
            model.push(e);
        }
    }
    if d.plugin {
        let (v, a, n, dx, fm) = if family_sliding {
            ("0.2", "0.2", "0.08", "0.001", "100.0")
        } else {
            ("0.5", "0.3", "0.15", "0.01", "500.0")
        };
        let left = if sections.len() == 2 {
            "left_joint"
        } else {
            "empty_joint"
        };
        let door_el = Element::new("door")
            .attr("name", d.name.clone())
            .attr("type", door_type)
            .attr("left_joint_name", left)
            .attr("right_joint_name", "right_joint");
        let params = [
            Element::new("v_max_door").text(v),
            Element::new("a_max_door").text(a),
            Element::new("a_nom_door").text(n),
            Element::new("dx_min_door").text(dx),
            Element::new("f_max_door").text(fm),
        ];
        let plugin = match flavour {
            Flavour::Gz => {
                let mut comp = Element::new("component").attr("name", "Door");
                for p in params {
                    comp.push(p);
                }
                comp.push(Element::new("ros_interface").text("true"));
                comp.push(door_el);
                Element::new("plugin")
                    .attr("name", "register_component")
                    .attr("filename", "libregister_component.so")
                    .child(comp)
            }
            Flavour::Classic | Flavour::Ignition => {
                let mut p = Element::new("plugin")
                    .attr("name", "door")
                    .attr("filename", "libdoor.so");
                for e in params {
                    p.push(e);
                }
                p.child(door_el)
            }
        };
        model.push(plugin);
    }
    Some(model)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mapc_ir::{CoordinateSystem, Level, MotionAxis, Params, Span, Vec2, Vertex};

    fn building(kind: &str, s: Vec2, e: Vec2, ratio: f64, dir: i64, plugin: bool) -> Building {
        let mut b = Building::new(
            "b".into(),
            CoordinateSystem::CartesianMeters,
            Params::default(),
        );
        let level = b.levels.append(
            Level {
                name: "L1".into(),
                elevation: 4.0,
                ..Level::default()
            },
            Span::default(),
        );
        let v = |pos| Vertex {
            level,
            name: String::new(),
            pos,
            raw: pos,
            params: Params::default(),
            roles: Default::default(),
        };
        let start = b.vertices.append(v(s), Span::default());
        let end = b.vertices.append(v(e), Span::default());
        b.doors.append(
            Door {
                level,
                start,
                end,
                name: "d".into(),
                kind: DoorKind::parse(kind),
                motion_axis: MotionAxis::Start,
                motion_direction: dir,
                motion_degrees: 90.0,
                right_left_ratio: ratio,
                plugin,
                params: Params::default(),
            },
            Span::default(),
        );
        b
    }

    fn door(b: &Building, flavour: Flavour) -> Option<Element> {
        door_model(b, b.doors.handle(0).unwrap(), flavour)
    }

    fn text<'a>(e: &'a Element, path: &[&str]) -> &'a str {
        let mut e = e;
        for p in path {
            e = e.find(p).unwrap_or_else(|| panic!("no {p}"));
        }
        e.text.as_deref().unwrap()
    }

    fn links(e: &Element) -> Vec<&Element> {
        e.children.iter().filter(|c| c.name == "link").collect()
    }

    fn joints(e: &Element) -> Vec<&Element> {
        e.children.iter().filter(|c| c.name == "joint").collect()
    }

    #[test]
    fn formulas() {
        assert!((swing_limit(90.0) - 1.57).abs() < 1e-12);
        assert_eq!(swing_limit(180.0), REFERENCE_PI);
        assert_eq!(py_float(swing_limit(180.0)), "3.14");
        let (r, l) = double_widths(3.0, 2.0);
        assert!((r - 2.0).abs() < 1e-12 && (l - 1.0).abs() < 1e-12);
        assert_eq!(double_widths(2.0, 1.0), (1.0, 1.0));
        assert_eq!(swing_axis(-1), "0 0 1");
        assert_eq!(swing_axis(1), "0 0 -1");
        assert!((box_inertia(50.0, 0.03, 2.2) - 50.0 / 12.0 * (0.0009 + 4.84)).abs() < 1e-12);
    }

    #[test]
    fn hinged_door_pose_inertia_limits() {
        let b = building(
            "hinged",
            Vec2::new(2.0, 0.0),
            Vec2::new(0.0, 0.0),
            1.0,
            1,
            true,
        );
        let m = door(&b, Flavour::Gz).unwrap();
        // Yaw points from the end to the start vertex.
        assert_eq!(text(&m, &["pose"]), "1.0 0.0 4.0 0 0 0.0");
        let ls = links(&m);
        assert_eq!(ls.len(), 1);
        let w = 2.0 - 0.01;
        assert_eq!(
            text(ls[0], &["inertial", "inertia", "iyy"]),
            py_float(50.0 / 12.0 * (w * w + 2.2 * 2.2))
        );
        assert_eq!(
            text(ls[0], &["inertial", "inertia", "izz"]),
            py_float(50.0 / 12.0 * (w * w + 0.03 * 0.03))
        );
        let j = joints(&m)[0];
        assert_eq!(j.attrs[1].1, "revolute");
        assert_eq!(text(j, &["axis", "xyz"]), "0 0 -1");
        assert_eq!(text(j, &["axis", "limit", "upper"]), "1.57");
        assert_eq!(text(j, &["pose"]), "1.0 0 0 0 0 0");
        let door = m.find("plugin").unwrap().find("component").unwrap();
        assert_eq!(text(door, &["f_max_door"]), "500.0");
        assert_eq!(door.find("door").unwrap().attrs[1].1, "SwingDoor");
        assert_eq!(door.find("door").unwrap().attrs[2].1, "empty_joint");
    }

    #[test]
    fn double_hinged_widths_and_axis() {
        // Start at -x: the door's +x points to -x (yaw π).
        let b = building(
            "double_hinged",
            Vec2::new(0.0, 0.0),
            Vec2::new(3.0, 0.0),
            2.0,
            -1,
            true,
        );
        let m = door(&b, Flavour::Classic).unwrap();
        assert!(text(&m, &["pose"]).ends_with(&py_float(std::f64::consts::PI)));
        let ls = links(&m);
        let js = joints(&m);
        assert_eq!(ls.len(), 2);
        // L = 3, r = 2: right leaf 2 m centred at 0.5, left leaf 1 m centred at -1.
        let size = |l: &Element| text(l, &["visual", "geometry", "box", "size"]).to_string();
        assert_eq!(size(ls[0]), format!("{} 0.03 2.2", py_float(2.0 - 0.01)));
        assert_eq!(size(ls[1]), format!("{} 0.03 2.2", py_float(1.0 - 0.01)));
        assert_eq!(text(ls[0], &["pose"]), "0.5 0 1.11 0 0 0");
        assert_eq!(text(ls[1], &["pose"]), "-1.0 0 1.11 0 0 0");
        assert_eq!(text(js[0], &["axis", "xyz"]), "0 0 1");
        assert_eq!(text(js[0], &["pose"]), "1.0 0 0 0 0 0");
        assert_eq!(text(js[1], &["pose"]), "-0.5 0 0 0 0 0");
        assert_eq!(text(js[1], &["axis", "limit", "lower"]), "-1.57");
        assert_eq!(text(js[1], &["axis", "limit", "upper"]), "0");
        // Classic: no pbr, model plugin with the parameters directly inside.
        assert!(ls[0]
            .find("visual")
            .unwrap()
            .find("material")
            .unwrap()
            .find("pbr")
            .is_none());
        let p = m.find("plugin").unwrap();
        assert_eq!(p.attrs[1].1, "libdoor.so");
        assert!(p.find("ros_interface").is_none());
        assert_eq!(p.find("door").unwrap().attrs[2].1, "left_joint");
    }

    #[test]
    fn sliding_doors() {
        let b = building(
            "sliding",
            Vec2::new(0.0, 0.0),
            Vec2::new(0.0, 1.0),
            1.0,
            1,
            false,
        );
        let m = door(&b, Flavour::Ignition).unwrap();
        assert_eq!(text(&m, &["static"]), "true");
        assert!(m.find("plugin").is_none());
        let j = joints(&m)[0];
        assert_eq!(j.attrs[1].1, "prismatic");
        assert_eq!(text(j, &["axis", "limit", "lower"]), "0.0");
        assert_eq!(text(j, &["axis", "limit", "upper"]), "1.0");
        assert_eq!(text(j, &["axis", "limit", "effort"]), "500.0");
        let b = building(
            "double_sliding",
            Vec2::new(4.0, 0.0),
            Vec2::new(0.0, 0.0),
            3.0,
            1,
            true,
        );
        let m = door(&b, Flavour::Ignition).unwrap();
        let js = joints(&m);
        assert_eq!(text(js[0], &["axis", "limit", "upper"]), "3.0");
        assert_eq!(text(js[1], &["axis", "limit", "lower"]), "-1.0");
        let p = m.find("plugin").unwrap();
        assert_eq!(text(p, &["v_max_door"]), "0.2");
        assert_eq!(p.find("door").unwrap().attrs[1].1, "DoubleSlidingDoor");
    }

    #[test]
    fn unknown_type_and_offset() {
        let b = building(
            "revolving",
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            1.0,
            1,
            true,
        );
        assert!(door(&b, Flavour::Gz).is_none());
        let mut b = building(
            "hinged",
            Vec2::new(10.0, 20.0),
            Vec2::new(12.0, 20.0),
            1.0,
            1,
            true,
        );
        b.offset = Vec2::new(10.0, 20.0);
        let m = door(&b, Flavour::Gz).unwrap();
        assert!(text(&m, &["pose"]).starts_with("1.0 0.0 4.0 "));
    }
}
