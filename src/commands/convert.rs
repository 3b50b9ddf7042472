//! `mapc convert IN OUT`: `.building.yaml` (or `.project.yaml`) ↔ rmf_site `.site.json`,
//! the formats taken from the file names. Frontend errors stop it (the map is incomplete);
//! validation findings do not (converting a map with a lane problem is fine) but are
//! reported. What the target format cannot say is a W0122 warning naming the element.
//! Exit codes: 0 ok, 1 invalid input, 2 usage or I/O error.

use crate::driver::{emit, load_and_check, output, summary_line, CliError, DiagOpts, Outcome};
use crate::ui::{report::Style, shown, Format};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub(crate) struct ConvertArgs {
    /// The map to read: a .building.yaml, .project.yaml or .site.json.
    input: PathBuf,
    // The file to write (a .site.json or a .building.yaml), positional or `-o`.
    #[command(flatten)]
    output: super::OutputFile,
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

pub(crate) fn run(args: &ConvertArgs) -> Result<Outcome, CliError> {
    let out = args.output.path()?;
    let Some(target) = target(out) else {
        return Err(CliError::Usage(format!(
            "`{}`: OUTPUT must end in .site.json or .building.yaml (the format is taken from the name)",
            shown(out)
        )));
    };
    if out.is_dir() {
        return Err(CliError::Usage(format!(
            "`{}` is a directory; OUTPUT must be a file",
            shown(out)
        )));
    }
    let mut checked = load_and_check(&args.input, &args.diag.lints)?;
    // The gate of a conversion: frontend errors only (the map is incomplete); what the
    // validation passes find is carried over, as the source has it.
    let building = match checked.parsed.building.as_ref() {
        Some(b) if !checked.parsed.has_errors() => b,
        _ => {
            emit(&checked, &args.diag, Style::Snippets);
            return Err(CliError::Invalid(format!(
                "{}: nothing written",
                shown(&args.input)
            )));
        }
    };
    let (text, diags) = match target {
        Target::Site => mapc_backends::site_json(building),
        Target::Building => mapc_backends::building_yaml(building),
    };
    checked.extend(diags);
    emit(&checked, &args.diag, Style::Snippets);
    if args.diag.format == Format::Human {
        summary_line(&args.input, &checked);
    }
    output::write_atomic(out, text.as_bytes())
        .map_err(|e| CliError::Usage(format!("{}: {e}", shown(out))))?;
    if !args.diag.quiet {
        eprintln!("{}: converted to {}", shown(&args.input), shown(out));
    }
    Ok(Outcome::Done)
}
