//! Collecting a sweep: OUT/plan.json (what the runs are, written when the sweep is planned)
//! and each run's report become OUT/results.csv, OUT/results.json and OUT/capacity.svg.
//! Every executor ends here, and only files are read, so the results are the same bytes
//! whoever ran the runs and in whatever order.

use super::run::{run_dir, up_to_date};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::Path;

/// OUT/plan.json.
#[derive(Serialize, Deserialize)]
pub(crate) struct PlanFile {
    pub mapc: String,
    /// The varying axes (columns), in column order.
    pub axes: Vec<AxisInfo>,
    pub runs: Vec<RunInfo>,
}

#[derive(Serialize, Deserialize)]
pub(crate) struct AxisInfo {
    pub path: String,
    pub zipped: bool,
}

#[derive(Serialize, Deserialize)]
pub(crate) struct RunInfo {
    pub run: String,
    /// One per axis; `text` as written in the sweep file.
    pub values: Vec<AxisValue>,
    pub inputs: String,
}

#[derive(Serialize, Deserialize, Clone)]
pub(crate) struct AxisValue {
    pub text: String,
    pub value: Value,
}

/// The headline numbers of a report, in column order.
pub(crate) const COLUMNS: &[&str] = &[
    "robots",
    "reserve",
    "tasks_completed",
    "tasks_failed",
    "tasks_unfinished",
    "throughput_per_hour",
    "utilisation",
    "idle_with_work",
    "wait_traffic_s",
    "wait_lift_s",
    "wait_door_s",
    "wait_workcell_s",
    "wait_charging_s",
    "door_utilisation_max",
    "lift_utilisation_max",
    "near_misses",
    "contacts",
    "stuck",
    "bottleneck",
    "bottleneck_cause",
    "bottleneck_wait_s",
    "bottleneck_share",
    "bound_per_hour",
    "bound_limited_by",
    "bound_share",
];

/// One row: a run and, when it is done, its headline numbers (same order as `COLUMNS`).
pub(crate) struct Row {
    pub run: String,
    pub values: Vec<AxisValue>,
    pub numbers: Option<Vec<Value>>,
}

impl Row {
    pub fn number(&self, column: &str) -> Option<f64> {
        let i = COLUMNS.iter().position(|c| *c == column)?;
        self.numbers.as_ref()?.get(i)?.as_f64()
    }
    pub fn text(&self, column: &str) -> Option<&str> {
        let i = COLUMNS.iter().position(|c| *c == column)?;
        self.numbers.as_ref()?.get(i)?.as_str()
    }
}

fn num(v: f64) -> Value {
    serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number)
}

/// The headline numbers of `report` (the JSON `mapc sim --report` writes).
fn headline(report: &Value) -> Vec<Value> {
    let list = |k: &str| report[k].as_array().cloned().unwrap_or_default();
    let fleets = list("fleets");
    let sum = |k: &str| fleets.iter().filter_map(|f| f[k].as_f64()).sum::<f64>();
    let robots: f64 = sum("robots");
    let busy: f64 = fleets
        .iter()
        .filter_map(|f| Some(f["utilisation"].as_f64()? * f["robots"].as_f64()?))
        .sum();
    let max_util = |k: &str| {
        list(k)
            .iter()
            .filter_map(|d| d["utilisation"].as_f64())
            .fold(0.0, f64::max)
    };
    let waits = &report["waits"];
    let b = &report["bottleneck"];
    // The fleets' sizes as asked; `reserve` of them stayed in the depot (not needed, or
    // no home).
    let reserve = sum("reserve") as u64;
    vec![
        Value::from(list("robots").len() as u64 + reserve),
        Value::from(reserve),
        Value::from(sum("tasks_completed") as u64),
        Value::from(sum("tasks_failed") as u64),
        Value::from(sum("tasks_unfinished") as u64),
        num(sum("throughput_per_hour")),
        num(if robots > 0.0 { busy / robots } else { 0.0 }),
        // Robots idle on average while work waited (see the report's `idle_with_work_s`).
        num(match report["end_time"].as_f64() {
            Some(t) if t > 0.0 => sum("idle_with_work_s") / t,
            _ => 0.0,
        }),
        waits["traffic_s"].clone(),
        waits["lift_s"].clone(),
        waits["door_s"].clone(),
        waits["workcell_s"].clone(),
        waits["charging_s"].clone(),
        num(max_util("doors")),
        num(max_util("lifts")),
        Value::from(list("near_misses").len()),
        Value::from(list("contacts").len()),
        Value::from(list("stuck").len()),
        b["place"].clone(),
        b["cause"].clone(),
        b["wait_s"].clone(),
        b["share"].clone(),
        report["throughput"]["tasks_per_hour"].clone(),
        report["throughput"]["limited_by"].clone(),
        report["throughput"]["share"].clone(),
    ]
}

/// Reads the plan and every run that is done.
pub(crate) fn read(out: &Path) -> Result<(PlanFile, Vec<Row>), String> {
    let path = out.join("plan.json");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        format!(
            "{}: {e} (is `{}` the output directory of a sweep?)",
            crate::ui::shown(&path),
            crate::ui::shown(out)
        )
    })?;
    let plan: PlanFile =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", crate::ui::shown(&path)))?;
    let mut rows = Vec::new();
    for r in &plan.runs {
        let numbers = if up_to_date(out, &r.run, &r.inputs) {
            let p = run_dir(out, &r.run).join("report.json");
            let report: Value = std::fs::read_to_string(&p)
                .map_err(|e| e.to_string())
                .and_then(|t| serde_json::from_str(&t).map_err(|e| e.to_string()))
                .map_err(|e| format!("{}: {e}", crate::ui::shown(&p)))?;
            Some(headline(&report))
        } else {
            None
        };
        rows.push(Row {
            run: r.run.clone(),
            values: r.values.clone(),
            numbers,
        });
    }
    Ok((plan, rows))
}

fn cell(v: &Value) -> String {
    match v {
        Value::Null => String::new(),
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

pub(crate) fn csv(plan: &PlanFile, rows: &[Row]) -> Result<Vec<u8>, String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["run".to_string()];
    header.extend(plan.axes.iter().map(|a| a.path.clone()));
    header.extend(COLUMNS.iter().map(|c| c.to_string()));
    w.write_record(&header).map_err(|e| e.to_string())?;
    for r in rows {
        let mut rec = vec![r.run.clone()];
        rec.extend(r.values.iter().map(|v| v.text.clone()));
        match &r.numbers {
            Some(n) => rec.extend(n.iter().map(cell)),
            None => rec.extend(COLUMNS.iter().map(|_| String::new())),
        }
        w.write_record(&rec).map_err(|e| e.to_string())?;
    }
    w.into_inner().map_err(|e| e.to_string())
}

/// A JSON object whose keys keep their order (a `serde_json::Map` sorts them).
struct Ordered(Vec<(String, Value)>);

impl Serialize for Ordered {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|(k, v)| (k, v)))
    }
}

pub(crate) fn json(plan: &PlanFile, rows: &[Row]) -> Result<Vec<u8>, String> {
    let runs: Vec<Ordered> = rows
        .iter()
        .map(|r| {
            let mut o = vec![("run".to_string(), Value::from(r.run.clone()))];
            o.push((
                "status".into(),
                Value::from(if r.numbers.is_some() {
                    "done"
                } else {
                    "missing"
                }),
            ));
            for (a, v) in plan.axes.iter().zip(&r.values) {
                o.push((a.path.clone(), v.value.clone()));
            }
            for (i, c) in COLUMNS.iter().enumerate() {
                let v = r.numbers.as_ref().map_or(Value::Null, |n| n[i].clone());
                o.push((c.to_string(), v));
            }
            Ordered(o)
        })
        .collect();
    let mut out = serde_json::to_vec_pretty(&runs).map_err(|e| e.to_string())?;
    out.push(b'\n');
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn idle_with_work_is_robots_idle_on_average() {
        let report = serde_json::json!({
            "end_time": 600.0,
            "fleets": [
                {"robots": 2, "utilisation": 0.5, "idle_with_work_s": 300.0},
                {"robots": 1, "utilisation": 1.0, "idle_with_work_s": 60.0},
            ],
        });
        let row = headline(&report);
        let col = |c: &str| row[COLUMNS.iter().position(|x| *x == c).unwrap()].as_f64();
        // (300 + 60) robot-s over 600 s; utilisation weighted by robots: (1 + 1) / 3.
        assert_eq!(col("idle_with_work"), Some(0.6));
        assert_eq!(col("utilisation"), Some(2.0 / 3.0));
        assert_eq!(row.len(), COLUMNS.len());
    }
}
