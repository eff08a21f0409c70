//! [`Smoother3`]: Laplacian smoothing of a tetrahedral mesh given as flat arrays.
//!
//! The 3D counterpart of [`crate::Smoother`], with the same rules: each free point moves
//! `X ← X + ω·Σ(X_i − X)/M` over its `M` edge neighbours; the move is kept only if every
//! tetrahedron around the point stays positively oriented (exact `orient3d`) and keeps a fifth
//! of its volume; otherwise it is halved, up to [`MAX_HALVINGS`] times, then skipped.
//! The face opposite the moving point is fixed, so a tetrahedron's volume is linear in the
//! point's position: one dot product with that face's normal per tetrahedron. The star's
//! tetrahedra are gathered at most once per move, a group when a trial first needs it, and
//! tested [`LANES`] at a time (vector instructions) with the expressions of the one-by-one
//! test; the floating-point volume decides the sign only where its error bound
//! ([`VOLUME_ERRBOUND`]) certifies it, else exact `orient3d` does, and a tetrahedron below the
//! angle floor goes to the one-by-one guard. A trial starts with the group that refused the
//! last one. The decisions are those of testing each tetrahedron in full (a unit test
//! compares them). `cargo bench --bench smoothing3 -- floor20` gave 140 ms per pass against
//! 203 ms for the one-by-one test; starting each trial with the refusing group and gathering
//! groups on first use then gave 138–140 ms against 153–175 ms (on a slower night).
//! When a trial tetrahedron is below the floor, the guard compares it with the star's
//! current angles: those are computed all at once, [`LANES`] at a time, with the expressions
//! of the one-by-one `min_dihedral_cos` ([`star_worst_cos`]). On the double ellipsoid
//! (`figure9`) 44% of the moves need them; one at a time, they cost a third of the passes.
//!
//! Laplacian smoothing in 3D also makes *slivers*: four nearly coplanar points, a flat
//! tetrahedron with dihedral angles near 0° and 180° but a fine radius–edge ratio, which the
//! orientation test lets through and the volume fraction only slows down (it bounds one move,
//! not thirty). [`DihedralGuard`] adds a third rule: a move may not make the smallest dihedral
//! angle of the point's tetrahedra smaller than a floor, nor smaller than it is now if it is
//! already below the floor; a move that would is halved like the others, then skipped.
//!
//! # Choosing the default guard (measured)
//! `cargo run --release -p delmesh-smoothing --example dihedral_guard 100000 spaced`: the
//! Delaunay tetrahedralisation of a jittered body-centred cubic lattice in the unit cube
//! (well-spaced points, as mesh generation makes; 105 525 points, 622 455 tetrahedra, hull
//! fixed), ω = 0.2, N = 30. Counts are tetrahedra by smallest dihedral angle.
//!
//! | guard        | < 5° | < 10° | 10–20° | mean smallest | worst radius–edge |
//! |--------------|-----:|------:|-------:|--------------:|------------------:|
//! | (input)      | 1199 |  4175 |   7485 |        46.45° |              2.45 |
//! | off          | 6716 | 10384 |   3650 |        53.39° |           3.4·10⁶ |
//! | floor 5°     |  166 | 10133 |   3837 |        53.22° |              6.09 |
//! | floor 10°    |  148 |  1983 |  11850 |        52.83° |              6.87 |
//! | floor 20°    |  139 |  1608 |   8628 |        51.93° |              5.83 |
//! | floor 30°    |  134 |  1614 |   8085 |        51.62° |              5.98 |
//! | no decrease  |  140 |  1639 |   8098 |        51.14° |              5.33 |
//!
//! Unguarded smoothing raises the mean but multiplies the slivers by 5.6 (some with a
//! radius–edge ratio in the millions); any floor removes almost nine in ten of the input's
//! slivers instead, because a point next to a sliver may still move as long as it does not
//! make the sliver worse. A floor lets elements sink down to it, so a low floor fills the bins
//! just above it (5°: ten thousand under 10°); 20° leaves the fewest elements under 20° of the
//! floors up to 20°, for 1.5° of mean angle, and higher floors gain little more. On a jittered
//! Kuhn grid (`kuhn`), whose bad elements come from the jitter alone, smoothing removes all of
//! them with or without a guard (smallest angle 41.9° unguarded and with a 20° floor).
//!
//! The guard costs CPU time on every move (the six angles of each tetrahedron tried, without
//! square roots while they are above the floor) and more where it refuses (five step lengths
//! tried): 1.6× the time of unguarded smoothing on the grid, 1.75× on the lattice mesh (10^5
//! points, one thread). [`Smoother3::new`] sets [`DihedralGuard::Floor`] of
//! [`DEFAULT_DIHEDRAL_FLOOR`] = 20° all the same: slivers cost a solver far more.
//!
//! Points are processed in colour classes (no two points of a class share an edge): within a
//! class every move reads only points that do not move, so the class is computed in parallel
//! (rayon) and applied at once, Gauss–Seidel in colour order, the same result whatever the
//! number of threads. The passes run on a copy numbered along a Z-order curve, so neighbours are
//! close in memory.

use crate::adjacency::{colour_classes, spatial_order3, Rows};
use crate::tet::{
    cross, dot, face_normals, min_dihedral_cos, sub, worst_cos_at_most, FACE_PAIRS, P3,
};
use crate::{SmoothError, SmoothStats, MAX_HALVINGS, REGULAR_DIHEDRAL};
use delmesh_predicates::{orient3d, Sign};
use rayon::prelude::*;

/// A move may shrink a tetrahedron around the point to this fraction of its old volume, no
/// further.
const VOLUME_KEEP: f64 = 0.2;

/// Smoothing stops early once no point moves by more than this fraction of the (root mean
/// square) length of its edges in a pass.
const CONVERGED: f64 = 5e-3;

/// The most ranges of points whose stars are gathered in parallel (each scans all the
/// tetrahedra, and keeps a mark per point to gather the neighbours).
const STAR_RANGES: usize = 8;

/// The floor (degrees) that [`Smoother3::new`] sets for [`DihedralGuard::Floor`].
pub const DEFAULT_DIHEDRAL_FLOOR: f64 = 20.0;

/// The vertex orders that put local vertex `k` of a positive tetrahedron first and keep it
/// positive (even permutations): `orient3d(t[k], t[a], t[b], t[c])` is the tetrahedron's
/// orientation for `[a, b, c] = OPPOSITE[k]`.
const OPPOSITE: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [2, 1, 0]];

/// The sliver guard of [`Smoother3`]: what a move may do to the smallest dihedral angle of the
/// tetrahedra around the moving point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DihedralGuard {
    /// No rule on angles (only orientation and the volume fraction).
    Off,
    /// A move may not make the smallest dihedral angle of the point's tetrahedra smaller than
    /// this many degrees, nor smaller than it is now if it is already below that. A floor at or
    /// above [`REGULAR_DIHEDRAL`] (which no tetrahedron exceeds) acts as
    /// [`DihedralGuard::NoDecrease`].
    Floor(f64),
    /// A move may never make the smallest dihedral angle of the point's tetrahedra smaller.
    NoDecrease,
}

/// Laplacian smoothing of tetrahedral meshes with relaxation factor ω and N passes; boundary
/// points stay fixed and no tetrahedron is ever inverted.
///
/// ```
/// use delmesh_smoothing::{QualityReport3, Smoother3};
/// // An octahedron (fixed) around one free point, off centre: eight tetrahedra, one per octant.
/// let mut points = vec![
///     [0.3, -0.2, 0.1],
///     [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0],
///     [0.0, 1.0, 0.0], [0.0, -1.0, 0.0],
///     [0.0, 0.0, 1.0], [0.0, 0.0, -1.0],
/// ];
/// let tets = [
///     [0, 1, 3, 5], [0, 2, 5, 3], [0, 1, 5, 4], [0, 1, 6, 3],
///     [0, 2, 4, 5], [0, 2, 3, 6], [0, 1, 4, 6], [0, 2, 6, 4],
/// ];
/// let mut fixed = [true; 7];
/// fixed[0] = false;
/// let before = QualityReport3::of_tetrahedra(&points, &tets);
/// let stats = Smoother3::new().smooth(&mut points, &tets, &fixed).unwrap();
/// let after = QualityReport3::of_tetrahedra(&points, &tets);
/// assert!(stats.moved > 0 && after.min_dihedral > before.min_dihedral);
/// assert!(points[0].iter().all(|x| x.abs() < 0.1)); // towards the centre
/// assert!((after.total_volume - 4.0 / 3.0).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smoother3 {
    omega: f64,
    iterations: usize,
    guard: DihedralGuard,
}

impl Default for Smoother3 {
    fn default() -> Self {
        Self::new()
    }
}

/// The checked, renumbered mesh that the passes work on.
struct Star {
    /// For each point, its edge neighbours.
    neighbours: Rows<u32>,
    /// For each point, the face opposite it in each of its tetrahedra, ordered so that
    /// `orient3d(point, face…)` is positive.
    faces: Rows<[u32; 3]>,
    /// Non-zero coordinate magnitudes below this are refused (see `relax`).
    tiny: f64,
}

impl Star {
    /// Each free point's edge neighbours and opposite faces (fixed points get empty rows:
    /// they never move). Built in parallel over ranges of points: each range scans all the
    /// tetrahedra for its own points' faces, so [`STAR_RANGES`] bounds the scans.
    fn build(points: &[[f64; 3]], tets: &[[u32; 4]], fixed: &[bool]) -> Star {
        let n = points.len();
        let ranges = rayon::current_num_threads().min(STAR_RANGES);
        let faces = Rows::build_in_ranges(n, ranges, |keys, lens, items| {
            let first = keys.start;
            let in_range = |v: u32| keys.contains(&(v as usize)) && !fixed[v as usize];
            let mut count = vec![0usize; keys.len() + 1];
            for t in tets {
                for &v in t {
                    if in_range(v) {
                        count[v as usize - first + 1] += 1;
                    }
                }
            }
            lens.extend_from_slice(&count[1..]);
            for i in 0..keys.len() {
                count[i + 1] += count[i];
            }
            items.resize(count[keys.len()], [0; 3]);
            for t in tets {
                for (k, &v) in t.iter().enumerate() {
                    if in_range(v) {
                        let slot = &mut count[v as usize - first];
                        items[*slot] = OPPOSITE[k].map(|i| t[i]);
                        *slot += 1;
                    }
                }
            }
        });
        // Each neighbour appears in several faces of a point's star: keep its first sight
        // (`seen[u] == v + 1` once `u` is in `v`'s row).
        let neighbours = Rows::build_in_ranges(n, ranges, |keys, lens, items| {
            let mut seen = vec![0u32; n];
            for v in keys {
                let before = items.len();
                for &u in faces.row(v).iter().flatten() {
                    if seen[u as usize] != v as u32 + 1 {
                        seen[u as usize] = v as u32 + 1;
                        items.push(u);
                    }
                }
                lens.push(items.len() - before);
            }
        });
        // Coordinates this much smaller than the largest are beyond what a triangulation of the
        // points can represent exactly (they are only reached by creeping towards a zero
        // coordinate): a move that makes one is refused.
        let largest = points.iter().flatten().fold(0.0f64, |m, &c| m.max(c.abs()));
        let tiny = largest * 2f64.powi(-100);
        Star {
            neighbours,
            faces,
            tiny,
        }
    }
}

impl Smoother3 {
    /// ω = 0.2, N = 30 (as in 2D), and [`DihedralGuard::Floor`] of
    /// [`DEFAULT_DIHEDRAL_FLOOR`] degrees.
    pub fn new() -> Self {
        Smoother3 {
            omega: 0.2,
            iterations: 30,
            guard: DihedralGuard::Floor(DEFAULT_DIHEDRAL_FLOOR),
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

    /// Sets the sliver guard.
    ///
    /// # Errors
    /// A [`DihedralGuard::Floor`] outside (0°, 180°) (as [`SmoothError::BadInput`]).
    pub fn dihedral_guard(mut self, guard: DihedralGuard) -> Result<Self, SmoothError> {
        if let DihedralGuard::Floor(f) = guard {
            if !(f > 0.0 && f < 180.0) {
                return Err(SmoothError::BadInput(format!(
                    "dihedral floor must be in (0°, 180°) (got {f:?})"
                )));
            }
        }
        self.guard = guard;
        Ok(self)
    }

    /// The guard in force.
    pub fn guard(&self) -> DihedralGuard {
        self.guard
    }

    /// Smooths `points` in place. `tets` are positively oriented (`orient3d` of their four
    /// points in order is positive, the `delmesh-predicates` and `delaunay-core` convention);
    /// points with `fixed` set (the boundary) never move. Every tetrahedron stays positively
    /// oriented; with the whole boundary fixed the mesh's total volume is unchanged.
    ///
    /// # Errors
    /// Lengths that do not match, an index out of range, a coordinate that is not finite, or
    /// an input tetrahedron that is not positively oriented.
    pub fn smooth(
        &self,
        points: &mut [[f64; 3]],
        tets: &[[u32; 4]],
        fixed: &[bool],
    ) -> Result<SmoothStats, SmoothError> {
        let n = points.len();
        if fixed.len() != n {
            return Err(SmoothError::BadInput(format!(
                "{} points but {} fixed flags",
                n,
                fixed.len()
            )));
        }
        if n > u32::MAX as usize {
            return Err(SmoothError::BadInput(format!(
                "{n} points: at most 2^32 - 1 can be indexed"
            )));
        }
        if let Some(i) = points.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
            return Err(SmoothError::BadInput(format!(
                "point {i} is not finite ({:?})",
                points[i]
            )));
        }
        // Coordinates far from ordinary magnitudes are smoothed scaled by a power of two
        // (exact both ways), so the predicates stay exact and the angle guard's products
        // neither overflow nor underflow; ordinary ones are used as they are.
        let scale = normalising_scale(points);
        let scaled: Option<Vec<[f64; 3]>> =
            (scale != 1.0).then(|| points.iter().map(|p| p.map(|x| x * scale)).collect());
        let view: &[[f64; 3]] = scaled.as_deref().unwrap_or(points);
        let bad = tets.par_iter().position_first(|t| {
            t.iter().any(|&v| v as usize >= n)
                || orient3d(
                    view[t[0] as usize],
                    view[t[1] as usize],
                    view[t[2] as usize],
                    view[t[3] as usize],
                ) != Sign::Positive
        });
        if let Some(k) = bad {
            let t = tets[k];
            if t.iter().any(|&v| v as usize >= n) {
                return Err(SmoothError::BadInput(format!(
                    "tetrahedron {k} {t:?} names a point out of range ({n} points)"
                )));
            }
            return Err(SmoothError::BadInput(format!(
                "tetrahedron {k} {t:?} is not positively oriented"
            )));
        }
        if tets.is_empty() || self.iterations == 0 {
            return Ok(SmoothStats::default());
        }
        // Work on a copy numbered along a space-filling curve, then copy the points back.
        let order = spatial_order3(view);
        let mut rank = vec![0u32; n];
        for (i, &v) in order.iter().enumerate() {
            rank[v as usize] = i as u32;
        }
        let mut local: Vec<[f64; 3]> = order.iter().map(|&v| view[v as usize]).collect();
        let local_fixed: Vec<bool> = order.iter().map(|&v| fixed[v as usize]).collect();
        let local_tets: Vec<[u32; 4]> = tets.iter().map(|t| t.map(|v| rank[v as usize])).collect();
        let stats = self.relax(&mut local, &local_tets, &local_fixed);
        let back = 1.0 / scale;
        for (i, &v) in order.iter().enumerate() {
            points[v as usize] = if scale == 1.0 {
                local[i]
            } else {
                local[i].map(|x| x * back)
            };
        }
        Ok(stats)
    }

    /// The smoothing passes proper, on checked input.
    fn relax(&self, points: &mut [[f64; 3]], tets: &[[u32; 4]], fixed: &[bool]) -> SmoothStats {
        let n = points.len();
        let star = Star::build(points, tets, fixed);
        let guard = Guard::from(self.guard);

        let classes = colour_classes(&star.neighbours, fixed);
        let mut stats = SmoothStats::default();
        // A point is looked at again only once it or a neighbour has moved by more than the
        // convergence threshold since it was last looked at: a refused or converged point whose
        // surroundings did not change would be refused or converged again.
        let mut dirty = vec![true; n];
        let converged2 = CONVERGED * CONVERGED;
        let mut work: Vec<u32> = Vec::new();
        for _ in 0..self.iterations {
            stats.passes += 1;
            let mut largest = 0.0f64;
            let mut any = false;
            for class in &classes {
                work.clear();
                work.extend(class.iter().copied().filter(|&v| dirty[v as usize]));
                if work.is_empty() {
                    continue;
                }
                any = true;
                let moves: Vec<Move> = work
                    .par_iter()
                    .map_init(Scratch::default, |scratch, &v| {
                        let (mv, ratio) = self.propose(points, v as usize, &star, guard, scratch);
                        (v, mv, ratio)
                    })
                    .collect();
                for (v, mv, ratio) in moves {
                    dirty[v as usize] = false;
                    match mv {
                        Some((y, halving)) => {
                            points[v as usize] = y;
                            if halving == 0 {
                                stats.moved += 1;
                            } else {
                                stats.reduced += 1;
                            }
                            largest = largest.max(ratio);
                            if ratio >= converged2 {
                                dirty[v as usize] = true;
                                for &u in star.neighbours.row(v as usize) {
                                    dirty[u as usize] = true;
                                }
                            }
                        }
                        None => stats.skipped += 1,
                    }
                }
            }
            stats.last_displacement = largest.sqrt();
            if !any || stats.last_displacement < CONVERGED {
                break;
            }
        }
        stats
    }

    /// The move of free point `v` towards the mean of its neighbours, halved until every
    /// tetrahedron around it stays positive (exact), keeps [`VOLUME_KEEP`] of its volume and
    /// passes the guard: the new position and the number of halvings, or `None` if refused;
    /// and the squared move over the mean squared length of `v`'s edges. `scratch` is room
    /// for the star's tetrahedra.
    fn propose(
        &self,
        points: &[P3],
        v: usize,
        star: &Star,
        guard: Guard,
        scratch: &mut Scratch,
    ) -> (Option<(P3, u32)>, f64) {
        let x = points[v];
        let ring = star.neighbours.row(v);
        let (mut s, mut ring_length2) = ([0.0; 3], 0.0);
        for &u in ring {
            let d = sub(points[u as usize], x);
            for k in 0..3 {
                s[k] += d[k];
            }
            ring_length2 += dot(d, d);
        }
        let m = ring.len() as f64;
        let mut step = s.map(|c| self.omega * c / m);
        let faces = star.faces.row(v);
        if faces.is_empty() {
            return (None, 0.0);
        }
        let Scratch {
            groups: lanes,
            current,
        } = scratch;
        make_room(faces, lanes);
        let face_points = |f: &[u32; 3]| f.map(|i| points[i as usize]);
        // The cosine of the smallest dihedral angle of each tetrahedron of the star now, and of
        // the star: only needed when a trial tetrahedron falls below the floor, so computed
        // then, all at once.
        current.clear();
        let mut now: Option<f64> = None;
        // The guard for tetrahedron `i` with face normals `g` that the lanes could not pass
        // (below the floor, or of extreme scale): the floor again, scaled, then allowed only
        // if the star is already worse than this.
        let mut guard_accepts = |i: usize, g: &[P3; 4], floor_cos: Option<f64>| {
            if floor_cos.is_some_and(|c| worst_cos_at_most(g, c)) {
                return true;
            }
            // The star is at least as bad as this tetrahedron now, so no worse than that is
            // fine.
            if current.is_empty() {
                star_worst_cos(points, faces, x, current);
            }
            if worst_cos_at_most(g, current[i]) {
                return true;
            }
            let limit = *now.get_or_insert_with(|| current.iter().copied().fold(-1.0, f64::max));
            worst_cos_at_most(g, limit)
        };
        let guard_off = matches!(guard, Guard::Off);
        let mut first = 0;
        for halving in 0..=MAX_HALVINGS {
            let y = [x[0] + step[0], x[1] + step[1], x[2] + step[2]];
            if y == x {
                return (Some((x, halving)), 0.0);
            }
            if y.iter().any(|&c| c != 0.0 && c.abs() < star.tiny) {
                step = step.map(|c| 0.5 * c);
                continue;
            }
            // The group that refused the last trial is tried first (the same tetrahedron
            // usually refuses the halved step too); the answer does not depend on the order.
            let ok = (first..lanes.len()).chain(0..first).all(|k| {
                if !lanes[k].ready {
                    lanes[k].gather(points, faces, x, k);
                }
                let t = lanes[k].trial(y, guard);
                let real = |j: usize| k * LANES + j < faces.len();
                let (mut kept, mut settled) = (true, true);
                for j in 0..LANES {
                    kept &= !real(j) | t.kept[j];
                    settled &= !real(j) | (t.certain[j] & (t.floor[j] | guard_off));
                }
                if !kept {
                    first = k;
                    return false;
                }
                // Rarely: a sign the floating-point volume cannot certify, or an angle below
                // the floor (or of extreme scale), asked one tetrahedron at a time.
                let passed = settled
                    || (0..LANES).filter(|&j| real(j)).all(|j| {
                        let i = k * LANES + j;
                        let [a, b, c] = face_points(&faces[i]);
                        if !t.certain[j] && orient3d(y, a, b, c) != Sign::Positive {
                            return false;
                        }
                        let Guard::On { floor_cos } = guard else {
                            return true;
                        };
                        t.floor[j] || {
                            // The face normals of (y, a, b, c), as `tet::face_normals` orders them.
                            let n = cross(sub(b, a), sub(c, a));
                            let (ya, yb, yc) = (sub(a, y), sub(b, y), sub(c, y));
                            let g = [
                                [-n[0], -n[1], -n[2]],
                                cross(yb, yc),
                                cross(yc, ya),
                                cross(ya, yb),
                            ];
                            guard_accepts(i, &g, floor_cos)
                        }
                    });
                if !passed {
                    first = k;
                }
                passed
            });
            if ok {
                return (Some((y, halving)), dot(step, step) / (ring_length2 / m));
            }
            step = step.map(|c| 0.5 * c);
        }
        (None, 0.0)
    }
}

/// Tetrahedra of a star tested together: the tests run on arrays of this many, which the
/// compiler turns into vector instructions (stars have 15 to 30 tetrahedra).
const LANES: usize = 4;

/// One number per tetrahedron of a group of [`LANES`].
type Lanes = [f64; LANES];

/// `(a − y)·n` in floating point (`n = s × t`, `s = b − a`, `t = c − a`, all rounded) is within
/// `8ε(1 + O(ε))·Σ_i |a_i − y_i|·(|s_j t_k| + |s_k t_j|)` of the exact orientation of
/// `(y, a, b, c)`: each product of the sum carries at most eight roundings. Twice that bound,
/// rounded up, certifies the sign; below it, exact `orient3d` decides.
const VOLUME_ERRBOUND: f64 = 2.0e-15;

/// Below this the products of the bound may have lost precision to underflow: exact decides.
const TINY_PRODUCTS: f64 = 1e-280;

/// [`LANES`] tetrahedra of a point's star, the faces opposite the point (`a`, `b`, `c`) and
/// what does not depend on where the point moves.
#[derive(Clone, Copy, Default)]
struct Group {
    a: [Lanes; 3],
    b: [Lanes; 3],
    c: [Lanes; 3],
    /// `(b − a) × (c − a)`, as `cross` computes it.
    n: [Lanes; 3],
    /// `|s_j t_k| + |s_k t_j|` for each component of `n` (the error bound's weights).
    weight: [Lanes; 3],
    /// [`VOLUME_KEEP`] times the volume (times six) with the point where it is.
    keep: Lanes,
    /// Gathered for the current move.
    ready: bool,
}

/// A thread's scratch space for [`Smoother3::propose`].
#[derive(Default)]
struct Scratch {
    /// The star's tetrahedra in groups of [`LANES`].
    groups: Vec<Group>,
    /// The cosine of the smallest dihedral angle of each tetrahedron of the star (filled when
    /// the guard first needs it).
    current: Vec<f64>,
}

/// `min_dihedral_cos` of each tetrahedron of the star of `x` (the faces opposite it) into
/// `out`: [`LANES`] at a time, with the expressions of `worst_cos` for face normals of ordinary
/// scale, so the same values; the others go to `min_dihedral_cos` itself.
fn star_worst_cos(points: &[P3], faces: &[[u32; 3]], x: P3, out: &mut Vec<f64>) {
    out.clear();
    for group in faces.chunks(LANES) {
        // g[k][d][j]: component d of face normal k of lane j.
        let mut g = [[[0.0; LANES]; 3]; 4];
        for j in 0..LANES {
            let [a, b, c] = group[j.min(group.len() - 1)].map(|i| points[i as usize]);
            let normals = face_normals(&[x, a, b, c]);
            for k in 0..4 {
                for d in 0..3 {
                    g[k][d][j] = normals[k][d];
                }
            }
        }
        let lane_dot = |k: usize, l: usize| -> Lanes {
            let mut r = [0.0; LANES];
            for j in 0..LANES {
                r[j] = g[k][0][j] * g[l][0][j] + g[k][1][j] * g[l][1][j] + g[k][2][j] * g[l][2][j];
            }
            r
        };
        let len2 = [0, 1, 2, 3].map(|k| lane_dot(k, k));
        let mut inv = [[0.0; LANES]; 4];
        let mut ordinary = [true; LANES];
        for k in 0..4 {
            for j in 0..LANES {
                let l = len2[k][j];
                ordinary[j] &= (l > 1e-140) & (l < 1e140);
                inv[k][j] = 1.0 / l.sqrt();
            }
        }
        let mut worst = [-1.0f64; LANES];
        for (k, l) in FACE_PAIRS {
            let d = lane_dot(k, l);
            for j in 0..LANES {
                worst[j] = worst[j].max(-d[j] * (inv[k][j] * inv[l][j]));
            }
        }
        for (j, f) in group.iter().enumerate() {
            out.push(if ordinary[j] {
                worst[j]
            } else {
                min_dihedral_cos(&[
                    x,
                    points[f[0] as usize],
                    points[f[1] as usize],
                    points[f[2] as usize],
                ])
            });
        }
    }
}

/// The lanes' answers for one trial position.
struct Trial {
    /// The tetrahedron keeps [`VOLUME_KEEP`] of its volume.
    kept: [bool; LANES],
    /// Its floating-point volume is certainly positive.
    certain: [bool; LANES],
    /// All its dihedral angles are above the guard's floor (false: ask the one-by-one test).
    floor: [bool; LANES],
}

/// Room for the star's tetrahedra (`faces`) in groups of [`LANES`], none gathered yet: a group
/// is gathered when a trial first needs it ([`Group::gather`]), so a move refused by an early
/// group never loads the points of the others.
fn make_room(faces: &[[u32; 3]], out: &mut Vec<Group>) {
    out.resize(faces.len().div_ceil(LANES), Group::default());
    for g in out.iter_mut() {
        g.ready = false;
    }
}

impl Group {
    /// Group `k` of the star's tetrahedra (`faces` opposite `x`); the lanes past the last
    /// tetrahedron repeat the first one (the caller does not count them).
    fn gather(&mut self, points: &[P3], faces: &[[u32; 3]], x: P3, k: usize) {
        for j in 0..LANES {
            let i = k * LANES + j;
            let f = faces[if i < faces.len() { i } else { 0 }];
            let [a, b, c] = f.map(|i| points[i as usize]);
            let (s, t) = (sub(b, a), sub(c, a));
            let n = cross(s, t);
            let weight = [
                (s[1] * t[2]).abs() + (s[2] * t[1]).abs(),
                (s[2] * t[0]).abs() + (s[0] * t[2]).abs(),
                (s[0] * t[1]).abs() + (s[1] * t[0]).abs(),
            ];
            for d in 0..3 {
                (self.a[d][j], self.b[d][j], self.c[d][j]) = (a[d], b[d], c[d]);
                (self.n[d][j], self.weight[d][j]) = (n[d], weight[d]);
            }
            self.keep[j] = VOLUME_KEEP * dot(sub(a, x), n);
        }
        self.ready = true;
    }

    /// The tests of the group's tetrahedra with the point moved to `y`, with the very
    /// expressions of the one-by-one tests (`dot`, `cross`, `worst_cos_at_most`).
    #[inline(always)]
    fn trial(&self, y: P3, guard: Guard) -> Trial {
        let mut t = Trial {
            kept: [false; LANES],
            certain: [false; LANES],
            floor: [false; LANES],
        };
        let floor_cos = match guard {
            Guard::On { floor_cos: Some(c) } if c >= 0.0 => Some(c),
            _ => None,
        };
        for j in 0..LANES {
            let ya = [
                self.a[0][j] - y[0],
                self.a[1][j] - y[1],
                self.a[2][j] - y[2],
            ];
            let n = [self.n[0][j], self.n[1][j], self.n[2][j]];
            let volume = dot(ya, n);
            let bound = ya[0].abs() * self.weight[0][j]
                + ya[1].abs() * self.weight[1][j]
                + ya[2].abs() * self.weight[2][j];
            // As the one-by-one test: refused when it shrinks below the fraction (a NaN is
            // not refused here, and exact `orient3d` then decides).
            let shrinks = volume < self.keep[j];
            t.kept[j] = !shrinks;
            t.certain[j] = (volume > VOLUME_ERRBOUND * bound) & (bound > TINY_PRODUCTS);
            if let Some(c) = floor_cos {
                let yb = [
                    self.b[0][j] - y[0],
                    self.b[1][j] - y[1],
                    self.b[2][j] - y[2],
                ];
                let yc = [
                    self.c[0][j] - y[0],
                    self.c[1][j] - y[1],
                    self.c[2][j] - y[2],
                ];
                let g = [
                    [-n[0], -n[1], -n[2]],
                    cross(yb, yc),
                    cross(yc, ya),
                    cross(ya, yb),
                ];
                t.floor[j] = floor_in_range(&g, c);
            }
        }
        t
    }
}

/// `worst_cos_at_most(g, c)` for `c ≥ 0` when the normals' squared lengths are of ordinary
/// scale (its branch-free part); false otherwise, for the caller to ask it.
#[inline(always)]
fn floor_in_range(g: &[P3; 4], c: f64) -> bool {
    let len2 = g.map(|x| dot(x, x));
    let ordinary = len2
        .iter()
        .fold(true, |ok, &l| ok & (l > 1e-140) & (l < 1e140));
    let c2 = c * c;
    ordinary
        & FACE_PAIRS.iter().fold(true, |ok, &(k, l)| {
            let d = -dot(g[k], g[l]);
            ok & ((d <= 0.0) | (d * d <= c2 * len2[k] * len2[l]))
        })
}

/// A point, its new position and halvings (`None`: refused), and its relative move squared.
type Move = (u32, Option<(P3, u32)>, f64);

/// The guard as the passes use it.
#[derive(Clone, Copy)]
enum Guard {
    Off,
    /// `floor_cos`: the cosine of the floor, `None` for no floor below which every
    /// angle is fine (never lower the minimum).
    On {
        floor_cos: Option<f64>,
    },
}

impl From<DihedralGuard> for Guard {
    fn from(g: DihedralGuard) -> Guard {
        match g {
            DihedralGuard::Off => Guard::Off,
            // No tetrahedron has all its angles above the regular one's: such a floor only
            // ever lets a move keep the current minimum.
            DihedralGuard::Floor(f) if f < REGULAR_DIHEDRAL => Guard::On {
                floor_cos: Some(f.to_radians().cos()),
            },
            DihedralGuard::Floor(_) | DihedralGuard::NoDecrease => Guard::On { floor_cos: None },
        }
    }
}

/// The power of two that brings the largest coordinate magnitude of `points` into [1, 2), or
/// 1 if it is already between 2^-100 and 2^100 (or all are zero).
fn normalising_scale(points: &[[f64; 3]]) -> f64 {
    let largest = points
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    if largest == 0.0 || (2f64.powi(-100)..=2f64.powi(100)).contains(&largest) {
        return 1.0;
    }
    // Any power of two near 1/largest will do (log2 may round up at the top of a binade).
    let exponent = largest.log2().floor() as i32;
    2f64.powi(-exponent.clamp(-1000, 1000))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opposite_faces_keep_the_orientation() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.1, 0.0],
            [0.2, 1.0, 0.1],
            [0.1, 0.3, 1.0],
        ];
        assert_eq!(orient3d(p[0], p[1], p[2], p[3]), Sign::Positive);
        for (k, f) in OPPOSITE.iter().enumerate() {
            assert_eq!(orient3d(p[k], p[f[0]], p[f[1]], p[f[2]]), Sign::Positive);
            assert!(!f.contains(&k));
        }
    }
    /// `Smoother3::propose` one tetrahedron at a time, each asked in full (the definition the
    /// lanes must match).
    fn propose_one_by_one(
        smoother: &Smoother3,
        points: &[P3],
        v: usize,
        star: &Star,
        guard: Guard,
    ) -> (Option<(P3, u32)>, f64) {
        let x = points[v];
        let ring = star.neighbours.row(v);
        let (mut s, mut ring_length2) = ([0.0; 3], 0.0);
        for &u in ring {
            let d = sub(points[u as usize], x);
            for k in 0..3 {
                s[k] += d[k];
            }
            ring_length2 += dot(d, d);
        }
        let m = ring.len() as f64;
        let mut step = s.map(|c| smoother.omega * c / m);
        let faces = star.faces.row(v);
        let face_points = |f: &[u32; 3]| f.map(|i| points[i as usize]);
        // The cosine of the smallest dihedral angle of each tetrahedron of the star now, and of
        // the star: only needed when a trial tetrahedron falls below the floor, so computed
        // then, once each.
        let mut current: Vec<f64> = Vec::new();
        let mut now: Option<f64> = None;
        let mut first = 0;
        for halving in 0..=MAX_HALVINGS {
            let y = [x[0] + step[0], x[1] + step[1], x[2] + step[2]];
            if y == x {
                return (Some((x, halving)), 0.0);
            }
            if y.iter().any(|&c| c != 0.0 && c.abs() < star.tiny) {
                step = step.map(|c| 0.5 * c);
                continue;
            }
            let mut accepts = |i: usize| {
                let [a, b, c] = face_points(&faces[i]);
                // Six times the volume with apex q is (a − q) · n, n = (b − a) × (c − a).
                let n = cross(sub(b, a), sub(c, a));
                if dot(sub(a, y), n) < VOLUME_KEEP * dot(sub(a, x), n)
                    || orient3d(y, a, b, c) != Sign::Positive
                {
                    return false;
                }
                let Guard::On { floor_cos } = guard else {
                    return true;
                };
                // The face normals of (y, a, b, c), as `tet::face_normals` orders them.
                let (ya, yb, yc) = (sub(a, y), sub(b, y), sub(c, y));
                let g = [
                    [-n[0], -n[1], -n[2]],
                    cross(yb, yc),
                    cross(yc, ya),
                    cross(ya, yb),
                ];
                if floor_cos.is_some_and(|c| worst_cos_at_most(&g, c)) {
                    return true;
                }
                // Below the floor: allowed only if the star is already worse than this. The
                // star is at least as bad as this tetrahedron now, so no worse than that is fine.
                if current.is_empty() {
                    current.resize(faces.len(), f64::NAN);
                }
                let mut cos_now = |j: usize| {
                    if current[j].is_nan() {
                        let [a, b, c] = face_points(&faces[j]);
                        current[j] = min_dihedral_cos(&[x, a, b, c]);
                    }
                    current[j]
                };
                if worst_cos_at_most(&g, cos_now(i)) {
                    return true;
                }
                let limit =
                    *now.get_or_insert_with(|| (0..faces.len()).map(cos_now).fold(-1.0, f64::max));
                worst_cos_at_most(&g, limit)
            };
            // The tetrahedron that refused the last trial is likely to refuse a halved one too:
            // ask it first (the answer does not depend on the order).
            let ok = accepts(first)
                && (0..faces.len()).all(|i| {
                    i == first || {
                        let yes = accepts(i);
                        if !yes {
                            first = i;
                        }
                        yes
                    }
                });
            if ok {
                return (Some((y, halving)), dot(step, step) / (ring_length2 / m));
            }
            step = step.map(|c| 0.5 * c);
        }
        (None, 0.0)
    }

    /// A jittered body-centred cubic lattice, Delaunay, its hull points fixed; `squash`
    /// flattens z so that many tetrahedra are thin and trial volumes come near rounding.
    fn lattice(k: usize, squash: f64, seed: u64) -> (Vec<P3>, Vec<[u32; 4]>, Vec<bool>) {
        use delmesh_delaunay_core::{Triangulation3, VertexId};
        let mut state = seed;
        let mut jitter = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.6
        };
        let mut input = Vec::new();
        for l in 0..=k {
            for j in 0..=k {
                for i in 0..=k {
                    input.push([i as f64, j as f64, l as f64 * squash]);
                    if i < k && j < k && l < k {
                        let c = [i, j, l].map(|c| c as f64 + 0.5);
                        input.push([c[0] + jitter(), c[1] + jitter(), (c[2] + jitter()) * squash]);
                    }
                }
            }
        }
        let tri = Triangulation3::new(&input).unwrap();
        let points: Vec<P3> = (0..tri.num_vertices() as u32)
            .map(|v| tri.vertex(VertexId(v)))
            .collect();
        let tets = tri
            .cells()
            .map(|c| {
                let v = tri.cell(c);
                [v[0].0, v[1].0, v[2].0, v[3].0]
            })
            .collect();
        let mut fixed = vec![false; points.len()];
        for c in tri.all_cells().filter(|&c| tri.is_ghost(c)) {
            for v in tri.cell(c).iter().filter(|v| !v.is_ghost()) {
                fixed[v.index()] = true;
            }
        }
        (points, tets, fixed)
    }

    #[test]
    fn the_lanes_decide_as_the_one_by_one_test() {
        let mut compared = [0usize; 2];
        for (squash, seed) in [(1.0, 1), (1e-9, 2), (1.0, 3)] {
            let (mut points, tets, fixed) = lattice(5, squash, seed);
            // Some free points moved most of the way to the mean of their neighbours first, so
            // that trials also meet tetrahedra already flattened.
            let star = Star::build(&points, &tets, &fixed);
            for v in (0..points.len()).filter(|&v| !fixed[v] && v % 3 == 0) {
                let ring = star.neighbours.row(v);
                let mut mean = [0.0; 3];
                for &u in ring {
                    for d in 0..3 {
                        mean[d] += points[u as usize][d] / ring.len() as f64;
                    }
                }
                let moved = [0, 1, 2].map(|d| points[v][d] + 0.9 * (mean[d] - points[v][d]));
                let faces = star.faces.row(v);
                if faces.iter().all(|f| {
                    let [a, b, c] = f.map(|i| points[i as usize]);
                    orient3d(moved, a, b, c) == Sign::Positive
                }) {
                    points[v] = moved;
                }
            }
            for guard in [
                DihedralGuard::Off,
                DihedralGuard::Floor(20.0),
                DihedralGuard::Floor(40.0),
                DihedralGuard::NoDecrease,
            ] {
                let smoother = Smoother3::new()
                    .omega(0.9)
                    .unwrap()
                    .dihedral_guard(guard)
                    .unwrap();
                let guard = Guard::from(guard);
                let mut scratch = Scratch::default();
                for v in (0..points.len()).filter(|&v| !fixed[v]) {
                    let fast = smoother.propose(&points, v, &star, guard, &mut scratch);
                    let slow = propose_one_by_one(&smoother, &points, v, &star, guard);
                    assert_eq!(fast.0, slow.0, "point {v}, squash {squash}");
                    compared[usize::from(fast.0.is_some())] += 1;
                }
            }
        }
        // Both outcomes occur.
        assert!(compared[0] > 0 && compared[1] > 0, "{compared:?}");
    }

    #[test]
    fn the_star_s_angles_in_lanes_are_those_of_one_tetrahedron_at_a_time() {
        // Ordinary scales, and scales whose face normals need the rescaled expressions.
        for scale in [1.0, 1e-75, 1e75] {
            let (points, tets, fixed) = lattice(4, 1.0, 5);
            let points: Vec<P3> = points.iter().map(|p| p.map(|x| x * scale)).collect();
            let star = Star::build(&points, &tets, &fixed);
            let mut lanes = Vec::new();
            let mut stars = 0;
            for v in (0..points.len()).filter(|&v| !fixed[v]) {
                let faces = star.faces.row(v);
                star_worst_cos(&points, faces, points[v], &mut lanes);
                let one: Vec<f64> = faces
                    .iter()
                    .map(|f| {
                        let [a, b, c] = f.map(|i| points[i as usize]);
                        min_dihedral_cos(&[points[v], a, b, c])
                    })
                    .collect();
                assert_eq!(lanes, one, "point {v}, scale {scale}");
                stars += 1;
            }
            assert!(stars > 0);
        }
    }

    #[test]
    fn fixed_points_get_empty_stars_and_free_points_all_their_tetrahedra() {
        let (points, tets, fixed) = lattice(4, 1.0, 7);
        let star = Star::build(&points, &tets, &fixed);
        for (v, &fixed) in fixed.iter().enumerate() {
            let around = tets.iter().filter(|t| t.contains(&(v as u32))).count();
            let expected = if fixed { 0 } else { around };
            assert_eq!(star.faces.row(v).len(), expected, "point {v}");
            assert_eq!(
                star.neighbours.row(v).is_empty(),
                expected == 0,
                "point {v}"
            );
        }
    }
}
