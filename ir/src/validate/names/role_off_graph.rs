//! # W0503 role-off-graph
//!
//! **What:** a vertex has a waypoint role (charger, parking spot, holding point, cleaning
//! zone, `dock_name`, `pickup_dispenser`, `dropoff_ingestor`, or a robot spawn) but no lane
//! of any graph starts or ends at it.
//!
//! **Why it matters:** only vertices used by lanes become nav-graph waypoints; roles on any
//! other vertex are silently dropped. The charger, parking spot or dispenser never exists
//! for the fleet, and tasks that refer to it fail. A robot spawned off the graph starts
//! where no waypoint is, so the fleet adapter cannot place it on its graph (and its spawn
//! yaw, taken from the first lane at the vertex, defaults to 0).
//!
//! **Fix:** connect the vertex with a lane to the graph of the fleet that should use it, or
//! move the role to the waypoint it was meant for.
//!
//! **Example:**
//! ```yaml
//! vertices:
//!   - [0, 0, 0, charger_1, {is_charger: [4, true]}]   # W0503: no lane here
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, WaypointRoles};

pub(crate) static RULE: Rule = Rule {
    code: "W0503",
    name: "role-off-graph",
    summary: "a vertex with a waypoint role that no lane uses",
    group: Group::Names,
    metric: false,
    check,
};

/// The roles that only mean something on a nav-graph waypoint, by parameter name.
pub(super) fn role_names(r: &WaypointRoles) -> Vec<&'static str> {
    let mut v = Vec::new();
    for (on, name) in [
        (r.is_charger, "is_charger"),
        (r.is_parking_spot, "is_parking_spot"),
        (r.is_holding_point, "is_holding_point"),
        (r.is_cleaning_zone, "is_cleaning_zone"),
        (r.dock_name.is_some(), "dock_name"),
        (r.pickup_dispenser.is_some(), "pickup_dispenser"),
        (r.dropoff_ingestor.is_some(), "dropoff_ingestor"),
        (r.spawn_robot_type.is_some(), "spawn_robot_type"),
    ] {
        if on {
            v.push(name);
        }
    }
    v
}

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, v) in ctx.b.vertices.iter() {
        if !ctx.lanes_at_vertex[h.index()].is_empty() {
            continue;
        }
        let roles = role_names(&v.roles);
        if roles.is_empty() {
            continue;
        }
        let list = roles
            .iter()
            .map(|r| format!("`{r}`"))
            .collect::<Vec<_>>()
            .join(", ");
        out.push(
            Diagnostic::warning(
                RULE.code,
                ctx.vertex_span(h),
                format!(
                    "{} has {list} but no lane starts or ends at it, so it is not a waypoint \
                     of any graph and the role is lost",
                    ctx.vertex_label(h)
                ),
            )
            .with_help("connect the vertex to its fleet's graph with a lane"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{param, params, TestMap};
    use crate::ParamValue;

    fn run(m: &TestMap) -> Vec<String> {
        crate::validate(&m.b)
            .into_iter()
            .filter(|d| d.code == "W0503")
            .map(|d| d.message)
            .collect()
    }

    #[test]
    fn roles_off_and_on_graph() {
        let mut m = TestMap::new();
        let charger = params(vec![
            param("is_charger", ParamValue::Bool(true)),
            param("dock_name", ParamValue::String("d".into())),
        ]);
        let a = m.vertex_with("a", 0.0, 0.0, charger.clone());
        let b = m.vertex("b", 4.0, 0.0);
        m.lane(a, b, 0, true);
        m.vertex_with("c", 8.0, 0.0, charger);
        // `is_charger: false` and plain vertices are not roles.
        m.vertex_with(
            "d",
            9.0,
            0.0,
            params(vec![param("is_charger", ParamValue::Bool(false))]),
        );
        m.vertex("e", 10.0, 0.0);
        let r = run(&m);
        assert_eq!(r.len(), 1, "{r:?}");
        assert!(r[0].contains("vertex `c`") && r[0].contains("`is_charger`, `dock_name`"));
    }

    #[test]
    fn spawn_off_graph() {
        let mut m = TestMap::new();
        m.vertex_with(
            "s",
            0.0,
            0.0,
            params(vec![
                param("spawn_robot_type", ParamValue::String("TinyRobot".into())),
                param("spawn_robot_name", ParamValue::String("tiny_1".into())),
            ]),
        );
        assert_eq!(run(&m).len(), 1);
    }
}
