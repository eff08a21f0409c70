//! delmesh: Delaunay mesh generation for computational fluid dynamics, as a library.
//!
//! This facade is what applications (and the `delmesh` command-line tool built from this crate)
//! use: it re-exports the kernel crates under short names ([`core`], [`io`]) together with their
//! main types, and adds the glue between them that every front end would otherwise repeat:
//! [`delaunay::triangulate_file`] reads a point file, builds the 2D or 3D triangulation its
//! dimension asks for and times the construction; [`delaunay::DelaunayRun`] writes the result
//! and its Voronoi dual in the formats of [`io`]. [`demos`] reproduces figures of the paper.
//! Errors are one enum, [`Error`], whose messages name the file concerned.
//!
//! ```no_run
//! use std::path::Path;
//!
//! let run = delmesh::delaunay::triangulate_file(Path::new("points.node"), false)?;
//! println!("{} cells in {:.6} s", run.num_cells(), run.build_seconds);
//! run.write(Path::new("mesh.vtu"))?;
//! run.write_voronoi(Path::new("cells.vtu"))?;
//! # Ok::<(), delmesh::Error>(())
//! ```
#![forbid(unsafe_code)]

pub use delmesh_boundary_recovery as recovery;
pub use delmesh_delaunay_core as core;
pub use delmesh_io as io;
pub use delmesh_point_gen as point_gen;
pub use delmesh_predicates as predicates;
pub use delmesh_smoothing as smoothing;

pub use delmesh_delaunay_core::{
    Triangulation, Triangulation2, Triangulation3, TriangulationError, VoronoiDiagram, D2, D3,
};
pub use delmesh_io::{IoError, PointSet};

pub mod delaunay;
pub mod demos;
mod error;
pub mod geometry;
pub mod geometry3;
pub mod mesh2d;
pub mod mesh3d;
mod sources;
mod surface_split;
pub mod units;

pub use error::Error;
