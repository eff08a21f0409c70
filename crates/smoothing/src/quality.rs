//! [`QualityReport`]: the figures a CFD engineer checks before running a solver on a mesh.

use crate::laplace::angle;
use rayon::slice::ParallelSliceMut;
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

impl QualityReport {
    /// Measures the triangles (counter-clockwise, indexing `points`).
    pub fn of_triangles(points: &[[f64; 2]], triangles: &[[u32; 3]]) -> QualityReport {
        let mut r = QualityReport {
            elements: triangles.len(),
            ..Default::default()
        };
        if triangles.is_empty() {
            return r;
        }
        let (mut lo, mut hi, mut sum_min) = (f64::INFINITY, 0.0f64, 0.0);
        let (mut amin, mut amax) = (f64::INFINITY, 0.0f64);
        let mut areas = Vec::with_capacity(triangles.len());
        for t in triangles {
            let p = t.map(|v| points.get(v as usize).copied().unwrap_or([f64::NAN; 2]));
            let angles: Vec<f64> = (0..3)
                .map(|k| angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]).to_degrees())
                .collect();
            let tmin = angles.iter().copied().fold(f64::INFINITY, f64::min);
            let tmax = angles.iter().copied().fold(0.0, f64::max);
            lo = lo.min(tmin);
            hi = hi.max(tmax);
            sum_min += tmin;
            let bin = ((tmin / 10.0) as usize).min(5);
            r.min_angle_histogram[bin] += 1;
            let area = 0.5
                * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                    - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
            amin = amin.min(area);
            amax = amax.max(area);
            r.total_area += area;
            areas.push(area);
        }
        r.min_angle = lo;
        r.max_angle = hi;
        r.mean_min_angle = sum_min / triangles.len() as f64;
        r.min_area = amin;
        r.max_area = amax;
        // Shared edges: sort the (edge, triangle) pairs so the two sides of an edge meet.
        let mut sides: Vec<(u64, u32)> = triangles
            .iter()
            .enumerate()
            .flat_map(|(k, t)| {
                (0..3).map(move |e| {
                    let (a, b) = (t[e], t[(e + 1) % 3]);
                    ((u64::from(a.min(b)) << 32) | u64::from(a.max(b)), k as u32)
                })
            })
            .collect();
        sides.par_sort_unstable();
        let (mut worst, mut sum, mut count) = (1.0f64, 0.0, 0usize);
        for w in sides.windows(2) {
            if w[0].0 == w[1].0 {
                let (x, y) = (areas[w[0].1 as usize].abs(), areas[w[1].1 as usize].abs());
                let ratio = x.max(y) / x.min(y);
                worst = worst.max(ratio);
                sum += ratio;
                count += 1;
            }
        }
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
            "areas: min {:.4e}, max {:.4e}, total {:.6}; neighbour area ratio: max {:.2}, mean {:.3}",
            self.min_area,
            self.max_area,
            self.total_area,
            self.max_neighbour_area_ratio,
            self.mean_neighbour_area_ratio
        )
    }
}
