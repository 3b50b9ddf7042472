//! `mapc convert IN OUT`: `.building.yaml` (or `.project.yaml`) ↔ rmf_site `.site.json`,
//! the formats taken from the file names. Frontend errors stop it (the map is incomplete);
//! validation findings do not (converting a map with a lane problem is fine) but are
//! reported. What the target format cannot say is a W0122 warning naming the element.
//! Exit codes: 0 ok, 1 invalid input, 2 usage or I/O error.

use crate::{emit, load_and_check, output, summary_line, DiagOpts, Format};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct ConvertArgs {
    /// The map to read: a .building.yaml, .project.yaml or .site.json.
    input: PathBuf,
    /// The file to write: a .site.json or a .building.yaml.
    output: PathBuf,
    #[command(flatten)]
    diag: DiagOpts,
}

enum Target {
    Site,
    Building,
}

fn target(p: &Path) -> Option<Target> {
    let name = p.file_name()?.to_string_lossy().to_lowercase();
    if name.ends_with(".site.json") {
        Some(Target::Site)
    } else if name.ends_with(".building.yaml") {
        Some(Target::Building)
    } else {
        None
    }
}

pub(crate) fn run(args: &ConvertArgs) -> ExitCode {
    let Some(target) = target(&args.output) else {
        eprintln!(
            "error: `{}`: OUTPUT must end in .site.json or .building.yaml (the format is taken from the name)",
            output::shown(&args.output)
        );
        return ExitCode::from(2);
    };
    if args.output.is_dir() {
        eprintln!(
            "error: `{}` is a directory; OUTPUT must be a file",
            output::shown(&args.output)
        );
        return ExitCode::from(2);
    }
    let mut checked = match load_and_check(&args.input, &args.diag.lints) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let building = match checked.parsed.building.as_ref() {
        Some(b) if !checked.parsed.has_errors() => b,
        _ => {
            emit(&checked, &args.diag, crate::report::Style::Snippets);
            eprintln!("error: {}: nothing written", output::shown(&args.input));
            return ExitCode::from(1);
        }
    };
    let (text, diags) = match target {
        Target::Site => mapc_backends::site_json(building),
        Target::Building => mapc_backends::building_yaml(building),
    };
    checked.extend(diags);
    emit(&checked, &args.diag, crate::report::Style::Snippets);
    if args.diag.format == Format::Human {
        summary_line(&args.input, &checked);
    }
    if let Err(e) = output::write_atomic(&args.output, text.as_bytes()) {
        eprintln!("error: {}: {e}", output::shown(&args.output));
        return ExitCode::from(2);
    }
    if !args.diag.quiet {
        eprintln!(
            "{}: converted to {}",
            output::shown(&args.input),
            output::shown(&args.output)
        );
    }
    ExitCode::SUCCESS
}
