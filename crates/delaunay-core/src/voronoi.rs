//! The Voronoi diagram, dual of the Delaunay triangulation (`../shared/paper.md` R2).
//!
//! Each finite cell of the triangulation is a Voronoi vertex at its circumcentre; its *forming
//! points* are the cell's vertices and its *neighbouring Voronoi vertices* are the cells across
//! its facets, `*` on the hull: the paper's Table 1. The Voronoi region of a point is the polygon
//! (2D) or polyhedron (3D) of the circumcentres around it: in 2D unbounded regions are clipped to
//! a box; in 3D only bounded regions (points inside the hull) are produced.
//!
//! Co-spherical points (a lattice) are triangulated by several cells inscribed in one sphere,
//! which share one circumcentre: the regions list it once, and 3D faces left without area
//! (the duals of the diagonals the triangulation chose through such points) are dropped.
//! Which cells share a circumcentre is decided by the exact in-sphere predicate, never by
//! comparing constructed centres.

use crate::dim::{Dim, D2, D3};
use crate::ids::{CellId, VertexId};
use crate::triangulation::Triangulation;
use rayon::prelude::*;
use std::fmt::Write as _;

/// The Voronoi vertices of a triangulation with their forming points and neighbours.
#[derive(Clone, Debug)]
pub struct VoronoiDiagram<D: Dim> {
    cells: Vec<CellId>,
    centers: Vec<D::Point>,
    forming: Vec<u32>,
    neighbors: Vec<Option<u32>>,
}

impl<D: Dim> VoronoiDiagram<D> {
    /// The Voronoi vertices of `tri`, numbered in the order of their forming points (sorted
    /// input indices, compared lexicographically), so the numbering does not depend on the
    /// insertion order.
    pub fn new(tri: &Triangulation<D>) -> Self {
        let mut cells: Vec<(Vec<u32>, CellId)> = tri
            .cells()
            .map(|c| {
                let mut f: Vec<u32> = tri
                    .cell(c)
                    .iter()
                    .map(|&v| tri.input_index(v) as u32)
                    .collect();
                f.sort_unstable();
                (f, c)
            })
            .collect();
        cells.sort_unstable();
        let mut number = vec![u32::MAX; tri.simplices.len()];
        for (k, (_, c)) in cells.iter().enumerate() {
            number[c.index()] = k as u32;
        }
        let mut diagram = VoronoiDiagram {
            cells: Vec::with_capacity(cells.len()),
            centers: Vec::with_capacity(cells.len()),
            forming: Vec::with_capacity(cells.len() * D::C),
            neighbors: Vec::with_capacity(cells.len() * D::C),
        };
        for (forming, c) in cells {
            diagram.cells.push(c);
            diagram.centers.push(circumcenter(tri, c));
            diagram.forming.extend_from_slice(&forming);
            let mut ns: Vec<Option<u32>> = (0..D::C)
                .map(|i| tri.neighbor(c, i).map(|n| number[n.index()]))
                .collect();
            // Defined neighbours first, ascending; `*` last, as in the paper's table.
            ns.sort_unstable_by_key(|n| n.unwrap_or(u32::MAX));
            diagram.neighbors.extend_from_slice(&ns);
        }
        diagram
    }

    /// Number of Voronoi vertices (finite cells).
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// True when there are no Voronoi vertices.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// The triangulation cell dual to Voronoi vertex `i`.
    pub fn cell(&self, i: usize) -> CellId {
        self.cells[i]
    }

    /// Position of Voronoi vertex `i`: the circumcentre of its cell.
    pub fn circumcenter(&self, i: usize) -> D::Point {
        self.centers[i]
    }

    /// The forming points of Voronoi vertex `i` (input indices, ascending).
    pub fn forming_points(&self, i: usize) -> &[u32] {
        &self.forming[i * D::C..(i + 1) * D::C]
    }

    /// The neighbouring Voronoi vertices of `i`, `None` (the paper's `*`) across the hull.
    pub fn neighbors(&self, i: usize) -> &[Option<u32>] {
        &self.neighbors[i * D::C..(i + 1) * D::C]
    }

    /// The structure as the paper's Table 1: one row per Voronoi vertex, numbered from 1, with
    /// forming points numbered from `first_index` and `*` for a missing neighbour.
    pub fn table(&self, first_index: u32) -> String {
        let mut out =
            String::from("Voronoi vertex\tForming points\tNeighboring Voronoi vertices\n");
        for i in 0..self.len() {
            let forming: Vec<String> = self
                .forming_points(i)
                .iter()
                .map(|p| (p + first_index).to_string())
                .collect();
            let neighbors: Vec<String> = self
                .neighbors(i)
                .iter()
                .map(|n| n.map_or("*".to_string(), |n| (n + 1).to_string()))
                .collect();
            let _ = writeln!(
                out,
                "{}\t{}\t{}",
                i + 1,
                forming.join(" "),
                neighbors.join(" ")
            );
        }
        out
    }
}

fn circumcenter<D: Dim>(tri: &Triangulation<D>, c: CellId) -> D::Point {
    let pts: Vec<D::Point> = tri.cell(c).iter().map(|&v| tri.point(v)).collect();
    let mut center = D::circumcenter(&pts);
    for x in center.as_mut() {
        *x *= tri.unscale();
    }
    center
}

/// The Voronoi region of one point in 2D, clipped to a box.
#[derive(Clone, Debug, PartialEq)]
pub struct VoronoiCell2 {
    /// Input index of the point.
    pub point: usize,
    /// The region's corners, counter-clockwise (empty if it misses the box).
    pub polygon: Vec<[f64; 2]>,
}

impl<D: Dim> Triangulation<D> {
    /// For every cell slot, the first slot of the finite cells with the same circumcentre
    /// (itself for a cell alone on its circumsphere, and for ghost and free slots).
    ///
    /// Two cells sharing a facet have the same circumcentre exactly when the far vertex of
    /// one lies on the circumsphere of the other ([`Dim::cospherical`]: the exact predicate,
    /// unperturbed), and the cells inscribed in one sphere (a triangulation of the polytope of
    /// its points, a lattice's square or cube) are connected through such facets.
    fn circumcentre_classes(&self) -> Vec<u32> {
        let slots = self.num_cell_slots();
        // The facets between cells of one circumsphere, each once (from its lower cell).
        let merges: Vec<(u32, u32)> = (0..slots as u32)
            .into_par_iter()
            .map(CellId)
            .filter(|&c| self.is_live(c) && !self.is_ghost(c))
            .flat_map_iter(|c| {
                (0..D::C).filter_map(move |i| {
                    let f = self.neighbor_facet(c, i);
                    let n = f.cell();
                    if n < c || self.is_ghost(n) {
                        return None;
                    }
                    let far = self.point(self.cell(n)[f.facet()]);
                    D::cospherical(&self.points, &self.simplices[c.index()].v, far)
                        .then_some((c.0, n.0))
                })
            })
            .collect();
        // Union–find, each class rooted at its first slot (every link points to a lower one).
        let mut class: Vec<u32> = (0..slots as u32).collect();
        let root = |class: &mut Vec<u32>, mut c: u32| {
            while class[c as usize] != c {
                let up = class[class[c as usize] as usize];
                class[c as usize] = up;
                c = up;
            }
            c
        };
        for (a, b) in merges {
            let (a, b) = (root(&mut class, a), root(&mut class, b));
            class[a.max(b) as usize] = a.min(b);
        }
        for c in 0..slots {
            class[c] = class[class[c] as usize];
        }
        class
    }
}

/// The bounded 3D Voronoi regions as polygons on shared vertices (see
/// [`Triangulation::voronoi_faces_shared`]): flat arrays, no allocation per face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VoronoiFaces3 {
    /// The Voronoi vertices: the circumcentres of the tetrahedra that bound a face, each
    /// once (tetrahedra inscribed in one sphere share theirs).
    pub vertices: Vec<[f64; 3]>,
    /// Per face, the input indices of the point whose region it bounds and of the point on
    /// the other side.
    pub sides: Vec<[usize; 2]>,
    /// Where each face's corners end in `corners` (face `k` is `corners[ends[k - 1]..ends[k]]`,
    /// VTK's polygon offsets).
    pub ends: Vec<usize>,
    /// The faces' corners (indices into `vertices`), each face in cyclic order, at least three
    /// and no two consecutive the same.
    pub corners: Vec<u32>,
}

impl VoronoiFaces3 {
    /// Number of faces.
    pub fn len(&self) -> usize {
        self.sides.len()
    }

    /// Whether there is no face (no point strictly inside the hull).
    pub fn is_empty(&self) -> bool {
        self.sides.is_empty()
    }

    /// The corners of face `k`.
    pub fn face(&self, k: usize) -> &[u32] {
        let start = if k == 0 { 0 } else { self.ends[k - 1] };
        &self.corners[start..self.ends[k]]
    }
}

/// One face of a bounded 3D Voronoi region: the face between `point` and `neighbor`.
#[derive(Clone, Debug, PartialEq)]
pub struct VoronoiFace3 {
    /// Input index of the point whose region this face bounds.
    pub point: usize,
    /// Input index of the point on the other side of the face.
    pub neighbor: usize,
    /// The circumcentres around the Delaunay edge `point–neighbor`, in cyclic order, each
    /// once.
    pub polygon: Vec<[f64; 3]>,
}

impl Triangulation<D2> {
    /// The Voronoi region of every vertex, clipped to the box `[lo, hi]`.
    ///
    /// A region is the polygon of the circumcentres around its point; the region of a point on
    /// the hull is unbounded, and its polygon starts and ends with *points at infinity* in the
    /// directions of its two rays (the outward normals of the point's hull edges). The polygons
    /// are clipped in homogeneous coordinates, where a ray's intersection with a side of the box
    /// is computed from its circumcentre and direction: no ray is truncated, so no finite
    /// stand-in for infinity can fall inside the box or fold the polygon over. The regions so
    /// tile the box (up to the rounding of the constructions) and each contains its point.
    /// Each distinct circumcentre is one corner: the triangles inscribed in one circle
    /// (co-circular points) give the same one, computed from the same triangle in every
    /// region, so neighbouring regions share it to the bit.
    /// Computed in the triangulation's internal units (a power of two from the caller's, so
    /// the box's sides come back exactly), where nothing overflows.
    pub fn voronoi_cells(&self, lo: [f64; 2], hi: [f64; 2]) -> Vec<VoronoiCell2> {
        // A box beyond the range of f64 in internal units is cut down to a finite one.
        let limit = f64::MAX / 16.0;
        let inside = |x: f64| (x * self.scale).clamp(-limit, limit);
        let (lo, hi) = (lo.map(inside), hi.map(inside));
        let class = self.circumcentre_classes();
        (0..self.num_vertices())
            .map(|v| {
                let v = VertexId(v as u32);
                let polygon = clip_to_box(self.voronoi_polygon(v, &class), lo, hi)
                    .into_iter()
                    .map(|p| p.map(|x| x * self.unscale))
                    .collect();
                VoronoiCell2 {
                    point: self.input_index(v),
                    polygon,
                }
            })
            .collect()
    }

    /// The cells around `v` counter-clockwise, starting after the hull if `v` is on it.
    fn ring_around(&self, v: VertexId) -> Vec<CellId> {
        let start = self.incident_cell(v);
        let mut ring = Vec::new();
        let mut c = start;
        loop {
            ring.push(c);
            let i = self
                .cell(c)
                .iter()
                .position(|&u| u == v)
                .expect("v in its ring");
            c = self.neighbor_facet(c, (i + 1) % 3).cell();
            if c == start {
                break;
            }
        }
        if let Some(g) = ring.iter().position(|&c| self.is_ghost(c)) {
            // Rotate so the finite cells come first, in order, after the ghost cells.
            let after = (g..g + ring.len())
                .map(|k| k % ring.len())
                .find(|&k| !self.is_ghost(ring[k]))
                .unwrap_or(g);
            ring.rotate_left(after);
        }
        ring
    }

    /// The Voronoi region of `v` counter-clockwise, in internal units: the circumcentres of
    /// its cells, each once (`class`: see `circumcentre_classes`), between the directions of
    /// its two rays if `v` is on the hull.
    fn voronoi_polygon(&self, v: VertexId, class: &[u32]) -> Vec<Corner> {
        let ring = self.ring_around(v);
        let finite: Vec<CellId> = ring
            .iter()
            .copied()
            .filter(|&c| !self.is_ghost(c))
            .collect();
        // Consecutive cells inscribed in one circle give one corner, at the circumcentre of
        // the first cell of that circle.
        let mut centres: Vec<CellId> = finite.iter().map(|&c| CellId(class[c.index()])).collect();
        centres.dedup();
        let closed = finite.len() == ring.len();
        if closed && centres.len() > 1 && centres.first() == centres.last() {
            centres.pop();
        }
        let mut poly: Vec<Corner> = centres
            .iter()
            .map(|&c| Corner::At(self.internal_circumcenter(c)))
            .collect();
        if closed {
            return poly;
        }
        // Unbounded: the ray of a hull edge `v w` leaves the circumcentre of the edge's cell
        // along the edge's outward normal. The interior is left of `v → w` for the first cell's
        // edge (to its next vertex) and of `w → v` for the last's (from its previous one).
        let p = self.point(v);
        let normal = |c: CellId, first: bool| -> [f64; 2] {
            let cell = self.cell(c);
            let i = cell.iter().position(|&u| u == v).expect("v in its cell");
            let w = self.point(cell[if first { (i + 1) % 3 } else { (i + 2) % 3 }]);
            let (dx, dy) = (w[0] - p[0], w[1] - p[1]);
            let n = if first { [dy, -dx] } else { [-dy, dx] };
            let len = n[0].hypot(n[1]);
            [n[0] / len, n[1] / len]
        };
        let last = *finite.last().expect("a hull vertex has a finite cell");
        let (first, last) = (normal(finite[0], true), normal(last, false));
        // The region turns counter-clockwise from the last ray to the first by less than a
        // half-turn, but a hull angle below the rounding of the directions (a point far from
        // two close ones) can make the computed turn a half-turn or more, and two directions
        // alone do not say which way. A third, between them, does: their sum for a narrow turn,
        // their difference turned clockwise for a wide one (each well defined where used).
        let (sum, diff) = (
            [first[0] + last[0], first[1] + last[1]],
            [first[0] - last[0], first[1] - last[1]],
        );
        let middle = if sum[0].hypot(sum[1]) >= diff[0].hypot(diff[1]) {
            sum
        } else {
            [diff[1], -diff[0]]
        };
        poly.insert(0, Corner::Toward(first));
        poly.push(Corner::Toward(last));
        poly.push(Corner::Toward(middle));
        poly
    }

    /// Circumcentre of the finite cell `c` in internal units.
    fn internal_circumcenter(&self, c: CellId) -> [f64; 2] {
        let cell = self.cell(c);
        D2::circumcenter(&[
            self.point(cell[0]),
            self.point(cell[1]),
            self.point(cell[2]),
        ])
    }
}

/// A corner of a 2D Voronoi region before clipping: a point, or the point at infinity in a
/// direction (where an unbounded region's ray ends).
#[derive(Clone, Copy, Debug)]
enum Corner {
    At([f64; 2]),
    Toward([f64; 2]),
}

/// Sutherland–Hodgman clipping of a convex polygon, possibly with points at infinity, to an
/// axis-aligned box; the result is the finite polygon.
///
/// The polygon lives in the projective plane: an edge between two points at infinity is the
/// arc of directions between them (less than a half-turn: see `voronoi_polygon`), and
/// the box's bounded sides cut away every point at infinity. A corner exactly on a side is
/// kept and makes no crossing, so no corner is repeated.
fn clip_to_box(mut poly: Vec<Corner>, lo: [f64; 2], hi: [f64; 2]) -> Vec<[f64; 2]> {
    for axis in 0..2 {
        for (bound, keep_below) in [(lo[axis], false), (hi[axis], true)] {
            if poly.is_empty() {
                break;
            }
            // Signed distance past the side: positive outside. A point at infinity is outside
            // when its direction points out through the side.
            let past = |c: &Corner| {
                let d = match c {
                    Corner::At(p) => p[axis] - bound,
                    Corner::Toward(u) => u[axis],
                };
                if keep_below {
                    d
                } else {
                    -d
                }
            };
            let mut out = Vec::with_capacity(poly.len() + 2);
            for k in 0..poly.len() {
                let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
                let (pa, pb) = (past(&a), past(&b));
                if pa <= 0.0 {
                    out.push(a);
                }
                if (pa < 0.0 && pb > 0.0) || (pa > 0.0 && pb < 0.0) {
                    out.push(crossing(a, b, axis, bound));
                }
            }
            poly = out;
        }
    }
    poly.into_iter()
        .filter_map(|c| match c {
            Corner::At(p) => Some(p),
            Corner::Toward(_) => None,
        })
        .collect()
}

/// Where the edge `a b` crosses the line `x[axis] = bound` (its ends are strictly on either
/// side).
fn crossing(a: Corner, b: Corner, axis: usize, bound: f64) -> Corner {
    let other = 1 - axis;
    match (a, b) {
        (Corner::At(p), Corner::At(q)) => {
            // From the lexicographically smaller end, so that the two regions sharing the edge
            // (which run it in opposite directions) get the same point.
            let (p, q) = if (p[0], p[1]) <= (q[0], q[1]) {
                (p, q)
            } else {
                (q, p)
            };
            let t = (bound - p[axis]) / (q[axis] - p[axis]);
            let mut x = [0.0; 2];
            x[axis] = bound;
            x[other] = p[other] + t * (q[other] - p[other]);
            Corner::At(x)
        }
        (Corner::At(p), Corner::Toward(u)) | (Corner::Toward(u), Corner::At(p)) => {
            // The ray from `p` along `u`.
            let mut x = [0.0; 2];
            x[axis] = bound;
            x[other] = p[other] + (bound - p[axis]) * (u[other] / u[axis]);
            Corner::At(x)
        }
        (Corner::Toward(u), Corner::Toward(w)) => {
            // The direction between the two that is parallel to the side.
            let mut x = [0.0; 2];
            x[other] = w[axis].abs() * u[other] + u[axis].abs() * w[other];
            Corner::Toward(x)
        }
    }
}

impl Triangulation<D3> {
    /// The faces of every bounded Voronoi region (points strictly inside the convex hull):
    /// one face per Delaunay edge at the point, a ring of circumcentres, each once. (Each face
    /// carries its own copy of its corners: [`Triangulation::voronoi_faces_shared`] is the
    /// compact form.)
    ///
    /// An edge whose ring has fewer than three distinct circumcentres has no face (no area):
    /// it is a diagonal the triangulation chose through co-spherical points, inside their
    /// polytope (one centre: a lattice cube's body diagonal) or across a polygon two such
    /// polytopes share (two centres: a square's diagonal).
    pub fn voronoi_faces(&self) -> Vec<VoronoiFace3> {
        let shared = self.voronoi_faces_shared();
        (0..shared.len())
            .map(|k| VoronoiFace3 {
                point: shared.sides[k][0],
                neighbor: shared.sides[k][1],
                polygon: shared
                    .face(k)
                    .iter()
                    .map(|&i| shared.vertices[i as usize])
                    .collect(),
            })
            .collect()
    }

    /// [`Triangulation::voronoi_faces`] on shared vertices: each circumcentre is computed and
    /// stored once (one per circumsphere), and the faces index them. The points' regions are
    /// gathered in parallel, in point order (the same result whatever the number of threads).
    pub fn voronoi_faces_shared(&self) -> VoronoiFaces3 {
        /// A run of points' faces: sides, corner counts, corners (first cell slots of their
        /// circumspheres).
        type Part = (Vec<[usize; 2]>, Vec<u32>, Vec<u32>);
        const CHUNK: usize = 1024;
        let n = self.num_vertices();
        let class = self.circumcentre_classes();
        let parts: Vec<Part> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|k| {
                let (mut sides, mut lengths, mut rings) = (Vec::new(), Vec::new(), Vec::new());
                for v in (k * CHUNK..((k + 1) * CHUNK).min(n)).map(|v| VertexId(v as u32)) {
                    let star = self.cells_around_vertex(v);
                    if star.iter().any(|&c| self.is_ghost(c)) {
                        continue;
                    }
                    let mut others: Vec<VertexId> = star
                        .iter()
                        .flat_map(|&c| self.cell(c).iter().copied())
                        .filter(|&u| u != v)
                        .collect();
                    others.sort_unstable();
                    others.dedup();
                    for w in others {
                        let before = rings.len();
                        self.ring_around_edge(v, w, &star, &class, &mut rings);
                        if rings.len() - before < 3 {
                            // Fewer than three distinct corners: no area, no face.
                            rings.truncate(before);
                            continue;
                        }
                        sides.push([self.input_index(v), self.input_index(w)]);
                        lengths.push((rings.len() - before) as u32);
                    }
                }
                (sides, lengths, rings)
            })
            .collect();
        // The circumspheres that bound a face (their first cells), numbered in slot order, and
        // their centres.
        let mut number = vec![u32::MAX; self.num_cell_slots()];
        for (_, _, rings) in &parts {
            for &c in rings {
                number[c as usize] = 0;
            }
        }
        let mut used = Vec::new();
        for (c, slot) in number.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = used.len() as u32;
                used.push(CellId(c as u32));
            }
        }
        let vertices = used.par_iter().map(|&c| circumcenter(self, c)).collect();
        let mut out = VoronoiFaces3 {
            vertices,
            ..VoronoiFaces3::default()
        };
        for (sides, lengths, rings) in parts {
            out.sides.extend(sides);
            let mut end = out.corners.len();
            out.ends.extend(lengths.iter().map(|&m| {
                end += m as usize;
                end
            }));
            out.corners
                .extend(rings.iter().map(|&c| number[c as usize]));
        }
        out
    }

    /// Appends the circumcentres of the cells around edge `v w` in cyclic order (all finite:
    /// `v` is interior) to `ring`, as their classes' slots (see `circumcentre_classes`):
    /// consecutive cells inscribed in one sphere give one corner.
    fn ring_around_edge(
        &self,
        v: VertexId,
        w: VertexId,
        star: &[CellId],
        class: &[u32],
        ring: &mut Vec<u32>,
    ) {
        let first = ring.len();
        let push = |ring: &mut Vec<u32>, c: CellId| {
            let k = class[c.index()];
            if ring.len() == first || ring.last() != Some(&k) {
                ring.push(k);
            }
        };
        let start = *star
            .iter()
            .find(|&&c| self.cell(c).contains(&w))
            .expect("w is a neighbour of v");
        push(ring, start);
        let mut prev = start;
        let mut c = start;
        loop {
            let verts = self.cell(c);
            let next = (0..4)
                .filter(|&k| verts[k] != v && verts[k] != w)
                .map(|k| self.neighbor_facet(c, k).cell())
                .find(|&n| n != prev)
                .expect("a tetrahedron has two facets through an edge");
            if next == start {
                break;
            }
            push(ring, next);
            prev = c;
            c = next;
        }
        // Around the ring, the last corner may be the first.
        if ring.len() > first + 1 && ring[first] == ring[ring.len() - 1] {
            ring.pop();
        }
    }
}
