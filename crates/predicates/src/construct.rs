//! Circumcentres computed exactly and rounded at the end: the fallback of delmesh's
//! floating-point circumcentres where their error bound is not small enough.
//!
//! A circumcentre is a rational function of the coordinates: with `B, C, E` the edge vectors
//! from the first point `a`, `o = a + N / (2·det)` where `det` is the orientation determinant
//! and `N` a polynomial of degree 3 (2D) or 4 (3D). As in [`crate::integer`], the coordinates
//! of one call are integers at a common power-of-two scale, so `a·2det + N` and `2det` are
//! computed exactly in [`Big`]; each is then rounded to `f64` once, and their quotient once
//! more: every coordinate is within 1.5 units in the last place of the exact one, whatever
//! the cell's shape and the scales of its points (a cluster of points 1e-12 apart next to
//! points 1e6 away, where the floating-point edge vectors from a far point coincide).
//!
//! This is a construction, not a predicate: nothing here decides topology.

use crate::bigint::Big;
use crate::integer::{exponents, to_big, BIG_B};
use crate::Sign;

/// The circumcentre of the triangle `a, b, c`, computed exactly and rounded (each coordinate
/// within 1.5 ulp). `None` for collinear points, or coordinates spanning more than
/// [`crate::COORDINATE_RANGE`] allows (or not finite).
pub fn circumcenter2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Option<[f64; 2]> {
    let (k, lo) = integers(&[a[0], a[1], b[0], b[1], c[0], c[1]])?;
    let [ax, ay, bx, by, cx, cy] = k;
    let (bx, by, cx, cy) = (bx - ax, by - ay, cx - ax, cy - ay);
    let det = bx * cy - by * cx;
    if det.sign() == Sign::Zero {
        return None;
    }
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    let den = det + det;
    Some([
        quotient(ax * den + (cy * b2 - by * c2), den, lo),
        quotient(ay * den + (bx * c2 - cx * b2), den, lo),
    ])
}

/// The circumcentre of the tetrahedron `a, b, c, d`, computed exactly and rounded (each
/// coordinate within 1.5 ulp). `None` for coplanar points, or coordinates spanning more than
/// [`crate::COORDINATE_RANGE`] allows (or not finite).
pub fn circumcenter3(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Option<[f64; 3]> {
    let (k, lo) = integers(&[
        a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2],
    ])?;
    let o = [k[0], k[1], k[2]];
    let edge = |i: usize| [k[i] - o[0], k[i + 1] - o[1], k[i + 2] - o[2]];
    let (b, c, e) = (edge(3), edge(6), edge(9));
    let cross = |u: [Big; 3], v: [Big; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let lift = |u: [Big; 3]| u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    let (ce, eb, bc) = (cross(c, e), cross(e, b), cross(b, c));
    let det = b[0] * ce[0] + b[1] * ce[1] + b[2] * ce[2];
    if det.sign() == Sign::Zero {
        return None;
    }
    let (b2, c2, e2) = (lift(b), lift(c), lift(e));
    let den = det + det;
    Some(std::array::from_fn(|i| {
        quotient(o[i] * den + (b2 * ce[i] + c2 * eb[i] + e2 * bc[i]), den, lo)
    }))
}

/// The coordinates as integers `x / 2^lo`, and `lo`; `None` if they are all zero, not finite,
/// or span more than [`BIG_B`] bits (then some product could exceed [`Big`]'s capacity).
///
/// Size bound: with `|k| < 2^n`, `n ≤ 400`, edge vectors are below `2^401` (7 limbs), their
/// cross products and squared lengths below `2^804` (13 limbs), the 3D determinant below
/// `2^1206` (19 limbs); the largest products (13 + 13 and 7 + 19 limbs) and every sum stay
/// within the 32 limbs.
fn integers<const M: usize>(x: &[f64; M]) -> Option<([Big; M], i32)> {
    let (lo, hi) = exponents(x)?;
    if lo == i32::MAX || hi - lo > BIG_B {
        return None;
    }
    Some((x.map(|v| to_big(v, lo)), lo))
}

/// `num / den · 2^lo`, rounded: each integer to the nearest `f64`, then their quotient.
fn quotient(num: Big, den: Big, lo: i32) -> f64 {
    let (n, en) = num.rounded();
    let (d, ed) = den.rounded();
    times_power_of_two(n / d, en - ed + lo)
}

/// `x · 2^e` for any `e` (in steps that stay finite), rounded once unless subnormal.
fn times_power_of_two(mut x: f64, mut e: i32) -> f64 {
    while e > 1000 {
        x *= 2f64.powi(1000);
        e -= 1000;
    }
    while e < -1000 {
        x *= 2f64.powi(-1000);
        e += 1000;
    }
    x * 2f64.powi(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simple_centres_are_exact() {
        assert_eq!(
            circumcenter2([0.0, 0.0], [2.0, 0.0], [0.0, 2.0]),
            Some([1.0, 1.0])
        );
        assert_eq!(
            circumcenter3([0.0; 3], [2.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 6.0]),
            Some([1.0, 2.0, 3.0])
        );
        // Far from the origin, and tiny.
        let s = 2f64.powi(-30);
        assert_eq!(
            circumcenter2([1e6, 1e6], [1e6 + 2.0 * s, 1e6], [1e6, 1e6 + 2.0 * s]),
            Some([1e6 + s, 1e6 + s])
        );
        let s = 2f64.powi(-140);
        assert_eq!(
            circumcenter2([s, s], [3.0 * s, s], [s, 5.0 * s]),
            Some([2.0 * s, 3.0 * s])
        );
        assert_eq!(circumcenter2([0.0; 2], [1.0, 1.0], [2.0, 2.0]), None);
        assert_eq!(circumcenter2([0.0; 2], [0.0; 2], [0.0; 2]), None);
        assert_eq!(
            circumcenter3([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]),
            None
        );
        assert_eq!(circumcenter2([f64::NAN, 0.0], [1.0, 0.0], [0.0, 1.0]), None);
        assert_eq!(circumcenter2([1e300, 0.0], [1e-300, 0.0], [0.0, 1.0]), None);
    }

    #[test]
    fn a_far_point_and_a_close_pair() {
        // The centre of (1, 1), (0, 0), (t, 0) is (t/2, 1 − t/2); for t = 2^-60 the edge
        // vectors from (1, 1) round to the same f64 (the naive formula's centre is (1, 1)).
        for e in [40, 60, 100] {
            let t = 2f64.powi(-e);
            let o = circumcenter2([1.0, 1.0], [0.0, 0.0], [t, 0.0]).unwrap();
            assert_eq!(o, [t / 2.0, 1.0 - t / 2.0], "{e}");
        }
    }
}
