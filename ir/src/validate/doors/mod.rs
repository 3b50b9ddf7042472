//! Rules of the `doors` group.

use super::Rule;

pub(super) static RULES: &[&Rule] = &[];
