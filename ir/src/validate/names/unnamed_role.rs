//! # W0507 unnamed-role-waypoint
//!
//! **What:** a charger (`is_charger`), `pickup_dispenser` or `dropoff_ingestor` vertex has
//! an empty name.
//!
//! **Why it matters:** these waypoints are referred to by name: a fleet configuration
//! assigns each robot its charger by waypoint name, and delivery tasks name their pickup
//! and dropoff places. An unnamed one exists in the graph but nothing can point at it.
//! (Parking spots and holding points are not checked: the fleet adapter finds them by
//! their flag, not by name, and unnamed ones are common and harmless.)
//!
//! **Fix:** give the vertex a name that is unique in its graph (e.g. `charger_1`).
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, "", {is_charger: [4, true]}]   # W0507
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0507",
    name: "unnamed-role-waypoint",
    summary: "a charger, dispenser or ingestor vertex has no name",
    group: Group::Names,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, v) in ctx.b.vertices.iter() {
        if !v.name.is_empty() {
            continue;
        }
        let r = &v.roles;
        let roles: Vec<&str> = [
            (r.is_charger, "a charger"),
            (r.pickup_dispenser.is_some(), "a pickup dispenser"),
            (r.dropoff_ingestor.is_some(), "a dropoff ingestor"),
        ]
        .into_iter()
        .filter_map(|(on, what)| on.then_some(what))
        .collect();
        if roles.is_empty() {
            continue;
        }
        out.push(
            Diagnostic::warning(
                RULE.code,
                ctx.vertex_span(h),
                format!(
                    "{} is {} but has no name, so fleet configurations and tasks cannot refer to it",
                    ctx.vertex_label(h),
                    roles.join(" and ")
                ),
            )
            .with_help("give the vertex a name that is unique in its graph"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{param, params, TestMap};
    use crate::ParamValue;

    #[test]
    fn unnamed_roles() {
        let mut m = TestMap::new();
        let charger = || params(vec![param("is_charger", ParamValue::Bool(true))]);
        m.vertex_with("", 0.0, 0.0, charger());
        m.vertex_with("c1", 1.0, 0.0, charger());
        m.vertex("", 2.0, 0.0);
        let parking = params(vec![
            param("is_parking_spot", ParamValue::Bool(true)),
            param("is_holding_point", ParamValue::Bool(true)),
        ]);
        m.vertex_with("", 2.5, 0.0, parking);
        m.vertex_with(
            "",
            3.0,
            0.0,
            params(vec![param(
                "pickup_dispenser",
                ParamValue::String("d".into()),
            )]),
        );
        let r: Vec<_> = crate::validate(&m.b)
            .into_iter()
            .filter(|d| d.code == "W0507")
            .map(|d| d.message)
            .collect();
        assert_eq!(r.len(), 2, "{r:?}");
        assert!(r[0].contains("is a charger but has no name"), "{r:?}");
    }
}
