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

    /// Circumcentre of the cell `p[0..C]` (a floating-point construction).
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
        // The denominator from the exact sign's evaluation where rounding could decide it
        // (nearly collinear points: the plain value can be 0, and the centre NaN).
        let (l, r) = (bx * cy, by * cx);
        let mut det = l - r;
        if det.abs() <= 3.4e-16 * (l.abs() + r.abs()) {
            det = exact_scaled(pred::orient2d_value(a, b, c), s * s, det);
        }
        let d = 2.0 * det;
        [
            a[0] + unscale * ((cy * b2 - by * c2) / d),
            a[1] + unscale * ((bx * c2 - cx * b2) / d),
        ]
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
        let (ce, eb, bc) = (cross(c, e), cross(e, b), cross(b, c));
        let mut det = dot(b, ce);
        // As in 2D: nearly coplanar points take the exact sign's evaluation.
        let permanent = b[0].abs() * ((c[1] * e[2]).abs() + (c[2] * e[1]).abs())
            + b[1].abs() * ((c[2] * e[0]).abs() + (c[0] * e[2]).abs())
            + b[2].abs() * ((c[0] * e[1]).abs() + (c[1] * e[0]).abs());
        if det.abs() <= 8e-16 * permanent {
            det = exact_scaled(pred::orient3d_value(p[0], p[1], p[2], p[3]), s * s * s, det);
        }
        let det = 2.0 * det;
        let (b2, c2, e2) = (dot(b, b), dot(c, c), dot(e, e));
        let mut r = [0.0; 3];
        for k in 0..3 {
            r[k] = a[k] + unscale * ((b2 * ce[k] + c2 * eb[k] + e2 * bc[k]) / det);
        }
        r
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

/// The exact determinant `exact` of the unscaled points in the scaled units (`factor`, the
/// scale to the power of the dimension), or the floating-point `fallback` where that
/// overflows or vanishes (an exact zero stays zero).
fn exact_scaled(exact: f64, factor: f64, fallback: f64) -> f64 {
    let scaled = exact * factor;
    if exact == 0.0 || (scaled.is_finite() && scaled != 0.0) {
        scaled
    } else {
        fallback
    }
}
