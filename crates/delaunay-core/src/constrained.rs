//! [`ConstrainedTriangulation2`]: a 2D triangulation with constrained edges, kept constrained
//! Delaunay by edge flips.
//!
//! Mesh generation needs three things plain Bowyer–Watson insertion cannot give:
//! - boundary edges that later insertions never cross or remove (the recovered boundary);
//! - segments inserted without adding points (Steiner-free recovery, beyond the paper);
//! - the Delaunay property restored after smoothing has moved points.
//!
//! All three are edge flips. A point is inserted by splitting the triangle (or the edge) it lies
//! in and flipping every non-constrained edge that fails the in-circle test (Lawson); a missing
//! segment is inserted by flipping away the edges it crosses (Sloan), then restoring the
//! Delaunay property around it. The in-circle test is the kernel's symbolically perturbed one,
//! so the result is the unique constrained Delaunay triangulation of the vertices and
//! constraints, whatever the order of operations.
//!
//! Each cell also carries a `u32` tag (mesh generation's region), which the cells made from it by
//! splits and flips inherit, and the epoch in which it last changed ([`Self::next_epoch`]), so
//! that passes over the mesh (point generation, refinement) can revisit only what changed.

use crate::dim::{Dim, D2};
use crate::error::{ConstraintError, TriangulationError};
use crate::ids::{CellId, FacetRef, VertexId};
use crate::prefetch::prefetch;
use crate::triangulation::{Insertion, Location, Simplex, Triangulation};
use delmesh_predicates::{orient2d, Sign};
use rayon::prelude::*;
use std::collections::VecDeque;

/// A 2D triangulation with constrained edges and a tag per cell.
///
/// Build it from a [`Triangulation`] (`D2`) with [`ConstrainedTriangulation2::new`], mark the
/// edges that must stay ([`Self::constrain_edge`]) or insert missing ones by flips
/// ([`Self::insert_segment`]), then insert points ([`Self::insert`]): the triangulation stays
/// the constrained Delaunay triangulation.
#[derive(Clone, Debug)]
pub struct ConstrainedTriangulation2 {
    tri: Triangulation<D2>,
    /// Per cell slot: its constraints, tag and change stamp.
    info: Vec<CellInfo>,
    /// The current epoch.
    epoch: u32,
    /// If on: the cells changed in the current epoch, each once, in order of first change.
    log: Option<Vec<CellId>>,
    /// Edges still to test during Lawson flipping.
    stack: Vec<FacetRef>,
}

/// What [`ConstrainedTriangulation2`] keeps per cell slot, side by side: an insertion or a
/// flip reads and writes all three for the cells it changes, so one array (one cache miss per
/// cell) rather than three.
#[derive(Clone, Copy, Debug, Default)]
struct CellInfo {
    /// The caller's tag.
    tag: u32,
    /// The epoch in which the cell was last created or changed.
    stamp: u32,
    /// Bit `i`: the edge opposite local vertex `i` is constrained. (A whole word, as wide as
    /// the compiler reads it: a one-byte store read back by a wider load, as just after an
    /// insertion, waits for the store to reach the cache.)
    constrained: u32,
}

#[inline]
fn next(i: usize) -> usize {
    if i == 2 {
        0
    } else {
        i + 1
    }
}

#[inline]
fn prev(i: usize) -> usize {
    if i == 0 {
        2
    } else {
        i - 1
    }
}

/// Whether two signs are strictly opposite (neither zero).
#[inline]
fn strictly_opposite(s: Sign, t: Sign) -> bool {
    matches!(
        (s, t),
        (Sign::Positive, Sign::Negative) | (Sign::Negative, Sign::Positive)
    )
}

#[inline]
fn bit(mask: u32, k: usize) -> u32 {
    (mask >> k) & 1
}

impl ConstrainedTriangulation2 {
    /// Wraps a Delaunay triangulation: no constraints yet, every tag 0.
    pub fn new(tri: Triangulation<D2>) -> Self {
        let n = tri.simplices.len();
        ConstrainedTriangulation2 {
            tri,
            info: vec![CellInfo::default(); n],
            epoch: 0,
            log: None,
            stack: Vec::new(),
        }
    }

    /// Changes the caller's units by `2^exponent` ([`Triangulation::rescale_units`]).
    pub fn rescale_units(&mut self, exponent: i32) -> bool {
        self.tri.rescale_units(exponent)
    }

    /// The underlying triangulation (cells, neighbours, vertices, queries).
    pub fn triangulation(&self) -> &Triangulation<D2> {
        &self.tri
    }

    /// Gives the underlying triangulation back, dropping constraints and tags.
    pub fn into_triangulation(self) -> Triangulation<D2> {
        self.tri
    }

    /// Whether the edge of `c` opposite its local vertex `i` is constrained.
    #[inline]
    pub fn is_constrained(&self, c: CellId, i: usize) -> bool {
        bit(self.info[c.index()].constrained, i) != 0
    }

    /// The tag of cell `c`.
    #[inline]
    pub fn tag(&self, c: CellId) -> u32 {
        self.info[c.index()].tag
    }

    /// Sets the tag of cell `c`.
    #[inline]
    pub fn set_tag(&mut self, c: CellId, tag: u32) {
        self.info[c.index()].tag = tag;
        self.touch(c);
    }

    /// Starts a new epoch and returns it: from now on, every cell created or changed (its
    /// vertices, neighbours, constraints, tag, or the position of one of its vertices) is
    /// stamped with it. Epochs start at 0 when the triangulation is wrapped.
    ///
    /// With `log`, the cells changed during the new epoch are also recorded, each once in
    /// order of first change, until [`Self::take_changed`] (or the next epoch) ends the record.
    pub fn next_epoch(&mut self, log: bool) -> u32 {
        self.epoch += 1;
        self.log = log.then(Vec::new);
        self.epoch
    }

    /// The current epoch.
    #[inline]
    pub fn changed_in_epoch(&self) -> u32 {
        self.epoch
    }

    /// The cells changed in the current epoch so far, each once, in order of first change (a
    /// slot may have changed again since, or be free): empty unless the epoch was started with
    /// `log`. Ends the record.
    pub fn take_changed(&mut self) -> Vec<CellId> {
        self.log.take().unwrap_or_default()
    }

    /// Renumbers the vertices and cells for memory locality ([`Triangulation::renumber`]);
    /// constraints, tags, change stamps and the record of changed cells move with their cells.
    pub fn renumber(&mut self) -> crate::Renumbering {
        self.sync();
        let map = self.tri.renumber();
        self.info = map.permute_cells(&self.info);
        if let Some(log) = &mut self.log {
            map.renumber_cells(log);
        }
        // (Scratch of the flips, empty between operations.)
        self.stack.clear();
        map
    }

    /// The epoch in which cell slot `c` was last created or changed: a cell whose epoch is
    /// older than some epoch `e` is exactly as it was when `e` began.
    #[inline]
    pub fn changed_in(&self, c: CellId) -> u32 {
        self.info[c.index()].stamp
    }

    /// Starts loading cell `c` (its vertices, neighbours and constraints) into the cache, for a
    /// caller that knows it will insert a point near it soon: point generation, which inserts
    /// from a list, calls it several candidates ahead (see `prefetch.rs`). Only a hint: a
    /// cell id out of range is ignored.
    #[inline]
    pub fn prefetch_cell(&self, c: CellId) {
        if let (Some(s), Some(info)) = (self.tri.simplices.get(c.index()), self.info.get(c.index()))
        {
            prefetch(s);
            prefetch(info);
        }
    }

    /// Starts loading the coordinates of cell `c`'s vertices. It reads `c` itself, so it comes
    /// a few steps after [`Self::prefetch_cell`] of the same cell.
    #[inline]
    pub fn prefetch_vertices(&self, c: CellId) {
        if let Some(s) = self.tri.simplices.get(c.index()) {
            for v in &s.v[..3] {
                if let Some(p) = self.tri.points.get(v.index()) {
                    prefetch(p);
                }
            }
        }
    }

    /// Starts loading the cells across the edges of cell `c`, which the flips after an
    /// insertion in `c` read. As [`Self::prefetch_vertices`], after [`Self::prefetch_cell`].
    #[inline]
    pub fn prefetch_neighbours(&self, c: CellId) {
        if let Some(s) = self.tri.simplices.get(c.index()) {
            for n in &s.n[..3] {
                if let Some(t) = self.tri.simplices.get(n.cell().index()) {
                    prefetch(t);
                }
            }
        }
    }

    /// Number of cell slots (live, ghost or free): cell ids are below it.
    #[inline]
    pub fn num_cell_slots(&self) -> usize {
        self.tri.simplices.len()
    }

    #[inline]
    fn touch(&mut self, c: CellId) {
        let stamp = &mut self.info[c.index()].stamp;
        if *stamp != self.epoch {
            *stamp = self.epoch;
            if let Some(log) = &mut self.log {
                log.push(c);
            }
        }
    }

    /// The constrained edges, each once, as vertex pairs.
    pub fn constrained_edges(&self) -> Vec<(VertexId, VertexId)> {
        let mut out = Vec::new();
        for c in self.tri.all_cells() {
            let m = self.info[c.index()].constrained;
            if m == 0 {
                continue;
            }
            let v = self.tri.cell(c);
            for i in 0..3 {
                let (a, b) = (v[next(i)], v[prev(i)]);
                // Each edge is seen from both sides; report it from the side where a < b.
                if bit(m, i) != 0 && a < b {
                    out.push((a, b));
                }
            }
        }
        out
    }

    /// Keeps the per-cell info as long as the cell arrays.
    fn sync(&mut self) {
        let n = self.tri.simplices.len();
        if self.info.len() < n {
            self.info.resize(n, CellInfo::default());
        }
    }

    #[inline]
    fn pt(&self, v: VertexId) -> [f64; 2] {
        self.tri.points[v.index()]
    }

    /// The cell and local facet of the edge `a b` (in either direction), if present. Walks
    /// around `a` through its incident cells, so it costs the degree of `a`.
    pub fn find_edge(&self, a: VertexId, b: VertexId) -> Option<(CellId, usize)> {
        if a == b || a.is_ghost() || a.index() >= self.tri.num_vertices() {
            return None;
        }
        let start = self.tri.incident[a.index()];
        let mut c = start;
        loop {
            let s = &self.tri.simplices[c.index()];
            let k = s.v[..3].iter().position(|&u| u == a)?;
            if s.v[next(k)] == b {
                return Some((c, prev(k)));
            }
            if s.v[prev(k)] == b {
                return Some((c, next(k)));
            }
            // Counter-clockwise around a: across the edge (a, v[k+2]), opposite v[k+1].
            c = s.n[next(k)].cell();
            if c == start {
                return None;
            }
        }
    }

    /// Marks the existing edge `a b` as constrained.
    ///
    /// # Errors
    /// [`ConstraintError::MissingEdge`] if the edge is not in the triangulation.
    pub fn constrain_edge(&mut self, a: VertexId, b: VertexId) -> Result<(), ConstraintError> {
        let (c, f) = self
            .find_edge(a, b)
            .ok_or(ConstraintError::MissingEdge { a, b })?;
        let across = self.tri.simplices[c.index()].n[f];
        self.info[c.index()].constrained |= 1 << f;
        self.info[across.cell().index()].constrained |= 1 << across.facet();
        self.touch(c);
        self.touch(across.cell());
        Ok(())
    }

    /// Inserts one point (caller's coordinates) and restores the constrained Delaunay property
    /// by flips. A point on a constrained edge splits it into two constrained edges.
    ///
    /// # Errors
    /// Bad coordinates (as [`Triangulation::insert`]), or a point outside the convex hull or on
    /// a hull edge (mesh generation only inserts inside the domain).
    pub fn insert(&mut self, point: [f64; 2]) -> Result<Insertion, ConstraintError> {
        let hint = self.tri.last;
        self.insert_where(point, hint, |_, _| true)
            .map(|i| i.expect("insertion accepted everywhere"))
    }

    /// Inserts `point` only if it lies in a cell tagged `tag` and not exactly on a constrained
    /// edge; `Ok(None)` otherwise (nothing changes). Point generation uses this, so a candidate
    /// rounded onto the boundary or across it is refused rather than inserted in the wrong place.
    ///
    /// # Errors
    /// As [`Self::insert`].
    pub fn insert_in_region(
        &mut self,
        point: [f64; 2],
        tag: u32,
    ) -> Result<Option<Insertion>, ConstraintError> {
        let hint = self.tri.last;
        self.insert_where(point, hint, |cdt, (c, on_edge)| {
            cdt.info[c.index()].tag == tag && on_edge.is_none_or(|i| !cdt.is_constrained(c, i))
        })
    }

    /// Inserts `point`, a constructed point (a centroid, a circumcentre), if `accept(self,
    /// cell, edge)` agrees, where `cell` is the finite cell containing it and `edge` the local
    /// index of the edge it lies on, if any; `Ok(None)` otherwise, and for a point outside the
    /// convex hull or on a hull edge (rounding put it there). A coordinate too small for the
    /// triangulation's range is flushed to zero. The walk starts at `hint` (a cell near the
    /// point makes it short). Cell slots are never freed by this type's operations, so an old
    /// cell id is always a valid hint.
    ///
    /// # Errors
    /// A non-finite coordinate, or one too large for the triangulation's range.
    pub fn insert_near_if(
        &mut self,
        point: [f64; 2],
        hint: CellId,
        accept: impl Fn(&Self, CellId, Option<usize>) -> bool,
    ) -> Result<Option<Insertion>, ConstraintError> {
        let hint = if hint.index() < self.tri.simplices.len()
            && self.tri.simplices[hint.index()].v[0] != VertexId::DEAD
        {
            hint
        } else {
            self.tri.last
        };
        // A constructed point: tiny coordinates are flushed to zero.
        let point = self.tri.flush_tiny(point);
        match self.insert_where(point, hint, |cdt, (c, e)| accept(cdt, c, e)) {
            Err(ConstraintError::OutsideHull { .. }) => Ok(None),
            other => other,
        }
    }

    /// As [`Self::insert_near_if`], but only if `point` is visible from cell `from`: the
    /// straight line from `from`'s centroid to it crosses no constrained edge (and stays in the
    /// convex hull); `Ok(None)` otherwise, without walking any further. For a circumcentre
    /// meant to remove `from`: a point that `from` cannot see could not remove it (the cavity
    /// of a constrained triangulation stops at constrained edges), and the walk to it, across a
    /// non-convex domain from one spike of a star to another, can cross the whole mesh.
    ///
    /// # Errors
    /// As [`Self::insert_near_if`].
    pub fn insert_visible_if(
        &mut self,
        point: [f64; 2],
        from: CellId,
        accept: impl Fn(&Self, CellId, Option<usize>) -> bool,
    ) -> Result<Option<Insertion>, ConstraintError> {
        let point = self.tri.flush_tiny(point);
        let p = self.tri.scaled_input(point)?;
        let Some(found) = self.walk_straight(p, from) else {
            return Ok(None);
        };
        match self.insert_located(point, p, found, |cdt, (c, e)| accept(cdt, c, e)) {
            // On a hull edge.
            Err(ConstraintError::OutsideHull { .. }) => Ok(None),
            other => other,
        }
    }

    /// The location of the (internal) point `p` walking from the finite cell `from` along the
    /// straight line from its centroid, and the edge of the cell `p` lies on, if any; `None`
    /// where the line crosses a constrained edge or the convex hull first. Each step leaves a
    /// cell by the edge the line crosses towards `p` (a line through a vertex taken as passing
    /// on its left, so there is one). Should rounding of the centroid (in a cell flat to
    /// rounding) leave no such edge, any edge `p` lies beyond is taken; a walk longer than the
    /// number of cells, which only that could make, gives `None`.
    fn walk_straight(&self, p: [f64; 2], from: CellId) -> Option<(Location, Option<usize>)> {
        let live = from.index() < self.tri.simplices.len() && self.tri.is_live(from);
        if !live || self.tri.is_ghost(from) {
            return None;
        }
        let v = self.tri.simplices[from.index()].v;
        let (a, b, c) = (self.pt(v[0]), self.pt(v[1]), self.pt(v[2]));
        let q = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0];
        let left = |u: VertexId| orient2d(q, p, self.pt(u)) != Sign::Negative;
        let (mut cell, mut came) = (from, usize::MAX);
        for _ in 0..=self.tri.simplices.len() {
            if self.tri.is_ghost(cell) {
                return None;
            }
            let s = &self.tri.simplices[cell.index()];
            let v = [s.v[0], s.v[1], s.v[2]];
            // Negative: p lies strictly beyond the edge opposite corner i.
            let side: [Sign; 3] =
                std::array::from_fn(|i| orient2d(p, self.pt(v[next(i)]), self.pt(v[prev(i)])));
            if side.iter().all(|&o| o != Sign::Negative) {
                // In the closed cell: at a vertex, on an edge (the lowest), or inside.
                if let Some(&u) = v.iter().find(|&&u| self.pt(u) == p) {
                    return Some((Location::Vertex(u), None));
                }
                let on = (0..3).find(|&i| side[i] == Sign::Zero);
                return Some((Location::Cell(cell), on));
            }
            let exit = (0..3)
                .find(|&i| {
                    i != came && side[i] == Sign::Negative && left(v[next(i)]) != left(v[prev(i)])
                })
                .or_else(|| (0..3).find(|&i| i != came && side[i] == Sign::Negative))?;
            if self.is_constrained(cell, exit) {
                return None;
            }
            let across = s.n[exit];
            (cell, came) = (across.cell(), across.facet());
        }
        None
    }

    /// Locates `point` (caller's coordinates): the cell containing it or the vertex at it.
    pub fn locate(&mut self, point: [f64; 2]) -> Location {
        self.tri.locate(point)
    }

    /// As [`ConstrainedTriangulation2::locate`], the walk starting at cell `near` (see
    /// [`Triangulation::locate_near`]).
    pub fn locate_near(&mut self, point: [f64; 2], near: CellId) -> Location {
        self.tri.locate_near(point, near)
    }

    fn insert_where(
        &mut self,
        point: [f64; 2],
        hint: CellId,
        accept: impl Fn(&Self, (CellId, Option<usize>)) -> bool,
    ) -> Result<Option<Insertion>, ConstraintError> {
        let p = self.tri.scaled_input(point)?;
        // The walk's own orientation tests tell whether the point is on an edge of its cell.
        let found = self.tri.locate_on_facet(p, hint);
        self.insert_located(point, p, found, accept)
    }

    /// Inserts `point` (internal coordinates `p`), found at `found` by a walk (with the edge of
    /// its cell it lies on, if any), if `accept` agrees; see [`Self::insert_near_if`].
    fn insert_located(
        &mut self,
        point: [f64; 2],
        p: [f64; 2],
        found: (Location, Option<usize>),
        accept: impl Fn(&Self, (CellId, Option<usize>)) -> bool,
    ) -> Result<Option<Insertion>, ConstraintError> {
        let input = self.tri.vertex_of_input.len();
        let (c, on_edge) = match found {
            (Location::Vertex(v), _) => {
                self.tri.vertex_of_input.push(v);
                let original = self.tri.input_index[v.index()] as usize;
                self.tri.duplicates.push((input, original));
                return Ok(Some(Insertion::Duplicate(v)));
            }
            (Location::Cell(c), on_edge) => (c, on_edge),
        };
        if self.tri.is_ghost(c) {
            return Err(ConstraintError::OutsideHull { point });
        }
        let s = self.tri.simplices[c.index()];
        if let Some(i) = on_edge {
            if self.tri.is_ghost(s.n[i].cell()) {
                return Err(ConstraintError::OutsideHull { point });
            }
        }
        if !accept(self, (c, on_edge)) {
            return Ok(None);
        }
        let v = self.tri.push_vertex(p, input as u32);
        self.stack.clear();
        match on_edge {
            None => self.split_cell(c, v),
            Some(i) => self.split_edge(c, i, v),
        }
        self.legalize_around(v);
        Ok(Some(Insertion::Inserted(v)))
    }

    /// Splits finite cell `c` into three at the new vertex `v` inside it; queues the three
    /// edges opposite `v`.
    fn split_cell(&mut self, c: CellId, v: VertexId) {
        let s = self.tri.simplices[c.index()];
        let (cons, tag) = (self.info[c.index()].constrained, self.info[c.index()].tag);
        // k_i is c with its vertex i replaced by v (k_0 is c itself): facet i of k_i is the
        // outer edge facet i of c was, and facet j of k_i (the edge through v and vertex
        // 3 − i − j) is facet i of k_j. Each cell is written whole.
        let k1 = self.tri.alloc_cell(&[s.v[0], v, s.v[2]]);
        let k2 = self.tri.alloc_cell(&[s.v[0], s.v[1], v]);
        self.sync();
        let inner = |k: CellId, i: usize| FacetRef::new(k, i);
        self.tri.simplices[c.index()] = Simplex {
            v: [v, s.v[1], s.v[2], s.v[3]],
            n: [s.n[0], inner(k1, 0), inner(k2, 0), s.n[3]],
        };
        self.tri.simplices[k1.index()].n[..3].copy_from_slice(&[inner(c, 1), s.n[1], inner(k2, 1)]);
        self.tri.simplices[k2.index()].n[..3].copy_from_slice(&[inner(c, 2), inner(k1, 2), s.n[2]]);
        // The cell across facet 0 still faces facet 0 of c; the other two now face k1, k2.
        self.tri.set_neighbor(s.n[1], inner(k1, 1));
        self.tri.set_neighbor(s.n[2], inner(k2, 2));
        for (i, k) in [c, k1, k2].into_iter().enumerate() {
            self.info[k.index()].constrained = bit(cons, i) << i;
            self.info[k.index()].tag = tag;
            self.touch(k);
            self.stack.push(FacetRef::new(k, i));
        }
        self.set_incident(v, c);
        self.set_incident(s.v[1], c);
        self.set_incident(s.v[2], c);
        self.set_incident(s.v[0], k1);
        self.tri.last = c;
    }

    /// Splits the edge of finite cell `c` opposite its local vertex `i` (shared with a finite
    /// cell) at the new vertex `v` on it: two cells become four. A constrained edge stays
    /// constrained in both halves. Queues the four edges opposite `v`.
    fn split_edge(&mut self, c: CellId, i: usize, v: VertexId) {
        let s = self.tri.simplices[c.index()];
        let across = s.n[i];
        let (e, j) = (across.cell(), across.facet());
        let t = self.tri.simplices[e.index()];
        let (cc, ce) = (
            self.info[c.index()].constrained,
            self.info[e.index()].constrained,
        );
        let (tc, te) = (self.info[c.index()].tag, self.info[e.index()].tag);
        let (a, b, q, d) = (s.v[i], s.v[next(i)], s.v[prev(i)], t.v[j]);
        // c1 = c with b → v; c2 = c with q → v; e1 = e with q → v; e2 = e with b → v.
        let mut c2v = s.v;
        c2v[prev(i)] = v;
        let c2 = self.tri.alloc_cell(&c2v[..3]);
        let mut e2v = t.v;
        e2v[prev(j)] = v;
        let e2 = self.tri.alloc_cell(&e2v[..3]);
        self.sync();
        self.tri.simplices[c.index()].v[next(i)] = v;
        self.tri.simplices[e.index()].v[next(j)] = v;
        let (c1, e1) = (c, e);
        self.tri.link(FacetRef::new(c1, next(i)), s.n[next(i)]);
        self.tri.link(FacetRef::new(c2, prev(i)), s.n[prev(i)]);
        self.tri.link(FacetRef::new(e1, next(j)), t.n[next(j)]);
        self.tri.link(FacetRef::new(e2, prev(j)), t.n[prev(j)]);
        self.tri.link(FacetRef::new(c1, i), FacetRef::new(e2, j));
        self.tri.link(FacetRef::new(c2, i), FacetRef::new(e1, j));
        self.tri
            .link(FacetRef::new(c1, prev(i)), FacetRef::new(c2, next(i)));
        self.tri
            .link(FacetRef::new(e1, prev(j)), FacetRef::new(e2, next(j)));
        let split = bit(cc, i);
        self.info[c1.index()].constrained = split << i | bit(cc, next(i)) << next(i);
        self.info[c2.index()].constrained = split << i | bit(cc, prev(i)) << prev(i);
        self.info[e1.index()].constrained = split << j | bit(ce, next(j)) << next(j);
        self.info[e2.index()].constrained = split << j | bit(ce, prev(j)) << prev(j);
        self.info[c1.index()].tag = tc;
        self.info[c2.index()].tag = tc;
        self.info[e1.index()].tag = te;
        self.info[e2.index()].tag = te;
        for k in [c1, c2, e1, e2] {
            self.touch(k);
        }
        for (k, f) in [(c1, next(i)), (c2, prev(i)), (e1, next(j)), (e2, prev(j))] {
            self.stack.push(FacetRef::new(k, f));
        }
        self.set_incident(v, c1);
        self.set_incident(a, c1);
        self.set_incident(q, c1);
        self.set_incident(b, c2);
        self.set_incident(d, e1);
        self.tri.last = c1;
    }

    #[inline]
    fn set_incident(&mut self, v: VertexId, c: CellId) {
        if !v.is_ghost() {
            self.tri.incident[v.index()] = c;
        }
    }

    /// Flips the edge of finite cell `c` opposite its local vertex `i`, shared with the finite
    /// cell across it. With `c = (a, b, q)` (a at `i`) and `d` across, the new cells are
    /// `(a, b, d)` in slot `c` and `(a, d, q)` in the neighbour's slot: `a` is local vertex 0
    /// of both and the new edge `a d` is facet 1 of the first, facet 2 of the second.
    fn flip(&mut self, c: CellId, i: usize) -> (CellId, CellId) {
        let s = self.tri.simplices[c.index()];
        let t = self.tri.simplices[s.n[i].cell().index()];
        self.flip_loaded(c, i, s, t)
    }

    /// [`Self::flip`], given the two cells as they are (`s` of `c`, `t` across its facet `i`).
    #[inline(always)]
    fn flip_loaded(&mut self, c: CellId, i: usize, s: Simplex, t: Simplex) -> (CellId, CellId) {
        let across = s.n[i];
        let (e, j) = (across.cell(), across.facet());
        let (a, b, q, d) = (s.v[i], s.v[next(i)], s.v[prev(i)], t.v[j]);
        debug_assert!(t.v[next(j)] == q && t.v[prev(j)] == b);
        let (cc, ce) = (
            self.info[c.index()].constrained,
            self.info[e.index()].constrained,
        );
        let tag = self.info[c.index()].tag;
        // The outer edges b d, a b (now of c) and d q, q a (now of e).
        let (bd, ab, dq, qa) = (t.n[next(j)], s.n[prev(i)], t.n[prev(j)], s.n[next(i)]);
        self.tri.simplices[c.index()] = Simplex {
            v: [a, b, d, VertexId::GHOST],
            n: [bd, FacetRef::new(e, 2), ab, s.n[3]],
        };
        self.tri.simplices[e.index()] = Simplex {
            v: [a, d, q, VertexId::GHOST],
            n: [dq, qa, FacetRef::new(c, 1), t.n[3]],
        };
        self.tri.set_neighbor(bd, FacetRef::new(c, 0));
        self.tri.set_neighbor(ab, FacetRef::new(c, 2));
        self.tri.set_neighbor(dq, FacetRef::new(e, 0));
        self.tri.set_neighbor(qa, FacetRef::new(e, 1));
        self.info[c.index()].constrained = bit(ce, next(j)) | bit(cc, prev(i)) << 2;
        self.info[e.index()].constrained = bit(ce, prev(j)) | bit(cc, next(i)) << 1;
        self.info[e.index()].tag = tag;
        self.touch(c);
        self.touch(e);
        self.set_incident(a, c);
        self.set_incident(b, c);
        self.set_incident(d, c);
        self.set_incident(q, e);
        (c, e)
    }

    /// Whether the edge of `c` opposite local vertex `i` must be flipped: not constrained, not
    /// on the hull, and the vertex across it lies inside the circumcircle of `c` (perturbed).
    #[inline]
    fn needs_flip(&self, c: CellId, i: usize) -> bool {
        let s = &self.tri.simplices[c.index()];
        if self.is_constrained(c, i) || s.v[..3].iter().any(|u| u.is_ghost()) {
            return false;
        }
        let across = s.n[i];
        // The cell across is a ghost exactly when its vertex opposite the (finite) edge is.
        let d = self.tri.simplices[across.cell().index()].v[across.facet()];
        if d.is_ghost() {
            return false;
        }
        D2::insphere_cell(&self.tri.points, &s.v, self.pt(d)) == Sign::Positive
    }

    /// Lawson flips after inserting `v`: the queued edges are opposite `v`; each flip queues the
    /// two new edges opposite `v`.
    ///
    /// (The test of [`Self::needs_flip`] on cells read once: a cell holding `v` is finite, since
    /// `v` is inside the hull.)
    fn legalize_around(&mut self, v: VertexId) {
        while let Some(fr) = self.stack.pop() {
            let (c, i) = (fr.cell(), fr.facet());
            // The test reads the cells field by field: they were just written so, and a load
            // of a whole cell would wait for those stores to reach the cache.
            let cell = &self.tri.simplices[c.index()];
            if cell.v[i] != v || self.is_constrained(c, i) {
                continue;
            }
            debug_assert!(cell.v[..3].iter().all(|u| !u.is_ghost()));
            let across = cell.n[i];
            let d = self.tri.simplices[across.cell().index()].v[across.facet()];
            if d.is_ghost()
                || D2::insphere_cell(&self.tri.points, &cell.v, self.pt(d)) != Sign::Positive
            {
                continue;
            }
            let (s, t) = (
                self.tri.simplices[c.index()],
                self.tri.simplices[across.cell().index()],
            );
            let (t1, t2) = self.flip_loaded(c, i, s, t);
            self.stack.push(FacetRef::new(t1, 0));
            self.stack.push(FacetRef::new(t2, 0));
        }
    }

    /// Lawson flips from the queued edges until every edge reached is locally (constrained)
    /// Delaunay; each flip queues the four outer edges of its quadrilateral. Returns the number
    /// of flips.
    fn legalize_queued(&mut self) -> usize {
        let mut flips = 0;
        while let Some(fr) = self.stack.pop() {
            let (c, i) = (fr.cell(), fr.facet());
            if self.tri.simplices[c.index()].v[0] == VertexId::DEAD || !self.needs_flip(c, i) {
                continue;
            }
            let (t1, t2) = self.flip(c, i);
            flips += 1;
            self.stack.extend([
                FacetRef::new(t1, 0),
                FacetRef::new(t1, 2),
                FacetRef::new(t2, 0),
                FacetRef::new(t2, 1),
            ]);
        }
        flips
    }

    /// Restores the constrained Delaunay property everywhere by edge flips (after vertices were
    /// moved, e.g. by smoothing). Returns the number of flips. Terminates: each flip lowers the
    /// triangulation on the (perturbed) lifting paraboloid.
    pub fn make_delaunay(&mut self) -> usize {
        // Only the edges failing the test start the flips: they are found in parallel, in cell
        // order (read-only). An edge that passes can fail only after a flip changes one of its
        // cells, and every flip queues the edges around it.
        // (The test of `needs_flip`, with each cell and its constraints read once.)
        self.sync();
        let this = &*self;
        let failing: Vec<FacetRef> = self
            .tri
            .simplices
            .par_iter()
            .zip(&self.info)
            .enumerate()
            .with_min_len(1 << 12)
            .flat_map_iter(|(c, (s, info))| {
                let cons = info.constrained;
                let c = CellId(c as u32);
                // Live (a free slot's first vertex is DEAD) and finite.
                let finite = s.v[..3]
                    .iter()
                    .all(|&u| !u.is_ghost() && u != VertexId::DEAD);
                (0..3).filter_map(move |i| {
                    let across = s.n[i];
                    if !finite || c >= across.cell() || bit(cons, i) != 0 {
                        return None;
                    }
                    let d = this.tri.simplices[across.cell().index()].v[across.facet()];
                    let fails = !d.is_ghost()
                        && D2::insphere_cell(&this.tri.points, &s.v, this.pt(d)) == Sign::Positive;
                    fails.then_some(FacetRef::new(c, i))
                })
            })
            .collect();
        self.stack = failing;
        self.legalize_queued()
    }

    /// Inserts the segment `a b` as a constrained edge without adding points: the edges it
    /// crosses are flipped away (Sloan's algorithm), then the Delaunay property is restored
    /// around it. Nothing to do but mark it if the edge exists.
    ///
    /// # Errors
    /// [`ConstraintError::VertexOnSegment`] if a vertex lies in the segment's interior,
    /// [`ConstraintError::CrossesConstraint`] if it crosses a constrained edge; the
    /// triangulation is unchanged in both cases.
    pub fn insert_segment(&mut self, a: VertexId, b: VertexId) -> Result<(), ConstraintError> {
        let n = self.tri.num_vertices();
        if a == b || a.is_ghost() || b.is_ghost() || a.index() >= n || b.index() >= n {
            return Err(ConstraintError::MissingEdge { a, b });
        }
        if self.find_edge(a, b).is_some() {
            return self.constrain_edge(a, b);
        }
        let mut crossed = self.crossed_edges(a, b)?;
        let (pa, pb) = (self.pt(a), self.pt(b));
        let mut new_edges = Vec::new();
        // Each pass over the queue flips at least one edge (Sloan), so this bound is generous.
        let mut budget = 4 * crossed.len() * crossed.len() + 64;
        while let Some((r, l)) = crossed.pop_front() {
            budget = budget.saturating_sub(1);
            if budget == 0 {
                return Err(ConstraintError::Stalled { a, b });
            }
            let (c, f) = self
                .find_edge(r, l)
                .expect("a crossed edge is in the triangulation: a bug in delmesh");
            let s = self.tri.simplices[c.index()];
            let across = s.n[f];
            let x = s.v[f];
            let y = self.tri.simplices[across.cell().index()].v[across.facet()];
            let (px, py) = (self.pt(x), self.pt(y));
            let convex =
                strictly_opposite(orient2d(px, py, self.pt(r)), orient2d(px, py, self.pt(l)));
            if !convex {
                crossed.push_back((r, l));
                continue;
            }
            self.flip(c, f);
            let (ox, oy) = (orient2d(pa, pb, px), orient2d(pa, pb, py));
            if strictly_opposite(ox, oy) {
                // The new edge x y still crosses the segment: x and y are on opposite sides.
                crossed.push_back(if ox == Sign::Negative { (x, y) } else { (y, x) });
            } else {
                new_edges.push((x, y));
            }
        }
        self.constrain_edge(a, b)?;
        self.stack.clear();
        for (x, y) in new_edges {
            if let Some((c, f)) = self.find_edge(x, y) {
                self.stack.push(FacetRef::new(c, f));
            }
        }
        self.legalize_queued();
        Ok(())
    }

    /// The edges the segment `a b` crosses, in order from `a`, as `(right, left)` vertex pairs
    /// (seen along `a → b`).
    fn crossed_edges(
        &self,
        a: VertexId,
        b: VertexId,
    ) -> Result<VecDeque<(VertexId, VertexId)>, ConstraintError> {
        let (pa, pb) = (self.pt(a), self.pt(b));
        let on_segment = |u: VertexId| {
            // u is collinear with a b: is it between them? (Never at b: the edge is absent.)
            let pu = self.pt(u);
            let along =
                |p: [f64; 2]| (p[0] - pa[0]) * (pb[0] - pa[0]) + (p[1] - pa[1]) * (pb[1] - pa[1]);
            along(pu) > 0.0 && along(pu) < along(pb)
        };
        // The cell around a whose wedge contains the direction to b.
        let start = self.tri.incident[a.index()];
        let mut c = start;
        // The crossed edge is facet `f` of `near`, whose opposite vertex is on a's side.
        let (mut near, mut f, mut r, mut l);
        loop {
            let s = &self.tri.simplices[c.index()];
            let k = s.v[..3]
                .iter()
                .position(|&u| u == a)
                .expect("the star of a contains a: a bug in delmesh");
            let (u, w) = (s.v[next(k)], s.v[prev(k)]);
            if !u.is_ghost() && !w.is_ghost() {
                let (ou, ow) = (orient2d(pa, pb, self.pt(u)), orient2d(pa, pb, self.pt(w)));
                // Both: a neighbour along the hull is in one finite cell only, as either.
                for (o, x) in [(ou, u), (ow, w)] {
                    if o == Sign::Zero && on_segment(x) {
                        return Err(ConstraintError::VertexOnSegment { a, b, vertex: x });
                    }
                }
                if ou == Sign::Negative && ow == Sign::Positive {
                    (near, f, r, l) = (c, k, u, w);
                    break;
                }
            }
            c = s.n[next(k)].cell();
            if c == start {
                // Only possible if the segment left the convex hull, which the segment between
                // two vertices never does.
                return Err(ConstraintError::MissingEdge { a, b });
            }
        }
        let mut crossed = VecDeque::new();
        loop {
            if self.is_constrained(near, f) {
                return Err(ConstraintError::CrossesConstraint { a, b, c: r, d: l });
            }
            crossed.push_back((r, l));
            let across = self.tri.simplices[near.index()].n[f];
            let far = across.cell();
            let fv = self.tri.simplices[far.index()].v;
            let x = fv[across.facet()];
            if x.is_ghost() {
                return Err(ConstraintError::MissingEdge { a, b });
            }
            if x == b {
                return Ok(crossed);
            }
            let position = |u: VertexId| fv[..3].iter().position(|&w| w == u).expect("shared edge");
            match orient2d(pa, pb, self.pt(x)) {
                // Leaves through x r (opposite l) or through l x (opposite r).
                Sign::Positive => {
                    f = position(l);
                    l = x;
                }
                Sign::Negative => {
                    f = position(r);
                    r = x;
                }
                Sign::Zero => return Err(ConstraintError::VertexOnSegment { a, b, vertex: x }),
            }
            near = far;
        }
    }

    /// Moves vertices (caller's coordinates) all at once, if every cell around them stays
    /// positively oriented; otherwise nothing moves. Hull vertices cannot move.
    ///
    /// # Errors
    /// [`ConstraintError::InvalidMove`] naming the first vertex whose move inverts a cell, or
    /// is on the hull; coordinate errors as for insertion.
    pub fn move_vertices(&mut self, moves: &[(VertexId, [f64; 2])]) -> Result<(), ConstraintError> {
        let (old, moved) = self.tri.place_vertices(moves)?;
        if !self.accept_moves(&moved) {
            // Name the first vertex, in `moves` order, with a broken star.
            let first = moves
                .iter()
                .find(|&&(v, _)| !self.star_positive(v))
                .map_or(moves[0].0, |&(v, _)| v);
            self.tri.put_back(&old);
            return Err(ConstraintError::InvalidMove { vertex: first });
        }
        Ok(())
    }

    /// [`Self::move_vertices`] for every vertex at once: vertex `v` goes to `positions[v]`
    /// (caller's coordinates; one per vertex, those of the hull where they are). Cheaper than
    /// listing the moves when most vertices move (smoothing): the positions are placed in
    /// parallel.
    ///
    /// # Errors
    /// As [`Self::move_vertices`] (the vertex named is the first in numbering order with a
    /// broken star); a number of positions other than of vertices is an
    /// [`ConstraintError::InvalidMove`] naming the vertex past the last.
    pub fn move_all_vertices(&mut self, positions: &[[f64; 2]]) -> Result<(), ConstraintError> {
        let (old, moved) = self.tri.place_all_vertices(positions)?;
        if !self.accept_moves(&moved) {
            let first = (0..moved.len() as u32)
                .map(VertexId)
                .find(|&v| moved[v.index()] && !self.star_positive(v))
                .unwrap_or(VertexId(0));
            self.tri.points = old;
            return Err(ConstraintError::InvalidMove { vertex: first });
        }
        Ok(())
    }

    /// After the vertices with `moved` set were placed: false if a cell around one of them is
    /// a ghost or not positive, else true with those cells marked as changed. One scan over
    /// the cells in slot order (memory order, in parallel), rather than a walk around each
    /// moved vertex.
    fn accept_moves(&mut self, moved: &[bool]) -> bool {
        let touches = |s: &crate::triangulation::Simplex| {
            s.v[0] != VertexId::DEAD && s.v[..3].iter().any(|&u| !u.is_ghost() && moved[u.index()])
        };
        let points = &self.tri.points;
        let broken = self
            .tri
            .simplices
            .par_iter()
            .with_min_len(1 << 12)
            .any(|s| {
                touches(s)
                    && (s.v[..3].iter().any(|u| u.is_ghost())
                        || orient2d(
                            points[s.v[0].index()],
                            points[s.v[1].index()],
                            points[s.v[2].index()],
                        ) != Sign::Positive)
            });
        if broken {
            return false;
        }
        if self.log.is_some() {
            for c in (0..self.tri.simplices.len() as u32).map(CellId) {
                if touches(&self.tri.simplices[c.index()]) {
                    self.touch(c);
                }
            }
        } else {
            let epoch = self.epoch;
            self.info
                .par_iter_mut()
                .zip(self.tri.simplices.par_iter())
                .with_min_len(1 << 12)
                .for_each(|(info, s)| {
                    if touches(s) {
                        info.stamp = epoch;
                    }
                });
        }
        true
    }

    /// Whether every cell around `v` is finite and positively oriented.
    fn star_positive(&self, v: VertexId) -> bool {
        let start = self.tri.incident[v.index()];
        let mut c = start;
        loop {
            let s = &self.tri.simplices[c.index()];
            if s.v[..3].iter().any(|u| u.is_ghost()) {
                return false;
            }
            let p = [self.pt(s.v[0]), self.pt(s.v[1]), self.pt(s.v[2])];
            if orient2d(p[0], p[1], p[2]) != Sign::Positive {
                return false;
            }
            let k = s.v[..3]
                .iter()
                .position(|&u| u == v)
                .expect("v in its star");
            c = s.n[next(k)].cell();
            if c == start {
                return true;
            }
        }
    }

    /// Checks the triangulation's invariants (as [`Triangulation::validate`]) with the
    /// Delaunay test waived across constrained edges (the constrained Delaunay property), and
    /// that both sides of every constrained edge agree.
    ///
    /// # Errors
    /// The first broken invariant found.
    pub fn validate(&self) -> Result<(), crate::ValidationError> {
        self.constraints_agree()?;
        self.tri.validate_skipping(|c, i| self.is_constrained(c, i))
    }

    /// [`Self::validate`] without the Delaunay test (a mesh whose smoothed connectivity was
    /// kept): structure, orientation and constrained edges only.
    ///
    /// # Errors
    /// The first broken invariant found.
    pub fn validate_structure(&self) -> Result<(), crate::ValidationError> {
        self.constraints_agree()?;
        self.tri.validate_skipping(|_, _| true)
    }

    /// Both sides of every constrained edge say it is.
    fn constraints_agree(&self) -> Result<(), crate::ValidationError> {
        for c in self.tri.all_cells() {
            for i in 0..3 {
                let across = self.tri.simplices[c.index()].n[i];
                if self.is_constrained(c, i) != self.is_constrained(across.cell(), across.facet()) {
                    return Err(crate::ValidationError::AsymmetricNeighbor {
                        cell: c.0,
                        facet: i,
                    });
                }
            }
        }
        Ok(())
    }
}

impl From<TriangulationError> for ConstraintError {
    fn from(e: TriangulationError) -> Self {
        ConstraintError::Triangulation(e)
    }
}
