//! Weatherill's automatic point generation (R10): centroid candidates accepted by the α test,
//! inserted by constrained Delaunay insertion, in passes until no candidate is accepted.
//!
//! Each pass looks at every element that existed when the pass began. Its candidate is the
//! centroid, with spacing `dp` from the [`SpacingField`] (interpolated from the element's nodes
//! by default, or from a background mesh). The candidate is inserted only if it is farther than
//! `α·dp` from every node of the element that contains it *now*: elements split earlier in the
//! same pass are seen as they are, so two candidates of neighbouring elements do not both go in
//! (the paper inserts each accepted point at once, with the same effect). The new node keeps
//! its `dp`. Insertion is constrained: a candidate never crosses or removes a boundary edge, and
//! one that rounding put on a boundary edge or outside its region is refused.

use crate::SpacingField;
use delmesh_boundary_recovery::{Mesh2, OUTSIDE};
use delmesh_delaunay_core::{CellId, ConstraintError, Insertion, VertexId};
use std::fmt;

/// Why point generation could not run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PointGenError {
    /// α must be a positive finite number.
    #[error("alpha must be positive and finite (got {0})")]
    BadAlpha(f64),
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
    /// A 3D candidate could not be inserted (a bad coordinate).
    #[error(transparent)]
    Insertion3(#[from] delmesh_delaunay_core::TriangulationError),
    /// An insertion failed (a bug in delmesh if it ever fires: candidates are inside).
    #[error(transparent)]
    Insertion(#[from] ConstraintError),
}

/// Settings of automatic point generation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointGeneration {
    /// α: a candidate must be farther than `α·dp` from the nodes; larger α, fewer points.
    pub alpha: f64,
    /// Stop after adding this many points.
    pub max_points: usize,
    /// Stop after this many passes.
    pub max_passes: usize,
}

impl Default for PointGeneration {
    fn default() -> Self {
        PointGeneration {
            alpha: 1.0,
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
    /// New nodes get their spacing in `mesh.spacing`.
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
        let mut dp = node_spacing(mesh, field)?;
        let mut report = GenerationReport::default();
        let mut added = 0usize;
        let mut cells: Vec<CellId> = Vec::new();
        while report.passes.len() < self.max_passes && added < self.max_points {
            cells.clear();
            cells.extend(mesh.elements());
            let mut accepted = 0;
            for &c in &cells {
                if added >= self.max_points {
                    break;
                }
                let tri = mesh.cdt.triangulation();
                let v = tri.cell(c);
                let tag = mesh.cdt.tag(c);
                if tag == OUTSIDE || v.iter().any(|u| u.is_ghost()) {
                    continue;
                }
                let p = [tri.vertex(v[0]), tri.vertex(v[1]), tri.vertex(v[2])];
                let g = [
                    (p[0][0] + p[1][0] + p[2][0]) / 3.0,
                    (p[0][1] + p[1][1] + p[2][1]) / 3.0,
                ];
                let from_nodes = (dp[v[0].index()] + dp[v[1].index()] + dp[v[2].index()]) / 3.0;
                let h = field.spacing(g, from_nodes);
                if !(h > 0.0 && h.is_finite()) {
                    return Err(PointGenError::BadSpacing {
                        value: h,
                        x: g[0],
                        y: g[1],
                    });
                }
                let reach = self.alpha * h;
                let reach2 = reach * reach;
                let dist2 =
                    |q: [f64; 2]| (q[0] - g[0]) * (q[0] - g[0]) + (q[1] - g[1]) * (q[1] - g[1]);
                // The element's own nodes first: most candidates fail here, before any walk.
                if p.iter().any(|&q| dist2(q) <= reach2) {
                    continue;
                }
                let inserted = mesh.cdt.insert_near_if(g, c, |cdt, cell, on_edge| {
                    if cdt.tag(cell) != tag || on_edge.is_some_and(|i| cdt.is_constrained(cell, i))
                    {
                        return false;
                    }
                    let t = cdt.triangulation();
                    t.cell(cell).iter().all(|&u| dist2(t.vertex(u)) > reach2)
                })?;
                if let Some(Insertion::Inserted(nv)) = inserted {
                    set(&mut dp, nv, h);
                    set(&mut mesh.spacing, nv, h);
                    accepted += 1;
                    added += 1;
                }
            }
            report.passes.push(GenerationPass {
                candidates: cells.len(),
                accepted,
                elements: mesh.num_elements(),
            });
            if accepted == 0 {
                break;
            }
        }
        Ok(report)
    }
}

fn set(values: &mut Vec<f64>, v: VertexId, x: f64) {
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
