//! [`StarSearch`]: the cells around a vertex, found in time proportional to their number.
//!
//! Boundary recovery asks, for thousands of surface edges and faces per pass, whether they are in
//! the triangulation. Each question is answered from the star of one end vertex (the cells
//! containing it), found by a search over neighbours from the vertex's incident cell. Visited
//! cells are marked with a stamp that changes per search, so nothing is cleared between
//! searches and no search allocates once the buffers have grown.

use crate::dim::Dim;
use crate::ids::{CellId, VertexId};
use crate::triangulation::Triangulation;

/// Reusable marks for star searches over one triangulation.
#[derive(Clone, Debug, Default)]
pub struct StarSearch {
    visited: Vec<u32>,
    stamp: u32,
}

impl StarSearch {
    /// The cells containing `v` (ghost cells included on the hull), in search order, into
    /// `out` (cleared first). Empty for the ghost vertex or an id out of range.
    pub fn star<D: Dim>(&mut self, tri: &Triangulation<D>, v: VertexId, out: &mut Vec<CellId>) {
        self.find(tri, v, out, |_| false);
    }

    /// The first cell of `v`'s star, in search order, whose vertices satisfy `wanted`; the
    /// search stops there (so a present edge or face costs about half a star search). `out`
    /// holds the cells searched (the whole star when none is wanted).
    pub fn find<D: Dim>(
        &mut self,
        tri: &Triangulation<D>,
        v: VertexId,
        out: &mut Vec<CellId>,
        mut wanted: impl FnMut(&[VertexId]) -> bool,
    ) -> Option<CellId> {
        self.find_cell(tri, v, out, |_, cell| wanted(cell))
    }

    /// [`StarSearch::find`] with each cell's id given to `wanted` too.
    pub fn find_cell<D: Dim>(
        &mut self,
        tri: &Triangulation<D>,
        v: VertexId,
        out: &mut Vec<CellId>,
        mut wanted: impl FnMut(CellId, &[VertexId]) -> bool,
    ) -> Option<CellId> {
        out.clear();
        if v.is_ghost() || v.index() >= tri.num_vertices() {
            return None;
        }
        if self.visited.len() < tri.simplices.len() {
            self.visited.resize(tri.simplices.len(), 0);
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.visited.fill(0);
            self.stamp = 1;
        }
        let s = self.stamp;
        let first = tri.incident_cell(v);
        self.visited[first.index()] = s;
        out.push(first);
        let mut i = 0;
        while i < out.len() {
            let c = out[i];
            i += 1;
            let cell = &tri.simplices[c.index()];
            if wanted(c, &cell.v[..D::C]) {
                return Some(c);
            }
            for k in 0..D::C {
                if cell.v[k] != v {
                    let n = cell.n[k].cell();
                    if self.visited[n.index()] != s {
                        self.visited[n.index()] = s;
                        out.push(n);
                    }
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Triangulation3;

    #[test]
    fn star_and_find_agree_with_the_cells_around_a_vertex() {
        // A jittered grid: every vertex's star, and every edge found from either end.
        let mut pts = Vec::new();
        for i in 0..5 {
            for j in 0..5 {
                for k in 0..5 {
                    let h = ((i * 31 + j * 17 + k * 7) % 11) as f64 * 0.01;
                    pts.push([i as f64 + h, j as f64 - h, k as f64 + 0.5 * h]);
                }
            }
        }
        let tri = Triangulation3::new(&pts).unwrap();
        let mut search = StarSearch::default();
        let mut out = Vec::new();
        for v in 0..tri.num_vertices() as u32 {
            let v = VertexId(v);
            search.star(&tri, v, &mut out);
            let mut got = out.clone();
            got.sort_unstable();
            let mut want = tri.cells_around_vertex(v);
            want.sort_unstable();
            assert_eq!(got, want, "star of {v:?}");
            for &c in &want {
                for &u in tri.cell(c) {
                    let found = search.find(&tri, v, &mut out, |cell| cell.contains(&u));
                    let c = found.expect("a neighbour is found");
                    assert!(tri.cell(c).contains(&u) && tri.cell(c).contains(&v));
                    assert!(out.len() <= want.len());
                }
            }
            let absent = search.find(&tri, v, &mut out, |_| false);
            assert!(absent.is_none() && out.len() == want.len());
        }
    }
}
