//! [`SpacingField3`]: how far apart points should be anywhere in a 3D domain (R10, R11).
//!
//! The 3D twin of [`crate::SpacingField`], with the same design so that 3D point generation
//! reads the spacing exactly as 2D does:
//! - From the boundary (the paper's default): the spacing interpolated linearly from the
//!   tetrahedron's nodes, whose values come from the surface point spacing.
//! - From a background mesh ([`BackgroundMesh3`]): a separate coarse tetrahedral mesh whose
//!   nodes carry spacing values, interpolated barycentrically (R11); outside it, the value at
//!   the nearest point of the mesh.
//! - From a solution ([`BackgroundMesh3::from_solution`]): a previous mesh's field (pressure,
//!   Mach number) turned into spacing by the size of its gradient: mesh adaptation.
//! - Analytic [`Source3`]s (points and segments), combined by taking the smallest spacing.
//!
//! A query point is located through a bucket grid (about one cell per tetrahedron) in which
//! every tetrahedron is listed in the cells its bounding box overlaps: the tetrahedron
//! containing the point is listed in the point's own cell. Outside the mesh (beyond its hull
//! or in a hole), the mesh's boundary faces, listed in a second grid the same way, are
//! searched in shells of cells around the point until no unsearched cell can hold a face
//! nearer than the best found, so the nearest point is exact, not a guess.
//!
//! Errors are [`SpacingError3`], whose messages name the node or tetrahedron (0-based), as
//! the 2D [`crate::SpacingError`] names triangles. Adaptation takes the same [`Adaptation`]
//! parameters as 2D.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::Adaptation;

/// Why a 3D spacing field could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpacingError3 {
    /// Arrays of different lengths.
    #[error("{0}")]
    Lengths(String),
    /// A tetrahedron names a node that does not exist.
    #[error("tetrahedron {tetrahedron}: node {node} does not exist ({n_nodes} nodes)")]
    BadNode {
        /// 0-based tetrahedron.
        tetrahedron: usize,
        /// The node index.
        node: u32,
        /// Number of nodes.
        n_nodes: usize,
    },
    /// A tetrahedron has zero volume (its nodes are coplanar, exactly).
    #[error("tetrahedron {0} has zero volume")]
    Degenerate(usize),
    /// A node's coordinate or value is not finite, or a spacing is not positive.
    #[error("node {node}: {what}")]
    BadValue {
        /// 0-based node.
        node: usize,
        /// What is wrong.
        what: String,
    },
    /// Adaptation bounds are not 0 < min ≤ max, or the growth is not finite and ≥ 0.
    #[error(
        "adaptation needs 0 < min spacing ≤ max spacing and a growth ≥ 0 \
         (got {min:?}, {max:?}, growth {growth:?})"
    )]
    Bounds {
        /// Smallest spacing.
        min: f64,
        /// Largest spacing.
        max: f64,
        /// Growth per unit distance.
        growth: f64,
    },
    /// The mesh has no tetrahedron.
    #[error("the background mesh has no tetrahedron")]
    Empty,
}

type P = [f64; 3];

pub(crate) fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: P, b: P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn dist(a: P, b: P) -> f64 {
    let d = sub(a, b);
    dot(d, d).sqrt()
}

/// The point of segment `ab` nearest to `p`.
pub(crate) fn nearest_on_segment(p: P, a: P, b: P) -> P {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]]
}

/// The point of triangle `abc` nearest to `p`: the projection onto its plane when that falls
/// inside, else the nearest point of its edges.
pub(crate) fn nearest_on_triangle(p: P, [a, b, c]: [P; 3]) -> P {
    let n = cross(sub(b, a), sub(c, a));
    let nn = dot(n, n);
    if nn > 0.0 {
        let q = {
            let s = dot(sub(p, a), n) / nn;
            [p[0] - s * n[0], p[1] - s * n[1], p[2] - s * n[2]]
        };
        // Inside when q is on the inner side of all three edges.
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(u, v)| dot(cross(sub(v, u), sub(q, u)), n) >= 0.0);
        if inside {
            return q;
        }
    }
    [(a, b), (b, c), (c, a)]
        .iter()
        .map(|&(u, v)| nearest_on_segment(p, u, v))
        .min_by(|&x, &y| dist(p, x).total_cmp(&dist(p, y)))
        .expect("a triangle has edges")
}

/// The bounding box of some points.
fn bounding_box(points: &[P]) -> (P, P) {
    let mut b = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for ((lo, hi), &c) in b.0.iter_mut().zip(b.1.iter_mut()).zip(p) {
            *lo = lo.min(c);
            *hi = hi.max(c);
        }
    }
    b
}

/// The distance from `p` to the box `(lo, hi)`.
fn box_distance((lo, hi): &(P, P), p: P) -> f64 {
    (0..3)
        .map(|k| {
            let d = (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0);
            d * d
        })
        .sum::<f64>()
        .sqrt()
}

/// Items registered in the cells of a grid: cell `c` holds `items[start[c]..start[c + 1]]`.
#[derive(Clone, Debug, Default)]
struct Buckets {
    start: Vec<u32>,
    items: Vec<u32>,
}

/// A tetrahedral mesh whose nodes carry spacing values, with bucket grids to find the
/// tetrahedron containing a point and, outside the mesh, its nearest boundary faces.
#[derive(Clone, Debug)]
pub struct BackgroundMesh3 {
    points: Vec<P>,
    tetrahedra: Vec<[u32; 4]>,
    spacing: Vec<f64>,
    lo: P,
    hi: P,
    inv: P,
    dims: [usize; 3],
    /// Tetrahedra by the cells their bounding boxes overlap.
    cells: Buckets,
    /// The boundary faces (in no other tetrahedron): the tetrahedron and its corners.
    faces: Vec<(u32, [u32; 3])>,
    /// Boundary faces by the cells their bounding boxes overlap.
    face_cells: Buckets,
}

impl BackgroundMesh3 {
    /// The same mesh in units `2^exponent` times larger: coordinates and spacing values
    /// scaled (exactly, for `|exponent|` up to 1000 and ordinary values), the search grids kept.
    pub fn scaled(&self, exponent: i32) -> Self {
        let f = 2f64.powi(exponent);
        BackgroundMesh3 {
            points: self.points.iter().map(|p| p.map(|x| x * f)).collect(),
            spacing: self.spacing.iter().map(|h| h * f).collect(),
            lo: self.lo.map(|x| x * f),
            hi: self.hi.map(|x| x * f),
            inv: self.inv.map(|x| x / f),
            ..self.clone()
        }
    }

    /// Checks the mesh and builds its search grid. Tetrahedra may be oriented either way.
    ///
    /// # Errors
    /// Mismatched lengths, bad indices, tetrahedra of zero volume (exact test), non-finite
    /// coordinates, spacing values that are not positive and finite; each names the node or
    /// tetrahedron (0-based).
    pub fn new(
        points: Vec<P>,
        tetrahedra: Vec<[u32; 4]>,
        spacing: Vec<f64>,
    ) -> Result<Self, SpacingError3> {
        if spacing.len() != points.len() {
            return Err(SpacingError3::Lengths(format!(
                "{} nodes but {} spacing values",
                points.len(),
                spacing.len()
            )));
        }
        for (i, (p, &h)) in points.iter().zip(&spacing).enumerate() {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(SpacingError3::BadValue {
                    node: i,
                    what: "coordinate is not finite".into(),
                });
            }
            if !(h > 0.0 && h.is_finite()) {
                return Err(SpacingError3::BadValue {
                    node: i,
                    what: format!("spacing {h} is not positive and finite"),
                });
            }
        }
        if tetrahedra.is_empty() {
            return Err(SpacingError3::Empty);
        }
        for (k, t) in tetrahedra.iter().enumerate() {
            if let Some(&node) = t.iter().find(|&&v| v as usize >= points.len()) {
                return Err(SpacingError3::BadNode {
                    tetrahedron: k,
                    node,
                    n_nodes: points.len(),
                });
            }
            let p = t.map(|v| points[v as usize]);
            if delmesh_predicates::orient3d(p[0], p[1], p[2], p[3])
                == delmesh_predicates::Sign::Zero
            {
                return Err(SpacingError3::Degenerate(k));
            }
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for t in &tetrahedra {
            for &v in t {
                let p = points[v as usize];
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        // Cubic cells, about one per tetrahedron.
        let extent = [0, 1, 2].map(|k| hi[k] - lo[k]);
        let cell = (extent[0] * extent[1] * extent[2] / tetrahedra.len() as f64).cbrt();
        let dims = extent.map(|e| ((e / cell).ceil() as usize).clamp(1, 1024));
        let inv = [0, 1, 2].map(|k| dims[k] as f64 / extent[k]);
        let mut mesh = BackgroundMesh3 {
            points,
            tetrahedra,
            spacing,
            lo,
            hi,
            inv,
            dims,
            cells: Buckets::default(),
            faces: Vec::new(),
            face_cells: Buckets::default(),
        };
        let boxes: Vec<(P, P)> = mesh
            .tetrahedra
            .iter()
            .map(|t| bounding_box(&t.map(|v| mesh.points[v as usize])))
            .collect();
        mesh.cells = mesh.buckets(&boxes);
        // Boundary faces: those of exactly one tetrahedron.
        let mut keyed: Vec<([u32; 3], u32, [u32; 3])> = Vec::with_capacity(4 * boxes.len());
        for (k, t) in mesh.tetrahedra.iter().enumerate() {
            for skip in 0..4 {
                let face = [t[(skip + 1) % 4], t[(skip + 2) % 4], t[(skip + 3) % 4]];
                let mut key = face;
                key.sort_unstable();
                keyed.push((key, k as u32, face));
            }
        }
        keyed.sort_unstable();
        let mut i = 0;
        while i < keyed.len() {
            let j = (i..keyed.len())
                .find(|&j| keyed[j].0 != keyed[i].0)
                .unwrap_or(keyed.len());
            if j == i + 1 {
                mesh.faces.push((keyed[i].1, keyed[i].2));
            }
            i = j;
        }
        let boxes: Vec<(P, P)> = mesh
            .faces
            .iter()
            .map(|(_, f)| bounding_box(&f.map(|v| mesh.points[v as usize])))
            .collect();
        mesh.face_cells = mesh.buckets(&boxes);
        Ok(mesh)
    }

    /// Registers item `k` in every grid cell its box `boxes[k]` overlaps.
    fn buckets(&self, boxes: &[(P, P)]) -> Buckets {
        let ncell = self.dims[0] * self.dims[1] * self.dims[2];
        let mut start = vec![0u32; ncell + 1];
        for b in boxes {
            self.for_box_cells(b, |c| start[c + 1] += 1);
        }
        for c in 0..ncell {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; start[ncell] as usize];
        for (k, b) in boxes.iter().enumerate() {
            self.for_box_cells(b, |c| {
                items[fill[c] as usize] = k as u32;
                fill[c] += 1;
            });
        }
        Buckets { start, items }
    }

    /// A background mesh from a solution field (mesh adaptation): the field's gradient is
    /// computed on each tetrahedron (the gradient of its linear interpolant) and averaged to
    /// the nodes weighted by volume; the spacing is `max_spacing` where it vanishes and
    /// `min_spacing` where it is largest, in between `h = max / (1 + (max/min − 1)·|∇f|/max|∇f|)`
    /// (inversely proportional to the gradient where it is large), as in 2D. Then the spacing
    /// is limited so that it grows by at most `growth` per unit of distance along the mesh's
    /// edges: `h_i ≤ h_j + growth·|x_i − x_j|` holds exactly on every edge (a shortest-path
    /// pass, where 2D does a few sweeps).
    ///
    /// # Errors
    /// As [`BackgroundMesh3::new`], bad bounds, or a non-finite field value (naming the node).
    pub fn from_solution(
        points: Vec<P>,
        tetrahedra: Vec<[u32; 4]>,
        field: &[f64],
        adaptation: &Adaptation,
    ) -> Result<Self, SpacingError3> {
        let (hmin, hmax, growth) = (
            adaptation.min_spacing,
            adaptation.max_spacing,
            adaptation.growth,
        );
        if !(hmin > 0.0 && hmin <= hmax && hmax.is_finite() && growth >= 0.0 && growth.is_finite())
        {
            return Err(SpacingError3::Bounds {
                min: hmin,
                max: hmax,
                growth,
            });
        }
        if field.len() != points.len() {
            return Err(SpacingError3::Lengths(format!(
                "{} nodes but {} field values",
                points.len(),
                field.len()
            )));
        }
        if let Some(i) = field.iter().position(|f| !f.is_finite()) {
            return Err(SpacingError3::BadValue {
                node: i,
                what: format!("field value {} is not finite", field[i]),
            });
        }
        // Check the mesh first (with a placeholder spacing).
        let mut mesh = BackgroundMesh3::new(points, tetrahedra, vec![hmax; field.len()])?;
        let n = mesh.points.len();
        let mut grad = vec![0.0f64; n];
        let mut weight = vec![0.0f64; n];
        for t in &mesh.tetrahedra {
            let p = t.map(|v| mesh.points[v as usize]);
            let f = t.map(|v| field[v as usize]);
            let e = [sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0])];
            let det = dot(e[0], cross(e[1], e[2]));
            // ∇f solves e_i · ∇f = f_i − f_0: Cramer's rule with the rows' cross products.
            let cols = [cross(e[1], e[2]), cross(e[2], e[0]), cross(e[0], e[1])];
            let df = [f[1] - f[0], f[2] - f[0], f[3] - f[0]];
            let g = [0, 1, 2].map(|k| (0..3).map(|i| df[i] * cols[i][k]).sum::<f64>() / det);
            let volume = det.abs() / 6.0;
            let size = dot(g, g).sqrt();
            for &v in t {
                grad[v as usize] += volume * size;
                weight[v as usize] += volume;
            }
        }
        for (g, w) in grad.iter_mut().zip(&weight) {
            if *w > 0.0 {
                *g /= w;
            }
        }
        let gmax = grad.iter().copied().fold(0.0, f64::max);
        let mut h: Vec<f64> = grad
            .iter()
            .map(|&g| {
                if gmax > 0.0 {
                    (hmax / (1.0 + (hmax / hmin - 1.0) * g / gmax)).clamp(hmin, hmax)
                } else {
                    hmax
                }
            })
            .collect();
        mesh.limit_growth(&mut h, growth);
        mesh.spacing = h;
        Ok(mesh)
    }

    /// Lowers `h` to the largest values with `h_i ≤ h_j + growth·|x_i − x_j|` along every edge:
    /// Dijkstra's algorithm from every node at once, each starting at its own value.
    fn limit_growth(&self, h: &mut [f64], growth: f64) {
        let n = self.points.len();
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(12 * self.tetrahedra.len());
        for t in &self.tetrahedra {
            for i in 0..4 {
                for j in i + 1..4 {
                    edges.push((t[i], t[j]));
                    edges.push((t[j], t[i]));
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let mut start = vec![0usize; n + 1];
        for &(a, _) in &edges {
            start[a as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }

        /// A node and its tentative spacing, smallest first in the heap.
        struct Entry(f64, u32);
        impl PartialEq for Entry {
            fn eq(&self, other: &Self) -> bool {
                self.cmp(other) == Ordering::Equal
            }
        }
        impl Eq for Entry {}
        impl PartialOrd for Entry {
            fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
                Some(self.cmp(other))
            }
        }
        impl Ord for Entry {
            fn cmp(&self, other: &Self) -> Ordering {
                other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
            }
        }

        let mut heap: BinaryHeap<Entry> = (0..n as u32).map(|v| Entry(h[v as usize], v)).collect();
        let mut done = vec![false; n];
        while let Some(Entry(hv, v)) = heap.pop() {
            let v = v as usize;
            if done[v] || hv > h[v] {
                continue;
            }
            done[v] = true;
            for &(_, w) in &edges[start[v]..start[v + 1]] {
                let w = w as usize;
                let limit = hv + growth * dist(self.points[v], self.points[w]);
                if limit < h[w] {
                    h[w] = limit;
                    heap.push(Entry(limit, w as u32));
                }
            }
        }
    }

    /// The nodes.
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// The tetrahedra.
    pub fn tetrahedra(&self) -> &[[u32; 4]] {
        &self.tetrahedra
    }

    /// The spacing at each node.
    pub fn node_spacing(&self) -> &[f64] {
        &self.spacing
    }

    /// The grid cell of coordinate `x` along axis `k` (clamped into the grid).
    fn cell(&self, x: f64, k: usize) -> usize {
        let c = (x - self.lo[k]) * self.inv[k];
        if c <= 0.0 {
            0
        } else {
            (c as usize).min(self.dims[k] - 1)
        }
    }

    fn cell_index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// Calls `f` with every grid cell that the box `(lo, hi)` overlaps.
    fn for_box_cells(&self, (lo, hi): &(P, P), mut f: impl FnMut(usize)) {
        let range = [0, 1, 2].map(|a| (self.cell(lo[a], a), self.cell(hi[a], a)));
        for z in range[2].0..=range[2].1 {
            for y in range[1].0..=range[1].1 {
                for x in range[0].0..=range[0].1 {
                    f(self.cell_index([x, y, z]));
                }
            }
        }
    }

    /// Barycentric coordinates of `p` in tetrahedron `k`.
    fn barycentric(&self, k: usize, p: P) -> [f64; 4] {
        let t = self.tetrahedra[k].map(|v| self.points[v as usize]);
        let e = [sub(t[1], t[0]), sub(t[2], t[0]), sub(t[3], t[0])];
        let q = sub(p, t[0]);
        let det = dot(e[0], cross(e[1], e[2]));
        let l1 = dot(q, cross(e[1], e[2])) / det;
        let l2 = dot(e[0], cross(q, e[2])) / det;
        let l3 = dot(e[0], cross(e[1], q)) / det;
        [1.0 - l1 - l2 - l3, l1, l2, l3]
    }

    /// The interpolated value in tetrahedron `k` at barycentric coordinates `l` (negative
    /// coordinates from rounding are clamped, so nothing is extrapolated).
    fn value(&self, k: usize, l: [f64; 4]) -> f64 {
        let l = l.map(|x| x.max(0.0));
        let sum: f64 = l.iter().sum();
        let t = self.tetrahedra[k];
        (0..4)
            .map(|i| l[i] * self.spacing[t[i] as usize])
            .sum::<f64>()
            / sum
    }

    /// A lower bound on the distance from `p` to any grid cell outside the block of cells
    /// `lo..=hi` (`None`: the block is the whole grid).
    fn outside_block_distance(&self, p: P, lo: [usize; 3], hi: [usize; 3]) -> Option<f64> {
        let mut best: Option<f64> = None;
        for a in 0..3 {
            let width = 1.0 / self.inv[a];
            let sides = [
                (lo[a] > 0).then(|| (self.lo[a], self.lo[a] + lo[a] as f64 * width)),
                (hi[a] + 1 < self.dims[a])
                    .then(|| (self.lo[a] + (hi[a] + 1) as f64 * width, self.hi[a])),
            ];
            for (from, to) in sides.into_iter().flatten() {
                // The distance from p to the grid's box cut down to [from, to] along axis a.
                let d2: f64 = (0..3)
                    .map(|k| {
                        let (l, h) = if k == a {
                            (from, to)
                        } else {
                            (self.lo[k], self.hi[k])
                        };
                        let d = (l - p[k]).max(p[k] - h).max(0.0);
                        d * d
                    })
                    .sum();
                let d = d2.sqrt();
                best = Some(best.map_or(d, |b: f64| b.min(d)));
            }
        }
        best
    }

    /// Calls `f` with the index of every grid cell at Chebyshev distance `ring` from cell `c`
    /// (`ring = 0`: `c` itself), clipped to the grid.
    fn for_shell(&self, c: [usize; 3], ring: usize, mut f: impl FnMut(usize)) {
        let lo = c.map(|x| x.saturating_sub(ring));
        let hi = [0, 1, 2].map(|k| (c[k] + ring).min(self.dims[k] - 1));
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                if z.abs_diff(c[2]) == ring || y.abs_diff(c[1]) == ring {
                    for x in lo[0]..=hi[0] {
                        f(self.cell_index([x, y, z]));
                    }
                } else {
                    // Inside the shell's y-z extent: only its two x ends are on the shell.
                    for x in [c[0].checked_sub(ring), Some(c[0] + ring)]
                        .into_iter()
                        .flatten()
                        .filter(|&x| x < self.dims[0])
                    {
                        f(self.cell_index([x, y, z]));
                    }
                }
            }
        }
    }

    /// The distance from `p` to the box of grid cell `cell` (a lower bound for everything
    /// registered there).
    fn cell_distance(&self, p: P, cell: usize) -> f64 {
        let idx = [
            cell % self.dims[0],
            (cell / self.dims[0]) % self.dims[1],
            cell / (self.dims[0] * self.dims[1]),
        ];
        (0..3)
            .map(|k| {
                let w = 1.0 / self.inv[k];
                let (l, h) = (
                    self.lo[k] + idx[k] as f64 * w,
                    self.lo[k] + (idx[k] + 1) as f64 * w,
                );
                let d = (l - p[k]).max(p[k] - h).max(0.0);
                d * d
            })
            .sum::<f64>()
            .sqrt()
    }

    /// The items registered in grid cell `cell`.
    fn cell_items(buckets: &Buckets, cell: usize) -> &[u32] {
        &buckets.items[buckets.start[cell] as usize..buckets.start[cell + 1] as usize]
    }

    /// The spacing at `p`: barycentric interpolation in the tetrahedron containing it; outside
    /// the mesh, the value at the nearest point of the mesh.
    pub fn spacing_at(&self, p: P) -> f64 {
        let c = [0, 1, 2].map(|k| self.cell(p[k], k));
        // A tetrahedron containing p overlaps p's cell, so p is inside the mesh if and only if
        // one of the tetrahedra listed there contains it (up to rounding on shared faces).
        for &k in Self::cell_items(&self.cells, self.cell_index(c)) {
            let l = self.barycentric(k as usize, p);
            if l.iter().all(|&x| x >= 0.0) {
                return self.value(k as usize, l);
            }
        }
        // Outside: search shells of cells outwards for the nearest boundary face, until no cell
        // outside the searched block can hold anything nearer.
        let mut best = (f64::INFINITY, 0usize, [0.25; 4]); // (distance, tetrahedron, barycentric)
        let max_ring = self.dims.iter().copied().max().unwrap_or(1);
        for ring in 0..=max_ring {
            self.for_shell(c, ring, |cell| {
                if self.cell_distance(p, cell) >= best.0 {
                    return;
                }
                for &f in Self::cell_items(&self.face_cells, cell) {
                    let (k, face) = self.faces[f as usize];
                    let corners = face.map(|v| self.points[v as usize]);
                    if box_distance(&bounding_box(&corners), p) >= best.0 {
                        continue;
                    }
                    let q = nearest_on_triangle(p, corners);
                    let d = dist(p, q);
                    if d < best.0 {
                        best = (d, k as usize, self.barycentric(k as usize, q));
                    }
                }
            });
            let lo = c.map(|x| x.saturating_sub(ring));
            let hi = [0, 1, 2].map(|k| (c[k] + ring).min(self.dims[k] - 1));
            match self.outside_block_distance(p, lo, hi) {
                None => break,
                Some(d) if d >= best.0 => break,
                Some(_) => {}
            }
        }
        if best.0.is_finite() {
            self.value(best.1, best.2)
        } else {
            self.spacing.iter().copied().fold(f64::INFINITY, f64::min)
        }
    }
}

/// An analytic source of fine spacing in 3D: `h0` within `radius` of a point or a segment,
/// growing linearly at `growth` per unit distance beyond.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Source3 {
    /// The point, or the first end of the segment.
    pub a: P,
    /// The second end of the segment (equal to `a` for a point source).
    pub b: P,
    /// Spacing at the source.
    pub h0: f64,
    /// Radius within which the spacing is `h0`.
    pub radius: f64,
    /// Growth of the spacing per unit distance beyond the radius.
    pub growth: f64,
}

impl Source3 {
    /// The same source in units `2^exponent` times larger (growth is a ratio: unchanged).
    pub fn scaled(&self, exponent: i32) -> Self {
        let f = 2f64.powi(exponent);
        Source3 {
            a: self.a.map(|x| x * f),
            b: self.b.map(|x| x * f),
            h0: self.h0 * f,
            radius: self.radius * f,
            growth: self.growth,
        }
    }

    /// The spacing this source asks for at `p`.
    pub fn spacing(&self, p: P) -> f64 {
        let d = crate::distance::point_segment3(p, self.a, self.b);
        self.h0 + self.growth * (d - self.radius).max(0.0)
    }

    /// The finest spacing this source asks for anywhere on the segment `a b`.
    pub fn finest_on_segment(&self, a: P, b: P) -> f64 {
        let d = crate::distance::segment_segment3(self.a, self.b, a, b);
        self.h0 + self.growth * (d - self.radius).max(0.0)
    }

    /// The finest spacing this source asks for anywhere on the triangle `t`.
    pub fn finest_on_triangle(&self, t: [P; 3]) -> f64 {
        let d = crate::distance::segment_triangle3(self.a, self.b, t);
        self.h0 + self.growth * (d - self.radius).max(0.0)
    }

    /// The finest spacing this source asks for anywhere in the tetrahedron `t`.
    pub fn finest_in(&self, t: [P; 4]) -> f64 {
        let d = crate::distance::segment_tetrahedron(self.a, self.b, t);
        self.h0 + self.growth * (d - self.radius).max(0.0)
    }
}

/// Where the spacing comes from.
#[derive(Clone, Debug)]
enum Base3 {
    Boundary,
    Background(Box<BackgroundMesh3>),
}

/// The spacing field of 3D point generation: a base (the boundary's spacing interpolated from
/// the tetrahedron's nodes, or a background mesh) refined by sources.
#[derive(Clone, Debug)]
pub struct SpacingField3 {
    base: Base3,
    sources: Vec<Source3>,
}

impl SpacingField3 {
    /// The paper's default: spacing interpolated from the tetrahedron's nodes.
    pub fn boundary() -> Self {
        SpacingField3 {
            base: Base3::Boundary,
            sources: Vec::new(),
        }
    }

    /// Spacing from a background mesh.
    pub fn background(mesh: BackgroundMesh3) -> Self {
        SpacingField3 {
            base: Base3::Background(Box::new(mesh)),
            sources: Vec::new(),
        }
    }

    /// Adds a source: the spacing becomes the smaller of the field's and the source's.
    pub fn with_source(mut self, source: Source3) -> Self {
        self.sources.push(source);
        self
    }

    /// Whether the field uses the values interpolated from the tetrahedron's nodes.
    pub fn uses_node_values(&self) -> bool {
        matches!(self.base, Base3::Boundary)
    }

    /// The finest spacing the sources ask for anywhere in the tetrahedron `t` (infinite
    /// without sources).
    pub fn finest_source_in(&self, t: [P; 4]) -> f64 {
        self.sources
            .iter()
            .fold(f64::INFINITY, |h, s| h.min(s.finest_in(t)))
    }

    /// The spacing at `p`; `from_nodes` is the value interpolated from the tetrahedron's nodes.
    pub fn spacing(&self, p: P, from_nodes: f64) -> f64 {
        let base = match &self.base {
            Base3::Boundary => from_nodes,
            Base3::Background(mesh) => mesh.spacing_at(p),
        };
        self.sources.iter().fold(base, |h, s| h.min(s.spacing(p)))
    }
}
