//! Laplacian smoothing and mesh quality statistics (planned; see `../shared/paper.md` R12).
//!
//! This crate will hold the `Smoother` (relaxation factor ω, N passes, boundary points fixed)
//! that never inverts an element, and the quality measures reported by the CLI. Nothing is
//! implemented yet.
