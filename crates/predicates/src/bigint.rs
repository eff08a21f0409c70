//! A small signed big integer on the stack, for the rare predicate calls whose coordinates
//! span too many bits for the fixed-width integer paths of [`crate::integer`].
//!
//! Sign and magnitude, the magnitude in at most [`CAP`] little-endian 64-bit limbs with `len`
//! of them in use (the rest are zero and never read). Addition, subtraction and
//! multiplication are the schoolbook algorithms on the used limbs and are exact; a result
//! that would need more than [`CAP`] limbs is a bug in the caller's size bound and panics
//! (the callers only build `Big`s from differences bounded so that every intermediate of
//! their determinant fits, see [`crate::integer`]).

use crate::Sign;
use std::cmp::Ordering;
use std::ops::{Add, Mul, Neg, Sub};

/// Capacity in limbs: 2048 bits.
pub(crate) const CAP: usize = 32;

/// A signed integer `±(mag[0] + mag[1]·2^64 + …)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Big {
    neg: bool,
    len: usize,
    mag: [u64; CAP],
}

impl Big {
    const ZERO: Big = Big {
        neg: false,
        len: 0,
        mag: [0; CAP],
    };

    /// The integer `v`.
    pub(crate) fn from_i128(v: i128) -> Big {
        let m = v.unsigned_abs();
        let mut r = Big::ZERO;
        r.mag[0] = m as u64;
        r.mag[1] = (m >> 64) as u64;
        r.len = 2;
        r.neg = v < 0;
        r.trim();
        r
    }

    /// The integer `±mant · 2^shift`.
    pub(crate) fn from_shifted(mant: u64, shift: u32, neg: bool) -> Big {
        let mut r = Big::ZERO;
        let (q, s) = ((shift / 64) as usize, shift % 64);
        let wide = u128::from(mant) << s;
        assert!(q + 2 <= CAP, "Big capacity exceeded");
        r.mag[q] = wide as u64;
        r.mag[q + 1] = (wide >> 64) as u64;
        r.len = q + 2;
        r.neg = neg;
        r.trim();
        r
    }

    /// The sign.
    pub(crate) fn sign(&self) -> Sign {
        match (self.len, self.neg) {
            (0, _) => Sign::Zero,
            (_, true) => Sign::Negative,
            (_, false) => Sign::Positive,
        }
    }

    /// `(m, e)` with `m · 2^e` the integer rounded to the nearest `f64` (`m` carries the sign;
    /// `(0, 0)` for zero): its top 64 bits, with any set bit below them folded into the lowest
    /// one (a sticky bit), so that converting them rounds as the whole number would.
    pub(crate) fn rounded(&self) -> (f64, i32) {
        if self.len == 0 {
            return (0.0, 0);
        }
        let top = self.mag[self.len - 1];
        let bits = 64 * (self.len as u32 - 1) + (64 - top.leading_zeros());
        let shift = bits.saturating_sub(64);
        let (q, r) = ((shift / 64) as usize, shift % 64);
        let mut m = self.mag[q] >> r;
        if r != 0 && q + 1 < self.len {
            m |= self.mag[q + 1] << (64 - r);
        }
        let dropped =
            (r != 0 && self.mag[q] << (64 - r) != 0) || self.mag[..q].iter().any(|&x| x != 0);
        m |= u64::from(dropped);
        let m = m as f64;
        (if self.neg { -m } else { m }, shift as i32)
    }

    fn used(&self) -> &[u64] {
        &self.mag[..self.len]
    }

    /// Drops leading zero limbs; zero is never negative.
    fn trim(&mut self) {
        while self.len > 0 && self.mag[self.len - 1] == 0 {
            self.len -= 1;
        }
        if self.len == 0 {
            self.neg = false;
        }
    }
}

fn cmp_mag(a: &[u64], b: &[u64]) -> Ordering {
    // Both are trimmed: the longer is larger.
    a.len().cmp(&b.len()).then_with(|| {
        for (x, y) in a.iter().rev().zip(b.iter().rev()) {
            match x.cmp(y) {
                Ordering::Equal => continue,
                o => return o,
            }
        }
        Ordering::Equal
    })
}

/// `|a| + |b|` with the given sign.
fn add_mag(a: &Big, b: &Big, neg: bool) -> Big {
    let (long, short) = if a.len >= b.len { (a, b) } else { (b, a) };
    let mut r = Big::ZERO;
    let mut carry = 0u64;
    for i in 0..long.len {
        let y = if i < short.len { short.mag[i] } else { 0 };
        let (s, c1) = long.mag[i].overflowing_add(y);
        let (s, c2) = s.overflowing_add(carry);
        r.mag[i] = s;
        carry = u64::from(c1 | c2);
    }
    r.len = long.len;
    if carry != 0 {
        assert!(r.len < CAP, "Big capacity exceeded");
        r.mag[r.len] = carry;
        r.len += 1;
    }
    r.neg = neg;
    r.trim();
    r
}

/// `|a| − |b|` for `|a| ≥ |b|`, with the given sign.
fn sub_mag(a: &Big, b: &Big, neg: bool) -> Big {
    let mut r = Big::ZERO;
    let mut borrow = 0u64;
    for i in 0..a.len {
        let y = if i < b.len { b.mag[i] } else { 0 };
        let (s, b1) = a.mag[i].overflowing_sub(y);
        let (s, b2) = s.overflowing_sub(borrow);
        r.mag[i] = s;
        borrow = u64::from(b1 | b2);
    }
    debug_assert_eq!(borrow, 0);
    r.len = a.len;
    r.neg = neg;
    r.trim();
    r
}

impl Add for Big {
    type Output = Big;
    fn add(self, b: Big) -> Big {
        if self.neg == b.neg {
            return add_mag(&self, &b, self.neg);
        }
        match cmp_mag(self.used(), b.used()) {
            Ordering::Less => sub_mag(&b, &self, b.neg),
            _ => sub_mag(&self, &b, self.neg),
        }
    }
}

impl Neg for Big {
    type Output = Big;
    fn neg(mut self) -> Big {
        self.neg = !self.neg && self.len > 0;
        self
    }
}

impl Sub for Big {
    type Output = Big;
    fn sub(self, b: Big) -> Big {
        self + (-b)
    }
}

impl Mul for Big {
    type Output = Big;
    fn mul(self, b: Big) -> Big {
        if self.len == 0 || b.len == 0 {
            return Big::ZERO;
        }
        assert!(self.len + b.len <= CAP, "Big capacity exceeded");
        let mut r = Big::ZERO;
        for (i, &x) in self.used().iter().enumerate() {
            let mut carry = 0u128;
            for (j, &y) in b.used().iter().enumerate() {
                let t = u128::from(x) * u128::from(y) + u128::from(r.mag[i + j]) + carry;
                r.mag[i + j] = t as u64;
                carry = t >> 64;
            }
            r.mag[i + b.len] = carry as u64;
        }
        r.len = self.len + b.len;
        r.neg = self.neg != b.neg;
        r.trim();
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Big` agrees with `i128` wherever `i128` does not overflow.
    #[test]
    fn agrees_with_i128() {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for _ in 0..20_000 {
            let bits = (rnd() % 62) as u32;
            let a = (rnd() as i64 >> bits) as i128;
            let b = (rnd() as i64 >> (rnd() % 62)) as i128;
            let (x, y) = (Big::from_i128(a), Big::from_i128(b));
            for (big, small) in [(x + y, a + b), (x - y, a - b), (x * y, a * b), (-x, -a)] {
                assert_eq!(big.sign(), Sign::of(small as f64), "{a} {b}");
                let expect = Big::from_i128(small);
                assert_eq!(big.used(), expect.used());
            }
        }
    }

    #[test]
    fn conversion_rounds_to_nearest() {
        // 2^200 + 2^147 + 1: the bit just below the 53 kept ones is set, and so is a far lower
        // one, so it rounds up (without the sticky bit it would be a tie, rounded to even).
        let x =
            Big::from_shifted(1, 200, false) + Big::from_shifted(1, 147, false) + Big::from_i128(1);
        let (m, e) = x.rounded();
        assert_eq!(m * 2f64.powi(e), 2f64.powi(200) + 2f64.powi(148));
        let (m, e) = (-Big::from_i128(-12345)).rounded();
        assert_eq!((m, e), (12345.0, 0));
        let (m, e) = Big::from_i128(-(1i128 << 100) - 3).rounded();
        assert_eq!(m * 2f64.powi(e), -(2f64.powi(100)));
        assert_eq!(Big::ZERO.rounded(), (0.0, 0));
    }

    #[test]
    fn wide_products_and_shifts() {
        // (2^64 − 1)² = 2^128 − 2^65 + 1, and 3·2^200 − 2^200 = 2^201.
        let m = Big::from_i128(u64::MAX as i128);
        let sq = m * m;
        assert_eq!(sq.used(), &[1, u64::MAX - 1]);
        let a = Big::from_shifted(3, 200, false) - Big::from_shifted(1, 200, false);
        assert_eq!(a.used(), Big::from_shifted(1, 201, false).used());
        let z = a - a;
        assert_eq!(z.sign(), Sign::Zero);
        assert_eq!((-a).sign(), Sign::Negative);
        assert_eq!((a * -a).sign(), Sign::Negative);
    }
}
