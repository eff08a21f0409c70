//! Weatherill's automatic point generation (R10): centroid candidates accepted by the α test,
//! inserted by constrained Delaunay insertion, in passes until no candidate is accepted.
//!
//! Each pass looks at the elements as they are when it begins. Each element's candidate is its
//! centroid, with spacing `dp` from the [`SpacingField`] (interpolated from the element's nodes
//! by default, or from a background mesh), and passes the α test if it is farther than `α·dp`
//! from every node of the element. The candidates that pass are then inserted one by one, in
//! Hilbert order (consecutive insertions are neighbours, so the walks are short and the memory
//! they touch is warm, and the new vertices and cells are numbered along the curve, which every
//! later stage's memory traffic benefits from). A candidate whose element an earlier insertion
//! of the same pass has already changed is dropped, so two candidates of neighbouring elements
//! do not both go in; the changed elements are looked at in the next pass. The new node keeps
//! its `dp`, but for one limit beyond the paper: a candidate's interpolated spacing is at least
//! its distance to the element's nearest node over the grading limit (64), up to the coarsest
//! spacing of the boundary, so that a small feature's spacing does not fill a whole domain
//! whose elements touch only small features. An element is tested at the finest spacing a
//! source asks anywhere in it, when finer than at its centroid (see `distance`): a source
//! smaller than the elements and off their centroids was never seen.
//! Insertion is constrained: a candidate never crosses or removes a boundary edge, and
//! one that rounding put on a boundary edge or outside its region is refused. Passes end when
//! one inserts nothing.
//!
//! Only what changed is looked at again: an element unchanged since the previous pass began
//! was looked at then, and refused or dropped for a change that made it a new element. The
//! exception is a candidate refused for the nodes of *another* element (rounding put a thin
//! element's centroid outside it), which is looked at again in the next pass. The candidates
//! of a pass are evaluated in parallel; the result does not depend on the number of threads.
//!
//! Large meshes are renumbered along a space-filling curve as they grow ([`RENUMBER_MIN`]), so
//! that the later passes and stages read memory in order.
//!
//! A spacing field may ask for more elements than 32-bit indices hold (a background mesh with
//! a spacing of 1e-300): each pass estimates the elements its candidates' spacing asks for in
//! their own elements, and over 2^30 the run stops with [`PointGenError::SpacingTooFine`]
//! rather than when memory runs out (the same in 3D); and with
//! [`PointGenError::NotEnoughMemory`] if they need more memory than the process has left.

use crate::area::{area, points};
use crate::memory::{elements_fitting, BYTES_PER_TRIANGLE};
use crate::SpacingField;
use delmesh_boundary_recovery::Mesh2;
use delmesh_delaunay_core::{CellId, ConstraintError, Dim, Insertion, VertexId, D2};
use rayon::prelude::*;
use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};

/// Why point generation could not run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PointGenError {
    /// α must be a positive finite number.
    #[error("alpha must be positive and finite (got {0:?})")]
    BadAlpha(f64),
    /// The grading limit must be at least 1.
    #[error("the grading limit must be at least 1 (got {0:?})")]
    BadGradingLimit(f64),
    /// A spacing value was not positive and finite at a candidate point.
    #[error("spacing {value} at ({x}, {y}) is not positive and finite")]
    BadSpacing {
        /// The value.
        value: f64,
        /// Where (x).
        x: f64,
        /// Where (y).
        y: f64,
    },
    /// A spacing value was not positive and finite at a candidate point in 3D.
    #[error("spacing {value} at ({x}, {y}, {z}) is not positive and finite")]
    BadSpacing3 {
        /// The value.
        value: f64,
        /// Where (x).
        x: f64,
        /// Where (y).
        y: f64,
        /// Where (z).
        z: f64,
    },
    /// A region's volume limit is not a positive number.
    #[error("region {region}: the maximum volume must be positive (got {value:?})")]
    BadVolumeLimit {
        /// The region's number.
        region: u64,
        /// The value.
        value: f64,
    },
    /// Volume limits ask for more tetrahedra than the mesh's 32-bit indices hold.
    #[error(
        "region {region}: a maximum volume of {max_volume:e} asks for about {elements:.1e} tetrahedra in the region's volume of {volume:e}, more than delmesh can index (2^30)"
    )]
    VolumeLimitTooSmall {
        /// The region's number.
        region: u64,
        /// Its limit.
        max_volume: f64,
        /// Its volume.
        volume: f64,
        /// Tetrahedra it asks for at least.
        elements: f64,
    },
    /// The spacing field asks for more elements than the mesh's 32-bit indices hold.
    #[error(
        "the spacing field asks for {} elements (alpha × spacing down to {spacing:.3e}), more \
         than delmesh can index (2^30); give a larger (minimum) spacing or alpha",
        about(*.elements)
    )]
    SpacingTooFine {
        /// Elements the candidates of one pass ask for, at least about.
        elements: f64,
        /// The finest distance between points they ask for (α times the finest spacing).
        spacing: f64,
    },
    /// The spacing field asks for more elements than fit in the memory left to the process.
    #[error(
        "the spacing field asks for {} elements (alpha × spacing down to {spacing:.3e}), \
         which need at least {} of memory, more than the {} this process has left; give a \
         larger (minimum) spacing or alpha",
        about(*.elements),
        crate::memory::size(*.bytes),
        crate::memory::size(*.available)
    )]
    NotEnoughMemory {
        /// Elements the candidates of one pass ask for, at least about.
        elements: f64,
        /// The finest distance between points they ask for (α times the finest spacing).
        spacing: f64,
        /// The memory they need at least.
        bytes: f64,
        /// The memory left (the system's available memory, or the process's limits).
        available: f64,
    },
    /// A 3D candidate could not be inserted (a bad coordinate).
    #[error(transparent)]
    Insertion3(#[from] delmesh_delaunay_core::TriangulationError),
    /// An insertion failed (a bug in delmesh if it ever fires: candidates are inside).
    #[error(transparent)]
    Insertion(#[from] ConstraintError),
}

/// Meshes of at least this many elements are renumbered along a space-filling curve
/// ([`Mesh2::renumber`]) whenever they have doubled since the last time, and at the end if
/// they have grown by a quarter since: passes over the whole domain number the new vertices
/// and cells pass by pass, so that neighbours end up far apart in memory and most reads of the
/// later passes and stages miss the cache (after generation at 10^6 triangles, 84% of
/// neighbour links span more than 4096 cell slots). Renumbering costs a few sweeps over the
/// mesh (0.08 s at 900,000 triangles); smaller meshes fit in the cache.
pub const RENUMBER_MIN: usize = 1 << 16;

/// "about 1.2e9", or "more than 1e308" for a count that overflowed.
fn about(n: f64) -> String {
    if n.is_finite() {
        format!("about {n:.1e}")
    } else {
        "more than 1e308".to_string()
    }
}

/// The error for a spacing field whose candidates ask for `asked` elements (points `finest`
/// apart) if that is more than can be indexed, or than fit in `memory` at `bytes_each`.
pub(crate) fn too_many(
    asked: f64,
    finest: f64,
    memory: Option<f64>,
    bytes_each: f64,
) -> Result<(), PointGenError> {
    if asked > MAX_ELEMENTS {
        return Err(PointGenError::SpacingTooFine {
            elements: asked,
            spacing: finest,
        });
    }
    match memory {
        Some(available) if asked > elements_fitting(memory, bytes_each) => {
            Err(PointGenError::NotEnoughMemory {
                elements: asked,
                spacing: finest,
                bytes: asked * bytes_each,
                available,
            })
        }
        _ => Ok(()),
    }
}

/// Equilateral triangles of side `h` in `area`.
fn triangles_in(area: f64, h: f64) -> f64 {
    area / (0.25 * 3f64.sqrt() * h * h)
}

/// How many cells ahead the evaluation of candidates and their insertion ask for a later cell
/// (`ConstrainedTriangulation2::prefetch_cell`), and for what around it they will read
/// (`prefetch_vertices`, `prefetch_neighbours`, which read the cell): at 10^6 triangles the
/// mesh outgrows the cache and both otherwise wait on those loads. Measured at
/// `pipeline2d 1000`: evaluation 90 → 65 ms, insertion 12–15% less; distances of 6–16 and
/// 2–6 alike.
const PREFETCH_CELL: usize = 8;
const PREFETCH_AROUND: usize = 3;

/// The most elements point generation makes: as many as 32-bit indices hold, with room.
pub(crate) const MAX_ELEMENTS: f64 = (1u64 << 30) as f64;

/// Settings of automatic point generation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointGeneration {
    /// α: a candidate must be farther than `α·dp` from the nodes; larger α, fewer points.
    pub alpha: f64,
    /// How much finer than an element the spacing interpolated from its nodes may be: the
    /// candidate's spacing is at least its distance to the element's nearest node divided by
    /// this (default 64), but not more than the coarsest spacing of the nodes at the start (an
    /// evenly spaced boundary is filled evenly). The paper's interpolation carries a small
    /// feature's spacing into every element whose nodes all lie on small features, however
    /// large: three holes 1e-5 across in a unit square filled it at their spacing until memory
    /// ran out. With the limit the spacing grows away from them instead. `f64::INFINITY` is
    /// the paper's rule as it is. A background mesh's spacing, and sources, are used as they
    /// are.
    pub grading_limit: f64,
    /// Stop after adding this many points.
    pub max_points: usize,
    /// Stop after this many passes.
    pub max_passes: usize,
}

impl Default for PointGeneration {
    fn default() -> Self {
        PointGeneration {
            alpha: 1.0,
            grading_limit: 64.0,
            max_points: usize::MAX,
            max_passes: 200,
        }
    }
}

/// One pass of point generation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GenerationPass {
    /// Elements looked at (the elements when the pass began).
    pub candidates: usize,
    /// Candidates inserted.
    pub accepted: usize,
    /// Elements after the pass.
    pub elements: usize,
}

/// What point generation did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GenerationReport {
    /// The passes, in order (the last accepted nothing, unless a limit stopped it).
    pub passes: Vec<GenerationPass>,
}

impl GenerationReport {
    /// Points added over all passes.
    pub fn points_added(&self) -> usize {
        self.passes.iter().map(|p| p.accepted).sum()
    }
}

impl fmt::Display for GenerationReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:>5} {:>11} {:>9} {:>9}",
            "pass", "candidates", "accepted", "elements"
        )?;
        for (k, p) in self.passes.iter().enumerate() {
            writeln!(
                f,
                "{:>5} {:>11} {:>9} {:>9}",
                k + 1,
                p.candidates,
                p.accepted,
                p.elements
            )?;
        }
        Ok(())
    }
}

impl PointGeneration {
    /// Fills the domain of `mesh` with points spaced as `field` says (see the module docs).
    /// New nodes get their spacing in `mesh.spacing`. A mesh that reaches [`RENUMBER_MIN`]
    /// elements is renumbered ([`Mesh2::renumber`]): vertex and cell ids taken before the call
    /// do not hold after it (input indices do).
    ///
    /// # Errors
    /// A bad α, or a spacing that is not positive and finite.
    pub fn run(
        &self,
        mesh: &mut Mesh2,
        field: &SpacingField,
    ) -> Result<GenerationReport, PointGenError> {
        if !(self.alpha > 0.0 && self.alpha.is_finite()) {
            return Err(PointGenError::BadAlpha(self.alpha));
        }
        if self.grading_limit.is_nan() || self.grading_limit < 1.0 {
            return Err(PointGenError::BadGradingLimit(self.grading_limit));
        }
        let mut dp = node_spacing(mesh, field)?;
        // The grading limit never coarsens past the coarsest spacing the nodes start with: a
        // domain whose boundary is spaced evenly is filled evenly, as the paper's rule does.
        let coarsest = dp
            .iter()
            .copied()
            .filter(|h| h.is_finite())
            .fold(0.0, f64::max);
        let mut report = GenerationReport::default();
        let mut added = 0usize;
        let mut elements = mesh.num_elements();
        let frame = Frame::of(mesh);
        // Cells whose candidate was refused because of another cell's nodes: that cell may
        // change, so they are looked at again in the next pass even if they did not.
        let mut retry: Vec<CellId> = Vec::new();
        // The elements to look at: all of them first, then those the previous pass changed
        // (recorded by the triangulation as it changes them).
        let mut cells = elements_where(mesh, |_| true);
        // The element count at the last renumbering (see `RENUMBER_MIN`).
        let mut renumbered = elements;
        let domain_area = mesh.area();
        // The memory left now, and the triangles it holds (see `too_many`).
        let memory = crate::memory::available();
        let fitting = elements_fitting(memory, BYTES_PER_TRIANGLE);
        while report.passes.len() < self.max_passes && added < self.max_points {
            let previous = mesh.cdt.changed_in_epoch();
            let epoch = mesh.cdt.next_epoch(true);
            for c in retry.drain(..) {
                // Not already listed as changed.
                if mesh.cdt.changed_in(c) != previous && mesh.is_element(c) {
                    cells.push(c);
                }
            }
            // Every candidate of the pass, evaluated in parallel on the mesh as it is now, then
            // visited in Hilbert order of the candidates.
            let dp_now: &[f64] = &dp;
            let frame = &frame;
            // Each accepted candidate with its Hilbert key (16 bits per axis, so 32 bits) above
            // its cell: sorting these keys is sorting by key, then cell.
            let bad = AtomicBool::new(false);
            let cdt = &mesh.cdt;
            let mut todo: Vec<(u64, [f64; 2], f64, f64)> = cells
                .par_chunks(1 << 10)
                .flat_map_iter(|chunk| {
                    chunk.iter().enumerate().map(move |(k, &c)| {
                        if let Some(&ahead) = chunk.get(k + PREFETCH_CELL) {
                            cdt.prefetch_cell(ahead);
                        }
                        if let Some(&ahead) = chunk.get(k + PREFETCH_AROUND) {
                            cdt.prefetch_vertices(ahead);
                        }
                        c
                    })
                })
                .filter_map(|c| match self.candidate(mesh, c, dp_now, coarsest, field) {
                    Candidate::At { g, h, reach2 } => {
                        let key = frame.key(g);
                        debug_assert!(key < 1 << 32);
                        Some(((key << 32) | u64::from(c.0), g, h, reach2))
                    }
                    Candidate::BadSpacing { .. } => {
                        bad.store(true, Ordering::Relaxed);
                        None
                    }
                    Candidate::Refused => None,
                })
                .collect();
            if bad.into_inner() {
                // The first bad spacing in the order of the cells.
                for &c in &cells {
                    if let Candidate::BadSpacing { value, at } =
                        self.candidate(mesh, c, dp_now, coarsest, field)
                    {
                        return Err(PointGenError::BadSpacing {
                            value,
                            x: at[0],
                            y: at[1],
                        });
                    }
                }
            }
            // The elements the candidates' spacing asks for in their own elements: more than can
            // be indexed (a spacing of 1e-300 in a background mesh) ends the run now rather
            // than when memory runs out. Summed only when the finest spacing could ask for
            // that many over the whole domain.
            // (Points go α·h apart: a tiny α asks for as many as a tiny spacing.)
            let finest = self.alpha * todo.iter().fold(f64::INFINITY, |m, t| m.min(t.2));
            if triangles_in(domain_area, finest) > fitting.min(MAX_ELEMENTS) {
                let mesh: &Mesh2 = mesh;
                let asked: f64 = todo
                    .par_iter()
                    .map(|&(key, _, h, _)| {
                        triangles_in(area(points(mesh, CellId(key as u32))), self.alpha * h)
                    })
                    .sum();
                too_many(asked, finest, memory, BYTES_PER_TRIANGLE)?;
            }
            // (Sorting (key, position) pairs instead moves less memory in the sort, but the
            // insertions then read the candidates out of order: no faster, measured.)
            todo.par_sort_unstable_by_key(|t| t.0);
            let mut accepted = 0;
            for (k, &(key, g, h, reach2)) in todo.iter().enumerate() {
                let c = CellId(key as u32);
                if added >= self.max_points {
                    break;
                }
                if let Some(&(ahead, ..)) = todo.get(k + PREFETCH_CELL) {
                    mesh.cdt.prefetch_cell(CellId(ahead as u32));
                }
                if let Some(&(ahead, ..)) = todo.get(k + PREFETCH_AROUND) {
                    let ahead = CellId(ahead as u32);
                    mesh.cdt.prefetch_vertices(ahead);
                    mesh.cdt.prefetch_neighbours(ahead);
                }
                // An element an earlier insertion of this pass changed is not the one that
                // made the candidate any more: it is looked at again in the next pass.
                if mesh.cdt.changed_in(c) == epoch {
                    continue;
                }
                let dist2 =
                    |q: [f64; 2]| (q[0] - g[0]) * (q[0] - g[0]) + (q[1] - g[1]) * (q[1] - g[1]);
                let tag = mesh.cdt.tag(c);
                let elsewhere = std::cell::Cell::new(false);
                let inserted = mesh.cdt.insert_near_if(g, c, |cdt, cell, on_edge| {
                    elsewhere.set(cell != c);
                    if cdt.tag(cell) != tag || on_edge.is_some_and(|i| cdt.is_constrained(cell, i))
                    {
                        return false;
                    }
                    let t = cdt.triangulation();
                    t.cell(cell).iter().all(|&u| dist2(t.vertex(u)) > reach2)
                })?;
                match inserted {
                    Some(Insertion::Inserted(nv)) => {
                        set(&mut dp, nv, h);
                        set(&mut mesh.spacing, nv, h);
                        accepted += 1;
                        added += 1;
                    }
                    _ if elsewhere.get() => retry.push(c),
                    _ => {}
                }
            }
            cells = mesh.cdt.take_changed();
            // Each insertion splits one element into three, or two sharing an edge (never a
            // boundary edge, so both in the region) into four.
            let before = elements;
            elements += 2 * accepted;
            debug_assert_eq!(elements, mesh.num_elements());
            report.passes.push(GenerationPass {
                candidates: before,
                accepted,
                elements,
            });
            if accepted == 0 {
                break;
            }
            if elements >= RENUMBER_MIN && elements >= 2 * renumbered {
                renumbered = elements;
                let map = mesh.renumber();
                dp = map.permute_vertices(&dp, f64::NAN);
                map.renumber_cells(&mut cells);
                map.renumber_cells(&mut retry);
            }
        }
        if elements >= RENUMBER_MIN && 4 * elements >= 5 * renumbered {
            mesh.renumber();
        }
        Ok(report)
    }

    /// The candidate of cell `c` if it is an element: its centroid with its spacing, unless a
    /// node of `c` is within `α·dp` of it (most candidates fail here, before any walk).
    fn candidate(
        &self,
        mesh: &Mesh2,
        c: CellId,
        dp: &[f64],
        coarsest: f64,
        field: &SpacingField,
    ) -> Candidate {
        // (The changed cells are not filtered beforehand: this is the one read of them.)
        if !mesh.is_element(c) {
            return Candidate::Refused;
        }
        let tri = mesh.cdt.triangulation();
        let v = tri.cell(c);
        let p = [tri.vertex(v[0]), tri.vertex(v[1]), tri.vertex(v[2])];
        let g = [
            (p[0][0] + p[1][0] + p[2][0]) / 3.0,
            (p[0][1] + p[1][1] + p[2][1]) / 3.0,
        ];
        let dist2 = |q: [f64; 2]| (q[0] - g[0]) * (q[0] - g[0]) + (q[1] - g[1]) * (q[1] - g[1]);
        let d2 = p.map(dist2);
        let mut from_nodes = (dp[v[0].index()] + dp[v[1].index()] + dp[v[2].index()]) / 3.0;
        // The grading limit, up to the coarsest node spacing (rarely reached: the square root
        // only then).
        let nearest2 = d2[0].min(d2[1]).min(d2[2]);
        let limit = self.grading_limit;
        if from_nodes < coarsest && from_nodes * from_nodes * (limit * limit) < nearest2 {
            from_nodes = (nearest2.sqrt() / limit).min(coarsest);
        }
        let h = field.spacing(g, from_nodes);
        if !(h > 0.0 && h.is_finite()) {
            return Candidate::BadSpacing { value: h, at: g };
        }
        // (The tag is read only when some region has a cap.)
        let h = if field.has_region_caps() {
            h.min(field.region_cap(mesh.cdt.tag(c)))
        } else {
            h
        };
        // A source may ask for finer spacing elsewhere in the element than at its centroid.
        let test = if field.has_sources() {
            h.min(field.finest_source_in(p))
        } else {
            h
        };
        let reach = self.alpha * test;
        let reach2 = reach * reach;
        // All three distances, then one branch (a branch per node went either way at random).
        let [n0, n1, n2] = d2.map(|d| d <= reach2);
        if n0 | n1 | n2 {
            return Candidate::Refused;
        }
        Candidate::At { g, h, reach2 }
    }
}

/// What an element proposes.
#[derive(Clone, Copy, Debug)]
enum Candidate {
    /// Nothing (not an element, or a node too close to its centroid).
    Refused,
    /// The spacing field gave a bad value at the centroid.
    BadSpacing { value: f64, at: [f64; 2] },
    /// Its centroid `g`, the spacing `h` there and the squared reach `(α·h)²`.
    At { g: [f64; 2], h: f64, reach2: f64 },
}

/// The bounding box of the mesh's vertices, for Hilbert keys of candidates.
struct Frame {
    lo: [f64; 2],
    scale: [f64; 2],
}

impl Frame {
    fn of(mesh: &Mesh2) -> Frame {
        let tri = mesh.cdt.triangulation();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for i in 0..tri.num_vertices() {
            let p = tri.vertex(VertexId(i as u32));
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let scale = [0, 1].map(|k| {
            let w = hi[k] - lo[k];
            if w > 0.0 {
                65535.0 / w
            } else {
                0.0
            }
        });
        Frame { lo, scale }
    }

    /// The Hilbert key of `p` on a 2^16 grid over the box (clamped).
    fn key(&self, p: [f64; 2]) -> u64 {
        let q = [0, 1].map(|k| ((p[k] - self.lo[k]) * self.scale[k]).clamp(0.0, 65535.0) as u32);
        D2::hilbert_key(&q)
    }
}

/// The elements of `mesh` that satisfy `keep`, in slot order (the slots are scanned in
/// parallel).
pub(crate) fn elements_where(mesh: &Mesh2, keep: impl Fn(CellId) -> bool + Sync) -> Vec<CellId> {
    (0..mesh.cdt.num_cell_slots() as u32)
        .into_par_iter()
        .with_min_len(1 << 12)
        .map(CellId)
        .filter(|&c| mesh.is_element(c) && keep(c))
        .collect()
}

/// Sets `values[v]`, growing `values` with NaN to hold it (per-vertex spacing).
pub(crate) fn set(values: &mut Vec<f64>, v: VertexId, x: f64) {
    if values.len() <= v.index() {
        values.resize(v.index() + 1, f64::NAN);
    }
    values[v.index()] = x;
}

/// The spacing at every vertex: the field's value there, given the vertex's own value (from
/// the boundary), or for vertices recovery gave none (isolated or external points) the mean
/// length of their edges in the domain.
fn node_spacing(mesh: &mut Mesh2, field: &SpacingField) -> Result<Vec<f64>, PointGenError> {
    let tri = mesh.cdt.triangulation();
    let n = tri.num_vertices();
    mesh.spacing.resize(n, f64::NAN);
    let mut sum = vec![0.0f64; n];
    let mut count = vec![0u32; n];
    for c in mesh.elements() {
        let v = tri.cell(c);
        for k in 0..3 {
            let (a, b) = (v[k], v[(k + 1) % 3]);
            let (pa, pb) = (tri.vertex(a), tri.vertex(b));
            let len = (pa[0] - pb[0]).hypot(pa[1] - pb[1]);
            for u in [a, b] {
                sum[u.index()] += len;
                count[u.index()] += 1;
            }
        }
    }
    let mut dp = vec![f64::NAN; n];
    for i in 0..n {
        if !mesh.spacing[i].is_finite() && count[i] > 0 {
            mesh.spacing[i] = sum[i] / f64::from(count[i]);
        }
        if count[i] > 0 {
            let p = tri.vertex(VertexId(i as u32));
            let h = field.spacing(p, mesh.spacing[i]);
            if !(h > 0.0 && h.is_finite()) {
                return Err(PointGenError::BadSpacing {
                    value: h,
                    x: p[0],
                    y: p[1],
                });
            }
            dp[i] = h;
        }
    }
    Ok(dp)
}
