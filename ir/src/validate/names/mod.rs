//! Rules of the `names` group.

use super::Rule;

pub(super) static RULES: &[&Rule] = &[];
