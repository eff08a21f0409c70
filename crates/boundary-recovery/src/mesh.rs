//! What a [`Mesh2`] reports: its elements (the cells inside the domain), their area, and flat
//! arrays for writers and for smoothing.

use crate::classify::OUTSIDE;
use crate::recovery::Mesh2;
use delmesh_delaunay_core::{CellId, Renumbering, VertexId};
use delmesh_predicates::{orient2d, Sign};
use rayon::prelude::*;
use rustc_hash::FxHashMap as HashMap;

/// A mesh as flat arrays, vertices renumbered: input points first in input order, then the
/// points added by recovery and generation in order of creation. Vertices used by no element
/// (outside the domain, in holes, duplicates) are left out.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshArrays {
    /// Vertex coordinates.
    pub coords: Vec<[f64; 2]>,
    /// Triangles, counter-clockwise.
    pub triangles: Vec<[u32; 3]>,
    /// Region attribute of each triangle.
    pub regions: Vec<f64>,
    /// Boundary marker of each vertex: the input point's marker if it has one, else the marker
    /// of a boundary edge through it, else 0.
    pub point_markers: Vec<i32>,
    /// Whether each vertex is on the boundary (an end of a boundary edge): smoothing keeps these
    /// fixed.
    pub on_boundary: Vec<bool>,
    /// Boundary edges: each an edge of an element. One with an element on one side only (on
    /// the boundary of the domain) has it on its left, so its outward normal is (dy, −dx); one
    /// inside the domain (a wake, a wall between regions) has its input segment's direction.
    pub edges: Vec<[u32; 2]>,
    /// Marker of each boundary edge.
    pub edge_markers: Vec<i32>,
    /// The triangulation vertex of each output vertex.
    pub vertex: Vec<VertexId>,
    /// For each triangle, the triangle across its edge `(t[e], t[(e + 1) % 3])`, or `u32::MAX`
    /// where the other side is not in the mesh.
    pub neighbours: Vec<[u32; 3]>,
}

impl Mesh2 {
    /// Changes the mesh's units by `2^exponent`: vertex coordinates (see
    /// `rescale_units` of the triangulation) and spacing. False, with nothing changed, if the
    /// units would leave the range of `f64`.
    pub fn rescale_units(&mut self, exponent: i32) -> bool {
        if !self.cdt.rescale_units(exponent) {
            return false;
        }
        let factor = 2f64.powi(exponent);
        for h in &mut self.spacing {
            *h *= factor;
        }
        true
    }

    /// The elements: cells inside the domain.
    pub fn elements(&self) -> impl Iterator<Item = CellId> + '_ {
        self.cdt
            .triangulation()
            .cells()
            .filter(|&c| self.cdt.tag(c) != OUTSIDE)
    }

    /// Whether cell slot `c` holds an element (a finite cell inside the domain).
    #[inline]
    pub fn is_element(&self, c: CellId) -> bool {
        let tri = self.cdt.triangulation();
        tri.is_live(c) && !tri.is_ghost(c) && self.cdt.tag(c) != OUTSIDE
    }

    /// The boundary edge `a b` as written (see [`Mesh2::to_arrays`]): `None` if no element is
    /// on either side, else with the element on its left if only one side has one, else as
    /// given.
    fn oriented(&self, a: VertexId, b: VertexId) -> Option<[VertexId; 2]> {
        let (c, facet) = self.cdt.find_edge(a, b)?;
        let tri = self.cdt.triangulation();
        let across = tri.neighbor_facet(c, facet).cell();
        // Whether c has a then b counter-clockwise: then c is on the left of a → b.
        let v = tri.cell(c);
        let k = v.iter().position(|&u| u == a)?;
        let (left, right) = if v[(k + 1) % 3] == b {
            (c, across)
        } else {
            (across, c)
        };
        match (self.is_element(left), self.is_element(right)) {
            (false, false) => None,
            (false, true) => Some([b, a]),
            _ => Some([a, b]),
        }
    }

    /// The input segments (0-based, as `segments` lists their end points in the input's
    /// numbering) with no element on either side: all of them (first list), or some piece
    /// (second list), in increasing order. Each segment's pieces are found along it, so a
    /// segment lying on another (whose pieces carry the other's number) is judged too.
    pub(crate) fn segments_outside(&self, segments: &[(u32, u32)]) -> (Vec<u32>, Vec<u32>) {
        let tri = self.cdt.triangulation();
        // The boundary edges at each vertex, with whether they bound an element.
        let mut at: HashMap<VertexId, Vec<(VertexId, bool)>> = HashMap::default();
        for e in &self.edges {
            let bounds = self.oriented(e.a, e.b).is_some();
            at.entry(e.a).or_default().push((e.b, bounds));
            at.entry(e.b).or_default().push((e.a, bounds));
        }
        let (mut outside, mut partly) = (Vec::new(), Vec::new());
        for (k, &(a, b)) in segments.iter().enumerate() {
            let (a, b) = (
                tri.vertex_of_input(a as usize),
                tri.vertex_of_input(b as usize),
            );
            let (pa, pb) = (tri.vertex(a), tri.vertex(b));
            let along =
                |p: [f64; 2]| (p[0] - pa[0]) * (pb[0] - pa[0]) + (p[1] - pa[1]) * (pb[1] - pa[1]);
            // From a towards b, piece by piece: the next is the edge to a vertex on a b
            // (exactly) farther along. A segment whose walk breaks off (not expected) is
            // not named.
            let (mut u, mut pieces, mut bounding) = (a, 0usize, 0usize);
            while u != b && pieces <= self.edges.len() {
                let next = at.get(&u).and_then(|edges| {
                    edges.iter().copied().find(|&(w, _)| {
                        let pw = tri.vertex(w);
                        orient2d(pa, pb, pw) == Sign::Zero
                            && along(pw) > along(tri.vertex(u))
                            && along(pw) <= along(pb)
                    })
                });
                let Some((w, bounds)) = next else {
                    break;
                };
                pieces += 1;
                bounding += usize::from(bounds);
                u = w;
            }
            if u != b || pieces == 0 {
                continue;
            }
            if bounding == 0 {
                outside.push(k as u32);
            } else if bounding < pieces {
                partly.push(k as u32);
            }
        }
        (outside, partly)
    }

    /// Renumbers the triangulation's vertices and cells along a space-filling curve, for the
    /// memory locality of every later sweep (see `Triangulation::renumber`); the spacing and the
    /// boundary edges move with their vertices. The output arrays, numbered by input order, do
    /// not change.
    pub fn renumber(&mut self) -> Renumbering {
        let map = self.cdt.renumber();
        self.spacing = map.permute_vertices(&self.spacing, f64::NAN);
        for e in &mut self.edges {
            (e.a, e.b) = (map.vertex(e.a), map.vertex(e.b));
        }
        map
    }

    /// Number of elements.
    pub fn num_elements(&self) -> usize {
        self.elements().count()
    }

    /// Total area of the elements.
    pub fn area(&self) -> f64 {
        let tri = self.cdt.triangulation();
        self.elements()
            .map(|c| {
                let v = tri.cell(c);
                let (a, b, d) = (tri.vertex(v[0]), tri.vertex(v[1]), tri.vertex(v[2]));
                0.5 * ((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]))
            })
            .sum()
    }

    /// The elements in slot order (the slots are scanned in parallel).
    pub fn element_list(&self) -> Vec<CellId> {
        (0..self.cdt.num_cell_slots() as u32)
            .into_par_iter()
            .with_min_len(1 << 12)
            .map(CellId)
            .filter(|&c| self.is_element(c))
            .collect()
    }

    /// What 2D smoothing reads of the connectivity, taken from the triangulation as it is,
    /// without building flat arrays: a function that appends the neighbours of vertex `v` (in
    /// the triangulation's numbering) counter-clockwise to `out` and returns true if `v` may
    /// move, false if it stays fixed: on a boundary edge, or with a cell around it that is not
    /// an element (on the border of the domain, or used by none). The ring is read off the
    /// cells' neighbours around `v`; the function may be called from several threads.
    pub fn smoothing_rings(&self) -> impl Fn(usize, &mut Vec<u32>) -> bool + Sync + '_ {
        let mut on_edge = vec![false; self.cdt.triangulation().num_vertices()];
        for e in &self.edges {
            for v in [e.a, e.b] {
                if let Some(f) = on_edge.get_mut(v.index()) {
                    *f = true;
                }
            }
        }
        move |v, out| !on_edge[v] && self.ring_around(VertexId(v as u32), out)
    }

    /// Appends the neighbours of `v` counter-clockwise to `out`, walking from cell to cell
    /// around it: false (with `out` holding garbage past its old length) if a cell around it
    /// is not an element.
    fn ring_around(&self, v: VertexId, out: &mut Vec<u32>) -> bool {
        /// More neighbours than any vertex of a mesh worth smoothing has: such a vertex stays
        /// fixed (and a broken neighbourhood cannot make the walk loop).
        const MOST: usize = 1 << 10;
        let tri = self.cdt.triangulation();
        let first = tri.incident_cell(v);
        let mut c = first;
        for _ in 0..MOST {
            if !self.is_element(c) {
                return false;
            }
            let cell = tri.cell(c);
            let Some(i) = cell.iter().position(|&u| u == v) else {
                return false;
            };
            // Cell (v, a, b) is counter-clockwise: a comes first around v, and the next cell
            // is the one across edge (v, b), opposite a.
            out.push(cell[(i + 1) % 3].0);
            c = tri.neighbor_facet(c, (i + 1) % 3).cell();
            if c == first {
                return true;
            }
        }
        false
    }

    /// The mesh as flat arrays (see [`MeshArrays`]).
    pub fn to_arrays(&self) -> MeshArrays {
        let tri = self.cdt.triangulation();
        let nv = tri.num_vertices();
        let cells = self.element_list();
        let mut used = vec![false; nv];
        for &c in &cells {
            for &v in tri.cell(c) {
                used[v.index()] = true;
            }
        }
        // In input order (each vertex has its own input index, so placing them by it sorts).
        let order: Vec<VertexId> = {
            let mut by_input = vec![VertexId::GHOST; tri.num_input_points()];
            for v in (0..nv as u32).map(VertexId).filter(|v| used[v.index()]) {
                by_input[tri.input_index(v)] = v;
            }
            by_input.into_iter().filter(|v| !v.is_ghost()).collect()
        };
        let mut number = vec![u32::MAX; nv];
        for (k, &v) in order.iter().enumerate() {
            number[v.index()] = k as u32;
        }
        let mut out = MeshArrays {
            coords: order.par_iter().map(|&v| tri.vertex(v)).collect(),
            point_markers: vec![0; order.len()],
            on_boundary: vec![false; order.len()],
            triangles: cells
                .par_iter()
                .map(|&c| {
                    let v = tri.cell(c);
                    [
                        number[v[0].index()],
                        number[v[1].index()],
                        number[v[2].index()],
                    ]
                })
                .collect(),
            ..Default::default()
        };
        let mut triangle_of = vec![u32::MAX; self.cdt.num_cell_slots()];
        for (k, &c) in cells.iter().enumerate() {
            triangle_of[c.index()] = k as u32;
        }
        out.regions = cells
            .par_iter()
            .map(|&c| {
                let tag = self.cdt.tag(c) as usize;
                self.region_attributes.get(tag).copied().unwrap_or(0.0)
            })
            .collect();
        // Edge (v[e], v[e + 1]) is the facet opposite local vertex e + 2.
        out.neighbours = cells
            .par_iter()
            .map(|&c| {
                std::array::from_fn(|e| {
                    triangle_of[tri.neighbor_facet(c, (e + 2) % 3).cell().index()]
                })
            })
            .collect();
        for e in &self.edges {
            // An edge with no element on either side (between a hole and the outside, or two
            // holes) bounds nothing; one with an element on one side only is written with the
            // domain on its left (outward normal (dy, −dx), as 3D faces point outward); one
            // inside the domain (a wake, a wall between regions) keeps its input direction.
            let Some([a, b]) = self.oriented(e.a, e.b) else {
                continue;
            };
            let (a, b) = (number[a.index()], number[b.index()]);
            out.edges.push([a, b]);
            out.edge_markers.push(e.marker);
            for k in [a, b] {
                out.on_boundary[k as usize] = true;
                if out.point_markers[k as usize] == 0 {
                    out.point_markers[k as usize] = e.marker;
                }
            }
        }
        for (k, &v) in order.iter().enumerate() {
            let i = tri.input_index(v);
            if let Some(&m) = self.point_markers.get(i) {
                if m != 0 {
                    out.point_markers[k] = m;
                }
            }
        }
        out.vertex = order;
        out
    }
}
