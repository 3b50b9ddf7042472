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
        .map(|(_, v)| v.as_str())
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
            PathBuf::from("config_resource/scene_file.xml")
        ]
    );
    for f in &files {
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
}
