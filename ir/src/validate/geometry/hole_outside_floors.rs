//! # W0604 hole-outside-floors
//!
//! **What:** a hole does not overlap any floor of its level: no hole vertex is inside a
//! floor, no floor vertex is inside the hole, and no edges cross.
//!
//! **Why it matters:** holes are subtracted from the floors of their level (to leave room
//! for stairs, shafts or atria). A hole that overlaps no floor cuts nothing, so it is
//! either misplaced (drawn on the wrong level, or the floor around it was moved) or left
//! over from an edit.
//!
//! **Fix:** move the hole onto the floor it should cut, draw it on the right level, or
//! delete it.
//!
//! **Example:**
//! ```yaml
//! vertices: [[0, 0, 0, ""], [4, 0, 0, ""], [4, 4, 0, ""], [0, 4, 0, ""],
//!            [10, 0, 0, ""], [11, 0, 0, ""], [11, 1, 0, ""]]
//! floors:
//!   - {vertices: [0, 1, 2, 3], parameters: {}}
//! holes:
//!   - {vertices: [4, 5, 6], parameters: {}}   # W0604
//! ```

use super::shapes::{distinct_vertices, polygons, ring, rings_overlap};
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0604",
    name: "hole-outside-floors",
    summary: "a hole overlaps no floor of its level",
    group: Group::Geometry,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    for p in polygons(b).filter(|p| p.kind == "hole") {
        if distinct_vertices(p.poly) < 3 {
            continue; // E0601
        }
        let level = &b.levels[p.poly.level];
        let (hole, _) = ring(b, p.poly);
        let overlaps = level
            .floors
            .iter()
            .any(|&f| rings_overlap(&hole, &ring(b, &b.floors[f]).0));
        if overlaps {
            continue;
        }
        let why = if level.floors.is_empty() {
            "the level has no floors".to_string()
        } else {
            match level.floors.len() {
                1 => "it does not overlap the level's floor".to_string(),
                n => format!("it overlaps none of the level's {n} floors"),
            }
        };
        out.push(
            Diagnostic::warning(
                RULE.code,
                p.span,
                format!(
                    "hole on level `{}` cuts nothing: {why}",
                    ctx.level_name(p.poly.level)
                ),
            )
            .with_help("move the hole onto the floor it should cut, or delete it"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};

    #[test]
    fn holes_must_overlap_a_floor() {
        let mut m = TestMap::new();
        let sq = |m: &mut TestMap, x: f64, y: f64, s: f64| {
            [(0.0, 0.0), (s, 0.0), (s, s), (0.0, s)].map(|(dx, dy)| m.vertex("", x + dx, y + dy))
        };
        let f = sq(&mut m, 0.0, 0.0, 4.0);
        m.floor(&f);
        let inside = sq(&mut m, 1.0, 1.0, 1.0);
        m.hole(&inside);
        let covering = sq(&mut m, -1.0, -1.0, 6.0);
        m.hole(&covering);
        // A plus sign: the hole's corners are all outside the floor and vice versa.
        let h = [(-1.0, 1.0), (5.0, 1.0), (5.0, 2.0), (-1.0, 2.0)].map(|(x, y)| m.vertex("", x, y));
        m.hole(&h);
        assert!(!codes_of(&m.b).contains(&"W0604"));
        let far = sq(&mut m, 10.0, 10.0, 1.0);
        m.hole(&far);
        assert_eq!(codes_of(&m.b).iter().filter(|c| **c == "W0604").count(), 1);
    }

    #[test]
    fn holes_on_levels_without_floors_warn() {
        let mut m = TestMap::new();
        let h = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)].map(|(x, y)| m.vertex("", x, y));
        m.hole(&h);
        assert!(codes_of(&m.b).contains(&"W0604"));
    }
}
