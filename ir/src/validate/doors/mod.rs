//! Rules about doors (E03xx).

use super::Rule;

mod duplicate_name;
mod empty_name;
mod implausible_width;
mod motion_params;
mod not_crossed;
mod unknown_type;
mod zero_width;

pub(super) static RULES: &[&Rule] = &[
    &empty_name::RULE,
    &duplicate_name::RULE,
    &unknown_type::RULE,
    &zero_width::RULE,
    &implausible_width::RULE,
    &not_crossed::RULE,
    &motion_params::RULE,
];
