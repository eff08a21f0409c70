//! Taking slivers out of a finished tetrahedral mesh by flips (beyond the paper).
//!
//! A Delaunay tetrahedralisation keeps slivers: four nearly coplanar points whose circumsphere
//! is empty, so no Delaunay flip removes them, and Laplacian smoothing, which moves points
//! one at a time, rarely does. Here each element whose quality is below a threshold is
//! looked at, and the flips around it are tried:
//! - removing one of its six edges: the cells around the edge are replaced by a fan of the
//!   ring of vertices around it (a 3-2 flip for three cells, 4-4 for four, n-m beyond);
//! - removing one of its four faces by a 2-3 flip with the cell across it.
//!
//! A flip is made only if the worst quality of the cells it makes is strictly better than the
//! worst of the cells it replaces, so no element gets worse than what was there and the
//! flips end (each one raises the sorted list of qualities). Flips never remove a protected
//! face, never join cells of different tags and add no vertex; every new cell is checked to
//! be strictly positive with exact orientation tests. The mesh is no longer Delaunay where a
//! flip was made.

use crate::constrained3::ConstrainedTriangulation3;
use crate::ids::{CellId, VertexId};
use delmesh_predicates::Sign;

/// Cells around an edge beyond which its removal is not tried (the fans get poor).
const MAX_RING: usize = 7;

/// What [`ConstrainedTriangulation3::improve_by_flips`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Improvement3 {
    /// Elements below the threshold before.
    pub below_before: usize,
    /// Elements below the threshold after.
    pub below_after: usize,
    /// Edges removed (3-2, 4-4 and n-m flips).
    pub edge_flips: usize,
    /// Faces removed (2-3 flips).
    pub face_flips: usize,
}

impl ConstrainedTriangulation3 {
    /// Flips away the elements whose tag is in scope and whose `quality` (larger is better,
    /// computed from the four vertices' coordinates, invariant under scaling) is below
    /// `threshold`, as the module docs say, in at most `max_passes` passes.
    pub fn improve_by_flips(
        &mut self,
        threshold: f64,
        quality: impl Fn(&[[f64; 3]; 4]) -> f64,
        in_scope: impl Fn(u32) -> bool,
        max_passes: usize,
    ) -> Improvement3 {
        let q = |cdt: &Self, v: &[VertexId; 4]| quality(&v.map(|u| cdt.tri.points[u.index()]));
        let is_bad = |cdt: &Self, c: CellId| {
            let v = cdt.tri.simplices[c.index()].v;
            v[0] != VertexId::DEAD
                && !v.contains(&VertexId::GHOST)
                && in_scope(cdt.tags[c.index()])
                && q(cdt, &v) < threshold
        };
        let all_bad = |cdt: &Self| -> Vec<CellId> {
            (0..cdt.tri.simplices.len() as u32)
                .map(CellId)
                .filter(|&c| is_bad(cdt, c))
                .collect()
        };
        let mut report = Improvement3::default();
        let mut bad = all_bad(self);
        report.below_before = bad.len();
        let mut ring = Vec::new();
        let mut made = Vec::new();
        for _ in 0..max_passes {
            made.clear();
            for &c in &bad {
                // Gone, or changed into a better cell by an earlier flip of this pass.
                if !is_bad(self, c) {
                    continue;
                }
                let v = self.tri.simplices[c.index()].v;
                if self.remove_an_edge(c, &v, &q, &mut ring, &mut made) {
                    report.edge_flips += 1;
                } else if self.remove_a_face(c, &q, &mut made) {
                    report.face_flips += 1;
                }
            }
            if made.is_empty() {
                break;
            }
            // Only where flips made new cells can a flip that failed now succeed: the new
            // cells and their neighbours are looked at again.
            let mut next = Vec::with_capacity(5 * made.len());
            for &c in &made {
                if self.tri.is_live(c) {
                    next.push(c);
                    next.extend((0..4).map(|i| self.tri.simplices[c.index()].n[i].cell()));
                }
            }
            next.sort_unstable();
            next.dedup();
            next.retain(|&c| is_bad(self, c));
            bad = next;
        }
        report.below_after = all_bad(self).len();
        report
    }

    /// Removes one of the six edges of the cell `c` (vertices `v`) if that improves the worst cell around it.
    fn remove_an_edge(
        &mut self,
        c: CellId,
        v: &[VertexId; 4],
        q: &impl Fn(&Self, &[VertexId; 4]) -> f64,
        ring: &mut Vec<(CellId, VertexId, VertexId)>,
        made: &mut Vec<CellId>,
    ) -> bool {
        for (a, b) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
            let (p, r) = (v[a], v[b]);
            if !self.edge_ring_at(c, p, r, ring)
                || ring.len() > MAX_RING
                || ring.iter().any(|x| x.1.is_ghost())
            {
                continue;
            }
            let tag = self.tags[ring[0].0.index()];
            if ring.iter().any(|x| self.tags[x.0.index()] != tag) {
                continue;
            }
            let worst = ring
                .iter()
                .map(|x| q(self, &self.tri.simplices[x.0.index()].v))
                .fold(f64::INFINITY, f64::min);
            let better = |cdt: &Self, new: &[[VertexId; 4]]| new.iter().all(|m| q(cdt, m) > worst);
            if let Some((_, _, cells)) = self.flip_nm(p, r, ring, &[], better) {
                made.extend(cells);
                return true;
            }
        }
        false
    }

    /// Removes one of the four faces of cell `c` by a 2-3 flip, if that improves the worse of
    /// the two cells.
    fn remove_a_face(
        &mut self,
        c: CellId,
        q: &impl Fn(&Self, &[VertexId; 4]) -> f64,
        made: &mut Vec<CellId>,
    ) -> bool {
        let v = self.tri.simplices[c.index()].v;
        for i in 0..4 {
            let m = self.tri.simplices[c.index()].n[i].cell();
            let mv = self.tri.simplices[m.index()].v;
            if self.is_protected(c, i)
                || mv.contains(&VertexId::GHOST)
                || self.tags[m.index()] != self.tags[c.index()]
            {
                continue;
            }
            // The apex of m across the face: the vertex of m not in c.
            let Some(&e) = mv.iter().find(|u| !v.contains(u)) else {
                continue;
            };
            // The three new cells: c with each vertex of the face in turn replaced by e.
            let new: Vec<[VertexId; 4]> = (0..4)
                .filter(|&k| k != i)
                .map(|k| {
                    let mut n = v;
                    n[k] = e;
                    n
                })
                .collect();
            if new.iter().any(|&n| self.orient(n) != Sign::Positive) {
                continue;
            }
            let worst = q(self, &v).min(q(self, &mv));
            if new.iter().any(|n| q(self, n) <= worst) {
                continue;
            }
            if let Some(cells) = self.replace_cells(&[c, m], &new) {
                made.extend(cells);
                return true;
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Triangulation;

    /// Minus the cosine of the smallest dihedral angle (larger is better).
    fn quality(p: &[[f64; 3]; 4]) -> f64 {
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        // Normals of the faces opposite each vertex, all pointing inwards.
        let n: Vec<[f64; 3]> = (0..4)
            .map(|k| {
                let f: Vec<[f64; 3]> = (0..4).filter(|&i| i != k).map(|i| p[i]).collect();
                let mut n = cross(sub(f[1], f[0]), sub(f[2], f[0]));
                if dot(n, sub(p[k], f[0])) < 0.0 {
                    n = n.map(|x| -x);
                }
                let l = dot(n, n).sqrt();
                n.map(|x| x / l)
            })
            .collect();
        let mut worst = -1.0f64;
        for i in 0..4 {
            for j in i + 1..4 {
                worst = worst.max(-dot(n[i], n[j]));
            }
        }
        -worst
    }

    #[test]
    fn slivers_of_a_jittered_grid_are_flipped_away_and_nothing_gets_worse() {
        // Points of a grid jittered a little: Delaunay keeps slivers among the nearly
        // co-spherical grid cubes' corners.
        let mut pts = Vec::new();
        for i in 0..6 {
            for j in 0..6 {
                for k in 0..6 {
                    let h = |s: u32| ((i * 7 + j * 13 + k * 29 + s) % 17) as f64 * 0.002;
                    pts.push([i as f64 + h(0), j as f64 + h(5), k as f64 + h(11)]);
                }
            }
        }
        let mut ct = ConstrainedTriangulation3::new(Triangulation::new(&pts).unwrap());
        let finite = |ct: &ConstrainedTriangulation3| -> Vec<[VertexId; 4]> {
            ct.triangulation()
                .cells()
                .map(|c| {
                    let v = ct.triangulation().cell(c);
                    [v[0], v[1], v[2], v[3]]
                })
                .collect()
        };
        let q_of = |ct: &ConstrainedTriangulation3, v: &[VertexId; 4]| {
            quality(&v.map(|u| ct.triangulation().vertex(u)))
        };
        let worst = |ct: &ConstrainedTriangulation3| {
            finite(ct)
                .iter()
                .map(|v| q_of(ct, v))
                .fold(f64::INFINITY, f64::min)
        };
        let threshold = -(15f64.to_radians().cos());
        let worst_before = worst(&ct);
        assert!(worst_before < threshold, "the grid has slivers");
        let r = ct.improve_by_flips(threshold, quality, |_| true, 8);
        assert!(
            r.below_before > 0 && r.edge_flips + r.face_flips > 0,
            "{r:?}"
        );
        assert!(r.below_after < r.below_before, "{r:?}");
        // (The worst cells lie flat on the hull, where no flip is tried.)
        assert!(worst(&ct) >= worst_before);
        ct.validate_structure().unwrap();
        // The same convex hull's volume (the hull cells are untouched: ghosts are skipped).
        let volume = |ct: &ConstrainedTriangulation3| -> f64 {
            finite(ct)
                .iter()
                .map(|v| {
                    let p = v.map(|u| ct.triangulation().vertex(u));
                    let d = |i: usize| [0, 1, 2].map(|k| p[i][k] - p[0][k]);
                    let (a, b, c) = (d(1), d(2), d(3));
                    (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                        + a[2] * (b[0] * c[1] - b[1] * c[0]))
                        / 6.0
                })
                .sum()
        };
        let fresh = ConstrainedTriangulation3::new(Triangulation::new(&pts).unwrap());
        assert!((volume(&ct) - volume(&fresh)).abs() < 1e-9 * volume(&fresh));
    }
}
