//! Making a missing edge or triangle part of a [`ConstrainedTriangulation3`] by flips, the way a
//! constrained (not conforming) boundary recovery does, with no new vertex.
//!
//! - **An edge `a b`** that is missing crosses faces or edges of the tetrahedralisation. The
//!   first of them seen from `a` (or from `b`) is flipped away: a face by a 2-3 flip, which
//!   joins `a` to the apex beyond it; an edge by a 3-2 flip, after 2-3 flips around it have
//!   brought the cells around it down to three. Each such flip takes a cell off the
//!   segment's path, so the flips end; they stop short where a flip would make a cell that is
//!   not positively oriented (a non-convex configuration), remove a protected face or a
//!   locked edge, or touch the hull.
//! - **A triangle `a b c`** whose edges are present but which is not a face is crossed by
//!   edges of the tetrahedralisation. Around each of its edges, say `a b`, one cell `a b x y`
//!   has `c` in its wedge, and its edge `x y` crosses the triangle: that edge is removed
//!   (2-3 flips around it, then a 3-2 flip), which makes `a b z` a face for the third vertex
//!   `z` left around it. When `z` is `c` the triangle is there.
//!
//! Every flip is checked with exact orientation tests before it is made (each new cell must be
//! strictly positive), so the result is always a valid tetrahedralisation of the same points;
//! it is no longer Delaunay where flips were made. Flips that did not reach their aim are
//! undone, so a failed attempt leaves the mesh as it was (Delaunay, where it was). What the flips cannot do, the caller does by
//! adding a vertex (see `delmesh-boundary-recovery`). The vertices of every cell a flip changed
//! are reported, so that the caller can re-check the edges and faces near them.

use crate::constrained3::ConstrainedTriangulation3;
use crate::flip3::local;
use crate::ids::{CellId, FacetRef, VertexId};
use delmesh_predicates::{orient3d, Sign};

/// What [`ConstrainedTriangulation3::flip_in_edge`] or
/// [`ConstrainedTriangulation3::flip_in_face`] achieved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlipIn {
    /// The edge or triangle is in the triangulation, after this many flips.
    Present(usize),
    /// The flips stopped short; the flips tried (this many) were undone.
    Stuck(usize),
}

/// Where a group of flips began (see [`ConstrainedTriangulation3::flip_mark`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FlipMark {
    log: usize,
}

/// A flip made, by what it made, so that it can be undone: a 2-3 flip's new edge, a 3-2
/// flip's new face, or the cells an edge-removing flip replaced and made.
#[derive(Clone, Debug)]
pub(crate) enum Flip {
    TwoThree([VertexId; 2]),
    ThreeTwo([VertexId; 3]),
    Replaced {
        old: Vec<[VertexId; 4]>,
        new: Vec<[VertexId; 4]>,
    },
}

/// How many levels down [`ConstrainedTriangulation3::remove_edge`] may remove an edge in the
/// way of a flip that brings the edge's ring down (TetGen calls it the flip link level).
const LINK_DEPTH: usize = 2;

/// Where a segment leaves its start vertex.
enum Crossing {
    /// Through the interior of the face of this cell opposite its local vertex (the start).
    Face(CellId, usize),
    /// Through the interior of this edge.
    Edge(VertexId, VertexId),
    /// Along a face or edge at the start, through a vertex, or off the finite cells: no flip
    /// is tried.
    Degenerate,
}

impl ConstrainedTriangulation3 {
    /// Makes `a b` an edge by flips, at most `max_flips` of them; never removes a protected
    /// face or an edge for which `locked` is true. The vertices of the cells changed are
    /// appended to `touched`.
    pub fn flip_in_edge(
        &mut self,
        a: VertexId,
        b: VertexId,
        locked: &impl Fn(VertexId, VertexId) -> bool,
        max_flips: usize,
        touched: &mut Vec<VertexId>,
    ) -> FlipIn {
        let start = self.flip_mark();
        self.flip_budget = max_flips;
        let mut flips = 0;
        let mut star = Vec::new();
        loop {
            if self.edge_cells(a, b, &mut star) {
                return FlipIn::Present(flips);
            }
            if flips >= max_flips {
                return self.undo_flips(start, touched);
            }
            let mut made = 0;
            for (from, to) in [(a, b), (b, a)] {
                made = match self.first_crossing(from, to, &mut star) {
                    Crossing::Face(c, i) => self.flip_face_away(c, i, locked, touched),
                    Crossing::Edge(p, q) => {
                        self.remove_edge(p, q, &[from], locked, touched, LINK_DEPTH)
                    }
                    Crossing::Degenerate => 0,
                };
                if made > 0 {
                    break;
                }
            }
            if made == 0 {
                return self.undo_flips(start, touched);
            }
            flips += made;
        }
    }

    /// Begins a group of flips that [`Self::undo_flips`] can take back.
    pub fn flip_mark(&self) -> FlipMark {
        FlipMark {
            log: self.flip_log.len(),
        }
    }

    /// Forgets the flips made so far: they can no longer be undone.
    pub fn keep_flips(&mut self) {
        self.flip_log.clear();
    }

    /// Undoes the flips made since `mark` (from [`Self::flip_mark`]), latest first, and
    /// forgets them; returns [`FlipIn::Stuck`] with their number.
    pub fn undo_flips(&mut self, mark: FlipMark, touched: &mut Vec<VertexId>) -> FlipIn {
        let mark = mark.log;
        let n = self.flip_log.len().saturating_sub(mark);
        // Taking flips back is never limited.
        self.flip_budget = usize::MAX;
        let mut ring = Vec::new();
        let mut star = Vec::new();
        while self.flip_log.len() > mark {
            let Some(flip) = self.flip_log.pop() else {
                break;
            };
            let logged = self.flip_log.len();
            // The inverse flip always applies (it restores cells that were valid); its own log
            // entry is dropped after it.
            let undone = match flip {
                Flip::TwoThree([x, y]) => {
                    self.edge_ring(x, y, &mut ring)
                        && ring.len() == 3
                        && self.try_flip32(x, y, &ring, touched)
                }
                Flip::Replaced { old, new } => {
                    // The cells made, found by their vertices, get the old ones back.
                    let cells: Option<Vec<CellId>> = new
                        .iter()
                        .map(|m| {
                            let first = *m.iter().find(|u| !u.is_ghost())?;
                            let tri = &self.tri;
                            self.stars
                                .find(tri, first, &mut star, |v| m.iter().all(|u| v.contains(u)))
                        })
                        .collect();
                    cells.is_some_and(|cells| {
                        let made = self.replace_cells(&cells, &old);
                        touched.extend(old.iter().flatten().filter(|u| !u.is_ghost()));
                        made.is_some()
                    })
                }
                Flip::ThreeTwo([x, y, z]) => {
                    let tri = &self.tri;
                    let found = self
                        .stars
                        .find(tri, x, &mut star, |v| v.contains(&y) && v.contains(&z));
                    found.is_some_and(|c| {
                        let v = self.tri.simplices[c.index()].v;
                        let i = (0..4).find(|&k| v[k] != x && v[k] != y && v[k] != z);
                        i.is_some_and(|i| self.try_flip23(c, i, touched))
                    })
                }
            };
            if undone {
                self.flip_log.truncate(logged);
            } else {
                debug_assert!(false, "an inverse flip applies: a bug in delmesh");
                self.flip_log.truncate(mark);
            }
        }
        FlipIn::Stuck(n)
    }

    /// Makes the triangle `a b c`, whose three edges must be present, a face by flips, at most
    /// `max_flips` of them; never removes a protected face or an edge for which `locked` is
    /// true. The vertices of the cells changed are appended to `touched`.
    pub fn flip_in_face(
        &mut self,
        a: VertexId,
        b: VertexId,
        c: VertexId,
        locked: &impl Fn(VertexId, VertexId) -> bool,
        max_flips: usize,
        touched: &mut Vec<VertexId>,
    ) -> FlipIn {
        let start = self.flip_mark();
        self.flip_budget = max_flips;
        let mut flips = 0;
        let mut star = Vec::new();
        loop {
            if self.face_in(a, b, c, &mut star) {
                return FlipIn::Present(flips);
            }
            if flips >= max_flips {
                return self.undo_flips(start, touched);
            }
            let mut made = 0;
            for (u, w, o) in [(a, b, c), (b, c, a), (c, a, b)] {
                if let Some((x, y)) = self.wedge_edge(u, w, o, &mut star) {
                    made = self.remove_edge(x, y, &[u, w], locked, touched, LINK_DEPTH);
                    if made > 0 {
                        break;
                    }
                }
            }
            if made == 0 {
                return self.undo_flips(start, touched);
            }
            flips += made;
        }
    }

    /// The cells around the edge `a b` into `star` (empty when it is not an edge); whether
    /// there are any.
    fn edge_cells(&mut self, a: VertexId, b: VertexId, star: &mut Vec<CellId>) -> bool {
        self.stars.star(&self.tri, a, star);
        let tri = &self.tri;
        star.retain(|&c| tri.simplices[c.index()].v.contains(&b));
        !star.is_empty()
    }

    /// Whether `a b c` is a face.
    fn face_in(&mut self, a: VertexId, b: VertexId, c: VertexId, star: &mut Vec<CellId>) -> bool {
        let tri = &self.tri;
        self.stars
            .find(tri, a, star, |v| v.contains(&b) && v.contains(&c))
            .is_some()
    }

    /// Where the segment from vertex `from` to vertex `to` (not an edge) leaves `from`: the
    /// cell of `from`'s star whose corner at `from` holds the segment's direction.
    fn first_crossing(&mut self, from: VertexId, to: VertexId, star: &mut Vec<CellId>) -> Crossing {
        self.stars.star(&self.tri, from, star);
        let pt = self.tri.points[to.index()];
        for &c in star.iter() {
            let v = self.tri.simplices[c.index()].v;
            if v.contains(&VertexId::GHOST) {
                continue;
            }
            let k = local(&v, from);
            // `to` on the cell's side of each of the three faces at `from`.
            let mut zeros = 0;
            let mut zero_at = 0;
            let mut inside = true;
            for j in (0..4).filter(|&j| j != k) {
                match self.orient_with(&v, j, pt) {
                    Sign::Negative => {
                        inside = false;
                        break;
                    }
                    Sign::Zero => {
                        zeros += 1;
                        zero_at = j;
                    }
                    Sign::Positive => {}
                }
            }
            if !inside {
                continue;
            }
            return match zeros {
                // Beyond the opposite face (it cannot be inside the cell: it is a vertex).
                0 if self.orient_with(&v, k, pt) == Sign::Negative => Crossing::Face(c, k),
                // In the plane of a face at `from`: through the edge of the opposite face
                // that lies in that plane.
                1 => {
                    let mut e = (0..4).filter(|&j| j != k && j != zero_at).map(|j| v[j]);
                    match (e.next(), e.next()) {
                        (Some(p), Some(q)) => Crossing::Edge(p, q),
                        _ => Crossing::Degenerate,
                    }
                }
                _ => Crossing::Degenerate,
            };
        }
        Crossing::Degenerate
    }

    /// Orientation of the four (finite) vertices `v`.
    #[inline]
    pub(crate) fn orient(&self, v: [VertexId; 4]) -> Sign {
        let q = v.map(|u| self.tri.points[u.index()]);
        orient3d(q[0], q[1], q[2], q[3])
    }

    /// Orientation of the finite cell `v` with its vertex at `j` replaced by the point `p`.
    #[inline]
    fn orient_with(&self, v: &[VertexId; 4], j: usize, p: [f64; 3]) -> Sign {
        let mut q = v.map(|u| self.tri.points[u.index()]);
        q[j] = p;
        orient3d(q[0], q[1], q[2], q[3])
    }

    /// Removes the face of `c` opposite its vertex `i` (crossed by a segment from that vertex)
    /// by a 2-3 flip, or, where the segment joining the two apexes passes beyond one of its
    /// edges, removes that edge. Returns the number of flips made (0: none possible).
    fn flip_face_away(
        &mut self,
        c: CellId,
        i: usize,
        locked: &impl Fn(VertexId, VertexId) -> bool,
        touched: &mut Vec<VertexId>,
    ) -> usize {
        if self.try_flip23(c, i, touched) {
            return 1;
        }
        let s = self.tri.simplices[c.index()];
        let across = s.n[i];
        let e = self.tri.simplices[across.cell().index()].v[across.facet()];
        if e.is_ghost() || s.v.contains(&VertexId::GHOST) {
            return 0;
        }
        // The face's edges that the segment from `s.v[i]` to `e` passes beyond.
        let pe = self.tri.points[e.index()];
        let face = [(i + 1) % 4, (i + 2) % 4, (i + 3) % 4];
        for &q in &face {
            // Beyond the edge opposite q, or through it (a coplanar 4-4 configuration).
            if self.orient_with(&s.v, q, pe) != Sign::Positive {
                let mut edge = face.iter().filter(|&&r| r != q).map(|&r| s.v[r]);
                if let (Some(x), Some(y)) = (edge.next(), edge.next()) {
                    let made = self.remove_edge(x, y, &[s.v[i], e], locked, touched, LINK_DEPTH);
                    if made > 0 {
                        return made;
                    }
                }
            }
        }
        0
    }

    /// The 2-3 flip of the face of `c` opposite its vertex `i`, if it is unprotected, between
    /// finite cells, and the segment joining their apexes crosses its interior.
    fn try_flip23(&mut self, c: CellId, i: usize, touched: &mut Vec<VertexId>) -> bool {
        let s = self.tri.simplices[c.index()];
        if self.flip_budget == 0 || self.is_protected(c, i) || s.v.contains(&VertexId::GHOST) {
            return false;
        }
        let across = s.n[i];
        let (m, j) = (across.cell(), across.facet());
        let e = self.tri.simplices[m.index()].v[j];
        if e.is_ghost() {
            return false;
        }
        let pe = self.tri.points[e.index()];
        let valid = (1..4).all(|d| self.orient_with(&s.v, (i + d) % 4, pe) == Sign::Positive);
        if !valid {
            return false;
        }
        self.flip_budget -= 1;
        self.flip23(c, i, m, j);
        self.flip_log.push(Flip::TwoThree([s.v[i], e]));
        touched.extend_from_slice(&s.v);
        touched.push(e);
        true
    }

    /// Removes the edge `p q` by flips: 2-3 flips of the faces around it (never one holding a
    /// vertex of `keep`) until three cells surround it, then a 3-2 flip. Returns the number of
    /// flips made (0: the edge is locked, on the hull, beside a protected face, or no flip
    /// applies; any 2-3 flips made stay).
    fn remove_edge(
        &mut self,
        p: VertexId,
        q: VertexId,
        keep: &[VertexId],
        locked: &impl Fn(VertexId, VertexId) -> bool,
        touched: &mut Vec<VertexId>,
        depth: usize,
    ) -> usize {
        if locked(p, q) {
            return 0;
        }
        let mut flips = 0;
        let mut ring = Vec::new();
        loop {
            if !self.edge_ring(p, q, &mut ring) {
                return flips;
            }
            match ring.len() {
                3 => return flips + usize::from(self.try_flip32(p, q, &ring, touched)),
                _ if self.try_flip_nm(p, q, &ring, keep, touched) => return flips + 1,
                _ => {}
            }
            // A ring vertex in one plane with p q and a kept vertex is kept too: with it, the
            // ring can come down to the 4-4 flip that joins the two.
            let pt = |u: VertexId| self.tri.points[u.index()];
            let partner = keep.first().and_then(|&k| {
                ring.iter().map(|r| r.1).find(|&w| {
                    !w.is_ghost() && w != k && orient3d(pt(p), pt(q), pt(k), pt(w)) == Sign::Zero
                })
            });
            // Reduce the ring: the face (p, q, w) between ring cells k - 1 and k, opposite
            // ring vertex w' = the other apex of cell k.
            let mut reduced = false;
            for &(c, w, w_next) in &ring {
                if keep.contains(&w) || Some(w) == partner {
                    continue;
                }
                let v = self.tri.simplices[c.index()].v;
                let i = local(&v, w_next);
                if self.try_flip23(c, i, touched) {
                    flips += 1;
                    reduced = true;
                    break;
                }
                if depth == 0 || v.contains(&VertexId::GHOST) {
                    continue;
                }
                // The segment joining the face's two apexes passes beyond its edge p w or
                // q w: that edge is removed first (one level down), then the face is tried
                // again.
                let across = self.tri.simplices[c.index()].n[i];
                let apex = self.tri.simplices[across.cell().index()].v[across.facet()];
                if apex.is_ghost() {
                    continue;
                }
                let pa = self.tri.points[apex.index()];
                for (end, other) in [(p, q), (q, p)] {
                    // Beyond the edge opposite `end` in the face: other w.
                    if self.orient_with(&v, local(&v, end), pa) == Sign::Negative {
                        let made =
                            self.remove_edge(other, w, &[apex, w_next], locked, touched, depth - 1);
                        if made > 0 {
                            flips += made;
                            reduced = true;
                            break;
                        }
                    }
                }
                if reduced {
                    break;
                }
            }
            if !reduced {
                return flips;
            }
        }
    }

    /// The cells around the edge `p q` in cyclic order, each with its two other vertices
    /// `(w_k, w_k+1)` so that cell `k` shares the face `p q w_k` with cell `k - 1` (on the
    /// hull, one `w` is the ghost vertex); false if `p q` is not an edge.
    pub(crate) fn edge_ring(
        &mut self,
        p: VertexId,
        q: VertexId,
        ring: &mut Vec<(CellId, VertexId, VertexId)>,
    ) -> bool {
        ring.clear();
        let mut star = std::mem::take(&mut self.scratch);
        let tri = &self.tri;
        let found = self.stars.find(tri, p, &mut star, |v| v.contains(&q));
        self.scratch = star;
        let Some(first) = found else {
            return false;
        };
        self.edge_ring_at(first, p, q, ring)
    }

    /// [`Self::edge_ring`], starting at `first`, a cell that has the edge `p q` (no search).
    pub(crate) fn edge_ring_at(
        &self,
        first: CellId,
        p: VertexId,
        q: VertexId,
        ring: &mut Vec<(CellId, VertexId, VertexId)>,
    ) -> bool {
        ring.clear();
        let tri = &self.tri;
        let mut c = first;
        let v = tri.simplices[c.index()].v;
        let mut others = v.iter().copied().filter(|&u| u != p && u != q);
        let (Some(mut w), Some(mut w_next)) = (others.next(), others.next()) else {
            return false;
        };
        loop {
            if ring.len() > 256 {
                return false;
            }
            ring.push((c, w, w_next));
            // Across the face p q w_next (opposite w) to the next cell.
            let v = self.tri.simplices[c.index()].v;
            c = self.tri.simplices[c.index()].n[local(&v, w)].cell();
            if c == first {
                return true;
            }
            let nv = self.tri.simplices[c.index()].v;
            let Some(next) = nv
                .iter()
                .copied()
                .find(|&u| u != p && u != q && u != w_next)
            else {
                return false;
            };
            (w, w_next) = (w_next, next);
        }
    }

    /// The 3-2 flip of the edge `p q` surrounded by the three cells of `ring`, if none of the
    /// three faces around it is protected and both new cells are strictly positive.
    fn try_flip32(
        &mut self,
        p: VertexId,
        q: VertexId,
        ring: &[(CellId, VertexId, VertexId)],
        touched: &mut Vec<VertexId>,
    ) -> bool {
        let (c, w0, w1) = ring[0];
        let (m, _, w2) = ring[1];
        if self.flip_budget == 0 || [w0, w1, w2].iter().any(|w| w.is_ghost()) {
            return false;
        }
        let v = self.tri.simplices[c.index()].v;
        let (i, k) = (local(&v, w0), local(&v, w1));
        // The three faces p q w: of c opposite w1 and w0, and of the third cell.
        let third = ring[2].0;
        let tv = self.tri.simplices[third.index()].v;
        if self.is_protected(c, i)
            || self.is_protected(c, k)
            || self.is_protected(third, local(&tv, w0))
        {
            return false;
        }
        // The new cells: c with p, then q, replaced by w2.
        let pw = self.tri.points[w2.index()];
        for end in [p, q] {
            if self.orient_with(&v, local(&v, end), pw) != Sign::Positive {
                return false;
            }
        }
        if self.flip32(c, i, k, m, &|_| true).is_none() {
            return false;
        }
        self.flip_budget -= 1;
        self.flip_log.push(Flip::ThreeTwo([w0, w1, w2]));
        touched.extend_from_slice(&[p, q, w0, w1, w2]);
        true
    }

    /// Removes the edge `p q` surrounded by the `n` cells of `ring` (n ≥ 4) in one flip: the
    /// ring's polygon is triangulated by a fan from one of its vertices `r`, and each fan
    /// triangle joined to `p` and to `q` gives the 2(n − 2) new cells (the 4-4 flip when n is
    /// 4; with the ghost vertex in the ring, the flip of two coplanar hull triangles' shared
    /// edge together with the cells under them). Fans from `keep`'s vertices are tried first.
    /// Made if none of the faces around `p q` is protected, every new finite cell is strictly
    /// positive and, on the hull, the two hull faces at `p q` lie in one plane and `r` is one of
    /// their corners (so the hull keeps its shape).
    fn try_flip_nm(
        &mut self,
        p: VertexId,
        q: VertexId,
        ring: &[(CellId, VertexId, VertexId)],
        keep: &[VertexId],
        touched: &mut Vec<VertexId>,
    ) -> bool {
        if self.flip_budget == 0 {
            return false;
        }
        let Some((old, new, _)) = self.flip_nm(p, q, ring, keep, |_, _| true) else {
            return false;
        };
        self.flip_budget -= 1;
        self.flip_log.push(Flip::Replaced { old, new });
        touched.extend_from_slice(&[p, q]);
        touched.extend(ring.iter().map(|r| r.1));
        true
    }

    /// [`Self::try_flip_nm`]'s flip, not logged, made only if `accept` takes the new cells'
    /// vertices too: the old and new cells' vertices and the new cells, or `None` (nothing
    /// changed).
    #[allow(clippy::type_complexity)]
    pub(crate) fn flip_nm(
        &mut self,
        p: VertexId,
        q: VertexId,
        ring: &[(CellId, VertexId, VertexId)],
        keep: &[VertexId],
        accept: impl Fn(&Self, &[[VertexId; 4]]) -> bool,
    ) -> Option<(Vec<[VertexId; 4]>, Vec<[VertexId; 4]>, Vec<CellId>)> {
        let n = ring.len();
        for &(c, _, w_next) in ring {
            // The face p q w is the one opposite w_next.
            let v = self.tri.simplices[c.index()].v;
            if self.is_protected(c, local(&v, w_next)) {
                return None;
            }
        }
        let r: Vec<VertexId> = ring.iter().map(|x| x.1).collect();
        // On the hull: the ring vertices beside the ghost, which must be coplanar with p q.
        let hull = r.iter().position(|w| w.is_ghost()).map(|g| {
            let (a, b) = (r[(g + n - 1) % n], r[(g + 1) % n]);
            (a, b, self.orient([p, q, a, b]) == Sign::Zero)
        });
        let mut apexes: Vec<usize> = (0..n).filter(|&i| !r[i].is_ghost()).collect();
        apexes.sort_by_key(|&i| !keep.contains(&r[i]));
        for i in apexes {
            if let Some((a, b, flat)) = hull {
                if !flat || (r[i] != a && r[i] != b) {
                    continue;
                }
            }
            // Cell j (p q r_j r_j+1), for the j not beside r_i, with q and then p replaced.
            let mut new = Vec::with_capacity(2 * (n - 2));
            for &(c, w, w_next) in ring {
                if w == r[i] || w_next == r[i] {
                    continue;
                }
                let v = self.tri.simplices[c.index()].v;
                for end in [q, p] {
                    let mut m = v;
                    m[local(&v, end)] = r[i];
                    new.push(m);
                }
            }
            let valid = new
                .iter()
                .all(|&m| m.contains(&VertexId::GHOST) || self.orient(m) == Sign::Positive);
            if !valid || !accept(self, &new) {
                continue;
            }
            let old_cells: Vec<CellId> = ring.iter().map(|x| x.0).collect();
            let old: Vec<[VertexId; 4]> = old_cells
                .iter()
                .map(|c| self.tri.simplices[c.index()].v)
                .collect();
            let Some(cells) = self.replace_cells(&old_cells, &new) else {
                continue;
            };
            return Some((old, new, cells));
        }
        None
    }

    /// Replaces the cells `old` (together a region whose boundary faces are the faces of
    /// `old` not shared between two of them) by cells with the vertices `new`, positively
    /// oriented, covering the same region: every face of a new cell must be either shared with
    /// another new cell or one of the region's boundary faces. Neighbours, incidence,
    /// protection of the boundary faces and the tag (of `old[0]`) follow. Returns the new
    /// cells, or `None`, changing nothing, if the faces do not match.
    pub(crate) fn replace_cells(
        &mut self,
        old: &[CellId],
        new: &[[VertexId; 4]],
    ) -> Option<Vec<CellId>> {
        let sorted = |mut f: [VertexId; 3]| {
            f.sort_unstable();
            f
        };
        let face =
            |v: &[VertexId; 4], i: usize| sorted([v[(i + 1) % 4], v[(i + 2) % 4], v[(i + 3) % 4]]);
        // The region's boundary faces: (vertices, the facet outside, protected).
        let mut outer: Vec<([VertexId; 3], FacetRef, bool)> = Vec::new();
        for &c in old {
            let s = self.tri.simplices[c.index()];
            for i in 0..4 {
                if !old.contains(&s.n[i].cell()) {
                    outer.push((face(&s.v, i), s.n[i], self.is_protected(c, i)));
                }
            }
        }
        // Each new face: matched to another new cell's, or to a boundary face (used once).
        enum Link {
            Inner(usize, usize),
            Outer(usize),
        }
        let mut links = Vec::with_capacity(4 * new.len());
        let mut used = vec![false; outer.len()];
        let keys: Vec<[[VertexId; 3]; 4]> = new
            .iter()
            .map(|v| [0, 1, 2, 3].map(|i| face(v, i)))
            .collect();
        for (a, ka) in keys.iter().enumerate() {
            for (i, f) in ka.iter().enumerate() {
                let inner = keys.iter().enumerate().find_map(|(b, kb)| {
                    (b != a)
                        .then(|| kb.iter().position(|g| g == f).map(|j| (b, j)))
                        .flatten()
                });
                if let Some((b, j)) = inner {
                    links.push((a, i, Link::Inner(b, j)));
                } else {
                    let k = outer.iter().position(|o| o.0 == *f)?;
                    if used[k] {
                        return None;
                    }
                    used[k] = true;
                    links.push((a, i, Link::Outer(k)));
                }
            }
        }
        if used.iter().any(|&u| !u) {
            return None;
        }
        let tag = self.tags[old[0].index()];
        let mut cells: Vec<CellId> = old.iter().copied().take(new.len()).collect();
        for v in new.iter().skip(old.len()) {
            cells.push(self.tri.alloc_cell(v));
        }
        self.grow_cell_data();
        for &c in old.iter().skip(new.len()) {
            self.tri.release_cell(c);
            self.protected[c.index()] = 0;
        }
        for (k, v) in new.iter().enumerate() {
            self.tri.set_cell_vertices(cells[k], *v);
            self.protected[cells[k].index()] = 0;
            self.tags[cells[k].index()] = tag;
        }
        for (a, i, link) in links {
            match link {
                Link::Inner(b, j) => {
                    self.tri.simplices[cells[a].index()].n[i] = FacetRef::new(cells[b], j);
                }
                Link::Outer(k) => {
                    let (_, outside, protected) = outer[k];
                    self.tri.link(FacetRef::new(cells[a], i), outside);
                    self.protected[cells[a].index()] |= u8::from(protected) << i;
                }
            }
        }
        for (k, v) in new.iter().enumerate() {
            for &u in v {
                if !u.is_ghost() {
                    self.tri.incident[u.index()] = cells[k];
                }
            }
        }
        self.tri.last = cells[0];
        Some(cells)
    }

    /// Of the cells around the edge `u w`, the one whose wedge strictly holds the point of
    /// vertex `o`: its other edge `x y`, which then crosses the triangle `u w o` (when `o` is
    /// not a vertex of it, i.e. the triangle is not a face). `None` if no cell holds it
    /// strictly (`u w` missing, or `o` in the plane of a face at `u w`).
    fn wedge_edge(
        &mut self,
        u: VertexId,
        w: VertexId,
        o: VertexId,
        star: &mut Vec<CellId>,
    ) -> Option<(VertexId, VertexId)> {
        if !self.edge_cells(u, w, star) {
            return None;
        }
        let po = self.tri.points[o.index()];
        for &c in star.iter() {
            let v = self.tri.simplices[c.index()].v;
            if v.contains(&VertexId::GHOST) || v.contains(&o) {
                continue;
            }
            let mut others = (0..4).filter(|&j| v[j] != u && v[j] != w);
            let (Some(jx), Some(jy)) = (others.next(), others.next()) else {
                continue;
            };
            if self.orient_with(&v, jx, po) == Sign::Positive
                && self.orient_with(&v, jy, po) == Sign::Positive
            {
                return Some((v[jx], v[jy]));
            }
        }
        None
    }
}
