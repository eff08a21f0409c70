//! Boundary integrity (planned; see `../shared/paper.md` R4–R8).
//!
//! This crate will turn a piecewise linear complex (`Plc`: points, boundary segments or surface
//! facets, holes, region seeds) into a boundary-conforming triangulation: a-posteriori edge and
//! face checking with mid-point / centroid insertion, the a-priori point-per-edge/face method,
//! and the flood fill that deletes elements outside the domain. It records the recovery history
//! in the shape of the paper's Table 2. Nothing is implemented yet.
