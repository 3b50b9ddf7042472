//! The one shape of every command that compiles one map: read and check it, produce the
//! files only when no error breaks the command's outputs (the gate), report, refuse when
//! blocked or suspiciously empty, and write.

use super::check::{load_and_check, Checked, Ready};
use super::opts::DiagOpts;
use super::output::{self, Written};
use super::produce::map_name;
use super::report::{emit, not_written, success_line, summary_line};
use super::{CliError, Outcome};
use crate::ui::{plural, report::Style, Format};
use mapc_backends::OutputFile;
use mapc_ir::lints::Outputs;
use mapc_ir::Diagnostic;
use std::path::Path;

/// A single-map command, for its gate and its messages.
pub(crate) struct Spec {
    /// Subcommand name (also names the manifest).
    pub name: &'static str,
    /// The output argument, as `--help` names it.
    pub role: &'static str,
    /// What the command exists to write, singular ("nav graph").
    pub kind: &'static str,
    /// Why a map can truly have none of them (`None`: writing none is no failure).
    pub none: Option<&'static str>,
    /// The outputs the command writes (what errors must not break).
    pub outputs: Outputs,
    /// How diagnostics are shown without `--verbose`: the drop-ins of
    /// `building_map_generator` print one line each, as build logs expect.
    pub style: Style,
}

/// What a command's producer made of a cleared map.
pub(crate) struct Product<F> {
    pub files: F,
    /// Found while producing (texture warnings): they join the report.
    pub diagnostics: Vec<Diagnostic>,
    /// How many of the command's kind (`Spec::kind`) the files hold.
    pub count: usize,
}

/// A map compiled and cleared for writing.
pub(crate) struct Compiled<F> {
    pub checked: Checked,
    pub files: F,
    pub count: usize,
    /// The map's name in messages and manifests.
    pub label: String,
}

/// Reads and checks `input`; unless an error breaks `spec.outputs`, `produce` makes the
/// files; reports; fails (exit 1, said) when an error blocks the outputs, or when none of
/// the command's kind was made while keys were ignored (probably a typo: a map that truly
/// has none, with nothing ignored, is fine).
pub(crate) fn compile<F>(
    input: &Path,
    opts: &DiagOpts,
    spec: &Spec,
    produce: impl FnOnce(Ready) -> Product<F>,
) -> Result<Compiled<F>, CliError> {
    let mut checked = load_and_check(input, &opts.lints)?;
    let product = checked.ready(spec.outputs).map(produce);
    let mut made = None;
    if let Some(p) = product {
        checked.extend(p.diagnostics);
        made = Some((p.files, p.count));
    }
    emit(&checked, opts, spec.style);
    if opts.format == Format::Human {
        summary_line(input, &checked);
    }
    if !checked.blocked(spec.outputs).is_empty() {
        // One output: when any part is blocked, nothing is written.
        not_written(input, &checked, spec.outputs, spec.outputs);
        return Err(CliError::InvalidReported);
    }
    let Some((files, count)) = made else {
        // Not reached: an unread map blocks every output.
        return Err(CliError::InvalidReported);
    };
    let label = map_name(input);
    if let Some(none) = spec.none {
        let ignored = checked.ignored_codes();
        if count == 0 && !ignored.is_empty() {
            return Err(CliError::Invalid(format!(
                "{label}: no {} written: {none}, but keys were ignored (see the warnings \
                 above); nothing written; {}",
                spec.kind,
                super::ways_out(input, &opts.lints, &ignored)
            )));
        }
    }
    Ok(Compiled {
        checked,
        files,
        count,
        label,
    })
}

/// A single-map command whose files all go to one directory (`nav`, `gltf`, `meshes`):
/// [`compile`], then one atomic write with its manifest, then the success line.
pub(crate) fn compile_into(
    input: &Path,
    out_dir: &Path,
    opts: &DiagOpts,
    spec: &Spec,
    produce: impl FnOnce(Ready) -> Product<Vec<OutputFile>>,
) -> Result<Outcome, CliError> {
    super::sanity::output_dir(out_dir, spec.role)?;
    let c = compile(input, opts, spec, produce)?;
    let w = output::single_write(out_dir, spec.role, &c.files, spec.name, &c.label)?;
    if !opts.quiet {
        if let (0, Some(none)) = (c.count, spec.none) {
            eprintln!("{}: no {} written: {none}", c.label, spec.kind);
        }
        finished(&c, &plural(c.count, spec.kind), out_dir, w);
    }
    Ok(Outcome::Done)
}

/// The success line of a compiled map.
pub(crate) fn finished<F>(c: &Compiled<F>, what: &str, dir: &Path, w: Written) {
    success_line(&c.label, what, dir, w, c.checked.diagnostics.len());
}
