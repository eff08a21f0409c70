//! Regional volume limits in 3D (TetGen's `-a` with the maximum volumes of a `.poly` or
//! `.smesh` file's regions): every tetrahedron larger than its region's limit gets a point at
//! its centroid, in passes, until none is left.
//!
//! Generation fills a region with a limit at about that volume (its spacing is capped at
//! [`spacing_for_volume`], see [`crate::PointGeneration3::run_capped`]), so these passes add
//! few points; they are what makes the limit a guarantee, run before smoothing and again after
//! the Delaunay restoration (a move changes volumes). The facade splits the surface next to
//! a limited region to its spacing first (the tetrahedra on a large surface triangle would
//! be flat).
//! A centroid lies inside its tetrahedron, a quarter of a height from each face, and every
//! height of a tetrahedron of volume above `V` in a domain of diameter `D` is above `6V/D²`:
//! each point added is farther than `3V/(2D²)` from every other, so the passes end. The
//! insertion is the refinement's (its cavity never crosses a boundary face and must be
//! star-shaped; after the restoration, it must keep the mesh Delaunay too). Where the mesh
//! need not stay Delaunay (before the restoration, and in a constrained recovery's mesh) a
//! refused centroid splits its tetrahedron in four instead; elsewhere it leaves it as it is.

use delmesh_boundary_recovery::{Mesh3, OUTSIDE};
use delmesh_delaunay_core::CellId;

/// The spacing that fills a region with tetrahedra no larger than `volume`: 0.6 of the edge
/// of the regular tetrahedron of that volume. Measured on a unit cube limited to 1e-4 (its
/// surface split to the same spacing): at 0.5, 33,697 tetrahedra; at 0.6, 20,918, of which
/// 188 centroids; at 0.7, 1,092 centroids; at the whole edge, 2,768 and more slivers.
pub fn spacing_for_volume(volume: f64) -> f64 {
    0.6 * (6.0 * std::f64::consts::SQRT_2 * volume).cbrt()
}

/// The volume limit of each region (by region index, as tetrahedra are tagged; infinite where
/// there is none): `delmesh_boundary_recovery::Plc3::volume_limits`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VolumeLimits {
    limits: Vec<f64>,
}

impl VolumeLimits {
    /// Limits by region index.
    pub fn new(limits: Vec<f64>) -> Self {
        VolumeLimits { limits }
    }

    /// The spacing cap of each region, for [`crate::PointGeneration3::run_capped`].
    pub fn spacing_caps(&self) -> Vec<f64> {
        self.limits.iter().map(|&v| spacing_for_volume(v)).collect()
    }

    /// The region that asks for the most tetrahedra, with its volume in `mesh` and the count
    /// it asks for (its volume over its limit), if all regions together ask for more than
    /// `most`.
    pub fn asking_too_much(&self, mesh: &Mesh3, most: f64) -> Option<(usize, f64, f64)> {
        let mut volume = vec![0.0; self.limits.len()];
        for c in mesh.elements() {
            if let Some(v) = volume.get_mut(mesh.ct.tag(c) as usize) {
                *v += tet_volume(points(mesh, c));
            }
        }
        let need: Vec<f64> = volume
            .iter()
            .zip(&self.limits)
            .map(|(v, l)| v / l)
            .collect();
        if need.iter().sum::<f64>() <= most {
            return None;
        }
        let tag = (0..need.len()).max_by(|&i, &j| need[i].total_cmp(&need[j]))?;
        Some((tag, volume[tag], need[tag]))
    }

    /// How many tetrahedra of `mesh` are larger than their region's limit (after [`Self::run`]:
    /// those whose centroid would have broken the Delaunay property it was asked to keep).
    pub fn exceeding(&self, mesh: &Mesh3) -> usize {
        mesh.elements().filter(|&c| self.exceeded(mesh, c)).count()
    }

    fn exceeded(&self, mesh: &Mesh3, c: CellId) -> bool {
        let limit = self
            .limits
            .get(mesh.ct.tag(c) as usize)
            .copied()
            .unwrap_or(f64::INFINITY);
        limit.is_finite() && tet_volume(points(mesh, c)) > limit
    }

    /// Splits every tetrahedron of `mesh` larger than its region's limit at its centroid,
    /// until none is or `max_points` have been added (see the module docs); with
    /// `keep_delaunay`, only where the mesh stays Delaunay. Returns the number of points added;
    /// new nodes get the mean spacing of the split tetrahedron's nodes.
    pub fn run(&self, mesh: &mut Mesh3, max_points: usize, keep_delaunay: bool) -> usize {
        if !self.limits.iter().any(|v| v.is_finite()) {
            return 0;
        }
        let mut todo: Vec<CellId> = mesh
            .elements()
            .filter(|&c| self.exceeded(mesh, c))
            .collect();
        let mut added = 0;
        while !todo.is_empty() {
            let mut next = Vec::new();
            for &c in &todo {
                if added >= max_points {
                    return added;
                }
                // A slot an earlier insertion reused may hold another tetrahedron.
                if !mesh.ct.is_live(c) || mesh.ct.tag(c) == OUTSIDE || !self.exceeded(mesh, c) {
                    continue;
                }
                let tri = mesh.ct.triangulation();
                let v = tri.cell(c);
                let corners = [v[0], v[1], v[2], v[3]];
                let p = points(mesh, c);
                let g = [0, 1, 2].map(|k| 0.25 * (p[0][k] + p[1][k] + p[2][k] + p[3][k]));
                let spacing = 0.25 * corners.iter().map(|u| mesh.spacing[u.index()]).sum::<f64>();
                let tag = mesh.ct.tag(c);
                let mut inserted = mesh.ct.insert_if_fine(
                    g,
                    c,
                    |ct, cell| ct.tag(cell) == tag,
                    |_| true,
                    keep_delaunay,
                );
                // Refused (a cavity that is not star-shaped, next to faces a constrained
                // recovery flipped in): where the mesh need not stay Delaunay, the tetrahedron
                // is split in four at its centroid, which is valid in any mesh (the new cells
                // keep its region and its protected faces).
                if matches!(inserted, Ok(None)) && !keep_delaunay {
                    inserted = mesh.ct.insert_splitting(g, corners[0]);
                }
                if let Ok(Some(nv)) = inserted {
                    mesh.set_interior_spacing(nv, spacing);
                    next.extend_from_slice(mesh.ct.last_new_cells());
                    added += 1;
                }
            }
            next.sort_unstable();
            next.dedup();
            next.retain(|&c| {
                mesh.ct.is_live(c) && mesh.ct.tag(c) != OUTSIDE && self.exceeded(mesh, c)
            });
            todo = next;
        }
        added
    }
}

/// The corners of element `c`.
pub(crate) fn points(mesh: &Mesh3, c: CellId) -> [[f64; 3]; 4] {
    let tri = mesh.ct.triangulation();
    let v = tri.cell(c);
    [0, 1, 2, 3].map(|k| tri.vertex(v[k]))
}

/// The volume of a tetrahedron (whatever its orientation).
pub(crate) fn tet_volume(p: [[f64; 3]; 4]) -> f64 {
    delmesh_boundary_recovery::tet_volume(p[0], p[1], p[2], p[3]).abs()
}
