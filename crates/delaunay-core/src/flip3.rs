//! Moving the vertices of a [`ConstrainedTriangulation3`] and restoring its constrained Delaunay
//! property by flips.
//!
//! Smoothing moves interior points, which leaves cells whose circumsphere holds a neighbour.
//! Rather than triangulating all the points again and recovering the surface a second time,
//! the mesh is repaired where it is: every unprotected face that fails the exact (symbolically
//! perturbed) insphere test is flipped,
//! - 2-3, when the segment between the two opposite vertices crosses the face: the two cells
//!   become three around that segment;
//! - 3-2, when it passes beyond one edge of the face and that edge has exactly three cells
//!   around it: they become two.
//!
//! A flip never removes a protected face, never joins cells of different tags and adds no
//! vertex. Each flip lowers the triangulation on the (perturbed) lifting paraboloid, so none is
//! ever undone and the flips terminate. In 3D they can stop short, though: a failing face whose
//! flip would need a 4-4 flip (a degenerate, coplanar configuration), an edge of degree above
//! three or a protected face (typically a boundary edge with only two cells around it in the
//! domain). [`ConstrainedTriangulation3::make_delaunay`] lists the faces left;
//! [`ConstrainedTriangulation3::edges_to_split`] names the edge whose split removes each one
//! ([`ConstrainedTriangulation3::split_edge`]), after which the flips go on from the new cells
//! ([`ConstrainedTriangulation3::make_delaunay_from`]).

use rayon::prelude::*;

use crate::constrained3::ConstrainedTriangulation3;
use crate::dim::{Dim, D3};
use crate::error::ConstraintError;
use crate::ids::{CellId, FacetRef, VertexId};
use delmesh_predicates::{orient3d, Sign};

impl Flips3 {
    /// Flips made, of every kind.
    pub fn flips(&self) -> usize {
        self.two_three + self.three_two + self.four_four
    }
}

/// What [`ConstrainedTriangulation3::make_delaunay`] did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Flips3 {
    /// Faces that failed the insphere test before any flip.
    pub failing: usize,
    /// 2-3 flips made.
    pub two_three: usize,
    /// 3-2 flips made.
    pub three_two: usize,
    /// 4-4 flips made (where the four points around an edge lie in one plane).
    pub four_four: usize,
    /// The faces still failing the test, which no flip could mend, each once (empty: the
    /// triangulation is constrained Delaunay across every face in scope). Valid until the
    /// triangulation changes.
    pub left: Vec<FacetRef>,
}

impl ConstrainedTriangulation3 {
    /// Moves vertices (caller's coordinates) all at once, if every cell around them stays
    /// finite and positively oriented; otherwise nothing moves.
    ///
    /// # Errors
    /// [`ConstraintError::InvalidMove`] naming the first vertex whose move inverts a cell, or
    /// that is on the hull; coordinate errors as for insertion.
    pub fn move_vertices(&mut self, moves: &[(VertexId, [f64; 3])]) -> Result<(), ConstraintError> {
        let (old, moved) = self.tri.place_vertices(moves)?;
        // One scan over the cells in slot order (in parallel): every live cell with a moved
        // vertex must be finite and positive.
        let points = &self.tri.points;
        let broken = |s: &crate::triangulation::Simplex| {
            s.v[0] != VertexId::DEAD
                && s.v.iter().any(|&u| !u.is_ghost() && moved[u.index()])
                && (s.v.iter().any(|u| u.is_ghost())
                    || D3::orient(&s.v.map(|u| points[u.index()])) != Sign::Positive)
        };
        let first = self
            .tri
            .simplices
            .par_iter()
            .with_min_len(1 << 12)
            .find_first(|s| broken(s))
            .copied();
        if let Some(s) = first {
            // Name the first vertex, in `moves` order, of the broken cell.
            let vertex = moves
                .iter()
                .map(|&(v, _)| v)
                .find(|v| s.v.contains(v))
                .unwrap_or(moves[0].0);
            self.tri.put_back(&old);
            return Err(ConstraintError::InvalidMove { vertex });
        }
        Ok(())
    }

    /// Moves vertex `v` to `point` (caller's coordinates) if every cell around it stays finite
    /// and positively oriented; otherwise it stays where it is. Checks the vertex's star only
    /// (cheaper than [`Self::move_vertices`] for a few vertices of a large mesh); `star` is a
    /// buffer. Returns whether it moved.
    pub fn move_vertex(&mut self, v: VertexId, point: [f64; 3], star: &mut Vec<CellId>) -> bool {
        if v.is_ghost() || v.index() >= self.tri.num_vertices() {
            return false;
        }
        let Ok(q) = self.tri.scaled_input(self.tri.flush_tiny(point)) else {
            return false;
        };
        self.star(v, star);
        let old = self.tri.points[v.index()];
        self.tri.points[v.index()] = q;
        let points = &self.tri.points;
        let valid = star.iter().all(|&c| {
            let s = &self.tri.simplices[c.index()];
            !s.v.iter().any(|u| u.is_ghost())
                && D3::orient(&s.v.map(|u| points[u.index()])) == Sign::Positive
        });
        if !valid {
            self.tri.points[v.index()] = old;
        }
        valid
    }

    /// Flips unprotected faces between finite cells whose tags are `in_scope` until each passes
    /// the insphere test, or no flip can mend those left (see the module docs). Cells out of
    /// scope are never changed.
    pub fn make_delaunay(&mut self, in_scope: impl Fn(u32) -> bool + Sync) -> Flips3 {
        // The failing faces, each once, found in parallel in cell order (read-only). A face
        // that passes can fail only after a flip changes one of its cells, and every flip
        // queues the faces around it.
        let this = &*self;
        let failing: Vec<FacetRef> = (0..self.tri.simplices.len() as u32)
            .into_par_iter()
            .with_min_len(1 << 12)
            .map(CellId)
            .flat_map_iter(|c| {
                let scope = &in_scope;
                (0..4).filter_map(move |i| {
                    let n = this.tri.simplices[c.index()].n[i].cell();
                    (c < n && this.fails(c, i, scope)).then_some(FacetRef::new(c, i))
                })
            })
            .collect();
        let n = failing.len();
        self.flip_from(failing, n, in_scope, &|_, _| false, &mut Vec::new())
    }

    /// [`Self::make_delaunay`] when the only faces that may fail are among `faces` (for
    /// instance those of the cells a change made, and the faces left by the last flips); stale
    /// or passing faces are skipped. `failing` counts the faces of `faces` that fail.
    pub fn make_delaunay_from(
        &mut self,
        faces: Vec<FacetRef>,
        in_scope: impl Fn(u32) -> bool,
    ) -> Flips3 {
        let failing = self.distinct_failing(&faces, &in_scope).len();
        self.flip_from(faces, failing, in_scope, &|_, _| false, &mut Vec::new())
    }

    /// [`Self::make_delaunay_from`] that never removes an edge for which `locked` is true (a
    /// boundary edge recovered by flips, whose faces are not protected yet), and appends the
    /// vertices of the cells it changes to `touched`.
    pub fn make_delaunay_from_locked(
        &mut self,
        faces: Vec<FacetRef>,
        in_scope: impl Fn(u32) -> bool,
        locked: &impl Fn(VertexId, VertexId) -> bool,
        touched: &mut Vec<VertexId>,
    ) -> Flips3 {
        let failing = self.distinct_failing(&faces, &in_scope).len();
        self.flip_from(faces, failing, in_scope, locked, touched)
    }

    /// The flips from the faces `stack` (`failing` of them fail).
    fn flip_from(
        &mut self,
        mut stack: Vec<FacetRef>,
        failing: usize,
        in_scope: impl Fn(u32) -> bool,
        locked: &impl Fn(VertexId, VertexId) -> bool,
        touched: &mut Vec<VertexId>,
    ) -> Flips3 {
        let mut report = Flips3 {
            failing,
            ..Flips3::default()
        };
        // No flip is ever undone, so the number of flips is bounded; this bound only guards
        // against a bug.
        let budget = 64 * self.tri.simplices.len() + 1024;
        let mut stuck: Vec<FacetRef> = Vec::new();
        loop {
            let before = report.flips();
            while let Some(f) = stack.pop() {
                if report.flips() >= budget {
                    stuck.push(f);
                    stuck.append(&mut stack);
                    break;
                }
                // The new cells' faces may fail now.
                let queue = |stack: &mut Vec<FacetRef>, cells: &[CellId]| {
                    for &cell in cells {
                        stack.extend((0..4).map(|q| FacetRef::new(cell, q)));
                    }
                };
                match self.mend(f, &in_scope, locked, touched) {
                    Mend::Passes => {}
                    Mend::Stuck => stuck.push(f),
                    Mend::TwoThree(cells) => {
                        report.two_three += 1;
                        queue(&mut stack, &cells);
                    }
                    Mend::ThreeTwo(cells) => {
                        report.three_two += 1;
                        queue(&mut stack, &cells);
                    }
                    Mend::Replaced(cells) => {
                        report.four_four += 1;
                        queue(&mut stack, &cells);
                    }
                }
            }
            // A face refused earlier may be flippable now that its surroundings changed.
            if stuck.is_empty() || report.flips() == before || report.flips() >= budget {
                break;
            }
            stack = std::mem::take(&mut stuck);
        }
        // Every failing face is in `stuck` now (possibly twice, or through a reused slot).
        report.left = self.distinct_failing(&stuck, &in_scope);
        report
    }

    /// Whether the face `f` is live, unprotected, between two finite cells in scope, and
    /// fails the insphere test.
    pub fn face_fails(&self, f: FacetRef, in_scope: impl Fn(u32) -> bool) -> bool {
        self.tri.is_live(f.cell()) && self.fails(f.cell(), f.facet(), &in_scope)
    }

    /// The faces of `faces` that fail, each once (named from its lower cell slot), sorted.
    fn distinct_failing(
        &self,
        faces: &[FacetRef],
        in_scope: &impl Fn(u32) -> bool,
    ) -> Vec<FacetRef> {
        let mut out: Vec<FacetRef> = faces
            .iter()
            .filter(|f| self.tri.is_live(f.cell()) && self.fails(f.cell(), f.facet(), in_scope))
            .map(|&f| {
                let twin = self.tri.simplices[f.cell().index()].n[f.facet()];
                if twin.0 < f.0 {
                    twin
                } else {
                    f
                }
            })
            .collect();
        out.sort_unstable_by_key(|f| f.0);
        out.dedup();
        out
    }

    /// The three edges of the failing face `f`, in the order to try splitting them where no
    /// flip mends it (splitting any removes the face: both its cells hold the edge). First the
    /// edge the segment between the two opposite vertices passes beyond, where there is one,
    /// then by decreasing length.
    pub fn edges_to_split(&self, f: FacetRef) -> [[VertexId; 2]; 3] {
        let (c, i) = (f.cell(), f.facet());
        let s = &self.tri.simplices[c.index()];
        let p = |u: VertexId| self.tri.points[u.index()];
        let (face, sign) = self.crossing(c, i);
        // The edge opposite face vertex `q`, and its squared length.
        let edge = |q: usize| {
            let (a, b) = (s.v[face[(q + 1) % 3]], s.v[face[(q + 2) % 3]]);
            if a < b {
                [a, b]
            } else {
                [b, a]
            }
        };
        let length2 = |q: usize| {
            let [a, b] = edge(q);
            let (pa, pb) = (p(a), p(b));
            (0..3)
                .map(|k| (pa[k] - pb[k]) * (pa[k] - pb[k]))
                .sum::<f64>()
        };
        let reflex = beyond_one_edge(&sign);
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| {
            (Some(b) == reflex)
                .cmp(&(Some(a) == reflex))
                .then(length2(b).total_cmp(&length2(a)))
        });
        order.map(edge)
    }

    /// Whether the face of `c` opposite its vertex `i` is unprotected, between two finite
    /// cells in scope, and fails the insphere test.
    fn fails(&self, c: CellId, i: usize, in_scope: &impl Fn(u32) -> bool) -> bool {
        let s = &self.tri.simplices[c.index()];
        if s.v[0] == VertexId::DEAD || self.is_protected(c, i) || !in_scope(self.tags[c.index()]) {
            return false;
        }
        let across = s.n[i];
        let m = across.cell();
        if s.v.contains(&VertexId::GHOST) || !in_scope(self.tags[m.index()]) {
            return false;
        }
        let e = self.tri.simplices[m.index()].v[across.facet()];
        if e.is_ghost() {
            return false;
        }
        D3::insphere_cell(&self.tri.points, &s.v, self.tri.points[e.index()]) == Sign::Positive
    }

    /// For the face of `c` opposite its vertex `i`: its local positions `face` in `c`, and the
    /// orientation of `c` with the vertex at `face[q]` replaced by the apex across the face.
    /// All positive exactly when the segment between the two apexes crosses the face.
    fn crossing(&self, c: CellId, i: usize) -> ([usize; 3], [Sign; 3]) {
        let s = &self.tri.simplices[c.index()];
        let across = s.n[i];
        let e = self.tri.simplices[across.cell().index()].v[across.facet()];
        let face: [usize; 3] = [(i + 1) % 4, (i + 2) % 4, (i + 3) % 4];
        let sign = face.map(|k| {
            let mut v = s.v.map(|u| self.tri.points[u.index()]);
            v[k] = self.tri.points[e.index()];
            orient3d(v[0], v[1], v[2], v[3])
        });
        (face, sign)
    }

    /// Flips the face `f` if it fails and a 2-3 or 3-2 flip applies (the latter never removing
    /// a `locked` edge), appending the vertices of the cells it looks at to `touched`.
    fn mend(
        &mut self,
        f: FacetRef,
        in_scope: &impl Fn(u32) -> bool,
        locked: &impl Fn(VertexId, VertexId) -> bool,
        touched: &mut Vec<VertexId>,
    ) -> Mend {
        let (c, i) = (f.cell(), f.facet());
        if !self.tri.is_live(c) || !self.fails(c, i, in_scope) {
            return Mend::Passes;
        }
        let across = self.tri.simplices[c.index()].n[i];
        let (m, j) = (across.cell(), across.facet());
        touched.extend_from_slice(&self.tri.simplices[c.index()].v);
        touched.push(self.tri.simplices[m.index()].v[j]);
        let (face, sign) = self.crossing(c, i);
        if sign.iter().all(|&g| g == Sign::Positive) {
            return Mend::TwoThree(self.flip23(c, i, m, j));
        }
        let Some(q) = beyond_one_edge(&sign) else {
            return self.mend_through_edge(c, &face, &sign, in_scope, locked);
        };
        let v = self.tri.simplices[c.index()].v;
        if locked(v[face[(q + 1) % 3]], v[face[(q + 2) % 3]]) {
            return Mend::Stuck;
        }
        self.flip32(c, i, face[q], m, in_scope)
            .map_or(Mend::Stuck, Mend::ThreeTwo)
    }

    /// The 2-3 flip of the face between `c` (opposite its vertex `i`) and `m` (opposite `j`):
    /// three cells around the segment joining their apexes, each `c` with one face vertex
    /// replaced by `m`'s apex (so every cell keeps `c`'s local numbering). Returns them.
    pub(crate) fn flip23(&mut self, c: CellId, i: usize, m: CellId, j: usize) -> [CellId; 3] {
        let s = self.tri.simplices[c.index()];
        let t = self.tri.simplices[m.index()];
        let e = t.v[j];
        let face: [usize; 3] = [(i + 1) % 4, (i + 2) % 4, (i + 3) % 4];
        // Where each face vertex sits in `m`.
        let in_t = face.map(|k| local(&t.v, s.v[k]));
        let (pc, pm, tag) = (
            self.protected[c.index()],
            self.protected[m.index()],
            self.tags[c.index()],
        );
        let third = {
            let mut v = s.v;
            v[face[2]] = e;
            self.tri.alloc_cell(&v)
        };
        let slots = [c, m, third];
        self.grow_cell_data();
        for (q, &k) in face.iter().enumerate() {
            let cell = slots[q];
            let mut v = s.v;
            v[k] = e;
            self.tri.set_cell_vertices(cell, v);
            for (r, &l) in face.iter().enumerate() {
                if l != k {
                    self.tri.simplices[cell.index()].n[l] = FacetRef::new(slots[r], k);
                }
            }
            self.protected[cell.index()] = ((pc >> k) & 1) << k | ((pm >> in_t[q]) & 1) << i;
            self.tags[cell.index()] = tag;
        }
        // The outer faces last: an outer neighbour is never one of the two old cells.
        for (q, &k) in face.iter().enumerate() {
            self.tri.link(FacetRef::new(slots[q], k), s.n[k]);
            self.tri.link(FacetRef::new(slots[q], i), t.n[in_t[q]]);
        }
        for (q, &k) in face.iter().enumerate() {
            // Face vertex `k` is in every new cell but the one that replaced it.
            self.tri.incident[s.v[k].index()] = slots[(q + 1) % 3];
        }
        self.tri.incident[s.v[i].index()] = c;
        self.tri.incident[e.index()] = c;
        self.tri.last = c;
        slots
    }

    /// The 3-2 flip around the edge of `c`'s face `i` that does not hold `c`'s vertex `k`, if
    /// exactly three cells surround it (`c`, `m` across face `i`, and a third holding both
    /// apexes), all in scope with unprotected faces between them. The two new cells are `c`
    /// with one end of the edge replaced by `m`'s apex. `None` (nothing changed) otherwise.
    pub(crate) fn flip32(
        &mut self,
        c: CellId,
        i: usize,
        k: usize,
        m: CellId,
        in_scope: &impl Fn(u32) -> bool,
    ) -> Option<[CellId; 2]> {
        let s = self.tri.simplices[c.index()];
        let t = self.tri.simplices[m.index()];
        let e = t.v[s.n[i].facet()];
        let z = s.v[k];
        // The third cell: across `c`'s face opposite `z` (apex, edge), and across `m`'s.
        let u_ref = s.n[k];
        let u = u_ref.cell();
        let zt = local(&t.v, z);
        let w = self.tri.simplices[u.index()];
        if self.is_protected(c, k)
            || self.is_protected(m, zt)
            || t.n[zt].cell() != u
            || w.v.contains(&VertexId::GHOST)
            || !w.v.contains(&e)
            || self.tags[u.index()] != self.tags[c.index()]
            || !in_scope(self.tags[u.index()])
        {
            return None;
        }
        let edge: [usize; 2] = {
            let mut q = (0..4).filter(|&q| q != i && q != k);
            [q.next().unwrap_or(0), q.next().unwrap_or(0)]
        };
        let (pc, pm, pu, tag) = (
            self.protected[c.index()],
            self.protected[m.index()],
            self.protected[u.index()],
            self.tags[c.index()],
        );
        // New cell `q` replaces the edge end at `edge[q]` by `e`; the other end stays in it.
        let slots = [c, m];
        for (q, &x) in edge.iter().enumerate() {
            let cell = slots[q];
            let other = edge[1 - q];
            let mut v = s.v;
            v[x] = e;
            self.tri.set_cell_vertices(cell, v);
            self.tri.simplices[cell.index()].n[other] = FacetRef::new(slots[1 - q], x);
            let end = s.v[x];
            let (in_t, in_w) = (local(&t.v, end), local(&w.v, end));
            self.protected[cell.index()] =
                ((pc >> x) & 1) << x | ((pm >> in_t) & 1) << i | ((pu >> in_w) & 1) << k;
            self.tags[cell.index()] = tag;
        }
        for (q, &x) in edge.iter().enumerate() {
            let end = s.v[x];
            let (in_t, in_w) = (local(&t.v, end), local(&w.v, end));
            self.tri.link(FacetRef::new(slots[q], x), s.n[x]);
            self.tri.link(FacetRef::new(slots[q], i), t.n[in_t]);
            self.tri.link(FacetRef::new(slots[q], k), w.n[in_w]);
        }
        // Free the third cell.
        self.tri.release_cell(u);
        self.protected[u.index()] = 0;
        for (q, &x) in edge.iter().enumerate() {
            // Each end of the edge stays only in the cell that kept it.
            self.tri.incident[s.v[x].index()] = slots[1 - q];
        }
        for v in [s.v[i], z, e] {
            self.tri.incident[v.index()] = c;
        }
        self.tri.last = c;
        Some(slots)
    }

    /// Per-cell data for cell slots the triangulation has just grown.
    pub(crate) fn grow_cell_data(&mut self) {
        let n = self.tri.simplices.len();
        if self.protected.len() < n {
            self.protected.resize(n, 0);
            self.tags.resize(n, 0);
        }
    }
}

impl ConstrainedTriangulation3 {
    /// Where the segment joining a failing face's two apexes passes exactly through one of its
    /// edges (`sign` zero there, positive elsewhere: the four points around that edge lie in
    /// one plane), the edge-removing flip of that edge when four cells surround it (the 4-4
    /// flip; [`Self::flip_nm`]), which removes the face; not where a face between two of its
    /// new cells would fail in turn (the other diagonal is no better: flipping back and forth
    /// would not end), nor across cells out of scope or of other tags.
    fn mend_through_edge(
        &mut self,
        c: CellId,
        face: &[usize; 3],
        sign: &[Sign; 3],
        in_scope: &impl Fn(u32) -> bool,
        locked: &impl Fn(VertexId, VertexId) -> bool,
    ) -> Mend {
        let zeros = sign.iter().filter(|&&g| g == Sign::Zero).count();
        let negatives = sign.iter().filter(|&&g| g == Sign::Negative).count();
        let Some(q) = sign.iter().position(|&g| g == Sign::Zero) else {
            return Mend::Stuck;
        };
        if zeros != 1 || negatives != 0 {
            return Mend::Stuck;
        }
        let v = self.tri.simplices[c.index()].v;
        let (x, y) = (v[face[(q + 1) % 3]], v[face[(q + 2) % 3]]);
        let mut ring = Vec::new();
        if locked(x, y) || !self.edge_ring(x, y, &mut ring) || ring.len() != 4 {
            return Mend::Stuck;
        }
        let tag = self.tags[c.index()];
        if !in_scope(tag) || ring.iter().any(|r| self.tags[r.0.index()] != tag) {
            return Mend::Stuck;
        }
        match self.flip_nm(x, y, &ring, &[], |this, new| this.inner_faces_pass(new)) {
            Some((_, _, cells)) => Mend::Replaced(cells),
            None => Mend::Stuck,
        }
    }
}

impl ConstrainedTriangulation3 {
    /// Whether every face shared by two of the (finite, positive) cells `new` passes the
    /// insphere test.
    fn inner_faces_pass(&self, new: &[[VertexId; 4]]) -> bool {
        let points = &self.tri.points;
        new.iter().enumerate().all(|(i, a)| {
            new[i + 1..].iter().all(|b| {
                let mut apart = b.iter().filter(|u| !a.contains(u));
                match (apart.next(), apart.next()) {
                    (Some(&apex), None) if !apex.is_ghost() && !a.contains(&VertexId::GHOST) => {
                        D3::insphere_cell(points, a, points[apex.index()]) != Sign::Positive
                    }
                    _ => true,
                }
            })
        })
    }
}

/// What [`ConstrainedTriangulation3::mend`] did with a face.
enum Mend {
    /// It passes the test (or is out of scope, protected, or gone).
    Passes,
    /// It fails, and no flip applies.
    Stuck,
    /// Flipped 2-3, into these cells.
    TwoThree([CellId; 3]),
    /// Flipped 3-2, into these cells.
    ThreeTwo([CellId; 2]),
    /// Flipped 4-4 (a coplanar configuration), into these cells.
    Replaced(Vec<CellId>),
}

/// Where the segment between the apexes of a face passes beyond exactly one edge of it (the
/// signs of [`ConstrainedTriangulation3::crossing`]: one negative, two positive), the position
/// `q` of the face vertex opposite that edge.
fn beyond_one_edge(sign: &[Sign; 3]) -> Option<usize> {
    let negative = sign.iter().filter(|&&g| g == Sign::Negative).count();
    let positive = sign.iter().filter(|&&g| g == Sign::Positive).count();
    (negative == 1 && positive == 2)
        .then(|| sign.iter().position(|&g| g == Sign::Negative))
        .flatten()
}

/// The local index of `v` in a cell's vertices (it is there: the callers checked).
#[inline]
pub(crate) fn local(cell: &[VertexId; 4], v: VertexId) -> usize {
    cell.iter()
        .position(|&u| u == v)
        .expect("the vertex is in the cell: a bug in delmesh")
}
