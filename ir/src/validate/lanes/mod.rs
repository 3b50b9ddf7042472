//! Rules about lanes and the navigation graphs they form.

use super::Rule;

mod crosses_wall;
mod dead_end;
mod demo_mock;
mod demo_mock_lift_only;
mod disconnected;
mod duplicate;
mod geom;
mod grazes_door;
mod near_waypoints;
mod orientation;
mod self_loop;
mod several_doors;
mod speed_limit;
mod zero_length;

pub(super) static RULES: &[&Rule] = &[
    &self_loop::RULE,
    &zero_length::RULE,
    &duplicate::RULE,
    &crosses_wall::RULE,
    &grazes_door::RULE,
    &several_doors::RULE,
    &near_waypoints::RULE,
    &disconnected::RULE,
    &dead_end::RULE,
    &orientation::RULE,
    &speed_limit::RULE,
    &demo_mock::RULE,
    &demo_mock_lift_only::RULE,
];

/// Adds a "the lane" label, unless the diagnostic already points into the lane's first
/// line (lanes are usually written on one line: a second underline there only clutters).
fn label_lane(
    d: crate::Diagnostic,
    ctx: &super::Context,
    lane: crate::Handle<crate::Lane>,
) -> crate::Diagnostic {
    let span = ctx.lane_span(lane);
    if span.file == d.span.file && span.line == d.span.line {
        d
    } else {
        d.with_label(span, "the lane")
    }
}
