//! Renumbering a triangulation in space-filling-curve order, for memory locality.
//!
//! Incremental insertion numbers vertices and cells in the order they were made. When points
//! are added in passes over the whole domain (automatic point generation), that order jumps
//! across the domain from pass to pass: after generation, neighbouring cells and the vertices
//! of one cell sit far apart in memory, and every later sweep over the mesh misses the cache
//! on most reads. [`Triangulation::renumber`] numbers the vertices along a Hilbert curve and
//! the cells by their smallest new vertex number, dropping free slots. Nothing geometric
//! changes: the same cells with the same neighbours, under new numbers.

use crate::dim::Dim;
use crate::ids::{CellId, FacetRef, VertexId};
use crate::sort::hilbert_order;
use crate::triangulation::Triangulation;
use rayon::prelude::*;

/// The new numbers given by a renumbering, indexed by the old ones.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Renumbering {
    /// `vertex[old]`: the vertex's new index.
    pub vertex: Vec<u32>,
    /// `cell[old]`: the cell's new index, or `u32::MAX` for a free slot (dropped).
    pub cell: Vec<u32>,
    /// The old index of each new vertex.
    vertex_order: Vec<u32>,
    /// The old slot of each new cell.
    cell_order: Vec<u32>,
}

impl Renumbering {
    /// The new id of vertex `v` ([`VertexId::GHOST`] stays itself).
    #[inline]
    pub fn vertex(&self, v: VertexId) -> VertexId {
        if v.is_ghost() {
            v
        } else {
            VertexId(self.vertex[v.index()])
        }
    }

    /// The new id of cell `c`, or `None` if its slot was free.
    #[inline]
    pub fn cell(&self, c: CellId) -> Option<CellId> {
        match self.cell.get(c.index()) {
            Some(&n) if n != u32::MAX => Some(CellId(n)),
            _ => None,
        }
    }

    /// Renumbers a list of cell ids in place, dropping those whose slot was free.
    pub fn renumber_cells(&self, cells: &mut Vec<CellId>) {
        cells.retain_mut(|c| match self.cell(*c) {
            Some(n) => {
                *c = n;
                true
            }
            None => false,
        });
    }

    /// `values` (one per old cell slot) moved to the new cell numbering; free slots' values
    /// are dropped.
    pub fn permute_cells<T: Copy + Send + Sync>(&self, values: &[T]) -> Vec<T> {
        self.cell_order
            .par_iter()
            .with_min_len(1 << 12)
            .map(|&old| values[old as usize])
            .collect()
    }

    /// `values` (one per old vertex; missing entries are `fill`) moved to the new vertex
    /// numbering.
    pub fn permute_vertices<T: Copy + Send + Sync>(&self, values: &[T], fill: T) -> Vec<T> {
        self.vertex_order
            .par_iter()
            .with_min_len(1 << 12)
            .map(|&old| values.get(old as usize).copied().unwrap_or(fill))
            .collect()
    }
}

impl<D: Dim> Triangulation<D> {
    /// Numbers the vertices along a Hilbert curve and the cells by their smallest new vertex
    /// (ties in old order), dropping free cell slots; returns the new numbers (see the module
    /// docs). Coordinates, adjacency, the input index maps and each vertex's incident cell move
    /// with their vertex or cell.
    pub fn renumber(&mut self) -> Renumbering {
        let nv = self.points.len();
        let vertex_order = hilbert_order::<D>(&self.points);
        let mut vertex = vec![0u32; nv];
        for (new, &old) in vertex_order.iter().enumerate() {
            vertex[old as usize] = new as u32;
        }
        // Cells by their smallest new vertex number, then old slot: a counting sort (ghost
        // cells, which have a finite vertex too, go with it).
        let c_of = D::C;
        let low: Vec<u32> = self
            .simplices
            .par_iter()
            .with_min_len(1 << 12)
            .map(|s| {
                if s.v[0] == VertexId::DEAD {
                    return u32::MAX;
                }
                s.v[..c_of]
                    .iter()
                    .filter(|u| !u.is_ghost())
                    .map(|u| vertex[u.index()])
                    .min()
                    .unwrap_or(u32::MAX)
            })
            .collect();
        let mut start = vec![0u32; nv + 1];
        for &l in &low {
            if l != u32::MAX {
                start[l as usize + 1] += 1;
            }
        }
        for i in 0..nv {
            start[i + 1] += start[i];
        }
        let mut cell_order = vec![0u32; start[nv] as usize];
        for (c, &l) in low.iter().enumerate() {
            if l != u32::MAX {
                cell_order[start[l as usize] as usize] = c as u32;
                start[l as usize] += 1;
            }
        }
        let mut cell = vec![u32::MAX; self.simplices.len()];
        for (new, &old) in cell_order.iter().enumerate() {
            cell[old as usize] = new as u32;
        }
        let map = Renumbering {
            vertex,
            cell,
            vertex_order,
            cell_order,
        };
        let old = std::mem::take(&mut self.simplices);
        self.simplices = map
            .cell_order
            .par_iter()
            .with_min_len(1 << 12)
            .map(|&c| {
                let mut s = old[c as usize];
                for i in 0..c_of {
                    s.v[i] = map.vertex(s.v[i]);
                    let n = s.n[i];
                    s.n[i] = FacetRef::new(CellId(map.cell[n.cell().index()]), n.facet());
                }
                s
            })
            .collect();
        self.free.clear();
        self.mark = vec![0; self.simplices.len()];
        self.points = map.permute_vertices(&self.points, D::Point::default());
        self.input_index = map.permute_vertices(&self.input_index, u32::MAX);
        self.incident = map
            .vertex_order
            .par_iter()
            .with_min_len(1 << 12)
            .map(|&v| map.cell(self.incident[v as usize]).unwrap_or(CellId(0)))
            .collect();
        for v in &mut self.vertex_of_input {
            *v = map.vertex(*v);
        }
        self.local = vec![u32::MAX; nv];
        self.last = map.cell(self.last).unwrap_or(CellId(0));
        self.cavity = Default::default();
        map
    }
}
