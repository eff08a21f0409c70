//! Boundary integrity (see `../shared/paper.md` R4–R8).
//!
//! This crate turns a piecewise linear complex ([`Plc2`]: points, boundary segments, holes,
//! region seeds) into a boundary-conforming triangulation: a-posteriori edge checking with
//! mid-point insertion, the a-priori point-per-edge method, Steiner-free recovery by edge flips,
//! and the flood fill that deletes elements outside the domain.

mod plc;

pub use plc::{Plc2, RegionSeed, Segment};
