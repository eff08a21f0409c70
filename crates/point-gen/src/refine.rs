//! Quality refinement, beyond the paper: elements whose smallest angle is below a bound get a
//! point at their circumcentre (Delaunay refinement, as in Ruppert's and Chew's algorithms),
//! in passes, after automatic point generation.
//!
//! The α criterion spaces points well but says nothing about angles where the spacing changes
//! fast (a narrow gap between two bodies, a trailing edge): a few skinny elements remain. A
//! circumcentre insertion removes a skinny element and, by the Delaunay property, cannot make
//! a smaller circumcircle than the one it removed, so the process ends for bounds up to about
//! 30°. Circumcentres outside the element's region or on a boundary edge are refused (the
//! boundary is never crossed), so elements at sharp boundary corners stay as they are; a cap
//! on the points added keeps any run bounded.
//!
//! After the first pass only the elements changed since the previous pass began are looked at
//! again: an unchanged element is still skinny and its circumcentre still refused (regions,
//! the hull and the vertices it could coincide with do not change), so the passes insert
//! exactly what a full scan would, in the same order.

use delmesh_boundary_recovery::{Mesh2, OUTSIDE};
use delmesh_delaunay_core::{Insertion, VertexId};

use crate::generate::{elements_where, set, PointGenError};

/// Settings of quality refinement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QualityRefinement {
    /// Elements with a smaller angle (degrees) are refined.
    pub min_angle: f64,
    /// Passes at most.
    pub max_passes: usize,
    /// Points added at most, as a fraction of the vertices at the start.
    pub max_growth: f64,
}

impl Default for QualityRefinement {
    fn default() -> Self {
        QualityRefinement {
            min_angle: 28.0,
            max_passes: 12,
            max_growth: 0.25,
        }
    }
}

impl QualityRefinement {
    /// Refines `mesh`; returns the number of points added. New nodes get the mean spacing of
    /// the refined element's nodes.
    ///
    /// # Errors
    /// Only if an insertion fails, which would be a bug.
    pub fn run(&self, mesh: &mut Mesh2) -> Result<usize, PointGenError> {
        self.run_capped(mesh, usize::MAX)
    }

    /// [`Self::run`], adding at most `max_points` points (what is left of a run's budget).
    ///
    /// # Errors
    /// As [`Self::run`].
    pub fn run_capped(&self, mesh: &mut Mesh2, max_points: usize) -> Result<usize, PointGenError> {
        let bound = self.min_angle.to_radians().sin();
        let cap = ((mesh.cdt.triangulation().num_vertices() as f64 * self.max_growth) as usize)
            .min(max_points);
        let mut added = 0;
        let skinny = |mesh: &Mesh2, c| {
            let tri = mesh.cdt.triangulation();
            let v = tri.cell(c);
            min_sine([tri.vertex(v[0]), tri.vertex(v[1]), tri.vertex(v[2])]) < bound
        };
        // All elements first, then those the previous pass changed, in slot order.
        let mut bad = elements_where(mesh, |c| skinny(mesh, c));
        for pass in 0..self.max_passes {
            if pass > 0 {
                bad = mesh.cdt.take_changed();
                bad.sort_unstable();
                bad.retain(|&c| mesh.is_element(c) && skinny(mesh, c));
            }
            mesh.cdt.next_epoch(true);
            let mut inserted = 0;
            for &c in &bad {
                if added >= cap {
                    return Ok(added);
                }
                let tri = mesh.cdt.triangulation();
                let tag = mesh.cdt.tag(c);
                let v: [VertexId; 3] = std::array::from_fn(|k| tri.cell(c)[k]);
                if tag == OUTSIDE || v.iter().any(|u| u.is_ghost()) {
                    continue;
                }
                let p = [tri.vertex(v[0]), tri.vertex(v[1]), tri.vertex(v[2])];
                // Still the same, still skinny? (An earlier insertion may have removed it.)
                if min_sine(p) >= bound {
                    continue;
                }
                let Some(centre) = circumcentre(p) else {
                    continue;
                };
                let spacing = v
                    .iter()
                    .map(|u| mesh.spacing.get(u.index()).copied().unwrap_or(f64::NAN))
                    .sum::<f64>()
                    / 3.0;
                let worst = min_sine(p);
                // Only a circumcentre the element sees is tried: behind a boundary edge it
                // could not remove the element (and the walk there could cross the mesh).
                let result = mesh.cdt.insert_visible_if(centre, c, |cdt, cell, on_edge| {
                    cdt.tag(cell) == tag
                        && on_edge.is_none_or(|i| !cdt.is_constrained(cell, i))
                        && !worse_on_boundary(cdt.triangulation(), cell, centre, worst, |i| {
                            cdt.is_constrained(cell, i)
                        })
                });
                match result {
                    Ok(Some(Insertion::Inserted(nv))) => {
                        set(&mut mesh.spacing, nv, spacing);
                        inserted += 1;
                        added += 1;
                    }
                    // (Also a circumcentre beyond the convex hull: refused like one outside.)
                    Ok(_) => {}
                    Err(e) => return Err(e.into()),
                }
            }
            if inserted == 0 {
                break;
            }
        }
        Ok(added)
    }
}

/// The sine of a triangle's smallest angle: twice its area over the product of the two longer
/// edges.
fn min_sine(p: [[f64; 2]; 3]) -> f64 {
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let (e0, e1, e2) = (d(p[1], p[2]), d(p[2], p[0]), d(p[0], p[1]));
    let twice_area =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    // Squared lengths of ordinary scales: their product neither overflows nor underflows.
    if [e0, e1, e2].iter().all(|&e| e > 1e-90 && e < 1e90) {
        let shortest = e0.min(e1).min(e2);
        return twice_area / (e0 * e1 * e2 / shortest).sqrt();
    }
    // Otherwise the two longer lengths one at a time (the area may still be 0 or infinite at
    // the very ends of the range, which reads as skinny or not, never as NaN).
    let mut l = [e0, e1, e2].map(f64::sqrt);
    l.sort_unstable_by(f64::total_cmp);
    twice_area / l[2] / l[1]
}

/// Whether the point `q`, in cell `cell`, would make a triangle with a boundary edge of the
/// cell (`constrained(i)` for the edge opposite corner `i`) whose smallest angle is smaller
/// than `worst`'s sine, the refined element's: such an edge is on the boundary of the point's
/// cavity, so the triangle is made. A circumcentre that rounding put a hair off a boundary
/// edge (the right angle of a triangle on it puts it on the edge's midpoint) made a triangle of
/// area 1e-13 and a 180° angle there.
fn worse_on_boundary(
    tri: &delmesh_delaunay_core::Triangulation<delmesh_delaunay_core::D2>,
    cell: delmesh_delaunay_core::CellId,
    q: [f64; 2],
    worst: f64,
    constrained: impl Fn(usize) -> bool,
) -> bool {
    let v = tri.cell(cell);
    (0..3).any(|i| {
        constrained(i) && {
            let (a, b) = (v[(i + 1) % 3], v[(i + 2) % 3]);
            !a.is_ghost()
                && !b.is_ghost()
                && min_sine([q, tri.vertex(a), tri.vertex(b)]).abs() < worst
        }
    })
}

/// The circumcentre of a triangle, if it is finite.
fn circumcentre(p: [[f64; 2]; 3]) -> Option<[f64; 2]> {
    let (bx, by) = (p[1][0] - p[0][0], p[1][1] - p[0][1]);
    let (cx, cy) = (p[2][0] - p[0][0], p[2][1] - p[0][1]);
    let d = 2.0 * (bx * cy - by * cx);
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    let c = [
        p[0][0] + (cy * b2 - by * c2) / d,
        p[0][1] + (bx * c2 - cx * b2) / d,
    ];
    (c[0].is_finite() && c[1].is_finite()).then_some(c)
}

#[cfg(test)]
mod tests {
    use super::min_sine;

    #[test]
    fn min_sine_does_not_depend_on_the_scale() {
        // A 30°-60°-90° triangle: the smallest angle's sine is 1/2 at every scale.
        let t = [[0.0, 0.0], [3f64.sqrt(), 0.0], [0.0, 1.0]];
        for e in [-140, -90, -60, -30, 0, 30, 60, 90, 140] {
            let s = 10f64.powi(e);
            let p = t.map(|q| q.map(|x| x * s));
            assert!(
                (min_sine(p) - 0.5).abs() < 1e-12,
                "scale 1e{e}: {}",
                min_sine(p)
            );
        }
    }
}
