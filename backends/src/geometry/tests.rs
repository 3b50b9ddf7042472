//! Unit tests on hand-built buildings: degenerate input is skipped without panicking, wall
//! boxes, UVs and grouping, floor cut-outs.

use super::*;
use mapc_ir::{
    CoordinateSystem, Lift, Param, ParamValue, Params, Polygon, Span, Vec2, Vertex, Wall,
};

pub(crate) struct Map {
    pub(crate) b: Building,
    pub(crate) level: Handle<Level>,
}

pub(crate) fn param(name: &str, value: ParamValue) -> Param {
    Param {
        name: name.into(),
        value,
        span: Span::default(),
    }
}

impl Map {
    pub(crate) fn new() -> Map {
        let mut b = Building::new(
            "t".into(),
            CoordinateSystem::CartesianMeters,
            Params::default(),
        );
        let level = b.levels.append(
            Level {
                name: "L1".into(),
                ..Level::default()
            },
            Span::default(),
        );
        Map { b, level }
    }
    pub(crate) fn v(&mut self, x: f64, y: f64) -> Handle<Vertex> {
        let h = self.b.vertices.append(
            Vertex {
                level: self.level,
                name: String::new(),
                pos: Vec2::new(x, y),
                raw: Vec2::new(x, y),
                params: Params::default(),
                roles: Default::default(),
            },
            Span::default(),
        );
        self.b.levels[self.level].vertices.push(h);
        h
    }
    pub(crate) fn poly(&mut self, pts: &[(f64, f64)]) -> Polygon {
        let vertices = pts.iter().map(|&(x, y)| self.v(x, y)).collect();
        Polygon {
            level: self.level,
            vertices,
            params: Params::default(),
        }
    }
    pub(crate) fn floor(&mut self, pts: &[(f64, f64)], params: Vec<Param>) {
        let mut p = self.poly(pts);
        p.params = Params(params);
        let h = self.b.floors.append(p, Span::default());
        self.b.levels[self.level].floors.push(h);
    }
    pub(crate) fn hole(&mut self, pts: &[(f64, f64)]) {
        let p = self.poly(pts);
        let h = self.b.holes.append(p, Span::default());
        self.b.levels[self.level].holes.push(h);
    }
    pub(crate) fn wall(&mut self, a: (f64, f64), b: (f64, f64), params: Vec<Param>) {
        let start = self.v(a.0, a.1);
        let end = self.v(b.0, b.1);
        let h = self.b.walls.append(
            Wall {
                level: self.level,
                start,
                end,
                params: Params(params),
            },
            Span::default(),
        );
        self.b.levels[self.level].walls.push(h);
    }
    pub(crate) fn meshes(&self) -> LevelMeshes {
        level_meshes(&self.b, self.level)
    }
}

const SQUARE: &[(f64, f64)] = &[(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)];

#[test]
fn degenerate_floors_are_skipped_but_counted() {
    let mut m = Map::new();
    m.floor(&[(0.0, 0.0), (1.0, 0.0)], vec![]);
    m.floor(&[(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)], vec![]); // no area
    m.floor(&[(5.0, 5.0), (5.0, 5.0), (5.0, 5.0), (5.0, 5.0)], vec![]);
    m.floor(SQUARE, vec![]);
    m.floor(&[], vec![]);
    let meshes = m.meshes();
    let names: Vec<&str> = meshes.floors.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["floor_4"]);
    assert!((meshes.floors[0].area_facing([0.0, 0.0, 1.0]) - 100.0).abs() < 1e-12);
}

#[test]
fn self_intersecting_and_degenerate_holes_do_not_panic() {
    let mut m = Map::new();
    // Bow tie floor (E0602), a hole with two points, a bow-tie hole, a hole covering all.
    m.floor(&[(0.0, 0.0), (4.0, 4.0), (4.0, 0.0), (0.0, 4.0)], vec![]);
    m.floor(SQUARE, vec![]);
    m.hole(&[(1.0, 1.0), (2.0, 2.0)]);
    m.hole(&[(1.0, 1.0), (3.0, 3.0), (3.0, 1.0), (1.0, 3.0)]);
    let _ = m.meshes();
    m.hole(&[(-1.0, -1.0), (11.0, -1.0), (11.0, 11.0), (-1.0, 11.0)]);
    let meshes = m.meshes();
    // Everything is cut away: no empty meshes.
    assert!(meshes.floors.is_empty(), "{:?}", meshes.floors);
}

#[test]
fn holes_inside_and_across_the_edge_are_cut() {
    let mut m = Map::new();
    m.floor(SQUARE, vec![]);
    m.hole(&[(2.0, 2.0), (4.0, 2.0), (4.0, 4.0), (2.0, 4.0)]);
    m.hole(&[(9.0, 5.0), (12.0, 5.0), (12.0, 6.0), (9.0, 6.0)]);
    // A hole off the floor changes nothing.
    m.hole(&[(20.0, 20.0), (21.0, 20.0), (21.0, 21.0)]);
    let f = &m.meshes().floors[0];
    assert!((f.area_facing([0.0, 0.0, 1.0]) - (100.0 - 4.0 - 1.0)).abs() < 1e-9);
    assert!((f.area_facing([0.0, 0.0, -1.0]) - 95.0).abs() < 1e-9);
    // Input corners are kept exactly (snapped back from the overlay's grid).
    assert!(f.positions.contains(&[10.0, 10.0, 0.0]));
    assert!(f.positions.contains(&[4.0, 4.0, 0.0]));
    assert!(f
        .positions
        .iter()
        .all(|p| p[2] == 0.0 || p[2] == -FLOOR_THICKNESS));
}

#[test]
fn lift_shafts_are_cut_on_the_levels_they_serve() {
    let mut m = Map::new();
    m.floor(SQUARE, vec![]);
    let lift = |doors: bool| Lift {
        name: "lift".into(),
        pos: Vec2::new(5.0, 5.0),
        raw: Vec2::new(5.0, 5.0),
        yaw: 0.7,
        width: 1.9,
        depth: 0.9,
        reference_level: m.level,
        initial_level: None,
        lowest_level: None,
        highest_level: None,
        plugins: false,
        doors: Vec::new(),
        level_doors: if doors {
            vec![mapc_ir::LevelDoors {
                level: m.level,
                doors: Vec::new(),
                span: Span::default(),
            }]
        } else {
            Vec::new()
        },
    };
    // A lift without level doors has no shaft.
    let l = lift(false);
    m.b.lifts.append(l, Span::default());
    assert!((m.meshes().floors[0].area_facing([0.0, 0.0, 1.0]) - 100.0).abs() < 1e-9);
    let l = lift(true);
    m.b.lifts.append(l, Span::default());
    let a = m.meshes().floors[0].area_facing([0.0, 0.0, 1.0]);
    assert!((a - (100.0 - 2.0 * 1.0)).abs() < 1e-9, "{a}");
}

#[test]
fn floor_uvs_ceilings_and_materials() {
    let mut m = Map::new();
    m.floor(
        SQUARE,
        vec![
            param("texture_name", ParamValue::String("concrete".into())),
            param("texture_scale", ParamValue::Double(4.0)),
            param("texture_rotation", ParamValue::Double(180.0)),
            param("indoor", ParamValue::Int(1)),
            param("ceiling_scale", ParamValue::Double(2.0)),
            param("ceiling_emissive_map", ParamValue::String("glow".into())),
            param("metalness_map", ParamValue::String("metal".into())),
        ],
    );
    let meshes = m.meshes();
    let f = &meshes.floors[0];
    assert_eq!(f.material.texture, "concrete");
    assert_eq!(
        f.material.pbr_maps,
        [("metalness_map".into(), "metal".into())]
    );
    for (p, uv) in f.positions.iter().zip(&f.uvs) {
        assert!((uv[0] + p[0] / 4.0).abs() < 1e-12 && (uv[1] + p[1] / 4.0).abs() < 1e-12);
    }
    let c = &meshes.ceilings[0];
    assert_eq!(c.name, "ceiling_1");
    assert_eq!(c.kind, crate::MeshKind::Ceiling);
    assert_eq!(c.material.texture, "blue_linoleum");
    assert_eq!(
        c.material.pbr_maps,
        [("emissive_map".into(), "glow".into())]
    );
    assert!(c.positions.iter().all(|p| p[2] == CEILING_HEIGHT));
    assert!((c.area_facing([0.0, 0.0, -1.0]) - 100.0).abs() < 1e-9);
    assert_eq!(c.uvs[2], [5.0, 5.0]);
    let order: Vec<&str> = meshes.all().map(|m| m.name.as_str()).collect();
    assert_eq!(order, ["floor_1", "ceiling_1"]);
}

#[test]
fn wall_box_corners_and_uvs_follow_the_spec() {
    let mut m = Map::new();
    m.wall(
        (0.0, 0.0),
        (4.0, 0.0),
        vec![
            param("texture_height", ParamValue::Double(5.0)),
            param("texture_width", ParamValue::Double(2.0)),
            param("texture_scale", ParamValue::Double(0.0)),
            param("alpha", ParamValue::Double(0.25)),
        ],
    );
    let w = &m.meshes().walls[0];
    assert_eq!(w.name, "wall_1");
    assert_eq!(w.material.texture, "default");
    assert_eq!(w.material.alpha, 0.25);
    let (lo, hi) = w.bounds().unwrap();
    let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
    assert!(close(lo, [-0.05, -0.05, 0.0]) && close(hi, [4.05, 0.05, WALL_HEIGHT]));
    // 4 sides of 4.1 x 2.5 or 0.1 x 2.5, top 4.1 x 0.1.
    let area = 2.0 * 4.1 * 2.5 + 2.0 * 0.1 * 2.5 + 4.1 * 0.1;
    assert!((w.area() - area).abs() < 1e-9);
    // vt_h = 2.5 / (5 / 2) = 1, s = vt_h (texture_scale 0): north face u 0..L, v 0..1.
    assert_eq!(
        &w.uvs[..4],
        &[[0.0, 0.0], [4.0, 0.0], [4.0, 1.0], [0.0, 1.0]]
    );
    // Normals: +y (north), +x (end), -y, -x, +z.
    let face_normals: Vec<[f64; 3]> = (0..5).map(|f| w.normals[4 * f]).collect();
    let want = [
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    for (n, e) in face_normals.iter().zip(want) {
        assert!(close(*n, e), "{n:?} vs {e:?}");
    }
}

#[test]
fn walls_group_by_parameter_map() {
    let mut m = Map::new();
    let a = || {
        vec![
            param("alpha", ParamValue::Double(1.0)),
            param("texture_name", ParamValue::String("default".into())),
        ]
    };
    m.wall((0.0, 0.0), (1.0, 0.0), a());
    m.wall((1.0, 0.0), (2.0, 0.0), vec![]);
    m.wall(
        (2.0, 0.0),
        (3.0, 0.0),
        vec![param("alpha", ParamValue::Int(1))],
    );
    m.wall(
        (3.0, 0.0),
        (4.0, 0.0),
        vec![param("texture_name", ParamValue::String("wall".into()))],
    );
    m.wall((4.0, 0.0), (5.0, 0.0), a().into_iter().rev().collect());
    // Zero length (E0605): a t x t box, no panic.
    m.wall((6.0, 0.0), (6.0, 0.0), vec![]);
    let groups = wall_groups(&m.b, m.level);
    let sizes: Vec<usize> = groups.iter().map(|g| g.walls.len()).collect();
    assert_eq!(sizes, [5, 1]);
    let walls = m.meshes().walls;
    assert_eq!(walls[1].material.texture, "wall");
    assert_eq!(walls[0].positions.len(), 5 * 20);
}

#[test]
fn empty_level_has_no_meshes() {
    let m = Map::new();
    assert!(m.meshes().is_empty());
    assert!(crate::level_obj_files(&m.b, m.level).is_empty());
}
