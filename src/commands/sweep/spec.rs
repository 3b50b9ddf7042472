//! The sweep file: a base scenario, fixed settings and axes (dotted paths into the scenario
//! with lists of values). Read with the frontend's located YAML tree, so every problem is a
//! diagnostic at its `file:line:col`; nothing here looks at the scenario yet (plan.rs does).

use crate::codes::sweep as codes;
use mapc_frontend::yaml_tree::{self, Kind, Node, Scalar};
use mapc_ir::{Diagnostic, FileId, Span};
use std::path::{Path, PathBuf};

const TOP_KEYS: &[&str] = &["scenario", "map", "set", "runs", "zip", "description"];

/// Most runs one sweep may have.
pub(crate) const MAX_RUNS: usize = 100_000;

/// One value of an axis, as written in the sweep file.
#[derive(Clone, Debug)]
pub(crate) struct Value {
    /// The source text (one line): what is spliced into the scenario.
    pub text: String,
    /// The value for results.json (numbers stay numbers).
    pub json: serde_json::Value,
    pub span: Span,
}

#[derive(Clone, Debug)]
pub(crate) struct Axis {
    /// Dotted path into the scenario, as written (`fleets.tinyRobot.count`).
    pub path: String,
    pub span: Span,
    pub values: Vec<Value>,
    /// Part of the `zip` group.
    pub zipped: bool,
    /// A `set` entry: one value, applied to every run, not a column.
    pub fixed: bool,
}

pub(crate) struct Spec {
    /// The base scenario, relative to the current directory.
    pub scenario: PathBuf,
    pub scenario_span: Span,
    /// `map:` of the sweep file (overrides the scenario's), relative to the current directory.
    pub map: Option<PathBuf>,
    /// Settings first, then the zip group, then the `runs` axes, in file order.
    pub axes: Vec<Axis>,
}

impl Spec {
    /// The axes that are columns and dimensions (not `set`).
    pub fn varying(&self) -> impl Iterator<Item = &Axis> {
        self.axes.iter().filter(|a| !a.fixed)
    }

    /// Number of runs: the zip group is one dimension, each `runs` axis another.
    pub fn run_count(&self) -> usize {
        self.dimensions().iter().product()
    }

    /// Sizes of the dimensions, outermost first (the zip group, then the `runs` axes).
    pub fn dimensions(&self) -> Vec<usize> {
        let mut dims = Vec::new();
        // The shortest list when the lengths differ (an error, reported; the runs are
        // still built so that their values can be checked too).
        if let Some(z) = self
            .axes
            .iter()
            .filter(|a| a.zipped)
            .map(|a| a.values.len())
            .min()
        {
            dims.push(z);
        }
        dims.extend(
            self.axes
                .iter()
                .filter(|a| !a.fixed && !a.zipped)
                .map(|a| a.values.len()),
        );
        dims
    }

    /// For run `index`, the value index of every axis (settings: 0), in `axes` order. The
    /// last dimension varies fastest.
    pub fn choice(&self, index: usize) -> Vec<usize> {
        let dims = self.dimensions();
        let mut digits = vec![0; dims.len()];
        let mut rest = index;
        for (d, size) in digits.iter_mut().zip(&dims).rev() {
            *d = rest % size;
            rest /= size;
        }
        let zip_dim = usize::from(self.axes.iter().any(|a| a.zipped));
        let mut next_run_dim = zip_dim;
        self.axes
            .iter()
            .map(|a| {
                if a.fixed {
                    0
                } else if a.zipped {
                    digits[0]
                } else {
                    next_run_dim += 1;
                    digits[next_run_dim - 1]
                }
            })
            .collect()
    }
}

fn error(code: &codes::Code, span: Span, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::error(code.code, span, msg)
}

/// Reads the sweep file `path` (text `text`, file id `file`). Paths in it are relative to
/// its directory. Returns the spec when there is no error, and every diagnostic.
pub(crate) fn parse(path: &Path, text: &str, file: FileId) -> (Option<Spec>, Vec<Diagnostic>) {
    let mut diags = Vec::new();
    let whole = Span {
        file,
        start: 0,
        end: 0,
        line: 1,
        col: 1,
    };
    let root = match yaml_tree::parse(text, file) {
        Ok(r) => r,
        Err(mut d) => {
            d.code = codes::SWEEP_INVALID.code;
            if !d.span.is_known() {
                d.span = whole;
            }
            return (None, vec![d]);
        }
    };
    let Some(top) = root.as_map() else {
        let span = if root.span.is_known() {
            root.span
        } else {
            whole
        };
        diags.push(
            error(
                &codes::SWEEP_INVALID,
                span,
                format!("a sweep file must be a mapping, found {}", root.type_name()),
            )
            .with_help("write `scenario: FILE` and `runs:` with the axes; see docs/sweep.md"),
        );
        return (None, diags);
    };
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    for (k, _) in top {
        let name = k.key_text().unwrap_or("");
        if !TOP_KEYS.contains(&name) {
            let mut d = error(
                &codes::SWEEP_INVALID,
                k.span,
                format!("unknown key `{name}` in the sweep file"),
            );
            d = match mapc_frontend::spelling::closest(name, TOP_KEYS) {
                Some(near) => d.with_help(format!("did you mean `{near}`?")),
                None => d.with_help(format!("the keys are {}", TOP_KEYS.join(", "))),
            };
            diags.push(d);
        }
    }
    let scenario = match root.get("scenario") {
        Some(v) => match v.scalar() {
            Some(Scalar::Str(s)) if !s.is_empty() => Some((dir.join(s), v.span)),
            _ => {
                diags.push(error(
                    &codes::SWEEP_INVALID,
                    v.span,
                    format!("`scenario` must be a file path, found {}", v.type_name()),
                ));
                None
            }
        },
        None => {
            diags.push(
                error(
                    &codes::SWEEP_INVALID,
                    whole,
                    "the sweep file names no `scenario`",
                )
                .with_help("add `scenario: base.scenario.yaml` (relative to the sweep file)"),
            );
            None
        }
    };
    let map = match root.get("map") {
        Some(v) => match v.scalar() {
            Some(Scalar::Str(s)) if !s.is_empty() => Some(dir.join(s)),
            _ => {
                diags.push(error(
                    &codes::SWEEP_INVALID,
                    v.span,
                    format!("`map` must be a file path, found {}", v.type_name()),
                ));
                None
            }
        },
        None => None,
    };
    let mut axes = Vec::new();
    if let Some(set) = root.get("set") {
        read_axes(set, "set", text, &mut axes, &mut diags);
    }
    if let Some(zip) = root.get("zip") {
        read_axes(zip, "zip", text, &mut axes, &mut diags);
        let zipped: Vec<&Axis> = axes.iter().filter(|a| a.zipped).collect();
        if let Some(first) = zipped.first() {
            for a in &zipped[1..] {
                if a.values.len() != first.values.len() {
                    diags.push(
                        error(
                            &codes::ZIP_LENGTH,
                            a.span,
                            format!(
                                "`{}` has {} value(s), but `{}` has {}",
                                a.path,
                                a.values.len(),
                                first.path,
                                first.values.len()
                            ),
                        )
                        .with_label(first.span, "the first axis of the group")
                        .with_help(
                            "zipped axes take their values together: give them equally many",
                        ),
                    );
                }
            }
        }
    }
    match root.get("runs") {
        Some(runs) => read_axes(runs, "runs", text, &mut axes, &mut diags),
        None if !axes.iter().any(|a| a.zipped) => diags.push(
            error(&codes::SWEEP_INVALID, whole, "the sweep file has no `runs`")
                .with_help("add `runs:` with at least one axis, e.g. `seed: [1, 2, 3]`"),
        ),
        None => {}
    }
    // Every run gets a directory and a line: a product in the millions is a mistake.
    let runs = axes
        .iter()
        .filter(|a| !a.fixed && !a.zipped)
        .map(|a| a.values.len())
        .chain(
            axes.iter()
                .filter(|a| a.zipped)
                .map(|a| a.values.len())
                .min(),
        )
        .try_fold(1usize, |n, k| n.checked_mul(k))
        .filter(|&n| n <= MAX_RUNS);
    if runs.is_none() {
        let span = root.get("runs").map_or(whole, |r| r.span);
        diags.push(
            error(
                &codes::SWEEP_INVALID,
                span,
                format!("the axes make more than {MAX_RUNS} runs"),
            )
            .with_help("split the study into several sweeps, or use fewer values per axis"),
        );
    }
    for (i, a) in axes.iter().enumerate() {
        if let Some(b) = axes[..i].iter().find(|b| b.path == a.path) {
            diags.push(
                error(
                    &codes::OVERLAPPING_AXES,
                    a.span,
                    format!("`{}` is set twice", a.path),
                )
                .with_label(b.span, "first set here"),
            );
        }
    }
    // Axes that overlap or do not zip are reported with whatever the plan finds next;
    // a file that cannot be read as a sweep stops here.
    if diags.iter().any(|d| d.code == codes::SWEEP_INVALID.code) {
        return (None, diags);
    }
    let Some((scenario, scenario_span)) = scenario else {
        return (None, diags);
    };
    (
        Some(Spec {
            scenario,
            scenario_span,
            map,
            axes,
        }),
        diags,
    )
}

fn read_axes(
    node: &Node,
    section: &str,
    text: &str,
    axes: &mut Vec<Axis>,
    diags: &mut Vec<Diagnostic>,
) {
    let Some(entries) = node.as_map() else {
        diags.push(
            error(
                &codes::SWEEP_INVALID,
                node.span,
                format!(
                    "`{section}` must be a mapping of scenario paths to {}, found {}",
                    if section == "set" {
                        "values"
                    } else {
                        "lists of values"
                    },
                    node.type_name()
                ),
            )
            .with_help(if section == "set" {
                "e.g. `set: {duration: 30min}`"
            } else {
                "e.g. `fleets.tinyRobot.count: [2, 4, 8]` on its own line under it"
            }),
        );
        return;
    };
    if entries.is_empty() && section != "set" {
        diags.push(error(
            &codes::SWEEP_INVALID,
            node.span,
            format!("`{section}` has no axis"),
        ));
    }
    for (k, v) in entries {
        let Some(path) = k.key_text() else {
            diags.push(error(
                &codes::SWEEP_INVALID,
                k.span,
                "an axis must be a dotted path such as `fleets.tinyRobot.count`",
            ));
            continue;
        };
        if path.split('.').any(str::is_empty) {
            diags.push(error(
                &codes::UNKNOWN_AXIS,
                k.span,
                format!("`{path}` has an empty segment"),
            ));
            continue;
        }
        let values: Vec<&Node> = if section == "set" {
            vec![v]
        } else {
            match v.as_seq() {
                Some(s) if !s.is_empty() => s.iter().collect(),
                Some(_) => {
                    diags.push(error(
                        &codes::SWEEP_INVALID,
                        v.span,
                        format!("the axis `{path}` has no values"),
                    ));
                    continue;
                }
                None => {
                    diags.push(
                        error(
                            &codes::SWEEP_INVALID,
                            v.span,
                            format!(
                                "the axis `{path}` must be a list of values, found {}",
                                v.type_name()
                            ),
                        )
                        .with_help("write `[a, b, c]`; a single fixed value goes under `set:`"),
                    );
                    continue;
                }
            }
        };
        let mut vals = Vec::new();
        for n in values {
            match value(n, text) {
                Some(val) => vals.push(val),
                None => diags.push(
                    error(
                        &codes::SWEEP_INVALID,
                        n.span,
                        "an axis value must be written on one line",
                    )
                    .with_help("write lists and mappings in flow style: `[a, b]`, `{x: 1}`"),
                ),
            }
        }
        axes.push(Axis {
            path: path.to_string(),
            span: k.span,
            values: vals,
            zipped: section == "zip",
            fixed: section == "set",
        });
    }
}

/// The value's source text (one line) and its JSON form.
fn value(n: &Node, text: &str) -> Option<Value> {
    let src = text.get(n.span.start as usize..n.span.end as usize)?.trim();
    if src.is_empty() || src.contains('\n') {
        return None;
    }
    let json = match &n.kind {
        Kind::Scalar { .. } => match n.scalar()? {
            Scalar::Null => serde_json::Value::Null,
            Scalar::Bool(b) => serde_json::Value::Bool(b),
            Scalar::Int(i) => serde_json::Value::from(i),
            Scalar::Float(f) => serde_json::Number::from_f64(f)
                .map(serde_json::Value::Number)
                .unwrap_or_else(|| serde_json::Value::String(src.to_string())),
            Scalar::Str(s) => serde_json::Value::String(s.to_string()),
        },
        _ => serde_json::Value::String(src.to_string()),
    };
    Some(Value {
        text: src.to_string(),
        json,
        span: n.span,
    })
}
