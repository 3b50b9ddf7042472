//! # E0803 crowd-goal-set-without-vertex
//!
//! **What:** a crowd goal set that a state uses has no goal: none of its `set_area` names
//! is the `human_goal_set_name` of a vertex.
//!
//! **Why it matters:** goals are the vertices whose `human_goal_set_name` is one of the
//! set's areas. An empty goal set makes Menge's goal selector fail when an agent enters the
//! state, and the people of `mapc sim` would stand still.
//!
//! **Fix:** give a vertex the parameter `human_goal_set_name` with one of the set's area
//! names (the editor's "human goal set" vertex property), or fix the area name.
//!
//! **Example:**
//! ```yaml
//! vertices: [[10, 5, 0, gate_a, {human_goal_set_name: [1, gate]}]]
//! crowd_sim:
//!   goal_sets: [{set_id: 0, capacity: 10, set_area: [gates]}]   # E0803
//! ```

use super::{crowd, goal_vertices};
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0803",
    name: "crowd-goal-set-without-vertex",
    summary: "a crowd goal set has no vertex with one of its area names",
    group: Group::Crowd,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let Some(c) = crowd(ctx) else { return };
    for g in &c.goal_sets {
        let used = c.states.iter().any(|s| s.goal_set == g.set_id);
        let empty = g
            .set_area
            .iter()
            .all(|a| goal_vertices(ctx, a).next().is_none());
        if used && empty {
            out.push(
                Diagnostic::error(
                    RULE.code,
                    g.span,
                    format!(
                        "crowd goal set {} has no goal: no vertex has `human_goal_set_name` {}",
                        g.set_id,
                        if g.set_area.is_empty() {
                            "(its set_area is empty)".to_string()
                        } else {
                            g.set_area
                                .iter()
                                .map(|a| format!("`{a}`"))
                                .collect::<Vec<_>>()
                                .join(" or ")
                        }
                    ),
                )
                .with_help(
                    "give a vertex the parameter `human_goal_set_name` with one of the set's \
                     area names",
                ),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{count, crowd_map};

    #[test]
    fn area_without_vertex() {
        let mut m = crowd_map();
        assert_eq!(count(&m, "E0803"), 0);
        m.b.crowd_sim.as_mut().unwrap().goal_sets[0].set_area = vec!["nowhere".into()];
        assert_eq!(count(&m, "E0803"), 1);
    }
}
