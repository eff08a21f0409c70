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
    /// Largest element area allowed in the region (`None`: no limit), as Triangle's `-a`
    /// reads it from a `.poly` file. Honoured when points are generated (see
    /// [`crate::BoundaryRecovery::with_area_limits`] and `delmesh-point-gen`'s `AreaLimits`).
    pub max_area: Option<f64>,
}

/// The spacing that fills a region with elements no larger than `area`: half the side of the
/// equilateral triangle of that area. Points spaced by the α test make elements of varied
/// size: on two unit squares limited to 0.001 and 0.01, generation at the full side left so
/// many elements too large that 663 centroids went in after its 232 points; at half the side,
/// 10 centroids for 2,370 elements.
pub fn spacing_for_area(area: f64) -> f64 {
    0.5 * (4.0 * area / 3f64.sqrt()).sqrt()
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

impl Plc2 {
    /// The area limit of each region index (0: the default region, `1 + k`: the `k`-th region
    /// seed, as elements are tagged), infinite where there is none.
    pub fn area_limits(&self) -> Vec<f64> {
        std::iter::once(f64::INFINITY)
            .chain(
                self.regions
                    .iter()
                    .map(|r| r.max_area.unwrap_or(f64::INFINITY)),
            )
            .collect()
    }

    /// Whether some region has an area limit.
    pub fn has_area_limits(&self) -> bool {
        self.regions.iter().any(|r| r.max_area.is_some())
    }
}
