//! `mapc`: the command line. Exit codes: 0 ok (warnings allowed), 1 invalid map (or scenario),
//! 2 usage or I/O error.

mod build;
mod convert;
mod crowdsim_cmd;
mod diff;
mod escape;
mod info;
mod limit;
mod lints;
mod lsp;
mod models_cmd;
mod output;
mod render_cmd;
mod replay;
mod report;
mod report_json;
mod ros2_cmd;
mod sanity;
mod signals;
mod sim_cmd;
mod snippet;
mod sweep;
mod texture;
mod world_cmd;

use clap::{Parser, Subcommand, ValueEnum};
use mapc_ir::lints::{policy, Outputs};
use mapc_ir::Diagnostic;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "mapc",
    version,
    about = "Compiles RMF .building.yaml maps into navigation graphs, simulation worlds and glTF scenes",
    long_about = "mapc reads traffic_editor .building.yaml maps, checks them, and writes the \
                  files RMF needs. `mapc nav` and `mapc gazebo` are drop-ins for \
                  `building_map_generator nav` and `gazebo`.\n\n\
                  Exit codes: 0 ok (warnings allowed), 1 invalid map or scenario, 2 usage or I/O error."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
enum Format {
    /// Source snippets with underlines (colour on a terminal).
    Human,
    /// JSON Lines on stdout: one object per diagnostic (schema in docs/diagnostics.md).
    Json,
    /// A SARIF 2.1.0 log on stdout, for code-scanning tools.
    Sarif,
}

#[derive(clap::Args, Debug)]
struct DiagOpts {
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value = "human")]
    format: Format,
    /// Do not print the success line (what was written) on stderr.
    #[arg(short, long)]
    quiet: bool,
    /// Show at most N diagnostics per code, then one line with the number found (`all`:
    /// show every one).
    #[arg(long, value_name = "N|all", default_value = "20")]
    max_diagnostics: limit::MaxDiagnostics,
    /// Show source snippets in `nav`, `gazebo`, `ignition` and `classic` too (they print
    /// one `file:line:col` line per diagnostic otherwise); in `build`, every warning with
    /// its snippet (by default: errors in full, warnings counted by code per map).
    #[arg(short = 'v', long)]
    verbose: bool,
    #[command(flatten)]
    lints: LintOpts,
}

/// Lint levels, on every command that reads a map.
#[derive(clap::Args, Clone, Debug)]
pub(crate) struct LintOpts {
    /// Treat warnings as errors (the same as `--deny warnings`).
    #[arg(long)]
    deny_warnings: bool,
    /// Do not report CODE (a code such as W0204 or a name such as lane-crosses-wall);
    /// repeatable. Errors after which no correct output can be written cannot be allowed.
    #[arg(long, value_name = "CODE")]
    allow: Vec<String>,
    /// Report CODE as a warning (repeatable); an error lowered so no longer blocks output.
    #[arg(long, value_name = "CODE")]
    warn: Vec<String>,
    /// Report CODE as an error (repeatable); `--deny warnings` makes every warning an error.
    #[arg(long, value_name = "CODE")]
    deny: Vec<String>,
    /// Lint levels from FILE (a `[lints]` table) instead of the mapc.toml found beside the
    /// map or in a parent directory. The command line wins over the file.
    #[arg(long, value_name = "FILE")]
    config: Option<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Write the navigation graph of each fleet: OUTPUT_DIR/<graph_idx>.yaml
    /// (same arguments as `building_map_generator nav`).
    Nav {
        /// The .building.yaml (or legacy .project.yaml) to read.
        input: PathBuf,
        /// Directory for the graph files; created if missing.
        output_dir: PathBuf,
        #[command(flatten)]
        diag: DiagOpts,
    },
    /// Write the whole building as one binary glTF scene, OUTPUT_DIR/<building>.glb: a node
    /// per level at its elevation with floors, ceilings, walls, door panels and lift cabins,
    /// textures embedded.
    Gltf {
        /// The .building.yaml (or legacy .project.yaml) to read.
        input: PathBuf,
        /// Directory for the .glb files; created if missing.
        output_dir: PathBuf,
        /// A directory to search for `<texture>.png` (repeatable; searched in order, before
        /// MAPC_TEXTURE_PATH and the map's directory).
        #[arg(long = "texture-path", value_name = "DIR")]
        texture_path: Vec<PathBuf>,
        /// Also write each level's meshes as OUTPUT_DIR/<building>_<level>.glb (the gz-sim
        /// level model meshes, without doors and lifts).
        #[arg(long)]
        per_level: bool,
        #[command(flatten)]
        diag: DiagOpts,
    },
    /// Write each level's meshes as Gazebo level models use them (the reference layout):
    /// OUTPUT_MODEL_DIR/<building>_<level>/meshes/ with floor_<n>, ceiling_<n> and wall_<k>
    /// OBJ + MTL files, the OGRE model.material script and the textures they name.
    Meshes {
        /// The .building.yaml (or legacy .project.yaml) to read.
        input: PathBuf,
        /// Model directory; created if missing.
        output_model_dir: PathBuf,
        /// A directory to search for `<texture>.png` (repeatable; searched in order, before
        /// MAPC_TEXTURE_PATH and the map's directory).
        #[arg(long = "texture-path", value_name = "DIR")]
        texture_path: Vec<PathBuf>,
        #[command(flatten)]
        diag: DiagOpts,
    },
    /// Build many maps to several targets at once (nav, gltf, meshes, classic, ignition,
    /// gz): OUTDIR/<map>/nav_graphs/<graph_idx>.yaml, OUTDIR/<map>/<building>.glb,
    /// OUTDIR/<map>/models/<building>_<level>/, OUTDIR/<map>/<map>{_classic,_ignition,}.world.
    /// Maps are built in parallel; unchanged files are not rewritten, stale ones removed;
    /// `--depfile` tells Make or Ninja what was read.
    Build(build::BuildArgs),
    /// Write a gz-sim (Harmonic onwards) world and its level models, like today's
    /// `building_map_generator gazebo`: OUTPUT_WORLD and
    /// OUTPUT_MODEL_DIR/<building>_<level>/{model.sdf,model.config,meshes/}.
    #[command(visible_alias = "gz")]
    Gazebo(world_cmd::WorldArgs),
    /// Write an Ignition Gazebo (Fortress era) world and its level models, like
    /// `building_map_generator ignition` before 2024-05.
    Ignition(world_cmd::WorldArgs),
    /// Write a Gazebo classic world and its level models, like `building_map_generator
    /// gazebo` before 2024-05.
    Classic(world_cmd::WorldArgs),
    /// Write the crowd simulator's Menge files into CONFIG_DIR and make WORLD hold the
    /// crowd_simulation plugin (a drop-in for `building_crowdsim MAP CONFIG_DIR WORLD`).
    Crowdsim(crowdsim_cmd::CrowdsimArgs),
    /// List the models a map needs (Fuel names, the crowd's actors) where
    /// `building_map_model_downloader` would download them; mapc downloads nothing and names
    /// those missing from the export directory (`-e DIR`).
    Models(models_cmd::ModelsArgs),
    /// Run a scenario (robots, tasks, doors, lifts) on a map with the headless RMF runtime and
    /// report what happened: task times, throughput, door and lift waits, near misses.
    /// Scenario format, trace and report: docs/sim.md.
    Sim(sim_cmd::SimArgs),
    /// Run a capacity study: a base scenario varied along axes (fleet sizes, task rates,
    /// seeds...), every run on all cores, a Slurm cluster or Kubernetes; writes
    /// OUT/results.csv, OUT/results.json and OUT/capacity.svg. Format: docs/sweep.md.
    Sweep(sweep::SweepArgs),
    /// List what a map holds for scenario authors: levels, graphs, named waypoints by role,
    /// doors, lifts, dispensers and ingestors.
    Info(info::InfoArgs),
    /// Draw each level as a picture: OUTPUT/<building>_<level>.svg (or .png) with floors,
    /// walls, doors, lifts, the lanes of each graph, waypoints and their roles, models, a
    /// legend and a scale bar; `--diagnostics` draws the problems at their places.
    Render(render_cmd::RenderArgs),
    /// Convert a map between traffic_editor's .building.yaml and rmf_site's .site.json
    /// (formats from the file names); what the target cannot say is a warning (docs/sites.md).
    Convert(convert::ConvertArgs),
    /// Serve maps to editors: a language server on stdin/stdout (diagnostics as you type,
    /// hover, go to definition, references, symbols, fixes). Set-up: docs/editors.md.
    Lsp(lsp::LspArgs),
    /// What changed by meaning between two versions of a map: levels, waypoints, lanes,
    /// doors, lifts, walls, floors, connectivity, diagnostics. Exit 0 when nothing
    /// changed, 1 when something did, 2 on errors (like diff).
    Diff(diff::DiffArgs),
    /// Check maps and report every problem found, without writing anything.
    Check {
        /// The .building.yaml (or legacy .project.yaml) files to read.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        #[command(flatten)]
        diag: DiagOpts,
    },
}

/// `Cli::parse()`, with a shortcut for the drop-in world commands, which build loops run
/// once per map: their own arguments are parsed without building every other subcommand's
/// (about 0.4 ms of a 10 ms compile; BENCHMARKS.md). Anything but a successful parse (help,
/// `--version`, a mistake) goes through the whole parser, so every message is its own.
fn parse_cli() -> Cli {
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    parse_world_args(&args).unwrap_or_else(Cli::parse)
}

/// The shortcut of [`parse_cli`]: `Some` only for a world command that parses.
fn parse_world_args(args: &[std::ffi::OsString]) -> Option<Cli> {
    use clap::{Args, FromArgMatches};
    let (name, command): (&'static str, fn(world_cmd::WorldArgs) -> Command) =
        match args.get(1)?.to_str()? {
            "gazebo" | "gz" => ("gazebo", Command::Gazebo),
            "ignition" => ("ignition", Command::Ignition),
            "classic" => ("classic", Command::Classic),
            _ => return None,
        };
    let parser = world_cmd::WorldArgs::augment_args(clap::Command::new(name));
    let matches = parser.try_get_matches_from(&args[1..]).ok()?;
    let world = world_cmd::WorldArgs::from_arg_matches(&matches).ok()?;
    Some(Cli {
        command: command(world),
    })
}

fn main() -> ExitCode {
    let cli = parse_cli();
    // `mapc sim` stops cooperatively on the first signal (it writes what ran); every other
    // command removes its temporaries and exits.
    signals::install(usize::from(matches!(cli.command, Command::Sim(_))));
    match cli.command {
        Command::Nav {
            input,
            output_dir,
            diag,
        } => nav(&input, &output_dir, &diag),
        Command::Gltf {
            input,
            output_dir,
            texture_path,
            per_level,
            diag,
        } => gltf(&input, &output_dir, &texture_path, per_level, &diag),
        Command::Meshes {
            input,
            output_model_dir,
            texture_path,
            diag,
        } => meshes(&input, &output_model_dir, &texture_path, &diag),
        Command::Build(args) => build::build(args),
        Command::Gazebo(args) => world_cmd::run(mapc_backends::sdf::Flavour::Gz, &args),
        Command::Ignition(args) => world_cmd::run(mapc_backends::sdf::Flavour::Ignition, &args),
        Command::Classic(args) => world_cmd::run(mapc_backends::sdf::Flavour::Classic, &args),
        Command::Crowdsim(args) => crowdsim_cmd::run(&args),
        Command::Models(args) => models_cmd::run(&args),
        Command::Sim(args) => sim_cmd::run(&args),
        Command::Sweep(args) => sweep::run(&args),
        Command::Info(args) => info::run(&args),
        Command::Render(args) => render_cmd::run(&args),
        Command::Lsp(args) => lsp::run(&args),
        Command::Diff(args) => diff::run(&args),
        Command::Check { inputs, diag } => check(&inputs, &diag),
        Command::Convert(args) => convert::run(&args),
    }
}

/// Stable name of a diagnostic code, from the frontend's, the backends' or the scenario
/// table, or the rule registry.
pub(crate) fn code_name(code: &str) -> &'static str {
    mapc_frontend::CODES
        .iter()
        .chain(mapc_frontend::site::codes::CODES)
        .find(|c| c.code == code)
        .map(|c| c.name)
        .or_else(|| mapc_ir::rule(code).map(|r| r.name))
        .or_else(|| {
            mapc_backends::CODES
                .iter()
                .find(|c| c.code == code)
                .map(|c| c.name)
        })
        .or_else(|| {
            mapc_sim::codes::CODES
                .iter()
                .chain(sweep::CODES)
                .find(|c| c.code == code)
                .map(|c| c.name)
        })
        .unwrap_or("")
}

/// A map read and checked: frontend diagnostics plus validation passes, at the user's
/// lint levels.
struct Checked {
    parsed: mapc_frontend::Parsed,
    diagnostics: Vec<Diagnostic>,
    lints: lints::Lints,
}

impl Checked {
    /// The outputs of `wanted` that the remaining errors break (all of them when the map
    /// could not be read).
    fn blocked(&self, wanted: Outputs) -> Outputs {
        let Some(b) = &self.parsed.building else {
            return wanted;
        };
        let mut blocked = Outputs::NONE;
        for d in self.diagnostics.iter().filter(|d| d.is_error()) {
            let p = policy(d.code);
            let mut blocks = if p.can_allow { p.blocks } else { Outputs::ALL };
            if p.nav_only_with_lanes && b.lanes.is_empty() {
                blocks = blocks.without(Outputs::NAV);
            }
            blocked = blocked.union(blocks);
        }
        blocked.intersection(wanted)
    }

    /// Adds diagnostics found while producing output (texture warnings), at the user's
    /// levels.
    fn extend(&mut self, mut diags: Vec<Diagnostic>) {
        self.lints.apply(&mut diags);
        self.diagnostics.extend(diags);
    }
}

/// The lint levels for `input`: the command line's over those of `--config` or of the
/// mapc.toml found for the map. `Err` is a usage error (exit 2).
pub(crate) fn lints_for(input: &Path, opts: &LintOpts) -> Result<lints::Lints, String> {
    let cli = lints::from_flags(&opts.allow, &opts.warn, &opts.deny, opts.deny_warnings)?;
    let file = match &opts.config {
        Some(path) => Some(lints::from_file(path)?),
        None => match lints::discover(input) {
            Some(path) => Some(lints::from_file(&path)?),
            None => None,
        },
    };
    Ok(lints::Lints::new(cli, file))
}

/// Validation rules that compare positions with thresholds in metres (a door's width, how
/// close two waypoints are, a lift cabin's extent): meaningless when the frontend could not
/// tell the map's units.
const METRIC_RULES: &[&str] = &[
    "W0202", "W0204", "W0205", "W0206", "W0207", "W0305", "W0402", "W0404", "E0407",
];

/// Frontend errors after which positions are in unknown units: an unknown coordinate
/// system, an unknown reference level, a wgs84 map without a CRS, a zero-length measurement.
const UNITS_UNKNOWN: &[&str] = &["E0106", "E0107", "E0108", "E0109"];

/// The frontend's diagnostics plus those of every validation pass (before lint levels).
pub(crate) fn all_diagnostics(parsed: &mapc_frontend::Parsed) -> Vec<Diagnostic> {
    let mut diagnostics = parsed.diagnostics.clone();
    // Passes run even after frontend errors so one run reports everything it can, except
    // those whose inputs the errors left unknown: they would only report consequences
    // (a 224 m wide door in a map whose pixels were taken for metres).
    let units_unknown = diagnostics.iter().any(|d| UNITS_UNKNOWN.contains(&d.code));
    if let Some(b) = &parsed.building {
        diagnostics.extend(
            mapc_ir::validate(b)
                .into_iter()
                .filter(|d| !(units_unknown && METRIC_RULES.contains(&d.code))),
        );
    }
    diagnostics
}

/// Reads a map and runs every validation pass, at the user's lint levels. `Err` is an I/O
/// or usage problem (exit 2).
fn load_and_check(input: &Path, opts: &LintOpts) -> Result<Checked, String> {
    sanity::map_input(input)?;
    let lints = lints_for(input, opts)?;
    let mut parsed = mapc_frontend::load(input).map_err(|e| {
        // The frontend names the file as given; print it without `./` noise.
        e.to_string()
            .replace(&input.display().to_string(), &output::shown(input))
    })?;
    for s in &mut parsed.sources {
        s.name = output::shown(Path::new(&s.name));
    }
    let mut diagnostics = all_diagnostics(&parsed);
    lints.apply(&mut diagnostics);
    Ok(Checked {
        parsed,
        diagnostics,
        lints,
    })
}

/// For commands that only read a map (`info`, `models`): loads and checks it, prints its
/// errors (warnings are `mapc check`'s business), and gives the checked map when a
/// building could be read. `Err` is the exit code: 2 for I/O or usage, 1 for an unreadable
/// map.
fn load_readable(input: &Path, opts: &LintOpts) -> Result<Checked, ExitCode> {
    let checked = load_and_check(input, opts).map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })?;
    let errors: Vec<&mapc_ir::Diagnostic> = checked
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .collect();
    report::emit(
        &checked.parsed.sources,
        &errors,
        &[],
        report::Style::Snippets,
    );
    if !errors.is_empty() {
        summary_line(input, &checked);
    }
    if checked.parsed.building.is_none() {
        eprintln!("error: {}: the map could not be read", output::shown(input));
        return Err(ExitCode::from(1));
    }
    Ok(checked)
}

/// Prints the diagnostics of `c` in the chosen format, at most `--max-diagnostics` per
/// code (SARIF is printed by the caller, once for all maps). `style` is the command's
/// human style; `--verbose` always gives snippets.
fn emit(c: &Checked, opts: &DiagOpts, style: report::Style) {
    let (shown, cut) = limit::select(&c.diagnostics, opts.max_diagnostics);
    let style = if opts.verbose {
        report::Style::Snippets
    } else {
        style
    };
    match opts.format {
        Format::Human => report::emit(&c.parsed.sources, &shown, &cut, style),
        Format::Json => {
            let mut out = std::io::BufWriter::new(std::io::stdout().lock());
            // Nothing useful to do if stdout is gone (e.g. a closed pipe).
            let _ = report_json::write_json_lines(&mut out, &c.parsed.sources, &shown, &cut);
        }
        Format::Sarif => print!("{}", report_json::sarif(&c.parsed.sources, &shown, &cut)),
    }
}

/// `error: MAP: nothing written` (or which outputs were not), with the codes to blame.
fn not_written(input: &Path, c: &Checked, blocked: Outputs, wanted: Outputs) {
    // The codes that break what was not written (not every error of the map).
    let mut codes: Vec<&str> = c
        .diagnostics
        .iter()
        .filter(|d| {
            let p = policy(d.code);
            d.is_error() && (!p.can_allow || p.blocks.intersects(blocked))
        })
        .map(|d| d.code)
        .collect();
    codes.sort();
    codes.dedup();
    let what = if blocked == wanted {
        "nothing written".to_string()
    } else {
        format!("{} not written", blocked.names().join(", "))
    };
    let why = if codes.is_empty() {
        String::new()
    } else {
        format!(" ({})", codes.join(", "))
    };
    eprintln!("error: {}: {what}{why}", output::shown(input));
}

fn summary_line(input: &Path, c: &Checked) {
    let errors = c.diagnostics.iter().filter(|d| d.is_error()).count();
    let warnings = c.diagnostics.len() - errors;
    if errors + warnings > 0 {
        say(format!(
            "{}: {errors} error(s), {warnings} warning(s)",
            output::shown(input)
        ));
    }
}

/// One line on stderr in one write (`eprintln!` writes each piece of its format on its
/// own to unbuffered stderr: a log's reader wakes for each, and lines of processes sharing
/// a log can interleave).
pub(crate) fn say(mut line: String) {
    use std::io::Write;
    line.push('\n');
    // Nothing useful to do if stderr is gone (e.g. a closed pipe).
    let _ = std::io::stderr().write_all(line.as_bytes());
}

fn nav(input: &Path, output_dir: &Path, opts: &DiagOpts) -> ExitCode {
    let cmd = Cmd {
        name: "nav",
        role: "OUTPUT_DIR",
        kind: "nav graph",
        none: "the map has no lanes",
        outputs: Outputs::NAV,
    };
    // A drop-in for `building_map_generator nav`: one line per diagnostic in build logs.
    run_command(input, output_dir, opts, &cmd, report::Style::OneLine, |b| {
        let files = mapc_backends::nav_graphs(b);
        let n = files.len();
        (files, Vec::new(), n)
    })
}

/// A single-map command, for its messages.
struct Cmd {
    /// Subcommand name (also names the manifest).
    name: &'static str,
    /// The output argument, as `--help` names it.
    role: &'static str,
    /// What the command exists to write, singular ("nav graph").
    kind: &'static str,
    /// Why a map can truly have none of them.
    none: &'static str,
    /// The outputs the command writes (what errors must not break).
    outputs: Outputs,
}

/// `n thing` or `n things`.
pub(crate) fn plural(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else if thing.ends_with("sh") || thing.ends_with('s') {
        format!("{n} {thing}es")
    } else {
        format!("{n} {thing}s")
    }
}

/// The codes of what the frontend ignored that could have held the missing outputs: an
/// unknown key (W0103), a likely typo (E0112); empty when nothing was.
pub(crate) fn ignored_codes(c: &Checked) -> Vec<&'static str> {
    ["W0103", "E0112"]
        .into_iter()
        .filter(|code| c.diagnostics.iter().any(|d| d.code == *code))
        .collect()
}

/// How to go on when ignored keys (`codes`) are meant to be ignored (a fork's extension
/// keys): the flag, or the mapc.toml setting in the file that applies to `input` (the
/// `--config` file, else the one found beside the map or above it, else one beside it).
pub(crate) fn ways_out(input: &Path, opts: &LintOpts, codes: &[&str]) -> String {
    let flags: Vec<String> = codes.iter().map(|c| format!("--allow {c}")).collect();
    let keys: Vec<String> = codes.iter().map(|c| format!("{c} = \"allow\"")).collect();
    let toml = opts
        .config
        .clone()
        .or_else(|| lints::discover(input))
        .unwrap_or_else(|| input.parent().unwrap_or(Path::new(".")).join("mapc.toml"));
    format!(
        "if those keys are meant to be ignored, pass `{}` on the command line, or add `{}` under `[lints]` in {}",
        flags.join(" "),
        keys.join("` and `"),
        toml.display()
    )
}

/// The success line on stderr: what was written where, and how many warnings.
pub(crate) fn success_line(
    label: &str,
    what: &str,
    dir: &Path,
    w: output::Written,
    warnings: usize,
) {
    let removed = if w.removed > 0 {
        format!(", {} stale removed", w.removed)
    } else {
        String::new()
    };
    let warn = if warnings > 0 {
        format!(", {}", plural(warnings, "warning"))
    } else {
        String::new()
    };
    say(format!(
        "{label}: {what}, {} written to {} ({} unchanged{removed}){warn}",
        plural(w.files, "file"),
        output::shown(dir),
        w.unchanged
    ));
}

/// The shape every single-map command shares: read and check `input`; unless an error
/// breaks the command's outputs, `produce` builds the output files and counts those of the command's kind (its
/// diagnostics, e.g. texture warnings, join the report); report; write the files under
/// `out_dir` unless anything failed. Zero outputs of the kind fail (exit 1) unless the map
/// truly has none: nothing was ignored on the way.
fn run_command(
    input: &Path,
    out_dir: &Path,
    opts: &DiagOpts,
    cmd: &Cmd,
    style: report::Style,
    produce: impl FnOnce(&mapc_ir::Building) -> (Vec<mapc_backends::OutputFile>, Vec<Diagnostic>, usize),
) -> ExitCode {
    if let Err(e) = sanity::output_dir(out_dir, cmd.role) {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    let mut checked = match load_and_check(input, &opts.lints) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let mut files = Vec::new();
    let mut count = 0;
    if checked.blocked(cmd.outputs).is_empty() {
        if let Some(b) = checked.parsed.building.as_ref() {
            let (f, diags, n) = produce(b);
            files = f;
            count = n;
            checked.extend(diags);
        }
    }
    emit(&checked, opts, style);
    if opts.format == Format::Human {
        summary_line(input, &checked);
    }
    let blocked = checked.blocked(cmd.outputs);
    if !blocked.is_empty() {
        // One output: when any part is blocked, nothing is written.
        not_written(input, &checked, cmd.outputs, cmd.outputs);
        return ExitCode::from(1);
    }
    let label = build::map_name(input);
    let ignored = ignored_codes(&checked);
    if count == 0 && !ignored.is_empty() {
        eprintln!(
            "error: {label}: no {} written: {}, but keys were ignored (see the warnings above); \
             nothing written; {}",
            cmd.kind,
            cmd.none,
            ways_out(input, &opts.lints, &ignored)
        );
        return ExitCode::from(1);
    }
    match output::single_write(out_dir, cmd.role, &files, cmd.name, &label) {
        Ok(w) => {
            if !opts.quiet {
                if count == 0 {
                    eprintln!("{label}: no {} written: {}", cmd.kind, cmd.none);
                }
                let warnings = checked.diagnostics.len();
                success_line(&label, &plural(count, cmd.kind), out_dir, w, warnings);
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// A name usable as one file name: path separators and control characters become `_`.
fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c == '/' || c == '\\' || c.is_control() {
                '_'
            } else {
                c
            }
        })
        .collect();
    if s.is_empty() || s == "." || s == ".." {
        "building".into()
    } else {
        s
    }
}

fn gltf(
    input: &Path,
    output_dir: &Path,
    texture_path: &[PathBuf],
    per_level: bool,
    opts: &DiagOpts,
) -> ExitCode {
    let cmd = Cmd {
        name: "gltf",
        role: "OUTPUT_DIR",
        kind: "level mesh",
        none: "the map has no floors or walls",
        outputs: Outputs::GLTF,
    };
    run_command(
        input,
        output_dir,
        opts,
        &cmd,
        report::Style::Snippets,
        |b| {
            let meshes = build::all_level_meshes(b);
            let n = meshes.iter().map(|(_, m)| m.all().count()).sum();
            let names = build::gltf_texture_names(&meshes);
            let (textures, diags) =
                textures_for(b, names.iter().map(String::as_str), texture_path, input);
            (
                build::gltf_files(b, &meshes, &textures, per_level),
                diags,
                n,
            )
        },
    )
}

/// Texture images for `names`, searched on the texture path (`--texture-path` directories,
/// MAPC_TEXTURE_PATH, the map's directory), with warnings for those not found.
fn textures_for<'a>(
    b: &mapc_ir::Building,
    names: impl IntoIterator<Item = &'a str>,
    texture_path: &[PathBuf],
    input: &Path,
) -> (mapc_backends::Textures, Vec<Diagnostic>) {
    let search = texture::SearchPath::from_env(texture_path, input);
    mapc_backends::resolve_textures(b, names, &mut |f| search.find(f))
}

fn meshes(input: &Path, model_dir: &Path, texture_path: &[PathBuf], opts: &DiagOpts) -> ExitCode {
    let cmd = Cmd {
        name: "meshes",
        role: "OUTPUT_MODEL_DIR",
        kind: "level mesh",
        none: "the map has no floors or walls",
        outputs: Outputs::MESHES,
    };
    run_command(input, model_dir, opts, &cmd, report::Style::Snippets, |b| {
        let meshes = build::all_level_meshes(b);
        let n = meshes.iter().map(|(_, m)| m.all().count()).sum();
        let names = build::mesh_texture_names(&meshes);
        let (textures, diags) =
            textures_for(b, names.iter().map(String::as_str), texture_path, input);
        (build::mesh_files(b, &meshes, &textures), diags, n)
    })
}

fn check(inputs: &[PathBuf], opts: &DiagOpts) -> ExitCode {
    let mut code = 0u8;
    let mut all: Vec<Checked> = Vec::new();
    for input in inputs {
        match load_and_check(input, &opts.lints) {
            Ok(c) => {
                if !c.blocked(Outputs::ALL).is_empty() {
                    code = code.max(1);
                }
                if opts.format != Format::Sarif {
                    emit(&c, opts, report::Style::Snippets);
                }
                if opts.format == Format::Human {
                    summary_line(input, &c);
                }
                // A clean map is said out loud too (problems have their count line).
                if c.diagnostics.is_empty() && !opts.quiet {
                    eprintln!("{}: no problems found", output::shown(input));
                }
                all.push(c);
            }
            Err(e) => {
                eprintln!("error: {e}");
                code = 2;
            }
        }
    }
    if opts.format == Format::Sarif {
        print_sarif(&all, opts.max_diagnostics);
    }
    ExitCode::from(code)
}

/// One SARIF log for several maps: sources merged, file ids re-based, at most `max`
/// diagnostics per code over all maps.
fn print_sarif<'a>(all: impl IntoIterator<Item = &'a Checked>, max: limit::MaxDiagnostics) {
    let mut sources = Vec::new();
    let mut diags = Vec::new();
    for c in all {
        let base = sources.len() as u32;
        sources.extend(c.parsed.sources.iter().cloned());
        for d in &c.diagnostics {
            let mut d = d.clone();
            d.span.file.0 += base;
            for l in &mut d.labels {
                l.span.file.0 += base;
            }
            diags.push(d);
        }
    }
    let (shown, cut) = limit::select(&diags, max);
    print!("{}", report_json::sarif(&sources, &shown, &cut));
}

#[cfg(test)]
mod cli_tests {
    use super::*;

    fn argv(s: &str) -> Vec<std::ffi::OsString> {
        std::iter::once("mapc")
            .chain(s.split_whitespace())
            .map(Into::into)
            .collect()
    }

    fn world(cli: &Cli) -> (&'static str, String) {
        match &cli.command {
            Command::Gazebo(a) => ("gazebo", format!("{a:?}")),
            Command::Ignition(a) => ("ignition", format!("{a:?}")),
            Command::Classic(a) => ("classic", format!("{a:?}")),
            _ => ("other", String::new()),
        }
    }

    /// The world commands' shortcut gives what the whole parser gives, and leaves help,
    /// versions, mistakes and other commands to it.
    #[test]
    fn the_world_shortcut_parses_as_the_whole_parser() {
        for line in [
            "gazebo m.building.yaml w.world models",
            "gz m.building.yaml w.world models --quiet --texture-path a --texture-path b",
            "ignition m.building.yaml w.world models -o x y -n --SKIP_CAMERA_POSE",
            "classic m.building.yaml w.world models --TEMPLATE_WORLD_FILE t.sdf --format json",
            "gazebo m.building.yaml w.world models --allow E0302 --deny warnings --max-diagnostics all",
            "gazebo m.building.yaml w.world models --config mapc.toml -m p -c q --verbose",
        ] {
            let args = argv(line);
            let fast = parse_world_args(&args).unwrap_or_else(|| panic!("{line}: no shortcut"));
            let full = Cli::try_parse_from(&args).unwrap();
            assert_eq!(world(&fast), world(&full), "{line}");
        }
        for line in [
            "gazebo --help",
            "gazebo -h",
            "gazebo --version",
            "gazebo m.building.yaml w.world",
            "gazebo m.building.yaml w.world models --no-such-flag",
            "gazebo m.building.yaml w.world models --format nope",
            "nav m.building.yaml out",
            "--version",
        ] {
            assert!(parse_world_args(&argv(line)).is_none(), "{line}");
        }
    }
}
