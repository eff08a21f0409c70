//! Automatic interior point generation (see `../shared/paper.md` R9–R11).
//!
//! [`SpacingField`] says how far apart points should be anywhere in the domain: interpolated
//! from the boundary spacing, from a background mesh, from a solution field (adaptation), with
//! optional analytic sources.

mod spacing;

pub use spacing::*;
