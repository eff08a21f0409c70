//! The [`Triangulation`]: flat arrays of cells and neighbours, built by Bowyer–Watson insertion.
//!
//! This is the paper's data structure (Table 1: each Voronoi vertex = its forming points and its
//! neighbouring Voronoi vertices) in modern form:
//!
//! - `cells[C·c .. C·c+C]` are the vertices of cell `c`, positively oriented;
//! - `neighbors[C·c + i]` is the [`FacetRef`] of the neighbour across the facet opposite local
//!   vertex `i`, *including the neighbour's own facet index*, so crossing a facet is O(1);
//! - a ghost vertex ([`VertexId::GHOST`]) closes the convex hull: every hull facet forms a ghost
//!   cell with it, so the result is exactly the Delaunay triangulation of the input points (the
//!   paper's box corners, R13, would change the hull);
//! - freed cells go on a free list and are reused (the paper's step 8);
//! - `incident[v]` is one cell containing vertex `v` (the paper's node → Voronoi vertex vector).
//!
//! Insertion (steps 2–8 of §3) is: walk from the cells made by the previous insertion to a cell
//! containing the new point (or a hull facet it sees), grow the cavity of cells whose
//! circumsphere contains it by a search over neighbours, connect the point to the cavity's
//! boundary facets, and link the new cells to each other. All decisions are exact predicates with
//! the symbolic perturbation of `delmesh-predicates`, so no point is ever rejected or retried.
//!
//! Vertices are numbered in insertion order (which is spatially sorted, for cache locality);
//! [`Triangulation::input_index`] and [`Triangulation::vertex_of_input`] translate to and from
//! the caller's numbering.

use crate::dim::Dim;
use crate::error::{ConstraintError, TriangulationError};
use crate::ids::{CellId, FacetRef, VertexId};
use crate::sort::{brio_order, SplitMix, PARALLEL_MIN};
use delmesh_predicates::{Sign, COORDINATE_RANGE};
use rayon::prelude::*;
use std::marker::PhantomData;

/// Most points a triangulation holds: cells (about 6.8 per point in 3D) must fit in the 30 bits
/// a [`FacetRef`] leaves for them.
const MAX_POINTS: usize = 1 << 27;

/// Where a point lies relative to the triangulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// In the closed finite cell (not at one of its vertices), or on the far side of the hull
    /// facet of this ghost cell.
    Cell(CellId),
    /// Exactly at an existing vertex.
    Vertex(VertexId),
}

/// The outcome of inserting one point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Insertion {
    /// The point became this new vertex.
    Inserted(VertexId),
    /// The point coincides with this existing vertex; nothing changed.
    Duplicate(VertexId),
}

impl Insertion {
    /// The vertex at the point, new or existing.
    pub fn vertex(self) -> VertexId {
        match self {
            Insertion::Inserted(v) | Insertion::Duplicate(v) => v,
        }
    }
}

/// One cell: its vertices (forming points) and the facets of its neighbours across the facet
/// opposite each vertex. 2D cells leave the fourth entries unused, so both dimensions share one
/// layout: 32 bytes, two cells per cache line.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Simplex {
    pub(crate) v: [VertexId; 4],
    pub(crate) n: [FacetRef; 4],
}

/// Scratch buffers of one insertion, kept between insertions so that inserting allocates
/// nothing once they have grown.
#[derive(Clone, Debug, Default)]
pub(crate) struct Cavity {
    /// Cells found in conflict, in discovery order.
    cells: Vec<CellId>,
    /// Cells still to search.
    stack: Vec<CellId>,
    /// Boundary facets: the new cell's vertices (the cavity cell's vertices with the new point
    /// at `apex`), and the facet of the outside neighbour it is glued to.
    pub(crate) boundary: Vec<BoundaryFacet>,
    /// Matches the facets shared by new cells (huge cavities).
    ridges: RidgeTable,
    /// The cavity's boundary vertices, indexed by their local number.
    verts: Vec<VertexId>,
    /// Local numbers of each boundary facet's vertices.
    local_ids: Vec<[u32; 4]>,
    /// Dense directed-ridge table: `nv × nv` (3D) or `2 × nv` (2D) entries.
    ridge_slots: Vec<FacetRef>,
    /// The cells made for the boundary facets, in the same order.
    pub(crate) new_cells: Vec<CellId>,
    /// Every cell whose mark a blocked cavity search set (see `insert_blocked`).
    touched: Vec<CellId>,
    /// For [`Triangulation::insert_star_shaped`], the cavity cell each boundary facet belongs to
    /// (the cell the new cell on it replaces), in the order of `boundary`.
    pub(crate) inside: Vec<CellId>,
}

/// The positions vertices had before [`Triangulation::place_vertices`] moved them.
pub(crate) type OldPositions<D> = Vec<(VertexId, <D as Dim>::Point)>;

/// Cavity search marks: not visited, in conflict, tested and not in conflict.
const UNSEEN: u8 = 0;
const INSIDE: u8 = 1;
const OUTSIDE: u8 = 2;

/// Largest dense ridge table (entries); bigger cavities use the hash table.
const DENSE_RIDGES: usize = 1 << 16;

/// Local vertex positions of the facet opposite `apex`, ordered counter-clockwise as seen from
/// the apex: `orient(x[f0], x[f1], x[f2], x[apex]) > 0` for a positive tetrahedron, and the
/// counter-clockwise edge `f0 → f1` of a triangle. Neighbouring new cells traverse their
/// shared ridge in opposite directions, which is how they find each other.
#[inline]
fn facet_of<D: Dim>(apex: usize) -> [usize; 3] {
    const FACET3: [[usize; 3]; 4] = [[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]];
    if D::N == 2 {
        [(apex + 1) % 3, (apex + 2) % 3, usize::MAX]
    } else {
        FACET3[apex]
    }
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct BoundaryFacet {
    pub(crate) vertices: [VertexId; 4],
    pub(crate) apex: u8,
    pub(crate) outside: FacetRef,
}

/// Open-addressing table pairing the two new cells that share a ridge (a vertex in 2D, an edge
/// in 3D, always together with the new point). Entries are stamped, so clearing is O(1).
#[derive(Clone, Debug, Default)]
struct RidgeTable {
    slots: Vec<(u64, FacetRef, u32)>,
    stamp: u32,
}

impl RidgeTable {
    fn reset(&mut self, n_entries: usize) {
        let want = (n_entries * 2).next_power_of_two().max(64);
        if self.slots.len() < want {
            self.slots = vec![(0, FacetRef::NONE, 0); want];
            self.stamp = 0;
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.slots.fill((0, FacetRef::NONE, 0));
            self.stamp = 1;
        }
    }

    /// Stores `facet` under `key`, or returns the facet stored earlier under the same key.
    #[inline]
    fn pair(&mut self, key: u64, facet: FacetRef) -> Option<FacetRef> {
        let mask = self.slots.len() - 1;
        let mut i = (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 32) as usize & mask;
        loop {
            let slot = &mut self.slots[i];
            if slot.2 != self.stamp {
                *slot = (key, facet, self.stamp);
                return None;
            }
            if slot.0 == key {
                // Each ridge is shared by exactly two new cells, so the entry is not needed
                // again; it stays in place to keep the probe chains of other keys intact.
                return Some(slot.1);
            }
            i = (i + 1) & mask;
        }
    }
}

/// A Delaunay triangulation in `D` dimensions ([`crate::D2`] or [`crate::D3`]).
///
/// Build one with [`Triangulation::new`]; add points with [`Triangulation::insert`].
#[derive(Clone, Debug)]
pub struct Triangulation<D: Dim> {
    /// Vertex coordinates, scaled by `scale` (a power of two, so exactly), insertion order.
    pub(crate) points: Vec<D::Point>,
    /// Multiply internal coordinates by this to get the caller's (exact: a power of two).
    pub(crate) unscale: f64,
    /// Multiply the caller's coordinates by this to get internal ones.
    pub(crate) scale: f64,
    /// Smallest internal magnitude the predicates handle exactly (zero excepted).
    pub(crate) min_magnitude: f64,
    /// Input index of each vertex.
    pub(crate) input_index: Vec<u32>,
    /// Vertex of each input point (duplicates share one).
    pub(crate) vertex_of_input: Vec<VertexId>,
    /// `(duplicate input index, input index of the point it repeats)`.
    pub(crate) duplicates: Vec<(usize, usize)>,
    /// Vertices and neighbours of each cell, side by side so one cache line holds both.
    pub(crate) simplices: Vec<Simplex>,
    /// Free cell slots (exactly the slots whose first vertex is `DEAD`).
    pub(crate) free: Vec<CellId>,
    /// Live ghost cells (hull facets): kept as cells are made and freed, so that counting the
    /// finite cells costs nothing (recovery records it after every round).
    pub(crate) ghosts: usize,
    /// One cell containing each vertex.
    pub(crate) incident: Vec<CellId>,
    /// Scratch: each vertex's local number in the current cavity (see `local_id`).
    pub(crate) local: Vec<u32>,
    /// During [`Triangulation::new`], `incident` is not maintained (nothing reads it) and is
    /// rebuilt at the end in one sequential pass.
    bulk: bool,
    /// Per-cell state of the cavity search ([`UNSEEN`], [`INSIDE`], [`OUTSIDE`]), reset to
    /// unseen after each insertion for the few cells it touched.
    pub(crate) mark: Vec<u8>,
    /// A cell made by the last insertion: where the next walk starts.
    pub(crate) last: CellId,
    pub(crate) cavity: Cavity,
    rng: SplitMix,
    _dim: PhantomData<D>,
}

impl<D: Dim> Triangulation<D> {
    /// The Delaunay triangulation of `points`, inserted in a spatially sorted random order.
    ///
    /// Exact duplicates are merged: they map to one vertex ([`Triangulation::vertex_of_input`])
    /// and are listed by [`Triangulation::duplicates`].
    ///
    /// # Errors
    /// A NaN or infinite coordinate, fewer than `D + 1` distinct points, all points on one line
    /// (plane), or coordinates spanning more than the exact predicates' range.
    pub fn new(points: &[D::Point]) -> Result<Self, TriangulationError> {
        Self::with_progress(points, |_, _| {})
    }

    /// As [`Triangulation::new`], calling `progress(inserted, total)` every 1,024 points.
    ///
    /// # Errors
    /// As [`Triangulation::new`].
    pub fn with_progress(
        points: &[D::Point],
        mut progress: impl FnMut(usize, usize),
    ) -> Result<Self, TriangulationError> {
        Self::with_progress_until(points, |done, total| {
            progress(done, total);
            true
        })
    }

    /// As [`Triangulation::with_progress`], but stops with [`TriangulationError::Cancelled`]
    /// as soon as `progress` returns false (it is called every 1,024 points): for a
    /// construction run beside another attempt that may make it unnecessary.
    ///
    /// # Errors
    /// As [`Triangulation::new`], or [`TriangulationError::Cancelled`].
    pub fn with_progress_until(
        points: &[D::Point],
        mut progress: impl FnMut(usize, usize) -> bool,
    ) -> Result<Self, TriangulationError> {
        if points.len() >= MAX_POINTS {
            return Err(TriangulationError::TooManyPoints(points.len()));
        }
        let (scale, min_magnitude) = scale_for::<D>(points)?;
        let mut order = brio_order::<D>(points);
        let mut tri = Self::empty(scale, min_magnitude, points.len());
        // Gathered once, in parallel, in insertion order. Vertices are numbered in the same
        // order, so each inserted point is moved down in place to its vertex slot (duplicates
        // leave the gap that this closes) and no second copy of the points is needed.
        let gather = |&i: &u32| tri_scale::<D>(points[i as usize], scale);
        let mut ordered: Vec<D::Point> = if order.len() < PARALLEL_MIN {
            order.iter().map(gather).collect()
        } else {
            order.par_iter().map(gather).collect()
        };

        // The first simplex: the first D + 1 affinely independent points in insertion order.
        let mut first: Vec<usize> = Vec::with_capacity(D::C); // positions in `order`
        let mut first_pts: Vec<D::Point> = Vec::with_capacity(D::C);
        for (pos, &p) in ordered.iter().enumerate() {
            first_pts.push(p);
            if D::independent(&first_pts) {
                first.push(pos);
                if first.len() == D::C {
                    break;
                }
            } else {
                first_pts.pop();
            }
        }
        if first.len() < D::C {
            let distinct = count_distinct::<D>(points);
            return Err(if distinct < D::C {
                TriangulationError::TooFewPoints {
                    distinct,
                    dim: D::N,
                    needed: D::C,
                }
            } else {
                TriangulationError::Degenerate {
                    distinct,
                    dim: D::N,
                    what: if first.len() == 2 {
                        "collinear"
                    } else {
                        "coplanar"
                    },
                }
            });
        }
        // Bring the first simplex to the front (positions only grow, so the swaps commute).
        for (k, &pos) in first.iter().enumerate() {
            ordered.swap(k, pos);
            order.swap(k, pos);
        }
        tri.points = ordered;
        for (k, &i) in order.iter().enumerate().take(D::C) {
            tri.push_vertex(tri.points[k], i);
        }
        tri.make_first_cell();

        let total = points.len();
        let mut done = D::C;
        let mut next_report = 1 << 10;
        for (pos, &i) in order.iter().enumerate().skip(D::C) {
            match tri.insert_scaled(tri.points[pos], i) {
                Insertion::Inserted(_) => {}
                Insertion::Duplicate(v) => {
                    // The vertex stands for the first occurrence in the caller's order.
                    tri.vertex_of_input[i as usize] = v;
                    let first = &mut tri.input_index[v.index()];
                    *first = (*first).min(i);
                }
            }
            done += 1;
            if done >= next_report {
                if !progress(done, total) {
                    return Err(TriangulationError::Cancelled);
                }
                next_report += 1 << 10;
            }
        }
        tri.duplicates = (0..total)
            .filter_map(|i| {
                let first = tri.input_index[tri.vertex_of_input[i].index()] as usize;
                (first != i).then_some((i, first))
            })
            .collect();
        tri.points.truncate(tri.input_index.len());
        tri.bulk = false;
        tri.rebuild_incident();
        if !progress(total, total) {
            return Err(TriangulationError::Cancelled);
        }
        Ok(tri)
    }

    fn empty(scale: f64, min_magnitude: f64, n: usize) -> Self {
        // Tetrahedralisations of uniform points have about 6.7 cells per vertex, triangulations
        // 2; reserving close to that avoids the doubling growth of `Vec` at the end.
        let cells_per_point = if D::N == 3 { 6.8 } else { 2.05 };
        let n_cells = (n as f64 * cells_per_point) as usize + 64;
        Triangulation {
            points: Vec::with_capacity(n),
            unscale: 1.0 / scale,
            scale,
            min_magnitude,
            input_index: Vec::with_capacity(n),
            vertex_of_input: vec![VertexId::GHOST; n],
            duplicates: Vec::new(),
            simplices: Vec::with_capacity(n_cells),
            free: Vec::new(),
            ghosts: 0,
            incident: Vec::with_capacity(n),
            local: Vec::with_capacity(n),
            bulk: true,
            mark: Vec::with_capacity(n_cells),
            last: CellId(0),
            cavity: Cavity::default(),
            rng: SplitMix(0x0DE1_A0A7),
            _dim: PhantomData,
        }
    }

    pub(crate) fn push_vertex(&mut self, p: D::Point, input: u32) -> VertexId {
        let v = VertexId(self.input_index.len() as u32);
        if self.bulk {
            // `points` already holds the insertion order; `v` is at most the point's position.
            self.points[v.index()] = p;
        } else {
            self.points.push(p);
        }
        self.input_index.push(input);
        if (input as usize) < self.vertex_of_input.len() {
            self.vertex_of_input[input as usize] = v;
        } else {
            self.vertex_of_input
                .resize(input as usize + 1, VertexId::GHOST);
            self.vertex_of_input[input as usize] = v;
        }
        self.incident.push(CellId(0));
        self.local.push(u32::MAX);
        v
    }

    /// Builds the first finite cell from vertices `0..C` and its `C` ghost cells.
    fn make_first_cell(&mut self) {
        let mut verts: [VertexId; 4] = [VertexId(0), VertexId(1), VertexId(2), VertexId(3)];
        let mut pts = [D::Point::default(); 5];
        pts[..D::C].copy_from_slice(&self.points[..D::C]);
        if D::orient(&pts[..D::C]) == Sign::Negative {
            verts.swap(0, 1);
        }
        let c0 = self.alloc_cell(&verts[..D::C]);
        // Ghost cell across facet f: the finite cell with vertex f replaced by the ghost, then
        // two other vertices swapped so that a point beyond the facet makes it positive.
        let mut ghosts = [CellId(0); 4];
        for f in 0..D::C {
            let mut g = verts;
            g[f] = VertexId::GHOST;
            let (a, b) = other_two(f);
            g.swap(a, b);
            ghosts[f] = self.alloc_cell(&g[..D::C]);
            let gpos = g[..D::C]
                .iter()
                .position(|v| v.is_ghost())
                .expect("ghost present");
            self.link(FacetRef::new(c0, f), FacetRef::new(ghosts[f], gpos));
        }
        // Ghost cells meet each other across facets containing the ghost vertex.
        self.cavity.ridges.reset(D::C * D::C);
        for &g in &ghosts[..D::C] {
            let gpos = self
                .cell(g)
                .iter()
                .position(|v| v.is_ghost())
                .expect("ghost present");
            self.link_around_apex(g, gpos);
        }
        self.incident[..D::C].fill(c0);
        self.last = c0;
    }

    fn rebuild_incident(&mut self) {
        for (c, simplex) in self.simplices.iter().enumerate() {
            if simplex.v[0] == VertexId::DEAD {
                continue;
            }
            for &u in &simplex.v[..D::C] {
                if !u.is_ghost() {
                    self.incident[u.index()] = CellId(c as u32);
                }
            }
        }
    }

    /// Inserts one point (in the caller's coordinates) and returns its vertex.
    ///
    /// The new vertex's input index is the next one after all points given so far, so
    /// [`Triangulation::input_index`] keeps counting in the caller's numbering.
    ///
    /// # Errors
    /// A NaN or infinite coordinate, or one outside the range fixed when the triangulation was
    /// built (more than 2^142 times smaller than its largest coordinate, or so large that the
    /// predicates would overflow).
    pub fn insert(&mut self, point: D::Point) -> Result<Insertion, TriangulationError> {
        let input = self.vertex_of_input.len();
        let p = self.scaled_input(point)?;
        let result = self.insert_scaled(p, input as u32);
        match result {
            Insertion::Inserted(_) => {}
            Insertion::Duplicate(v) => {
                self.vertex_of_input.push(v);
                let original = self.input_index[v.index()] as usize;
                self.duplicates.push((input, original));
            }
        }
        Ok(result)
    }

    /// As [`Triangulation::insert`], with the point location walk started at a cell of vertex
    /// `near` instead of where the last insertion ended: much shorter when the caller knows a
    /// vertex close to the point (boundary recovery splitting an edge next to its end).
    ///
    /// # Errors
    /// As [`Triangulation::insert`].
    pub fn insert_near(
        &mut self,
        point: D::Point,
        near: VertexId,
    ) -> Result<Insertion, TriangulationError> {
        if !near.is_ghost() && near.index() < self.incident.len() {
            self.last = self.incident[near.index()];
        }
        self.insert(point)
    }

    /// Checks a new point (caller's coordinates) for the next input index and returns it in
    /// internal coordinates.
    pub(crate) fn scaled_input(&self, point: D::Point) -> Result<D::Point, TriangulationError> {
        let input = self.vertex_of_input.len();
        if input >= MAX_POINTS {
            return Err(TriangulationError::TooManyPoints(input));
        }
        let p = tri_scale::<D>(point, self.scale);
        for (axis, (&x, &s)) in point.as_ref().iter().zip(p.as_ref()).enumerate() {
            if !x.is_finite() {
                return Err(TriangulationError::NonFinite {
                    index: input,
                    axis,
                    value: x,
                });
            }
            let m = s.abs();
            if x != 0.0 && !(self.min_magnitude..=COORDINATE_RANGE.1).contains(&m) {
                return Err(TriangulationError::CoordinateRange {
                    index: input,
                    value: x,
                    largest: self.unscale,
                });
            }
        }
        Ok(p)
    }

    /// `point` (caller's coordinates) with every coordinate too small for the triangulation's
    /// range (see [`Triangulation::insert`]) flushed to zero, which the predicates handle
    /// exactly. For constructed points (centroids, circumcentres, mid-points, smoothed
    /// positions): one that lands within `2^-142` of the largest coordinate from an axis
    /// moves onto it, far below what any test can see; input points are refused instead.
    pub(crate) fn flush_tiny(&self, point: D::Point) -> D::Point {
        let mut p = point;
        for x in p.as_mut() {
            if (*x * self.scale).abs() < self.min_magnitude {
                *x = 0.0;
            }
        }
        p
    }

    /// Puts the vertices of `moves` at their new positions (caller's coordinates), checking no
    /// cell: the constrained triangulations check their cells, and [`Self::put_back`] the old
    /// positions (returned, with a mask of the moved vertices) if a cell inverts. Tiny
    /// magnitudes (averages of values near zero) are flushed to zero, which the predicates
    /// handle exactly. On a ghost or unknown vertex, or a coordinate out of range, nothing
    /// moves.
    pub(crate) fn place_vertices(
        &mut self,
        moves: &[(VertexId, D::Point)],
    ) -> Result<(OldPositions<D>, Vec<bool>), ConstraintError> {
        let mut old = Vec::with_capacity(moves.len());
        let mut moved = vec![false; self.num_vertices()];
        for &(v, p) in moves {
            let p = self.flush_tiny(p);
            let q = if v.is_ghost() || v.index() >= self.num_vertices() {
                Err(ConstraintError::InvalidMove { vertex: v })
            } else {
                self.scaled_input(p).map_err(ConstraintError::from)
            };
            let q = match q {
                Ok(q) => q,
                Err(e) => {
                    self.put_back(&old);
                    return Err(e);
                }
            };
            old.push((v, self.points[v.index()]));
            self.points[v.index()] = q;
            moved[v.index()] = true;
        }
        Ok((old, moved))
    }

    /// [`Self::place_vertices`] for every vertex, `positions[v]` for vertex `v`, in parallel:
    /// returns the old positions and the mask of the vertices whose position changed. On an
    /// error nothing moves.
    pub(crate) fn place_all_vertices(
        &mut self,
        positions: &[D::Point],
    ) -> Result<(Vec<D::Point>, Vec<bool>), ConstraintError> {
        if positions.len() != self.num_vertices() {
            return Err(ConstraintError::InvalidMove {
                vertex: VertexId(positions.len() as u32),
            });
        }
        let placed: Vec<D::Point> = positions
            .par_iter()
            .with_min_len(1 << 12)
            .map(|&p| self.scaled_input(self.flush_tiny(p)))
            .collect::<Result<_, _>>()?;
        let old = std::mem::replace(&mut self.points, placed);
        let moved = old
            .par_iter()
            .zip(&self.points)
            .with_min_len(1 << 12)
            .map(|(a, b)| a != b)
            .collect();
        Ok((old, moved))
    }

    /// Undoes [`Self::place_vertices`] given the old positions it returned.
    pub(crate) fn put_back(&mut self, old: &OldPositions<D>) {
        for &(u, q) in old.iter().rev() {
            self.points[u.index()] = q;
        }
    }

    /// Inserts an internal (scaled) point with the given input index.
    pub(crate) fn insert_scaled(&mut self, p: D::Point, input: u32) -> Insertion {
        let start = match self.locate_from(p, self.last) {
            Location::Vertex(v) => return Insertion::Duplicate(v),
            Location::Cell(c) => c,
        };
        let v = self.push_vertex(p, input);
        self.dig_cavity(start, v);
        self.fill_cavity();
        Insertion::Inserted(v)
    }

    // ----- location -----

    /// Locates `point` (caller's coordinates): the cell containing it, the ghost cell of a hull
    /// facet it sees, or the vertex it coincides with.
    pub fn locate(&mut self, point: D::Point) -> Location {
        let p = tri_scale::<D>(point, self.scale);
        self.locate_from(p, self.last)
    }

    /// As [`Triangulation::locate`], with the walk starting at cell `near` (if it is a live
    /// cell): much shorter when the caller knows a cell close to the point.
    pub fn locate_near(&mut self, point: D::Point, near: CellId) -> Location {
        let p = tri_scale::<D>(point, self.scale);
        let start = if near.index() < self.simplices.len()
            && self.simplices[near.index()].v[0] != VertexId::DEAD
        {
            near
        } else {
            self.last
        };
        self.locate_from(p, start)
    }

    /// Visibility walk (the paper's §5 search, with exact orientation tests): from `start`,
    /// repeatedly cross a facet that has the point strictly on its far side. Delaunay
    /// triangulations have no cycles for this walk; the facet tried first is random, which keeps
    /// the walk short on regular grids.
    #[inline]
    pub(crate) fn locate_from(&mut self, p: D::Point, start: CellId) -> Location {
        self.locate_on_facet(p, start).0
    }

    /// [`Self::locate_from`], with, for a point in a finite cell, a facet of the cell whose
    /// plane (line) the point lies on, if any: its orientation test was zero during the walk
    /// (the facet the walk came in by is never one: the point is strictly beyond it).
    #[inline]
    pub(crate) fn locate_on_facet(
        &mut self,
        p: D::Point,
        start: CellId,
    ) -> (Location, Option<usize>) {
        let mut c = start;
        if let Some(g) = self.ghost_position(c) {
            c = self.simplices[c.index()].n[g].cell();
        }
        let mut came_from = usize::MAX;
        'walk: loop {
            let cell = self.simplices[c.index()];
            let offset = self.rng.below(D::C);
            let mut on = None;
            for step in 0..D::C {
                let f = (offset + step) % D::C;
                if f == came_from {
                    continue;
                }
                match D::orient_replacing(&self.points, &cell.v, f, p) {
                    Sign::Negative => {
                        let next = cell.n[f];
                        c = next.cell();
                        came_from = next.facet();
                        if self.ghost_position(c).is_some() {
                            // Strictly beyond a hull facet: that ghost cell is in conflict.
                            return (Location::Cell(c), None);
                        }
                        continue 'walk;
                    }
                    // The lowest such facet, whatever the order of the tests.
                    Sign::Zero => on = Some(on.map_or(f, |g: usize| g.min(f))),
                    Sign::Positive => {}
                }
            }
            // The point is in the closed cell: at a vertex, or inside (then in conflict).
            for k in 0..D::C {
                if self.points[cell.v[k].index()] == p {
                    return (Location::Vertex(cell.v[k]), None);
                }
            }
            return (Location::Cell(c), on);
        }
    }

    // ----- insertion -----

    /// Whether `p` (vertex `v`'s point) lies inside the circumsphere of cell `c`. For a ghost
    /// cell the "sphere" is the open half-space beyond its hull facet; a point on the facet's
    /// plane (line) is decided by the finite cell across the facet, so both agree exactly.
    #[inline]
    fn in_conflict(&self, c: CellId, p: D::Point) -> bool {
        let cell = &self.simplices[c.index()];
        let Some(ghost) = cell.v[..D::C].iter().position(|u| u.is_ghost()) else {
            return D::insphere_cell(&self.points, &cell.v, p) == Sign::Positive;
        };
        // Replace the ghost by a finite vertex of the cell, then by p: "p beyond the facet".
        let mut finite = cell.v;
        finite[ghost] = cell.v[(ghost + 1) % D::C];
        match D::orient_replacing(&self.points, &finite, ghost, p) {
            Sign::Positive => true,
            Sign::Negative => false,
            Sign::Zero => self.in_conflict(cell.n[ghost].cell(), p),
        }
    }

    /// Steps 3–5: the cavity of cells in conflict with `v`, found by a search over neighbours
    /// from `start` (which must be in conflict), and its boundary facets.
    fn dig_cavity(&mut self, start: CellId, v: VertexId) {
        let p = self.points[v.index()];
        let (inside, outside) = (INSIDE, OUTSIDE);
        let mut cavity = std::mem::take(&mut self.cavity);
        cavity.cells.clear();
        cavity.boundary.clear();
        cavity.stack.clear();
        cavity.stack.push(start);
        cavity.cells.push(start);
        self.mark[start.index()] = inside;
        while let Some(c) = cavity.stack.pop() {
            let cell = self.simplices[c.index()];
            for f in 0..D::C {
                let across = cell.n[f];
                let n = across.cell();
                let m = self.mark[n.index()];
                if m == inside {
                    continue;
                }
                if m != outside {
                    if self.in_conflict(n, p) {
                        self.mark[n.index()] = inside;
                        cavity.cells.push(n);
                        cavity.stack.push(n);
                        continue;
                    }
                    self.mark[n.index()] = outside;
                }
                let mut vertices = cell.v;
                vertices[f] = v;
                cavity.boundary.push(BoundaryFacet {
                    vertices,
                    apex: f as u8,
                    outside: across,
                });
            }
        }
        self.cavity = cavity;
    }

    /// Bowyer–Watson insertion of the internal point `p` whose cavity never crosses a facet
    /// for which `blocked` is true (a protected boundary face): the insertion step of a
    /// constrained triangulation. `start` is the finite cell containing `p` (from a walk). If
    /// `p` does not see every boundary facet of that cavity strictly (it lies on a blocked
    /// facet, a blocked facet of a non-convex boundary faces away from it, or the cavity
    /// reaches both sides of a blocked facet), nothing changes and `None` is returned:
    /// shrinking the cavity instead would leave cells whose circumsphere holds `p`. After
    /// success, `self.cavity.boundary[k]` is the facet `self.cavity.new_cells[k]` was built on,
    /// for the caller's per-cell data. `fine` sees the points, the corners of each new finite
    /// cell but the new point (the boundary facet it is built on) and `p`, and may refuse the
    /// insertion too. With `keep_delaunay`, so is an insertion that would leave a new cell not
    /// Delaunay across a facet that is not blocked (see [`Self::cavity_keeps_delaunay`]).
    pub(crate) fn insert_blocked(
        &mut self,
        p: D::Point,
        input: u32,
        start: CellId,
        blocked: impl Fn(FacetRef) -> bool,
        fine: impl Fn(&[D::Point], &[VertexId], D::Point) -> bool,
        keep_delaunay: bool,
    ) -> Option<VertexId> {
        let mut cavity = self.seed_cavity(&[start]);
        let v = VertexId(self.input_index.len() as u32);
        let mut star_shaped = true;
        'search: while let Some(c) = cavity.stack.pop() {
            let cell = self.simplices[c.index()];
            for f in 0..D::C {
                let across = cell.n[f];
                let n = across.cell();
                let m = self.mark[n.index()];
                let is_blocked = blocked(FacetRef::new(c, f));
                if m == INSIDE {
                    if is_blocked {
                        // Both sides of a protected face in the cavity: it would be lost.
                        star_shaped = false;
                        break 'search;
                    }
                    continue;
                }
                if m == UNSEEN && !is_blocked {
                    cavity.touched.push(n);
                    if self.in_conflict(n, p) {
                        self.mark[n.index()] = INSIDE;
                        cavity.cells.push(n);
                        cavity.stack.push(n);
                        continue;
                    }
                    self.mark[n.index()] = OUTSIDE;
                }
                // A boundary facet: the new cell on it must be positive.
                let finite = !cell.v[..D::C].contains(&VertexId::GHOST);
                if finite && D::orient_replacing(&self.points, &cell.v, f, p) != Sign::Positive {
                    star_shaped = false;
                    break 'search;
                }
                let mut vertices = cell.v;
                vertices[f] = v;
                if finite {
                    let mut facet = [VertexId::GHOST; 4];
                    let mut k = 0;
                    for (i, &u) in cell.v[..D::C].iter().enumerate() {
                        if i != f {
                            facet[k] = u;
                            k += 1;
                        }
                    }
                    if !fine(&self.points, &facet[..k], p) {
                        star_shaped = false;
                        break 'search;
                    }
                }
                cavity.boundary.push(BoundaryFacet {
                    vertices,
                    apex: f as u8,
                    outside: across,
                });
            }
        }
        let star_shaped =
            star_shaped && (!keep_delaunay || self.cavity_keeps_delaunay(&cavity, v, p, &blocked));
        self.commit_cavity(cavity, star_shaped, p, input)
    }

    /// Whether every cell that filling `cavity` with `p` (as vertex `v`) would make is
    /// Delaunay across each of its facets that is not `blocked`: against the vertex beyond
    /// its facet on the cavity's boundary, and against the far vertex of each new neighbour,
    /// by the very test [`Triangulation::validate`] makes. A search that stops at blocked
    /// facets is not the whole conflict region: where a cell beyond one is in conflict, a new
    /// cell on it may hold a vertex of the cavity's boundary that lies beyond that facet's
    /// plane. A cavity on the hull is refused.
    fn cavity_keeps_delaunay(
        &self,
        cavity: &Cavity,
        v: VertexId,
        p: D::Point,
        blocked: &impl Fn(FacetRef) -> bool,
    ) -> bool {
        let point = |u: VertexId| if u == v { p } else { self.points[u.index()] };
        let in_sphere = |cell: &[VertexId; 4], q: D::Point| {
            // The cell's corners as a local array (the predicates read coordinates only).
            let corners: [D::Point; 4] =
                std::array::from_fn(|k| point(if k < D::C { cell[k] } else { v }));
            let local = [0, 1, 2, 3].map(VertexId);
            D::insphere_cell(&corners, &local, q) == Sign::Positive
        };
        // Each new cell's facets through `v`, by their other corners (sorted), with the cell
        // (its boundary facet) and its corner opposite the facet.
        let mut ridges: Vec<([VertexId; 3], usize, VertexId)> = Vec::new();
        for (i, b) in cavity.boundary.iter().enumerate() {
            let cell = &b.vertices;
            if cell[..D::C].contains(&VertexId::GHOST) {
                return false;
            }
            if !blocked(b.outside) {
                let beyond = self.simplices[b.outside.cell().index()].v[b.outside.facet()];
                if !beyond.is_ghost() && in_sphere(cell, self.points[beyond.index()]) {
                    return false;
                }
            }
            let apex = b.apex as usize;
            for k in (0..D::C).filter(|&k| k != apex) {
                let mut key = [VertexId::GHOST; 3];
                let others = (0..D::C).filter(|&j| j != k && j != apex);
                for (slot, j) in key.iter_mut().zip(others) {
                    *slot = cell[j];
                }
                key[..D::C - 2].sort_unstable();
                ridges.push((key, i, cell[k]));
            }
        }
        ridges.sort_unstable_by_key(|r| r.0);
        ridges.chunk_by(|a, b| a.0 == b.0).all(|pair| {
            let [(_, i, x), (_, j, y)] = pair else {
                return false;
            };
            !in_sphere(&cavity.boundary[*i].vertices, point(*y))
                && !in_sphere(&cavity.boundary[*j].vertices, point(*x))
        })
    }

    /// The cavity buffers, cleared, with `starts` in the cavity (marked inside, to search from).
    fn seed_cavity(&mut self, starts: &[CellId]) -> Cavity {
        let mut cavity = std::mem::take(&mut self.cavity);
        cavity.touched.clear();
        cavity.cells.clear();
        cavity.stack.clear();
        cavity.boundary.clear();
        cavity.inside.clear();
        for &start in starts {
            if self.mark[start.index()] != INSIDE {
                cavity.stack.push(start);
                cavity.cells.push(start);
                cavity.touched.push(start);
                self.mark[start.index()] = INSIDE;
            }
        }
        cavity
    }

    /// Ends a blocked search: the marks it set are cleared, and if the cavity is
    /// `star_shaped`, `p` is inserted into it (the new vertex returned); else nothing changes.
    fn commit_cavity(
        &mut self,
        cavity: Cavity,
        star_shaped: bool,
        p: D::Point,
        input: u32,
    ) -> Option<VertexId> {
        for &c in &cavity.touched {
            self.mark[c.index()] = UNSEEN;
        }
        if !star_shaped {
            self.cavity = cavity;
            return None;
        }
        for &c in &cavity.cells {
            self.mark[c.index()] = INSIDE;
        }
        self.cavity = cavity;
        let v = self.push_vertex(p, input);
        self.fill_cavity();
        Some(v)
    }

    /// [`Self::insert_blocked`] for a point whose conflict region need not be star-shaped from
    /// it: the cells around it are not all Delaunay (a constrained mesh being repaired), or a
    /// rounded point lies just beyond a nearly flat cell that must be in the cavity. Where the
    /// new cell on a boundary facet would not be positive and the facet is not blocked, the
    /// cell beyond it joins the cavity. The conflict search crosses neither `blocked` nor
    /// `avoided` facets; the growth crosses `avoided` ones where it must (and a hull facet that
    /// `p` lies on). If a blocked or hull facet faces away from `p`, the cavity reaches both
    /// sides of a blocked facet, swallows a vertex, or takes every cell of one of the groups
    /// `keep_one_of` (the cells around an edge that must stay), nothing changes and `None` is
    /// returned.
    pub(crate) fn insert_star_shaped(
        &mut self,
        p: D::Point,
        input: u32,
        starts: &[CellId],
        blocked: impl Fn(FacetRef) -> bool,
        avoided: impl Fn(FacetRef) -> bool,
        keep_one_of: &[Vec<CellId>],
    ) -> Option<VertexId> {
        let mut cavity = self.seed_cavity(starts);
        let v = VertexId(self.input_index.len() as u32);
        // The conflict region, not crossing blocked facets.
        while let Some(c) = cavity.stack.pop() {
            let cell = self.simplices[c.index()];
            for f in 0..D::C {
                let n = cell.n[f].cell();
                let facet = FacetRef::new(c, f);
                if self.mark[n.index()] != UNSEEN || blocked(facet) || avoided(facet) {
                    continue;
                }
                cavity.touched.push(n);
                if self.in_conflict(n, p) {
                    self.mark[n.index()] = INSIDE;
                    cavity.cells.push(n);
                    cavity.stack.push(n);
                } else {
                    self.mark[n.index()] = OUTSIDE;
                }
            }
        }
        // Grown until star-shaped: a cell beyond a facet that faces away from `p` joins (and is
        // scanned in turn, since it is appended).
        let mut star_shaped = true;
        let mut k = 0;
        'grow: while k < cavity.cells.len() {
            let c = cavity.cells[k];
            k += 1;
            let cell = self.simplices[c.index()];
            let finite = !cell.v[..D::C].contains(&VertexId::GHOST);
            for f in 0..D::C {
                let n = cell.n[f].cell();
                let is_blocked = blocked(FacetRef::new(c, f));
                if self.mark[n.index()] == INSIDE {
                    if is_blocked {
                        star_shaped = false;
                        break 'grow;
                    }
                    continue;
                }
                let side = if finite {
                    D::orient_replacing(&self.points, &cell.v, f, p)
                } else {
                    Sign::Positive
                };
                if side != Sign::Positive {
                    // A ghost cell joins only when the point lies on its hull facet.
                    if is_blocked || (self.is_ghost(n) && side == Sign::Negative) {
                        star_shaped = false;
                        break 'grow;
                    }
                    if self.mark[n.index()] == UNSEEN {
                        cavity.touched.push(n);
                    }
                    self.mark[n.index()] = INSIDE;
                    cavity.cells.push(n);
                }
            }
        }
        star_shaped &= keep_one_of
            .iter()
            .all(|group| group.iter().any(|c| self.mark[c.index()] != INSIDE));
        if star_shaped {
            self.cavity_boundary(&mut cavity, v);
            star_shaped = !self.swallows_vertex(&cavity);
        }
        self.commit_cavity(cavity, star_shaped, p, input)
    }

    /// The boundary facets of the cavity whose cells are marked inside, for the new vertex
    /// `v`, each with the cavity cell it belongs to.
    fn cavity_boundary(&self, cavity: &mut Cavity, v: VertexId) {
        for &c in &cavity.cells {
            let cell = self.simplices[c.index()];
            for f in 0..D::C {
                let across = cell.n[f];
                if self.mark[across.cell().index()] != INSIDE {
                    let mut vertices = cell.v;
                    vertices[f] = v;
                    cavity.boundary.push(BoundaryFacet {
                        vertices,
                        apex: f as u8,
                        outside: across,
                    });
                    cavity.inside.push(c);
                }
            }
        }
    }

    /// Inserts the internal point `p`, strictly beyond the hull facet of the ghost cell
    /// `start`, as a new hull vertex: the cavity is the ghost cells whose hull facet it lies
    /// strictly beyond, connected to `start`, so every new finite cell is a visible hull facet
    /// joined to it (positive) in any triangulation, Delaunay or not. `None` if `start` is not
    /// such a ghost cell.
    pub(crate) fn insert_beyond_hull(
        &mut self,
        p: D::Point,
        input: u32,
        start: CellId,
    ) -> Option<VertexId> {
        let beyond = |this: &Self, c: CellId| {
            let cell = &this.simplices[c.index()];
            let Some(ghost) = cell.v[..D::C].iter().position(|u| u.is_ghost()) else {
                return false;
            };
            let mut finite = cell.v;
            finite[ghost] = cell.v[(ghost + 1) % D::C];
            D::orient_replacing(&this.points, &finite, ghost, p) == Sign::Positive
        };
        if !beyond(self, start) {
            return None;
        }
        let mut cavity = self.seed_cavity(&[start]);
        let v = VertexId(self.input_index.len() as u32);
        while let Some(c) = cavity.stack.pop() {
            let cell = self.simplices[c.index()];
            for f in 0..D::C {
                let n = cell.n[f].cell();
                if self.mark[n.index()] != UNSEEN {
                    continue;
                }
                cavity.touched.push(n);
                if beyond(self, n) {
                    self.mark[n.index()] = INSIDE;
                    cavity.cells.push(n);
                    cavity.stack.push(n);
                } else {
                    self.mark[n.index()] = OUTSIDE;
                }
            }
        }
        self.cavity_boundary(&mut cavity, v);
        self.commit_cavity(cavity, true, p, input)
    }

    /// Whether a vertex of the cavity's cells is not on its boundary: the cavity would swallow
    /// it. Bowyer–Watson cavities of a Delaunay triangulation never do; grown ones in a
    /// triangulation that is not Delaunay can.
    fn swallows_vertex(&self, cavity: &Cavity) -> bool {
        let mut on_boundary: Vec<VertexId> = cavity
            .boundary
            .iter()
            .flat_map(|b| {
                (0..D::C)
                    .filter(move |&k| k != b.apex as usize)
                    .map(move |k| b.vertices[k])
            })
            .collect();
        on_boundary.sort_unstable();
        on_boundary.dedup();
        cavity.cells.iter().any(|c| {
            self.simplices[c.index()].v[..D::C]
                .iter()
                .any(|u| on_boundary.binary_search(u).is_err())
        })
    }

    /// Steps 6–8: one new cell per boundary facet (the facet joined to the new vertex), glued to
    /// the outside neighbour and to each other; the cavity's cells are reused first.
    fn fill_cavity(&mut self) {
        let mut cavity = std::mem::take(&mut self.cavity);
        for &c in &cavity.cells {
            self.release_cell(c);
            self.mark[c.index()] = UNSEEN;
        }
        for b in &cavity.boundary {
            self.mark[b.outside.cell().index()] = UNSEEN;
        }
        // Number the cavity's boundary vertices 0..nv (a sparse set over `self.local`, so
        // nothing needs clearing), then pair the new cells' shared facets by directed ridges.
        cavity.verts.clear();
        cavity.local_ids.clear();
        for b in &cavity.boundary {
            let mut ids = [0u32; 4];
            for (k, id) in ids.iter_mut().enumerate().take(D::C) {
                if k != b.apex as usize {
                    *id = self.local_id(&mut cavity.verts, b.vertices[k]);
                }
            }
            cavity.local_ids.push(ids);
        }
        let nv = cavity.verts.len();
        let dense = if D::N == 2 { 2 * nv } else { nv * nv };
        if dense > DENSE_RIDGES {
            self.cavity = cavity;
            return self.fill_cavity_hashed();
        }
        if cavity.ridge_slots.len() < dense {
            cavity.ridge_slots.resize(dense, FacetRef::NONE);
        }
        cavity.new_cells.clear();
        for (b, ids) in cavity.boundary.iter().zip(&cavity.local_ids) {
            let c = self.glue_new_cell(b);
            cavity.new_cells.push(c);
            // Register this cell's side facets under their directed ridges.
            let f = facet_of::<D>(b.apex as usize);
            if D::N == 2 {
                // Boundary edge u0 → u1: the facet through u0 (opposite u1) is "starts at u0",
                // the facet through u1 (opposite u0) is "ends at u1".
                cavity.ridge_slots[2 * ids[f[0]] as usize] = FacetRef::new(c, f[1]);
                cavity.ridge_slots[2 * ids[f[1]] as usize + 1] = FacetRef::new(c, f[0]);
            } else {
                for k in 0..3 {
                    let (a, b2) = (ids[f[(k + 1) % 3]], ids[f[(k + 2) % 3]]);
                    cavity.ridge_slots[(a as usize) * nv + b2 as usize] = FacetRef::new(c, f[k]);
                }
            }
        }
        // Each directed ridge's reverse belongs to the new cell across it.
        let mut last_finite = None;
        for ((b, ids), &c) in cavity
            .boundary
            .iter()
            .zip(&cavity.local_ids)
            .zip(&cavity.new_cells)
        {
            let f = facet_of::<D>(b.apex as usize);
            let n = &mut self.simplices[c.index()].n;
            if D::N == 2 {
                n[f[0]] = cavity.ridge_slots[2 * ids[f[1]] as usize];
                n[f[1]] = cavity.ridge_slots[2 * ids[f[0]] as usize + 1];
            } else {
                for k in 0..3 {
                    let (a, b2) = (ids[f[(k + 1) % 3]], ids[f[(k + 2) % 3]]);
                    n[f[k]] = cavity.ridge_slots[(b2 as usize) * nv + a as usize];
                }
            }
            if !b.vertices[..D::C].contains(&VertexId::GHOST) {
                last_finite = Some(c);
            }
        }
        self.last = last_finite
            .or(cavity.new_cells.last().copied())
            .expect("a cavity has at least one boundary facet: a bug in delmesh");
        self.cavity = cavity;
    }

    /// The cell for boundary facet `b` (the facet joined to the new vertex), glued to the
    /// outside neighbour; its other neighbours are linked by the caller.
    #[inline]
    fn glue_new_cell(&mut self, b: &BoundaryFacet) -> CellId {
        let c = self.alloc_cell(&b.vertices[..D::C]);
        self.link(FacetRef::new(c, b.apex as usize), b.outside);
        if !self.bulk {
            for &u in &b.vertices[..D::C] {
                if !u.is_ghost() {
                    self.incident[u.index()] = c;
                }
            }
        }
        c
    }

    /// The local number of `u` among the cavity's boundary vertices, assigned on first sight.
    #[inline]
    fn local_id(&mut self, verts: &mut Vec<VertexId>, u: VertexId) -> u32 {
        if u.is_ghost() {
            if let Some(k) = verts.iter().position(|w| w.is_ghost()) {
                return k as u32;
            }
        } else {
            let k = self.local[u.index()];
            if (k as usize) < verts.len() && verts[k as usize] == u {
                return k;
            }
            self.local[u.index()] = verts.len() as u32;
        }
        verts.push(u);
        verts.len() as u32 - 1
    }

    /// [`Self::fill_cavity`] for huge cavities (degenerate inputs), where a dense ridge table
    /// would be too large: the new cells are paired through a hash table instead.
    fn fill_cavity_hashed(&mut self) {
        let mut cavity = std::mem::take(&mut self.cavity);
        // (Marks were reset by `fill_cavity`, which hands over to this.)
        cavity.ridges.reset(cavity.boundary.len() * (D::C - 1));
        cavity.new_cells.clear();
        let mut last = None;
        let mut last_finite = None;
        for b in &cavity.boundary {
            let c = self.glue_new_cell(b);
            cavity.new_cells.push(c);
            let apex = b.apex as usize;
            for j in 0..D::C {
                if j != apex {
                    let key = ridge_key(&b.vertices[..D::C], apex, j);
                    if let Some(other) = cavity.ridges.pair(key, FacetRef::new(c, j)) {
                        self.link(FacetRef::new(c, j), other);
                    }
                }
            }
            last = Some(c);
            if !b.vertices[..D::C].contains(&VertexId::GHOST) {
                last_finite = Some(c);
            }
        }
        self.last = last_finite
            .or(last)
            .expect("a cavity has at least one boundary facet: a bug in delmesh");
        self.cavity = cavity;
    }

    /// Links the new cell `c`, whose apex (new vertex or ghost) is at local `apex`, to the
    /// cells already registered in the ridge table.
    fn link_around_apex(&mut self, c: CellId, apex: usize) {
        let mut verts = [VertexId::GHOST; 4];
        verts[..D::C].copy_from_slice(self.cell(c));
        for j in 0..D::C {
            if j != apex {
                let key = ridge_key(&verts[..D::C], apex, j);
                let mut ridges = std::mem::take(&mut self.cavity.ridges);
                if let Some(other) = ridges.pair(key, FacetRef::new(c, j)) {
                    self.link(FacetRef::new(c, j), other);
                }
                self.cavity.ridges = ridges;
            }
        }
    }

    #[inline]
    pub(crate) fn link(&mut self, a: FacetRef, b: FacetRef) {
        self.simplices[a.cell().index()].n[a.facet()] = b;
        self.simplices[b.cell().index()].n[b.facet()] = a;
    }

    /// Sets the neighbour seen across facet `f` (the facet of the cell on the other side).
    #[inline]
    pub(crate) fn set_neighbor(&mut self, f: FacetRef, across: FacetRef) {
        self.simplices[f.cell().index()].n[f.facet()] = across;
    }

    /// Room for more cells: a quarter more rather than double, since the arrays are most of
    /// the memory.
    #[cold]
    fn grow_cells(&mut self) {
        let extra = (self.simplices.len() / 4).max(64);
        self.simplices.reserve_exact(extra);
        self.mark.reserve_exact(extra);
    }

    #[inline]
    pub(crate) fn alloc_cell(&mut self, verts: &[VertexId]) -> CellId {
        self.ghosts += usize::from(verts.contains(&VertexId::GHOST));
        if let Some(c) = self.free.pop() {
            self.simplices[c.index()].v[..D::C].copy_from_slice(verts);
            return c;
        }
        let c = CellId(self.mark.len() as u32);
        if self.simplices.len() == self.simplices.capacity() {
            self.grow_cells();
        }
        let mut simplex = Simplex {
            v: [VertexId::GHOST; 4],
            n: [FacetRef::NONE; 4],
        };
        simplex.v[..D::C].copy_from_slice(verts);
        self.simplices.push(simplex);
        self.mark.push(0);
        c
    }

    /// Gives live cell `c` the vertices `v` (a flip reusing its slot).
    #[inline]
    pub(crate) fn set_cell_vertices(&mut self, c: CellId, v: [VertexId; 4]) {
        let s = &mut self.simplices[c.index()];
        let ghost = |v: &[VertexId]| usize::from(v.contains(&VertexId::GHOST));
        self.ghosts = self.ghosts + ghost(&v[..D::C]) - ghost(&s.v[..D::C]);
        s.v = v;
    }

    /// Frees live cell `c`'s slot for reuse.
    #[inline]
    pub(crate) fn release_cell(&mut self, c: CellId) {
        let s = &mut self.simplices[c.index()];
        self.ghosts -= usize::from(s.v[..D::C].contains(&VertexId::GHOST));
        s.v[0] = VertexId::DEAD;
        self.free.push(c);
    }

    // ----- queries -----

    /// Number of vertices (distinct inserted points).
    pub fn num_vertices(&self) -> usize {
        self.input_index.len()
    }

    /// Number of input points given so far, duplicates included.
    pub fn num_input_points(&self) -> usize {
        self.vertex_of_input.len()
    }

    /// Number of cell slots (live, ghost or free): cell ids are below it.
    #[inline]
    pub fn num_cell_slots(&self) -> usize {
        self.simplices.len()
    }

    /// Number of finite cells (triangles or tetrahedra).
    pub fn num_cells(&self) -> usize {
        self.simplices.len() - self.free.len() - self.ghosts
    }

    /// Number of facets on the convex hull (edges in 2D, triangles in 3D).
    pub fn num_hull_facets(&self) -> usize {
        self.ghosts
    }

    /// The coordinates of vertex `v` (the caller's, exactly).
    #[inline]
    pub fn vertex(&self, v: VertexId) -> D::Point {
        let mut p = self.points[v.index()];
        for x in p.as_mut() {
            *x *= self.unscale;
        }
        p
    }

    /// Input index of vertex `v`.
    #[inline]
    pub fn input_index(&self, v: VertexId) -> usize {
        self.input_index[v.index()] as usize
    }

    /// Vertex of input point `i` (duplicates map to the vertex of the point they repeat).
    #[inline]
    pub fn vertex_of_input(&self, i: usize) -> VertexId {
        self.vertex_of_input[i]
    }

    /// The vertices of the cells the last insertion replaced (the boundary of its cavity; the
    /// ghost vertex among them on the hull): with the new vertex, the vertices of its star.
    /// Only meaningful right after an insertion that added a vertex.
    pub fn last_cavity_vertices(&self) -> &[VertexId] {
        &self.cavity.verts
    }

    /// Input points that repeat an earlier one: `(duplicate, first occurrence)` input indices,
    /// sorted. The vertex keeps the first occurrence's input index.
    pub fn duplicates(&self) -> &[(usize, usize)] {
        &self.duplicates
    }

    /// All live cells, ghost cells included.
    pub fn all_cells(&self) -> impl Iterator<Item = CellId> + '_ {
        (0..self.mark.len() as u32)
            .map(CellId)
            .filter(|c| self.simplices[c.index()].v[0] != VertexId::DEAD)
    }

    /// Whether cell slot `c` holds a cell (finite or ghost), rather than being free.
    #[inline]
    pub fn is_live(&self, c: CellId) -> bool {
        self.simplices[c.index()].v[0] != VertexId::DEAD
    }

    /// The finite cells (triangles or tetrahedra), each positively oriented.
    pub fn cells(&self) -> impl Iterator<Item = CellId> + '_ {
        self.all_cells().filter(|&c| !self.is_ghost(c))
    }

    /// The vertices of cell `c` (one may be [`VertexId::GHOST`] for a hull cell).
    #[inline]
    pub fn cell(&self, c: CellId) -> &[VertexId] {
        &self.simplices[c.index()].v[..D::C]
    }

    /// The neighbour of `c` across the facet opposite its local vertex `i`, with that facet.
    #[inline]
    pub fn neighbor_facet(&self, c: CellId, i: usize) -> FacetRef {
        self.simplices[c.index()].n[i]
    }

    /// The finite neighbour of `c` across the facet opposite its local vertex `i`, or `None` on
    /// the hull (the paper's `*`).
    #[inline]
    pub fn neighbor(&self, c: CellId, i: usize) -> Option<CellId> {
        let n = self.neighbor_facet(c, i).cell();
        (!self.is_ghost(n)).then_some(n)
    }

    /// True for a ghost (hull) cell.
    #[inline]
    pub fn is_ghost(&self, c: CellId) -> bool {
        self.ghost_position(c).is_some()
    }

    #[inline]
    pub(crate) fn ghost_position(&self, c: CellId) -> Option<usize> {
        self.cell(c).iter().position(|v| v.is_ghost())
    }

    /// One finite or ghost cell containing `v`.
    pub fn incident_cell(&self, v: VertexId) -> CellId {
        self.incident[v.index()]
    }

    /// All cells containing vertex `v` (ghost cells included when `v` is on the hull), by a
    /// search over neighbours from its incident cell.
    pub fn cells_around_vertex(&self, v: VertexId) -> Vec<CellId> {
        self.cells_around(&[v])
    }

    /// All cells containing every vertex of `simplex` (an edge, or a triangle in 3D): empty if
    /// the simplex is not in the triangulation.
    pub fn cells_around(&self, simplex: &[VertexId]) -> Vec<CellId> {
        let Some(&v) = simplex.first() else {
            return Vec::new();
        };
        if v.is_ghost() || v.index() >= self.num_vertices() {
            return Vec::new();
        }
        // Star of v: cells containing v, connected through facets containing v. A list
        // searched linearly while small; a set past that, since a vertex can have thousands
        // of cells (the centre of a fan) and recovery asks about its edges over and over.
        const LINEAR: usize = 64;
        let mut seen = vec![self.incident[v.index()]];
        let mut set: std::collections::HashSet<CellId> = std::collections::HashSet::new();
        let mut i = 0;
        while i < seen.len() {
            let c = seen[i];
            i += 1;
            let verts = self.cell(c);
            for (k, &u) in verts.iter().enumerate() {
                if u != v {
                    let n = self.neighbor_facet(c, k).cell();
                    let new = if seen.len() < LINEAR {
                        !seen.contains(&n)
                    } else {
                        if set.is_empty() {
                            set.extend(seen.iter().copied());
                        }
                        set.insert(n)
                    };
                    if new {
                        seen.push(n);
                    }
                }
            }
        }
        seen.retain(|&c| simplex.iter().all(|s| self.cell(c).contains(s)));
        seen
    }

    /// Whether the edge `a b` is in the triangulation.
    pub fn has_edge(&self, a: VertexId, b: VertexId) -> bool {
        self.edge_cell(a, b, None).is_some()
    }

    /// A cell (finite or ghost) that has the edge `a b`, or `None` if the edge is not in the
    /// triangulation. `hint`, a cell that had the edge before some change, is tried first
    /// (one cell read when the edge survived the change).
    pub fn edge_cell(&self, a: VertexId, b: VertexId, hint: Option<CellId>) -> Option<CellId> {
        let real = |v: VertexId| !v.is_ghost() && v.index() < self.num_vertices();
        if a == b || !real(a) {
            return None;
        }
        if let Some(h) = hint {
            if h.index() < self.simplices.len() && self.is_live(h) {
                let v = self.cell(h);
                if v.contains(&a) && v.contains(&b) {
                    return Some(h);
                }
            }
        }
        if D::C == 3 && real(b) {
            // In 2D, turn around `a` and around `b` at once, one triangle each per step,
            // until one finds the other or either turn closes: no search structure, and the
            // work is bounded by the smaller of the two stars (recovery asks this of every
            // boundary piece in every pass, and fan centres have thousands of triangles).
            let start = [self.incident[a.index()], self.incident[b.index()]];
            let mut c = start;
            for _ in 0..self.simplices.len() {
                for (k, (x, y)) in [(a, b), (b, a)].into_iter().enumerate() {
                    let v = self.cell(c[k]);
                    let i = v.iter().position(|&u| u == x).unwrap_or(0);
                    if v[(i + 1) % 3] == y || v[(i + 2) % 3] == y {
                        return Some(c[k]);
                    }
                    c[k] = self.neighbor_facet(c[k], (i + 1) % 3).cell();
                    if c[k] == start[k] {
                        return None;
                    }
                }
            }
        }
        self.cells_around(&[a, b]).first().copied()
    }

    /// Whether the triangle `a b c` is in the triangulation (a facet in 3D, a cell in 2D).
    pub fn has_triangle(&self, a: VertexId, b: VertexId, c: VertexId) -> bool {
        a != b
            && b != c
            && a != c
            && self
                .cells_around(&[a, b, c])
                .iter()
                .any(|&x| !self.is_ghost(x))
    }

    /// The finite cells as vertex tuples in the caller's (input) numbering.
    pub fn cells_in_input_numbering(&self) -> Vec<u32> {
        let mut out = Vec::with_capacity(self.simplices.len() * D::C);
        for c in self.cells() {
            out.extend(self.cell(c).iter().map(|v| self.input_index[v.index()]));
        }
        out
    }

    /// The finite cells' neighbours as indices into [`Triangulation::cells`]' order, `-1` on
    /// the hull (the `.neigh` convention).
    pub fn neighbors_in_cell_order(&self) -> Vec<i64> {
        let mut order = vec![-1i64; self.mark.len()];
        for (k, c) in self.cells().enumerate() {
            order[c.index()] = k as i64;
        }
        let mut out = Vec::new();
        for c in self.cells() {
            for i in 0..D::C {
                out.push(order[self.neighbor_facet(c, i).cell().index()]);
            }
        }
        out
    }

    /// Scaled coordinates of vertex `v` (what the predicates see).
    #[inline]
    pub(crate) fn point(&self, v: VertexId) -> D::Point {
        self.points[v.index()]
    }

    /// Whether vertex `v` (an existing vertex) is in conflict with cell `c`: used by validation.
    pub(crate) fn vertex_in_conflict(&self, c: CellId, v: VertexId) -> bool {
        self.in_conflict(c, self.points[v.index()])
    }

    /// The factor from internal to caller's coordinates.
    pub(crate) fn unscale(&self) -> f64 {
        self.unscale
    }

    /// Changes the caller's units by the factor `2^exponent`: from now on every coordinate
    /// the triangulation gives ([`Triangulation::vertex`] and the rest) is that many times what
    /// it was, and coordinates given to it are read in the new units. Vertices and cells do not
    /// change, and a power of two changes no coordinate's digits. Returns false (and changes
    /// nothing) if the units would leave the range of `f64`.
    ///
    /// A problem far from ordinary magnitudes can so be solved scaled into them and its result
    /// handed back in the caller's units.
    pub fn rescale_units(&mut self, exponent: i32) -> bool {
        if exponent.unsigned_abs() > 1000 {
            return false;
        }
        let factor = 2f64.powi(exponent);
        let (unscale, scale) = (self.unscale * factor, self.scale / factor);
        let ordinary = |x: f64| x.is_normal() && (2f64.powi(-1000)..=2f64.powi(1000)).contains(&x);
        if !(ordinary(unscale) && ordinary(scale)) {
            return false;
        }
        (self.unscale, self.scale) = (unscale, scale);
        true
    }
}

/// The key of the ridge of a new cell opposite its apex and its local vertex `j`: the cell's
/// other vertices (one in 2D, two in 3D), in a canonical order.
#[inline]
fn ridge_key(verts: &[VertexId], apex: usize, j: usize) -> u64 {
    let mut key = [u32::MAX; 2];
    let mut n = 0;
    for (k, v) in verts.iter().enumerate() {
        if k != apex && k != j {
            key[n] = v.0;
            n += 1;
        }
    }
    if n == 1 {
        u64::from(key[0])
    } else {
        let (a, b) = if key[0] < key[1] {
            (key[0], key[1])
        } else {
            (key[1], key[0])
        };
        u64::from(a) << 32 | u64::from(b)
    }
}

/// Two local indices other than `f` (for swapping), valid for cells of 3 and 4 vertices.
fn other_two(f: usize) -> (usize, usize) {
    match f {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

fn tri_scale<D: Dim>(mut p: D::Point, scale: f64) -> D::Point {
    for x in p.as_mut() {
        *x *= scale;
    }
    p
}

/// The power-of-two scale that brings the largest coordinate magnitude into `[0.5, 1)`, and
/// the smallest internal magnitude allowed; checks every coordinate.
fn scale_for<D: Dim>(points: &[D::Point]) -> Result<(f64, f64), TriangulationError> {
    let mut largest = 0.0f64;
    for (index, p) in points.iter().enumerate() {
        for (axis, &x) in p.as_ref().iter().enumerate() {
            if !x.is_finite() {
                return Err(TriangulationError::NonFinite {
                    index,
                    axis,
                    value: x,
                });
            }
            largest = largest.max(x.abs());
        }
    }
    if largest == 0.0 {
        return Ok((1.0, COORDINATE_RANGE.0));
    }
    let exponent = largest.log2().floor() as i32 + 1;
    let scale = 2f64.powi(-exponent);
    if !scale.is_normal() || !(1.0 / scale).is_normal() {
        // Only for magnitudes beyond 2^±1000, where scaling by a power of two is inexact.
        let index = points
            .iter()
            .position(|p| p.as_ref().iter().any(|x| x.abs() == largest))
            .unwrap_or(0);
        return Err(TriangulationError::CoordinateRange {
            index,
            value: largest,
            largest,
        });
    }
    let min_magnitude = COORDINATE_RANGE.0;
    for (index, p) in points.iter().enumerate() {
        for &x in p.as_ref() {
            // (A subnormal `x` can scale to zero: the test is on `x`.)
            let m = x.abs() * scale;
            if x != 0.0 && m < min_magnitude {
                return Err(TriangulationError::CoordinateRange {
                    index,
                    value: x,
                    largest,
                });
            }
        }
    }
    Ok((scale, min_magnitude))
}

fn count_distinct<D: Dim>(points: &[D::Point]) -> usize {
    let mut keys: Vec<Vec<u64>> = points
        .iter()
        .map(|p| p.as_ref().iter().map(|x| (x + 0.0).to_bits()).collect())
        .collect();
    keys.sort_unstable();
    keys.dedup();
    keys.len()
}
