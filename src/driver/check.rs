//! Reading a map and checking it: the frontend, every validation pass, the user's lint
//! levels, and the gate between a checked map and the backends.

use super::lints::{self, Lints};
use super::opts::LintOpts;
use super::sanity;
use crate::codes;
use crate::ui::shown;
use mapc_frontend::codes as fc;
use mapc_ir::lints::Outputs;
use mapc_ir::{Building, Diagnostic};
use std::path::Path;

/// A map read and checked: frontend diagnostics plus validation passes, at the user's
/// lint levels.
pub(crate) struct Checked {
    pub parsed: mapc_frontend::Parsed,
    pub diagnostics: Vec<Diagnostic>,
    lints: Lints,
}

/// A building cleared for some outputs: no error at the user's levels breaks them. Only
/// [`Checked::ready`] makes one, and every file producer of the driver takes one, so a
/// map that was not checked (or whose errors break an output) cannot reach a backend.
#[derive(Clone, Copy)]
pub(crate) struct Ready<'a> {
    building: &'a Building,
    outputs: Outputs,
}

impl<'a> Ready<'a> {
    pub(crate) fn building(&self) -> &'a Building {
        self.building
    }

    /// Panics unless `o` was cleared: a producer asked for an output the gate refused.
    pub(crate) fn require(&self, o: Outputs) -> &'a Building {
        assert!(
            self.outputs.intersection(o) == o,
            "an output was produced although errors block it"
        );
        self.building
    }
}

impl Checked {
    /// The outputs of `wanted` that the remaining errors break (all of them when the map
    /// could not be read).
    pub(crate) fn blocked(&self, wanted: Outputs) -> Outputs {
        let Some(b) = &self.parsed.building else {
            return wanted;
        };
        let mut blocked = Outputs::NONE;
        for d in self.diagnostics.iter().filter(|d| d.is_error()) {
            let p = codes::policy(d.code);
            let mut blocks = if p.can_allow { p.blocks } else { Outputs::ALL };
            if p.nav_only_with_lanes && b.lanes.is_empty() {
                blocks = blocks.without(Outputs::NAV);
            }
            blocked = blocked.union(blocks);
        }
        blocked.intersection(wanted)
    }

    /// The building, cleared for `wanted`, when it was read and no error breaks any of
    /// `wanted`.
    pub(crate) fn ready(&self, wanted: Outputs) -> Option<Ready<'_>> {
        let building = self.parsed.building.as_ref()?;
        self.blocked(wanted).is_empty().then_some(Ready {
            building,
            outputs: wanted,
        })
    }

    /// Adds diagnostics found while producing output (texture warnings), at the user's
    /// levels.
    pub(crate) fn extend(&mut self, mut diags: Vec<Diagnostic>) {
        self.lints.apply(&mut diags);
        self.diagnostics.extend(diags);
    }

    /// The codes of what the frontend ignored that could have held missing outputs: an
    /// unknown key (W0103), a likely typo (E0112); empty when nothing was.
    pub(crate) fn ignored_codes(&self) -> Vec<&'static str> {
        [&fc::UNKNOWN_KEY, &fc::LIKELY_TYPO]
            .into_iter()
            .filter(|c| self.diagnostics.iter().any(|d| c.is(d)))
            .map(|c| c.code)
            .collect()
    }

    pub(crate) fn errors(&self) -> usize {
        self.diagnostics.iter().filter(|d| d.is_error()).count()
    }
}

/// The lint levels for `input`: the command line's over those of `--config` or of the
/// mapc.toml found for the map. `Err` is a usage error (exit 2).
pub(crate) fn lints_for(input: &Path, opts: &LintOpts) -> Result<Lints, String> {
    let cli = lints::from_flags(&opts.allow, &opts.warn, &opts.deny, opts.deny_warnings)?;
    let file = match &opts.config {
        Some(path) => Some(lints::from_file(path)?),
        None => match lints::discover(input) {
            Some(path) => Some(lints::from_file(&path)?),
            None => None,
        },
    };
    Ok(Lints::new(cli, file))
}

/// Frontend errors after which positions are in unknown units: an unknown coordinate
/// system, an unknown reference level, a wgs84 map without a CRS, a zero-length measurement.
const UNITS_UNKNOWN: [&mapc_ir::Code; 4] = [
    &fc::UNKNOWN_COORDINATE_SYSTEM,
    &fc::UNKNOWN_LEVEL,
    &fc::CRS,
    &fc::DEGENERATE_ALIGNMENT,
];

/// The frontend's diagnostics plus those of every validation pass (before lint levels).
pub(crate) fn all_diagnostics(parsed: &mapc_frontend::Parsed) -> Vec<Diagnostic> {
    let mut diagnostics = parsed.diagnostics.clone();
    // Passes run even after frontend errors so one run reports everything it can, except
    // those whose inputs the errors left unknown: they would only report consequences
    // (a 224 m wide door in a map whose pixels were taken for metres).
    let units_unknown = diagnostics
        .iter()
        .any(|d| UNITS_UNKNOWN.iter().any(|c| c.is(d)));
    // The rules that compare positions with thresholds in metres (`Rule::metric`).
    let metric = |d: &Diagnostic| codes::find(d.code).is_some_and(|e| e.metric);
    if let Some(b) = &parsed.building {
        diagnostics.extend(
            mapc_ir::validate(b)
                .into_iter()
                .filter(|d| !(units_unknown && metric(d))),
        );
    }
    diagnostics
}

/// Reads a map and runs every validation pass, at the user's lint levels. `Err` is an I/O
/// or usage problem (exit 2).
pub(crate) fn load_and_check(input: &Path, opts: &LintOpts) -> Result<Checked, String> {
    sanity::map_input(input)?;
    let lints = lints_for(input, opts)?;
    let mut parsed = mapc_frontend::load(input).map_err(|e| {
        // The frontend names the file as given; print it without `./` noise.
        e.to_string()
            .replace(&input.display().to_string(), &shown(input))
    })?;
    for s in &mut parsed.sources {
        s.name = shown(Path::new(&s.name));
    }
    let mut diagnostics = all_diagnostics(&parsed);
    lints.apply(&mut diagnostics);
    Ok(Checked {
        parsed,
        diagnostics,
        lints,
    })
}
