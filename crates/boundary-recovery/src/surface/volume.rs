//! Enclosed volumes and the inside/outside test of closed surfaces.
//!
//! **Volume.** By the divergence theorem a closed, consistently oriented surface encloses the
//! signed volume `Σ det(a − o, b − o, c − o) / 6` over its triangles, for any reference point
//! `o`. With `o` at the middle of the surface's bounding box the terms are small, and they are
//! added with Neumaier's compensated summation. The sign (outward or inward orientation) is a
//! decision, so it is certified: the float sum comes with a rigorous error bound (the
//! determinants' permanents times a multiple of the unit round-off, plus the summation's
//! error), and when the sum does not clear it (a surface of almost no volume) the sum is
//! redone exactly: with `o` at the origin each determinant is six triple products of input
//! coordinates, each an exact sum of four doubles (three products, each with its rounding
//! error from a fused multiply–add), which go into one exact floating-point expansion
//! (Shewchuk's Grow-Expansion with zero elimination). Coordinates are scaled by a power of two into `[0.5, 1)` and at least
//! `2^-142` in magnitude, so no product underflows and every step is exact.
//!
//! **Inside or outside.** The winding number of a closed surface about a point `p` not on it is
//! the signed count of the triangles crossed by a ray from `p`. The ray goes along `+x` from
//! `p` moved by the infinitesimal `(0, ε, ε²)`. In the `(y, z)` projection the ray is that
//! perturbed point `q`, and `orient2d(u, w, q)` is `orient2d(u, w, p) + ε(u_z − w_z) +
//! ε²(w_y − u_y)`: its sign is the first non-zero term, so `q` is never on a projected edge of
//! a triangle whose projection has area (and a triangle whose projection has none is parallel
//! to the ray, which misses it). An edge shared by two triangles gets the same answer from both,
//! so every crossing is counted exactly once. The ray crosses the plane in front of `p` iff
//! `orient3d(a, b, c, p)` and the projected orientation (the sign of the normal's `x`
//! component) are strictly opposite; the crossing counts that sign. When `q` is inside the
//! projected triangle and `p` is on its plane, `p` lies on the closed triangle (the projection
//! is a bijection of the plane), so a point off the surface never needs more. No direction can
//! be unlucky: there is no degenerate case left to fail on.

use super::bvh::Boxes;
use super::intersect::{orient2d, orient3d, point_on_triangle, P};
use delmesh_predicates::Sign;

const EPS: f64 = f64::EPSILON / 2.0;

/// The signed volume (scaled coordinates) enclosed by `tris` and its certified sign.
pub(crate) fn signed_volume(pts: &[P], tris: &[[u32; 3]]) -> (f64, Sign) {
    if tris.is_empty() {
        return (0.0, Sign::Zero);
    }
    if let (v, Some(sign)) = float_volume(pts, tris) {
        return (v, sign);
    }
    let exact = exact_sum(pts, tris);
    let value: f64 = exact.iter().sum();
    let sign = exact.last().map_or(Sign::Zero, |&x| Sign::of(x));
    (value / 6.0, sign)
}

/// The compensated float volume, and its sign if the error bound certifies it.
fn float_volume(pts: &[P], tris: &[[u32; 3]]) -> (f64, Option<Sign>) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for t in tris {
        for &v in t {
            let p = pts[v as usize];
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    let o: P = std::array::from_fn(|k| lo[k] + (hi[k] - lo[k]) / 2.0);
    let (mut sum, mut comp) = (0.0f64, 0.0f64);
    let (mut permanents, mut magnitudes) = (0.0f64, 0.0f64);
    for t in tris {
        let [a, b, c] = t.map(|v| {
            let p = pts[v as usize];
            [p[0] - o[0], p[1] - o[1], p[2] - o[2]]
        });
        let (m0, m1, m2) = (
            b[1] * c[2] - b[2] * c[1],
            b[2] * c[0] - b[0] * c[2],
            b[0] * c[1] - b[1] * c[0],
        );
        let det = a[0] * m0 + a[1] * m1 + a[2] * m2;
        let ab = a.map(f64::abs);
        let (bb, cb) = (b.map(f64::abs), c.map(f64::abs));
        permanents += ab[0] * (bb[1] * cb[2] + bb[2] * cb[1])
            + ab[1] * (bb[2] * cb[0] + bb[0] * cb[2])
            + ab[2] * (bb[0] * cb[1] + bb[1] * cb[0]);
        magnitudes += det.abs();
        // Neumaier's compensated summation.
        let s = sum + det;
        comp += if sum.abs() >= det.abs() {
            (sum - s) + det
        } else {
            (det - s) + sum
        };
        sum = s;
    }
    let total = sum + comp;
    let n = tris.len() as f64;
    // Each determinant is off by at most ~7ε of its permanent (Shewchuk's stage-A bound,
    // differences included); 32ε leaves room for the rounding of the bound itself. The
    // compensated sum is off by at most 2ε|S| + O(nε²)Σ|x|.
    let bound =
        32.0 * EPS * permanents + 4.0 * EPS * total.abs() + 8.0 * n * EPS * EPS * magnitudes;
    (total / 6.0, (total.abs() > bound).then(|| Sign::of(total)))
}

/// `a · b` as an exact pair `(product, error)`.
#[inline]
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `a + b` as an exact pair `(sum, error)` (Knuth's two-sum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bv = s - a;
    let av = s - bv;
    (s, (a - av) + (b - bv))
}

/// Adds `b` to the non-overlapping expansion `e` (increasing magnitude), exactly, dropping
/// zero components (Shewchuk 1997, Grow-Expansion with zero elimination).
fn grow(e: &mut Vec<f64>, b: f64) {
    let mut q = b;
    let mut out = 0;
    for i in 0..e.len() {
        let (s, h) = two_sum(q, e[i]);
        if h != 0.0 {
            e[out] = h;
            out += 1;
        }
        q = s;
    }
    e.truncate(out);
    if q != 0.0 {
        e.push(q);
    }
}

/// `Σ det(a, b, c)` over the triangles, exactly, as an expansion (largest component last).
fn exact_sum(pts: &[P], tris: &[[u32; 3]]) -> Vec<f64> {
    let mut e = Vec::new();
    let triple = |x: f64, y: f64, z: f64, e: &mut Vec<f64>| {
        let (p, err) = two_product(x, y);
        let (p1, e1) = two_product(p, z);
        let (p2, e2) = two_product(err, z);
        for term in [e2, p2, e1, p1] {
            if term != 0.0 {
                grow(e, term);
            }
        }
    };
    for t in tris {
        let [a, b, c] = t.map(|v| pts[v as usize]);
        // det = a·(b × c), six signed triple products.
        triple(a[0], b[1], c[2], &mut e);
        triple(-a[0], b[2], c[1], &mut e);
        triple(a[1], b[2], c[0], &mut e);
        triple(-a[1], b[0], c[2], &mut e);
        triple(a[2], b[0], c[1], &mut e);
        triple(-a[2], b[1], c[0], &mut e);
    }
    e
}

/// What a ray from `p` along `+x` (perturbed, see the module docs) does at one triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Crossing {
    /// It misses the triangle, or meets its plane behind `p`.
    Miss,
    /// It crosses the triangle in front of `p`; the sign of the normal's `x` component.
    Front(i32),
    /// `p` lies on the closed triangle.
    On,
}

/// The sign of `orient2d(u, w, q)` in the `(y, z)` projection, `q = p + (0, ε, ε²)`.
#[inline]
fn side_perturbed(u: P, w: P, p: P) -> Sign {
    match orient2d([u[1], u[2]], [w[1], w[2]], [p[1], p[2]]) {
        Sign::Zero => match Sign::of(u[2] - w[2]) {
            Sign::Zero => Sign::of(w[1] - u[1]),
            s => s,
        },
        s => s,
    }
}

/// The ray from `p` against the triangle `t` (see [`Crossing`]). Triangles parallel to the
/// ray report [`Crossing::Miss`] even when `p` lies on them; [`point_on_triangle`] tells those.
pub(crate) fn ray_crossing(t: [P; 3], p: P) -> Crossing {
    let [a, b, c] = t;
    let s = orient2d([a[1], a[2]], [b[1], b[2]], [c[1], c[2]]);
    if s == Sign::Zero {
        return Crossing::Miss;
    }
    if side_perturbed(a, b, p) != s || side_perturbed(b, c, p) != s || side_perturbed(c, a, p) != s
    {
        return Crossing::Miss;
    }
    match orient3d(a, b, c, p) {
        Sign::Zero => Crossing::On,
        o if o == s.reversed() => Crossing::Front(s.as_i32()),
        _ => Crossing::Miss,
    }
}

/// Adds each triangle crossed by the ray from `p` to the winding count of its component
/// (skipping component `skip`). The candidates are the triangles whose box meets the ray's box
/// `[p, p + ∞·x]` (the perturbation is infinitesimal, so a triangle the perturbed ray crosses
/// ahead has its box there). With `check_on`, returns the triangle `p` lies on, if any (the
/// counts are then not meaningful); without it, `p` must not lie on the surface.
pub(crate) fn wind(
    surface: Surface<'_>,
    boxes: &Boxes,
    skip: u32,
    p: P,
    check_on: bool,
    w: &mut Winding,
) -> Option<u32> {
    let ray = (p, [f64::INFINITY, p[1], p[2]]);
    let mut on = None;
    boxes.overlapping(&ray, &mut w.stack, |t| {
        let c = surface.component[t as usize];
        if c == skip || on.is_some() {
            return;
        }
        let tri = surface.tris[t as usize].map(|v| surface.pts[v as usize]);
        match ray_crossing(tri, p) {
            Crossing::Miss => {
                if check_on && point_on_triangle(tri, p) {
                    on = Some(t);
                }
            }
            Crossing::On => on = Some(t),
            Crossing::Front(s) => {
                if !w.seen[c as usize] {
                    w.seen[c as usize] = true;
                    w.touched.push(c);
                }
                w.counts[c as usize] += s;
            }
        }
    });
    on
}

/// The arrays a ray query reads: scaled points, triangles, the component of each triangle.
#[derive(Clone, Copy)]
pub(crate) struct Surface<'a> {
    pub(crate) pts: &'a [P],
    pub(crate) tris: &'a [[u32; 3]],
    pub(crate) component: &'a [u32],
}

/// Winding counts per component, with the list of components touched (so that resetting costs
/// only what was touched).
#[derive(Clone, Debug)]
pub(crate) struct Winding {
    counts: Vec<i32>,
    seen: Vec<bool>,
    touched: Vec<u32>,
    stack: Vec<u32>,
}

impl Winding {
    pub(crate) fn new(n_components: usize) -> Winding {
        Winding {
            counts: vec![0; n_components],
            seen: vec![false; n_components],
            touched: Vec::new(),
            stack: Vec::new(),
        }
    }

    /// The components with a non-zero count (sorted), and resets.
    pub(crate) fn take_nonzero(&mut self) -> Vec<u32> {
        let mut out: Vec<u32> = self
            .touched
            .iter()
            .copied()
            .filter(|&c| self.counts[c as usize] != 0)
            .collect();
        out.sort_unstable();
        for &c in &self.touched {
            self.counts[c as usize] = 0;
            self.seen[c as usize] = false;
        }
        self.touched.clear();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};

    const TETRA: [[u32; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];

    #[test]
    fn near_flat_tetrahedra_fall_back_to_the_exact_sum() {
        let mut rng = StdRng::seed_from_u64(7);
        let mut fallbacks = 0;
        for _ in 0..2000 {
            let [a, b, c]: [P; 3] =
                std::array::from_fn(|_| std::array::from_fn(|_| rng.gen::<f64>()));
            // A point on the segment between two corners' mid-points, rounded: within a few
            // units in the last place of the plane.
            let t: f64 = rng.gen();
            let d: P = std::array::from_fn(|k| {
                let (m1, m2) = ((a[k] + b[k]) / 2.0, (a[k] + c[k]) / 2.0);
                m1 + t * (m2 - m1)
            });
            let pts = [a, b, c, d];
            let want = orient3d(a, b, c, d);
            let (_, sign) = signed_volume(&pts, &TETRA);
            assert_eq!(sign, want);
            let exact = exact_sum(&pts, &TETRA);
            assert_eq!(exact.last().map_or(Sign::Zero, |&x| Sign::of(x)), want);
            if float_volume(&pts, &TETRA).1.is_none() {
                fallbacks += 1;
            }
        }
        assert!(fallbacks > 100, "{fallbacks}");
    }

    #[test]
    fn expansion_sum_is_exact() {
        let mut e = Vec::new();
        for x in [1e100, 1.0, -1e100, 1e-100, 3.0, -1.0] {
            grow(&mut e, x);
        }
        assert_eq!(e, vec![1e-100, 3.0]);
    }
}
