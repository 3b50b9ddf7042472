//! Rules of the `lifts` group.

use super::Rule;

pub(super) static RULES: &[&Rule] = &[];
