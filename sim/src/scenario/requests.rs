//! `requests:` a JSON Lines file of RMF task API requests, one per line with the simulated
//! time it arrives: `{"at": "5min", "request": {"type": "dispatch_task_request", ...}}`.
//! Read with serde types of the API's shapes (rmf_api_msgs' `dispatch_task_request`,
//! `robot_task_request`, `cancel_task_request`, and the fleet adapter's task descriptions);
//! each description is mapped onto one of mapc's task kinds. Problems are located at
//! file:line:col in the requests file.

use super::{codes, parse_duration, TaskKind, P};
use mapc_ir::{FileId, Span};
use serde::Deserialize;
use serde_json::Value;

/// Most lines a requests file may have.
const MAX_LINES: usize = 1_000_000;

/// One line of the requests file.
#[derive(Debug, Clone, PartialEq)]
pub struct RequestSpec {
    /// 1-based line in the requests file.
    pub line: usize,
    /// The whole line.
    pub span: Span,
    /// When it arrives (s).
    pub at: f64,
    pub what: RequestKind,
    /// The request as written (for the task state's booking).
    pub json: Value,
    /// The run's start in unix milliseconds (`requests: {start_unix_millis}`).
    pub start_unix_millis: i64,
}

#[derive(Debug, Clone, PartialEq)]
pub enum RequestKind {
    /// A task for any fleet (`fleet` set by `fleet_name`) or for one robot's fleet.
    Task(RequestedTask),
    /// `cancel_task_request` for a task id.
    Cancel(String),
    /// A well-formed request for something mapc cannot simulate (an action other than
    /// cleaning, ...): refused, and why.
    Unsupported(String),
}

#[derive(Debug, Clone, PartialEq)]
pub struct RequestedTask {
    /// RMF's category (`patrol`, `delivery`, `clean`, `compose` or its own category).
    pub category: String,
    pub kind: TaskKind,
    /// The places it names and where (to check them against the map).
    pub places: Vec<(String, Span)>,
    /// `fleet_name` of the request, or the fleet of a robot task.
    pub fleet: Option<String>,
    /// The robot of a `robot_task_request` (the only robot that may do it).
    pub robot: Option<String>,
    /// `unix_millis_earliest_start_time` (ms).
    pub earliest_start_ms: Option<i64>,
    /// The binary priority's value (0 or 1).
    pub priority: u64,
}

// ---- the API's shapes (only what mapc reads; other fields are allowed, as in RMF) ----

#[derive(Deserialize)]
struct Line {
    at: Value,
    request: Value,
}

#[derive(Deserialize)]
#[serde(tag = "type")]
enum ApiRequest {
    #[serde(rename = "dispatch_task_request")]
    Dispatch { request: TaskRequest },
    #[serde(rename = "robot_task_request")]
    Robot {
        robot: String,
        fleet: String,
        request: TaskRequest,
    },
    #[serde(rename = "cancel_task_request")]
    Cancel { task_id: String },
}

#[derive(Deserialize)]
struct TaskRequest {
    category: String,
    description: Value,
    #[serde(default)]
    unix_millis_earliest_start_time: Option<i64>,
    #[serde(default)]
    #[allow(dead_code)] // read for the schema's sake
    unix_millis_request_time: Option<i64>,
    #[serde(default)]
    priority: Option<Priority>,
    #[serde(default)]
    fleet_name: Option<String>,
    #[serde(default)]
    #[allow(dead_code)]
    labels: Option<Vec<String>>,
    #[serde(default)]
    #[allow(dead_code)]
    requester: Option<String>,
}

#[derive(Deserialize)]
struct Priority {
    #[serde(default)]
    #[allow(dead_code)]
    r#type: Option<String>,
    #[serde(default)]
    value: Option<u64>,
}

/// `place.json`: a waypoint name (or index), or `{waypoint, orientation}`.
#[derive(Deserialize)]
#[serde(untagged)]
enum Place {
    Name(String),
    Index(u64),
    Full {
        waypoint: Box<Place>,
        #[serde(default)]
        #[allow(dead_code)]
        orientation: Option<f64>,
    },
}

#[derive(Deserialize)]
struct Patrol {
    places: Vec<Place>,
    #[serde(default)]
    rounds: Option<u32>,
}

#[derive(Deserialize)]
struct Transfer {
    place: Place,
    #[serde(default)]
    handler: Option<String>,
    #[allow(dead_code)] // required by the schema; items are not simulated
    payload: Value,
}

#[derive(Deserialize)]
struct Delivery {
    pickup: Transfer,
    dropoff: Transfer,
}

#[derive(Deserialize)]
struct Clean {
    zone: String,
}

#[derive(Deserialize)]
struct Compose {
    #[serde(default)]
    category: Option<String>,
    phases: Vec<Phase>,
}

#[derive(Deserialize)]
struct Phase {
    activity: Activity,
}

#[derive(Deserialize)]
struct Activity {
    category: String,
    description: Value,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum GoTo {
    Place(Place),
    To { place: Place },
}

#[derive(Deserialize)]
struct PerformAction {
    category: String,
    description: Value,
    #[serde(default)]
    #[allow(dead_code)]
    unix_millis_action_duration_estimate: Option<i64>,
}

/// A step of a composed task, flattened out of its phases and sequences.
enum Step {
    GoTo(String),
    Pickup(String, Option<String>),
    Dropoff(String, Option<String>),
    Action(String, Value),
}

/// Why a line is not a request mapc can read (message, byte offset in the line).
type Bad = (String, usize);

fn place_name(p: &Place) -> Result<String, String> {
    match p {
        Place::Name(n) if !n.is_empty() => Ok(n.clone()),
        Place::Name(_) => Err("a place is an empty name".into()),
        Place::Index(i) => Err(format!(
            "place {i} is a waypoint index; mapc names places (use the waypoint's name)"
        )),
        Place::Full { waypoint, .. } => place_name(waypoint),
    }
}

fn from<T: for<'de> Deserialize<'de>>(v: &Value, what: &str) -> Result<T, String> {
    T::deserialize(v).map_err(|e| format!("{what}: {e}"))
}

/// Steps of an activity (a `sequence` is flattened).
fn steps(a: &Activity, out: &mut Vec<Step>, depth: usize) -> Result<(), String> {
    if depth > 16 {
        return Err("sequences nest too deep".into());
    }
    match a.category.as_str() {
        "sequence" => {
            // `[activity, ...]` or `{activities: [...]}`.
            let list = match &a.description {
                Value::Array(l) => l.clone(),
                Value::Object(m) => match m.get("activities") {
                    Some(Value::Array(l)) => l.clone(),
                    _ => return Err("a sequence lists no activities".into()),
                },
                _ => return Err("a sequence's description must be a list of activities".into()),
            };
            for item in &list {
                let act: Activity = from(item, "an activity of the sequence")?;
                steps(&act, out, depth + 1)?;
            }
        }
        "go_to_place" => {
            let g: GoTo = from(&a.description, "go_to_place")?;
            let p = match &g {
                GoTo::Place(p) | GoTo::To { place: p } => place_name(p)?,
            };
            out.push(Step::GoTo(p));
        }
        "pickup" | "dropoff" => {
            let t: Transfer = from(&a.description, &a.category)?;
            let p = place_name(&t.place)?;
            out.push(if a.category == "pickup" {
                Step::Pickup(p, t.handler)
            } else {
                Step::Dropoff(p, t.handler)
            });
        }
        "perform_action" => {
            let pa: PerformAction = from(&a.description, "perform_action")?;
            // rmf_demos' deliveries: the pick-up and drop-off as actions at the place
            // the robot went to, the workcell named in the action's description.
            let last = out.iter().rev().find_map(|s| match s {
                Step::GoTo(p) => Some(p.clone()),
                _ => None,
            });
            let text = |k: &str| {
                pa.description
                    .get(k)
                    .and_then(Value::as_str)
                    .map(String::from)
            };
            match pa.category.as_str() {
                "delivery_pickup" => match text("pickup_place_name").or(last) {
                    Some(p) => out.push(Step::Pickup(p, text("pickup_dispenser"))),
                    None => return Err("the delivery_pickup action has no place".into()),
                },
                "delivery_dropoff" => match text("dropoff_place_name").or(last) {
                    Some(p) => out.push(Step::Dropoff(p, text("dropoff_ingestor"))),
                    None => return Err("the delivery_dropoff action has no place".into()),
                },
                _ => out.push(Step::Action(pa.category, pa.description)),
            }
        }
        "clean" => {
            let c: Clean = from(&a.description, "clean")?;
            out.push(Step::Action(
                "clean".into(),
                serde_json::json!({"zone": c.zone}),
            ));
        }
        other => return Err(format!("mapc cannot simulate a `{other}` activity")),
    }
    Ok(())
}

/// A composed task as one of mapc's kinds: going to a place, going between two places,
/// a pick-up then a drop-off (the robot drives between them by itself), or cleaning a zone
/// (perform_action `clean`, usually after going there).
fn compose_kind(steps: &[Step]) -> Result<TaskKind, String> {
    if let Some(Step::Action(cat, desc)) = steps.iter().find(|s| matches!(s, Step::Action(..))) {
        if cat != "clean" {
            return Err(format!(
                "mapc cannot simulate the action `{cat}` (its robots go to places, deliver and clean)"
            ));
        }
        let zone = desc
            .get("zone")
            .and_then(Value::as_str)
            .ok_or("the `clean` action names no `zone`")?;
        return Ok(TaskKind::Clean { zone: zone.into() });
    }
    let pickups: Vec<_> = steps
        .iter()
        .filter_map(|s| match s {
            Step::Pickup(p, h) => Some((p, h)),
            _ => None,
        })
        .collect();
    let dropoffs: Vec<_> = steps
        .iter()
        .filter_map(|s| match s {
            Step::Dropoff(p, h) => Some((p, h)),
            _ => None,
        })
        .collect();
    let gotos: Vec<&String> = steps
        .iter()
        .filter_map(|s| match s {
            Step::GoTo(p) => Some(p),
            _ => None,
        })
        .collect();
    match (pickups.as_slice(), dropoffs.as_slice(), gotos.as_slice()) {
        ([(p, ph)], [(d, dh)], _) => Ok(TaskKind::Delivery {
            pickup: (*p).clone(),
            dropoff: (*d).clone(),
            dispenser: (*ph).clone(),
            ingestor: (*dh).clone(),
        }),
        ([], [], [p]) => Ok(TaskKind::GoToPlace {
            place: (*p).clone(),
        }),
        ([], [], [a, b]) => Ok(TaskKind::Loop {
            start: (*a).clone(),
            finish: (*b).clone(),
            loops: 1,
        }),
        _ => Err("mapc cannot simulate this composition (it simulates go_to_place, two places in turn, one pickup then one dropoff, or a clean action)".into()),
    }
}

/// The task kind and RMF category of a task request.
fn task_kind(r: &TaskRequest) -> Result<(String, TaskKind), String> {
    let kind = match r.category.as_str() {
        "patrol" => {
            let p: Patrol = from(&r.description, "the patrol description")?;
            let names = p
                .places
                .iter()
                .map(place_name)
                .collect::<Result<Vec<_>, _>>()?;
            let rounds = p.rounds.unwrap_or(1).max(1);
            match names.as_slice() {
                [one] => TaskKind::GoToPlace { place: one.clone() },
                [a, b] => TaskKind::Loop {
                    start: a.clone(),
                    finish: b.clone(),
                    loops: rounds,
                },
                [] => return Err("the patrol lists no places".into()),
                _ => TaskKind::Patrol {
                    places: names,
                    rounds,
                },
            }
        }
        "delivery" => {
            let d: Delivery = from(&r.description, "the delivery description")?;
            TaskKind::Delivery {
                pickup: place_name(&d.pickup.place)?,
                dropoff: place_name(&d.dropoff.place)?,
                dispenser: d.pickup.handler,
                ingestor: d.dropoff.handler,
            }
        }
        "clean" => {
            let c: Clean = from(&r.description, "the clean description")?;
            TaskKind::Clean { zone: c.zone }
        }
        "compose" => {
            let c: Compose = from(&r.description, "the compose description")?;
            if c.phases.is_empty() {
                return Err("the composed task has no phases".into());
            }
            let mut out = Vec::new();
            for ph in &c.phases {
                steps(&ph.activity, &mut out, 0)?;
            }
            let k = compose_kind(&out)?;
            return Ok((c.category.unwrap_or_else(|| "compose".into()), k));
        }
        other => {
            return Err(format!(
                "unknown task category `{other}`; RMF's are patrol, delivery, clean and compose"
            ))
        }
    };
    Ok((r.category.clone(), kind))
}

/// Where in the line a serde message's offending value is: the quoted string of an
/// `invalid type: string "x"` or `invalid value: string "x"`, when it is there once.
fn locate(line: &str, msg: &str) -> Option<usize> {
    let rest = msg.split("string \"").nth(1)?;
    let value = rest.split('"').next()?;
    let quoted = serde_json::to_string(value).ok()?;
    let at = line.find(&quoted)?;
    (line.matches(&quoted).count() == 1).then_some(at)
}

/// Byte offset of the JSON string `s` in `line` (for locating a place), else 0.
fn find_str(line: &str, s: &str) -> usize {
    let quoted = serde_json::to_string(s).unwrap_or_default();
    line.find(&quoted).map_or(0, |i| i + 1)
}

type Places = Vec<(String, usize)>;

fn task_of(
    request: TaskRequest,
    robot: Option<String>,
    text: &str,
    req_pos: usize,
) -> Result<(RequestKind, Places), Bad> {
    let desc_pos = text.find("\"description\"").unwrap_or(req_pos);
    let (category, kind) = match task_kind(&request) {
        Ok(x) => x,
        Err(e) if e.starts_with("mapc cannot") => {
            return Ok((RequestKind::Unsupported(e), Vec::new()));
        }
        Err(e) => {
            let at = locate(text, &e).unwrap_or(desc_pos);
            return Err((e, at));
        }
    };
    let places: Places = kind
        .places()
        .into_iter()
        .map(|p| (p.to_string(), find_str(text, p)))
        .collect();
    let priority = request.priority.and_then(|p| p.value).unwrap_or(0);
    Ok((
        RequestKind::Task(RequestedTask {
            category,
            kind,
            places: Vec::new(),
            fleet: request.fleet_name,
            robot,
            earliest_start_ms: request.unix_millis_earliest_start_time,
            priority,
        }),
        places,
    ))
}

/// Reads one line (without its newline).
fn read_line(text: &str) -> Result<(f64, RequestKind, Value, Places), Bad> {
    let line: Line = serde_json::from_str(text).map_err(|e| {
        let col = e.column().saturating_sub(1);
        let msg = e.to_string();
        // serde_json ends its messages with " at line L column C".
        let msg = msg.split(" at line ").next().unwrap_or(&msg).to_string();
        (msg, col)
    })?;
    let at_pos = text.find("\"at\"").unwrap_or(0);
    let at = match &line.at {
        Value::Number(n) => n.as_f64().filter(|x| x.is_finite() && *x >= 0.0),
        Value::String(s) => parse_duration(s).ok(),
        _ => None,
    }
    .ok_or_else(|| {
        (
            format!(
                "`at` must be a time: seconds, or a duration such as \"90s\", \"5min\", found {}",
                line.at
            ),
            at_pos,
        )
    })?;
    let req_pos = text.find("\"request\"").unwrap_or(0);
    let api: ApiRequest = from(&line.request, "the request").map_err(|e| (e, req_pos))?;
    let (what, places) = match api {
        ApiRequest::Cancel { task_id } => (RequestKind::Cancel(task_id), Vec::new()),
        ApiRequest::Dispatch { request } => task_of(request, None, text, req_pos)?,
        ApiRequest::Robot {
            robot,
            fleet,
            mut request,
        } => {
            request.fleet_name = Some(fleet);
            task_of(request, Some(robot), text, req_pos)?
        }
    };
    Ok((at, what, line.request, places))
}

impl P<'_> {
    /// Reads the requests file (already included as file `id`).
    pub(super) fn requests(&mut self, id: FileId, text: &str) -> Option<Vec<RequestSpec>> {
        let mut out = Vec::new();
        let mut ok = true;
        let mut offset = 0usize;
        for (i, raw) in text.split_inclusive('\n').enumerate() {
            let start = offset;
            offset += raw.len();
            let line = raw.trim_end_matches(['\n', '\r']);
            if line.trim().is_empty() {
                continue;
            }
            let span_at = |col: usize| Span {
                file: id,
                start: (start + col) as u32,
                end: (start + line.len()) as u32,
                line: (i + 1) as u32,
                col: line[..col.min(line.len())].chars().count() as u32 + 1,
            };
            if i >= MAX_LINES {
                self.error(
                    codes::TOO_LARGE,
                    span_at(0),
                    format!("the requests file has more than {MAX_LINES} lines"),
                );
                return None;
            }
            match read_line(line) {
                Ok((at, mut what, json, places)) => {
                    if let RequestKind::Task(t) = &mut what {
                        t.places = places
                            .into_iter()
                            .map(|(p, col)| {
                                let mut s = span_at(col);
                                s.end = s.start + p.len() as u32;
                                (p, s)
                            })
                            .collect();
                    }
                    out.push(RequestSpec {
                        line: i + 1,
                        span: span_at(0),
                        at,
                        what,
                        json,
                        start_unix_millis: 0,
                    });
                }
                Err((msg, col)) => {
                    self.error(codes::BAD_REQUEST, span_at(col.min(line.len())), msg);
                    self.help("one JSON object a line: {\"at\": \"5min\", \"request\": {\"type\": \"dispatch_task_request\", \"request\": {\"category\": ..., \"description\": ...}}}, as RMF's API server takes it");
                    ok = false;
                }
            }
        }
        ok.then_some(out)
    }
}

/// What became of a request once checked against the map.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum RequestOutcome {
    /// Queued as `scenario.tasks[i]` of the scenario returned with it.
    Task(usize),
    /// Refused as RMF would refuse it (or as mapc cannot do it), and why.
    Refused(String),
    /// A cancel of this task, as `scenario.cancels[i]`.
    Cancel(String, usize),
}

/// The scenario with its accepted requests appended to `tasks`, and what became of each
/// request. A place no waypoint of the map is named is an error (located in the requests
/// file); a request no fleet can take (its category, its fleet, its places off the graphs
/// of the fleets that could) is refused, as RMF's dispatcher refuses it.
pub(crate) fn accept_requests(
    building: &mapc_ir::Building,
    scenario: &super::Scenario,
) -> Result<(super::Scenario, Vec<RequestOutcome>), Vec<mapc_ir::Diagnostic>> {
    use std::collections::{BTreeMap, BTreeSet};
    let mut out = scenario.clone();
    let mut outcomes = Vec::with_capacity(scenario.requests.len());
    if scenario.requests.is_empty() {
        return Ok((out, outcomes));
    }
    let named: BTreeSet<&str> = building
        .vertices
        .iter()
        .map(|(_, v)| v.name.as_str())
        .filter(|n| !n.is_empty())
        .collect();
    // Per graph, the names of its lanes' ends.
    let mut on_graph: BTreeMap<i64, BTreeSet<&str>> = BTreeMap::new();
    for (_, l) in building.lanes.iter() {
        let set = on_graph.entry(l.graph).or_default();
        for v in [l.start, l.end] {
            let n = building.vertices[v].name.as_str();
            if !n.is_empty() {
                set.insert(n);
            }
        }
    }
    let mut diags = Vec::new();
    for r in &scenario.requests {
        let t = match &r.what {
            RequestKind::Cancel(id) => {
                // What it does is known as the run goes (the fleet layer says).
                outcomes.push(RequestOutcome::Cancel(id.clone(), out.cancels.len()));
                out.cancels.push(super::CancelSpec {
                    at: r.at,
                    task_id: id.clone(),
                });
                continue;
            }
            RequestKind::Unsupported(why) => {
                outcomes.push(RequestOutcome::Refused(why.clone()));
                continue;
            }
            RequestKind::Task(t) => t,
        };
        for (p, span) in &t.places {
            if !named.contains(p.as_str()) {
                let hint = mapc_frontend::spelling::nearest(p, named.iter().copied())
                    .map(|n| format!("nearest: `{n}`"))
                    .unwrap_or_else(|| "the map has no named waypoints".into());
                diags.push(
                    mapc_ir::Diagnostic::error(
                        super::codes::UNKNOWN_WAYPOINT.code,
                        *span,
                        format!("no waypoint of the map is named `{p}`"),
                    )
                    .with_help(hint),
                );
            }
        }
        let cat = t.kind.category();
        let fleets: Vec<&super::FleetSpec> = scenario
            .fleets
            .iter()
            .filter(|f| t.fleet.as_ref().is_none_or(|n| *n == f.name))
            .collect();
        let refused = if let (Some(n), true) = (&t.fleet, fleets.is_empty()) {
            Some(format!("no fleet is named `{n}`"))
        } else {
            let capable: Vec<&&super::FleetSpec> = fleets
                .iter()
                .filter(|f| f.task_kinds.is_empty() || f.task_kinds.contains(&cat))
                .collect();
            if capable.is_empty() {
                Some(format!(
                    "no fleet{} is capable of {} tasks",
                    t.fleet
                        .as_ref()
                        .map(|n| format!(" (`{n}`)"))
                        .unwrap_or_default(),
                    t.category
                ))
            } else if !capable.iter().any(|f| {
                let set = on_graph.get(&f.graph);
                t.places
                    .iter()
                    .all(|(p, _)| set.is_some_and(|s| s.contains(p.as_str())))
            }) {
                let places: Vec<String> = t.places.iter().map(|p| format!("`{}`", p.0)).collect();
                Some(format!(
                    "{} not on the graph of any fleet capable of it",
                    places.join(", ")
                ))
            } else {
                None
            }
        };
        match refused {
            Some(why) => outcomes.push(RequestOutcome::Refused(why)),
            None => {
                outcomes.push(RequestOutcome::Task(out.tasks.len()));
                out.tasks.push(super::TaskSpec {
                    at: r.at,
                    kind: t.kind.clone(),
                    fleet: t.fleet.clone(),
                    robot: t.robot.clone(),
                    priority: t.priority,
                    span: t.places.first().map_or(r.span, |p| p.1),
                });
            }
        }
    }
    if diags.is_empty() {
        Ok((out, outcomes))
    } else {
        Err(diags)
    }
}

/// The id the fleet layer gives each of `scenario.tasks` (`<category>_<n>`, numbered per
/// category in the order tasks are requested: by time, listed tasks before generated
/// ones at equal times).
pub(crate) fn task_ids(scenario: &super::Scenario) -> Vec<String> {
    use std::collections::BTreeMap;
    // (time, source order, task index if listed, category).
    let mut order: Vec<(f64, usize, Option<usize>, super::TaskCategory)> = Vec::new();
    for (i, t) in scenario.tasks.iter().enumerate() {
        order.push((t.at, i, Some(i), t.kind.category()));
    }
    let base = scenario.tasks.len();
    for (g, gen) in scenario.generators.iter().enumerate() {
        for at in gen.times(scenario.duration) {
            order.push((at, base + g, None, gen.kind.category()));
        }
    }
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut counters: BTreeMap<super::TaskCategory, usize> = BTreeMap::new();
    let mut ids = vec![String::new(); scenario.tasks.len()];
    for (_, _, listed, cat) in order {
        let n = counters.entry(cat).or_insert(0);
        if let Some(i) = listed {
            ids[i] = format!("{}_{}", cat.as_str(), *n);
        }
        *n += 1;
    }
    ids
}
