//! Quality refinement in 3D, beyond the paper: tetrahedra whose radius–edge ratio
//! (circumradius over shortest edge) exceeds a bound get a point at their circumcentre
//! (Delaunay refinement, as in Shewchuk's and TetGen's `-q`), in passes, after automatic point
//! generation.
//!
//! As in 2D ([`crate::QualityRefinement`]): a circumcentre outside the tetrahedron's region, on a
//! protected face, or whose cavity would not be star-shaped is refused, so the boundary is
//! never crossed and tetrahedra at sharp boundary features stay as they are; caps on the passes
//! and on the points added keep any run bounded. Radius–edge refinement removes the needles
//! and caps; slivers (a good radius–edge ratio but a tiny dihedral angle) are left to smoothing.

use delmesh_boundary_recovery::{Mesh3, OUTSIDE};
use delmesh_delaunay_core::{CellId, Dim, D3};

use crate::generate::PointGenError;

/// Settings of 3D quality refinement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QualityRefinement3 {
    /// Tetrahedra with a larger circumradius / shortest edge are refined (a regular
    /// tetrahedron has √6/4 ≈ 0.61; TetGen's `-q` default is 2).
    pub max_radius_edge: f64,
    /// Passes at most.
    pub max_passes: usize,
    /// Points added at most, as a fraction of the vertices at the start.
    pub max_growth: f64,
}

impl Default for QualityRefinement3 {
    fn default() -> Self {
        QualityRefinement3 {
            max_radius_edge: 2.0,
            max_passes: 8,
            max_growth: 0.25,
        }
    }
}

/// Circumcentre and radius–edge ratio of a tetrahedron.
fn circumcentre_ratio(p: &[[f64; 3]; 4]) -> ([f64; 3], f64) {
    let c = D3::circumcenter(p);
    let d2 = |a: [f64; 3], b: [f64; 3]| {
        (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
    };
    let mut shortest = f64::INFINITY;
    for i in 0..4 {
        for j in i + 1..4 {
            shortest = shortest.min(d2(p[i], p[j]));
        }
    }
    (c, (d2(c, p[0]) / shortest).sqrt())
}

impl QualityRefinement3 {
    /// Refines `mesh`; returns the number of points added. New nodes get the mean spacing of
    /// the refined tetrahedron's nodes.
    ///
    /// # Errors
    /// A coordinate the triangulation cannot take (a bug if it ever fires).
    pub fn run(&self, mesh: &mut Mesh3) -> Result<usize, PointGenError> {
        self.run_capped(mesh, usize::MAX)
    }

    /// [`Self::run`], adding at most `max_points` points (what is left of a run's budget).
    ///
    /// # Errors
    /// As [`Self::run`].
    pub fn run_capped(&self, mesh: &mut Mesh3, max_points: usize) -> Result<usize, PointGenError> {
        let cap = ((mesh.ct.triangulation().num_vertices() as f64 * self.max_growth) as usize)
            .min(max_points);
        let mut added = 0;
        let mut cells: Vec<CellId> = mesh.elements().collect();
        let mut next: Vec<CellId> = Vec::new();
        for _ in 0..self.max_passes {
            next.clear();
            let mut inserted = 0;
            for &c in &cells {
                if added >= cap {
                    return Ok(added);
                }
                if !mesh.ct.is_live(c) || mesh.ct.tag(c) == OUTSIDE {
                    continue;
                }
                let tri = mesh.ct.triangulation();
                let v = tri.cell(c);
                if v.iter().any(|u| u.is_ghost()) {
                    continue;
                }
                let p = [0, 1, 2, 3].map(|k| tri.vertex(v[k]));
                let (centre, ratio) = circumcentre_ratio(&p);
                if ratio.is_nan()
                    || ratio <= self.max_radius_edge
                    || centre.iter().any(|x| !x.is_finite())
                {
                    continue;
                }
                let spacing = 0.25 * v.iter().map(|u| mesh.spacing[u.index()]).sum::<f64>();
                let tag = mesh.ct.tag(c);
                let Ok(Some(nv)) = mesh.ct.insert_if(centre, c, |ct, cell| ct.tag(cell) == tag)
                else {
                    continue; // outside the region, beyond the range, or refused
                };
                mesh.set_interior_spacing(nv, spacing);
                next.extend_from_slice(mesh.ct.last_new_cells());
                inserted += 1;
                added += 1;
            }
            if inserted == 0 {
                break;
            }
            next.sort_unstable();
            next.dedup();
            std::mem::swap(&mut cells, &mut next);
        }
        Ok(added)
    }
}
