//! Automatic interior point generation (see `../shared/paper.md` R9–R11).
//!
//! [`SpacingField`] says how far apart points should be anywhere in the domain: interpolated
//! from the boundary spacing, from a background mesh, from a solution field (adaptation), with
//! optional analytic sources. [`PointGeneration`] fills a boundary-conforming mesh with points
//! by Weatherill's α criterion, in passes ([`GenerationReport`]); [`QualityRefinement`] then
//! removes the few skinny elements left where the spacing changes fast, and [`AreaLimits`]
//! makes sure no element is larger than its region's area limit ([`VolumeLimits`] in 3D).
#![forbid(unsafe_code)]

mod area;
mod distance;
mod generate;
mod generate3;
mod memory;
mod refine;
mod refine3;
mod spacing;
mod spacing3;
mod volume;

pub use area::AreaLimits;
pub use generate::{
    GenerationPass, GenerationReport, PointGenError, PointGeneration, RENUMBER_MIN,
};
pub use generate3::{GenerationPass3, GenerationReport3, PointGeneration3};
pub use refine::QualityRefinement;
pub use refine3::QualityRefinement3;
pub use spacing::*;
pub use spacing3::*;
pub use volume::{spacing_for_volume, VolumeLimits};
