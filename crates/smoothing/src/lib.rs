//! Laplacian smoothing that never inverts an element, and mesh quality statistics (R12).
//!
//! [`Smoother`] (triangles) and [`Smoother3`] (tetrahedra) move every free point towards the
//! mean of its neighbours, `X ← X + ω·Σ(X_i − X)/M`, for N passes (Gauss–Seidel, in place). A
//! move is kept only if every element around the point stays positively oriented (exact
//! `orient2d`/`orient3d`) and keeps a fifth of its area or volume (no element is badly
//! degraded); otherwise the move is halved, up to [`MAX_HALVINGS`] times, then skipped. In 2D
//! the smallest angle of the star may not fall below 30° and below what it was, in 3D a
//! [`DihedralGuard`] keeps moves from making slivers (plain Laplacian smoothing sharpens a few
//! elements while improving the mean). Passes stop early once no point moves by more than a
//! small fraction of the length of its edges. In 2D, points whose triangles do not close around
//! them are on the boundary and stay fixed too.
//!
//! [`QualityReport`] measures a triangle mesh (angles, areas, the area ratio of neighbours),
//! [`QualityReport3`] a tetrahedral one (dihedral angles, slivers, radius–edge ratio, volumes,
//! the volume ratio of neighbours).
#![forbid(unsafe_code)]

mod adjacency;
mod laplace;
mod laplace3;
mod quality;
mod quality3;
mod stars;
mod tet;

pub use laplace::{
    SmoothError, SmoothStats, Smoother, DEFAULT_ITERATIONS, DEFAULT_OMEGA, MAX_HALVINGS,
};
pub use laplace3::{DihedralGuard, Smoother3, DEFAULT_DIHEDRAL_FLOOR};
pub use quality::QualityReport;
pub use quality3::{
    dihedral_range, min_dihedral_cosine, QualityReport3, DIHEDRAL_BIN_EDGES, REGULAR_DIHEDRAL,
    SLIVER_ANGLE,
};
pub use stars::Stars;
