//! Scenario files: what to simulate on a map (fleets, workcells, tasks, duration, seed).
//! Read with the frontend's located YAML tree so that every problem gets file:line:col.
//! Here: the scenario's types and the entry points; the reader (`P`) has a file per part
//! (`read`: its primitives, `document`, `fleet`, `task`, `include`, `faults`, `requests`,
//! `rmf_config`).

use crate::codes::{self, Code};
use crate::params::RobotParams;
use mapc_frontend::yaml_tree::{self, Node, Scalar};
use mapc_ir::{Diagnostic, FileId, Span};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

mod document;
mod faults;
mod fleet;
mod include;
mod read;
mod requests;
mod rmf_config;
mod task;
pub use faults::{FaultSpec, FaultTarget};
pub(crate) use requests::{accept_requests, task_ids, RequestOutcome};
pub use requests::{RequestKind, RequestSpec, RequestedTask};
pub use rmf_config::{Finishing, RmfFleet, RmfRobot};

#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The map, resolved against the scenario file's directory (None if the scenario does
    /// not name one; then `--map` must).
    pub map: Option<PathBuf>,
    pub seed: u64,
    /// Simulated time to run (s).
    pub duration: f64,
    /// Physics step (s), default 0.01 as in generated worlds.
    pub step: f64,
    pub fleets: Vec<FleetSpec>,
    pub workcells: Vec<WorkcellSpec>,
    pub tasks: Vec<TaskSpec>,
    pub generators: Vec<GeneratorSpec>,
    /// Things out of service for a while (`faults.rs`).
    pub faults: Vec<FaultSpec>,
    pub options: SimOptions,
    /// RMF task API requests (`requests:`, `requests.rs`), in file order.
    pub requests: Vec<RequestSpec>,
    /// Tasks cancelled while the run goes (`cancel_task_request`s, once accepted).
    pub cancels: Vec<CancelSpec>,
}

/// A task cancelled at `at` (s): taken off the queue, or stopped where its robot is.
#[derive(Debug, Clone, PartialEq)]
pub struct CancelSpec {
    pub at: f64,
    pub task_id: String,
}

#[derive(Debug, Clone, PartialEq)]
pub struct FleetSpec {
    pub name: String,
    /// Nav graph index the fleet drives on.
    pub graph: i64,
    pub robot: RobotParams,
    pub count: usize,
    pub spawn: SpawnSpec,
    /// Go charging when the state of charge falls below this (0..1).
    pub recharge_threshold: f64,
    /// Leave the charger when charged to this (0..1).
    pub recharge_soc: f64,
    /// Task categories this fleet accepts (empty: all).
    pub task_kinds: Vec<TaskCategory>,
    pub span: Span,
    /// What the fleet's RMF adapter config says beyond the above (`config:`): its robots'
    /// names and start waypoints above all.
    pub rmf: Option<Box<RmfFleet>>,
}

/// A file a scenario names (a fleet's `config:`): its diagnostics have file id
/// `scenario's id + 1 + its index` in [`Parsed::included`].
#[derive(Debug, Clone, PartialEq)]
pub struct Included {
    pub path: PathBuf,
    pub text: String,
    /// The scenario's node that names it.
    pub from: Span,
}

/// A scenario read with the files it names.
#[derive(Debug)]
pub struct Parsed {
    pub scenario: Option<Scenario>,
    pub diagnostics: Vec<Diagnostic>,
    pub included: Vec<Included>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum SpawnSpec {
    /// The map's spawn waypoints (`spawn_robot_type` params); with a robot type filter
    /// when the fleet names one of the map's robot types.
    MapSpawnPoints,
    /// Named waypoints, one per robot (cycled if fewer than `count`? no: must be enough).
    Waypoints(Vec<String>),
    /// Free waypoints chosen by the runtime: chargers, parking spots, holding points, then
    /// any vertex, in graph order, never two robots on one.
    Auto,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TaskCategory {
    Loop,
    Delivery,
    Clean,
    GoToPlace,
}

impl TaskCategory {
    pub fn as_str(self) -> &'static str {
        match self {
            TaskCategory::Loop => "loop",
            TaskCategory::Delivery => "delivery",
            TaskCategory::Clean => "clean",
            TaskCategory::GoToPlace => "go_to_place",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WorkcellKind {
    Dispenser,
    Ingestor,
}

/// A teleport dispenser or ingestor placed at a waypoint (in addition to the map's
/// `TeleportDispenser`/`TeleportIngestor` models).
#[derive(Debug, Clone, PartialEq)]
pub struct WorkcellSpec {
    pub name: String,
    pub kind: WorkcellKind,
    pub waypoint: String,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum TaskKind {
    Loop {
        start: String,
        finish: String,
        loops: u32,
    },
    Delivery {
        pickup: String,
        dropoff: String,
        /// Defaults: the waypoint's `pickup_dispenser` / `dropoff_ingestor` param.
        dispenser: Option<String>,
        ingestor: Option<String>,
    },
    Clean {
        zone: String,
    },
    GoToPlace {
        place: String,
    },
    /// RMF's patrol of three places or more: each in order, `rounds` times (a loop of the
    /// task category `loop`).
    Patrol {
        places: Vec<String>,
        rounds: u32,
    },
}

impl TaskKind {
    pub fn category(&self) -> TaskCategory {
        match self {
            TaskKind::Loop { .. } | TaskKind::Patrol { .. } => TaskCategory::Loop,
            TaskKind::Delivery { .. } => TaskCategory::Delivery,
            TaskKind::Clean { .. } => TaskCategory::Clean,
            TaskKind::GoToPlace { .. } => TaskCategory::GoToPlace,
        }
    }

    /// The waypoints the task names, in order.
    pub fn places(&self) -> Vec<&str> {
        match self {
            TaskKind::Loop { start, finish, .. } => vec![start, finish],
            TaskKind::Delivery {
                pickup, dropoff, ..
            } => vec![pickup, dropoff],
            TaskKind::Clean { zone } => vec![zone],
            TaskKind::GoToPlace { place } => vec![place],
            TaskKind::Patrol { places, .. } => places.iter().map(String::as_str).collect(),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct TaskSpec {
    /// Request time (s).
    pub at: f64,
    pub kind: TaskKind,
    /// Restrict to one fleet (default: any fleet that accepts the category).
    pub fleet: Option<String>,
    /// Only this robot (of `fleet`) may do it: an RMF `robot_task_request`.
    pub robot: Option<String>,
    /// RMF's binary priority: a task of priority 1 goes before every task of priority 0
    /// still waiting.
    pub priority: u64,
    pub span: Span,
}

/// "A task every `every` seconds from `start` until `end`".
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratorSpec {
    pub every: f64,
    pub start: f64,
    pub end: Option<f64>,
    pub kind: TaskKind,
    pub fleet: Option<String>,
    pub span: Span,
}

impl GeneratorSpec {
    /// The request times within a run of `duration` s: none for a generator whose times are
    /// not finite or not increasing (validation reports those), at most a million.
    pub fn times(&self, duration: f64) -> impl Iterator<Item = f64> + '_ {
        let valid = self.every.is_finite() && self.start.is_finite() && self.every > 0.0;
        let end = self.end.unwrap_or(duration).min(duration);
        (0..=1_000_000u64)
            .take_while(move |_| valid)
            .map(move |k| self.start + k as f64 * self.every)
            .take_while(move |&at| at <= end)
    }
}

/// Switches for behaviours of the upstream plugins flagged as quirks in the runtime spec.
/// The defaults are the intended behaviour.
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    /// Start lift cabins at their initial floor (true) or, like Gazebo, at z = 0 and drive
    /// there first (false; runtime spec §4.2).
    pub lifts_start_at_initial_floor: bool,
    /// Cleaning time at a cleaning zone when the map has no cleaning path (s).
    pub clean_duration: f64,
    /// End the run as soon as every task has ended (instead of running to `duration`).
    pub stop_when_done: bool,
    /// The toggle_charging GUI's switches, for every robot (runtime spec §1.9, §8): robots
    /// charge at chargers, charge instantly, and their batteries drain.
    pub charging: bool,
    pub instant_charging: bool,
    pub battery_drain: bool,
    /// The scenario's top-level `crowd` (read there, kept here with the other switches).
    pub crowd: CrowdOptions,
}

/// The scenario's `crowd: {enabled, scale}`: whether the map's crowd (when its crowd_sim is
/// enabled) walks, and a factor on the size of every human group.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrowdOptions {
    pub enabled: bool,
    pub scale: f64,
}

impl Default for CrowdOptions {
    fn default() -> Self {
        CrowdOptions {
            enabled: true,
            scale: 1.0,
        }
    }
}

/// Largest `crowd.scale`.
pub const MAX_CROWD_SCALE: f64 = 1000.0;

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            lifts_start_at_initial_floor: true,
            clean_duration: 60.0,
            stop_when_done: false,
            charging: true,
            instant_charging: false,
            battery_drain: true,
            crowd: CrowdOptions::default(),
        }
    }
}

/// Largest fleet (and largest total of robots) a scenario may ask for.
pub const MAX_ROBOTS: i64 = 10_000;
/// Longest run (s): one year.
pub const MAX_DURATION: f64 = 365.0 * 24.0 * 3600.0;
/// Most task requests (listed plus generated) and most loops in one task.
pub const MAX_TASKS: f64 = 1_000_000.0;
/// Largest step (s); see S0107.
pub const MAX_STEP: f64 = 0.1;

const TOP_KEYS: &[&str] = &[
    "map",
    "seed",
    "duration",
    "step",
    "fleets",
    "workcells",
    "tasks",
    "generators",
    "faults",
    "options",
    "crowd",
    "description",
    "requests",
];
const CROWD_KEYS: &[&str] = &["enabled", "scale"];
const FLEET_KEYS: &[&str] = &[
    "config",
    "name",
    "graph",
    "robot",
    "count",
    "spawn",
    "recharge_threshold",
    "recharge_soc",
    "tasks",
];
const WORKCELL_KEYS: &[&str] = &["name", "kind", "waypoint"];
const TASK_KEYS: &[&str] = &["at", "fleet"];
const GENERATOR_KEYS: &[&str] = &["every", "start", "end", "fleet"];
const KINDS: &[&str] = &["loop", "delivery", "clean", "go_to_place"];
const OPTION_KEYS: &[&str] = &[
    "lifts_start_at_initial_floor",
    "clean_duration",
    "stop_when_done",
    "charging",
    "instant_charging",
    "battery_drain",
];

/// Parses a duration: a number of seconds, or `<number><unit>` parts with units `d`, `h`,
/// `min`, `s`, `ms` (`1h30min`, `2.5h`, `90s`), optionally separated by spaces.
pub fn parse_duration(text: &str) -> Result<f64, String> {
    let t = text.trim();
    if t.is_empty() {
        return Err("the duration is empty".into());
    }
    if let Ok(v) = t.parse::<f64>() {
        if t.chars().all(|c| c.is_ascii_digit() || c == '.') {
            return Ok(v);
        }
    }
    let b = t.as_bytes();
    let mut i = 0;
    let mut total = 0.0;
    while i < b.len() {
        while i < b.len() && b[i] == b' ' {
            i += 1;
        }
        let start = i;
        while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
            i += 1;
        }
        let num = &t[start..i];
        let ustart = i;
        while i < b.len() && b[i].is_ascii_alphabetic() {
            i += 1;
        }
        let unit = &t[ustart..i];
        if num.is_empty() {
            return Err(format!("expected a number at `{}`", &t[start..]));
        }
        let v: f64 = num
            .parse()
            .map_err(|_| format!("`{num}` is not a number"))?;
        let scale = match unit {
            "d" => 86_400.0,
            "h" => 3600.0,
            "min" => 60.0,
            "s" => 1.0,
            "ms" => 0.001,
            "" => {
                return Err(format!(
                    "`{num}` has no unit; numbers in a duration string need one"
                ))
            }
            "m" => return Err("`m` is ambiguous; write `min` for minutes".into()),
            u => return Err(format!("unknown unit `{u}`")),
        };
        total += v * scale;
        while i < b.len() && b[i] == b' ' {
            i += 1;
        }
    }
    Ok(total)
}

/// Levenshtein distance, for "did you mean" hints on short names.
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// The closest of `names` to `word`, when close enough to be a likely typo.
fn closest<'n>(word: &str, names: impl IntoIterator<Item = &'n str>) -> Option<&'n str> {
    let w = word.to_ascii_lowercase();
    names
        .into_iter()
        .map(|n| (distance(&w, &n.to_ascii_lowercase()), n))
        .filter(|(d, n)| *d <= 2.max(n.len() / 3))
        .min_by_key(|(d, _)| *d)
        .map(|(_, n)| n)
}

fn list(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A mapping's entries with their key text (keys that are not strings are reported).
struct Entries<'n, 'a> {
    span: Span,
    items: Vec<(&'n str, &'n Node<'a>, &'n Node<'a>)>,
}

impl<'n, 'a> Entries<'n, 'a> {
    /// The last value of `key` (duplicates are warned about when the entries are read).
    fn get(&self, key: &str) -> Option<&'n Node<'a>> {
        self.items.iter().rev().find(|e| e.0 == key).map(|e| e.2)
    }
}

/// Most diagnostics reported for one scenario; the rest are counted (S0002). A garbage
/// file can have a problem per node, and a million rendered diagnostics help nobody.
pub const MAX_DIAGNOSTICS: usize = 1000;

struct P<'d> {
    diags: &'d mut Vec<Diagnostic>,
    /// The scenario's file id; included files follow it.
    file: FileId,
    /// The scenario's directory (included files are relative to it).
    base: PathBuf,
    included: Vec<Included>,
    /// `--requests FILE`: read instead of the scenario's `requests`.
    requests: Option<PathBuf>,
    /// Diagnostics past MAX_DIAGNOSTICS, not kept.
    suppressed: usize,
    /// Where diagnostics past the limit are written (and forgotten).
    scratch: Diagnostic,
    had_error: bool,
}

fn category(s: &str) -> Option<TaskCategory> {
    Some(match s {
        "loop" => TaskCategory::Loop,
        "delivery" => TaskCategory::Delivery,
        "clean" => TaskCategory::Clean,
        "go_to_place" => TaskCategory::GoToPlace,
        _ => return None,
    })
}

/// Reads a scenario. `base` is the scenario file's directory (for `map`). Returns the
/// scenario when there are no errors, and all diagnostics (warnings too). Problems in the
/// files the scenario names (a fleet's `config:`) are reported at the scenario's node that
/// names the file, their own position in the message; [`parse_files`] keeps them located
/// in those files.
pub fn parse(file: FileId, text: &str, base: &Path) -> (Option<Scenario>, Vec<Diagnostic>) {
    let p = parse_files(file, text, base);
    let mut diags = p.diagnostics;
    for d in &mut diags {
        let k = d.span.file.0.wrapping_sub(file.0 + 1) as usize;
        if d.span.file != file && k < p.included.len() {
            let inc = &p.included[k];
            d.message = format!(
                "{}:{}:{}: {}",
                inc.path.display(),
                d.span.line,
                d.span.col,
                d.message
            );
            d.span = inc.from;
            d.labels.retain(|l| l.span.file == file);
        }
    }
    (p.scenario, diags)
}

/// Like [`parse`], with the files the scenario names: their diagnostics have file ids
/// after `file` (see [`Included`]).
pub fn parse_files(file: FileId, text: &str, base: &Path) -> Parsed {
    parse_files_with(file, text, base, None)
}

/// Like [`parse_files`], reading `requests` (a requests file, as `--requests` names it)
/// instead of the scenario's own `requests:`.
pub fn parse_files_with(file: FileId, text: &str, base: &Path, requests: Option<&Path>) -> Parsed {
    let mut diags = Vec::new();
    let done = |scenario, diagnostics| Parsed {
        scenario,
        diagnostics,
        included: Vec::new(),
    };
    let whole = Span {
        file,
        start: 0,
        end: 0,
        line: 1,
        col: 1,
    };
    if text.len() as u64 > mapc_frontend::MAX_FILE_BYTES {
        diags.push(
            Diagnostic::error(
                codes::INPUT_LIMIT.code,
                whole,
                format!(
                    "the file is larger than the input limit of {} bytes",
                    mapc_frontend::MAX_FILE_BYTES
                ),
            )
            .with_help("scenarios are a few dozen lines; check that this is the right file"),
        );
        return done(None, diags);
    }
    let root = match yaml_tree::parse(text, file) {
        Ok(r) => r,
        Err(mut d) => {
            // The reader reports map codes; say it is the scenario's YAML.
            d.code = if d.code == "E0002" {
                codes::INPUT_LIMIT.code
            } else {
                codes::INVALID_YAML.code
            };
            if !d.span.is_known() {
                d.span = whole;
            }
            diags.push(d);
            return done(None, diags);
        }
    };
    if root.is_null() {
        let span = if root.span.is_known() {
            root.span
        } else {
            whole
        };
        diags.push(
            Diagnostic::error(codes::INVALID_YAML.code, span, "the scenario file is empty")
                .with_help("a scenario needs at least `duration` and `fleets`; see docs/sim.md"),
        );
        return done(None, diags);
    }
    let mut p = P {
        diags: &mut diags,
        suppressed: 0,
        scratch: Diagnostic::error("", whole, ""),
        had_error: false,
        file,
        base: base.to_path_buf(),
        included: Vec::new(),
        requests: requests.map(Path::to_path_buf),
    };
    let scenario = p.scenario(&root, base);
    let suppressed = p.suppressed;
    let included = std::mem::take(&mut p.included);
    if suppressed > 0 {
        diags.push(
            Diagnostic::error(
                codes::INPUT_LIMIT.code,
                whole,
                format!(
                    "{suppressed} more problem(s) not shown: a scenario with more than {MAX_DIAGNOSTICS} problems is refused"
                ),
            )
            .with_help("this is probably not a scenario file; fix the problems above first"),
        );
    }
    Parsed {
        scenario,
        diagnostics: diags,
        included,
    }
}

#[cfg(test)]
mod tests;
