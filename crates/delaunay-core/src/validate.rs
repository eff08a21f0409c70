//! [`Triangulation::validate`]: every invariant of the structure, checked exactly.
//!
//! Local Delaunay-ness of every facet implies the global empty-circumsphere property (Delaunay's
//! lemma), so checking each cell against the vertex opposite each of its facets, with the same
//! perturbed predicate the insertion used, proves the whole triangulation Delaunay.

use crate::dim::Dim;
use crate::error::ValidationError;
use crate::ids::{CellId, VertexId};
use crate::triangulation::Triangulation;
use delmesh_predicates::Sign;
use std::collections::HashSet;

impl<D: Dim> Triangulation<D> {
    /// Checks neighbour symmetry and shared facets, positive orientation of every finite cell,
    /// the empty-circumsphere property (exact, with the symbolic perturbation), vertex
    /// incidence, and Euler's relation for a triangulated convex polygon / polyhedron.
    ///
    /// # Errors
    /// The first broken invariant found (which would be a bug in delmesh).
    pub fn validate(&self) -> Result<(), ValidationError> {
        self.validate_skipping(|_, _| false)
    }

    /// [`Triangulation::validate`] with the Delaunay test waived across the facets for which
    /// `waived(cell, facet)` is true (constrained edges).
    pub(crate) fn validate_skipping(
        &self,
        waived: impl Fn(CellId, usize) -> bool,
    ) -> Result<(), ValidationError> {
        let n = self.num_vertices();
        let mut n_finite = 0usize;
        let mut n_ghost = 0usize;
        for c in self.all_cells() {
            let verts = self.cell(c);
            let ghosts = verts.iter().filter(|v| v.is_ghost()).count();
            if ghosts > 1 || verts.iter().any(|v| !v.is_ghost() && v.index() >= n) {
                return Err(ValidationError::BadCell { cell: c.0 });
            }
            if ghosts == 0 {
                n_finite += 1;
                let pts: Vec<D::Point> = verts.iter().map(|&v| self.point(v)).collect();
                if D::orient(&pts) != Sign::Positive {
                    return Err(ValidationError::Orientation { cell: c.0 });
                }
            } else {
                n_ghost += 1;
            }
            for f in 0..D::C {
                let across = self.neighbor_facet(c, f);
                let m = across.cell();
                if m.index() >= self.simplices.len()
                    || self.simplices[m.index()].v[0] == VertexId::DEAD
                {
                    return Err(ValidationError::AsymmetricNeighbor {
                        cell: c.0,
                        facet: f,
                    });
                }
                if self.neighbor_facet(m, across.facet()) != crate::FacetRef::new(c, f) {
                    return Err(ValidationError::AsymmetricNeighbor {
                        cell: c.0,
                        facet: f,
                    });
                }
                let mut mine: Vec<VertexId> =
                    (0..D::C).filter(|&k| k != f).map(|k| verts[k]).collect();
                let theirs_all = self.cell(m);
                let mut theirs: Vec<VertexId> = (0..D::C)
                    .filter(|&k| k != across.facet())
                    .map(|k| theirs_all[k])
                    .collect();
                mine.sort_unstable();
                theirs.sort_unstable();
                if mine != theirs {
                    return Err(ValidationError::FacetMismatch {
                        cell: c.0,
                        other: m.0,
                    });
                }
                let opposite = theirs_all[across.facet()];
                if !opposite.is_ghost() && !waived(c, f) && self.vertex_in_conflict(c, opposite) {
                    return Err(ValidationError::NotDelaunay {
                        cell: c.0,
                        vertex: opposite.0,
                    });
                }
            }
        }
        for v in 0..n {
            let c = self.incident_cell(VertexId(v as u32));
            if c.index() >= self.simplices.len() || !self.cell(c).contains(&VertexId(v as u32)) {
                return Err(ValidationError::Incidence { vertex: v as u32 });
            }
        }
        if self.ghosts != n_ghost || self.num_cells() != n_finite {
            return Err(ValidationError::Euler(format!(
                "{n_finite} finite and {n_ghost} hull cells, counted as {} and {}",
                self.num_cells(),
                self.ghosts
            )));
        }
        self.check_euler(n, n_finite, n_ghost)
    }

    fn check_euler(&self, n: usize, n_finite: usize, n_hull: usize) -> Result<(), ValidationError> {
        if D::N == 2 {
            // A triangulated convex polygon with h hull edges: T = 2V − 2 − h.
            if n_finite + 2 + n_hull != 2 * n {
                return Err(ValidationError::Euler(format!(
                    "{n_finite} triangles, {n} vertices, {n_hull} hull edges: expected T = 2V - 2 - h"
                )));
            }
            return Ok(());
        }
        // A triangulated ball: V − E + F − T = 1.
        let mut edges: HashSet<(VertexId, VertexId)> = HashSet::new();
        for c in self.cells() {
            let v = self.cell(c);
            for i in 0..D::C {
                for j in i + 1..D::C {
                    edges.insert((v[i].min(v[j]), v[i].max(v[j])));
                }
            }
        }
        let faces = (4 * n_finite + n_hull) / 2;
        let chi = n as i64 - edges.len() as i64 + faces as i64 - n_finite as i64;
        if chi != 1 || (4 * n_finite + n_hull) % 2 != 0 {
            return Err(ValidationError::Euler(format!(
                "V={n} E={} F={faces} T={n_finite}: V - E + F - T = {chi}, expected 1",
                edges.len()
            )));
        }
        Ok(())
    }

    /// Brute-force check for tests on small inputs: no vertex is in conflict with any cell.
    /// Quadratic; [`Triangulation::validate`] proves the same through Delaunay's lemma.
    pub fn validate_globally(&self) -> Result<(), ValidationError> {
        let cells: Vec<CellId> = self.all_cells().collect();
        for c in cells {
            for v in 0..self.num_vertices() as u32 {
                let v = VertexId(v);
                if !self.cell(c).contains(&v) && self.vertex_in_conflict(c, v) {
                    return Err(ValidationError::NotDelaunay {
                        cell: c.0,
                        vertex: v.0,
                    });
                }
            }
        }
        Ok(())
    }
}
