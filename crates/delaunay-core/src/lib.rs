//! Delaunay triangulations in 2D and 3D by Bowyer–Watson insertion, and their Voronoi dual.
//!
//! This crate is delmesh's kernel (`../shared/paper.md` R1–R3, R13–R16): [`Triangulation`]
//! holds the paper's data structure (each simplex = its forming points + its neighbours) in flat
//! arrays, builds it by incremental insertion in a spatially sorted order, and answers the
//! queries the mesh-generation stages need (is this edge / face present? which cells surround a
//! vertex?). [`VoronoiDiagram`] is the dual: circumcentres, forming points and neighbours (the
//! paper's Table 1) and the Voronoi cells of the points. The crate never does I/O.
//!
//! ```
//! use delmesh_delaunay_core::{Triangulation2, D2};
//! let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
//! let tri = Triangulation2::new(&pts).unwrap();
//! assert_eq!(tri.num_cells(), 2); // co-circular: the perturbation picks one diagonal
//! tri.validate().unwrap();
//! ```
// One audited exception, the cache hint of `prefetch` (see there); nothing else may use unsafe.
#![deny(unsafe_code)]

mod constrained;
mod constrained3;
mod dim;
mod error;
mod flip3;
mod flip_in3;
mod ids;
mod improve3;
mod prefetch;
mod renumber;
mod sort;
mod star;
mod triangulation;
mod validate;
mod voronoi;

pub use constrained::ConstrainedTriangulation2;
pub use constrained3::{find_face_in, ConstrainedTriangulation3};
pub use dim::{Dim, D2, D3};
pub use error::{ConstraintError, TriangulationError, ValidationError};
pub use flip3::Flips3;
pub use flip_in3::{FlipIn, FlipMark};
pub use ids::{CellId, FacetRef, VertexId};
pub use improve3::Improvement3;
pub use renumber::Renumbering;
pub use star::StarSearch;
pub use triangulation::{Insertion, Location, Triangulation};
pub use voronoi::{VoronoiCell2, VoronoiDiagram, VoronoiFace3, VoronoiFaces3};

/// An order in which to insert a batch of `points` (indices into it) into an existing
/// triangulation: biased randomised rounds (the first of about 64 points, whatever the batch's
/// size), each along a Hilbert curve. The random rounds matter when the triangulation's cells are large next to
/// the batch's spacing (points just inside a finely divided circle: in boundary order every
/// insertion would rebuild the cells across the whole circle); the Hilbert order keeps walks
/// short. Deterministic for a given input.
pub fn insertion_order<D: Dim>(points: &[D::Point]) -> Vec<u32> {
    sort::brio_order_from::<D>(points, sort::SMALL_FIRST_ROUND)
}

/// A 2D Delaunay triangulation.
pub type Triangulation2 = Triangulation<D2>;
/// A 3D Delaunay tetrahedralisation.
pub type Triangulation3 = Triangulation<D3>;
