//! mapc's projection against PROJ itself: `tests/data/proj_epsg_points.csv` holds, for every
//! projected metre CRS of the EPSG database, points in its area of use with the easting and
//! northing pyproj (PROJ's default transformation, no grid files) gives for them. Both it
//! and mapc's table come from `tools/crs/gen_epsg.py`. Every point must agree within 1 mm,
//! except for the CRSs mapc refuses (listed with their reasons below).

use mapc_frontend::crs::{lookup, Lookup};
use std::collections::{BTreeMap, BTreeSet};

/// Refused codes and why: PROJ itself has no transformation from WGS 84 to them (so the
/// reference fails too), or their projection method is not implemented in mapc.
const REFUSED: &[(&str, &[u32])] = &[(
    "PROJ has no transformation from WGS 84 to it",
    &[
        2218, 2221, 2296, 2297, 2298, 2299, 2300, 2301, 2302, 2303, 2304, 2305, 2306, 2307, 2963,
        2985, 2986, 3052, 3053, 3144, 3145, 3173, 3752, 5017, 7082, 22700, 32600, 32700,
    ],
)];

#[test]
fn every_projected_metre_crs_agrees_with_proj_within_1_mm() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/proj_epsg_points.csv"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let mut pass = BTreeSet::new();
    let mut fail: BTreeMap<u32, (f64, f64, f64)> = BTreeMap::new();
    let mut refused: BTreeMap<String, BTreeSet<u32>> = BTreeMap::new();
    let mut points = 0;
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let code: u32 = f[0].parse().unwrap();
        let n = |i: usize| f[i].parse::<f64>().unwrap();
        let (lon, lat, e, nn) = (n(1), n(2), n(3), n(4));
        points += 1;
        match lookup(code) {
            Lookup::Crs(crs) => match crs.project(lon, lat) {
                Some((x, y)) if (x - e).hypot(y - nn) <= 1e-3 => {
                    pass.insert(code);
                }
                got => {
                    let err = got.map_or(f64::INFINITY, |(x, y)| (x - e).hypot(y - nn));
                    let worst = fail.entry(code).or_insert((lon, lat, 0.0));
                    if err > worst.2 {
                        *worst = (lon, lat, err);
                    }
                }
            },
            Lookup::Refused(why) => {
                refused.entry(why).or_default().insert(code);
            }
            Lookup::NotMetres(u) => panic!("EPSG:{code} in the points file but in {u}"),
            Lookup::Unknown => panic!("EPSG:{code} in the points file but not in the table"),
        }
    }
    // A code passes when every one of its points does.
    let pass: BTreeSet<u32> = pass
        .difference(&fail.keys().copied().collect())
        .copied()
        .collect();
    println!(
        "{points} points; {} CRSs agree with PROJ within 1 mm",
        pass.len()
    );
    for (why, codes) in &refused {
        println!("refused ({}): {why}: {codes:?}", codes.len());
    }
    for (code, (lon, lat, err)) in &fail {
        println!("EPSG:{code} off by {err:.4} m at {lon} {lat}");
    }
    assert!(fail.is_empty(), "{} CRSs disagree with PROJ", fail.len());
    for (why, codes) in &refused {
        let expected: BTreeSet<u32> = REFUSED
            .iter()
            .filter(|(w, _)| why.contains(w))
            .flat_map(|(_, c)| c.iter().copied())
            .collect();
        let unexpected: Vec<_> = codes.difference(&expected).collect();
        assert!(unexpected.is_empty(), "refused ({why}): {unexpected:?}");
    }
}
