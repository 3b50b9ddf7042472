//! How many diagnostics are shown: at most `--max-diagnostics` per code (20 by default,
//! clang's `-ferror-limit`), the rest counted. Every format then states, per code that
//! was cut, the true total (human: one line; JSON: a summary record; SARIF: a tool
//! notification), so the output grows with what a person can read, not with the map.

use mapc_ir::Diagnostic;
use std::collections::BTreeMap;
use std::str::FromStr;

/// Diagnostics shown per code when `--max-diagnostics` is not given.
pub const DEFAULT_PER_CODE: usize = 20;

/// `--max-diagnostics N|all`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaxDiagnostics {
    PerCode(usize),
    All,
}

impl Default for MaxDiagnostics {
    fn default() -> Self {
        MaxDiagnostics::PerCode(DEFAULT_PER_CODE)
    }
}

impl FromStr for MaxDiagnostics {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s.eq_ignore_ascii_case("all") {
            return Ok(MaxDiagnostics::All);
        }
        s.parse::<usize>()
            .map(MaxDiagnostics::PerCode)
            .map_err(|_| format!("expected a number or `all`, found `{s}`"))
    }
}

/// A code whose diagnostics were not all shown.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CodeCount {
    pub code: &'static str,
    pub found: usize,
    pub shown: usize,
}

/// The diagnostics to show (in their order) and, in code order, the codes that were cut.
pub fn select(diags: &[Diagnostic], max: MaxDiagnostics) -> (Vec<&Diagnostic>, Vec<CodeCount>) {
    let limit = match max {
        MaxDiagnostics::All => usize::MAX,
        MaxDiagnostics::PerCode(n) => n,
    };
    let mut counts: BTreeMap<&'static str, (usize, usize)> = BTreeMap::new();
    let mut shown = Vec::new();
    for d in diags {
        let c = counts.entry(d.code).or_default();
        c.0 += 1;
        if c.1 < limit {
            c.1 += 1;
            shown.push(d);
        }
    }
    let cut = counts
        .into_iter()
        .filter(|(_, (found, shown))| found > shown)
        .map(|(code, (found, shown))| CodeCount { code, found, shown })
        .collect();
    (shown, cut)
}

/// "W0207 unconnected-near-waypoints: 24,878 found, 20 shown; --max-diagnostics all to see
/// them".
pub fn summary_text(c: &CodeCount) -> String {
    format!(
        "{} {}: {} found, {} shown; --max-diagnostics all to see them",
        c.code,
        crate::codes::code_name(c.code),
        mapc_ir::count_text(c.found),
        mapc_ir::count_text(c.shown),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use mapc_ir::Span;

    fn diags(codes: &[&'static str]) -> Vec<Diagnostic> {
        codes
            .iter()
            .map(|c| Diagnostic::warning(c, Span::default(), "m"))
            .collect()
    }

    #[test]
    fn caps_per_code_and_counts_the_rest() {
        let d = diags(&["W0207", "W0208", "W0207", "W0207", "E0101"]);
        let (shown, cut) = select(&d, MaxDiagnostics::PerCode(2));
        let codes: Vec<_> = shown.iter().map(|d| d.code).collect();
        assert_eq!(codes, ["W0207", "W0208", "W0207", "E0101"]);
        assert_eq!(
            cut,
            [CodeCount {
                code: "W0207",
                found: 3,
                shown: 2
            }]
        );
        let (shown, cut) = select(&d, MaxDiagnostics::All);
        assert_eq!((shown.len(), cut.len()), (5, 0));
        let (shown, cut) = select(&d, MaxDiagnostics::PerCode(0));
        assert_eq!((shown.len(), cut.len()), (0, 3));
    }

    #[test]
    fn parses_the_flag() {
        assert_eq!("all".parse(), Ok(MaxDiagnostics::All));
        assert_eq!("7".parse(), Ok(MaxDiagnostics::PerCode(7)));
        assert!("-1".parse::<MaxDiagnostics>().is_err());
        assert!("many".parse::<MaxDiagnostics>().is_err());
    }

    #[test]
    fn summary_line() {
        let c = CodeCount {
            code: "W0207",
            found: 24_878,
            shown: 20,
        };
        assert_eq!(
            summary_text(&c),
            "W0207 unconnected-near-waypoints: 24,878 found, 20 shown; --max-diagnostics all \
             to see them"
        );
    }
}
