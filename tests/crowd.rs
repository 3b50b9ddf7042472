//! The crowd simulator (runtime.md §6): the `crowd_simulation` world plugin and the Menge
//! files in config_resource/, from the cartesian_warehouse fixture (crowd_sim enabled, a
//! human lane, a goal vertex, an offset) and, when ../shared is here, the airport_terminal
//! demo map.

use mapc_backends::sdf::crowd::{behavior_file, crowd_files, crowd_plugin, scene_file};
use mapc_backends::sdf::world::{world_text, WorldOptions};
use mapc_backends::sdf::xml::Element;
use mapc_backends::sdf::Flavour;
use mapc_ir::Building;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn load(path: &Path) -> Building {
    let text = std::fs::read_to_string(path).unwrap();
    let parsed = mapc_frontend::parse_str(&path.display().to_string(), &text);
    parsed
        .valid_building()
        .unwrap_or_else(|| panic!("{}: errors {:#?}", path.display(), parsed.diagnostics))
        .clone()
}

fn warehouse() -> Building {
    load(&root().join("fixtures/cartesian_warehouse.building.yaml"))
}

fn attr<'a>(e: &'a Element, k: &str) -> &'a str {
    e.attrs
        .iter()
        .find(|(n, _)| n == k)
        .map(|(_, v)| v.as_ref())
        .unwrap_or_else(|| panic!("<{}> has no {k}", e.name))
}

fn num(e: &Element, k: &str) -> f64 {
    attr(e, k).parse().unwrap()
}

fn all<'a>(e: &'a Element, name: &'a str) -> impl Iterator<Item = &'a Element> {
    e.children.iter().filter(move |c| c.name == name)
}

/// Reads `text` to the end with quick-xml: every tag closed, attributes well-formed, one
/// root element.
fn assert_well_formed(name: &str, text: &str) {
    use quick_xml::events::Event;
    let mut r = quick_xml::Reader::from_str(text);
    r.config_mut().check_end_names = true;
    let (mut depth, mut roots) = (0i32, 0);
    loop {
        match r.read_event() {
            Ok(Event::Start(e)) => {
                if depth == 0 {
                    roots += 1;
                }
                depth += 1;
                for a in e.attributes() {
                    a.unwrap_or_else(|err| panic!("{name}: {err}"));
                }
            }
            Ok(Event::Empty(e)) => {
                if depth == 0 {
                    roots += 1;
                }
                for a in e.attributes() {
                    a.unwrap_or_else(|err| panic!("{name}: {err}"));
                }
            }
            Ok(Event::End(_)) => depth -= 1,
            Ok(Event::Eof) => break,
            Ok(_) => {}
            Err(e) => panic!("{name}: {e}"),
        }
    }
    assert_eq!((depth, roots), (0, 1), "{name}");
}

#[test]
fn snapshot_plugin_and_menge_files() {
    let b = warehouse();
    insta::assert_snapshot!("crowd_plugin", crowd_plugin(&b).unwrap().to_document(false));
    let files = crowd_files(&b);
    let names: Vec<_> = files.iter().map(|f| f.path.clone()).collect();
    assert_eq!(
        names,
        [
            PathBuf::from("config_resource/behavior_file.xml"),
            PathBuf::from("config_resource/scene_file.xml"),
            PathBuf::from("config_resource/L1_navmesh.nav"),
        ]
    );
    for f in &files[..2] {
        let text = std::str::from_utf8(&f.contents).unwrap();
        assert_well_formed(&f.path.display().to_string(), text);
    }
    let text = |i: usize| String::from_utf8(files[i].contents.clone()).unwrap();
    insta::assert_snapshot!("crowd_behavior_file", text(0));
    insta::assert_snapshot!("crowd_scene_file", text(1));
}

/// Values from the fixture: the plugin in every flavour, the goal at the goal vertex less
/// the offset, one agent per agents_number at the group's position less the offset, the
/// external group first, the or-condition and the targets.
#[test]
fn warehouse_values() {
    let b = warehouse();
    let c = b.crowd_sim.as_ref().unwrap();
    let (ox, oy) = (b.offset.x, b.offset.y);
    assert_eq!((ox, oy), (25000.0, 31000.0));
    for f in [Flavour::Gz, Flavour::Ignition, Flavour::Classic] {
        let w = world_text(&b, f, &WorldOptions::default());
        let block = crowd_plugin(&b).unwrap().to_document(false);
        let indented: String = block.lines().map(|l| format!("    {l}\n")).collect();
        assert!(w.contains(&indented), "{f:?}");
        assert_eq!(w.matches("name=\"crowd_simulation\"").count(), 1);
    }
    let p = crowd_plugin(&b).unwrap();
    let ext: Vec<_> = all(&p, "external_agent")
        .map(|e| e.text.as_deref().unwrap())
        .collect();
    assert_eq!(ext, ["bot_a"]);
    let mt = p.find("model_type").unwrap();
    assert_eq!(
        mt.find("filename").unwrap().text.as_deref(),
        Some(c.model_types[0].model_uri.as_str())
    );
    assert_eq!(
        mt.find("initial_pose").unwrap().text.as_deref().unwrap(),
        "0.0 0.0 0.0 0.0 0.0 0.0"
    );

    // Behaviour: the goal vertex crowd_goal_1 is at (25015, 31015) in the file.
    let bf = behavior_file(&b, c);
    let set = bf.find("GoalSet").unwrap();
    let goals: Vec<_> = all(set, "Goal").collect();
    assert_eq!(goals.len(), 1);
    assert_eq!(
        (num(goals[0], "x"), num(goals[0], "y")),
        (25015.0 - ox, 31015.0 - oy)
    );
    assert_eq!(attr(goals[0], "capacity"), "2");
    let states: Vec<_> = all(&bf, "State").collect();
    assert_eq!(states.len(), c.states.len());
    let wandering = states
        .iter()
        .find(|s| attr(s, "name") == "wandering")
        .unwrap();
    let vc = wandering.find("VelComponent").unwrap();
    assert_eq!(
        (attr(vc, "type"), attr(vc, "heading_threshold")),
        ("nav_mesh", "15")
    );
    assert_eq!(attr(vc, "file_name"), "L1_navmesh.nav");
    let tr = bf.find("Transition").unwrap();
    let cond = tr.find("Condition").unwrap();
    assert_eq!(attr(cond, "type"), "or");
    let kinds: Vec<_> = all(cond, "Condition").map(|c| attr(c, "type")).collect();
    assert_eq!(kinds, ["goal_reached", "timer"]);
    let target = tr.find("Target").unwrap();
    assert_eq!(attr(target, "type"), "prob");
    assert_eq!(attr(target.find("State").unwrap(), "name"), "wandering");

    // Scene: the external group (x 0, y 0 in the file) first, then two humans at
    // (25005, 31015).
    let sf = scene_file(&b, c);
    let groups: Vec<_> = all(&sf, "AgentGroup").collect();
    assert_eq!(groups.len(), 2);
    let agents = |g: &Element| -> Vec<(f64, f64)> {
        all(g.find("Generator").unwrap(), "Agent")
            .map(|a| (num(a, "p_x"), num(a, "p_y")))
            .collect()
    };
    assert_eq!(
        attr(groups[0].find("ProfileSelector").unwrap(), "name"),
        "external_agent"
    );
    assert_eq!(agents(groups[0]), [(0.0 - ox, 0.0 - oy)]);
    assert_eq!(agents(groups[1]), [(25005.0 - ox, 31015.0 - oy); 2]);
    let human = all(&sf, "AgentProfile")
        .find(|p| attr(p, "name") == "human")
        .unwrap();
    let common = human.find("Common").unwrap();
    assert_eq!(num(common, "max_speed"), 1.2);
    assert_eq!(num(common, "r"), 0.3);
    assert_eq!(num(human.find("ORCA").unwrap(), "tauObst"), 0.4);
    assert_eq!(
        attr(sf.find("ObstacleSet").unwrap(), "file_name"),
        "L1_navmesh.nav"
    );
    assert_eq!(num(sf.find("Common").unwrap(), "time_step"), 0.1);
}

/// Disabled crowd_sim: no plugin, no files.
#[test]
fn disabled_crowd_sim_writes_nothing() {
    let mut b = warehouse();
    if let Some(c) = b.crowd_sim.as_mut() {
        c.enable = false;
    }
    assert!(crowd_plugin(&b).is_none());
    assert!(crowd_files(&b).is_empty());
    let w = world_text(&b, Flavour::Gz, &WorldOptions::default());
    assert!(!w.contains("crowd_simulation"));
}

/// The CLI writes config_resource/ next to the world, and the world passes sdf-check.
#[test]
fn cli_writes_menge_files_and_world_passes_sdf_check() {
    let tmp = tempfile::tempdir().unwrap();
    let world = tmp.path().join("out/w.world");
    let models = tmp.path().join("models");
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(root())
        .env_remove("MAPC_TEXTURE_PATH")
        .args([
            "gz",
            "fixtures/cartesian_warehouse.building.yaml",
            world.to_str().unwrap(),
            models.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let b = warehouse();
    for f in crowd_files(&b) {
        let written = std::fs::read(tmp.path().join("out").join(&f.path)).unwrap();
        assert_eq!(written, f.contents, "{}", f.path.display());
    }
    let tool = root().join("../shared/tools/sdf-check");
    let Ok(check) = Command::new(&tool)
        .env("SDF_PATH", &models)
        .env("SDF_CHECK_IGNORE_MISSING", "1")
        .arg(&world)
        .output()
    else {
        println!("skipped: sdf-check not found");
        return;
    };
    let stdout = String::from_utf8_lossy(&check.stdout);
    if !stdout.contains(" errors") {
        println!("skipped: sdf-check could not run");
        return;
    }
    assert!(stdout.contains(": 0 errors"), "{stdout}");
}

/// airport_terminal: the human groups sit next to the goals of their state's goal set (so
/// the editor's group x/y are map metres, as crowd.rs takes them), every goal vertex is a
/// goal, and the external agents are the external groups' names in file order.
#[test]
fn airport_terminal() {
    let p = root().join("../shared/maps/airport_terminal/airport_terminal.building.yaml");
    if !p.is_file() {
        println!("skipped: ../shared not found");
        return;
    }
    let b = load(&p);
    let c = b.crowd_sim.as_ref().unwrap();
    let bf = behavior_file(&b, c);
    let goal_vertices = b
        .vertices
        .iter()
        .filter(|(_, v)| v.roles.human_goal_set_name.is_some())
        .count();
    let goals = all(&bf, "GoalSet").flat_map(|s| all(s, "Goal")).count();
    assert_eq!(goals, goal_vertices);
    let sf = scene_file(&b, c);
    let mut humans = 0;
    for g in all(&sf, "AgentGroup") {
        let profile = attr(g.find("ProfileSelector").unwrap(), "name");
        if profile == "external_agent" {
            continue;
        }
        let state = attr(g.find("StateSelector").unwrap(), "name");
        let set = c.states.iter().find(|s| s.name == state).unwrap().goal_set;
        let gs = all(&bf, "GoalSet")
            .find(|s| attr(s, "id") == set.to_string())
            .unwrap();
        for a in all(g.find("Generator").unwrap(), "Agent") {
            let (x, y) = (num(a, "p_x"), num(a, "p_y"));
            let d = all(gs, "Goal")
                .map(|q| (num(q, "x") - x).hypot(num(q, "y") - y))
                .fold(f64::INFINITY, f64::min);
            assert!(d < 1.0, "{state}: {d} m from its goal");
            humans += 1;
        }
    }
    assert_eq!(humans, 10);
    let p = crowd_plugin(&b).unwrap();
    let ext: Vec<_> = all(&p, "external_agent")
        .map(|e| e.text.clone().unwrap())
        .collect();
    let want: Vec<_> = c
        .agent_groups
        .iter()
        .filter(|g| g.profile_selector == "external_agent")
        .flat_map(|g| g.agents_name.clone())
        .collect();
    assert_eq!(ext, want);
    assert_eq!(ext.len(), 11);
    // The navmesh of L1's human lanes parses, with no degenerate obstacle.
    let files = crowd_files(&b);
    let nav = files
        .iter()
        .find(|f| f.path == Path::new("config_resource/L1_navmesh.nav"))
        .expect("L1_navmesh.nav");
    let m = parse_nav(std::str::from_utf8(&nav.contents).unwrap());
    assert!(!m.nodes.is_empty() && !m.edges.is_empty());
    assert_no_degenerate_obstacles(&m);
}

/// A navmesh node: vertex ring, plane (A B C), edge ids, obstacle ids.
type NavNode = (Vec<usize>, [f64; 3], Vec<usize>, Vec<usize>);

/// A parsed `.nav` file: vertices, edges (v0 v1 n0 n1), obstacles (v0 v1 node next),
/// nodes (centre, ring, plane, edges, obstacles).
struct Nav {
    verts: Vec<(f64, f64)>,
    edges: Vec<[usize; 4]>,
    obstacles: Vec<(usize, usize, usize, i64)>,
    nodes: Vec<NavNode>,
}

fn parse_nav(text: &str) -> Nav {
    let mut t = text.split_whitespace();
    let mut next = || t.next().expect("truncated .nav");
    let n = |s: &str| -> usize { s.parse().unwrap() };
    let nv = n(next());
    let verts = (0..nv)
        .map(|_| (next().parse().unwrap(), next().parse().unwrap()))
        .collect();
    let ne = n(next());
    let edges = (0..ne)
        .map(|_| [n(next()), n(next()), n(next()), n(next())])
        .collect();
    let no = n(next());
    let obstacles = (0..no)
        .map(|_| (n(next()), n(next()), n(next()), next().parse().unwrap()))
        .collect();
    assert_eq!(next(), "walkable");
    let nn = n(next());
    let mut nodes = Vec::new();
    for _ in 0..nn {
        let _centre: (f64, f64) = (next().parse().unwrap(), next().parse().unwrap());
        let k = n(next());
        let ring = (0..k).map(|_| n(next())).collect();
        let plane = [(); 3].map(|_| next().parse::<f64>().unwrap());
        let k = n(next());
        let e = (0..k).map(|_| n(next())).collect();
        let k = n(next());
        let o = (0..k).map(|_| n(next())).collect();
        nodes.push((ring, plane, e, o));
    }
    Nav {
        verts,
        edges,
        obstacles,
        nodes,
    }
}

/// Every coordinate finite and every obstacle longer than zero (Menge normalises them).
fn assert_no_degenerate_obstacles(m: &Nav) {
    assert!(m.verts.iter().all(|v| v.0.is_finite() && v.1.is_finite()));
    for o in &m.obstacles {
        let (p, q) = (m.verts[o.0], m.verts[o.1]);
        assert!((p.0 - q.0).hypot(p.1 - q.1) > 1e-6, "{o:?}");
    }
}

/// A T of human lanes (three 1.2 m lanes meeting at (5, 5), at 90°, 90° and 180°) and a
/// separate 0.8 m lane: lane rectangles of the lane widths, one junction shared by the T's
/// rectangles, counter-clockwise convex nodes, closed obstacle chains on the outline, and
/// lane ends pulled back from the junction by half the width / tan(45°).
#[test]
fn navmesh_from_human_lanes() {
    let yaml = "coordinate_system: cartesian_meters
crowd_sim: {enable: 1, update_time_step: 0.1}
levels:
  L1:
    elevation: 2
    human_lanes:
      - [0, 1, {graph_idx: [2, 9], width: [3, 1.2]}]
      - [0, 2, {graph_idx: [2, 9], width: [3, 1.2]}]
      - [3, 0, {graph_idx: [2, 9], width: [3, 1.2]}]
      - [4, 5, {graph_idx: [2, 9], width: [3, 0.8]}]
    vertices:
      - [5, 5, 0, c]
      - [0, 5, 0, w]
      - [10, 5, 0, e]
      - [5, 10, 0, n]
      - [20, 0, 0, a]
      - [20, 8, 0, b]
name: t
";
    let parsed = mapc_frontend::parse_str("t.building.yaml", yaml);
    let b = parsed.building.clone().unwrap();
    let files = crowd_files(&b);
    let nav = files
        .iter()
        .find(|f| f.path == Path::new("config_resource/L1_navmesh.nav"))
        .expect("L1_navmesh.nav");
    let text = std::str::from_utf8(&nav.contents).unwrap();
    let m = parse_nav(text);
    // 4 lane rectangles + 1 junction (c); w, e, n, a, b are dead ends.
    assert_eq!(m.nodes.len(), 5);
    // Four corners per lane, less the two where the n arm meets the e and w arms.
    assert_eq!(m.verts.len(), 4 * 4 - 2);
    let area = |ring: &[usize]| {
        let mut a = 0.0;
        for k in 0..ring.len() {
            let (p, q) = (m.verts[ring[k]], m.verts[ring[(k + 1) % ring.len()]]);
            a += p.0 * q.1 - q.0 * p.1;
        }
        a / 2.0
    };
    for (ring, plane, _, _) in &m.nodes {
        assert!(area(ring) > 0.0, "{ring:?} is not counter-clockwise");
        assert_eq!(plane, &[0.0, 0.0, 2.0]);
        // Convex: every turn is to the left.
        for k in 0..ring.len() {
            let [p, q, r] = [0, 1, 2].map(|j| m.verts[ring[(k + j) % ring.len()]]);
            let cross = (q.0 - p.0) * (r.1 - q.1) - (q.1 - p.1) * (r.0 - q.0);
            assert!(cross > -1e-9, "{ring:?} not convex");
        }
    }
    // Lane rectangles: widths and lengths. The T's arms end h / tan(45°) = h = 0.6 m from
    // c; the lone lane is 8 m long and 0.8 m wide.
    let h = 0.6;
    let areas: Vec<f64> = m.nodes[..4].iter().map(|n| area(&n.0)).collect();
    for a in &areas[..3] {
        assert!((a - 1.2 * (5.0 - h)).abs() < 1e-9, "{areas:?}");
    }
    assert!((areas[3] - 0.8 * 8.0).abs() < 1e-9, "{areas:?}");
    // The junction: the arms' end corners, a 1.2 m square around c (the n arm's corners
    // are the e and w arms' upper ones).
    let junction = &m.nodes[4];
    assert_eq!(junction.0.len(), 4);
    assert!((area(&junction.0) - 1.2 * 1.2).abs() < 1e-9);
    // Edges: each arm shares its end with the junction; nothing else is shared.
    assert_eq!(m.edges.len(), 3);
    for [v0, v1, n0, n1] in &m.edges {
        assert_eq!(*n1, 4);
        for n in [n0, n1] {
            assert!(m.nodes[*n].0.contains(v0) && m.nodes[*n].0.contains(v1));
            assert!(m.nodes[*n].2.contains(
                &m.edges
                    .iter()
                    .position(|e| e == &[*v0, *v1, *n0, *n1])
                    .unwrap()
            ));
        }
    }
    assert_no_degenerate_obstacles(&m);
    // Obstacles: every side not shared, clockwise around its node, in closed chains.
    let sides: usize = m.nodes.iter().map(|n| n.0.len()).sum();
    assert_eq!(m.obstacles.len(), sides - 2 * m.edges.len());
    for (k, &(v0, v1, node, next)) in m.obstacles.iter().enumerate() {
        let ring = &m.nodes[node].0;
        let i = ring.iter().position(|&v| v == v1).unwrap();
        assert_eq!(ring[(i + 1) % ring.len()], v0, "obstacle {k} not clockwise");
        assert!(m.nodes[node].3.contains(&k));
        let next = usize::try_from(next).expect("outlines are closed");
        assert_eq!(m.obstacles[next].0, v1);
    }
    // Two outlines: the T and the lone lane; following `next` closes each.
    let mut seen = vec![false; m.obstacles.len()];
    let mut loops = 0;
    for s in 0..m.obstacles.len() {
        if seen[s] {
            continue;
        }
        loops += 1;
        let mut k = s;
        while !seen[k] {
            seen[k] = true;
            k = m.obstacles[k].3 as usize;
        }
        assert_eq!(k, s);
    }
    assert_eq!(loops, 2);
}
