//! What differs between 2D and 3D: the point type, the cell size and the predicates.
//!
//! Bowyer–Watson insertion, the walk, the cavity search, the re-linking of neighbours and the
//! validation are written once over [`Dim`]. A cell is `D::C = D::N + 1` vertices, positively
//! oriented; its local facet `i` is the one opposite its local vertex `i`. Replacing one vertex
//! of a cell by another point keeps the orientation convention, which both the walk ("is the point
//! beyond facet `i`?") and the cavity re-triangulation ("connect the new point to the facet") use.

use crate::ids::VertexId;
use delmesh_predicates::{self as pred, Sign};
use std::fmt::Debug;

/// A space dimension: [`D2`] (triangles) or [`D3`] (tetrahedra).
pub trait Dim: Copy + Clone + Debug + Send + Sync + 'static {
    /// Number of coordinates.
    const N: usize;
    /// Number of vertices of a cell (`N + 1`).
    const C: usize;
    /// A point, `[f64; N]`.
    type Point: Copy + Debug + Default + PartialEq + Send + Sync + AsRef<[f64]> + AsMut<[f64]>;

    /// Orientation of the cell `p[0..C]`: positive for a counter-clockwise triangle or a
    /// positive-volume tetrahedron.
    fn orient(p: &[Self::Point]) -> Sign;

    /// Whether `q` is inside the circumsphere of the finite cell `cell` (vertex ids into
    /// `points`), exact and symbolically perturbed (never zero): the hot path of cavity search.
    fn insphere_cell(points: &[Self::Point], cell: &[VertexId; 4], q: Self::Point) -> Sign;

    /// Whether `q` lies exactly on the circumsphere (circumcircle) of the finite cell `cell`:
    /// the exact in-sphere determinant, unperturbed, is zero. A neighbour across a facet whose
    /// far vertex is so placed has the same circumcentre (the Voronoi dual merges the two).
    fn cospherical(points: &[Self::Point], cell: &[VertexId; 4], q: Self::Point) -> bool;

    /// Orientation of the finite cell `cell` with its vertex `f` replaced by `q`: negative
    /// when `q` lies strictly beyond the cell's facet `f` (the hot path of the walk).
    fn orient_replacing(
        points: &[Self::Point],
        cell: &[VertexId; 4],
        f: usize,
        q: Self::Point,
    ) -> Sign;

    /// Whether the points `p` (at most `N` of them) are affinely independent.
    fn independent(p: &[Self::Point]) -> bool;

    /// The Hilbert-curve key of a point quantised to 16 bits per axis.
    fn hilbert_key(q: &[u32]) -> u64;

    /// Circumcentre of the cell `p[0..C]`: a construction, within about 1.4e-14 of its largest
    /// coordinate (floating point where its error bound allows, else computed exactly and
    /// rounded), for any shape and scale of the cell. Not finite for a flat cell.
    fn circumcenter(p: &[Self::Point]) -> Self::Point;
}

/// [`pred::incircle_lex`] for four cocircular points (rare: kept out of the hot path).
#[cold]
#[inline(never)]
fn incircle_on_circle(p: [[f64; 2]; 4]) -> Sign {
    pred::incircle_lex(p)
}

/// Two dimensions: triangles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct D2;

/// Three dimensions: tetrahedra.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct D3;

impl Dim for D2 {
    const N: usize = 2;
    const C: usize = 3;
    type Point = [f64; 2];

    #[inline]
    fn orient(p: &[[f64; 2]]) -> Sign {
        pred::orient2d(p[0], p[1], p[2])
    }

    #[inline(always)]
    fn insphere_cell(points: &[[f64; 2]], cell: &[VertexId; 4], q: [f64; 2]) -> Sign {
        let (a, b, c) = (
            points[cell[0].index()],
            points[cell[1].index()],
            points[cell[2].index()],
        );
        // The plain test first, with the points passed as they are: packing them into one
        // array made the compiler store them and reload them wider, which stalls (store
        // forwarding fails). Only a zero needs the perturbation.
        match pred::incircle(a, b, c, q) {
            Sign::Zero => incircle_on_circle([a, b, c, q]),
            s => s,
        }
    }

    fn cospherical(points: &[[f64; 2]], cell: &[VertexId; 4], q: [f64; 2]) -> bool {
        let p = |k: usize| points[cell[k].index()];
        pred::incircle(p(0), p(1), p(2), q) == Sign::Zero
    }

    #[inline(always)]
    fn orient_replacing(points: &[[f64; 2]], cell: &[VertexId; 4], f: usize, q: [f64; 2]) -> Sign {
        let (a, b, c) = (
            points[cell[0].index()],
            points[cell[1].index()],
            points[cell[2].index()],
        );
        match f {
            0 => pred::orient2d(q, b, c),
            1 => pred::orient2d(a, q, c),
            _ => pred::orient2d(a, b, q),
        }
    }

    fn independent(p: &[[f64; 2]]) -> bool {
        match p.len() {
            0 => true,
            1 => true,
            2 => p[0] != p[1],
            _ => pred::orient2d(p[0], p[1], p[2]) != Sign::Zero,
        }
    }

    fn hilbert_key(q: &[u32]) -> u64 {
        crate::sort::hilbert_key::<2>([q[0], q[1]])
    }

    fn circumcenter(p: &[[f64; 2]]) -> [f64; 2] {
        let (a, b, c) = (p[0], p[1], p[2]);
        // The edge vectors scaled by a power of two to magnitude about 1 (see `unit_scale`).
        let (s, unscale) = unit_scale(&[b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]]);
        let (bx, by) = (s * (b[0] - a[0]), s * (b[1] - a[1]));
        let (cx, cy) = (s * (c[0] - a[0]), s * (c[1] - a[1]));
        let b2 = bx * bx + by * by;
        let c2 = cx * cx + cy * cy;
        let (l, r) = (bx * cy, by * cx);
        let det = l - r;
        let n = [cy * b2 - by * c2, bx * c2 - cx * b2];
        let center = [
            a[0] + unscale * (n[0] / (2.0 * det)),
            a[1] + unscale * (n[1] / (2.0 * det)),
        ];
        // Error bounds, counting the rounding of the edge vectors: γ7 and γ4 times the
        // permanents (one more unit for the second-order terms).
        let bound = Bounds {
            numerators: [
                8.0 * UNIT * (cy.abs() * b2 + by.abs() * c2),
                8.0 * UNIT * (bx.abs() * c2 + cx.abs() * b2),
            ],
            determinant: 5.0 * UNIT * (l.abs() + r.abs()),
        };
        if bound.accepts(&center, &n, det, unscale) {
            center
        } else {
            pred::circumcenter2(a, b, c).unwrap_or(center)
        }
    }
}

impl Dim for D3 {
    const N: usize = 3;
    const C: usize = 4;
    type Point = [f64; 3];

    #[inline]
    fn orient(p: &[[f64; 3]]) -> Sign {
        pred::orient3d(p[0], p[1], p[2], p[3])
    }

    #[inline(always)]
    fn insphere_cell(points: &[[f64; 3]], cell: &[VertexId; 4], q: [f64; 3]) -> Sign {
        let (a, b) = (points[cell[0].index()], points[cell[1].index()]);
        let (c, d) = (points[cell[2].index()], points[cell[3].index()]);
        pred::insphere_lex([a, b, c, d, q])
    }

    fn cospherical(points: &[[f64; 3]], cell: &[VertexId; 4], q: [f64; 3]) -> bool {
        let p = |k: usize| points[cell[k].index()];
        pred::insphere(p(0), p(1), p(2), p(3), q) == Sign::Zero
    }

    #[inline(always)]
    fn orient_replacing(points: &[[f64; 3]], cell: &[VertexId; 4], f: usize, q: [f64; 3]) -> Sign {
        let (a, b) = (points[cell[0].index()], points[cell[1].index()]);
        let (c, d) = (points[cell[2].index()], points[cell[3].index()]);
        match f {
            0 => pred::orient3d(q, b, c, d),
            1 => pred::orient3d(a, q, c, d),
            2 => pred::orient3d(a, b, q, d),
            _ => pred::orient3d(a, b, c, q),
        }
    }

    fn independent(p: &[[f64; 3]]) -> bool {
        match p.len() {
            0 | 1 => true,
            2 => p[0] != p[1],
            // Three points are collinear iff all three coordinate projections are.
            3 => {
                let proj = |i: usize, j: usize| {
                    pred::orient2d([p[0][i], p[0][j]], [p[1][i], p[1][j]], [p[2][i], p[2][j]])
                };
                proj(0, 1) != Sign::Zero || proj(1, 2) != Sign::Zero || proj(0, 2) != Sign::Zero
            }
            _ => pred::orient3d(p[0], p[1], p[2], p[3]) != Sign::Zero,
        }
    }

    fn hilbert_key(q: &[u32]) -> u64 {
        crate::sort::hilbert_key::<3>([q[0], q[1], q[2]])
    }

    fn circumcenter(p: &[[f64; 3]]) -> [f64; 3] {
        let a = p[0];
        let d = |q: [f64; 3]| [q[0] - a[0], q[1] - a[1], q[2] - a[2]];
        let (b, c, e) = (d(p[1]), d(p[2]), d(p[3]));
        // Scaled by a power of two to magnitude about 1 (see `unit_scale`).
        let (s, unscale) = unit_scale(&[b[0], b[1], b[2], c[0], c[1], c[2], e[0], e[1], e[2]]);
        let (b, c, e) = (b.map(|x| s * x), c.map(|x| s * x), e.map(|x| s * x));
        let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        let cross = |u: [f64; 3], v: [f64; 3]| {
            [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ]
        };
        // The cross products' permanents (each term's magnitude), for the error bounds.
        let crossed = |u: [f64; 3], v: [f64; 3]| {
            [
                (u[1] * v[2]).abs() + (u[2] * v[1]).abs(),
                (u[2] * v[0]).abs() + (u[0] * v[2]).abs(),
                (u[0] * v[1]).abs() + (u[1] * v[0]).abs(),
            ]
        };
        let (ce, eb, bc) = (cross(c, e), cross(e, b), cross(b, c));
        let (ce_, eb_, bc_) = (crossed(c, e), crossed(e, b), crossed(b, c));
        let det = dot(b, ce);
        let (b2, c2, e2) = (dot(b, b), dot(c, c), dot(e, e));
        let n: [f64; 3] = std::array::from_fn(|k| b2 * ce[k] + c2 * eb[k] + e2 * bc[k]);
        let center: [f64; 3] = std::array::from_fn(|k| a[k] + unscale * (n[k] / (2.0 * det)));
        // γ12 for the numerators and γ8 for the determinant, as in 2D.
        let bound = Bounds {
            numerators: std::array::from_fn(|k| {
                13.0 * UNIT * (b2 * ce_[k] + c2 * eb_[k] + e2 * bc_[k])
            }),
            determinant: 9.0 * UNIT * dot(b.map(f64::abs), ce_),
        };
        if bound.accepts(&center, &n, det, unscale) {
            center
        } else {
            pred::circumcenter3(p[0], p[1], p[2], p[3]).unwrap_or(center)
        }
    }
}

/// Unit roundoff of `f64`.
const UNIT: f64 = f64::EPSILON / 2.0;

/// The largest error accepted from a floating-point circumcentre, relative to its largest
/// coordinate (about 1.4e-14); beyond it the centre is constructed exactly
/// ([`pred::circumcenter2`], [`pred::circumcenter3`]).
///
/// The floating-point formula loses digits where its terms cancel: nearly flat cells,
/// centres close to the origin next to their size, and cells with points at very different
/// scales, where the edge vectors from a far point to a tight cluster round to the same
/// vector (the "centre" was then that far point).
const CENTER_TOLERANCE: f64 = 1.0 / (1u64 << 46) as f64;

/// Bounds on the rounding errors of the circumcentre formula's numerators and determinant
/// (in the scaled units of `unit_scale`), from which [`Bounds::accepts`] bounds the centre's.
struct Bounds<const N: usize> {
    numerators: [f64; N],
    determinant: f64,
}

impl<const N: usize> Bounds<N> {
    /// Whether `center`, computed as `a + unscale · n / (2 det)`, is certainly within
    /// [`CENTER_TOLERANCE`] of the exact centre. With `|Δn| ≤ En` and `|Δdet| ≤ Ed`, the
    /// quotient is off by at most `(|n|·Ed/|det| + En) / (2(|det| − Ed))`, plus a rounding of
    /// the quotient and of the sum.
    fn accepts(&self, center: &[f64; N], n: &[f64; N], det: f64, unscale: f64) -> bool {
        let margin = det.abs() - self.determinant;
        let size = center.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        // (Also false for NaN and infinite values.)
        if !(margin > 0.0 && size < f64::INFINITY) {
            return false;
        }
        (0..N).all(|k| {
            let q = n[k].abs() / (2.0 * det.abs());
            let dq =
                (n[k].abs() * self.determinant / det.abs() + self.numerators[k]) / (2.0 * margin);
            let error = unscale * (dq + UNIT * q) + UNIT * center[k].abs();
            error <= CENTER_TOLERANCE * size
        })
    }
}

/// A power of two `s` that brings the largest of `v` to between 1 and 2, and `1 / s`: the
/// circumcentre formulas square and cube the edge vectors, which overflow (or vanish) for
/// edges beyond about 1e±100 unscaled. Multiplying by a power of two changes no digit, so
/// where nothing overflows the centre is the same to the bit. (Within ±1000 octaves, so that
/// both factors are finite.)
fn unit_scale(v: &[f64]) -> (f64, f64) {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if !(m > 0.0 && m.is_finite()) {
        return (1.0, 1.0);
    }
    let e = (m.log2().floor() as i32).clamp(-1000, 1000);
    (2f64.powi(-e), 2f64.powi(e))
}
