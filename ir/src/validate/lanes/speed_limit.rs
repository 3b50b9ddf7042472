//! # W0211 speed-limit-out-of-range
//!
//! **What:** a lane's `speed_limit` parameter is negative, not finite, or above 5 m/s.
//! (`0` means "no limit" and is fine.)
//!
//! **Why it matters:** a negative limit is silently dropped from the nav graph (only
//! positive limits are written), so the lane has no limit at all, which is probably not
//! what was meant. A limit above 5 m/s (18 km/h) is far beyond what indoor delivery and
//! cleaning robots drive; it is most likely a value in the wrong unit (km/h, or mm/s) and
//! gives the planner wrong travel times.
//!
//! **Fix:** give the limit in metres per second, between 0 and 5, or remove the parameter.
//!
//! **Example:**
//! ```yaml
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], speed_limit: [3, 12]}]   # W0211: 12 m/s
//! ```

use super::label_lane;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::Diagnostic;

pub(crate) static RULE: Rule = Rule {
    code: "W0211",
    name: "speed-limit-out-of-range",
    summary: "a lane speed limit that is negative or above 5 m/s",
    group: Group::Lanes,
    metric: false,
    check,
};

/// Highest plausible speed limit, metres per second.
const MAX_SPEED: f64 = 5.0;

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, lane) in ctx.b.lanes.iter() {
        let Some(p) = lane.params.param("speed_limit") else {
            continue;
        };
        let Some(v) = p.value.as_f64() else {
            continue; // Not a number: reported when the map is read.
        };
        let what = if v.is_nan() {
            "is not a number, so the lane gets no limit".to_string()
        } else if v < 0.0 {
            format!("is negative ({v} m/s), so the lane gets no limit at all")
        } else if v > MAX_SPEED {
            format!("of {v} m/s is above {MAX_SPEED} m/s; is it in another unit?")
        } else {
            continue;
        };
        out.push(label_lane(
            Diagnostic::warning(RULE.code, p.span, format!("lane `speed_limit` {what}"))
                .with_help("give the limit in metres per second, from 0 (no limit) to 5"),
            ctx,
            h,
        ));
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, param, params, TestMap};
    use crate::ParamValue;

    fn with(value: ParamValue) -> usize {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 1.0, 0.0);
        let l = m.lane(a, b, 0, true);
        m.b.lanes[l].params = params(vec![param("speed_limit", value)]);
        codes_of(&m.b).iter().filter(|c| **c == "W0211").count()
    }

    #[test]
    fn range() {
        assert_eq!(with(ParamValue::Double(0.0)), 0);
        assert_eq!(with(ParamValue::Double(0.5)), 0);
        assert_eq!(with(ParamValue::Int(5)), 0);
        assert_eq!(with(ParamValue::Double(-0.1)), 1);
        assert_eq!(with(ParamValue::Double(5.01)), 1);
        assert_eq!(with(ParamValue::Double(f64::INFINITY)), 1);
        assert_eq!(with(ParamValue::Double(f64::NAN)), 1);
        assert_eq!(with(ParamValue::String("fast".into())), 0);
    }
}
