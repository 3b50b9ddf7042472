use super::*;
use crate::fleet::Placement;
use crate::params::RobotParams;
use crate::world::RobotSpawn;

/// The sweep finds exactly the approaches that checking every pair finds: robots doing
/// random walks in a small room, some on a second level, with mixed footprints.
#[test]
fn sweep_matches_all_pairs() {
    let parsed = mapc_frontend::parse_str(
        "clinic",
        include_str!("../../../fixtures/two_level_clinic.building.yaml"),
    );
    let building = parsed.building.unwrap();
    let n = 30;
    let fps: Vec<f64> = (0..n).map(|i| 0.2 + 0.05 * (i % 5) as f64).collect();
    let text = format!("duration: 1h\nfleets: [{{name: f, robot: TinyRobot, count: {n}}}]\n");
    let (scenario, _) =
        crate::scenario::parse(mapc_ir::FileId(0), &text, std::path::Path::new("."));
    let placement = Placement {
        robots: (0..n)
            .map(|i| RobotSpawn {
                name: format!("r{i:02}"),
                fleet: "f".into(),
                params: RobotParams {
                    footprint: fps[i],
                    ..RobotParams::default()
                },
                x: 0.0,
                y: 0.0,
                yaw: 0.0,
                level: building.reference_level,
            })
            .collect(),
        workcells: Vec::new(),
        reserve: Vec::new(),
        warnings: Vec::new(),
        parks: Default::default(),
        finishes: Vec::new(),
    };
    let mut b = ReportBuilder::new(&building, &scenario.unwrap(), &placement);
    let mut rng = fastrand::Rng::with_seed(11);
    let mut pos: Vec<(f64, f64, f64)> = (0..n)
        .map(|i| {
            let z = if i % 7 == 0 { 4.0 } else { 0.0 };
            (rng.f64() * 8.0, rng.f64() * 8.0, z)
        })
        .collect();
    // Reference: every pair, same rules (open below the near distance, close at near +
    // hysteresis or on another level), min distance per approach.
    let mut open: BTreeMap<(usize, usize), f64> = BTreeMap::new();
    let mut closed: Vec<((usize, usize), f64)> = Vec::new();
    let mut t = 0.0;
    for _ in 0..600 {
        for p in pos.iter_mut() {
            p.0 = (p.0 + (rng.f64() - 0.5) * 0.3).clamp(0.0, 8.0);
            p.1 = (p.1 + (rng.f64() - 0.5) * 0.3).clamp(0.0, 8.0);
        }
        let truth: Vec<RobotTruth> = pos
            .iter()
            .map(|&(x, y, z)| RobotTruth {
                x,
                y,
                z,
                yaw: 0.0,
                v: 0.0,
                footprint: 0.0,
            })
            .collect();
        b.sample(t, &truth);
        for i in 0..n {
            for j in i + 1..n {
                let (a, c) = (pos[i], pos[j]);
                let d = (a.0 - c.0).hypot(a.1 - c.1);
                let near = fps[i] + fps[j] + NEAR_MISS_MARGIN;
                let level = (a.2 - c.2).abs() < SAME_LEVEL_DZ;
                match open.get_mut(&(i, j)) {
                    Some(m) => {
                        if !level || d >= near + NEAR_MISS_HYSTERESIS {
                            closed.push(((i, j), *m));
                            open.remove(&(i, j));
                        } else if d < *m {
                            *m = d;
                        }
                    }
                    None if level && d < near => {
                        open.insert((i, j), d);
                    }
                    None => {}
                }
            }
        }
        t += 0.1;
    }
    closed.extend(open);
    let report = b.finish(t - 0.1, &[]);
    let mut got: Vec<(String, String, f64)> = report
        .near_misses
        .iter()
        .chain(&report.contacts)
        .map(|e| (e.robots[0].clone(), e.robots[1].clone(), e.min_distance_m))
        .collect();
    let mut want: Vec<(String, String, f64)> = closed
        .iter()
        .map(|&((i, j), m)| (format!("r{i:02}"), format!("r{j:02}"), m))
        .collect();
    let order = |a: &(String, String, f64), b: &(String, String, f64)| {
        (&a.0, &a.1).cmp(&(&b.0, &b.1)).then(a.2.total_cmp(&b.2))
    };
    got.sort_by(order);
    want.sort_by(order);
    assert!(
        want.len() > 20,
        "too few approaches to test: {}",
        want.len()
    );
    assert_eq!(got, want);
    let contacts = closed
        .iter()
        .filter(|&&((i, j), m)| m < fps[i] + fps[j])
        .count();
    assert_eq!(report.contacts.len(), contacts);
}
