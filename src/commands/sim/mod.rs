//! `mapc sim`: runs a scenario on a map with the headless runtime (mapc-sim) and writes a
//! trace (JSON Lines) and a report (JSON). Exit codes: 0 ok, 1 invalid scenario or map (or
//! a scenario that does not fit the map), 2 usage or I/O error.

mod replay;
mod ros2;

use crate::driver::{load_and_check, output, signals, summary_line, Checked, CliError, Outcome};
use crate::ui::{json as report_json, progress::Progress, report};
use clap::ValueEnum;
use mapc_frontend::SourceFile;
use mapc_ir::{Diagnostic, FileId, Span};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
pub(crate) enum SimFormat {
    /// Diagnostics with source snippets on stderr, a short summary on stdout.
    Human,
    /// JSON Lines on stdout: one object per diagnostic, then `{"report": {...}}`.
    Json,
}

#[derive(clap::Args)]
pub(crate) struct SimArgs {
    /// The scenario file (.scenario.yaml; format in docs/sim.md).
    scenario: PathBuf,
    /// The .building.yaml to run on, instead of the scenario's `map`.
    #[arg(long, value_name = "MAP")]
    map: Option<PathBuf>,
    /// Stop at this simulated time instead of the scenario's `duration`: seconds, or a
    /// duration such as 90s, 15min, 8h, 1h30min.
    #[arg(long, value_name = "TIME", value_parser = parse_until)]
    until: Option<f64>,
    /// Write every published message here, one JSON object per line (zstd-compressed when
    /// FILE ends in `.zst`, e.g. `run.jsonl.zst`).
    #[arg(long, value_name = "FILE")]
    trace: Option<PathBuf>,
    /// Only these topics go to the trace (comma-separated, e.g.
    /// `task_events,door_states`; default: all).
    #[arg(long, value_name = "TOPICS", value_delimiter = ',', value_parser = parse_topic)]
    trace_topics: Vec<mapc_sim::msgs::Topic>,
    /// Trace state topics (robot, fleet, door, lift, dispenser and ingestor states, door
    /// supervisor heartbeats) at most once per this period per publisher: seconds or a
    /// duration such as 1s, 1min (default: every message).
    #[arg(long, value_name = "TIME", value_parser = parse_period)]
    trace_state_period: Option<f64>,
    /// Write the run report here (JSON).
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// RMF task API requests (JSON Lines, `{"at": TIME, "request": {...}}` a line), read
    /// instead of the scenario's `requests:`.
    #[arg(long, value_name = "FILE")]
    requests: Option<PathBuf>,
    /// Write each task's final state as RMF's API `task_state`, one JSON object a line.
    #[arg(long, value_name = "FILE")]
    task_states: Option<PathBuf>,
    /// Write the fleets' states as RMF's API `fleet_state_update`s, one JSON object a line.
    #[arg(long, value_name = "FILE")]
    fleet_states: Option<PathBuf>,
    /// Write a self-contained HTML page that replays the run (levels, robots, doors, lifts,
    /// tasks, charts; no network needed).
    #[arg(long, value_name = "FILE")]
    html: Option<PathBuf>,
    /// How to print diagnostics and the summary.
    #[arg(long, value_enum, default_value = "human")]
    format: SimFormat,
    #[command(flatten)]
    ros2: ros2::Ros2Args,
    #[command(flatten)]
    lints: crate::driver::LintOpts,
    /// Do not print the success line (what was written) on stderr.
    #[arg(short, long)]
    quiet: bool,
    /// When the map's crowd walks, run the scenario a second time without people and put
    /// each fleet's task times of both runs in the report's `crowd.compare`.
    #[arg(long)]
    compare_crowd: bool,
}

fn parse_topic(s: &str) -> Result<mapc_sim::msgs::Topic, String> {
    mapc_sim::msgs::Topic::from_name(s.trim()).ok_or_else(|| {
        let names: Vec<&str> = mapc_sim::msgs::Topic::ALL
            .iter()
            .map(|t| &t.name()[1..])
            .collect();
        format!("unknown topic; one of: {}", names.join(", "))
    })
}

fn parse_period(s: &str) -> Result<f64, String> {
    let t = mapc_sim::parse_duration(s)?;
    if !t.is_finite() || t < 0.0 {
        return Err("must be a time of at least 0".into());
    }
    Ok(t)
}

/// Before simulating (an 8 h run can take minutes): every output path can be written. A
/// temporary is created and removed in the file's directory, which is created if missing.
fn check_writable(path: &Path, what: &str) -> Result<(), String> {
    if path.is_dir() {
        return Err(format!(
            "`{}` is a directory; {what} must be a file path",
            crate::ui::shown(path)
        ));
    }
    if output::is_stream(path) {
        // Written in place; opening a FIFO here would wait for its reader.
        return Ok(());
    }
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let err = |e: std::io::Error| {
        format!(
            "{what}: {}; nothing simulated",
            output::io_message(dir, "its directory", path, &e)
        )
    };
    std::fs::create_dir_all(dir).map_err(err)?;
    let (tmp, _f) = output::create_temporary(path).map_err(err)?;
    let _ = std::fs::remove_file(&tmp);
    output::release_temporary(&tmp);
    Ok(())
}

/// A building map passed where the scenario belongs: say so instead of reporting that the
/// "scenario" lacks every scenario key.
fn looks_like_map(path: &Path, text: &str) -> bool {
    let name = path.to_string_lossy();
    name.ends_with(".building.yaml")
        || name.ends_with(".project.yaml")
        || name.ends_with(".site.json")
        || text.lines().any(|l| l.starts_with("levels:"))
}

fn parse_until(s: &str) -> Result<f64, String> {
    let t = mapc_sim::parse_duration(s)?;
    if !t.is_finite() || t <= 0.0 {
        return Err("must be a positive time".into());
    }
    if t > mapc_sim::MAX_DURATION {
        return Err("must be at most one year".into());
    }
    Ok(t)
}

/// The scenario file's text, or a diagnostic when it is too large or not UTF-8 (exit 1),
/// or an I/O error (exit 2).
fn read_scenario(path: &Path, file: FileId) -> Result<(String, Option<Diagnostic>), String> {
    use std::io::Read;
    let err = |e: std::io::Error| format!("{}: {e}", path.display());
    let meta = std::fs::metadata(path).map_err(err)?;
    if !meta.is_file() {
        return Err(format!("{}: not a regular file", path.display()));
    }
    let whole = Span {
        file,
        start: 0,
        end: 0,
        line: 1,
        col: 1,
    };
    let limit = mapc_frontend::MAX_FILE_BYTES;
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(limit + 1).read_to_end(&mut bytes))
        .map_err(err)?;
    if bytes.len() as u64 > limit {
        let d = Diagnostic::error(
            mapc_sim::codes::INPUT_LIMIT.code,
            whole,
            format!("the file is larger than the input limit of {limit} bytes"),
        )
        .with_help("scenarios are a few dozen lines; check that this is the right file");
        return Ok((String::new(), Some(d)));
    }
    match String::from_utf8(bytes) {
        Ok(t) => Ok((t, None)),
        Err(e) => {
            let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
            let line = valid.iter().filter(|&&c| c == b'\n').count() + 1;
            let tail = valid.rsplit(|&c| c == b'\n').next().unwrap_or(valid);
            let col = String::from_utf8_lossy(tail).chars().count() + 1;
            let off = valid.len() as u32;
            let d = Diagnostic::error(
                mapc_sim::codes::NOT_UTF8.code,
                Span {
                    file,
                    start: off,
                    end: off,
                    line: line as u32,
                    col: col as u32,
                },
                "the file is not valid UTF-8",
            )
            .with_help("pass a scenario file (YAML text), saved as UTF-8");
            Ok((String::from_utf8_lossy(e.as_bytes()).into_owned(), Some(d)))
        }
    }
}

/// The files a scenario names, as sources for diagnostics (their ids follow the
/// scenario's).
fn included_sources(included: &[mapc_sim::Included]) -> Vec<SourceFile> {
    included
        .iter()
        .map(|i| SourceFile {
            name: crate::ui::shown(&i.path),
            text: i.text.clone(),
        })
        .collect()
}

fn emit(sources: &[SourceFile], diags: &[Diagnostic], format: SimFormat) {
    // A scenario's diagnostics are few (it is small and hand-written): all are shown.
    let all: Vec<&Diagnostic> = diags.iter().collect();
    match format {
        SimFormat::Human => report::emit(sources, &all, &[], report::Style::Snippets),
        SimFormat::Json => {
            let mut out = std::io::BufWriter::new(std::io::stdout().lock());
            let _ = report_json::write_json_lines(&mut out, sources, &all, &[]);
        }
    }
}

pub(crate) fn run(args: &SimArgs) -> Result<Outcome, CliError> {
    let failed = |msg: String| Err(CliError::Usage(msg));
    // 1. The scenario alone (its own file table), to find the map and report its problems.
    let (text, bad_bytes) = match read_scenario(&args.scenario, FileId(0)) {
        Ok(x) => x,
        Err(e) => return failed(e),
    };
    if looks_like_map(&args.scenario, &text) {
        return failed(format!(
            "`{}` is a building map; use --map {} and pass a scenario (docs/sim.md)",
            crate::ui::shown(&args.scenario),
            crate::ui::shown(&args.scenario)
        ));
    }
    for (path, what) in [
        (&args.report, "--report"),
        (&args.trace, "--trace"),
        (&args.html, "--html"),
        (&args.ros2.mcap, "--mcap"),
        (&args.task_states, "--task-states"),
        (&args.fleet_states, "--fleet-states"),
    ] {
        if let Some(p) = path {
            if let Err(e) = check_writable(p, what) {
                return failed(e);
            }
        }
    }
    let name = crate::ui::shown(&args.scenario);
    let base = args
        .scenario
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let mut scenario_only = vec![SourceFile {
        name: name.clone(),
        text: text.clone(),
    }];
    let (scenario, diags) = match bad_bytes {
        Some(d) => (None, vec![d]),
        None => {
            // With the files it names (fleet configs), so that their problems are shown
            // where they are.
            let p = mapc_sim::parse_scenario_files_with(
                FileId(0),
                &text,
                base,
                args.requests.as_deref(),
            );
            scenario_only.extend(included_sources(&p.included));
            (p.scenario, p.diagnostics)
        }
    };
    emit(&scenario_only, &diags, args.format);
    let Some(scenario) = scenario else {
        if args.format == SimFormat::Human {
            count_line(&name, &diags);
        }
        return Err(CliError::Invalid(format!(
            "{name}: invalid scenario, nothing simulated"
        )));
    };

    // 2. The map, checked like `mapc check`.
    let Some(map) = args.map.clone().or(scenario.map.clone()) else {
        return failed(format!(
            "{name} names no `map`; add `map: <path>` to it or pass --map"
        ));
    };
    let checked: Checked = match load_and_check(&map, &args.lints) {
        Ok(c) => c,
        Err(e) => return failed(e),
    };
    // On a terminal, map errors are shown in full but map warnings (demo maps have dozens)
    // only as a count, so that they do not bury the run's own output (`mapc check` shows
    // them). JSON consumers get everything and can filter.
    let shown: Vec<Diagnostic> = checked
        .diagnostics
        .iter()
        .filter(|d| d.is_error() || args.format == SimFormat::Json)
        .cloned()
        .collect();
    emit(&checked.parsed.sources, &shown, args.format);
    if args.format == SimFormat::Human {
        summary_line(&map, &checked);
        if shown.len() < checked.diagnostics.len() {
            eprintln!("  (run `mapc check {}` to see the warnings)", map.display());
        }
    }
    let building = match checked.parsed.building.as_ref() {
        // The runtime needs what nav graphs and worlds carry (lanes, doors, lifts).
        Some(b)
            if checked
                .blocked(mapc_ir::lints::Outputs::NAV.union(mapc_ir::lints::Outputs::WORLDS))
                .is_empty() =>
        {
            b
        }
        _ => {
            return Err(CliError::Invalid(format!(
                "{}: invalid map, nothing simulated",
                map.display()
            )));
        }
    };

    // 3. The scenario again, with its file id after the map's files, so that diagnostics of
    // the fleet layer can point into both.
    let mut sources = checked.parsed.sources.clone();
    let sid = FileId(sources.len() as u32);
    sources.push(SourceFile { name, text });
    let parsed = mapc_sim::parse_scenario_files_with(
        sid,
        &sources[sid.0 as usize].text,
        base,
        args.requests.as_deref(),
    );
    sources.extend(included_sources(&parsed.included));
    let Some(scenario) = parsed.scenario else {
        // Same text, same result; never reached.
        return failed("the scenario could not be read twice".into());
    };

    // 4. Run, streaming the trace into a temporary file renamed at the end.
    let mut trace = match args.trace.as_deref().map(TraceFile::create).transpose() {
        Ok(t) => t,
        Err(e) => return failed(e),
    };
    let bar = Progress::new(0, "s simulated", !args.quiet);
    let started = std::time::Instant::now();
    let mut progress = |t: f64, end: f64| {
        let wall = started.elapsed().as_secs_f64();
        let speed = if wall > 0.0 { t / wall } else { 0.0 };
        bar.update(t as u64, end as u64, format!("({speed:.0}x real time)"));
    };
    let topics =
        (!args.trace_topics.is_empty()).then(|| args.trace_topics.iter().copied().collect());
    let mut recorder = args
        .html
        .as_ref()
        .map(|_| replay::Recorder::new(building, &scenario));
    let ros2 = match ros2::Ros2Run::start(&args.ros2, building) {
        Ok(r) => r,
        Err(e) => return failed(e),
    };
    let observing = args.html.is_some() || ros2.active() || args.fleet_states.is_some();
    let injecting = ros2.injects();
    let ros2 = std::cell::RefCell::new(ros2);
    let start_ms = mapc_sim::rmf_states::start_unix_millis(&scenario);
    let mut fleet_states: Vec<u8> = Vec::new();
    let mut observe = |p: &mapc_sim::msgs::Published| {
        if let Some(r) = recorder.as_mut() {
            r.observe(p);
        }
        ros2.borrow_mut().observe(p);
        if let (Some(_), mapc_sim::msgs::Msg::FleetState(f)) = (&args.fleet_states, &p.msg) {
            let u = mapc_sim::rmf_states::fleet_state_update(f, p.t, start_ms);
            // A `Value` always serialises.
            let _ = serde_json::to_writer(&mut fleet_states, &u);
            fleet_states.push(b'\n');
        }
    };
    let mut inject = |t: f64, out: &mut Vec<_>| ros2.borrow_mut().inject(t, out);
    let opts = mapc_sim::RunOptions {
        until: args.until,
        trace: trace.as_mut().map(|t| t.writer()),
        progress: if bar.is_shown() {
            Some(&mut progress)
        } else {
            None
        },
        stop: Some(&signals::INTERRUPTED),
        trace_filter: mapc_sim::TraceFilter::new(topics, args.trace_state_period.unwrap_or(0.0)),
        observer: if observing { Some(&mut observe) } else { None },
        inject: if injecting { Some(&mut inject) } else { None },
        plugins_only: args.ros2.plugins_only,
        plan_times: None,
    };
    let result = mapc_sim::simulate(building, &scenario, opts);
    drop(bar);
    let mut run_report = match result {
        Ok(r) => r,
        Err(mapc_sim::SimError::Invalid(diags)) => {
            emit(&sources, &diags, args.format);
            return Err(CliError::Invalid(format!(
                "{}: the scenario does not fit the map, nothing simulated",
                args.scenario.display()
            )));
        }
        Err(mapc_sim::SimError::Io(e)) => {
            let path = args.trace.as_deref().unwrap_or(Path::new("trace"));
            return failed(format!("{}: {e}", path.display()));
        }
    };
    if args.compare_crowd && run_report.crowd.is_some() && !run_report.interrupted {
        let mut alone = scenario.clone();
        alone.options.crowd.enabled = false;
        let opts = mapc_sim::RunOptions {
            until: args.until,
            stop: Some(&signals::INTERRUPTED),
            ..Default::default()
        };
        match mapc_sim::simulate(building, &alone, opts) {
            Ok(without) => mapc_sim::compare_crowd(&mut run_report, &without),
            Err(_) => return failed("the run without people failed".into()),
        }
    }
    // Also after an interruption: the trace up to the stop is kept under its final name.
    if let Some(t) = trace {
        if let Err(e) = t.finish() {
            return failed(e);
        }
    }
    if let Err(e) = ros2.into_inner().finish() {
        return failed(e);
    }
    if let (Some(path), Some(r)) = (&args.html, recorder) {
        if let Err(e) = output::write_atomic(path, r.page().as_bytes()) {
            return failed(format!("{}: {e}", path.display()));
        }
    }
    if let Some(path) = &args.fleet_states {
        if let Err(e) = output::write_atomic(path, &fleet_states) {
            return failed(format!("{}: {e}", path.display()));
        }
    }
    if let Some(path) = &args.task_states {
        let mut lines = Vec::new();
        for st in mapc_sim::rmf_states::task_states(&scenario, &run_report) {
            let _ = serde_json::to_writer(&mut lines, &st);
            lines.push(b'\n');
        }
        if let Err(e) = output::write_atomic(path, &lines) {
            return failed(format!("{}: {e}", path.display()));
        }
    }
    if let Some(path) = &args.report {
        let mut json = match serde_json::to_vec_pretty(&run_report) {
            Ok(j) => j,
            Err(e) => return failed(format!("report: {e}")),
        };
        json.push(b'\n');
        if let Err(e) = output::write_atomic(path, &json) {
            return failed(format!("{}: {e}", path.display()));
        }
    }
    match args.format {
        SimFormat::Human => print!("{}", run_report.summary()),
        // Through a struct, not `json!`: a `serde_json::Value` map sorts keys, and the
        // report's key order is documented.
        SimFormat::Json => match serde_json::to_string(&JsonReport {
            report: &run_report,
        }) {
            Ok(j) => println!("{j}"),
            Err(e) => return failed(format!("report: {e}")),
        },
    }
    if !args.quiet {
        let mut written = Vec::new();
        if let Some(p) = &args.report {
            written.push(format!("report {}", crate::ui::shown(p)));
        }
        if let Some(p) = &args.trace {
            written.push(format!("trace {}", crate::ui::shown(p)));
        }
        if let Some(p) = &args.task_states {
            written.push(format!("task states {}", crate::ui::shown(p)));
        }
        if let Some(p) = &args.fleet_states {
            written.push(format!("fleet states {}", crate::ui::shown(p)));
        }
        if let Some(p) = &args.ros2.mcap {
            written.push(format!("mcap {}", crate::ui::shown(p)));
        }
        let written = if written.is_empty() {
            "nothing written (no --report or --trace)".to_string()
        } else {
            format!("wrote {}", written.join(", "))
        };
        eprintln!(
            "{}: simulated {:.0} s{}, {written}",
            crate::ui::shown(&args.scenario),
            run_report.end_time,
            if run_report.interrupted {
                " (interrupted)"
            } else {
                ""
            }
        );
    }
    if run_report.interrupted {
        return Ok(Outcome::Interrupted);
    }
    Ok(Outcome::Done)
}

#[derive(serde::Serialize)]
struct JsonReport<'a> {
    report: &'a mapc_sim::Report,
}

fn count_line(name: &str, diags: &[Diagnostic]) {
    let errors = diags.iter().filter(|d| d.is_error()).count();
    let warnings = diags.len() - errors;
    if errors + warnings > 0 {
        eprintln!("{name}: {errors} error(s), {warnings} warning(s)");
    }
}

/// A trace being written: a temporary file next to the target, renamed when the run ends
/// (completed or interrupted) and removed on failure, so a reader never sees half a trace
/// under the final name. Names ending in `.zst` are zstd-compressed.
struct TraceFile {
    /// `None` only inside `finish`.
    writer: Option<TraceWriter>,
    /// Removes the temporary when dropped unfinished.
    pending: Option<output::Pending>,
    path: PathBuf,
}

enum TraceWriter {
    Plain(BufWriter<std::fs::File>),
    Zstd(zstd::Encoder<'static, BufWriter<std::fs::File>>),
}

impl TraceFile {
    fn create(path: &Path) -> Result<TraceFile, String> {
        let err = |e: std::io::Error| format!("{}: {e}", crate::ui::shown(path));
        let dir = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(dir).map_err(err)?;
        if path.file_name().and_then(|n| n.to_str()).is_none() {
            return Err(format!("{}: not a file path", crate::ui::shown(path)));
        }
        output::sweep_temporaries(dir);
        let (pending, file) = output::Pending::create(path).map_err(err)?;
        let buffered = BufWriter::with_capacity(1 << 20, file);
        let writer = if path.extension().is_some_and(|e| e == "zst") {
            // Level 3, zstd's default: a trace compresses about 30x, fast enough to keep up.
            TraceWriter::Zstd(zstd::Encoder::new(buffered, 3).map_err(err)?)
        } else {
            TraceWriter::Plain(buffered)
        };
        Ok(TraceFile {
            writer: Some(writer),
            pending: Some(pending),
            path: path.to_path_buf(),
        })
    }

    fn writer(&mut self) -> &mut dyn Write {
        match &mut self.writer {
            Some(TraceWriter::Plain(w)) => w,
            Some(TraceWriter::Zstd(w)) => w,
            None => unreachable!("the writer is only taken by finish, which consumes self"),
        }
    }

    fn finish(mut self) -> Result<(), String> {
        let err = |e: std::io::Error| format!("{}: {e}", crate::ui::shown(&self.path));
        let mut file = match self.writer.take() {
            Some(TraceWriter::Plain(w)) => w,
            Some(TraceWriter::Zstd(w)) => w.finish().map_err(err)?,
            None => return Ok(()),
        };
        file.flush().map_err(err)?;
        match self.pending.take() {
            Some(p) => p.commit(file.get_ref()).map_err(err),
            None => Ok(()),
        }
    }
}
