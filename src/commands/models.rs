//! `mapc models MAP [-e DIR] ...`: the models a map needs, where rmf_demos_maps'
//! CMakeLists.txt runs `building_map_model_downloader MAP -f -e ~/.gazebo/models` after
//! each world. mapc downloads nothing (a build should not reach the network): it lists the
//! names the downloader would fetch from Fuel (every level model's `model_name`, and the
//! crowd's actor models, `model_uri` less its scheme, when crowd_sim is enabled), one per
//! line on stdout, and says on stderr which of them are not under the export directory, so
//! that the build succeeds and the user knows what to fetch (`gz fuel download`, or the
//! real downloader). It accepts the downloader's options so that the same command line works.

use crate::driver::{self, load_readable, CliError, Outcome};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub(crate) struct ModelsArgs {
    /// The .building.yaml (or legacy .project.yaml) to read.
    input: PathBuf,
    /// Where the downloader would put models (classic layout, DIR/<model>/): the models not
    /// found there are named on stderr.
    #[arg(short = 'e', long = "export-path", value_name = "DIR")]
    export_path: Option<PathBuf>,
    /// Searched before the export directory for models already present.
    #[arg(short = 'i', long = "include", value_name = "DIR")]
    include: Option<PathBuf>,
    /// Accepted and ignored (the downloader's deprecated Fuel-tools switch).
    #[arg(short = 'f', long = "fuel-tools")]
    _fuel_tools: bool,
    /// Accepted and ignored (the downloader's pit_crew cache file).
    #[arg(short = 'c', long = "cache", value_name = "FILE")]
    _cache: Option<PathBuf>,
    /// Accepted and ignored (the downloader's deprecated model path).
    #[arg(short = 'm', long = "model-path", value_name = "DIR")]
    _model_path: Option<PathBuf>,
    #[command(flatten)]
    lints: crate::driver::LintOpts,
}

/// The models `b` needs, by the names the map gives them (`Author/Name` or `Name`), sorted.
pub(crate) fn needed(b: &mapc_ir::Building) -> BTreeSet<String> {
    let mut names: BTreeSet<String> = b
        .models
        .iter()
        .map(|(_, m)| m.model_name.trim().to_string())
        .filter(|n| !n.is_empty())
        .collect();
    if let Some(c) = b.crowd_sim.as_ref().filter(|c| c.enable) {
        for t in &c.model_types {
            let uri = t.model_uri.trim();
            let name = uri.rsplit("://").next().unwrap_or(uri);
            if !name.is_empty() {
                names.insert(name.to_string());
            }
        }
    }
    names
}

/// Is `name` (`Author/Name` or `Name`) a model directory under `dir`? The downloader's
/// classic layout drops the author: DIR/<Name>/.
fn present(dir: &Path, name: &str) -> bool {
    let short = name.rsplit('/').next().unwrap_or(name);
    dir.join(short).is_dir() || dir.join(short.to_lowercase()).is_dir()
}

pub(crate) fn run(args: &ModelsArgs) -> Result<Outcome, CliError> {
    // Errors matter (the listing may be incomplete); warnings are `mapc check`'s business.
    let checked = load_readable(&args.input, &args.lints)?;
    let Some(b) = checked.parsed.building.as_ref() else {
        return Err(CliError::InvalidReported);
    };
    let names = needed(b);
    for n in &names {
        println!("{n}");
    }
    let dirs: Vec<&PathBuf> = args.include.iter().chain(&args.export_path).collect();
    let missing: Vec<&String> = if dirs.is_empty() {
        Vec::new()
    } else {
        names
            .iter()
            .filter(|n| !dirs.iter().any(|d| present(d, n)))
            .collect()
    };
    let label = driver::map_name(&args.input);
    eprintln!(
        "{label}: {} model(s) needed; mapc downloads nothing (fetch them with `gz fuel download` or rmf_building_map_tools' building_map_model_downloader)",
        names.len()
    );
    if !missing.is_empty() {
        let dirs: Vec<String> = dirs.iter().map(|d| crate::ui::shown(d)).collect();
        eprintln!(
            "{label}: not found under {}: {}",
            dirs.join(", "),
            missing
                .iter()
                .map(|s| s.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    if checked.errors() > 0 {
        // Said with the listing: it may be incomplete.
        Err(CliError::InvalidReported)
    } else {
        Ok(Outcome::Done)
    }
}
