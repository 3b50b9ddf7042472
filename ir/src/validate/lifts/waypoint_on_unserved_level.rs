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
    use crate::Vec2;

    #[test]
    fn a_lane_vertex_in_the_shaft_on_a_level_without_doors() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let a = m.vertex("in1", 10.0, 5.0);
        let b = m.vertex("out1", 10.0, 2.0);
        m.lane(a, b, 0, true);
        let l2 = m.level("L2", 3.0);
        let c = m.vertex("in2", 10.0, 5.0);
        let d = m.vertex("out2", 10.0, 2.0);
        m.lane(c, d, 0, true);
        m.level("L3", 6.0);
        let e = m.vertex("in3", 10.0, 5.0);
        let f = m.vertex("out3", 10.0, 2.0);
        m.lane(e, f, 0, true);
        // A second vertex in the shaft on L3: still one warning for the level.
        let g = m.vertex("in3b", 10.2, 5.0);
        m.lane(g, f, 0, true);
        m.lift("LA", Vec2::new(10.0, 5.0), 2.0, 2.0, &[l1, l2]);
        let diags = crate::validate(&m.b);
        let w: Vec<_> = diags.iter().filter(|d| d.code == "W0411").collect();
        assert_eq!(w.len(), 1, "{w:#?}");
        assert!(w[0].message.contains("`in3`") && w[0].message.contains("`L3`"));
        assert!(w[0].message.contains("`L1`, `L2`"), "{}", w[0].message);
    }

    #[test]
    fn served_levels_and_levels_past_the_shaft_are_fine() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let a = m.vertex("in1", 10.0, 5.0);
        let b = m.vertex("out1", 10.0, 2.0);
        m.lane(a, b, 0, true);
        let l2 = m.level("L2", 3.0);
        let c = m.vertex("in2", 10.0, 5.0);
        let d = m.vertex("out2", 10.0, 2.0);
        m.lane(c, d, 0, true);
        // L3 is above the shaft (highest floor L2): not the lift's business.
        m.level("L3", 6.0);
        let e = m.vertex("in3", 10.0, 5.0);
        let f = m.vertex("out3", 10.0, 2.0);
        m.lane(e, f, 0, true);
        let lift = m.lift("LA", Vec2::new(10.0, 5.0), 2.0, 2.0, &[l1, l2]);
        m.b.lifts[lift].highest_level = Some(l2);
        let diags = crate::validate(&m.b);
        assert!(!diags.iter().any(|d| d.code == "W0411"), "{diags:#?}");
    }
}
