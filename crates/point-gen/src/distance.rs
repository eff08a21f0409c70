//! Distances from a source (a point, or a segment) to an element (a triangle, or a
//! tetrahedron), for the finest spacing a source asks for anywhere in the element.
//!
//! Point generation samples the spacing at an element's centroid. A source smaller than the
//! element and away from its centroid (a source at a corner of a coarse domain) is then never
//! seen: the centroid's spacing is coarse, a node is within it, and no point is added. The α
//! test therefore also uses the spacing the source asks for at the element's point nearest to
//! it. These are constructions on spacing values, not topology: plain f64.

use crate::spacing3::{cross, dist, dot, nearest_on_triangle, sub};
use delmesh_predicates::{orient2d, orient2d_value, orient3d, orient3d_value, Sign};

type P2 = [f64; 2];
type P3 = [f64; 3];

fn sub2(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot2(a: P2, b: P2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Distance from `p` to the segment `a b` (a point if `a == b`). Beside the segment, the
/// distance to its line is the exact cross product (rounded once) over the length: the
/// projection `a + t (b − a)` loses `p`'s digits when the ends are far from it (a source
/// line from −1e100 to 1e100 across a unit square was at distance 0 from every point).
pub(crate) fn point_segment2(p: P2, a: P2, b: P2) -> f64 {
    let (d, r) = (sub2(b, a), sub2(p, a));
    let len2 = dot2(d, d);
    let t = if len2 > 0.0 { dot2(r, d) / len2 } else { 0.0 };
    if t > 0.0 && t < 1.0 {
        return orient2d_value(a, b, p).abs() / d[0].hypot(d[1]);
    }
    let e = if t >= 1.0 { b } else { a };
    (p[0] - e[0]).hypot(p[1] - e[1])
}

/// Whether `p` is in the closed triangle `t` (either orientation; exact).
fn in_triangle2(p: P2, t: [P2; 3]) -> bool {
    let s = [0, 1, 2].map(|i| orient2d(t[i], t[(i + 1) % 3], p));
    s.iter().all(|&x| x != Sign::Negative) || s.iter().all(|&x| x != Sign::Positive)
}

/// Whether the closed segments `a b` and `c d` meet (proper crossings and touches; the sides
/// exact, as a point far away gets them wrong in floating point).
fn segments_meet2(a: P2, b: P2, c: P2, d: P2) -> bool {
    let opposite = |x: Sign, y: Sign| x != Sign::Zero && y == x.reversed();
    let (s1, s2) = (orient2d(a, b, c), orient2d(a, b, d));
    let (s3, s4) = (orient2d(c, d, a), orient2d(c, d, b));
    if opposite(s1, s2) && opposite(s3, s4) {
        return true;
    }
    // Touching or collinear: an end on the other segment.
    point_segment2(c, a, b) == 0.0
        || point_segment2(d, a, b) == 0.0
        || point_segment2(a, c, d) == 0.0
        || point_segment2(b, c, d) == 0.0
}

/// Distance between the segments `a b` and `c d` (either may be a point).
pub(crate) fn segment_segment2(a: P2, b: P2, c: P2, d: P2) -> f64 {
    if segments_meet2(a, b, c, d) {
        return 0.0;
    }
    point_segment2(a, c, d)
        .min(point_segment2(b, c, d))
        .min(point_segment2(c, a, b))
        .min(point_segment2(d, a, b))
}

/// Distance from the segment `a b` (a point if `a == b`) to the triangle `t` (0 if they meet).
pub(crate) fn segment_triangle2(a: P2, b: P2, t: [P2; 3]) -> f64 {
    if in_triangle2(a, t) || in_triangle2(b, t) {
        return 0.0;
    }
    let mut d = f64::INFINITY;
    for i in 0..3 {
        let (c, e) = (t[i], t[(i + 1) % 3]);
        if segments_meet2(a, b, c, e) {
            return 0.0;
        }
        d = d
            .min(point_segment2(a, c, e))
            .min(point_segment2(b, c, e))
            .min(point_segment2(c, a, b));
    }
    d
}

/// Distance from `p` to the segment `a b` (a point if `a == b`), as [`point_segment2`]: beside
/// the segment, the cross product's components are the exact 2D cross products of the three
/// coordinate projections, rounded once.
pub(crate) fn point_segment3(p: P3, a: P3, b: P3) -> f64 {
    let (d, r) = (sub(b, a), sub(p, a));
    let len2 = dot(d, d);
    let t = if len2 > 0.0 { dot(r, d) / len2 } else { 0.0 };
    if t > 0.0 && t < 1.0 {
        let project = |i: usize, j: usize| orient2d_value([a[i], a[j]], [b[i], b[j]], [p[i], p[j]]);
        let c = [project(1, 2), project(2, 0), project(0, 1)];
        let norm = |v: P3| v[0].hypot(v[1]).hypot(v[2]);
        return norm(c) / norm(d);
    }
    dist(p, if t >= 1.0 { b } else { a })
}

/// Distance between the segments `a b` and `c e` (either may be a point): the closest
/// parameters, clamped to the segments. Where the closest points are inside both, the
/// distance between the lines is the exact `orient3d` of the four ends, rounded once, over
/// the cross product's length; elsewhere an end is nearest, [`point_segment3`]: the
/// parametric points lose the digits of ends far away (a source line drawn from -1e100 to
/// 1e100 through a sphere split its surface otherwise than the same line from -10 to 10).
pub(crate) fn segment_segment3(a: P3, b: P3, c: P3, e: P3) -> f64 {
    let (d1, d2, r) = (sub(b, a), sub(e, c), sub(a, c));
    let (aa, ee, f) = (dot(d1, d1), dot(d2, d2), dot(d2, r));
    if aa > 0.0 && ee > 0.0 {
        let (bb, cc) = (dot(d1, d2), dot(d1, r));
        let denom = aa * ee - bb * bb;
        if denom > 0.0 {
            let s = (bb * f - cc * ee) / denom;
            let t = (aa * f - bb * cc) / denom;
            if s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0 {
                let n = cross(d1, d2);
                let norm = (n[0].hypot(n[1])).hypot(n[2]);
                if norm > 0.0 {
                    return orient3d_value(a, b, c, e).abs() / norm;
                }
            }
        }
    }
    point_segment3(a, c, e)
        .min(point_segment3(b, c, e))
        .min(point_segment3(c, a, b))
        .min(point_segment3(e, a, b))
}

/// Distance from the segment `a b` (a point if `a == b`) to the triangle `t`.
pub(crate) fn segment_triangle3(a: P3, b: P3, t: [P3; 3]) -> f64 {
    // They meet where the ends are not strictly on one side of the plane and the segment's
    // line passes the three edges turning one way (exact: the point where a segment with
    // far ends meets the plane was lost to rounding, and seemed inside every triangle).
    let (sa, sb) = (orient3d(t[0], t[1], t[2], a), orient3d(t[0], t[1], t[2], b));
    // (Both on the plane, coplanar, is left to the distances to the edges.)
    if sa != sb {
        let s = [0, 1, 2].map(|i| orient3d(a, b, t[i], t[(i + 1) % 3]));
        if s.iter().all(|&x| x != Sign::Negative) || s.iter().all(|&x| x != Sign::Positive) {
            return 0.0;
        }
    }
    let mut d = dist(a, nearest_on_triangle(a, t)).min(dist(b, nearest_on_triangle(b, t)));
    for i in 0..3 {
        d = d.min(segment_segment3(a, b, t[i], t[(i + 1) % 3]));
    }
    d
}

/// Whether `p` is in the closed tetrahedron `t` (either orientation; exact: the volumes of a
/// point far away, a segment source's end, come out of either sign in floating point, and
/// every tetrahedron then seemed to hold it).
fn in_tetrahedron(p: P3, t: [P3; 4]) -> bool {
    let s = [
        orient3d(p, t[1], t[2], t[3]),
        orient3d(t[0], p, t[2], t[3]),
        orient3d(t[0], t[1], p, t[3]),
        orient3d(t[0], t[1], t[2], p),
    ];
    s.iter().all(|&x| x != Sign::Negative) || s.iter().all(|&x| x != Sign::Positive)
}

/// Distance from the segment `a b` (a point if `a == b`) to the tetrahedron `t` (0 if they
/// meet).
pub(crate) fn segment_tetrahedron(a: P3, b: P3, t: [P3; 4]) -> f64 {
    if in_tetrahedron(a, t) || in_tetrahedron(b, t) {
        return 0.0;
    }
    const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
    FACES
        .iter()
        .map(|f| segment_triangle3(a, b, f.map(|i| t[i])))
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_to_a_triangle() {
        let t = [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]];
        assert_eq!(segment_triangle2([1.0, 1.0], [1.0, 1.0], t), 0.0);
        assert_eq!(segment_triangle2([-1.0, 0.0], [-1.0, 0.0], t), 1.0);
        // (|cross| / length: 8 / √32, within an ulp of √2.)
        assert!((segment_triangle2([3.0, 3.0], [3.0, 3.0], t) - 2f64.sqrt()).abs() < 1e-15);
        // A segment through the triangle with both ends outside.
        assert_eq!(segment_triangle2([-1.0, 1.0], [5.0, 1.0], t), 0.0);
        // A segment beside the hypotenuse.
        assert!((segment_triangle2([5.0, 1.0], [1.0, 5.0], t) - 2f64.sqrt()).abs() < 1e-15);
        // A corner is nearest.
        assert_eq!(segment_triangle2([-1.0, -3.0], [-1.0, 3.0], t), 1.0);
        // Ends far away: the same as the part beside the triangle (the projection lost the
        // digits of the triangle's points: distance 0, or worse).
        for far in [1e8, 1e50, 1e100] {
            let d = segment_triangle2([-far, 5.0], [far, 5.0], t);
            assert_eq!(d, 1.0, "{far}");
        }
    }

    #[test]
    fn distances_to_a_tetrahedron() {
        let t = [
            [0.0, 0.0, 0.0],
            [4.0, 0.0, 0.0],
            [0.0, 4.0, 0.0],
            [0.0, 0.0, 4.0],
        ];
        let p = |x: P3| segment_tetrahedron(x, x, t);
        assert_eq!(p([0.5, 0.5, 0.5]), 0.0);
        assert_eq!(p([0.5, 0.5, -2.0]), 2.0);
        assert_eq!(p([-1.0, -1.0, 0.0]), 2f64.sqrt());
        assert_eq!(p([-1.0, -2.0, -2.0]), 3.0);
        assert!((p([2.0, 2.0, 2.0]) - 2.0 / 3f64.sqrt()).abs() < 1e-15);
        // A segment piercing two faces, both ends outside.
        assert_eq!(
            segment_tetrahedron([1.0, 1.0, -1.0], [1.0, 1.0, 9.0], t),
            0.0
        );
        // A segment passing an edge at distance 1.
        assert!((segment_tetrahedron([-1.0, -1.0, 2.0], [1.0, -1.0, 2.0], t) - 1.0).abs() < 1e-15);
        // The same line with far ends (every tetrahedron seemed to hold an end 1e8 away, and
        // the parametric closest points lost the tetrahedron's digits).
        for far in [1e8, 1e50, 1e100] {
            let d = segment_tetrahedron([-far, -1.0, 2.0], [far, -1.0, 2.0], t);
            assert!((d - 1.0).abs() < 1e-15, "{far}: {d}");
            let q = crate::Source3 {
                a: [-far, -1.0, 2.0],
                b: [far, -1.0, 2.0],
                h0: 1.0,
                radius: 0.0,
                growth: 1.0,
            };
            assert!((q.spacing([0.0, 0.0, 2.0]) - 2.0).abs() < 1e-15, "{far}");
        }
    }
}
