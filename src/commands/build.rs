//! `mapc build`: many maps, several targets, one parse per map. Maps are built in parallel
//! (`std::thread::scope`, `--jobs` workers pulling from a shared counter); the main thread
//! prints each map's diagnostics in input order as soon as it and every earlier map are done,
//! and keeps a progress line on stderr when stderr is a terminal. `--depfile` writes a
//! Make/Ninja dependency file (outputs: the map, the files it includes, the textures found)
//! so build systems rerun mapc only when an input changed.
//!
//! The per-target file producers (`gltf_files`, `mesh_files`, and `mapc_backends::nav_graphs`)
//! are shared with the single-target commands of `main.rs`.

use crate::driver::{
    self, emit, load_and_check, map_name, not_written, output, summary_line, texture, Checked,
    CliError, DiagOpts, Outcome, Ready,
};
use crate::ui::{self, progress::Progress, Format};
use mapc_backends::sdf::world::WorldOptions;
use mapc_backends::sdf::Flavour;
use mapc_backends::OutputFile;
use mapc_ir::lints::Outputs;
use mapc_ir::Diagnostic;
use std::collections::BTreeMap;
use std::num::NonZeroUsize;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;

/// What `mapc build` can write for a map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, clap::ValueEnum)]
pub(crate) enum Target {
    /// Navigation graphs: `<map>/nav_graphs/<graph_idx>.yaml`.
    Nav,
    /// The whole building as one binary glTF: `<map>/<building>.glb`.
    Gltf,
    /// Level model meshes: `<map>/models/<building>_<level>/meshes/...`.
    Meshes,
    /// Gazebo classic world `<map>/<map>_classic.world` and level models in `<map>/models/`.
    Classic,
    /// Ignition (Fortress) world `<map>/<map>_ignition.world` and level models in
    /// `<map>/models/`.
    Ignition,
    /// gz-sim (Harmonic onwards) world `<map>/<map>.world` and level models in
    /// `<map>/models/` (the rmf_demos_maps layout). Also accepted as `gazebo`, like the
    /// subcommand.
    #[value(alias = "gazebo")]
    Gz,
}

impl Target {
    const ALL: [Target; 6] = [
        Target::Nav,
        Target::Gltf,
        Target::Meshes,
        Target::Classic,
        Target::Ignition,
        Target::Gz,
    ];

    /// The outputs the target consists of: a world includes its level models' meshes.
    fn outputs(self) -> Outputs {
        match self {
            Target::Nav => Outputs::NAV,
            Target::Gltf => Outputs::GLTF,
            Target::Meshes => Outputs::MESHES,
            Target::Classic | Target::Ignition | Target::Gz => {
                Outputs::WORLDS.union(Outputs::MESHES)
            }
        }
    }

    /// The manifest group of a file this map writes (path relative to the map's directory):
    /// a target, `models` (shared by meshes and every world) or `crowd` (every world).
    fn group_of(map: &str, rel: &Path) -> String {
        let first = rel
            .components()
            .next()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .unwrap_or_default();
        let name = rel.to_string_lossy();
        match first.as_str() {
            "nav_graphs" => "nav".into(),
            "models" => "models".into(),
            "config_resource" => "crowd".into(),
            _ if name == format!("{map}_classic.world") => "classic".into(),
            _ if name == format!("{map}_ignition.world") => "ignition".into(),
            _ if name == format!("{map}.world") => "gz".into(),
            _ => "gltf".into(),
        }
    }

    /// The manifest groups a run of `targets` owns.
    fn owned_groups(targets: &[Target]) -> std::collections::BTreeSet<String> {
        let mut g = std::collections::BTreeSet::new();
        for t in targets {
            g.insert(
                match t {
                    Target::Nav => "nav",
                    Target::Gltf => "gltf",
                    Target::Meshes => "models",
                    Target::Classic => "classic",
                    Target::Ignition => "ignition",
                    Target::Gz => "gz",
                }
                .to_string(),
            );
            if t.flavour().is_some() {
                g.insert("models".into());
                g.insert("crowd".into());
            }
        }
        g
    }

    fn flavour(self) -> Option<(Flavour, &'static str)> {
        match self {
            Target::Classic => Some((Flavour::Classic, "_classic")),
            Target::Ignition => Some((Flavour::Ignition, "_ignition")),
            Target::Gz => Some((Flavour::Gz, "")),
            _ => None,
        }
    }
}

#[derive(clap::Args, Clone)]
pub(crate) struct BuildArgs {
    /// The .building.yaml (or legacy .project.yaml) files to read.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Output directory: each map's files go to OUTDIR/<map>/ (<map> is the file name less
    /// `.building.yaml`).
    #[arg(short = 'o', long = "output", value_name = "OUTDIR")]
    out_dir: PathBuf,
    /// Comma-separated targets to write (default: all): nav, gltf, meshes, classic,
    /// ignition, gz (or gazebo).
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = Target::ALL)]
    targets: Vec<Target>,
    /// A directory to search for `<texture>.png` (repeatable; searched in order, before
    /// MAPC_TEXTURE_PATH and the map's directory).
    #[arg(long = "texture-path", value_name = "DIR")]
    texture_path: Vec<PathBuf>,
    /// Write a Make/Ninja depfile: `OUTPUTS...: MAP TEXTURES...` (only when every map
    /// succeeds).
    #[arg(long, value_name = "FILE")]
    depfile: Option<PathBuf>,
    /// Touch FILE when every map succeeds, and name it as the depfile's only target (what
    /// Ninja and CMake expect when the outputs are not known before the build).
    #[arg(long, value_name = "FILE")]
    stamp: Option<PathBuf>,
    /// As `mapc gazebo`'s: use this SDF as the skeleton of every world target instead of
    /// mapc's default for the simulator (templates are simulator-specific, so select one
    /// world target with --targets).
    #[arg(long = "TEMPLATE_WORLD_FILE", value_name = "PATH")]
    template_world_file: Option<PathBuf>,
    /// As `mapc gazebo`'s: keep the template's camera pose instead of placing the camera
    /// over the first floor.
    #[arg(long = "SKIP_CAMERA_POSE")]
    skip_camera_pose: bool,
    /// Maps built at once (default: the available parallelism).
    #[arg(short = 'j', long, value_name = "N")]
    jobs: Option<NonZeroUsize>,
    #[command(flatten)]
    diag: DiagOpts,
}

/// One map's outcome.
struct MapResult {
    input: PathBuf,
    /// `None` when the map could not be read at all (`error` says why).
    checked: Option<Checked>,
    /// An I/O problem (exit 2).
    error: Option<String>,
    /// 0 ok, 1 invalid map, 2 I/O error.
    code: u8,
    /// Files this map's outputs consist of (written or already up to date).
    outputs: Vec<PathBuf>,
    /// What the write did (for the success line).
    written: output::Written,
    /// The success line's description: "1 graph, 2 level meshes".
    what: String,
    /// Files read: the map, the files it names, the textures found (and the texture search
    /// directories when a texture was not found).
    deps: Vec<PathBuf>,
    /// The outputs asked for, and those errors broke (not written).
    wanted: Outputs,
    blocked: Outputs,
}

/// Every file of the selected targets, paths relative to the map's directory, plus texture
/// warnings and the texture files read.
fn target_files(
    r: Ready,
    map: &str,
    targets: &[Target],
    texture_path: &[PathBuf],
    input: &Path,
    opts: &WorldOptions,
) -> (Vec<OutputFile>, Vec<Diagnostic>, Vec<PathBuf>) {
    let has = |t| targets.contains(&t);
    let mut files = Vec::new();
    if has(Target::Nav) {
        for f in driver::nav_files(r) {
            files.push(OutputFile {
                path: Path::new("nav_graphs").join(f.path),
                contents: f.contents,
            });
        }
    }
    let mut diags = Vec::new();
    let mut found = Vec::new();
    let mut missing = false;
    let worlds: Vec<(Flavour, &str)> = targets.iter().filter_map(|t| t.flavour()).collect();
    let models = has(Target::Meshes) || !worlds.is_empty();
    if has(Target::Gltf) || models {
        let meshes = driver::all_level_meshes(r);
        let mut names = std::collections::BTreeSet::new();
        if has(Target::Gltf) {
            names.extend(driver::gltf_texture_names(&meshes));
        }
        if models {
            names.extend(driver::mesh_texture_names(&meshes));
        }
        let search = texture::SearchPath::from_env(texture_path, input);
        let (textures, d) = mapc_backends::resolve_textures(
            r.building(),
            names.iter().map(String::as_str),
            &mut |f| {
                let Some((path, bytes)) = search.locate(f) else {
                    missing = true;
                    return None;
                };
                found.push(path);
                Some(bytes)
            },
        );
        diags = d;
        // A texture not found yet: the search directories change when it is added.
        if missing {
            found.extend(search.dirs.iter().filter(|d| d.is_dir()).cloned());
        }
        if has(Target::Gltf) {
            files.extend(driver::gltf_files(r, &meshes, &textures, false));
        }
        // Worlds through the function `mapc gazebo` uses, so the bytes are the same. Their
        // level models (model.sdf, model.config, meshes, textures) are the same for every
        // flavour and include the meshes target's files.
        let mut model_files = None;
        let mut crowd_files = None;
        for (flavour, suffix) in worlds {
            let b = r.require(Outputs::WORLDS.union(Outputs::MESHES));
            let w = mapc_backends::sdf::world::world_files(b, flavour, opts, &meshes, &textures);
            files.push(OutputFile {
                path: PathBuf::from(format!("{map}{suffix}.world")),
                contents: w.world.into_bytes(),
            });
            model_files.get_or_insert(w.models);
            // The Menge files are the same for every flavour: once, next to the worlds.
            crowd_files.get_or_insert(w.crowd);
        }
        files.extend(crowd_files.unwrap_or_default());
        let model_files = match model_files {
            Some(m) => m,
            None if has(Target::Meshes) => driver::mesh_files(r, &meshes, &textures),
            None => Vec::new(),
        };
        for f in model_files {
            files.push(OutputFile {
                path: Path::new("models").join(f.path),
                contents: f.contents,
            });
        }
    }
    (files, diags, found)
}

/// The outputs `targets` consist of.
fn outputs_of(targets: &[Target]) -> Outputs {
    targets
        .iter()
        .fold(Outputs::NONE, |o, t| o.union(t.outputs()))
}

fn build_one(input: &Path, args: &BuildArgs, opts: &WorldOptions) -> MapResult {
    let wanted = outputs_of(&args.targets);
    let mut result = MapResult {
        input: input.to_path_buf(),
        checked: None,
        error: None,
        code: 0,
        outputs: Vec::new(),
        written: output::Written::default(),
        what: String::new(),
        deps: vec![input.to_path_buf()],
        wanted,
        blocked: Outputs::NONE,
    };
    let mut checked = match load_and_check(input, &args.diag.lints) {
        Ok(c) => c,
        Err(e) => {
            result.error = Some(e);
            result.code = 2;
            return result;
        }
    };
    for s in checked.parsed.sources.iter().skip(1) {
        result.deps.push(PathBuf::from(&s.name));
    }
    // Only the targets no error breaks; texture warnings denied to errors can break more,
    // and then the files are made again for what is left.
    let unblocked = |c: &Checked| -> Vec<Target> {
        let t = args.targets.iter();
        t.filter(|t| c.blocked(t.outputs()).is_empty())
            .copied()
            .collect()
    };
    let map = map_name(input);
    let mut targets = unblocked(&checked);
    let mut files = Vec::new();
    for round in 0..2 {
        let Some(r) = checked.ready(outputs_of(&targets)) else {
            break;
        };
        if targets.is_empty() {
            break;
        }
        let (f, diags, found) = target_files(r, &map, &targets, &args.texture_path, input, opts);
        files = f;
        result.deps.truncate(checked.parsed.sources.len());
        result.deps.extend(found);
        if round > 0 {
            // The second round's texture diagnostics repeat some of the first's.
            break;
        }
        checked.extend(diags);
        let left = unblocked(&checked);
        if left == targets {
            break;
        }
        targets = left;
        files.clear();
    }
    result.blocked = checked.blocked(wanted);
    if !result.blocked.is_empty() {
        result.code = 1;
    }
    // What the written targets hold, for the success line; zero of a kind asked for while
    // keys were ignored is probably a typo.
    let mut empty = Vec::new();
    if let (Some(r), false) = (checked.ready(outputs_of(&targets)), targets.is_empty()) {
        let mut what = Vec::new();
        if targets.contains(&Target::Nav) {
            let graphs = files
                .iter()
                .filter(|f| f.path.starts_with("nav_graphs"))
                .count();
            what.push(ui::plural(graphs, "graph"));
            if graphs == 0 {
                empty.push("no nav graph (the map has no lanes)");
            }
        }
        if targets.iter().any(|t| *t != Target::Nav) {
            let meshes = driver::mesh_count(&driver::all_level_meshes(r));
            what.push(ui::plural(meshes, "level mesh"));
            if meshes == 0 {
                empty.push("no level mesh (the map has no floors or walls)");
            }
        }
        result.what = what.join(", ");
    }
    let ignored = checked.ignored_codes();
    if !empty.is_empty() && !ignored.is_empty() {
        // Zero outputs of a kind asked for, while keys were ignored: probably a typo.
        result.error = Some(format!(
            "{}: {}, but keys were ignored (see the warnings above); nothing written; {}",
            map,
            empty.join(" and "),
            driver::ways_out(input, &args.diag.lints, &ignored)
        ));
        result.code = 1;
    } else if !files.is_empty() || result.blocked.is_empty() {
        let dir = args.out_dir.join(&map);
        let group = |p: &Path| Target::group_of(&map, p);
        // Only the targets written own their groups: a blocked target's earlier files stay.
        let manifest = output::Manifest {
            name: ".mapc-manifest".into(),
            group: &group,
            owned: Target::owned_groups(&targets),
        };
        match output::write_dir(&dir, "OUTDIR/<map>", &files, &manifest) {
            Ok(w) => {
                result.written = w;
                result.outputs = files.iter().map(|f| dir.join(&f.path)).collect();
            }
            Err(e) => {
                result.error = Some(e);
                result.code = 2;
            }
        }
    }
    result.checked = Some(checked);
    result
}

/// One map's report. On a terminal-style report without `--verbose`, warnings are counted
/// by code instead of shown one by one (a demo map has over a hundred).
fn report(r: &MapResult, args: &BuildArgs) {
    let opts = &args.diag;
    let (format, verbose) = (opts.format, opts.verbose);
    if let Some(c) = &r.checked {
        if format == Format::Human && !verbose {
            let errors: Vec<mapc_ir::Diagnostic> = c
                .diagnostics
                .iter()
                .filter(|d| d.is_error())
                .cloned()
                .collect();
            let (shown, cut) = ui::limit::select(&errors, opts.max_diagnostics);
            ui::report::emit(&c.parsed.sources, &shown, &cut, ui::report::Style::Snippets);
            let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
            for d in c.diagnostics.iter().filter(|d| !d.is_error()) {
                *counts.entry(d.code).or_default() += 1;
            }
            if !counts.is_empty() {
                let list: Vec<String> = counts
                    .iter()
                    .map(|(code, n)| format!("{code} {} ×{n}", crate::codes::code_name(code)))
                    .collect();
                eprintln!(
                    "{}: warnings: {} (--verbose shows each)",
                    r.input.display(),
                    list.join(", ")
                );
            }
        } else if format != Format::Sarif {
            emit(c, opts, ui::report::Style::Snippets);
        }
        if format == Format::Human {
            summary_line(&r.input, c);
        }
    }
    match (&r.error, &r.checked) {
        (Some(e), _) => crate::ui::error(e),
        (None, Some(c)) if !r.blocked.is_empty() => {
            // Partially blocked: what was written still gets its line.
            if r.blocked != r.wanted && !args.diag.quiet {
                success_of(r, args);
            }
            not_written(&r.input, c, r.blocked, r.wanted)
        }
        (None, None) => {}
        _ if !args.diag.quiet => success_of(r, args),
        _ => {}
    }
}

/// The success line of a map: what was written where.
fn success_of(r: &MapResult, args: &BuildArgs) {
    driver::success_line(
        &map_name(&r.input),
        &r.what,
        &args.out_dir.join(map_name(&r.input)),
        r.written,
        r.checked.as_ref().map_or(0, |c| c.diagnostics.len()),
    );
}

/// Make/Ninja depfile text: `targets: deps`, one dependency per continuation line. No
/// `gcc -MP` style empty rules: CMake's Makefile generator adds its own, and keeps rules it
/// once read, so that a texture deleted later would rerun mapc on every build.
///
/// Neither Make nor Ninja can read a path with a control character (a newline ends the
/// rule, a tab separates words): such a path is an error, and no depfile is written.
pub(crate) fn depfile_text(targets: &[PathBuf], deps: &[PathBuf]) -> Result<String, String> {
    if let Some(bad) = targets
        .iter()
        .chain(deps)
        .find(|p| p.to_string_lossy().chars().any(char::is_control))
    {
        return Err(format!(
            "cannot write a depfile naming `{}`: Make and Ninja cannot read a path with a \
             control character",
            ui::escape::display_safe(&bad.to_string_lossy())
        ));
    }
    let mut s = String::new();
    let names: Vec<String> = targets.iter().map(|t| escape(t)).collect();
    s.push_str(&names.join(" \\\n  "));
    s.push(':');
    for d in deps {
        s.push_str(" \\\n  ");
        s.push_str(&escape(d));
    }
    s.push('\n');
    Ok(s)
}

/// A path as Make and Ninja read it in a depfile: spaces and `#` backslash-escaped, `$`
/// doubled.
fn escape(p: &Path) -> String {
    let mut out = String::new();
    for c in p.to_string_lossy().chars() {
        match c {
            ' ' => out.push_str("\\ "),
            '#' => out.push_str("\\#"),
            '$' => out.push_str("$$"),
            _ => out.push(c),
        }
    }
    out
}

pub(crate) fn run(args: &BuildArgs) -> Result<Outcome, CliError> {
    let mut targets = args.targets.clone();
    targets.sort();
    targets.dedup();
    let args = &BuildArgs {
        targets,
        ..args.clone()
    };
    driver::sanity::output_dir(&args.out_dir, "OUTDIR")?;
    // Two inputs with the same name would write the same directory.
    let mut seen: BTreeMap<String, &Path> = BTreeMap::new();
    for input in &args.inputs {
        if let Some(other) = seen.insert(map_name(input), input) {
            return Err(CliError::Usage(format!(
                "`{}` and `{}` would both write {}/{}",
                other.display(),
                input.display(),
                args.out_dir.display(),
                map_name(input)
            )));
        }
    }
    // The template is read once for every map, as `mapc gazebo` reads it.
    let template = match &args.template_world_file {
        None => None,
        Some(p) => Some(driver::read_template(p, args.skip_camera_pose)?),
    };
    let opts = &WorldOptions {
        template,
        skip_camera_pose: args.skip_camera_pose,
    };
    let n = args.inputs.len();
    let jobs = args
        .jobs
        .or_else(|| std::thread::available_parallelism().ok())
        .map_or(1, NonZeroUsize::get)
        .min(n);
    let progress = Progress::new(
        n as u64,
        "maps",
        args.diag.format == Format::Human && !args.diag.quiet,
    );
    let next = AtomicUsize::new(0);
    let mut results: Vec<Option<MapResult>> = (0..n).map(|_| None).collect();
    std::thread::scope(|s| {
        let (tx, rx) = mpsc::channel();
        for _ in 0..jobs {
            let tx = tx.clone();
            let next = &next;
            s.spawn(move || loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= n {
                    break;
                }
                let r = build_one(&args.inputs[i], args, opts);
                if tx.send((i, r)).is_err() {
                    break;
                }
            });
        }
        drop(tx);
        let mut printed = 0;
        for (done, (i, r)) in rx.into_iter().enumerate() {
            let last = format!("built {}", r.input.display());
            results[i] = Some(r);
            progress.suspend(|| {
                while let Some(Some(r)) = results.get(printed) {
                    report(r, args);
                    printed += 1;
                }
            });
            progress.set(done as u64 + 1, last);
        }
    });
    drop(progress);
    let results: Vec<MapResult> = results.into_iter().flatten().collect();
    if args.diag.format == Format::Sarif {
        driver::print_sarif(
            results.iter().filter_map(|r| r.checked.as_ref()),
            args.diag.max_diagnostics,
        );
    }
    // Each map's error was said with its report.
    match results.iter().map(|r| r.code).max().unwrap_or(0) {
        0 => {
            finish(args, &results)?;
            Ok(Outcome::Done)
        }
        1 => Err(CliError::InvalidReported),
        _ => Err(CliError::UsageReported),
    }
}

/// The depfile and then the stamp, once every map succeeded.
fn finish(args: &BuildArgs, results: &[MapResult]) -> Result<(), String> {
    let outputs: Vec<PathBuf> = results.iter().flat_map(|r| r.outputs.clone()).collect();
    if let Some(depfile) = &args.depfile {
        let mut deps: Vec<PathBuf> = Vec::new();
        for d in results.iter().flat_map(|r| &r.deps) {
            if !deps.contains(d) {
                deps.push(d.clone());
            }
        }
        let targets = match &args.stamp {
            Some(stamp) => vec![stamp.clone()],
            None => outputs.clone(),
        };
        let text = depfile_text(&targets, &deps)?;
        // Always rewritten, as compilers do: CMake's Makefile generator reads a depfile
        // again only when it is newer than what it consolidated last time.
        output::write_atomic(depfile, text.as_bytes())
            .map_err(|e| format!("{}: {e}", depfile.display()))?;
    }
    if let Some(stamp) = &args.stamp {
        // Always rewritten, last: its modification time is what build systems compare. In
        // place rather than renamed, so its directory's time does not move past it.
        let list: String = outputs
            .iter()
            .map(|p| format!("{}\n", p.display()))
            .collect();
        if let Some(dir) = stamp.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        std::fs::write(stamp, list).map_err(|e| format!("{}: {e}", stamp.display()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depfile_refuses_control_characters() {
        let e = depfile_text(
            &[PathBuf::from("out/x.stamp")],
            &[PathBuf::from("m\nx.yaml")],
        );
        assert!(e.unwrap_err().contains("`m\\nx.yaml`"));
        assert!(depfile_text(&[PathBuf::from("a\tb")], &[]).is_err());
    }

    #[test]
    fn depfile_escapes() {
        let t = depfile_text(
            &[PathBuf::from("out/a b.stamp")],
            &[
                PathBuf::from("m#1.building.yaml"),
                PathBuf::from("t/$x.png"),
            ],
        )
        .unwrap();
        assert_eq!(
            t,
            "out/a\\ b.stamp: \\\n  m\\#1.building.yaml \\\n  t/$$x.png\n"
        );
    }
}
