//! # E0210 invalid-orientation
//!
//! **What:** a lane's `orientation` parameter is something other than empty, `forward` or
//! `backward` (or is not a string at all).
//!
//! **Why it matters:** the nav graph passes the value on as `orientation_constraint`, and
//! the fleet adapter refuses to load a graph whose constraint is not `forward` or
//! `backward`, so the whole fleet fails to start. (The reference generator copies the value
//! through unchecked and writes `''` for the reverse of a two-way lane, which is rejected
//! too.) A value of another type is ignored by mapc, which is not what its author meant.
//!
//! **Fix:** use `[1, forward]` (robots must drive forward along the lane), `[1, backward]`
//! (reverse along it), or remove the parameter (any orientation).
//!
//! **Example:**
//! ```yaml
//! lanes:
//!   - [0, 1, {graph_idx: [2, 0], orientation: [1, sideways]}]   # E0210
//! ```

use super::label_lane;
use crate::lints::Group;
use crate::validate::{Context, Rule};
use crate::{Diagnostic, Orientation, ParamValue};

pub(crate) static RULE: Rule = Rule {
    code: "E0210",
    name: "invalid-orientation",
    summary: "a lane orientation other than '', forward or backward",
    group: Group::Lanes,
    metric: false,
    check,
};

fn check(ctx: &Context, out: &mut Vec<Diagnostic>) {
    for (h, lane) in ctx.b.lanes.iter() {
        let Some(p) = lane.params.param("orientation") else {
            continue;
        };
        let found = match (&lane.orientation, &p.value) {
            (Orientation::Other(s), _) => format!("`{s}`"),
            (_, ParamValue::String(_)) => continue,
            (_, v) => format!("a {} instead of a string", v.type_name()),
        };
        out.push(label_lane(
            Diagnostic::error(
                RULE.code,
                p.span,
                format!(
                    "lane orientation must be empty, `forward` or `backward`, found {found}; \
                     the fleet adapter rejects the graph"
                ),
            )
            .with_help(
                "write `orientation: [1, forward]` or `[1, backward]`, or remove the parameter",
            ),
            ctx,
            h,
        ));
    }
}

#[cfg(test)]
mod tests {
    use crate::validate::tests::{codes_of, param, params, TestMap};
    use crate::{Orientation, ParamValue};

    fn with(value: ParamValue) -> usize {
        let mut m = TestMap::new();
        let a = m.vertex("a", 0.0, 0.0);
        let b = m.vertex("b", 1.0, 0.0);
        let l = m.lane(a, b, 0, true);
        if let ParamValue::String(s) = &value {
            m.b.lanes[l].orientation = match s.as_str() {
                "" => Orientation::Any,
                "forward" => Orientation::Forward,
                "backward" => Orientation::Backward,
                other => Orientation::Other(other.into()),
            };
        }
        m.b.lanes[l].params = params(vec![param("orientation", value)]);
        codes_of(&m.b).iter().filter(|c| **c == "E0210").count()
    }

    #[test]
    fn accepted_values() {
        for s in ["", "forward", "backward"] {
            assert_eq!(with(ParamValue::String(s.into())), 0, "{s}");
        }
    }

    #[test]
    fn rejected_values() {
        assert_eq!(with(ParamValue::String("sideways".into())), 1);
        assert_eq!(with(ParamValue::String("Forward".into())), 1);
        assert_eq!(with(ParamValue::Int(1)), 1);
    }
}
