//! The Slurm executor: the runs to do become one job array (`sbatch --array=LIST%K`), each
//! task running `mapc sweep SWEEP -o OUT --run $SLURM_ARRAY_TASK_ID` with absolute paths
//! (OUT on a file system the nodes share). Waiting polls `squeue` (no accounting database
//! needed); a task failed when its run directory has no matching stamp afterwards, and the
//! failed ones are submitted once more.

use super::plan::absolute;
use crate::driver::output;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

pub(crate) struct Options<'a> {
    pub sweep: &'a Path,
    pub out: &'a Path,
    pub no_wait: bool,
    pub sbatch_args: &'a str,
    pub max_parallel: Option<usize>,
    pub quiet: bool,
    /// The lint options, passed on to every task.
    pub lint_args: Vec<String>,
}

pub(crate) enum Outcome {
    /// `--no-wait`: the array was submitted.
    Submitted,
    /// Every task has ended (done or failed twice); collect now.
    Finished,
}

/// `0-3,5,7-9`: Slurm's array index list.
pub(crate) fn array_list(indices: &[usize]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < indices.len() {
        let mut j = i;
        while j + 1 < indices.len() && indices[j + 1] == indices[j] + 1 {
            j += 1;
        }
        parts.push(if j == i {
            indices[i].to_string()
        } else {
            format!("{}-{}", indices[i], indices[j])
        });
        i = j + 1;
    }
    parts.join(",")
}

fn quote(p: &Path) -> String {
    format!("'{}'", p.to_string_lossy().replace('\'', r"'\''"))
}

/// Writes OUT/slurm/job.sh.
fn script(o: &Options) -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find mapc itself: {e}"))?;
    let text = format!(
        "#!/bin/sh\n# One run of a mapc sweep per array task (written by `mapc sweep --executor slurm`).\nexec {} sweep {} -o {} --run \"$SLURM_ARRAY_TASK_ID\" --quiet{}\n",
        quote(&exe),
        quote(&absolute(o.sweep)),
        quote(&absolute(o.out)),
        o.lint_args
            .iter()
            .map(|a| format!(" {}", quote(Path::new(a))))
            .collect::<String>()
    );
    let path = o.out.join("slurm").join("job.sh");
    output::write_atomic(&path, text.as_bytes())
        .map_err(|e| format!("{}: {e}", crate::ui::shown(&path)))?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755));
    }
    Ok(path)
}

fn submit(o: &Options, script: &Path, indices: &[usize]) -> Result<String, String> {
    let mut array = array_list(indices);
    if let Some(k) = o.max_parallel {
        array.push_str(&format!("%{}", k.max(1)));
    }
    let log = absolute(&o.out.join("slurm")).join("%A_%a.log");
    let mut cmd = Command::new("sbatch");
    cmd.arg("--parsable")
        .arg("--job-name=mapc-sweep")
        .arg(format!("--array={array}"))
        .arg(format!("--output={}", log.display()))
        .args(o.sbatch_args.split_whitespace())
        .arg(absolute(script));
    let res = cmd
        .output()
        .map_err(|e| format!("cannot run sbatch: {e} (is Slurm's client installed?)"))?;
    if !res.status.success() {
        return Err(format!(
            "sbatch failed: {}",
            String::from_utf8_lossy(&res.stderr).trim()
        ));
    }
    let id = String::from_utf8_lossy(&res.stdout)
        .trim()
        .split(';')
        .next()
        .unwrap_or("")
        .to_string();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        return Err(format!("sbatch printed no job id: {id:?}"));
    }
    Ok(id)
}

/// Waits until job `id` has left the queue.
fn wait(id: &str) -> Result<(), String> {
    let mut errors = 0;
    loop {
        let res = Command::new("squeue")
            .args(["-h", "-j", id, "-o", "%i"])
            .output()
            .map_err(|e| format!("cannot run squeue: {e}"))?;
        let stderr = String::from_utf8_lossy(&res.stderr);
        if res.status.success() {
            if String::from_utf8_lossy(&res.stdout).trim().is_empty() {
                return Ok(());
            }
            errors = 0;
        } else if stderr.contains("Invalid job id") {
            // Already purged from the controller's memory: it has ended.
            return Ok(());
        } else {
            errors += 1;
            if errors >= 30 {
                return Err(format!("squeue keeps failing: {}", stderr.trim()));
            }
        }
        std::thread::sleep(Duration::from_secs(2));
    }
}

pub(crate) fn run(
    o: &Options,
    indices: &[usize],
    done: impl Fn(usize) -> bool,
) -> Result<Outcome, String> {
    if indices.is_empty() {
        return Ok(Outcome::Finished);
    }
    let script = script(o)?;
    let mut todo = indices.to_vec();
    for attempt in 0..2 {
        let id = submit(o, &script, &todo)?;
        if !o.quiet {
            eprintln!(
                "submitted Slurm job {id}: {} run(s){}",
                todo.len(),
                if attempt > 0 { " again" } else { "" }
            );
        }
        if o.no_wait {
            if !o.quiet {
                eprintln!(
                    "when it has finished: mapc sweep collect {}",
                    crate::ui::shown(o.out)
                );
            }
            return Ok(Outcome::Submitted);
        }
        wait(&id)?;
        todo.retain(|&i| !done(i));
        if todo.is_empty() {
            break;
        }
        if !o.quiet {
            eprintln!(
                "{} run(s) failed (logs in {}){}",
                todo.len(),
                crate::ui::shown(&o.out.join("slurm")),
                if attempt == 0 {
                    "; resubmitting them once"
                } else {
                    ""
                }
            );
        }
    }
    Ok(Outcome::Finished)
}

#[cfg(test)]
mod tests {
    #[test]
    fn array_lists_use_ranges() {
        assert_eq!(super::array_list(&[0, 1, 2, 3, 5, 7, 8, 9]), "0-3,5,7-9");
        assert_eq!(super::array_list(&[4]), "4");
    }
}
