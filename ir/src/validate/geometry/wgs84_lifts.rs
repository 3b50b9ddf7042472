//! # W0607 wgs84-lifts
//!
//! **What:** a `wgs84` map defines lifts.
//!
//! **Why it matters:** in `wgs84` maps, vertices and models are written as longitude and
//! latitude, but traffic_editor writes a lift's `x`/`y` in its internal Web-Mercator
//! metres without converting them back, while generators (the reference one and mapc)
//! read them as longitude/latitude like everything else. Either the lift lands far away
//! from the building (editor-written files: mapc then usually cannot even project it), or
//! its `x`/`y` were hand-edited to longitude/latitude, which traffic_editor does not
//! expect, since it handles lift `x`/`y` as Web-Mercator metres. Lift doors, width and
//! depth are metres in both cases.
//!
//! **Fix:** check the lift's position on the map; write `x`/`y` as longitude/latitude of
//! the cabin centre, and re-check after every save from traffic_editor. Consider a
//! `cartesian_meters` map for buildings with lifts.
//!
//! **Example:**
//! ```yaml
//! coordinate_system: wgs84
//! lifts:
//!   LA:   # W0607
//!     x: 11542071.5   # Web-Mercator metres, not a longitude
//!     y: 149452.3
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{CoordinateSystem, Diagnostic};

pub(crate) static RULE: Rule = Rule {
    code: "W0607",
    name: "wgs84-lifts",
    summary: "a wgs84 map has lifts, whose coordinates the editor does not write as lon/lat",
    group: Group::LiftGeometry,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    if b.coordinate_system != CoordinateSystem::Wgs84 {
        return;
    }
    for (h, lift) in b.lifts.iter() {
        let looks_like_degrees = lift.raw.x.abs() <= 180.0 && lift.raw.y.abs() <= 90.0;
        let hint = if looks_like_degrees {
            "they look like degrees, but traffic_editor handles lift x/y as Web-Mercator metres"
        } else {
            "they are not degrees (traffic_editor writes lift x/y as Web-Mercator metres)"
        };
        out.push(
            Diagnostic::warning(
                RULE.code,
                b.lifts.span(h),
                format!(
                    "lift `{}` in a wgs84 map: its x/y ({}, {}) are read as longitude/latitude; {hint}",
                    lift.name, lift.raw.x, lift.raw.y
                ),
            )
            .with_label(b.spans.coordinate_system, "the map is wgs84")
            .with_help("check the lift's position; write x/y as the cabin centre's longitude/latitude"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::{CoordinateSystem, Vec2};

    #[test]
    fn only_wgs84_maps_warn() {
        let mut m = TestMap::new();
        let l1 = m.level;
        m.lift("LA", Vec2::new(103.8, 1.3), 2.0, 2.0, &[l1]);
        assert!(!codes_of(&m.b).contains(&"W0607"));
        m.b.coordinate_system = CoordinateSystem::Wgs84;
        assert_eq!(codes_of(&m.b).iter().filter(|c| **c == "W0607").count(), 1);
    }
}
