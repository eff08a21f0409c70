//! Exterior deletion by flood fill (R8): which elements are inside the domain, and in which
//! region.
//!
//! Cells are grouped into components connected across non-boundary (unconstrained) edges. The
//! hull's ghost cells are outside, at depth 0; a component's depth is the fewest boundary edges
//! crossed to reach it from outside. Closed loops nest, so odd depth is inside the domain and
//! even depth is outside: the far field's inside is domain, a body's inside is not, an island in
//! a lake is domain again. (So a region walled in by two others, as where two shapes cut along
//! each other overlap, is a hole unless a region seed is in it: in 2D it cannot be told from a
//! hole touching the boundary at two vertices; 3D tells them apart, see [`flood_fill`].) An
//! open internal line (a wake) has the same component on both sides and changes nothing. Hole
//! seeds then remove their component, and region seeds give theirs an attribute (and make it
//! part of the domain, unless it touches the outside of the hull). A seed on a segment or at a
//! vertex between two components is an error: it names neither.

use crate::error::RecoveryError;
use crate::plc::Plc2;
use crate::union_find::UnionFind;
use delmesh_delaunay_core::{CellId, ConstrainedTriangulation2, Location};
use delmesh_predicates::{orient2d, Sign};
use std::collections::{HashMap, VecDeque};

/// The tag of cells outside the domain (and in holes).
pub const OUTSIDE: u32 = u32::MAX;

/// A seed as messages name it: `("hole" | "region", number)` in the input's numbering.
pub type SeedName = (&'static str, u64);

/// The seeds that do nothing: outside the domain ([`seeds_outside`]), or overridden by
/// another seed ([`overridden_seeds`]).
pub(crate) struct SeedReport {
    /// Outside the domain.
    pub(crate) outside: Vec<SeedName>,
    /// (overridden, winner).
    pub(crate) overridden: Vec<(SeedName, SeedName)>,
}

/// The warning for a seed overridden by another (see [`overridden_seeds`]), without the
/// leading "warning: ".
pub(crate) fn overridden_message((what, k): SeedName, (by, j): SeedName) -> String {
    if by == "hole" {
        format!("{what} seed {k} lies in the part hole seed {j} removes and does nothing")
    } else {
        format!(
            "{what} seeds {k} and {j} lie in the same region with different attributes: \
             seed {j}'s is used"
        )
    }
}

/// Tags every cell of `cdt` with its region index (0 for the default region, `1 + k` for the
/// `k`-th region seed) or [`OUTSIDE`]; returns the attribute of each region index, and the
/// seeds that do nothing (beyond the outer boundary, or overridden).
pub(crate) fn classify(
    cdt: &mut ConstrainedTriangulation2,
    plc: &Plc2,
) -> Result<(Vec<f64>, SeedReport), RecoveryError> {
    let tri = cdt.triangulation();
    let cells: Vec<CellId> = tri.all_cells().collect();
    let components = flood_fill(
        &cells,
        3,
        |c, i| cdt.is_constrained(c, i),
        |c, i| tri.neighbor_facet(c, i).cell(),
        |c| tri.is_ghost(c),
        None,
    );
    let component = &components.of_cell;
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
    let seeds = SeedReport {
        outside: seeds_outside(&components, &regions, &holes, base),
        overridden: overridden_seeds(&components, &regions, &holes, base),
    };
    let tri = cdt.triangulation();
    let (tags, attributes) =
        domain_tags(&cells, &components, &regions, &holes, |c| tri.is_ghost(c))?;
    for (&c, tag) in cells.iter().zip(tags) {
        cdt.set_tag(c, tag);
    }
    Ok((attributes, seeds))
}

/// The seeds (regions with their attributes, then holes; numbered from `base`) whose
/// component is the exterior: they do nothing. Shared by the 2D and 3D flood fills.
pub(crate) fn seeds_outside(
    components: &Components,
    regions: &[(Option<usize>, f64)],
    holes: &[Option<usize>],
    base: u64,
) -> Vec<SeedName> {
    regions
        .iter()
        .map(|r| ("region", r.0))
        .enumerate()
        .chain(holes.iter().map(|&h| ("hole", h)).enumerate())
        .filter(|(_, (_, comp))| comp.is_some_and(|c| components.exterior[c]))
        .map(|(k, (what, _))| (what, k as u64 + base))
        .collect()
}

/// Seeds that another seed overrides (same numbering as [`seeds_outside`]), as (overridden,
/// winner), in order: a region seed in the same region as the next one there with another
/// attribute (the last wins), a region seed in the part a hole seed removes. Seeds outside the
/// domain are left to [`seeds_outside`]. Shared by the 2D and 3D flood fills.
pub(crate) fn overridden_seeds(
    components: &Components,
    regions: &[(Option<usize>, f64)],
    holes: &[Option<usize>],
    base: u64,
) -> Vec<(SeedName, SeedName)> {
    let inside = |comp: &Option<usize>| comp.filter(|&c| !components.exterior[c]);
    // The first hole seed of each component, and the last region seed seen so far.
    let mut hole_in: HashMap<usize, usize> = HashMap::new();
    for (h, comp) in holes.iter().enumerate() {
        if let Some(c) = inside(comp) {
            hole_in.entry(c).or_insert(h);
        }
    }
    let mut last: HashMap<usize, usize> = HashMap::new();
    let mut out = Vec::new();
    for (k, (comp, attribute)) in regions.iter().enumerate() {
        let Some(c) = inside(comp) else {
            continue;
        };
        let name = ("region", k as u64 + base);
        if let Some(&h) = hole_in.get(&c) {
            out.push((name, ("hole", h as u64 + base)));
        } else if let Some(j) = last.insert(c, k) {
            if regions[j].1.to_bits() != attribute.to_bits() {
                out.push((("region", j as u64 + base), name));
            }
        }
    }
    out.sort_unstable();
    out
}

/// The tag of each of `cells` (in order) from the flood fill's components: a component
/// inside the domain is the default region 0, a region seed's component (`Some` component,
/// attribute) gets region `1 + k` unless it is outside the hull, a hole seed's component and
/// every ghost cell are [`OUTSIDE`]. Returns the tags and the attribute of each region index.
/// Shared by the 2D and 3D flood fills.
///
/// # Errors
/// [`RecoveryError::EmptyDomain`] if no cell is inside.
pub(crate) fn domain_tags(
    cells: &[CellId],
    components: &Components,
    regions: &[(Option<usize>, f64)],
    holes: &[Option<usize>],
    is_ghost: impl Fn(CellId) -> bool,
) -> Result<(Vec<u32>, Vec<f64>), RecoveryError> {
    let mut region: Vec<u32> = components
        .inside
        .iter()
        .map(|&inside| if inside { 0 } else { OUTSIDE })
        .collect();
    let mut attributes = vec![0.0];
    for &(comp, attribute) in regions {
        if let Some(comp) = comp {
            if !components.exterior[comp] {
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
                region[components.of_cell[c.index()] as usize]
            }
        })
        .collect();
    if tags.iter().all(|&t| t == OUTSIDE) {
        return Err(RecoveryError::EmptyDomain);
    }
    Ok((tags, attributes))
}

/// The flood fill's result: the component of each cell slot (indexed by `CellId`), and of
/// each component whether it is outside the hull (holds ghost cells) and whether it is inside
/// the domain by the nesting of the boundary.
pub(crate) struct Components {
    pub(crate) of_cell: Vec<u32>,
    pub(crate) exterior: Vec<bool>,
    pub(crate) inside: Vec<bool>,
}

/// Groups `cells` (each with `facets` facets) into components connected across facets that are
/// not boundary facets, and says which components the boundary encloses. Shared by the 2D and
/// 3D flood fills.
///
/// With `corners` (3D: a boundary face's vertices, sorted), the boundary faces are first split
/// into *sheets*, connected across edges where exactly two boundary faces meet. A sheet that
/// meets every other edge an even number of times is closed (a closed surface, even one
/// touching another at a vertex or an edge): crossing it toggles inside and outside, so closed
/// sheets nest. The other sheets are walls (a domain cut into regions, solids cut along each
/// other) and are grouped by the edges they share; a group's inside is what cannot be reached
/// from outside without crossing it. A component is inside the domain if it is inside an odd
/// number of closed sheets and groups.
///
/// Without (2D) every boundary facet is taken as part of a closed loop: a component is inside
/// if the fewest boundary facets crossed to reach it from outside is odd. In 2D a loop
/// touching others at two vertices (a hole spanning a channel) and shapes cut along each other
/// (a fragment) look the same, and the rule is the nesting of closed loops; region
/// seeds say otherwise.
pub(crate) fn flood_fill(
    cells: &[CellId],
    facets: usize,
    is_boundary: impl Fn(CellId, usize) -> bool,
    across: impl Fn(CellId, usize) -> CellId,
    is_ghost: impl Fn(CellId) -> bool,
    corners: Option<&dyn Fn(CellId, usize) -> [u32; 3]>,
) -> Components {
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
    // The boundary facets, each once: the components on their two sides, and their corners.
    let mut sides: Vec<(u32, u32)> = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    for &c in cells {
        for i in 0..facets {
            let n = across(c, i);
            if c.index() < n.index() && is_boundary(c, i) {
                sides.push((component[c.index()], component[n.index()]));
                if let Some(corners) = corners {
                    faces.push(corners(c, i));
                }
            }
        }
    }
    let kinds = match corners {
        Some(_) => sheet_kinds(&faces),
        None => vec![CLOSED; sides.len()],
    };
    // Component adjacency across boundary facets, labelled by the facets' kind.
    let mut adjacent: Vec<(u32, u32, u32)> = Vec::with_capacity(2 * sides.len());
    for (&(x, y), &kind) in sides.iter().zip(&kinds) {
        if x != y {
            adjacent.push((x, y, kind));
            adjacent.push((y, x, kind));
        }
    }
    adjacent.sort_unstable();
    adjacent.dedup();
    let nc = n_components as usize;
    let mut start = vec![0usize; nc + 1];
    for &(x, _, _) in &adjacent {
        start[x as usize + 1] += 1;
    }
    for k in 0..nc {
        start[k + 1] += start[k];
    }
    let mut exterior = vec![false; nc];
    for &c in cells {
        if is_ghost(c) {
            exterior[component[c.index()] as usize] = true;
        }
    }
    // Breadth-first from outside over the crossings not of kind `skip`: which components are
    // reached, and the parity of the closed sheets crossed on the way.
    let reach = |skip: u32| {
        let mut parity = vec![u8::MAX; nc];
        let mut queue: VecDeque<usize> = (0..nc).filter(|&k| exterior[k]).collect();
        for &k in &queue {
            parity[k] = 0;
        }
        while let Some(k) = queue.pop_front() {
            for &(_, y, kind) in &adjacent[start[k]..start[k + 1]] {
                if kind != skip && parity[y as usize] == u8::MAX {
                    parity[y as usize] = parity[k] ^ u8::from(kind == CLOSED);
                    queue.push_back(y as usize);
                }
            }
        }
        parity
    };
    let parity = reach(u32::MAX);
    let mut inside: Vec<bool> = parity.iter().map(|&p| p == 1).collect();
    let mut groups: Vec<u32> = kinds.iter().copied().filter(|&k| k != CLOSED).collect();
    groups.sort_unstable();
    groups.dedup();
    for g in groups {
        for (k, p) in reach(g).into_iter().enumerate() {
            inside[k] ^= p == u8::MAX && parity[k] != u8::MAX;
        }
    }
    Components {
        of_cell: component,
        exterior,
        inside,
    }
}

/// The kind of boundary facet: in a closed sheet.
const CLOSED: u32 = u32::MAX - 1;

/// The kind of each boundary face (given by its sorted corners): [`CLOSED`], or the group of
/// walls it belongs to (see [`flood_fill`]).
fn sheet_kinds(facets: &[[u32; 3]]) -> Vec<u32> {
    // Every (edge, face) pair, sorted by edge.
    let mut ridges: Vec<([u32; 2], u32)> = Vec::with_capacity(3 * facets.len());
    for (f, v) in facets.iter().enumerate() {
        let f = f as u32;
        ridges.extend([([v[0], v[1]], f), ([v[0], v[2]], f), ([v[1], v[2]], f)]);
    }
    ridges.sort_unstable();
    let runs: Vec<&[([u32; 2], u32)]> = ridges.chunk_by(|a, b| a.0 == b.0).collect();
    let mut sheet = UnionFind::new(facets.len());
    for run in &runs {
        if let [(_, a), (_, b)] = run {
            sheet.union(*a, *b);
        }
    }
    // A sheet meeting some other edge an odd number of times is open: a wall.
    let mut open = vec![false; facets.len()];
    let mut at_ridge: Vec<u32> = Vec::new();
    for run in runs.iter().filter(|r| r.len() != 2) {
        at_ridge.clear();
        at_ridge.extend(run.iter().map(|&(_, f)| sheet.find(f)));
        at_ridge.sort_unstable();
        for same in at_ridge.chunk_by(|a, b| a == b) {
            if same.len() % 2 == 1 {
                open[same[0] as usize] = true;
            }
        }
    }
    // Walls that share an edge form one group.
    let mut group = UnionFind::new(facets.len());
    for run in runs.iter().filter(|r| r.len() != 2) {
        let mut walls = run
            .iter()
            .map(|&(_, f)| sheet.find(f))
            .filter(|&s| open[s as usize]);
        if let Some(first) = walls.next() {
            for s in walls {
                group.union(first, s);
            }
        }
    }
    (0..facets.len() as u32)
        .map(|f| {
            let s = sheet.find(f);
            if open[s as usize] {
                group.find(s)
            } else {
                CLOSED
            }
        })
        .collect()
}
