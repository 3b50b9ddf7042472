//! Rules about geometry and coordinates (E06xx), and the plane geometry helpers
//! ([`shapes`]) other groups share.

use super::Rule;

mod empty_model_name;
mod hole_outside_floors;
mod inconsistent_measurements;
mod model_outside_floors;
mod self_intersecting;
pub(crate) mod shapes;
mod too_few_vertices;
mod wgs84_lifts;
mod zero_area;
mod zero_length_wall;

pub(super) static RULES: &[&Rule] = &[
    &too_few_vertices::RULE,
    &self_intersecting::RULE,
    &zero_area::RULE,
    &hole_outside_floors::RULE,
    &zero_length_wall::RULE,
    &inconsistent_measurements::RULE,
    &wgs84_lifts::RULE,
    &model_outside_floors::RULE,
    &empty_model_name::RULE,
];
