//! Exterior deletion by flood fill in 3D (R8): which tetrahedra are inside the domain, and in
//! which region.
//!
//! As in 2D (`classify`): cells are grouped into components connected across faces that are not
//! protected (not boundary faces). The hull's ghost cells are outside. Closed surfaces nest, so
//! a component inside an odd number of them is inside the domain: inside the far field is
//! domain, inside a body is not, a body inside a hollow body is domain again. Walls (faces
//! meeting others at edges shared by three or more: blocks sharing faces, overlapping solids
//! cut along each other as gmsh's fragments write them) do not nest: what a group of walls
//! encloses is inside it however it is reached. Hole seeds then remove their component, and
//! region seeds give theirs an attribute.

use crate::error::RecoveryError;
use crate::plc3::Plc3;
use delmesh_delaunay_core::{CellId, ConstrainedTriangulation3, Location, VertexId};

pub(crate) use crate::classify::OUTSIDE;
use crate::classify::{domain_tags, flood_fill};

/// Tags every cell of `ct` with its region index (0 for the default region, `1 + k` for the
/// `k`-th region seed) or [`OUTSIDE`]; returns the attribute of each region index.
pub(crate) fn classify3(
    ct: &mut ConstrainedTriangulation3,
    plc: &Plc3,
) -> Result<Vec<f64>, RecoveryError> {
    let tri = ct.triangulation();
    let cells: Vec<CellId> = tri.all_cells().collect();
    let components = flood_fill(
        &cells,
        4,
        |c, i| ct.is_protected(c, i),
        |c, i| tri.neighbor_facet(c, i).cell(),
        |c| tri.is_ghost(c),
        Some(&|c, i| face_corners(tri.cell(c), i)),
    );
    let component = &components.of_cell;
    let component_at = |ct: &mut ConstrainedTriangulation3, p: [f64; 3]| match ct.locate(p) {
        Location::Cell(c) => Some(component[c.index()] as usize),
        Location::Vertex(_) => None,
    };
    let regions: Vec<_> = plc
        .regions
        .iter()
        .map(|r| (component_at(ct, r.point), r.attribute))
        .collect();
    let holes: Vec<_> = plc.holes.iter().map(|&h| component_at(ct, h)).collect();
    let tri = ct.triangulation();
    let (tags, attributes) =
        domain_tags(&cells, &components, &regions, &holes, |c| tri.is_ghost(c))?;
    for (&c, tag) in cells.iter().zip(tags) {
        ct.set_tag(c, tag);
    }
    Ok(attributes)
}

/// The corners of the face of a tetrahedron (vertices `v`) opposite its vertex `i`, sorted.
pub(crate) fn face_corners(v: &[VertexId], i: usize) -> [u32; 3] {
    let mut f = [v[(i + 1) % 4].0, v[(i + 2) % 4].0, v[(i + 3) % 4].0];
    f.sort_unstable();
    f
}
