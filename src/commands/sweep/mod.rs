//! `mapc sweep`: capacity studies. A sweep file names a base scenario and axes (dotted
//! paths into it with lists of values); the runs are their Cartesian product. The plan
//! (plan.rs) is checked whole before anything runs; the runs go to an executor (local
//! threads, a Slurm job array, or a Kubernetes Indexed Job manifest), each run writing
//! OUT/runs/<run>/; collect.rs turns the run directories into results.csv, results.json
//! and capacity.svg. Orchestration only: every run is the library call `mapc sim` makes.

mod collect;
mod k8s;
mod local;
mod plan;
mod run;
mod slurm;
mod spec;
mod svg;

use crate::driver::output;
use crate::driver::{CliError, Outcome};
use clap::{Subcommand, ValueEnum};
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
pub(crate) enum Executor {
    /// Every run on this machine, on all cores (--jobs).
    Local,
    /// One Slurm job array; each task runs `mapc sweep SWEEP -o OUT --run $SLURM_ARRAY_TASK_ID`
    /// (OUT must be on a file system the nodes share).
    Slurm,
    /// Write OUT/k8s/job.yaml, a Kubernetes Indexed Job (one pod per run), and stop.
    K8sManifest,
}

#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub(crate) struct SweepArgs {
    #[command(subcommand)]
    command: Option<SweepCommand>,
    /// The sweep file (format in docs/sweep.md).
    #[arg(required = true)]
    sweep: Option<PathBuf>,
    /// Output directory: OUT/runs/<run>/, OUT/results.csv, OUT/results.json, OUT/capacity.svg.
    #[arg(short = 'o', long = "out", value_name = "OUT", required = true)]
    out: Option<PathBuf>,
    /// Where the runs run.
    #[arg(long, value_enum, default_value = "local")]
    executor: Executor,
    /// Local executor: runs at once (default: the number of CPUs).
    #[arg(short = 'j', long, value_name = "N")]
    jobs: Option<usize>,
    /// Run only run N (0-based) and write its directory; what a cluster task does.
    #[arg(long, value_name = "N")]
    run: Option<usize>,
    /// Slurm: submit and return; collect later with `mapc sweep collect OUT`.
    #[arg(long)]
    no_wait: bool,
    /// Slurm: extra sbatch options, split at spaces (e.g. "--partition=batch --time=30
    /// --mem=2G").
    #[arg(long, value_name = "ARGS", allow_hyphen_values = true)]
    sbatch_args: Option<String>,
    /// Slurm and Kubernetes: at most K runs at once (sbatch --array=...%K, Job parallelism).
    #[arg(long, value_name = "K")]
    max_parallel: Option<usize>,
    /// Kubernetes: the container image with mapc on its PATH.
    #[arg(long, value_name = "IMAGE", default_value = "mapc:latest")]
    image: String,
    /// Kubernetes: the PersistentVolumeClaim holding the sweep, its inputs and OUT; mounted
    /// at /sweep, the pods' working directory (paths are passed as given, so run from the
    /// claim's root).
    #[arg(long, value_name = "NAME", default_value = "mapc-sweep")]
    claim: String,
    #[command(flatten)]
    lints: crate::driver::LintOpts,
    /// No summary on stdout and no messages on stderr except errors.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Subcommand)]
enum SweepCommand {
    /// Collect the results of runs that ran elsewhere (after `--executor slurm --no-wait`
    /// or a Kubernetes Job): OUT/results.csv, OUT/results.json, OUT/capacity.svg.
    Collect {
        /// The sweep's output directory.
        out: PathBuf,
        #[arg(short, long)]
        quiet: bool,
    },
}

/// The lint options again, for the cluster tasks' command lines.
fn lint_args(l: &crate::driver::LintOpts) -> Vec<String> {
    let mut v = Vec::new();
    if l.deny_warnings {
        v.push("--deny-warnings".to_string());
    }
    for (flag, codes) in [
        ("--allow", &l.allow),
        ("--warn", &l.warn),
        ("--deny", &l.deny),
    ] {
        for c in codes {
            v.push(format!("{flag}={c}"));
        }
    }
    if let Some(c) = &l.config {
        v.push(format!("--config={}", plan::absolute(c).display()));
    }
    v
}

fn failed(msg: String) -> Result<Outcome, CliError> {
    Err(CliError::Usage(msg))
}

pub(crate) fn run(args: &SweepArgs) -> Result<Outcome, CliError> {
    if let Some(SweepCommand::Collect { out, quiet }) = &args.command {
        return finish(out, *quiet);
    }
    let (Some(sweep), Some(out)) = (&args.sweep, &args.out) else {
        return failed("give a sweep file and -o OUT".into());
    };
    let text = match std::fs::read(sweep) {
        Ok(b) => match String::from_utf8(b) {
            Ok(t) => t,
            Err(_) => return failed(format!("{}: not UTF-8 text", crate::ui::shown(sweep))),
        },
        Err(e) => return failed(format!("{}: {e}", crate::ui::shown(sweep))),
    };
    if out.is_file() {
        return failed(format!(
            "`{}` is a file; OUT must be a directory",
            crate::ui::shown(out)
        ));
    }
    let mut report = plan::Report::default();
    let planned = plan::plan(sweep, &text, out, &args.lints, args.run, &mut report);
    report.emit();
    let plan = match planned {
        Ok(p) => p,
        Err(plan::Failed(code)) => {
            if code == 1 {
                return Err(CliError::Invalid(format!(
                    "{}: {} error(s), nothing run",
                    crate::ui::shown(sweep),
                    report.errors().max(1)
                )));
            }
            return Err(CliError::UsageReported);
        }
    };
    let count = plan.runs.len();

    // A cluster task: one run, nothing else.
    if let Some(i) = args.run {
        let Some(r) = plan.runs.get(i) else {
            return failed(format!(
                "--run {i}: the sweep has {count} runs (0..{count})"
            ));
        };
        if run::up_to_date(out, &r.name, &r.inputs) {
            if !args.quiet {
                eprintln!("run {}: up to date", r.name);
            }
            return Ok(Outcome::Done);
        }
        return match run::execute(&plan, r, out) {
            Ok(()) => Ok(Outcome::Done),
            Err(e) => failed(e),
        };
    }

    let plan_file = collect::PlanFile {
        mapc: env!("CARGO_PKG_VERSION").into(),
        axes: plan
            .spec
            .varying()
            .map(|a| collect::AxisInfo {
                path: a.path.clone(),
                zipped: a.zipped,
            })
            .collect(),
        runs: plan
            .runs
            .iter()
            .map(|r| collect::RunInfo {
                run: r.name.clone(),
                values: plan
                    .spec
                    .axes
                    .iter()
                    .zip(&r.choice)
                    .filter(|(a, _)| !a.fixed)
                    .map(|(a, &c)| collect::AxisValue {
                        text: a.values[c].text.clone(),
                        value: a.values[c].json.clone(),
                    })
                    .collect(),
                inputs: r.inputs.clone(),
            })
            .collect(),
    };
    let mut json = match serde_json::to_vec_pretty(&plan_file) {
        Ok(j) => j,
        Err(e) => return failed(e.to_string()),
    };
    json.push(b'\n');
    let plan_path = out.join("plan.json");
    if let Err(e) = output::write_atomic(&plan_path, &json) {
        return failed(format!("{}: {e}", crate::ui::shown(&plan_path)));
    }
    let todo: Vec<&plan::Run> = plan
        .runs
        .iter()
        .filter(|r| !run::up_to_date(out, &r.name, &r.inputs))
        .collect();
    if !args.quiet {
        eprintln!(
            "{}: {count} runs, {} to run, {} up to date",
            crate::ui::shown(sweep),
            todo.len(),
            count - todo.len()
        );
    }
    match args.executor {
        Executor::Local => {
            let jobs = args
                .jobs
                .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
            let failures = local::execute(&plan, &todo, out, jobs, args.quiet);
            let collected = finish(out, args.quiet);
            if failures.is_empty() {
                return collected;
            }
            // Failed runs (said as they failed) make the exit 1 whatever the collection
            // found; what it could not do is still said.
            if let Some(m) = collected.as_ref().err().and_then(CliError::message) {
                crate::ui::error(m);
            }
            Err(CliError::InvalidReported)
        }
        Executor::Slurm => {
            let indices: Vec<usize> = todo.iter().map(|r| r.index).collect();
            let opts = slurm::Options {
                sweep,
                out,
                no_wait: args.no_wait,
                sbatch_args: args.sbatch_args.as_deref().unwrap_or(""),
                max_parallel: args.max_parallel,
                quiet: args.quiet,
                lint_args: lint_args(&args.lints),
            };
            match slurm::run(&opts, &indices, |i| {
                let r = &plan.runs[i];
                run::up_to_date(out, &r.name, &r.inputs)
            }) {
                Ok(slurm::Outcome::Submitted) => Ok(Outcome::Done),
                Ok(slurm::Outcome::Finished) => finish(out, args.quiet),
                Err(e) => failed(e),
            }
        }
        Executor::K8sManifest => {
            let job = k8s::Job {
                sweep,
                out,
                runs: count,
                max_parallel: args.max_parallel,
                image: &args.image,
                claim: &args.claim,
                lint_args: lint_args(&args.lints),
            };
            match k8s::write(&job) {
                Ok(p) => {
                    if !args.quiet {
                        eprintln!(
                            "wrote {}: `kubectl apply -f {}`, then `mapc sweep collect {}` when the Job has completed",
                            crate::ui::shown(&p),
                            crate::ui::shown(&p),
                            crate::ui::shown(out)
                        );
                    }
                    Ok(Outcome::Done)
                }
                Err(e) => failed(e),
            }
        }
    }
}

/// Collects OUT; exit 1 when runs are missing.
fn finish(out: &Path, quiet: bool) -> Result<Outcome, CliError> {
    match collect_results(out, quiet) {
        Ok(missing) if missing.is_empty() => Ok(Outcome::Done),
        Ok(missing) => Err(CliError::Invalid(format!(
            "{} run(s) not done: {}; run the sweep again to redo them",
            missing.len(),
            missing.join(", ")
        ))),
        Err(e) => failed(e),
    }
}

/// Writes results.csv, results.json and capacity.svg and prints the summary. Returns the
/// runs that are not done.
fn collect_results(out: &Path, quiet: bool) -> Result<Vec<String>, String> {
    let (plan, rows) = collect::read(out)?;
    let write = |name: &str, bytes: &[u8]| {
        let p = out.join(name);
        output::write_atomic(&p, bytes).map_err(|e| format!("{}: {e}", crate::ui::shown(&p)))
    };
    write("results.csv", &collect::csv(&plan, &rows)?)?;
    write("results.json", &collect::json(&plan, &rows)?)?;
    let chart = svg::capacity(&plan, &rows);
    match &chart {
        Some(c) => write("capacity.svg", c.svg.as_bytes())?,
        None => {
            let p = out.join("capacity.svg");
            if p.is_file() {
                let _ = std::fs::remove_file(&p);
            }
        }
    }
    let missing: Vec<String> = rows
        .iter()
        .filter(|r| r.numbers.is_none())
        .map(|r| r.run.clone())
        .collect();
    let done = rows.len() - missing.len();
    if !quiet {
        println!(
            "{done} of {} runs done; results in {}",
            rows.len(),
            crate::ui::shown(&out.join("results.csv"))
        );
        if let Some(c) = &chart {
            print!("{}", c.summary);
        }
    }
    Ok(missing)
}
