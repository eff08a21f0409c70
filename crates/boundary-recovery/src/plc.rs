//! [`Plc2`]: the input of 2D mesh generation, a planar straight-line graph with holes and regions.
//!
//! A piecewise linear complex in 2D is what Triangle's `.poly` file holds: points, segments
//! (boundary edges, each with a boundary marker), hole seeds and region seeds. The segments may
//! form several closed loops (an outer far field, any number of bodies) and open internal lines
//! (a wake). Every input segment ends up in the mesh as a union of edges.

/// One input segment: the points it joins (0-based indices into [`Plc2::points`]) and its
/// boundary marker (carried to every sub-segment the recovery splits it into).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Segment {
    /// First end point.
    pub a: u32,
    /// Second end point.
    pub b: u32,
    /// Boundary marker (0 when the input has none).
    pub marker: i32,
}

/// A region seed: every element of the connected part of the domain containing `point` (not
/// separated from it by a segment) gets `attribute`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegionSeed {
    /// A point strictly inside the region.
    pub point: [f64; 2],
    /// The regional attribute given to the region's elements.
    pub attribute: f64,
    /// Largest element area wanted in the region (`None`: no limit). Kept for Triangle
    /// compatibility; the spacing field controls element size in delmesh.
    pub max_area: Option<f64>,
}

/// A planar straight-line graph: the 2D input of [`crate`]'s boundary recovery.
///
/// Holes are given by seed points; without seeds, closed loops nested inside other closed loops
/// bound holes by their nesting (the far field's inside is domain, a body's inside is not, an
/// island in a lake is domain again).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Plc2 {
    /// Point coordinates.
    pub points: Vec<[f64; 2]>,
    /// Boundary marker of each point (empty, or one per point).
    pub point_markers: Vec<i32>,
    /// Segments between points.
    pub segments: Vec<Segment>,
    /// Hole seeds: the part of the domain containing each is removed.
    pub holes: Vec<[f64; 2]>,
    /// Region seeds.
    pub regions: Vec<RegionSeed>,
    /// How the source numbers points and segments (0 or 1), so that error messages name them
    /// as the user's file does.
    pub first_index: u32,
}
