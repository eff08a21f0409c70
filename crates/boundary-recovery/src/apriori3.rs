//! The paper's a-priori method in 3D (R7): a point for every boundary face, placed so that the
//! sphere through the face and the point holds no other point, which makes the face Delaunay by
//! construction.
//!
//! For a surface triangle with circumcentre `c`, circumradius `R`, unit normal `n` and mean edge
//! length `L`, the point is `f + s·h·n` on the side `s` (±1) of the domain, above the foot `f`:
//! the circumcentre, or, where that lies outside the triangle (an obtuse one), the midpoint of
//! the longest edge, the triangle's point nearest to it. Above the circumcentre of a needle the
//! point lay as far beside the face as `R` (1.25e10 for a 1e-11-high triangle in a unit cube)
//! and its sphere's radius was `R²/2h`. The point is at the height `h = √(2/3)·L` of a regular
//! tetrahedron on the face, or lower (3/4, 1/2 of it) if the sphere through the face and the
//! point is not empty, or if another point lies within `h/4` of the new one (on the sphere: the
//! two triangles of a rectangle would get one point), or if the point lies on the surface or
//! within `h/1000` of it (a right triangle's circumcentre is the midpoint of its longest edge,
//! and where that edge is a cube's, or a wall meets a facet, the normal runs along the next
//! facet: a point in a surface triangle makes it unrecoverable; where two surfaces touch at a
//! point, the normal of a face there can run into the other surface, and a point on it to
//! rounding made a flat tetrahedron or an unrecoverable edge). That sphere has its centre at `c + s·σ·n` with
//! `σ = (h² − R² + |f − c|²)/(2h)` and radius `√(R² + σ²)`, at least `R`. Emptiness is checked
//! against every point known so far (surface points, field points and the a-priori points
//! already placed) by the exact in-sphere test, on the points a uniform grid finds near the
//! sphere. Faces for which no height works (tight corners, skinny faces whose circumsphere is
//! large) are left to edge and face checking, which also repairs anything the new points
//! broke; the history says how many.

use crate::plc3::SurfaceTriangle;
use crate::recovery3::{dot, sub};
use delmesh_predicates::{insphere, orient3d, Sign};
use rustc_hash::FxHashMap as HashMap;

/// An a-priori point must be farther than this many times its height from every other point.
const NEAR: f64 = 0.25;

/// An a-priori point must be farther than this many times its height from every surface
/// triangle other than its face: closer, it makes a flat tetrahedron with the triangle (a
/// point rounded onto the surface, as where two surfaces touch, would even sit in it).
const CLEAR: f64 = 1e-3;

/// A ball spanning more grid cells than this is not searched: it counts as occupied.
const MAX_CELLS: f64 = 4096.0;

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

    /// The cell of `p`. Saturating past `i64` (a point beyond 2^63 cells) keeps the key
    /// monotonic in each coordinate, which is all the range search needs.
    fn key(&self, p: [f64; 3]) -> [i64; 3] {
        p.map(|x| (x / self.cell).floor() as i64)
    }

    fn add(&mut self, p: [f64; 3]) {
        let k = self.key(p);
        self.buckets.entry(k).or_default().push(p);
    }

    /// Whether `inside` holds for some point near the ball at `centre` of `radius` (every
    /// point in it is tried). A ball much larger than the grid spacing, or not finite, is not
    /// searched: it counts as occupied.
    fn any_inside(&self, centre: [f64; 3], radius: f64, inside: impl Fn([f64; 3]) -> bool) -> bool {
        // The ball is rounded: widened by far more than that for any face not flat to rounding,
        // so that the exact test sees every point it would find inside (what a point placed
        // next to a missed one breaks, checking repairs).
        let reach = radius + radius / 1024.0;
        // The cell range is counted in floating point first. In integers, a ball beyond i64's
        // cells (the sphere of a needle face, 1e20 across) saturated both ends, `hi − lo + 1`
        // wrapped to 0, the count passed and the loops ran over 2^64 cells per axis.
        let lo = centre.map(|x| ((x - reach) / self.cell).floor());
        let hi = centre.map(|x| ((x + reach) / self.cell).floor());
        let cells: f64 = (0..3).map(|k| hi[k] - lo[k] + 1.0).product();
        if cells.is_nan() || cells > MAX_CELLS {
            return true;
        }
        // At most MAX_CELLS cells, in the same monotonic keys as `key`.
        let (lo, hi) = (lo.map(|x| x as i64), hi.map(|x| x as i64));
        for i in lo[0]..=hi[0] {
            for j in lo[1]..=hi[1] {
                for k in lo[2]..=hi[2] {
                    let Some(bucket) = self.buckets.get(&[i, j, k]) else {
                        continue;
                    };
                    if bucket.iter().any(|&q| inside(q)) {
                        return true;
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
    near_surface: impl Fn([f64; 3], f64) -> bool,
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
        let (f, w2) = foot(p, c, r);
        let length = (dist(p[0], p[1]) + dist(p[1], p[2]) + dist(p[2], p[0])) / 3.0;
        let sides: &[f64] = match side(k) {
            s if s > 0.0 => &[1.0],
            s if s < 0.0 => &[-1.0],
            _ => &[-1.0, 1.0],
        };
        let mut found = None;
        'search: for &s in sides {
            for scale in [1.0, 0.75, 0.5] {
                let h = scale * (2.0f64 / 3.0).sqrt() * length;
                let q = [0, 1, 2].map(|i| f[i] + s * h * n[i]);
                // The point must lie off the face's plane on side `s`, exactly (the normal of
                // a face flat to rounding can point anywhere); its side orients the sphere.
                let turn = if q.iter().all(|x| x.is_finite()) {
                    orient3d(p[0], p[1], p[2], q)
                } else {
                    Sign::Zero
                };
                if turn != Sign::of(s) {
                    continue;
                }
                let sigma = (h * h - w2) / (2.0 * h);
                let centre = [0, 1, 2].map(|i| c[i] + s * sigma * n[i]);
                let radius = (r * r + sigma * sigma).sqrt();
                let in_sphere = |x| insphere(p[0], p[1], p[2], q, x) == turn;
                let near = |x| dist(x, q) < NEAR * h;
                // A point on the sphere is no obstacle to the face, but one at (or by) q would
                // be a near-duplicate: the two triangles of a rectangle have one circumcircle,
                // normal and mean edge length, so their points fell together (to rounding).
                // A point on the surface (another facet crossing the face's normal, as
                // walls between regions do) would sit inside a surface triangle.
                if !grid.any_inside(centre, radius, in_sphere)
                    && !grid.any_inside(q, NEAR * h, near)
                    && !near_surface(q, CLEAR * h)
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

/// The foot `f` of a face's point (see the module docs) and `R² − |f − c|²`, minus the power
/// of the foot with respect to the circumcircle: `R²` at the circumcentre, half the longest
/// edge squared at its midpoint (so, without cancelling two squares of a large circumradius).
/// The two feet agree at a right angle, so rounding in the choice moves the point by rounding.
fn foot(p: [[f64; 3]; 3], c: [f64; 3], r: f64) -> ([f64; 3], f64) {
    let edge = |k: usize| (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
    let (a, b, apex) = (0..3)
        .map(edge)
        .max_by(|x, y| dist(x.0, x.1).total_cmp(&dist(y.0, y.1)))
        .expect("three edges");
    if dot(sub(a, apex), sub(b, apex)) >= 0.0 {
        return (c, r * r);
    }
    let half = dist(a, b) / 2.0;
    ([0, 1, 2].map(|k| 0.5 * (a[k] + b[k])), half * half)
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
    use std::sync::mpsc;
    use std::time::Duration;

    /// `f`'s result, or a failure if it takes longer than `seconds` (instead of a test that
    /// never ends).
    fn within<T: Send + 'static>(seconds: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
        let (send, receive) = mpsc::channel();
        std::thread::spawn(move || send.send(f()));
        receive
            .recv_timeout(Duration::from_secs(seconds))
            .expect("finished")
    }

    /// A unit cube's corners and a point `height` off its top edge `y = 0` at `x`: the top
    /// triangle `[4, 5, 8]` is a needle.
    fn needle(x: f64, height: f64) -> Vec<[f64; 3]> {
        let mut points: Vec<[f64; 3]> = (0..8)
            .map(|c| [0, 1, 2].map(|k| f64::from((c >> k) & 1)))
            .collect();
        points.push([x, height, 1.0]);
        points
    }

    #[test]
    fn a_needle_face_gets_no_point_and_the_search_ends() {
        // Above the circumcentre of a 1e-11-high needle (1.25e10 away) the sphere's radius was
        // 1e20: its cell range saturated i64, the count of cells wrapped to 0 and the search
        // ran over 2^64 cells per axis. Its sphere is still at least the circumradius across:
        // too large to search, so the face is left to checking.
        for (x, height) in [(0.5, 1e-11), (0.3, 1e-14), (0.9, 1e-16), (0.5, 1e-10)] {
            let t = [SurfaceTriangle {
                v: [4, 5, 8],
                marker: 0,
                facet: 0,
            }];
            let points = needle(x, height);
            let (placed, none) = within(10, move || {
                a_priori_points(&points, &[], &t, |_| -1.0, |_, _| false)
            });
            assert_eq!((placed.len(), none), (0, 1), "{x} {height}: {placed:?}");
        }
    }

    #[test]
    fn balls_too_large_for_the_cells_are_occupied_and_far_ones_searched() {
        let any = |_| true;
        for radius in [1e20, 1e300, f64::MAX, f64::INFINITY, f64::NAN] {
            assert!(
                within(10, move || Grid::new(1.0).any_inside([0.0; 3], radius, any)),
                "{radius}"
            );
        }
        // Points beyond i64's cells share the last one (keys saturate), and are found there.
        let mut grid = Grid::new(1.0);
        for x in [1e25, f64::MAX] {
            grid.add([x, 0.0, 0.0]);
        }
        for x in [1e25, f64::MAX] {
            assert!(grid.any_inside([x, 0.0, 0.0], 0.5, |q| q[0] == x), "{x}");
            assert!(!grid.any_inside([x, 3.0, 0.0], 0.5, any), "{x}");
        }
    }

    #[test]
    fn an_obtuse_face_gets_its_point_above_it() {
        // The circumcentre lies 1.2 beyond the longest edge: the point goes above that edge's
        // midpoint, not beside the face, and its sphere's radius is 1.30 (R = 1.3), not 1.81.
        let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.1, 0.0]];
        let t = [SurfaceTriangle {
            v: [0, 1, 2],
            marker: 0,
            facet: 0,
        }];
        let (placed, none) = a_priori_points(&points, &[], &t, |_| 1.0, |_, _| false);
        assert_eq!((placed.len(), none), (1, 0));
        let q = placed[0];
        assert!(q[0] == 0.5 && q[1] == 0.0 && q[2] > 0.0, "{q:?}");
        let (c, r, _) = circle(points).unwrap();
        assert_eq!(foot(points, c, r), ([0.5, 0.0, 0.0], 0.25));
    }

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
        let (alone, _) = a_priori_points(&points, &[], &t, |_| 1.0, |_, _| false);
        let q = alone[0];
        let other = [q[0], q[1], q[2] + 1e-9];
        let (placed, none) = a_priori_points(&points, &[other], &t, |_| 1.0, |_, _| false);
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
        let (up, none) = a_priori_points(&points, &[], &t, |_| 1.0, |_, _| false);
        assert_eq!((up.len(), none), (1, 0));
        assert!(up[0][2] > 0.0);
        // A point above the face pushes that side's point lower; the other side is free.
        let blocker = [[0.3, 0.3, 0.6]];
        let (lower, _) = a_priori_points(&points, &blocker, &t, |_| 1.0, |_, _| false);
        assert!(
            lower[0][2] > 0.0 && lower[0][2] < 0.99 * up[0][2],
            "{lower:?} {up:?}"
        );
        let (down, _) = a_priori_points(&points, &blocker, &t, |_| 0.0, |_, _| false);
        assert!(down[0][2] < 0.0);
    }
}
