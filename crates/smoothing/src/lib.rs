//! Laplacian smoothing that never inverts an element, and mesh quality statistics (R12).
//!
//! [`Smoother`] moves every free point towards the mean of its neighbours,
//! `X ← X + ω·Σ(X_i − X)/M`, for N passes (Gauss–Seidel, in place). A move is kept only if
//! every triangle around the point stays positively oriented (exact `orient2d`), keeps a fifth
//! of its area and the smallest angle of the star does not fall below 30° and below what it
//! was (no element is badly degraded: plain Laplacian smoothing sharpens a few elements while
//! improving the mean); otherwise the move is halved, up to [`MAX_HALVINGS`] times, then
//! skipped. Passes stop early once no point moves by more than 0.5% of the root mean square
//! length of its edges. Points whose triangles do not close around them are on the boundary and
//! stay fixed too. [`QualityReport`] measures a mesh:
//! angles, areas, the area ratio of neighbours.

mod laplace;
mod quality;

pub use laplace::{
    SmoothError, SmoothStats, Smoother, DEFAULT_ITERATIONS, DEFAULT_OMEGA, MAX_HALVINGS,
};
pub use quality::QualityReport;
