//! Validation passes: one rule per file, each with a stable code. A rule's `//!` doc
//! comment (what it means, why it matters, how to fix it, an example) is gathered into
//! docs/diagnostics.md by `cargo test --test docs` (MAPC_UPDATE_DOCS=1 rewrites it).
//!
//! Rules read a [`Building`] that the frontend produced (all handles valid) and never
//! panic; they may assume nothing else (degenerate geometry, duplicate names, ... are
//! exactly what they look for).

mod context;
mod crowd;
mod doors;
mod geometry;
mod grid;
mod lanes;
mod lifts;
mod names;
#[cfg(test)]
pub(crate) mod tests;

pub use context::Context;

use crate::{Building, Diagnostic, Severity};

/// A validation rule.
pub struct Rule {
    /// Stable code, e.g. `E0201`. The letter gives the default severity.
    pub code: &'static str,
    /// Stable kebab-case name, e.g. `lane-self-loop`.
    pub name: &'static str,
    /// One line: what the rule finds.
    pub summary: &'static str,
    /// What an error of this rule breaks, and whether it may be allowed.
    pub group: crate::lints::Group,
    /// The rule compares positions with thresholds in metres (a door's width, how close two
    /// waypoints are): meaningless, and not run, when the frontend could not tell the map's
    /// units.
    pub metric: bool,
    pub check: fn(&Context, &mut Vec<Diagnostic>),
}

impl Rule {
    /// The rule's facts as a [`crate::Code`], as the other crates declare theirs.
    pub fn code(&self) -> crate::Code {
        crate::Code {
            code: self.code,
            name: self.name,
            summary: self.summary,
            group: self.group,
        }
    }

    pub fn severity(&self) -> Severity {
        if self.code.starts_with('E') {
            Severity::Error
        } else {
            Severity::Warning
        }
    }
}

/// Every rule, grouped: lanes (E02xx), doors (E03xx), lifts (E04xx), names and roles
/// (E05xx), geometry and coordinates (E06xx), crowd simulation (E08xx).
pub fn rules() -> impl Iterator<Item = &'static Rule> {
    lanes::RULES
        .iter()
        .chain(doors::RULES)
        .chain(lifts::RULES)
        .chain(names::RULES)
        .chain(geometry::RULES)
        .chain(crowd::RULES)
        .copied()
}

/// Runs every rule; diagnostics come out sorted by position, then code.
pub fn validate(b: &Building) -> Vec<Diagnostic> {
    let ctx = Context::new(b);
    let rules: Vec<&Rule> = rules().collect();
    let mut out = if !(PARALLEL_FROM..PARALLEL_BELOW).contains(&elements(b)) {
        let mut out = Vec::new();
        for rule in &rules {
            (rule.check)(&ctx, &mut out);
        }
        out
    } else {
        run_on_two_threads(&ctx, &rules)
    };
    out.sort_by(|a, b| {
        (a.span.file, a.span.start, a.code, &a.message).cmp(&(
            b.span.file,
            b.span.start,
            b.code,
            &b.message,
        ))
    });
    out
}

/// From this many waypoints, walls, models and doors on, the rules run on two threads
/// (a thread costs about what validating a few hundred elements does; the hotel demo's
/// 800 validate 0.07 ms sooner on two, BENCHMARKS.md); from the second
/// bound on, on one again: two rules then hold their indexes at once, and a huge map's
/// memory is bounded by its size (issue 18) more tightly than its time.
const PARALLEL_FROM: usize = 500;
const PARALLEL_BELOW: usize = 20_000;

fn elements(b: &Building) -> usize {
    b.vertices.len() + b.walls.len() + b.models.len() + b.doors.len()
}

/// The rules on two threads, each taking the next rule not yet taken (their costs differ
/// by orders of magnitude); diagnostics come back in rule order, as one thread gives them.
fn run_on_two_threads(ctx: &Context, rules: &[&Rule]) -> Vec<Diagnostic> {
    // A panicking rule is a bug: `map` surfaces it here.
    let found = crate::par::map(rules, |rule| {
        let mut found = Vec::new();
        (rule.check)(ctx, &mut found);
        found
    });
    found.into_iter().flatten().collect()
}

/// Looks up a rule by code.
pub fn rule(code: &str) -> Option<&'static Rule> {
    rules().find(|r| r.code == code)
}

#[cfg(test)]
mod parallel_tests {
    use super::tests::TestMap;
    use super::*;

    #[test]
    fn two_threads_find_what_one_finds_in_the_same_order() {
        // Past the threshold, with problems for many rules: duplicate names, self loops,
        // lanes doubled, dead ends, walls crossing lanes, waypoints on one spot.
        let mut m = TestMap::new();
        let mut vs = Vec::new();
        for i in 0..1200 {
            let name = format!("w{}", i % 700);
            vs.push(m.vertex(&name, (i % 37) as f64 * 0.5, (i / 37) as f64 * 0.5));
        }
        for i in 0..vs.len() - 1 {
            m.lane(vs[i], vs[i + 1], (i % 3) as i64, i % 5 != 0);
            if i % 11 == 0 {
                m.lane(vs[i], vs[i], 0, true);
                m.lane(vs[i], vs[i + 1], (i % 3) as i64, true);
            }
            if i % 13 == 0 {
                m.wall(vs[i], vs[(i + 40) % vs.len()]);
            }
        }
        assert!(elements(&m.b) >= PARALLEL_FROM);
        let ctx = Context::new(&m.b);
        let rules: Vec<&Rule> = rules().collect();
        let mut one = Vec::new();
        for rule in &rules {
            (rule.check)(&ctx, &mut one);
        }
        let two = run_on_two_threads(&ctx, &rules);
        assert!(one.len() > 1000, "{} diagnostics", one.len());
        let codes: std::collections::BTreeSet<_> = one.iter().map(|d| d.code).collect();
        assert!(codes.len() >= 4, "{codes:?}");
        assert_eq!(format!("{one:?}"), format!("{two:?}"));
    }
}
