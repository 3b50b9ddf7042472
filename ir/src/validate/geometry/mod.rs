//! Rules of the `geometry` group.

use super::Rule;

pub(super) static RULES: &[&Rule] = &[];
