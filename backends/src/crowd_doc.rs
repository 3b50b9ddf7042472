//! The `crowd_sim` mapping of a `.building.yaml`, written back from the IR in the shape
//! the frontend reads (building_yaml.md §8): for `mapc convert`, which puts it in the
//! `.building.yaml` it writes and in a site's `extensions.data.mapc` (rmf_site has no
//! crowd simulation), so a round trip keeps the world's crowd.

use crate::yaml::Yaml;
use mapc_ir::*;
use serde_json::{Map, Value};

fn map(entries: Vec<(&str, Yaml)>) -> Yaml {
    Yaml::Map(
        entries
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect(),
    )
}

fn strings(v: &[String]) -> Yaml {
    Yaml::Flow(Box::new(Yaml::Seq(v.iter().map(Yaml::str).collect())))
}

fn condition(c: &Condition) -> Yaml {
    let kind = |k: &str| ("type", Yaml::str(k));
    match c {
        Condition::GoalReached { distance } => map(vec![
            kind("goal_reached"),
            ("distance", Yaml::Float(*distance)),
        ]),
        Condition::Timer(t) => {
            let mut e = vec![kind("timer")];
            match t.duration {
                TimerDuration::Const(v) => {
                    e.push(("dist", Yaml::str("c")));
                    e.push(("value", Yaml::Float(v)));
                }
                TimerDuration::Uniform { min, max } => {
                    e.push(("dist", Yaml::str("u")));
                    e.push(("min", Yaml::Float(min)));
                    e.push(("max", Yaml::Float(max)));
                }
            }
            e.push(("per_agent", Yaml::Bool(t.per_agent)));
            map(e)
        }
        Condition::Auto => map(vec![kind("auto")]),
        Condition::And(a, b) => map(vec![
            kind("and"),
            ("condition1", condition(a)),
            ("condition2", condition(b)),
        ]),
        Condition::Or(a, b) => map(vec![
            kind("or"),
            ("condition1", condition(a)),
            ("condition2", condition(b)),
        ]),
        Condition::Not(a) => map(vec![kind("not"), ("condition1", condition(a))]),
        Condition::Other(k) => map(vec![kind(k)]),
    }
}

/// `crowd_sim` as the frontend reads it.
pub(crate) fn crowd_sim(c: &CrowdSim) -> Yaml {
    let states = c
        .states
        .iter()
        .map(|s| {
            map(vec![
                ("name", Yaml::str(&s.name)),
                ("goal_set", Yaml::Int(s.goal_set)),
                ("navmesh_file_name", Yaml::str(&s.navmesh_file_name)),
                ("final", Yaml::Int(i64::from(s.is_final))),
            ])
        })
        .collect();
    let goal_sets = c
        .goal_sets
        .iter()
        .map(|g| {
            map(vec![
                ("set_id", Yaml::Int(g.set_id)),
                ("capacity", Yaml::Int(g.capacity)),
                ("set_area", strings(&g.set_area)),
            ])
        })
        .collect();
    let profiles = c
        .agent_profiles
        .iter()
        .map(|p| {
            map(vec![
                ("name", Yaml::str(&p.name)),
                ("class", Yaml::Int(p.class)),
                ("max_accel", Yaml::Float(p.max_accel)),
                ("max_angle_vel", Yaml::Float(p.max_angle_vel)),
                ("max_neighbors", Yaml::Int(p.max_neighbors)),
                ("max_speed", Yaml::Float(p.max_speed)),
                ("neighbor_dist", Yaml::Float(p.neighbor_dist)),
                ("obstacle_set", Yaml::Int(p.obstacle_set)),
                ("pref_speed", Yaml::Float(p.pref_speed)),
                ("r", Yaml::Float(p.r)),
                ("ORCA_tau", Yaml::Float(p.orca_tau)),
                ("ORCA_tauObst", Yaml::Float(p.orca_tau_obst)),
            ])
        })
        .collect();
    let transitions = c
        .transitions
        .iter()
        .map(|t| {
            let mut e = vec![("from", Yaml::str(&t.from)), ("to", Yaml::str(&t.to))];
            if !t.targets.is_empty() {
                let ts = t
                    .targets
                    .iter()
                    .map(|(n, w, _)| map(vec![("name", Yaml::str(n)), ("weight", Yaml::Float(*w))]))
                    .collect();
                e.push(("Target", Yaml::Seq(ts)));
            }
            if let Some(c) = &t.condition {
                e.push(("Condition", condition(c)));
            }
            map(e)
        })
        .collect();
    let groups = c
        .agent_groups
        .iter()
        .map(|g| {
            map(vec![
                ("group_id", Yaml::Int(g.group_id)),
                ("profile_selector", Yaml::str(&g.profile_selector)),
                ("state_selector", Yaml::str(&g.state_selector)),
                ("agents_number", Yaml::Int(g.agents_number)),
                ("agents_name", strings(&g.agents_name)),
                ("x", Yaml::Float(g.pos.x)),
                ("y", Yaml::Float(g.pos.y)),
            ])
        })
        .collect();
    let models = c
        .model_types
        .iter()
        .map(|m| {
            map(vec![
                ("typename", Yaml::str(&m.typename)),
                ("animation", Yaml::str(&m.animation)),
                ("animation_speed", Yaml::Float(m.animation_speed)),
                ("model_uri", Yaml::str(&m.model_uri)),
                (
                    "init_pose",
                    Yaml::Flow(Box::new(Yaml::Seq(
                        m.init_pose.iter().map(|v| Yaml::Float(*v)).collect(),
                    ))),
                ),
            ])
        })
        .collect();
    let mut e = vec![
        ("enable", Yaml::Int(i64::from(c.enable))),
        ("update_time_step", Yaml::Float(c.update_time_step)),
        ("states", Yaml::Seq(states)),
        ("goal_sets", Yaml::Seq(goal_sets)),
        ("agent_profiles", Yaml::Seq(profiles)),
        ("transitions", Yaml::Seq(transitions)),
    ];
    if let Some(o) = &c.obstacle_set {
        e.push((
            "obstacle_set",
            map(vec![
                ("class", Yaml::Int(o.class)),
                ("file_name", Yaml::str(&o.file_name)),
                ("type", Yaml::str(&o.kind)),
            ]),
        ));
    }
    e.push(("agent_groups", Yaml::Seq(groups)));
    e.push(("model_types", Yaml::Seq(models)));
    map(e)
}

/// The same tree as JSON, for a site's extension data.
pub(crate) fn to_json(y: &Yaml) -> Value {
    match y {
        Yaml::Str(s) => Value::from(s.as_str()),
        Yaml::Int(i) => Value::from(*i),
        Yaml::Float(f) => Value::from(*f),
        Yaml::Bool(b) => Value::from(*b),
        Yaml::Seq(v) => Value::Array(v.iter().map(to_json).collect()),
        Yaml::Map(m) => Value::Object(
            m.iter()
                .map(|(k, v)| (k.clone(), to_json(v)))
                .collect::<Map<String, Value>>(),
        ),
        Yaml::Flow(inner) => to_json(inner),
    }
}
