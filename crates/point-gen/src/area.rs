//! Regional area limits (Triangle's `-a` with the maximum areas of a `.poly` file's regions):
//! every element larger than its region's limit gets a point at its centroid, in passes, until
//! none is left.
//!
//! Recovery splits the boundary next to a region with a limit, and generation fills the region
//! at about that area (its spacing is capped, see [`SpacingField::with_area_limits`]), so this
//! pass adds few points; it is what makes the limit a guarantee, run before smoothing and again
//! after it (a move changes areas). A centroid lies inside its element, a third of a height
//! from each side, and every height of an element of area above `A` in a domain of diameter
//! `D` is above `2A/D`: each point added is farther than `2A/(3D)` from every other point,
//! so the passes end. Insertion keeps the (constrained) Delaunay property and never crosses a
//! boundary edge; a centroid that rounding puts on a boundary edge or in another region is
//! refused and its element left as it is.
//!
//! [`SpacingField::with_area_limits`]: crate::SpacingField::with_area_limits

use crate::generate::{elements_where, set, PointGenError};
use delmesh_boundary_recovery::Mesh2;
use delmesh_delaunay_core::{CellId, Insertion};

/// The area limit of each region (by region index, as elements are tagged; infinite where
/// there is none): `delmesh_boundary_recovery::Plc2::area_limits`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AreaLimits {
    limits: Vec<f64>,
}

impl AreaLimits {
    /// Limits by region index.
    pub fn new(limits: Vec<f64>) -> Self {
        AreaLimits { limits }
    }

    /// Whether any region has a limit.
    pub fn any(&self) -> bool {
        self.limits.iter().any(|a| a.is_finite())
    }

    /// The elements of `mesh` larger than their region's limit.
    pub fn too_large(&self, mesh: &Mesh2) -> Vec<CellId> {
        elements_where(mesh, |c| self.exceeded(mesh, c))
    }

    fn exceeded(&self, mesh: &Mesh2, c: CellId) -> bool {
        let limit = self
            .limits
            .get(mesh.cdt.tag(c) as usize)
            .copied()
            .unwrap_or(f64::INFINITY);
        limit.is_finite() && area(points(mesh, c)) > limit
    }

    /// Splits every element of `mesh` larger than its region's limit at its centroid, until
    /// none is or `max_points` have been added (see the module docs); returns the number of
    /// points added. New nodes get the mean spacing of the split element's nodes.
    ///
    /// # Errors
    /// Only if an insertion fails, which would be a bug.
    pub fn run(&self, mesh: &mut Mesh2, max_points: usize) -> Result<usize, PointGenError> {
        if !self.any() {
            return Ok(0);
        }
        let mut added = 0;
        let mut todo = self.too_large(mesh);
        while !todo.is_empty() {
            mesh.cdt.next_epoch(true);
            let mut inserted = 0;
            for &c in &todo {
                if added + inserted >= max_points {
                    return Ok(added + inserted);
                }
                // An earlier insertion of this pass may have split it already.
                if !mesh.is_element(c) || !self.exceeded(mesh, c) {
                    continue;
                }
                let p = points(mesh, c);
                let g = [
                    (p[0][0] + p[1][0] + p[2][0]) / 3.0,
                    (p[0][1] + p[1][1] + p[2][1]) / 3.0,
                ];
                let tri = mesh.cdt.triangulation();
                let spacing = tri
                    .cell(c)
                    .iter()
                    .map(|u| mesh.spacing.get(u.index()).copied().unwrap_or(f64::NAN))
                    .sum::<f64>()
                    / 3.0;
                let tag = mesh.cdt.tag(c);
                let result = mesh.cdt.insert_near_if(g, c, |cdt, cell, on_edge| {
                    cdt.tag(cell) == tag && on_edge.is_none_or(|i| !cdt.is_constrained(cell, i))
                });
                match result {
                    Ok(Some(Insertion::Inserted(v))) => {
                        set(&mut mesh.spacing, v, spacing);
                        inserted += 1;
                    }
                    Ok(_) => {}
                    Err(e) => return Err(e.into()),
                }
            }
            if inserted == 0 {
                break;
            }
            added += inserted;
            todo = mesh.cdt.take_changed();
            todo.sort_unstable();
            todo.dedup();
            todo.retain(|&c| mesh.is_element(c) && self.exceeded(mesh, c));
        }
        Ok(added)
    }
}

/// The corners of element `c`.
pub(crate) fn points(mesh: &Mesh2, c: CellId) -> [[f64; 2]; 3] {
    let tri = mesh.cdt.triangulation();
    let v = tri.cell(c);
    [tri.vertex(v[0]), tri.vertex(v[1]), tri.vertex(v[2])]
}

/// The area of a counter-clockwise triangle.
pub(crate) fn area(p: [[f64; 2]; 3]) -> f64 {
    0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]))
}
