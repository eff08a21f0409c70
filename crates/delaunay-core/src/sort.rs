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

/// The first round has at least this many points (all of them for small inputs)...
const FIRST_ROUND: usize = 1024;
/// ...except below [`SMALL_INPUT`] points, where it has at least this many. Small inputs are
/// mostly surface points (a boundary's, a facet's), which lie on curves: in pure Hilbert order
/// each point along a curve rebuilds the long thin cells spanning it (the aerofoil's 1,984
/// boundary points: a mean cavity of 31 cells, 6 with random rounds from 64 points). Larger
/// inputs keep the bigger first round, whose locality matters more to them (a 37,000-point
/// bunny recovers 15–25% slower with rounds from 64).
pub(crate) const SMALL_FIRST_ROUND: usize = 64;
/// See [`SMALL_FIRST_ROUND`].
const SMALL_INPUT: usize = 16384;
/// Resolution of the Hilbert curve per axis: plenty for ordering, and the key (at most 48
/// bits) leaves room for the round number above it.
const HILBERT_BITS: u32 = 16;

/// The Hilbert index of a point with 16-bit integer coordinates `x` (Skilling's curve, 2004),
/// `K` levels (bits per axis) at a time through a state table (see [`HilbertTable`]).
#[inline]
pub(crate) fn hilbert_key<const N: usize>(x: [u32; N]) -> u64 {
    if N == 2 {
        HILBERT_2D.key(&x[..2])
    } else {
        HILBERT_3D.key(&x[..3])
    }
}

/// The 2D table: four levels (8 input bits) per step, four steps.
static HILBERT_2D: HilbertTable<2, 4, { HilbertTable::<2, 4, 0>::LEN }> = HilbertTable::new();
/// The 3D table: two levels (6 input bits) per step, eight steps.
static HILBERT_3D: HilbertTable<3, 2, { HilbertTable::<3, 2, 0>::LEN }> = HilbertTable::new();

/// Skilling's transposition algorithm ("Programming the Hilbert curve", AIP Conf. Proc. 707,
/// 2004) read level by level, from the top bit of the coordinates down. At each level the bits
/// of the coordinates are seen through a signed permutation (which axis each transposed axis
/// reads, and whether it is inverted), which the level's bits then update: a set bit `i`
/// inverts axis 0, a clear one exchanges axes 0 and `i`. The key digit of the level is the Gray
/// code (prefix XOR) of the permuted bits, XORed with the parity of the last Gray bit over the
/// levels above. So the key is a finite-state transducer: the state is (permutation, inversions,
/// parity), and a table gives, for each state and the bits of `K` levels of every axis, the
/// `N·K` key bits and the next state. The keys are exactly those of the bit-serial algorithm (a
/// test compares them).
pub(crate) struct HilbertTable<const N: usize, const K: usize, const LEN: usize> {
    /// Per `state · 2^(N·K) + input`: the key bits (low `N·K` bits) and the next state above.
    next: [u16; LEN],
}

impl<const N: usize, const K: usize, const LEN: usize> HilbertTable<N, K, LEN> {
    /// Permutation codes: `p[0] + N·p[1]` (the last axis is the one left).
    const PERMS: usize = if N == 2 { 2 } else { 9 };
    /// States: permutation code, inversion mask (N bits), parity bit.
    const STATES: usize = Self::PERMS << (N + 1);
    /// The table length.
    pub(crate) const LEN: usize = Self::STATES << (N * K);
    /// The state at the top level: identity permutation, no inversion, parity 0.
    const START: usize = (if N == 2 { 0 } else { 3 }) << (N + 1);

    const fn decode(state: usize) -> ([usize; 3], [bool; 3], bool) {
        let code = state >> (N + 1);
        let mut perm = [0, 1, 2];
        if N == 2 {
            perm[0] = code;
            perm[1] = 1 - code;
        } else {
            perm[0] = code % 3;
            perm[1] = code / 3;
            // (Codes with p[0] = p[1] are not permutations; they get a wrong last axis.)
            perm[2] = (3 + 3 - perm[0] - perm[1]) % 3;
        }
        let mut flip = [false; 3];
        let mut j = 0;
        while j < N {
            flip[j] = (state >> (j + 1)) & 1 != 0;
            j += 1;
        }
        (perm, flip, state & 1 != 0)
    }

    const fn encode(perm: [usize; 3], flip: [bool; 3], parity: bool) -> usize {
        let code = if N == 2 {
            perm[0]
        } else {
            perm[0] + 3 * perm[1]
        };
        let mut state = (code << (N + 1)) | parity as usize;
        let mut j = 0;
        while j < N {
            state |= (flip[j] as usize) << (j + 1);
            j += 1;
        }
        state
    }

    /// One level: the key digit (`N` bits, axis 0 the most significant) and the next state,
    /// from the state and the level's bit of each coordinate.
    const fn level(state: usize, bits: [bool; 3]) -> (usize, usize) {
        let (mut perm, mut flip, mut parity) = Self::decode(state);
        let mut y = [false; 3];
        let mut j = 0;
        while j < N {
            y[j] = bits[perm[j]] ^ flip[j];
            j += 1;
        }
        // Gray code of the transposed bits, inverted by the parity of the levels above.
        let (mut gray, mut digit, mut i) = (false, 0, 0);
        while i < N {
            gray ^= y[i];
            digit |= ((gray ^ parity) as usize) << (N - 1 - i);
            i += 1;
        }
        parity ^= gray;
        // The transform of the levels below.
        let mut i = 0;
        while i < N {
            if y[i] {
                flip[0] = !flip[0];
            } else {
                (perm[0], perm[i]) = (perm[i], perm[0]);
                (flip[0], flip[i]) = (flip[i], flip[0]);
            }
            i += 1;
        }
        (digit, Self::encode(perm, flip, parity))
    }

    const fn new() -> Self {
        let mut next = [0u16; LEN];
        let inputs = 1 << (N * K);
        let mut state = 0;
        while state < Self::STATES {
            let perm = Self::decode(state).0;
            if perm[0] == perm[1] {
                // Not a permutation (3D codes with p[0] = p[1]): never reached.
                state += 1;
                continue;
            }
            let mut input = 0;
            while input < inputs {
                // Input bit (j·K + l) is bit l of axis j's chunk, level K − 1 the top one.
                let (mut s, mut key, mut l) = (state, 0, K);
                while l > 0 {
                    l -= 1;
                    let mut bits = [false; 3];
                    let mut j = 0;
                    while j < N {
                        bits[j] = (input >> (j * K + l)) & 1 != 0;
                        j += 1;
                    }
                    let (digit, t) = Self::level(s, bits);
                    key = (key << N) | digit;
                    s = t;
                }
                next[state * inputs + input] = (key | (s << (N * K))) as u16;
                input += 1;
            }
            state += 1;
        }
        HilbertTable { next }
    }

    /// The key of 16-bit coordinates `x` (the high bits of each are ignored).
    #[inline]
    fn key(&self, x: &[u32]) -> u64 {
        let (width, chunk) = (N * K, (1u32 << K) - 1);
        let mut state = Self::START;
        let mut key = 0u64;
        let mut shift = HILBERT_BITS as usize;
        while shift > 0 {
            shift -= K;
            let mut input = 0;
            for (j, &xj) in x.iter().enumerate() {
                input |= (((xj >> shift) & chunk) as usize) << (j * K);
            }
            let e = self.next[(state << width) | input];
            key = (key << width) | u64::from(e & ((1 << width) - 1));
            state = usize::from(e >> width);
        }
        key
    }
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
        (((self.next_u64() >> 32) * n as u64) >> 32) as usize
    }
}

/// Inputs with fewer points than this are ordered on the calling thread.
pub(crate) const PARALLEL_MIN: usize = 8192;

/// The BRIO insertion order of `points` (indices into it). Deterministic for a given input.
///
/// Each point draws its round from a hash of its index: it lands in the last round with
/// probability 7/8, the one before with 7/64, and so on, and the first round holds the rest
/// (about [`FIRST_ROUND`] points, or [`SMALL_FIRST_ROUND`] for small inputs). One sort by `(round, Hilbert key)` then gives the order, with
/// the points read sequentially.
pub(crate) fn brio_order<D: Dim>(points: &[D::Point]) -> Vec<u32> {
    let first_round = if points.len() < SMALL_INPUT {
        SMALL_FIRST_ROUND
    } else {
        FIRST_ROUND
    };
    brio_order_from::<D>(points, first_round)
}

/// [`brio_order`] with a first round of at least `first_round` points.
pub(crate) fn brio_order_from<D: Dim>(points: &[D::Point], first_round: usize) -> Vec<u32> {
    let n = points.len();
    let frame = HilbertFrame::of::<D>(points);
    let mut rounds = 0u32;
    while n >> (3 * (rounds + 1)) >= first_round {
        rounds += 1;
    }
    let key = |(i, p): (usize, &D::Point)| {
        let hilbert = frame.key::<D>(p);
        // Level ≥ k with probability 8^-k; the rarest levels are inserted first.
        let level = (SplitMix(i as u64 ^ 0x5EED_DE1A).next_u64().leading_zeros() / 3).min(rounds);
        (u64::from(rounds - level) << 58 | hilbert, i as u32)
    };
    // Small inputs (a facet's points in boundary recovery) are not worth waking other threads.
    let keyed = if n < PARALLEL_MIN {
        let mut keyed: Vec<(u64, u32)> = points.iter().enumerate().map(key).collect();
        keyed.sort_unstable();
        keyed
    } else {
        let mut keyed: Vec<(u64, u32)> = points.par_iter().enumerate().map(key).collect();
        keyed.par_sort_unstable();
        keyed
    };
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// The grid the Hilbert keys are taken on: the points' bounding box, with one scale for all
/// axes (the curve's cells stay cubes, so thin slabs stay well ordered) onto 16 bits.
struct HilbertFrame {
    lo: [f64; 3],
    scale: f64,
}

impl HilbertFrame {
    fn of<D: Dim>(points: &[D::Point]) -> HilbertFrame {
        let grow = |(mut lo, mut hi): ([f64; 3], [f64; 3]), p: &D::Point| {
            for (k, &x) in p.as_ref().iter().enumerate() {
                lo[k] = lo[k].min(x);
                hi[k] = hi[k].max(x);
            }
            (lo, hi)
        };
        let empty = || ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let (lo, hi) = if points.len() < PARALLEL_MIN {
            points.iter().fold(empty(), grow)
        } else {
            points
                .par_iter()
                .with_min_len(1 << 12)
                .fold(empty, grow)
                .reduce(empty, |a, b| {
                    (
                        std::array::from_fn(|k| a.0[k].min(b.0[k])),
                        std::array::from_fn(|k| a.1[k].max(b.1[k])),
                    )
                })
        };
        let extent = (0..D::N).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
        let cells = f64::from((1u32 << HILBERT_BITS) - 1);
        let scale = if extent > 0.0 { cells / extent } else { 0.0 };
        HilbertFrame { lo, scale }
    }

    /// The Hilbert key of `p` (at most `16·N` bits).
    #[inline]
    fn key<D: Dim>(&self, p: &D::Point) -> u64 {
        let p = p.as_ref();
        let mut q = [0u32; 3];
        for k in 0..D::N {
            q[k] = ((p[k] - self.lo[k]) * self.scale) as u32;
        }
        D::hilbert_key(&q[..D::N])
    }
}

/// The points' order along a Hilbert curve (16 bits per axis over their bounding box, one
/// scale for all axes), ties by index: [`brio_order_from`] with a single round, cheaper where
/// the key and the index fit in one `u64` (2D).
pub(crate) fn hilbert_order<D: Dim>(points: &[D::Point]) -> Vec<u32> {
    if D::N as u32 * HILBERT_BITS > 32 {
        return brio_order_from::<D>(points, usize::MAX);
    }
    let frame = HilbertFrame::of::<D>(points);
    let mut keyed: Vec<u64> = points
        .par_iter()
        .enumerate()
        .with_min_len(1 << 12)
        .map(|(i, p)| frame.key::<D>(p) << 32 | i as u64)
        .collect();
    // A mesh renumbered before holds its vertices in long runs close to this order (the last
    // renumbering's, then each generation pass's, inserted along a curve): the adaptive merge
    // sort takes such runs as they are (the keys are distinct: stability changes nothing).
    // At 10^6 triangles the renumberings' sorts took 14.5 ms in all, 8.5 ms this way.
    keyed.par_sort();
    keyed.into_par_iter().map(|k| k as u32).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bit-serial form of Skilling's algorithm (the definition the tables must match).
    fn reference_key<const N: usize>(mut x: [u32; N], bits: u32) -> u64 {
        let m = 1u32 << (bits - 1);
        // Inverse undo excess work (branch-free: the bits are unpredictable).
        let mut q = m;
        while q > 1 {
            let p = q - 1;
            for i in 0..N {
                let set = 0u32.wrapping_sub(u32::from(x[i] & q != 0));
                // Bit set: invert the low bits of x[0]; clear: exchange them with x[i]'s.
                let t = (x[0] ^ x[i]) & p & !set;
                x[0] ^= (p & set) | t;
                x[i] ^= t;
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
            t ^= (q - 1) & 0u32.wrapping_sub(u32::from(x[N - 1] & q != 0));
            q >>= 1;
        }
        for xi in &mut x {
            *xi ^= t;
        }
        // Interleave the transposed bits, most significant first: x[0] holds the top bit.
        let mut key = 0u64;
        for (i, &xi) in x.iter().enumerate() {
            key |= spread::<N>(xi) << (N - 1 - i);
        }
        key
    }

    /// Spreads the low 21 bits of `x` so that consecutive bits land `N` positions apart.
    #[inline]
    fn spread<const N: usize>(x: u32) -> u64 {
        let mut x = u64::from(x);
        if N == 2 {
            x &= 0xFFFF_FFFF;
            x = (x | x << 16) & 0x0000_FFFF_0000_FFFF;
            x = (x | x << 8) & 0x00FF_00FF_00FF_00FF;
            x = (x | x << 4) & 0x0F0F_0F0F_0F0F_0F0F;
            x = (x | x << 2) & 0x3333_3333_3333_3333;
            (x | x << 1) & 0x5555_5555_5555_5555
        } else {
            x &= 0x1F_FFFF;
            x = (x | x << 32) & 0x001F_0000_0000_FFFF;
            x = (x | x << 16) & 0x001F_0000_FF00_00FF;
            x = (x | x << 8) & 0x100F_00F0_0F00_F00F;
            x = (x | x << 4) & 0x10C3_0C30_C30C_30C3;
            (x | x << 2) & 0x1249_2492_4924_9249
        }
    }

    #[test]
    fn spread_interleaves() {
        assert_eq!(spread::<2>(0b1011), 0b1_00_01_01);
        assert_eq!(spread::<3>(0b1011), 0b1_000_001_001);
        assert_eq!(spread::<3>(0xFFFF).count_ones(), 16);
    }

    #[test]
    fn hilbert_2d_visits_a_4x4_grid_by_unit_steps() {
        let mut cells: Vec<(u64, [u32; 2])> = Vec::new();
        for x in 0..4 {
            for y in 0..4 {
                cells.push((hilbert_key::<2>([x, y]), [x, y]));
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
                    cells.push((hilbert_key::<3>([x, y, z]), [x, y, z]));
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

    #[test]
    fn tables_give_the_bit_serial_keys() {
        let mut rng = SplitMix(7);
        for _ in 0..200_000 {
            let r = rng.next_u64();
            let x2 = [r as u32 & 0xFFFF, (r >> 16) as u32 & 0xFFFF];
            assert_eq!(hilbert_key::<2>(x2), reference_key::<2>(x2, 16), "{x2:?}");
            let x3 = [
                (r >> 32) as u32 & 0xFFFF,
                (r >> 48) as u32,
                r as u32 & 0xFFFF,
            ];
            assert_eq!(hilbert_key::<3>(x3), reference_key::<3>(x3, 16), "{x3:?}");
        }
        // Every coordinate pair of a corner block and along the axes and the far edges.
        for a in 0..256 {
            for b in 0..256 {
                for x in [
                    [a, b],
                    [a << 8, b << 8],
                    [0xFFFF - a, b],
                    [a * 257, 0xFFFF - b],
                ] {
                    assert_eq!(hilbert_key::<2>(x), reference_key::<2>(x, 16), "{x:?}");
                }
            }
        }
        for a in 0..32 {
            for b in 0..32 {
                for c in 0..32 {
                    for x in [
                        [a, b, c],
                        [a << 11, b << 11, c << 11],
                        [0xFFFF - a, b, c << 11],
                    ] {
                        assert_eq!(hilbert_key::<3>(x), reference_key::<3>(x, 16), "{x:?}");
                    }
                }
            }
        }
    }
}
