//! Simulation worlds (`mapc gazebo`/`ignition`/`classic`):
//! - every world and level model.sdf of the demo maps loads in libsdformat with no error
//!   (../shared/tools/sdf-check; Fuel models are not on this machine, so only "Unable to
//!   find uri" errors for models that are not our level models are tolerated);
//! - each world means the same as the reference's `<flavour>.world`: the same included
//!   models and robots with poses within 1e-6, the same level models at the same
//!   elevations, the same chargers, the same door and lift model names, the same
//!   toggle_floors lists and camera pose (doors and lifts in detail are tests/doors_lifts);
//! - snapshots of two fixture worlds; the CLI's old options, templates and confinement.
//!
//! Deliberate differences from the reference, checked as such below:
//! - everything is less `Building::offset`: chargers (the reference leaves them in map
//!   coordinates) and level includes (the reference puts wgs84 levels at −offset because it
//!   does not shift their meshes; ours are shifted, so levels sit at 0 0);
//! - `<static>` is `true`/`false` (the reference writes Python's `True`/`False`);
//! - the classic world is named `sim_world` (libsdformat ≥ 1.8 reserves `world`);
//! - maps with crowd_sim enabled (airport_terminal) get the `crowd_simulation` world plugin
//!   (the reference generator ignores crowd_sim; tests/crowd.rs checks the plugin).

use mapc_backends::sdf::world::{parse_template, world_text, WorldOptions};
use mapc_backends::sdf::xml::Element;
use mapc_backends::sdf::Flavour;
use mapc_ir::Building;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn shared() -> Option<PathBuf> {
    let p = root().join("../shared");
    if p.join("maps").is_dir() {
        Some(p)
    } else {
        println!("skipped: ../shared not found");
        None
    }
}

fn load(path: &Path) -> Building {
    let text = std::fs::read_to_string(path).unwrap();
    let parsed = mapc_frontend::parse_str(&path.display().to_string(), &text);
    parsed
        .valid_building()
        .unwrap_or_else(|| panic!("{}: errors {:#?}", path.display(), parsed.diagnostics))
        .clone()
}

fn demo_maps(shared: &Path) -> Vec<String> {
    let mut maps: Vec<String> = std::fs::read_dir(shared.join("maps"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    maps.sort();
    maps
}

const FLAVOURS: [(Flavour, &str, &str); 3] = [
    (Flavour::Gz, "gazebo", "gz"),
    (Flavour::Ignition, "ignition", "classic_ignition"),
    (Flavour::Classic, "classic", "classic_gazebo"),
];

fn mapc(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(root())
        .env_remove("MAPC_TEXTURE_PATH")
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn parse(text: &str) -> Element {
    parse_template(text, true).unwrap()
}

fn attr<'a>(e: &'a Element, k: &str) -> &'a str {
    e.attrs
        .iter()
        .find(|(n, _)| n == k)
        .map(|(_, v)| v.as_ref())
        .unwrap_or_else(|| panic!("<{}> has no {k}", e.name))
}

fn text<'a>(e: &'a Element, child: &str) -> &'a str {
    e.find(child)
        .and_then(|c| c.text.as_deref())
        .unwrap_or_else(|| panic!("<{}> has no <{child}>", e.name))
}

fn nums(s: &str) -> Vec<f64> {
    s.split_whitespace().map(|x| x.parse().unwrap()).collect()
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-6)
}

/// What a world means, for comparison.
#[derive(Debug, Default)]
struct Meaning {
    /// Placed models and robots: name → (uri, pose, static).
    includes: BTreeMap<String, (String, Vec<f64>, Option<String>)>,
    /// Level models: name → pose.
    levels: BTreeMap<String, Vec<f64>>,
    /// World-level `<model>` names (doors, shaft doors, lift cabins).
    models: Vec<String>,
    /// Chargers: name → (x, y, level or z).
    chargers: Vec<(String, f64, f64, String)>,
    /// toggle_floors: (floor, model_name, listed models).
    toggle: Vec<(String, String, Vec<String>)>,
    camera: Vec<f64>,
    offset: Option<Vec<f64>>,
    crs: Option<String>,
    name: String,
}

fn meaning(doc: &Element, level_models: &[String]) -> Meaning {
    let w = doc.find("world").unwrap();
    let mut m = Meaning {
        name: attr(w, "name").to_string(),
        ..Meaning::default()
    };
    for c in &w.children {
        match c.name.as_ref() {
            "include" if c.find("name").is_some() => {
                let name = text(c, "name").to_string();
                let pose = nums(text(c, "pose"));
                if level_models.contains(&name) {
                    m.levels.insert(name, pose);
                } else {
                    let st = c
                        .find("static")
                        .and_then(|s| s.text.as_ref().map(|t| t.to_string()));
                    m.includes
                        .insert(name, (text(c, "uri").to_string(), pose, st));
                }
            }
            "model" => m.models.push(attr(c, "name").to_string()),
            "plugin" if attr(c, "name") == "register_component" => {
                for comp in &c.children {
                    if attr(comp, "name") == "Chargers" {
                        for ch in &comp.children {
                            m.chargers.push((
                                attr(ch, "name").into(),
                                attr(ch, "x").parse().unwrap(),
                                attr(ch, "y").parse().unwrap(),
                                attr(ch, "z").into(),
                            ));
                        }
                    }
                }
            }
            "rmf_charger_waypoints" => {
                for ch in &c.children {
                    m.chargers.push((
                        attr(ch, "name").into(),
                        attr(ch, "x").parse().unwrap(),
                        attr(ch, "y").parse().unwrap(),
                        attr(ch, "level").into(),
                    ));
                }
            }
            "offset" => m.offset = Some(nums(c.text.as_deref().unwrap())),
            "crs" => m.crs = c.text.as_ref().map(|t| t.to_string()),
            "gui" => {
                for p in &c.children {
                    if p.name == "camera" {
                        m.camera = nums(text(p, "pose"));
                    }
                    if p.name != "plugin" {
                        continue;
                    }
                    if let Some(cp) = p.find("camera_pose") {
                        m.camera = nums(cp.text.as_deref().unwrap());
                    }
                    if attr(p, "name") == "toggle_floors" {
                        for f in &p.children {
                            m.toggle.push((
                                attr(f, "name").into(),
                                attr(f, "model_name").into(),
                                f.children.iter().map(|x| attr(x, "name").into()).collect(),
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    m
}

#[test]
fn worlds_mean_what_the_reference_worlds_mean() {
    let Some(shared) = shared() else { return };
    for map in demo_maps(&shared) {
        let b = load(&shared.join(format!("maps/{map}/{map}.building.yaml")));
        let levels: Vec<String> = b
            .levels
            .iter()
            .map(|(h, _)| mapc_backends::sdf::level::level_model_name(&b, h))
            .collect();
        let (ox, oy) = (b.offset.x, b.offset.y);
        for (flavour, _, reference) in FLAVOURS {
            let what = format!("{map} {reference}");
            let ours = meaning(
                &parse(&world_text(&b, flavour, &WorldOptions::default())),
                &levels,
            );
            let path = shared.join(format!("reference/{map}/{reference}.world"));
            let theirs = meaning(&parse(&std::fs::read_to_string(path).unwrap()), &levels);

            // Deliberate: the classic world is sim_world, not the reserved `world`.
            assert_eq!(ours.name, "sim_world", "{what}");

            // Models and robots: same names, URIs, poses; static as a boolean.
            assert_eq!(
                ours.includes.keys().collect::<Vec<_>>(),
                theirs.includes.keys().collect::<Vec<_>>(),
                "{what}: included models and robots"
            );
            for (name, (uri, pose, st)) in &ours.includes {
                let (ruri, rpose, rst) = &theirs.includes[name];
                assert_eq!(uri, ruri, "{what}: {name}");
                assert!(close(pose, rpose), "{what}: {name}: {pose:?} vs {rpose:?}");
                // Deliberate: `true`/`false`, where the reference writes `True`/`False`.
                assert_eq!(
                    st.as_deref().map(str::to_ascii_lowercase),
                    rst.as_deref().map(str::to_ascii_lowercase),
                    "{what}: {name} static"
                );
            }

            // Level models: same elevations; deliberate: always at x = y = 0 (the
            // reference puts wgs84 levels at −offset because it does not shift the meshes).
            assert_eq!(ours.levels.len(), theirs.levels.len(), "{what}");
            for (name, pose) in &ours.levels {
                let r = &theirs.levels[name];
                assert_eq!(pose, &vec![0.0, 0.0, r[2], 0.0, 0.0, 0.0], "{what}: {name}");
                assert!(
                    close(&r[..2], &[0.0, 0.0]) || close(&r[..2], &[-ox, -oy]),
                    "{what}: {name}: reference at {r:?}"
                );
            }

            // Doors, shaft doors and cabins: the same model names, in the same order.
            assert_eq!(ours.models, theirs.models, "{what}: door and lift models");

            // Chargers: deliberate: less the offset (the reference does not subtract it),
            // and a waypoint with `is_charger: false` is no charger (the reference
            // registers any waypoint that has the key).
            let not_chargers: Vec<&str> = b
                .vertices
                .iter()
                .filter(|(_, v)| v.params.bool("is_charger") == Some(false))
                .map(|(_, v)| v.name.as_str())
                .collect();
            let theirs_chargers: Vec<_> = theirs
                .chargers
                .iter()
                .filter(|c| !not_chargers.contains(&c.0.as_str()))
                .collect();
            assert_eq!(ours.chargers.len(), theirs_chargers.len(), "{what}");
            for (a, r) in ours.chargers.iter().zip(theirs_chargers) {
                assert_eq!((&a.0, &a.3), (&r.0, &r.3), "{what}: charger");
                assert!(
                    close(&[a.1, a.2], &[r.1 - ox, r.2 - oy]),
                    "{what}: charger {a:?} vs {r:?}"
                );
            }

            assert_eq!(ours.toggle, theirs.toggle, "{what}: toggle_floors");
            assert!(
                close(&ours.camera, &theirs.camera),
                "{what}: camera {:?} vs {:?}",
                ours.camera,
                theirs.camera
            );
            assert_eq!(ours.offset, theirs.offset, "{what}: offset");
            assert_eq!(ours.crs, theirs.crs, "{what}: crs");

            // Deliberate: the crowd simulator plugin when crowd_sim is enabled
            // (airport_terminal); the reference generator ignores crowd_sim.
            let crowd = |doc: &Element| {
                doc.find("world").unwrap().children.iter().any(|c| {
                    c.name == "plugin"
                        && c.attrs
                            .iter()
                            .any(|(k, v)| k == "name" && v == "crowd_simulation")
                })
            };
            let ours_doc = parse(&world_text(&b, flavour, &WorldOptions::default()));
            let enabled = b.crowd_sim.as_ref().is_some_and(|c| c.enable);
            assert_eq!(crowd(&ours_doc), enabled, "{what}: crowd plugin");
            let theirs_doc = parse(
                &std::fs::read_to_string(shared.join(format!("reference/{map}/{reference}.world")))
                    .unwrap(),
            );
            assert!(!crowd(&theirs_doc), "{what}");
        }
    }
}

/// Runs sdf-check; `None` when the tool cannot run here.
fn sdf_check(files: &[PathBuf], sdf_path: &Path) -> Option<String> {
    let tool = root().join("../shared/tools/sdf-check");
    let out = Command::new(&tool)
        .env("SDF_PATH", sdf_path)
        // Missing-URI errors are filtered below, so that a missing level model still fails.
        .env_remove("SDF_CHECK_IGNORE_MISSING")
        .args(files)
        .output()
        .ok()?;
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    if !stdout.contains(" errors (") {
        println!(
            "skipped: sdf-check could not run: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        return None;
    }
    Some(stdout)
}

#[test]
fn demo_worlds_and_models_pass_sdf_check() {
    let Some(shared) = shared() else { return };
    let tmp = tempfile::tempdir().unwrap();
    let textures = shared.join("textures");
    let mut report = String::new();
    let mut inputs: Vec<(String, PathBuf)> = demo_maps(&shared)
        .into_iter()
        .map(|m| {
            (
                m.clone(),
                shared.join(format!("maps/{m}/{m}.building.yaml")),
            )
        })
        .collect();
    for f in FIXTURES {
        inputs.push((
            f.replace(".building.yaml", ""),
            root().join("fixtures").join(f),
        ));
    }
    // One job per map and flavour, run in parallel (sdf-check takes a while on big maps).
    let mut jobs = Vec::new();
    for (map, input) in &inputs {
        let b = load(input);
        let levels: Vec<String> = b
            .levels
            .iter()
            .map(|(h, _)| mapc_backends::sdf::level::level_model_name(&b, h))
            .collect();
        for (_, cmd, _) in FLAVOURS {
            jobs.push((map.clone(), input.clone(), levels.clone(), cmd));
        }
    }
    let results: Vec<Option<String>> = std::thread::scope(|s| {
        let handles: Vec<_> = jobs
            .iter()
            .map(|(map, input, levels, cmd)| {
                let dir = tmp.path().join(map).join(cmd);
                let textures = &textures;
                s.spawn(move || check_world(map, input, levels, cmd, &dir, textures))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for r in results {
        match r {
            Some(line) => report.push_str(&line),
            None => return,
        }
    }
    println!("{report}");
}

/// Writes one world with the CLI and runs sdf-check on it and its level models: the report
/// line, or `None` when sdf-check cannot run here. Panics on any error.
fn check_world(
    map: &str,
    input: &Path,
    levels: &[String],
    cmd: &str,
    dir: &Path,
    textures: &Path,
) -> Option<String> {
    let world = dir.join(format!("{map}.world"));
    let models = dir.join("models");
    let (code, err) = mapc(&[
        cmd,
        input.to_str().unwrap(),
        world.to_str().unwrap(),
        models.to_str().unwrap(),
        "--texture-path",
        textures.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{map} {cmd}: {err}");
    let mut files = vec![world.clone()];
    files.extend(levels.iter().map(|l| models.join(l).join("model.sdf")));
    let out = sdf_check(&files, &models)?;
    let mut errors = Vec::new();
    let mut fuel = 0;
    for line in out.lines().filter(|l| l.contains(": error: ")) {
        let missing = line
            .split_once("Unable to find uri[model://")
            .map(|(_, rest)| rest.trim_end_matches(']'));
        match missing {
            Some(m) if !levels.iter().any(|l| l == m) => fuel += 1,
            _ => errors.push(line.to_string()),
        }
    }
    assert!(errors.is_empty(), "{map} {cmd}:\n{}", errors.join("\n"));
    Some(format!(
        "{map} {cmd}: world + {} model.sdf, 0 errors ({fuel} Fuel models not here)\n",
        levels.len()
    ))
}

/// Fixture maps: every coordinate system, offsets, a lift, doors of every type.
const FIXTURES: &[&str] = &[
    "two_level_clinic.building.yaml",
    "cartesian_warehouse.building.yaml",
    "wgs84_campus.building.yaml",
    "legacy_2019.building.yaml",
    "web_mercator_legacy.building.yaml",
    "lift_doors.building.yaml",
];

fn fixture_world(file: &str, flavour: Flavour) -> String {
    let b = load(&root().join("fixtures").join(file));
    world_text(&b, flavour, &WorldOptions::default())
}

#[test]
fn snapshot_two_level_clinic_gz() {
    insta::assert_snapshot!(fixture_world("two_level_clinic.building.yaml", Flavour::Gz));
}

#[test]
fn snapshot_legacy_2019_classic() {
    insta::assert_snapshot!(fixture_world("legacy_2019.building.yaml", Flavour::Classic));
}

#[test]
fn old_options_template_and_skip_camera_pose() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let template = t.join("template.sdf");
    std::fs::write(
        &template,
        "<?xml version=\"1.0\"?>\n<!-- mine -->\n<sdf version=\"1.7\"><world name=\"mine\"><gui>\
         <plugin filename=\"MinimalScene\" name=\"3D View\"><camera_pose>1 2 3 0 0 0</camera_pose>\
         </plugin></gui></world></sdf>\n",
    )
    .unwrap();
    let world = t.join("out/w.world");
    let models = t.join("models");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "gazebo",
            "fixtures/two_level_clinic.building.yaml",
            world.to_str().unwrap(),
            models.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        mapc(&args)
    };
    let (code, err) = run(&["-o", "gazebo", "-n", "-m", "x", "-c", "y"]);
    assert_eq!(code, 0, "{err}");
    let w = std::fs::read_to_string(&world).unwrap();
    assert!(w.contains("<world name=\"sim_world\">"));
    assert!(models.join("two_level_clinic_L1/model.sdf").is_file());
    assert!(models.join("two_level_clinic_L1/model.config").is_file());

    let (code, err) = run(&["--TEMPLATE_WORLD_FILE", template.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let w = std::fs::read_to_string(&world).unwrap();
    assert!(w.contains("<world name=\"mine\">") && !w.contains("mine -->"));
    assert!(!w.contains("<camera_pose>1 2 3 0 0 0</camera_pose>"));
    assert!(w.contains("toggle_floors"));

    let (code, err) = run(&[
        "--TEMPLATE_WORLD_FILE",
        template.to_str().unwrap(),
        "--SKIP_CAMERA_POSE",
    ]);
    assert_eq!(code, 0, "{err}");
    let w = std::fs::read_to_string(&world).unwrap();
    assert!(w.contains("<camera_pose>1 2 3 0 0 0</camera_pose>"));

    // A template without a camera pose to set is a usage error (the reference crashes).
    std::fs::write(&template, "<sdf><world name=\"w\"><gui/></world></sdf>").unwrap();
    let (code, err) = run(&["--TEMPLATE_WORLD_FILE", template.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--SKIP_CAMERA_POSE"), "{err}");

    // The three flavours' subcommands and the gz alias.
    for cmd in ["gz", "ignition", "classic"] {
        let (code, err) = mapc(&[
            cmd,
            "fixtures/legacy_2019.building.yaml",
            t.join(format!("{cmd}.world")).to_str().unwrap(),
            models.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{cmd}: {err}");
    }
}

#[test]
fn level_names_cannot_escape_the_model_dir() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let text = std::fs::read_to_string(root().join("fixtures/legacy_2019.building.yaml")).unwrap();
    for (i, bad) in ["../../x", "/etc/x"].iter().enumerate() {
        let dir = t.join(format!("case{i}"));
        std::fs::create_dir_all(&dir).unwrap();
        let map = dir.join("m.building.yaml");
        // Rename the building so that `<building>_<level>` leaves the model dir.
        let renamed = rename_building(&text, bad);
        std::fs::write(&map, renamed).unwrap();
        let models = dir.join("a/b/models");
        let (code, err) = mapc(&[
            "gazebo",
            map.to_str().unwrap(),
            dir.join("w.world").to_str().unwrap(),
            models.to_str().unwrap(),
        ]);
        assert_ne!(code, 0, "{bad}: {err}");
        assert!(!dir.join("w.world").exists(), "{bad}");
        assert!(!dir.join("a/x_L1").exists() && !dir.join("x_L1").exists());
        assert!(!Path::new("/etc/x_L1").exists());
    }
}

fn rename_building(text: &str, name: &str) -> String {
    let mut out = String::new();
    let mut done = false;
    for line in text.lines() {
        if !done && (line.starts_with("name:") || line.starts_with("building_name:")) {
            let key = line.split(':').next().unwrap();
            out.push_str(&format!("{key}: \"{name}\"\n"));
            done = true;
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    if !done {
        out = format!("name: \"{name}\"\n{out}");
    }
    out
}

/// A level model.sdf's links: name → (visual name, mesh URI, albedo map, script name,
/// transparency, pose).
type Links = BTreeMap<
    String,
    (
        String,
        String,
        String,
        String,
        Option<f64>,
        Option<Vec<f64>>,
    ),
>;

fn links(doc: &Element) -> Links {
    let model = doc.find("model").unwrap();
    assert_eq!(text(model, "static"), "true");
    model
        .children
        .iter()
        .filter(|c| c.name == "link")
        .map(|l| {
            let v = l.find("visual").unwrap();
            let mat = v.find("material").unwrap();
            let metal = mat.find("pbr").unwrap().find("metal").unwrap();
            let col = l.find("collision").unwrap();
            let uri = text(v.find("geometry").unwrap().find("mesh").unwrap(), "uri");
            let cu = text(col.find("geometry").unwrap().find("mesh").unwrap(), "uri");
            assert_eq!(uri, cu);
            (
                attr(l, "name").to_string(),
                (
                    attr(v, "name").to_string(),
                    uri.to_string(),
                    text(metal, "albedo_map").to_string(),
                    text(mat.find("script").unwrap(), "name").to_string(),
                    v.find("transparency")
                        .map(|t| t.text.as_deref().unwrap().parse().unwrap()),
                    l.find("pose").map(|p| nums(p.text.as_deref().unwrap())),
                ),
            )
        })
        .collect()
}

#[test]
fn level_models_mean_what_the_reference_models_mean() {
    let Some(shared) = shared() else { return };
    for map in demo_maps(&shared) {
        let b = load(&shared.join(format!("maps/{map}/{map}.building.yaml")));
        for (h, _) in b.levels.iter() {
            let name = mapc_backends::sdf::level::level_model_name(&b, h);
            let dir = shared.join(format!("reference/{map}/models/{name}"));
            let meshes = mapc_backends::level_meshes(&b, h);
            // model.config: byte for byte.
            assert_eq!(
                mapc_backends::sdf::level::level_model_config(&b, h).to_document(true),
                std::fs::read_to_string(dir.join("model.config")).unwrap(),
                "{map} {name}"
            );
            let ours = links(&parse_any(
                &mapc_backends::sdf::level::level_model_sdf(&b, h, &meshes).to_document(true),
            ));
            let theirs = links(&parse_any(
                &std::fs::read_to_string(dir.join("model.sdf")).unwrap(),
            ));
            assert_eq!(
                ours.keys().collect::<Vec<_>>(),
                theirs.keys().collect::<Vec<_>>(),
                "{map} {name}: links"
            );
            for (k, a) in &ours {
                let r = &theirs[k];
                assert_eq!(
                    (&a.0, &a.1, &a.2, &a.3),
                    (&r.0, &r.1, &r.2, &r.3),
                    "{map} {k}"
                );
                assert!(
                    match (a.4, r.4) {
                        (Some(x), Some(y)) => (x - y).abs() < 1e-9,
                        (x, y) => x == y,
                    },
                    "{map} {k}: transparency"
                );
                match (&a.5, &r.5) {
                    (Some(x), Some(y)) => assert!(close(x, y), "{map} {k}: {x:?} vs {y:?}"),
                    (x, y) => assert_eq!(x, y, "{map} {k}: pose"),
                }
            }
        }
    }
}

/// Parses an SDF document whose root is `<sdf>` (no world needed).
fn parse_any(text: &str) -> Element {
    let wrapped = text.replace("<?xml version='1.0' encoding='utf-8'?>", "");
    // parse_template wants a world: wrap the model in one.
    let doc = parse_template(
        &wrapped
            .replacen(
                "<sdf version=\"1.7\">",
                "<sdf version=\"1.7\"><world name=\"w\">",
                1,
            )
            .replacen("</sdf>", "</world></sdf>", 1),
        true,
    )
    .unwrap();
    doc.find("world").unwrap().clone()
}

/// Offset maps: everything in the world is less the building offset, so models, robots,
/// doors, lifts and chargers sit near the origin with the level meshes, and `<offset>`
/// states what was subtracted.
#[test]
fn offset_is_subtracted_from_everything() {
    for (file, offset, crs) in [
        (
            "cartesian_warehouse.building.yaml",
            [25000.0, 31000.0],
            "EPSG:3414",
        ),
        (
            "wgs84_campus.building.yaml",
            [364200.0, 143700.0],
            "EPSG:32648",
        ),
    ] {
        let b = load(&root().join("fixtures").join(file));
        let doc = parse(&world_text(&b, Flavour::Gz, &WorldOptions::default()));
        let w = doc.find("world").unwrap();
        let mut poses = 0;
        for c in &w.children {
            if matches!(c.name.as_ref(), "include" | "model") {
                if let Some(p) = c.find("pose") {
                    let p = nums(p.text.as_deref().unwrap());
                    assert!(p[0].abs() < 1000.0 && p[1].abs() < 1000.0, "{file}: {p:?}");
                    poses += 1;
                }
            }
        }
        assert!(poses > 1, "{file}");
        let m = meaning(&doc, &[]);
        for ch in &m.chargers {
            assert!(ch.1.abs() < 1000.0 && ch.2.abs() < 1000.0, "{file}: {ch:?}");
        }
        assert!(m.camera[0].abs() < 1000.0 && m.camera[1].abs() < 1000.0);
        assert_eq!(
            m.offset,
            Some(vec![offset[0], offset[1], 0.0, 0.0, 0.0, 0.0])
        );
        assert_eq!(m.crs.as_deref(), Some(crs));
    }
}

/// A failed run (an error that breaks worlds) writes nothing: the previous world and models
/// stay. (A lane error such as E0201 breaks only nav graphs, so it would not do.)
#[test]
fn failed_run_leaves_previous_outputs() {
    let tmp = tempfile::tempdir().unwrap();
    let world = tmp.path().join("w.world");
    let models = tmp.path().join("models");
    let args = |map: &str| {
        vec![
            "gazebo".to_string(),
            map.to_string(),
            world.display().to_string(),
            models.display().to_string(),
        ]
    };
    let ok = args("fixtures/legacy_2019.building.yaml");
    let (code, err) = mapc(&ok.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    let before = std::fs::read(&world).unwrap();
    let sdf = models.join("legacy_office_L1/model.sdf");
    let sdf_before = std::fs::read(&sdf).unwrap();
    let bad = args("fixtures/invalid/E0302-duplicate-door-name.building.yaml");
    let (code, err) = mapc(&bad.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("nothing written"), "{err}");
    assert_eq!(std::fs::read(&world).unwrap(), before);
    assert_eq!(std::fs::read(&sdf).unwrap(), sdf_before);
}

/// A rotated lift with several doors (fixtures/lift_doors: two front doors opening on L1,
/// listed there in the opposite order to the lift's `doors`, and a right-side door opening
/// on L2), checked against generator.md §2.8 computed here: shaft-door poses, cabin-door
/// poses, door pairs in the `doors` order, joint limits, wall segments with the door gaps,
/// toggle_floors lists; and the Ignition cabin-door links (§3).
/// A lift's floors as the lift plugin lists them: (name, elevation, (cabin, shaft) pairs).
type Floors = Vec<(String, f64, Vec<(String, String)>)>;

#[test]
// 1.5708 is the fixture's motion_axis_orientation, not an approximation of π/2 to fix.
#[allow(clippy::approx_constant)]
fn lift_with_several_doors() {
    let b = load(&root().join("fixtures/lift_doors.building.yaml"));
    // The fixture's values.
    let (lx, ly, psi, w, d) = (10.0, 5.0, 0.5_f64, 3.0, 2.0);
    let (g, inset, hc) = (0.05, 0.025, 2.5);
    // name, x, y, width, motion_axis_orientation, front (true) or right side.
    let doors = [
        ("front_a", -0.7, 1.0, 1.0, 0.0, true),
        ("front_b", 0.8, 1.0, 0.8, 0.0, true),
        ("east", 1.5, 0.0, 1.2, 1.5708, false),
    ];
    let levels = [
        ("L1", 0.0, vec!["front_a", "front_b"]),
        ("L2", 3.5, vec!["east"]),
    ];
    let door = |n: &str| *doors.iter().find(|x| x.0 == n).unwrap();

    for (flavour, _, _) in FLAVOURS {
        let doc = parse(&world_text(&b, flavour, &WorldOptions::default()));
        let world = doc.find("world").unwrap();
        let model = |name: &str| {
            world
                .children
                .iter()
                .find(|c| c.name == "model" && attr(c, "name") == name)
                .unwrap_or_else(|| panic!("{flavour:?}: no model {name}"))
        };
        // Shaft doors: one per (level, listed door), in level order then `doors` order.
        let shaft_names: Vec<String> = world
            .children
            .iter()
            .filter(|c| c.name == "model" && attr(c, "name").starts_with("ShaftDoor_"))
            .map(|c| attr(c, "name").to_string())
            .collect();
        let want: Vec<String> = levels
            .iter()
            .flat_map(|(l, _, ds)| ds.iter().map(move |n| format!("ShaftDoor_lift_1_{l}_{n}")))
            .collect();
        assert_eq!(shaft_names, want, "{flavour:?}");
        for (l, elev, ds) in &levels {
            for n in ds {
                let (_, x, y, dw, mao, front) = door(n);
                let (sx, sy) = if front {
                    (x, d / 2.0 + g)
                } else {
                    (w / 2.0 + g, y)
                };
                let m = model(&format!("ShaftDoor_lift_1_{l}_{n}"));
                let pose = nums(text(m, "pose"));
                let want = [
                    lx + sx * psi.cos() - sy * psi.sin(),
                    ly + sx * psi.sin() + sy * psi.cos(),
                    *elev,
                    0.0,
                    0.0,
                    psi + mao,
                ];
                assert!(close(&pose, &want), "{flavour:?} {n}: {pose:?} vs {want:?}");
                // Leaves w/2 wide; joints right [0, w/2], left [-w/2, 0].
                let joint = |j: &str| {
                    let j = m
                        .children
                        .iter()
                        .find(|c| c.name == "joint" && attr(c, "name") == j)
                        .unwrap();
                    let lim = j.find("axis").unwrap().find("limit").unwrap();
                    [text(lim, "lower"), text(lim, "upper")].map(|t| t.parse::<f64>().unwrap())
                };
                assert_eq!(joint("right_joint"), [0.0, dw / 2.0]);
                assert_eq!(joint("left_joint"), [-dw / 2.0, 0.0]);
            }
        }

        // The cabin at the lift's pose, door pairs per floor in the `doors` order.
        let cabin = model("lift_1");
        assert!(close(
            &nums(text(cabin, "pose")),
            &[lx, ly, 0.0, 0.0, 0.0, psi]
        ));
        let lift_params = match flavour {
            Flavour::Gz => cabin
                .children
                .iter()
                .filter(|c| c.name == "plugin")
                .filter_map(|p| p.find("component"))
                .find(|c| attr(c, "name") == "Lift")
                .unwrap(),
            _ => cabin
                .children
                .iter()
                .find(|c| c.name == "plugin" && attr(c, "name") == "lift")
                .unwrap(),
        };
        let floors: Floors = lift_params
            .children
            .iter()
            .filter(|c| c.name == "floor")
            .map(|f| {
                (
                    attr(f, "name").to_string(),
                    attr(f, "elevation").parse().unwrap(),
                    f.children
                        .iter()
                        .map(|p| {
                            (
                                attr(p, "cabin_door").to_string(),
                                attr(p, "shaft_door").to_string(),
                            )
                        })
                        .collect(),
                )
            })
            .collect();
        let want: Floors = levels
            .iter()
            .map(|(l, e, ds)| {
                (
                    l.to_string(),
                    *e,
                    ds.iter()
                        .map(|n| {
                            (
                                format!("CabinDoor_lift_1_{n}"),
                                format!("ShaftDoor_lift_1_{l}_{n}"),
                            )
                        })
                        .collect(),
                )
            })
            .collect();
        assert_eq!(floors, want, "{flavour:?}");
        assert_eq!(text(lift_params, "initial_floor"), "L2");

        // Cabin doors: every lift door, at its cabin-door position.
        for (n, x, y, dw, mao, front) in doors {
            let (cx, cy) = if front {
                (x, d / 2.0 - inset)
            } else {
                (w / 2.0 - inset, y)
            };
            let cname = format!("CabinDoor_lift_1_{n}");
            if flavour == Flavour::Ignition {
                // Links directly in the cabin, at the leaf centres.
                for (leaf, sign) in [("right_door", 1.0), ("left_door", -1.0)] {
                    let link = cabin
                        .children
                        .iter()
                        .find(|c| c.name == "link" && attr(c, "name") == format!("{cname}_{leaf}"))
                        .unwrap();
                    let want = [
                        cx + sign * mao.cos() * dw / 4.0,
                        cy + sign * mao.sin() * dw / 4.0,
                        hc / 2.0,
                        0.0,
                        0.0,
                        mao,
                    ];
                    assert!(close(&nums(text(link, "pose")), &want), "{cname} {leaf}");
                }
            } else {
                let nested = cabin
                    .children
                    .iter()
                    .find(|c| c.name == "model" && attr(c, "name") == cname)
                    .unwrap();
                let want = [cx, cy, 0.0, 0.0, 0.0, mao];
                assert!(
                    close(&nums(text(nested, "pose")), &want),
                    "{flavour:?} {cname}"
                );
            }
        }

        // Walls: front [-W/2, W/2] cut by both front doors, right [-D/2+tw, D/2-tw] by the
        // east door.
        let platform = cabin
            .children
            .iter()
            .find(|c| c.name == "link" && attr(c, "name") == "platform")
            .unwrap();
        let walls: Vec<(String, f64)> = platform
            .children
            .iter()
            .filter(|c| c.name == "visual" && attr(c, "name").contains("wall"))
            .map(|v| {
                let size = nums(text(
                    v.find("geometry").unwrap().find("box").unwrap(),
                    "size",
                ));
                (
                    attr(v, "name").trim_end_matches("_visual").to_string(),
                    size[0],
                )
            })
            .collect();
        let tw = 0.05;
        let want = [
            ("frontwall1", -1.2 - -1.5),
            ("frontwall2", 0.4 - -0.2),
            ("frontwall3", 1.5 - 1.2),
            ("backwall1", w),
            ("leftwall1", d - 2.0 * tw),
            ("rightwall1", -0.6 - (-d / 2.0 + tw)),
            ("rightwall2", (d / 2.0 - tw) - 0.6),
        ];
        assert_eq!(walls.len(), want.len(), "{walls:?}");
        for ((n, l), (wn, wl)) in walls.iter().zip(want) {
            assert_eq!(n, wn);
            assert!((l - wl).abs() < 1e-9, "{n}: {l} vs {wl}");
        }

        // toggle_floors lists each level's shaft doors.
        let m = meaning(&doc, &[]);
        for (l, _, ds) in &levels {
            let (_, _, listed) = m.toggle.iter().find(|t| t.0 == *l).unwrap();
            for n in ds {
                assert!(
                    listed.contains(&format!("ShaftDoor_lift_1_{l}_{n}")),
                    "{l}: {listed:?}"
                );
            }
        }
    }
}
