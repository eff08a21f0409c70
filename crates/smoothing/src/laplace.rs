//! [`Smoother`]: Laplacian smoothing of a 2D triangle mesh given as flat arrays.
//!
//! The passes run on a private copy laid out for them:
//! - each free point's neighbours are one row, in counter-clockwise order around it, so the
//!   mean and the triangles of its star (consecutive neighbours) come from the same few loads;
//!   rows are padded with the point itself to a multiple of [`LANES`], so that the loop
//!   gathering them runs the same number of times for almost every point (a loop exit that
//!   depends on the degree was mispredicted about once per move: 5–10% of the smoothing time);
//! - the free points, in Z-order, are cut into tiles of [`TILE`] points. A tile's inner points
//!   (all of whose free neighbours are in the tile) are smoothed Gauss–Seidel, in place, on a
//!   buffer holding the tile and the few points around it, which stays in cache; the tiles run
//!   in parallel, since no triangle has inner points of two tiles;
//! - the points on the seams between tiles are coloured so that no two of one colour share an
//!   edge, and numbered colour by colour: the moves of one colour read only points that do not
//!   move, so they are computed in parallel into a scratch slice and copied back in one block.
//!
//! That is Gauss–Seidel in a fixed order, with the same result whatever the number of threads,
//! and no allocation per pass.
//!
//! A move is tested with the floating-point area of each triangle of the star and Shewchuk's
//! error bound for that very expression: only when the bound cannot certify the sign does the
//! exact `orient2d` decide, so no accepted move ever inverts an element. A move must also keep
//! the smallest angle of the star at 30° or at what it was ([`SIN2_GUARD`]). The neighbours are
//! gathered once per move, x and y apart, straight into vector registers ([`Group`]: a ring
//! written to scratch memory and read back as vectors cost a third of the smoothing time, in
//! stalled loads), and the triangles of the star tested [`LANES`] at a time, with the very
//! expressions of the one-by-one test [`star_accepts`], so the decisions are the same.
//!
//! A point whose triangles do not close around it (on the border of the triangles, or where
//! two fans touch) has no well-defined star to keep valid: it is boundary and stays fixed.

use crate::stars::Stars;
use delmesh_predicates::{orient2d, Sign};
use rayon::prelude::*;
use std::fmt;

/// The default relaxation factor ω (see [`Smoother::new`]).
pub const DEFAULT_OMEGA: f64 = 0.25;

/// The default number of passes N (see [`Smoother::new`]).
pub const DEFAULT_ITERATIONS: usize = 24;

/// How many times a rejected move is halved before the point is left where it is.
pub const MAX_HALVINGS: u32 = 4;

/// A move may shrink a triangle around the point to this fraction of its old area, no further.
const AREA_KEEP: f64 = 0.2;

/// `sin²` of the guard angle (30°): a move may not leave the smallest angle of the point's star
/// below it and smaller than it was.
const SIN2_GUARD: f64 = 0.25;

/// Smoothing stops early once no point moves by more than this fraction of the (root mean
/// square) length of its edges in a pass.
const CONVERGED: f64 = 5e-3;

/// Shewchuk's `ccwerrboundA`, `(3 + 16ε)ε`, rounded up: if `|l − r|` exceeds this times
/// `|l| + |r|` (with `l`, `r` the two products of `orient2d`), the floating-point sign is exact.
const CCW_ERRBOUND: f64 = 3.330_669_073_875_472e-16;

/// Below this, the products of the orientation test may have lost precision to underflow; the
/// exact predicate decides.
const TINY_PRODUCTS: f64 = 1e-290;

/// Points per parallel task within a seam colour; smaller colours run on the calling thread.
const CHUNK: usize = 1024;

/// Free points per tile: a tile's points, halo and rings (under 1 MB) fit in a core's L2 cache,
/// and bigger tiles leave fewer seam points (slower: their neighbours are not in one buffer).
const TILE: usize = 16384;

/// Bad smoothing options or input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SmoothError {
    /// ω must be in (0, 1].
    #[error("smoothing factor omega must be in (0, 1] (got {0:?})")]
    BadOmega(f64),
    /// The arrays do not fit together.
    #[error("smoothing input: {0}")]
    BadInput(String),
}

/// What a smoothing run did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SmoothStats {
    /// Passes made.
    pub passes: usize,
    /// Moves accepted at full length.
    pub moved: usize,
    /// Moves accepted after halving.
    pub reduced: usize,
    /// Moves refused (would invert or badly degrade an element).
    pub skipped: usize,
    /// Largest displacement of a point in the last pass, relative to the root mean square
    /// length of its edges.
    pub last_displacement: f64,
}

impl fmt::Display for SmoothStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} passes, {} moves, {} reduced, {} refused",
            self.passes, self.moved, self.reduced, self.skipped
        )
    }
}

/// Laplacian smoothing with relaxation factor ω and N passes; boundary points stay fixed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smoother {
    omega: f64,
    iterations: usize,
}

impl Default for Smoother {
    fn default() -> Self {
        Self::new()
    }
}

/// Counts of one colour's moves (or a chunk's), and the largest squared relative move.
#[derive(Clone, Copy, Default)]
struct Tally {
    moved: usize,
    reduced: usize,
    skipped: usize,
    largest: f64,
}

impl Tally {
    fn merge(self, o: Tally) -> Tally {
        Tally {
            moved: self.moved + o.moved,
            reduced: self.reduced + o.reduced,
            skipped: self.skipped + o.skipped,
            largest: self.largest.max(o.largest),
        }
    }
}

/// The smoothing copy: the inner points of each tile, tile by tile; then the seam points,
/// colour by colour; then the points that never move.
struct Layout {
    /// Caller's index of each local point.
    original: Vec<u32>,
    tiles: Vec<Tile>,
    /// Local index of the first seam point (all inner points are below).
    seam_start: usize,
    /// The rings (local indices) of the seam points (seam point `seam_start + i` is row `i`).
    rings: Rows,
    /// Local ranges of the seam colours.
    colours: Vec<std::ops::Range<usize>>,
    /// The most neighbours of a free point.
    widest: usize,
}

/// A run of free points consecutive in Z-order. Its inner points (all of whose free neighbours
/// are in the tile) are smoothed on a private buffer: the inner points, then the halo (the
/// other points they read, which do not move while the tile runs).
struct Tile {
    /// Local range of the inner points.
    inner: std::ops::Range<usize>,
    /// Local indices of the halo points (seam or fixed, all at or above `seam_start`).
    halo: Vec<u32>,
    /// The inner points that seam points read (indices in the tile): only these are copied
    /// out after each pass, the others once after the last.
    exposed: Vec<u32>,
    /// Rings of the inner points, in buffer indices (inner point `i` is `i`, halo point `h` is
    /// `inner.len() + h`).
    rings: Rows,
}

/// Rings of neighbours, counter-clockwise, one row per point. A row is the ring's last point,
/// then the ring, so that entries `k` and `k + 1` are the two neighbours of triangle `k` of the
/// star; the ring is padded to a multiple of [`LANES`] with the point itself, whose offset to
/// itself is zero: the gathering loop then runs a whole number of lane groups, the same number
/// for almost every point (rings of up to 8), so its exit is predicted, and the padding adds
/// nothing to the sums.
#[derive(Default)]
struct Rows {
    /// `ring[start[i]..start[i + 1]]`: row `i` (last neighbour, ring, padding).
    start: Vec<u32>,
    /// The number of neighbours of row `i` (its length without the padding).
    degree: Vec<u32>,
    ring: Vec<u32>,
}

impl Rows {
    fn new() -> Rows {
        Rows {
            start: vec![0],
            ..Default::default()
        }
    }

    /// Appends the row of point `own` (in the rows' numbering).
    fn push(&mut self, neighbours: impl IntoIterator<Item = u32>, own: u32) {
        let first = self.ring.len();
        // The slot for the last neighbour, repeated in front.
        self.ring.push(own);
        self.ring.extend(neighbours);
        let m = self.ring.len() - first - 1;
        self.ring[first] = self.ring[first + m];
        self.degree.push(m as u32);
        // At least one whole group of lanes, whatever the ring (the gathers read one).
        while (self.ring.len() - first - 1) % LANES != 0 || self.ring.len() - first == 1 {
            self.ring.push(own);
        }
        self.start.push(self.ring.len() as u32);
    }

    /// Row `i` (last neighbour, ring, padding) and its number of neighbours.
    #[inline(always)]
    fn row(&self, i: usize) -> (&[u32], usize) {
        let row = &self.ring[self.start[i] as usize..self.start[i + 1] as usize];
        (row, self.degree[i] as usize)
    }
}

impl Smoother {
    /// ω = 0.25, N = 24 (the paper uses ω in 0.05–0.25, N in 20–50). The smooth part of the
    /// error decays like `(1 − ωλ)^N ≈ e^(−ωNλ)`, so this is the relaxation of ω = 0.2 with 30
    /// passes in a fifth fewer passes; on the paper's demos its angles are as good or better.
    pub fn new() -> Self {
        Smoother {
            omega: DEFAULT_OMEGA,
            iterations: DEFAULT_ITERATIONS,
        }
    }

    /// Sets the relaxation factor ω.
    ///
    /// # Errors
    /// ω outside (0, 1].
    pub fn omega(mut self, omega: f64) -> Result<Self, SmoothError> {
        if !(omega > 0.0 && omega <= 1.0) {
            return Err(SmoothError::BadOmega(omega));
        }
        self.omega = omega;
        Ok(self)
    }

    /// Sets the number of passes N.
    pub fn iterations(mut self, n: usize) -> Self {
        self.iterations = n;
        self
    }

    /// Smooths `points` in place. `triangles` are counter-clockwise; points with `fixed` set
    /// (the boundary) never move, nor do points whose triangles do not close around them (on
    /// the border of the triangles, or where two fans touch): they are boundary too. Every
    /// triangle stays positively oriented.
    ///
    /// # Errors
    /// Lengths that do not match, an index out of range, a non-finite coordinate, or an input
    /// triangle that is not positively oriented.
    pub fn smooth(
        &self,
        points: &mut [[f64; 2]],
        triangles: &[[u32; 3]],
        fixed: &[bool],
    ) -> Result<SmoothStats, SmoothError> {
        let n = points.len();
        check_points(points, fixed.len(), "fixed flags")?;
        // The first triangle out of range or not counter-clockwise (checked in parallel).
        let out_of_range = |t: &[u32; 3]| t.iter().any(|&v| v as usize >= n);
        if let Some(k) = triangles.par_iter().position_first(|t| {
            out_of_range(t) || {
                let p = t.map(|v| points[v as usize]);
                orient2d(p[0], p[1], p[2]) != Sign::Positive
            }
        }) {
            return Err(SmoothError::BadInput(if out_of_range(&triangles[k]) {
                format!("triangle {k} names a point out of range")
            } else {
                format!("triangle {k} is not counter-clockwise")
            }));
        }
        // The stars in Z-order numbering, so that building them and the tiles reads memory in
        // order whatever the caller's numbering.
        let z = z_order(points);
        let mut rank = vec![0u32; n];
        for (i, &v) in z.iter().enumerate() {
            rank[v as usize] = i as u32;
        }
        let stars = Stars::from_triangles(triangles, fixed, &rank);
        let identity: Vec<u32> = (0..n as u32).collect();
        let mut layout = Layout::new(&stars, &identity);
        for v in &mut layout.original {
            *v = z[*v as usize];
        }
        Ok(self.run(points, &layout))
    }

    /// Smooths `points` in place, each free point moving within its star in `stars` (see
    /// [`Stars::from_rings`]); points with an empty ring stay fixed. The result is that of
    /// [`Smoother::smooth`] on the triangles of the stars, with the boundary fixed, and costs
    /// less when the caller's triangulation gives its stars directly (by walking its own
    /// adjacency) than building them from a triangle list.
    ///
    /// # Errors
    /// A number of stars other than of points, a non-finite coordinate, or a star triangle
    /// (a point and two consecutive neighbours) that is not positively oriented.
    pub fn smooth_stars(
        &self,
        points: &mut [[f64; 2]],
        stars: &Stars,
    ) -> Result<SmoothStats, SmoothError> {
        let n = points.len();
        check_points(points, stars.len(), "stars")?;
        let p: &[[f64; 2]] = points;
        let inverted = (0..n)
            .into_par_iter()
            .with_min_len(1 << 10)
            .find_first(|&i| {
                let ring = stars.ring(i);
                let mut a = match ring.last() {
                    Some(&a) => p[a as usize],
                    None => return false,
                };
                ring.iter().any(|&b| {
                    let b = p[b as usize];
                    let positive = orient2d(p[i], a, b) == Sign::Positive;
                    a = b;
                    !positive
                })
            });
        if let Some(i) = inverted {
            return Err(SmoothError::BadInput(format!(
                "a triangle of the star of point {i} is not counter-clockwise"
            )));
        }
        let layout = Layout::new(stars, &z_order(points));
        Ok(self.run(points, &layout))
    }

    /// The passes on a copy of `points` laid out by `layout`, copied back.
    fn run(&self, points: &mut [[f64; 2]], layout: &Layout) -> SmoothStats {
        let mut local: Vec<[f64; 2]> = layout
            .original
            .par_iter()
            .map(|&v| points[v as usize])
            .collect();
        let stats = self.relax(&mut local, layout);
        for (p, &v) in local.iter().zip(&layout.original) {
            points[v as usize] = *p;
        }
        stats
    }

    /// The smoothing passes proper, on the laid-out copy. Each pass smooths the tiles' inner
    /// points (tiles in parallel, each Gauss–Seidel in Z-order on its buffer, which stays in
    /// cache), then the seam points (colour by colour, in parallel chunks).
    fn relax(&self, points: &mut [[f64; 2]], layout: &Layout) -> SmoothStats {
        let widest = layout.colours.iter().map(|r| r.len()).max().unwrap_or(0);
        let mut scratch = vec![[0.0f64; 2]; widest];
        // `ω / m` for rings of `m` points: no division on the way from the sums to the move.
        let weight: &[f64] = &(0..=layout.widest)
            .map(|m| self.omega / m as f64)
            .collect::<Vec<_>>();
        let mut buffers: Vec<Vec<[f64; 2]>> = layout
            .tiles
            .iter()
            .map(|t| vec![[0.0; 2]; t.inner.len() + t.halo.len()])
            .collect();
        let mut stats = SmoothStats::default();
        for pass in 0..self.iterations {
            stats.passes += 1;
            let (inner, rest) = points.split_at_mut(layout.seam_start);
            let rest: &[[f64; 2]] = rest;
            let mut slices = Vec::with_capacity(layout.tiles.len());
            let mut tail = inner;
            for t in &layout.tiles {
                let (head, more) = tail.split_at_mut(t.inner.len());
                slices.push(head);
                tail = more;
            }
            let mut all = slices
                .into_par_iter()
                .zip(buffers.par_iter_mut())
                .zip(layout.tiles.par_iter())
                .map(|((own, buf), tile)| {
                    let n = own.len();
                    // Only this tile moves its inner points: after the first pass, its buffer
                    // already holds them; only the halo is read again.
                    if pass == 0 {
                        buf[..n].copy_from_slice(own);
                    }
                    for (slot, &h) in buf[n..].iter_mut().zip(&tile.halo) {
                        *slot = rest[h as usize - layout.seam_start];
                    }
                    let mut t = Tally::default();
                    for v in 0..n {
                        let (row, m) = tile.rings.row(v);
                        buf[v] = Self::propose(buf, v, row, m, weight, &mut t);
                    }
                    for &i in &tile.exposed {
                        own[i as usize] = buf[i as usize];
                    }
                    t
                })
                .reduce(Tally::default, Tally::merge);
            for range in &layout.colours {
                let out = &mut scratch[..range.len()];
                let read: &[[f64; 2]] = points;
                let task = |(k, chunk): (usize, &mut [[f64; 2]])| {
                    let first = range.start + k * CHUNK;
                    let mut t = Tally::default();
                    for (i, slot) in chunk.iter_mut().enumerate() {
                        let (row, m) = layout.rings.row(first + i - layout.seam_start);
                        *slot = Self::propose(read, first + i, row, m, weight, &mut t);
                    }
                    t
                };
                let tally = if range.len() > CHUNK {
                    out.par_chunks_mut(CHUNK)
                        .enumerate()
                        .map(task)
                        .reduce(Tally::default, Tally::merge)
                } else {
                    task((0, out))
                };
                points[range.clone()].copy_from_slice(out);
                all = all.merge(tally);
            }
            stats.moved += all.moved;
            stats.reduced += all.reduced;
            stats.skipped += all.skipped;
            stats.last_displacement = all.largest.sqrt();
            if stats.last_displacement < CONVERGED {
                break;
            }
        }
        // The inner points of the tiles, from their buffers (which hold them after a pass).
        if stats.passes > 0 {
            let mut tail = &mut points[..layout.seam_start];
            for (t, buf) in layout.tiles.iter().zip(&buffers) {
                let (own, more) = tail.split_at_mut(t.inner.len());
                own.copy_from_slice(&buf[..t.inner.len()]);
                tail = more;
            }
        }
        stats
    }

    /// The new position of free point `v`: the move towards the mean of its neighbours, halved
    /// until every triangle around it stays positive (exact) and keeps [`AREA_KEEP`] of its
    /// area (the edge opposite `v` is fixed, so a triangle's area is linear in `v`'s position),
    /// or its old position if refused. Counts the outcome in `tally`, with the squared move
    /// over the mean squared length of `v`'s edges. `row` is `v`'s row (see [`Rows`]), with
    /// `m` neighbours; `weight[m]` is `ω / m`.
    #[inline(always)]
    fn propose(
        points: &[[f64; 2]],
        v: usize,
        row: &[u32],
        m: usize,
        weight: &[f64],
        tally: &mut Tally,
    ) -> [f64; 2] {
        let x = points[v];
        let (mut sx, mut sy, mut length2) = (0.0, 0.0, 0.0);
        // In order, so the sums are those over the ring alone (the padding adds zeros).
        let mut add = |group: &Group| {
            for j in 0..LANES {
                let (dx, dy) = (group.bx[j] - x[0], group.by[j] - x[1]);
                sx += dx;
                sy += dy;
                length2 += dx * dx + dy * dy;
            }
        };
        // The whole star for rings of up to `LANES` points: gathered once for the move.
        let first = Group::gather(points, row, 0);
        add(&first);
        for k in (LANES..row.len() - 1).step_by(LANES) {
            add(&Group::gather(points, row, k));
        }
        let w = weight[m];
        let mut step = [w * sx, w * sy];
        let mut y = [x[0] + step[0], x[1] + step[1]];
        // The first try on the gathered star (most moves stop here), then the halvings.
        let mut accepted = y == x || star_accepts_lanes(&first, m, x, y, points, row);
        let mut halving = 0;
        while !accepted && halving < MAX_HALVINGS {
            halving += 1;
            step = [0.5 * step[0], 0.5 * step[1]];
            y = [x[0] + step[0], x[1] + step[1]];
            accepted = y == x || {
                let first = Group::gather(points, row, 0);
                star_accepts_lanes(&first, m, x, y, points, row)
            };
        }
        if accepted {
            let moved2 = step[0] * step[0] + step[1] * step[1];
            if y != x {
                tally.largest = tally.largest.max(moved2 * m as f64 / length2);
            }
            tally.moved += usize::from(halving == 0);
            tally.reduced += usize::from(halving > 0);
            return y;
        }
        tally.skipped += 1;
        x
    }
}

/// Errors unless there are `given` of `what` (one per point) and every point is finite.
fn check_points(points: &[[f64; 2]], given: usize, what: &str) -> Result<(), SmoothError> {
    if given != points.len() {
        return Err(SmoothError::BadInput(format!(
            "{} points but {given} {what}",
            points.len()
        )));
    }
    match points
        .iter()
        .position(|p| !p[0].is_finite() || !p[1].is_finite())
    {
        Some(i) => Err(SmoothError::BadInput(format!("point {i} is not finite"))),
        None => Ok(()),
    }
}

/// Triangles of a star tested together: the tests run on arrays of this many triangles, which
/// the compiler turns into vector instructions (most rings have 5 to 8 points).
const LANES: usize = 8;

/// One number per triangle of a group of [`LANES`].
type Lanes = [f64; LANES];

/// The neighbours of [`LANES`] consecutive triangles of a star, x and y apart: triangle `j` of
/// the group is (centre, a_j, b_j).
#[derive(Default)]
struct Group {
    ax: Lanes,
    ay: Lanes,
    bx: Lanes,
    by: Lanes,
}

impl Group {
    /// Triangles `k..k + LANES` of the star in `row` (see [`Rows`]; past the ring, the lanes
    /// hold the padding). Each neighbour is loaded straight into its lanes, not through memory
    /// written just before, which the processor cannot forward to a vector load.
    #[inline(always)]
    fn gather(points: &[[f64; 2]], row: &[u32], k: usize) -> Group {
        let ends: &[u32; LANES + 1] = row[k..=k + LANES].try_into().expect("a padded row");
        let mut g = Group::default();
        for j in 0..LANES {
            let b = points[ends[j + 1] as usize];
            (g.bx[j], g.by[j]) = (b[0], b[1]);
        }
        let a = points[ends[0] as usize];
        (g.ax[0], g.ay[0]) = (a[0], a[1]);
        for j in 1..LANES {
            (g.ax[j], g.ay[j]) = (g.bx[j - 1], g.by[j - 1]);
        }
        g
    }

    /// The [`Triangle`] tests of the group's first `real` triangles (all if more) for the move
    /// from `x` to `y`: whether one is refused, one unsure, one sharp.
    #[inline(always)]
    fn test(&self, real: usize, x: [f64; 2], y: [f64; 2]) -> [bool; 3] {
        let (mut refused, mut unsure, mut sharp) = (false, false, false);
        for j in 0..LANES {
            let t = Triangle::new([self.ax[j], self.ay[j]], [self.bx[j], self.by[j]], x, y);
            let real = j < real;
            refused |= real & !t.kept;
            unsure |= real & !t.certain;
            sharp |= real & t.sharp;
        }
        [refused, unsure, sharp]
    }
}

/// [`star_accepts`] for the star of `m` neighbours in `row` (see [`Rows`]), whose first
/// triangles are `first`, tested [`LANES`] at a time: the same floating-point expressions per
/// triangle, so the same answer.
#[inline(always)]
fn star_accepts_lanes(
    first: &Group,
    m: usize,
    x: [f64; 2],
    y: [f64; 2],
    points: &[[f64; 2]],
    row: &[u32],
) -> bool {
    let [mut refused, mut unsure, mut sharp] = first.test(m, x, y);
    for k in (LANES..m).step_by(LANES) {
        let [r, u, s] = Group::gather(points, row, k).test(m - k, x, y);
        (refused, unsure, sharp) = (refused | r, unsure | u, sharp | s);
    }
    let ring = &row[1..=m];
    if refused {
        return false;
    }
    if unsure {
        return star_accepts(points, ring, x, y);
    }
    // A star sharper than the guard after the move must not be sharper than before.
    if !sharp {
        return true;
    }
    let after = star_sharpness(points, ring, y);
    after >= SIN2_GUARD || after >= star_sharpness(points, ring, x)
}

/// The tests of one triangle (y, a, b) of a star whose centre moves from x to y.
struct Triangle {
    /// It keeps at least [`AREA_KEEP`] of its area.
    kept: bool,
    /// Its floating-point area is certainly positive (else the exact test decides).
    certain: bool,
    /// Its smallest angle is below the guard.
    sharp: bool,
}

impl Triangle {
    #[inline(always)]
    fn new(a: [f64; 2], b: [f64; 2], x: [f64; 2], y: [f64; 2]) -> Triangle {
        let (ay, by) = ([a[0] - y[0], a[1] - y[1]], [b[0] - y[0], b[1] - y[1]]);
        let (ax, bx) = ([a[0] - x[0], a[1] - x[1]], [b[0] - x[0], b[1] - x[1]]);
        // Twice the area of (y, a, b) in orient2d's own expression (c = y), so that its error
        // bound applies.
        let (l, r) = (ay[0] * by[1], ay[1] * by[0]);
        let twice_y = l - r;
        let twice_x = ax[0] * bx[1] - ax[1] * bx[0];
        let bound = l.abs() + r.abs();
        // The smallest angle θ of a triangle: sin²θ = (2·area)² / (product of the two longer
        // squared edges), and that product is the largest of the three pairwise ones.
        let a2 = ay[0] * ay[0] + ay[1] * ay[1];
        let b2 = by[0] * by[0] + by[1] * by[1];
        let ab = [by[0] - ay[0], by[1] - ay[1]];
        let ab2 = ab[0] * ab[0] + ab[1] * ab[1];
        let longer = larger(larger(a2 * b2, a2 * ab2), b2 * ab2);
        Triangle {
            kept: twice_y >= AREA_KEEP * twice_x,
            certain: (twice_y > CCW_ERRBOUND * bound) & (bound > TINY_PRODUCTS),
            sharp: twice_y * twice_y < SIN2_GUARD * longer,
        }
    }
}

/// Whether moving the centre of the star `ring` (counter-clockwise) from `x` to `y` keeps every
/// triangle positive (exactly) and at least [`AREA_KEEP`] of its area.
#[inline(always)]
fn star_accepts(points: &[[f64; 2]], ring: &[u32], x: [f64; 2], y: [f64; 2]) -> bool {
    let Some(&last) = ring.last() else {
        return true;
    };
    let mut a = points[last as usize];
    // Each neighbour relative to y and to x, and its squared distance to y, carried over to the
    // next triangle.
    let (mut ay, mut ax) = ([a[0] - y[0], a[1] - y[1]], [a[0] - x[0], a[1] - x[1]]);
    let mut a2 = ay[0] * ay[0] + ay[1] * ay[1];
    // Whether a triangle of the star is sharper than the guard after the move (rare: then the
    // star's sharpness before and after decide, out of this loop and its divisions).
    let mut sharp = false;
    for &ib in ring {
        let b = points[ib as usize];
        let by = [b[0] - y[0], b[1] - y[1]];
        let bx = [b[0] - x[0], b[1] - x[1]];
        // Twice the area of (y, a, b) in orient2d's own expression (c = y), so that its error
        // bound applies.
        let (l, r) = (ay[0] * by[1], ay[1] * by[0]);
        let twice_y = l - r;
        let twice_x = ax[0] * bx[1] - ax[1] * bx[0];
        let bound = l.abs() + r.abs();
        let kept = twice_y >= AREA_KEEP * twice_x;
        let certain = twice_y > CCW_ERRBOUND * bound && bound > TINY_PRODUCTS;
        if !(kept && (certain || orient2d(y, a, b) == Sign::Positive)) {
            return false;
        }
        // The smallest angle θ of a triangle: sin²θ = (2·area)² / (product of the two longer
        // squared edges), and that product is the largest of the three pairwise ones.
        let b2 = by[0] * by[0] + by[1] * by[1];
        let ab = [by[0] - ay[0], by[1] - ay[1]];
        let ab2 = ab[0] * ab[0] + ab[1] * ab[1];
        let longer = larger(larger(a2 * b2, a2 * ab2), b2 * ab2);
        sharp |= twice_y * twice_y < SIN2_GUARD * longer;
        (a, ay, ax, a2) = (b, by, bx, b2);
    }
    // A star sharper than the guard after the move must not be sharper than before.
    if !sharp {
        return true;
    }
    let after = star_sharpness(points, ring, y);
    after >= SIN2_GUARD || after >= star_sharpness(points, ring, x)
}

/// The larger of two numbers that are not NaN (a plain comparison, cheaper than `f64::max`).
#[inline(always)]
fn larger(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// sin² of the smallest angle of the star `ring` around `x`.
fn star_sharpness(points: &[[f64; 2]], ring: &[u32], x: [f64; 2]) -> f64 {
    let Some(&last) = ring.last() else {
        return 1.0;
    };
    let d = |p: [f64; 2]| [p[0] - x[0], p[1] - x[1]];
    let mut a = d(points[last as usize]);
    let mut sharpest = 1.0f64;
    for &ib in ring {
        let b = d(points[ib as usize]);
        let twice = a[0] * b[1] - a[1] * b[0];
        let (a2, b2) = (a[0] * a[0] + a[1] * a[1], b[0] * b[0] + b[1] * b[1]);
        let ab2 = (b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2);
        let longer = larger(larger(a2 * b2, a2 * ab2), b2 * ab2);
        sharpest = sharpest.min(twice * twice / longer);
        a = b;
    }
    sharpest
}

impl Layout {
    /// Cuts the free points (those with a ring), in the order `sequence` lists them, into
    /// tiles, colours the seam points (greedily, in that order) and numbers everything tile by
    /// tile and colour by colour. `original` is in the numbering of `stars`.
    fn new(stars: &Stars, sequence: &[u32]) -> Layout {
        let n = stars.len();
        let ring_at = |i: usize| stars.ring(i);
        let free: Vec<u32> = sequence
            .iter()
            .copied()
            .filter(|&i| !ring_at(i as usize).is_empty())
            .collect();
        // Tiles: runs of TILE free points in sequence. A point is inner if every free neighbour
        // is in its tile, else on the seam.
        let mut tile_of = vec![u32::MAX; n];
        for (k, &i) in free.iter().enumerate() {
            tile_of[i as usize] = (k / TILE) as u32;
        }
        let inner = |i: usize| {
            ring_at(i)
                .iter()
                .all(|&u| matches!(tile_of[u as usize], t if t == u32::MAX || t == tile_of[i]))
        };
        // Each tile's inner and seam points (tiles in parallel), concatenated in order.
        let split: Vec<(Vec<u32>, Vec<u32>)> = free
            .par_chunks(TILE)
            .map(|run| run.iter().partition(|&&i| inner(i as usize)))
            .collect();
        let mut order: Vec<u32> = Vec::with_capacity(n);
        let mut tile_ranges = Vec::with_capacity(split.len());
        let mut seam: Vec<u32> = Vec::new();
        for (inner, on_seam) in split {
            let s = order.len();
            order.extend_from_slice(&inner);
            tile_ranges.push(s..order.len());
            seam.extend_from_slice(&on_seam);
        }
        let seam_start = order.len();
        // Greedy colouring of the seam points, in Z-order: the smallest colour no seam
        // neighbour has.
        let mut colour = vec![u32::MAX; n];
        let mut members: Vec<Vec<u32>> = Vec::new();
        let mut taken: Vec<u32> = Vec::new();
        for &i in &seam {
            taken.clear();
            taken.extend(ring_at(i as usize).iter().map(|&u| colour[u as usize]));
            taken.sort_unstable();
            let mut k = 0u32;
            for &t in &taken {
                if t == k {
                    k += 1;
                } else if t > k {
                    break;
                }
            }
            colour[i as usize] = k;
            if members.len() <= k as usize {
                members.resize(k as usize + 1, Vec::new());
            }
            members[k as usize].push(i);
        }
        let mut colours = Vec::with_capacity(members.len());
        for m in &members {
            let s = order.len();
            order.extend_from_slice(m);
            colours.push(s..order.len());
        }
        let moving = order.len();
        order.extend((0..n as u32).filter(|&i| tile_of[i as usize] == u32::MAX));
        let mut local = vec![0u32; n];
        for (k, &i) in order.iter().enumerate() {
            local[i as usize] = k as u32;
        }
        // Seam rings in local indices.
        let mut seam_rings = Rows::new();
        for &i in &order[seam_start..moving] {
            let own = local[i as usize];
            seam_rings.push(ring_at(i as usize).iter().map(|&u| local[u as usize]), own);
        }
        // The inner points on seam rings, in order (the padding is the seam point itself).
        let mut exposed: Vec<u32> = seam_rings
            .ring
            .iter()
            .copied()
            .filter(|&l| (l as usize) < seam_start)
            .collect();
        exposed.sort_unstable();
        exposed.dedup();
        // Tiles: rings in buffer indices, halo points numbered after the inner ones.
        let tiles = tile_ranges
            .into_par_iter()
            .map(|range| {
                let within = |l: &u32| (*l as usize) < range.start;
                let from = exposed.partition_point(within);
                let to = exposed.partition_point(|l| (*l as usize) < range.end);
                let mut tile = Tile {
                    inner: range.clone(),
                    halo: Vec::new(),
                    exposed: exposed[from..to]
                        .iter()
                        .map(|&l| l - range.start as u32)
                        .collect(),
                    rings: Rows::new(),
                };
                let members = &order[range.clone()];
                let outside = |u: u32| {
                    let l = local[u as usize] as usize;
                    (!range.contains(&l)).then_some(l as u32)
                };
                tile.halo = members
                    .iter()
                    .flat_map(|&i| ring_at(i as usize).iter().filter_map(|&u| outside(u)))
                    .collect();
                tile.halo.sort_unstable();
                tile.halo.dedup();
                for (own, &i) in members.iter().enumerate() {
                    let halo = &tile.halo;
                    let buffer_index = |&u: &u32| {
                        let l = local[u as usize] as usize;
                        let b = match outside(u) {
                            None => l - range.start,
                            Some(h) => range.len() + halo.binary_search(&h).expect("in halo"),
                        };
                        b as u32
                    };
                    let row = ring_at(i as usize).iter().map(buffer_index);
                    tile.rings.push(row, own as u32);
                }
                tile
            })
            .collect();
        Layout {
            widest: stars.widest(),
            original: order,
            tiles,
            seam_start,
            rings: seam_rings,
            colours,
        }
    }
}

/// The points' order along a Z-order (Morton) curve of 16 bits per axis.
fn z_order(points: &[[f64; 2]]) -> Vec<u32> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let scale = [0, 1].map(|k| {
        let w = hi[k] - lo[k];
        if w > 0.0 {
            65535.0 / w
        } else {
            0.0
        }
    });
    let spread = |x: u32| {
        let mut x = u64::from(x) & 0xFFFF;
        x = (x | (x << 8)) & 0x00FF_00FF;
        x = (x | (x << 4)) & 0x0F0F_0F0F;
        x = (x | (x << 2)) & 0x3333_3333;
        (x | (x << 1)) & 0x5555_5555
    };
    let mut keyed: Vec<u64> = points
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            let qx = ((p[0] - lo[0]) * scale[0]) as u32;
            let qy = ((p[1] - lo[1]) * scale[1]) as u32;
            ((spread(qx) | (spread(qy) << 1)) << 32) | i as u64
        })
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|k| k as u32).collect()
}

/// The angle at `o` between `u` and `w` (radians).
pub(crate) fn angle(o: [f64; 2], u: [f64; 2], w: [f64; 2]) -> f64 {
    let (ux, uy, wx, wy) = (u[0] - o[0], u[1] - o[1], w[0] - o[0], w[1] - o[1]);
    (ux * wy - uy * wx).abs().atan2(ux * wx + uy * wy)
}
