//! Boundary integrity (see `../shared/paper.md` R4–R9).
//!
//! This crate turns a piecewise linear complex ([`Plc2`]: points, boundary segments, holes,
//! region seeds) into a boundary-conforming triangulation ([`Mesh2`]): a-posteriori edge
//! checking with mid-point insertion, the a-priori point-per-edge method, Steiner-free recovery
//! by edge flips ([`RecoveryMethod`]), and the flood fill that deletes elements outside the
//! domain. The passes are recorded ([`RecoveryHistory`], the 2D analogue of the paper's
//! Table 2).
//!
//! ```
//! use delmesh_boundary_recovery::{BoundaryRecovery, Plc2, RecoveryMethod, Segment};
//! // A unit square with a square hole.
//! let points = vec![
//!     [0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0],
//!     [1.0, 1.0], [1.0, 3.0], [3.0, 3.0], [3.0, 1.0],
//! ];
//! let segments = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4)]
//!     .map(|(a, b)| Segment { a, b, marker: 1 })
//!     .to_vec();
//! let plc = Plc2 { points, segments, ..Default::default() };
//! let mesh = BoundaryRecovery::new(RecoveryMethod::Stitch).run(&plc)?;
//! assert_eq!(mesh.area(), 12.0);
//! # Ok::<(), delmesh_boundary_recovery::RecoveryError>(())
//! ```
#![forbid(unsafe_code)]

mod apriori3;
mod check;
mod classify;
mod classify3;
mod error;
mod mesh;
mod mesh3;
mod planar;
mod plc;
mod plc3;
mod recovery;
mod recovery3;
mod surface;
mod union_find;

pub use classify::{SeedName, OUTSIDE};
pub use error::RecoveryError;
pub use mesh::MeshArrays;
pub use mesh3::{tet_volume, FaceIndex, MeshArrays3};
pub use plc::{spacing_for_area, Plc2, RegionSeed, Segment};
pub use plc3::{Plc3, RegionSeed3, SurfaceTriangle};
pub use recovery::{
    BoundaryEdge, BoundaryRecovery, Mesh2, RecoveryHistory, RecoveryMethod, RecoveryPass,
    SegmentSplits, SplitFn,
};
pub use recovery3::{
    costly_bound, BoundaryFace, BoundaryRecovery3, Mesh3, RecoveryHistory3, RecoveryMethod3,
    RecoveryStep,
};
pub use surface::{
    check_surface, first_occurrences, CheckedSurface, EdgeName, Junction, Listed, PointLocation,
    PointOnTriangle, PolygonFacet, SurfaceComponent, SurfaceEdge, SurfaceError, TJunctions,
    TriangleName, TrianglePair,
};
