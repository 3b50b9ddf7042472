//! # E0801 crowd-unknown-state
//!
//! **What:** a crowd transition (`from`, `to`, a `Target` name) or an agent group's
//! `state_selector` names a state that `crowd_sim.states` does not have.
//!
//! **Why it matters:** Menge refuses a behaviour file whose transitions name unknown states
//! (the crowd simulator plugin then loads no one), and an agent group starting in an unknown
//! state has no behaviour at all. `mapc sim` cannot walk such people either.
//!
//! **Fix:** spell the state as it is named under `states`, or add the state.
//!
//! **Example:**
//! ```yaml
//! crowd_sim:
//!   states: [{name: walking, goal_set: 0, final: 0, navmesh_file_name: L1_navmesh.nav}]
//!   transitions:
//!     - {from: walkin, to: walking, Condition: {type: auto}}   # E0801
//! ```

use super::crowd;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Span};

pub(crate) static RULE: Rule = Rule {
    code: "E0801",
    name: "crowd-unknown-state",
    summary: "a crowd transition or agent group names an unknown state",
    group: Group::Crowd,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let Some(c) = crowd(ctx) else { return };
    let known = |n: &str| c.states.iter().any(|s| s.name == n);
    let mut report = |name: &str, what: &str, span: Span| {
        if !known(name) {
            let names: Vec<&str> = c.states.iter().map(|s| s.name.as_str()).collect();
            out.push(
                Diagnostic::error(
                    RULE.code,
                    span,
                    format!("{what} names the crowd state `{name}`, which does not exist"),
                )
                .with_help(format!(
                    "use one of the states: {}",
                    if names.is_empty() {
                        "(none are defined)".to_string()
                    } else {
                        names.join(", ")
                    }
                )),
            );
        }
    };
    for t in &c.transitions {
        report(&t.from, "a transition's `from`", t.span);
        // `to` is empty when the transition has weighted targets instead.
        if !t.to.is_empty() || t.targets.is_empty() {
            report(&t.to, "a transition's `to`", t.span);
        }
        for (name, _, span) in &t.targets {
            report(name, "a transition target", *span);
        }
    }
    for g in &c.agent_groups {
        report(
            &g.state_selector,
            "an agent group's `state_selector`",
            g.span,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{count, crowd_map};

    #[test]
    fn misspelled_states() {
        let mut m = crowd_map();
        let c = m.b.crowd_sim.as_mut().unwrap();
        c.transitions[0].from = "walkin".into();
        c.transitions[0].to = String::new();
        c.transitions[0].targets = vec![
            ("stop".into(), 1.0, Default::default()),
            ("stopp".into(), 1.0, Default::default()),
        ];
        c.agent_groups[0].state_selector = "nowhere".into();
        assert_eq!(count(&m, "E0801"), 3);
        m.b.crowd_sim.as_mut().unwrap().enable = false;
        assert_eq!(count(&m, "E0801"), 0);
    }
}
