//! The four classic predicates, exact, with delmesh's sign conventions.
//!
//! Each fixes the sign convention (positive volume = positive orientation in 3D) and returns
//! a [`Sign`].
//!
//! In front of each sits a *semi-static filter*: the determinant in floating point, accepted
//! when it exceeds an error bound built from the largest coordinate difference `M` instead of
//! Shewchuk's permanent (which costs as much as the determinant). The bound is Shewchuk's
//! stage-A bound (`errboundA × permanent`, Shewchuk 1997, §4.3) with the permanent replaced by
//! its upper bound `k·M^d`, so whatever the filter accepts, stage A would have accepted too.
//! Anything closer to degenerate falls through to the exact integer evaluation of
//! [`crate::integer`], and only input it cannot represent (outside [`crate::COORDINATE_RANGE`]
//! or not finite) to [`robust`] (Shewchuk's adaptive predicates).

use crate::Sign;
use robust::{Coord, Coord3D};

#[inline(always)]
fn c2(p: [f64; 2]) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

#[inline(always)]
fn c3(p: [f64; 3]) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

/// Below this largest difference the bounds `k·M^d` could underflow: go exact directly.
const TINY: f64 = 1e-30;

/// Orientation of the triangle `a, b, c`: [`Sign::Positive`] if counter-clockwise,
/// [`Sign::Negative`] if clockwise, [`Sign::Zero`] if the three points are collinear.
#[inline]
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    let (acx, acy) = (a[0] - c[0], a[1] - c[1]);
    let (bcx, bcy) = (b[0] - c[0], b[1] - c[1]);
    let det = acx * bcy - acy * bcx;
    let m = fmax(fmax(acx.abs(), acy.abs()), fmax(bcx.abs(), bcy.abs()));
    // Shewchuk: ccwerrboundA = (3 + 16ε)ε, permanent ≤ 2M².
    if m > TINY && det.abs() > 7.0e-16 * (m * m) {
        return Sign::of(det);
    }
    if let Some(s) = crate::integer::orient2d(&[a[0], a[1], b[0], b[1], c[0], c[1]]) {
        return s;
    }
    Sign::of(robust::orient2d(c2(a), c2(b), c2(c)))
}

/// Orientation of the tetrahedron `a, b, c, d`: the sign of its volume
/// `(b − a) · ((c − a) × (d − a))`. [`Sign::Positive`] when `d` lies on the side of the plane
/// `a, b, c` from which `a, b, c` appear clockwise (right-handed tetrahedron); [`Sign::Zero`]
/// when the four points are coplanar.
#[inline]
pub fn orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Sign {
    let ad = [a[0] - d[0], a[1] - d[1], a[2] - d[2]];
    let bd = [b[0] - d[0], b[1] - d[1], b[2] - d[2]];
    let cd = [c[0] - d[0], c[1] - d[1], c[2] - d[2]];
    // det[ad; bd; cd] is the volume of (a, b, c, d) with robust's sign (−ours).
    let det = ad[0] * (bd[1] * cd[2] - bd[2] * cd[1]) - ad[1] * (bd[0] * cd[2] - bd[2] * cd[0])
        + ad[2] * (bd[0] * cd[1] - bd[1] * cd[0]);
    let m = fmax(fmax(max_abs(&ad), max_abs(&bd)), max_abs(&cd));
    // Shewchuk: o3derrboundA = (7 + 56ε)ε, permanent ≤ 6M³.
    if m > TINY && det.abs() > 4.8e-15 * (m * m * m) {
        return Sign::of(-det);
    }
    orient3d_exact(a, b, c, d)
}

/// Exact [`orient3d`] after its filter failed (out of line, as [`insphere_exact`]).
#[cold]
#[inline(never)]
fn orient3d_exact(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Sign {
    // Four points with one coordinate equal lie in a plane normal to that axis (the faces of
    // boxes, far fields and symmetry planes, where many exact calls land): zero, without the
    // exact arithmetic.
    if (0..3).any(|k| a[k] == d[k] && b[k] == d[k] && c[k] == d[k]) {
        return Sign::Zero;
    }
    if let Some(s) = crate::integer::orient3d(&[
        a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2],
    ]) {
        return s.reversed();
    }
    // robust::orient3d is positive when d is *below* the plane of a counter-clockwise a, b, c,
    // i.e. when the volume above is negative.
    Sign::of(-robust::orient3d(c3(a), c3(b), c3(c), c3(d)))
}

/// In-circle test: [`Sign::Positive`] if `d` lies strictly inside the circle through `a, b, c`,
/// [`Sign::Negative`] if strictly outside, [`Sign::Zero`] if on it.
///
/// Precondition: `orient2d(a, b, c)` is positive; otherwise the sign is reversed.
#[inline]
pub fn incircle(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> Sign {
    let (adx, ady) = (a[0] - d[0], a[1] - d[1]);
    let (bdx, bdy) = (b[0] - d[0], b[1] - d[1]);
    let (cdx, cdy) = (c[0] - d[0], c[1] - d[1]);
    let alift = adx * adx + ady * ady;
    let blift = bdx * bdx + bdy * bdy;
    let clift = cdx * cdx + cdy * cdy;
    let det = alift * (bdx * cdy - cdx * bdy)
        + blift * (cdx * ady - adx * cdy)
        + clift * (adx * bdy - bdx * ady);
    let m = fmax(
        fmax(fmax(adx.abs(), ady.abs()), fmax(bdx.abs(), bdy.abs())),
        fmax(cdx.abs(), cdy.abs()),
    );
    // Shewchuk: iccerrboundA = (10 + 96ε)ε, permanent ≤ 12M⁴.
    if m > TINY && det.abs() > 1.4e-14 * ((m * m) * (m * m)) {
        return Sign::of(det);
    }
    if let Some(s) = crate::integer::incircle(&[a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1]]) {
        return s;
    }
    Sign::of(robust::incircle(c2(a), c2(b), c2(c), c2(d)))
}

/// The value of the determinant [`orient2d`] decides the sign of, `(b − a) × (c − a)`, to
/// nearly full relative precision and with the exact sign (robust's adaptive evaluation, which
/// returns its exact expansion's largest component): for constructions that divide by it, such
/// as a circumcentre, where the plain floating-point value can be 0 or of the wrong sign for
/// nearly collinear points.
pub fn orient2d_value(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    robust::orient2d(c2(a), c2(b), c2(c))
}

/// The value of the determinant [`orient3d`] decides the sign of, `(b − a) · ((c − a) × (d − a))`,
/// as [`orient2d_value`] gives it in 2D.
pub fn orient3d_value(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    // robust's orientation is the opposite of ours.
    -robust::orient3d(c3(a), c3(b), c3(c), c3(d))
}

/// In-sphere test: [`Sign::Positive`] if `e` lies strictly inside the sphere through
/// `a, b, c, d`, [`Sign::Negative`] if strictly outside, [`Sign::Zero`] if on it.
///
/// Precondition: `orient3d(a, b, c, d)` is positive; otherwise the sign is reversed.
#[inline]
pub fn insphere(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3], e: [f64; 3]) -> Sign {
    if let Some(s) = insphere_filter(a, b, c, d, e) {
        return s;
    }
    insphere_exact(&[a, b, c, d, e])
}

/// The semi-static filter of [`insphere`]: the sign when the floating-point determinant is
/// certain, `None` otherwise.
#[inline(always)]
pub(crate) fn insphere_filter(
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    d: [f64; 3],
    e: [f64; 3],
) -> Option<Sign> {
    let ae = [a[0] - e[0], a[1] - e[1], a[2] - e[2]];
    let be = [b[0] - e[0], b[1] - e[1], b[2] - e[2]];
    let ce = [c[0] - e[0], c[1] - e[1], c[2] - e[2]];
    let de = [d[0] - e[0], d[1] - e[1], d[2] - e[2]];
    // 2×2 minors of the x, y columns.
    let ab = ae[0] * be[1] - be[0] * ae[1];
    let bc = be[0] * ce[1] - ce[0] * be[1];
    let cd = ce[0] * de[1] - de[0] * ce[1];
    let da = de[0] * ae[1] - ae[0] * de[1];
    let ac = ae[0] * ce[1] - ce[0] * ae[1];
    let bd = be[0] * de[1] - de[0] * be[1];
    // 3×3 minors with the z column.
    let abc = ae[2] * bc - be[2] * ac + ce[2] * ab;
    let bcd = be[2] * cd - ce[2] * bd + de[2] * bc;
    let cda = ce[2] * da + de[2] * ac + ae[2] * cd;
    let dab = de[2] * ab + ae[2] * bd + be[2] * da;
    let lift = |p: [f64; 3]| p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    let det = (lift(de) * abc - lift(ce) * dab) + (lift(be) * cda - lift(ae) * bcd);
    let m = fmax(
        fmax(max_abs(&ae), max_abs(&be)),
        fmax(max_abs(&ce), max_abs(&de)),
    );
    // Shewchuk: isperrboundA = (16 + 224ε)ε, permanent ≤ 72M⁵. `det` has robust's sign.
    let m2 = m * m;
    if m > TINY && det.abs() > 1.3e-13 * (m2 * m2 * m) {
        return Some(Sign::of(-det));
    }
    None
}

/// Exact [`insphere`] after its filter failed. Out of line: its integer arithmetic needs a
/// large stack frame (tens of kilobytes, probed page by page), which inlined would be set up on
/// every call of the filter's fast path.
#[cold]
#[inline(never)]
pub(crate) fn insphere_exact(p: &[[f64; 3]; 5]) -> Sign {
    let flat: [f64; 15] = std::array::from_fn(|i| p[i / 3][i % 3]);
    if let Some(s) = crate::integer::insphere(&flat) {
        return s.reversed();
    }
    // robust::insphere expects robust's positive orientation, which is our negative one.
    Sign::of(-robust::insphere(
        c3(p[0]),
        c3(p[1]),
        c3(p[2]),
        c3(p[3]),
        c3(p[4]),
    ))
}

/// `max` without NaN handling (the inputs are finite): one instruction instead of three.
#[inline(always)]
fn fmax(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

#[inline(always)]
fn max_abs(p: &[f64; 3]) -> f64 {
    fmax(fmax(p[0].abs(), p[1].abs()), p[2].abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orientation_values_have_the_exact_sign() {
        // Nearly collinear / coplanar: the plain determinant rounds to 0 or the wrong sign.
        for i in 1..200 {
            let t = f64::from(i);
            let (a, b, c) = (
                [0.0, 0.0],
                [0.1 * t, 0.3 * t],
                [0.1 * (t + 1.0), 0.3 * (t + 1.0)],
            );
            let v = orient2d_value(a, b, c);
            assert_eq!(Sign::of(v), orient2d(a, b, c), "{t}");
            let d3 = |p: [f64; 2]| [p[0], p[1], 0.3 * p[1]];
            let e = [0.7 * t, 0.2, 0.06];
            let w = orient3d_value(d3(a), d3(b), d3(c), e);
            assert_eq!(Sign::of(w), orient3d(d3(a), d3(b), d3(c), e), "{t}");
        }
        assert!(orient2d_value([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]) > 0.0);
        let (o, x, y, z) = ([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        assert_eq!(orient3d_value(o, x, y, z), 1.0);
    }

    #[test]
    fn orient2d_convention() {
        assert_eq!(orient2d([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), Sign::Positive);
        assert_eq!(orient2d([0.0, 0.0], [0.0, 1.0], [1.0, 0.0]), Sign::Negative);
        assert_eq!(orient2d([0.0, 0.0], [1.0, 1.0], [3.0, 3.0]), Sign::Zero);
    }

    #[test]
    fn orient3d_convention_is_positive_volume() {
        let (o, x, y, z) = ([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        // (x − o) · ((y − o) × (z − o)) = 1.
        assert_eq!(orient3d(o, x, y, z), Sign::Positive);
        assert_eq!(orient3d(o, y, x, z), Sign::Negative);
        assert_eq!(orient3d(o, x, y, [2.0, 3.0, 0.0]), Sign::Zero);
    }

    #[test]
    fn incircle_convention() {
        let (a, b, c) = ([0.0, 0.0], [2.0, 0.0], [0.0, 2.0]);
        assert_eq!(incircle(a, b, c, [0.5, 0.5]), Sign::Positive);
        assert_eq!(incircle(a, b, c, [3.0, 3.0]), Sign::Negative);
        assert_eq!(incircle(a, b, c, [2.0, 2.0]), Sign::Zero);
    }

    #[test]
    fn insphere_convention() {
        let (a, b, c, d) = ([0.0; 3], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]);
        assert_eq!(orient3d(a, b, c, d), Sign::Positive);
        assert_eq!(insphere(a, b, c, d, [0.5, 0.5, 0.5]), Sign::Positive);
        assert_eq!(insphere(a, b, c, d, [3.0, 3.0, 3.0]), Sign::Negative);
        assert_eq!(insphere(a, b, c, d, [2.0, 2.0, 0.0]), Sign::Zero);
    }

    /// The filters must agree with robust's exact answers everywhere, in particular near
    /// degeneracies, where they must fall through instead of guessing.
    #[test]
    #[allow(clippy::needless_range_loop)] // the loop indexes several points at once
    fn filters_agree_with_exact_predicates() {
        let mut s = 0x1234_5678_9abc_def0u64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for round in 0..200_000 {
            // Mix generic points with nearly degenerate ones: points on a line/plane/sphere
            // perturbed by a few ulps, and tiny/huge scales.
            let scale = [1.0, 1e-12, 1e12, 3.0e-7][round % 4];
            let mut p: Vec<[f64; 3]> = (0..5)
                .map(|_| [rnd() * scale, rnd() * scale, rnd() * scale])
                .collect();
            if round % 3 == 1 {
                // e on the line / plane through the others, then nudged.
                let t = rnd();
                let (p0, p1, p2) = (p[0], p[1], p[2]);
                p[4] = std::array::from_fn(|k| p0[k] + t * (p1[k] - p0[k]));
                p[3] = std::array::from_fn(|k| {
                    p0[k] + t * (p1[k] - p0[k]) + (1.0 - t) * (p2[k] - p0[k])
                });
                p[2][0] = p[0][0] + 0.5 * (p[1][0] - p[0][0]);
                p[2][1] = p[0][1] + 0.5 * (p[1][1] - p[0][1]);
            }
            let [a, b, c, d, e] = [p[0], p[1], p[2], p[3], p[4]];
            let a2 = [a[0], a[1]];
            let b2 = [b[0], b[1]];
            let c2_ = [c[0], c[1]];
            let d2 = [d[0], d[1]];
            let e2 = [e[0], e[1]];
            assert_eq!(
                orient2d(a2, b2, e2),
                Sign::of(robust::orient2d(c2(a2), c2(b2), c2(e2)))
            );
            assert_eq!(
                orient3d(a, b, c, e),
                Sign::of(-robust::orient3d(c3(a), c3(b), c3(c), c3(e)))
            );
            assert_eq!(
                incircle(a2, b2, c2_, d2),
                Sign::of(robust::incircle(c2(a2), c2(b2), c2(c2_), c2(d2)))
            );
            assert_eq!(
                insphere(a, b, c, d, e),
                Sign::of(-robust::insphere(c3(a), c3(b), c3(c), c3(d), c3(e)))
            );
        }
    }

    /// Small-integer (grid) inputs take the integer path: it must agree with robust.
    #[test]
    fn integer_path_agrees_with_exact_predicates() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = |m: u64| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % m) as f64
        };
        for round in 0..100_000 {
            let (m, scale) = [(3, 1.0), (5, 0.125), (1 << 22, 1.0), (9, 1024.0)][round % 4];
            let p: Vec<[f64; 3]> = (0..5)
                .map(|_| [rnd(m) * scale, rnd(m) * scale, -rnd(m) * scale])
                .collect();
            let [a, b, c, d, e] = [p[0], p[1], p[2], p[3], p[4]];
            let (a2, b2, c2_, d2) = ([a[0], a[1]], [b[0], b[1]], [c[0], c[1]], [d[0], d[1]]);
            assert_eq!(
                orient2d(a2, b2, c2_),
                Sign::of(robust::orient2d(c2(a2), c2(b2), c2(c2_)))
            );
            assert_eq!(
                orient3d(a, b, c, e),
                Sign::of(-robust::orient3d(c3(a), c3(b), c3(c), c3(e)))
            );
            assert_eq!(
                incircle(a2, b2, c2_, d2),
                Sign::of(robust::incircle(c2(a2), c2(b2), c2(c2_), c2(d2)))
            );
            assert_eq!(
                insphere(a, b, c, d, e),
                Sign::of(-robust::insphere(c3(a), c3(b), c3(c), c3(d), c3(e)))
            );
        }
    }

    #[test]
    fn exact_where_floating_point_fails() {
        // Nearly collinear points whose naive determinant has the wrong sign or is zero:
        // b lies exactly on the line y = x scaled, the perturbed point by one ulp.
        let a = [0.5, 0.5];
        let b = [12.0, 12.0];
        let c = [24.0, 24.0];
        assert_eq!(orient2d(a, b, c), Sign::Zero);
        let up = [24.0, f64::from_bits(24.0f64.to_bits() + 1)];
        assert_eq!(orient2d(a, b, up), Sign::Positive);
        let down = [24.0, f64::from_bits(24.0f64.to_bits() - 1)];
        assert_eq!(orient2d(a, b, down), Sign::Negative);
    }

    #[test]
    fn points_sharing_a_coordinate_are_coplanar_and_one_ulp_off_is_not() {
        // In the plane y = 0.1 (not exact in binary, the same double for all four points), in
        // any order, and with the fourth point one ulp above or below it.
        for axis in 0..3 {
            let put = |u: f64, w: f64, at: f64| {
                let mut p = [u, w, u + w];
                p[axis] = at;
                p
            };
            let (a, b, c) = (put(0.3, 7.1, 0.1), put(-2.9, 1.7, 0.1), put(5.5, -0.4, 0.1));
            for d in [put(1.3, 2.2, 0.1), put(1e9, -3e-9, 0.1)] {
                assert_eq!(orient3d(a, b, c, d), Sign::Zero);
                assert_eq!(orient3d(d, c, b, a), Sign::Zero);
            }
            let above = put(1.3, 2.2, f64::from_bits(0.1f64.to_bits() + 1));
            let below = put(1.3, 2.2, f64::from_bits(0.1f64.to_bits() - 1));
            let (s_above, s_below) = (orient3d(a, b, c, above), orient3d(a, b, c, below));
            assert_ne!(s_above, Sign::Zero);
            assert_eq!(s_below, s_above.reversed());
            // The side of a point well above the plane, which the filter decides.
            assert_eq!(s_above, orient3d(a, b, c, put(1.3, 2.2, 1.1)));
        }
    }
}
