//! Symbolically perturbed in-circle and in-sphere tests that never return zero.
//!
//! The in-circle (in-sphere) determinant is linear in the lifted coordinates `w_i = |p_i|²` of its
//! points. We perturb them to `w_i + ε^(k_i)` where a larger id gets a smaller exponent `k_i`, so
//! the point with the largest id is perturbed most. When the exact determinant is zero, its sign
//! after perturbation is the sign of the coefficient of the dominant (largest-id) perturbation
//! whose coefficient is non-zero. Each coefficient is the orientation of the other points:
//!
//! - the query point's own coefficient is `−orient(a, b, c[, d])`: raising its lift moves it
//!   outside. It is never zero since the simplex is non-degenerate, so the loop always ends;
//! - the coefficient of a simplex vertex `p_i` is the orientation of the simplex with `p_i`
//!   replaced by the query point (the determinant is alternating in its points).
//!
//! Because this is a real perturbation of a (weighted) point set, every answer is consistent
//! with every other: there is exactly one perturbed Delaunay triangulation, and it is one of the
//! Delaunay triangulations of the unperturbed points.

use crate::{incircle, insphere, orient2d, orient3d, Sign};

/// In-circle test with symbolic perturbation: [`Sign::Positive`] if `p[3]` is inside the circle
/// through `p[0], p[1], p[2]`, never [`Sign::Zero`] for distinct ids.
///
/// `ids` rank the points (any consistent total order: vertex indices, or [`Lex`] for the
/// coordinates themselves): the same point must always carry the same id, and distinct points
/// distinct ids. The point with the largest id is perturbed most.
///
/// Precondition: `orient2d(p[0], p[1], p[2])` is positive.
pub fn incircle_sos<K: Ord + Copy>(p: [[f64; 2]; 4], ids: [K; 4]) -> Sign {
    let exact = incircle(p[0], p[1], p[2], p[3]);
    if exact != Sign::Zero {
        return exact;
    }
    incircle_tiebreak(p, ids)
}

/// The perturbed answer of [`incircle_sos`] for four points already known to be exactly
/// co-circular (`incircle` returned zero): saves re-evaluating the determinant.
///
/// Precondition: as [`incircle_sos`], and `incircle(p[0], …, p[3])` is zero.
pub fn incircle_tiebreak<K: Ord + Copy>(p: [[f64; 2]; 4], ids: [K; 4]) -> Sign {
    let mut order = DecreasingIds::new(ids);
    while let Some(slot) = order.next() {
        let coefficient = if slot == 3 {
            orient2d(p[0], p[1], p[2]).reversed()
        } else {
            let mut q = [p[0], p[1], p[2]];
            q[slot] = p[3];
            orient2d(q[0], q[1], q[2])
        };
        if coefficient != Sign::Zero {
            return coefficient;
        }
    }
    // Only reachable when the precondition is violated (p[0], p[1], p[2] collinear).
    Sign::Zero
}

/// In-sphere test with symbolic perturbation: [`Sign::Positive`] if `p[4]` is inside the sphere
/// through `p[0..4]`, never [`Sign::Zero`] for distinct ids.
///
/// `ids` are the points' global identifiers, as for [`incircle_sos`].
///
/// Precondition: `orient3d(p[0], p[1], p[2], p[3])` is positive.
pub fn insphere_sos<K: Ord + Copy>(p: [[f64; 3]; 5], ids: [K; 5]) -> Sign {
    let exact = insphere(p[0], p[1], p[2], p[3], p[4]);
    if exact != Sign::Zero {
        return exact;
    }
    insphere_tiebreak(p, ids)
}

/// The perturbed answer of [`insphere_sos`] for five points already known to be exactly
/// co-spherical (`insphere` returned zero): saves re-evaluating the determinant.
///
/// Precondition: as [`insphere_sos`], and `insphere(p[0], …, p[4])` is zero.
pub fn insphere_tiebreak<K: Ord + Copy>(p: [[f64; 3]; 5], ids: [K; 5]) -> Sign {
    tiebreak3(&p, ids)
}

/// The in-sphere test delmesh uses: exact, with the perturbation ranked by the points'
/// lexicographic order (the lexicographically smallest point is perturbed most), so it never
/// returns zero and degenerate input gets a triangulation that depends only on the geometry.
///
/// Precondition: `orient3d(p[0], p[1], p[2], p[3])` is positive.
#[inline]
pub fn insphere_lex(p: [[f64; 3]; 5]) -> Sign {
    if let Some(s) = crate::exact::insphere_filter(p[0], p[1], p[2], p[3], p[4]) {
        return s;
    }
    insphere_lex_exact(p)
}

/// [`insphere_lex`] after its filter failed: out of line, so that the fast path inlined into
/// the triangulation's cavity search keeps a small stack frame.
#[cold]
#[inline(never)]
fn insphere_lex_exact(p: [[f64; 3]; 5]) -> Sign {
    match crate::exact::insphere_exact(&p) {
        Sign::Zero => tiebreak3(&p, p.map(|q| std::cmp::Reverse(Lex(q)))),
        s => s,
    }
}

/// The 2D counterpart of [`insphere_lex`].
///
/// Precondition: `orient2d(p[0], p[1], p[2])` is positive.
#[inline]
pub fn incircle_lex(p: [[f64; 2]; 4]) -> Sign {
    match incircle(p[0], p[1], p[2], p[3]) {
        Sign::Zero => incircle_tiebreak(p, p.map(|q| std::cmp::Reverse(Lex(q)))),
        s => s,
    }
}

/// [`insphere_tiebreak`]: the coefficients of the perturbation by decreasing id.
fn tiebreak3<K: Ord + Copy>(p: &[[f64; 3]; 5], ids: [K; 5]) -> Sign {
    let orient = |q: [usize; 4]| orient3d(p[q[0]], p[q[1]], p[q[2]], p[q[3]]);
    let mut order = DecreasingIds::new(ids);
    while let Some(slot) = order.next() {
        let coefficient = if slot == 4 {
            orient([0, 1, 2, 3]).reversed()
        } else {
            let mut q = [0, 1, 2, 3];
            q[slot] = 4;
            orient(q)
        };
        if coefficient != Sign::Zero {
            return coefficient;
        }
    }
    // Only reachable when the precondition is violated (p[0..4] coplanar).
    Sign::Zero
}

/// A point ranked by its coordinates, compared lexicographically (x, then y, then z): a
/// perturbation order that depends only on the geometry, so the perturbed triangulation does not
/// depend on the order or numbering of the input (and matches CGAL's choice on grids).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lex<const N: usize>(pub [f64; N]);

impl<const N: usize> Eq for Lex<N> {}

impl<const N: usize> PartialOrd for Lex<N> {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl<const N: usize> Ord for Lex<N> {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        // Coordinates are finite (callers reject NaN), so plain comparisons are a total order.
        for k in 0..N {
            if self.0[k] < other.0[k] {
                return std::cmp::Ordering::Less;
            }
            if self.0[k] > other.0[k] {
                return std::cmp::Ordering::Greater;
            }
        }
        std::cmp::Ordering::Equal
    }
}

/// The slots `0..N` by decreasing id, found lazily: the loops above usually stop at the first
/// or second slot, so sorting all of them would be wasted work.
struct DecreasingIds<K, const N: usize> {
    ids: [K; N],
    used: [bool; N],
}

impl<K: Ord + Copy, const N: usize> DecreasingIds<K, N> {
    fn new(ids: [K; N]) -> Self {
        DecreasingIds {
            ids,
            used: [false; N],
        }
    }

    #[inline]
    fn next(&mut self) -> Option<usize> {
        let mut best: Option<usize> = None;
        for k in 0..N {
            if !self.used[k] && best.is_none_or(|b| self.ids[k] > self.ids[b]) {
                best = Some(k);
            }
        }
        if let Some(b) = best {
            self.used[b] = true;
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};

    fn sign_of_permutation<const N: usize>(perm: &[usize; N]) -> i32 {
        let mut s = 1;
        for i in 0..N {
            for j in i + 1..N {
                if perm[i] > perm[j] {
                    s = -s;
                }
            }
        }
        s
    }

    /// The perturbed determinant is alternating in its points: permuting the four (five)
    /// points together with their ids multiplies the answer by the permutation's sign. This is
    /// what makes the answers of different simplices sharing a facet consistent.
    fn check_incircle_alternating(p: [[f64; 2]; 4], ids: [u32; 4]) {
        // The sign of the perturbed determinant, for any order of the points: a negatively
        // oriented first triangle is made positive by swapping its first two points.
        let perturbed_det = |q: [[f64; 2]; 4], qi: [u32; 4]| -> Option<i32> {
            match orient2d(q[0], q[1], q[2]) {
                Sign::Zero => None,
                Sign::Positive => Some(incircle_sos(q, qi).as_i32()),
                Sign::Negative => Some(
                    -incircle_sos([q[1], q[0], q[2], q[3]], [qi[1], qi[0], qi[2], qi[3]]).as_i32(),
                ),
            }
        };
        let Some(base) = perturbed_det(p, ids) else {
            return;
        };
        assert_ne!(base, 0);
        let perms: [[usize; 4]; 6] = [
            [0, 1, 2, 3],
            [1, 0, 2, 3],
            [0, 1, 3, 2],
            [3, 1, 2, 0],
            [2, 3, 0, 1],
            [1, 2, 3, 0],
        ];
        for perm in perms {
            if let Some(s) = perturbed_det(perm.map(|i| p[i]), perm.map(|i| ids[i])) {
                assert_eq!(
                    s * sign_of_permutation(&perm),
                    base,
                    "perm {perm:?} of {p:?} ids {ids:?}"
                );
            }
        }
    }

    #[test]
    fn cocircular_square_is_decided_and_consistent() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(incircle(sq[0], sq[1], sq[2], sq[3]), Sign::Zero);
        for ids in [[0, 1, 2, 3], [3, 2, 1, 0], [7, 1, 9, 4], [2, 0, 3, 1]] {
            assert_ne!(incircle_sos(sq, ids), Sign::Zero);
            check_incircle_alternating(sq, ids);
        }
    }

    #[test]
    fn square_diagonal_choice_is_a_triangulation() {
        // For the unit square 0,1,2,3 exactly one diagonal must be chosen: triangle (0,1,2)
        // rejects 3 iff triangle (0,2,3) accepts... i.e. the two triangulations are each
        // self-consistent: if 3 is outside circle(0,1,2) then 1 is outside circle(0,2,3).
        let p = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        for ids in [[0u32, 1, 2, 3], [1, 0, 3, 2], [5, 9, 2, 7], [9, 5, 7, 2]] {
            let three_in_012 = incircle_sos([p[0], p[1], p[2], p[3]], ids);
            let one_in_023 =
                incircle_sos([p[0], p[2], p[3], p[1]], [ids[0], ids[2], ids[3], ids[1]]);
            assert_eq!(three_in_012, one_in_023, "ids {ids:?}");
            let two_in_013 =
                incircle_sos([p[0], p[1], p[3], p[2]], [ids[0], ids[1], ids[3], ids[2]]);
            let zero_in_123 =
                incircle_sos([p[1], p[2], p[3], p[0]], [ids[1], ids[2], ids[3], ids[0]]);
            assert_eq!(two_in_013, zero_in_123, "ids {ids:?}");
            // And the two diagonals are mutually exclusive: exactly one is Delaunay.
            assert_ne!(three_in_012, two_in_013, "ids {ids:?}");
        }
    }

    #[test]
    fn random_cocircular_points_are_consistent() {
        let mut rng = StdRng::seed_from_u64(7);
        for _ in 0..2000 {
            // Integer points on the circle x² + y² = 25 (exactly representable).
            let circle = [
                [5.0, 0.0],
                [4.0, 3.0],
                [3.0, 4.0],
                [0.0, 5.0],
                [-3.0, 4.0],
                [-4.0, 3.0],
                [-5.0, 0.0],
                [-4.0, -3.0],
                [-3.0, -4.0],
                [0.0, -5.0],
                [3.0, -4.0],
                [4.0, -3.0],
            ];
            let mut pick = [0usize; 4];
            loop {
                for k in &mut pick {
                    *k = rng.gen_range(0..circle.len());
                }
                let mut s = pick;
                s.sort_unstable();
                if s.windows(2).all(|w| w[0] != w[1]) {
                    break;
                }
            }
            let p = pick.map(|k| circle[k]);
            let ids = pick.map(|k| k as u32 * 3 + 1);
            check_incircle_alternating(p, ids);
        }
    }

    #[test]
    fn random_nondegenerate_agrees_with_exact() {
        let mut rng = StdRng::seed_from_u64(11);
        for _ in 0..5000 {
            let mut p = [[0.0; 3]; 5];
            for q in &mut p {
                *q = [rng.gen(), rng.gen(), rng.gen()];
            }
            if orient3d(p[0], p[1], p[2], p[3]) != Sign::Positive {
                p.swap(0, 1);
            }
            let exact = insphere(p[0], p[1], p[2], p[3], p[4]);
            assert_eq!(insphere_sos(p, [0, 1, 2, 3, 4]), exact);
        }
    }

    /// Five co-spherical points (cube corners): the perturbed answer is alternating, like the
    /// 2D case, and never zero.
    #[test]
    fn cospherical_cube_corners_are_consistent() {
        let corners: Vec<[f64; 3]> = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        let mut rng = StdRng::seed_from_u64(3);
        let mut checked = 0;
        while checked < 3000 {
            let mut pick = [0usize; 5];
            for k in &mut pick {
                *k = rng.gen_range(0..8);
            }
            let mut s = pick;
            s.sort_unstable();
            if s.windows(2).any(|w| w[0] == w[1]) {
                continue;
            }
            let p = pick.map(|k| corners[k]);
            let ids = pick.map(|k| (k as u32 * 7) % 11);
            let o = orient3d(p[0], p[1], p[2], p[3]);
            if o == Sign::Zero {
                continue;
            }
            let base = insphere_sos(
                if o == Sign::Positive {
                    p
                } else {
                    [p[1], p[0], p[2], p[3], p[4]]
                },
                if o == Sign::Positive {
                    ids
                } else {
                    [ids[1], ids[0], ids[2], ids[3], ids[4]]
                },
            );
            assert_ne!(base, Sign::Zero);
            // Swap the query point with a simplex vertex: the sign must flip (after restoring
            // positive orientation), as for any alternating function.
            for slot in 0..4 {
                let mut q = p;
                let mut qi = ids;
                q.swap(slot, 4);
                qi.swap(slot, 4);
                let o2 = orient3d(q[0], q[1], q[2], q[3]);
                if o2 == Sign::Zero {
                    continue;
                }
                let (q, qi) = if o2 == Sign::Positive {
                    (q, qi)
                } else {
                    (
                        [q[1], q[0], q[2], q[3], q[4]],
                        [qi[1], qi[0], qi[2], qi[3], qi[4]],
                    )
                };
                let s = insphere_sos(q, qi);
                // base·o (orientation-normalised) = −s·o2.
                assert_eq!(
                    base.as_i32() * o.as_i32(),
                    -s.as_i32() * o2.as_i32(),
                    "{pick:?} slot {slot}"
                );
            }
            checked += 1;
        }
    }
}
