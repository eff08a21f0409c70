//! The Voronoi diagram, dual of the Delaunay triangulation (`../shared/paper.md` R2).
//!
//! Each finite cell of the triangulation is a Voronoi vertex at its circumcentre; its *forming
//! points* are the cell's vertices and its *neighbouring Voronoi vertices* are the cells across
//! its facets, `*` on the hull: the paper's Table 1. The Voronoi region of a point is the polygon
//! (2D) or polyhedron (3D) of the circumcentres around it: in 2D unbounded regions are clipped to
//! a box; in 3D only bounded regions (points inside the hull) are produced.

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

/// The bounded 3D Voronoi regions as polygons on shared vertices (see
/// [`Triangulation::voronoi_faces_shared`]): flat arrays, no allocation per face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VoronoiFaces3 {
    /// The Voronoi vertices: the circumcentres of the tetrahedra that bound a face, each once.
    pub vertices: Vec<[f64; 3]>,
    /// Per face, the input indices of the point whose region it bounds and of the point on
    /// the other side.
    pub sides: Vec<[usize; 2]>,
    /// Where each face's corners end in `corners` (face `k` is `corners[ends[k - 1]..ends[k]]`,
    /// VTK's polygon offsets).
    pub ends: Vec<usize>,
    /// The faces' corners (indices into `vertices`), each face in cyclic order.
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
    /// The circumcentres around the Delaunay edge `point–neighbor`, in cyclic order.
    pub polygon: Vec<[f64; 3]>,
}

impl Triangulation<D2> {
    /// The Voronoi region of every vertex, clipped to the box `[lo, hi]`.
    pub fn voronoi_cells(&self, lo: [f64; 2], hi: [f64; 2]) -> Vec<VoronoiCell2> {
        // Far enough that the truncation of unbounded regions lies outside the box.
        let reach = {
            let mut r = (hi[0] - lo[0]).abs() + (hi[1] - lo[1]).abs();
            for c in self.cells() {
                let p = circumcenter(self, c);
                r = r.max((p[0] - lo[0]).abs() + (p[1] - lo[1]).abs());
            }
            // In the box's own units (a ray of length 1 past a box 1e-300 wide leaves nothing
            // of the box's digits where it is clipped), and below the largest float (a ray's
            // end must stay finite to be clipped).
            if r > 0.0 {
                (4.0 * r).min(f64::MAX / 16.0)
            } else {
                1.0
            }
        };
        (0..self.num_vertices())
            .map(|v| {
                let v = VertexId(v as u32);
                let polygon = clip_to_box(self.voronoi_polygon(v, reach), lo, hi);
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

    fn voronoi_polygon(&self, v: VertexId, reach: f64) -> Vec<[f64; 2]> {
        let ring = self.ring_around(v);
        let finite: Vec<CellId> = ring
            .iter()
            .copied()
            .filter(|&c| !self.is_ghost(c))
            .collect();
        let mut poly: Vec<[f64; 2]> = finite.iter().map(|&c| circumcenter(self, c)).collect();
        if finite.len() == ring.len() {
            return poly;
        }
        // Unbounded region: rays along the outward normals of v's two hull edges.
        let p = self.vertex(v);
        let ray = |c: CellId, before: bool| -> [f64; 2] {
            let cell = self.cell(c);
            let i = cell.iter().position(|&u| u == v).expect("v in cell");
            // The hull edge through v: to the next vertex (first cell) or the previous (last).
            let w = if before {
                cell[(i + 1) % 3]
            } else {
                cell[(i + 2) % 3]
            };
            let q = self.vertex(w);
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            // The interior is to the left of v→w for the first cell's edge, to the right of
            // w→v... so the outward normal is (dy, −dx) for v→w and (−dy, dx) for the other.
            let n = if before { [dy, -dx] } else { [-dy, dx] };
            // (`hypot`: the squares of coordinates near 1e±200 overflow or vanish.)
            let len = n[0].hypot(n[1]);
            let o = circumcenter(self, c);
            [o[0] + reach * (n[0] / len), o[1] + reach * (n[1] / len)]
        };
        let first = ray(finite[0], true);
        let last = ray(
            *finite.last().expect("a hull vertex has a finite cell"),
            false,
        );
        let mid_dir = [
            first[0] + last[0] - 2.0 * p[0],
            first[1] + last[1] - 2.0 * p[1],
        ];
        let mid_len = mid_dir[0].hypot(mid_dir[1]).max(f64::MIN_POSITIVE);
        let mid = [
            p[0] + 2.0 * reach * (mid_dir[0] / mid_len),
            p[1] + 2.0 * reach * (mid_dir[1] / mid_len),
        ];
        poly.insert(0, first);
        poly.push(last);
        poly.push(mid);
        poly
    }
}

/// Sutherland–Hodgman clipping of a convex polygon to an axis-aligned box.
fn clip_to_box(mut poly: Vec<[f64; 2]>, lo: [f64; 2], hi: [f64; 2]) -> Vec<[f64; 2]> {
    for axis in 0..2 {
        for (bound, keep_below) in [(lo[axis], false), (hi[axis], true)] {
            if poly.is_empty() {
                return poly;
            }
            let inside = |p: &[f64; 2]| {
                if keep_below {
                    p[axis] <= bound
                } else {
                    p[axis] >= bound
                }
            };
            let mut out = Vec::with_capacity(poly.len() + 2);
            for k in 0..poly.len() {
                let a = poly[k];
                let b = poly[(k + 1) % poly.len()];
                if inside(&a) {
                    out.push(a);
                }
                if inside(&a) != inside(&b) {
                    let t = (bound - a[axis]) / (b[axis] - a[axis]);
                    let mut x = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                    x[axis] = bound;
                    out.push(x);
                }
            }
            poly = out;
        }
    }
    poly
}

impl Triangulation<D3> {
    /// The faces of every bounded Voronoi region (points strictly inside the convex hull):
    /// one face per Delaunay edge at the point, a ring of circumcentres. (Each face carries its
    /// own copy of its corners: [`Triangulation::voronoi_faces_shared`] is the compact form.)
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
    /// stored once, and the faces index them. The points' regions are gathered in parallel,
    /// in point order (the same result whatever the number of threads).
    pub fn voronoi_faces_shared(&self) -> VoronoiFaces3 {
        /// A run of points' faces: sides, ring lengths, rings (cell slots).
        type Part = (Vec<[usize; 2]>, Vec<u32>, Vec<u32>);
        const CHUNK: usize = 1024;
        let n = self.num_vertices();
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
                        self.ring_around_edge(v, w, &star, &mut rings);
                        sides.push([self.input_index(v), self.input_index(w)]);
                        lengths.push((rings.len() - before) as u32);
                    }
                }
                (sides, lengths, rings)
            })
            .collect();
        // The cells that bound a face, numbered in slot order, and their circumcentres.
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

    /// Appends the cells around edge `v w` in cyclic order (all finite: `v` is interior) to
    /// `ring`, as slot numbers.
    fn ring_around_edge(&self, v: VertexId, w: VertexId, star: &[CellId], ring: &mut Vec<u32>) {
        let start = *star
            .iter()
            .find(|&&c| self.cell(c).contains(&w))
            .expect("w is a neighbour of v");
        ring.push(start.0);
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
            ring.push(next.0);
            prev = c;
            c = next;
        }
    }
}
