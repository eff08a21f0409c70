//! Floating-point measures of one tetrahedron: signed volume, dihedral angles, circumradius.
//!
//! Shared by the 3D smoother's dihedral guard and [`crate::QualityReport3`]. These are
//! constructions (quality figures), never topological decisions: whether a tetrahedron is
//! positively oriented is always asked of the exact `orient3d`.
//!
//! The dihedral angles come from the four face normals `g_k`, the cross products that are
//! (up to the common factor `1/6V`) the gradients of the barycentric coordinates: they all
//! point inwards (or all outwards for a negative tetrahedron), so the interior angle at the
//! edge shared by faces `k` and `l` is the angle between `g_k` and `−g_l`, whatever the
//! orientation.

pub(crate) type P3 = [f64; 3];

#[inline(always)]
pub(crate) fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
pub(crate) fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
pub(crate) fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Each vector divided by its largest component in magnitude (zero vectors kept): directions
/// unchanged, lengths in [1, √3], so that products of four lengths neither overflow nor
/// underflow whatever the mesh's scale.
#[inline]
fn scaled(g: &[P3; 4]) -> [P3; 4] {
    g.map(|x| {
        let m = x[0].abs().max(x[1].abs()).max(x[2].abs());
        if m > 0.0 {
            let r = 1.0 / m;
            [x[0] * r, x[1] * r, x[2] * r]
        } else {
            x
        }
    })
}

/// The pairs of faces (by opposite local vertex) that meet at each of the six edges.
pub(crate) const FACE_PAIRS: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];

/// The face normals of `p`: `g[k]` is normal to the face opposite `p[k]`, with length twice
/// that face's area, all pointing to the same side (inwards for a positive tetrahedron).
/// Each is a cross product of two edges of its own face, so a small face stays accurate.
#[inline]
pub(crate) fn face_normals(p: &[P3; 4]) -> [P3; 4] {
    let (e1, e2, e3) = (sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0]));
    [
        cross(sub(p[3], p[1]), sub(p[2], p[1])),
        cross(e2, e3),
        cross(e3, e1),
        cross(e1, e2),
    ]
}

/// Six times the signed volume, `(p1 − p0) · ((p2 − p0) × (p3 − p0))` (positive for a
/// positively oriented tetrahedron, as `orient3d`).
#[inline]
pub(crate) fn volume6(p: &[P3; 4]) -> f64 {
    dot(sub(p[1], p[0]), cross(sub(p[2], p[0]), sub(p[3], p[0])))
}

/// The cosine of the smallest dihedral angle of `p` (the largest of the six cosines): 1 for a
/// tetrahedron with a degenerate face (angle 0).
#[inline]
pub(crate) fn min_dihedral_cos(p: &[P3; 4]) -> f64 {
    worst_cos(&face_normals(p))
}

/// The cosine of the smallest dihedral angle of the tetrahedron with face normals `g` (as
/// [`face_normals`] gives them): 1 if a face is degenerate.
#[inline]
pub(crate) fn worst_cos(g: &[P3; 4]) -> f64 {
    let len2 = g.map(|x| dot(x, x));
    // Squared lengths of ordinary scales: no rescaling needed.
    if len2.iter().all(|&l| l > 1e-140 && l < 1e140) {
        let inv = len2.map(|l| 1.0 / l.sqrt());
        let mut worst = -1.0f64;
        for (k, l) in FACE_PAIRS {
            worst = worst.max(-dot(g[k], g[l]) * (inv[k] * inv[l]));
        }
        return worst;
    }
    let g = scaled(g);
    let len = g.map(|x| dot(x, x).sqrt());
    if len.iter().any(|&l| l.is_nan() || l <= 0.0) {
        return 1.0;
    }
    let mut worst = -1.0f64;
    for (k, l) in FACE_PAIRS {
        worst = worst.max(-dot(g[k], g[l]) / (len[k] * len[l]));
    }
    worst
}

/// Whether every dihedral angle of the tetrahedron with face normals `g` has a cosine of at
/// most `c` (any `c`): `worst_cos(g) <= c`, without square roots. False if a face is degenerate
/// (for `c < 1`).
#[inline]
pub(crate) fn worst_cos_at_most(g: &[P3; 4], c: f64) -> bool {
    if c >= 1.0 {
        return true;
    }
    let len2 = g.map(|x| dot(x, x));
    if len2.iter().all(|&l| l > 1e-140 && l < 1e140) {
        cos_at_most(g, &len2, c)
    } else {
        let g = scaled(g);
        let len2 = g.map(|x| dot(x, x));
        len2.iter().all(|&l| l > 0.0) && cos_at_most(&g, &len2, c)
    }
}

/// `−g_k·g_l ≤ c·|g_k|·|g_l|` for the six pairs, compared squared with the signs kept.
#[inline(always)]
fn cos_at_most(g: &[P3; 4], len2: &[f64; 4], c: f64) -> bool {
    let c2 = c * c;
    FACE_PAIRS.iter().all(|&(k, l)| {
        let d = -dot(g[k], g[l]);
        let r = c2 * len2[k] * len2[l];
        if c >= 0.0 {
            d <= 0.0 || d * d <= r
        } else {
            d < 0.0 && d * d >= r
        }
    })
}

/// The angle (radians) between `g_k` and `−g_l`: the interior dihedral angle at their edge.
#[inline]
fn angle_between(gk: P3, gl: P3) -> f64 {
    let c = cross(gk, gl);
    dot(c, c).sqrt().atan2(-dot(gk, gl))
}

/// The smallest and largest dihedral angles of `p` in degrees. The two extreme edges are
/// picked by their cosines, then measured with `atan2` (accurate near 0° and 180°, where a
/// sliver's angles are). A tetrahedron with a degenerate face gives 0° and 180°.
pub(crate) fn dihedral_extremes(p: &[P3; 4]) -> (f64, f64) {
    let g = scaled(&face_normals(p));
    let len = g.map(|x| dot(x, x).sqrt());
    if len.iter().any(|&l| l.is_nan() || l <= 0.0) {
        if len.iter().any(|l| l.is_nan()) {
            return (f64::NAN, f64::NAN);
        }
        return (0.0, 180.0);
    }
    let (mut lo, mut hi) = ((0, 1), (0, 1));
    let (mut cmax, mut cmin) = (f64::NEG_INFINITY, f64::INFINITY);
    for (k, l) in FACE_PAIRS {
        let c = -dot(g[k], g[l]) / (len[k] * len[l]);
        if c > cmax {
            cmax = c;
            lo = (k, l);
        }
        if c < cmin {
            cmin = c;
            hi = (k, l);
        }
    }
    (
        angle_between(g[lo.0], g[lo.1]).to_degrees(),
        angle_between(g[hi.0], g[hi.1]).to_degrees(),
    )
}

/// Circumradius over shortest edge (infinite for a flat tetrahedron).
pub(crate) fn radius_edge(p: &[P3; 4]) -> f64 {
    let (e1, e2, e3) = (sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0]));
    let (g1, g2, g3) = (cross(e2, e3), cross(e3, e1), cross(e1, e2));
    let det = 2.0 * dot(e1, g1);
    let (l1, l2, l3) = (dot(e1, e1), dot(e2, e2), dot(e3, e3));
    let mut r = [0.0; 3];
    for k in 0..3 {
        r[k] = (l1 * g1[k] + l2 * g2[k] + l3 * g3[k]) / det;
    }
    let shortest = [
        l1,
        l2,
        l3,
        dot(sub(p[2], p[1]), sub(p[2], p[1])),
        dot(sub(p[3], p[1]), sub(p[3], p[1])),
        dot(sub(p[3], p[2]), sub(p[3], p[2])),
    ]
    .into_iter()
    .fold(f64::INFINITY, f64::min);
    if det == 0.0 {
        return f64::INFINITY;
    }
    (dot(r, r) / shortest).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_point_the_same_way_and_close_the_surface() {
        let p = [
            [0.1, 0.2, 0.0],
            [1.3, 0.1, 0.2],
            [0.2, 1.1, -0.1],
            [0.3, 0.4, 0.9],
        ];
        let g = face_normals(&p);
        let sum = [0, 1, 2].map(|k| g.iter().map(|x| x[k]).sum::<f64>());
        assert!(sum.iter().all(|s| s.abs() < 1e-12), "{sum:?}");
        // Inwards for a positive tetrahedron: towards the opposite vertex.
        assert!(volume6(&p) > 0.0);
        for k in 0..4 {
            let on_face = p[(k + 1) % 4];
            assert!(dot(g[k], sub(p[k], on_face)) > 0.0, "face {k}");
        }
    }

    #[test]
    fn cosine_bound_agrees_with_the_worst_cosine() {
        // A deterministic spread of shapes: regular-ish, flat, needle-like, tiny and huge.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for i in 0..20_000 {
            let scale = [1e-30, 1e-3, 1.0, 1e3, 1e30][i % 5];
            let mut p = [[0.0; 3]; 4];
            for q in &mut p {
                *q = [
                    next() * scale,
                    next() * scale,
                    next() * scale * [1.0, 1e-6][i % 2],
                ];
            }
            let g = face_normals(&p);
            let w = worst_cos(&g);
            for c in [-0.9, -0.3, 0.0, 0.2, 0.5, 0.94, 0.999, 1.0] {
                // Away from the boundary itself the two must agree.
                if (w - c).abs() > 1e-9 {
                    assert_eq!(worst_cos_at_most(&g, c), w <= c, "{p:?} c {c} worst {w}");
                }
            }
        }
    }

    #[test]
    fn regular_tetrahedron() {
        let p = [
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ];
        let want = (1.0f64 / 3.0).acos().to_degrees();
        let (lo, hi) = dihedral_extremes(&p);
        assert!((lo - want).abs() < 1e-12 && (hi - want).abs() < 1e-12);
        assert!((min_dihedral_cos(&p) - 1.0 / 3.0).abs() < 1e-15);
        assert!((radius_edge(&p) - 6f64.sqrt() / 4.0).abs() < 1e-15);
        let g = face_normals(&p);
        assert!(worst_cos_at_most(&g, 0.3334));
        assert!(!worst_cos_at_most(&g, 0.3333));
        // Scale does not matter, even where squared products of normals would overflow.
        for scale in [1e-60, 1e60] {
            let q = p.map(|x| x.map(|c| c * scale));
            let g = face_normals(&q);
            assert!(worst_cos_at_most(&g, 0.3334), "{scale}");
            assert!(!worst_cos_at_most(&g, 0.3333), "{scale}");
            assert!((min_dihedral_cos(&q) - 1.0 / 3.0).abs() < 1e-15);
            let (lo, hi) = dihedral_extremes(&q);
            assert!((lo - want).abs() < 1e-12 && (hi - want).abs() < 1e-12);
        }
        assert_eq!(volume6(&p).abs(), 16.0);
    }
}
