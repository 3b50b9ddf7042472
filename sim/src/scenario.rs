//! Scenario files: what to simulate on a map (fleets, workcells, tasks, duration, seed).
//! Read with the frontend's located YAML tree so that every problem gets file:line:col.

use crate::codes::{self, Code};
use crate::params::RobotParams;
use mapc_frontend::yaml_tree::{self, Node, Scalar};
use mapc_ir::{Diagnostic, FileId, Span};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

mod faults;
mod requests;
mod rmf_config;
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

/// Robot parameters a `robot:` mapping may set, and whether they must be > 0 (else ≥ 0).
const ROBOT_NUMBERS: &[(&str, bool)] = &[
    ("nominal_drive_speed", true),
    ("nominal_drive_acceleration", true),
    ("max_drive_acceleration", true),
    ("nominal_turn_speed", true),
    ("nominal_turn_acceleration", true),
    ("max_turn_acceleration", true),
    ("stop_distance", false),
    ("stop_radius", false),
    ("nominal_voltage", true),
    ("nominal_capacity", true),
    ("charging_current", false),
    ("mass", true),
    ("inertia", true),
    ("friction_coefficient", false),
    ("nominal_power", false),
    ("footprint", true),
];

fn robot_number<'p>(p: &'p mut RobotParams, key: &str) -> Option<&'p mut f64> {
    Some(match key {
        "nominal_drive_speed" => &mut p.nominal_drive_speed,
        "nominal_drive_acceleration" => &mut p.nominal_drive_acceleration,
        "max_drive_acceleration" => &mut p.max_drive_acceleration,
        "nominal_turn_speed" => &mut p.nominal_turn_speed,
        "nominal_turn_acceleration" => &mut p.nominal_turn_acceleration,
        "max_turn_acceleration" => &mut p.max_turn_acceleration,
        "stop_distance" => &mut p.stop_distance,
        "stop_radius" => &mut p.stop_radius,
        "nominal_voltage" => &mut p.nominal_voltage,
        "nominal_capacity" => &mut p.nominal_capacity,
        "charging_current" => &mut p.charging_current,
        "mass" => &mut p.mass,
        "inertia" => &mut p.inertia,
        "friction_coefficient" => &mut p.friction_coefficient,
        "nominal_power" => &mut p.nominal_power,
        "footprint" => &mut p.footprint,
        _ => return None,
    })
}

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

impl P<'_> {
    fn push(&mut self, d: Diagnostic) -> &mut Diagnostic {
        self.had_error |= d.is_error();
        if self.diags.len() >= MAX_DIAGNOSTICS {
            self.suppressed += 1;
            self.scratch = d;
            return &mut self.scratch;
        }
        self.diags.push(d);
        let last = self.diags.len() - 1;
        &mut self.diags[last]
    }
    fn full(&self) -> bool {
        self.diags.len() >= MAX_DIAGNOSTICS
    }
    fn error(&mut self, code: Code, span: Span, msg: impl Into<String>) -> &mut Diagnostic {
        self.push(Diagnostic::error(code.code, span, msg))
    }
    fn warning(&mut self, code: Code, span: Span, msg: impl Into<String>) -> &mut Diagnostic {
        self.push(Diagnostic::warning(code.code, span, msg))
    }
    /// Sets the help of the diagnostic just reported.
    fn help(&mut self, help: impl Into<String>) {
        if self.suppressed > 0 {
            self.scratch.help = Some(help.into());
        } else if let Some(d) = self.diags.last_mut() {
            d.help = Some(help.into());
        }
    }

    fn wrong_type(&mut self, v: &Node, what: &str, expected: &str) {
        self.error(
            codes::WRONG_TYPE,
            v.span,
            format!("{what} must be {expected}, found {}", v.type_name()),
        );
    }

    /// Reads a mapping; warns about duplicate keys and, when `known` is given, unknown
    /// ones (`unknown_code` picks the warning).
    fn entries<'n, 'a>(
        &mut self,
        v: &'n Node<'a>,
        what: &str,
        known: Option<(&[&str], Code)>,
    ) -> Option<Entries<'n, 'a>> {
        let Some(m) = v.as_map() else {
            self.wrong_type(v, what, "a mapping");
            return None;
        };
        let mut items: Vec<(&'n str, &'n Node<'a>, &'n Node<'a>)> = Vec::with_capacity(m.len());
        // First span of each key: duplicates in O(n log n) even for huge mappings.
        let mut seen: BTreeMap<&'n str, Span> = BTreeMap::new();
        for (k, val) in m {
            let Some(key) = k.key_text() else {
                self.wrong_type(k, &format!("a key of {what}"), "a string");
                continue;
            };
            if let Some(&first_span) = seen.get(key) {
                self.warning(
                    codes::DUPLICATE_KEY,
                    k.span,
                    format!("duplicate key `{key}` in {what}; the last one is used"),
                )
                .labels
                .push(mapc_ir::Label {
                    span: first_span,
                    message: "first defined here".into(),
                });
                self.help("remove one of the two");
            }
            seen.entry(key).or_insert(k.span);
            items.push((key, k, val));
        }
        if let Some((names, code)) = known {
            for (key, k, _) in &items {
                if !names.contains(key) {
                    self.warning(
                        code,
                        k.span,
                        format!("unknown key `{key}` in {what}; it is ignored"),
                    );
                    match closest(key, names.iter().copied()) {
                        Some(c) => self.help(format!("did you mean `{c}`?")),
                        None => self.help(format!("known keys: {}", list(names))),
                    }
                }
            }
        }
        Some(Entries {
            span: v.span,
            items,
        })
    }

    fn required<'n, 'a>(
        &mut self,
        e: &Entries<'n, 'a>,
        key: &str,
        what: &str,
    ) -> Option<&'n Node<'a>> {
        let v = e.get(key);
        if v.is_none() {
            self.error(codes::MISSING_KEY, e.span, format!("{what} has no `{key}`"));
        }
        v
    }

    /// A name: any non-empty scalar but null (`1` is the name "1").
    fn name(&mut self, v: &Node, what: &str) -> Option<String> {
        match v.key_text() {
            Some(t) if !t.trim().is_empty() && v.as_seq().is_none() => Some(t.to_string()),
            _ => {
                self.wrong_type(v, what, "a non-empty name");
                None
            }
        }
    }

    fn number(&mut self, v: &Node, what: &str) -> Option<f64> {
        let Some(x) = v.as_f64() else {
            self.wrong_type(v, what, "a number");
            return None;
        };
        if !x.is_finite() {
            self.error(
                codes::OUT_OF_RANGE,
                v.span,
                format!("{what} must be finite"),
            );
            return None;
        }
        Some(x)
    }

    /// An integer; integral floats beyond i64 are clamped so range checks report them.
    fn int(&mut self, v: &Node, what: &str) -> Option<i64> {
        if let Some(i) = v.as_i64() {
            return Some(i);
        }
        match v.as_f64() {
            Some(f) if f.is_finite() && f.fract() == 0.0 => {
                Some(if f > 0.0 { i64::MAX } else { i64::MIN })
            }
            _ => {
                self.wrong_type(v, what, "an integer");
                None
            }
        }
    }

    fn bool(&mut self, v: &Node, what: &str) -> Option<bool> {
        let b = v.as_bool();
        if b.is_none() {
            self.wrong_type(v, what, "true or false");
        }
        b
    }

    /// A time: seconds as a number, or a duration string. Never negative.
    fn duration(&mut self, v: &Node, what: &str) -> Option<f64> {
        let x = match v.scalar() {
            Some(Scalar::Int(i)) => i as f64,
            Some(Scalar::Float(f)) => f,
            Some(Scalar::Str(s)) => match parse_duration(s) {
                Ok(x) => x,
                Err(e) => {
                    self.error(
                        codes::BAD_DURATION,
                        v.span,
                        format!("{what} `{s}` is not a duration: {e}"),
                    );
                    self.help("write seconds as a number, or a duration such as `90s`, `15min`, `8h`, `1h30min`");
                    return None;
                }
            },
            _ => {
                self.error(
                    codes::BAD_DURATION,
                    v.span,
                    format!("{what} must be a duration, found {}", v.type_name()),
                );
                self.help("write seconds as a number, or a duration such as `90s`, `15min`, `8h`, `1h30min`");
                return None;
            }
        };
        if !x.is_finite() || x < 0.0 {
            self.error(
                codes::BAD_DURATION,
                v.span,
                format!("{what} must be a finite time of 0 s or more"),
            );
            return None;
        }
        Some(x)
    }

    fn positive(&mut self, v: &Node, x: f64, what: &str) -> Option<f64> {
        if x > 0.0 {
            Some(x)
        } else {
            self.error(
                codes::NOT_POSITIVE,
                v.span,
                format!("{what} must be greater than 0"),
            );
            None
        }
    }

    // ---- the document ----

    fn scenario(&mut self, root: &Node, base: &Path) -> Option<Scenario> {
        let top = self.entries(root, "the scenario", Some((TOP_KEYS, codes::UNKNOWN_KEY)))?;
        let mut ok = true;

        let map = match top.get("map") {
            None => None,
            Some(v) => match self.name(v, "`map`") {
                Some(m) => Some(base.join(m)),
                None => {
                    ok = false;
                    None
                }
            },
        };
        if let Some(v) = top.get("description") {
            if v.key_text().is_none() && !v.is_null() {
                self.wrong_type(v, "`description`", "a string");
            }
        }
        let seed = match top.get("seed") {
            None => Some(0),
            Some(v) => match self.int(v, "`seed`") {
                Some(i) if i >= 0 => Some(i as u64),
                Some(_) => {
                    self.error(codes::OUT_OF_RANGE, v.span, "`seed` must be 0 or more");
                    None
                }
                None => None,
            },
        };
        let duration = self
            .required(&top, "duration", "the scenario")
            .and_then(|v| {
                let d = self.duration(v, "`duration`")?;
                let d = self.positive(v, d, "`duration`")?;
                if d > MAX_DURATION {
                    self.error(
                        codes::TOO_LARGE,
                        v.span,
                        format!("`duration` of {d} s is longer than one year ({MAX_DURATION} s)"),
                    );
                    self.help("check the unit; split very long studies into several runs");
                    return None;
                }
                Some(d)
            });
        let step = match top.get("step") {
            None => Some(0.01),
            Some(v) => self.duration(v, "`step`").and_then(|s| {
                let s = self.positive(v, s, "`step`")?;
                if s > MAX_STEP {
                    self.error(
                        codes::STEP_TOO_LARGE,
                        v.span,
                        format!("`step` of {s} s is larger than {MAX_STEP} s"),
                    );
                    self.help(
                        "the plugins run at 100 Hz; leave `step` out (0.01 s) or use at most 0.1 s",
                    );
                    return None;
                }
                Some(s)
            }),
        };

        let fleets = match self.required(&top, "fleets", "the scenario") {
            Some(v) => self.fleets(v),
            None => None,
        };
        let workcells = match top.get("workcells") {
            Some(v) if !v.is_null() => self.workcells(v),
            _ => Some(Vec::new()),
        };
        let tasks = match top.get("tasks") {
            Some(v) if !v.is_null() => self.seq(v, "`tasks`", |p, n| p.task(n, duration)),
            _ => Some(Vec::new()),
        };
        let generators = match top.get("generators") {
            Some(v) if !v.is_null() => self.seq(v, "`generators`", |p, n| p.generator(n, duration)),
            _ => Some(Vec::new()),
        };
        let faults = match top.get("faults") {
            Some(v) if !v.is_null() => self.seq(v, "`faults`", |p, n| p.fault(n, duration)),
            _ => Some(Vec::new()),
        };
        let mut options = match top.get("options") {
            Some(v) if !v.is_null() => self.options(v),
            _ => Some(SimOptions::default()),
        };
        if let Some(v) = top.get("crowd").filter(|v| !v.is_null()) {
            match (self.crowd(v), options.as_mut()) {
                (Some(c), Some(o)) => o.crowd = c,
                (None, _) => ok = false,
                _ => {}
            }
        }

        let requests = match top.get("requests") {
            Some(v) if !v.is_null() => self.requests_file(Some(v), duration),
            _ if self.requests.is_some() => self.requests_file(None, duration),
            _ => Some(Vec::new()),
        };
        if let (Some(fleets), Some(tasks), Some(gens)) = (&fleets, &tasks, &generators) {
            self.cross_check(fleets, tasks, gens);
            ok &= self.count_tasks(tasks, gens, duration);
        }

        if self.had_error || self.suppressed > 0 || !ok {
            return None;
        }
        Some(Scenario {
            map,
            seed: seed?,
            duration: duration?,
            step: step?,
            fleets: fleets?,
            workcells: workcells?,
            tasks: tasks?,
            generators: generators?,
            faults: faults?,
            options: options?,
            requests: requests?,
            cancels: Vec::new(),
        })
    }

    /// Reads every element of a sequence (all of them, even after a bad one).
    fn seq<T>(
        &mut self,
        v: &Node,
        what: &str,
        mut one: impl FnMut(&mut Self, &Node) -> Option<T>,
    ) -> Option<Vec<T>> {
        let Some(items) = v.as_seq() else {
            self.wrong_type(v, what, "a list");
            return None;
        };
        let mut out = Vec::with_capacity(items.len());
        let mut ok = true;
        for n in items {
            match one(self, n) {
                Some(x) => out.push(x),
                None => ok = false,
            }
        }
        ok.then_some(out)
    }

    fn fleets(&mut self, v: &Node) -> Option<Vec<FleetSpec>> {
        let fleets = self.seq(v, "`fleets`", |p, n| p.fleet(n))?;
        if fleets.is_empty() {
            self.error(
                codes::MISSING_KEY,
                v.span,
                "`fleets` is empty; a scenario needs at least one fleet",
            );
            return None;
        }
        let total: usize = fleets.iter().map(|f| f.count).sum();
        if total as i64 > MAX_ROBOTS {
            self.error(
                codes::TOO_LARGE,
                v.span,
                format!("the fleets have {total} robots in all, more than {MAX_ROBOTS}"),
            );
            return None;
        }
        let mut ok = true;
        let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
        for f in &fleets {
            if let Some(&first_span) = seen.get(f.name.as_str()) {
                self.error(
                    codes::DUPLICATE_FLEET,
                    f.span,
                    format!("a fleet named `{}` is already defined", f.name),
                )
                .labels
                .push(mapc_ir::Label {
                    span: first_span,
                    message: "first defined here".into(),
                });
                self.help("give every fleet its own name");
                ok = false;
            }
            seen.entry(&f.name).or_insert(f.span);
        }
        ok.then_some(fleets)
    }

    /// Reads a file the scenario names (relative to the scenario's directory) and keeps
    /// it with the scenario's sources; returns its index in `included`.
    fn include(&mut self, v: &Node, what: &str) -> Option<usize> {
        let name = self.name(v, what)?;
        let path = self.base.join(&name);
        self.include_path(path, v.span, what)
    }

    fn include_path(&mut self, path: PathBuf, from: Span, what: &str) -> Option<usize> {
        let text = match read_limited(&path) {
            Ok(t) => t,
            Err(e) => {
                self.error(
                    codes::INCLUDED_FILE,
                    from,
                    format!("{what} `{}` cannot be read: {e}", path.display()),
                );
                self.help(if what == "`--requests`" {
                    "the path is relative to the current directory"
                } else {
                    "the path is relative to the scenario file"
                });
                return None;
            }
        };
        self.included.push(Included { path, text, from });
        Some(self.included.len() - 1)
    }

    /// `requests: FILE` or `{file: FILE, start_unix_millis: N}`: the requests, their
    /// `unix_millis_earliest_start_time` read against N (the run's start; default 0).
    /// With `--requests FILE` (`self.requests`), that file instead of the scenario's.
    fn requests_file(
        &mut self,
        v: Option<&Node>,
        duration: Option<f64>,
    ) -> Option<Vec<RequestSpec>> {
        let (file, epoch) = match v {
            None => (None, 0),
            Some(v) => {
                let (f, e) = self.requests_key(v)?;
                (Some(f), e)
            }
        };
        let k = match (self.requests.clone(), file) {
            (Some(path), _) => {
                let from = file.map_or(Span::UNKNOWN, |f| f.span);
                self.include_path(path, from, "`--requests`")?
            }
            (None, Some(f)) => self.include(f, "`requests`")?,
            (None, None) => return Some(Vec::new()),
        };
        let id = self.included_id(k);
        let text = self.included[k].text.clone();
        let mut reqs = self.requests(id, &text)?;
        for r in &mut reqs {
            r.start_unix_millis = epoch;
            if let RequestKind::Task(t) = &r.what {
                if let Some(ms) = t.earliest_start_ms {
                    r.at = r.at.max(ms.saturating_sub(epoch) as f64 / 1000.0);
                }
            }
            if let Some(d) = duration.filter(|&d| r.at >= d) {
                self.warning(
                    codes::TASK_AFTER_END,
                    r.span,
                    format!(
                        "the request arrives (or may start) at {} s, at or after the end of the run ({d} s)",
                        r.at
                    ),
                );
                self.help("check `at` and `unix_millis_earliest_start_time` (read against `start_unix_millis`)");
            }
        }
        Some(reqs)
    }

    /// The `requests` key: its file node and `start_unix_millis`.
    fn requests_key<'n, 'a>(&mut self, v: &'n Node<'a>) -> Option<(&'n Node<'a>, i64)> {
        let (file, epoch) = if v.as_map().is_some() {
            let e = self.entries(
                v,
                "`requests`",
                Some((&["file", "start_unix_millis"], codes::UNKNOWN_KEY)),
            )?;
            let f = self.required(&e, "file", "`requests`")?;
            let epoch = match e.get("start_unix_millis") {
                None => 0,
                Some(n) => self.int(n, "`start_unix_millis`")?,
            };
            (f, epoch)
        } else {
            (v, 0)
        };
        Some((file, epoch))
    }

    fn included_id(&self, k: usize) -> FileId {
        FileId(self.file.0 + 1 + k as u32)
    }

    /// The fleet described by an RMF fleet adapter config (`config:`).
    fn config_fleet(&mut self, v: &Node) -> Option<rmf_config::ConfigFleet> {
        let k = self.include(v, "`config`")?;
        let id = self.included_id(k);
        let text = self.included[k].text.clone();
        let path = self.included[k].path.clone();
        let root = match yaml_tree::parse(&text, id) {
            Ok(r) => r,
            Err(mut d) => {
                d.code = codes::INVALID_YAML.code;
                if !d.span.is_known() {
                    d.span = v.span;
                }
                self.push(d);
                return None;
            }
        };
        if root.is_null() {
            self.error(
                codes::RMF_CONFIG_NO_FLEET,
                v.span,
                "the fleet config is empty",
            );
            return None;
        }
        self.rmf_config(&root, path)
    }

    fn recharge_threshold(&mut self, t: &Node) -> Option<f64> {
        self.number(t, "`recharge_threshold`").and_then(|x| {
            if (0.0..1.0).contains(&x) {
                Some(x)
            } else {
                self.error(
                    codes::OUT_OF_RANGE,
                    t.span,
                    format!("`recharge_threshold` is {x}; it must be in [0, 1)"),
                );
                self.help("it is a fraction of the battery: 0.2 means 20 %");
                None
            }
        })
    }

    fn recharge_soc(&mut self, t: &Node) -> Option<f64> {
        self.number(t, "`recharge_soc`").and_then(|x| {
            if x > 0.0 && x <= 1.0 {
                Some(x)
            } else {
                self.error(
                    codes::OUT_OF_RANGE,
                    t.span,
                    format!("`recharge_soc` is {x}; it must be in (0, 1]"),
                );
                self.help("it is a fraction of the battery: 1.0 means full");
                None
            }
        })
    }

    fn fleet(&mut self, v: &Node) -> Option<FleetSpec> {
        let e = self.entries(v, "a fleet", Some((FLEET_KEYS, codes::UNKNOWN_KEY)))?;
        // From an RMF fleet adapter config; the scenario's own keys override it.
        let cfg = match e.get("config") {
            Some(c) => Some(self.config_fleet(c)?),
            None => None,
        };
        let name = match (e.get("name"), &cfg) {
            (None, Some(c)) => Some(c.name.clone()),
            _ => self
                .required(&e, "name", "a fleet")
                .and_then(|n| self.name(n, "a fleet's `name`")),
        };
        let graph = match e.get("graph") {
            None => Some(0),
            Some(g) => self.int(g, "`graph`").and_then(|i| {
                if i < 0 {
                    self.error(codes::OUT_OF_RANGE, g.span, "`graph` must be 0 or more");
                    None
                } else {
                    Some(i)
                }
            }),
        };
        let robot = match (e.get("robot"), &cfg) {
            (None, Some(c)) => Some(c.robot.clone()),
            (r, c) => r
                .or_else(|| self.required(&e, "robot", "a fleet"))
                .and_then(|r| self.robot(r, c.as_ref().map(|c| c.robot.clone()))),
        };
        let count = match e.get("count") {
            Some(c) => self.int(c, "`count`").and_then(|i| {
                if i <= 0 {
                    self.error(
                        codes::NOT_POSITIVE,
                        c.span,
                        "`count` must be greater than 0",
                    );
                    self.help("a fleet needs at least one robot; remove the fleet instead");
                    None
                } else if i > MAX_ROBOTS {
                    self.error(
                        codes::TOO_LARGE,
                        c.span,
                        format!("`count` must be at most {MAX_ROBOTS}"),
                    );
                    None
                } else {
                    Some(i as usize)
                }
            }),
            None => None,
        };
        let spawn = match (e.get("spawn"), &cfg) {
            (Some(s), _) => self.spawn(s),
            // The config's robots at their start waypoints; more robots than it lists
            // (a `count` override) are placed automatically.
            (None, Some(c)) => Some(match count {
                Some(n) if n > c.rmf.robots.len() => SpawnSpec::Auto,
                n => SpawnSpec::Waypoints(
                    c.rmf
                        .robots
                        .iter()
                        .take(n.unwrap_or(usize::MAX))
                        .map(|r| r.start.clone())
                        .collect(),
                ),
            }),
            (None, None) => Some(SpawnSpec::Auto),
        };
        let count = match (count, e.get("count")) {
            (Some(n), _) => Some(n),
            (None, Some(_)) => None,
            (None, None) => match &spawn {
                Some(SpawnSpec::Waypoints(w)) => Some(w.len()),
                Some(_) => {
                    self.error(codes::MISSING_KEY, e.span, "a fleet has no `count`");
                    self.help("set `count`, or list one spawn waypoint per robot under `spawn`");
                    None
                }
                None => None,
            },
        };
        if let (Some(SpawnSpec::Waypoints(w)), Some(n), Some(s)) = (&spawn, count, e.get("spawn")) {
            if w.len() != n {
                self.error(
                    codes::SPAWN_COUNT,
                    s.span,
                    format!("`spawn` names {} waypoint(s) for {n} robot(s)", w.len()),
                );
                self.help("list one waypoint per robot, leave `count` out, or use `spawn: auto`");
            }
        }
        let threshold = match (e.get("recharge_threshold"), &cfg) {
            (None, Some(c)) => Some(c.recharge_threshold),
            (None, None) => Some(0.2),
            (Some(t), _) => self.recharge_threshold(t),
        };
        let soc = match (e.get("recharge_soc"), &cfg) {
            (None, Some(c)) => Some(c.recharge_soc),
            (None, None) => Some(1.0),
            (Some(t), _) => self.recharge_soc(t),
        };
        // A config's own pair is made consistent where it is read (`rmf_config`).
        let own_pair = e.get("recharge_soc").is_some() || e.get("recharge_threshold").is_some();
        if let (Some(t), Some(s), true) = (threshold, soc, own_pair || cfg.is_none()) {
            if t >= s {
                let span = e
                    .get("recharge_soc")
                    .or(e.get("recharge_threshold"))
                    .map_or(e.span, |n| n.span);
                self.error(
                    codes::OUT_OF_RANGE,
                    span,
                    format!("`recharge_soc` ({s}) must be above `recharge_threshold` ({t})"),
                );
                self.help("a robot leaves the charger at recharge_soc and goes back below recharge_threshold");
            }
        }
        let kinds = match (e.get("tasks"), &cfg) {
            (None, Some(c)) => Some(c.task_kinds.clone()),
            (None, None) => Some(Vec::new()),
            (Some(t), _) => self.categories(t),
        };
        Some(FleetSpec {
            name: name?,
            graph: graph?,
            robot: robot?,
            count: count?,
            spawn: spawn?,
            recharge_threshold: threshold?,
            recharge_soc: soc?,
            task_kinds: kinds?,
            span: v.span,
            rmf: cfg.map(|c| Box::new(c.rmf)),
        })
    }

    /// A preset name, or a mapping of parameters over a preset or over `base` (a fleet
    /// config's robot).
    fn robot(&mut self, v: &Node, base: Option<RobotParams>) -> Option<RobotParams> {
        if v.as_map().is_none() {
            let name = self.name(v, "`robot`")?;
            return self.preset(v, &name);
        }
        let mut known: Vec<&str> = vec!["preset", "model", "reversible"];
        known.extend(ROBOT_NUMBERS.iter().map(|r| r.0));
        let e = self.entries(v, "`robot`", Some((&known, codes::UNKNOWN_KEY)))?;
        let mut p = match e.get("preset") {
            Some(n) => {
                let name = self.name(n, "`preset`")?;
                self.preset(n, &name)?
            }
            None => base.unwrap_or_default(),
        };
        let mut ok = true;
        if let Some(m) = e.get("model") {
            match self.name(m, "`model`") {
                Some(n) => p.model = n,
                None => ok = false,
            }
        }
        if let Some(r) = e.get("reversible") {
            match self.bool(r, "`reversible`") {
                Some(b) => p.reversible = b,
                None => ok = false,
            }
        }
        // Document order, so that diagnostics come out in reading order.
        for &(key, _, n) in &e.items {
            let Some(&(_, strictly)) = ROBOT_NUMBERS.iter().find(|r| r.0 == key) else {
                continue;
            };
            let what = format!("`{key}`");
            let Some(x) = self.number(n, &what) else {
                ok = false;
                continue;
            };
            if strictly && x <= 0.0 {
                self.error(
                    codes::NOT_POSITIVE,
                    n.span,
                    format!("{what} must be greater than 0"),
                );
                ok = false;
            } else if x < 0.0 {
                self.error(
                    codes::OUT_OF_RANGE,
                    n.span,
                    format!("{what} must be 0 or more"),
                );
                ok = false;
            } else if let Some(slot) = robot_number(&mut p, key) {
                *slot = x;
            }
        }
        ok.then_some(p)
    }

    fn preset(&mut self, v: &Node, name: &str) -> Option<RobotParams> {
        let p = RobotParams::preset(name);
        if p.is_none() {
            let names: Vec<&str> = RobotParams::preset_names().collect();
            self.error(
                codes::UNKNOWN_PRESET,
                v.span,
                format!("unknown robot preset `{name}`"),
            );
            let hint = closest(name, names.iter().copied())
                .map(|c| format!("did you mean `{c}`? "))
                .unwrap_or_default();
            self.help(format!(
                "{hint}presets: {}; or describe the robot as a mapping of parameters",
                list(&names)
            ));
        }
        p
    }

    fn spawn(&mut self, v: &Node) -> Option<SpawnSpec> {
        if let Some(items) = v.as_seq() {
            let mut names: Vec<String> = Vec::with_capacity(items.len());
            let mut seen: BTreeSet<String> = BTreeSet::new();
            let mut ok = true;
            for n in items {
                match self.name(n, "a spawn waypoint") {
                    Some(s) if seen.contains(&s) => {
                        self.error(
                            codes::SPAWN_COUNT,
                            n.span,
                            format!("waypoint `{s}` is listed twice; two robots would start on it"),
                        );
                        ok = false;
                    }
                    Some(s) => {
                        seen.insert(s.clone());
                        names.push(s);
                    }
                    None => ok = false,
                }
            }
            return ok.then_some(SpawnSpec::Waypoints(names));
        }
        match v.scalar() {
            Some(Scalar::Str("spawn_points")) => Some(SpawnSpec::MapSpawnPoints),
            Some(Scalar::Str("auto")) => Some(SpawnSpec::Auto),
            _ => {
                self.error(
                    codes::WRONG_TYPE,
                    v.span,
                    format!(
                        "`spawn` must be `spawn_points`, `auto` or a list of waypoint names, found {}",
                        v.type_name()
                    ),
                );
                None
            }
        }
    }

    fn categories(&mut self, v: &Node) -> Option<Vec<TaskCategory>> {
        let mut out: Vec<TaskCategory> = self.seq(v, "a fleet's `tasks`", |p, n| {
            let s = p.name(n, "a task category")?;
            let c = category(&s);
            if c.is_none() {
                p.error(
                    codes::UNKNOWN_TASK_KIND,
                    n.span,
                    format!("unknown task category `{s}`"),
                );
                p.help(format!("categories: {}", list(KINDS)));
            }
            c
        })?;
        if out.is_empty() {
            self.wrong_type(
                v,
                "a fleet's `tasks`",
                "a non-empty list (leave it out to accept every category)",
            );
            return None;
        }
        out.sort();
        out.dedup();
        Some(out)
    }

    fn workcells(&mut self, v: &Node) -> Option<Vec<WorkcellSpec>> {
        let cells = self.seq(v, "`workcells`", |p, n| {
            let e = p.entries(n, "a workcell", Some((WORKCELL_KEYS, codes::UNKNOWN_KEY)))?;
            let name = p
                .required(&e, "name", "a workcell")
                .and_then(|x| p.name(x, "a workcell's `name`"));
            let kind = p
                .required(&e, "kind", "a workcell")
                .and_then(|k| match k.scalar() {
                    Some(Scalar::Str("dispenser")) => Some(WorkcellKind::Dispenser),
                    Some(Scalar::Str("ingestor")) => Some(WorkcellKind::Ingestor),
                    _ => {
                        p.wrong_type(k, "a workcell's `kind`", "`dispenser` or `ingestor`");
                        None
                    }
                });
            let waypoint = p
                .required(&e, "waypoint", "a workcell")
                .and_then(|x| p.name(x, "a workcell's `waypoint`"));
            Some(WorkcellSpec {
                name: name?,
                kind: kind?,
                waypoint: waypoint?,
                span: n.span,
            })
        })?;
        let mut ok = true;
        let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
        for c in &cells {
            if let Some(&first_span) = seen.get(c.name.as_str()) {
                self.error(
                    codes::DUPLICATE_WORKCELL,
                    c.span,
                    format!("a workcell named `{}` is already defined", c.name),
                )
                .labels
                .push(mapc_ir::Label {
                    span: first_span,
                    message: "first defined here".into(),
                });
                ok = false;
            }
            seen.entry(&c.name).or_insert(c.span);
        }
        ok.then_some(cells)
    }

    /// The task kind among a task's or generator's keys (`plain` are the other known keys).
    fn kind(&mut self, e: &Entries, plain: &[&str], what: &str) -> Option<TaskKind> {
        let kinds: Vec<_> = e.items.iter().filter(|i| KINDS.contains(&i.0)).collect();
        let others: Vec<_> = e
            .items
            .iter()
            .filter(|i| !KINDS.contains(&i.0) && !plain.contains(&i.0))
            .collect();
        for (n, (key, k, _)) in others.iter().enumerate() {
            if n == 0 && kinds.is_empty() {
                self.error(
                    codes::UNKNOWN_TASK_KIND,
                    k.span,
                    format!("`{key}` is not a task kind"),
                );
                let hint = closest(key, KINDS.iter().copied())
                    .map(|c| format!("did you mean `{c}`? "))
                    .unwrap_or_default();
                self.help(format!("{hint}kinds: {}", list(KINDS)));
            } else {
                self.warning(
                    codes::UNKNOWN_KEY,
                    k.span,
                    format!("unknown key `{key}` in {what}; it is ignored"),
                );
                let mut known: Vec<&str> = plain.to_vec();
                known.extend(KINDS);
                if let Some(c) = closest(key, known.iter().copied()) {
                    self.help(format!("did you mean `{c}`?"));
                }
            }
        }
        match kinds.as_slice() {
            [] => {
                if others.is_empty() {
                    self.error(codes::MISSING_KEY, e.span, format!("{what} has no kind"));
                    self.help(format!("add one of {}", list(KINDS)));
                }
                None
            }
            [(key, _, v)] => self.kind_body(key, v),
            [_, (key, k, _), ..] => {
                self.error(
                    codes::SEVERAL_TASK_KINDS,
                    k.span,
                    format!("{what} has more than one kind (`{key}` is the second)"),
                );
                self.help("one request is one task; split it into several tasks");
                None
            }
        }
    }

    fn kind_body(&mut self, key: &str, v: &Node) -> Option<TaskKind> {
        // `go_to_place: lobby` and `clean: zone_1` are short forms.
        if v.as_map().is_none() && matches!(key, "go_to_place" | "clean") {
            let n = self.name(v, &format!("`{key}`"))?;
            return Some(if key == "clean" {
                TaskKind::Clean { zone: n }
            } else {
                TaskKind::GoToPlace { place: n }
            });
        }
        let what = format!("`{key}`");
        let fields: &[&str] = match key {
            "loop" => &["start", "finish", "loops"],
            "delivery" => &["pickup", "dropoff", "dispenser", "ingestor"],
            "clean" => &["zone"],
            _ => &["place"],
        };
        let e = self.entries(v, &what, Some((fields, codes::UNKNOWN_KEY)))?;
        let req = |p: &mut Self, f: &str| {
            p.required(&e, f, &what)
                .and_then(|n| p.name(n, &format!("`{key}.{f}`")))
        };
        Some(match key {
            "loop" => {
                let start = req(self, "start");
                let finish = req(self, "finish");
                let loops = match e.get("loops") {
                    None => Some(1),
                    Some(n) => self.int(n, "`loops`").and_then(|i| {
                        if i <= 0 {
                            self.error(
                                codes::NOT_POSITIVE,
                                n.span,
                                "`loops` must be greater than 0",
                            );
                            None
                        } else if i as f64 > MAX_TASKS {
                            self.error(
                                codes::TOO_LARGE,
                                n.span,
                                format!("`loops` must be at most {MAX_TASKS}"),
                            );
                            None
                        } else {
                            Some(i as u32)
                        }
                    }),
                };
                TaskKind::Loop {
                    start: start?,
                    finish: finish?,
                    loops: loops?,
                }
            }
            "delivery" => {
                let pickup = req(self, "pickup");
                let dropoff = req(self, "dropoff");
                let opt = |p: &mut Self, f: &str| match e.get(f) {
                    None => Some(None),
                    Some(n) => p.name(n, &format!("`delivery.{f}`")).map(Some),
                };
                let dispenser = opt(self, "dispenser");
                let ingestor = opt(self, "ingestor");
                TaskKind::Delivery {
                    pickup: pickup?,
                    dropoff: dropoff?,
                    dispenser: dispenser?,
                    ingestor: ingestor?,
                }
            }
            "clean" => TaskKind::Clean {
                zone: req(self, "zone")?,
            },
            _ => TaskKind::GoToPlace {
                place: req(self, "place")?,
            },
        })
    }

    fn fleet_ref(&mut self, e: &Entries) -> Option<Option<String>> {
        match e.get("fleet") {
            None => Some(None),
            Some(f) if f.is_null() => Some(None),
            Some(f) => self.name(f, "`fleet`").map(Some),
        }
    }

    fn task(&mut self, v: &Node, duration: Option<f64>) -> Option<TaskSpec> {
        let e = self.entries(v, "a task", None)?;
        let at = match e.get("at") {
            None => Some(0.0),
            Some(a) => self.duration(a, "`at`"),
        };
        let kind = self.kind(&e, TASK_KEYS, "a task");
        let fleet = self.fleet_ref(&e);
        if let (Some(a), Some(d), Some(n)) = (at, duration, e.get("at")) {
            if a >= d {
                self.warning(
                    codes::TASK_AFTER_END,
                    n.span,
                    format!(
                        "the task is requested at {a} s, at or after the end of the run ({d} s)"
                    ),
                );
                self.help("request it earlier or lengthen `duration`; it is never requested");
            }
        }
        Some(TaskSpec {
            at: at?,
            kind: kind?,
            fleet: fleet?,
            robot: None,
            priority: 0,
            span: v.span,
        })
    }

    fn generator(&mut self, v: &Node, duration: Option<f64>) -> Option<GeneratorSpec> {
        let e = self.entries(v, "a generator", None)?;
        let every = self.required(&e, "every", "a generator").and_then(|n| {
            self.duration(n, "`every`")
                .and_then(|x| self.positive(n, x, "`every`"))
        });
        let start = match e.get("start") {
            None => Some(0.0),
            Some(n) => self.duration(n, "`start`"),
        };
        let end = match e.get("end") {
            None => Some(None),
            Some(n) if n.is_null() => Some(None),
            Some(n) => self.duration(n, "`end`").map(Some),
        };
        if let (Some(s), Some(Some(en)), Some(n)) = (start, end, e.get("end")) {
            if en < s {
                self.error(
                    codes::OUT_OF_RANGE,
                    n.span,
                    format!("`end` ({en} s) comes before `start` ({s} s)"),
                );
                return None;
            }
        }
        if let (Some(s), Some(d)) = (start, duration) {
            if s >= d {
                self.warning(
                    codes::TASK_AFTER_END,
                    e.get("start").map_or(v.span, |n| n.span),
                    format!(
                        "the generator starts at {s} s, at or after the end of the run ({d} s)"
                    ),
                );
                self.help("start it earlier or lengthen `duration`; it generates nothing");
            }
        }
        let kind = self.kind(&e, GENERATOR_KEYS, "a generator");
        let fleet = self.fleet_ref(&e);
        Some(GeneratorSpec {
            every: every?,
            start: start?,
            end: end?,
            kind: kind?,
            fleet: fleet?,
            span: v.span,
        })
    }

    fn options(&mut self, v: &Node) -> Option<SimOptions> {
        let e = self.entries(v, "`options`", Some((OPTION_KEYS, codes::UNKNOWN_OPTION)))?;
        let mut o = SimOptions::default();
        let mut ok = true;
        if let Some(n) = e.get("lifts_start_at_initial_floor") {
            match self.bool(n, "`lifts_start_at_initial_floor`") {
                Some(b) => o.lifts_start_at_initial_floor = b,
                None => ok = false,
            }
        }
        for (key, field) in [
            ("stop_when_done", &mut o.stop_when_done),
            ("charging", &mut o.charging),
            ("instant_charging", &mut o.instant_charging),
            ("battery_drain", &mut o.battery_drain),
        ] {
            if let Some(n) = e.get(key) {
                match self.bool(n, &format!("`{key}`")) {
                    Some(b) => *field = b,
                    None => ok = false,
                }
            }
        }
        if let Some(n) = e.get("clean_duration") {
            match self
                .duration(n, "`clean_duration`")
                .and_then(|x| self.positive(n, x, "`clean_duration`"))
            {
                Some(x) => o.clean_duration = x,
                None => ok = false,
            }
        }
        ok.then_some(o)
    }

    fn crowd(&mut self, v: &Node) -> Option<CrowdOptions> {
        let e = self.entries(v, "`crowd`", Some((CROWD_KEYS, codes::UNKNOWN_KEY)))?;
        let mut c = CrowdOptions::default();
        let mut ok = true;
        if let Some(n) = e.get("enabled") {
            match self.bool(n, "`crowd.enabled`") {
                Some(b) => c.enabled = b,
                None => ok = false,
            }
        }
        if let Some(n) = e.get("scale") {
            match self.number(n, "`crowd.scale`") {
                Some(x) if (0.0..=MAX_CROWD_SCALE).contains(&x) => c.scale = x,
                Some(x) => {
                    self.error(
                        codes::OUT_OF_RANGE,
                        n.span,
                        format!("`crowd.scale` of {x} is not between 0 and {MAX_CROWD_SCALE}"),
                    );
                    ok = false;
                }
                None => ok = false,
            }
        }
        ok.then_some(c)
    }

    /// Fleets named by tasks exist and accept the task's category. Lookups are by map, so
    /// that a million tasks against ten thousand fleets stay fast.
    fn cross_check(&mut self, fleets: &[FleetSpec], tasks: &[TaskSpec], gens: &[GeneratorSpec]) {
        let accepts =
            |f: &FleetSpec, c: TaskCategory| f.task_kinds.is_empty() || f.task_kinds.contains(&c);
        let by_name: BTreeMap<&str, &FleetSpec> =
            fleets.iter().map(|f| (f.name.as_str(), f)).collect();
        let all = [
            TaskCategory::Loop,
            TaskCategory::Delivery,
            TaskCategory::Clean,
            TaskCategory::GoToPlace,
        ];
        let accepted: BTreeSet<TaskCategory> = all
            .into_iter()
            .filter(|&c| fleets.iter().any(|f| accepts(f, c)))
            .collect();
        let names: Vec<&str> = fleets.iter().map(|f| f.name.as_str()).collect();
        let items = tasks
            .iter()
            .map(|t| (&t.fleet, t.kind.category(), t.span))
            .chain(gens.iter().map(|g| (&g.fleet, g.kind.category(), g.span)));
        for (fleet, cat, span) in items {
            let cat_name = cat.as_str();
            match fleet.as_deref().map(|n| (n, by_name.get(n))) {
                Some((name, None)) => {
                    self.error(
                        codes::UNKNOWN_FLEET,
                        span,
                        format!("no fleet is named `{name}`"),
                    );
                    // The hint costs an edit distance per fleet: only while reporting.
                    if !self.full() {
                        let hint = closest(name, names.iter().copied())
                            .map(|c| format!("did you mean `{c}`? "))
                            .unwrap_or_default();
                        let shown: Vec<&str> = names.iter().copied().take(20).collect();
                        let more = if names.len() > shown.len() {
                            ", ..."
                        } else {
                            ""
                        };
                        self.help(format!("{hint}fleets: {}{more}", list(&shown)));
                    }
                }
                Some((name, Some(f))) if !accepts(f, cat) => {
                    let fspan = f.span;
                    self.error(
                        codes::NO_FLEET_FOR_TASK,
                        span,
                        format!("fleet `{name}` does not accept {cat_name} tasks"),
                    )
                    .labels
                    .push(mapc_ir::Label {
                        span: fspan,
                        message: "the fleet".into(),
                    });
                    self.help(format!(
                        "add `{cat_name}` to the fleet's `tasks`, or send the task to another fleet"
                    ));
                }
                None if !accepted.contains(&cat) => {
                    self.error(
                        codes::NO_FLEET_FOR_TASK,
                        span,
                        format!("no fleet accepts {cat_name} tasks"),
                    );
                    self.help(format!("add `{cat_name}` to a fleet's `tasks`"));
                }
                _ => {}
            }
        }
    }

    /// Bounds the number of task requests, generators included (S0109).
    fn count_tasks(
        &mut self,
        tasks: &[TaskSpec],
        gens: &[GeneratorSpec],
        duration: Option<f64>,
    ) -> bool {
        let mut total = tasks.len() as f64;
        for g in gens {
            let end = match (g.end, duration) {
                (Some(e), Some(d)) => e.min(d),
                (Some(e), None) => e,
                (None, Some(d)) => d,
                (None, None) => continue,
            };
            // Requests at start, start + every, ... while before `end`.
            let n = if end > g.start {
                ((end - g.start) / g.every).ceil()
            } else {
                0.0
            };
            total += n;
            if total > MAX_TASKS {
                self.error(
                    codes::TOO_LARGE,
                    g.span,
                    format!(
                        "this generator requests {n} tasks, more than {MAX_TASKS} task requests in all"
                    ),
                );
                self.help("check the unit of `every` (1ms instead of 1min?)");
                return false;
            }
        }
        true
    }
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

/// Reads a file a scenario names, within the input limit, as UTF-8.
fn read_limited(path: &Path) -> Result<String, String> {
    use std::io::Read;
    let limit = mapc_frontend::MAX_FILE_BYTES;
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(limit + 1).read_to_end(&mut bytes))
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!(
            "it is larger than the input limit of {limit} bytes"
        ));
    }
    String::from_utf8(bytes).map_err(|_| "it is not valid UTF-8".to_string())
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
mod tests {
    use super::*;

    fn run(text: &str) -> (Option<Scenario>, Vec<Diagnostic>) {
        parse(FileId(0), text, Path::new("/scen"))
    }

    fn ok(text: &str) -> Scenario {
        let (s, d) = run(text);
        assert!(!mapc_ir::has_errors(&d), "{d:#?}");
        s.expect("a scenario when there are no errors")
    }

    /// Codes of the diagnostics; every one must have a position.
    fn codes_of(text: &str) -> Vec<&'static str> {
        let (s, d) = run(text);
        for x in &d {
            assert!(x.span.line > 0 && x.span.col > 0, "no position: {x:?}");
        }
        if mapc_ir::has_errors(&d) {
            assert!(s.is_none());
        }
        d.iter().map(|x| x.code).collect()
    }

    const MIN: &str = "duration: 1h\nfleets: [{name: f, robot: TinyRobot, count: 1}]\n";

    #[test]
    fn durations() {
        assert_eq!(parse_duration("1h30min"), Ok(5400.0));
        assert_eq!(parse_duration("90s"), Ok(90.0));
        assert_eq!(parse_duration("15min"), Ok(900.0));
        assert_eq!(parse_duration("8h"), Ok(8.0 * 3600.0));
        assert_eq!(parse_duration("2.5h"), Ok(9000.0));
        assert_eq!(parse_duration("1d 2h"), Ok(86_400.0 + 7200.0));
        assert_eq!(parse_duration("250ms"), Ok(0.25));
        assert_eq!(parse_duration("42"), Ok(42.0));
        for bad in ["15m", "8 hours", "h", "1h30", "", "1.2.3s", "-5s", "1e3s"] {
            assert!(parse_duration(bad).is_err(), "{bad}");
        }
        let s = ok(&format!("{MIN}step: 10ms\n").replace("duration: 1h", "duration: 1h30min"));
        assert_eq!(s.duration, 5400.0);
        assert!((s.step - 0.01).abs() < 1e-15);
        assert_eq!(ok(&MIN.replace("1h", "7200")).duration, 7200.0);
        assert_eq!(ok(&MIN.replace("1h", "0.5")).duration, 0.5);
    }

    #[test]
    fn full_example_and_defaults() {
        let s = ok(r#"
map: ../maps/hotel/hotel.building.yaml   # relative to the scenario file
seed: 7
duration: 8h
step: 0.01
fleets:
  - name: tinyRobot
    graph: 0
    robot: TinyRobot
    count: 4
    spawn: spawn_points
    recharge_threshold: 0.2
    recharge_soc: 1.0
    tasks: [loop, delivery]
  - name: deliveryRobot
    robot: {preset: DeliveryRobot, nominal_drive_speed: 0.6, footprint: 0.3}
    spawn: [a, b]
workcells:
  - {name: pantry_dispenser, kind: dispenser, waypoint: pantry}
tasks:
  - {at: 0, loop: {start: lobby, finish: room_1, loops: 3}, fleet: tinyRobot}
  - {at: 5min, delivery: {pickup: pantry, dropoff: room_1}}
  - {at: 10min, go_to_place: {place: lobby}}
  - {at: 20min, go_to_place: lobby}
generators:
  - {every: 5min, start: 0, end: 8h, delivery: {pickup: pantry, dropoff: room_1}}
options: {lifts_start_at_initial_floor: false, clean_duration: 2min, stop_when_done: true}
"#);
        assert_eq!(
            s.map,
            Some(PathBuf::from("/scen/../maps/hotel/hotel.building.yaml"))
        );
        assert_eq!((s.seed, s.duration, s.step), (7, 28_800.0, 0.01));
        let f = &s.fleets[0];
        assert_eq!((f.name.as_str(), f.graph, f.count), ("tinyRobot", 0, 4));
        assert_eq!(f.spawn, SpawnSpec::MapSpawnPoints);
        assert_eq!(
            f.task_kinds,
            vec![TaskCategory::Loop, TaskCategory::Delivery]
        );
        assert_eq!(f.robot, RobotParams::preset("TinyRobot").unwrap());
        let g = &s.fleets[1];
        // count defaults to the number of spawn waypoints; other defaults as documented.
        assert_eq!(g.count, 2);
        assert_eq!((g.recharge_threshold, g.recharge_soc), (0.2, 1.0));
        assert!(g.task_kinds.is_empty());
        assert_eq!(g.robot.nominal_drive_speed, 0.6);
        assert_eq!(g.robot.nominal_drive_acceleration, 0.5); // from the preset
        assert_eq!(g.robot.nominal_capacity, 40.0);
        assert_eq!(g.robot.footprint, 0.3);
        assert_eq!(s.workcells[0].kind, WorkcellKind::Dispenser);
        assert_eq!(
            s.tasks[0].kind,
            TaskKind::Loop {
                start: "lobby".into(),
                finish: "room_1".into(),
                loops: 3
            }
        );
        assert_eq!(s.tasks[0].fleet.as_deref(), Some("tinyRobot"));
        assert_eq!(s.tasks[1].at, 300.0);
        assert_eq!(s.tasks[2].kind, s.tasks[3].kind);
        assert_eq!(s.generators[0].every, 300.0);
        assert_eq!(s.generators[0].end, Some(28_800.0));
        assert_eq!(
            s.options,
            SimOptions {
                lifts_start_at_initial_floor: false,
                clean_duration: 120.0,
                stop_when_done: true,
                ..SimOptions::default()
            }
        );
        // Defaults of a minimal scenario.
        let m = ok(MIN);
        assert_eq!((m.seed, m.step, m.map.clone()), (0, 0.01, None));
        assert_eq!(m.fleets[0].spawn, SpawnSpec::Auto);
        assert_eq!(m.options, SimOptions::default());
    }

    #[test]
    fn presets_are_the_runtime_spec_table() {
        // Runtime spec §1.1: v_nom a_nom a_max w_nom α_nom α_max stop reversible V Ah I m I μ P.
        let rows: [(&str, [f64; 7], bool, [f64; 7]); 4] = [
            (
                "TinyRobot",
                [0.5, 0.25, 0.75, 0.6, 1.5, 2.0, 0.75],
                true,
                [12., 24., 5., 20., 10., 0.22, 20.],
            ),
            (
                "DeliveryRobot",
                [0.7, 0.5, 0.75, 0.6, 1.5, 2.0, 0.75],
                true,
                [24., 40., 8.8, 70., 40., 0.22, 20.],
            ),
            (
                "CleanerBotA",
                [0.7, 0.5, 0.6, 0.4, 1.0, 1.2, 1.5],
                false,
                [24., 20., 10., 70., 40., 0.22, 100.],
            ),
            (
                "HospitalRobot",
                [0.7, 0.5, 0.75, 0.3, 1.5, 2.0, 0.75],
                false,
                [24., 24., 5., 70., 40., 0.22, 20.],
            ),
        ];
        for (name, m, rev, b) in rows {
            let s = ok(&MIN.replace("TinyRobot", name));
            let r = &s.fleets[0].robot;
            assert_eq!(r.model, name);
            let got = [
                r.nominal_drive_speed,
                r.nominal_drive_acceleration,
                r.max_drive_acceleration,
                r.nominal_turn_speed,
                r.nominal_turn_acceleration,
                r.max_turn_acceleration,
                r.stop_distance,
            ];
            assert_eq!(got, m, "{name}");
            assert_eq!(r.stop_radius, m[6]);
            assert_eq!(r.reversible, rev);
            let got = [
                r.nominal_voltage,
                r.nominal_capacity,
                r.charging_current,
                r.mass,
                r.inertia,
                r.friction_coefficient,
                r.nominal_power,
            ];
            assert_eq!(got, b, "{name}");
        }
        // Custom robot: slotcar defaults (§1.1) plus what is set.
        let s = ok(&MIN.replace(
            "TinyRobot",
            "{model: Mine, nominal_drive_speed: 1.2, reversible: false}",
        ));
        let r = &s.fleets[0].robot;
        assert_eq!(
            (r.model.as_str(), r.nominal_drive_speed, r.reversible),
            ("Mine", 1.2, false)
        );
        assert_eq!(r.nominal_turn_speed, std::f64::consts::PI / 8.0);
        assert_eq!(r.nominal_capacity, 24.0);
    }

    #[test]
    fn unknown_preset_lists_presets() {
        let (_, d) = run(&MIN.replace("TinyRobot", "TinyBot"));
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].code, "S0301");
        let help = d[0].help.as_deref().unwrap();
        assert!(help.contains("did you mean `TinyRobot`"), "{help}");
        for p in RobotParams::preset_names() {
            assert!(help.contains(p), "{help}");
        }
        // line 2, column of `TinyBot` in `fleets: [{name: f, robot: TinyBot, ...`.
        assert_eq!((d[0].span.line, d[0].span.col), (2, 27));
    }

    #[test]
    fn unknown_keys_warn_with_a_suggestion_and_keep_the_scenario() {
        let text = format!("{MIN}sed: 3\noptions: {{stop_when_finished: true}}\n")
            .replace("count: 1", "count: 1, recharge_treshold: 0.5");
        let (s, d) = run(&text);
        assert!(s.is_some());
        let codes: Vec<_> = d.iter().map(|x| x.code).collect();
        assert_eq!(codes, ["S0103", "S0103", "S0307"]);
        assert!(d.iter().all(|x| !x.is_error()));
        // Top-level keys are read before the fleets.
        assert_eq!(d[0].help.as_deref(), Some("did you mean `seed`?"));
        assert_eq!(
            d[1].help.as_deref(),
            Some("did you mean `recharge_threshold`?")
        );
        // Too far from any option for a guess: the help lists them.
        assert_eq!(
            d[2].help.as_deref(),
            Some(
                "known keys: `lifts_start_at_initial_floor`, `clean_duration`, `stop_when_done`, \
                 `charging`, `instant_charging`, `battery_drain`"
            )
        );
        assert_eq!(d[0].span.line, 3);
    }

    #[test]
    fn every_problem_is_reported_in_one_run() {
        let text = "\
seed: seven
duration: 8 hours
step: 1
fleets:
  - {name: a, robot: TinyRobot, count: 0}
  - {name: a, robot: TinyRobot, count: 2, recharge_threshold: 20}
  - {robot: [1], count: x}
tasks:
  - {at: 0, patrol: {start: a, finish: b}}
  - {at: 0, loop: {start: a}, go_to_place: b}
  - {go_to_place: {place: p}, fleet: nobody}
";
        let codes = codes_of(text);
        for want in [
            "S0101", "S0105", "S0107", "S0106", "S0108", "S0102", "S0302", "S0303",
        ] {
            assert!(codes.contains(&want), "{want} missing from {codes:?}");
        }
        // seed, duration, step, count 0, threshold, missing name, robot type, count type,
        // patrol, two kinds.
        assert!(codes.len() >= 10, "{codes:?}");
    }

    #[test]
    fn fleet_cross_checks() {
        let base = "duration: 1h\nfleets:\n  - {name: tinyRobot, robot: TinyRobot, count: 1}\n  - {name: cleaners, robot: CleanerBotA, count: 1, tasks: [clean]}\n";
        let t = |task: &str| codes_of(&format!("{base}tasks:\n  - {task}\n"));
        assert_eq!(t("{go_to_place: lobby, fleet: tinyRobots}"), ["S0305"]);
        assert_eq!(
            t("{delivery: {pickup: a, dropoff: b}, fleet: cleaners}"),
            ["S0306"]
        );
        assert!(t("{clean: zone_1, fleet: cleaners}").is_empty());
        let (_, d) = run(&format!(
            "{base}tasks:\n  - {{go_to_place: lobby, fleet: tinyRobots}}\n"
        ));
        assert_eq!(
            d[0].help.as_deref(),
            Some("did you mean `tinyRobot`? fleets: `tinyRobot`, `cleaners`")
        );
        assert_eq!(
            codes_of(&base.replace("name: cleaners", "name: tinyRobot")),
            ["S0304"]
        );
        let only_cleaners =
            "duration: 1h\nfleets: [{name: c, robot: CleanerBotA, count: 1, tasks: [clean]}]\n";
        assert_eq!(
            codes_of(&format!(
                "{only_cleaners}tasks: [{{loop: {{start: a, finish: b}}}}]\n"
            )),
            ["S0306"]
        );
        assert_eq!(
            codes_of(&MIN.replace("count: 1", "count: 3, spawn: [a, b]")),
            ["S0309"]
        );
        assert_eq!(
            codes_of(&MIN.replace("count: 1", "spawn: [a, a]")),
            ["S0309"]
        );
        assert_eq!(
            codes_of(&MIN.replace("count: 1", "count: 1, spawn: anywhere")),
            ["S0101"]
        );
        assert_eq!(
            codes_of(&format!("{MIN}workcells:\n  - {{name: w, kind: dispenser, waypoint: a}}\n  - {{name: w, kind: ingestor, waypoint: b}}\n")),
            ["S0308"]
        );
        assert_eq!(
            codes_of(&format!(
                "{MIN}workcells: [{{name: w, kind: robot, waypoint: a}}]\n"
            )),
            ["S0101"]
        );
    }

    #[test]
    fn ranges_and_absurd_sizes() {
        assert_eq!(
            codes_of(&MIN.replace("count: 1", "count: 10001")),
            ["S0109"]
        );
        assert_eq!(
            codes_of(&MIN.replace("count: 1", "count: 1e300")),
            ["S0109"]
        );
        assert_eq!(codes_of(&MIN.replace("count: 1", "count: -2")), ["S0106"]);
        assert_eq!(codes_of(&MIN.replace("count: 1", "count: 1.5")), ["S0101"]);
        assert!(codes_of(&MIN.replace("count: 1", "count: 10000")).is_empty());
        assert_eq!(codes_of(&MIN.replace("1h", "366d")), ["S0109"]);
        assert!(codes_of(&MIN.replace("1h", "365d")).is_empty());
        assert_eq!(codes_of(&MIN.replace("1h", "0")), ["S0106"]);
        assert_eq!(codes_of(&MIN.replace("1h", ".inf")), ["S0105"]);
        assert_eq!(codes_of(&MIN.replace("1h", "-3")), ["S0105"]);
        assert_eq!(codes_of(&format!("{MIN}step: 0.2\n")), ["S0107"]);
        assert!(codes_of(&format!("{MIN}step: 0.1\n")).is_empty());
        assert_eq!(codes_of(&format!("{MIN}step: 0\n")), ["S0106"]);
        assert_eq!(codes_of(&format!("{MIN}seed: -1\n")), ["S0108"]);
        assert_eq!(
            codes_of(&MIN.replace("count: 1", "count: 1, recharge_soc: 1.5")),
            ["S0108"]
        );
        assert_eq!(
            codes_of(&MIN.replace("count: 1", "count: 1, recharge_threshold: 1")),
            ["S0108"]
        );
        assert_eq!(
            codes_of(&MIN.replace(
                "count: 1",
                "count: 1, recharge_threshold: 0.5, recharge_soc: 0.4"
            )),
            ["S0108"]
        );
        assert_eq!(
            codes_of(&MIN.replace("count: 1", "count: 1, graph: -1")),
            ["S0108"]
        );
        assert_eq!(
            codes_of(&MIN.replace(
                "TinyRobot",
                "{preset: TinyRobot, mass: 0, stop_distance: -1, nominal_power: .nan}"
            )),
            ["S0106", "S0108", "S0108"]
        );
        // 8 h every 30 ms is 960,000 requests: accepted; every 20 ms is 1,440,000: refused.
        let gen = |every: &str| {
            codes_of(&format!(
                "{}generators: [{{every: {every}, go_to_place: a}}]\n",
                MIN.replace("1h", "8h")
            ))
        };
        assert!(gen("30ms").is_empty());
        assert_eq!(gen("20ms"), ["S0109"]);
        assert_eq!(gen("0"), ["S0106"]);
        assert_eq!(
            codes_of(&format!(
                "{MIN}generators: [{{every: 1min, start: 2h, end: 1h, go_to_place: a}}]\n"
            )),
            ["S0108"]
        );
        assert_eq!(
            codes_of(&format!("{MIN}tasks: [{{at: 2h, go_to_place: a}}]\n")),
            ["S0310"]
        );
        assert_eq!(
            codes_of(&format!(
                "{MIN}tasks: [{{loop: {{start: a, finish: b, loops: 2000000}}}}]\n"
            )),
            ["S0109"]
        );
    }

    #[test]
    fn malformed_files_never_panic_and_are_located() {
        let bomb = "a: &a [x, x, x, x, x, x, x, x, x, x]\nb: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a, *a]\nc: &c [*b, *b, *b, *b, *b, *b, *b, *b, *b, *b]\nd: &d [*c, *c, *c, *c, *c, *c, *c, *c, *c, *c]\ne: &e [*d, *d, *d, *d, *d, *d, *d, *d, *d, *d]\nf: [*e, *e, *e, *e, *e, *e, *e, *e, *e, *e]\n";
        let deep = format!("duration: {}1{}\n", "[".repeat(200), "]".repeat(200));
        let garbage: String = (0u32..2000)
            .map(|i| char::from_u32((i * 7919) % 0x2FF + 1).unwrap_or('?'))
            .collect();
        let cases: Vec<(&str, String, &str)> = vec![
            ("empty", String::new(), "S0001"),
            ("comment only", "# nothing\n".into(), "S0001"),
            ("scalar root", "hello".into(), "S0101"),
            ("list root", "- a\n- b\n".into(), "S0101"),
            ("syntax", "fleets: [{name: a\n".into(), "S0001"),
            ("tab", "duration:\n\t- 1\n".into(), "S0001"),
            ("alias bomb", bomb.into(), "S0002"),
            ("deep nesting", deep, "S0002"),
            ("garbage", garbage, ""),
            ("missing all", "seed: 1\n".into(), "S0102"),
            (
                "fleets map",
                "duration: 1\nfleets: {a: 1}\n".into(),
                "S0101",
            ),
            ("fleet scalar", "duration: 1\nfleets: [3]\n".into(), "S0101"),
            (
                "huge int",
                "duration: 99999999999999999999999\nfleets: []\n".into(),
                "S0109",
            ),
            (
                "huge float",
                "duration: 1e400\nfleets: []\n".into(),
                "S0105",
            ),
            ("empty fleets", "duration: 1\nfleets: []\n".into(), "S0102"),
            (
                "null key",
                "duration: 1\n~: 3\nfleets: []\n".into(),
                "S0101",
            ),
            ("task not map", format!("{MIN}tasks: [loop]\n"), "S0101"),
            (
                "kind not map",
                format!("{MIN}tasks: [{{loop: 3}}]\n"),
                "S0101",
            ),
            ("no kind", format!("{MIN}tasks: [{{at: 3}}]\n"), "S0102"),
            (
                "loop no finish",
                format!("{MIN}tasks: [{{loop: {{start: a}}}}]\n"),
                "S0102",
            ),
            ("options list", format!("{MIN}options: [1]\n"), "S0101"),
            (
                "option type",
                format!("{MIN}options: {{stop_when_done: yes}}\n"),
                "S0101",
            ),
            ("dup key", format!("{MIN}seed: 1\nseed: 2\n"), "S0104"),
        ];
        for (name, text, want) in cases {
            let (s, d) = run(&text);
            assert!(!d.is_empty(), "{name}: no diagnostics");
            for x in &d {
                assert!(
                    x.span.line > 0 && x.span.col > 0,
                    "{name}: no position: {x:?}"
                );
            }
            if !want.is_empty() {
                assert!(
                    d.iter().any(|x| x.code == want),
                    "{name}: want {want}, got {d:#?}"
                );
            }
            if mapc_ir::has_errors(&d) {
                assert!(s.is_none(), "{name}");
            }
        }
    }

    #[test]
    fn codes_in_use_are_listed() {
        let src = include_str!("scenario.rs");
        for c in codes::CODES {
            assert!(c.code.starts_with('S') && c.code.len() == 5);
        }
        for (i, _) in src.match_indices("codes::") {
            let name: String = src[i + 7..]
                .chars()
                .take_while(|c| c.is_ascii_uppercase() || *c == '_' || c.is_ascii_digit())
                .collect();
            if name.len() > 2 && name != "CODES" {
                assert!(
                    codes::CODES.iter().any(|c| {
                        let const_src = include_str!("codes.rs");
                        const_src.contains(&format!(
                            "pub const {name}: Code = Code {{\n    code: \"{}\"",
                            c.code
                        ))
                    }),
                    "{name} is not in CODES"
                );
            }
        }
    }

    #[test]
    fn json_schema_lists_the_keys_the_parser_reads() {
        let schema: serde_json::Value =
            serde_json::from_str(include_str!("../../docs/scenario.schema.json")).unwrap();
        assert_eq!(
            schema["$schema"],
            "https://json-schema.org/draft/2020-12/schema"
        );
        let keys = |v: &serde_json::Value| -> Vec<String> {
            let mut k: Vec<String> = v["properties"]
                .as_object()
                .unwrap_or_else(|| panic!("no properties in {v}"))
                .keys()
                .cloned()
                .collect();
            k.sort();
            k
        };
        let want = |names: &[&str], more: &[&str]| -> Vec<String> {
            let mut k: Vec<String> = names.iter().chain(more).map(|s| s.to_string()).collect();
            k.sort();
            k
        };
        let defs = &schema["$defs"];
        assert_eq!(keys(&schema), want(TOP_KEYS, &[]));
        assert_eq!(keys(&defs["fleet"]), want(FLEET_KEYS, &[]));
        assert_eq!(keys(&defs["workcell"]), want(WORKCELL_KEYS, &[]));
        assert_eq!(keys(&defs["options"]), want(OPTION_KEYS, &[]));
        assert_eq!(keys(&defs["crowd"]), want(CROWD_KEYS, &[]));
        assert_eq!(keys(&defs["task"]), want(TASK_KEYS, KINDS));
        assert_eq!(keys(&defs["generator"]), want(GENERATOR_KEYS, KINDS));
        assert_eq!(keys(&defs["fault"]), want(faults::FAULT_KEYS, &[]));
        let robot: Vec<&str> = ROBOT_NUMBERS.iter().map(|r| r.0).collect();
        assert_eq!(
            keys(&defs["robot"]["oneOf"][1]),
            want(&robot, &["preset", "model", "reversible"])
        );
        // Strictly positive robot numbers have exclusiveMinimum 0, the others minimum 0.
        for (k, strict) in ROBOT_NUMBERS {
            let p = &defs["robot"]["oneOf"][1]["properties"][k];
            let bound = if *strict {
                "exclusiveMinimum"
            } else {
                "minimum"
            };
            assert_eq!(p[bound], 0, "{k}");
        }
        for p in RobotParams::preset_names() {
            assert!(defs["preset"]["pattern"].as_str().unwrap().contains(p));
        }
    }

    #[test]
    fn huge_garbage_is_capped_and_fast() {
        // 100,000 unknown keys and 100,000 tasks naming unknown fleets: at most
        // MAX_DIAGNOSTICS are kept, then one S0002; quadratic checks would take minutes.
        let mut text = String::from(MIN);
        for i in 0..100_000 {
            text.push_str(&format!("k{i}: 1\n"));
        }
        text.push_str("tasks:\n");
        for i in 0..100_000 {
            text.push_str(&format!("  - {{go_to_place: p, fleet: g{i}}}\n"));
        }
        let start = std::time::Instant::now();
        let (s, d) = run(&text);
        assert!(s.is_none());
        assert_eq!(d.len(), MAX_DIAGNOSTICS + 1);
        let last = d.last().unwrap();
        assert_eq!(last.code, "S0002");
        assert!(
            last.message.starts_with("199000 more problem(s)"),
            "{}",
            last.message
        );
        // Generous even for a debug build on a loaded machine.
        assert!(start.elapsed().as_secs() < 30, "{:?}", start.elapsed());
        // Warnings alone past the limit still refuse the file.
        let mut text = String::from(MIN);
        for i in 0..1500 {
            text.push_str(&format!("k{i}: 1\n"));
        }
        let (s, d) = run(&text);
        assert!(s.is_none());
        assert_eq!(d.last().unwrap().code, "S0002");
    }
}
