//! Index newtypes: vertices, cells (simplices) and facets of cells.
//!
//! All are `u32` so that the flat arrays of the triangulation stay small. A [`FacetRef`] packs a
//! cell and one of its local facets (`cell << 2 | facet`), so "the facet of my neighbour that
//! faces me" is one load, as in the paper's neighbour lists but with the opposite facet included.

use std::fmt;

/// A vertex of the triangulation (an inserted, distinct input point).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[repr(transparent)]
pub struct VertexId(pub u32);

impl VertexId {
    /// The ghost (infinite) vertex that closes the convex hull: every hull facet forms a
    /// ghost cell with it.
    pub const GHOST: VertexId = VertexId(u32::MAX);
    /// Marks a cell slot that is on the free list (never visible through the public API).
    pub(crate) const DEAD: VertexId = VertexId(u32::MAX - 1);

    /// The vertex's position in the triangulation's vertex arrays.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }

    /// True for [`VertexId::GHOST`].
    #[inline]
    pub fn is_ghost(self) -> bool {
        self == VertexId::GHOST
    }
}

impl fmt::Debug for VertexId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_ghost() {
            write!(f, "v∞")
        } else {
            write!(f, "v{}", self.0)
        }
    }
}

/// A cell: a triangle in 2D, a tetrahedron in 3D (a Voronoi vertex in the paper's terms).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[repr(transparent)]
pub struct CellId(pub u32);

impl CellId {
    /// The cell's position in the triangulation's cell arrays.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Debug for CellId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "c{}", self.0)
    }
}

/// Facet `facet` of cell `cell`: the facet opposite the cell's local vertex `facet`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
#[repr(transparent)]
pub struct FacetRef(pub u32);

impl FacetRef {
    /// Not a facet: used only while a cell's neighbours are being linked.
    pub(crate) const NONE: FacetRef = FacetRef(u32::MAX);

    /// Packs a cell and a local facet index (0..=3).
    #[inline]
    pub fn new(cell: CellId, facet: usize) -> FacetRef {
        debug_assert!(facet < 4 && cell.0 < (1 << 30));
        FacetRef(cell.0 << 2 | facet as u32)
    }

    /// The cell.
    #[inline]
    pub fn cell(self) -> CellId {
        CellId(self.0 >> 2)
    }

    /// The local facet index, which is also the local index of the vertex opposite the facet.
    #[inline]
    pub fn facet(self) -> usize {
        (self.0 & 3) as usize
    }
}

impl fmt::Debug for FacetRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "c{}.f{}", self.0 >> 2, self.0 & 3)
    }
}
