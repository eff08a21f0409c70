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
use delmesh_predicates::{orient3d, Sign};

pub(crate) use crate::classify::OUTSIDE;
use crate::classify::{domain_tags, flood_fill, overridden_seeds, seeds_outside, SeedReport};

/// Tags every cell of `ct` with its region index (0 for the default region, `1 + k` for the
/// `k`-th region seed) or [`OUTSIDE`]; returns the attribute of each region index, and the
/// seeds that do nothing (outside every closed surface, or overridden).
pub(crate) fn classify3(
    ct: &mut ConstrainedTriangulation3,
    plc: &Plc3,
) -> Result<(Vec<f64>, SeedReport), RecoveryError> {
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
    // The component at a seed: that of every cell whose closed tetrahedron holds it. A seed
    // on a face, an edge or a vertex between two components does not say which one it means.
    let base = u64::from(plc.first_index);
    let component_at = |ct: &mut ConstrainedTriangulation3,
                        p: [f64; 3],
                        what: &'static str,
                        k: usize|
     -> Result<Option<usize>, RecoveryError> {
        let at = match ct.locate(p) {
            Location::Cell(c) => cells_holding(ct, c, p),
            Location::Vertex(v) => ct.triangulation().cells_around_vertex(v),
        };
        let first = component[at[0].index()];
        for c in at {
            if component[c.index()] != first {
                return Err(RecoveryError::SeedOnSurface {
                    what,
                    index: k as u64 + base,
                    point: p,
                });
            }
        }
        Ok(Some(first as usize))
    };
    let mut regions = Vec::with_capacity(plc.regions.len());
    for (k, r) in plc.regions.iter().enumerate() {
        regions.push((component_at(ct, r.point, "region", k)?, r.attribute));
    }
    let mut holes = Vec::with_capacity(plc.holes.len());
    for (k, &h) in plc.holes.iter().enumerate() {
        holes.push(component_at(ct, h, "hole", k)?);
    }
    let seeds = SeedReport {
        outside: seeds_outside(&components, &regions, &holes, base),
        overridden: overridden_seeds(&components, &regions, &holes, base),
    };
    let tri = ct.triangulation();
    let (tags, attributes) =
        domain_tags(&cells, &components, &regions, &holes, |c| tri.is_ghost(c))?;
    for (&c, tag) in cells.iter().zip(tags) {
        ct.set_tag(c, tag);
    }
    Ok((attributes, seeds))
}

/// The cells whose closed tetrahedron holds `p`, found from `start` (one of them) across the
/// faces `p` lies on (exactly): one cell, two across a face, a ring around an edge. A ghost
/// cell is crossed only through its hull face.
fn cells_holding(ct: &ConstrainedTriangulation3, start: CellId, p: [f64; 3]) -> Vec<CellId> {
    let tri = ct.triangulation();
    let mut found = vec![start];
    let mut at = 0;
    while at < found.len() {
        let c = found[at];
        at += 1;
        let v = tri.cell(c);
        for i in 0..4 {
            let f = [1, 2, 3].map(|k| v[(i + k) % 4]);
            if f.iter().any(|u| u.is_ghost()) {
                continue;
            }
            let f = f.map(|u| tri.vertex(u));
            if orient3d(f[0], f[1], f[2], p) == Sign::Zero {
                let d = tri.neighbor_facet(c, i).cell();
                if !found.contains(&d) {
                    found.push(d);
                }
            }
        }
    }
    found
}

/// The corners of the face of a tetrahedron (vertices `v`) opposite its vertex `i`, sorted.
pub(crate) fn face_corners(v: &[VertexId], i: usize) -> [u32; 3] {
    let mut f = [v[(i + 1) % 4].0, v[(i + 2) % 4].0, v[(i + 3) % 4].0];
    f.sort_unstable();
    f
}
