//! Chapter 14's checkpoints (level 1) and hard cases (level 2).

use crate::check::catalog::*;

pub const IMAGE_HINT: &str = "";

pub fn checkpoints() -> Vec<Case> {
    vec![]
}

pub fn robustness() -> Vec<Case> {
    vec![]
}
