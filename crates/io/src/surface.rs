//! [`SurfaceFile`], the plain-data 3D boundary description every surface reader returns, and
//! [`read_surface`], which picks the reader from the file extension.
//!
//! 3D mesh generation starts from the surfaces that bound the flow domain: a far field and the
//! bodies inside it, each surface patch carrying a boundary marker (wall, inlet, symmetry...)
//! that must reach the solver's boundary conditions. The formats that carry such surfaces
//! differ widely (TetGen PLCs with polygonal facets and holes, triangle soups in STL, CAD
//! exports in OBJ, gmsh and Medit meshes), so every reader produces the same flat value:
//! points, facets (one or more polygons each, with the marker and the source line, so later
//! stages can say *which line of the user's file* a bad facet came from), hole and region
//! seeds, and, for the formats that can hold a volume mesh, its tetrahedra. Turning polygonal
//! facets into triangles is the job of the mesh generator, not of this crate.

use std::path::Path;

use crate::IoError;

/// One input facet: a planar patch of the boundary.
///
/// Most formats give one polygon per facet (a triangle, a quadrilateral, an OFF/OBJ polygon).
/// A TetGen `.poly` facet may have several polygons (an outer boundary, inner loops, and
/// segments or isolated points that must appear in the mesh of the facet) and hole points
/// that remove the parts of the facet containing them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceFacet {
    /// The polygons, each a list of 0-based point indices in order around it. Polygons of
    /// TetGen files may have 1 or 2 corners (a point or a segment in the facet); the other
    /// formats give at least 3.
    pub polygons: Vec<Vec<u32>>,
    /// Hole points in the plane of the facet (TetGen `.poly` only).
    pub holes: Vec<[f64; 3]>,
    /// Boundary marker (patch id) the facet's triangles carry to the output; 0 when the file
    /// gives none.
    pub marker: i32,
    /// 1-based line of the file where the facet starts, for error messages; for binary STL,
    /// which has no lines, the 1-based number of the triangle in the file.
    pub line: usize,
}

/// A region seed in 3D: the part of the domain containing `point` gets `attribute`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceRegion {
    /// A point inside the region.
    pub point: [f64; 3],
    /// The regional attribute (cell zone) given to the region's tetrahedra.
    pub attribute: f64,
    /// Largest tetrahedron volume wanted in the region (`None`: no limit; a file's value `<= 0`
    /// also means no limit, as in TetGen).
    pub max_volume: Option<f64>,
}

/// The contents of a 3D surface file, whatever its format.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceFile {
    /// Point coordinates, in file order (STL: distinct points in order of first appearance).
    pub points: Vec<[f64; 3]>,
    /// A boundary marker per point, when the file has them (TetGen `.node` markers, Medit
    /// vertex references).
    pub point_markers: Option<Vec<i32>>,
    /// The facets, in file order.
    pub facets: Vec<SurfaceFacet>,
    /// Hole seeds: the part of the domain containing each is not meshed.
    pub holes: Vec<[f64; 3]>,
    /// Region seeds.
    pub regions: Vec<SurfaceRegion>,
    /// Names of boundary markers, when the file names them (gmsh physical names of dimension
    /// 2, OBJ groups, ASCII STL solids), sorted by marker.
    pub marker_names: Vec<(i32, String)>,
    /// Tetrahedra (0-based point indices), when the file is a volume mesh (Medit `.mesh`,
    /// gmsh `.msh`); empty for surface formats.
    pub tetrahedra: Vec<[u32; 4]>,
    /// One region per tetrahedron (Medit reference, gmsh physical tag; 0 when none).
    pub tetrahedron_regions: Vec<i32>,
    /// How the file numbers its points (0 or 1; gmsh tags are arbitrary and reported as 1), so
    /// messages can name points as the user's file does.
    pub first_index: u32,
}

impl SurfaceFile {
    /// Whether every facet is a single triangle without holes.
    pub fn is_triangulated(&self) -> bool {
        self.facets
            .iter()
            .all(|f| f.holes.is_empty() && f.polygons.len() == 1 && f.polygons[0].len() == 3)
    }
}

/// Reads a 3D surface (or volume mesh) file, choosing the reader from the extension:
/// `.smesh` and `.poly` (TetGen; a 2D Triangle `.poly` is refused with a hint), `.off`,
/// `.stl` (ASCII or binary), `.obj`, `.ply` (ASCII or binary), `.mesh` (Medit), `.msh` (gmsh
/// 2.2 / 4.1, ASCII or binary). Any other
/// extension is an [`IoError::UnknownFormat`].
pub fn read_surface(path: &Path) -> Result<SurfaceFile, IoError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("smesh") => crate::read_smesh(path),
        Some("poly") => crate::read_tetgen_poly(path),
        Some("off") => crate::read_off(path),
        Some("stl") => crate::read_stl(path),
        Some("obj") => crate::read_obj(path),
        Some("ply") => crate::read_ply(path),
        Some("mesh") => crate::read_medit(path),
        Some("msh") => crate::read_msh(path),
        _ => Err(IoError::UnknownFormat {
            file: path.to_path_buf(),
        }),
    }
}

/// Checks a facet polygon read from a surface format: at least 3 corners (`what` names the
/// record in the message).
pub(crate) fn check_polygon_size(
    n: usize,
    what: &str,
    file: &Path,
    line: usize,
) -> Result<(), IoError> {
    if n < 3 {
        return Err(IoError::parse(
            file,
            line,
            format!("{what} has {n} corners, at least 3 are needed"),
        ));
    }
    Ok(())
}
