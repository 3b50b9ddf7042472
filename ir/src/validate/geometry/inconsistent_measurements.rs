//! # W0606 inconsistent-measurements
//!
//! **What:** on a `reference_image` map, a measurement of the reference level implies a
//! scale (its `distance` in metres divided by its length in image pixels) that differs
//! by more than 5 % from the median scale of all the level's measurements. (The median
//! rather than the mean, so that one bad measurement among three does not make the good
//! ones look wrong too; with two measurements both are reported.)
//!
//! **Why it matters:** the map's scale is the mean of the measurements' scales, so one
//! wrong measurement (a mistyped distance, or an end point snapped to the wrong corner)
//! silently stretches or shrinks every level: lanes, doors, lifts and models all end up
//! the wrong size, and robots' positions drift away from their real ones.
//!
//! **Fix:** check the flagged measurement's `distance` and end points against the floor
//! plan, and correct or delete it.
//!
//! **Example:**
//! ```yaml
//! measurements:
//!   - [0, 1, {distance: [3, 10.0]}]   # 200 px: 0.05 m/px
//!   - [2, 3, {distance: [3, 10.0]}]   # 200 px: 0.05 m/px
//!   - [4, 5, {distance: [3, 15.0]}]   # W0606: 200 px: 0.075 m/px
//! ```

use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{CoordinateSystem, Diagnostic};

/// Largest accepted relative deviation from the mean scale.
const TOLERANCE: f64 = 0.05;

pub(crate) static RULE: Rule = Rule {
    code: "W0606",
    name: "inconsistent-measurements",
    summary: "a measurement's scale differs by more than 5% from the median scale",
    group: Group::Scale,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    let b = ctx.b;
    if b.coordinate_system != CoordinateSystem::ReferenceImage {
        return;
    }
    let level = &b.levels[b.reference_level];
    // (measurement, pixels, metres per pixel); degenerate ones are the frontend's (E0109).
    let est: Vec<_> = level
        .measurements
        .iter()
        .filter_map(|&m| {
            let meas = &b.measurements[m];
            let px = b.vertices[meas.start]
                .raw
                .minus(b.vertices[meas.end].raw)
                .norm();
            let s = meas.distance / px;
            (px > 0.0 && meas.distance > 0.0 && s.is_finite()).then_some((m, px, s))
        })
        .collect();
    if est.len() < 2 {
        return;
    }
    let mean = est.iter().map(|e| e.2).sum::<f64>() / est.len() as f64;
    let mut sorted: Vec<f64> = est.iter().map(|e| e.2).collect();
    sorted.sort_by(f64::total_cmp);
    let k = sorted.len();
    let median = if k % 2 == 1 {
        sorted[k / 2]
    } else {
        (sorted[k / 2 - 1] + sorted[k / 2]) / 2.0
    };
    for &(m, px, s) in &est {
        let dev = (s - median) / median;
        if dev.abs() <= TOLERANCE {
            continue;
        }
        let meas = &b.measurements[m];
        out.push(
            Diagnostic::warning(
                RULE.code,
                b.measurements.span(m),
                format!(
                    "measurement of {} m over {px:.1} px gives {s:.5} m/px, {:.1}% {} the median {median:.5} m/px \
                     of the {} measurements on reference level `{}` (the map uses their mean, {mean:.5} m/px)",
                    meas.distance,
                    dev.abs() * 100.0,
                    if dev > 0.0 { "above" } else { "below" },
                    est.len(),
                    level.name
                ),
            )
            .with_help("check this measurement's distance and end points against the floor plan"),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, TestMap};
    use crate::{CoordinateSystem, Measurement, Params, Span};

    fn map(distances: &[f64], cs: CoordinateSystem) -> usize {
        let mut m = TestMap::new();
        m.b.coordinate_system = cs;
        for (i, &d) in distances.iter().enumerate() {
            let y = 10.0 * i as f64;
            let a = m.vertex("", 0.0, y);
            let b = m.vertex("", 200.0, y);
            let level = m.level;
            let h = m.b.measurements.append(
                Measurement {
                    level,
                    start: a,
                    end: b,
                    distance: d,
                    params: Params::default(),
                },
                Span::UNKNOWN,
            );
            m.b.levels[level].measurements.push(h);
        }
        codes_of(&m.b).iter().filter(|c| **c == "W0606").count()
    }

    #[test]
    fn consistent_measurements_are_fine() {
        assert_eq!(map(&[10.0, 10.2, 9.9], CoordinateSystem::ReferenceImage), 0);
        assert_eq!(map(&[10.0], CoordinateSystem::ReferenceImage), 0);
    }

    #[test]
    fn finds_the_odd_one_out() {
        assert_eq!(
            map(&[10.0, 10.0, 10.0, 15.0], CoordinateSystem::ReferenceImage),
            1
        );
        assert_eq!(map(&[10.0, 10.0, 7.0], CoordinateSystem::ReferenceImage), 1);
        // Two that disagree: no way to tell which is wrong.
        assert_eq!(map(&[10.0, 12.0], CoordinateSystem::ReferenceImage), 2);
        // Only reference-image maps derive their scale from measurements.
        assert_eq!(
            map(&[10.0, 10.0, 10.0, 15.0], CoordinateSystem::CartesianMeters),
            0
        );
    }
}
