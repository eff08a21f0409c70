//! [`SurfaceError`]: why a surface triangulation (or a polygonal facet) cannot be meshed.
//!
//! Every variant names what the user's file names: points and facets in the input's numbering
//! ([`crate::Plc3::first_index`] added), each triangle by its facet and its three corners as the
//! input gives them. A check that finds several offenders lists the first
//! [`Listed::MAX_SHOWN`] of them (in input order) and says how many there are in all, so one run
//! shows the extent of the damage without flooding the terminal.

use delmesh_delaunay_core::ConstraintError;
use std::fmt;

/// The first few of a list of offenders, and how many there are in all.
#[derive(Clone, Debug, PartialEq)]
pub struct Listed<T> {
    /// The first offenders (at most [`Listed::MAX_SHOWN`]), in input order.
    pub items: Vec<T>,
    /// How many offenders there are in all (at least `items.len()`).
    pub total: usize,
}

impl<T> Listed<T> {
    /// How many offenders a message shows.
    pub const MAX_SHOWN: usize = 10;

    /// Keeps the first [`Listed::MAX_SHOWN`] of `all`.
    pub(crate) fn of(mut all: Vec<T>) -> Listed<T> {
        let total = all.len();
        all.truncate(Self::MAX_SHOWN);
        Listed { items: all, total }
    }
}

impl<T: fmt::Display> fmt::Display for Listed<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, item) in self.items.iter().enumerate() {
            if k > 0 {
                f.write_str("; ")?;
            }
            write!(f, "{item}")?;
        }
        if self.total > self.items.len() {
            write!(f, "; … ({} in all)", self.total)?;
        }
        Ok(())
    }
}

/// A triangle as the user's file names it: its facet and its corners (input numbering).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriangleName {
    /// The input facet.
    pub facet: u64,
    /// The corners, as the input gives them.
    pub points: [u64; 3],
}

impl fmt::Display for TriangleName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b, c] = self.points;
        write!(f, "facet {} (points {a}, {b}, {c})", self.facet)
    }
}

/// Two triangles (a duplicated pair, an intersecting pair).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TrianglePair {
    /// The first in input order.
    pub first: TriangleName,
    /// The second.
    pub second: TriangleName,
}

impl fmt::Display for TrianglePair {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} and {}", self.first, self.second)
    }
}

/// A surface edge and the facets of the triangles using it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EdgeName {
    /// The end points (input numbering of the first occurrence of each merged point), in the
    /// direction the first listed triangle traverses the edge.
    pub points: [u64; 2],
    /// The facet of each triangle using the edge, in input order of the triangles.
    pub facets: Vec<u64>,
}

impl fmt::Display for EdgeName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b] = self.points;
        write!(f, "edge {a}-{b} (")?;
        write_facets(f, &self.facets)?;
        f.write_str(")")
    }
}

/// Points lying inside open edges (see [`SurfaceError::OpenEdges`]): each point (input
/// numbering) and the edge's end points.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TJunctions(pub Vec<(u64, [u64; 2])>);

impl fmt::Display for TJunctions {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, (p, [a, b])) in self.0.iter().enumerate() {
            let sep = if k == 0 { "; " } else { ", " };
            write!(f, "{sep}point {p} lies inside edge {a}-{b}")?;
        }
        if !self.0.is_empty() {
            f.write_str(
                " (a T-junction: the triangles on one side use the point, the other's do not; \
                 split that triangle at the point)",
            )?;
        }
        Ok(())
    }
}

/// A point lying on a triangle it is not a corner of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PointOnTriangle {
    /// The point (input numbering).
    pub point: u64,
    /// The triangle.
    pub triangle: TriangleName,
}

impl fmt::Display for PointOnTriangle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "point {} on {}", self.point, self.triangle)
    }
}

fn write_facets(f: &mut fmt::Formatter<'_>, facets: &[u64]) -> fmt::Result {
    f.write_str(if facets.len() == 1 {
        "facet "
    } else {
        "facets "
    })?;
    for (k, x) in facets.iter().enumerate() {
        if k > 0 {
            f.write_str(", ")?;
        }
        write!(f, "{x}")?;
    }
    Ok(())
}

/// Why a surface triangulation ([`crate::Plc3`]) or a polygonal facet cannot be meshed.
///
/// Points and facets are named in the input's numbering (`first_index` added).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SurfaceError {
    /// A coordinate is NaN or infinite.
    #[error("point {point}: coordinate is not finite")]
    NonFinite {
        /// The point.
        point: u64,
    },
    /// A non-zero coordinate is so much smaller than the largest one that exact predicates
    /// would underflow.
    #[error(
        "point {point}: coordinate {value:e} is more than 2^142 times smaller than the largest \
         coordinate magnitude {largest:e}; exact predicates cannot handle that range"
    )]
    CoordinateRange {
        /// The point.
        point: u64,
        /// The offending coordinate.
        value: f64,
        /// The largest coordinate magnitude of the input.
        largest: f64,
    },
    /// A hole or region seed is not finite.
    #[error("{what} {index}: seed coordinates are not finite")]
    BadSeed {
        /// "hole" or "region".
        what: &'static str,
        /// Its number.
        index: u64,
    },
    /// `point_markers` is neither empty nor one per point.
    #[error("{markers} point markers given for {points} points (give none or one per point)")]
    PointMarkerCount {
        /// Markers given.
        markers: usize,
        /// Points given.
        points: usize,
    },
    /// A triangle or polygon names a point that does not exist.
    #[error("facet {facet}: point {point} does not exist ({n_points} points)")]
    BadIndex {
        /// The facet.
        facet: u64,
        /// The missing point's number.
        point: u64,
        /// How many points the input has.
        n_points: usize,
    },
    /// Triangles with a corner repeated (after merging duplicate points).
    #[error("degenerate triangles, a corner repeated (duplicate points merged): {triangles}")]
    RepeatedCorner {
        /// The triangles.
        triangles: Listed<TriangleName>,
    },
    /// Triangles whose three corners lie exactly on one line.
    #[error("degenerate triangles, three collinear corners: {triangles}")]
    Collinear {
        /// The triangles.
        triangles: Listed<TriangleName>,
    },
    /// Triangles with the same three corners as an earlier one.
    #[error(
        "duplicated triangles (same three corners; a closed surface has each triangle once, and \
         the copies may carry different markers): {pairs}"
    )]
    DuplicateTriangles {
        /// Each duplicate with the first triangle it repeats.
        pairs: Listed<TrianglePair>,
    },
    /// No triangle at all: nothing encloses a domain.
    #[error(
        "the surface has no triangles ({points} points): nothing encloses a domain (files of \
         second-order triangles or of quadrilaterals only give none)"
    )]
    NoTriangles {
        /// How many points there are.
        points: usize,
    },
    /// Edges used by one triangle only: the surface has a hole.
    #[error("the surface is not closed: edges used by only one triangle: {edges}{t_junctions}")]
    OpenEdges {
        /// The edges and their facet.
        edges: Listed<EdgeName>,
        /// Points lying inside one of the listed edges: T-junctions, where the triangles on
        /// the other side use the point and this edge's triangle does not.
        t_junctions: TJunctions,
    },
    /// A one-sided surface: however its triangles are reversed, two sharing an edge traverse
    /// it in the same direction (a closed one-sided surface also intersects itself).
    #[error(
        "inconsistent orientation: the surface is one-sided, no choice of triangle \
         orientations makes the two triangles at every edge traverse it in opposite \
         directions; as given, both traverse each of these edges in the same direction: {edges}"
    )]
    InconsistentOrientation {
        /// The edges (in the direction both traverse them) and their two facets.
        edges: Listed<EdgeName>,
    },
    /// Points lying on a triangle they are not a corner of (on its interior or an edge).
    #[error("points lie on triangles they are not a corner of: {hits}")]
    PointOnTriangle {
        /// The points and triangles.
        hits: Listed<PointOnTriangle>,
    },
    /// Pairs of triangles that intersect other than in their shared corners or edge.
    #[error("the surface intersects itself: {pairs}{}", in_one_plane(*coplanar))]
    SelfIntersection {
        /// The intersecting pairs.
        pairs: Listed<TrianglePair>,
        /// How many of them lie in one plane (overlapping).
        coplanar: usize,
    },
    /// A polygonal facet has fewer than three distinct points, or all its points are collinear.
    #[error("facet {facet} is degenerate: {why}")]
    FacetDegenerate {
        /// The facet.
        facet: u64,
        /// What is wrong.
        why: &'static str,
    },
    /// A polygonal facet's points do not lie in one plane.
    #[error(
        "facet {facet} is not planar: point {point} is off the plane of points {}, {}, {}",
        plane[0], plane[1], plane[2]
    )]
    FacetNotPlanar {
        /// The facet.
        facet: u64,
        /// A point off the plane.
        point: u64,
        /// Three points spanning the plane.
        plane: [u64; 3],
    },
    /// A polygon edge joins a point to itself (or to a duplicate of it).
    #[error("facet {facet}: polygon edge {a}-{b} has zero length")]
    FacetZeroEdge {
        /// The facet.
        facet: u64,
        /// First end.
        a: u64,
        /// Second end.
        b: u64,
    },
    /// A point of a facet lies inside one of its polygon edges.
    #[error("facet {facet}: point {point} lies inside polygon edge {a}-{b}")]
    FacetPointOnEdge {
        /// The facet.
        facet: u64,
        /// The point.
        point: u64,
        /// First end of the edge.
        a: u64,
        /// Second end of the edge.
        b: u64,
    },
    /// Two polygon edges of a facet cross.
    #[error("facet {facet}: polygon edges {}-{} and {}-{} cross", first[0], first[1], second[0], second[1])]
    FacetEdgesCross {
        /// One edge.
        first: [u64; 2],
        /// The edge it crosses.
        second: [u64; 2],
        /// The facet.
        facet: u64,
    },
    /// A facet hole point lies on one of the facet's polygon edges or points.
    #[error("facet {facet}: hole point {hole} lies on a polygon edge or point of the facet")]
    FacetHoleOnBoundary {
        /// The facet.
        facet: u64,
        /// The hole point's number within the facet.
        hole: u64,
    },
    /// Nothing of a facet is left after removing its holes (or its polygons enclose nothing).
    #[error(
        "facet {facet} encloses no area (its polygons must form closed loops; check its holes)"
    )]
    FacetEmpty {
        /// The facet.
        facet: u64,
    },
    /// A facet hole point has a coordinate that is not finite.
    #[error("facet {facet}: hole point {hole} is not finite")]
    FacetBadHole {
        /// The facet.
        facet: u64,
        /// The hole point's number within the facet.
        hole: u64,
    },
    /// The 2D triangulation of a facet failed (a bug in delmesh if it ever fires).
    #[error("facet {facet}: {source}")]
    FacetTriangulation {
        /// The facet.
        facet: u64,
        /// What the kernel said.
        source: ConstraintError,
    },
}

/// The hint for self-intersecting pairs of which `n` lie in one plane.
fn in_one_plane(n: usize) -> String {
    if n == 0 {
        return String::new();
    }
    format!(
        " ({n} of these pairs overlap in one plane: a face two bodies share, given by each \
         and cut along different diagonals? give it once)"
    )
}
