//! A uniform grid of buckets over axis-aligned boxes, in 2 or 3 dimensions.
//!
//! Each box is listed in every cell it overlaps. The cell of a coordinate is
//! `floor((x − lo) · inv)` in floating point, which is monotone in `x` whatever the rounding,
//! so two closed boxes that overlap always share a cell and a point inside a closed box always
//! falls in one of the box's cells: the grid only ever narrows the candidates, it never decides.

/// An axis-aligned box: lower and upper corners.
pub(crate) type Aabb<const N: usize> = ([f64; N], [f64; N]);

/// Whether two closed boxes overlap (touching counts).
#[inline]
pub(crate) fn overlap<const N: usize>(a: &Aabb<N>, b: &Aabb<N>) -> bool {
    (0..N).all(|k| a.0[k] <= b.1[k] && b.0[k] <= a.1[k])
}

/// Whether the closed box contains the point.
#[inline]
pub(crate) fn contains<const N: usize>(b: &Aabb<N>, p: &[f64; N]) -> bool {
    (0..N).all(|k| b.0[k] <= p[k] && p[k] <= b.1[k])
}

/// Buckets of boxes on a uniform grid.
#[derive(Clone, Debug)]
pub(crate) struct Grid<const N: usize> {
    lo: [f64; N],
    inv: [f64; N],
    dims: [usize; N],
    /// Cell `k` holds `items[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl<const N: usize> Grid<N> {
    /// Buckets the boxes. Cells are about as wide as the mean box, and there are at most about
    /// four times as many cells as boxes.
    pub(crate) fn new(boxes: &[Aabb<N>]) -> Grid<N> {
        let mut lo = [f64::INFINITY; N];
        let mut hi = [f64::NEG_INFINITY; N];
        let mut mean = 0.0;
        for b in boxes {
            let mut size = 0.0f64;
            for k in 0..N {
                lo[k] = lo[k].min(b.0[k]);
                hi[k] = hi[k].max(b.1[k]);
                size = size.max(b.1[k] - b.0[k]);
            }
            mean += size;
        }
        if boxes.is_empty() {
            lo = [0.0; N];
            hi = [0.0; N];
        }
        mean /= boxes.len().max(1) as f64;
        let limit = (4 * boxes.len() + 64) as f64;
        let extent: [f64; N] = std::array::from_fn(|k| hi[k] - lo[k]);
        let largest = extent.iter().fold(0.0f64, |m, &e| m.max(e));
        // Cell width: the mean box size, widened until the cell count is within the limit.
        let mut h = if mean > 0.0 { mean } else { largest.max(1.0) };
        let count = |h: f64| -> f64 {
            extent
                .iter()
                .map(|&e| (e / h).ceil().clamp(1.0, 1e6))
                .product()
        };
        if largest > 0.0 {
            while count(h) > limit {
                h *= (count(h) / limit).powf(1.0 / N as f64).max(1.01);
            }
        }
        let dims: [usize; N] = std::array::from_fn(|k| {
            if largest > 0.0 {
                (extent[k] / h).ceil().clamp(1.0, 1e6) as usize
            } else {
                1
            }
        });
        let inv: [f64; N] = std::array::from_fn(|k| {
            if extent[k] > 0.0 {
                dims[k] as f64 / extent[k]
            } else {
                0.0
            }
        });
        let n_cells: usize = dims.iter().product();
        let mut grid = Grid {
            lo,
            inv,
            dims,
            start: Vec::new(),
            items: Vec::new(),
        };
        // Counting sort: counts, prefix sums, fill.
        let mut start = vec![0u32; n_cells + 1];
        for b in boxes {
            grid.for_cells(b, |k| start[k + 1] += 1);
        }
        for k in 0..n_cells {
            start[k + 1] += start[k];
        }
        let mut items = vec![0u32; start[n_cells] as usize];
        let mut fill = start.clone();
        for (i, b) in boxes.iter().enumerate() {
            grid.for_cells(b, |k| {
                items[fill[k] as usize] = i as u32;
                fill[k] += 1;
            });
        }
        grid.start = start;
        grid.items = items;
        grid
    }

    #[inline]
    fn coordinate(&self, x: f64, k: usize) -> usize {
        // Negative values saturate to 0; the clamp keeps the upper edge in the last cell.
        (((x - self.lo[k]) * self.inv[k]) as usize).min(self.dims[k] - 1)
    }

    /// Calls `f` with every cell the closed box overlaps.
    pub(crate) fn for_cells(&self, b: &Aabb<N>, mut f: impl FnMut(usize)) {
        let from: [usize; N] = std::array::from_fn(|k| self.coordinate(b.0[k], k));
        let to: [usize; N] = std::array::from_fn(|k| self.coordinate(b.1[k], k));
        let mut at = from;
        loop {
            let mut cell = 0;
            for k in (0..N).rev() {
                cell = cell * self.dims[k] + at[k];
            }
            f(cell);
            // Odometer over the cell range.
            let mut k = 0;
            loop {
                if k == N {
                    return;
                }
                if at[k] < to[k] {
                    at[k] += 1;
                    break;
                }
                at[k] = from[k];
                k += 1;
            }
        }
    }

    /// The cell of a point.
    #[inline]
    pub(crate) fn cell_of(&self, p: &[f64; N]) -> usize {
        let mut cell = 0;
        for k in (0..N).rev() {
            cell = cell * self.dims[k] + self.coordinate(p[k], k);
        }
        cell
    }

    /// The boxes listed in cell `k`.
    #[inline]
    pub(crate) fn bucket(&self, k: usize) -> &[u32] {
        &self.items[self.start[k] as usize..self.start[k + 1] as usize]
    }
}
