//! # E0804 crowd-unknown-profile
//!
//! **What:** an agent group's `profile_selector` is not the name of an agent profile.
//!
//! **Why it matters:** the profile gives the group's people their radius, speeds and
//! avoidance parameters; Menge refuses a scene whose group names an unknown profile, and
//! `mapc sim` cannot size or move them.
//!
//! **Fix:** use the name of one of `agent_profiles` (the robots' groups use
//! `external_agent`).
//!
//! **Example:**
//! ```yaml
//! crowd_sim:
//!   agent_profiles: [{name: human, r: 0.25, pref_speed: 1.34, max_speed: 2}]
//!   agent_groups:
//!     - {profile_selector: humans, state_selector: walking, agents_number: 2, x: 1, y: 1}   # E0804
//! ```

use super::crowd;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0804",
    name: "crowd-unknown-profile",
    summary: "an agent group names an agent profile that does not exist",
    group: Group::Crowd,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let Some(c) = crowd(ctx) else { return };
    for g in &c.agent_groups {
        if !c
            .agent_profiles
            .iter()
            .any(|p| p.name == g.profile_selector)
        {
            let names: Vec<&str> = c.agent_profiles.iter().map(|p| p.name.as_str()).collect();
            out.push(
                Diagnostic::error(
                    RULE.code,
                    g.span,
                    format!(
                        "agent group {} uses the profile `{}`, which does not exist",
                        g.group_id, g.profile_selector
                    ),
                )
                .with_help(format!(
                    "use one of the agent profiles: {}",
                    if names.is_empty() {
                        "(none are defined)".to_string()
                    } else {
                        names.join(", ")
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
    fn unknown_profile() {
        let mut m = crowd_map();
        m.b.crowd_sim.as_mut().unwrap().agent_groups[0].profile_selector = "humans".into();
        assert_eq!(count(&m, "E0804"), 1);
    }
}
