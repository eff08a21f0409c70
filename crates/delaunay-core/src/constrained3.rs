//! [`ConstrainedTriangulation3`]: a 3D Delaunay triangulation with protected faces and a tag per
//! cell, for mesh generation after the boundary has been recovered.
//!
//! Once boundary recovery has made every surface triangle a face of the Delaunay
//! tetrahedralisation, the paper's point generation (R10) inserts field points inside the domain
//! and must never destroy a recovered face. Here those faces are *protected*: a Bowyer–Watson
//! cavity never grows across them, so a protected face either stays as it is or is rebuilt, as a
//! cavity boundary facet, joined to the new point. A point whose cavity is not star-shaped from
//! it (which a non-convex boundary can cause) is refused instead of inserted.
//!
//! The result is always a valid, boundary-conforming tetrahedralisation, but next to protected
//! faces it is not always constrained Delaunay: where a cavity fills the wedge between two
//! protected faces at their edge, the two new cells on them share a face that can fail the
//! insphere test. Refusing such points refuses most candidates near the boundary early on
//! (later insertions usually mend those faces; the paper met the same problem: 725 rejected
//! points on its double ellipsoid). The 3D pipeline instead restores the property at the end,
//! by flips ([`Self::make_delaunay`], module `flip3`) and, where flips cannot mend a face,
//! by splitting an edge ([`Self::split_edge`]). [`Self::validate`] checks the constrained
//! Delaunay property (true right after recovery); [`Self::validate_structure`] everything
//! else.
//!
//! Each cell carries a `u32` tag (mesh generation's region); new cells take the tag of the cell
//! the point was found in, which is the cavity's, since cavities never leave a region.

use crate::dim::D3;
use crate::error::{TriangulationError, ValidationError};
use crate::flip_in3::Flip;
use crate::ids::{CellId, FacetRef, VertexId};
use crate::star::StarSearch;
use crate::triangulation::{Insertion, Location, Triangulation};

/// A 3D triangulation with protected faces and a tag per cell.
///
/// Build it from a [`Triangulation`] (`D3`) with [`ConstrainedTriangulation3::new`], protect the
/// recovered boundary faces ([`Self::protect_face`]), tag the cells, then insert points with
/// [`Self::insert_if`].
#[derive(Clone, Debug)]
pub struct ConstrainedTriangulation3 {
    pub(crate) tri: Triangulation<D3>,
    /// Per cell slot, bit `i`: the face opposite local vertex `i` is protected.
    pub(crate) protected: Vec<u8>,
    /// Per cell slot: the caller's tag.
    pub(crate) tags: Vec<u32>,
    /// Marks for star searches.
    pub(crate) stars: StarSearch,
    /// The flips made by [`Self::flip_in_edge`] and [`Self::flip_in_face`], to undo them.
    pub(crate) flip_log: Vec<Flip>,
    /// Scratch cells for star searches inside flips.
    pub(crate) scratch: Vec<CellId>,
    /// Flips the current flip-in may still make.
    pub(crate) flip_budget: usize,
}

impl ConstrainedTriangulation3 {
    /// Wraps a Delaunay triangulation: nothing protected, every tag 0.
    pub fn new(tri: Triangulation<D3>) -> Self {
        let n = tri.simplices.len();
        ConstrainedTriangulation3 {
            tri,
            protected: vec![0; n],
            tags: vec![0; n],
            stars: StarSearch::default(),
            flip_log: Vec::new(),
            scratch: Vec::new(),
            flip_budget: 0,
        }
    }

    /// Renumbers the vertices and cells for memory locality ([`Triangulation::renumber`]);
    /// protected faces and tags move with their cells. Vertex and cell ids from before the
    /// call do not survive it (input indices do).
    pub fn renumber(&mut self) -> crate::Renumbering {
        let map = self.tri.renumber();
        self.protected = map.permute_cells(&self.protected);
        self.tags = map.permute_cells(&self.tags);
        // (Scratch and the flip log of an attempt are empty between operations.)
        self.flip_log.clear();
        self.scratch.clear();
        self.stars = StarSearch::default();
        map
    }

    /// Changes the caller's units by `2^exponent` ([`Triangulation::rescale_units`]).
    pub fn rescale_units(&mut self, exponent: i32) -> bool {
        self.tri.rescale_units(exponent)
    }

    /// The underlying triangulation (cells, neighbours, vertices, queries).
    pub fn triangulation(&self) -> &Triangulation<D3> {
        &self.tri
    }

    /// Gives the underlying triangulation back, dropping protection and tags.
    pub fn into_triangulation(self) -> Triangulation<D3> {
        self.tri
    }

    /// Whether the face of `c` opposite its local vertex `i` is protected.
    #[inline]
    pub fn is_protected(&self, c: CellId, i: usize) -> bool {
        (self.protected[c.index()] >> i) & 1 != 0
    }

    /// The tag of cell `c`.
    #[inline]
    pub fn tag(&self, c: CellId) -> u32 {
        self.tags[c.index()]
    }

    /// Sets the tag of cell `c`.
    #[inline]
    pub fn set_tag(&mut self, c: CellId, tag: u32) {
        self.tags[c.index()] = tag;
    }

    /// Locates `point` (caller's coordinates): the cell containing it (a ghost cell beyond the
    /// hull) or the vertex at it.
    pub fn locate(&mut self, point: [f64; 3]) -> Location {
        self.tri.locate(point)
    }

    /// The cells containing vertex `v` (ghost cells included on the hull), in search order.
    pub fn star(&mut self, v: VertexId, out: &mut Vec<CellId>) {
        self.stars.star(&self.tri, v, out);
    }

    /// The face `a b c` as a facet of one of the two cells sharing it, or `None` if the three
    /// vertices do not form a face.
    pub fn find_face(&mut self, a: VertexId, b: VertexId, c: VertexId) -> Option<FacetRef> {
        let mut cells = Vec::new();
        self.star(a, &mut cells);
        find_face_in(&self.tri, &cells, a, b, c)
    }

    /// Protects the face `a b c` (on both of its sides). Returns false, changing nothing, if it
    /// is not a face of the triangulation.
    pub fn protect_face(&mut self, a: VertexId, b: VertexId, c: VertexId) -> bool {
        let Some(f) = self.find_face(a, b, c) else {
            return false;
        };
        self.protect(f);
        true
    }

    /// Protects the facet `f` and its twin.
    pub fn protect(&mut self, f: FacetRef) {
        let twin = self.tri.simplices[f.cell().index()].n[f.facet()];
        self.protected[f.cell().index()] |= 1 << f.facet();
        self.protected[twin.cell().index()] |= 1 << twin.facet();
    }

    /// Unprotects the facet `f` and its twin.
    pub fn unprotect(&mut self, f: FacetRef) {
        let twin = self.tri.simplices[f.cell().index()].n[f.facet()];
        self.protected[f.cell().index()] &= !(1 << f.facet());
        self.protected[twin.cell().index()] &= !(1 << twin.facet());
    }

    /// The protected faces, each once, as vertex triples (counter-clockwise seen from the cell
    /// that reports it).
    pub fn protected_faces(&self) -> Vec<[VertexId; 3]> {
        self.protected_facets()
            .into_iter()
            .map(|f| face_vertices(self.tri.cell(f.cell()), f.facet()))
            .collect()
    }

    /// The protected faces, each once, seen from one of their two cells.
    pub fn protected_facets(&self) -> Vec<FacetRef> {
        let mut out = Vec::new();
        for c in self.tri.all_cells() {
            let m = self.protected[c.index()];
            if m == 0 {
                continue;
            }
            for i in 0..4 {
                if (m >> i) & 1 == 0 {
                    continue;
                }
                let twin = self.tri.simplices[c.index()].n[i];
                if (c.0, i) < (twin.cell().0, twin.facet()) {
                    out.push(FacetRef::new(c, i));
                }
            }
        }
        out
    }

    /// Inserts `point` (caller's coordinates) if it lies strictly inside a finite cell `cell`
    /// for which `accept(self, cell)` is true, and its cavity, grown without crossing a
    /// protected face, is star-shaped from it. Returns the new vertex, or `None` (nothing
    /// changed) for a refused point, a point at an existing vertex, or one outside the hull. The
    /// walk starts at `hint`, which may be any cell id seen before (slots of deleted cells are
    /// replaced by the last insertion's cells).
    ///
    /// # Errors
    /// A non-finite coordinate or one outside the range of the triangulation.
    pub fn insert_if(
        &mut self,
        point: [f64; 3],
        hint: CellId,
        accept: impl Fn(&Self, CellId) -> bool,
    ) -> Result<Option<VertexId>, TriangulationError> {
        self.insert_if_fine(point, hint, accept, |_| true, false)
    }

    /// [`Self::insert_if`], refused too if `fine` is false for one of the new cells, given by
    /// its corners (the new point last) in the triangulation's internal units (a power of two
    /// times the caller's: for tests that do not depend on the scale). With `keep_delaunay`,
    /// for a mesh that is Delaunay but across protected faces, refused too if a new cell would
    /// not be Delaunay across a face that is not protected: a cavity that stops at protected
    /// faces is not always the whole conflict region, and the cells built on such a face can
    /// then hold a vertex of the cavity.
    ///
    /// # Errors
    /// A non-finite coordinate or one outside the range of the triangulation.
    pub fn insert_if_fine(
        &mut self,
        point: [f64; 3],
        hint: CellId,
        accept: impl Fn(&Self, CellId) -> bool,
        fine: impl Fn([[f64; 3]; 4]) -> bool,
        keep_delaunay: bool,
    ) -> Result<Option<VertexId>, TriangulationError> {
        let p = self.tri.scaled_input(self.tri.flush_tiny(point))?;
        let hint = if hint.index() < self.tri.simplices.len()
            && self.tri.simplices[hint.index()].v[0] != VertexId::DEAD
        {
            hint
        } else {
            self.tri.last
        };
        let c = match self.tri.locate_from(p, hint) {
            Location::Vertex(_) => return Ok(None),
            Location::Cell(c) => c,
        };
        if self.tri.is_ghost(c) || !accept(self, c) {
            return Ok(None);
        }
        let tag = self.tags[c.index()];
        let input = self.tri.vertex_of_input.len() as u32;
        let protected = &self.protected;
        let Some(v) = self.tri.insert_blocked(
            p,
            input,
            c,
            |f| (protected[f.cell().index()] >> f.facet()) & 1 != 0,
            |points, facet, p| {
                let q = |k: usize| points[facet[k].index()];
                fine([q(0), q(1), q(2), p])
            },
            keep_delaunay,
        ) else {
            return Ok(None);
        };
        let n = self.tri.simplices.len();
        self.protected.resize(n, 0);
        self.tags.resize(n, 0);
        let cavity = &self.tri.cavity;
        for (b, &c) in cavity.boundary.iter().zip(&cavity.new_cells) {
            let apex = b.apex as usize;
            let outside = b.outside;
            let bit = (self.protected[outside.cell().index()] >> outside.facet()) & 1;
            self.protected[c.index()] = bit << apex;
            self.tags[c.index()] = tag;
        }
        Ok(Some(v))
    }

    /// Inserts `point` (caller's coordinates: a point of the edge `x y`, such as its
    /// mid-point) as a new vertex that splits the edge. The cavity holds every cell around the
    /// edge and grows by the insphere test, never across a protected face that does not hold
    /// the edge; each protected face `x y w` becomes the two protected faces `x v w` and
    /// `v y w`. New cells take the tag of the cell they replace. Returns the new vertex and the
    /// third vertex `w` of each protected face split, or `None` (nothing changed) when `x y` is
    /// not an edge, is on the hull, or the cavity is not star-shaped from the point.
    ///
    /// # Errors
    /// A non-finite coordinate or one outside the range of the triangulation.
    pub fn split_edge(
        &mut self,
        x: VertexId,
        y: VertexId,
        point: [f64; 3],
    ) -> Result<Option<(VertexId, Vec<VertexId>)>, TriangulationError> {
        let p = self.tri.scaled_input(self.tri.flush_tiny(point))?;
        let n = self.tri.num_vertices();
        if x == y || x.is_ghost() || y.is_ghost() || x.index() >= n || y.index() >= n {
            return Ok(None);
        }
        let around = self.cells_around_edge(x, y);
        if around.is_empty() || around.iter().any(|&c| self.tri.is_ghost(c)) {
            return Ok(None);
        }
        // The protected faces holding the edge, by their third vertex, and the faces of the
        // cells around the edge that hold it (the cavity crosses those).
        let mut split = Vec::new();
        let mut holding = Vec::new();
        for &c in &around {
            let v = self.tri.simplices[c.index()].v;
            for i in 0..4 {
                if v[i] == x || v[i] == y {
                    continue;
                }
                holding.push(FacetRef::new(c, i));
                if self.is_protected(c, i) {
                    let w = (0..4)
                        .map(|k| v[k])
                        .find(|&u| u != x && u != y && u != v[i])
                        .unwrap_or(VertexId::GHOST);
                    split.push(w);
                }
            }
        }
        split.sort_unstable();
        split.dedup();
        // The cavity must not take every cell around an edge `x w` or `y w` of a split face,
        // or the halves of that face would not be faces: the conflict search does not cross
        // the faces around those edges, and the cavity may cross them only to be star-shaped.
        let mut keep = Vec::new();
        let mut around_halves = Vec::new();
        for &w in &split {
            for end in [x, y] {
                let cells = self.cells_around_edge(end, w);
                for &c in &cells {
                    let v = self.tri.simplices[c.index()].v;
                    for (i, &u) in v.iter().enumerate() {
                        if u != end && u != w {
                            around_halves.push(FacetRef::new(c, i));
                        }
                    }
                }
                keep.push(cells);
            }
        }
        let input = self.tri.vertex_of_input.len() as u32;
        let protected = &self.protected;
        let blocked = |f: FacetRef| {
            (protected[f.cell().index()] >> f.facet()) & 1 != 0 && !holding.contains(&f)
        };
        let avoided = |f: FacetRef| around_halves.contains(&f) && !holding.contains(&f);
        let Some(v) = self
            .tri
            .insert_star_shaped(p, input, &around, blocked, avoided, &keep)
        else {
            return Ok(None);
        };
        self.after_insertion();
        for &w in &split {
            for (a, b) in [(x, v), (v, y)] {
                let found = self.find_face(a, b, w);
                debug_assert!(found.is_some(), "a half of a split face is a face");
                if let Some(f) = found {
                    self.protect(f);
                }
            }
        }
        Ok(Some((v, split)))
    }

    /// Inserts `point` (caller's coordinates), walking from a cell of vertex `near`, by
    /// splitting what it lies in: the cell (1-4), the face (2-6) or the edge (the cells around
    /// it, each in two). Valid in any triangulation, Delaunay or not, since the point sees every
    /// face of those cells that it does not lie on; followed by
    /// [`Self::make_delaunay_from_locked`] from [`Self::last_new_cells`], it gives what
    /// Bowyer–Watson would in a Delaunay triangulation of points in general position (not
    /// always where four points around an edge are coplanar: there a flip can stop short). A
    /// point just beyond the hull (rounded off a hull facet) becomes a hull vertex joined to
    /// the facets it sees. Protected faces it splits are not protected; the others stay.
    /// Returns the new vertex, or `None` (nothing changed) at an existing vertex.
    /// [`Triangulation::last_cavity_vertices`] then holds its star's other vertices.
    ///
    /// # Errors
    /// A non-finite coordinate or one outside the range of the triangulation.
    pub fn insert_splitting(
        &mut self,
        point: [f64; 3],
        near: VertexId,
    ) -> Result<Option<VertexId>, TriangulationError> {
        self.insert_in(point, near, false)
    }

    /// [`Self::insert_splitting`], but with the Bowyer–Watson cavity (the cells whose
    /// circumsphere holds the point, connected to the one containing it, grown until
    /// star-shaped) where that swallows no vertex: where the cells around the point are
    /// Delaunay, that is exactly Bowyer–Watson's insertion, degenerate (coplanar, cospherical)
    /// configurations included; elsewhere, the split.
    ///
    /// # Errors
    /// As [`Self::insert_splitting`].
    pub fn insert_growing(
        &mut self,
        point: [f64; 3],
        near: VertexId,
    ) -> Result<Option<VertexId>, TriangulationError> {
        self.insert_in(point, near, true)
    }

    fn insert_in(
        &mut self,
        point: [f64; 3],
        near: VertexId,
        bowyer_watson: bool,
    ) -> Result<Option<VertexId>, TriangulationError> {
        let p = self.tri.scaled_input(self.tri.flush_tiny(point))?;
        let start = if !near.is_ghost() && near.index() < self.tri.num_vertices() {
            self.tri.incident[near.index()]
        } else {
            self.tri.last
        };
        let c = match self.tri.locate_from(p, start) {
            Location::Vertex(_) => return Ok(None),
            Location::Cell(c) => c,
        };
        let input = self.tri.vertex_of_input.len() as u32;
        let inserted = if self.tri.is_ghost(c) {
            // Beyond the hull (a point of a hull facet, rounded outwards).
            self.tri.insert_beyond_hull(p, input, c)
        } else {
            let tri = &mut self.tri;
            bowyer_watson
                .then(|| tri.insert_star_shaped(p, input, &[c], |_| false, |_| false, &[]))
                .flatten()
                // No conflict search (every facet is avoided): the growth adds the cells
                // across the facets the point lies on.
                .or_else(|| tri.insert_star_shaped(p, input, &[c], |_| false, |_| true, &[]))
        };
        let Some(v) = inserted else {
            return Ok(None);
        };
        self.after_insertion();
        Ok(Some(v))
    }

    /// Plain Bowyer–Watson insertion of `point` (caller's coordinates) in a Delaunay
    /// triangulation, walking from a cell of vertex `near`, as
    /// [`Triangulation::insert_near`]: protected faces do not stop the cavity; those it keeps
    /// stay protected. The new cells' tags are 0 (this is for recovery, before the cells are
    /// classified).
    ///
    /// # Errors
    /// As [`Triangulation::insert`].
    pub fn insert_near(
        &mut self,
        point: [f64; 3],
        near: VertexId,
    ) -> Result<Insertion, TriangulationError> {
        let result = self.tri.insert_near(point, near)?;
        if let Insertion::Inserted(_) = result {
            let n = self.tri.simplices.len();
            self.protected.resize(n, 0);
            self.tags.resize(n, 0);
            for (b, &c) in self
                .tri
                .cavity
                .boundary
                .iter()
                .zip(&self.tri.cavity.new_cells)
            {
                let outside = b.outside;
                let bit = (self.protected[outside.cell().index()] >> outside.facet()) & 1;
                self.protected[c.index()] = bit << b.apex;
                self.tags[c.index()] = 0;
            }
        }
        Ok(result)
    }

    /// Per-cell data of the cells the last star-shaped insertion made: protection from the
    /// faces they were built on, tags from the cells they replace (read before their slots are
    /// written again).
    fn after_insertion(&mut self) {
        let cavity = &self.tri.cavity;
        let tags: Vec<u32> = cavity.inside.iter().map(|c| self.tags[c.index()]).collect();
        let n = self.tri.simplices.len();
        self.protected.resize(n, 0);
        self.tags.resize(n, 0);
        for ((b, &c), &tag) in cavity.boundary.iter().zip(&cavity.new_cells).zip(&tags) {
            let outside = b.outside;
            let bit = (self.protected[outside.cell().index()] >> outside.facet()) & 1;
            self.protected[c.index()] = bit << b.apex;
            self.tags[c.index()] = tag;
        }
    }

    /// Unprotects every face.
    pub fn unprotect_all(&mut self) {
        self.protected.fill(0);
    }

    /// The cells holding both `a` and `b`.
    fn cells_around_edge(&mut self, a: VertexId, b: VertexId) -> Vec<CellId> {
        let mut star = Vec::new();
        self.stars.star(&self.tri, a, &mut star);
        star.retain(|&c| self.tri.simplices[c.index()].v.contains(&b));
        star
    }

    /// The cells made by the last successful [`Self::insert_if`] or [`Self::split_edge`].
    pub fn last_new_cells(&self) -> &[CellId] {
        &self.tri.cavity.new_cells
    }

    /// Whether `c` is a live cell (not a freed slot, not out of range).
    pub fn is_live(&self, c: CellId) -> bool {
        c.index() < self.tri.simplices.len() && self.tri.simplices[c.index()].v[0] != VertexId::DEAD
    }

    /// Checks the triangulation's invariants (as [`Triangulation::validate`]) with the
    /// Delaunay test waived across protected faces (the constrained Delaunay property), and
    /// that both sides of every protected face agree.
    ///
    /// # Errors
    /// The first broken invariant found.
    pub fn validate(&self) -> Result<(), ValidationError> {
        self.check_protection()?;
        self.tri.validate_skipping(|c, i| self.is_protected(c, i))
    }

    /// [`Self::validate`] without the Delaunay test: adjacency, orientation, incidence, Euler's
    /// relation and the agreement of protected faces, which hold after any insertion.
    ///
    /// # Errors
    /// The first broken invariant found.
    pub fn validate_structure(&self) -> Result<(), ValidationError> {
        self.check_protection()?;
        self.tri.validate_skipping(|_, _| true)
    }

    fn check_protection(&self) -> Result<(), ValidationError> {
        for c in self.tri.all_cells() {
            for i in 0..4 {
                let across = self.tri.simplices[c.index()].n[i];
                if self.is_protected(c, i) != self.is_protected(across.cell(), across.facet()) {
                    return Err(ValidationError::AsymmetricNeighbor {
                        cell: c.0,
                        facet: i,
                    });
                }
            }
        }
        Ok(())
    }
}

/// The vertices of the face of `cell` opposite local vertex `i`, counter-clockwise seen from
/// outside the cell (from the neighbour across it).
pub(crate) fn face_vertices(cell: &[VertexId], i: usize) -> [VertexId; 3] {
    const FACE: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
    FACE[i].map(|k| cell[k])
}

/// The face `a b c` among `cells` (the star of `a`, from [`StarSearch::star`]): a facet of a
/// cell holding all three, or `None`.
pub fn find_face_in(
    tri: &Triangulation<D3>,
    cells: &[CellId],
    a: VertexId,
    b: VertexId,
    c: VertexId,
) -> Option<FacetRef> {
    if a == b || b == c || a == c {
        return None;
    }
    cells.iter().find_map(|&x| {
        let v = tri.cell(x);
        if v.contains(&a) && v.contains(&b) && v.contains(&c) {
            let i = (0..4).find(|&k| v[k] != a && v[k] != b && v[k] != c)?;
            Some(FacetRef::new(x, i))
        } else {
            None
        }
    })
}
