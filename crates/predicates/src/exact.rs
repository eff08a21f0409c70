//! The four classic predicates, exact, with delmesh's sign conventions.
//!
//! Thin wrappers over [`robust`] (Shewchuk's adaptive predicates): they fix the sign convention
//! (positive volume = positive orientation in 3D) and return a [`Sign`].

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

/// Orientation of the triangle `a, b, c`: [`Sign::Positive`] if counter-clockwise,
/// [`Sign::Negative`] if clockwise, [`Sign::Zero`] if the three points are collinear.
#[inline]
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    Sign::of(robust::orient2d(c2(a), c2(b), c2(c)))
}

/// Orientation of the tetrahedron `a, b, c, d`: the sign of its volume
/// `(b − a) · ((c − a) × (d − a))`. [`Sign::Positive`] when `d` lies on the side of the plane
/// `a, b, c` from which `a, b, c` appear clockwise (right-handed tetrahedron); [`Sign::Zero`]
/// when the four points are coplanar.
#[inline]
pub fn orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Sign {
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
    Sign::of(robust::incircle(c2(a), c2(b), c2(c), c2(d)))
}

/// In-sphere test: [`Sign::Positive`] if `e` lies strictly inside the sphere through
/// `a, b, c, d`, [`Sign::Negative`] if strictly outside, [`Sign::Zero`] if on it.
///
/// Precondition: `orient3d(a, b, c, d)` is positive; otherwise the sign is reversed.
#[inline]
pub fn insphere(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3], e: [f64; 3]) -> Sign {
    // robust::insphere expects robust's positive orientation, which is our negative one.
    Sign::of(-robust::insphere(c3(a), c3(b), c3(c), c3(d), c3(e)))
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
