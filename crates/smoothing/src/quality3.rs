//! [`QualityReport3`]: the figures a CFD engineer checks on a tetrahedral mesh before running a
//! solver on it.
//!
//! Dihedral angles are the measure that matters most in 3D: a *sliver* (four nearly coplanar
//! points spread around a circle) has a good radius–edge ratio (about 0.71) but dihedral angles
//! near 0° and 180°, and it spoils the conditioning of finite-volume and finite-element
//! discretisations. The report gives both, so that a mesh whose radius–edge ratio looks fine but
//! which has slivers shows it. Volumes and the volume ratio of face neighbours tell how smoothly
//! the element size varies.
//!
//! Per-tetrahedron figures are computed in parallel (rayon) over fixed-size chunks whose
//! partial results are combined in chunk order, so every figure, sums included, is the same
//! whatever the number of threads.

use crate::tet::{dihedral_extremes, radius_edge, volume6, P3};
use delmesh_predicates::{orient3d, orient3d_value, Sign};
use rayon::prelude::*;
use std::fmt;

/// The largest possible smallest dihedral angle, that of the regular tetrahedron:
/// `acos(1/3)` in degrees.
pub const REGULAR_DIHEDRAL: f64 = 70.528_779_365_509_31;

/// A tetrahedron whose smallest dihedral angle is below this many degrees is counted as a
/// sliver by [`QualityReport3::slivers`].
pub const SLIVER_ANGLE: f64 = 5.0;

/// The bin edges (degrees) of [`QualityReport3::min_dihedral_histogram`]: bin `k` holds the
/// tetrahedra whose smallest dihedral angle is in `[EDGES[k], EDGES[k + 1])`, the last bin up to
/// and including [`REGULAR_DIHEDRAL`].
pub const DIHEDRAL_BIN_EDGES: [f64; 9] = [
    0.0,
    5.0,
    10.0,
    20.0,
    30.0,
    40.0,
    50.0,
    60.0,
    REGULAR_DIHEDRAL,
];

/// Tetrahedra per parallel work item: fixed, so that sums are added in the same order
/// whatever the number of threads.
const CHUNK: usize = 4096;

/// Quality statistics of a tetrahedral mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct QualityReport3 {
    /// Number of tetrahedra.
    pub elements: usize,
    /// Tetrahedra that are not positively oriented (exact `orient3d`: inverted or flat).
    pub non_positive: usize,
    /// Sum of the signed volumes.
    pub total_volume: f64,
    /// Smallest signed volume.
    pub min_volume: f64,
    /// Largest signed volume.
    pub max_volume: f64,
    /// Smallest dihedral angle of any tetrahedron (degrees).
    pub min_dihedral: f64,
    /// Largest dihedral angle of any tetrahedron (degrees).
    pub max_dihedral: f64,
    /// Mean over tetrahedra of their smallest dihedral angle (degrees).
    pub mean_min_dihedral: f64,
    /// Tetrahedra by smallest dihedral angle, in the bins of [`DIHEDRAL_BIN_EDGES`]
    /// (0–5°, 5–10°, 10–20°, …, 60–70.53°).
    pub min_dihedral_histogram: [usize; 8],
    /// Tetrahedra whose smallest dihedral angle is below [`SLIVER_ANGLE`].
    pub slivers: usize,
    /// Smallest circumradius / shortest edge (the regular tetrahedron's, √6/4 ≈ 0.612, is the
    /// least possible).
    pub min_radius_edge: f64,
    /// Largest circumradius / shortest edge (infinite if a tetrahedron is flat).
    pub max_radius_edge: f64,
    /// Mean circumradius / shortest edge.
    pub mean_radius_edge: f64,
    /// Largest ratio of the volumes of two tetrahedra sharing a face (≥ 1).
    pub max_neighbour_volume_ratio: f64,
    /// Mean of that ratio over shared faces (1 if none).
    pub mean_neighbour_volume_ratio: f64,
}

impl Default for QualityReport3 {
    fn default() -> Self {
        QualityReport3 {
            elements: 0,
            non_positive: 0,
            total_volume: 0.0,
            min_volume: 0.0,
            max_volume: 0.0,
            min_dihedral: 0.0,
            max_dihedral: 0.0,
            mean_min_dihedral: 0.0,
            min_dihedral_histogram: [0; 8],
            slivers: 0,
            min_radius_edge: 0.0,
            max_radius_edge: 0.0,
            mean_radius_edge: 0.0,
            max_neighbour_volume_ratio: 1.0,
            mean_neighbour_volume_ratio: 1.0,
        }
    }
}

/// The partial figures of a run of tetrahedra.
#[derive(Clone)]
struct Partial {
    non_positive: usize,
    total: f64,
    vmin: f64,
    vmax: f64,
    dmin: f64,
    dmax: f64,
    sum_min: f64,
    histogram: [usize; 8],
    slivers: usize,
    rmin: f64,
    rmax: f64,
    rsum: f64,
}

impl Partial {
    fn new() -> Partial {
        Partial {
            non_positive: 0,
            total: 0.0,
            vmin: f64::INFINITY,
            vmax: f64::NEG_INFINITY,
            dmin: f64::INFINITY,
            dmax: f64::NEG_INFINITY,
            sum_min: 0.0,
            histogram: [0; 8],
            slivers: 0,
            rmin: f64::INFINITY,
            rmax: f64::NEG_INFINITY,
            rsum: 0.0,
        }
    }

    fn add(&mut self, o: &Partial) {
        self.non_positive += o.non_positive;
        self.total += o.total;
        self.vmin = self.vmin.min(o.vmin);
        self.vmax = self.vmax.max(o.vmax);
        self.dmin = self.dmin.min(o.dmin);
        self.dmax = self.dmax.max(o.dmax);
        self.sum_min += o.sum_min;
        for (h, x) in self.histogram.iter_mut().zip(o.histogram) {
            *h += x;
        }
        self.slivers += o.slivers;
        self.rmin = self.rmin.min(o.rmin);
        self.rmax = self.rmax.max(o.rmax);
        self.rsum += o.rsum;
    }
}

/// Volume ratios of face neighbours: the largest, their sum and how many shared faces.
#[derive(Clone, Copy)]
struct Ratios {
    worst: f64,
    sum: f64,
    shared: usize,
}

impl Ratios {
    const NONE: Ratios = Ratios {
        worst: 1.0,
        sum: 0.0,
        shared: 0,
    };

    /// Counts the face shared by tetrahedra of volumes `x` and `y`.
    fn add(&mut self, x: f64, y: f64) {
        let ratio = crate::quality::size_ratio(x, y);
        self.worst = self.worst.max(ratio);
        self.sum += ratio;
        self.shared += 1;
    }

    fn merge(self, o: Ratios) -> Ratios {
        Ratios {
            worst: self.worst.max(o.worst),
            sum: self.sum + o.sum,
            shared: self.shared + o.shared,
        }
    }
}

/// As [`neighbour_ratios`], from the neighbour rows: each shared face is visited once, from
/// its lower-numbered tetrahedron, in parallel over fixed chunks.
fn ratios_across(neighbours: &[[u32; 4]], volumes: &[f64]) -> Ratios {
    let runs: Vec<Ratios> = neighbours
        .par_chunks(CHUNK)
        .enumerate()
        .map(|(c, rows)| {
            let mut r = Ratios::NONE;
            for (i, row) in rows.iter().enumerate() {
                let t = c * CHUNK + i;
                // Each shared face once, from its lower-numbered side.
                for &u in row
                    .iter()
                    .filter(|&&u| (u as usize) > t && (u as usize) < volumes.len())
                {
                    r.add(volumes[t], volumes[u as usize]);
                }
            }
            r
        })
        .collect();
    runs.into_iter().fold(Ratios::NONE, Ratios::merge)
}

/// The volume ratios of face neighbours, the shared faces found by sorting.
///
/// Faces are bucketed by their smallest vertex (a counting sort), so each bucket is a few
/// dozen faces sorted on their own, in parallel over fixed runs of buckets. Tetrahedra naming a
/// point out of range are left out.
fn neighbour_ratios(n: usize, tets: &[[u32; 4]], volumes: &[f64]) -> Ratios {
    let faces = |t: [u32; 4]| {
        (0..4).map(move |i| {
            let mut f = [t[(i + 1) % 4], t[(i + 2) % 4], t[(i + 3) % 4]];
            f.sort_unstable();
            f
        })
    };
    let in_range = |t: &&[u32; 4]| t.iter().all(|&v| (v as usize) < n);
    let mut start = vec![0usize; n + 1];
    for t in tets.iter().filter(in_range) {
        for f in faces(*t) {
            start[f[0] as usize + 1] += 1;
        }
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    // Within bucket f[0]: the other two vertices as one key, and the tetrahedron.
    let mut items = vec![(0u64, 0u32); start[n]];
    let mut fill = start.clone();
    for (k, t) in tets.iter().enumerate().filter(|(_, t)| in_range(t)) {
        for f in faces(*t) {
            let slot = &mut fill[f[0] as usize];
            items[*slot] = ((u64::from(f[1]) << 32) | u64::from(f[2]), k as u32);
            *slot += 1;
        }
    }
    let runs: Vec<Ratios> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|run| {
            let mut r = Ratios::NONE;
            let mut bucket = Vec::new();
            for v in run * CHUNK..((run + 1) * CHUNK).min(n) {
                bucket.clear();
                bucket.extend_from_slice(&items[start[v]..start[v + 1]]);
                bucket.sort_unstable();
                for w in bucket.windows(2) {
                    if w[0].0 == w[1].0 {
                        r.add(volumes[w[0].1 as usize], volumes[w[1].1 as usize]);
                    }
                }
            }
            r
        })
        .collect();
    runs.into_iter().fold(Ratios::NONE, Ratios::merge)
}

/// The histogram bin of a smallest dihedral angle (NaN in the first).
fn bin(angle: f64) -> usize {
    DIHEDRAL_BIN_EDGES[1..8]
        .iter()
        .position(|&e| angle.is_nan() || angle < e)
        .unwrap_or(7)
}

impl QualityReport3 {
    /// Measures the tetrahedra (positively oriented, indexing `points`).
    ///
    /// A tetrahedron naming a point out of range is measured with NaN coordinates: it counts as
    /// non-positive and as a sliver, and turns the sums and means NaN (`null` in JSON), so the
    /// report shows it instead of hiding it.
    pub fn of_tetrahedra(points: &[[f64; 3]], tets: &[[u32; 4]]) -> QualityReport3 {
        Self::measure(points, tets, None)
    }

    /// As [`Self::of_tetrahedra`], with `neighbours[t][k]` the tetrahedron across the face of
    /// `tets[t]` opposite its vertex `k`, or `u32::MAX` on the border: the shared faces are
    /// then read from it instead of found by sorting (same figures, summed in another order).
    /// Rows that are not one per tetrahedron are not used (the faces are sorted instead).
    pub fn of_mesh(
        points: &[[f64; 3]],
        tets: &[[u32; 4]],
        neighbours: &[[u32; 4]],
    ) -> QualityReport3 {
        Self::measure(
            points,
            tets,
            Some(neighbours).filter(|n| n.len() == tets.len()),
        )
    }

    fn measure(
        points: &[[f64; 3]],
        tets: &[[u32; 4]],
        neighbours: Option<&[[u32; 4]]>,
    ) -> QualityReport3 {
        let mut r = QualityReport3 {
            elements: tets.len(),
            ..Default::default()
        };
        if tets.is_empty() {
            return r;
        }
        let corner = |v: u32| points.get(v as usize).copied().unwrap_or([f64::NAN; 3]);
        let (volumes, partials): (Vec<Vec<f64>>, Vec<Partial>) = tets
            .par_chunks(CHUNK)
            .map(|chunk| {
                let mut part = Partial::new();
                let mut vols = Vec::with_capacity(chunk.len());
                for t in chunk {
                    let p: [P3; 4] = t.map(corner);
                    let sign = orient3d(p[0], p[1], p[2], p[3]);
                    if sign != Sign::Positive {
                        part.non_positive += 1;
                    }
                    let mut vol = volume6(&p) / 6.0;
                    // A tetrahedron flat to rounding: its floating-point volume can be 0 or of
                    // the wrong sign, beside the exact count above. The exact expansion's
                    // leading term then (rare: only there).
                    if Sign::of(vol) != sign && vol.is_finite() {
                        vol = orient3d_value(p[0], p[1], p[2], p[3]) / 6.0;
                    }
                    vols.push(vol);
                    part.total += vol;
                    part.vmin = part.vmin.min(vol);
                    part.vmax = part.vmax.max(vol);
                    let (lo, hi) = dihedral_extremes(&p);
                    part.dmin = part.dmin.min(lo);
                    part.dmax = part.dmax.max(hi);
                    part.sum_min += lo;
                    part.histogram[bin(lo)] += 1;
                    if lo.is_nan() || lo < SLIVER_ANGLE {
                        part.slivers += 1;
                    }
                    let re = radius_edge(&p);
                    part.rmin = part.rmin.min(re);
                    part.rmax = part.rmax.max(re);
                    part.rsum += re;
                }
                (vols, part)
            })
            .unzip();
        let mut all = Partial::new();
        for p in &partials {
            all.add(p);
        }
        let count = tets.len() as f64;
        r.non_positive = all.non_positive;
        r.total_volume = all.total;
        r.min_volume = all.vmin;
        r.max_volume = all.vmax;
        r.min_dihedral = all.dmin;
        r.max_dihedral = all.dmax;
        r.mean_min_dihedral = all.sum_min / count;
        r.min_dihedral_histogram = all.histogram;
        r.slivers = all.slivers;
        r.min_radius_edge = all.rmin;
        r.max_radius_edge = all.rmax;
        r.mean_radius_edge = all.rsum / count;
        let volumes: Vec<f64> = volumes.concat();
        // Shared faces: from the neighbour rows, or by sorting the faces.
        let ratios = match neighbours {
            Some(n) => ratios_across(n, &volumes),
            None => neighbour_ratios(points.len(), tets, &volumes),
        };
        r.max_neighbour_volume_ratio = ratios.worst;
        r.mean_neighbour_volume_ratio = if ratios.shared > 0 {
            ratios.sum / ratios.shared as f64
        } else {
            1.0
        };
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
            "{{\"elements\": {}, \"non_positive\": {}, \"total_volume\": {}, \
             \"min_volume\": {}, \"max_volume\": {}, \"min_dihedral\": {}, \
             \"max_dihedral\": {}, \"mean_min_dihedral\": {}, \
             \"min_dihedral_histogram\": [{}], \"slivers\": {}, \"min_radius_edge\": {}, \
             \"max_radius_edge\": {}, \"mean_radius_edge\": {}, \
             \"max_neighbour_volume_ratio\": {}, \"mean_neighbour_volume_ratio\": {}}}",
            self.elements,
            self.non_positive,
            num(self.total_volume),
            num(self.min_volume),
            num(self.max_volume),
            num(self.min_dihedral),
            num(self.max_dihedral),
            num(self.mean_min_dihedral),
            self.min_dihedral_histogram
                .iter()
                .map(|c| c.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            self.slivers,
            num(self.min_radius_edge),
            num(self.max_radius_edge),
            num(self.mean_radius_edge),
            num(self.max_neighbour_volume_ratio),
            num(self.mean_neighbour_volume_ratio),
        )
    }
}

impl fmt::Display for QualityReport3 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "tetrahedra: {} ({} not positive, {} slivers under {}°)",
            self.elements, self.non_positive, self.slivers, SLIVER_ANGLE
        )?;
        writeln!(
            f,
            "dihedral angles: min {:.2}°, max {:.2}°, mean of minima {:.2}°",
            self.min_dihedral, self.max_dihedral, self.mean_min_dihedral
        )?;
        write!(f, "minimum-dihedral histogram:")?;
        for (k, c) in self.min_dihedral_histogram.iter().enumerate() {
            let (lo, hi) = (DIHEDRAL_BIN_EDGES[k], DIHEDRAL_BIN_EDGES[k + 1]);
            if k < 7 {
                write!(f, " {lo}-{hi}°: {c},")?;
            } else {
                write!(f, " {lo}-{hi:.2}°: {c}")?;
            }
        }
        writeln!(f)?;
        writeln!(
            f,
            "radius-edge ratio: min {:.3}, max {:.3}, mean {:.3} (regular: 0.612)",
            self.min_radius_edge, self.max_radius_edge, self.mean_radius_edge
        )?;
        writeln!(
            f,
            "volumes: min {:.4e}, max {:.4e}, total {}; neighbour volume ratio: max {:.2}, mean {:.3}",
            self.min_volume,
            self.max_volume,
            crate::quality::total(self.total_volume),
            self.max_neighbour_volume_ratio,
            self.mean_neighbour_volume_ratio
        )
    }
}

/// The smallest and largest dihedral angles of the tetrahedron `p`, in degrees (as the report
/// measures them: accurate near 0° and 180°; a degenerate face gives 0° and 180°).
pub fn dihedral_range(p: &[[f64; 3]; 4]) -> (f64, f64) {
    crate::tet::dihedral_extremes(p)
}

/// The cosine of the smallest dihedral angle of the tetrahedron `p` (1 for a degenerate
/// face): cheaper than [`dihedral_range`] where only comparisons are needed.
pub fn min_dihedral_cosine(p: &[[f64; 3]; 4]) -> f64 {
    crate::tet::min_dihedral_cos(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins() {
        assert_eq!(bin(0.0), 0);
        assert_eq!(bin(4.999), 0);
        assert_eq!(bin(5.0), 1);
        assert_eq!(bin(19.0), 2);
        assert_eq!(bin(60.0), 7);
        assert_eq!(bin(REGULAR_DIHEDRAL), 7);
        assert_eq!(bin(f64::NAN), 0);
        assert!((REGULAR_DIHEDRAL - (1.0f64 / 3.0).acos().to_degrees()).abs() < 1e-12);
    }

    #[test]
    fn neighbour_rows_give_the_same_report_as_the_face_sort() {
        // A jittered grid of cubes, six tetrahedra each (Kuhn), so shared faces abound.
        let n = 5;
        let id = |i: u32, j: u32, k: u32| (i * (n + 1) + j) * (n + 1) + k;
        let mut points = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                for k in 0..=n {
                    let w = f64::from(id(i, j, k) % 7) * 0.01;
                    points.push([f64::from(i) + w, f64::from(j) - w, f64::from(k) + 0.5 * w]);
                }
            }
        }
        let mut tets = Vec::new();
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let c = |d: [u32; 3]| id(i + d[0], j + d[1], k + d[2]);
                    for path in [
                        [0, 1, 2],
                        [0, 2, 1],
                        [1, 0, 2],
                        [1, 2, 0],
                        [2, 0, 1],
                        [2, 1, 0],
                    ] {
                        let mut d = [0u32; 3];
                        let mut t = [c(d); 4];
                        for (s, &axis) in path.iter().enumerate() {
                            d[axis] = 1;
                            t[s + 1] = c(d);
                        }
                        let p = t.map(|v| points[v as usize]);
                        if orient3d(p[0], p[1], p[2], p[3]) != Sign::Positive {
                            t.swap(0, 1);
                        }
                        tets.push(t);
                    }
                }
            }
        }
        // Neighbour rows by brute force.
        let mut by_face = std::collections::HashMap::new();
        for (t, v) in tets.iter().enumerate() {
            for k in 0..4 {
                let mut f: Vec<u32> = (0..4).filter(|&m| m != k).map(|m| v[m]).collect();
                f.sort_unstable();
                by_face.entry(f).or_insert_with(Vec::new).push((t, k));
            }
        }
        let mut rows = vec![[u32::MAX; 4]; tets.len()];
        for sides in by_face.values() {
            if let [(a, i), (b, j)] = sides[..] {
                rows[a][i] = b as u32;
                rows[b][j] = a as u32;
            }
        }
        let sorted = QualityReport3::of_tetrahedra(&points, &tets);
        let rowed = QualityReport3::of_mesh(&points, &tets, &rows);
        assert_eq!(
            rowed.max_neighbour_volume_ratio,
            sorted.max_neighbour_volume_ratio
        );
        let mean = |r: &QualityReport3| r.mean_neighbour_volume_ratio;
        assert!((mean(&rowed) - mean(&sorted)).abs() < 1e-12 * mean(&sorted));
        assert!(rowed.max_neighbour_volume_ratio > 1.0);
        let strip = |mut r: QualityReport3| {
            r.mean_neighbour_volume_ratio = 0.0;
            r
        };
        // Rows that are not one per tetrahedron are not used: the faces are sorted.
        let short = QualityReport3::of_mesh(&points, &tets, &rows[1..]);
        assert_eq!(strip(rowed), strip(sorted.clone()));
        assert_eq!(short, sorted);
    }
}
