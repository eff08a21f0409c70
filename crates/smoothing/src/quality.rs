//! [`QualityReport`]: the figures a CFD engineer checks before running a solver on a mesh.

use crate::laplace::angle;
use rayon::prelude::*;
use std::fmt;

/// Quality statistics of a triangle mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct QualityReport {
    /// Number of triangles.
    pub elements: usize,
    /// Smallest angle of any triangle (degrees).
    pub min_angle: f64,
    /// Largest angle of any triangle (degrees).
    pub max_angle: f64,
    /// Mean over triangles of their smallest angle (degrees).
    pub mean_min_angle: f64,
    /// Triangles whose smallest angle is in [0°, 10°), [10°, 20°), ..., [50°, 60°].
    pub min_angle_histogram: [usize; 6],
    /// Smallest triangle area.
    pub min_area: f64,
    /// Largest triangle area.
    pub max_area: f64,
    /// Sum of the areas.
    pub total_area: f64,
    /// Largest area ratio of two triangles sharing an edge (≥ 1).
    pub max_neighbour_area_ratio: f64,
    /// Mean area ratio over shared edges.
    pub mean_neighbour_area_ratio: f64,
}

/// Triangles per parallel task. Sums are combined task by task in order, so the report is the
/// same whatever the number of threads (and, below this size, the same as one sequential loop).
const CHUNK: usize = 1 << 14;

/// The per-triangle figures of one chunk.
struct Part {
    lo: f64,
    /// The largest angle's cosine, squared and signed (decreasing in the angle), and the
    /// triangle and vertex where it is.
    widest: (f64, usize, usize),
    sum_min: f64,
    histogram: [usize; 6],
    amin: f64,
    amax: f64,
    total_area: f64,
}

impl Part {
    /// Each triangle's smallest angle is opposite its shortest edge and its largest opposite its
    /// longest: one `atan2` per triangle, and one for the chunk's largest angle.
    fn of(points: &[[f64; 2]], triangles: &[[u32; 3]], first: usize, areas: &mut [f64]) -> Part {
        let mut r = Part {
            lo: f64::INFINITY,
            widest: (f64::INFINITY, usize::MAX, 0),
            sum_min: 0.0,
            histogram: [0; 6],
            amin: f64::INFINITY,
            amax: 0.0,
            total_area: 0.0,
        };
        for (k, (t, slot)) in triangles.iter().zip(areas).enumerate() {
            let p = t.map(|v| points.get(v as usize).copied().unwrap_or([f64::NAN; 2]));
            let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
            // Squared length of the edge opposite each vertex.
            let e = [d(p[1], p[2]), d(p[2], p[0]), d(p[0], p[1])];
            // Which edge is shortest and longest (the first of equals), without branches: the
            // comparisons are as likely one way as the other.
            let pick = |one: bool, two: bool| usize::from(one) + 2 * usize::from(two & !one);
            let shortest = pick(
                (e[1] < e[0]) & (e[1] <= e[2]),
                (e[2] < e[0]) & (e[2] < e[1]),
            );
            let longest = pick(
                (e[1] > e[0]) & (e[1] >= e[2]),
                (e[2] > e[0]) & (e[2] > e[1]),
            );
            let tmin = corner(p, shortest).to_degrees();
            r.lo = r.lo.min(tmin);
            r.sum_min += tmin;
            let bin = ((tmin / 10.0) as usize).min(5);
            r.histogram[bin] += 1;
            let (o, u, w) = (p[longest], p[NEXT[longest]], p[NEXT[NEXT[longest]]]);
            let dot = (u[0] - o[0]) * (w[0] - o[0]) + (u[1] - o[1]) * (w[1] - o[1]);
            let cos2 = dot * dot.abs() / (d(u, o) * d(w, o));
            if cos2 < r.widest.0 {
                r.widest = (cos2, first + k, longest);
            }
            let area = 0.5
                * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                    - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
            r.amin = r.amin.min(area);
            r.amax = r.amax.max(area);
            r.total_area += area;
            *slot = area;
        }
        r
    }
}

/// The next vertex of a triangle, counter-clockwise.
const NEXT: [usize; 3] = [1, 2, 0];

/// The angle of triangle `p` at its vertex `k` (radians).
fn corner(p: [[f64; 2]; 3], k: usize) -> f64 {
    angle(p[k], p[NEXT[k]], p[NEXT[NEXT[k]]])
}

impl QualityReport {
    /// Measures the triangles (counter-clockwise, indexing `points`). Triangles sharing an
    /// edge are found from the vertices; [`Self::of_mesh`] is faster when they are known.
    pub fn of_triangles(points: &[[f64; 2]], triangles: &[[u32; 3]]) -> QualityReport {
        Self::measure(points, triangles, None)
    }

    /// As [`Self::of_triangles`], with `neighbours[t][e]` the triangle across edge
    /// `(triangles[t][e], triangles[t][(e + 1) % 3])`, or `u32::MAX` on the border. The shared
    /// edges are then visited by triangle (same figures, summed in another order).
    ///
    /// # Panics
    /// If `neighbours` is not as long as `triangles`.
    pub fn of_mesh(
        points: &[[f64; 2]],
        triangles: &[[u32; 3]],
        neighbours: &[[u32; 3]],
    ) -> QualityReport {
        assert_eq!(
            neighbours.len(),
            triangles.len(),
            "one neighbour row per triangle"
        );
        Self::measure(points, triangles, Some(neighbours))
    }

    fn measure(
        points: &[[f64; 2]],
        triangles: &[[u32; 3]],
        neighbours: Option<&[[u32; 3]]>,
    ) -> QualityReport {
        let mut r = QualityReport {
            elements: triangles.len(),
            ..Default::default()
        };
        if triangles.is_empty() {
            return r;
        }
        let mut areas = vec![0.0f64; triangles.len()];
        let parts: Vec<Part> = triangles
            .par_chunks(CHUNK)
            .zip(areas.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, (t, a))| Part::of(points, t, c * CHUNK, a))
            .collect();
        let (mut lo, mut sum_min) = (f64::INFINITY, 0.0);
        let mut widest = (f64::INFINITY, usize::MAX, 0);
        let (mut amin, mut amax) = (f64::INFINITY, 0.0f64);
        for p in &parts {
            lo = lo.min(p.lo);
            if p.widest.0 < widest.0 {
                widest = p.widest;
            }
            sum_min += p.sum_min;
            for (h, c) in r.min_angle_histogram.iter_mut().zip(p.histogram) {
                *h += c;
            }
            amin = amin.min(p.amin);
            amax = amax.max(p.amax);
            r.total_area += p.total_area;
        }
        let hi = match widest {
            (_, usize::MAX, _) => 0.0,
            (_, t, k) => {
                let p =
                    triangles[t].map(|v| points.get(v as usize).copied().unwrap_or([f64::NAN; 2]));
                corner(p, k).to_degrees()
            }
        };
        r.min_angle = lo;
        r.max_angle = hi;
        r.mean_min_angle = sum_min / triangles.len() as f64;
        r.min_area = amin;
        r.max_area = amax;
        let (worst, sum, count) = match neighbours {
            Some(across) => ratios_across(across, &areas),
            None => neighbour_ratios(points.len(), triangles, &areas),
        };
        r.max_neighbour_area_ratio = worst;
        r.mean_neighbour_area_ratio = if count > 0 { sum / count as f64 } else { 1.0 };
        r
    }

    /// The report as a JSON object (keys in a fixed order; non-finite numbers as `null`).
    pub fn to_json(&self) -> String {
        let num = |x: f64| {
            if x.is_finite() {
                format!("{x}")
            } else {
                "null".to_string()
            }
        };
        format!(
            "{{\"elements\": {}, \"min_angle\": {}, \"max_angle\": {}, \"mean_min_angle\": {}, \
             \"min_angle_histogram\": [{}], \"min_area\": {}, \"max_area\": {}, \
             \"total_area\": {}, \"max_neighbour_area_ratio\": {}, \
             \"mean_neighbour_area_ratio\": {}}}",
            self.elements,
            num(self.min_angle),
            num(self.max_angle),
            num(self.mean_min_angle),
            self.min_angle_histogram
                .iter()
                .map(|c| c.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            num(self.min_area),
            num(self.max_area),
            num(self.total_area),
            num(self.max_neighbour_area_ratio),
            num(self.mean_neighbour_area_ratio),
        )
    }
}

impl fmt::Display for QualityReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "elements: {}", self.elements)?;
        writeln!(
            f,
            "angles: min {:.2}°, max {:.2}°, mean of minima {:.2}°",
            self.min_angle, self.max_angle, self.mean_min_angle
        )?;
        write!(f, "minimum-angle histogram:")?;
        for (k, c) in self.min_angle_histogram.iter().enumerate() {
            write!(f, " {}-{}°: {c}", 10 * k, 10 * (k + 1))?;
            if k < 5 {
                write!(f, ",")?;
            }
        }
        writeln!(f)?;
        writeln!(
            f,
            "areas: min {:.4e}, max {:.4e}, total {}; neighbour area ratio: max {:.2}, mean {:.3}",
            self.min_area,
            self.max_area,
            total(self.total_area),
            self.max_neighbour_area_ratio,
            self.mean_neighbour_area_ratio
        )
    }
}

/// The largest area ratio of two triangles sharing an edge, the sum of the ratios and their
/// number, over the shared edges in increasing order of (smaller vertex, larger vertex).
///
/// The sides of each edge are grouped under its smaller vertex (a counting sort), each group
/// sorted by the larger vertex and the triangle: consecutive sides of one edge are a pair.
fn neighbour_ratios(n: usize, triangles: &[[u32; 3]], areas: &[f64]) -> (f64, f64, usize) {
    // Vertices beyond the points (the report tolerates them) get rows too.
    let n = triangles
        .iter()
        .flatten()
        .map(|&v| v as usize + 1)
        .max()
        .unwrap_or(0)
        .max(n);
    let mut start = vec![0u32; n + 1];
    for t in triangles {
        for e in 0..3 {
            start[t[e].min(t[(e + 1) % 3]) as usize + 1] += 1;
        }
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut sides = vec![(0u32, 0u32); start[n] as usize];
    for (k, t) in triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            let row = a.min(b) as usize;
            sides[fill[row] as usize] = (a.max(b), k as u32);
            fill[row] += 1;
        }
    }
    drop(fill);
    let rows_per_task = (CHUNK / 2).max(1);
    let parts: Vec<(f64, f64, usize)> = (0..n.div_ceil(rows_per_task))
        .into_par_iter()
        .map(|task| {
            let rows = task * rows_per_task..((task + 1) * rows_per_task).min(n);
            let (mut worst, mut sum, mut count) = (1.0f64, 0.0, 0usize);
            let mut row: Vec<(u32, u32)> = Vec::new();
            for i in rows {
                row.clear();
                row.extend_from_slice(&sides[start[i] as usize..start[i + 1] as usize]);
                row.sort_unstable();
                for w in row.windows(2) {
                    if w[0].0 == w[1].0 {
                        let ratio = size_ratio(areas[w[0].1 as usize], areas[w[1].1 as usize]);
                        worst = worst.max(ratio);
                        sum += ratio;
                        count += 1;
                    }
                }
            }
            (worst, sum, count)
        })
        .collect();
    parts
        .into_iter()
        .fold((1.0f64, 0.0, 0usize), |(w, s, c), p| {
            (w.max(p.0), s + p.1, c + p.2)
        })
}

/// As [`neighbour_ratios`], from the triangles across each edge: each shared edge is visited
/// from its triangle with the smaller index, in parallel chunks summed in order.
fn ratios_across(across: &[[u32; 3]], areas: &[f64]) -> (f64, f64, usize) {
    let parts: Vec<(f64, f64, usize)> = across
        .par_chunks(CHUNK)
        .enumerate()
        .map(|(c, rows)| {
            let (mut worst, mut sum, mut count) = (1.0f64, 0.0, 0usize);
            for (i, row) in rows.iter().enumerate() {
                let t = c * CHUNK + i;
                for &n in row {
                    if n != u32::MAX && (n as usize) > t && (n as usize) < areas.len() {
                        let ratio = size_ratio(areas[t], areas[n as usize]);
                        worst = worst.max(ratio);
                        sum += ratio;
                        count += 1;
                    }
                }
            }
            (worst, sum, count)
        })
        .collect();
    parts
        .into_iter()
        .fold((1.0f64, 0.0, 0usize), |(w, s, c), p| {
            (w.max(p.0), s + p.1, c + p.2)
        })
}

/// The ratio of the larger to the smaller of two element sizes (areas or volumes, either sign):
/// 1 for two equal sizes, zeros too (elements so flat that their floating-point size is 0
/// gave NaN, and a NaN mean), infinite for a zero beside a non-zero.
pub(crate) fn size_ratio(x: f64, y: f64) -> f64 {
    let (x, y) = (x.abs(), y.abs());
    if x == y {
        1.0
    } else {
        x.max(y) / x.min(y)
    }
}

/// A total area or volume for the summary: six decimals for ordinary sizes, seven significant
/// digits in scientific notation for tiny or huge ones (a model in metres a millimetre across
/// printed as 0.000000 before).
pub(crate) fn total(x: f64) -> String {
    if x == 0.0 || (1e-3..1e6).contains(&x.abs()) {
        format!("{x:.6}")
    } else {
        format!("{x:.6e}")
    }
}
