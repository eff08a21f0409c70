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
        out.clear();
        if v.is_ghost() || v.index() >= tri.num_vertices() {
            return;
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
    }
}
