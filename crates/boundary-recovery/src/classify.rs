//! Exterior deletion by flood fill (R8): which elements are inside the domain, and in which
//! region.
//!
//! Cells are grouped into components connected across non-boundary (unconstrained) edges. The
//! hull's ghost cells are outside, at depth 0; a component's depth is the fewest boundary edges
//! crossed to reach it from outside. Closed loops nest, so odd depth is inside the domain and
//! even depth is outside: the far field's inside is domain, a body's inside is not, an island in
//! a lake is domain again. An open internal line (a wake) has the same component on both sides
//! and changes nothing. Hole seeds then remove their component, and region seeds give theirs an
//! attribute (and make it part of the domain, unless it touches the outside of the hull). A seed
//! on a segment or at a vertex between two components is an error: it names neither.

use crate::error::RecoveryError;
use crate::plc::Plc2;
use delmesh_delaunay_core::{CellId, ConstrainedTriangulation2, Location};
use delmesh_predicates::{orient2d, Sign};
use std::collections::VecDeque;

/// The tag of cells outside the domain (and in holes).
pub const OUTSIDE: u32 = u32::MAX;

/// Tags every cell of `cdt` with its region index (0 for the default region, `1 + k` for the
/// `k`-th region seed) or [`OUTSIDE`]; returns the attribute of each region index.
pub(crate) fn classify(
    cdt: &mut ConstrainedTriangulation2,
    plc: &Plc2,
) -> Result<Vec<f64>, RecoveryError> {
    let tri = cdt.triangulation();
    let cells: Vec<CellId> = tri.all_cells().collect();
    let (component, depth) = components_by_depth(
        &cells,
        3,
        |c, i| cdt.is_constrained(c, i),
        |c, i| tri.neighbor_facet(c, i).cell(),
        |c| tri.is_ghost(c),
    );
    // The component at a seed: that of every cell whose closed triangle holds it. A seed on a
    // segment, or at a vertex, between two components does not say which one it means.
    let base = u64::from(plc.first_index);
    let component_at = |cdt: &mut ConstrainedTriangulation2,
                        p: [f64; 2],
                        what: &'static str,
                        k: usize|
     -> Result<Option<usize>, RecoveryError> {
        let at = match cdt.locate(p) {
            Location::Cell(c) => {
                let tri = cdt.triangulation();
                let v = tri.cell(c);
                let mut at = vec![c];
                for i in 0..3 {
                    let (a, b) = (v[(i + 1) % 3], v[(i + 2) % 3]);
                    if !tri.is_ghost(c) && orient2d(tri.vertex(a), tri.vertex(b), p) == Sign::Zero {
                        at.push(tri.neighbor_facet(c, i).cell());
                    }
                }
                at
            }
            Location::Vertex(v) => cdt.triangulation().cells_around_vertex(v),
        };
        let first = component[at[0].index()];
        if at.iter().any(|c| component[c.index()] != first) {
            return Err(RecoveryError::SeedOnBoundary {
                what,
                index: k as u64 + base,
                point: p,
            });
        }
        Ok(Some(first as usize))
    };
    let mut regions = Vec::with_capacity(plc.regions.len());
    for (k, r) in plc.regions.iter().enumerate() {
        regions.push((component_at(cdt, r.point, "region", k)?, r.attribute));
    }
    let mut holes = Vec::with_capacity(plc.holes.len());
    for (k, &h) in plc.holes.iter().enumerate() {
        holes.push(component_at(cdt, h, "hole", k)?);
    }
    let tri = cdt.triangulation();
    let (tags, attributes) = domain_tags(&cells, &component, &depth, &regions, &holes, |c| {
        tri.is_ghost(c)
    })?;
    for (&c, tag) in cells.iter().zip(tags) {
        cdt.set_tag(c, tag);
    }
    Ok(attributes)
}

/// The tag of each of `cells` (in order) from the flood fill's components and depths: odd
/// depth is the default region 0, a region seed's component (`Some` component, attribute)
/// gets region `1 + k` unless it is outside the hull, a hole seed's component and every ghost
/// cell are [`OUTSIDE`]. Returns the tags and the attribute of each region index. Shared by
/// the 2D and 3D flood fills.
///
/// # Errors
/// [`RecoveryError::EmptyDomain`] if no cell is inside.
pub(crate) fn domain_tags(
    cells: &[CellId],
    component: &[u32],
    depth: &[u32],
    regions: &[(Option<usize>, f64)],
    holes: &[Option<usize>],
    is_ghost: impl Fn(CellId) -> bool,
) -> Result<(Vec<u32>, Vec<f64>), RecoveryError> {
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
    for &(comp, attribute) in regions {
        if let Some(comp) = comp {
            if depth[comp] > 0 && depth[comp] != u32::MAX {
                region[comp] = attributes.len() as u32;
            }
        }
        attributes.push(attribute);
    }
    for &comp in holes.iter().flatten() {
        region[comp] = OUTSIDE;
    }
    let tags: Vec<u32> = cells
        .iter()
        .map(|&c| {
            if is_ghost(c) {
                OUTSIDE
            } else {
                region[component[c.index()] as usize]
            }
        })
        .collect();
    if tags.iter().all(|&t| t == OUTSIDE) {
        return Err(RecoveryError::EmptyDomain);
    }
    Ok((tags, attributes))
}

/// Groups `cells` (each with `facets` facets) into components connected across facets that are
/// not boundary facets, and gives each component its depth: the fewest boundary facets crossed
/// to reach it from a ghost (outside) cell, `u32::MAX` if unreachable. Returns the component of
/// each cell slot (indexed by `CellId`) and the depth of each component. Shared by the 2D and
/// 3D flood fills.
pub(crate) fn components_by_depth(
    cells: &[CellId],
    facets: usize,
    is_boundary: impl Fn(CellId, usize) -> bool,
    across: impl Fn(CellId, usize) -> CellId,
    is_ghost: impl Fn(CellId) -> bool,
) -> (Vec<u32>, Vec<u32>) {
    let slots = cells.iter().map(|c| c.index() + 1).max().unwrap_or(0);
    let mut component = vec![u32::MAX; slots];
    let mut n_components = 0u32;
    let mut stack = Vec::new();
    for &c in cells {
        if component[c.index()] != u32::MAX {
            continue;
        }
        component[c.index()] = n_components;
        stack.push(c);
        while let Some(c) = stack.pop() {
            for i in 0..facets {
                if is_boundary(c, i) {
                    continue;
                }
                let n = across(c, i);
                if component[n.index()] == u32::MAX {
                    component[n.index()] = n_components;
                    stack.push(n);
                }
            }
        }
        n_components += 1;
    }
    // Component adjacency across boundary facets, then depth by breadth-first search.
    let mut adjacent: Vec<(u32, u32)> = Vec::new();
    for &c in cells {
        for i in 0..facets {
            if is_boundary(c, i) {
                let (x, y) = (component[c.index()], component[across(c, i).index()]);
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
    for &c in cells {
        if is_ghost(c) {
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
    (component, depth)
}
