//! `crowd_sim`: the people's agent groups, states, transitions and their conditions.

use super::*;

impl Lower<'_> {
    /// crowd_sim is read leniently: the generator ignores it and the editor resets it to
    /// defaults when it does not parse, so problems here are warnings.
    pub(crate) fn crowd_sim(&mut self, node: &Node) -> Option<CrowdSim> {
        node.as_map()?;
        let mut inner = Vec::new();
        let cs = {
            let mut l = Lower { diags: &mut inner };
            l.crowd_sim_inner(node)
        };
        for mut d in inner {
            d.severity = Severity::Warning;
            d.code = "W0105";
            d.message = format!("crowd_sim: {}", d.message);
            self.diags.push(d);
        }
        Some(cs)
    }

    pub(super) fn crowd_sim_inner(&mut self, n: &Node) -> CrowdSim {
        let w = "crowd_sim";
        let list = |l: &mut Self, key: &str| -> Vec<Node> {
            n.get(key)
                .and_then(|s| l.seq(s, &format!("crowd_sim `{key}`")))
                .map(|s| s.to_vec())
                .unwrap_or_default()
        };
        let strings = |l: &mut Self, n: &Node, key: &str| -> Vec<String> {
            n.get(key)
                .and_then(|s| l.seq(s, key))
                .unwrap_or(&[])
                .iter()
                .filter_map(|s| l.string(s, key))
                .collect()
        };
        let mut cs = CrowdSim {
            enable: self.opt_bool(n, "enable", w, false),
            update_time_step: self.opt_f64(n, "update_time_step", w, 0.1),
            span: n.span,
            ..CrowdSim::default()
        };
        for s in list(self, "states") {
            cs.states.push(CrowdState {
                name: self.opt_string(&s, "name", "a state"),
                goal_set: self.opt_i64(&s, "goal_set", "a state", -1),
                navmesh_file_name: self.opt_string(&s, "navmesh_file_name", "a state"),
                is_final: self.opt_bool(&s, "final", "a state", false),
                span: s.span,
            });
        }
        for g in list(self, "goal_sets") {
            cs.goal_sets.push(GoalSet {
                set_id: self.opt_i64(&g, "set_id", "a goal set", 0),
                capacity: self.opt_i64(&g, "capacity", "a goal set", 0),
                set_area: strings(self, &g, "set_area"),
                span: g.span,
            });
        }
        for p in list(self, "agent_profiles") {
            let f = |l: &mut Self, k: &str| l.opt_f64(&p, k, "an agent profile", 0.0);
            cs.agent_profiles.push(AgentProfile {
                name: self.opt_string(&p, "name", "an agent profile"),
                class: self.opt_i64(&p, "class", "an agent profile", 1),
                max_accel: f(self, "max_accel"),
                max_angle_vel: f(self, "max_angle_vel"),
                max_neighbors: self.opt_i64(&p, "max_neighbors", "an agent profile", 10),
                max_speed: f(self, "max_speed"),
                neighbor_dist: f(self, "neighbor_dist"),
                obstacle_set: self.opt_i64(&p, "obstacle_set", "an agent profile", 1),
                pref_speed: f(self, "pref_speed"),
                r: f(self, "r"),
                orca_tau: f(self, "ORCA_tau"),
                orca_tau_obst: f(self, "ORCA_tauObst"),
                span: p.span,
            });
        }
        for t in list(self, "transitions") {
            let mut targets = Vec::new();
            if let Some(ts) = t.get("Target").and_then(|x| self.seq(x, "`Target`")) {
                for x in ts {
                    targets.push((
                        self.opt_string(x, "name", "a target"),
                        self.opt_f64(x, "weight", "a target", 1.0),
                        x.span,
                    ));
                }
            }
            cs.transitions.push(Transition {
                from: self.opt_string(&t, "from", "a transition"),
                to: self.opt_string(&t, "to", "a transition"),
                targets,
                condition: t.get("Condition").map(|c| self.condition(c, 0)),
                span: t.span,
            });
        }
        if let Some(o) = n.get("obstacle_set") {
            cs.obstacle_set = Some(ObstacleSet {
                class: self.opt_i64(o, "class", "the obstacle set", 1),
                file_name: self.opt_string(o, "file_name", "the obstacle set"),
                kind: self.opt_string(o, "type", "the obstacle set"),
            });
        }
        for g in list(self, "agent_groups") {
            cs.agent_groups.push(AgentGroup {
                group_id: self.opt_i64(&g, "group_id", "an agent group", 0),
                profile_selector: self.opt_string(&g, "profile_selector", "an agent group"),
                state_selector: self.opt_string(&g, "state_selector", "an agent group"),
                agents_number: self.opt_i64(&g, "agents_number", "an agent group", 0),
                agents_name: strings(self, &g, "agents_name"),
                pos: Vec2::new(
                    self.opt_f64(&g, "x", "an agent group", 0.0),
                    self.opt_f64(&g, "y", "an agent group", 0.0),
                ),
                span: g.span,
            });
        }
        for m in list(self, "model_types") {
            let init_pose = m
                .get("init_pose")
                .and_then(|p| self.seq(p, "`init_pose`"))
                .unwrap_or(&[])
                .iter()
                .filter_map(|v| self.f64(v, "an init_pose value"))
                .collect();
            cs.model_types.push(ModelType {
                typename: self.opt_string(&m, "typename", "a model type"),
                animation: self.opt_string(&m, "animation", "a model type"),
                animation_speed: self.opt_f64(&m, "animation_speed", "a model type", 0.0),
                model_uri: self.opt_string(&m, "model_uri", "a model type"),
                init_pose,
            });
        }
        cs
    }

    pub(super) fn condition(&mut self, c: &Node, depth: usize) -> Condition {
        let kind = self.opt_string(c, "type", "a condition");
        // Depth is bounded by the YAML depth limit already; this is belt and braces.
        let sub = |l: &mut Self, key: &str| -> Box<Condition> {
            Box::new(match c.get(key) {
                Some(n) if depth < 32 => l.condition(n, depth + 1),
                _ => Condition::Other(String::new()),
            })
        };
        match kind.as_str() {
            "goal_reached" => Condition::GoalReached {
                distance: self.opt_f64(c, "distance", "a condition", 0.1),
            },
            "timer" => {
                // Menge's distributions: `c` constant (`value`), `u` uniform (`min`, `max`);
                // the editor writes `dist: c` and `per_agent: true`.
                let dist = self.opt_string(c, "dist", "a timer");
                let duration = if dist == "u" {
                    TimerDuration::Uniform {
                        min: self.opt_f64(c, "min", "a timer", 0.0),
                        max: self.opt_f64(c, "max", "a timer", 0.0),
                    }
                } else {
                    TimerDuration::Const(self.opt_f64(c, "value", "a condition", 0.0))
                };
                Condition::Timer(Timer {
                    duration,
                    per_agent: self.opt_bool(c, "per_agent", "a timer", true),
                })
            }
            "auto" => Condition::Auto,
            "and" => Condition::And(sub(self, "condition1"), sub(self, "condition2")),
            "or" => Condition::Or(sub(self, "condition1"), sub(self, "condition2")),
            "not" => Condition::Not(sub(self, "condition1")),
            other => Condition::Other(other.to_string()),
        }
    }
}
