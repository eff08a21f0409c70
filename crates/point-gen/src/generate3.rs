//! Weatherill's automatic point generation in 3D (R10): centroid candidates accepted by the α
//! test against the tetrahedron's nodes, inserted by constrained Delaunay insertion, in passes
//! until no candidate is accepted.
//!
//! As in 2D ([`crate::PointGeneration`]): each tetrahedron's candidate is its centroid, with
//! spacing `dp` from the spacing function (by default the mean of its nodes' values); it is
//! inserted only if it is farther than `α·dp` from every node of the tetrahedron that contains
//! it *now*. Insertion never grows a cavity across a protected (recovered) boundary face, so the
//! surface is never destroyed; a candidate whose cavity would not be star-shaped (next to a
//! non-convex part of the boundary) is refused and counted. The paper's variant, which rejects
//! every field point that would delete a protected tetrahedron, refused 725 points on the
//! double ellipsoid.
//!
//! A tetrahedron's candidate and its α test depend only on its own nodes, so a tetrahedron
//! rejected once stays rejected while it exists: after the first pass only the tetrahedra made
//! by the previous pass's insertions are looked at.
//!
//! A pass evaluates its candidates in parallel, then visits them in the Hilbert order of their
//! centroids, so consecutive insertions are neighbours and the cells and points they read are
//! still in cache. A slot whose tetrahedron an earlier insertion of the pass has replaced is
//! looked at as it is then: a cavity reuses its own slots, so the new tetrahedron is the old
//! one's neighbour, and the count of points stays that of visiting the slots in order (which
//! it was before, and which missed the cache on nearly every conflict test).

use crate::memory::BYTES_PER_TETRAHEDRON;
use crate::volume::{points, tet_volume};
use crate::{PointGenError, SpacingField3, RENUMBER_MIN};
use delmesh_boundary_recovery::{Mesh3, OUTSIDE};
use delmesh_delaunay_core::{CellId, Dim, VertexId, D3};
use rayon::prelude::*;
use std::fmt;

/// Settings of automatic point generation in 3D.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointGeneration3 {
    /// α: a candidate must be farther than `α·dp` from the nodes; larger α, fewer points.
    pub alpha: f64,
    /// Stop after adding this many points.
    pub max_points: usize,
    /// Stop after this many passes.
    pub max_passes: usize,
}

impl Default for PointGeneration3 {
    fn default() -> Self {
        PointGeneration3 {
            alpha: 1.0,
            max_points: usize::MAX,
            max_passes: 200,
        }
    }
}

/// One pass of 3D point generation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GenerationPass3 {
    /// Tetrahedra looked at.
    pub candidates: usize,
    /// Candidates inserted.
    pub accepted: usize,
    /// Candidates that passed the α test but whose insertion was refused (the cavity was not
    /// star-shaped, or the point rounded onto the boundary).
    pub refused: usize,
    /// Elements (tetrahedra in the domain) after the pass.
    pub elements: usize,
}

/// What 3D point generation did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GenerationReport3 {
    /// The passes, in order (the last accepted nothing, unless a limit stopped it).
    pub passes: Vec<GenerationPass3>,
}

impl GenerationReport3 {
    /// Points added over all passes.
    pub fn points_added(&self) -> usize {
        self.passes.iter().map(|p| p.accepted).sum()
    }

    /// Candidates refused at insertion over all passes.
    pub fn refused(&self) -> usize {
        self.passes.iter().map(|p| p.refused).sum()
    }
}

impl fmt::Display for GenerationReport3 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:>5} {:>11} {:>9} {:>8} {:>10}",
            "pass", "candidates", "accepted", "refused", "elements"
        )?;
        for (k, p) in self.passes.iter().enumerate() {
            writeln!(
                f,
                "{:>5} {:>11} {:>9} {:>8} {:>10}",
                k + 1,
                p.candidates,
                p.accepted,
                p.refused,
                p.elements
            )?;
        }
        Ok(())
    }
}

impl PointGeneration3 {
    /// Fills the domain of `mesh` with points spaced as `field` says, given at a candidate the
    /// mean of its tetrahedron's node values (the paper's interpolation) and at an existing
    /// node its own value. A tetrahedron some source asks to be finer somewhere than at its
    /// centroid is tested at that finer spacing (see `distance`). New nodes get their spacing
    /// in `mesh.spacing`. The candidates of a pass are evaluated in parallel; the result does
    /// not depend on the number of threads.
    ///
    /// # Errors
    /// A bad α, or a spacing that is not positive and finite.
    pub fn run(
        &self,
        mesh: &mut Mesh3,
        field: &SpacingField3,
    ) -> Result<GenerationReport3, PointGenError> {
        self.run_capped(mesh, field, &[])
    }

    /// [`PointGeneration3::run`] with the spacing in each region (by region index, as cells
    /// are tagged) at most `region_caps[tag]` (regions past the end: no cap), as volume limits
    /// ask (see [`crate::VolumeLimits`]).
    ///
    /// # Errors
    /// As [`PointGeneration3::run`].
    pub fn run_capped(
        &self,
        mesh: &mut Mesh3,
        field: &SpacingField3,
        region_caps: &[f64],
    ) -> Result<GenerationReport3, PointGenError> {
        if !(self.alpha > 0.0 && self.alpha.is_finite()) {
            return Err(PointGenError::BadAlpha(self.alpha));
        }
        let mut dp = node_spacing3(mesh, field)?;
        let largest = (0..mesh.ct.triangulation().num_vertices())
            .flat_map(|v| mesh.ct.triangulation().vertex(VertexId(v as u32)))
            .fold(0.0f64, |m, c| m.max(c.abs()));
        let tiny = largest * 2f64.powi(-100);
        let frame = Frame3::of(mesh);
        let mut report = GenerationReport3::default();
        let mut added = 0usize;
        let mut cells: Vec<CellId> = mesh.elements().collect();
        let domain_volume = mesh.volume();
        // The memory left now, and the tetrahedra it holds (see `generate::too_many`).
        let memory = crate::memory::available();
        let fitting = crate::memory::elements_fitting(memory, BYTES_PER_TETRAHEDRON);
        // The cell slots made in the current pass (a slot freed and reused counts once).
        let mut made: Vec<bool> = Vec::new();
        while report.passes.len() < self.max_passes && added < self.max_points {
            // Every candidate of the pass, evaluated in parallel on the mesh as it is now, with
            // the Hilbert key of its tetrahedron's centroid (10 bits per axis) above its id.
            let dp_now: &[f64] = &dp;
            let mesh_now: &Mesh3 = mesh;
            let mut looked: Vec<(u64, Candidate3)> = cells
                .par_iter()
                .with_min_len(1 << 10)
                .map(|&c| {
                    let (g, k) = self.candidate(mesh_now, c, dp_now, field, region_caps, tiny);
                    (frame.key(g) << 32 | u64::from(c.0), k)
                })
                .collect();
            // Then visited in that order: consecutive insertions are neighbours, so the cells
            // and points they read are still in cache (in slot order nearly every conflict
            // test missed it), and new cells and vertices are numbered along the curve. A slot
            // whose tetrahedron an earlier insertion of this pass replaced (cavities reuse
            // their own slots, so the new one is there or nearby) is looked at as it is now.
            looked.par_sort_unstable_by_key(|t| t.0);
            // As in 2D: a spacing asking for more elements than can be indexed ends the run.
            let finest = self.alpha
                * looked.iter().fold(f64::INFINITY, |m, t| match t.1 {
                    Candidate3::At { h, .. } => m.min(h),
                    _ => m,
                });
            if tetrahedra_in(domain_volume, finest) > fitting.min(crate::generate::MAX_ELEMENTS) {
                let mesh: &Mesh3 = mesh;
                let asked: f64 = looked
                    .par_iter()
                    .filter_map(|&(key, k)| match k {
                        Candidate3::At { h, .. } => Some(tetrahedra_in(
                            tet_volume(points(mesh, CellId(key as u32))),
                            self.alpha * h,
                        )),
                        _ => None,
                    })
                    .sum();
                crate::generate::too_many(asked, finest, memory, BYTES_PER_TETRAHEDRON)?;
            }
            let (mut accepted, mut refused) = (0, 0);
            for &(key, early) in &looked {
                if added >= self.max_points {
                    break;
                }
                let c = CellId(key as u32);
                if !mesh.ct.is_live(c) {
                    continue;
                }
                let replaced = made.get(c.index()).copied().unwrap_or(false);
                let now = if replaced {
                    self.candidate(mesh, c, &dp, field, region_caps, tiny).1
                } else {
                    early
                };
                let (g, h, reach2) = match now {
                    Candidate3::Refused => continue,
                    Candidate3::Tiny => {
                        refused += 1;
                        continue;
                    }
                    Candidate3::BadSpacing { value, at } => return Err(bad_spacing(value, at)),
                    Candidate3::At { g, h, reach2 } => (g, h, reach2),
                };
                let tag = mesh.ct.tag(c);
                let dist2 = |q: [f64; 3]| {
                    (q[0] - g[0]) * (q[0] - g[0])
                        + (q[1] - g[1]) * (q[1] - g[1])
                        + (q[2] - g[2]) * (q[2] - g[2])
                };
                let inserted = mesh.ct.insert_if(g, c, |ct, cell| {
                    if ct.tag(cell) != tag {
                        return false;
                    }
                    let t = ct.triangulation();
                    t.cell(cell).iter().all(|&u| dist2(t.vertex(u)) > reach2)
                })?;
                match inserted {
                    Some(nv) => {
                        set(&mut dp, nv, h);
                        mesh.set_interior_spacing(nv, h);
                        for &n in mesh.ct.last_new_cells() {
                            if made.len() <= n.index() {
                                made.resize(n.index() + 1, false);
                            }
                            made[n.index()] = true;
                        }
                        accepted += 1;
                        added += 1;
                    }
                    // Refused only if the cell still exists and held the point.
                    None => refused += 1,
                }
            }
            report.passes.push(GenerationPass3 {
                candidates: cells.len(),
                accepted,
                refused,
                elements: mesh.num_elements(),
            });
            // Only the cells made in this pass can give a new candidate, in slot order.
            cells.clear();
            for (i, m) in made.iter_mut().enumerate() {
                if std::mem::take(m) {
                    cells.push(CellId(i as u32));
                }
            }
            if accepted == 0 {
                break;
            }
        }
        // Passes number vertices and cells pass by pass, each pass along its own Hilbert
        // curve: renumbered once along one, the later stages (output arrays, smoothing's
        // stars, the Delaunay restoration) read neighbours near each other in memory.
        if added > 0 && report.passes.last().map_or(0, |p| p.elements) >= RENUMBER_MIN {
            mesh.renumber();
        }
        Ok(report)
    }
}

impl PointGeneration3 {
    /// The centroid of cell `c`, and its candidate if `c` is an element: the centroid with its
    /// spacing, unless a node of `c` is within `α·dp` of it (most candidates fail here).
    fn candidate(
        &self,
        mesh: &Mesh3,
        c: CellId,
        dp: &[f64],
        field: &SpacingField3,
        region_caps: &[f64],
        tiny: f64,
    ) -> ([f64; 3], Candidate3) {
        let nothing = ([0.0; 3], Candidate3::Refused);
        if !mesh.ct.is_live(c) {
            return nothing;
        }
        let tri = mesh.ct.triangulation();
        let v = tri.cell(c);
        if mesh.ct.tag(c) == OUTSIDE || v.iter().any(|u| u.is_ghost()) {
            return nothing;
        }
        let p = [0, 1, 2, 3].map(|k| tri.vertex(v[k]));
        let g = [0, 1, 2].map(|k| 0.25 * (p[0][k] + p[1][k] + p[2][k] + p[3][k]));
        let from_nodes = 0.25 * v.iter().map(|u| dp[u.index()]).sum::<f64>();
        let h = field.spacing(g, from_nodes);
        if !(h > 0.0 && h.is_finite()) {
            return (g, Candidate3::BadSpacing { value: h, at: g });
        }
        let h = match region_caps.get(mesh.ct.tag(c) as usize) {
            Some(&cap) => h.min(cap),
            None => h,
        };
        // A source may ask for finer spacing elsewhere in the tetrahedron than at its centroid.
        let test = h.min(field.finest_source_in(p));
        let reach2 = (self.alpha * test) * (self.alpha * test);
        let dist2 = |q: [f64; 3]| {
            (q[0] - g[0]) * (q[0] - g[0])
                + (q[1] - g[1]) * (q[1] - g[1])
                + (q[2] - g[2]) * (q[2] - g[2])
        };
        if p.iter().any(|&q| dist2(q) <= reach2) {
            return (g, Candidate3::Refused);
        }
        if g.iter().any(|&x| x != 0.0 && x.abs() < tiny) {
            // Beyond the exact range of the triangulation (a centroid creeping onto a zero
            // coordinate): not a point worth adding.
            return (g, Candidate3::Tiny);
        }
        (g, Candidate3::At { g, h, reach2 })
    }
}

/// What a tetrahedron proposes.
#[derive(Clone, Copy, Debug)]
enum Candidate3 {
    /// Nothing (not an element, or a node too close to its centroid).
    Refused,
    /// A centroid too close to a zero coordinate to be represented exactly (counted refused).
    Tiny,
    /// The spacing field gave a bad value at the centroid.
    BadSpacing { value: f64, at: [f64; 3] },
    /// Its centroid `g`, the spacing `h` there and the squared reach `(α·h)²`.
    At { g: [f64; 3], h: f64, reach2: f64 },
}

/// The bounding box of the mesh's vertices, for Hilbert keys of candidates.
struct Frame3 {
    lo: [f64; 3],
    scale: f64,
}

impl Frame3 {
    /// Key resolution: 10 bits per axis, so the key and a cell id fit in 62 bits.
    const CELLS: f64 = 1023.0;

    fn of(mesh: &Mesh3) -> Frame3 {
        let tri = mesh.ct.triangulation();
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for i in 0..tri.num_vertices() {
            let p = tri.vertex(VertexId(i as u32));
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        // One scale for the three axes keeps the curve's cells cubes.
        let w = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
        let scale = if w > 0.0 && w.is_finite() {
            Self::CELLS / w
        } else {
            0.0
        };
        Frame3 { lo, scale }
    }

    /// The Hilbert key of `p` on a 2^10 grid over the box (clamped): below 2^30.
    fn key(&self, p: [f64; 3]) -> u64 {
        let q =
            [0, 1, 2].map(|k| ((p[k] - self.lo[k]) * self.scale).clamp(0.0, Self::CELLS) as u32);
        D3::hilbert_key(&q)
    }
}

/// Regular tetrahedra of edge `h` in `volume`.
fn tetrahedra_in(volume: f64, h: f64) -> f64 {
    volume / (h * h * h / (6.0 * 2f64.sqrt()))
}

fn bad_spacing(value: f64, p: [f64; 3]) -> PointGenError {
    PointGenError::BadSpacing3 {
        value,
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

fn set(values: &mut Vec<f64>, v: VertexId, x: f64) {
    if values.len() <= v.index() {
        values.resize(v.index() + 1, f64::NAN);
    }
    values[v.index()] = x;
}

/// The spacing at every vertex of the domain: the field's value there, given the vertex's own
/// value (from the surface), or for vertices recovery gave none (external field points) the
/// mean length of their edges in the domain.
fn node_spacing3(mesh: &mut Mesh3, field: &SpacingField3) -> Result<Vec<f64>, PointGenError> {
    let tri = mesh.ct.triangulation();
    let n = tri.num_vertices();
    mesh.spacing.resize(n, f64::NAN);
    let mut sum = vec![0.0f64; n];
    let mut count = vec![0u32; n];
    for c in mesh.elements() {
        let v = tri.cell(c);
        for i in 0..4 {
            for j in i + 1..4 {
                let (pa, pb) = (tri.vertex(v[i]), tri.vertex(v[j]));
                let len =
                    ((pa[0] - pb[0]).powi(2) + (pa[1] - pb[1]).powi(2) + (pa[2] - pb[2]).powi(2))
                        .sqrt();
                for u in [v[i], v[j]] {
                    sum[u.index()] += len;
                    count[u.index()] += 1;
                }
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
                return Err(bad_spacing(h, p));
            }
            dp[i] = h;
        }
    }
    Ok(dp)
}
