//! # W0402 lift-door-off-cabin
//!
//! **What:** a lift cabin door is not placed on a side of the cabin: its centre (`x`,
//! `y`, cabin frame) is more than 0.3 m from the nearest side, or it sits at a corner
//! where the nearest side is ambiguous (within 5 cm of both), or the door, centred
//! where it is, extends past the ends of its side.
//!
//! **Why it matters:** the generator snaps each door to the nearest cabin side (front,
//! back, left or right) and cuts an opening of the door's width into that side's wall.
//! A door far from every side, or at a corner, lands on an arbitrary side; a door that
//! overruns its side produces wall segments outside the cabin and leaves the opening
//! partly walled. The shaft door on each level is placed the same way, so the robot's
//! way in may not match the map.
//!
//! A door drawn slightly outside the cabin, on the shaft wall (the hotel and clinic demo
//! maps put theirs 0.12 to 0.15 m out), is fine: the generator moves it onto the side.
//!
//! **Fix:** put the door centre on the side the door is on: `y = ±depth/2` for the front
//! or back, `x = ±width/2` for the sides, and keep it no wider than that side.
//!
//! **Example:**
//! ```yaml
//! lifts:
//!   LA:
//!     width: 2.0
//!     depth: 2.0
//!     doors:
//!       door1: {door_type: 2, x: 0, y: 0, width: 1.0, motion_axis_orientation: 0}   # W0402: at the centre
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Lift, LiftDoor};

/// A door centre farther than this from every side is off the cabin, metres.
pub(crate) const SIDE_TOLERANCE: f64 = 0.3;
/// Distances to two sides closer than this make the side ambiguous, metres.
const AMBIGUITY: f64 = 0.05;
/// The generator's cabin wall thickness: left and right sides span depth - 2 * this.
const WALL: f64 = 0.05;

pub(crate) static RULE: Rule = Rule {
    code: "W0402",
    name: "lift-door-off-cabin",
    summary: "a lift door is not on a side of its cabin, or is wider than the side",
    group: Group::Lifts,
    metric: true,
    check,
};

/// What is wrong with a door's placement, if anything.
pub(crate) fn problem(lift: &Lift, door: &LiftDoor) -> Option<String> {
    let (w, d) = (lift.width, lift.depth);
    let (x, y) = (door.pos.x, door.pos.y);
    let dx = (x.abs() - w / 2.0).abs();
    let dy = (y.abs() - d / 2.0).abs();
    // The generator's classification.
    let (side, along, lo, hi) = if dx <= dy {
        (
            if x > 0.0 { "right" } else { "left" },
            y,
            -d / 2.0 + WALL,
            d / 2.0 - WALL,
        )
    } else {
        (if y > 0.0 { "front" } else { "back" }, x, -w / 2.0, w / 2.0)
    };
    let nearest = dx.min(dy);
    if nearest > SIDE_TOLERANCE {
        return Some(format!(
            "its centre ({x}, {y}) is {nearest:.2} m from the nearest side of the {w} × {d} m cabin; \
             the generator puts it on the {side} side"
        ));
    }
    if (dx - dy).abs() < AMBIGUITY {
        return Some(format!(
            "its centre ({x}, {y}) is at a corner of the {w} × {d} m cabin, so its side is \
             ambiguous; the generator puts it on the {side} side"
        ));
    }
    let (a, b) = (along - door.width / 2.0, along + door.width / 2.0);
    if a < lo - 1e-6 || b > hi + 1e-6 {
        return Some(format!(
            "it spans {a:.3}..{b:.3} m along the {side} side, which only spans {lo:.3}..{hi:.3} m"
        ));
    }
    None
}

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (_, lift) in ctx.b.lifts.iter() {
        if lift.width <= 0.0 || lift.depth <= 0.0 {
            continue; // E0401
        }
        for door in &lift.doors {
            if let Some(why) = problem(lift, door) {
                out.push(
                    Diagnostic::warning(
                        RULE.code,
                        door.span,
                        format!("door `{}` of lift `{}` is not on a cabin side: {why}", door.name, lift.name),
                    )
                    .with_help(
                        "place the door centre on a side (y = ±depth/2 or x = ±width/2, cabin frame) \
                         and keep it within that side",
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

    fn door_at(x: f64, y: f64, width: f64) -> usize {
        let mut m = TestMap::new();
        let l1 = m.level;
        let lift = m.lift("LA", Vec2::new(0.0, 0.0), 2.5, 3.0, &[l1]);
        m.b.lifts[lift].doors[0].pos = Vec2::new(x, y);
        m.b.lifts[lift].doors[0].width = width;
        codes_of(&m.b).iter().filter(|c| **c == "W0402").count()
    }

    #[test]
    fn doors_on_or_near_a_side_are_fine() {
        assert_eq!(door_at(0.0, -1.5, 1.4), 0);
        assert_eq!(door_at(0.0, 1.62, 1.4), 0); // on the shaft wall (clinic demo)
        assert_eq!(door_at(1.25, 0.3, 1.0), 0);
        assert_eq!(door_at(0.0, 1.5, 2.5), 0); // exactly as wide as the front
    }

    #[test]
    fn off_side_corner_and_overrunning_doors_warn() {
        assert_eq!(door_at(0.0, 0.0, 1.0), 1);
        assert_eq!(door_at(0.0, 1.0, 1.0), 1);
        assert_eq!(door_at(0.0, 2.2, 1.0), 1);
        assert_eq!(door_at(1.25, 1.5, 0.5), 1);
        assert_eq!(door_at(0.0, 1.5, 2.6), 1);
        assert_eq!(door_at(0.8, 1.5, 1.4), 1);
        assert_eq!(door_at(-1.25, 0.0, 2.95), 1);
    }
}
