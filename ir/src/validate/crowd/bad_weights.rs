//! # E0806 crowd-bad-weights
//!
//! **What:** the weights of a crowd transition's `Target` states are not all finite and
//! non-negative, or do not add up to a positive number.
//!
//! **Why it matters:** the next state is drawn with probability proportional to its
//! weight. With weights summing to zero (or a negative or NaN weight) there is no
//! distribution to draw from: Menge fails when an agent takes the transition, and the
//! people of `mapc sim` would stay in their state forever.
//!
//! **Fix:** give the targets positive weights (they need not sum to 1).
//!
//! **Example:**
//! ```yaml
//! transitions:
//!   - from: walking
//!     to: ""
//!     Condition: {type: goal_reached, distance: 1}
//!     Target: [{name: gate_a, weight: 0}, {name: gate_b, weight: 0}]   # E0806
//! ```

use super::crowd;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "E0806",
    name: "crowd-bad-weights",
    summary: "a crowd transition's target weights do not sum to a positive number",
    group: Group::Crowd,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let Some(c) = crowd(ctx) else { return };
    for t in &c.transitions {
        if t.targets.is_empty() {
            continue;
        }
        let bad = t.targets.iter().find(|x| !(x.1.is_finite() && x.1 >= 0.0));
        let sum: f64 = t.targets.iter().map(|x| x.1).sum();
        if bad.is_some() || !(sum > 0.0 && sum.is_finite()) {
            let span = bad.map_or(t.span, |x| x.2);
            let what = match bad {
                Some((name, w, _)) => format!("target `{name}` has weight {w}"),
                None => format!("the target weights sum to {sum}"),
            };
            out.push(
                Diagnostic::error(
                    RULE.code,
                    span,
                    format!(
                        "the crowd transition from `{}` cannot choose its next state: {what}",
                        t.from
                    ),
                )
                .with_help("give the targets positive weights (they need not sum to 1)"),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{count, crowd_map};

    #[test]
    fn weights() {
        let mut m = crowd_map();
        let t = &mut m.b.crowd_sim.as_mut().unwrap().transitions[0];
        t.targets = vec![
            ("stop".into(), 0.0, Default::default()),
            ("walk".into(), 0.0, Default::default()),
        ];
        assert_eq!(count(&m, "E0806"), 1);
        let t = &mut m.b.crowd_sim.as_mut().unwrap().transitions[0];
        t.targets[0].1 = -1.0;
        t.targets[1].1 = 2.0;
        assert_eq!(count(&m, "E0806"), 1);
        let t = &mut m.b.crowd_sim.as_mut().unwrap().transitions[0];
        t.targets[0].1 = 0.5;
        assert_eq!(count(&m, "E0806"), 0);
    }
}
