//! [`Stars`]: each free point's neighbours in counter-clockwise order, the one thing the 2D
//! smoother reads of the mesh's connectivity.
//!
//! They are built from a triangle list (the corners of each point's triangles, chained into
//! one cycle), or taken from a triangulation that walks its own adjacency around each vertex,
//! which is cheaper than rebuilding it from triangles (about a fifth of the smoothing time at
//! 10^6 triangles).

use crate::laplace::SmoothError;
use rayon::prelude::*;

/// Points per parallel task when chaining corners into rings.
const RING_CHUNK: usize = 1 << 14;

/// Ranges of points whose corners are gathered in parallel (a fixed number, so that the work
/// does not depend on the number of threads; each range scans all the triangles).
const FILL_RANGES: usize = 2;

/// The ring of neighbours of every point, counter-clockwise, in one flat array: point `i`'s is
/// `ring[start[i]..start[i + 1]]`. A point with an empty ring is fixed (boundary).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Stars {
    start: Vec<u32>,
    ring: Vec<u32>,
}

impl Stars {
    /// Stars from rings already chained: `start` has one entry per point and one more (the
    /// first `0`, non-decreasing, the last `ring.len()`), `ring` the neighbours. Each ring must
    /// be the counter-clockwise cycle of neighbours of its point in a triangulation whose
    /// triangles are all positive: [`crate::Smoother::smooth_stars`] checks that every
    /// triangle of every star is positive, and keeps it so.
    ///
    /// # Errors
    /// `start` not as described, a neighbour out of range or equal to its point, or a
    /// non-empty ring of fewer than three points.
    pub fn from_rings(start: Vec<u32>, ring: Vec<u32>) -> Result<Stars, SmoothError> {
        let bad = |what: String| Err(SmoothError::BadInput(what));
        if start.first() != Some(&0) || start.last().map(|&s| s as usize) != Some(ring.len()) {
            return bad(format!(
                "ring starts must begin at 0 and end at the ring length {}",
                ring.len()
            ));
        }
        if let Some(i) = start.windows(2).position(|w| w[0] > w[1]) {
            return bad(format!("ring starts decrease at point {i}"));
        }
        let stars = Stars { start, ring };
        stars.check()?;
        Ok(stars)
    }

    /// Errors unless every ring is empty or at least three other points.
    fn check(&self) -> Result<(), SmoothError> {
        let n = self.len();
        let broken = (0..n).into_par_iter().find_first(|&i| {
            let r = self.ring(i);
            (!r.is_empty() && r.len() < 3) || r.iter().any(|&u| u as usize >= n || u as usize == i)
        });
        match broken {
            Some(i) => Err(SmoothError::BadInput(format!(
                "the ring of point {i} is not a cycle of at least three other points"
            ))),
            None => Ok(()),
        }
    }

    /// The stars of the points of `triangles` (counter-clockwise), in the numbering `rank`
    /// gives the points (`rank[v]` for point `v`; the result's point `rank[v]` is `v`). A point
    /// that is `fixed`, or whose triangles' corners do not chain into one closed cycle (on the
    /// border of the triangles, or where two fans touch), gets an empty ring.
    pub(crate) fn from_triangles(triangles: &[[u32; 3]], fixed: &[bool], rank: &[u32]) -> Stars {
        let n = rank.len();
        // The corners of each point (ranked): the edge opposite it in each of its triangles, as
        // (first, second) counter-clockwise.
        let ranked: Vec<[u32; 3]> = triangles
            .par_iter()
            .map(|t| t.map(|v| rank[v as usize]))
            .collect();
        let mut first = vec![0u32; n + 1];
        for r in &ranked {
            for &v in r {
                first[v as usize + 1] += 1;
            }
        }
        for i in 0..n {
            first[i + 1] += first[i];
        }
        // Filled in parallel over FILL_RANGES ranges of points: each range scans all triangles
        // and keeps its own corners (the scattered writes, not the scan, are the cost).
        let mut corners = vec![[0u32; 2]; first[n] as usize];
        let bounds: Vec<usize> = (0..=FILL_RANGES).map(|r| r * n / FILL_RANGES).collect();
        let mut slices = Vec::with_capacity(FILL_RANGES);
        let mut rest = &mut corners[..];
        for r in 0..FILL_RANGES {
            let len = (first[bounds[r + 1]] - first[bounds[r]]) as usize;
            let (own, tail) = rest.split_at_mut(len);
            slices.push(own);
            rest = tail;
        }
        slices.into_par_iter().enumerate().for_each(|(r, own)| {
            let points = bounds[r]..bounds[r + 1];
            let base = first[points.start];
            let mut fill: Vec<u32> = first[points.clone()].iter().map(|&f| f - base).collect();
            for t in &ranked {
                for k in 0..3 {
                    let v = t[k] as usize;
                    if points.contains(&v) {
                        let at = &mut fill[v - points.start];
                        own[*at as usize] = [t[(k + 1) % 3], t[(k + 2) % 3]];
                        *at += 1;
                    }
                }
            }
        });
        drop(ranked);
        let mut is_fixed = vec![false; n];
        for (v, &f) in fixed.iter().enumerate() {
            is_fixed[rank[v] as usize] = f;
        }
        Stars::gather(n, |i, out| {
            let c = &corners[first[i] as usize..first[i + 1] as usize];
            !is_fixed[i] && !c.is_empty() && chain(c, out)
        })
    }

    /// The stars of `n` points, each appended by `ring(i, out)` (counter-clockwise), which
    /// returns false for a point that stays fixed (what it appended is dropped); points in
    /// parallel chunks, concatenated in order. Checked as [`Stars::from_rings`] checks.
    ///
    /// # Errors
    /// As [`Stars::from_rings`].
    pub fn build(
        n: usize,
        ring: impl Fn(usize, &mut Vec<u32>) -> bool + Sync,
    ) -> Result<Stars, SmoothError> {
        let stars = Stars::gather(n, ring);
        stars.check()?;
        Ok(stars)
    }

    /// [`Stars::build`] unchecked.
    fn gather(n: usize, ring: impl Fn(usize, &mut Vec<u32>) -> bool + Sync) -> Stars {
        // Each chunk's rings and the ring length of each of its points.
        let parts: Vec<(Vec<u32>, Vec<u32>)> = (0..n.div_ceil(RING_CHUNK))
            .into_par_iter()
            .map(|k| {
                let points = k * RING_CHUNK..((k + 1) * RING_CHUNK).min(n);
                let (mut rings, mut lengths) = (Vec::new(), Vec::with_capacity(points.len()));
                for i in points {
                    let at = rings.len();
                    if !ring(i, &mut rings) {
                        rings.truncate(at);
                    }
                    lengths.push((rings.len() - at) as u32);
                }
                (rings, lengths)
            })
            .collect();
        let mut stars = Stars {
            start: Vec::with_capacity(n + 1),
            ring: Vec::with_capacity(parts.iter().map(|p| p.0.len()).sum()),
        };
        stars.start.push(0);
        for (rings, lengths) in parts {
            let mut at = stars.ring.len() as u32;
            for len in lengths {
                at += len;
                stars.start.push(at);
            }
            stars.ring.extend_from_slice(&rings);
        }
        stars
    }

    /// The number of points.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// True if there are no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The ring of point `i` (empty if it is fixed).
    #[inline]
    pub fn ring(&self, i: usize) -> &[u32] {
        &self.ring[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// The most neighbours of a point.
    pub(crate) fn widest(&self) -> usize {
        self.start
            .windows(2)
            .map(|w| (w[1] - w[0]) as usize)
            .max()
            .unwrap_or(0)
    }
}

/// Appends the neighbours of a point in counter-clockwise order to `out`, from its corners
/// (the opposite edge of each of its triangles): true if they chain into one closed cycle
/// through every corner once, false otherwise (`out` then holds garbage past its old length).
///
/// The chain follows, from each neighbour, the last corner starting there; a walk that comes
/// back to its start after exactly one step per corner has visited distinct neighbours, hence
/// every corner once.
fn chain(corners: &[[u32; 2]], out: &mut Vec<u32>) -> bool {
    let [start, mut at] = corners[0];
    out.push(start);
    for _ in 1..corners.len() {
        if at == start {
            return false;
        }
        // Without an early exit (the loop is short, a mispredicted exit is not).
        let mut next = usize::MAX;
        for (k, c) in corners.iter().enumerate() {
            if c[0] == at {
                next = k;
            }
        }
        if next == usize::MAX {
            return false;
        }
        out.push(at);
        at = corners[next][1];
    }
    at == start
}
