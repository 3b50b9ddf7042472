//! # E0802 crowd-unknown-goal-set
//!
//! **What:** a crowd state's `goal_set` is not the `set_id` of any goal set (a state
//! without goals, like the robots' `external_static`, has `goal_set: -1`).
//!
//! **Why it matters:** the state's goal selector picks goals from that set; Menge refuses
//! the behaviour file and `mapc sim` has nowhere to send the people in that state.
//!
//! **Fix:** use the `set_id` of one of `goal_sets`, or `-1` for a state without goals.
//!
//! **Example:**
//! ```yaml
//! crowd_sim:
//!   goal_sets: [{set_id: 0, capacity: 10, set_area: [gate]}]
//!   states: [{name: walking, goal_set: 3, final: 0, navmesh_file_name: L1_navmesh.nav}]   # E0802
//! ```

use super::crowd;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0802",
    name: "crowd-unknown-goal-set",
    summary: "a crowd state names a goal set that does not exist",
    group: Group::Crowd,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let Some(c) = crowd(ctx) else { return };
    for s in &c.states {
        if s.goal_set >= 0 && !c.goal_sets.iter().any(|g| g.set_id == s.goal_set) {
            let ids: Vec<String> = c.goal_sets.iter().map(|g| g.set_id.to_string()).collect();
            out.push(
                Diagnostic::error(
                    RULE.code,
                    s.span,
                    format!(
                        "crowd state `{}` uses goal set {}, which does not exist",
                        s.name, s.goal_set
                    ),
                )
                .with_help(format!(
                    "use a goal set id ({}) or -1 for a state without goals",
                    if ids.is_empty() {
                        "none are defined".to_string()
                    } else {
                        ids.join(", ")
                    }
                )),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{count, crowd_map};

    #[test]
    fn missing_goal_set() {
        let mut m = crowd_map();
        m.b.crowd_sim.as_mut().unwrap().states[0].goal_set = 4;
        assert_eq!(count(&m, "E0802"), 1);
    }
}
