//! The crowd simulator (runtime.md §6): the world plugin `crowd_simulation` and the two
//! Menge files it loads, `scene_file.xml` and `behavior_file.xml`, from
//! `Building::crowd_sim` when it is enabled.
//!
//! The Menge files go to `config_resource/` next to the world ([`CROWD_DIR`]); the plugin
//! resolves them against `MENGE_RESOURCE_PATH`, which must point at that directory (the
//! plugin disables itself when the variable is unset). A navmesh `<level>_navmesh.nav` (the
//! editor's name for them) is generated for every level with human lanes
//! ([`super::navmesh`]); a navmesh the crowd_sim names otherwise is not generated and must
//! be supplied in the same directory.
//!
//! Coordinates: the editor writes agent group `x`/`y` in map-frame metres already (in the
//! airport_terminal demo, a reference_image map, the groups sit at about (131.5, -32.3), next
//! to their goal vertex at pixel (1600.9, 393.4), i.e. metres after the y flip and scale), so
//! they are taken as map-frame metres. Goals are the map-frame positions of the vertices
//! whose `human_goal_set_name` names a goal set's area. Both have the building offset
//! subtracted, as everything else in the world.

use super::xml::Element;
use crate::py_float;
use mapc_ir::{Building, Condition, CrowdSim, TimerDuration};
use std::path::PathBuf;

/// The directory, relative to the world's directory, holding the Menge files.
pub const CROWD_DIR: &str = "config_resource";
/// The agent profile whose groups are robots (external agents), as the editor names it.
pub const EXTERNAL_PROFILE: &str = "external_agent";

/// The enabled crowd simulation of `b`, if any.
pub fn enabled(b: &Building) -> Option<&CrowdSim> {
    b.crowd_sim.as_ref().filter(|c| c.enable)
}

/// Agent groups in scene order: the external groups first (file order), then the others
/// (file order). The plugin makes the first n agents of the scene the n external agents, so
/// the external groups must come first whatever the file order is.
fn ordered_groups(c: &CrowdSim) -> impl Iterator<Item = &mapc_ir::AgentGroup> {
    let ext = |g: &&mapc_ir::AgentGroup| g.profile_selector == EXTERNAL_PROFILE;
    c.agent_groups
        .iter()
        .filter(ext)
        .chain(c.agent_groups.iter().filter(move |g| !ext(g)))
}

/// The external agent names: the `agents_name` of the external groups, in file order.
pub fn external_agents(c: &CrowdSim) -> Vec<&str> {
    c.agent_groups
        .iter()
        .filter(|g| g.profile_selector == EXTERNAL_PROFILE)
        .flat_map(|g| g.agents_name.iter().map(String::as_str))
        .collect()
}

/// The world plugin block (the same name and library in the three flavours, like the
/// world-level door and lift plugins), or `None` when crowd_sim is absent or disabled.
pub fn crowd_plugin(b: &Building) -> Option<Element> {
    let c = enabled(b)?;
    let mut p = Element::new("plugin")
        .attr("filename", "libcrowd_simulator.so")
        .attr("name", "crowd_simulation")
        .leaf("update_time_step", py_float(c.update_time_step))
        .leaf("behavior_file", "behavior_file.xml")
        .leaf("scene_file", "scene_file.xml");
    for m in &c.model_types {
        // Six numbers: x y z pitch roll yaw; missing ones are 0, extra ones dropped.
        let pose: Vec<String> = (0..6)
            .map(|i| py_float(m.init_pose.get(i).copied().unwrap_or(0.0)))
            .collect();
        p.push(
            Element::new("model_type")
                .leaf("typename", m.typename.clone())
                .leaf("filename", m.model_uri.clone())
                .leaf("animation", m.animation.clone())
                .leaf("animation_speed", py_float(m.animation_speed))
                .leaf("initial_pose", pose.join(" ")),
        );
    }
    for n in external_agents(c) {
        p.push(Element::new("external_agent").text(n.to_string()));
    }
    Some(p)
}

/// The Menge scene file (`<Experiment version="2.0">`, runtime.md §6.3).
pub fn scene_file(b: &Building, c: &CrowdSim) -> Element {
    let mut e = Element::new("Experiment")
        .attr("version", "2.0")
        .child(
            Element::new("SpatialQuery")
                .attr("type", "kd-tree")
                .attr("test_visibility", "false"),
        )
        .child(Element::new("Common").attr("time_step", py_float(c.update_time_step)));
    if let Some(o) = &c.obstacle_set {
        e.push(
            Element::new("ObstacleSet")
                .attr("type", o.kind.clone())
                .attr("file_name", o.file_name.clone())
                .attr("class", o.class.to_string()),
        );
    }
    for p in &c.agent_profiles {
        e.push(
            Element::new("AgentProfile")
                .attr("name", p.name.clone())
                .child(
                    Element::new("Common")
                        .attr("class", p.class.to_string())
                        .attr("max_accel", py_float(p.max_accel))
                        .attr("max_angle_vel", py_float(p.max_angle_vel))
                        .attr("max_neighbors", p.max_neighbors.to_string())
                        .attr("max_speed", py_float(p.max_speed))
                        .attr("neighbor_dist", py_float(p.neighbor_dist))
                        .attr("obstacleSet", p.obstacle_set.to_string())
                        .attr("pref_speed", py_float(p.pref_speed))
                        .attr("r", py_float(p.r)),
                )
                .child(
                    Element::new("ORCA")
                        .attr("tau", py_float(p.orca_tau))
                        .attr("tauObst", py_float(p.orca_tau_obst)),
                ),
        );
    }
    for g in ordered_groups(c) {
        let x = py_float(g.pos.x - b.offset.x);
        let y = py_float(g.pos.y - b.offset.y);
        let mut gen = Element::new("Generator").attr("type", "explicit");
        for _ in 0..g.agents_number.max(0) {
            gen.push(
                Element::new("Agent")
                    .attr("p_x", x.clone())
                    .attr("p_y", y.clone()),
            );
        }
        e.push(
            Element::new("AgentGroup")
                .child(
                    Element::new("ProfileSelector")
                        .attr("type", "const")
                        .attr("name", g.profile_selector.clone()),
                )
                .child(
                    Element::new("StateSelector")
                        .attr("type", "const")
                        .attr("name", g.state_selector.clone()),
                )
                .child(gen),
        );
    }
    e
}

fn condition(c: &Condition) -> Element {
    let e = Element::new("Condition");
    match c {
        Condition::GoalReached { distance } => e
            .attr("type", "goal_reached")
            .attr("distance", py_float(*distance)),
        Condition::Timer(t) => {
            let e = e.attr("type", "timer");
            let e = match t.duration {
                TimerDuration::Const(v) => e.attr("value", py_float(v)).attr("dist", "c"),
                TimerDuration::Uniform { min, max } => e
                    .attr("min", py_float(min))
                    .attr("max", py_float(max))
                    .attr("dist", "u"),
            };
            e.attr("per_agent", if t.per_agent { "true" } else { "false" })
        }
        Condition::Auto => e.attr("type", "auto"),
        Condition::And(a, b) => e
            .attr("type", "and")
            .child(condition(a))
            .child(condition(b)),
        Condition::Or(a, b) => e.attr("type", "or").child(condition(a)).child(condition(b)),
        Condition::Not(a) => e.attr("type", "not").child(condition(a)),
        // Parameterless conditions (`auto`) as written.
        Condition::Other(t) => e.attr("type", t.clone()),
    }
}

/// The Menge behaviour file (`<BFSM>`, runtime.md §6.3).
pub fn behavior_file(b: &Building, c: &CrowdSim) -> Element {
    let mut e = Element::new("BFSM");
    for gs in &c.goal_sets {
        let mut set = Element::new("GoalSet").attr("id", gs.set_id.to_string());
        let mut id = 0usize;
        // Vertex order: levels in document order, vertices in level order.
        for area in &gs.set_area {
            for (_, lvl) in b.levels.iter() {
                for &vh in &lvl.vertices {
                    let v = &b.vertices[vh];
                    if v.roles.human_goal_set_name.as_deref() != Some(area.as_str()) {
                        continue;
                    }
                    set.push(
                        Element::new("Goal")
                            .attr("type", "point")
                            .attr("id", id.to_string())
                            .attr("x", py_float(v.pos.x - b.offset.x))
                            .attr("y", py_float(v.pos.y - b.offset.y))
                            .attr("weight", "1")
                            .attr("capacity", gs.capacity.to_string()),
                    );
                    id += 1;
                }
            }
        }
        e.push(set);
    }
    for s in &c.states {
        let st = Element::new("State")
            .attr("name", s.name.clone())
            .attr("final", if s.is_final { "1" } else { "0" });
        // A state without a goal set (the editor writes -1 for the external agents' state)
        // keeps the agent where it is: Menge's identity goal and zero velocity.
        let st = if s.goal_set < 0 {
            st.child(Element::new("GoalSelector").attr("type", "identity"))
                .child(Element::new("VelComponent").attr("type", "zero"))
        } else {
            st.child(
                Element::new("GoalSelector")
                    .attr("type", "weighted")
                    .attr("goal_set", s.goal_set.to_string())
                    .attr("dist", "u"),
            )
            .child(
                Element::new("VelComponent")
                    .attr("type", "nav_mesh")
                    .attr("heading_threshold", "15")
                    .attr("file_name", s.navmesh_file_name.clone()),
            )
        };
        e.push(st);
    }
    for t in &c.transitions {
        let mut tr = Element::new("Transition").attr("from", t.from.clone());
        // Menge takes either a fixed `to` or a `Target`; the editor writes `to: ""` with
        // targets.
        if !t.to.is_empty() {
            tr = tr.attr("to", t.to.clone());
        }
        if let Some(cond) = &t.condition {
            tr.push(condition(cond));
        }
        if !t.targets.is_empty() {
            let mut target = Element::new("Target").attr("type", "prob");
            for (name, w, _) in &t.targets {
                target.push(
                    Element::new("State")
                        .attr("name", name.clone())
                        .attr("weight", py_float(*w)),
                );
            }
            tr.push(target);
        }
        e.push(tr);
    }
    e
}

/// The Menge files, paths relative to the world's directory (`config_resource/...`): the
/// behaviour and scene files, then `<level>_navmesh.nav` for every level with human lanes
/// ([`super::navmesh`]); empty when crowd_sim is absent or disabled.
pub fn crowd_files(b: &Building) -> Vec<crate::OutputFile> {
    let Some(c) = enabled(b) else {
        return Vec::new();
    };
    let doc = |e: Element| {
        let mut s = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        s.push_str(&e.to_document(false));
        s.into_bytes()
    };
    let mut files = vec![
        crate::OutputFile {
            path: PathBuf::from(CROWD_DIR).join("behavior_file.xml"),
            contents: doc(behavior_file(b, c)),
        },
        crate::OutputFile {
            path: PathBuf::from(CROWD_DIR).join("scene_file.xml"),
            contents: doc(scene_file(b, c)),
        },
    ];
    for (h, _) in b.levels.iter() {
        if let Some(text) = super::navmesh::level_navmesh(b, h) {
            files.push(crate::OutputFile {
                path: PathBuf::from(CROWD_DIR).join(super::navmesh::navmesh_file_name(b, h)),
                contents: text.into_bytes(),
            });
        }
    }
    files
}

#[cfg(test)]
mod tests {
    use super::*;
    use mapc_ir::{AgentGroup, CoordinateSystem, Params};

    fn building() -> Building {
        let mut b = Building::new(
            "b".into(),
            CoordinateSystem::CartesianMeters,
            Params::default(),
        );
        b.offset = mapc_ir::Vec2::new(10.0, 20.0);
        b.crowd_sim = Some(CrowdSim {
            enable: true,
            update_time_step: 0.1,
            agent_groups: vec![
                AgentGroup {
                    profile_selector: "human".into(),
                    agents_number: 2,
                    pos: mapc_ir::Vec2::new(11.5, 22.0),
                    ..AgentGroup::default()
                },
                AgentGroup {
                    profile_selector: EXTERNAL_PROFILE.into(),
                    agents_number: 1,
                    agents_name: vec!["r1".into()],
                    ..AgentGroup::default()
                },
            ],
            ..CrowdSim::default()
        });
        b
    }

    #[test]
    fn external_groups_first_and_offset() {
        let b = building();
        let c = enabled(&b).unwrap();
        let s = scene_file(&b, c);
        let groups: Vec<_> = s
            .children
            .iter()
            .filter(|e| e.name == "AgentGroup")
            .collect();
        assert_eq!(groups.len(), 2);
        assert_eq!(groups[0].children[0].attrs[1].1, EXTERNAL_PROFILE);
        let agents = &groups[1].find("Generator").unwrap().children;
        assert_eq!(agents.len(), 2);
        // 11.5 - 10 and 22 - 20.
        assert_eq!(agents[0].attrs[0].1, py_float(11.5 - 10.0));
        assert_eq!(agents[0].attrs[1].1, py_float(22.0 - 20.0));
    }

    #[test]
    fn disabled_writes_nothing() {
        let mut b = building();
        if let Some(c) = b.crowd_sim.as_mut() {
            c.enable = false;
        }
        assert!(crowd_plugin(&b).is_none());
        assert!(crowd_files(&b).is_empty());
    }

    #[test]
    fn nested_conditions() {
        let c = Condition::Not(Box::new(Condition::And(
            Box::new(Condition::Timer(mapc_ir::Timer {
                duration: TimerDuration::Const(2.5),
                per_agent: true,
            })),
            Box::new(Condition::Other("auto".into())),
        )));
        let e = condition(&c);
        assert_eq!(e.attrs[0].1, "not");
        let and = &e.children[0];
        assert_eq!(and.attrs[0].1, "and");
        assert_eq!(and.children[0].attrs[1].1, "2.5");
        assert_eq!(and.children[1].attrs[0].1, "auto");
    }
}
