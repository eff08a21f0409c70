//! Errors of the Delaunay kernel: bad input is reported, never panicked on.

use crate::ids::VertexId;

/// Why a triangulation could not be built or a point not inserted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TriangulationError {
    /// The caller stopped the construction (see [`crate::Triangulation::with_progress_until`]).
    #[error("the triangulation was stopped before it was finished")]
    Cancelled,
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
    /// would underflow, or the largest magnitude itself (`value == largest`) is beyond
    /// `2^±1000`.
    #[error("{}", coordinate_range(*.index, *.value, *.largest))]
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

impl TriangulationError {
    /// The error with its point index shifted by `first` (the number of the first point in
    /// the caller's numbering, 1 for a file numbered from 1).
    pub fn numbered_from(self, first: usize) -> Self {
        match self {
            TriangulationError::NonFinite { index, axis, value } => TriangulationError::NonFinite {
                index: index + first,
                axis,
                value,
            },
            TriangulationError::CoordinateRange {
                index,
                value,
                largest,
            } => TriangulationError::CoordinateRange {
                index: index + first,
                value,
                largest,
            },
            other => other,
        }
    }

    /// The error with its coordinates multiplied by `factor` (a problem solved in scaled
    /// units reports them in the caller's).
    pub fn in_units(self, factor: f64) -> Self {
        match self {
            TriangulationError::CoordinateRange {
                index,
                value,
                largest,
            } => TriangulationError::CoordinateRange {
                index,
                value: value * factor,
                largest: largest * factor,
            },
            other => other,
        }
    }
}

/// Why an operation on a [`crate::ConstrainedTriangulation2`] failed. Vertex ids are the
/// triangulation's; map them to input numbers with `Triangulation::input_index`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConstraintError {
    /// A bad point (non-finite, out of range).
    #[error(transparent)]
    Triangulation(TriangulationError),
    /// A point to insert lies outside the convex hull or on a hull edge.
    #[error("point ({}, {}) lies outside the triangulated region or on its hull", point[0], point[1])]
    OutsideHull {
        /// The point (caller's coordinates).
        point: [f64; 2],
    },
    /// The edge `a b` is not in the triangulation (or is not an edge between two vertices).
    #[error("edge {a:?} {b:?} is not in the triangulation")]
    MissingEdge {
        /// First vertex.
        a: VertexId,
        /// Second vertex.
        b: VertexId,
    },
    /// A vertex lies in the interior of the segment `a b`.
    #[error("vertex {vertex:?} lies on segment {a:?} {b:?}")]
    VertexOnSegment {
        /// First end of the segment.
        a: VertexId,
        /// Second end of the segment.
        b: VertexId,
        /// The vertex on it.
        vertex: VertexId,
    },
    /// The segment `a b` crosses the constrained edge `c d`.
    #[error("segment {a:?} {b:?} crosses constrained edge {c:?} {d:?}")]
    CrossesConstraint {
        /// First end of the segment.
        a: VertexId,
        /// Second end of the segment.
        b: VertexId,
        /// First end of the constrained edge.
        c: VertexId,
        /// Second end of the constrained edge.
        d: VertexId,
    },
    /// Flipping made no progress inserting segment `a b` (a bug in delmesh if it ever fires).
    #[error("segment {a:?} {b:?}: edge flipping made no progress")]
    Stalled {
        /// First end of the segment.
        a: VertexId,
        /// Second end of the segment.
        b: VertexId,
    },
    /// Moving `vertex` would invert a cell, or it is a hull vertex.
    #[error("moving vertex {vertex:?} would invert a cell (or it is on the hull)")]
    InvalidMove {
        /// The vertex.
        vertex: VertexId,
    },
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
    #[error("vertex {vertex} lies inside the circumcircle (circumsphere in 3D) of cell {cell}")]
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

/// The message of [`TriangulationError::CoordinateRange`].
fn coordinate_range(index: usize, value: f64, largest: f64) -> String {
    if value.abs() == largest {
        format!(
            "point {index}: coordinate magnitude {value:e} is outside the range 2^-1000 to \
             2^1000 that exact predicates handle"
        )
    } else {
        format!(
            "point {index}: coordinate {value:e} is more than 2^142 times smaller than the \
             largest coordinate magnitude {largest:e}; exact predicates cannot handle that range"
        )
    }
}
