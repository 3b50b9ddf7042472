//! mapc's projection against PROJ itself: `tests/data/proj_epsg_points.csv` holds, for every
//! projected metre CRS of the EPSG database, points in its area of use with the easting and
//! northing pyproj (PROJ's default transformation, no grid files) gives for them. Both it
//! and mapc's table come from `tools/crs/gen_epsg.py`. Every metre CRS of the table must
//! either agree with PROJ within 1 mm on every one of its points, or be refused for one of
//! the reasons listed below.

use mapc_frontend::crs::{codes, lookup, Lookup};
use std::collections::{BTreeMap, BTreeSet};

/// Refused codes and why: PROJ itself has no transformation from WGS 84 to them (so the
/// reference fails too), or their projection method is not implemented in mapc.
const REFUSED: &[(&str, &[u32])] = &[
    (
        "PROJ has no transformation from WGS 84 to it",
        &[
            2218, 2221, 2296, 2297, 2298, 2299, 2300, 2301, 2302, 2303, 2304, 2305, 2306, 2307,
            2963, 2985, 2986, 3052, 3053, 3144, 3145, 3173, 3752, 5017, 7082, 22700, 32600, 32700,
        ],
    ),
    (
        "the projection method `mod_krovak` is not implemented",
        &[5224, 5225, 5515, 5516],
    ),
];

#[test]
fn every_projected_metre_crs_agrees_with_proj_within_1_mm() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/proj_epsg_points.csv"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let mut points: BTreeMap<u32, Vec<[f64; 4]>> = BTreeMap::new();
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let n = |i: usize| f[i].parse::<f64>().unwrap();
        points
            .entry(f[0].parse().unwrap())
            .or_default()
            .push([n(1), n(2), n(3), n(4)]);
    }
    let (mut metre, mut pass, mut feet) = (0, 0, 0);
    let mut fail: BTreeMap<u32, (f64, f64, f64)> = BTreeMap::new();
    let mut refused: BTreeMap<String, BTreeSet<u32>> = BTreeMap::new();
    for code in codes() {
        match lookup(code) {
            Lookup::Crs(crs) => {
                metre += 1;
                let pts = points.get(&code).map_or(&[][..], Vec::as_slice);
                assert!(
                    !pts.is_empty(),
                    "EPSG:{code}: no PROJ points to compare with"
                );
                let mut worst = (0.0, 0.0, 0.0);
                for &[lon, lat, e, n] in pts {
                    let err = crs
                        .project(lon, lat)
                        .map_or(f64::INFINITY, |(x, y)| (x - e).hypot(y - n));
                    if err > worst.2 {
                        worst = (lon, lat, err);
                    }
                }
                if worst.2 <= 1e-3 {
                    pass += 1;
                } else {
                    fail.insert(code, worst);
                }
            }
            Lookup::Refused(why) => {
                metre += 1;
                refused.entry(why).or_default().insert(code);
            }
            Lookup::NotMetres(_) => feet += 1,
            Lookup::Unknown => panic!("EPSG:{code} is in the table but not found"),
        }
    }
    println!("{metre} projected metre CRSs ({feet} in other units, refused): {pass} agree with PROJ within 1 mm on all their points");
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
        assert_eq!(codes, &expected, "refused for {why}");
    }
    let listed: usize = REFUSED.iter().map(|(_, c)| c.len()).sum();
    assert_eq!(
        pass + listed,
        metre,
        "every metre CRS agrees or is listed as refused"
    );
    // The table covers the whole database: thousands of CRSs, not a sample.
    assert!(metre > 4500, "{metre}");
}
