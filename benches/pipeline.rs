//! Compile-time of the nav pipeline: `mapc_frontend::parse_str` (YAML, lowering, coordinate
//! transforms) followed by `mapc_backends::nav_graphs`, on every `fixtures/*.building.yaml`
//! (listed when the benchmark starts) and on the demo maps in `../shared/maps` when present.
//!
//! `meshes` times the level geometry of every level (`mapc_backends::level_meshes`) and
//! `obj_files` the OBJ/MTL output on top of it.
//!
//! `check` times what `mapc check` computes in process (parse, lower, transform, validation
//! passes) on each demo map; `validate_only` times the validation passes alone on the largest
//! input.
//!
//! Run with `cargo bench --bench pipeline`. Inputs are read once, before any timing; the
//! timed closures only see `&str`s. Benchmark names are `fixture/<stem>` and
//! `shared/<map>`.

use divan::counter::BytesCount;
use divan::{black_box, Bencher};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn main() {
    let inputs = inputs();
    if !shared_dir().is_dir() {
        eprintln!("skipped: ../shared not found (demo maps not benchmarked)");
    }
    for i in inputs {
        if mapc_frontend::parse_str(&i.name, &i.text)
            .valid_building()
            .is_none()
        {
            eprintln!(
                "note: {} has errors; its pipeline stops after parsing",
                i.name
            );
        }
    }
    divan::main();
}

struct Input {
    /// `fixture/<stem>` or `shared/<map>`.
    name: String,
    text: String,
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn shared_dir() -> PathBuf {
    root().join("../shared/maps")
}

fn building_files(dir: &Path) -> Vec<PathBuf> {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = rd
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.is_file()
                && p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.ends_with(".building.yaml"))
        })
        .collect();
    files.sort();
    files
}

fn stem(p: &Path) -> String {
    let n = p.file_name().unwrap().to_string_lossy();
    n.trim_end_matches(".building.yaml").to_string()
}

/// Every input, read once.
fn inputs() -> &'static [Input] {
    static INPUTS: OnceLock<Vec<Input>> = OnceLock::new();
    INPUTS.get_or_init(|| {
        let mut out = Vec::new();
        for p in building_files(&root().join("fixtures")) {
            if let Ok(text) = std::fs::read_to_string(&p) {
                out.push(Input {
                    name: format!("fixture/{}", stem(&p)),
                    text,
                });
            }
        }
        let shared = shared_dir();
        let mut maps: Vec<PathBuf> = std::fs::read_dir(&shared)
            .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        maps.sort();
        for dir in maps {
            for p in building_files(&dir) {
                if let Ok(text) = std::fs::read_to_string(&p) {
                    out.push(Input {
                        name: format!("shared/{}", stem(&p)),
                        text,
                    });
                }
            }
        }
        out
    })
}

fn names() -> Vec<&'static str> {
    inputs().iter().map(|i| i.name.as_str()).collect()
}

/// The demo maps (`shared/<map>`); empty without `../shared`, which skips the benchmark.
fn shared_names() -> Vec<&'static str> {
    inputs()
        .iter()
        .map(|i| i.name.as_str())
        .filter(|n| n.starts_with("shared/"))
        .collect()
}

fn text(name: &str) -> &'static str {
    &inputs().iter().find(|i| i.name == name).unwrap().text
}

/// The largest input (by bytes), for the parse-only and validate-only benchmarks.
fn largest() -> Vec<&'static str> {
    inputs()
        .iter()
        .max_by_key(|i| i.text.len())
        .map(|i| i.name.as_str())
        .into_iter()
        .collect()
}

/// parse + lower + transform + nav graphs (what `mapc nav` computes before writing).
#[divan::bench(args = names())]
fn parse_lower_nav(bencher: Bencher, name: &str) {
    let text = text(name);
    bencher.counter(BytesCount::of_str(text)).bench(|| {
        let parsed = mapc_frontend::parse_str(name, black_box(text));
        let files = parsed.valid_building().map(mapc_backends::nav_graphs);
        (parsed, files)
    });
}

/// Parsing alone (YAML, lowering, transforms) of the largest map.
#[divan::bench(args = largest())]
fn parse_only(bencher: Bencher, name: &str) {
    let text = text(name);
    bencher
        .counter(BytesCount::of_str(text))
        .bench(|| mapc_frontend::parse_str(name, black_box(text)));
}

/// The validation passes `mapc nav`/`check` also run, on an already parsed map (for
/// information: the CLI cost is parse_lower_nav + validate + writing the files).
#[divan::bench(args = names())]
fn validate(bencher: Bencher, name: &str) {
    let parsed = mapc_frontend::parse_str(name, text(name));
    let Some(b) = parsed.building.as_ref() else {
        return;
    };
    bencher.bench(|| mapc_ir::validate(black_box(b)));
}

/// What `mapc check` computes in process: parse + lower + transform, then the validation
/// passes on any building returned (even with frontend errors, as the CLI does). Rendering
/// the diagnostics and process start-up are not included. Target: the largest demo map
/// under 10 ms.
#[divan::bench(args = shared_names())]
fn check(bencher: Bencher, name: &str) {
    let text = text(name);
    bencher.counter(BytesCount::of_str(text)).bench(|| {
        let parsed = mapc_frontend::parse_str(name, black_box(text));
        let diagnostics = parsed.building.as_ref().map(mapc_ir::validate);
        (parsed, diagnostics)
    });
}

/// The validation passes alone on the largest input, already parsed.
#[divan::bench(args = largest())]
fn validate_only(bencher: Bencher, name: &str) {
    let parsed = mapc_frontend::parse_str(name, text(name));
    let Some(b) = parsed.building.as_ref() else {
        return;
    };
    bencher.bench(|| mapc_ir::validate(black_box(b)));
}

/// Level geometry of every level of a map (floors with holes and lift shafts cut out and
/// triangulated, ceilings, walls; `mapc_backends::level_meshes`), on an already parsed map.
/// Target: the largest demo map under 20 ms.
#[divan::bench(args = names())]
fn meshes(bencher: Bencher, name: &str) {
    let parsed = mapc_frontend::parse_str(name, text(name));
    let Some(b) = parsed.valid_building() else {
        return;
    };
    bencher.bench(|| {
        b.levels
            .iter()
            .map(|(h, _)| mapc_backends::level_meshes(black_box(b), h))
            .collect::<Vec<_>>()
    });
}

/// Level meshes and their OBJ/MTL/material files for every level (what the gazebo level
/// models need besides model.sdf).
#[divan::bench(args = shared_names())]
fn obj_files(bencher: Bencher, name: &str) {
    let parsed = mapc_frontend::parse_str(name, text(name));
    let Some(b) = parsed.valid_building() else {
        return;
    };
    bencher.bench(|| {
        b.levels
            .iter()
            .map(|(h, _)| mapc_backends::level_obj_files(black_box(b), h))
            .collect::<Vec<_>>()
    });
}

/// What `mapc gazebo` computes for one map once it is read and checked: level meshes, then
/// the gz-sim world text and every level-model file (model.sdf, model.config, OBJ/MTL,
/// model.material, texture files). Textures are placeholders here, so texture reading and
/// copying are excluded, as the target ("under 20 ms plus texture copying") states.
#[divan::bench(args = shared_names())]
fn gazebo_world(bencher: Bencher, name: &str) {
    use mapc_backends::sdf::{world::world_files, world::WorldOptions, Flavour};
    let parsed = mapc_frontend::parse_str(name, text(name));
    let Some(b) = parsed.valid_building() else {
        return;
    };
    let textures = mapc_backends::Textures::default();
    let opts = WorldOptions::default();
    bencher.bench(|| {
        let meshes: Vec<_> = b
            .levels
            .iter()
            .map(|(h, _)| (h, mapc_backends::level_meshes(black_box(b), h)))
            .collect();
        world_files(b, Flavour::Gz, &opts, &meshes, &textures)
    });
}
