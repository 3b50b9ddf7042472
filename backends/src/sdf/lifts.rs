//! Lift models: shaft doors per level and the cabin (generator.md §2.8, flavour
//! differences §3).
//!
//! **Offsets.** Like doors (see [`super::doors`]), the reference does not subtract
//! `Building::offset` from lift and shaft-door poses (generator.md §6.1); mapc does, so
//! lifts stay in their shafts in maps with an offset. With a zero offset (every demo map
//! with lifts) the poses are the reference's.
//!
//! **Several cabin doors.** The demo maps have one door per lift, so the order of several
//! is taken from generator.md §2.8/§3: per door (the lift's `doors` order) its nested model
//! and joints (gz), its nested model (classic), or its links, joints and door plugin
//! (Ignition); door pairs and shaft doors list doors in the `doors` order too.
//!
//! **Degenerate walls.** A cabin door wider than its side (or reaching past it) makes the
//! reference emit wall boxes of zero or negative length; mapc leaves those segments out.

use super::doors::{bitmask_surface, box_geometry, box_inertia};
use super::xml::Element;
use super::Flavour;
use crate::py_float;
use mapc_ir::{Building, Handle, Level, Lift, LiftDoor, Vec2};

/// Cabin wall height, metres.
pub const CABIN_HEIGHT: f64 = 2.5;
/// Cabin wall thickness, metres.
pub const WALL_THICKNESS: f64 = 0.05;
/// Cabin floor thickness, metres.
pub const FLOOR_THICKNESS: f64 = 0.05;
/// Gap between the cabin and the shaft doors, metres.
pub const SHAFT_GAP: f64 = 0.05;
/// Cabin mass, kg.
pub const CABIN_MASS: f64 = 1200.0;
/// Lift door leaf thickness, metres.
pub const LIFT_DOOR_THICKNESS: f64 = 0.03;
/// How far cabin doors sit inside the cabin's outline, metres.
pub const CABIN_DOOR_INSET: f64 = 0.025;

/// The side of the cabin a door is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Front,
    Back,
    Left,
    Right,
}

/// Where a lift door sits, from its position in the cabin frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DoorPlacement {
    pub side: Side,
    /// The door's extent along its side: `[centre − w/2, centre + w/2]`.
    pub interval: (f64, f64),
    /// Shaft-door position in the cabin frame.
    pub shaft: Vec2,
    /// Cabin-door position in the cabin frame.
    pub cabin: Vec2,
}

/// Side classification (generator.md §2.8): the door belongs to the side whose line it is
/// nearest to, left/right winning ties.
pub fn classify(lift: &Lift, door: &LiftDoor) -> DoorPlacement {
    let (w, d) = (lift.width, lift.depth);
    let Vec2 { x, y } = door.pos;
    let dx = (x.abs() - w / 2.0).abs();
    let dy = (y.abs() - d / 2.0).abs();
    let half = door.width / 2.0;
    if dx <= dy {
        let sign = if x > 0.0 { 1.0 } else { -1.0 };
        DoorPlacement {
            side: if x > 0.0 { Side::Right } else { Side::Left },
            interval: (y - half, y + half),
            shaft: Vec2::new(sign * (w / 2.0 + SHAFT_GAP), y),
            cabin: Vec2::new(sign * (w / 2.0 - CABIN_DOOR_INSET), y),
        }
    } else {
        let sign = if y > 0.0 { 1.0 } else { -1.0 };
        DoorPlacement {
            side: if y > 0.0 { Side::Front } else { Side::Back },
            interval: (x - half, x + half),
            shaft: Vec2::new(x, sign * (d / 2.0 + SHAFT_GAP)),
            cabin: Vec2::new(x, sign * (d / 2.0 - CABIN_DOOR_INSET)),
        }
    }
}

/// A cabin wall segment: name, length, pose text.
#[derive(Debug, Clone, PartialEq)]
pub struct WallSegment {
    pub name: String,
    pub length: f64,
    pub pose: String,
}

/// The cabin's wall segments with gaps for the doors, sides in the order front, back,
/// left, right.
pub fn cabin_walls(lift: &Lift) -> Vec<WallSegment> {
    let (w, d, tw) = (lift.width, lift.depth, WALL_THICKNESS);
    let f = py_float;
    let mut out = Vec::new();
    for side in [Side::Front, Side::Back, Side::Left, Side::Right] {
        let mut points = match side {
            Side::Front | Side::Back => vec![-w / 2.0, w / 2.0],
            Side::Left | Side::Right => vec![-d / 2.0 + tw, d / 2.0 - tw],
        };
        for door in &lift.doors {
            let p = classify(lift, door);
            if p.side == side {
                points.extend([p.interval.0, p.interval.1]);
            }
        }
        points.sort_by(f64::total_cmp);
        let prefix = match side {
            Side::Front => "front",
            Side::Back => "back",
            Side::Left => "left",
            Side::Right => "right",
        };
        for (j, pair) in points.chunks_exact(2).enumerate() {
            let length = pair[1] - pair[0];
            if length.is_nan() || length <= 0.0 {
                continue;
            }
            let m = (pair[0] + pair[1]) / 2.0;
            let z = CABIN_HEIGHT / 2.0;
            let pose = match side {
                Side::Front => format!("{} {} {} 0 0 0", f(m), f(d / 2.0 - tw / 2.0), f(z)),
                Side::Back => format!("{} {} {} 0 0 0", f(m), f(-d / 2.0 + tw / 2.0), f(z)),
                Side::Left => format!(
                    "{} {} {} 0 0 {}",
                    f(-w / 2.0 + tw / 2.0),
                    f(m),
                    f(z),
                    f(std::f64::consts::FRAC_PI_2)
                ),
                Side::Right => format!(
                    "{} {} {} 0 0 {}",
                    f(w / 2.0 - tw / 2.0),
                    f(m),
                    f(z),
                    f(std::f64::consts::FRAC_PI_2)
                ),
            };
            out.push(WallSegment {
                name: format!("{prefix}wall{}", j + 1),
                length,
                pose,
            });
        }
    }
    out
}

fn lift_material() -> Element {
    Element::new("material")
        .leaf("ambient", "0.5 0.5 0.5 1")
        .leaf("diffuse", "0.7 0.7 0.7 1")
        .leaf("specular", "0.6 0.6 0.6 1")
        .leaf("emissive", "0.1 0.1 0.1 1")
}

/// `box_link(N, size, pose, bitmask)` of the reference.
fn box_link(name: &str, size: &str, pose: &str, mask: &str) -> Element {
    Element::new("link")
        .attr("name", name.to_owned())
        .leaf("pose", pose.to_owned())
        .child(
            Element::new("visual")
                .attr("name", format!("{name}_visual"))
                .child(box_geometry(size))
                .child(lift_material()),
        )
        .child(
            Element::new("collision")
                .attr("name", format!("{name}_collision"))
                .child(box_geometry(size))
                .child(bitmask_surface(mask)),
        )
}

fn leaf_size(door: &LiftDoor) -> String {
    format!(
        "{} {} {}",
        py_float(door.width / 2.0),
        LIFT_DOOR_THICKNESS,
        py_float(CABIN_HEIGHT)
    )
}

/// The right and left door leaves, as links named `<prefix>right_door` and
/// `<prefix>left_door`, centred at `±w/4` along `axis` from `centre` (z = Hc/2), with the
/// pose yaw `yaw` (None: the literal `0`).
fn door_links(door: &LiftDoor, prefix: &str, centre: Vec2, yaw: Option<f64>) -> [Element; 2] {
    let q = door.width / 4.0;
    let (s, c) = door.motion_axis_orientation.sin_cos();
    let (ax, ay) = if yaw.is_some() {
        (c * q, s * q)
    } else {
        (q, 0.0)
    };
    let yaw = yaw.map_or_else(|| "0".to_string(), py_float);
    let pose = |sign: f64| {
        let x = centre.x + sign * ax;
        let y = centre.y + sign * ay;
        // Leaves of a door at the origin print their y as the literal 0, as the reference.
        let y = if centre == Vec2::default() && ay == 0.0 {
            "0".to_string()
        } else {
            py_float(y)
        };
        format!(
            "{} {y} {} 0 0 {yaw}",
            py_float(x),
            py_float(CABIN_HEIGHT / 2.0)
        )
    };
    let size = leaf_size(door);
    [
        box_link(&format!("{prefix}right_door"), &size, &pose(1.0), "0x02"),
        box_link(&format!("{prefix}left_door"), &size, &pose(-1.0), "0x02"),
    ]
}

/// Prismatic joints `(right, left)` of a lift door's leaves.
fn door_joints(
    door: &LiftDoor,
    names: [&str; 2],
    parent: &str,
    children: [&str; 2],
) -> [Element; 2] {
    let half = py_float(door.width / 2.0);
    let joint = |name: &str, child: &str, lo: &str, hi: &str| {
        Element::new("joint")
            .attr("name", name.to_owned())
            .attr("type", "prismatic")
            .leaf("parent", parent.to_owned())
            .leaf("child", child.to_owned())
            .child(
                Element::new("axis").leaf("xyz", "1 0 0").child(
                    Element::new("limit")
                        .leaf("lower", lo.to_owned())
                        .leaf("upper", hi.to_owned()),
                ),
            )
    };
    [
        joint(names[0], children[0], "0", &half),
        joint(names[1], children[1], &py_float(-door.width / 2.0), "0"),
    ]
}

/// The controller of a lift door (always double sliding, generator.md §6.6).
fn door_plugin(name: &str, right_joint: &str, left_joint: &str, flavour: Flavour) -> Element {
    let children = [
        Element::new("v_max_door").text("0.3"),
        Element::new("a_max_door").text("0.2"),
        Element::new("a_nom_door").text("0.1"),
        Element::new("dx_min_door").text("0.0001"),
        Element::new("f_max_door").text("35.0"),
        Element::new("door")
            .attr("left_joint_name", left_joint.to_owned())
            .attr("name", name.to_owned())
            .attr("right_joint_name", right_joint.to_owned())
            .attr("type", "DoubleSlidingDoor"),
    ];
    plugin(flavour, "Door", "door", "libdoor.so", children)
}

fn plugin<const N: usize>(
    flavour: Flavour,
    component: &str,
    name: &str,
    filename: &str,
    children: [Element; N],
) -> Element {
    match flavour {
        Flavour::Gz => {
            let mut c = Element::new("component").attr("name", component.to_owned());
            c.children.extend(children);
            Element::new("plugin")
                .attr("name", "register_component")
                .attr("filename", "libregister_component.so")
                .child(c)
        }
        Flavour::Classic | Flavour::Ignition => {
            let mut p = Element::new("plugin")
                .attr("name", name.to_owned())
                .attr("filename", filename.to_owned());
            p.children.extend(children);
            p
        }
    }
}

/// Shaft doors of a lift: for each level in `level_doors` (its order) and each lift door
/// (the lift's `doors` order) listed for that level, the level and the door. Empty when
/// `level_doors` is empty (such a lift is not simulated).
pub fn shaft_doors(b: &Building, lift: Handle<Lift>) -> Vec<(Handle<Level>, &LiftDoor)> {
    let l = &b.lifts[lift];
    let mut out = Vec::new();
    for ld in &l.level_doors {
        for door in &l.doors {
            if ld.doors.iter().any(|(n, _)| *n == door.name) {
                out.push((ld.level, door));
            }
        }
    }
    out
}

/// `ShaftDoor_<lift>_<level>_<door>`.
pub fn shaft_door_name(lift: &str, level: &str, door: &str) -> String {
    format!("ShaftDoor_{lift}_{level}_{door}")
}

/// `CabinDoor_<lift>_<door>`.
pub fn cabin_door_name(lift: &str, door: &str) -> String {
    format!("CabinDoor_{lift}_{door}")
}

/// The shaft-door model names of a lift with their levels, in model order: what the
/// world's toggle_floors plugin lists per floor.
pub fn shaft_door_names(b: &Building, lift: Handle<Lift>) -> Vec<(Handle<Level>, String)> {
    let l = &b.lifts[lift];
    shaft_doors(b, lift)
        .into_iter()
        .map(|(level, door)| {
            (
                level,
                shaft_door_name(&l.name, &b.levels[level].name, &door.name),
            )
        })
        .collect()
}

/// The lift's models for the world (generator.md §2.8): its shaft doors, then its cabin.
/// Empty when `level_doors` is empty. Poses are less `Building::offset` (module docs).
pub fn lift_models(b: &Building, lift: Handle<Lift>, flavour: Flavour) -> Vec<Element> {
    let l = &b.lifts[lift];
    if l.level_doors.is_empty() {
        return Vec::new();
    }
    let f = py_float;
    let pos = l.pos.minus(b.offset);
    let (w, d, tf) = (l.width, l.depth, FLOOR_THICKNESS);
    let mut out = Vec::new();

    // Shaft doors.
    for (level, door) in shaft_doors(b, lift) {
        let name = shaft_door_name(&l.name, &b.levels[level].name, &door.name);
        let p = classify(l, door).shaft.rotate(l.yaw).plus(pos);
        let mut m = Element::new("model").attr("name", name.clone()).leaf(
            "pose",
            format!(
                "{} {} {} 0 0 {}",
                f(p.x),
                f(p.y),
                f(b.levels[level].elevation),
                f(l.yaw + door.motion_axis_orientation)
            ),
        );
        let [rl, ll] = door_links(door, "", Vec2::default(), None);
        let [rj, lj] = door_joints(
            door,
            ["right_joint", "left_joint"],
            "world",
            ["right_door", "left_door"],
        );
        match flavour {
            Flavour::Gz => m.children.extend([rl, ll, rj, lj]),
            Flavour::Classic | Flavour::Ignition => m.children.extend([rl, rj, ll, lj]),
        }
        m.push(box_link(
            "ramp",
            &format!("{} {} {}", f(door.width), f(2.0 * SHAFT_GAP), f(tf)),
            &format!("0 0 {} 0 0 0", f(-tf / 2.0)),
            "0x02",
        ));
        m.push(
            Element::new("joint")
                .attr("name", "ramp_joint")
                .attr("type", "fixed")
                .leaf("parent", "world")
                .leaf("child", "ramp"),
        );
        if l.plugins {
            m.push(door_plugin(&name, "right_joint", "left_joint", flavour));
        }
        out.push(m);
    }

    // Cabin.
    let mut platform = Element::new("link").attr("name", "platform").child(
        Element::new("inertial").leaf("mass", "1200").child(
            Element::new("inertia")
                .leaf("ixx", f(box_inertia(CABIN_MASS, w, tf)))
                .leaf("iyy", f(box_inertia(CABIN_MASS, d, tf)))
                .leaf("izz", f(box_inertia(CABIN_MASS, w, d))),
        ),
    );
    let floor_size = format!("{} {} {}", f(w), f(d), f(tf));
    let floor_pose = format!("0 0 {} 0 0 0", f(-tf / 2.0));
    platform.push(
        Element::new("visual")
            .attr("name", "floor_visual")
            .leaf("pose", floor_pose.clone())
            .child(box_geometry(&floor_size))
            .child(lift_material()),
    );
    platform.push(
        Element::new("collision")
            .attr("name", "floor_collision")
            .leaf("pose", floor_pose)
            .child(box_geometry(&floor_size))
            .child(bitmask_surface("0x01")),
    );
    for seg in cabin_walls(l) {
        let size = format!(
            "{} {} {}",
            f(seg.length),
            f(WALL_THICKNESS),
            f(CABIN_HEIGHT)
        );
        platform.push(
            Element::new("visual")
                .attr("name", format!("{}_visual", seg.name))
                .leaf("pose", seg.pose.clone())
                .child(box_geometry(&size))
                .child(lift_material()),
        );
        platform.push(
            Element::new("collision")
                .attr("name", format!("{}_collision", seg.name))
                .leaf("pose", seg.pose)
                .child(box_geometry(&size))
                .child(bitmask_surface("0x01")),
        );
    }
    let mut cabin = Element::new("model")
        .attr("name", l.name.clone())
        .child(platform)
        .child(
            Element::new("joint")
                .attr("name", "cabin_joint")
                .attr("type", "prismatic")
                .leaf("parent", "world")
                .leaf("child", "platform")
                .child(Element::new("axis").leaf("xyz", "0 0 1")),
        );
    for door in &l.doors {
        let cname = cabin_door_name(&l.name, &door.name);
        let c = classify(l, door).cabin;
        let mao = door.motion_axis_orientation;
        let rjn = format!("{cname}_right_joint");
        let ljn = format!("{cname}_left_joint");
        match flavour {
            Flavour::Gz | Flavour::Classic => {
                let mut nested = Element::new("model")
                    .attr("name", cname.clone())
                    .leaf("pose", format!("{} {} 0 0 0 {}", f(c.x), f(c.y), f(mao)));
                let [rl, ll] = door_links(door, "", Vec2::default(), None);
                if flavour == Flavour::Gz {
                    nested.children.extend([rl, ll]);
                    if l.plugins {
                        nested.push(door_plugin(&cname, &rjn, &ljn, flavour));
                    }
                    cabin.push(nested);
                    let rc = format!("{cname}::right_door");
                    let lc = format!("{cname}::left_door");
                    cabin
                        .children
                        .extend(door_joints(door, [&rjn, &ljn], "platform", [&rc, &lc]));
                } else {
                    let [rj, lj] = door_joints(
                        door,
                        ["right_joint", "left_joint"],
                        "platform",
                        ["right_door", "left_door"],
                    );
                    nested.children.extend([rl, rj, ll, lj]);
                    if l.plugins {
                        nested.push(door_plugin(&cname, "right_joint", "left_joint", flavour));
                    }
                    cabin.push(nested);
                }
            }
            Flavour::Ignition => {
                let prefix = format!("{cname}_");
                let [rl, ll] = door_links(door, &prefix, c, Some(mao));
                let rc = format!("{cname}_right_door");
                let lc = format!("{cname}_left_door");
                let [rj, lj] = door_joints(door, [&rjn, &ljn], "platform", [&rc, &lc]);
                cabin.children.extend([rl, rj, ll, lj]);
                if l.plugins {
                    cabin.push(door_plugin(&cname, &rjn, &ljn, flavour));
                }
            }
        }
    }
    if l.plugins {
        let mut floors = Vec::new();
        for ld in &l.level_doors {
            let level = &b.levels[ld.level];
            let mut floor = Element::new("floor")
                .attr("name", level.name.clone())
                .attr("elevation", f(level.elevation));
            for door in &l.doors {
                if ld.doors.iter().any(|(n, _)| *n == door.name) {
                    floor.push(
                        Element::new("door_pair")
                            .attr("cabin_door", cabin_door_name(&l.name, &door.name))
                            .attr(
                                "shaft_door",
                                shaft_door_name(&l.name, &level.name, &door.name),
                            ),
                    );
                }
            }
            floors.push(floor);
        }
        let initial = l
            .initial_floor()
            .map(|h| b.levels[h].name.clone())
            .unwrap_or_default();
        let mut children = vec![Element::new("lift_name").text(l.name.clone())];
        children.extend(floors);
        children.extend([
            Element::new("initial_floor").text(initial),
            Element::new("v_max_cabin").text("2.0"),
            Element::new("a_max_cabin").text("1.2"),
            Element::new("a_nom_cabin").text("1.0"),
            Element::new("dx_min_cabin").text("0.001"),
            Element::new("f_max_cabin").text("25323.0"),
            Element::new("cabin_joint_name").text("cabin_joint"),
        ]);
        let mut p = plugin(flavour, "Lift", "lift", "liblift.so", []);
        match flavour {
            Flavour::Gz => p.children[0].children = children,
            Flavour::Classic | Flavour::Ignition => p.children = children,
        }
        cabin.push(p);
    } else {
        cabin.push(Element::new("static").text("true"));
    }
    cabin.push(Element::new("pose").text(format!("{} {} 0 0 0 {}", f(pos.x), f(pos.y), f(l.yaw))));
    out.push(cabin);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use mapc_ir::{CoordinateSystem, Level, LevelDoors, Params, Span};

    fn lift_door(name: &str, x: f64, y: f64, width: f64) -> LiftDoor {
        LiftDoor {
            name: name.into(),
            door_type: 2,
            pos: Vec2::new(x, y),
            width,
            motion_axis_orientation: 0.0,
            span: Span::default(),
        }
    }

    /// A 2 × 3 m lift at (10, 20) with yaw π/2, a front door and a right door, served on
    /// L1 (front only) and L2 (both).
    fn building(plugins: bool) -> Building {
        let mut b = Building::new(
            "b".into(),
            CoordinateSystem::CartesianMeters,
            Params::default(),
        );
        let l1 = b.levels.append(
            Level {
                name: "L1".into(),
                ..Level::default()
            },
            Span::default(),
        );
        let l2 = b.levels.append(
            Level {
                name: "L2".into(),
                elevation: 5.0,
                ..Level::default()
            },
            Span::default(),
        );
        let ld = |level, names: &[&str]| LevelDoors {
            level,
            doors: names
                .iter()
                .map(|n| (n.to_string(), Span::default()))
                .collect(),
            span: Span::default(),
        };
        b.lifts.append(
            Lift {
                name: "Lift".into(),
                pos: Vec2::new(10.0, 20.0),
                raw: Vec2::new(10.0, 20.0),
                yaw: std::f64::consts::FRAC_PI_2,
                width: 2.0,
                depth: 3.0,
                reference_level: l1,
                initial_level: Some(l2),
                lowest_level: None,
                highest_level: None,
                plugins,
                doors: vec![
                    lift_door("front", 0.0, 1.6, 1.0),
                    lift_door("side", 1.0, 0.5, 1.2),
                ],
                level_doors: vec![ld(l1, &["front"]), ld(l2, &["side", "front"])],
            },
            Span::default(),
        );
        b
    }

    fn text<'a>(e: &'a Element, path: &[&str]) -> &'a str {
        let mut e = e;
        for p in path {
            e = e.find(p).unwrap_or_else(|| panic!("no {p}"));
        }
        e.text.as_deref().unwrap()
    }

    fn named<'a>(e: &'a Element, name: &str) -> &'a Element {
        e.children
            .iter()
            .find(|c| c.attrs.first().is_some_and(|a| a.1 == name))
            .unwrap_or_else(|| panic!("no {name}"))
    }

    #[test]
    fn side_classification() {
        let b = building(true);
        let l = &b.lifts[b.lifts.handle(0).unwrap()];
        let p = classify(l, &l.doors[0]);
        assert_eq!(p.side, Side::Front);
        assert_eq!(p.interval, (-0.5, 0.5));
        assert_eq!(p.shaft, Vec2::new(0.0, 1.5 + SHAFT_GAP));
        assert_eq!(p.cabin, Vec2::new(0.0, 1.5 - 0.025));
        let p = classify(l, &l.doors[1]);
        assert_eq!(p.side, Side::Right);
        assert_eq!(p.interval, (0.5 - 0.6, 0.5 + 0.6));
        assert_eq!(p.shaft, Vec2::new(1.0 + SHAFT_GAP, 0.5));
        // Ties go to left/right; negative coordinates to back/left.
        let mut d = lift_door("x", -1.5, -1.5, 1.0);
        d.pos = Vec2::new(-1.5, -2.0);
        assert_eq!(classify(l, &d).side, Side::Left);
        d.pos = Vec2::new(0.2, -1.4);
        assert_eq!(classify(l, &d).side, Side::Back);
    }

    #[test]
    fn walls_have_door_gaps() {
        let b = building(true);
        let l = &b.lifts[b.lifts.handle(0).unwrap()];
        let walls = cabin_walls(l);
        let names: Vec<&str> = walls.iter().map(|w| w.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "frontwall1",
                "frontwall2",
                "backwall1",
                "leftwall1",
                "rightwall1",
                "rightwall2"
            ]
        );
        // Front: [-1, -0.5] and [0.5, 1].
        assert!((walls[0].length - 0.5).abs() < 1e-12);
        assert_eq!(walls[0].pose, "-0.75 1.475 1.25 0 0 0");
        // Right: [-1.45, -0.1] and [1.1, 1.45].
        assert!((walls[4].length - 1.35).abs() < 1e-12);
        assert!((walls[5].length - 0.35).abs() < 1e-12);
        assert!(walls[5].pose.starts_with("0.975 "));
    }

    #[test]
    fn shaft_doors_and_cabin() {
        let b = building(true);
        let h = b.lifts.handle(0).unwrap();
        let names: Vec<String> = shaft_door_names(&b, h).into_iter().map(|x| x.1).collect();
        // Levels in level_doors order, doors in the lift's doors order.
        assert_eq!(
            names,
            [
                "ShaftDoor_Lift_L1_front",
                "ShaftDoor_Lift_L2_front",
                "ShaftDoor_Lift_L2_side"
            ]
        );
        let models = lift_models(&b, h, Flavour::Gz);
        assert_eq!(models.len(), 4);
        // Shaft door of the front door: cabin-frame (0, 1.55) rotated by π/2 → (-1.55, 0).
        let pose = text(&models[0], &["pose"]);
        let v: Vec<f64> = pose.split(' ').map(|x| x.parse().unwrap()).collect();
        assert!((v[0] - (10.0 - 1.55)).abs() < 1e-12 && (v[1] - 20.0).abs() < 1e-12);
        assert_eq!(v[2], 0.0);
        assert_eq!(text(&models[1], &["pose"]).split(' ').nth(2), Some("5.0"));
        let ramp = named(&models[0], "ramp");
        assert_eq!(
            text(ramp, &["visual", "geometry", "box", "size"]),
            "1.0 0.1 0.05"
        );
        let cabin = &models[3];
        let platform = named(cabin, "platform");
        let inertia = platform.find("inertial").unwrap().find("inertia").unwrap();
        assert_eq!(text(inertia, &["ixx"]), py_float(100.0 * (4.0 + 0.0025)));
        assert_eq!(text(inertia, &["iyy"]), py_float(100.0 * (9.0 + 0.0025)));
        assert_eq!(text(inertia, &["izz"]), py_float(100.0 * 13.0));
        let comp = cabin.find("plugin").unwrap().find("component").unwrap();
        assert_eq!(text(comp, &["initial_floor"]), "L2");
        let floors: Vec<&Element> = comp.children.iter().filter(|c| c.name == "floor").collect();
        assert_eq!(floors.len(), 2);
        assert_eq!(floors[1].children.len(), 2);
        assert_eq!(floors[1].attrs[1].1, "5.0");
        let j = named(cabin, "CabinDoor_Lift_side_left_joint");
        assert_eq!(text(j, &["child"]), "CabinDoor_Lift_side::left_door");
        assert_eq!(text(j, &["axis", "limit", "lower"]), "-0.6");
        assert_eq!(
            text(cabin, &["pose"]),
            format!("10.0 20.0 0 0 0 {}", py_float(std::f64::consts::FRAC_PI_2))
        );
    }

    #[test]
    fn flavours_and_static() {
        let b = building(false);
        let h = b.lifts.handle(0).unwrap();
        for flavour in [Flavour::Classic, Flavour::Ignition, Flavour::Gz] {
            let models = lift_models(&b, h, flavour);
            let cabin = models.last().unwrap();
            assert_eq!(text(cabin, &["static"]), "true");
            assert!(models.iter().all(|m| m.find("plugin").is_none()));
        }
        let b = building(true);
        let classic = lift_models(&b, h, Flavour::Classic);
        let cabin = classic.last().unwrap();
        let nested = named(cabin, "CabinDoor_Lift_front");
        assert_eq!(text(named(nested, "right_joint"), &["parent"]), "platform");
        assert_eq!(cabin.find("plugin").unwrap().attrs[1].1, "liblift.so");
        let ign = lift_models(&b, h, Flavour::Ignition);
        let cabin = ign.last().unwrap();
        let link = named(cabin, "CabinDoor_Lift_front_right_door");
        assert_eq!(text(link, &["pose"]), "0.25 1.475 1.25 0 0 0.0");
        assert!(cabin.find("model").is_none());
        // Shaft doors: interleaved links and joints in the old flavours.
        let order: Vec<&str> = ign[0]
            .children
            .iter()
            .skip(1)
            .take(4)
            .map(|c| c.attrs[0].1.as_ref())
            .collect();
        assert_eq!(
            order,
            ["right_door", "right_joint", "left_door", "left_joint"]
        );
        // No level_doors: nothing.
        let mut b = building(true);
        b.lifts[h].level_doors.clear();
        assert!(lift_models(&b, h, Flavour::Gz).is_empty());
    }

    #[test]
    fn offset_is_subtracted() {
        let mut b = building(true);
        b.offset = Vec2::new(10.0, 20.0);
        let h = b.lifts.handle(0).unwrap();
        let models = lift_models(&b, h, Flavour::Gz);
        assert!(text(models.last().unwrap(), &["pose"]).starts_with("0.0 0.0 0 "));
    }
}
