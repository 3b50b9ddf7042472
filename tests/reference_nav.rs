//! Acceptance: for each demo map in ../shared/maps, `mapc nav` writes graphs with the same
//! meaning as the reference generator's in ../shared/reference/<map>/nav. Both sides are
//! parsed (with saphyr, an independent YAML loader) and compared structurally.

use saphyr::{LoadableYamlNode, YamlOwned};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A YAML value reduced to what matters for meaning: numbers compare numerically.
#[derive(Debug, Clone, PartialEq)]
enum V {
    Null,
    Bool(bool),
    Num(f64),
    Str(String),
    Seq(Vec<V>),
    Map(BTreeMap<String, V>),
}

fn conv(y: &YamlOwned) -> V {
    match y {
        YamlOwned::Value(s) => match s {
            saphyr::ScalarOwned::Null => V::Null,
            saphyr::ScalarOwned::Boolean(b) => V::Bool(*b),
            saphyr::ScalarOwned::Integer(i) => V::Num(*i as f64),
            saphyr::ScalarOwned::FloatingPoint(f) => V::Num(f.into_inner()),
            saphyr::ScalarOwned::String(s) => V::Str(s.clone()),
        },
        YamlOwned::Sequence(s) => V::Seq(s.iter().map(conv).collect()),
        YamlOwned::Mapping(m) => V::Map(m.iter().map(|(k, v)| (key(k), conv(v))).collect()),
        YamlOwned::Tagged(_, inner) => conv(inner),
        other => panic!("unexpected YAML node {other:?}"),
    }
}

fn key(k: &YamlOwned) -> String {
    match conv(k) {
        V::Str(s) => s,
        V::Num(n) => n.to_string(),
        other => format!("{other:?}"),
    }
}

fn load(path: &Path) -> V {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let docs =
        YamlOwned::load_from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    conv(&docs[0])
}

/// Compares with a numeric tolerance; returns the path of the first difference.
fn diff(a: &V, b: &V, tol: f64, at: &str) -> Option<String> {
    match (a, b) {
        (V::Num(x), V::Num(y)) => ((x - y).abs() > tol).then(|| format!("{at}: {x} != {y}")),
        (V::Seq(x), V::Seq(y)) => {
            if x.len() != y.len() {
                return Some(format!("{at}: length {} != {}", x.len(), y.len()));
            }
            x.iter()
                .zip(y)
                .enumerate()
                .find_map(|(i, (p, q))| diff(p, q, tol, &format!("{at}[{i}]")))
        }
        (V::Map(x), V::Map(y)) => {
            let kx: Vec<_> = x.keys().collect();
            let ky: Vec<_> = y.keys().collect();
            if kx != ky {
                return Some(format!("{at}: keys {kx:?} != {ky:?}"));
            }
            x.iter()
                .find_map(|(k, p)| diff(p, &y[k], tol, &format!("{at}.{k}")))
        }
        _ => (a != b).then(|| format!("{at}: {a:?} != {b:?}")),
    }
}

/// Lanes are a set of directed edges: compare them sorted, independent of order.
fn sort_lanes(v: &mut V) {
    if let V::Map(root) = v {
        if let Some(V::Map(levels)) = root.get_mut("levels") {
            for level in levels.values_mut() {
                if let V::Map(l) = level {
                    if let Some(V::Seq(lanes)) = l.get_mut("lanes") {
                        lanes.sort_by_key(|lane| format!("{lane:?}"));
                    }
                }
            }
        }
    }
}

fn shared() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared");
    p.join("maps").is_dir().then_some(p)
}

#[test]
fn nav_graphs_match_reference_for_every_demo_map() {
    let Some(shared) = shared() else {
        println!("skipped: ../shared not found");
        return;
    };
    let mut maps: Vec<String> = std::fs::read_dir(shared.join("maps"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    maps.sort();
    assert_eq!(maps.len(), 7, "expected the 7 demo maps");
    let mut compared = 0;
    for map in &maps {
        let input = shared.join(format!("maps/{map}/{map}.building.yaml"));
        let out = tempfile::tempdir().unwrap();
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_mapc"))
            .arg("nav")
            .arg(&input)
            .arg(out.path())
            .status()
            .unwrap();
        assert!(status.success(), "mapc nav failed on {map}");

        let ref_dir = shared.join(format!("reference/{map}/nav"));
        let list = |d: &Path| {
            // mapc's manifest (what it wrote, for pruning) is not an output.
            let mut v: Vec<String> = std::fs::read_dir(d)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| !n.starts_with(".mapc-manifest"))
                .collect();
            v.sort();
            v
        };
        assert_eq!(
            list(out.path()),
            list(&ref_dir),
            "{map}: graph files differ"
        );
        // wgs84 maps go through a projection library; allow 1 mm there.
        let tol = if map == "campus" { 1e-3 } else { 1e-6 };
        for f in list(&ref_dir) {
            let mut expected = load(&ref_dir.join(&f));
            let mut actual = load(&out.path().join(&f));
            sort_lanes(&mut expected);
            sort_lanes(&mut actual);
            if let Some(d) = diff(&expected, &actual, tol, &format!("{map}/{f}")) {
                panic!("{d}");
            }
            compared += 1;
        }
    }
    assert_eq!(compared, 13, "all 13 reference graphs compared");
}

#[test]
fn comparison_detects_differences() {
    // Guard against a comparison that cannot fail.
    let a = V::Map(BTreeMap::from([("x".into(), V::Num(1.0))]));
    let b = V::Map(BTreeMap::from([("x".into(), V::Num(1.0 + 1e-5))]));
    assert!(diff(&a, &b, 1e-6, "").is_some());
    assert!(diff(&a, &a, 1e-6, "").is_none());
    let c = V::Map(BTreeMap::from([("y".into(), V::Num(1.0))]));
    assert!(diff(&a, &c, 1e-6, "").is_some());
}
