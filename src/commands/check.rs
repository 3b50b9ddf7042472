//! `mapc check MAP...`: every problem of every map, nothing written.

use crate::driver::{self, CliError, DiagOpts, Outcome};
use crate::ui::{report::Style, shown, Format};
use mapc_ir::lints::Outputs;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub(crate) struct CheckArgs {
    /// The .building.yaml (or legacy .project.yaml) files to read.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    #[command(flatten)]
    diag: DiagOpts,
}

pub(crate) fn run(args: &CheckArgs) -> Result<Outcome, CliError> {
    let opts = &args.diag;
    let mut result = Ok(Outcome::Done);
    let mut all = Vec::new();
    for input in &args.inputs {
        match driver::load_and_check(input, &opts.lints) {
            Ok(c) => {
                if !c.blocked(Outputs::ALL).is_empty() && result.is_ok() {
                    result = Err(CliError::InvalidReported);
                }
                if opts.format != Format::Sarif {
                    driver::emit(&c, opts, Style::Snippets);
                }
                if opts.format == Format::Human {
                    driver::summary_line(input, &c);
                }
                // A clean map is said out loud too (problems have their count line).
                if c.diagnostics.is_empty() && !opts.quiet {
                    eprintln!("{}: no problems found", shown(input));
                }
                all.push(c);
            }
            Err(e) => {
                // Said now, in order; the other maps are still checked.
                crate::ui::error(e);
                result = Err(CliError::UsageReported);
            }
        }
    }
    if opts.format == Format::Sarif {
        driver::print_sarif(&all, opts.max_diagnostics);
    }
    result
}
