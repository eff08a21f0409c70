//! Insertion order: a biased randomised insertion order (BRIO) of Hilbert-sorted rounds.
//!
//! Bowyer–Watson is fastest when consecutive points are close in space (the walk from the
//! previous insertion is then short, §5 of the paper) and robustly fast when the order is also
//! random enough that no early cavity becomes huge. BRIO (Amenta, Choi & Rote, 2003) gets both:
//! the points are shuffled, cut into rounds whose sizes grow geometrically, and each round is
//! sorted along a Hilbert curve. The Hilbert index is Skilling's transposition algorithm
//! ("Programming the Hilbert curve", AIP Conf. Proc. 707, 2004).

use crate::dim::Dim;
use rayon::prelude::*;

/// Rounds shrink by this factor from the last one backwards.
const ROUND_RATIO: usize = 8;
/// Below this many points there is a single (sorted) round.
const FIRST_ROUND: usize = 2048;

/// The Hilbert index of a point with `bits`-bit integer coordinates `x` (Skilling 2004).
pub(crate) fn hilbert_key<const N: usize>(mut x: [u32; N], bits: u32) -> u64 {
    let m = 1u32 << (bits - 1);
    // Inverse undo excess work.
    let mut q = m;
    while q > 1 {
        let p = q - 1;
        for i in 0..N {
            if x[i] & q != 0 {
                x[0] ^= p;
            } else {
                let t = (x[0] ^ x[i]) & p;
                x[0] ^= t;
                x[i] ^= t;
            }
        }
        q >>= 1;
    }
    // Gray encode.
    for i in 1..N {
        x[i] ^= x[i - 1];
    }
    let mut t = 0;
    let mut q = m;
    while q > 1 {
        if x[N - 1] & q != 0 {
            t ^= q - 1;
        }
        q >>= 1;
    }
    for xi in &mut x {
        *xi ^= t;
    }
    // Interleave the transposed bits, most significant first.
    let mut key = 0u64;
    for b in (0..bits).rev() {
        for xi in &x {
            key = key << 1 | u64::from((xi >> b) & 1);
        }
    }
    key
}

/// A small, fast, seeded generator (SplitMix64) so the order is reproducible.
#[derive(Clone, Debug)]
pub(crate) struct SplitMix(pub(crate) u64);

impl SplitMix {
    #[inline]
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    #[inline]
    pub(crate) fn below(&mut self, n: usize) -> usize {
        ((self.next_u64() >> 32) * n as u64 >> 32) as usize
    }
}

/// The BRIO insertion order of `points` (indices into it). Deterministic for a given input.
pub(crate) fn brio_order<D: Dim>(points: &[D::Point]) -> Vec<u32> {
    let n = points.len();
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for (k, &x) in p.as_ref().iter().enumerate() {
            lo[k] = lo[k].min(x);
            hi[k] = hi[k].max(x);
        }
    }
    // One scale for all axes keeps the curve's cells cubes, so thin slabs stay well ordered.
    let extent = (0..D::N).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
    let cells = f64::from((1u32 << D::HILBERT_BITS) - 1);
    let scale = if extent > 0.0 { cells / extent } else { 0.0 };
    let key = |i: u32| -> u64 {
        let p = points[i as usize].as_ref();
        let mut q = [0u32; 3];
        for k in 0..D::N {
            q[k] = ((p[k] - lo[k]) * scale) as u32;
        }
        D::hilbert_key(&q[..D::N])
    };

    let mut order: Vec<u32> = (0..n as u32).collect();
    let mut rng = SplitMix(0x5EED_DE1A_u64 ^ n as u64);
    for i in (1..n).rev() {
        order.swap(i, rng.below(i + 1));
    }
    let mut keyed: Vec<(u64, u32)> = order.into_par_iter().map(|i| (key(i), i)).collect();
    let mut end = n;
    while end > 0 {
        let start = if end <= FIRST_ROUND {
            0
        } else {
            end / ROUND_RATIO
        };
        let start = if start < FIRST_ROUND / ROUND_RATIO {
            0
        } else {
            start
        };
        keyed[start..end].par_sort_unstable();
        end = start;
    }
    keyed.into_iter().map(|(_, i)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hilbert_2d_visits_a_4x4_grid_by_unit_steps() {
        let mut cells: Vec<(u64, [u32; 2])> = Vec::new();
        for x in 0..4 {
            for y in 0..4 {
                cells.push((hilbert_key::<2>([x, y], 2), [x, y]));
            }
        }
        cells.sort();
        let keys: Vec<u64> = cells.iter().map(|c| c.0).collect();
        assert_eq!(keys, (0..16).collect::<Vec<_>>());
        for w in cells.windows(2) {
            let d = w[0].1[0].abs_diff(w[1].1[0]) + w[0].1[1].abs_diff(w[1].1[1]);
            assert_eq!(d, 1, "{:?} -> {:?}", w[0].1, w[1].1);
        }
    }

    #[test]
    fn hilbert_3d_visits_an_8x8x8_grid_by_unit_steps() {
        let mut cells = Vec::new();
        for x in 0..8 {
            for y in 0..8 {
                for z in 0..8 {
                    cells.push((hilbert_key::<3>([x, y, z], 3), [x, y, z]));
                }
            }
        }
        cells.sort();
        assert!(cells.iter().enumerate().all(|(i, c)| c.0 == i as u64));
        for w in cells.windows(2) {
            let d: u32 = (0..3).map(|k| w[0].1[k].abs_diff(w[1].1[k])).sum();
            assert_eq!(d, 1);
        }
    }

    #[test]
    fn brio_is_a_permutation() {
        let mut rng = SplitMix(1);
        let pts: Vec<[f64; 3]> = (0..10_000)
            .map(|_| [rng.next_u64() as f64, rng.next_u64() as f64, 0.5])
            .collect();
        let mut order = brio_order::<crate::D3>(&pts);
        order.sort_unstable();
        assert!(order.iter().enumerate().all(|(i, &o)| o as usize == i));
    }
}
