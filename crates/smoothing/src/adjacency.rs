//! Flat adjacency rows, the greedy colouring of a point graph and a 3D Z-order, for the 3D
//! smoother.
//!
//! The 2D smoother has its own copies of these (kept as they are while it is being tuned);
//! these are generic over the row item so that the 3D smoother can keep each point's opposite
//! faces as one `[u32; 3]` per tetrahedron.

use rayon::prelude::*;
use std::ops::Range;

/// Compressed rows: `items[start[i]..start[i + 1]]` belong to row `i`.
pub(crate) struct Rows<T> {
    start: Vec<usize>,
    items: Vec<T>,
}

impl<T: Copy + Default> Rows<T> {
    /// Rows for `n` keys built in parallel over ranges of keys: `fill(range, lens, items)`
    /// appends, key by key of `range`, the row's length to `lens` and its items to `items`.
    /// The ranges are cut by `ranges`; the rows do not depend on how.
    pub(crate) fn build_in_ranges(
        n: usize,
        ranges: usize,
        fill: impl Fn(Range<usize>, &mut Vec<usize>, &mut Vec<T>) + Sync,
    ) -> Rows<T>
    where
        T: Send,
    {
        let ranges = ranges.clamp(1, n.max(1));
        let pieces: Vec<(Vec<usize>, Vec<T>)> = (0..ranges)
            .into_par_iter()
            .map(|r| {
                let keys = n * r / ranges..n * (r + 1) / ranges;
                let (mut lens, mut items) = (Vec::with_capacity(keys.len()), Vec::new());
                fill(keys, &mut lens, &mut items);
                (lens, items)
            })
            .collect();
        let mut start = Vec::with_capacity(n + 1);
        start.push(0);
        let mut items = Vec::with_capacity(pieces.iter().map(|p| p.1.len()).sum());
        for (lens, piece) in pieces {
            for l in lens {
                start.push(start[start.len() - 1] + l);
            }
            items.extend(piece);
        }
        debug_assert_eq!(start.len(), n + 1);
        Rows { start, items }
    }

    /// Row `i`.
    #[inline]
    pub(crate) fn row(&self, i: usize) -> &[T] {
        &self.items[self.start[i]..self.start[i + 1]]
    }
}

/// The free points with neighbours, in classes of one colour each: a greedy colouring of the
/// neighbour graph in memory order, so no two points of a class share an edge. Points are in
/// increasing order within a class. No limit on the number of colours.
pub(crate) fn colour_classes(neighbours: &Rows<u32>, fixed: &[bool]) -> Vec<Vec<u32>> {
    let n = fixed.len();
    let mut colour = vec![u32::MAX; n];
    // `seen[c] == v + 1` marks colour `c` as used by a neighbour of `v`.
    let mut seen: Vec<usize> = Vec::new();
    let mut classes: Vec<Vec<u32>> = Vec::new();
    for v in 0..n {
        if fixed[v] || neighbours.row(v).is_empty() {
            continue;
        }
        for &u in neighbours.row(v) {
            let c = colour[u as usize];
            if c != u32::MAX {
                seen[c as usize] = v + 1;
            }
        }
        let c = (0..seen.len())
            .find(|&c| seen[c] != v + 1)
            .unwrap_or(seen.len());
        if c == seen.len() {
            seen.push(0);
            classes.push(Vec::new());
        }
        colour[v] = c as u32;
        classes[c].push(v as u32);
    }
    classes
}

/// The points' order along a Z-order (Morton) curve of 21 bits per axis (ties by index).
pub(crate) fn spatial_order3(points: &[[f64; 3]]) -> Vec<u32> {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    const CELLS: f64 = ((1u32 << 21) - 1) as f64;
    let scale = [0, 1, 2].map(|k| {
        let w = hi[k] - lo[k];
        if w > 0.0 {
            CELLS / w
        } else {
            0.0
        }
    });
    let spread = |x: u32| {
        let mut x = u64::from(x) & 0x1F_FFFF;
        x = (x | (x << 32)) & 0x001F_0000_0000_FFFF;
        x = (x | (x << 16)) & 0x001F_0000_FF00_00FF;
        x = (x | (x << 8)) & 0x100F_00F0_0F00_F00F;
        x = (x | (x << 4)) & 0x10C3_0C30_C30C_30C3;
        (x | (x << 2)) & 0x1249_2492_4924_9249
    };
    let mut keyed: Vec<(u64, u32)> = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let q = [0, 1, 2].map(|k| (((p[k] - lo[k]) * scale[k]) as u32).min(CELLS as u32));
            (
                spread(q[0]) | (spread(q[1]) << 1) | (spread(q[2]) << 2),
                i as u32,
            )
        })
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn morton_interleaves_bits() {
        // Along x only, the key order is x's order; a unit step in z outranks any step in x
        // within the same octant of the finest level.
        let pts = [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.5, 0.0, 0.0]];
        assert_eq!(spatial_order3(&pts), vec![1, 2, 0]);
        let pts = [[0.0, 0.0, 1.0], [1.0, 1.0, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(spatial_order3(&pts), vec![2, 1, 0]);
    }

    #[test]
    fn colouring_separates_neighbours() {
        // A path 0-1-2-3 and a triangle 3-4-5.
        let edges = [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 3)];
        let rows = Rows::build_in_ranges(6, 2, |keys, lens, items| {
            for v in keys {
                let before = items.len();
                for &(a, b) in &edges {
                    if a == v {
                        items.push(b as u32);
                    } else if b == v {
                        items.push(a as u32);
                    }
                }
                lens.push(items.len() - before);
            }
        });
        let classes = colour_classes(&rows, &[false; 6]);
        assert_eq!(classes, vec![vec![0, 2, 4], vec![1, 3], vec![5]]);
        let classes = colour_classes(&rows, &[false, true, false, false, false, false]);
        assert_eq!(classes, vec![vec![0, 2, 4], vec![3], vec![5]]);
    }

    #[test]
    fn rows_do_not_depend_on_the_ranges() {
        let fill = |keys: Range<usize>, lens: &mut Vec<usize>, items: &mut Vec<u32>| {
            for v in keys {
                lens.push(v % 4);
                items.extend((0..v % 4).map(|k| (v * 10 + k) as u32));
            }
        };
        let one = Rows::build_in_ranges(50, 1, fill);
        for ranges in [2, 3, 7, 50, 80] {
            let rows = Rows::build_in_ranges(50, ranges, fill);
            assert_eq!(rows.start, one.start, "{ranges} ranges");
            assert_eq!(rows.items, one.items, "{ranges} ranges");
        }
        assert_eq!(one.row(7), &[70, 71, 72]);
        assert!(Rows::<u32>::build_in_ranges(0, 4, fill).start == vec![0]);
    }
}
