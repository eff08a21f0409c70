//! Laplacian smoothing that never inverts an element, and mesh quality statistics (R12).
//!
//! [`Smoother`] (triangles) and [`Smoother3`] (tetrahedra) move every free point towards the
//! mean of its neighbours, `X ← X + ω·Σ(X_i − X)/M`, for N passes (Gauss–Seidel, in place). A
//! move is kept only if every element around the point stays positively oriented (exact
//! `orient2d`/`orient3d`) and keeps a fifth of its area or volume (no element is badly
//! degraded); otherwise the move is halved, up to [`MAX_HALVINGS`] times, then skipped. Passes
//! stop early once every move is below a small fraction of the local edge length. In 3D a
//! [`DihedralGuard`] also keeps moves from making slivers.
//!
//! [`QualityReport`] measures a triangle mesh (angles, areas, the area ratio of neighbours),
//! [`QualityReport3`] a tetrahedral one (dihedral angles, slivers, radius–edge ratio, volumes,
//! the volume ratio of neighbours).

mod adjacency;
mod laplace;
mod laplace3;
mod quality;
mod quality3;
mod tet;

pub use laplace::{SmoothError, SmoothStats, Smoother, MAX_HALVINGS};
pub use laplace3::{DihedralGuard, Smoother3, DEFAULT_DIHEDRAL_FLOOR};
pub use quality::QualityReport;
pub use quality3::{
    dihedral_range, QualityReport3, DIHEDRAL_BIN_EDGES, REGULAR_DIHEDRAL, SLIVER_ANGLE,
};
