//! # W0306 door-not-crossed
//!
//! **What:** no lane of any navigation graph crosses the door.
//!
//! **Why it matters:** a lane that crosses a door gets the door's name (`door_name`) in
//! the nav graph, and that is the only way robots learn that they must ask for the door
//! to open. A door no lane crosses is never opened for robots: either it is meant for
//! people only (then the warning can be ignored), or the lane through it is missing or
//! misses the door segment (for example it ends just short of it, or runs along it).
//!
//! mapc tests the crossing in metres with a scale-free segment test, so it also works on
//! `wgs84` maps, where the reference generator's fixed threshold never detects a door.
//!
//! **Fix:** draw the lane so that it crosses the door segment, or ignore the warning for
//! doors robots never use.
//!
//! **Example:**
//! ```yaml
//! vertices: [[0, 0, 0, a], [4, 0, 0, b], [2, 1, 0, ""], [2, 2, 0, ""]]
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]
//! doors:
//!   - [2, 3, {name: [1, d1], type: [1, sliding]}]   # W0306: the lane passes below
//! ```

use super::zero_width::MIN_DOOR_WIDTH;
use crate::lints::Group;
use crate::validate::geometry::shapes::{segments_meet, Meet};
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0306",
    name: "door-not-crossed",
    summary: "no lane crosses a door, so robots never open it",
    group: Group::Doors,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    for (h, door) in b.doors.iter() {
        let p1 = b.vertices[door.start].pos;
        let p2 = b.vertices[door.end].pos;
        if p1.minus(p2).norm() < MIN_DOOR_WIDTH {
            continue; // E0304
        }
        let crossed = b.levels[door.level].lanes.iter().any(|&l| {
            let lane = &b.lanes[l];
            let q1 = b.vertices[lane.start].pos;
            let q2 = b.vertices[lane.end].pos;
            segments_meet(p1, p2, q1, q2) == Meet::Cross
        });
        if !crossed {
            out.push(
                Diagnostic::warning(
                    RULE.code,
                    b.doors.span(h),
                    format!(
                        "no lane crosses door `{}` on level `{}`, so robots never ask for it to open",
                        door.name,
                        ctx.level_name(door.level)
                    ),
                )
                .with_help(
                    "draw a lane across the door segment if robots use this door; \
                     doors for people only can keep this warning",
                ),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::DoorKind;

    fn map(door: [(f64, f64); 2]) -> Vec<&'static str> {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 4.0, 0.0);
        m.lane(a, b, 0, true);
        let c = m.vertex("", door[0].0, door[0].1);
        let d = m.vertex("", door[1].0, door[1].1);
        m.door("d", DoorKind::Sliding, c, d);
        codes_of(&m.b)
    }

    #[test]
    fn crossed_doors_are_fine() {
        assert!(!map([(2.0, -1.0), (2.0, 1.0)]).contains(&"W0306"));
        // Slanted, and touching the lane's end.
        assert!(!map([(3.0, -1.0), (5.0, 1.0)]).contains(&"W0306"));
        assert!(!map([(4.0, 0.0), (4.0, 1.0)]).contains(&"W0306"));
    }

    #[test]
    fn missed_and_parallel_doors_warn() {
        assert!(map([(2.0, 0.5), (2.0, 1.5)]).contains(&"W0306"));
        assert!(map([(5.0, -1.0), (5.0, 1.0)]).contains(&"W0306"));
        // Lying along the lane.
        assert!(map([(1.0, 0.0), (3.0, 0.0)]).contains(&"W0306"));
    }

    #[test]
    fn lanes_of_other_levels_do_not_count() {
        let mut m = TestMap::new();
        let c = m.vertex("", 2.0, -1.0);
        let d = m.vertex("", 2.0, 1.0);
        m.door("d", DoorKind::Sliding, c, d);
        m.level("L2", 3.0);
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 4.0, 0.0);
        m.lane(a, b, 0, true);
        assert!(codes_of(&m.b).contains(&"W0306"));
    }
}
