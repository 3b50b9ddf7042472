//! # W0404 lift-level-without-waypoint
//!
//! **What:** robots use a lift (a lane vertex lies inside its shaft, the cabin rectangle
//! plus 5 cm on each side, on some level), but on another level listed in its
//! `level_doors` no lane vertex lies inside the shaft.
//!
//! **Why it matters:** robots board a lift by driving along a lane to a waypoint inside
//! it; the nav graph tags such waypoints with the lift's name. Without one, the lift
//! stops at the level for people (and in simulation) but no robot can get on or off
//! there, so tasks to that level through the lift cannot be planned. Lifts that no lane
//! reaches on any level are taken to be for people only and are not reported; levels
//! outside the lift's `lowest_floor`..`highest_floor` range are reported by W0406.
//!
//! **Fix:** add a waypoint at the lift's centre on that level and connect it with a lane
//! through the lift door (traffic_editor creates the `lift_cabin` vertex for you), or
//! remove the level from `level_doors` if robots should not use the lift there.
//!
//! **Example:**
//! ```yaml
//! lifts:
//!   LA:
//!     x: 10
//!     y: 5
//!     level_doors:
//!       L1: [door1]   # a lane on L1 ends at (10, 5)
//!       L2: [door1]   # W0404: no lane on L2 reaches (10, 5)
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Handle, Level, Lift};
use std::collections::HashSet;

pub(crate) static RULE: Rule = Rule {
    code: "W0404",
    name: "lift-level-without-waypoint",
    summary: "a level a lift serves has no lane vertex inside the lift",
    group: Group::LiftWaypoints,
    metric: true,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    if b.lifts.is_empty() {
        return;
    }
    // (lift, level) pairs with a lane vertex inside the shaft.
    let mut boarded: HashSet<(Handle<Lift>, Handle<Level>)> = HashSet::new();
    for (vh, v) in b.vertices.iter() {
        if let Some(l) = ctx.lift_of(vh) {
            if !ctx.lanes_at_vertex[vh.index()].is_empty() {
                boarded.insert((l, v.level));
            }
        }
    }
    for (lh, lift) in b.lifts.iter() {
        if lift.width <= 0.0 || lift.depth <= 0.0 {
            continue; // E0401: nothing can be inside
        }
        if !boarded.iter().any(|&(l, _)| l == lh) {
            continue; // no robot uses this lift anywhere
        }
        for ld in &lift.level_doors {
            if !b.lifts_on_level(ld.level).any(|x| x == lh) {
                continue; // W0406: the shaft does not reach the level
            }
            if !boarded.contains(&(lh, ld.level)) {
                out.push(
                    Diagnostic::warning(
                        RULE.code,
                        ld.span,
                        format!(
                            "robots use lift `{}`, but on level `{}`, which it serves, no lane reaches a waypoint inside it",
                            lift.name,
                            ctx.level_name(ld.level)
                        ),
                    )
                    .with_help(
                        "add a waypoint inside the lift on this level and a lane to it through the door, \
                         or drop the level from `level_doors`",
                    ),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::Vec2;

    #[test]
    fn needs_a_lane_vertex_inside_on_each_level() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let a = m.vertex("in1", 10.0, 5.0);
        let b = m.vertex("out1", 10.0, 2.0);
        m.lane(a, b, 0, true);
        let l2 = m.level("L2", 3.0);
        // Inside, but on no lane.
        m.vertex("in2", 10.0, 5.0);
        let l3 = m.level("L3", 6.0);
        let c = m.vertex("in3", 10.3, 5.0);
        let d = m.vertex("out3", 10.0, 2.0);
        m.lane(d, c, 1, false);
        m.lift("LA", Vec2::new(10.0, 5.0), 2.0, 2.0, &[l1, l2, l3]);
        let diags = crate::validate(&m.b);
        let w: Vec<_> = diags.iter().filter(|d| d.code == "W0404").collect();
        assert_eq!(w.len(), 1);
        assert!(w[0].message.contains("`L2`"));
    }

    #[test]
    fn lifts_no_robot_uses_are_not_reported() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let a = m.vertex("cabin", 10.0, 5.0);
        let b = m.vertex("elsewhere", 0.0, 0.0);
        let c = m.vertex("far", 0.0, 3.0);
        m.lane(b, c, 0, true);
        let _ = a;
        let l2 = m.level("L2", 3.0);
        m.lift("LA", Vec2::new(10.0, 5.0), 2.0, 2.0, &[l1, l2]);
        assert!(!codes_of(&m.b).contains(&"W0404"));
    }

    #[test]
    fn levels_outside_the_range_are_left_to_w0406() {
        let mut m = TestMap::new();
        let l1 = m.level;
        let a = m.vertex("in1", 0.0, 0.0);
        let b = m.vertex("out1", 0.0, -3.0);
        m.lane(a, b, 0, true);
        let l2 = m.level("L2", 3.0);
        let lift = m.lift("LA", Vec2::new(0.0, 0.0), 2.0, 2.0, &[l1, l2]);
        m.b.lifts[lift].highest_level = Some(l1);
        assert!(!codes_of(&m.b).contains(&"W0404"));
    }
}
