//! Rules about lanes and the navigation graphs they form.

use super::Rule;

mod self_loop;

pub(super) static RULES: &[&Rule] = &[&self_loop::RULE];
