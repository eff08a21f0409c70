//! What a [`Mesh3`] reports: its elements (the tetrahedra inside the domain), their volume, and
//! flat arrays for writers and for smoothing.

use rustc_hash::FxHashMap as HashMap;

use rayon::prelude::*;

use crate::classify::OUTSIDE;

/// Elements (or faces) per parallel task in [`Mesh3::to_arrays`]: below a few of these,
/// waking the other threads costs more than the work shared.
const PARALLEL_CHUNK: usize = 1 << 15;
use crate::recovery3::{cross, dot, sub, BoundaryFace, Mesh3, RecoveryMethod3};
use delmesh_delaunay_core::{
    CellId, ConstrainedTriangulation3, FacetRef, Renumbering, TriangulationError, VertexId,
};
use delmesh_predicates::{orient3d, Sign};

/// Where each boundary face of a [`Mesh3`] is in [`Mesh3::faces`], by its sorted corners: for
/// [`Mesh3::split_edge`], which keeps it up to date.
#[derive(Clone, Debug, Default)]
pub struct FaceIndex(HashMap<[VertexId; 3], usize>);

/// Rounds of [`Mesh3::split_flat_elements`]: a centroid's new elements are not flat, so one
/// round is enough unless flat elements touch; the bound keeps any input bounded.
const FLAT_SPLIT_ROUNDS: usize = 4;

/// Whether the tetrahedron `p` is flat: its height over its largest face is within 2^-30 of
/// that face's width (twice its area over the longest edge), so that its dihedral angles are
/// within about 2^-30 of 0° and 180° (the test of [`Mesh3::remove_flat_surface_elements`]
/// too). Against a length alone, long bodies had elements called flat: against the longest
/// edge cubed, a needle (a corner 0.11 off a CAD cylinder's cap 50 long); against the
/// longest edge, the two side faces of a hexagonal prism 1e9 long meeting at 120°, whose
/// diagonal was swapped and 14% of the volume lost.
fn flat(p: [[f64; 3]; 4]) -> bool {
    let mut longest2 = 0.0f64;
    for i in 0..4 {
        for j in i + 1..4 {
            let d = sub(p[i], p[j]);
            longest2 = longest2.max(dot(d, d));
        }
    }
    // Twice the largest face area, and six times the volume: the height over that face is
    // their ratio, and the face's width twice its area over the longest edge.
    let largest = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]]
        .iter()
        .map(|&[a, b, c]| {
            let n = cross(sub(p[b], p[a]), sub(p[c], p[a]));
            dot(n, n).sqrt()
        })
        .fold(0.0f64, f64::max);
    let six_volume = dot(cross(sub(p[1], p[0]), sub(p[2], p[0])), sub(p[3], p[0])).abs();
    // height ≤ 2^-30 width: six_volume / largest ≤ 2^-30 largest / longest (a NaN volume is
    // not flat).
    six_volume * longest2.sqrt() <= largest * largest * 2f64.powi(-30)
}

fn sorted(mut v: [VertexId; 3]) -> [VertexId; 3] {
    v.sort_unstable();
    v
}

/// A tetrahedral mesh as flat arrays, vertices renumbered: input points first in input order,
/// then the points added by recovery and generation in order of creation. Vertices used by no
/// element (outside the domain, in holes, duplicates) are left out.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshArrays3 {
    /// Vertex coordinates.
    pub coords: Vec<[f64; 3]>,
    /// Tetrahedra, positively oriented.
    pub tets: Vec<[u32; 4]>,
    /// Region attribute of each tetrahedron.
    pub regions: Vec<f64>,
    /// Boundary marker of each vertex: the input point's marker if it has one, else the marker
    /// of a boundary face through it, else 0.
    pub point_markers: Vec<i32>,
    /// Whether each vertex is on the boundary surface: smoothing keeps these fixed.
    pub on_boundary: Vec<bool>,
    /// Boundary triangles. Each on the boundary of the domain faces out of it (its normal by
    /// the right-hand rule points away from its element, as solvers expect); one between two
    /// parts of the domain (an internal wall) is oriented like the input triangle it subdivides.
    pub faces: Vec<[u32; 3]>,
    /// Marker of each boundary triangle.
    pub face_markers: Vec<i32>,
    /// Input facet (0-based) of each boundary triangle.
    pub face_facets: Vec<u32>,
    /// The triangulation vertex of each output vertex.
    pub vertex: Vec<VertexId>,
    /// `neighbours[t][k]`: the tetrahedron across the face of `tets[t]` opposite its vertex
    /// `k`, or `u32::MAX` where that face is on the boundary of the output.
    pub neighbours: Vec<[u32; 4]>,
}

/// Signed volume of the tetrahedron `a b c d` (positive when right-handed).
pub fn tet_volume(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let w = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
    (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0]))
        / 6.0
}

impl Mesh3 {
    /// Renumbers the vertices along a Hilbert curve and the cells by their smallest vertex
    /// ([`ConstrainedTriangulation3::renumber`](delmesh_delaunay_core::ConstrainedTriangulation3::renumber)),
    /// for memory locality after point generation, which numbers them pass by pass; spacing,
    /// surface flags and boundary faces move with their vertices.
    pub fn renumber(&mut self) -> Renumbering {
        let map = self.ct.renumber();
        self.spacing = map.permute_vertices(&self.spacing, f64::NAN);
        self.on_surface = map.permute_vertices(&self.on_surface, false);
        for f in &mut self.faces {
            f.v = f.v.map(|v| map.vertex(v));
        }
        map
    }

    /// Changes the mesh's units by `2^exponent`: vertex coordinates (see
    /// `rescale_units` of the triangulation) and spacing. False, with nothing changed, if the
    /// units would leave the range of `f64`.
    pub fn rescale_units(&mut self, exponent: i32) -> bool {
        if !self.ct.rescale_units(exponent) {
            return false;
        }
        let factor = 2f64.powi(exponent);
        for h in &mut self.spacing {
            *h *= factor;
        }
        true
    }

    /// The elements: finite cells inside the domain.
    pub fn elements(&self) -> impl Iterator<Item = CellId> + '_ {
        self.ct
            .triangulation()
            .cells()
            .filter(|&c| self.ct.tag(c) != OUTSIDE)
    }

    /// Number of elements.
    pub fn num_elements(&self) -> usize {
        self.elements().count()
    }

    /// Total volume of the elements.
    pub fn volume(&self) -> f64 {
        let tri = self.ct.triangulation();
        self.elements()
            .map(|c| {
                let v = tri.cell(c);
                tet_volume(
                    tri.vertex(v[0]),
                    tri.vertex(v[1]),
                    tri.vertex(v[2]),
                    tri.vertex(v[3]),
                )
            })
            .sum()
    }

    /// The index of [`Self::faces`] that [`Self::split_edge`] needs.
    pub fn face_index(&self) -> FaceIndex {
        FaceIndex(
            self.faces
                .iter()
                .enumerate()
                .map(|(k, f)| (sorted(f.v), k))
                .collect(),
        )
    }

    /// Splits the edge `x y` at its mid-point (see
    /// [`delmesh_delaunay_core::ConstrainedTriangulation3::split_edge`]): a boundary edge splits
    /// the boundary faces on it, which keep their marker and facet, and its new vertex is on
    /// the surface. Returns the new vertex, or `None` (nothing changed) where the edge cannot
    /// be split so.
    ///
    /// # Errors
    /// A mid-point outside the triangulation's coordinate range.
    pub fn split_edge(
        &mut self,
        x: VertexId,
        y: VertexId,
        index: &mut FaceIndex,
    ) -> Result<Option<VertexId>, TriangulationError> {
        let tri = self.ct.triangulation();
        let (a, b) = (tri.vertex(x), tri.vertex(y));
        let mid = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
        let Some((v, split)) = self.ct.split_edge(x, y, mid)? else {
            return Ok(None);
        };
        let at = |values: &[f64], u: VertexId| values.get(u.index()).copied().unwrap_or(f64::NAN);
        let h = 0.5 * (at(&self.spacing, x) + at(&self.spacing, y));
        let n = v.index() + 1;
        self.spacing.resize(n.max(self.spacing.len()), f64::NAN);
        self.on_surface.resize(n.max(self.on_surface.len()), false);
        self.spacing[v.index()] = h;
        self.on_surface[v.index()] = !split.is_empty();
        for w in split {
            let Some(k) = index.0.remove(&sorted([x, y, w])) else {
                continue;
            };
            let f = self.faces[k];
            // The face's corners from the edge's first end in the face's order: (u, u2, o).
            let first = (0..3)
                .find(|&i| f.v[(i + 2) % 3] == w)
                .expect("w is a corner of the face");
            let (u, u2, o) = (f.v[first], f.v[(first + 1) % 3], w);
            self.faces[k] = BoundaryFace { v: [u, v, o], ..f };
            index.0.insert(sorted([u, v, o]), k);
            index.0.insert(sorted([v, u2, o]), self.faces.len());
            self.faces.push(BoundaryFace { v: [v, u2, o], ..f });
        }
        Ok(Some(v))
    }

    /// Takes out of the domain every element that lies flat on the surface, and returns how
    /// many: two of its faces are boundary faces with the exterior beyond both, of one input
    /// facet or of two facets with one marker, and its four corners lie in one plane to
    /// rounding (its volume is at most 2^-30 of its longest edge cubed), and the
    /// quadrilateral they make is convex (exact orientations about the faces' normal). Its two
    /// other faces become the boundary faces there: the diagonal is swapped. Within one facet
    /// the facet is covered as before. Across two facets, the surface moves by the element's
    /// volume (rounding): those are nearly coplanar neighbours, such as the triangles of a
    /// planar face of a CAD part rotated into a general position, whose corners rounding put
    /// a hair off one plane (each new face is counted in one of the two facets). Splits of
    /// surface edges (recovery, restoration) and such neighbours leave elements with dihedral
    /// angles of 0° and 180° and a volume whose floating-point sign is noise, that no move of
    /// interior points mends. Faces between two regions are left alone.
    pub fn remove_flat_surface_elements(&mut self) -> usize {
        // Elements with two protected faces, the only ones that can be; an element taken out
        // makes its neighbours across its two other faces candidates.
        let two_protected = |mesh: &Self, c: CellId| {
            mesh.ct.tag(c) != OUTSIDE && (0..4).filter(|&k| mesh.ct.is_protected(c, k)).count() == 2
        };
        let mut todo: Vec<CellId> = self
            .elements()
            .filter(|&c| two_protected(self, c))
            .collect();
        if todo.is_empty() {
            return 0;
        }
        let mut index = self.face_index();
        let mut removed = 0;
        while let Some(c) = todo.pop() {
            if !two_protected(self, c) || !self.remove_if_flat(c, &mut index) {
                continue;
            }
            removed += 1;
            let tri = self.ct.triangulation();
            for k in 0..4 {
                if let Some(n) = tri.neighbor(c, k) {
                    if two_protected(self, n) {
                        todo.push(n);
                    }
                }
            }
        }
        removed
    }

    /// [`Self::remove_flat_surface_elements`] for the element `c`.
    fn remove_if_flat(&mut self, c: CellId, index: &mut FaceIndex) -> bool {
        let tri = self.ct.triangulation();
        let corners = tri.cell(c);
        let v = [corners[0], corners[1], corners[2], corners[3]];
        // Local indices of the faces on the exterior; the others must be interior faces.
        let mut out = Vec::with_capacity(4);
        for k in 0..4 {
            let beyond = tri.neighbor(c, k).filter(|&n| self.ct.tag(n) != OUTSIDE);
            match (self.ct.is_protected(c, k), beyond) {
                (true, None) => out.push(k),
                (false, Some(_)) => {}
                _ => return false,
            }
        }
        let [i, j] = out[..] else {
            return false;
        };
        let face = |k: usize| sorted([v[(k + 1) % 4], v[(k + 2) % 4], v[(k + 3) % 4]]);
        let (Some(&f1), Some(&f2)) = (index.0.get(&face(i)), index.0.get(&face(j))) else {
            return false;
        };
        // Faces of two facets must have one marker, or the line where markers meet would move.
        if self.faces[f1].facet != self.faces[f2].facet
            && self.faces[f1].marker != self.faces[f2].marker
        {
            return false;
        }
        // Face f1 holds v[j] (its corner off the shared edge), f2 holds v[i]. Rotate f1 to
        // (a, b, c) with c = v[j]: the shared edge runs a → b in it and b → a in f2.
        let (c_, d_) = (v[j], v[i]);
        let t1 = self.faces[f1].v;
        let r = (0..3)
            .find(|&m| t1[m] == c_)
            .expect("v[j] is a corner of its face");
        let (a, b) = (t1[(r + 1) % 3], t1[(r + 2) % 3]);
        let t2 = self.faces[f2].v;
        let consistent = (0..3).any(|m| t2[m] == b && t2[(m + 1) % 3] == a);
        if !consistent {
            return false;
        }
        let p = |u: VertexId| tri.vertex(u);
        let (pa, pb, pc, pd) = (p(a), p(b), p(c_), p(d_));
        if !flat([pa, pb, pc, pd]) {
            return false;
        }
        // An apex off the facet on its normal's side, as far as the longest edge: the four
        // triangles (old and new) must all turn the same way about it, so the quadrilateral
        // a d b c is convex.
        let longest = [(pa, pb), (pa, pc), (pa, pd), (pb, pc), (pb, pd), (pc, pd)]
            .iter()
            .map(|&(x, y)| dot(sub(x, y), sub(x, y)))
            .fold(0.0f64, f64::max)
            .sqrt();
        let n = cross(sub(pb, pa), sub(pc, pa));
        let scale = longest / dot(n, n).sqrt();
        let apex = [0, 1, 2].map(|k| 0.25 * (pa[k] + pb[k] + pc[k] + pd[k]) + n[k] * scale);
        if !(scale.is_finite() && apex.iter().all(|x| x.is_finite())) {
            return false;
        }
        let new1 = [a, d_, c_];
        let new2 = [d_, b, c_];
        let turn = |t: [VertexId; 3]| orient3d(p(t[0]), p(t[1]), p(t[2]), apex);
        let s = turn([a, b, c_]);
        if s == Sign::Zero || turn([b, a, d_]) != s || turn(new1) != s || turn(new2) != s {
            return false;
        }
        // The new boundary faces are the faces of c opposite b and a.
        let at = |u: VertexId| (0..4).find(|&m| v[m] == u).expect("a corner of c");
        let (ka, kb) = (at(a), at(b));
        self.ct.set_tag(c, OUTSIDE);
        self.ct.unprotect(FacetRef::new(c, i));
        self.ct.unprotect(FacetRef::new(c, j));
        self.ct.protect(FacetRef::new(c, kb));
        self.ct.protect(FacetRef::new(c, ka));
        index.0.remove(&sorted(t1));
        index.0.remove(&sorted(t2));
        self.faces[f1].v = new1;
        self.faces[f2].v = new2;
        index.0.insert(sorted(new1), f1);
        index.0.insert(sorted(new2), f2);
        true
    }

    /// Splits every element that lies flat inside the domain by a point at its centroid, and
    /// returns how many points went in. Four corners on one circle (a rectangle or any
    /// symmetric trapezoid: the vertical sides of a thin slab, mirror-image Steiner points of a
    /// symmetric part) lie on a whole family of spheres, and the symbolic perturbation that
    /// settles such ties may keep the four as one element of no volume (its volume is at most
    /// 2^-30 of its longest edge cubed; dihedral angles 0° and 180°) whose faces are all
    /// interior, which [`Self::remove_flat_surface_elements`] cannot take out and a solver cannot
    /// use. The centroid lies inside the circle, hence strictly inside every sphere through it:
    /// the element and its neighbours on both sides go into the new point's cavity, and the
    /// new elements join it to faces off the plane. The insertion is the refinement's (its
    /// cavity never crosses a boundary face and must be star-shaped, the element's region only),
    /// and it is refused where one of the new elements would be flat itself (other points in
    /// or just by the plane: splitting there made more flat elements than it took out), and,
    /// in a Delaunay mesh (all but a constrained recovery's), where the mesh would not stay
    /// Delaunay: next to the surface the centroid's conflict region can reach across a
    /// boundary face, where the cavity stops, and a new element on that face can then hold a
    /// vertex of the cavity ([`ConstrainedTriangulation3::insert_if_fine`]; cheese's
    /// meshes failed validation so). A refused centroid leaves the element as it was. New
    /// points get the mean spacing of the element's corners. At most four rounds over the
    /// flat elements left.
    pub fn split_flat_elements(&mut self) -> usize {
        let mut todo = self.flat_elements();
        // A constrained recovery's mesh is not Delaunay next to the faces it flipped in.
        let delaunay = self.history.method != RecoveryMethod3::Constrained
            || self.history.constrained_fallback;
        let mut added = 0;
        for _ in 0..FLAT_SPLIT_ROUNDS {
            let mut next = Vec::new();
            let mut inserted = 0;
            for c in todo {
                match self.split_at_centroid(c, delaunay) {
                    Some(new_cells) => {
                        next.extend_from_slice(new_cells);
                        inserted += 1;
                    }
                    None => next.push(c),
                }
            }
            added += inserted;
            if inserted == 0 {
                break;
            }
            next.sort_unstable();
            next.dedup();
            todo = next;
        }
        added
    }

    /// The flat elements (one parallel scan of the cell slots).
    fn flat_elements(&self) -> Vec<CellId> {
        let tri = self.ct.triangulation();
        (0..tri.num_cell_slots() as u32)
            .into_par_iter()
            .with_min_len(1 << 12)
            .map(CellId)
            .filter(|&c| tri.is_live(c) && self.ct.tag(c) != OUTSIDE && self.is_flat(c))
            .collect()
    }

    /// Puts a point at the centroid of element `c` if it is (still) flat, as
    /// [`Self::split_flat_elements`] says; `keep_delaunay` refuses it where the mesh would not
    /// stay Delaunay. Returns the new cells, or `None` if nothing changed.
    fn split_at_centroid(&mut self, c: CellId, keep_delaunay: bool) -> Option<&[CellId]> {
        // A slot an earlier insertion reused may hold another element.
        if !self.ct.is_live(c) || self.ct.tag(c) == OUTSIDE || !self.is_flat(c) {
            return None;
        }
        let tri = self.ct.triangulation();
        let v = tri.cell(c);
        let corners = [v[0], v[1], v[2], v[3]];
        let p = corners.map(|u| tri.vertex(u));
        let centroid = [0, 1, 2].map(|k| 0.25 * (p[0][k] + p[1][k] + p[2][k] + p[3][k]));
        let spacing = 0.25 * corners.iter().map(|u| self.spacing[u.index()]).sum::<f64>();
        let tag = self.ct.tag(c);
        let accept = |ct: &ConstrainedTriangulation3, cell| ct.tag(cell) == tag;
        // No new element may be flat itself (near other points in or by the plane).
        let fine = |corners| !flat(corners);
        let nv = self
            .ct
            .insert_if_fine(centroid, c, accept, fine, keep_delaunay)
            .ok()??;
        self.set_interior_spacing(nv, spacing);
        Some(self.ct.last_new_cells())
    }

    /// Records the spacing of a vertex just inserted off the surface (by point generation,
    /// refinement or a split), growing the per-vertex arrays to hold it.
    pub fn set_interior_spacing(&mut self, v: VertexId, spacing: f64) {
        if self.spacing.len() <= v.index() {
            self.spacing.resize(v.index() + 1, f64::NAN);
        }
        if self.on_surface.len() <= v.index() {
            self.on_surface.resize(v.index() + 1, false);
        }
        self.spacing[v.index()] = spacing;
    }

    /// Whether finite cell `c` is [`flat`].
    fn is_flat(&self, c: CellId) -> bool {
        let tri = self.ct.triangulation();
        let v = tri.cell(c);
        !v.iter().any(|u| u.is_ghost()) && flat([0, 1, 2, 3].map(|k| tri.vertex(v[k])))
    }

    /// The mesh as flat arrays (see [`MeshArrays3`]).
    pub fn to_arrays(&self) -> MeshArrays3 {
        let tri = self.ct.triangulation();
        let nv = tri.num_vertices();
        // (Slots scanned, and the per-element arrays made, in parallel: this runs after every
        // stage that changes the mesh.)
        let elements: Vec<CellId> = (0..tri.num_cell_slots() as u32)
            .into_par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .map(CellId)
            .filter(|&c| tri.is_live(c) && !tri.is_ghost(c) && self.ct.tag(c) != OUTSIDE)
            .collect();
        let mut used = vec![false; nv];
        for &c in &elements {
            for &v in tri.cell(c) {
                used[v.index()] = true;
            }
        }
        // The used vertices in input order (each vertex has its own input index, so placing
        // them by it sorts).
        let mut by_input = vec![VertexId::GHOST; tri.num_input_points()];
        for v in (0..nv as u32).map(VertexId).filter(|v| used[v.index()]) {
            by_input[tri.input_index(v)] = v;
        }
        let order: Vec<VertexId> = by_input.into_iter().filter(|v| !v.is_ghost()).collect();
        let mut number = vec![u32::MAX; nv];
        for (k, &v) in order.iter().enumerate() {
            number[v.index()] = k as u32;
        }
        let mut out = MeshArrays3 {
            coords: order.par_iter().map(|&v| tri.vertex(v)).collect(),
            point_markers: vec![0; order.len()],
            on_boundary: vec![false; order.len()],
            vertex: order.clone(),
            ..Default::default()
        };
        // Each element's output index, by cell slot, for the neighbours.
        let slots = elements.last().map_or(0, |c| c.index() + 1);
        let mut index = vec![u32::MAX; slots];
        for (k, &c) in elements.iter().enumerate() {
            index[c.index()] = k as u32;
        }
        out.neighbours = elements
            .par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .map(|&c| {
                [0, 1, 2, 3].map(|k| {
                    tri.neighbor(c, k)
                        .and_then(|n| index.get(n.index()).copied())
                        .unwrap_or(u32::MAX)
                })
            })
            .collect();
        out.tets = elements
            .par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .map(|&c| {
                let v = tri.cell(c);
                [0, 1, 2, 3].map(|k| number[v[k].index()])
            })
            .collect();
        out.regions = elements
            .par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .map(|&c| {
                let tag = self.ct.tag(c) as usize;
                self.region_attributes.get(tag).copied().unwrap_or(0.0)
            })
            .collect();
        // The corner opposite each face of the output's boundary, in its one element: a
        // boundary face there is turned to face out of the domain.
        let inside_of: HashMap<[u32; 3], u32> = out
            .tets
            .par_iter()
            .zip(&out.neighbours)
            .with_min_len(PARALLEL_CHUNK)
            .flat_map_iter(|(t, n)| {
                (0..4).filter(|&k| n[k] == u32::MAX).map(move |k| {
                    let mut f = [t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]];
                    f.sort_unstable();
                    (f, t[k])
                })
            })
            .collect();
        let is_element =
            |c: CellId| tri.is_live(c) && !tri.is_ghost(c) && self.ct.tag(c) != OUTSIDE;
        for f in &self.faces {
            let mut t = f.v.map(|v| number[v.index()]);
            if t.contains(&u32::MAX) {
                continue; // a face between two exterior regions
            }
            let mut key = t;
            key.sort_unstable();
            if let Some(&o) = inside_of.get(&key) {
                let p = t.map(|k| out.coords[k as usize]);
                if orient3d(p[0], p[1], p[2], out.coords[o as usize]) == Sign::Positive {
                    t.swap(1, 2);
                }
            } else if !tri.cells_around(&f.v).into_iter().any(is_element) {
                // Its corners are used, but it has no element on either side (between a
                // hole and the outside): it bounds nothing.
                continue;
            }
            out.faces.push(t);
            out.face_markers.push(f.marker);
            out.face_facets.push(f.facet);
            for k in t {
                out.on_boundary[k as usize] = true;
                if out.point_markers[k as usize] == 0 {
                    out.point_markers[k as usize] = f.marker;
                }
            }
        }
        for (k, &v) in order.iter().enumerate() {
            if self.on_surface.get(v.index()).copied().unwrap_or(false) {
                out.on_boundary[k] = true;
            }
            let i = tri.input_index(v);
            if let Some(&m) = self.point_markers.get(i) {
                if m != 0 {
                    out.point_markers[k] = m;
                }
            }
        }
        out
    }
}
