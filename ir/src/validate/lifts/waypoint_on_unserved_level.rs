//! # W0411 lift-waypoint-on-unserved-level
//!
//! **What:** a lane vertex lies inside a lift's shaft on a level that the shaft passes
//! (within `lowest_floor`..`highest_floor`) but that is not in the lift's `level_doors`.
//!
//! **Why it matters:** the nav graph tags the waypoint with the lift's name, as on the
//! levels the lift serves, so a fleet adapter plans rides to and from it. But the cabin
//! stops only where it has doors: a robot sent there asks for a floor the lift does not
//! have and waits for a cabin that never comes (its task fails when the request times
//! out). On a level the lift only passes through, the waypoint is a leftover, or the
//! level was meant to be served.
//!
//! **Fix:** list the level in `level_doors` with the cabin door that opens there, or move
//! the waypoint (and its lanes) out of the shaft.
//!
//! **Example:**
//! ```yaml
//! lifts:
//!   LA:
//!     x: 10
//!     y: 5
//!     level_doors:
//!       L1: [door1]
//!       L2: [door1]   # and a lane on L3 ends at (10, 5): W0411
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Handle, Level, Lift};
use std::collections::BTreeSet;

pub(crate) static RULE: Rule = Rule {
    code: "W0411",
    name: "lift-waypoint-on-unserved-level",
    summary: "a lane vertex lies inside a lift on a level the lift has no door on",
    group: Group::LiftWaypoints,
    metric: true,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    if b.lifts.is_empty() {
        return;
    }
    // Once per (lift, level), at the first lane vertex in document order.
    let mut seen: BTreeSet<(Handle<Lift>, Handle<Level>)> = BTreeSet::new();
    for (vh, v) in b.vertices.iter() {
        let Some(lh) = ctx.lift_of(vh) else { continue };
        if ctx.lanes_at_vertex[vh.index()].is_empty() {
            continue;
        }
        let lift = &b.lifts[lh];
        if lift.level_doors.iter().any(|d| d.level == v.level) || !seen.insert((lh, v.level)) {
            continue;
        }
        let served: Vec<String> = lift
            .level_doors
            .iter()
            .map(|d| format!("`{}`", ctx.level_name(d.level)))
            .collect();
        out.push(
            Diagnostic::warning(
                RULE.code,
                ctx.vertex_span(vh),
                format!(
                    "{} is inside lift `{}`, which stops only at {}: robots sent there wait \
                     for a cabin that never comes",
                    ctx.vertex_label(vh),
                    lift.name,
                    served.join(", ")
                ),
            )
            .with_help(
                "add the level to the lift's `level_doors` with the door that opens there, \
                 or move the waypoint out of the shaft",
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::TestMap;
    use crate::{Diagnostic, Vec2};

    /// Lift LA at (10, 5) with doors on L1 and L2; on each of L1..L3 a lane from a
    /// waypoint in the shaft to one outside; `top` (when set) the lift's highest level.
    fn three_levels(extra_on_l3: bool, top: Option<usize>) -> Vec<Diagnostic> {
        let mut m = TestMap::new();
        let mut levels = vec![m.level];
        for (k, name) in ["L1", "L2", "L3"].iter().enumerate() {
            if k > 0 {
                levels.push(m.level(name, 3.0 * k as f64));
            }
            let a = m.vertex(&format!("in{}", k + 1), 10.0, 5.0);
            let b = m.vertex(&format!("out{}", k + 1), 10.0, 2.0);
            m.lane(a, b, 0, true);
            if extra_on_l3 && k == 2 {
                let c = m.vertex("in3b", 10.2, 5.0);
                m.lane(c, b, 0, true);
            }
        }
        let lift = m.lift("LA", Vec2::new(10.0, 5.0), 2.0, 2.0, &levels[..2]);
        m.b.lifts[lift].highest_level = top.map(|k| levels[k]);
        crate::validate(&m.b)
            .into_iter()
            .filter(|d| d.code == "W0411")
            .collect()
    }

    #[test]
    fn a_lane_vertex_in_the_shaft_on_a_level_without_doors() {
        // A second vertex in the shaft on L3: still one warning for the level.
        let w = three_levels(true, None);
        assert_eq!(w.len(), 1, "{w:#?}");
        assert!(w[0].message.contains("`in3`") && w[0].message.contains("`L3`"));
        assert!(w[0].message.contains("`L1`, `L2`"), "{}", w[0].message);
    }

    #[test]
    fn levels_past_the_shaft_are_fine() {
        // L3 is above the shaft (highest floor L2): not the lift's business.
        assert!(three_levels(false, Some(1)).is_empty());
    }
}
