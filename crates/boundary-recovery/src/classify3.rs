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
use std::collections::VecDeque;

pub(crate) use crate::classify::OUTSIDE;

/// Tags every cell of `ct` with its region index (0 for the default region, `1 + k` for the
/// `k`-th region seed) or [`OUTSIDE`]; returns the attribute of each region index.
pub(crate) fn classify3(
    ct: &mut ConstrainedTriangulation3,
    plc: &Plc3,
) -> Result<Vec<f64>, RecoveryError> {
    let tri = ct.triangulation();
    let slots = tri.all_cells().map(|c| c.index() + 1).max().unwrap_or(0);
    let cells: Vec<CellId> = tri.all_cells().collect();
    // Components across faces that are not protected.
    let mut component = vec![u32::MAX; slots];
    let mut n_components = 0u32;
    let mut stack = Vec::new();
    for &c in &cells {
        if component[c.index()] != u32::MAX {
            continue;
        }
        component[c.index()] = n_components;
        stack.push(c);
        while let Some(c) = stack.pop() {
            for i in 0..4 {
                if ct.is_protected(c, i) {
                    continue;
                }
                let n = tri.neighbor_facet(c, i).cell();
                if component[n.index()] == u32::MAX {
                    component[n.index()] = n_components;
                    stack.push(n);
                }
            }
        }
        n_components += 1;
    }
    // Component adjacency across protected faces, then depth by breadth-first search.
    let mut adjacent: Vec<(u32, u32)> = Vec::new();
    for &c in &cells {
        for i in 0..4 {
            if ct.is_protected(c, i) {
                let n = tri.neighbor_facet(c, i).cell();
                let (x, y) = (component[c.index()], component[n.index()]);
                if x != y {
                    adjacent.push((x, y));
                }
            }
        }
    }
    adjacent.sort_unstable();
    adjacent.dedup();
    let nc = n_components as usize;
    let mut start = vec![0usize; nc + 1];
    for &(x, _) in &adjacent {
        start[x as usize + 1] += 1;
    }
    for k in 0..nc {
        start[k + 1] += start[k];
    }
    let mut depth = vec![u32::MAX; nc];
    let mut queue = VecDeque::new();
    for &c in &cells {
        if tri.is_ghost(c) {
            let k = component[c.index()] as usize;
            if depth[k] == u32::MAX {
                depth[k] = 0;
                queue.push_back(k);
            }
        }
    }
    while let Some(k) = queue.pop_front() {
        for &(_, y) in &adjacent[start[k]..start[k + 1]] {
            if depth[y as usize] == u32::MAX {
                depth[y as usize] = depth[k] + 1;
                queue.push_back(y as usize);
            }
        }
    }
    let mut region: Vec<u32> = depth
        .iter()
        .map(|&d| if d % 2 == 1 { 0 } else { OUTSIDE })
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
