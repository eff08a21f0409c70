//! [`Smoother`]: Laplacian smoothing of a 2D triangle mesh given as flat arrays.

use delmesh_predicates::{orient2d, Sign};
use std::fmt;

/// How many times a rejected move is halved before the point is left where it is.
pub const MAX_HALVINGS: u32 = 4;

/// A move may lower the smallest angle around the point to this fraction of its old value.
const ANGLE_KEEP: f64 = 0.5;

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
    /// Largest displacement of a point in the last pass.
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
        // Point → triangles, point → neighbours (each edge once per direction).
        let incident = Rows::build(
            n,
            triangles
                .iter()
                .enumerate()
                .flat_map(|(k, t)| t.iter().map(move |&v| (v, k as u32))),
        );
        let mut pairs: Vec<(u32, u32)> = triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
            .flat_map(|(a, b)| [(a, b), (b, a)])
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        let neighbours = Rows::build(n, pairs.iter().copied());

        let mut stats = SmoothStats::default();
        for _ in 0..self.iterations {
            stats.passes += 1;
            let mut largest = 0.0f64;
            for v in 0..n {
                if fixed[v] || neighbours.row(v).is_empty() {
                    continue;
                }
                let x = points[v];
                let ring = neighbours.row(v);
                let (mut sx, mut sy) = (0.0, 0.0);
                for &u in ring {
                    sx += points[u as usize][0] - x[0];
                    sy += points[u as usize][1] - x[1];
                }
                let m = ring.len() as f64;
                let mut step = [self.omega * sx / m, self.omega * sy / m];
                // The move may lower the smallest angle around v to ANGLE_KEEP of its value;
                // compared through sines (the smallest angle of a triangle is at most 60°).
                let before = min_sine_around(points, triangles, incident.row(v));
                let floor = (ANGLE_KEEP * before.clamp(-1.0, 1.0).asin()).sin();
                let mut accepted = None;
                for halving in 0..=MAX_HALVINGS {
                    let y = [x[0] + step[0], x[1] + step[1]];
                    if y == x {
                        break;
                    }
                    points[v] = y;
                    let ok = incident.row(v).iter().all(|&k| {
                        let p = triangles[k as usize].map(|w| points[w as usize]);
                        orient2d(p[0], p[1], p[2]) == Sign::Positive
                    }) && min_sine_around(points, triangles, incident.row(v)) >= floor;
                    if ok {
                        accepted = Some(halving);
                        break;
                    }
                    step = [0.5 * step[0], 0.5 * step[1]];
                }
                match accepted {
                    Some(h) => {
                        if h == 0 {
                            stats.moved += 1;
                        } else {
                            stats.reduced += 1;
                        }
                        let y = points[v];
                        largest = largest.max((y[0] - x[0]).hypot(y[1] - x[1]));
                    }
                    None => {
                        points[v] = x;
                        stats.skipped += 1;
                    }
                }
            }
            stats.last_displacement = largest;
            if largest == 0.0 {
                break;
            }
        }
        Ok(stats)
    }
}

/// The sine of the smallest angle of the given triangles.
fn min_sine_around(points: &[[f64; 2]], triangles: &[[u32; 3]], ids: &[u32]) -> f64 {
    ids.iter()
        .map(|&k| min_sine(triangles[k as usize].map(|w| points[w as usize])))
        .fold(f64::INFINITY, f64::min)
}

/// The sine of a triangle's smallest angle: twice its area over the product of its two longest
/// edges (the smallest angle is opposite the shortest edge and at most 60°).
fn min_sine(p: [[f64; 2]; 3]) -> f64 {
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let (e0, e1, e2) = (d(p[1], p[2]), d(p[2], p[0]), d(p[0], p[1]));
    let shortest = e0.min(e1).min(e2);
    let twice_area =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    // Product of the two longest = sqrt(e_a · e_b) with e_a e_b = e0 e1 e2 / shortest.
    twice_area / (e0 * e1 * e2 / shortest).sqrt()
}

/// The angle at `o` between `u` and `w` (radians).
pub(crate) fn angle(o: [f64; 2], u: [f64; 2], w: [f64; 2]) -> f64 {
    let (ux, uy, wx, wy) = (u[0] - o[0], u[1] - o[1], w[0] - o[0], w[1] - o[1]);
    (ux * wy - uy * wx).abs().atan2(ux * wx + uy * wy)
}
