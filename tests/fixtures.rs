//! Hand-made fixture maps (`fixtures/*.building.yaml`): snapshots of the IR summary and of
//! every nav graph, plus value tests whose expected numbers come from formulas (the spec's
//! transforms, an independent transverse Mercator, plain segment geometry), not from mapc.
//!
//! Snapshots live in `tests/snapshots/`; after an intended change run
//! `INSTA_UPDATE=always cargo test --test fixtures` and review the diff.

use mapc_ir::{Building, Handle, Level, Vec2};
use saphyr::{LoadableYamlNode, YamlOwned};
use std::collections::BTreeMap;
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Every fixture, with the graph files `mapc nav` must write for it and the warning codes it
/// is meant to raise (none has errors).
const FIXTURES: &[(&str, &[i64], &[&str])] = &[
    ("two_level_clinic", &[0], &[]),
    ("cartesian_warehouse", &[0, 1, 9], &[]),
    ("wgs84_campus", &[0], &[]),
    ("web_mercator_legacy", &[0], &["W0108"]),
    ("legacy_2019", &[0], &[]),
];

// ---------------------------------------------------------------------------------------
// Helpers

fn fixture_path(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(file)
}

fn building_path(name: &str) -> PathBuf {
    fixture_path(&format!("{name}.building.yaml"))
}

fn parse(path: &Path) -> mapc_frontend::Parsed {
    mapc_frontend::load(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// The fixture's building; panics if the frontend reported any error.
fn building(name: &str) -> Building {
    let parsed = parse(&building_path(name));
    let errors: Vec<_> = parsed.diagnostics.iter().filter(|d| d.is_error()).collect();
    assert!(errors.is_empty(), "{name}: unexpected errors {errors:#?}");
    parsed
        .building
        .unwrap_or_else(|| panic!("{name}: no building"))
}

/// Nav graph documents keyed by graph index, as written by the nav backend.
fn nav_docs(b: &Building) -> BTreeMap<i64, YamlOwned> {
    mapc_backends::nav_graphs(b)
        .into_iter()
        .map(|f| {
            let graph: i64 = f
                .path
                .file_stem()
                .and_then(|s| s.to_str())
                .and_then(|s| s.parse().ok())
                .unwrap_or_else(|| panic!("unexpected nav file name {}", f.path.display()));
            let text = String::from_utf8(f.contents).expect("nav output is UTF-8");
            (graph, yaml(&text))
        })
        .collect()
}

fn yaml(text: &str) -> YamlOwned {
    let mut docs = YamlOwned::load_from_str(text).expect("valid YAML");
    assert_eq!(docs.len(), 1, "one YAML document expected");
    docs.remove(0)
}

/// The fixture file itself, read with an independent YAML loader.
fn fixture_yaml(name: &str) -> YamlOwned {
    let text = std::fs::read_to_string(building_path(name)).expect("fixture readable");
    yaml(&text)
}

fn num(y: &YamlOwned) -> f64 {
    y.as_floating_point()
        .or_else(|| y.as_integer().map(|i| i as f64))
        .unwrap_or_else(|| panic!("not a number: {y:?}"))
}

fn seq(y: &YamlOwned) -> &Vec<YamlOwned> {
    y.as_vec()
        .unwrap_or_else(|| panic!("not a sequence: {y:?}"))
}

fn str_of<'a>(map: &'a YamlOwned, key: &str) -> Option<&'a str> {
    map.as_mapping_get(key).and_then(|v| v.as_str())
}

fn level(b: &Building, name: &str) -> Handle<Level> {
    b.level_by_name(name)
        .unwrap_or_else(|| panic!("no level {name}"))
}

#[track_caller]
fn assert_close(actual: Vec2, expected: Vec2, tol: f64, what: &str) {
    let d = actual.minus(expected).norm();
    assert!(
        d <= tol,
        "{what}: got ({}, {}), expected ({}, {}), off by {d}",
        actual.x,
        actual.y,
        expected.x,
        expected.y
    );
}

/// A lane of a nav document: `[from, to, {params}]`.
struct NavLane<'a> {
    from: usize,
    to: usize,
    params: &'a YamlOwned,
}

impl NavLane<'_> {
    fn str(&self, key: &str) -> Option<&str> {
        str_of(self.params, key)
    }
    fn has(&self, key: &str) -> bool {
        self.params.as_mapping_get(key).is_some()
    }
}

fn nav_lanes<'a>(doc: &'a YamlOwned, level: &str) -> Vec<NavLane<'a>> {
    seq(&doc["levels"][level]["lanes"])
        .iter()
        .map(|l| {
            let l = seq(l);
            NavLane {
                from: l[0].as_integer().expect("lane start index") as usize,
                to: l[1].as_integer().expect("lane end index") as usize,
                params: &l[2],
            }
        })
        .collect()
}

/// `[x, y, {params}]` of a nav document level.
fn nav_vertices<'a>(doc: &'a YamlOwned, level: &str) -> Vec<(Vec2, &'a YamlOwned)> {
    seq(&doc["levels"][level]["vertices"])
        .iter()
        .map(|v| {
            let v = seq(v);
            (Vec2::new(num(&v[0]), num(&v[1])), &v[2])
        })
        .collect()
}

/// The nav vertex called `name` on `level`, as (index, position, params).
fn nav_vertex<'a>(doc: &'a YamlOwned, level: &str, name: &str) -> (usize, Vec2, &'a YamlOwned) {
    nav_vertices(doc, level)
        .into_iter()
        .enumerate()
        .find(|(_, (_, p))| str_of(p, "name") == Some(name))
        .map(|(i, (pos, p))| (i, pos, p))
        .unwrap_or_else(|| panic!("no nav vertex {name} on {level}"))
}

fn lane_between<'a, 'd>(lanes: &'a [NavLane<'d>], from: usize, to: usize) -> Vec<&'a NavLane<'d>> {
    lanes
        .iter()
        .filter(|l| l.from == from && l.to == to)
        .collect()
}

/// Do closed segments a-b and p-q cross or touch? Plain orientation tests.
fn segments_intersect(a: Vec2, b: Vec2, p: Vec2, q: Vec2) -> bool {
    let orient = |o: Vec2, u: Vec2, v: Vec2| u.minus(o).cross(v.minus(o));
    let eps = 1e-9 * (1.0 + a.norm().max(p.norm()));
    let (d1, d2) = (orient(p, q, a), orient(p, q, b));
    let (d3, d4) = (orient(a, b, p), orient(a, b, q));
    let parallel = a.minus(b).cross(p.minus(q)).abs() <= eps;
    !parallel && d1 * d2 <= eps && d3 * d4 <= eps
}

// ---------------------------------------------------------------------------------------
// Transverse Mercator, independent of proj4rs (which uses the Poder/Engsager algorithm):
// Krüger's series to third order in n, in the form of Karney (2011) "Transverse Mercator
// with an accuracy of a few nanometers", eq. (35), also the form in Wikipedia's "Universal
// Transverse Mercator coordinate system". Truncation error is far below 0.1 mm within
// 150 km of the central meridian, which is where the fixtures are.

struct Tm {
    lon0: f64,
    lat0: f64,
    k0: f64,
    false_easting: f64,
    false_northing: f64,
}

/// EPSG:32648, WGS 84 / UTM zone 48N.
const UTM_48N: Tm = Tm {
    lon0: 105.0,
    lat0: 0.0,
    k0: 0.9996,
    false_easting: 500_000.0,
    false_northing: 0.0,
};

/// EPSG:3414, SVY21 / Singapore TM (WGS 84 ellipsoid; lat0 1°22'N, lon0 103°50'E).
const SVY21: Tm = Tm {
    lon0: 103.0 + 50.0 / 60.0,
    lat0: 1.0 + 22.0 / 60.0,
    k0: 1.0,
    false_easting: 28_001.642,
    false_northing: 38_744.572,
};

/// Unscaled (ξ, η) series terms times A, for longitude difference `dlon` (degrees).
fn kruger(lat: f64, dlon: f64) -> (f64, f64) {
    let a: f64 = 6_378_137.0;
    let f: f64 = 1.0 / 298.257_223_563;
    let n = f / (2.0 - f);
    let big_a = a / (1.0 + n) * (1.0 + n * n / 4.0 + n.powi(4) / 64.0);
    let alpha = [
        n / 2.0 - 2.0 * n * n / 3.0 + 5.0 * n.powi(3) / 16.0,
        13.0 * n * n / 48.0 - 3.0 * n.powi(3) / 5.0,
        61.0 * n.powi(3) / 240.0,
    ];
    let e = 2.0 * n.sqrt() / (1.0 + n);
    let (phi, lam) = (lat.to_radians(), dlon.to_radians());
    let t = (phi.sin().atanh() - e * (e * phi.sin()).atanh()).sinh();
    let xi = t.atan2(lam.cos());
    let eta = (lam.sin() / (1.0 + t * t).sqrt()).atanh();
    let (mut east, mut north) = (eta, xi);
    for (j, al) in alpha.iter().enumerate() {
        let k = 2.0 * (j + 1) as f64;
        east += al * (k * xi).cos() * (k * eta).sinh();
        north += al * (k * xi).sin() * (k * eta).cosh();
    }
    (big_a * east, big_a * north)
}

/// (easting, northing) of a longitude/latitude in degrees.
fn transverse_mercator(tm: &Tm, lon: f64, lat: f64) -> Vec2 {
    let (e, n) = kruger(lat, lon - tm.lon0);
    let (_, n0) = kruger(tm.lat0, 0.0);
    Vec2::new(
        tm.false_easting + tm.k0 * e,
        tm.false_northing + tm.k0 * (n - n0),
    )
}

#[test]
fn transverse_mercator_sanity() {
    // The natural origin maps to the false origin; a point on the central meridian has the
    // false easting; east of the meridian is east of the false easting.
    assert_close(
        transverse_mercator(&SVY21, SVY21.lon0, SVY21.lat0),
        Vec2::new(SVY21.false_easting, SVY21.false_northing),
        1e-9,
        "SVY21 origin",
    );
    assert_close(
        transverse_mercator(&UTM_48N, 105.0, 0.0),
        Vec2::new(500_000.0, 0.0),
        1e-9,
        "UTM origin",
    );
    // One degree of latitude along the central meridian near the equator is 110.574 km
    // (meridian arc of WGS 84) times k0.
    let p = transverse_mercator(&UTM_48N, 105.0, 1.0);
    assert!((p.y - 0.9996 * 110_574.389).abs() < 0.01, "{}", p.y);
    assert!(transverse_mercator(&UTM_48N, 106.0, 1.0).x > 500_000.0);
}

// ---------------------------------------------------------------------------------------
// Snapshots

/// Summary and nav snapshots of one fixture; the set of graph files is checked too, since a
/// graph that disappeared would otherwise go unnoticed.
fn snapshot(name: &str) {
    let &(_, graphs, _) = FIXTURES.iter().find(|f| f.0 == name).expect("listed");
    let b = building(name);
    insta::assert_snapshot!(format!("summary__{name}"), mapc_ir::summary(&b));
    let files = mapc_backends::nav_graphs(&b);
    let written: Vec<String> = files.iter().map(|f| f.path.display().to_string()).collect();
    let expected: Vec<String> = graphs.iter().map(|g| format!("{g}.yaml")).collect();
    assert_eq!(written, expected, "{name}: nav files");
    for f in files {
        let graph = f.path.file_stem().unwrap().to_string_lossy().into_owned();
        let text = String::from_utf8(f.contents).expect("UTF-8");
        insta::assert_snapshot!(format!("nav__{name}__{graph}"), text);
    }
}

#[test]
fn snapshot_two_level_clinic() {
    snapshot("two_level_clinic");
}

#[test]
fn snapshot_cartesian_warehouse() {
    snapshot("cartesian_warehouse");
}

#[test]
fn snapshot_wgs84_campus() {
    snapshot("wgs84_campus");
}

#[test]
fn snapshot_web_mercator_legacy() {
    snapshot("web_mercator_legacy");
}

#[test]
fn snapshot_legacy_2019() {
    snapshot("legacy_2019");
}

// ---------------------------------------------------------------------------------------
// Diagnostics and the command line

#[test]
fn fixtures_have_no_errors_and_only_intended_warnings() {
    for &(name, _, warnings) in FIXTURES {
        let parsed = parse(&building_path(name));
        assert!(parsed.building.is_some(), "{name}: no building");
        let mut errors = Vec::new();
        let mut got = Vec::new();
        for d in &parsed.diagnostics {
            if d.is_error() {
                errors.push(format!("{} {}", d.code, d.message));
            } else {
                got.push(d.code);
            }
        }
        assert!(errors.is_empty(), "{name}: errors {errors:?}");
        assert_eq!(got, warnings, "{name}: warnings {:#?}", parsed.diagnostics);
        assert!(parsed.valid_building().is_some());
    }
}

#[test]
fn cli_check_and_nav_on_every_fixture() {
    let exe = env!("CARGO_BIN_EXE_mapc");
    for &(name, graphs, _) in FIXTURES {
        let input = building_path(name);
        let out = Command::new(exe).arg("check").arg(&input).output().unwrap();
        assert!(
            out.status.success(),
            "mapc check {name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );

        let dir = tempfile::tempdir().unwrap();
        let out = Command::new(exe)
            .arg("nav")
            .arg(&input)
            .arg(dir.path())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "mapc nav {name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        // mapc's manifest (what it wrote, for pruning) aside.
        let mut files: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| !n.starts_with(".mapc-manifest"))
            .collect();
        files.sort_by_key(|f| f.trim_end_matches(".yaml").parse::<i64>().unwrap_or(-1));
        let expected: Vec<String> = graphs.iter().map(|g| format!("{g}.yaml")).collect();
        assert_eq!(files, expected, "{name}: files written by mapc nav");
        // The files on disk are exactly what the backend produces.
        for f in mapc_backends::nav_graphs(&building(name)) {
            let on_disk = std::fs::read(dir.path().join(&f.path)).unwrap();
            assert_eq!(on_disk, f.contents, "{name}: {}", f.path.display());
        }
    }
}

#[test]
fn graph_nine_and_above_is_written() {
    // The reference generator only emits graphs 0..8; mapc writes every graph that has a lane.
    let b = building("cartesian_warehouse");
    let docs = nav_docs(&b);
    assert_eq!(docs.keys().copied().collect::<Vec<_>>(), vec![0, 1, 9]);
    let lanes = nav_lanes(&docs[&9], "L1");
    assert_eq!(lanes.len(), 2, "one two-way lane in graph 9");
    let (goal, _, params) = nav_vertex(&docs[&9], "L1", "crowd_goal_1");
    assert_eq!(str_of(params, "human_goal_set_name"), Some("crowd_goal_1"));
    assert!(lanes.iter().any(|l| l.to == goal));
    // Human lanes (graph_idx 9 too) are not robot lanes: crowd_start is only on a human lane.
    assert!(nav_vertices(&docs[&9], "L1")
        .iter()
        .all(|(_, p)| str_of(p, "name") != Some("crowd_start")));
}

#[test]
fn project_file_gives_the_same_building() {
    let project = parse(&fixture_path("legacy_2019.project.yaml"));
    let direct = parse(&building_path("legacy_2019"));
    assert!(!project.has_errors(), "{:#?}", project.diagnostics);
    assert_eq!(project.sources.len(), 2, "project file and building file");
    let (p, d) = (
        project.valid_building().expect("building through project"),
        direct.valid_building().expect("building"),
    );
    assert_eq!(mapc_ir::summary(p), mapc_ir::summary(d));
    assert_eq!(
        p.name, "legacy_office",
        "`building_name` is the 2019 spelling of `name`"
    );
    assert_eq!(mapc_backends::nav_graphs(p), mapc_backends::nav_graphs(d));
}

// ---------------------------------------------------------------------------------------
// Coordinate systems

/// Checks the reference level of a reference_image fixture against the spec's formula:
/// s = distance / pixel length of the measurement, vertex (x, y) px -> (s·x, -s·y) m.
fn check_reference_scale(name: &str, level_name: &str, expected_scale: f64) {
    let file = fixture_yaml(name);
    let lv = &file["levels"][level_name];
    let vertices = seq(&lv["vertices"]);
    let m = seq(&seq(&lv["measurements"])[0]);
    let px = |i: usize| {
        let v = seq(&vertices[i]);
        Vec2::new(num(&v[0]), num(&v[1]))
    };
    let (i, j) = (m[0].as_integer().unwrap(), m[1].as_integer().unwrap());
    let distance = num(&seq(&m[2]["distance"])[1]);
    let s = distance / px(i as usize).minus(px(j as usize)).norm();
    assert!((s - expected_scale).abs() < 1e-12, "{name}: scale {s}");

    let b = building(name);
    let lh = level(&b, level_name);
    assert!((b.levels[lh].transform.scale - s).abs() < 1e-12);
    assert_eq!(b.levels[lh].vertices.len(), vertices.len());
    for (k, &vh) in b.levels[lh].vertices.iter().enumerate() {
        let p = px(k);
        assert_close(
            b.vertices[vh].pos,
            Vec2::new(s * p.x, -s * p.y),
            1e-9,
            &format!("{name} {level_name} vertex {k}"),
        );
    }
    for (k, m) in seq(&lv["models"]).iter().enumerate() {
        let mh = b.levels[lh].models[k];
        let expected = Vec2::new(s * num(&m["x"]), -s * num(&m["y"]));
        assert_close(b.models[mh].pos, expected, 1e-9, "model");
        // The reference level is not rotated, so the yaw is the file's.
        assert!((b.models[mh].yaw - num(&m["yaw"])).abs() < 1e-12);
    }
}

#[test]
fn reference_image_scale_comes_from_the_measurement() {
    // 24 m over 480 px.
    check_reference_scale("two_level_clinic", "L1", 24.0 / 480.0);
    // 10 m over 200 px, in a 2019 file without `coordinate_system`.
    check_reference_scale("legacy_2019", "L1", 10.0 / 200.0);
}

#[test]
fn second_level_is_aligned_by_its_fiducials() {
    // L1 is 20 px/m (24 m over 480 px). L2 was drawn at 40 px/m and turned a quarter turn:
    // its fiducial F1 at px (600, 200) is L1's F1 at px (100, 100) = (5, -5) m, and going
    // down the L2 image (+V) is going east (+x) in L1 while going right (+U) is going north.
    // So an L2 pixel (U, V) lies at (5 + (V - 200)/40, -5 + (U - 600)/40) metres.
    let expected = |u: f64, v: f64| Vec2::new(5.0 + (v - 200.0) / 40.0, -5.0 + (u - 600.0) / 40.0);

    let b = building("two_level_clinic");
    let file = fixture_yaml("two_level_clinic");
    let l2 = level(&b, "L2");
    let t = b.levels[l2].transform;
    assert!(
        (t.scale - 0.025).abs() < 1e-12,
        "0.05 m/px halved: {}",
        t.scale
    );
    assert!((t.rotation - FRAC_PI_2).abs() < 1e-12, "{}", t.rotation);
    assert_close(t.translation, Vec2::new(0.0, -20.0), 1e-9, "translation");

    let vertices = seq(&file["levels"]["L2"]["vertices"]);
    assert_eq!(vertices.len(), b.levels[l2].vertices.len());
    for (k, (v, &vh)) in vertices.iter().zip(&b.levels[l2].vertices).enumerate() {
        let v = seq(v);
        let want = expected(num(&v[0]), num(&v[1]));
        assert_close(b.vertices[vh].pos, want, 1e-9, &format!("L2 vertex {k}"));
    }
    // Models move the same way and turn with the level: yaw 0 drawn on L2 faces north.
    let models = seq(&file["levels"]["L2"]["models"]);
    assert_eq!(models.len(), b.levels[l2].models.len());
    for (m, &mh) in models.iter().zip(&b.levels[l2].models) {
        let model = &b.models[mh];
        let want = expected(num(&m["x"]), num(&m["y"]));
        assert_close(model.pos, want, 1e-9, &model.name);
        assert!((model.yaw - (num(&m["yaw"]) + FRAC_PI_2)).abs() < 1e-12);
        assert_eq!(
            model.z,
            num(&m["z"]),
            "height above the level, not elevation"
        );
    }

    // Every fiducial of L2 lands on the L1 fiducial of the same name.
    let l1 = level(&b, "L1");
    for &f2 in &b.levels[l2].fiducials {
        let f2 = &b.fiducials[f2];
        let f1 = b.levels[l1]
            .fiducials
            .iter()
            .map(|&h| &b.fiducials[h])
            .find(|f| f.name == f2.name)
            .expect("shared fiducial");
        assert_close(f2.pos, f1.pos, 1e-9, &f2.name);
    }

    // The lift cabin vertex of each level sits at the lift centre, px (400, 200) on L1.
    let centre = Vec2::new(400.0 * 0.05, -200.0 * 0.05);
    let lift = b.lifts.iter().next().unwrap().1;
    assert_close(lift.pos, centre, 1e-9, "lift");
    for lh in [l1, l2] {
        let cabins: Vec<Vec2> = b.levels[lh]
            .vertices
            .iter()
            .map(|&h| &b.vertices[h])
            .filter(|v| v.roles.lift_cabin.as_deref() == Some("lift_1"))
            .map(|v| v.pos)
            .collect();
        assert_eq!(cabins.len(), 1);
        assert_close(cabins[0], centre, 1e-9, "cabin vertex");
    }
}

#[test]
fn cartesian_meters_keep_coordinates_and_publish_the_offset() {
    let b = building("cartesian_warehouse");
    let file = fixture_yaml("cartesian_warehouse");
    let params = &file["parameters"];
    let offset = [
        num(&seq(&params["offset_x"])[1]),
        num(&seq(&params["offset_y"])[1]),
    ];
    assert_eq!(offset, [25_000.0, 31_000.0]);

    let vertices = seq(&file["levels"]["L1"]["vertices"]);
    let lh = level(&b, "L1");
    let mut by_name = BTreeMap::new();
    for (v, &vh) in vertices.iter().zip(&b.levels[lh].vertices) {
        let v = seq(v);
        let raw = Vec2::new(num(&v[0]), num(&v[1]));
        assert_eq!(b.vertices[vh].pos, raw);
        by_name.insert(v[3].as_str().unwrap().to_string(), raw);
    }
    let mut checked = 0;
    for (g, doc) in nav_docs(&b) {
        let o: Vec<f64> = seq(&doc["offset"]).iter().map(num).collect();
        assert_eq!(o, offset, "graph {g} offset");
        assert_eq!(str_of(&doc, "crs_name"), Some("EPSG:3414"));
        // Nav vertices are the file's coordinates: the offset is published, not subtracted.
        for (pos, p) in nav_vertices(&doc, "L1") {
            assert_eq!(pos, by_name[str_of(p, "name").unwrap()]);
            checked += 1;
        }
    }
    assert_eq!(checked, 8 + 3 + 2);
}

#[test]
fn wgs84_projects_to_utm_zone_48n() {
    let b = building("wgs84_campus");
    let file = fixture_yaml("wgs84_campus");
    assert_eq!(b.crs_name.as_deref(), Some("EPSG:32648"));
    assert_eq!(b.offset, Vec2::new(364_200.0, 143_700.0));

    let lh = level(&b, "L1");
    let vertices = seq(&file["levels"]["L1"]["vertices"]);
    for (v, &vh) in vertices.iter().zip(&b.levels[lh].vertices) {
        let v = seq(v);
        let (lon, lat) = (num(&v[0]), num(&v[1]));
        let want = transverse_mercator(&UTM_48N, lon, lat);
        assert_close(b.vertices[vh].pos, want, 1e-3, &format!("({lon}, {lat})"));
    }
    // Easting first: west of the 105°E meridian the easting is below 500 km, and the
    // northing of a point 1.3° north of the equator is about 144 km.
    let west = b.vertices[b.levels[lh].vertices[0]].pos;
    assert!((364_000.0..365_000.0).contains(&west.x), "{}", west.x);
    assert!((143_000.0..145_000.0).contains(&west.y), "{}", west.y);
    let m = &b.models[b.levels[lh].models[0]];
    assert_close(
        m.pos,
        transverse_mercator(&UTM_48N, 103.7803, 1.3007),
        1e-3,
        "model",
    );

    let docs = nav_docs(&b);
    let doc = &docs[&0];
    assert_eq!(str_of(doc, "crs_name"), Some("EPSG:32648"));
    let o: Vec<f64> = seq(&doc["offset"]).iter().map(num).collect();
    assert_eq!(o, [364_200.0, 143_700.0]);
    let (_, pos, _) = nav_vertex(doc, "L1", "campus_north");
    assert_close(
        pos,
        transverse_mercator(&UTM_48N, 103.7804, 1.3009),
        1e-3,
        "nav",
    );
}

#[test]
fn web_mercator_goes_through_epsg3857() {
    // Spec §7.5: world pixels -> EPSG:3857 metres (y already negated in the file), then to
    // generate_crs (SVY21 here). EPSG:3857 -> lon/lat is the inverse spherical Mercator.
    let r = 6_378_137.0;
    let to_svy21 = |x: f64, y: f64| {
        let east = r * PI * (x - 128.0) / 128.0;
        let north = r * PI * (128.0 + y) / 128.0;
        let lon = (east / r).to_degrees();
        let lat = (2.0 * (north / r).exp().atan() - FRAC_PI_2).to_degrees();
        transverse_mercator(&SVY21, lon, lat)
    };
    let b = building("web_mercator_legacy");
    let file = fixture_yaml("web_mercator_legacy");
    assert_eq!(b.crs_name.as_deref(), Some("EPSG:3414"));
    let lh = level(&b, "L1");
    let vertices = seq(&file["levels"]["L1"]["vertices"]);
    for (v, &vh) in vertices.iter().zip(&b.levels[lh].vertices) {
        let v = seq(v);
        let want = to_svy21(num(&v[0]), num(&v[1]));
        assert_close(b.vertices[vh].pos, want, 1e-3, "vertex");
    }
    // The vertex named `origin` defines the offset.
    let origin = b.levels[lh]
        .vertices
        .iter()
        .map(|&h| &b.vertices[h])
        .find(|v| v.name == "origin")
        .unwrap();
    assert_eq!(b.offset, origin.pos);
    // About 20 m between neighbouring vertices (0.000128 world pixel).
    let east = b.vertices[b.levels[lh].vertices[1]].pos;
    assert!((east.minus(origin.pos).norm() - 20.03).abs() < 0.05);
    let doc = &nav_docs(&b)[&0];
    let o: Vec<f64> = seq(&doc["offset"]).iter().map(num).collect();
    assert_eq!(o, [origin.pos.x, origin.pos.y]);
}

// ---------------------------------------------------------------------------------------
// Nav graph semantics

#[test]
fn door_name_is_on_exactly_the_lanes_that_cross_a_door() {
    let mut crossing = BTreeMap::<String, usize>::new();
    let mut without = 0;
    for &(name, _, _) in FIXTURES {
        let b = building(name);
        for (g, doc) in nav_docs(&b) {
            let doors = doc["doors"].as_mapping().expect("doors mapping");
            for (lname, _) in doc["levels"].as_mapping().unwrap() {
                let lname = lname.as_str().unwrap();
                let vertices = nav_vertices(&doc, lname);
                for lane in nav_lanes(&doc, lname) {
                    let (a, z) = (vertices[lane.from].0, vertices[lane.to].0);
                    let crossed: Vec<&str> = doors
                        .iter()
                        .filter(|(_, d)| str_of(d, "map") == Some(lname))
                        .filter(|(_, d)| {
                            let e = seq(&d["endpoints"]);
                            let p = |i: usize| Vec2::new(num(&seq(&e[i])[0]), num(&seq(&e[i])[1]));
                            segments_intersect(a, z, p(0), p(1))
                        })
                        .map(|(n, _)| n.as_str().unwrap())
                        .collect();
                    let what = format!("{name} graph {g} {lname} lane {}->{}", lane.from, lane.to);
                    match lane.str("door_name") {
                        Some(d) => {
                            assert!(crossed.contains(&d), "{what}: {d} not crossed");
                            *crossing.entry(d.to_string()).or_default() += 1;
                        }
                        None => {
                            assert!(crossed.is_empty(), "{what}: crosses {crossed:?}");
                            without += 1;
                        }
                    }
                }
            }
        }
    }
    // Every door type is crossed by a two-way lane, so each name is on both directions.
    let expected: BTreeMap<String, usize> = [
        "L1_lobby_door",    // hinged
        "L1_pharmacy_door", // double_sliding
        "L2_ward_a_door",   // sliding
        "L2_ward_b_door",   // double_hinged
        "campus_gate",      // double_sliding, on a wgs84 map (degrees in the file)
        "main_door",        // hinged, 2019 file
    ]
    .into_iter()
    .map(|d| (d.to_string(), 2))
    .collect();
    assert_eq!(crossing, expected);
    assert!(without > 10, "most lanes cross no door");

    // The clinic's charger lane crosses nothing, in either direction.
    let b = building("two_level_clinic");
    let doc = &nav_docs(&b)[&0];
    let lanes = nav_lanes(doc, "L1");
    let (c, _, _) = nav_vertex(doc, "L1", "tinyRobot1_charger");
    let (l, _, _) = nav_vertex(doc, "L1", "lobby");
    for lane in lane_between(&lanes, c, l)
        .into_iter()
        .chain(lane_between(&lanes, l, c))
    {
        assert!(!lane.has("door_name"));
    }
}

#[test]
fn door_kinds_are_read() {
    let b = building("two_level_clinic");
    let kinds: BTreeMap<&str, &str> = b
        .doors
        .iter()
        .map(|(_, d)| (d.name.as_str(), d.kind.as_str()))
        .collect();
    assert_eq!(
        kinds,
        BTreeMap::from([
            ("L1_lobby_door", "hinged"),
            ("L1_pharmacy_door", "double_sliding"),
            ("L2_ward_a_door", "sliding"),
            ("L2_ward_b_door", "double_hinged"),
        ])
    );
    let ward_b = b
        .doors
        .iter()
        .find(|(_, d)| d.name == "L2_ward_b_door")
        .unwrap()
        .1;
    assert_eq!(ward_b.motion_direction, -1);
}

#[test]
fn one_way_and_two_way_lanes() {
    let b = building("cartesian_warehouse");
    let docs = nav_docs(&b);
    let doc = &docs[&0];
    let lanes = nav_lanes(doc, "L1");
    let idx = |n: &str| nav_vertex(doc, "L1", n).0;

    // Graph 0 of the file has 5 two-way and 2 one-way lanes: 5 * 2 + 2 entries.
    let file = fixture_yaml("cartesian_warehouse");
    let (mut two, mut one) = (0, 0);
    for l in seq(&file["levels"]["L1"]["lanes"]) {
        let p = &seq(l)[2];
        if seq(&p["graph_idx"])[1].as_integer() == Some(0) {
            if seq(&p["bidirectional"])[1].as_bool() == Some(true) {
                two += 1;
            } else {
                one += 1;
            }
        }
    }
    assert_eq!((two, one), (5, 2));
    assert_eq!(lanes.len(), 2 * two + one);
    assert_eq!(
        lanes.iter().filter(|l| l.has("is_bidirectional")).count(),
        one
    );

    // One-way aisle_1 -> pass_1 (orientation forward): one entry, none backwards.
    let (a1, p1) = (idx("aisle_1"), idx("pass_1"));
    let fwd = lane_between(&lanes, a1, p1);
    assert_eq!(fwd.len(), 1);
    assert_eq!(
        fwd[0]
            .params
            .as_mapping_get("is_bidirectional")
            .and_then(|v| v.as_bool()),
        Some(false)
    );
    assert_eq!(fwd[0].str("orientation_constraint"), Some("forward"));
    assert!(lane_between(&lanes, p1, a1).is_empty());

    // One-way pass_1 -> aisle_2 with a speed limit.
    let a2 = idx("aisle_2");
    let l = lane_between(&lanes, p1, a2);
    assert_eq!(l.len(), 1);
    assert_eq!(num(&l[0].params["speed_limit"]), 1.2);

    // Two-way charger_a <-> hold_a, orientation backward: the reverse lane is `forward`, and
    // no `is_bidirectional` key is written.
    let (c, h) = (idx("charger_a"), idx("hold_a"));
    let (there, back) = (lane_between(&lanes, c, h), lane_between(&lanes, h, c));
    assert_eq!((there.len(), back.len()), (1, 1));
    assert_eq!(there[0].str("orientation_constraint"), Some("backward"));
    assert_eq!(back[0].str("orientation_constraint"), Some("forward"));
    assert!(!there[0].has("is_bidirectional") && !back[0].has("is_bidirectional"));
    assert!(!there[0].has("speed_limit"), "speed_limit 0 means none");

    // Two-way hold_a <-> aisle_1: speed limit and lane mutex in both directions.
    for l in lane_between(&lanes, h, a1)
        .into_iter()
        .chain(lane_between(&lanes, a1, h))
    {
        assert_eq!(num(&l.params["speed_limit"]), 0.5);
        assert_eq!(l.str("mutex"), Some("aisle_1_mutex"));
    }
    assert_eq!(lanes.iter().filter(|l| l.has("mutex")).count(), 2);

    // Demo mock lift lane pickup <-> dropoff.
    let (pk, dr) = (idx("pickup"), idx("dropoff"));
    for l in lane_between(&lanes, pk, dr)
        .into_iter()
        .chain(lane_between(&lanes, dr, pk))
    {
        assert_eq!(l.str("demo_mock_floor_name"), Some("L2"));
        assert_eq!(l.str("demo_mock_lift_name"), Some("mock_lift"));
    }
    assert_eq!(
        lanes
            .iter()
            .filter(|l| l.has("demo_mock_lift_name"))
            .count(),
        2
    );

    // Graph 1 has its own lanes and vertex numbering.
    let g1 = nav_lanes(&docs[&1], "L1");
    assert_eq!(g1.len(), 3);
    assert_eq!(nav_vertices(&docs[&1], "L1").len(), 3);
}

#[test]
fn dock_and_undock_names_on_lanes_at_a_dock() {
    let b = building("cartesian_warehouse");
    let doc = &nav_docs(&b)[&0];
    let lanes = nav_lanes(doc, "L1");
    let (dock, _, params) = nav_vertex(doc, "L1", "dock_in");
    assert_eq!(str_of(params, "dock_name"), Some("dock_1"));
    for l in &lanes {
        let into = l.to == dock;
        let out_of = l.from == dock;
        assert_eq!(
            l.str("dock_name"),
            into.then_some("dock_1"),
            "{}->{}",
            l.from,
            l.to
        );
        assert_eq!(
            l.str("undock_name"),
            out_of.then_some("dock_1"),
            "{}->{}",
            l.from,
            l.to
        );
    }
    assert_eq!(lanes.iter().filter(|l| l.to == dock).count(), 1);
    assert_eq!(lanes.iter().filter(|l| l.from == dock).count(), 1);
}

#[test]
fn every_waypoint_role_is_read_and_passed_through() {
    let b = building("cartesian_warehouse");
    let v = |name: &str| {
        b.vertices
            .iter()
            .map(|(_, v)| v)
            .find(|v| v.name == name)
            .unwrap_or_else(|| panic!("no vertex {name}"))
    };
    let charger = &v("charger_a").roles;
    assert!(charger.is_charger && charger.is_parking_spot && !charger.is_holding_point);
    assert_eq!(charger.spawn_robot_type.as_deref(), Some("TinyRobot"));
    assert_eq!(charger.spawn_robot_name.as_deref(), Some("bot_a"));
    assert!(v("hold_a").roles.is_holding_point);
    assert_eq!(v("hold_a").roles.mutex.as_deref(), Some("charger_zone"));
    assert!(v("pass_1").roles.is_passthrough_point);
    assert!(v("clean_zone").roles.is_cleaning_zone);
    assert_eq!(v("aisle_1").roles.merge_radius, Some(0.5));
    assert_eq!(v("dock_in").roles.dock_name.as_deref(), Some("dock_1"));
    assert_eq!(
        v("pickup").roles.pickup_dispenser.as_deref(),
        Some("dispenser_1")
    );
    assert_eq!(
        v("dropoff").roles.dropoff_ingestor.as_deref(),
        Some("ingestor_1")
    );
    assert_eq!(
        v("crowd_goal_1").roles.human_goal_set_name.as_deref(),
        Some("crowd_goal_1")
    );
    assert_eq!(v("aisle_2").roles, Default::default());

    // Every vertex param is copied into the nav graphs, whichever graph uses the vertex.
    let docs = nav_docs(&b);
    let mut seen = BTreeMap::<String, String>::new();
    for doc in docs.values() {
        for (_, p) in nav_vertices(doc, "L1") {
            let name = str_of(p, "name").unwrap().to_string();
            for (k, val) in p.as_mapping().unwrap() {
                let k = k.as_str().unwrap();
                if k != "name" {
                    let val = match (val.as_str(), val.as_bool()) {
                        (Some(s), _) => s.to_string(),
                        (_, Some(x)) => x.to_string(),
                        _ => num(val).to_string(),
                    };
                    seen.insert(format!("{name}.{k}"), val);
                }
            }
        }
    }
    let expected: BTreeMap<String, String> = [
        ("charger_a.is_charger", "true"),
        ("charger_a.is_parking_spot", "true"),
        ("charger_a.spawn_robot_name", "bot_a"),
        ("charger_a.spawn_robot_type", "TinyRobot"),
        ("hold_a.is_holding_point", "true"),
        ("hold_a.mutex", "charger_zone"),
        ("aisle_1.merge_radius", "0.5"),
        ("pass_1.is_passthrough_point", "true"),
        ("dock_in.dock_name", "dock_1"),
        ("pickup.pickup_dispenser", "dispenser_1"),
        ("dropoff.dropoff_ingestor", "ingestor_1"),
        ("clean_zone.is_cleaning_zone", "true"),
        ("crowd_goal_1.human_goal_set_name", "crowd_goal_1"),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.to_string()))
    .collect();
    assert_eq!(seen, expected);
}

#[test]
fn lift_cabin_vertices_carry_the_lift_name() {
    let b = building("two_level_clinic");
    let lift = b.lifts.iter().next().unwrap().1;
    assert_eq!(lift.name, "lift_1");
    // The shaft passes through both levels (lowest L1, highest L2).
    for name in ["L1", "L2"] {
        let on: Vec<_> = b.lifts_on_level(level(&b, name)).collect();
        assert_eq!(on.len(), 1, "{name}");
    }
    let doc = &nav_docs(&b)[&0];
    // Shaft: 2 m x 2 m cabin centred at (20, -10), yaw 0, plus 0.05 m on each side.
    let in_shaft = |p: Vec2| (p.x - 20.0).abs() <= 1.05 && (p.y + 10.0).abs() <= 1.05;
    let mut cabins = 0;
    for lname in ["L1", "L2"] {
        let vertices = nav_vertices(doc, lname);
        for (pos, p) in &vertices {
            let tagged = str_of(p, "lift");
            assert_eq!(tagged.is_some(), in_shaft(*pos), "{lname} {pos:?}");
            assert_eq!(tagged, str_of(p, "lift_cabin"));
            if tagged.is_some() {
                assert_eq!(tagged, Some("lift_1"));
                cabins += 1;
            }
        }
        // A lane goes into the cabin and one comes out of it.
        let cabin = vertices
            .iter()
            .position(|(_, p)| str_of(p, "lift").is_some())
            .unwrap();
        let lanes = nav_lanes(doc, lname);
        assert_eq!(lanes.iter().filter(|l| l.to == cabin).count(), 1, "{lname}");
        assert_eq!(
            lanes.iter().filter(|l| l.from == cabin).count(),
            1,
            "{lname}"
        );
    }
    assert_eq!(cabins, 2);
    let pos: Vec<f64> = seq(&doc["lifts"]["lift_1"]["position"])
        .iter()
        .map(num)
        .collect();
    assert_eq!(pos, [20.0, -10.0, 0.0]);
    let dims: Vec<f64> = seq(&doc["lifts"]["lift_1"]["dims"])
        .iter()
        .map(num)
        .collect();
    assert_eq!(dims, [2.0, 2.0]);
}

#[test]
fn every_key_is_read() {
    // Elements the nav graphs do not use still reach the IR.
    let clinic = building("two_level_clinic");
    let l1 = &clinic.levels[level(&clinic, "L1")];
    assert_eq!((l1.walls.len(), l1.floors.len(), l1.holes.len()), (4, 1, 1));
    assert_eq!(
        (l1.models.len(), l1.fiducials.len(), l1.measurements.len()),
        (2, 3, 1)
    );
    let door = |n: &str| clinic.doors.iter().find(|(_, d)| d.name == n).unwrap().1;
    assert_eq!(door("L1_lobby_door").motion_axis, mapc_ir::MotionAxis::End);
    assert!(door("L1_pharmacy_door").plugin);
    assert!(
        !door("L2_ward_b_door").plugin,
        "plugin: none is a static door"
    );
    let lift = clinic.lifts.iter().next().unwrap().1;
    assert_eq!(lift.doors.len(), 2);
    assert_eq!(lift.level_doors.len(), 2);
    assert_eq!(lift.initial_floor(), Some(level(&clinic, "L1")));

    let w = building("cartesian_warehouse");
    let l = &w.levels[level(&w, "L1")];
    assert_eq!(l.human_lanes.len(), 1);
    assert_eq!((l.x_meters, l.y_meters), (Some(30.0), Some(20.0)));
    assert_eq!(l.features.len(), 1);
    assert_eq!(l.constraints[0].ids.len(), 2);
    assert_eq!(l.layers.len(), 1);
    assert_eq!(l.layers[0].features.len(), 1);
    assert_eq!(l.layers[0].scale, 0.05);
    assert_eq!(w.graphs.len(), 3);
    let cs = w.crowd_sim.as_ref().expect("crowd_sim");
    assert!(cs.enable);
    assert_eq!(cs.goal_sets[0].set_area, ["crowd_goal_1"]);
    assert_eq!(cs.transitions.len(), 1);
    assert_eq!(cs.model_types.len(), 1);

    let campus = building("wgs84_campus");
    let layer = &campus.levels[level(&campus, "L1")].layers[0];
    assert_eq!(layer.translation, Vec2::new(103.78, 1.3009));

    // 2019 models have no z, static or dispensable: the defaults apply.
    let legacy = building("legacy_2019");
    let m = legacy.models.iter().next().unwrap().1;
    assert_eq!((m.z, m.is_static, m.dispensable), (0.0, true, false));
    assert_eq!(legacy.coordinate_system.as_str(), "reference_image");
}
