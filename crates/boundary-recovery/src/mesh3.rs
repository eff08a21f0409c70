//! What a [`Mesh3`] reports: its elements (the tetrahedra inside the domain), their volume, and
//! flat arrays for writers and for smoothing.

use std::collections::HashMap;

use crate::classify::OUTSIDE;
use crate::recovery3::{BoundaryFace, Mesh3};
use delmesh_delaunay_core::{CellId, TriangulationError, VertexId};

/// Where each boundary face of a [`Mesh3`] is in [`Mesh3::faces`], by its sorted corners: for
/// [`Mesh3::split_edge`], which keeps it up to date.
#[derive(Clone, Debug, Default)]
pub struct FaceIndex(HashMap<[VertexId; 3], usize>);

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
    /// Boundary triangles, oriented like the input surface triangles they subdivide.
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

    /// The mesh as flat arrays (see [`MeshArrays3`]).
    pub fn to_arrays(&self) -> MeshArrays3 {
        let tri = self.ct.triangulation();
        let nv = tri.num_vertices();
        let mut used = vec![false; nv];
        let elements: Vec<CellId> = self.elements().collect();
        for &c in &elements {
            for &v in tri.cell(c) {
                used[v.index()] = true;
            }
        }
        let mut order: Vec<VertexId> = (0..nv as u32)
            .map(VertexId)
            .filter(|v| used[v.index()])
            .collect();
        order.sort_by_key(|&v| tri.input_index(v));
        let mut number = vec![u32::MAX; nv];
        for (k, &v) in order.iter().enumerate() {
            number[v.index()] = k as u32;
        }
        let mut out = MeshArrays3 {
            coords: order.iter().map(|&v| tri.vertex(v)).collect(),
            point_markers: vec![0; order.len()],
            on_boundary: vec![false; order.len()],
            vertex: order.clone(),
            tets: Vec::with_capacity(elements.len()),
            regions: Vec::with_capacity(elements.len()),
            ..Default::default()
        };
        // Each element's output index, by cell slot, for the neighbours.
        let slots = elements.iter().map(|c| c.index() + 1).max().unwrap_or(0);
        let mut index = vec![u32::MAX; slots];
        for (k, &c) in elements.iter().enumerate() {
            index[c.index()] = k as u32;
        }
        out.neighbours = elements
            .iter()
            .map(|&c| {
                [0, 1, 2, 3].map(|k| {
                    tri.neighbor(c, k)
                        .and_then(|n| index.get(n.index()).copied())
                        .unwrap_or(u32::MAX)
                })
            })
            .collect();
        for &c in &elements {
            let v = tri.cell(c);
            out.tets.push([0, 1, 2, 3].map(|k| number[v[k].index()]));
            let tag = self.ct.tag(c) as usize;
            out.regions
                .push(self.region_attributes.get(tag).copied().unwrap_or(0.0));
        }
        for f in &self.faces {
            let t = f.v.map(|v| number[v.index()]);
            if t.contains(&u32::MAX) {
                continue; // a face between two exterior regions
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
