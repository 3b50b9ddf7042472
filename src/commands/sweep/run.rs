//! One run of a sweep: the variant scenario simulated by the same library calls as
//! `mapc sim`, and OUT/runs/<run>/{scenario.yaml, report.json, inputs.sha256} written. The
//! stamp (`inputs.sha256`, the run's inputs hash) is written last and removed first, so a
//! run directory with a matching stamp always holds that run's complete result.

use super::plan::{absolute, Plan, Run};
use crate::driver::output;
use mapc_ir::FileId;
use std::path::{Path, PathBuf};

pub(crate) const STAMP: &str = "inputs.sha256";

pub(crate) fn run_dir(out: &Path, name: &str) -> PathBuf {
    out.join("runs").join(name)
}

/// The run's directory holds the result of exactly these inputs.
pub(crate) fn up_to_date(out: &Path, name: &str, inputs: &str) -> bool {
    let dir = run_dir(out, name);
    std::fs::read_to_string(dir.join(STAMP)).is_ok_and(|s| s.trim() == inputs)
        && dir.join("report.json").is_file()
}

/// Simulates `r` and writes its directory.
pub(crate) fn execute(plan: &Plan, r: &Run, out: &Path) -> Result<(), String> {
    let dir = run_dir(out, &r.name);
    let m = &plan.maps[r.map];
    let (scenario, _) = mapc_sim::parse_scenario(FileId(0), &r.text, &absolute(&dir));
    let scenario = scenario.ok_or_else(|| format!("run {}: invalid scenario", r.name))?;
    let report = match mapc_sim::simulate(m.building(), &scenario, Default::default()) {
        Ok(rep) => rep,
        Err(mapc_sim::SimError::Invalid(_)) => {
            return Err(format!("run {}: the scenario does not fit the map", r.name))
        }
        Err(mapc_sim::SimError::Io(e)) => return Err(format!("run {}: {e}", r.name)),
    };
    // As `mapc sim --report` writes it, so the two files are byte-identical.
    let mut json = serde_json::to_vec_pretty(&report).map_err(|e| e.to_string())?;
    json.push(b'\n');
    let err = |p: &Path, e: std::io::Error| format!("{}: {e}", crate::ui::shown(p));
    std::fs::create_dir_all(&dir).map_err(|e| err(&dir, e))?;
    output::sweep_temporaries(&dir);
    let stamp = dir.join(STAMP);
    match std::fs::remove_file(&stamp) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(err(&stamp, e)),
        _ => {}
    }
    for (name, bytes) in [
        ("scenario.yaml", r.text.as_bytes()),
        ("report.json", &json[..]),
        (STAMP, format!("{}\n", r.inputs).as_bytes()),
    ] {
        let p = dir.join(name);
        output::write_atomic(&p, bytes).map_err(|e| err(&p, e))?;
    }
    Ok(())
}
