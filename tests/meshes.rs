//! Level meshes (floors, ceilings, walls; `mapc_backends::level_meshes`) and their OBJ files:
//! - every floor's top face covers the polygon minus its holes and lift shafts, with the
//!   expected area computed independently of the meshing code (shoelace, Sutherland-Hodgman
//!   clipping against the convex cutters, inclusion-exclusion);
//! - every wall face's normal points out of its wall;
//! - per level, floor and wall areas and wall bounding boxes agree with the reference OBJ
//!   meshes in ../shared/reference/<map>/models (skipped when ../shared is absent);
//! - snapshots of counts, areas and bounds on the fixtures.

use mapc_backends::{level_meshes, level_obj_files, wall_origin, Mesh, MeshKind};
use mapc_ir::{Building, Handle, Level};
use std::fmt::Write;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn shared() -> Option<PathBuf> {
    let p = root().join("../shared");
    p.join("maps").is_dir().then_some(p)
}

fn load(path: &Path) -> Building {
    let text = std::fs::read_to_string(path).unwrap();
    let parsed = mapc_frontend::parse_str(&path.display().to_string(), &text);
    parsed
        .valid_building()
        .unwrap_or_else(|| panic!("{}: errors {:#?}", path.display(), parsed.diagnostics))
        .clone()
}

/// Valid fixtures with floors or walls.
const FIXTURES: &[&str] = &[
    "fixtures/meshes/cutouts.building.yaml",
    "fixtures/two_level_clinic.building.yaml",
    "fixtures/cartesian_warehouse.building.yaml",
    "fixtures/wgs84_campus.building.yaml",
    "fixtures/legacy_2019.building.yaml",
    "fixtures/web_mercator_legacy.building.yaml",
];

fn demo_maps() -> Vec<(String, Building)> {
    let Some(shared) = shared() else {
        return Vec::new();
    };
    let mut maps: Vec<String> = std::fs::read_dir(shared.join("maps"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    maps.sort();
    maps.into_iter()
        .map(|m| {
            let b = load(&shared.join(format!("maps/{m}/{m}.building.yaml")));
            (m, b)
        })
        .collect()
}

fn all_inputs() -> Vec<(String, Building)> {
    let mut v: Vec<(String, Building)> = FIXTURES
        .iter()
        .map(|f| (f.to_string(), load(&root().join(f))))
        .collect();
    v.extend(demo_maps());
    v
}

// ---------------------------------------------------------------------------------------
// Independent area of a floor minus its cutters

type Pt = [f64; 2];

fn shoelace(p: &[Pt]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}

fn ccw(mut p: Vec<Pt>) -> Vec<Pt> {
    if shoelace(&p) < 0.0 {
        p.reverse();
    }
    p
}

fn is_convex(p: &[Pt]) -> bool {
    let n = p.len();
    (0..n).all(|i| {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) >= -1e-12
    })
}

/// Sutherland-Hodgman: `subject` (any simple polygon) clipped by the convex CCW `clip`. The
/// result may contain zero-width bridges where a non-convex subject splits, which do not
/// change its signed area.
fn clip(subject: &[Pt], clip: &[Pt]) -> Vec<Pt> {
    let mut out = subject.to_vec();
    for i in 0..clip.len() {
        let (a, b) = (clip[i], clip[(i + 1) % clip.len()]);
        let side = |p: Pt| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        let input = std::mem::take(&mut out);
        for j in 0..input.len() {
            let (p, q) = (input[j], input[(j + 1) % input.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// |F \ (C1 ∪ … ∪ Cn)| = Σ over subsets S of (−1)^|S| |F ∩ ⋂S|, every C convex.
fn area_minus(floor: &[Pt], cutters: &[Vec<Pt>]) -> f64 {
    fn rec(region: &[Pt], cutters: &[Vec<Pt>], start: usize, sign: f64) -> f64 {
        let a = shoelace(region);
        if a.abs() < 1e-12 {
            return 0.0;
        }
        let mut total = sign * a;
        for i in start..cutters.len() {
            let r = clip(region, &cutters[i]);
            if r.len() >= 3 {
                total += rec(&r, cutters, i + 1, -sign);
            }
        }
        total
    }
    rec(&ccw(floor.to_vec()), cutters, 0, 1.0)
}

fn pts(b: &Building, vs: &[Handle<mapc_ir::Vertex>]) -> Vec<Pt> {
    vs.iter()
        .map(|&v| [b.vertices[v].pos.x, b.vertices[v].pos.y])
        .collect()
}

/// Expected top area of floor `i` of `level`, or `None` for a skipped (degenerate) floor.
fn expected_floor_area(b: &Building, level: Handle<Level>, i: usize) -> Option<f64> {
    let lvl = &b.levels[level];
    let floor = pts(b, &b.floors[lvl.floors[i]].vertices);
    if floor.len() < 3 || shoelace(&floor) == 0.0 {
        return None;
    }
    // Work relative to the floor's first point: wgs84 maps have 10⁴-10⁵ m coordinates.
    let o = floor[0];
    let local =
        |p: Vec<Pt>| -> Vec<Pt> { p.into_iter().map(|q| [q[0] - o[0], q[1] - o[1]]).collect() };
    let mut cutters: Vec<Vec<Pt>> = lvl
        .holes
        .iter()
        .map(|&h| local(pts(b, &b.holes[h].vertices)))
        .filter(|h| h.len() >= 3 && shoelace(h) != 0.0)
        .map(ccw)
        .collect();
    for l in b.lifts_on_level(level) {
        let c = b.lifts[l].shaft_corners().map(|c| [c.x, c.y]).to_vec();
        cutters.push(ccw(local(c)));
    }
    for c in &cutters {
        assert!(is_convex(c), "the independent area needs convex holes");
    }
    Some(area_minus(&local(floor), &cutters))
}

fn floor_number(m: &Mesh) -> usize {
    m.name.trim_start_matches("floor_").parse().unwrap()
}

#[test]
fn floor_top_area_is_polygon_minus_holes_and_shafts() {
    let mut checked = 0;
    for (name, b) in all_inputs() {
        for (level, lvl) in b.levels.iter() {
            let meshes = level_meshes(&b, level);
            let mut seen = Vec::new();
            for m in &meshes.floors {
                let n = floor_number(m);
                seen.push(n);
                let expected =
                    expected_floor_area(&b, level, n - 1).expect("meshed a degenerate floor");
                let top = m.area_facing([0.0, 0.0, 1.0]);
                let bottom = m.area_facing([0.0, 0.0, -1.0]);
                let rel = (top - expected).abs() / expected.max(1e-12);
                assert!(
                    rel <= 1e-6,
                    "{name} {} {}: top area {top} != expected {expected} (rel {rel:e})",
                    lvl.name,
                    m.name
                );
                assert!(
                    (bottom - top).abs() <= 1e-9 * top.max(1.0),
                    "{name} {}: slab faces differ",
                    m.name
                );
                checked += 1;
            }
            // Every floor with area is meshed.
            for i in 0..lvl.floors.len() {
                if expected_floor_area(&b, level, i).is_some_and(|a| a > 1e-9) {
                    assert!(
                        seen.contains(&(i + 1)),
                        "{name} {}: floor_{} missing",
                        lvl.name,
                        i + 1
                    );
                }
            }
            for c in &meshes.ceilings {
                let n: usize = c.name.trim_start_matches("ceiling_").parse().unwrap();
                let f = meshes.floors.iter().find(|f| floor_number(f) == n).unwrap();
                let down = c.area_facing([0.0, 0.0, -1.0]);
                let top = f.area_facing([0.0, 0.0, 1.0]);
                assert!((down - top).abs() <= 1e-9 * top, "{name}: ceiling_{n} area");
                assert_eq!(
                    c.area_facing([0.0, 0.0, 1.0]),
                    0.0,
                    "{name}: ceiling_{n} faces down"
                );
            }
        }
    }
    assert!(checked > 0);
}

#[test]
fn wall_face_normals_point_out_of_their_wall() {
    let mut faces = 0;
    for (name, b) in all_inputs() {
        for (level, _) in b.levels.iter() {
            for m in level_meshes(&b, level).walls {
                assert_eq!(m.kind, MeshKind::Walls);
                assert_eq!(m.positions.len() % 20, 0, "20 vertices per wall");
                assert_eq!(
                    m.triangles.len() * 2,
                    m.positions.len(),
                    "10 triangles per wall"
                );
                for (k, t) in m.triangles.iter().enumerate() {
                    // Each wall owns 20 vertices and 10 triangles.
                    let wall = k / 10;
                    let verts = &m.positions[20 * wall..20 * wall + 20];
                    let centre = verts.iter().fold([0.0; 3], |c, p| {
                        [c[0] + p[0] / 20.0, c[1] + p[1] / 20.0, 0.0]
                    });
                    let centre = [centre[0], centre[1], 1.25];
                    let [a, bb, c] = t.map(|i| m.positions[i as usize]);
                    let u = [bb[0] - a[0], bb[1] - a[1], bb[2] - a[2]];
                    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
                    let g = [
                        u[1] * v[2] - u[2] * v[1],
                        u[2] * v[0] - u[0] * v[2],
                        u[0] * v[1] - u[1] * v[0],
                    ];
                    let len = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
                    if len < 1e-12 {
                        continue;
                    }
                    let g = g.map(|x| x / len);
                    let mid = [
                        (a[0] + bb[0] + c[0]) / 3.0,
                        (a[1] + bb[1] + c[1]) / 3.0,
                        (a[2] + bb[2] + c[2]) / 3.0,
                    ];
                    let out = [mid[0] - centre[0], mid[1] - centre[1], mid[2] - centre[2]];
                    for i in t {
                        let n = m.normals[*i as usize];
                        let d = n[0] * g[0] + n[1] * g[1] + n[2] * g[2];
                        assert!(
                            d > 0.999,
                            "{name} {}: vertex normal {n:?} vs winding {g:?}",
                            m.name
                        );
                        let o = n[0] * out[0] + n[1] * out[1] + n[2] * out[2];
                        assert!(
                            o > 0.0,
                            "{name} {}: normal {n:?} points into its wall",
                            m.name
                        );
                    }
                    faces += 1;
                }
            }
        }
    }
    assert!(faces > 0);
}

// ---------------------------------------------------------------------------------------
// Against the reference OBJ meshes

struct Obj {
    v: Vec<[f64; 3]>,
    f: Vec<[usize; 3]>,
}

fn parse_obj(text: &str) -> Obj {
    let mut v = Vec::new();
    let mut f = Vec::new();
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it.map(|x| x.parse().unwrap()).collect();
                v.push([c[0], c[1], c[2]]);
            }
            Some("f") => {
                let idx: Vec<usize> = it
                    .map(|x| x.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect();
                for k in 1..idx.len() - 1 {
                    f.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Obj { v, f }
}

impl Obj {
    fn area_where(&self, keep: impl Fn([[f64; 3]; 3]) -> bool) -> f64 {
        self.f
            .iter()
            .map(|t| t.map(|i| self.v[i]))
            .filter(|t| keep(*t))
            .map(|[a, b, c]| {
                let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
                let g = [
                    u[1] * v[2] - u[2] * v[1],
                    u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0],
                ];
                0.5 * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt()
            })
            .sum()
    }
    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        self.v.iter().fold(
            ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |(lo, hi), p| {
                (
                    [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                    [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
                )
            },
        )
    }
}

/// `<pose>` of link `name` in a model.sdf, as x y.
fn link_pose(sdf: &str, name: &str) -> [f64; 2] {
    let start = sdf.find(&format!("<link name=\"{name}\">")).unwrap();
    let body = &sdf[start..start + sdf[start..].find("</link>").unwrap()];
    let Some(p) = body.find("<pose>") else {
        return [0.0, 0.0];
    };
    let text = &body[p + 6..p + body[p..].find("</pose>").unwrap()];
    let c: Vec<f64> = text
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    [c[0], c[1]]
}

/// Our wall OBJ has the reference's lines (numbers within rounding), except that the two
/// end-face normals of every wall are swapped back (the reference quirk).
fn same_wall_obj(ours: &str, theirs: &str, what: &str) {
    let a: Vec<&str> = ours.lines().collect();
    let b: Vec<&str> = theirs.lines().collect();
    assert_eq!(a.len(), b.len(), "{what}: line count");
    let vn_start = b.iter().position(|l| l.starts_with("vn ")).unwrap();
    let nums = |l: &str| -> Vec<f64> {
        l.split_whitespace()
            .skip(1)
            .map(|x| x.parse().unwrap())
            .collect()
    };
    for (i, (x, y)) in a.iter().zip(&b).enumerate() {
        let kind = y.split_whitespace().next().unwrap_or("");
        match kind {
            "v" | "vt" => {
                let (p, q) = (nums(x), nums(y));
                assert!(
                    x.starts_with(&format!("{kind} "))
                        && p.iter().zip(&q).all(|(u, v)| (u - v).abs() <= 1.5e-4),
                    "{what} line {}: {x} vs {y}",
                    i + 1
                );
            }
            "vn" => {
                // vn 1 is up; then 4 per wall: north, east, south, west. The reference
                // has west's normal second and east's fourth.
                let k = i - vn_start;
                let j = if k == 0 {
                    i
                } else {
                    match (k - 1) % 4 {
                        1 => i + 2,
                        3 => i - 2,
                        _ => i,
                    }
                };
                let (p, q) = (nums(x), nums(b[j]));
                assert!(
                    p.iter().zip(&q).all(|(u, v)| (u - v).abs() <= 1.5e-4),
                    "{what} line {}: {x} vs reference {}",
                    i + 1,
                    b[j]
                );
            }
            _ => assert_eq!(x, y, "{what} line {}", i + 1),
        }
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-12)
}

#[test]
fn level_meshes_match_reference_areas_and_wall_bounds() {
    let Some(shared) = shared() else {
        println!("skipped: ../shared not found");
        return;
    };
    let mut levels = 0;
    let mut uncut_floors = 0;
    for (map, b) in demo_maps() {
        for (level, lvl) in b.levels.iter() {
            let dir = shared.join(format!("reference/{map}/models/{}_{}", b.name, lvl.name));
            let meshes = level_meshes(&b, level);
            let files: Vec<String> = std::fs::read_dir(dir.join("meshes"))
                .map(|rd| {
                    rd.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                        .filter(|f| f.ends_with(".obj"))
                        .collect()
                })
                .unwrap_or_default();
            // The reference meshes are shifted by −offset for wgs84 maps (our OBJ writer does
            // the same); areas do not care, bounds get the offset back.
            let (ox, oy) = (b.offset.x, b.offset.y);
            let sdf = std::fs::read_to_string(dir.join("model.sdf")).unwrap();
            let obj_files = level_obj_files(&b, level);

            // Floors: top faces (z = 0). The demo maps have no indoor floors, so the
            // reference has no ceilings to compare with (ours are checked against floors above).
            let mut ref_floor = 0.0;
            let mut ref_floors = 0;
            let mut ref_walls = Vec::new();
            for f in &files {
                let obj = parse_obj(&std::fs::read_to_string(dir.join("meshes").join(f)).unwrap());
                if f.starts_with("floor_") {
                    ref_floor += obj.area_where(|t| t.iter().all(|p| p[2] == 0.0));
                    ref_floors += 1;
                } else if f.starts_with("wall_") {
                    ref_walls.push((f.trim_end_matches(".obj").to_string(), obj));
                } else {
                    assert!(f.starts_with("ceiling_"), "{map}: unexpected {f}");
                }
            }
            assert_eq!(
                meshes.floors.len(),
                ref_floors,
                "{map} {}: floor meshes",
                lvl.name
            );
            let ours: f64 = meshes
                .floors
                .iter()
                .map(|m| m.area_facing([0.0, 0.0, 1.0]))
                .sum();
            println!(
                "{map} {}: floor top area {ours:.6} (reference {ref_floor:.6})",
                lvl.name
            );
            if ref_floors > 0 {
                assert!(
                    rel(ours, ref_floor) <= 1e-3,
                    "{map} {}: floor area {ours} vs reference {ref_floor}",
                    lvl.name
                );
            }

            // Floors not cut by holes or shafts keep the polygon's own vertices, in order,
            // as the reference's vertex list starts.
            for m in &meshes.floors {
                let poly = &b.floors[lvl.floors[floor_number(m) - 1]];
                if m.positions.len() != 2 * poly.vertices.len() {
                    continue;
                }
                let path = PathBuf::from(format!("{}_{}/meshes/{}.obj", b.name, lvl.name, m.name));
                let ours = parse_obj(
                    std::str::from_utf8(
                        &obj_files.iter().find(|f| f.path == path).unwrap().contents,
                    )
                    .unwrap(),
                );
                let theirs = parse_obj(
                    &std::fs::read_to_string(dir.join(format!("meshes/{}.obj", m.name))).unwrap(),
                );
                for (i, (p, q)) in ours.v.iter().zip(&theirs.v).enumerate() {
                    assert!(
                        p.iter()
                            .zip(q)
                            .all(|(u, v)| (u - v).abs() <= 1e-9 * v.abs().max(1.0)),
                        "{map} {} {} v {}: {p:?} vs {q:?}",
                        lvl.name,
                        m.name,
                        i + 1
                    );
                }
                uncut_floors += 1;
            }

            // Walls: the same faces (4 sides + top cap per wall), so the same area; bounds
            // per wall_k are the OBJ's plus the link pose (plus the offset) in the reference.
            ref_walls.sort_by_key(|(n, _)| n.trim_start_matches("wall_").parse::<usize>().unwrap());
            assert_eq!(
                meshes.walls.len(),
                ref_walls.len(),
                "{map} {}: wall meshes",
                lvl.name
            );
            let ours: f64 = meshes.walls.iter().map(Mesh::area).sum();
            let theirs: f64 = ref_walls.iter().map(|(_, o)| o.area_where(|_| true)).sum();
            println!(
                "{map} {}: wall area {ours:.6} (reference {theirs:.6})",
                lvl.name
            );
            if !ref_walls.is_empty() {
                assert!(
                    rel(ours, theirs) <= 1e-3,
                    "{map} {}: wall area {ours} vs {theirs}",
                    lvl.name
                );
            }
            for (m, (name, obj)) in meshes.walls.iter().zip(&ref_walls) {
                assert_eq!(&m.name, name);
                let pose = link_pose(&sdf, name);
                let (rlo, rhi) = obj.bounds();
                let (lo, hi) = m.bounds().unwrap();
                let rlo = [rlo[0] + pose[0] + ox, rlo[1] + pose[1] + oy, rlo[2]];
                let rhi = [rhi[0] + pose[0] + ox, rhi[1] + pose[1] + oy, rhi[2]];
                for i in 0..3 {
                    assert!(
                        (lo[i] - rlo[i]).abs() <= 1e-4 && (hi[i] - rhi[i]).abs() <= 1e-4,
                        "{map} {} {name}: bounds {lo:?}-{hi:?} vs reference {rlo:?}-{rhi:?}",
                        lvl.name
                    );
                }
                // Our OBJ file is laid out like the reference's: same origin (the link pose)
                // and the same bounds relative to it.
                let origin = wall_origin(m, b.offset);
                assert!(
                    (origin[0] - pose[0]).abs() <= 1e-4 && (origin[1] - pose[1]).abs() <= 1e-4,
                    "{map} {name}: origin {origin:?} vs pose {pose:?}"
                );
                let path = PathBuf::from(format!("{}_{}/meshes/{name}.obj", b.name, lvl.name));
                let file = obj_files.iter().find(|f| f.path == path).unwrap();
                let ref_text =
                    std::fs::read_to_string(dir.join(format!("meshes/{name}.obj"))).unwrap();
                same_wall_obj(
                    std::str::from_utf8(&file.contents).unwrap(),
                    &ref_text,
                    &format!("{map} {name}"),
                );
                let (wlo, whi) = parse_obj(std::str::from_utf8(&file.contents).unwrap()).bounds();
                let (rlo, rhi) = obj.bounds();
                for i in 0..3 {
                    assert!(
                        (wlo[i] - rlo[i]).abs() <= 2e-4 && (whi[i] - rhi[i]).abs() <= 2e-4,
                        "{map} {name}: OBJ bounds {wlo:?}-{whi:?} vs {rlo:?}-{rhi:?}"
                    );
                }
            }
            levels += 1;
        }
    }
    assert!(levels >= 7);
    println!("{uncut_floors} uncut floors have the reference's vertex list");
    assert!(uncut_floors > 0);
}

#[test]
fn obj_files_round_trip_the_meshes() {
    for (name, b) in all_inputs() {
        for (level, lvl) in b.levels.iter() {
            let meshes = level_meshes(&b, level);
            let files = level_obj_files(&b, level);
            let prefix = format!("{}_{}/meshes/", b.name, lvl.name);
            if meshes.floors.is_empty() && meshes.walls.is_empty() {
                assert!(files.is_empty());
                continue;
            }
            for f in &files {
                assert!(
                    f.path.to_string_lossy().starts_with(&prefix),
                    "{name}: {}",
                    f.path.display()
                );
            }
            for m in meshes
                .floors
                .iter()
                .chain(&meshes.ceilings)
                .chain(&meshes.walls)
            {
                let path = PathBuf::from(&prefix).join(format!("{}.obj", m.name));
                let f = files.iter().find(|f| f.path == path).unwrap();
                let obj = parse_obj(std::str::from_utf8(&f.contents).unwrap());
                assert_eq!(obj.f.len(), m.triangles.len());
                let a = obj.area_where(|_| true);
                // Walls are written with 4 decimals.
                let tol = if m.kind == MeshKind::Walls {
                    1e-3
                } else {
                    1e-9
                };
                assert!(
                    rel(a, m.area()) <= tol,
                    "{name} {}: {a} vs {}",
                    m.name,
                    m.area()
                );
                assert!(files
                    .iter()
                    .any(|f| f.path == PathBuf::from(&prefix).join(format!("{}.mtl", m.name))));
            }
            let material = files
                .iter()
                .find(|f| f.path.ends_with("model.material"))
                .unwrap();
            let text = std::str::from_utf8(&material.contents).unwrap();
            assert_eq!(
                text.matches("material ").count(),
                meshes.floors.len() + meshes.ceilings.len() + meshes.walls.len()
            );
            // Deterministic.
            assert_eq!(files, level_obj_files(&b, level));
        }
    }
}

// ---------------------------------------------------------------------------------------
// Snapshots: counts, areas, bounds

fn summary(b: &Building) -> String {
    let mut s = String::new();
    for (level, lvl) in b.levels.iter() {
        let meshes = level_meshes(b, level);
        let _ = writeln!(s, "level {}", lvl.name);
        for m in meshes
            .floors
            .iter()
            .chain(&meshes.ceilings)
            .chain(&meshes.walls)
        {
            let (lo, hi) = m.bounds().unwrap();
            let f = |v: [f64; 3]| format!("({:.4}, {:.4}, {:.4})", v[0], v[1], v[2]);
            let _ = writeln!(
                s,
                "  {} [{}] vertices {} triangles {} area {:.6} up {:.6} bounds {} {} texture {} alpha {} pbr {:?}",
                m.name,
                m.material.name,
                m.positions.len(),
                m.triangles.len(),
                m.area(),
                m.area_facing([0.0, 0.0, 1.0]),
                f(lo),
                f(hi),
                m.material.texture,
                m.material.alpha,
                m.material.pbr_maps,
            );
        }
    }
    s
}

#[test]
fn snapshot_fixture_meshes() {
    for f in FIXTURES {
        let b = load(&root().join(f));
        let stem = Path::new(f)
            .file_name()
            .unwrap()
            .to_string_lossy()
            .trim_end_matches(".building.yaml")
            .to_string();
        let text = summary(&b);
        if text.lines().any(|l| l.starts_with("  ")) {
            insta::assert_snapshot!(stem, text);
        }
    }
}

#[test]
fn cutouts_fixture_cuts_what_it_should() {
    let b = load(&root().join("fixtures/meshes/cutouts.building.yaml"));
    let l1 = b.level_by_name("L1").unwrap();
    let m = level_meshes(&b, l1);
    let names: Vec<&str> = m.floors.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["floor_1", "floor_2", "floor_3"]);
    assert_eq!(m.ceilings.len(), 1);
    assert_eq!(m.ceilings[0].name, "ceiling_1");
    // Walls: {alpha 1, default} twice (key order does not matter), the textured one, and
    // the two parameterless ones, which normalise to the first map.
    assert_eq!(m.walls.len(), 2);
    assert_eq!(m.walls[0].positions.len(), 5 * 20);
    assert_eq!(m.walls[1].material.texture, "wall_white");
    assert_eq!(m.walls[1].material.alpha, 0.5);
    // The untouched square keeps its four corners exactly.
    let sq = &m.floors[1];
    assert_eq!(sq.positions.len(), 8);
    assert_eq!(sq.positions[0], [30.0, 0.0, 0.0]);
    // Texture rotation 90° and scale 2 on floor_1: (x, y) → (y, −x) / 2.
    let f1 = &m.floors[0];
    for (p, uv) in f1.positions.iter().zip(&f1.uvs) {
        assert!((uv[0] - p[1] / 2.0).abs() < 1e-12 && (uv[1] + p[0] / 2.0).abs() < 1e-12);
    }
    // L2 is served by lift_a only.
    let l2 = b.level_by_name("L2").unwrap();
    let area = level_meshes(&b, l2).floors[0].area_facing([0.0, 0.0, 1.0]);
    assert!((area - (160.0 - 2.1 * 2.1)).abs() < 1e-9, "{area}");
}

/// Random star-shaped floors with random rotated rectangular holes (overlapping each other
/// and the floor's edge, or off the floor): the mesh covers exactly the independent area.
#[test]
fn random_floors_minus_random_holes() {
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for case in 0..1000 {
        let n = 3 + (rnd() * 10.0) as usize;
        // Angular gaps under π keep the origin inside, so the polygon is simple.
        let angles: Vec<f64> = (0..n)
            .map(|i| (i as f64 + 0.4 * rnd()) * std::f64::consts::TAU / n as f64)
            .collect();
        let mut verts: Vec<Pt> = angles
            .iter()
            .map(|a| {
                let r = 2.0 + 8.0 * rnd();
                [r * a.cos(), r * a.sin()]
            })
            .collect();
        if rnd() < 0.5 {
            verts.reverse();
        }
        let holes = (rnd() * 4.0) as usize;
        let mut hole_pts: Vec<Vec<Pt>> = Vec::new();
        for _ in 0..holes {
            let (cx, cy) = (20.0 * rnd() - 10.0, 20.0 * rnd() - 10.0);
            let (w, h, t) = (0.5 + 5.0 * rnd(), 0.5 + 5.0 * rnd(), rnd() * 3.0);
            let (s, c) = f64::sin_cos(t);
            hole_pts.push(
                [(-w, -h), (w, -h), (w, h), (-w, h)]
                    .iter()
                    .map(|&(x, y)| {
                        [
                            cx + c * x / 2.0 - s * y / 2.0,
                            cy + s * x / 2.0 + c * y / 2.0,
                        ]
                    })
                    .collect(),
            );
        }
        let mut yaml = String::from("coordinate_system: cartesian_meters\nlevels:\n  L1:\n    elevation: 0\n    floors:\n      - parameters: {}\n        vertices: [");
        let idx: Vec<String> = (0..n).map(|i| i.to_string()).collect();
        yaml += &idx.join(", ");
        yaml += "]\n    holes:\n";
        let mut next = n;
        for _ in &hole_pts {
            yaml += &format!(
                "      - parameters: {{}}\n        vertices: [{}, {}, {}, {}]\n",
                next,
                next + 1,
                next + 2,
                next + 3
            );
            next += 4;
        }
        yaml += "    vertices:\n";
        for p in verts.iter().chain(hole_pts.iter().flatten()) {
            yaml += &format!("      - [{:?}, {:?}, 0, \"\"]\n", p[0], p[1]);
        }
        yaml += "name: random\n";
        let parsed = mapc_frontend::parse_str("random", &yaml);
        let b = parsed.building.as_ref().expect("random map parses");
        let level = b.level_by_name("L1").unwrap();
        let meshes = level_meshes(b, level);
        let expected = expected_floor_area(b, level, 0).unwrap();
        let got: f64 = meshes
            .floors
            .iter()
            .map(|m| m.area_facing([0.0, 0.0, 1.0]))
            .sum();
        assert!(
            (got - expected).abs() <= 1e-6 * expected.max(1.0),
            "case {case}: {got} vs {expected}\n{yaml}"
        );
    }
}

/// Meshing never panics, even on the broken maps of `fixtures/invalid` (whatever building
/// the frontend still returns, errors and all).
#[test]
fn meshing_invalid_fixtures_does_not_panic() {
    let mut meshed = 0;
    for e in std::fs::read_dir(root().join("fixtures/invalid")).unwrap() {
        let path = e.unwrap().path();
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue;
        };
        let parsed = mapc_frontend::parse_str(&path.display().to_string(), &text);
        let Some(b) = parsed.building.as_ref() else {
            continue;
        };
        for (level, _) in b.levels.iter() {
            let _ = level_obj_files(b, level);
            meshed += 1;
        }
    }
    assert!(meshed > 0);
}
