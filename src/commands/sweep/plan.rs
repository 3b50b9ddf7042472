//! From a sweep spec to runs: each run's scenario is the base scenario's text with the
//! axes' values spliced in where the paths point (everything else, comments included, stays
//! as written) and `map` rewritten relative to the run's directory, so that
//! `mapc sim OUT/runs/<run>/scenario.yaml` is the same run. Every run is checked (scenario
//! parser, then placement on the map) before anything runs; problems caused by an axis
//! value are reported at that value in the sweep file.

use super::spec::{Axis, Spec};
use crate::codes::sweep as codes;
use crate::driver::{load_and_check, Checked, LintOpts};
use mapc_frontend::yaml_tree::{self, Node};
use mapc_frontend::SourceFile;
use mapc_ir::{Diagnostic, FileId};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

/// Where an axis writes in the base scenario's text.
#[derive(Clone, Debug)]
enum Target {
    /// Replace the value at these bytes.
    Replace { start: usize, end: usize },
    /// Add `key: value` to a mapping that lacks the key.
    Insert {
        at: usize,
        key: String,
        /// Flow mapping (`{...}`): `, key: v` before the `}`; `first`: it is empty.
        flow: bool,
        first: bool,
        indent: usize,
    },
}

impl Target {
    fn at(&self) -> usize {
        match self {
            Target::Replace { start, .. } => *start,
            Target::Insert { at, .. } => *at,
        }
    }
}

/// A map read and checked once, shared by every run on it.
pub(crate) struct LoadedMap {
    pub checked: Checked,
}

impl LoadedMap {
    pub fn building(&self) -> &mapc_ir::Building {
        self.checked
            .parsed
            .building
            .as_ref()
            .expect("maps are only kept when their building is usable")
    }
}

pub(crate) struct Run {
    pub index: usize,
    /// Directory name under OUT/runs (zero-padded index).
    pub name: String,
    /// Value index per axis of the spec.
    pub choice: Vec<usize>,
    /// The variant scenario.
    pub text: String,
    /// Index into `Plan::maps`.
    pub map: usize,
    /// SHA-256 of what determines the run: mapc's version, the scenario, the map files.
    pub inputs: String,
    /// Byte ranges of the spliced values in `text`, per axis (for diagnostics).
    placed: Vec<(usize, usize, usize, bool)>,
}

pub(crate) struct Plan {
    pub spec: Spec,
    pub runs: Vec<Run>,
    pub maps: Vec<LoadedMap>,
}

/// What went wrong while planning: already reported; the exit code to return.
pub(crate) struct Failed(pub u8);

/// Diagnostics to print, grouped by the file table their spans refer to.
#[derive(Default)]
pub(crate) struct Report {
    pub groups: Vec<(Vec<SourceFile>, Vec<Diagnostic>)>,
}

impl Report {
    pub fn emit(&self) {
        for (sources, diags) in &self.groups {
            let all: Vec<&Diagnostic> = diags.iter().collect();
            crate::ui::report::emit(sources, &all, &[], crate::ui::report::Style::Snippets);
        }
    }
    pub fn errors(&self) -> usize {
        self.groups
            .iter()
            .flat_map(|(_, d)| d)
            .filter(|d| d.is_error())
            .count()
    }
}

pub(crate) fn run_name(index: usize, count: usize) -> String {
    let width = count.saturating_sub(1).to_string().len().max(4);
    format!("{index:0width$}")
}

/// Plans the sweep in `sweep` (already read as `text`) for output directory `out`. With
/// `only`, only that run is checked on the map (a cluster task runs one run).
pub(crate) fn plan(
    sweep: &Path,
    text: &str,
    out: &Path,
    lints: &LintOpts,
    only: Option<usize>,
    report: &mut Report,
) -> Result<Plan, Failed> {
    let sweep_name = crate::ui::shown(sweep);
    let sweep_src = vec![SourceFile {
        name: sweep_name.clone(),
        text: text.to_string(),
    }];
    let (spec, diags) = super::spec::parse(sweep, text, FileId(0));
    let Some(spec) = spec else {
        report.groups.push((sweep_src, diags));
        return Err(Failed(1));
    };
    let mut sweep_diags = diags;

    // The base scenario, which must be valid on its own.
    let scen_name = crate::ui::shown(&spec.scenario);
    let base_text = match std::fs::read_to_string(&spec.scenario) {
        Ok(t) => t,
        Err(e) => {
            sweep_diags.push(Diagnostic::error(
                codes::SWEEP_INVALID.code,
                spec.scenario_span,
                format!("cannot read the scenario `{scen_name}`: {e}"),
            ));
            report.groups.push((sweep_src, sweep_diags));
            return Err(Failed(1));
        }
    };
    let scen_dir = spec
        .scenario
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .to_path_buf();
    let (base, base_diags) = mapc_sim::parse_scenario(FileId(0), &base_text, &scen_dir);
    if base.is_none() {
        report.groups.push((
            vec![SourceFile {
                name: scen_name,
                text: base_text,
            }],
            base_diags,
        ));
        eprintln!("error: {sweep_name}: the base scenario is invalid, nothing run");
        return Err(Failed(1));
    }
    let root = match yaml_tree::parse(&base_text, FileId(0)) {
        Ok(r) => r,
        Err(_) => return Err(Failed(1)), // parse_scenario accepted it: never reached
    };

    // Where each axis writes; `map` is handled below.
    let mut targets: Vec<Option<Target>> = Vec::new();
    for a in &spec.axes {
        match resolve(&root, &base_text, &a.path) {
            Ok(t) => targets.push(Some(t)),
            Err((msg, help)) => {
                let mut d = Diagnostic::error(codes::UNKNOWN_AXIS.code, a.span, msg);
                if let Some(h) = help {
                    d = d.with_help(h);
                }
                sweep_diags.push(d);
                targets.push(None);
            }
        }
    }
    overlaps(&spec.axes, &mut targets, &mut sweep_diags);
    // The map: the sweep's `map`, else an axis on `map`, else the scenario's.
    let map_axis = spec.axes.iter().position(|a| a.path == "map");
    if let (Some(i), true) = (map_axis, spec.map.is_some()) {
        sweep_diags.push(Diagnostic::error(
            codes::OVERLAPPING_AXES.code,
            spec.axes[i].span,
            "the sweep file's `map` already sets the map",
        ));
    }
    let base_map = root
        .get("map")
        .and_then(|m| m.key_text())
        .map(|m| scen_dir.join(m));
    if spec.map.is_none() && map_axis.is_none() && base_map.is_none() {
        sweep_diags.push(
            Diagnostic::error(
                codes::SWEEP_INVALID.code,
                spec.scenario_span,
                "neither the sweep file nor its scenario names a `map`",
            )
            .with_help("add `map: FILE` to the sweep file or to the scenario"),
        );
    }
    // Without a map nothing can be checked further; bad axes are left out of the runs
    // below (they are reported), so that the values of the others are checked too.
    if spec.map.is_none() && map_axis.is_none() && base_map.is_none() {
        report.groups.push((sweep_src, sweep_diags));
        return Err(Failed(1));
    }
    let map_target = match map_axis {
        Some(i) => targets[i].clone(),
        None => resolve(&root, &base_text, "map").ok(),
    };
    let Some(map_target) = map_target else {
        return Err(Failed(1)); // resolving a top-level key never fails
    };

    // The runs' texts and maps. All run directories are at the same depth, so the map's
    // path relative to them is the same for every run on that map.
    let count = spec.run_count();
    let runs_dir = absolute(&out.join("runs").join(run_name(0, count)));
    // Files the scenario names relative to itself (fleets' `config`, `requests`), re-pointed
    // from the run directories, unless an axis sets them.
    let mut file_paths: Vec<String> = Vec::new();
    if let Some(fleets) = root.get("fleets").and_then(Node::as_seq) {
        for (i, f) in fleets.iter().enumerate() {
            if f.get("config").and_then(Node::key_text).is_some() {
                file_paths.push(format!("fleets.{i}.config"));
            }
        }
    }
    match root.get("requests") {
        Some(r) if r.as_map().is_some() => file_paths.push("requests.file".into()),
        Some(r) if r.key_text().is_some() => file_paths.push("requests".into()),
        _ => {}
    }
    let mut file_targets: Vec<(Target, String)> = Vec::new();
    for path in file_paths {
        let set_by_axis = spec.axes.iter().any(|a| {
            a.path == path
                || (path.starts_with("fleets.")
                    && a.path.starts_with("fleets.")
                    && a.path.ends_with(".config"))
        });
        let value = path
            .split('.')
            .try_fold(&root, |n, seg| match seg.parse::<usize>() {
                Ok(k) => n.as_seq().and_then(|s| s.get(k)),
                Err(_) => n.get(seg),
            })
            .and_then(Node::key_text)
            .map(str::to_string);
        if let (false, Some(v), Ok(t)) = (set_by_axis, value, resolve(&root, &base_text, &path)) {
            let rel = relative(&runs_dir, &absolute(&scen_dir.join(v)));
            file_targets.push((t, yaml_string(&rel)));
        }
    }
    let mut map_index: BTreeMap<PathBuf, usize> = BTreeMap::new();
    let mut map_paths: Vec<PathBuf> = Vec::new();
    let mut runs = Vec::with_capacity(count);
    for index in 0..count {
        let choice = spec.choice(index);
        let map = match (&spec.map, map_axis) {
            (Some(m), _) => m.clone(),
            (None, Some(i)) => {
                let v = &spec.axes[i].values[choice[i]];
                scen_dir.join(v.json.as_str().unwrap_or(&v.text))
            }
            (None, None) => base_map.clone().unwrap_or_default(),
        };
        let rel = relative(&runs_dir, &absolute(&map));
        let mi = *map_index.entry(map.clone()).or_insert_with(|| {
            map_paths.push(map.clone());
            map_paths.len() - 1
        });
        let mut edits: Vec<(usize, &Target, String)> = Vec::new();
        for (ai, (a, t)) in spec.axes.iter().zip(&targets).enumerate() {
            if Some(ai) == map_axis {
                continue;
            }
            if let Some(t) = t {
                edits.push((ai, t, a.values[choice[ai]].text.clone()));
            }
        }
        edits.push((usize::MAX, &map_target, yaml_string(&rel)));
        for (t, v) in &file_targets {
            edits.push((usize::MAX, t, v.clone()));
        }
        let (text, placed) = splice(&base_text, &mut edits);
        runs.push(Run {
            index,
            name: run_name(index, count),
            choice,
            text,
            map: mi,
            inputs: String::new(),
            placed,
        });
    }

    // The maps, checked like `mapc sim` checks them.
    let mut maps = Vec::new();
    for path in map_paths {
        let checked = match load_and_check(&path, lints) {
            Ok(c) => c,
            Err(e) => {
                crate::ui::error(e);
                return Err(Failed(2));
            }
        };
        let usable = checked.parsed.building.is_some()
            && checked
                .blocked(mapc_ir::lints::Outputs::NAV.union(mapc_ir::lints::Outputs::WORLDS))
                .is_empty();
        if !usable {
            let errors: Vec<Diagnostic> = checked
                .diagnostics
                .iter()
                .filter(|d| d.is_error())
                .cloned()
                .collect();
            report.groups.push((checked.parsed.sources.clone(), errors));
            eprintln!(
                "error: {}: invalid map, nothing run",
                crate::ui::shown(&path)
            );
            return Err(Failed(1));
        }
        maps.push(LoadedMap { checked });
    }
    // The files the scenario names (fleet configs, requests) are inputs too: a changed
    // config reruns the runs.
    let named: String = mapc_sim::parse_scenario_files(FileId(0), &base_text, &scen_dir)
        .included
        .iter()
        .map(|i| i.text.as_str())
        .collect();
    for r in &mut runs {
        r.inputs = inputs_hash(
            &format!("{}{named}", r.text),
            &maps[r.map].checked.parsed.sources,
        );
    }

    // Every run (or the one asked for) checked: the scenario parser, then placement.
    let mut remapped: Vec<Diagnostic> = Vec::new();
    let mut other_groups = 0;
    for r in runs.iter().filter(|r| only.is_none_or(|i| i == r.index)) {
        let m = &maps[r.map];
        let sid = FileId(m.checked.parsed.sources.len() as u32);
        let run_dir = absolute(&out.join("runs").join(&r.name));
        let (scenario, mut diags) = mapc_sim::parse_scenario(sid, &r.text, &run_dir);
        if let Some(s) = &scenario {
            let opts = mapc_sim::RunOptions {
                until: Some(0.0),
                ..Default::default()
            };
            if let Err(mapc_sim::SimError::Invalid(d)) = mapc_sim::simulate(m.building(), s, opts) {
                diags.extend(d);
            }
        }
        let mut left = Vec::new();
        for d in diags {
            let seen = |nd: &Diagnostic| {
                remapped
                    .iter()
                    .chain(&sweep_diags)
                    .any(|x| x.code == nd.code && x.span == nd.span && x.message == nd.message)
            };
            match remap(&spec, r, sid, &d) {
                Some(nd) if !seen(&nd) => remapped.push(nd),
                Some(_) => {}
                None if d.is_error() => left.push(d),
                None => {}
            }
        }
        if !left.is_empty() {
            other_groups += 1;
            // The same problem usually repeats in every run: show the first few.
            if other_groups <= 3 {
                let mut sources = m.checked.parsed.sources.clone();
                sources.push(SourceFile {
                    name: format!("{scen_name} (run {}: {})", r.name, describe(&spec, r)),
                    text: r.text.clone(),
                });
                report.groups.push((sources, left));
            }
        }
    }
    sweep_diags.extend(remapped);
    sweep_diags.sort_by_key(|d| (d.span.start, d.span.end));
    if !sweep_diags.is_empty() {
        report.groups.push((sweep_src, sweep_diags));
    }
    if other_groups > 0 || report.errors() > 0 {
        if other_groups > 3 {
            eprintln!("({} more runs have errors)", other_groups - 3);
        }
        return Err(Failed(1));
    }
    Ok(Plan { spec, runs, maps })
}

/// `fleets.tinyRobot.count=4, seed=2`: the run's axis values.
pub(crate) fn describe(spec: &Spec, r: &Run) -> String {
    spec.axes
        .iter()
        .zip(&r.choice)
        .filter(|(a, _)| !a.fixed)
        .map(|(a, &c)| format!("{}={}", a.path, a.values[c].text))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A diagnostic of run `r` that lies in a spliced value, reported at that value in the
/// sweep file (file 0).
fn remap(spec: &Spec, r: &Run, sid: FileId, d: &Diagnostic) -> Option<Diagnostic> {
    if d.span.file != sid {
        return None;
    }
    let (s, e) = (d.span.start as usize, d.span.end as usize);
    let &(ai, _, _, inserted) = r
        .placed
        .iter()
        .find(|&&(_, ps, pe, _)| s >= ps && e <= pe && s < pe.max(ps + 1))?;
    // (Edits of no axis, such as re-pointed file paths, are left as they are.)
    let axis = spec.axes.get(ai)?;
    let value = &axis.values[r.choice[ai]];
    let unknown_key = d.code == mapc_sim::codes::UNKNOWN_KEY.code;
    if !d.is_error() && !unknown_key {
        return None;
    }
    let out = if unknown_key && inserted {
        Diagnostic::error(
            codes::UNKNOWN_AXIS.code,
            axis.span,
            format!("`{}`: {}", axis.path, d.message),
        )
    } else {
        Diagnostic::error(
            codes::AXIS_VALUE.code,
            value.span,
            format!(
                "`{}: {}`: {} ({})",
                axis.path, value.text, d.message, d.code
            ),
        )
    };
    Some(match &d.help {
        Some(h) => out.with_help(h.clone()),
        None => out,
    })
}

/// Two axes writing the same place.
fn overlaps(axes: &[Axis], targets: &mut [Option<Target>], diags: &mut Vec<Diagnostic>) {
    for i in 0..axes.len() {
        for j in 0..i {
            let clash = match (&targets[i], &targets[j]) {
                (Some(a), Some(b)) => clashes(a, b),
                _ => false,
            };
            if !clash {
                continue;
            }
            // Only the first of the two is applied (the same path twice is reported by
            // the spec already).
            targets[i] = None;
            if axes[i].path != axes[j].path {
                diags.push(
                    Diagnostic::error(
                        codes::OVERLAPPING_AXES.code,
                        axes[i].span,
                        format!(
                            "`{}` changes the same place of the scenario as `{}`",
                            axes[i].path, axes[j].path
                        ),
                    )
                    .with_label(axes[j].span, "the other axis")
                    .with_help("keep one; to vary two values together, put both in `zip`"),
                );
            }
        }
    }
}

fn clashes(a: &Target, b: &Target) -> bool {
    let range = |t: &Target| match t {
        Target::Replace { start, end } => (*start, *end),
        Target::Insert { at, .. } => (*at, *at),
    };
    match (a, b) {
        (Target::Insert { at: x, key: k, .. }, Target::Insert { at: y, key: l, .. }) => {
            x == y && k == l
        }
        _ => {
            let ((s1, e1), (s2, e2)) = (range(a), range(b));
            // Inserting at the very end of a replaced value is inside it too.
            (s1 < e2 && s2 < e1)
                || (s1 == e1 && s2 < s1 && s1 <= e2)
                || (s2 == e2 && s1 < s2 && s2 <= e1)
        }
    }
}

/// Applies `edits` (axis index, target, text) to `base`; returns the text and where each
/// axis's value landed: (axis, start, end, inserted).
fn splice(
    base: &str,
    edits: &mut [(usize, &Target, String)],
) -> (String, Vec<(usize, usize, usize, bool)>) {
    edits.sort_by_key(|(ai, t, _)| (t.at(), *ai));
    let mut out = String::with_capacity(base.len() + 64);
    let mut placed = Vec::new();
    let mut pos = 0;
    for (ai, t, value) in edits.iter() {
        match t {
            Target::Replace { start, end } => {
                out.push_str(&base[pos..*start]);
                let s = out.len();
                out.push_str(value);
                placed.push((*ai, s, out.len(), false));
                pos = *end;
            }
            Target::Insert {
                at,
                key,
                flow,
                first,
                indent,
            } => {
                out.push_str(&base[pos..*at]);
                pos = *at;
                let s = out.len();
                if *flow {
                    if !*first {
                        out.push_str(", ");
                    }
                    out.push_str(&format!("{key}: {value}"));
                } else {
                    if !out.is_empty() && !out.ends_with('\n') {
                        out.push('\n');
                    }
                    out.push_str(&format!("{}{key}: {value}\n", " ".repeat(*indent)));
                }
                placed.push((*ai, s, out.len(), true));
            }
        }
    }
    out.push_str(&base[pos..]);
    (out, placed)
}

/// Where `path` points in the scenario `root` (text `text`). Items of lists are addressed
/// by index or by their `name`.
fn resolve(root: &Node, text: &str, path: &str) -> Result<Target, (String, Option<String>)> {
    let segs: Vec<&str> = path.split('.').collect();
    let mut node = root;
    for (i, seg) in segs.iter().enumerate() {
        let last = i + 1 == segs.len();
        let here = if i == 0 {
            "the scenario".to_string()
        } else {
            format!("`{}`", segs[..i].join("."))
        };
        if let Some(entries) = node.as_map() {
            match entries.iter().rev().find(|(k, _)| k.key_text() == Some(seg)) {
                Some((_, v)) if last => {
                    return Ok(Target::Replace {
                        start: v.span.start as usize,
                        end: v.span.end as usize,
                    })
                }
                Some((_, v)) => node = v,
                None if last => return Ok(insert_target(node, text, seg)),
                None => {
                    return Err((
                        format!("{here} has no `{seg}`"),
                        Some(format!(
                            "add `{seg}` to the base scenario first; an axis can only add the last key of its path"
                        )),
                    ))
                }
            }
        } else if let Some(items) = node.as_seq() {
            let found = match seg.parse::<usize>() {
                Ok(k) => items.get(k),
                Err(_) => items
                    .iter()
                    .find(|it| it.get("name").and_then(Node::key_text) == Some(seg)),
            };
            let names: Vec<String> = items
                .iter()
                .enumerate()
                .map(|(k, it)| match it.get("name").and_then(Node::key_text) {
                    Some(n) => format!("`{n}`"),
                    None => k.to_string(),
                })
                .collect();
            match found {
                Some(v) if last => {
                    return Ok(Target::Replace {
                        start: v.span.start as usize,
                        end: v.span.end as usize,
                    })
                }
                Some(v) => node = v,
                None => {
                    let help = match mapc_frontend::spelling::nearest(
                        seg,
                        items
                            .iter()
                            .filter_map(|it| it.get("name").and_then(Node::key_text)),
                    ) {
                        Some(n) => format!("did you mean `{n}`?"),
                        None => format!(
                            "its items are {} (by name or by index 0..{})",
                            names.join(", "),
                            items.len()
                        ),
                    };
                    return Err((
                        format!("{here} has no item `{seg}` (named or numbered)"),
                        Some(help),
                    ));
                }
            }
        } else {
            return Err((
                format!("{here} is {}, which has no `{seg}`", node.type_name()),
                None,
            ));
        }
    }
    Err(("an empty path".into(), None))
}

fn insert_target(map: &Node, text: &str, key: &str) -> Target {
    let entries = map.as_map().unwrap_or(&[]);
    let (s, e) = (map.span.start as usize, map.span.end as usize);
    let flow = text.as_bytes().get(s) == Some(&b'{');
    if flow {
        let close = text[s..e.min(text.len())].rfind('}').map_or(e, |k| s + k);
        return Target::Insert {
            at: close,
            key: key.into(),
            flow: true,
            first: entries.is_empty(),
            indent: 0,
        };
    }
    let indent = entries
        .first()
        .map_or(0, |(k, _)| k.span.col.saturating_sub(1) as usize);
    // After the line on which the mapping's last value ends.
    let end = entries
        .last()
        .map_or(e, |(_, v)| v.span.end as usize)
        .min(text.len());
    let at = if end > 0 && text.as_bytes()[end - 1] == b'\n' {
        end
    } else {
        text[end..].find('\n').map_or(text.len(), |k| end + k + 1)
    };
    Target::Insert {
        at,
        key: key.into(),
        flow: false,
        first: false,
        indent,
    }
}

/// The path as a YAML scalar: plain when it is safe, single-quoted otherwise.
fn yaml_string(p: &Path) -> String {
    let s = p.to_string_lossy();
    let plain = !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "._/-+".contains(c))
        && !s.starts_with('-');
    if plain {
        s.into_owned()
    } else {
        format!("'{}'", s.replace('\'', "''"))
    }
}

/// `p` made absolute (against the current directory) and normalised lexically.
pub(crate) fn absolute(p: &Path) -> PathBuf {
    let abs = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let mut out = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// The path from directory `from` to `to` (both absolute and normalised).
fn relative(from: &Path, to: &Path) -> PathBuf {
    let f: Vec<Component> = from.components().collect();
    let t: Vec<Component> = to.components().collect();
    if f.first() != t.first() {
        return to.to_path_buf();
    }
    let common = f.iter().zip(&t).take_while(|(a, b)| a == b).count();
    // Nothing shared but the root: the absolute path says more than a chain of `..`.
    if common <= 1 {
        return to.to_path_buf();
    }
    let mut out = PathBuf::new();
    for _ in common..f.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c);
    }
    out
}

/// What decides a run's result: mapc's version, the variant scenario and every map file
/// read (a legacy project file and its building).
fn inputs_hash(scenario: &str, map_sources: &[SourceFile]) -> String {
    let mut h = Sha256::new();
    h.update(b"mapc ");
    h.update(env!("CARGO_PKG_VERSION").as_bytes());
    h.update(b"\0");
    h.update((scenario.len() as u64).to_le_bytes());
    h.update(scenario.as_bytes());
    for s in map_sources {
        h.update((s.text.len() as u64).to_le_bytes());
        h.update(s.text.as_bytes());
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edit(base: &str, path: &str, value: &str) -> String {
        let root = yaml_tree::parse(base, FileId(0)).unwrap();
        let t = resolve(&root, base, path).unwrap();
        splice(base, &mut [(0, &t, value.to_string())]).0
    }

    #[test]
    fn replaces_and_inserts_in_block_and_flow_style() {
        let base = "seed: 1 # the seed\nduration: 1h\nfleets:\n  - {name: a, robot: TinyRobot, count: 2}\n  - name: b\n    robot: TinyRobot\n";
        assert_eq!(
            edit(base, "seed", "7"),
            base.replace("seed: 1 #", "seed: 7 #")
        );
        assert_eq!(
            edit(base, "fleets.a.count", "8"),
            base.replace("count: 2", "count: 8")
        );
        assert_eq!(
            edit(base, "fleets.0.spawn", "auto"),
            base.replace("count: 2}", "count: 2, spawn: auto}")
        );
        assert_eq!(
            edit(base, "fleets.b.count", "3"),
            format!("{base}    count: 3\n")
        );
        assert_eq!(edit(base, "step", "0.02"), format!("{base}step: 0.02\n"));
        // A key added to a mapping whose last value is a block list, before the next item.
        let nested =
            "fleets:\n  - name: a\n    tasks:\n      - loop\n      - clean\n  - name: b\nseed: 1\n";
        assert_eq!(
            edit(nested, "fleets.a.count", "2"),
            nested.replace("- clean\n", "- clean\n    count: 2\n")
        );
        let nested_flow = "fleets:\n  - name: a\n    robot:\n      preset: TinyRobot\n      footprint: 0.3\nseed: 1\n";
        assert_eq!(
            edit(nested_flow, "fleets.a.robot.speed", "1"),
            nested_flow.replace("0.3\n", "0.3\n      speed: 1\n")
        );
        let quoted = "duration: '1h'\nfleets: []\n";
        assert_eq!(edit(quoted, "duration", "2h"), "duration: 2h\nfleets: []\n");
    }

    #[test]
    fn unknown_paths_say_what_exists() {
        let base = "fleets:\n  - {name: tinyRobot, robot: TinyRobot}\n";
        let root = yaml_tree::parse(base, FileId(0)).unwrap();
        let (msg, help) = resolve(&root, base, "fleets.tinyRobots.count").unwrap_err();
        assert_eq!(msg, "`fleets` has no item `tinyRobots` (named or numbered)");
        assert_eq!(help.as_deref(), Some("did you mean `tinyRobot`?"));
        let (msg, _) = resolve(&root, base, "options.clean_duration").unwrap_err();
        assert_eq!(msg, "the scenario has no `options`");
        let (msg, _) = resolve(&root, base, "fleets.0.name.x").unwrap_err();
        assert_eq!(msg, "`fleets.0.name` is a string, which has no `x`");
    }

    #[test]
    fn relative_paths_between_directories() {
        assert_eq!(
            relative(Path::new("/a/out/runs/0000"), Path::new("/a/maps/m.yaml")),
            PathBuf::from("../../../maps/m.yaml")
        );
        assert_eq!(
            absolute(Path::new("/a/b/../c/./d")),
            PathBuf::from("/a/c/d")
        );
    }
}
