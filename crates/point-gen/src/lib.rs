//! Automatic interior point generation (planned; see `../shared/paper.md` R9–R11).
//!
//! This crate will hold `SpacingField` (spacing from the boundary, from a background mesh, or
//! from a solution field for adaptation) and Weatherill's α-criterion centroid insertion, run in
//! passes until no candidate is accepted. Nothing is implemented yet.
