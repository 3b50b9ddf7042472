//! `mapc info MAP`: what a map holds that scenario authors refer to by name: levels, nav
//! graphs, named waypoints by role, doors, lifts, dispensers and ingestors. Human text or
//! one JSON object (`--format json`).

use crate::driver::{load_readable, CliError, Outcome};
use mapc_ir::Building;
use serde_json::{json, Value};
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

#[derive(Clone, Copy, clap::ValueEnum, PartialEq, Eq)]
pub(crate) enum InfoFormat {
    /// Indented text on stdout.
    Human,
    /// One JSON object on stdout.
    Json,
}

#[derive(clap::Args)]
pub(crate) struct InfoArgs {
    /// The .building.yaml (or legacy .project.yaml) to read.
    input: PathBuf,
    /// How to print.
    #[arg(long, value_enum, default_value = "human")]
    format: InfoFormat,
    #[command(flatten)]
    lints: crate::driver::LintOpts,
}

/// A named waypoint: (name, level).
fn wp(b: &Building, v: &mapc_ir::Vertex) -> Value {
    json!({ "name": v.name, "level": b.levels[v.level].name })
}

/// Everything `info` lists, as JSON (the human form is rendered from it).
pub(crate) fn info(b: &Building) -> Value {
    let levels: Vec<Value> = b
        .levels
        .iter()
        .map(|(_, l)| {
            json!({
                "name": l.name,
                "elevation": l.elevation,
                "vertices": l.vertices.len(),
                "lanes": l.lanes.len(),
            })
        })
        .collect();
    // Graphs are the lanes' graph_idx values; their names come from `graphs` when present.
    let mut graph_lanes: BTreeMap<i64, (usize, BTreeSet<String>)> = BTreeMap::new();
    for (_, lane) in b.lanes.iter() {
        let e = graph_lanes.entry(lane.graph).or_default();
        e.0 += 1;
        for v in [lane.start, lane.end] {
            let name = &b.vertices[v].name;
            if !name.is_empty() {
                e.1.insert(name.clone());
            }
        }
    }
    let graphs: Vec<Value> = graph_lanes
        .iter()
        .map(|(idx, (lanes, names))| {
            let name = b
                .graphs
                .iter()
                .find(|g| g.index == *idx)
                .map_or(String::new(), |g| g.name.clone());
            json!({ "index": idx, "name": name, "lanes": lanes, "named_waypoints": names.len() })
        })
        .collect();
    let mut roles: BTreeMap<&str, Vec<Value>> = BTreeMap::new();
    let mut dispensers = Vec::new();
    let mut ingestors = Vec::new();
    for (_, v) in b.vertices.iter() {
        let r = &v.roles;
        for (flag, role) in [
            (r.is_charger, "charger"),
            (r.is_parking_spot, "parking_spot"),
            (r.is_holding_point, "holding_point"),
        ] {
            if flag {
                roles.entry(role).or_default().push(wp(b, v));
            }
        }
        if let Some(d) = &r.dock_name {
            let mut w = wp(b, v);
            w["dock"] = json!(d);
            roles.entry("dock").or_default().push(w);
        }
        if let Some(name) = &r.spawn_robot_name {
            let mut w = wp(b, v);
            w["robot"] = json!(name);
            w["model"] = json!(r.spawn_robot_type.clone().unwrap_or_default());
            roles.entry("spawn").or_default().push(w);
        }
        if let Some(d) = &r.pickup_dispenser {
            let mut w = wp(b, v);
            w["dispenser"] = json!(d);
            dispensers
                .push(json!({ "name": d, "waypoint": v.name, "level": b.levels[v.level].name }));
            roles.entry("pickup").or_default().push(w);
        }
        if let Some(d) = &r.dropoff_ingestor {
            let mut w = wp(b, v);
            w["ingestor"] = json!(d);
            ingestors
                .push(json!({ "name": d, "waypoint": v.name, "level": b.levels[v.level].name }));
            roles.entry("dropoff").or_default().push(w);
        }
    }
    let doors: Vec<Value> = b
        .doors
        .iter()
        .map(|(_, d)| json!({ "name": d.name, "level": b.levels[d.level].name, "type": d.kind.as_str() }))
        .collect();
    let lifts: Vec<Value> = b
        .lifts
        .iter()
        .map(|(_, l)| {
            let levels: Vec<&str> = l
                .level_doors
                .iter()
                .map(|ld| b.levels[ld.level].name.as_str())
                .collect();
            json!({ "name": l.name, "levels": levels, "width": l.width, "depth": l.depth })
        })
        .collect();
    json!({
        "building": b.name,
        "levels": levels,
        "graphs": graphs,
        "waypoints": roles,
        "doors": doors,
        "lifts": lifts,
        "dispensers": dispensers,
        "ingestors": ingestors,
    })
}

fn s(v: &Value, k: &str) -> String {
    match &v[k] {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// The human rendering: one section per kind, one line per item.
pub(crate) fn human(i: &Value) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let list = |k: &str| i[k].as_array().cloned().unwrap_or_default();
    let _ = writeln!(out, "building {}", s(i, "building"));
    let levels = list("levels");
    let _ = writeln!(out, "levels ({}):", levels.len());
    for l in &levels {
        let _ = writeln!(
            out,
            "  {}  elevation {} m, {} vertices, {} lanes",
            s(l, "name"),
            s(l, "elevation"),
            s(l, "vertices"),
            s(l, "lanes")
        );
    }
    let graphs = list("graphs");
    let _ = writeln!(out, "graphs ({}):", graphs.len());
    for g in &graphs {
        let name = s(g, "name");
        let name = if name.is_empty() {
            String::new()
        } else {
            format!(" {name}")
        };
        let _ = writeln!(
            out,
            "  {}{name}  {} lanes, {} named waypoints",
            s(g, "index"),
            s(g, "lanes"),
            s(g, "named_waypoints")
        );
    }
    let _ = writeln!(out, "waypoints by role:");
    if let Some(roles) = i["waypoints"].as_object() {
        if roles.is_empty() {
            let _ = writeln!(out, "  (none)");
        }
        for (role, items) in roles {
            let names: Vec<String> = items
                .as_array()
                .into_iter()
                .flatten()
                .map(|w| {
                    let extra = ["dock", "robot", "dispenser", "ingestor"]
                        .iter()
                        .find(|k| w.get(**k).is_some())
                        .map_or(String::new(), |k| format!(" ({k} {})", s(w, k)));
                    format!("{}@{}{extra}", s(w, "name"), s(w, "level"))
                })
                .collect();
            let _ = writeln!(out, "  {role} ({}): {}", names.len(), names.join(", "));
        }
    }
    for (key, title) in [("doors", "doors"), ("lifts", "lifts")] {
        let items = list(key);
        let _ = writeln!(out, "{title} ({}):", items.len());
        for d in &items {
            let detail = if key == "doors" {
                format!("{} on {}", s(d, "type"), s(d, "level"))
            } else {
                let levels: Vec<String> = d["levels"]
                    .as_array()
                    .into_iter()
                    .flatten()
                    .map(|l| l.as_str().unwrap_or_default().to_string())
                    .collect();
                format!("serves {}", levels.join(", "))
            };
            let _ = writeln!(out, "  {}  {detail}", s(d, "name"));
        }
    }
    for key in ["dispensers", "ingestors"] {
        let items = list(key);
        let _ = writeln!(out, "{key} ({}):", items.len());
        for d in &items {
            let _ = writeln!(
                out,
                "  {}  at {}@{}",
                s(d, "name"),
                s(d, "waypoint"),
                s(d, "level")
            );
        }
    }
    out
}

pub(crate) fn run(args: &InfoArgs) -> Result<Outcome, CliError> {
    // Errors matter (the listing may be incomplete); warnings are `mapc check`'s business.
    let checked = load_readable(&args.input, &args.lints)?;
    let Some(b) = checked.parsed.building.as_ref() else {
        return Err(CliError::InvalidReported);
    };
    let i = info(b);
    match args.format {
        InfoFormat::Human => print!("{}", human(&i)),
        InfoFormat::Json => println!("{i}"),
    }
    if checked.errors() > 0 {
        // Said with the listing: it may be incomplete.
        Err(CliError::InvalidReported)
    } else {
        Ok(Outcome::Done)
    }
}
