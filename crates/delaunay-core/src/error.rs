//! Errors of the Delaunay kernel: bad input is reported, never panicked on.

/// Why a triangulation could not be built or a point not inserted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TriangulationError {
    /// A coordinate is NaN or infinite.
    #[error("point {index}: coordinate {axis} is not finite ({value})")]
    NonFinite {
        /// Input index of the point.
        index: usize,
        /// Axis (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// The offending value.
        value: f64,
    },
    /// Fewer distinct points than a single simplex needs.
    #[error("{distinct} distinct point(s) given; a {dim}D triangulation needs at least {needed}")]
    TooFewPoints {
        /// Number of distinct input points.
        distinct: usize,
        /// Space dimension.
        dim: usize,
        /// `dim + 1`.
        needed: usize,
    },
    /// All points lie on one line (2D) or one plane (3D).
    #[error("all {distinct} distinct points are {what}: no {dim}D triangulation exists")]
    Degenerate {
        /// Number of distinct input points.
        distinct: usize,
        /// Space dimension.
        dim: usize,
        /// "collinear" or "coplanar" (or "collinear" for 3D lines).
        what: &'static str,
    },
    /// A non-zero coordinate is so much smaller than the largest one that exact predicates
    /// would underflow.
    #[error(
        "point {index}: coordinate {value:e} is more than 2^142 times smaller than the largest \
         coordinate magnitude {largest:e}; exact predicates cannot handle that range"
    )]
    CoordinateRange {
        /// Input index of the point.
        index: usize,
        /// The offending value.
        value: f64,
        /// The largest coordinate magnitude of the input.
        largest: f64,
    },
    /// More vertices or cells than `u32` indices allow.
    #[error("too many points for 32-bit indices ({0})")]
    TooManyPoints(usize),
}

/// A broken invariant found by `Triangulation::validate` (a bug in delmesh if it ever fires).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ValidationError {
    /// Cell `cell`'s neighbour across facet `facet` does not point back.
    #[error("cell {cell}: neighbour across facet {facet} does not point back")]
    AsymmetricNeighbor {
        /// Cell index.
        cell: u32,
        /// Local facet.
        facet: usize,
    },
    /// Two neighbouring cells do not share the facet they claim to share.
    #[error("cells {cell} and {other} are linked but do not share a facet")]
    FacetMismatch {
        /// Cell index.
        cell: u32,
        /// Neighbour index.
        other: u32,
    },
    /// A finite cell is not positively oriented.
    #[error("cell {cell} is not positively oriented")]
    Orientation {
        /// Cell index.
        cell: u32,
    },
    /// A vertex lies inside the circumsphere of a cell (or beyond a hull facet).
    #[error("vertex {vertex} lies inside the circumsphere of cell {cell}")]
    NotDelaunay {
        /// Cell index.
        cell: u32,
        /// Vertex index.
        vertex: u32,
    },
    /// A cell has more than one ghost vertex, or a bad vertex index.
    #[error("cell {cell} has invalid vertices")]
    BadCell {
        /// Cell index.
        cell: u32,
    },
    /// A vertex's incident cell does not contain it, or a vertex is in no cell.
    #[error("vertex {vertex}: incident cell is wrong or missing")]
    Incidence {
        /// Vertex index.
        vertex: u32,
    },
    /// The counts of vertices, cells and hull facets violate Euler's relation.
    #[error("Euler characteristic check failed: {0}")]
    Euler(String),
}
