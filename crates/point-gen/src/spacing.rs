//! [`SpacingField`]: how far apart points should be anywhere in the domain (R10, R11).
//!
//! - From the boundary (the paper's default): the spacing interpolated linearly from the
//!   element's nodes, whose values come from the boundary point spacing.
//! - From a background mesh ([`BackgroundMesh2`]): a separate coarse triangle mesh whose nodes
//!   carry spacing values, interpolated barycentrically (R11).
//! - From a solution ([`BackgroundMesh2::from_solution`]): a previous mesh's field (pressure,
//!   Mach number) turned into spacing by its gradient: mesh adaptation.
//! - Analytic [`Source`]s, combined by taking the smallest spacing.

/// Why a spacing field could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpacingError {
    /// Arrays of different lengths.
    #[error("{0}")]
    Lengths(String),
    /// A triangle names a node that does not exist.
    #[error("triangle {triangle}: node {node} does not exist ({n_nodes} nodes)")]
    BadNode {
        /// 0-based triangle.
        triangle: usize,
        /// The node index.
        node: u32,
        /// Number of nodes.
        n_nodes: usize,
    },
    /// A triangle has zero area.
    #[error("triangle {0} has zero area")]
    Degenerate(usize),
    /// A node's coordinate or value is not finite, or a spacing is not positive.
    #[error("node {node}: {what}")]
    BadValue {
        /// 0-based node.
        node: usize,
        /// What is wrong.
        what: String,
    },
    /// Adaptation bounds are not 0 < min ≤ max.
    #[error("adaptation needs 0 < min spacing ≤ max spacing (got {min:?}, {max:?})")]
    Bounds {
        /// Smallest spacing.
        min: f64,
        /// Largest spacing.
        max: f64,
    },
    /// The mesh has no triangle (of nonzero area: those of no area are left out).
    #[error("the background mesh has no triangle of nonzero area")]
    Empty,
}

/// A triangle mesh whose nodes carry spacing values, with a bucket grid to find the triangle
/// containing a point.
#[derive(Clone, Debug)]
pub struct BackgroundMesh2 {
    points: Vec<[f64; 2]>,
    triangles: Vec<[u32; 3]>,
    spacing: Vec<f64>,
    lo: [f64; 2],
    inv: [f64; 2],
    dims: [usize; 2],
    start: Vec<u32>,
    items: Vec<u32>,
}

impl BackgroundMesh2 {
    /// The same mesh in units `2^exponent` times larger: coordinates and spacing values
    /// scaled (exactly, for `|exponent|` up to 1000 and ordinary values), the search grid kept.
    pub fn scaled(&self, exponent: i32) -> Self {
        let f = 2f64.powi(exponent);
        BackgroundMesh2 {
            points: self.points.iter().map(|p| p.map(|x| x * f)).collect(),
            spacing: self.spacing.iter().map(|h| h * f).collect(),
            lo: self.lo.map(|x| x * f),
            inv: self.inv.map(|x| x / f),
            ..self.clone()
        }
    }

    /// Checks the mesh and builds its search grid. Triangles may be oriented either way.
    ///
    /// # Errors
    /// Mismatched lengths, bad indices, zero-area triangles, non-finite coordinates, spacing
    /// values that are not positive and finite.
    pub fn new(
        points: Vec<[f64; 2]>,
        triangles: Vec<[u32; 3]>,
        spacing: Vec<f64>,
    ) -> Result<Self, SpacingError> {
        if spacing.len() != points.len() {
            return Err(SpacingError::Lengths(format!(
                "{} nodes but {} spacing values",
                points.len(),
                spacing.len()
            )));
        }
        for (i, (p, &h)) in points.iter().zip(&spacing).enumerate() {
            if !p[0].is_finite() || !p[1].is_finite() {
                return Err(SpacingError::BadValue {
                    node: i,
                    what: "coordinate is not finite".into(),
                });
            }
            if !(h > 0.0 && h.is_finite()) {
                return Err(SpacingError::BadValue {
                    node: i,
                    what: format!("spacing {h} is not positive and finite"),
                });
            }
        }
        if triangles.is_empty() {
            return Err(SpacingError::Empty);
        }
        for (k, t) in triangles.iter().enumerate() {
            if let Some(&node) = t.iter().find(|&&v| v as usize >= points.len()) {
                return Err(SpacingError::BadNode {
                    triangle: k,
                    node,
                    n_nodes: points.len(),
                });
            }
            let p = t.map(|v| points[v as usize]);
            if delmesh_predicates::orient2d(p[0], p[1], p[2]) == delmesh_predicates::Sign::Zero {
                return Err(SpacingError::Degenerate(k));
            }
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for t in &triangles {
            for &v in t {
                let p = points[v as usize];
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        let side = ((triangles.len() as f64).sqrt().ceil() as usize).clamp(1, 2048);
        let dims = [side, side];
        let inv = [0, 1].map(|k| {
            let w = hi[k] - lo[k];
            if w > 0.0 {
                dims[k] as f64 / w
            } else {
                0.0
            }
        });
        let mut mesh = BackgroundMesh2 {
            points,
            triangles,
            spacing,
            lo,
            inv,
            dims,
            start: Vec::new(),
            items: Vec::new(),
        };
        let ncell = dims[0] * dims[1];
        let mut count = vec![0u32; ncell + 1];
        for k in 0..mesh.triangles.len() {
            mesh.for_cells(k, |c| count[c + 1] += 1);
        }
        for c in 0..ncell {
            count[c + 1] += count[c];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[ncell] as usize];
        for k in 0..mesh.triangles.len() {
            mesh.for_cells(k, |c| {
                items[fill[c] as usize] = k as u32;
                fill[c] += 1;
            });
        }
        mesh.start = count;
        mesh.items = items;
        Ok(mesh)
    }

    /// A background mesh from a solution field (mesh adaptation): spacing is `max_spacing`
    /// where the field's gradient vanishes and `min_spacing` where it is largest, in between
    /// `h = max / (1 + (max/min − 1)·|∇f|/max|∇f|)` (so the spacing is inversely proportional
    /// to the gradient where it is large), then limited so neighbouring nodes' spacings grow by
    /// at most `growth` per unit of distance relative to the spacing.
    ///
    /// # Errors
    /// As [`BackgroundMesh2::new`], bad bounds, or a non-finite field value.
    pub fn from_solution(
        points: Vec<[f64; 2]>,
        triangles: Vec<[u32; 3]>,
        field: &[f64],
        adaptation: &Adaptation,
    ) -> Result<Self, SpacingError> {
        let (hmin, hmax) = (adaptation.min_spacing, adaptation.max_spacing);
        if !(hmin > 0.0 && hmin <= hmax && hmax.is_finite()) {
            return Err(SpacingError::Bounds {
                min: hmin,
                max: hmax,
            });
        }
        if field.len() != points.len() {
            return Err(SpacingError::Lengths(format!(
                "{} nodes but {} field values",
                points.len(),
                field.len()
            )));
        }
        if let Some(i) = field.iter().position(|f| !f.is_finite()) {
            return Err(SpacingError::BadValue {
                node: i,
                what: "field value is not finite".into(),
            });
        }
        // Check the mesh first (with a placeholder spacing).
        let checked = BackgroundMesh2::new(points, triangles, vec![hmax; field.len()])?;
        let n = checked.points.len();
        let mut grad = vec![0.0f64; n];
        let mut weight = vec![0.0f64; n];
        for t in &checked.triangles {
            let p = t.map(|v| checked.points[v as usize]);
            let f = t.map(|v| field[v as usize]);
            let (x1, y1) = (p[1][0] - p[0][0], p[1][1] - p[0][1]);
            let (x2, y2) = (p[2][0] - p[0][0], p[2][1] - p[0][1]);
            let det = x1 * y2 - x2 * y1;
            let (df1, df2) = (f[1] - f[0], f[2] - f[0]);
            let gx = (df1 * y2 - df2 * y1) / det;
            let gy = (x1 * df2 - x2 * df1) / det;
            let area = 0.5 * det.abs();
            for &v in t {
                grad[v as usize] += area * gx.hypot(gy);
                weight[v as usize] += area;
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
        // Gradation: h_i ≤ h_j + growth·|x_i − x_j| along edges, a few sweeps.
        for _ in 0..8 {
            let mut changed = false;
            for t in &checked.triangles {
                for k in 0..3 {
                    let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                    let d = (checked.points[a][0] - checked.points[b][0])
                        .hypot(checked.points[a][1] - checked.points[b][1]);
                    let limit = adaptation.growth * d;
                    if h[a] > h[b] + limit {
                        h[a] = h[b] + limit;
                        changed = true;
                    }
                    if h[b] > h[a] + limit {
                        h[b] = h[a] + limit;
                        changed = true;
                    }
                }
            }
            if !changed {
                break;
            }
        }
        let mut mesh = checked;
        mesh.spacing = h;
        Ok(mesh)
    }

    /// The nodes.
    pub fn points(&self) -> &[[f64; 2]] {
        &self.points
    }

    /// The triangles.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The spacing at each node.
    pub fn node_spacing(&self) -> &[f64] {
        &self.spacing
    }

    fn cell(&self, x: f64, k: usize) -> usize {
        let c = (x - self.lo[k]) * self.inv[k];
        if c <= 0.0 {
            0
        } else {
            (c as usize).min(self.dims[k] - 1)
        }
    }

    fn for_cells(&self, k: usize, mut f: impl FnMut(usize)) {
        let p = self.triangles[k].map(|v| self.points[v as usize]);
        let xs = [p[0][0], p[1][0], p[2][0]];
        let ys = [p[0][1], p[1][1], p[2][1]];
        let (x0, x1) = (
            self.cell(xs.iter().copied().fold(f64::INFINITY, f64::min), 0),
            self.cell(xs.iter().copied().fold(f64::NEG_INFINITY, f64::max), 0),
        );
        let (y0, y1) = (
            self.cell(ys.iter().copied().fold(f64::INFINITY, f64::min), 1),
            self.cell(ys.iter().copied().fold(f64::NEG_INFINITY, f64::max), 1),
        );
        for y in y0..=y1 {
            for x in x0..=x1 {
                f(y * self.dims[0] + x);
            }
        }
    }

    /// Barycentric coordinates of `p` in triangle `k`.
    fn barycentric(&self, k: usize, p: [f64; 2]) -> [f64; 3] {
        let t = self.triangles[k].map(|v| self.points[v as usize]);
        let det =
            (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1]);
        let l1 =
            ((p[0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (p[1] - t[0][1])) / det;
        let l2 =
            ((t[1][0] - t[0][0]) * (p[1] - t[0][1]) - (p[0] - t[0][0]) * (t[1][1] - t[0][1])) / det;
        [1.0 - l1 - l2, l1, l2]
    }

    /// The point of triangle `k`'s boundary nearest to `p`, and its distance.
    fn nearest_on_boundary(&self, k: usize, p: [f64; 2]) -> (f64, [f64; 2]) {
        let t = self.triangles[k].map(|v| self.points[v as usize]);
        let mut best = (f64::INFINITY, t[0]);
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let s =
                (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            let q = [a[0] + s * dx, a[1] + s * dy];
            let d = (p[0] - q[0]).hypot(p[1] - q[1]);
            if d < best.0 {
                best = (d, q);
            }
        }
        best
    }

    fn value(&self, k: usize, l: [f64; 3]) -> f64 {
        let t = self.triangles[k];
        l[0] * self.spacing[t[0] as usize]
            + l[1] * self.spacing[t[1] as usize]
            + l[2] * self.spacing[t[2] as usize]
    }

    /// Whether `p` lies in a triangle of the mesh (or on one, up to rounding): where it does
    /// not, [`Self::spacing_at`] takes the value of the nearest point of the mesh.
    pub fn covers(&self, p: [f64; 2]) -> bool {
        let inside_grid = (0..2).all(|k| {
            let c = (p[k] - self.lo[k]) * self.inv[k];
            c >= 0.0 && c <= self.dims[k] as f64
        });
        if !inside_grid {
            return false;
        }
        // Every triangle whose box holds `p` is listed in `p`'s cell.
        let c = self.cell(p[1], 1) * self.dims[0] + self.cell(p[0], 0);
        self.items[self.start[c] as usize..self.start[c + 1] as usize]
            .iter()
            .any(|&k| {
                let l = self.barycentric(k as usize, p);
                l[0].min(l[1]).min(l[2]) >= -1e-9
            })
    }

    /// The spacing at `p`: barycentric interpolation in the triangle containing it; outside
    /// the mesh, the value at the nearest point of the nearest triangle found near `p`.
    pub fn spacing_at(&self, p: [f64; 2]) -> f64 {
        let (cx, cy) = (self.cell(p[0], 0), self.cell(p[1], 1));
        let mut best = (f64::INFINITY, 0usize, [1.0 / 3.0; 3]); // (distance, triangle, barycentric)
                                                                // Search rings of cells outwards until a containing triangle is found or the ring
                                                                // cannot hold anything closer than the best so far.
        let max_ring = self.dims[0].max(self.dims[1]);
        for ring in 0..=max_ring {
            let (x0, x1) = (cx.saturating_sub(ring), (cx + ring).min(self.dims[0] - 1));
            let (y0, y1) = (cy.saturating_sub(ring), (cy + ring).min(self.dims[1] - 1));
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let on_ring = x == x0 || x == x1 || y == y0 || y == y1;
                    if ring > 0 && !on_ring {
                        continue;
                    }
                    let c = y * self.dims[0] + x;
                    for &k in &self.items[self.start[c] as usize..self.start[c + 1] as usize] {
                        let l = self.barycentric(k as usize, p);
                        if l[0].min(l[1]).min(l[2]) >= 0.0 {
                            return self.value(k as usize, l);
                        }
                        let (d, q) = self.nearest_on_boundary(k as usize, p);
                        if d < best.0 {
                            best = (d, k as usize, self.barycentric(k as usize, q));
                        }
                    }
                }
            }
            // Beyond this ring, cells are farther than the best distance found: stop.
            let cell_size = 1.0 / self.inv[0].max(self.inv[1]).max(f64::MIN_POSITIVE);
            if best.0.is_finite() && (ring as f64) * cell_size > best.0 {
                break;
            }
        }
        if best.0.is_finite() {
            self.value(best.1, best.2)
        } else {
            self.spacing.iter().copied().fold(f64::INFINITY, f64::min)
        }
    }
}

/// Parameters of adaptation from a solution field ([`BackgroundMesh2::from_solution`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adaptation {
    /// Spacing where the gradient is largest.
    pub min_spacing: f64,
    /// Spacing where the field is flat.
    pub max_spacing: f64,
    /// Largest growth of spacing per unit distance between neighbouring nodes.
    pub growth: f64,
}

impl Adaptation {
    /// Bounds `min ≤ max`, growth 0.3 (the spacing grows by at most 30% of the distance).
    pub fn new(min_spacing: f64, max_spacing: f64) -> Self {
        Adaptation {
            min_spacing,
            max_spacing,
            growth: 0.3,
        }
    }
}

/// The most pieces [`graded_splits`] cuts an edge into (2^20).
pub const MAX_SOURCE_PIECES: usize = 1 << 20;

/// Samples of a background mesh's spacing along a boundary edge, at first
/// ([`SpacingField::boundary_splits`]).
const SPLIT_SAMPLES: usize = 64;

/// Where to split an edge `length` long so that each piece is no longer than the spacing
/// `spacing_at(t)` (`t` in `[0, 1]` along the edge) anywhere along it, given that the spacing
/// changes by at most `growth` per unit length: a step from `t` is the spacing there over
/// `1 + growth`, so the spacing cannot fall below the step within it. A constant spacing
/// (`growth` 0) gives `ceil(length / h)` equal pieces; otherwise a last piece under half the
/// step before it is evened out with that one where the bound allows. The parameters in
/// `(0, 1)`, increasing; at most [`MAX_SOURCE_PIECES`] pieces (equal ones if more were asked).
pub fn graded_splits(length: f64, spacing_at: impl Fn(f64) -> f64, growth: f64) -> Vec<f64> {
    let step = |t: f64| spacing_at(t) / (1.0 + growth) / length;
    let mut ts = Vec::new();
    let mut t = 0.0;
    loop {
        let s = step(t);
        if s.is_nan() || s <= 0.0 {
            return Vec::new();
        }
        if t + s >= 1.0 || ts.len() + 1 >= MAX_SOURCE_PIECES {
            break;
        }
        t += s;
        ts.push(t);
    }
    if ts.len() + 1 >= MAX_SOURCE_PIECES {
        let n = MAX_SOURCE_PIECES;
        return (1..n).map(|j| j as f64 / n as f64).collect();
    }
    let Some(&last) = ts.last() else {
        return ts;
    };
    if growth == 0.0 {
        // A constant spacing: n equal pieces, n the steps it takes to pass the end.
        let n = ts.len() + 1;
        return (1..n).map(|j| j as f64 / n as f64).collect();
    }
    let before = if ts.len() > 1 { ts[ts.len() - 2] } else { 0.0 };
    let mid = 0.5 * (before + 1.0);
    if 1.0 - last < 0.5 * (last - before) && 1.0 - mid <= step(mid).max(step(1.0)) {
        *ts.last_mut().expect("a last point") = mid;
    }
    ts
}

/// An analytic source of fine spacing: `h0` within `radius` of a point or a segment,
/// growing linearly at `growth` per unit distance beyond.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Source {
    /// The point, or the first end of the segment.
    pub a: [f64; 2],
    /// The second end of the segment (equal to `a` for a point source).
    pub b: [f64; 2],
    /// Spacing at the source.
    pub h0: f64,
    /// Radius within which the spacing is `h0`.
    pub radius: f64,
    /// Growth of the spacing per unit distance beyond the radius.
    pub growth: f64,
}

impl Source {
    /// The same source in units `2^exponent` times larger (growth is a ratio: unchanged).
    pub fn scaled(&self, exponent: i32) -> Self {
        let f = 2f64.powi(exponent);
        Source {
            a: self.a.map(|x| x * f),
            b: self.b.map(|x| x * f),
            h0: self.h0 * f,
            radius: self.radius * f,
            growth: self.growth,
        }
    }

    /// The spacing this source asks for at `p`.
    pub fn spacing(&self, p: [f64; 2]) -> f64 {
        let d = crate::distance::point_segment2(p, self.a, self.b);
        self.h0 + self.growth * (d - self.radius).max(0.0)
    }

    /// The finest spacing this source asks for anywhere on the segment `a b`.
    pub fn finest_on(&self, a: [f64; 2], b: [f64; 2]) -> f64 {
        let d = crate::distance::segment_segment2(self.a, self.b, a, b);
        self.h0 + self.growth * (d - self.radius).max(0.0)
    }

    /// The finest spacing this source asks for anywhere in the triangle `t`.
    pub fn finest_in(&self, t: [[f64; 2]; 3]) -> f64 {
        let d = crate::distance::segment_triangle2(self.a, self.b, t);
        self.h0 + self.growth * (d - self.radius).max(0.0)
    }
}

/// Where the spacing comes from.
#[derive(Clone, Debug)]
enum Base {
    Boundary,
    Background(BackgroundMesh2),
}

/// The spacing field of point generation: a base (the boundary's spacing interpolated from the
/// element's nodes, or a background mesh) refined by sources.
#[derive(Clone, Debug)]
pub struct SpacingField {
    base: Base,
    sources: Vec<Source>,
    /// The largest spacing in each region (by region index), from its area limit.
    region_caps: Vec<f64>,
}

impl SpacingField {
    /// The paper's default: spacing interpolated from the element's nodes.
    pub fn boundary() -> Self {
        SpacingField {
            base: Base::Boundary,
            sources: Vec::new(),
            region_caps: Vec::new(),
        }
    }

    /// Spacing from a background mesh.
    pub fn background(mesh: BackgroundMesh2) -> Self {
        SpacingField {
            base: Base::Background(mesh),
            sources: Vec::new(),
            region_caps: Vec::new(),
        }
    }

    /// Adds a source: the spacing becomes the smaller of the field's and the source's.
    pub fn with_source(mut self, source: Source) -> Self {
        self.sources.push(source);
        self
    }

    /// Caps the spacing in each region (by region index, as elements are tagged; infinite:
    /// no cap) by its area limit (`delmesh_boundary_recovery::Plc2::area_limits`, through
    /// `spacing_for_area`), so that generation fills a region with elements under its limit.
    pub fn with_area_limits(mut self, limits: &[f64]) -> Self {
        self.region_caps = limits
            .iter()
            .map(|&a| delmesh_boundary_recovery::spacing_for_area(a))
            .collect();
        self
    }

    /// Whether some region's spacing is capped ([`SpacingField::with_area_limits`]).
    #[inline]
    pub fn has_region_caps(&self) -> bool {
        !self.region_caps.is_empty()
    }

    /// The largest spacing allowed in region `tag` (infinite where there is no limit).
    #[inline]
    pub fn region_cap(&self, tag: u32) -> f64 {
        self.region_caps
            .get(tag as usize)
            .copied()
            .unwrap_or(f64::INFINITY)
    }

    /// Whether the field uses the values interpolated from the element's nodes.
    pub fn uses_node_values(&self) -> bool {
        matches!(self.base, Base::Boundary)
    }

    /// Whether the field has sources.
    #[inline]
    pub fn has_sources(&self) -> bool {
        !self.sources.is_empty()
    }

    /// The finest spacing the sources ask for anywhere in the triangle `t` (infinite without
    /// sources).
    pub fn finest_source_in(&self, t: [[f64; 2]; 3]) -> f64 {
        self.sources
            .iter()
            .fold(f64::INFINITY, |h, s| h.min(s.finest_in(t)))
    }

    /// Where the sources ask for the boundary edge `a b` to be split (see [`graded_splits`];
    /// empty if the edge is no longer than the spacing they ask anywhere on it), for
    /// [`delmesh_boundary_recovery::BoundaryRecovery::with_segment_splits`]: generation cannot
    /// fill the domain next to an edge finer than the edge, and thin elements pile up on it.
    pub fn source_splits(&self, a: [f64; 2], b: [f64; 2]) -> Vec<f64> {
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        let finest = self
            .sources
            .iter()
            .fold(f64::INFINITY, |h, s| h.min(s.finest_on(a, b)));
        if length.is_nan() || length <= finest {
            return Vec::new();
        }
        let growth = self.sources.iter().fold(0.0f64, |g, s| g.max(s.growth));
        graded_splits(
            length,
            |t| {
                let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                self.sources
                    .iter()
                    .fold(f64::INFINITY, |h, s| h.min(s.spacing(p)))
            },
            growth,
        )
    }

    /// About how many spacings long the edge `a b` is under this field (`∫ ds / h`, from a
    /// coarse sampling; the boundary's own spacing counts for nothing, so only sources do
    /// without a background): what [`Self::boundary_splits`] would cut it into, without
    /// cutting. Infinite where the spacing is not positive somewhere.
    pub fn spacings_along(&self, a: [f64; 2], b: [f64; 2]) -> f64 {
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        let k = SPLIT_SAMPLES;
        let inverse: f64 = (0..=k)
            .map(|i| {
                let t = i as f64 / k as f64;
                // (The boundary's own spacing counts for nothing: only sources then.)
                let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                let h = self.spacing(p, f64::INFINITY);
                let w = if i == 0 || i == k { 0.5 } else { 1.0 };
                if h > 0.0 && !h.is_nan() {
                    w / h
                } else {
                    f64::INFINITY
                }
            })
            .sum();
        length * inverse / k as f64
    }

    /// Where the field asks for the boundary edge `a b` to be split, for
    /// [`delmesh_boundary_recovery::BoundaryRecovery::with_segment_splits`]: generation cannot
    /// fill the domain next to an edge much longer than the spacing there, and thin elements
    /// pile up along it. Without a background mesh, as [`Self::source_splits`]. With one (or
    /// an adaptation's), the spacing along the edge is sampled, and the edge is cut into as
    /// many pieces as it is long in spacings (`∫ ds / h`, rounded to the nearest whole
    /// number: an edge up to one and a half times the spacing stays whole), placed at equal
    /// steps of that integral so that they grade as the spacing does. Empty where the spacing
    /// is not positive and finite (generation names that point).
    pub fn boundary_splits(&self, a: [f64; 2], b: [f64; 2]) -> Vec<f64> {
        if matches!(self.base, Base::Boundary) {
            return self.source_splits(a, b);
        }
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        if !(length > 0.0 && length.is_finite()) {
            return Vec::new();
        }
        let at = |t: f64| {
            self.spacing(
                [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
                f64::INFINITY,
            )
        };
        // Samples at least eight per finest spacing seen in a first, coarse sampling.
        let sample = |k: usize| -> Option<Vec<f64>> {
            let h: Vec<f64> = (0..=k).map(|i| at(i as f64 / k as f64)).collect();
            h.iter().all(|&x| x > 0.0 && x.is_finite()).then_some(h)
        };
        let Some(coarse) = sample(SPLIT_SAMPLES) else {
            return Vec::new();
        };
        let finest = coarse.iter().copied().fold(f64::INFINITY, f64::min);
        let wanted = (8.0 * length / finest).ceil();
        let (k, h) = if wanted > SPLIT_SAMPLES as f64 {
            let k = wanted.min(MAX_SOURCE_PIECES as f64) as usize;
            match sample(k) {
                Some(h) => (k, h),
                None => return Vec::new(),
            }
        } else {
            (SPLIT_SAMPLES, coarse)
        };
        // The edge's length in spacings up to each sample (trapezoids in 1/h).
        let dt = 1.0 / k as f64;
        let mut within = Vec::with_capacity(k + 1);
        within.push(0.0);
        for w in h.windows(2) {
            let last = within[within.len() - 1];
            within.push(last + 0.5 * length * dt * (1.0 / w[0] + 1.0 / w[1]));
        }
        let total = within[k];
        let pieces = total.round().min(MAX_SOURCE_PIECES as f64) as usize;
        let mut ts = Vec::with_capacity(pieces.saturating_sub(1));
        let mut j = 0;
        for piece in 1..pieces {
            let target = total * piece as f64 / pieces as f64;
            while j + 1 < k && within[j + 1] < target {
                j += 1;
            }
            let step = within[j + 1] - within[j];
            let f = if step > 0.0 {
                (target - within[j]) / step
            } else {
                0.5
            };
            let t = (j as f64 + f.clamp(0.0, 1.0)) * dt;
            if t > ts.last().copied().unwrap_or(0.0) && t < 1.0 {
                ts.push(t);
            }
        }
        ts
    }

    /// The spacing at `p`; `from_nodes` is the value interpolated from the element's nodes.
    pub fn spacing(&self, p: [f64; 2], from_nodes: f64) -> f64 {
        let base = match &self.base {
            Base::Boundary => from_nodes,
            Base::Background(mesh) => mesh.spacing_at(p),
        };
        self.sources.iter().fold(base, |h, s| h.min(s.spacing(p)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_spacing_gives_equal_pieces() {
        assert_eq!(graded_splits(10.0, |_| 3.0, 0.0), [0.25, 0.5, 0.75]);
        assert!(graded_splits(10.0, |_| 10.0, 0.0).is_empty());
    }

    #[test]
    fn graded_pieces_are_no_longer_than_the_spacing_anywhere_along_them() {
        // The boundary edge y = 0, x in [0, 10], of a square with a source in its corner.
        let source = Source {
            a: [0.5, 0.5],
            b: [0.5, 0.5],
            h0: 0.01,
            radius: 1.0,
            growth: 1.0,
        };
        let at = |t: f64| [10.0 * t, 0.0];
        let ts = graded_splits(10.0, |t| source.spacing(at(t)), 1.0);
        assert!(ts.len() > 100, "{}", ts.len());
        let mut all = vec![0.0];
        all.extend(&ts);
        all.push(1.0);
        for w in all.windows(2) {
            assert!(w[0] < w[1]);
            let piece = 10.0 * (w[1] - w[0]);
            let finest = source.finest_on(at(w[0]), at(w[1]));
            assert!(piece <= finest, "{w:?}: {piece} > {finest}");
            // And not much finer than asked at its end nearer the source.
            assert!(piece >= finest / 3.0, "{w:?}: {piece} for {finest}");
        }
    }
}
