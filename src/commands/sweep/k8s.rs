//! The Kubernetes executor writes a manifest and stops: an Indexed Job (`completionMode:
//! Indexed`) with one completion per run; each pod runs `mapc sweep SWEEP -o OUT --run
//! $(JOB_COMPLETION_INDEX)` in /sweep, where a PersistentVolumeClaim holding the sweep,
//! its inputs and OUT is mounted. Runs that are up to date return at once, so applying the
//! Job again redoes only what changed. `mapc sweep collect OUT` gathers the results.

use crate::driver::output;
use std::path::{Path, PathBuf};

/// A YAML double-quoted scalar (JSON string syntax is valid YAML).
fn q(s: &str) -> String {
    serde_json::Value::from(s).to_string()
}

pub(crate) struct Job<'a> {
    pub sweep: &'a Path,
    pub out: &'a Path,
    pub runs: usize,
    pub max_parallel: Option<usize>,
    pub image: &'a str,
    pub claim: &'a str,
    /// The lint options, passed on to every pod.
    pub lint_args: Vec<String>,
}

fn manifest(j: &Job) -> String {
    let (sweep, out, runs, image, claim) = (j.sweep, j.out, j.runs, j.image, j.claim);
    let parallelism = j.max_parallel.unwrap_or(runs).clamp(1, runs.max(1));
    let mut command = vec![
        "mapc".to_string(),
        "sweep".into(),
        crate::ui::shown(sweep),
        "-o".into(),
        crate::ui::shown(out),
        "--run".into(),
        "$(JOB_COMPLETION_INDEX)".into(),
        "--quiet".into(),
    ];
    command.extend(j.lint_args.iter().cloned());
    let command: Vec<String> = command.iter().map(|s| q(s)).collect();
    format!(
        "# One pod per run of a mapc sweep (written by `mapc sweep --executor k8s-manifest`).\n\
         # From the root of the volume claim: kubectl apply -f {manifest}\n\
         # then, when the Job has completed: mapc sweep collect {out}\n\
         apiVersion: batch/v1\n\
         kind: Job\n\
         metadata:\n\
         \x20 name: mapc-sweep\n\
         \x20 labels: {{app.kubernetes.io/name: mapc-sweep}}\n\
         spec:\n\
         \x20 completionMode: Indexed\n\
         \x20 completions: {runs}\n\
         \x20 parallelism: {parallelism}\n\
         \x20 # Each run is retried once, like the Slurm executor's resubmission.\n\
         \x20 backoffLimitPerIndex: 1\n\
         \x20 template:\n\
         \x20   metadata:\n\
         \x20     labels: {{app.kubernetes.io/name: mapc-sweep}}\n\
         \x20   spec:\n\
         \x20     restartPolicy: Never\n\
         \x20     containers:\n\
         \x20       - name: run\n\
         \x20         image: {image}\n\
         \x20         workingDir: /sweep\n\
         \x20         command: [{command}]\n\
         \x20         volumeMounts:\n\
         \x20           - {{name: sweep, mountPath: /sweep}}\n\
         \x20     volumes:\n\
         \x20       - name: sweep\n\
         \x20         persistentVolumeClaim: {{claimName: {claim}}}\n",
        manifest = crate::ui::shown(&out.join("k8s").join("job.yaml")),
        out = crate::ui::shown(out),
        image = q(image),
        command = command.join(", "),
        claim = q(claim),
    )
}

/// Writes OUT/k8s/job.yaml; returns its path.
pub(crate) fn write(j: &Job) -> Result<PathBuf, String> {
    let path = j.out.join("k8s").join("job.yaml");
    let text = manifest(j);
    output::write_atomic(&path, text.as_bytes())
        .map_err(|e| format!("{}: {e}", crate::ui::shown(&path)))?;
    Ok(path)
}
