//! Exterior deletion by flood fill in 3D (R8): which tetrahedra are inside the domain, and in
//! which region.
//!
//! As in 2D (`classify`): cells are grouped into components connected across faces that are not
//! protected (not boundary faces). The hull's ghost cells are outside, at depth 0; a component's
//! depth is the fewest boundary faces crossed to reach it from outside. Closed surfaces nest, so
//! odd depth is inside the domain: inside the far field is domain, inside a body is not, a body
//! inside a hollow body is domain again. Hole seeds then remove their component, and region
//! seeds give theirs an attribute.

use crate::error::RecoveryError;
use crate::plc3::Plc3;
use delmesh_delaunay_core::{CellId, ConstrainedTriangulation3, Location};

use crate::classify::components_by_depth;
pub(crate) use crate::classify::OUTSIDE;

/// Tags every cell of `ct` with its region index (0 for the default region, `1 + k` for the
/// `k`-th region seed) or [`OUTSIDE`]; returns the attribute of each region index.
pub(crate) fn classify3(
    ct: &mut ConstrainedTriangulation3,
    plc: &Plc3,
) -> Result<Vec<f64>, RecoveryError> {
    let tri = ct.triangulation();
    let cells: Vec<CellId> = tri.all_cells().collect();
    let (component, depth) = components_by_depth(
        &cells,
        4,
        |c, i| ct.is_protected(c, i),
        |c, i| tri.neighbor_facet(c, i).cell(),
        |c| tri.is_ghost(c),
    );
    let mut region: Vec<u32> = depth
        .iter()
        .map(|&d| {
            if d != u32::MAX && d % 2 == 1 {
                0
            } else {
                OUTSIDE
            }
        })
        .collect();
    let mut attributes = vec![0.0];
    let component_at = |ct: &mut ConstrainedTriangulation3, p: [f64; 3]| match ct.locate(p) {
        Location::Cell(c) => Some(component[c.index()] as usize),
        Location::Vertex(_) => None,
    };
    for r in &plc.regions {
        if let Some(comp) = component_at(ct, r.point) {
            if depth[comp] > 0 && depth[comp] != u32::MAX {
                region[comp] = attributes.len() as u32;
            }
        }
        attributes.push(r.attribute);
    }
    for &h in &plc.holes {
        if let Some(comp) = component_at(ct, h) {
            region[comp] = OUTSIDE;
        }
    }
    let mut any_inside = false;
    for &c in &cells {
        let mut tag = region[component[c.index()] as usize];
        if ct.triangulation().is_ghost(c) {
            tag = OUTSIDE;
        }
        any_inside |= tag != OUTSIDE;
        ct.set_tag(c, tag);
    }
    if !any_inside {
        return Err(RecoveryError::EmptyDomain);
    }
    Ok(attributes)
}
