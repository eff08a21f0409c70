//! [`Smoother`]: Laplacian smoothing of a 2D triangle mesh given as flat arrays.

use delmesh_predicates::{orient2d, Sign};
use rayon::prelude::*;
use std::fmt;

/// How many times a rejected move is halved before the point is left where it is.
pub const MAX_HALVINGS: u32 = 4;

/// A move may shrink a triangle around the point to this fraction of its old area, no further.
const AREA_KEEP: f64 = 0.2;

/// Smoothing stops early once no point moves by more than this fraction of the (root mean
/// square) length of its edges in a pass.
const CONVERGED: f64 = 5e-3;

/// Bad smoothing options or input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SmoothError {
    /// ω must be in (0, 1].
    #[error("smoothing factor omega must be in (0, 1] (got {0})")]
    BadOmega(f64),
    /// The arrays do not fit together.
    #[error("smoothing input: {0}")]
    BadInput(String),
}

/// What a smoothing run did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SmoothStats {
    /// Passes made.
    pub passes: usize,
    /// Moves accepted at full length.
    pub moved: usize,
    /// Moves accepted after halving.
    pub reduced: usize,
    /// Moves refused (would invert or badly degrade an element).
    pub skipped: usize,
    /// Largest displacement of a point in the last pass, relative to the mean length of its
    /// edges.
    pub last_displacement: f64,
}

impl fmt::Display for SmoothStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} passes, {} moves, {} reduced, {} refused",
            self.passes, self.moved, self.reduced, self.skipped
        )
    }
}

/// Laplacian smoothing with relaxation factor ω and N passes; boundary points stay fixed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smoother {
    omega: f64,
    iterations: usize,
}

impl Default for Smoother {
    fn default() -> Self {
        Self::new()
    }
}

/// Compressed rows: `items[start[i]..start[i + 1]]` belong to row `i`.
struct Rows {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Rows {
    fn build(n: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) -> Rows {
        let mut start = vec![0u32; n + 1];
        for (r, _) in pairs.clone() {
            start[r as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; start[n] as usize];
        for (r, x) in pairs {
            items[fill[r as usize] as usize] = x;
            fill[r as usize] += 1;
        }
        Rows { start, items }
    }

    fn row(&self, i: usize) -> &[u32] {
        &self.items[self.start[i] as usize..self.start[i + 1] as usize]
    }
}

impl Smoother {
    /// ω = 0.2, N = 30 (the paper uses ω in 0.05–0.25, N in 20–50).
    pub fn new() -> Self {
        Smoother {
            omega: 0.2,
            iterations: 30,
        }
    }

    /// Sets the relaxation factor ω.
    ///
    /// # Errors
    /// ω outside (0, 1].
    pub fn omega(mut self, omega: f64) -> Result<Self, SmoothError> {
        if !(omega > 0.0 && omega <= 1.0) {
            return Err(SmoothError::BadOmega(omega));
        }
        self.omega = omega;
        Ok(self)
    }

    /// Sets the number of passes N.
    pub fn iterations(mut self, n: usize) -> Self {
        self.iterations = n;
        self
    }

    /// Smooths `points` in place. `triangles` are counter-clockwise; points with `fixed` set
    /// (the boundary) never move. Every triangle stays positively oriented.
    ///
    /// # Errors
    /// Lengths that do not match, an index out of range, a non-finite coordinate, or an input
    /// triangle that is not positively oriented.
    pub fn smooth(
        &self,
        points: &mut [[f64; 2]],
        triangles: &[[u32; 3]],
        fixed: &[bool],
    ) -> Result<SmoothStats, SmoothError> {
        let n = points.len();
        if fixed.len() != n {
            return Err(SmoothError::BadInput(format!(
                "{} points but {} fixed flags",
                n,
                fixed.len()
            )));
        }
        if let Some(i) = points
            .iter()
            .position(|p| !p[0].is_finite() || !p[1].is_finite())
        {
            return Err(SmoothError::BadInput(format!("point {i} is not finite")));
        }
        for (k, t) in triangles.iter().enumerate() {
            if t.iter().any(|&v| v as usize >= n) {
                return Err(SmoothError::BadInput(format!(
                    "triangle {k} names a point out of range"
                )));
            }
            let p = t.map(|v| points[v as usize]);
            if orient2d(p[0], p[1], p[2]) != Sign::Positive {
                return Err(SmoothError::BadInput(format!(
                    "triangle {k} is not counter-clockwise"
                )));
            }
        }
        // Work on a copy numbered along a space-filling curve, so that neighbours are close in
        // memory (the caller's numbering is often far from it), then copy the points back.
        let order = spatial_order(points);
        let mut rank = vec![0u32; n];
        for (i, &v) in order.iter().enumerate() {
            rank[v as usize] = i as u32;
        }
        let mut local: Vec<[f64; 2]> = order.iter().map(|&v| points[v as usize]).collect();
        let local_fixed: Vec<bool> = order.iter().map(|&v| fixed[v as usize]).collect();
        let local_tris: Vec<[u32; 3]> = triangles
            .iter()
            .map(|t| t.map(|v| rank[v as usize]))
            .collect();
        let stats = self.relax(&mut local, &local_tris, &local_fixed);
        for (i, &v) in order.iter().enumerate() {
            points[v as usize] = local[i];
        }
        Ok(stats)
    }

    /// The smoothing passes proper, on checked input.
    fn relax(
        &self,
        points: &mut [[f64; 2]],
        triangles: &[[u32; 3]],
        fixed: &[bool],
    ) -> SmoothStats {
        let n = points.len();
        // Point → triangles, point → neighbours (each edge once per direction).
        // For each point, the edges opposite it in its triangles, counter-clockwise: two row
        // sets filled in the same order (first and second end of each edge).
        let corners = || {
            triangles
                .iter()
                .flat_map(|t| (0..3).map(move |i| (t[i], t[(i + 1) % 3], t[(i + 2) % 3])))
        };
        let opposite_a = Rows::build(n, corners().map(|(v, a, _)| (v, a)));
        let opposite_b = Rows::build(n, corners().map(|(v, _, b)| (v, b)));
        let mut pairs: Vec<(u32, u32)> = triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
            .flat_map(|(a, b)| [(a, b), (b, a)])
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        let neighbours = Rows::build(n, pairs.iter().copied());

        // Points of one colour share no edge, so within a colour every move reads only points
        // that do not move: they are computed in parallel and applied together, which is
        // Gauss–Seidel in colour order, whatever the number of threads.
        let classes = colour_classes(&neighbours, fixed);
        let mut stats = SmoothStats::default();
        for _ in 0..self.iterations {
            stats.passes += 1;
            let mut largest = 0.0f64;
            for class in &classes {
                let moves: Vec<(u32, Option<([f64; 2], u32)>, f64)> = class
                    .par_iter()
                    .map(|&v| {
                        let (mv, ratio) =
                            self.propose(points, v as usize, &neighbours, &opposite_a, &opposite_b);
                        (v, mv, ratio)
                    })
                    .collect();
                for (v, mv, ratio) in moves {
                    match mv {
                        Some((y, halving)) => {
                            points[v as usize] = y;
                            if halving == 0 {
                                stats.moved += 1;
                            } else {
                                stats.reduced += 1;
                            }
                            largest = largest.max(ratio);
                        }
                        None => stats.skipped += 1,
                    }
                }
            }
            stats.last_displacement = largest.sqrt();
            if stats.last_displacement < CONVERGED {
                break;
            }
        }
        stats
    }
}

impl Smoother {
    /// The move of free point `v` towards the mean of its neighbours, halved until every
    /// triangle around it stays positive (exact) and keeps [`AREA_KEEP`] of its area (the edge
    /// opposite `v` is fixed, so a triangle's area is linear in `v`'s position): the new
    /// position and the number of halvings, or `None` if refused; and the squared move over the
    /// mean squared length of `v`'s edges.
    fn propose(
        &self,
        points: &[[f64; 2]],
        v: usize,
        neighbours: &Rows,
        opposite_a: &Rows,
        opposite_b: &Rows,
    ) -> (Option<([f64; 2], u32)>, f64) {
        let x = points[v];
        let ring = neighbours.row(v);
        let (mut sx, mut sy, mut ring_length2) = (0.0, 0.0, 0.0);
        for &u in ring {
            let q = points[u as usize];
            sx += q[0] - x[0];
            sy += q[1] - x[1];
            ring_length2 += (q[0] - x[0]) * (q[0] - x[0]) + (q[1] - x[1]) * (q[1] - x[1]);
        }
        let m = ring.len() as f64;
        let mut step = [self.omega * sx / m, self.omega * sy / m];
        for halving in 0..=MAX_HALVINGS {
            let y = [x[0] + step[0], x[1] + step[1]];
            if y == x {
                return (Some((x, halving)), 0.0);
            }
            let ok = opposite_a
                .row(v)
                .iter()
                .zip(opposite_b.row(v))
                .all(|(&ia, &ib)| {
                    let (a, b) = (points[ia as usize], points[ib as usize]);
                    let twice =
                        |q: [f64; 2]| (a[0] - q[0]) * (b[1] - q[1]) - (a[1] - q[1]) * (b[0] - q[0]);
                    twice(y) >= AREA_KEEP * twice(x) && orient2d(y, a, b) == Sign::Positive
                });
            if ok {
                let moved2 = step[0] * step[0] + step[1] * step[1];
                return (Some((y, halving)), moved2 / (ring_length2 / m));
            }
            step = [0.5 * step[0], 0.5 * step[1]];
        }
        (None, 0.0)
    }
}

/// The free points with neighbours, in classes of one colour each: a greedy colouring of the
/// neighbour graph, so no two points of a class share an edge. Points are in increasing order
/// within a class (memory order, which is spatial).
fn colour_classes(neighbours: &Rows, fixed: &[bool]) -> Vec<Vec<u32>> {
    let n = fixed.len();
    let mut colour = vec![u8::MAX; n];
    let mut classes: Vec<Vec<u32>> = Vec::new();
    for v in 0..n {
        if fixed[v] || neighbours.row(v).is_empty() {
            continue;
        }
        let mut used = 0u64;
        for &u in neighbours.row(v) {
            let c = colour[u as usize];
            if c < 64 {
                used |= 1 << c;
            }
        }
        let c = (!used).trailing_zeros() as usize;
        // More than 64 colours would need a degree over 63 on every colour; fall back to a
        // class of its own beyond that (still correct: the point then moves alone).
        let c = c.min(63);
        if c < 63 {
            colour[v] = c as u8;
        }
        if classes.len() <= c {
            classes.resize(c + 1, Vec::new());
        }
        if c == 63 {
            classes.push(vec![v as u32]);
        } else {
            classes[c].push(v as u32);
        }
    }
    classes
}

/// The angle at `o` between `u` and `w` (radians).
pub(crate) fn angle(o: [f64; 2], u: [f64; 2], w: [f64; 2]) -> f64 {
    let (ux, uy, wx, wy) = (u[0] - o[0], u[1] - o[1], w[0] - o[0], w[1] - o[1]);
    (ux * wy - uy * wx).abs().atan2(ux * wx + uy * wy)
}

/// The points' order along a Z-order (Morton) curve of 16 bits per axis.
fn spatial_order(points: &[[f64; 2]]) -> Vec<u32> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
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
    let spread = |x: u32| {
        let mut x = u64::from(x) & 0xFFFF;
        x = (x | (x << 8)) & 0x00FF_00FF;
        x = (x | (x << 4)) & 0x0F0F_0F0F;
        x = (x | (x << 2)) & 0x3333_3333;
        (x | (x << 1)) & 0x5555_5555
    };
    let mut keyed: Vec<(u64, u32)> = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let qx = ((p[0] - lo[0]) * scale[0]) as u32;
            let qy = ((p[1] - lo[1]) * scale[1]) as u32;
            (spread(qx) | (spread(qy) << 1), i as u32)
        })
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}
