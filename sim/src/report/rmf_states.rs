//! A run in RMF's own API format: each task's final `task_state` and the fleets'
//! `fleet_state` updates (rmf_api_msgs' schemas), so that tools written against RMF's API
//! read a run of mapc. Times are `unix_millis`: the run's start is the requests file's
//! `start_unix_millis` (0 without one) plus the simulated time.

use super::{Report, TaskReport};
use crate::msgs::{robot_mode, FleetState};
use crate::scenario::{RequestKind, Scenario};
use serde_json::{json, Map, Value};

fn millis(start: i64, t: f64) -> i64 {
    start.saturating_add((t * 1000.0).round() as i64)
}

/// RMF's category for a task of mapc's own scenario (`tasks:`, `generators:`).
fn rmf_category(mapc: &str) -> &str {
    match mapc {
        "loop" => "patrol",
        "go_to_place" => "compose",
        c => c,
    }
}

/// The run's start in unix milliseconds.
pub fn start_unix_millis(scenario: &Scenario) -> i64 {
    scenario.requests.first().map_or(0, |r| r.start_unix_millis)
}

/// Each task's final state (in `report.tasks` order), then one failed state per refused
/// request; one JSON object each.
pub fn task_states(scenario: &Scenario, report: &Report) -> Vec<Value> {
    let start = start_unix_millis(scenario);
    let request_of = |line: usize| scenario.requests.iter().find(|r| r.line == line);
    // Task id -> the request it came from (its line in the file; not a cancel of it).
    let mut from_request = std::collections::BTreeMap::new();
    // Task id -> the cancel request that ended it (the first one accepted).
    let mut cancelled_by = std::collections::BTreeMap::new();
    for r in &report.requests {
        let cancel = request_of(r.line).is_some_and(|q| matches!(q.what, RequestKind::Cancel(_)));
        match (&r.task_id, cancel) {
            (Some(id), false) => {
                from_request.insert(id.as_str(), r.line);
            }
            (Some(id), true) if r.refused.is_none() => {
                cancelled_by.entry(id.as_str()).or_insert(r);
            }
            _ => {}
        }
    }
    let mut out: Vec<Value> = report
        .tasks
        .iter()
        .map(|t| {
            let req = from_request.get(t.id.as_str()).and_then(|&l| request_of(l));
            let mut state = task_state(t, req, start);
            // What RMF keeps of the cancel request: when it came, and its labels.
            if let (Some(c), "cancelled") = (cancelled_by.get(t.id.as_str()), t.result.as_str()) {
                let labels = request_of(c.line)
                    .and_then(|q| q.json.get("labels").cloned())
                    .unwrap_or_else(|| json!([]));
                state["cancellation"] = json!({
                    "unix_millis_request_time": millis(start, c.at),
                    "labels": labels,
                });
            }
            state
        })
        .collect();
    for r in report.requests.iter().filter(|r| r.refused.is_some()) {
        let Some(req) = request_of(r.line) else {
            continue;
        };
        let why = r.refused.clone().unwrap_or_default();
        let (category, booking) = booking(&format!("refused_{}", r.line), Some(req), start, r.at);
        out.push(json!({
            "booking": booking,
            "category": category.unwrap_or_else(|| "cancel".into()),
            "detail": why,
            "status": "failed",
            "dispatch": {
                "status": "failed_to_assign",
                "errors": [{"code": 0, "category": "refused", "detail": why}],
            },
        }));
    }
    out
}

/// The booking of a task (and the RMF category its request gave it).
fn booking(
    id: &str,
    req: Option<&crate::scenario::RequestSpec>,
    start: i64,
    requested: f64,
) -> (Option<String>, Value) {
    let mut b = Map::new();
    b.insert("id".into(), json!(id));
    b.insert(
        "unix_millis_request_time".into(),
        json!(millis(start, requested)),
    );
    let mut category = None;
    if let Some(r) = req {
        // The task request inside the API request.
        let inner = &r.json["request"];
        // The requester's own request time, when it gave one, as RMF keeps it.
        for key in [
            "unix_millis_request_time",
            "unix_millis_earliest_start_time",
            "priority",
            "labels",
            "requester",
        ] {
            if let Some(v) = inner.get(key) {
                b.insert(key.into(), v.clone());
            }
        }
        if let RequestKind::Task(t) = &r.what {
            category = Some(t.category.clone());
        }
    }
    (category, Value::Object(b))
}

fn task_state(t: &TaskReport, req: Option<&crate::scenario::RequestSpec>, start: i64) -> Value {
    let requested = t.requested.unwrap_or(0.0);
    let (category, booking) = booking(&t.id, req, start, requested);
    let category = category.unwrap_or_else(|| rmf_category(&t.category).to_string());
    let status = match t.result.as_str() {
        "completed" => "completed",
        "failed" => "failed",
        "cancelled" => "canceled",
        _ if t.started.is_some() => "underway",
        _ if t.assigned.is_some() => "standby",
        _ => "queued",
    };
    let mut s = Map::new();
    s.insert("booking".into(), booking);
    s.insert("category".into(), json!(category));
    let detail = match req {
        Some(r) => r.json["request"]["description"].clone(),
        None => json!(t.detail),
    };
    s.insert("detail".into(), detail);
    if let Some(a) = t.started {
        s.insert("unix_millis_start_time".into(), json!(millis(start, a)));
    }
    if let Some(f) = t.finished {
        s.insert("unix_millis_finish_time".into(), json!(millis(start, f)));
    }
    if !t.robot.is_empty() {
        s.insert(
            "assigned_to".into(),
            json!({"group": t.fleet, "name": t.robot}),
        );
    }
    s.insert("status".into(), json!(status));
    let dispatch = if !t.robot.is_empty() {
        json!({"status": "dispatched", "assignment": {"fleet_name": t.fleet, "expected_robot_name": t.robot}})
    } else if t.result == "failed" {
        json!({"status": "failed_to_assign", "errors": [{"code": 0, "category": "failed", "detail": t.detail}]})
    } else {
        json!({"status": "queued"})
    };
    s.insert("dispatch".into(), dispatch);
    phases(&mut s, t, start);
    Value::Object(s)
}

/// RMF's category of a phase (what RMF's own phases of the kind are called), from its
/// detail as the fleet layer names it.
fn phase_category(detail: &str) -> String {
    let (kind, rest) = detail.split_once(' ').unwrap_or((detail, ""));
    match kind {
        "go_to_place" => format!("Go to [place:{rest}]"),
        "pickup" => "Pick up".into(),
        "dropoff" => "Drop Off".into(),
        "clean" => "Clean".into(),
        _ => detail.into(),
    }
}

/// One RMF phase per phase of the task (ids from 1), each with one event: `completed`
/// once done, the task's status for the phase it ended in or is under way in; phases not
/// reached have no times and no event and are `pending`.
fn phases(s: &mut Map<String, Value>, t: &TaskReport, start: i64) {
    if t.phases.is_empty() {
        return;
    }
    let (mut phases, mut completed, mut active, mut pending) =
        (Map::new(), Vec::new(), None, Vec::new());
    for (k, p) in t.phases.iter().enumerate() {
        let id = k + 1;
        let category = phase_category(&p.detail);
        let mut phase = Map::new();
        phase.insert("id".into(), json!(id));
        phase.insert("category".into(), json!(category));
        phase.insert("detail".into(), json!(p.detail));
        if let Some(a) = p.started {
            phase.insert("unix_millis_start_time".into(), json!(millis(start, a)));
        }
        if let Some(f) = p.finished {
            phase.insert("unix_millis_finish_time".into(), json!(millis(start, f)));
        }
        let status = match p.result.as_str() {
            "completed" => "completed",
            "failed" => "failed",
            "cancelled" => "canceled",
            "unfinished" => "underway",
            _ => "",
        };
        match status {
            "" => pending.push(id),
            "underway" => active = Some(id),
            _ => completed.push(id),
        }
        if !status.is_empty() {
            phase.insert("final_event_id".into(), json!(0));
            phase.insert(
                "events".into(),
                json!({"0": {"id": 0, "status": status, "name": category, "detail": p.detail}}),
            );
        }
        phases.insert(id.to_string(), Value::Object(phase));
    }
    s.insert("phases".into(), Value::Object(phases));
    s.insert("completed".into(), json!(completed));
    if let Some(a) = active {
        s.insert("active".into(), json!(a));
    }
    s.insert("pending".into(), json!(pending));
}

/// A `fleet_state_update` of a fleet state the fleet layer published at `t`.
pub fn fleet_state_update(f: &FleetState, t: f64, start_unix_millis: i64) -> Value {
    let mut robots = Map::new();
    for r in &f.robots {
        let status = match r.mode.mode {
            robot_mode::IDLE => "idle",
            robot_mode::CHARGING => "charging",
            robot_mode::EMERGENCY | robot_mode::ADAPTER_ERROR => "error",
            _ if r.task_id.is_empty() => "idle",
            _ => "working",
        };
        robots.insert(
            r.name.clone(),
            json!({
                "name": r.name,
                "status": status,
                "task_id": r.task_id,
                "unix_millis_time": millis(start_unix_millis, t),
                "location": {
                    "map": r.location.level_name,
                    "x": r.location.x,
                    "y": r.location.y,
                    "yaw": r.location.yaw,
                },
                "battery": (r.battery_percent / 100.0).clamp(0.0, 1.0),
                "issues": [],
            }),
        );
    }
    json!({"type": "fleet_state_update", "data": {"name": f.name, "robots": robots}})
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::PhaseReport;

    fn phase(
        detail: &str,
        started: Option<f64>,
        finished: Option<f64>,
        result: &str,
    ) -> PhaseReport {
        PhaseReport {
            detail: detail.into(),
            started,
            finished,
            result: result.into(),
        }
    }

    /// A failed task: the phase it failed in is `failed` and among the completed ones;
    /// the ones not reached are pending, without times or events. A task under way at the
    /// end: its phase under way is the active one.
    #[test]
    fn phases_say_where_the_task_ended() {
        let mut t = TaskReport {
            id: "delivery_0".into(),
            category: "delivery".into(),
            started: Some(2.0),
            finished: Some(15.0),
            result: "failed".into(),
            phases: vec![
                phase("go_to_place a", Some(2.0), Some(10.0), "completed"),
                phase("pickup at a from d", Some(10.0), Some(15.0), "failed"),
                phase("go_to_place b", None, None, "pending"),
                phase("dropoff at b into i", None, None, "pending"),
            ],
            ..TaskReport::default()
        };
        let s = task_state(&t, None, 1000);
        assert_eq!(s["status"], "failed");
        assert_eq!(s["completed"], json!([1, 2]));
        assert_eq!(s["pending"], json!([3, 4]));
        assert!(s.get("active").is_none());
        let p = &s["phases"];
        assert_eq!(p["1"]["category"], "Go to [place:a]");
        assert_eq!(p["1"]["unix_millis_start_time"], 3000);
        assert_eq!(p["1"]["unix_millis_finish_time"], 11000);
        assert_eq!(p["1"]["events"]["0"]["status"], "completed");
        assert_eq!(p["2"]["category"], "Pick up");
        assert_eq!(p["2"]["unix_millis_finish_time"], 16000);
        assert_eq!(p["2"]["events"]["0"]["status"], "failed");
        assert_eq!(p["2"]["final_event_id"], 0);
        assert_eq!(p["4"]["category"], "Drop Off");
        assert_eq!(
            p["3"],
            json!({"id": 3, "category": "Go to [place:b]", "detail": "go_to_place b"})
        );
        // Under way when the run ended.
        t.result = "unfinished".into();
        t.finished = None;
        t.phases[1] = phase("pickup at a from d", Some(10.0), None, "unfinished");
        let s = task_state(&t, None, 1000);
        assert_eq!(s["status"], "underway");
        assert_eq!(s["completed"], json!([1]));
        assert_eq!(s["active"], 2);
        assert_eq!(s["pending"], json!([3, 4]));
        assert_eq!(s["phases"]["2"]["events"]["0"]["status"], "underway");
        assert!(s["phases"]["2"].get("unix_millis_finish_time").is_none());
        // Never started: no phases.
        let q = task_state(&TaskReport::default(), None, 0);
        assert!(q.get("phases").is_none() && q.get("completed").is_none());
    }
}
