//! Input checks of a [`Plc2`]: everything later stages rely on, reported in the user's numbering.
//!
//! - coordinates are finite; duplicate points are merged (segments use the first occurrence);
//! - segment end points exist and differ; repeated segments are dropped (a repeat's marker
//!   must be the first's, or one of them 0: different markers are an error naming both);
//! - a point lying inside a segment splits it there (as Triangle does), so the segment can be
//!   recovered at all; collinear segments that overlap are thereby split into shared pieces,
//!   each kept once;
//! - no two segments cross: that is an error naming both, since no recovery could make both
//!   present.
//!
//! Segment pairs and point–segment pairs are found through a uniform grid of buckets, so the
//! checks cost about linear time on ordinary inputs; every decision is an exact orientation test.

use crate::error::RecoveryError;
use crate::plc::{Plc2, Segment};
use delmesh_predicates::{orient2d, Sign};
use rustc_hash::FxHashMap as HashMap;

/// A checked input: merged points, segments that may be recovered.
#[derive(Clone, Debug)]
pub(crate) struct CheckedPlc {
    /// The input points (duplicates stay, unused by segments).
    pub(crate) points: Vec<[f64; 2]>,
    /// Segments after merging and splitting at interior points.
    pub(crate) segments: Vec<Segment>,
    /// For each segment, the input segment it came from (0-based).
    pub(crate) origin: Vec<u32>,
    /// Points that repeat an earlier one exactly: (duplicate, first occurrence), 0-based.
    pub(crate) merged: Vec<(u32, u32)>,
}

/// The marker of a segment given twice (or of a piece two overlapping segments share), from
/// each occurrence's marker and number: the same, or the one that is not 0 (none); two
/// different markers are an error naming both segments.
pub(crate) fn agreed_marker(first: (i32, u64), repeat: (i32, u64)) -> Result<i32, RecoveryError> {
    match (first.0, repeat.0) {
        (m, n) if m == n || n == 0 => Ok(m),
        (0, n) => Ok(n),
        (m, n) => Err(RecoveryError::ConflictingMarkers {
            first: first.1,
            second: repeat.1,
            first_marker: m,
            second_marker: n,
        }),
    }
}

/// A uniform grid of buckets over a bounding box.
struct Grid {
    lo: [f64; 2],
    inv: [f64; 2],
    dims: [usize; 2],
    /// Bucket `k` holds `items[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Grid {
    /// Buckets each item's bounding box. Cells are about as large as the median box (so most
    /// segments touch few cells, and a few long ones, like a far field's, do not make the cells
    /// of a finely divided body huge), with at most 16 cells per item.
    fn new(boxes: &[([f64; 2], [f64; 2])], lo: [f64; 2], hi: [f64; 2]) -> Grid {
        let mut sizes: Vec<f64> = boxes
            .iter()
            .map(|b| (b.1[0] - b.0[0]).max(b.1[1] - b.0[1]))
            .collect();
        let mid = sizes.len() / 2;
        let median = if sizes.is_empty() {
            0.0
        } else {
            *sizes.select_nth_unstable_by(mid, f64::total_cmp).1
        };
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let by_count = 4.0 * (boxes.len() as f64).sqrt().ceil();
        let by_size = if median > 0.0 {
            (extent / median).ceil()
        } else {
            by_count
        };
        let side = (by_count.min(by_size) as usize).clamp(1, 1024);
        let dims = [side, side];
        let inv = [0, 1].map(|k| {
            let w = hi[k] - lo[k];
            if w > 0.0 {
                dims[k] as f64 / w
            } else {
                0.0
            }
        });
        let mut grid = Grid {
            lo,
            inv,
            dims,
            start: vec![0; dims[0] * dims[1] + 1],
            items: Vec::new(),
        };
        // Counting sort: counts, prefix sums, fill.
        let mut count = vec![0u32; dims[0] * dims[1] + 1];
        for b in boxes {
            grid.for_cells(b, |k| count[k + 1] += 1);
        }
        for k in 0..dims[0] * dims[1] {
            count[k + 1] += count[k];
        }
        grid.items = vec![0; count[dims[0] * dims[1]] as usize];
        let mut fill = count.clone();
        for (i, b) in boxes.iter().enumerate() {
            let mut cells = Vec::new();
            grid.for_cells(b, |k| cells.push(k));
            for k in cells {
                grid.items[fill[k] as usize] = i as u32;
                fill[k] += 1;
            }
        }
        grid.start = count;
        grid
    }

    fn cell_range(&self, x: f64, k: usize) -> usize {
        (((x - self.lo[k]) * self.inv[k]) as usize).min(self.dims[k] - 1)
    }

    fn for_cells(&self, b: &([f64; 2], [f64; 2]), mut f: impl FnMut(usize)) {
        let (x0, x1) = (self.cell_range(b.0[0], 0), self.cell_range(b.1[0], 0));
        let (y0, y1) = (self.cell_range(b.0[1], 1), self.cell_range(b.1[1], 1));
        for y in y0..=y1 {
            for x in x0..=x1 {
                f(y * self.dims[0] + x);
            }
        }
    }

    fn bucket(&self, k: usize) -> &[u32] {
        &self.items[self.start[k] as usize..self.start[k + 1] as usize]
    }
}

fn bbox(p: [f64; 2], q: [f64; 2]) -> ([f64; 2], [f64; 2]) {
    (
        [p[0].min(q[0]), p[1].min(q[1])],
        [p[0].max(q[0]), p[1].max(q[1])],
    )
}

/// Whether `x` lies strictly between `a` and `b` on the line through them (given collinear).
fn strictly_between(a: [f64; 2], b: [f64; 2], x: [f64; 2]) -> bool {
    let k = if a[0] != b[0] { 0 } else { 1 };
    (a[k] < x[k] && x[k] < b[k]) || (b[k] < x[k] && x[k] < a[k])
}

/// Whether segments `p q` and `r s` intersect anywhere other than at a shared end point.
fn segments_intersect(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> bool {
    let (o1, o2) = (orient2d(p, q, r), orient2d(p, q, s));
    let (o3, o4) = (orient2d(r, s, p), orient2d(r, s, q));
    let opposite = |a: Sign, b: Sign| a != Sign::Zero && b != Sign::Zero && a != b;
    if opposite(o1, o2) && opposite(o3, o4) {
        return true;
    }
    // Touching or overlapping: an end point of one inside the other.
    (o1 == Sign::Zero && strictly_between(p, q, r))
        || (o2 == Sign::Zero && strictly_between(p, q, s))
        || (o3 == Sign::Zero && strictly_between(r, s, p))
        || (o4 == Sign::Zero && strictly_between(r, s, q))
}

/// Checks `plc` (see the module docs).
///
/// With `geometric` false the costliest checks, points inside segments and crossing segments,
/// are skipped: the Steiner-free recovery finds both itself, exactly, while inserting the
/// segments.
pub(crate) fn check(plc: &Plc2, geometric: bool) -> Result<CheckedPlc, RecoveryError> {
    let base = u64::from(plc.first_index);
    let name = |i: usize| i as u64 + base;
    let n = plc.points.len();
    for (i, p) in plc.points.iter().enumerate() {
        if !p[0].is_finite() || !p[1].is_finite() {
            return Err(RecoveryError::NonFinite { point: name(i) });
        }
    }
    for (what, seeds) in [
        ("hole", plc.holes.clone()),
        ("region", plc.regions.iter().map(|r| r.point).collect()),
    ] {
        if let Some(i) = seeds
            .iter()
            .position(|p| !p[0].is_finite() || !p[1].is_finite())
        {
            return Err(RecoveryError::BadSeed {
                what,
                index: name(i),
            });
        }
    }
    for (i, r) in plc.regions.iter().enumerate() {
        if let Some(a) = r.max_area.filter(|a| a.is_nan() || *a <= 0.0) {
            return Err(RecoveryError::BadAreaLimit {
                index: name(i),
                value: a,
            });
        }
    }
    // Merge duplicate points: each maps to its first occurrence.
    let mut first: HashMap<(u64, u64), u32> =
        HashMap::with_capacity_and_hasher(n, Default::default());
    let canon: Vec<u32> = plc
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            *first
                .entry(((p[0] + 0.0).to_bits(), (p[1] + 0.0).to_bits()))
                .or_insert(i as u32)
        })
        .collect();
    let merged: Vec<(u32, u32)> = (0..n as u32)
        .filter(|&i| canon[i as usize] != i)
        .map(|i| (i, canon[i as usize]))
        .collect();

    let mut segments = Vec::with_capacity(plc.segments.len());
    let mut origin = Vec::with_capacity(plc.segments.len());
    // Each segment's first occurrence (its index in `segments`).
    let mut seen: HashMap<(u32, u32), usize> =
        HashMap::with_capacity_and_hasher(plc.segments.len(), Default::default());
    for (i, s) in plc.segments.iter().enumerate() {
        for e in [s.a, s.b] {
            if e as usize >= n {
                return Err(RecoveryError::BadEndpoint {
                    segment: name(i),
                    point: u64::from(e) + base,
                    n_points: n,
                });
            }
        }
        let (a, b) = (canon[s.a as usize], canon[s.b as usize]);
        if a == b {
            return Err(RecoveryError::ZeroLength {
                segment: name(i),
                a: u64::from(s.a) + base,
                b: u64::from(s.b) + base,
            });
        }
        if let Some(&k) = seen.get(&(a.min(b), a.max(b))) {
            let first: &mut Segment = &mut segments[k];
            first.marker = agreed_marker(
                (first.marker, name(origin[k] as usize)),
                (s.marker, name(i)),
            )?;
            continue;
        }
        seen.insert((a.min(b), a.max(b)), segments.len());
        segments.push(Segment {
            a,
            b,
            marker: s.marker,
        });
        origin.push(i as u32);
    }

    let (lo, hi) = plc.points.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    );
    let pts = &plc.points;
    let boxes: Vec<_> = segments
        .iter()
        .map(|s| bbox(pts[s.a as usize], pts[s.b as usize]))
        .collect();
    if segments.is_empty() || !geometric {
        return Ok(CheckedPlc {
            points: plc.points.clone(),
            segments,
            origin,
            merged,
        });
    }
    let grid = Grid::new(&boxes, lo, hi);

    // Points inside segments: split the segment there.
    let mut on_segment: Vec<(u32, f64, u32)> = Vec::new(); // (segment, parameter, point)
    for (v, p) in pts.iter().enumerate() {
        if canon[v] != v as u32 {
            continue;
        }
        let mut cells = Vec::new();
        grid.for_cells(&(*p, *p), |k| cells.push(k));
        for k in cells {
            for &si in grid.bucket(k) {
                let s = segments[si as usize];
                let (a, b) = (pts[s.a as usize], pts[s.b as usize]);
                let inside_box = boxes[si as usize].0[0] <= p[0]
                    && p[0] <= boxes[si as usize].1[0]
                    && boxes[si as usize].0[1] <= p[1]
                    && p[1] <= boxes[si as usize].1[1];
                if inside_box && orient2d(a, b, *p) == Sign::Zero && strictly_between(a, b, *p) {
                    let t = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1]))
                        / ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2));
                    on_segment.push((si, t, v as u32));
                }
            }
        }
    }
    on_segment.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
    on_segment.dedup_by_key(|x| (x.0, x.2));
    if !on_segment.is_empty() {
        let mut split_segments = Vec::with_capacity(segments.len() + on_segment.len());
        let mut split_origin = Vec::with_capacity(segments.len() + on_segment.len());
        let mut k = 0;
        for (si, s) in segments.iter().enumerate() {
            let mut from = s.a;
            while k < on_segment.len() && on_segment[k].0 as usize == si {
                let v = on_segment[k].2;
                split_segments.push(Segment {
                    a: from,
                    b: v,
                    marker: s.marker,
                });
                split_origin.push(origin[si]);
                from = v;
                k += 1;
            }
            split_segments.push(Segment {
                a: from,
                b: s.b,
                marker: s.marker,
            });
            split_origin.push(origin[si]);
        }
        // Collinear segments that overlap now share pieces: keep the first of each, with the
        // markers agreeing as for repeats.
        seen.clear();
        let mut keep = vec![true; split_segments.len()];
        for j in 0..split_segments.len() {
            let s = split_segments[j];
            let Some(&k) = seen.get(&(s.a.min(s.b), s.a.max(s.b))) else {
                seen.insert((s.a.min(s.b), s.a.max(s.b)), j);
                continue;
            };
            keep[j] = false;
            split_segments[k].marker = agreed_marker(
                (split_segments[k].marker, name(split_origin[k] as usize)),
                (s.marker, name(split_origin[j] as usize)),
            )?;
        }
        segments = split_segments
            .into_iter()
            .zip(&keep)
            .filter_map(|(s, &k)| k.then_some(s))
            .collect();
        origin = split_origin
            .into_iter()
            .zip(&keep)
            .filter_map(|(o, &k)| k.then_some(o))
            .collect();
    }
    check_crossings(plc, segments, origin, merged, lo, hi)
}

/// Errors if two segments intersect other than at a shared end point.
fn check_crossings(
    plc: &Plc2,
    segments: Vec<Segment>,
    origin: Vec<u32>,
    merged: Vec<(u32, u32)>,
    lo: [f64; 2],
    hi: [f64; 2],
) -> Result<CheckedPlc, RecoveryError> {
    let pts = &plc.points;
    let boxes: Vec<_> = segments
        .iter()
        .map(|s| bbox(pts[s.a as usize], pts[s.b as usize]))
        .collect();
    let grid = Grid::new(&boxes, lo, hi);
    let mut stamp = vec![u32::MAX; segments.len()];
    let overlap = |i: usize, j: usize| {
        let (a, b) = (boxes[i], boxes[j]);
        a.0[0] <= b.1[0] && b.0[0] <= a.1[0] && a.0[1] <= b.1[1] && b.0[1] <= a.1[1]
    };
    for (i, s) in segments.iter().enumerate() {
        let mut cells = Vec::new();
        grid.for_cells(&boxes[i], |k| cells.push(k));
        for k in cells {
            for &j in grid.bucket(k) {
                let j = j as usize;
                if j <= i || stamp[j] == i as u32 || !overlap(i, j) {
                    continue;
                }
                stamp[j] = i as u32;
                let t = segments[j];
                let (p, q) = (pts[s.a as usize], pts[s.b as usize]);
                let (r, u) = (pts[t.a as usize], pts[t.b as usize]);
                if segments_intersect(p, q, r, u) {
                    let base = u64::from(plc.first_index);
                    let (x, y) = (origin[i].min(origin[j]), origin[i].max(origin[j]));
                    return Err(RecoveryError::Crossing {
                        first: u64::from(x) + base,
                        second: u64::from(y) + base,
                    });
                }
            }
        }
    }
    Ok(CheckedPlc {
        points: plc.points.clone(),
        segments,
        origin,
        merged,
    })
}
