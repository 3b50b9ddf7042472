//! # E0805 crowd-level-without-human-lanes
//!
//! **What:** the crowd has people (agent groups that are not robots, with a positive
//! `agents_number`) but the level they walk on has no human lanes: a level holding a goal
//! vertex of the crowd, or, when no goal vertex exists, any level.
//!
//! **Why it matters:** people walk on the navigation mesh that the level's human lanes
//! define (`<level>_navmesh.nav`). Without human lanes there is no mesh: Menge cannot plan
//! a path and `mapc sim` has nowhere for the people to walk.
//!
//! **Fix:** draw human lanes (the editor's human lane tool, graph 9) joining the goal
//! vertices, or disable the crowd (`enable: 0`).
//!
//! **Example:**
//! ```yaml
//! levels:
//!   L1:
//!     vertices: [[10, 5, 0, gate_a, {human_goal_set_name: [1, gate]}]]   # E0805
//!     # no human_lanes
//! ```

use super::{crowd, goal_vertices, EXTERNAL_PROFILE};
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;
use std::collections::BTreeSet;

pub(crate) static RULE: Rule = Rule {
    code: "E0805",
    name: "crowd-level-without-human-lanes",
    summary: "people walk on a level that has no human lanes",
    group: Group::Crowd,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let Some(c) = crowd(ctx) else { return };
    let people: i64 = c
        .agent_groups
        .iter()
        .filter(|g| g.profile_selector != EXTERNAL_PROFILE && g.agents_name.is_empty())
        .map(|g| g.agents_number.max(0))
        .sum();
    if people == 0 {
        return;
    }
    let b = ctx.b;
    let mut levels = BTreeSet::new();
    for g in &c.goal_sets {
        for a in &g.set_area {
            for v in goal_vertices(ctx, a) {
                if levels.insert(b.vertices[v].level)
                    && b.levels[b.vertices[v].level].human_lanes.is_empty()
                {
                    out.push(
                        Diagnostic::error(
                            RULE.code,
                            ctx.vertex_span(v),
                            format!(
                                "people walk to {} on level `{}`, which has no human lanes",
                                ctx.vertex_label(v),
                                ctx.level_name(b.vertices[v].level)
                            ),
                        )
                        .with_help(
                            "draw human lanes joining the crowd's goals on this level, or \
                             disable the crowd (`enable: 0`)",
                        ),
                    );
                }
            }
        }
    }
    if levels.is_empty() && b.levels.iter().all(|(_, l)| l.human_lanes.is_empty()) {
        out.push(
            Diagnostic::error(
                RULE.code,
                c.span,
                format!("the crowd has {people} people but no level has human lanes"),
            )
            .with_help("draw human lanes for the people to walk on, or disable the crowd"),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{count, crowd_map};

    #[test]
    fn no_human_lanes() {
        let mut m = crowd_map();
        let l = m.level;
        m.b.levels[l].human_lanes.clear();
        assert_eq!(count(&m, "E0805"), 1);
        // Robots only: no one walks.
        m.b.crowd_sim.as_mut().unwrap().agent_groups[0].profile_selector = "external_agent".into();
        assert_eq!(count(&m, "E0805"), 0);
    }
}
