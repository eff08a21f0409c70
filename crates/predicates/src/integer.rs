//! The exact stage after the filters: the determinants in integer arithmetic.
//!
//! # Why integers
//! Every finite `f64` is an integer times a power of two, so the coordinates of one predicate
//! call are `x_i = k_i · 2^L` for integers `k_i`, with `L` the lowest set bit over all of them.
//! A predicate's determinant is a homogeneous polynomial of degree `n` in the coordinate
//! differences (2 for `orient2d`, 3 for `orient3d`, 4 for `incircle`, 5 for `insphere`), so its
//! sign is the sign of the same polynomial evaluated in the integers `k_i`: the factor
//! `2^(nL)` is positive. Integer arithmetic is exact as long as nothing overflows, which the
//! bounds below rule out, so **every sign returned here is the sign of the exact determinant**
//! of the `f64` inputs, whatever their rounding history and however close to degenerate.
//!
//! This replaces Shewchuk's adaptive stages, which is where delmesh spent its time on
//! nearly co-spherical (smooth surfaces) and exactly co-circular (structured grids) inputs:
//! `robust`'s adaptive in-sphere zero-fills about 30 KB of stack arrays per call. Here the
//! numbers have the size they need: the kernel scales points into `[0.5, 1)`, so after a
//! failed filter the points are close together, the differences `k_a − k_e` of their integer
//! forms have at most about 55 bits, and the degree-5 in-sphere determinant fits 320 bits.
//!
//! # Bounds
//! With `b` the bit length of the largest difference (`|d| ≤ 2^b`), a `k×k` minor of
//! differences is at most `k!·2^(kb)`, and a lift `Σ d²` at most `N·2^(2b)` (N = 2 or 3), so:
//!
//! | predicate | 2×2 minor      | lift         | 3×3 minor      | determinant   |
//! |-----------|----------------|--------------|----------------|---------------|
//! | orient2d  | (the determinant)            | | | `≤ 2^(2b+1)`  |
//! | orient3d  | `≤ 2^(2b+1)`   |              | `< 2^(3b+3)`   | `< 2^(3b+3)`  |
//! | incircle  | `≤ 2^(2b+1)`   | `≤ 2^(2b+1)` |                | `< 2^(4b+4)`  |
//! | insphere  | `≤ 2^(2b+1)`   | `< 2^(2b+2)` | `< 2^(3b+3)`   | `< 2^(5b+7)`  |
//!
//! (`insphere`: four terms `lift · 3×3 minor`, `4 · 3·2^(2b) · 6·2^(3b) < 2^(5b+7)`.) A signed
//! `W`-bit integer holds every value of magnitude below `2^(W−1)`, which gives the tiers:
//!
//! - **`i64`** when the whole determinant fits (`b ≤ 11` for insphere, `14` incircle, `20`
//!   orient3d): small integer grids, as cheap as the floating-point filter.
//! - **Wide, `b ≤ 62`** (the common case: differences fit `i64`): 2×2 minors in `i128`
//!   (`≤ 2^125`), 3×3 minors in 192-bit two's complement (`< 2^189`), lifts in `u128`
//!   (`< 2^126`), the in-sphere determinant in 320 bits (`< 2^317`), the in-circle one in 256
//!   (`< 2^252`). The wide sums are computed modulo `2^W` (wrapping limb arithmetic): that is a
//!   ring homomorphism, so the residue equals the true value once the true value is known to
//!   lie in `[−2^(W−1), 2^(W−1))`, by the table above.
//! - **[`Big`]**, larger `b` (points with one coordinate near zero, tiny clusters far from the
//!   origin): the same formulas with a stack bignum of at most 2048 bits, enough for every
//!   input in [`crate::COORDINATE_RANGE`] (`b ≤ 397`; see [`BIG_B`]). The kernel keeps
//!   coordinates in `[2^-142, 1)`, so `b ≤ 195` there.
//! - Otherwise (only for input outside [`crate::COORDINATE_RANGE`], or not finite) the caller
//!   falls back to `robust`.
//!
//! All functions return the sign in `robust`'s conventions (the callers adapt it).

use crate::bigint::Big;
use crate::Sign;
use std::ops::{Add, Mul, Sub};

const FRACTION: u64 = (1 << 52) - 1;
const HIDDEN: u64 = 1 << 52;

/// Largest `b` for which [`Big`] holds every intermediate. The largest products are of
/// operands below `2^(2b+2)` and `2^(3b+3)` in insphere (13 + 19 limbs for `b = 400`),
/// `2^(b+1)` and `2^(2b+1)` in orient3d (7 + 13), `2^(2b+1)` twice in incircle (13 + 13) and
/// `2^(b+1)` twice in orient2d (7 + 7): all within [`crate::bigint::CAP`] = 32 limbs, and every
/// partial sum is below the determinant's bound (`< 2^2007` for insphere). Coordinates in
/// [`crate::COORDINATE_RANGE`] have `b ≤ 202 + 194 + 1 = 397`.
pub(crate) const BIG_B: i32 = 400;

/// `|v| = mant · 2^exp` with `mant < 2^53` (`mant = 0` for `±0`), and the sign bit.
#[inline(always)]
fn split(v: f64) -> (u64, i32, bool) {
    let bits = v.to_bits();
    let field = ((bits >> 52) & 0x7FF) as i32;
    let fraction = bits & FRACTION;
    let neg = (bits >> 63) != 0;
    if field == 0 {
        (fraction, -1074, neg) // zero or subnormal
    } else {
        (fraction | HIDDEN, field - 1075, neg)
    }
}

/// The exponent `lo` of the lowest set bit over all non-zero `x`, and `hi` with every
/// `|x| < 2^hi`; `(i32::MAX, i32::MIN)` if all are zero, `None` if any is infinite or NaN.
#[inline(always)]
pub(crate) fn exponents(x: &[f64]) -> Option<(i32, i32)> {
    let (mut lo, mut hi) = (i32::MAX, i32::MIN);
    for &v in x {
        if !v.is_finite() {
            return None;
        }
        let (mant, exp, _) = split(v);
        if mant != 0 {
            lo = lo.min(exp + mant.trailing_zeros() as i32);
            hi = hi.max(exp + 64 - mant.leading_zeros() as i32);
        }
    }
    Some((lo, hi))
}

/// `x / 2^lo` as an integer; exact when `lo` is at most the lowest set bit of `x` and
/// `|x| < 2^(lo + 127)`.
#[inline(always)]
fn to_i128(v: f64, lo: i32) -> i128 {
    let (mant, exp, neg) = split(v);
    if mant == 0 {
        return 0;
    }
    let tz = mant.trailing_zeros();
    let k = i128::from(mant >> tz) << (exp + tz as i32 - lo);
    if neg {
        -k
    } else {
        k
    }
}

/// `x / 2^lo` as a [`Big`], under the same condition as [`to_i128`] but any magnitude that
/// fits the capacity.
pub(crate) fn to_big(v: f64, lo: i32) -> Big {
    let (mant, exp, neg) = split(v);
    if mant == 0 {
        return Big::from_i128(0);
    }
    let tz = mant.trailing_zeros();
    Big::from_shifted(mant >> tz, (exp + tz as i32 - lo) as u32, neg)
}

/// Bit length of the largest `|d|`, in the sense `−2^b ≤ d < 2^b` (so `|d| ≤ 2^b`).
#[inline(always)]
fn bit_length(d: &[i128]) -> i32 {
    // d ^ (d >> 127) is d for d ≥ 0 and −d − 1 = |d| − 1 for d < 0.
    let m = d.iter().fold(0u128, |m, &v| m | (v ^ (v >> 127)) as u128);
    128 - m.leading_zeros() as i32
}

/// The differences `p_i − p_last` of points of `n` coordinates (flattened in `x`), as
/// integers at the common scale, with their [`bit_length`]; `None` if a coordinate is not
/// finite.
///
/// When the coordinates span more than 126 bits, too many for `i128`, `Err(b)` gives
/// instead a `b` with `|d| ≤ 2^b` for the [`Big`] path (`|k| < 2^(hi − lo)`).
#[inline(always)]
fn differences<const M: usize, const D: usize>(
    x: &[f64; M],
    n: usize,
) -> Option<Result<([i128; D], i32), i32>> {
    let (lo, hi) = exponents(x)?;
    if lo == i32::MAX {
        return Some(Ok(([0; D], 0))); // all zero
    }
    if hi - lo > 126 {
        return Some(Err(hi - lo + 1));
    }
    // |k| < 2^126: the differences fit i128.
    let k: [i128; M] = std::array::from_fn(|i| to_i128(x[i], lo));
    let last = M - n;
    let d: [i128; D] = std::array::from_fn(|i| k[i] - k[last + i % n]);
    let b = bit_length(&d);
    Some(Ok((d, b)))
}

/// The common case of [`differences`], cheaply: with `E` the largest biased exponent of the
/// coordinates (so every `|x| < 2^(E − 1022)`), the coordinates times `S = 2^(1083 − E)` are
/// below `2^61` in magnitude; when they are all integers `k`, their differences fit `i64`
/// with `|d| < 2^62` (the wide tier's bound), and they are the integers of the module doc at
/// the scale `2^(E − 1083)` (any common power of two does: the determinant's sign does not
/// depend on it).
///
/// Exactness: `x · S` is read off the bits of `x` with integer shifts and accepted only if no
/// set bit is shifted out, so `k = x · S` exactly. `None` when some coordinate has bits below
/// `2^(E − 1083)` (a span of more than 61 bits: then [`differences`] decides), for non-finite
/// input, and when every coordinate is zero or subnormal.
#[inline(always)]
fn small_differences<const M: usize, const D: usize>(x: &[f64; M], n: usize) -> Option<[i64; D]> {
    // The largest biased exponent field E: every |x| < 2^(E − 1022).
    let field = x
        .iter()
        .fold(0u64, |m, v| m.max(v.to_bits() & (0x7FF << 52)))
        >> 52;
    if !(1..=2046).contains(&field) {
        return None; // non-finite (E = 2047), or all zero / subnormal (E = 0)
    }
    // x · S from the bits: x = m·2^(e − 1075) (e ≥ 1 the exponent, m < 2^53 the significand),
    // so x · S = m · 2^(e + 8 − E) = (m·2^8) / 2^r with r = E − e ≥ 0. It is an integer iff the
    // r low bits of m·2^8 < 2^61 are zero (all of them when r ≥ 63).
    let mut lost = 0u64;
    let k: [i64; M] = std::array::from_fn(|i| {
        let bits = x[i].to_bits();
        let e = (bits >> 52) & 0x7FF;
        let m = ((bits & FRACTION) | (u64::from(e != 0) << 52)) << 8;
        let r = (field - e.max(1)).min(63);
        lost |= m & ((1u64 << r) - 1);
        let sign = (bits as i64) >> 63; // 0 or −1
        ((m >> r) as i64 ^ sign) - sign
    });
    if lost != 0 {
        return None;
    }
    let last = M - n;
    Some(std::array::from_fn(|i| k[i] - k[last + i % n]))
}

/// Divides the differences by their largest common power of two (which keeps the sign of
/// every determinant) and returns the bit length `b` of the result (`−2^b ≤ d < 2^b`); the
/// differences are unchanged, and `b` is that of the unshifted ones, when `b > limit`.
#[inline(always)]
fn reduce<const D: usize>(d: &mut [i64; D], limit: u32) -> u32 {
    let or = d.iter().fold(0i64, |m, &v| m | v);
    let magnitude = d.iter().fold(0u64, |m, &v| m | (v ^ (v >> 63)) as u64);
    let length = 64 - magnitude.leading_zeros();
    if or == 0 {
        return 0;
    }
    let t = or.trailing_zeros();
    if length - t.min(length) <= limit {
        for v in d.iter_mut() {
            *v >>= t;
        }
        return length - t.min(length);
    }
    length
}

/// The differences as [`Big`]s, for spans beyond `i128`.
fn big_differences<const M: usize, const D: usize>(x: &[f64; M], n: usize) -> [Big; D] {
    let (lo, _) = exponents(x).expect("finite");
    let k: [Big; M] = std::array::from_fn(|i| to_big(x[i], lo));
    let last = M - n;
    std::array::from_fn(|i| k[i] - k[last + i % n])
}

/// The integer types the determinant formulas are evaluated in.
trait Ring: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> {
    fn sign(self) -> Sign;
}

impl Ring for i64 {
    #[inline(always)]
    fn sign(self) -> Sign {
        Sign::of(self as f64)
    }
}

impl Ring for i128 {
    #[inline(always)]
    fn sign(self) -> Sign {
        Sign::of(self.signum() as f64)
    }
}

impl Ring for Big {
    fn sign(self) -> Sign {
        Big::sign(&self)
    }
}

// ---- The determinant formulas, once for every ring. `d` holds the differences to the last
// point, point by point (x, y[, z]). ----

#[inline(always)]
fn orient2d_ring<T: Ring>(d: [T; 4]) -> Sign {
    let [acx, acy, bcx, bcy] = d;
    (acx * bcy - acy * bcx).sign()
}

#[inline(always)]
fn orient3d_ring<T: Ring>(d: [T; 9]) -> Sign {
    let [ax, ay, az, bx, by, bz, cx, cy, cz] = d;
    (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)).sign()
}

#[inline(always)]
fn incircle_ring<T: Ring>(d: [T; 6]) -> Sign {
    let [ax, ay, bx, by, cx, cy] = d;
    let (al, bl, cl) = (ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy);
    (al * (bx * cy - cx * by) + bl * (cx * ay - ax * cy) + cl * (ax * by - bx * ay)).sign()
}

#[inline(always)]
fn insphere_ring<T: Ring>(d: [T; 12]) -> Sign {
    let [ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz] = d;
    let ab = ax * by - bx * ay;
    let bc = bx * cy - cx * by;
    let cd = cx * dy - dx * cy;
    let da = dx * ay - ax * dy;
    let ac = ax * cy - cx * ay;
    let bd = bx * dy - dx * by;
    let abc = az * bc - bz * ac + cz * ab;
    let bcd = bz * cd - cz * bd + dz * bc;
    let cda = cz * da + dz * ac + az * cd;
    let dab = dz * ab + az * bd + bz * da;
    let al = ax * ax + ay * ay + az * az;
    let bl = bx * bx + by * by + bz * bz;
    let cl = cx * cx + cy * cy + cz * cz;
    let dl = dx * dx + dy * dy + dz * dz;
    ((dl * abc - cl * dab) + (bl * cda - al * bcd)).sign()
}

// ---- Wide fixed-size arithmetic for differences of at most 62 bits. ----

/// A 192-bit two's-complement integer `hi · 2^128 + lo`.
#[derive(Clone, Copy)]
struct I192 {
    lo: u128,
    hi: u64,
}

impl I192 {
    /// `z · m` exactly, for `|z| ≤ 2^62` and `|m| ≤ 2^125`.
    #[inline(always)]
    fn product(z: i64, m: i128) -> I192 {
        // z·m = p0 + p1·2^64 with |p0| < 2^126 and |p1| ≤ 2^123: both exact in i128.
        let p0 = i128::from(z) * i128::from(m as u64);
        let p1 = i128::from(z) * (m >> 64);
        let upper = (p0 >> 64) + p1; // |upper| < 2^124
        I192 {
            lo: u128::from(p0 as u64) | (u128::from(upper as u64) << 64),
            hi: (upper >> 64) as u64,
        }
    }

    /// Sum modulo 2^192.
    #[inline(always)]
    fn add(self, o: I192) -> I192 {
        let (lo, carry) = self.lo.overflowing_add(o.lo);
        I192 {
            lo,
            hi: self.hi.wrapping_add(o.hi).wrapping_add(u64::from(carry)),
        }
    }

    #[inline(always)]
    fn sign(self) -> Sign {
        if (self.hi as i64) < 0 {
            Sign::Negative
        } else if self.hi == 0 && self.lo == 0 {
            Sign::Zero
        } else {
            Sign::Positive
        }
    }

    /// `z·m + y·n + x·o` for three 3×3-minor terms.
    #[inline(always)]
    fn dot3(z: [i64; 3], m: [i128; 3]) -> I192 {
        I192::product(z[0], m[0])
            .add(I192::product(z[1], m[1]))
            .add(I192::product(z[2], m[2]))
    }
}

/// `l · c` modulo 2^320 for a lift `l < 2^128` and a signed 192-bit `c`, as five limbs.
#[inline(always)]
fn mul_lift(l: u128, c: I192) -> [u64; 5] {
    let ls = [l as u64, (l >> 64) as u64];
    let cs = [c.lo as u64, (c.lo >> 64) as u64, c.hi];
    // l times c read as unsigned (c + 2^192 when c < 0): 2×3 limbs, exact in 5 limbs.
    let mut r = [0u64; 5];
    for (i, &x) in ls.iter().enumerate() {
        let mut carry = 0u128;
        for (j, &y) in cs.iter().enumerate() {
            let t = u128::from(x) * u128::from(y) + u128::from(r[i + j]) + carry;
            r[i + j] = t as u64;
            carry = t >> 64;
        }
        r[i + 3] = carry as u64;
    }
    // Then subtract l·2^192 if c is negative.
    let mask = ((c.hi as i64) >> 63) as u128;
    let upper = (u128::from(r[3]) | (u128::from(r[4]) << 64)).wrapping_sub(l & mask);
    r[3] = upper as u64;
    r[4] = (upper >> 64) as u64;
    r
}

/// Sum modulo 2^(64·N).
#[inline(always)]
fn add_limbs<const N: usize>(a: [u64; N], b: [u64; N]) -> [u64; N] {
    let mut r = [0u64; N];
    let mut carry = false;
    for i in 0..N {
        let (s, c1) = a[i].overflowing_add(b[i]);
        let (s, c2) = s.overflowing_add(u64::from(carry));
        r[i] = s;
        carry = c1 | c2;
    }
    r
}

/// Sign of a two's-complement integer in `N` limbs.
#[inline(always)]
fn sign_limbs<const N: usize>(r: [u64; N]) -> Sign {
    if (r[N - 1] as i64) < 0 {
        Sign::Negative
    } else if r.iter().all(|&x| x == 0) {
        Sign::Zero
    } else {
        Sign::Positive
    }
}

#[inline(always)]
fn minor2(p: [i64; 2], q: [i64; 2]) -> i128 {
    // |·| ≤ 2·2^124 = 2^125 for |coordinates| ≤ 2^62.
    i128::from(p[0]) * i128::from(q[1]) - i128::from(q[0]) * i128::from(p[1])
}

#[inline(always)]
fn lift3(p: [i64; 3]) -> u128 {
    // < 3·2^124 < 2^126.
    (i128::from(p[0]) * i128::from(p[0])
        + i128::from(p[1]) * i128::from(p[1])
        + i128::from(p[2]) * i128::from(p[2])) as u128
}

fn orient3d_wide(d: [i64; 9]) -> Sign {
    let [ax, ay, az, bx, by, bz, cx, cy, cz] = d;
    let m = [
        minor2([by, bz], [cy, cz]),
        minor2([bx, bz], [cx, cz]),
        minor2([bx, by], [cx, cy]),
    ];
    I192::dot3([ax, -ay, az], m).sign()
}

fn incircle_wide(d: [i64; 6]) -> Sign {
    let [ax, ay, bx, by, cx, cy] = d;
    let lift = |x: i64, y: i64| i128::from(x) * i128::from(x) + i128::from(y) * i128::from(y);
    let terms = [
        (lift(ax, ay), minor2([bx, by], [cx, cy])),
        (lift(bx, by), minor2([cx, cy], [ax, ay])),
        (lift(cx, cy), minor2([ax, ay], [bx, by])),
    ];
    // lift ≤ 2^125 and |minor| ≤ 2^125: each product of magnitude ≤ 2^250, in 256 bits.
    let mut sum = [0u64; 4];
    for (l, m) in terms {
        let (l, mu) = (l as u128, m as u128);
        let (l0, l1) = (l as u64, (l >> 64) as u64);
        let (m0, m1) = (mu as u64, (mu >> 64) as u64);
        // l · (m read as unsigned), 2×2 limbs, then − l·2^128 if m < 0.
        let mut r = [0u64; 4];
        for (i, &x) in [l0, l1].iter().enumerate() {
            let mut carry = 0u128;
            for (j, &y) in [m0, m1].iter().enumerate() {
                let t = u128::from(x) * u128::from(y) + u128::from(r[i + j]) + carry;
                r[i + j] = t as u64;
                carry = t >> 64;
            }
            r[i + 2] = carry as u64;
        }
        let mask = (m >> 127) as u128;
        let upper = (u128::from(r[2]) | (u128::from(r[3]) << 64)).wrapping_sub(l & mask);
        r[2] = upper as u64;
        r[3] = (upper >> 64) as u64;
        sum = add_limbs(sum, r);
    }
    sign_limbs(sum)
}

fn insphere_wide(d: [i64; 12]) -> Sign {
    let a = [d[0], d[1], d[2]];
    let b = [d[3], d[4], d[5]];
    let c = [d[6], d[7], d[8]];
    let e = [d[9], d[10], d[11]];
    let xy = |p: [i64; 3], q: [i64; 3]| minor2([p[0], p[1]], [q[0], q[1]]);
    let (ab, bc, cd, da, ac, bd) = (xy(a, b), xy(b, c), xy(c, e), xy(e, a), xy(a, c), xy(b, e));
    // The four 3×3 minors, the two subtracted ones negated (|z| ≤ 2^62, so −z is an i64).
    let abc = I192::dot3([a[2], -b[2], c[2]], [bc, ac, ab]);
    let neg_bcd = I192::dot3([-b[2], c[2], -e[2]], [cd, bd, bc]);
    let cda = I192::dot3([c[2], e[2], a[2]], [da, ac, cd]);
    let neg_dab = I192::dot3([-e[2], -a[2], -b[2]], [ab, bd, da]);
    let sum = add_limbs(
        add_limbs(mul_lift(lift3(e), abc), mul_lift(lift3(c), neg_dab)),
        add_limbs(mul_lift(lift3(b), cda), mul_lift(lift3(a), neg_bcd)),
    );
    sign_limbs(sum)
}

// ---- Entry points: the sign of robust's determinant, or None (then the caller asks robust). --

/// Sign of `robust::orient2d(a, b, c)` for `x = [a, b, c]` flattened.
#[inline]
pub(crate) fn orient2d(x: &[f64; 6]) -> Option<Sign> {
    if let Some(d) = small_differences::<6, 4>(x, 2) {
        // |d| < 2^62: the 2×2 determinant is below 2^125 in i128.
        return Some(orient2d_ring(d.map(i128::from)));
    }
    orient2d_general(x)
}

/// Sign of `robust::orient3d(a, b, c, d)` for `x = [a, b, c, d]` flattened.
#[inline]
pub(crate) fn orient3d(x: &[f64; 12]) -> Option<Sign> {
    if let Some(mut d) = small_differences::<12, 9>(x, 3) {
        return Some(if reduce(&mut d, 20) <= 20 {
            orient3d_ring(d)
        } else {
            orient3d_wide(d)
        });
    }
    orient3d_general(x)
}

/// Sign of `robust::incircle(a, b, c, d)` for `x = [a, b, c, d]` flattened.
#[inline]
pub(crate) fn incircle(x: &[f64; 8]) -> Option<Sign> {
    if let Some(mut d) = small_differences::<8, 6>(x, 2) {
        return Some(if reduce(&mut d, 14) <= 14 {
            incircle_ring(d)
        } else {
            incircle_wide(d)
        });
    }
    incircle_general(x)
}

/// Sign of `robust::insphere(a, b, c, d, e)` for `x = [a, b, c, d, e]` flattened.
#[inline]
pub(crate) fn insphere(x: &[f64; 15]) -> Option<Sign> {
    if let Some(mut d) = small_differences::<15, 12>(x, 3) {
        return Some(if reduce(&mut d, 11) <= 11 {
            insphere_ring(d)
        } else {
            insphere_wide(d)
        });
    }
    insphere_general(x)
}

// The general conversion, for coordinates spanning more than 61 bits (or beyond 2^61): out of
// line, so that the common path above keeps a small stack frame.

#[cold]
#[inline(never)]
fn orient2d_general(x: &[f64; 6]) -> Option<Sign> {
    match differences::<6, 4>(x, 2)? {
        Ok((d, b)) if b <= 62 => Some(orient2d_ring(d)),
        Ok((d, _)) => Some(orient2d_ring(d.map(Big::from_i128))),
        Err(b) if b <= BIG_B => Some(orient2d_ring(big_differences(x, 2))),
        Err(_) => None,
    }
}

#[cold]
#[inline(never)]
fn orient3d_general(x: &[f64; 12]) -> Option<Sign> {
    match differences::<12, 9>(x, 3)? {
        Ok((d, b)) if b <= 20 => Some(orient3d_ring(d.map(|v| v as i64))),
        Ok((d, b)) if b <= 62 => Some(orient3d_wide(d.map(|v| v as i64))),
        Ok((d, _)) => Some(orient3d_ring(d.map(Big::from_i128))),
        Err(b) if b <= BIG_B => Some(orient3d_ring(big_differences(x, 3))),
        Err(_) => None,
    }
}

#[cold]
#[inline(never)]
fn incircle_general(x: &[f64; 8]) -> Option<Sign> {
    match differences::<8, 6>(x, 2)? {
        Ok((d, b)) if b <= 14 => Some(incircle_ring(d.map(|v| v as i64))),
        Ok((d, b)) if b <= 62 => Some(incircle_wide(d.map(|v| v as i64))),
        Ok((d, _)) => Some(incircle_ring(d.map(Big::from_i128))),
        Err(b) if b <= BIG_B => Some(incircle_ring(big_differences(x, 2))),
        Err(_) => None,
    }
}

#[cold]
#[inline(never)]
fn insphere_general(x: &[f64; 15]) -> Option<Sign> {
    match differences::<15, 12>(x, 3)? {
        Ok((d, b)) if b <= 11 => Some(insphere_ring(d.map(|v| v as i64))),
        Ok((d, b)) if b <= 62 => Some(insphere_wide(d.map(|v| v as i64))),
        Ok((d, _)) => Some(insphere_ring(d.map(Big::from_i128))),
        Err(b) if b <= BIG_B => Some(insphere_ring(big_differences(x, 3))),
        Err(_) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};

    /// Cases per generator: `DELMESH_PREDICATE_CASES` (default 20,000; the long run used for
    /// the README is 1,000,000).
    fn cases() -> usize {
        std::env::var("DELMESH_PREDICATE_CASES")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(20_000)
    }

    fn c2(p: &[f64]) -> robust::Coord<f64> {
        robust::Coord { x: p[0], y: p[1] }
    }

    fn c3(p: &[f64]) -> robust::Coord3D<f64> {
        robust::Coord3D {
            x: p[0],
            y: p[1],
            z: p[2],
        }
    }

    /// `x` moved by `k` ulps.
    fn ulps(x: f64, k: i64) -> f64 {
        let mut y = x;
        for _ in 0..k.unsigned_abs() {
            y = if k > 0 { y.next_up() } else { y.next_down() };
        }
        y
    }

    /// A uniform value in `[-1, 1]` with a full 53-bit mantissa (not only multiples of 2^-53).
    fn full(rng: &mut StdRng) -> f64 {
        let m: f64 = rng.gen_range(0.5..1.0);
        let e: i32 = -rng.gen_range(0..6);
        if rng.gen() {
            m * 2f64.powi(e)
        } else {
            -m * 2f64.powi(e)
        }
    }

    fn unit(rng: &mut StdRng) -> [f64; 3] {
        loop {
            let v = [full(rng), full(rng), full(rng)];
            let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if r > 0.1 {
                return v.map(|x| x / r);
            }
        }
    }

    /// A power of two inside the kernel's range `[2^-142, 2^201]`, with a bias to the limits.
    fn magnitude(rng: &mut StdRng) -> f64 {
        match rng.gen_range(0..4) {
            0 => 2f64.powi(rng.gen_range(-142..-100)),
            1 => 2f64.powi(rng.gen_range(150..195)),
            _ => 2f64.powi(rng.gen_range(-40..40)),
        }
    }

    /// Five points from one of the generators: uniform, nearly co-spherical, exactly
    /// co-spherical (box corners, grids), coplanar and co-circular, near the coordinate planes,
    /// ulp-sized clusters, at every magnitude of the range and of both signs.
    fn points(rng: &mut StdRng, kind: usize) -> [[f64; 3]; 5] {
        let s = magnitude(rng);
        let mut p = [[0.0; 3]; 5];
        match kind {
            // Uniform.
            0 => {
                for q in &mut p {
                    *q = [full(rng) * s, full(rng) * s, full(rng) * s];
                }
            }
            // Nearby points on a sphere (the kernel's surface case), rounded, nudged by ulps.
            1 => {
                let centre = [full(rng) * s, full(rng) * s, full(rng) * s];
                let r = s * rng.gen_range(0.1..2.0);
                let u0 = unit(rng);
                let h = 2f64.powi(-rng.gen_range(1..30));
                for q in &mut p {
                    let u = unit(rng);
                    let v = [u0[0] + h * u[0], u0[1] + h * u[1], u0[2] + h * u[2]];
                    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    for k in 0..3 {
                        q[k] = centre[k] + r * v[k] / n;
                        if rng.gen_range(0..3) == 0 {
                            q[k] = ulps(q[k], rng.gen_range(-3..=3));
                        }
                    }
                }
            }
            // Corners of a box with non-dyadic sides: exactly co-spherical and co-circular,
            // sometimes nudged by an ulp.
            2 => {
                let lo = [full(rng) * s, full(rng) * s, full(rng) * s];
                let hi = lo.map(|x| x + s * rng.gen_range(1e-9..1.0));
                let mut corners: Vec<usize> = (0..8).collect();
                for (i, q) in p.iter_mut().enumerate() {
                    let j = rng.gen_range(i..8);
                    corners.swap(i, j);
                    let c = corners[i];
                    *q = std::array::from_fn(|k| if c >> k & 1 == 0 { lo[k] } else { hi[k] });
                }
                if rng.gen() {
                    let (i, k) = (rng.gen_range(0..5), rng.gen_range(0..3));
                    p[i][k] = ulps(p[i][k], if rng.gen() { 1 } else { -1 });
                }
            }
            // A dyadic grid with an offset: many exact zeros in every predicate.
            3 => {
                let step = s * 2f64.powi(-rng.gen_range(0..20));
                let offset = [full(rng) * s, full(rng) * s, full(rng) * s];
                let n = rng.gen_range(2..5);
                for q in &mut p {
                    *q = std::array::from_fn(|k| offset[k] + step * f64::from(rng.gen_range(0..n)));
                }
            }
            // Four co-circular points on an axis-aligned plane (a rectangle), one anywhere.
            4 => {
                let axis = rng.gen_range(0..3);
                let level = full(rng) * s;
                let lo = [full(rng) * s, full(rng) * s];
                let hi = [lo[0] + s * rng.gen_range(1e-6..1.0), lo[1] + s * 0.3];
                for (i, q) in p.iter_mut().enumerate().take(4) {
                    let uv = [
                        if i & 1 == 0 { lo[0] } else { hi[0] },
                        if i & 2 == 0 { lo[1] } else { hi[1] },
                    ];
                    q[axis] = level;
                    q[(axis + 1) % 3] = uv[0];
                    q[(axis + 2) % 3] = uv[1];
                }
                p[4] = if rng.gen() {
                    [full(rng) * s, full(rng) * s, full(rng) * s]
                } else {
                    let mut q = p[rng.gen_range(0..4)];
                    q[(axis + 1) % 3] = full(rng) * s; // coplanar
                    q
                };
                p.swap(rng.gen_range(0..5), rng.gen_range(0..5));
                if rng.gen() {
                    let (i, k) = (rng.gen_range(0..5), rng.gen_range(0..3));
                    p[i][k] = ulps(p[i][k], if rng.gen() { 1 } else { -1 });
                }
            }
            // Near-spherical points with some coordinates tiny or zero: wide spans (Big).
            5 => {
                p = points(rng, 1);
                for _ in 0..rng.gen_range(1..4) {
                    let (i, k) = (rng.gen_range(0..5), rng.gen_range(0..3));
                    p[i][k] = match rng.gen_range(0..3) {
                        0 => 0.0,
                        1 => full(rng) * 2f64.powi(-rng.gen_range(0..142)),
                        _ => full(rng) * 1.7e-43,
                    };
                }
                let (lo, hi) = COORDINATE_RANGE_TEST;
                for q in p.iter_mut().flatten() {
                    if q.abs() > hi {
                        *q = hi.copysign(*q);
                    } else if *q != 0.0 && q.abs() < lo {
                        *q = lo.copysign(*q);
                    }
                }
            }
            // A cluster of points a few ulps apart: tiny differences of huge coordinates.
            _ => {
                let centre = [full(rng) * s, full(rng) * s, full(rng) * s];
                for q in &mut p {
                    *q = centre.map(|x| ulps(x, rng.gen_range(-4..=4)));
                }
            }
        }
        p
    }

    const COORDINATE_RANGE_TEST: (f64, f64) = crate::COORDINATE_RANGE;
    const KINDS: usize = 7;

    fn in_range(p: &[[f64; 3]; 5]) -> bool {
        let (lo, hi) = crate::COORDINATE_RANGE;
        p.iter()
            .flatten()
            .all(|&x| x == 0.0 || (lo..=hi).contains(&x.abs()))
    }

    /// Every predicate of the integer stage and of the public API (filter first) against
    /// robust, on the same points.
    fn check(p: [[f64; 3]; 5], stats: &mut [usize; 6]) {
        let [a, b, c, d, e] = p;
        let flat5: [f64; 15] = std::array::from_fn(|i| p[i / 3][i % 3]);
        // Which insphere path answers: the fast conversion, the general one into i128, Big.
        stats[match (
            small_differences::<15, 12>(&flat5, 3),
            differences::<15, 12>(&flat5, 3),
        ) {
            (Some(_), _) => 3,
            (None, Some(Ok(_))) => 4,
            _ => 5,
        }] += 1;
        let want = Sign::of(robust::insphere(c3(&a), c3(&b), c3(&c), c3(&d), c3(&e)));
        stats[(want.as_i32() + 1) as usize] += 1;
        assert_eq!(insphere(&flat5), Some(want), "insphere {p:?}");
        assert_eq!(crate::insphere(a, b, c, d, e), want.reversed(), "{p:?}");
        let flat4: [f64; 12] = std::array::from_fn(|i| flat5[i + 3]);
        let want = Sign::of(robust::orient3d(c3(&b), c3(&c), c3(&d), c3(&e)));
        assert_eq!(orient3d(&flat4), Some(want), "orient3d {p:?}");
        assert_eq!(crate::orient3d(b, c, d, e), want.reversed(), "{p:?}");
        // 2D: the xy, yz and zx projections.
        for k in 0..3 {
            let q = p.map(|v| [v[k], v[(k + 1) % 3]]);
            let flat: [f64; 8] = std::array::from_fn(|i| q[i / 2][i % 2]);
            let want = Sign::of(robust::incircle(c2(&q[0]), c2(&q[1]), c2(&q[2]), c2(&q[3])));
            assert_eq!(incircle(&flat), Some(want), "incircle {q:?}");
            assert_eq!(crate::incircle(q[0], q[1], q[2], q[3]), want, "{q:?}");
            let flat: [f64; 6] = std::array::from_fn(|i| q[2 + i / 2][i % 2]);
            let want = Sign::of(robust::orient2d(c2(&q[2]), c2(&q[3]), c2(&q[4])));
            assert_eq!(orient2d(&flat), Some(want), "orient2d {q:?}");
            assert_eq!(crate::orient2d(q[2], q[3], q[4]), want, "{q:?}");
        }
    }

    #[test]
    fn agrees_with_robust_on_every_generator() {
        for kind in 0..KINDS {
            let mut rng = StdRng::seed_from_u64(1000 + kind as u64);
            let mut stats = [0usize; 6];
            let mut checked = 0;
            while checked < cases() {
                let p = points(&mut rng, kind);
                if in_range(&p) {
                    check(p, &mut stats);
                    checked += 1;
                }
            }
            println!(
                "generator {kind}: insphere signs (−, 0, +) {:?}, paths (fast, i128, Big) {:?}",
                &stats[..3],
                &stats[3..]
            );
            // The degenerate generators must produce zeros (or the test would be vacuous).
            if [2, 3, 4].contains(&kind) {
                assert!(stats[1] > checked / 20, "kind {kind}: {stats:?}");
            }
        }
    }

    /// Random differences of exactly `b` bits (the extreme values included) in every tier
    /// that holds them, against the Big evaluation (independent code).
    #[test]
    fn tiers_agree_at_their_limits() {
        let mut rng = StdRng::seed_from_u64(99);
        let value = |b: i32, rng: &mut StdRng| -> i128 {
            let m = 1i128 << b;
            match rng.gen_range(0..6) {
                0 => m,
                1 => -m,
                2 => m - 1,
                3 => -(m - 1),
                _ => rng.gen_range(-m..=m),
            }
        };
        for round in 0..cases() {
            let b = [11, 14, 20, 24, 41, 62][round % 6];
            let d: [i128; 12] = std::array::from_fn(|_| value(b, &mut rng));
            // Exact zeros too: repeat a row or make two rows opposite.
            let mut d = d;
            if round % 5 == 0 {
                let (i, j) = (rng.gen_range(0..4), rng.gen_range(0..4));
                for k in 0..3 {
                    d[3 * i + k] = d[3 * j + k];
                }
            }
            let big = |v: &[i128]| -> Vec<Big> { v.iter().map(|&x| Big::from_i128(x)).collect() };
            let d12: [Big; 12] = big(&d).try_into().unwrap();
            let want = insphere_ring(d12);
            assert_eq!(insphere_wide(d.map(|v| v as i64)), want, "{d:?}");
            if b <= 11 {
                assert_eq!(insphere_ring(d.map(|v| v as i64)), want);
            }
            if b <= 24 {
                assert_eq!(insphere_ring(d), want);
            }
            let d9: [i128; 9] = std::array::from_fn(|i| d[i]);
            let want = orient3d_ring::<Big>(big(&d9).try_into().unwrap());
            assert_eq!(orient3d_wide(d9.map(|v| v as i64)), want, "{d9:?}");
            if b <= 20 {
                assert_eq!(orient3d_ring(d9.map(|v| v as i64)), want);
            }
            if b <= 41 {
                assert_eq!(orient3d_ring(d9), want);
            }
            let d6: [i128; 6] = std::array::from_fn(|i| d[i]);
            let want = incircle_ring::<Big>(big(&d6).try_into().unwrap());
            assert_eq!(incircle_wide(d6.map(|v| v as i64)), want, "{d6:?}");
            if b <= 14 {
                assert_eq!(incircle_ring(d6.map(|v| v as i64)), want);
            }
            if b <= 30 {
                assert_eq!(incircle_ring(d6), want);
            }
            let d4: [i128; 4] = std::array::from_fn(|i| d[i]);
            let want = orient2d_ring::<Big>(big(&d4).try_into().unwrap());
            assert_eq!(orient2d_ring(d4), want);
        }
    }

    /// The Big tier at the widest spans the kernel produces: coordinates from `2^-142` to
    /// just below 1 in one call (b = 195), against robust.
    #[test]
    fn widest_kernel_spans() {
        let mut rng = StdRng::seed_from_u64(5);
        let tiny = 2f64.powi(-142);
        for _ in 0..cases() / 10 {
            let mut p = [[0.0; 3]; 5];
            for q in &mut p {
                for x in q.iter_mut() {
                    *x = match rng.gen_range(0..4) {
                        0 => ulps(0.75, rng.gen_range(-3..=3)),
                        1 => -tiny * rng.gen_range(1.0..1.9),
                        2 => full(&mut rng),
                        _ => ulps(tiny, rng.gen_range(0..=3)),
                    };
                }
            }
            // At least one coordinate at each end of the range.
            p[rng.gen_range(0..5)][0] = 0.75;
            p[rng.gen_range(0..5)][1 + rng.gen_range(0..2)] = tiny;
            let flat: [f64; 15] = std::array::from_fn(|i| p[i / 3][i % 3]);
            let got = differences::<15, 12>(&flat, 3).map(|r| r.map(|(_, b)| b));
            assert!(matches!(got, Some(Err(b)) if b <= 196), "{got:?} {flat:?}");
            check(p, &mut [0; 6]);
        }
    }

    /// The fast conversion takes exactly the spans of at most 61 bits below `2^(E − 1022)`.
    #[test]
    fn fast_conversion_limits() {
        let t = 2f64.powi(-60);
        let fast = |x: [f64; 6]| small_differences::<6, 4>(&x, 2);
        // 1.0 has E = 1023: S = 2^60, so 2^-60 scales to 1 and 2^-61 to 1/2.
        assert_eq!(fast([1.0, 0.0, t, -t, 0.0, 0.0]), Some([1 << 60, 0, 1, -1]));
        assert_eq!(fast([1.0, 0.0, t / 2.0, 0.0, 0.0, 0.0]), None);
        assert_eq!(
            fast([-1.5, 0.0, 0.0, 0.0, 0.0, 0.75]),
            Some([-3 << 59, -3 << 58, 0, -3 << 58])
        );
        assert_eq!(fast([0.0; 6]), None);
        assert_eq!(fast([f64::INFINITY, 0.0, 0.0, 0.0, 0.0, 0.0]), None);
        assert_eq!(fast([f64::from_bits(3), 0.0, 0.0, 0.0, 0.0, 0.0]), None); // all subnormal
        let big = 2f64.powi(1000);
        assert_eq!(
            fast([big, 0.0, 0.0, big, 0.0, 0.0]),
            Some([1 << 60, 0, 0, 1 << 60])
        );
        // Beyond the fast span the general path answers, and agrees.
        let x = [1.0, 0.0, t / 2.0, 1.0, 0.0, 0.0];
        assert_eq!(orient2d(&x), Some(Sign::Positive)); // 1·1 − 0·2^-61
        assert_eq!(
            orient2d(&x),
            Some(Sign::of(robust::orient2d(
                c2(&x[0..]),
                c2(&x[2..]),
                c2(&x[4..])
            )))
        );
    }

    #[test]
    fn out_of_range_and_non_finite_fall_back() {
        let p = [0.0, 0.0, 1.0, 0.0, 0.0, f64::NAN];
        assert_eq!(orient2d(&p), None);
        let q = [0.0, 0.0, 1.0, 0.0, 0.0, f64::INFINITY];
        assert_eq!(orient2d(&q), None);
        // A span of 2^-1074 to 2^1000 is beyond every Big tier.
        let mut x = [0.0; 15];
        x[0] = 2f64.powi(1000);
        x[4] = f64::from_bits(1);
        x[8] = 1.0;
        assert_eq!(insphere(&x), None);
        // Subnormals within a narrow span are still exact.
        let s = f64::from_bits(1);
        let sub = [0.0, 0.0, 2.0 * s, 0.0, 0.0, 2.0 * s];
        assert_eq!(orient2d(&sub), Some(Sign::Positive));
        assert_eq!(orient2d(&[0.0; 6]), Some(Sign::Zero));
    }
}
