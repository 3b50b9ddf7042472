//! Rules about lifts (E04xx).

use super::Rule;

mod dimensions;
mod door_never_opens;
mod door_off_cabin;
mod door_outside_range;
mod floors_at_one_elevation;
mod initial_floor_not_served;
mod lane_between_lifts;
mod level_without_waypoint;
mod range_inverted;
mod unknown_door;
mod waypoint_on_unserved_level;
mod waypoints_misaligned;

pub(super) static RULES: &[&Rule] = &[
    &dimensions::RULE,
    &door_off_cabin::RULE,
    &unknown_door::RULE,
    &level_without_waypoint::RULE,
    &range_inverted::RULE,
    &door_outside_range::RULE,
    &waypoints_misaligned::RULE,
    &initial_floor_not_served::RULE,
    &lane_between_lifts::RULE,
    &door_never_opens::RULE,
    &waypoint_on_unserved_level::RULE,
    &floors_at_one_elevation::RULE,
];
