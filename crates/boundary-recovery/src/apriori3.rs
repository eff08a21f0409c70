//! The paper's a-priori method in 3D (R7): a point for every boundary face, placed so that the
//! sphere through the face and the point holds no other point, which makes the face Delaunay by
//! construction.
//!
//! For a surface triangle with circumcentre `c`, circumradius `R`, unit normal `n` and mean edge
//! length `L`, the point is `c + s·h·n` on the side `s` (±1) of the domain, at the height
//! `h = √(2/3)·L` of a regular tetrahedron on the face, or lower (3/4, 1/2 of it) if the sphere
//! through the face and the point is not empty, or if another point lies within `h/4` of the
//! new one (on the sphere: the two triangles of a rectangle would get one point), or if the
//! point lies on the surface (a right triangle's circumcentre is the midpoint of its longest
//! edge, and where that edge is a cube's, or a wall meets a facet, the normal runs along the
//! next facet: a point in a surface triangle makes it unrecoverable). That sphere
//! has its centre at `c + s·σ·n` with `σ = (h² − R²)/(2h)` and radius `√(R² + σ²)`. Emptiness
//! is checked against every point known so far (surface points, field points and the a-priori
//! points already placed) through a uniform grid. Faces for which no height works (tight
//! corners, skinny faces whose circumsphere is large) are left to edge and face checking, which
//! also repairs anything the new points broke; the history says how many.

use crate::plc3::SurfaceTriangle;
use rustc_hash::FxHashMap as HashMap;

/// An a-priori point must be farther than this many times its height from every other point.
const NEAR: f64 = 0.25;

/// A uniform hash grid of points for ball queries.
struct Grid {
    cell: f64,
    buckets: HashMap<[i64; 3], Vec<[f64; 3]>>,
}

impl Grid {
    fn new(cell: f64) -> Grid {
        Grid {
            cell,
            buckets: HashMap::default(),
        }
    }

    fn key(&self, p: [f64; 3]) -> [i64; 3] {
        p.map(|x| (x / self.cell).floor() as i64)
    }

    fn add(&mut self, p: [f64; 3]) {
        let k = self.key(p);
        self.buckets.entry(k).or_default().push(p);
    }

    /// Whether some point other than `exclude` lies strictly inside the ball.
    fn any_inside(&self, centre: [f64; 3], radius: f64, exclude: &[[f64; 3]; 3]) -> bool {
        let lo = self.key(centre.map(|x| x - radius));
        let hi = self.key(centre.map(|x| x + radius));
        // A ball much larger than the grid spacing is not worth searching: treat as occupied.
        if (0..3).map(|k| (hi[k] - lo[k] + 1) as u64).product::<u64>() > 4096 {
            return true;
        }
        let r2 = radius * radius;
        for i in lo[0]..=hi[0] {
            for j in lo[1]..=hi[1] {
                for k in lo[2]..=hi[2] {
                    let Some(bucket) = self.buckets.get(&[i, j, k]) else {
                        continue;
                    };
                    for q in bucket {
                        if exclude.contains(q) {
                            continue;
                        }
                        let d = [q[0] - centre[0], q[1] - centre[1], q[2] - centre[2]];
                        if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < r2 {
                            return true;
                        }
                    }
                }
            }
        }
        false
    }
}

/// The a-priori points of `triangles` (corners in `points`, other points in `others`), placed
/// on side `side(k)` of triangle `k` (+1 along its normal, −1 against it, 0 for either, the
/// negative side tried first); and how many triangles got none.
pub(crate) fn a_priori_points(
    points: &[[f64; 3]],
    others: &[[f64; 3]],
    triangles: &[SurfaceTriangle],
    side: impl Fn(usize) -> f64,
    on_surface: impl Fn([f64; 3]) -> bool,
) -> (Vec<[f64; 3]>, usize) {
    let mean = triangles
        .iter()
        .map(|t| {
            let p = t.v.map(|i| points[i as usize]);
            (dist(p[0], p[1]) + dist(p[1], p[2]) + dist(p[2], p[0])) / 3.0
        })
        .sum::<f64>()
        / triangles.len().max(1) as f64;
    let mut grid = Grid::new(if mean > 0.0 { mean } else { 1.0 });
    for &p in points.iter().chain(others) {
        grid.add(p);
    }
    let mut placed = Vec::new();
    let mut rejected = 0;
    for (k, t) in triangles.iter().enumerate() {
        let p = t.v.map(|i| points[i as usize]);
        let Some((c, r, n)) = circle(p) else {
            rejected += 1;
            continue;
        };
        let length = (dist(p[0], p[1]) + dist(p[1], p[2]) + dist(p[2], p[0])) / 3.0;
        let sides: &[f64] = match side(k) {
            s if s > 0.0 => &[1.0],
            s if s < 0.0 => &[-1.0],
            _ => &[-1.0, 1.0],
        };
        let mut found = None;
        'search: for &s in sides {
            for f in [1.0, 0.75, 0.5] {
                let h = f * (2.0f64 / 3.0).sqrt() * length;
                let sigma = (h * h - r * r) / (2.0 * h);
                let centre = [0, 1, 2].map(|i| c[i] + s * sigma * n[i]);
                let radius = (r * r + sigma * sigma).sqrt();
                let q = [0, 1, 2].map(|i| c[i] + s * h * n[i]);
                // A point on the sphere is no obstacle to the face, but one at (or by) q would
                // be a near-duplicate: the two triangles of a rectangle have one circumcircle,
                // normal and mean edge length, so their points fell together (to rounding).
                // A point on the surface (another facet crossing the face's normal, as
                // walls between regions do) would sit inside a surface triangle.
                if !grid.any_inside(centre, radius, &p)
                    && !grid.any_inside(q, NEAR * h, &p)
                    && !on_surface(q)
                {
                    found = Some(q);
                    break 'search;
                }
            }
        }
        match found {
            Some(q) => {
                grid.add(q);
                placed.push(q);
            }
            None => rejected += 1,
        }
    }
    (placed, rejected)
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Circumcentre, circumradius and unit normal of a triangle (`None` if degenerate).
fn circle(p: [[f64; 3]; 3]) -> Option<([f64; 3], f64, [f64; 3])> {
    let a = p[0];
    let u = [p[1][0] - a[0], p[1][1] - a[1], p[1][2] - a[2]];
    let v = [p[2][0] - a[0], p[2][1] - a[1], p[2][2] - a[2]];
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if n2.is_nan() || n2 <= 0.0 {
        return None;
    }
    let (u2, v2) = (
        u[0] * u[0] + u[1] * u[1] + u[2] * u[2],
        v[0] * v[0] + v[1] * v[1] + v[2] * v[2],
    );
    // c − a = (|u|² (v × n) + |v|² (n × u)) / (2 |n|²).
    let vxn = [
        v[1] * n[2] - v[2] * n[1],
        v[2] * n[0] - v[0] * n[2],
        v[0] * n[1] - v[1] * n[0],
    ];
    let nxu = [
        n[1] * u[2] - n[2] * u[1],
        n[2] * u[0] - n[0] * u[2],
        n[0] * u[1] - n[1] * u[0],
    ];
    let d = [0, 1, 2].map(|k| (u2 * vxn[k] + v2 * nxu[k]) / (2.0 * n2));
    let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let len = n2.sqrt();
    Some(([0, 1, 2].map(|k| a[k] + d[k]), r, n.map(|x| x / len)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circumcircle_of_a_right_triangle() {
        let (c, r, n) = circle([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]).unwrap();
        assert_eq!(c, [1.0, 1.0, 0.0]);
        assert!((r - 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(n, [0.0, 0.0, 1.0]);
    }

    #[test]
    fn no_point_by_another_point_on_the_sphere() {
        // The two triangles of a rectangle have one circumcircle, normal and mean edge length:
        // the second point fell on the first (1e-16 apart in a thin slab's side). Here the
        // other point is a hair above where the face's point would go, outside its sphere.
        let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let t = [SurfaceTriangle {
            v: [0, 1, 2],
            marker: 0,
            facet: 0,
        }];
        let (alone, _) = a_priori_points(&points, &[], &t, |_| 1.0, |_| false);
        let q = alone[0];
        let other = [q[0], q[1], q[2] + 1e-9];
        let (placed, none) = a_priori_points(&points, &[other], &t, |_| 1.0, |_| false);
        assert_eq!((placed.len(), none), (1, 0));
        assert!(dist(placed[0], other) > 0.1 * q[2], "{placed:?} {other:?}");
    }

    #[test]
    fn a_point_per_face_on_the_requested_side() {
        let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let t = [SurfaceTriangle {
            v: [0, 1, 2],
            marker: 0,
            facet: 0,
        }];
        let (up, none) = a_priori_points(&points, &[], &t, |_| 1.0, |_| false);
        assert_eq!((up.len(), none), (1, 0));
        assert!(up[0][2] > 0.0);
        // A point above the face pushes that side's point lower; the other side is free.
        let blocker = [[0.3, 0.3, 0.6]];
        let (lower, _) = a_priori_points(&points, &blocker, &t, |_| 1.0, |_| false);
        assert!(
            lower[0][2] > 0.0 && lower[0][2] < 0.99 * up[0][2],
            "{lower:?} {up:?}"
        );
        let (down, _) = a_priori_points(&points, &blocker, &t, |_| 0.0, |_| false);
        assert!(down[0][2] < 0.0);
    }
}
