//! Rules about the crowd simulation (E08xx): what breaks Menge's behaviour and scene files
//! and the runtime's crowd. They run only when `crowd_sim` is enabled (a disabled crowd is
//! written nowhere and simulated by no one).

use super::{Context, Rule};
use crate::{CrowdSim, Handle, Vertex};

mod bad_weights;
mod goal_set_without_vertex;
mod level_without_human_lanes;
mod unknown_goal_set;
mod unknown_profile;
mod unknown_state;

pub(super) static RULES: &[&Rule] = &[
    &unknown_state::RULE,
    &unknown_goal_set::RULE,
    &goal_set_without_vertex::RULE,
    &unknown_profile::RULE,
    &level_without_human_lanes::RULE,
    &bad_weights::RULE,
];

/// The enabled crowd, if any.
fn crowd<'a>(ctx: &Context<'a>) -> Option<&'a CrowdSim> {
    ctx.b.crowd_sim.as_ref().filter(|c| c.enable)
}

/// The vertices whose `human_goal_set_name` is `area`, in document order.
fn goal_vertices<'a>(ctx: &'a Context, area: &'a str) -> impl Iterator<Item = Handle<Vertex>> + 'a {
    ctx.b
        .vertices
        .iter()
        .filter(move |(_, v)| v.roles.human_goal_set_name.as_deref() == Some(area))
        .map(|(h, _)| h)
}

/// The profile name that marks robots (external agents), as the editor writes it.
pub(crate) const EXTERNAL_PROFILE: &str = "external_agent";

#[cfg(test)]
pub(crate) mod tests {
    use crate::validate::tests::{param, params, TestMap};
    use crate::*;

    /// A one-level map with a 10 m human lane a-b, goal vertex `b` (area `g`), one goal
    /// set 0 over `g`, states `walk` (goal set 0) and `stop` (final), profile `human`, a
    /// group of 2 in `walk` and a transition walk → stop.
    pub fn crowd_map() -> TestMap {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let goal = params(vec![param(
            "human_goal_set_name",
            ParamValue::String("g".into()),
        )]);
        let b = m.vertex_with("b", 10.0, 0.0, goal);
        m.human_lane(a, b, 2.0);
        m.b.crowd_sim = Some(CrowdSim {
            enable: true,
            update_time_step: 0.1,
            states: vec![
                CrowdState {
                    name: "walk".into(),
                    goal_set: 0,
                    navmesh_file_name: "L1_navmesh.nav".into(),
                    ..Default::default()
                },
                CrowdState {
                    name: "stop".into(),
                    goal_set: -1,
                    is_final: true,
                    ..Default::default()
                },
            ],
            goal_sets: vec![GoalSet {
                set_id: 0,
                capacity: 10,
                set_area: vec!["g".into()],
                ..Default::default()
            }],
            agent_profiles: vec![AgentProfile {
                name: "human".into(),
                r: 0.25,
                pref_speed: 1.34,
                max_speed: 2.0,
                max_accel: 5.0,
                neighbor_dist: 5.0,
                max_neighbors: 10,
                orca_tau: 1.0,
                orca_tau_obst: 0.4,
                ..Default::default()
            }],
            transitions: vec![Transition {
                from: "walk".into(),
                to: "stop".into(),
                condition: Some(Condition::GoalReached { distance: 0.5 }),
                ..Default::default()
            }],
            agent_groups: vec![AgentGroup {
                profile_selector: "human".into(),
                state_selector: "walk".into(),
                agents_number: 2,
                pos: Vec2::new(1.0, 0.0),
                ..Default::default()
            }],
            ..Default::default()
        });
        m
    }

    pub fn count(m: &TestMap, code: &str) -> usize {
        crate::validate(&m.b)
            .iter()
            .filter(|d| d.code == code)
            .count()
    }

    #[test]
    fn the_fixture_is_clean() {
        let m = crowd_map();
        let d = crate::validate(&m.b);
        assert!(d.iter().all(|d| !d.code.starts_with("E08")), "{d:?}");
    }
}
