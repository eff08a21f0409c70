//! [`Plc3`]: the input of 3D mesh generation, a closed surface triangulation with holes and
//! regions.
//!
//! The paper's 3D input (§4.1) is a triangulation of the boundary surfaces: one far-field
//! surface and any number of bodies inside it, each a closed, consistently oriented triangle
//! mesh. Every triangle carries a boundary marker (a TetGen facet marker, a gmsh physical group)
//! and the number of the input facet it came from, so that markers survive to the output and
//! errors name what the user's file names. Polygonal facets (TetGen `.poly`/`.smesh`, `.obj`)
//! are triangulated in their plane before they get here.

/// One surface triangle: three points (0-based indices into [`Plc3::points`]), its boundary
/// marker, and the input facet it belongs to (0-based; several triangles share a facet when a
/// polygonal facet was triangulated).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SurfaceTriangle {
    /// The corners.
    pub v: [u32; 3],
    /// Boundary marker (0 when the input has none).
    pub marker: i32,
    /// The input facet (0-based).
    pub facet: u32,
}

/// A region seed in 3D: every tetrahedron of the connected part of the domain containing
/// `point` (not separated from it by a surface) gets `attribute`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegionSeed3 {
    /// A point strictly inside the region.
    pub point: [f64; 3],
    /// The regional attribute given to the region's tetrahedra.
    pub attribute: f64,
    /// Largest tetrahedron volume allowed in the region (`None`: no limit), as TetGen's `-a`
    /// reads it from a `.poly` or `.smesh` file. Honoured when points are generated
    /// (`delmesh-point-gen`'s `VolumeLimits`).
    pub max_volume: Option<f64>,
}

/// A piecewise linear complex in 3D given by its boundary triangles: the input of 3D boundary
/// recovery.
///
/// Holes are given by seed points; without seeds, closed surfaces nested inside other closed
/// surfaces bound holes by their nesting (inside the far field is domain, inside a body is not,
/// a body inside a hollow body is domain again).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Plc3 {
    /// Point coordinates.
    pub points: Vec<[f64; 3]>,
    /// Boundary marker of each point (empty, or one per point).
    pub point_markers: Vec<i32>,
    /// The surface triangles.
    pub triangles: Vec<SurfaceTriangle>,
    /// Hole seeds: the part of the domain containing each is removed.
    pub holes: Vec<[f64; 3]>,
    /// Region seeds.
    pub regions: Vec<RegionSeed3>,
    /// How the source numbers points and facets (0 or 1), so that error messages name them as
    /// the user's file does.
    pub first_index: u32,
    /// Names of facet markers (gmsh physical names), for the outputs that name their groups;
    /// recovery does not read them.
    pub marker_names: Vec<(i32, String)>,
}

impl Plc3 {
    /// A PLC from points and triangles, all with marker 0, triangle `k` being facet `k`.
    pub fn from_triangles(points: Vec<[f64; 3]>, triangles: &[[u32; 3]]) -> Plc3 {
        Plc3 {
            points,
            triangles: triangles
                .iter()
                .enumerate()
                .map(|(k, &v)| SurfaceTriangle {
                    v,
                    marker: 0,
                    facet: k as u32,
                })
                .collect(),
            ..Default::default()
        }
    }
}

impl Plc3 {
    /// The volume limit of each region index (0: the default region, `1 + k`: the `k`-th
    /// region seed, as tetrahedra are tagged), infinite where there is none.
    pub fn volume_limits(&self) -> Vec<f64> {
        std::iter::once(f64::INFINITY)
            .chain(
                self.regions
                    .iter()
                    .map(|r| r.max_volume.unwrap_or(f64::INFINITY)),
            )
            .collect()
    }

    /// Whether some region has a volume limit.
    pub fn has_volume_limits(&self) -> bool {
        self.regions.iter().any(|r| r.max_volume.is_some())
    }
}
