//! Crowd tests: the walking against published figures (RiMEA test 1 free walking, the
//! Weidmann fundamental diagram in a ring corridor, bottleneck flow growing with width, no
//! overlap), on maps written here and read by the real frontend.

use super::*;
use std::fmt::Write;

/// A cartesian map whose human lanes join `pts` as `lanes` (index pairs, width), with a
/// crowd_sim of `states` (name, goal vertex index or none = final), `transitions`
/// (from, to, goal_reached distance or none = never), and `groups` (state, count, x, y).
struct MapSpec<'a> {
    pts: Vec<(f64, f64)>,
    lanes: Vec<(usize, usize, f64)>,
    states: Vec<(&'a str, Option<usize>)>,
    transitions: Vec<(&'a str, &'a str, f64)>,
    groups: Vec<(&'a str, usize, f64, f64)>,
    pref_speed: f64,
    r: f64,
}

fn building(m: &MapSpec) -> Building {
    let mut y = String::from("name: t\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    elevation: 0\n    vertices:\n");
    for (i, (px, py)) in m.pts.iter().enumerate() {
        let goal = if m.states.iter().any(|s| s.1 == Some(i)) {
            format!(", {{human_goal_set_name: [1, g{i}]}}")
        } else {
            String::new()
        };
        let _ = writeln!(y, "      - [{px}, {py}, 0, v{i}{goal}]");
    }
    y.push_str("    human_lanes:\n");
    for (a, b, w) in &m.lanes {
        let _ = writeln!(
            y,
            "      - [{a}, {b}, {{bidirectional: [4, true], graph_idx: [2, 9], width: [3, {w}]}}]"
        );
    }
    y.push_str("crowd_sim:\n  enable: 1\n  update_time_step: 0.1\n");
    y.push_str("  obstacle_set: {class: 1, file_name: L1_navmesh.nav, type: nav_mesh}\n");
    let _ = writeln!(
        y,
        "  agent_profiles:\n    - {{name: human, r: {}, pref_speed: {}, max_speed: 2, max_accel: 5, neighbor_dist: 5, max_neighbors: 10, ORCA_tau: 1, ORCA_tauObst: 0.4}}",
        m.r, m.pref_speed
    );
    y.push_str("  goal_sets:\n");
    for (_, g) in &m.states {
        if let Some(g) = g {
            let _ = writeln!(
                y,
                "    - {{set_id: {g}, capacity: 100000, set_area: [g{g}]}}"
            );
        }
    }
    y.push_str("  states:\n");
    for (name, g) in &m.states {
        let _ = writeln!(
            y,
            "    - {{name: {name}, goal_set: {}, final: {}, navmesh_file_name: L1_navmesh.nav}}",
            g.map_or(-1, |g| g as i64),
            i32::from(g.is_none())
        );
    }
    y.push_str("  transitions:\n");
    for (from, to, d) in &m.transitions {
        let _ = writeln!(
            y,
            "    - {{from: {from}, to: {to}, Condition: {{type: goal_reached, distance: {d}}}}}"
        );
    }
    y.push_str("  agent_groups:\n");
    for (k, (state, n, x, gy)) in m.groups.iter().enumerate() {
        let _ = writeln!(
            y,
            "    - {{group_id: {k}, profile_selector: human, state_selector: {state}, agents_number: {n}, agents_name: [], x: {x}, y: {gy}}}"
        );
    }
    let parsed = mapc_frontend::parse_str("t.building.yaml", &y);
    let errors: Vec<_> = parsed
        .diagnostics
        .iter()
        .filter(|d| d.severity == mapc_ir::Severity::Error)
        .collect();
    assert!(errors.is_empty(), "{errors:?}\n{y}");
    let b = parsed.building.expect("a building");
    let v = mapc_ir::validate(&b);
    assert!(v.iter().all(|d| !d.code.starts_with("E08")), "{v:?}");
    b
}

fn crowd(b: &Building) -> Crowd {
    let floors: Vec<f64> = b.levels.iter().map(|(_, l)| l.elevation).collect();
    Crowd::new(b, &floors, 1.0, 7, 0.01)
        .unwrap()
        .expect("people")
}

/// Smallest centre distance minus the radii over all pairs (brute force: tests only).
fn min_gap(c: &Crowd) -> f64 {
    let mut m = f64::INFINITY;
    for i in 0..c.people.len() {
        for j in i + 1..c.people.len() {
            let (a, b) = (&c.people[i], &c.people[j]);
            let g = a.pos.minus(b.pos).norm() - c.profiles[a.profile].r - c.profiles[b.profile].r;
            m = m.min(g);
        }
    }
    m
}

/// How far the person farthest off the navmesh is outside it (0 when all are on it).
fn off_mesh(c: &Crowd) -> f64 {
    c.people
        .iter()
        .map(|p| {
            c.mesh
                .snap(p.pos)
                .map_or(f64::INFINITY, |(_, q)| q.minus(p.pos).norm())
        })
        .fold(0.0, f64::max)
}

/// RiMEA test 1 (free walking): one person, a 40 m corridor 2 m wide, 1.33 m/s; the time
/// is distance over preferred speed, plus the acceleration from rest (v/2a).
#[test]
fn free_walking_time_is_distance_over_speed() {
    let b = building(&MapSpec {
        pts: vec![(0.0, 0.0), (41.0, 0.0), (45.0, 0.0)],
        lanes: vec![(0, 1, 2.0), (1, 2, 2.0)],
        states: vec![("walk", Some(1)), ("arrived", None)],
        transitions: vec![("walk", "arrived", 0.01)],
        groups: vec![("walk", 1, 1.0, 0.0)],
        pref_speed: 1.33,
        r: 0.25,
    });
    let mut c = crowd(&b);
    let arrived = c
        .fsm
        .states
        .iter()
        .position(|s| s.name == "arrived")
        .unwrap();
    let mut t_arrive = None;
    for k in 1..=600u64 {
        let t = k as f64 * 0.1;
        c.walk(t, &[]);
        if c.people[0].mind.state == arrived {
            t_arrive = Some(t);
            break;
        }
    }
    let t = t_arrive.expect("arrived");
    let want = 40.0 / 1.33 + 1.33 / (2.0 * 5.0);
    // One crowd step of slack for the goal test.
    assert!((t - want).abs() <= 0.15, "{t} s, want {want} s");
    // RiMEA's accepted band: 26 s to 34 s.
    assert!((26.0..=34.0).contains(&t));
    assert!(
        (c.people[0].walked - 40.0).abs() < 0.05,
        "{}",
        c.people[0].walked
    );
}

/// A ring corridor of `n` lanes on a circle of radius `rad`, `width` wide, with four goals
/// at the quarter points people chase round and round.
fn ring(people: usize, rad: f64, width: f64, pref: f64, r: f64) -> (Building, f64) {
    let n = 24;
    let pts: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let a = k as f64 / n as f64 * std::f64::consts::TAU;
            (
                (rad * a.cos() * 1000.0).round() / 1000.0,
                (rad * a.sin() * 1000.0).round() / 1000.0,
            )
        })
        .collect();
    let lanes = (0..n).map(|k| (k, (k + 1) % n, width)).collect();
    let q = n / 4;
    let names = ["q0", "q1", "q2", "q3"];
    let states = (0..4)
        .map(|k| (names[k], Some(((k + 1) * q) % n)))
        .collect();
    let transitions = (0..4)
        .map(|k| (names[k], names[(k + 1) % 4], width))
        .collect();
    // People start spread round the ring: one group per vertex.
    let mut groups = Vec::new();
    for k in 0..n {
        let count = people / n + usize::from(k < people % n);
        let (x, y) = pts[k];
        // Chasing the next quarter point ahead.
        groups.push((names[k / q], count, x, y));
    }
    let b = building(&MapSpec {
        pts,
        lanes,
        states,
        transitions,
        groups,
        pref_speed: pref,
        r,
    });
    let circumference = n as f64 * 2.0 * rad * (std::f64::consts::PI / n as f64).sin();
    (b, circumference * width)
}

/// Weidmann (1993): v(ρ) = v0·(1 − exp(−γ·(1/ρ − 1/ρmax))).
fn weidmann(rho: f64) -> f64 {
    1.34 * (1.0 - (-1.913 * (1.0 / rho - 1.0 / 5.4)).exp())
}

/// Mean speed of everyone between 20 s and 40 s in a ring of `people`.
fn ring_speed(people: usize) -> (f64, f64, f64) {
    let (b, area) = ring(people, 8.0, 2.0, 1.34, 0.2);
    let mut c = crowd(&b);
    let mut sum = 0.0;
    let mut count = 0.0;
    let mut gap = f64::INFINITY;
    for k in 1..=400u64 {
        c.walk(k as f64 * 0.1, &[]);
        if k > 200 {
            for p in &c.people {
                sum += p.vel.norm();
                count += 1.0;
            }
            if k % 20 == 0 {
                gap = gap.min(min_gap(&c));
                let off = off_mesh(&c);
                assert!(off < 0.05, "{off} m off the navmesh");
            }
        }
    }
    (c.people.len() as f64 / area, sum / count, gap)
}

/// Unidirectional flow in a ring: people walk near Weidmann's speed at every density
/// (ORCA alone would keep the free speed, having no closing speeds to react to; the
/// density filter slows them; docs/sim.md has the table). Speed never rises with density
/// and people overlap by less than 2 cm.
#[test]
fn ring_corridor_speed_against_weidmann() {
    let mut last = f64::INFINITY;
    let mut rows = Vec::new();
    for people in [25, 50, 100, 150] {
        let (rho, v, gap) = ring_speed(people);
        rows.push((rho, v, weidmann(rho), gap));
        assert!(v < last + 0.02, "{rows:?}");
        last = v;
        assert!(gap > -0.02, "overlap {gap} at ρ = {rho}: {rows:?}");
        assert!(v <= 1.34 + 0.02, "{rows:?}");
    }
    println!("ρ, v, Weidmann, min gap: {rows:?}");
    for &(rho, v, w, _) in &rows {
        // Near the diagram: within 0.06 m/s up to 0.5 /m², 0.2 m/s above (the density each
        // person sees in a 1 m circle, not the ring's mean).
        let tol = if rho <= 0.5 { 0.06 } else { 0.2 };
        assert!(
            (v - w).abs() < tol,
            "ρ = {rho}: {v} vs Weidmann {w}: {rows:?}"
        );
    }
    // Speed falls with density: at 1.5 /m² well below the free speed.
    assert!(rows[3].1 < 0.8 * rows[0].1, "{rows:?}");
}

/// People from a room through a bottleneck of width `w` (2 m long): the time between the
/// first and the last of `n` crossing its exit.
fn bottleneck_flow(w: f64, n: usize) -> f64 {
    let b = building(&MapSpec {
        pts: vec![(0.0, 0.0), (8.0, 0.0), (10.0, 0.0), (20.0, 0.0)],
        lanes: vec![(0, 1, 5.0), (1, 2, w), (2, 3, 5.0)],
        states: vec![("out", Some(3)), ("done", None)],
        transitions: vec![("out", "done", 1.0)],
        groups: vec![("out", n, 3.0, 0.0)],
        pref_speed: 1.34,
        r: 0.2,
    });
    let mut c = crowd(&b);
    let exit = 10.0 - c.mesh.origin.x;
    let mut crossed: Vec<Option<f64>> = vec![None; c.people.len()];
    for k in 1..=1200u64 {
        let t = k as f64 * 0.1;
        c.walk(t, &[]);
        for (i, p) in c.people.iter().enumerate() {
            if crossed[i].is_none() && p.pos.x > exit {
                crossed[i] = Some(t);
            }
        }
        if crossed.iter().all(Option::is_some) {
            break;
        }
    }
    let mut ts: Vec<f64> = crossed.iter().map(|t| t.expect("everyone out")).collect();
    ts.sort_by(f64::total_cmp);
    (n - 1) as f64 / (ts[n - 1] - ts[0])
}

/// Flow through a bottleneck grows with its width (Seyfried et al. 2009, Kretz 2006).
#[test]
fn bottleneck_flow_grows_with_width() {
    let flows: Vec<(f64, f64)> = [0.8, 1.2, 1.6]
        .iter()
        .map(|&w| (w, bottleneck_flow(w, 40)))
        .collect();
    println!("width, flow (1/s): {flows:?}");
    for k in 1..flows.len() {
        assert!(flows[k].1 > flows[k - 1].1, "{flows:?}");
    }
    // Near the measured specific flow, about 1.9 /s per metre of width (Seyfried et al.
    // 2009): within a factor of two.
    for &(w, f) in &flows {
        let measured = 1.9 * w;
        assert!(
            f > measured / 2.0 && f < measured * 2.0,
            "width {w}: {f} /s vs {measured}: {flows:?}"
        );
    }
}

#[test]
fn spread_places_everyone_apart_on_the_mesh() {
    let (b, _) = ring(150, 8.0, 2.0, 1.34, 0.2);
    let c = crowd(&b);
    assert_eq!(c.people.len(), 150);
    assert!(min_gap(&c) >= 0.1 - 1e-9);
    for p in &c.people {
        assert!(c.mesh.locate(p.pos).is_some());
    }
}

#[test]
fn same_seed_same_walk() {
    let (b, _) = ring(60, 8.0, 2.0, 1.34, 0.2);
    let run = || {
        let mut c = crowd(&b);
        for k in 1..=100u64 {
            c.walk(k as f64 * 0.1, &[]);
        }
        c.positions()
    };
    assert_eq!(run(), run());
}

/// A robot of footprint 0.4 m standing at (10, 0), facing `yaw`.
fn standing_robot(yaw: f64) -> RobotTruth {
    RobotTruth {
        x: 10.0,
        y: 0.0,
        z: 0.0,
        yaw,
        v: 0.0,
        footprint: 0.4,
    }
}

/// A robot standing in the corridor: people walk around it and never touch it.
#[test]
fn people_avoid_a_robot() {
    let b = building(&MapSpec {
        pts: vec![(0.0, 0.0), (20.0, 0.0)],
        lanes: vec![(0, 1, 3.0)],
        states: vec![("walk", Some(1)), ("arrived", None)],
        transitions: vec![("walk", "arrived", 0.5)],
        groups: vec![("walk", 6, 2.0, 0.0)],
        pref_speed: 1.34,
        r: 0.25,
    });
    let mut c = crowd(&b);
    let robot = standing_robot(0.0);
    for k in 1..=400u64 {
        c.walk(k as f64 * 0.1, &[robot]);
    }
    let r = c.report(40.0);
    assert_eq!(r.contacts, 0, "{r:?}");
    assert!(r.walked_m.min > 15.0, "{r:?}");
    // Everyone got past the robot.
    assert!(c.positions().iter().all(|p| p.x > 15.0));
    // And a slotcar sees them: one person stands at the goal end.
    let p = c.positions()[0];
    assert!(c.any_within([p.x + 0.5, p.y, 0.0], 0.75));
    assert!(!c.any_within([p.x + 0.5, p.y, 5.0], 0.75));
}

/// The grid's k-nearest query equals a brute-force scan and sort, whatever the first
/// guess of the radius, for points inside and outside the grid's box, crowded and sparse.
#[test]
fn nearest_equals_brute_force() {
    let mut rng = fastrand::Rng::with_seed(7);
    let (lo, hi) = (Vec2::new(0.0, 0.0), Vec2::new(30.0, 12.0));
    let mut g = grid::Grid::new(lo, hi, 0.5, 1e6);
    // A dense knot, a sparse field, and some points beyond the box on every side.
    let mut pts: Vec<Vec2> = (0..300)
        .map(|_| Vec2::new(5.0 + 2.0 * rng.f64(), 5.0 + 2.0 * rng.f64()))
        .collect();
    pts.extend((0..200).map(|_| Vec2::new(34.0 * rng.f64() - 2.0, 16.0 * rng.f64() - 2.0)));
    // Two coincident points (left out of each other's neighbours).
    pts.push(Vec2::new(20.0, 6.0));
    pts.push(Vec2::new(20.0, 6.0));
    g.rebuild(pts.iter().copied());
    let mut near = Vec::new();
    let mut checked = 0;
    for (i, &p) in pts.iter().enumerate() {
        for (r, k) in [(5.0, 10), (1.5, 3), (0.7, 50)] {
            let mut all: Vec<(f64, usize)> = pts
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(j, q)| {
                    let d = q.minus(p);
                    (d.x * d.x + d.y * d.y, j)
                })
                .filter(|&(d2, _)| d2 < r * r && d2 > 1e-8)
                .collect();
            let count = all.iter().filter(|a| a.0 < 1.0).count();
            all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            all.truncate(k);
            for hint in [0.0, 0.3, 2.0, 100.0] {
                let c = g.nearest(p, r, k, i, 1.0, hint, &mut near);
                assert_eq!(near, all, "point {i} at {p:?}, r {r}, k {k}, hint {hint}");
                assert_eq!(c, count, "point {i}, r {r}");
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 502 * 3 * 4);
}

/// A robot standing in a corridor too narrow to pass it, facing a person whose goal lies
/// behind it: the robot stops for the person in front of it, so the person gives way
/// (steps back after `GIVE_WAY_AFTER` s), and the robot's stop zone clears. Without it
/// both would wait for ever (a stand-off that lasted hours on the airport map).
#[test]
fn a_person_held_up_by_a_waiting_robot_gives_way() {
    let b = building(&MapSpec {
        pts: vec![(0.0, 0.0), (20.0, 0.0)],
        lanes: vec![(0, 1, 1.2)],
        states: vec![("walk", Some(1)), ("arrived", None)],
        transitions: vec![("walk", "arrived", 0.5)],
        groups: vec![("walk", 1, 4.0, 0.0)],
        pref_speed: 1.34,
        r: 0.25,
    });
    let mut c = crowd(&b);
    // Facing the person (yaw pi): its stop zone is 0.75 m ahead, 0.75 m around.
    let robot = standing_robot(std::f64::consts::PI);
    let zone = [10.0 - 0.75, 0.0, 0.0];
    let (mut entered, mut cleared) = (None, None);
    for k in 1..=300u64 {
        let t = k as f64 * 0.1;
        c.walk(t, &[robot]);
        let inside = c.any_within(zone, 0.75);
        if inside && entered.is_none() {
            entered = Some(t);
        }
        if !inside && entered.is_some() && cleared.is_none() {
            cleared = Some(t);
        }
    }
    let (t_in, t_out) = (entered.expect("walks up to the robot"), cleared);
    let t_out = t_out.expect("the person never gave way");
    // It walks up, stands still for GIVE_WAY_AFTER s, then backs off at half its speed
    // for at most GIVE_WAY s.
    assert!(t_out - t_in >= GIVE_WAY_AFTER, "{t_in} {t_out}");
    assert!(
        t_out - t_in <= GIVE_WAY_AFTER + GIVE_WAY + 1.0,
        "{t_in} {t_out}"
    );
    assert_eq!(c.report(30.0).contacts, 0);
}
