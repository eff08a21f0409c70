//! Errors of boundary recovery. Points and segments are named in the input's numbering
//! ([`crate::Plc2::first_index`]), so messages match the user's file.

use delmesh_delaunay_core::TriangulationError;

/// Why a [`crate::Plc2`] could not be meshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RecoveryError {
    /// The caller stopped the recovery (see `BoundaryRecovery3::cancel_on`).
    #[error("boundary recovery was stopped before it was finished")]
    Cancelled,
    /// A coordinate is NaN or infinite.
    #[error("point {point}: coordinate is not finite")]
    NonFinite {
        /// The point.
        point: u64,
    },
    /// A segment names a point that does not exist.
    #[error("segment {segment}: point {point} does not exist ({n_points} points)")]
    BadEndpoint {
        /// The segment.
        segment: u64,
        /// The missing point's number.
        point: u64,
        /// How many points the input has.
        n_points: usize,
    },
    /// A segment joins a point to itself (or to a duplicate of it).
    #[error("segment {segment} has zero length (points {a} and {b} coincide)")]
    ZeroLength {
        /// The segment.
        segment: u64,
        /// First end.
        a: u64,
        /// Second end.
        b: u64,
    },
    /// The same segment is given twice, or two collinear segments overlap, with different
    /// boundary markers (which one the shared edges carry would be a guess).
    #[error(
        "segments {first} and {second} overlap with different markers ({first_marker} and {second_marker}): which one the shared edges carry would be a guess"
    )]
    ConflictingMarkers {
        /// The first occurrence.
        first: u64,
        /// The repeat.
        second: u64,
        /// The first's marker.
        first_marker: i32,
        /// The repeat's marker.
        second_marker: i32,
    },
    /// Two segments cross or overlap.
    #[error("segments {first} and {second} intersect (they may only meet at shared end points)")]
    Crossing {
        /// One segment.
        first: u64,
        /// The other.
        second: u64,
    },
    /// A hole or region seed is not finite.
    #[error("{what} {index}: seed coordinates are not finite")]
    BadSeed {
        /// "hole" or "region".
        what: &'static str,
        /// Its number.
        index: u64,
    },
    /// A region's area limit is not a positive number.
    #[error("region {index}: the maximum area must be positive (got {value:?})")]
    BadAreaLimit {
        /// The region's number.
        index: u64,
        /// The value.
        value: f64,
    },
    /// A region's area limit asks for more elements than the mesh's 32-bit indices hold.
    #[error(
        "region {index}: a maximum area of {max_area:e} asks for about {elements:.1e} elements in the region's area of {area:e}, more than delmesh can index (2^30)"
    )]
    AreaLimitTooSmall {
        /// The region's number.
        index: u64,
        /// Its limit.
        max_area: f64,
        /// Its area.
        area: f64,
        /// Elements it would need at least.
        elements: f64,
    },
    /// A hole or region seed lies on a segment (or at a vertex) between two parts of the domain,
    /// so it does not say which part it means.
    #[error(
        "{what} {index} at ({}, {}) lies on a segment between two parts of the domain (or \
         between the domain and the outside); move it inside the part it is meant for",
        point[0],
        point[1]
    )]
    SeedOnBoundary {
        /// "hole" or "region".
        what: &'static str,
        /// Its number.
        index: u64,
        /// Its coordinates.
        point: [f64; 2],
    },
    /// A hole or region seed lies on the surface (a face, an edge or a vertex) between two
    /// parts of the domain, or between the domain and the outside, so it does not say which
    /// part it means.
    #[error(
        "{what} {index} at ({}, {}, {}) lies on the surface between two parts of the domain \
         (or between the domain and the outside); move it inside the part it is meant for",
        point[0],
        point[1],
        point[2]
    )]
    SeedOnSurface {
        /// "hole" or "region".
        what: &'static str,
        /// Its number.
        index: u64,
        /// Its coordinates.
        point: [f64; 3],
    },
    /// The points cannot be triangulated (too few, all collinear, bad range).
    #[error(transparent)]
    Triangulation(#[from] TriangulationError),
    /// Splitting a segment reached the resolution of double precision at its coordinates: a
    /// split point rounds onto a vertex, or the pieces are shorter than 2^-44 of the input's
    /// extent (a domain a few thousand ulps across, far from the origin).
    #[error(
        "segment {segment} could not be recovered: after {splits} splits its pieces are too short \
         for double precision at its coordinates (translate the input nearer the origin, or \
         recover segments by flips, which adds no points)"
    )]
    BeyondPrecision {
        /// The input segment.
        segment: u64,
        /// Splits made on it.
        splits: usize,
    },
    /// Recovery of a segment did not finish within the split budget (a bug in delmesh, or an
    /// input beyond double precision, such as segments closer than 1e-300).
    #[error("segment {segment} could not be recovered after {splits} splits")]
    NotRecovered {
        /// The input segment.
        segment: u64,
        /// Splits made on it.
        splits: usize,
    },
    /// A surface triangle names a point that does not exist.
    #[error("facet {facet}: point {point} does not exist ({n_points} points)")]
    BadFacetPoint {
        /// The facet.
        facet: u64,
        /// The missing point's number.
        point: u64,
        /// How many points the input has.
        n_points: usize,
    },
    /// A surface triangle has two equal corners (or corners at the same coordinates).
    #[error("facet {facet} is degenerate: two of its corners coincide")]
    DegenerateFacet {
        /// The facet.
        facet: u64,
    },
    /// 3D boundary recovery did not finish within its bound of added points, or a
    /// sub-segment became too short to split in double precision.
    #[error(
        "the surface could not be recovered ({added} points added); facets that resisted: {}",
        list(facets)
    )]
    SurfaceNotRecovered {
        /// The facets still missing sub-faces or sub-segments (input numbering).
        facets: Vec<u64>,
        /// Points added before giving up.
        added: usize,
    },
    /// The 3D surface fails an input check (open, non-manifold, self-intersecting, ...).
    #[error(transparent)]
    Surface(#[from] crate::surface::SurfaceError),
    /// After removing the exterior and the holes nothing is left.
    #[error(
        "no element is inside the domain: every part of it is outside the boundary (in 2D the \
         segments must form closed loops around it) or in a hole (check the hole seeds)"
    )]
    EmptyDomain,
}

/// Up to ten numbers, then how many more.
fn list(items: &[u64]) -> String {
    let mut s: Vec<String> = items.iter().take(10).map(u64::to_string).collect();
    if items.len() > 10 {
        s.push(format!("and {} more", items.len() - 10));
    }
    s.join(", ")
}
