//! An exact integer path for inputs on a coarse dyadic lattice (regular grids).
//!
//! Regular grids are the worst case for adaptive floating-point predicates: every cell is
//! co-circular (co-spherical), so the determinant is exactly zero and Shewchuk's arithmetic runs
//! to its last, slowest stage. But grid coordinates are small integers times a common power of
//! two. When all coordinates of a call are `k · 2^L` with `|k| < 2^23` for one `L`, the
//! determinant is computed exactly in `i128` instead (degree 5 in differences below `2^24`:
//! `|det| < 72 · 2^120 < 2^127`), which costs about as much as the floating-point filter.

/// Largest magnitude, in bits, of the integer coordinates this path accepts.
const BITS: i32 = 23;

/// The coordinates as integers `k` with `x = k · 2^L` for one common `L`, if they fit in
/// [`BITS`] bits; `None` otherwise (then the caller uses the adaptive path).
#[inline]
pub(crate) fn lattice<const M: usize>(x: [f64; M]) -> Option<[i64; M]> {
    let mut lo = i32::MAX; // exponent of the lowest set bit over all coordinates
    let mut hi = i32::MIN; // exponent of the highest set bit
    for &v in &x {
        if v == 0.0 {
            continue;
        }
        let bits = v.to_bits();
        let exp = ((bits >> 52) & 0x7FF) as i32;
        if exp == 0 || exp == 0x7FF {
            return None; // subnormal, infinite or NaN
        }
        let mant = bits & ((1 << 52) - 1) | (1 << 52);
        lo = lo.min(exp - 1075 + mant.trailing_zeros() as i32);
        hi = hi.max(exp - 1023);
    }
    if lo == i32::MAX {
        return Some([0; M]);
    }
    if hi - lo >= BITS {
        return None;
    }
    let mut k = [0i64; M];
    for (ki, &v) in k.iter_mut().zip(&x) {
        if v == 0.0 {
            continue;
        }
        let bits = v.to_bits();
        let exp = ((bits >> 52) & 0x7FF) as i32;
        let mant = (bits & ((1 << 52) - 1) | (1 << 52)) as i64;
        let tz = mant.trailing_zeros() as i32;
        let low_exp = exp - 1075 + tz;
        let magnitude = (mant >> tz) << (low_exp - lo);
        *ki = if v < 0.0 { -magnitude } else { magnitude };
    }
    Some(k)
}

/// Sign (−1, 0, 1) of the 2×2 orientation determinant, in robust's convention.
pub(crate) fn orient2d(k: [i64; 6]) -> i32 {
    let (acx, acy) = (k[0] - k[4], k[1] - k[5]);
    let (bcx, bcy) = (k[2] - k[4], k[3] - k[5]);
    (i128::from(acx) * i128::from(bcy) - i128::from(acy) * i128::from(bcx)).signum() as i32
}

/// Sign of `det[a − d; b − d; c − d]` (robust's orient3d sign).
pub(crate) fn orient3d(k: [i64; 12]) -> i32 {
    let d = |p: usize, j: usize| i128::from(k[3 * p + j] - k[9 + j]);
    let (ax, ay, az) = (d(0, 0), d(0, 1), d(0, 2));
    let (bx, by, bz) = (d(1, 0), d(1, 1), d(1, 2));
    let (cx, cy, cz) = (d(2, 0), d(2, 1), d(2, 2));
    let det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    det.signum() as i32
}

/// Sign of robust's incircle determinant.
pub(crate) fn incircle(k: [i64; 8]) -> i32 {
    let d = |p: usize, j: usize| i128::from(k[2 * p + j] - k[6 + j]);
    let (ax, ay, bx, by, cx, cy) = (d(0, 0), d(0, 1), d(1, 0), d(1, 1), d(2, 0), d(2, 1));
    let (al, bl, cl) = (ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy);
    let det = al * (bx * cy - cx * by) + bl * (cx * ay - ax * cy) + cl * (ax * by - bx * ay);
    det.signum() as i32
}

/// Sign of robust's insphere determinant.
pub(crate) fn insphere(k: [i64; 15]) -> i32 {
    // Differences below 2^11 keep |det| < 72 · 2^55 < 2^63: plain i64 arithmetic suffices.
    let small = k.iter().all(|&x| (-(1 << 10)..(1 << 10)).contains(&x));
    if small {
        return insphere_i64(k);
    }
    let d = |p: usize, j: usize| i128::from(k[3 * p + j] - k[12 + j]);
    let v: [[i128; 3]; 4] = std::array::from_fn(|p| [d(p, 0), d(p, 1), d(p, 2)]);
    let [a, b, c, e] = v;
    let m2 = |p: [i128; 3], q: [i128; 3]| p[0] * q[1] - q[0] * p[1];
    let (ab, bc, cd, da, ac, bd) = (m2(a, b), m2(b, c), m2(c, e), m2(e, a), m2(a, c), m2(b, e));
    let abc = a[2] * bc - b[2] * ac + c[2] * ab;
    let bcd = b[2] * cd - c[2] * bd + e[2] * bc;
    let cda = c[2] * da + e[2] * ac + a[2] * cd;
    let dab = e[2] * ab + a[2] * bd + b[2] * da;
    let lift = |p: [i128; 3]| p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    let det = (lift(e) * abc - lift(c) * dab) + (lift(b) * cda - lift(a) * bcd);
    det.signum() as i32
}

fn insphere_i64(k: [i64; 15]) -> i32 {
    let d = |p: usize, j: usize| k[3 * p + j] - k[12 + j];
    let v: [[i64; 3]; 4] = std::array::from_fn(|p| [d(p, 0), d(p, 1), d(p, 2)]);
    let [a, b, c, e] = v;
    let m2 = |p: [i64; 3], q: [i64; 3]| p[0] * q[1] - q[0] * p[1];
    let (ab, bc, cd, da, ac, bd) = (m2(a, b), m2(b, c), m2(c, e), m2(e, a), m2(a, c), m2(b, e));
    let abc = a[2] * bc - b[2] * ac + c[2] * ab;
    let bcd = b[2] * cd - c[2] * bd + e[2] * bc;
    let cda = c[2] * da + e[2] * ac + a[2] * cd;
    let dab = e[2] * ab + a[2] * bd + b[2] * da;
    let lift = |p: [i64; 3]| p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    let det = (lift(e) * abc - lift(c) * dab) + (lift(b) * cda - lift(a) * bcd);
    det.signum() as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_detects_common_dyadic_grid() {
        assert_eq!(lattice([0.5, 0.25, -0.75]), Some([2, 1, -3]));
        assert_eq!(lattice([3.0, 0.0, 1024.0]), Some([3, 0, 1024]));
        assert_eq!(lattice([0.1, 0.2]), None); // 0.1 has 52 significant bits
        assert_eq!(lattice([1.0, 2f64.powi(30)]), None); // range too wide
        assert_eq!(lattice([0.0, -0.0]), Some([0, 0]));
        assert_eq!(lattice([f64::MIN_POSITIVE / 2.0, 1.0]), None); // subnormal
    }
}
