//! Distances from a source (a point, or a segment) to an element (a triangle, or a
//! tetrahedron), for the finest spacing a source asks for anywhere in the element.
//!
//! Point generation samples the spacing at an element's centroid. A source smaller than the
//! element and away from its centroid (a source at a corner of a coarse domain) is then never
//! seen: the centroid's spacing is coarse, a node is within it, and no point is added. The α
//! test therefore also uses the spacing the source asks for at the element's point nearest to
//! it. These are constructions on spacing values, not topology: plain f64.

use crate::spacing3::{cross, dist, dot, nearest_on_triangle, sub};

type P2 = [f64; 2];
type P3 = [f64; 3];

fn sub2(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}

fn cross2(a: P2, b: P2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn dot2(a: P2, b: P2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Distance from `p` to the segment `a b` (a point if `a == b`).
pub(crate) fn point_segment2(p: P2, a: P2, b: P2) -> f64 {
    let (d, r) = (sub2(b, a), sub2(p, a));
    let len2 = dot2(d, d);
    let t = if len2 > 0.0 {
        (dot2(r, d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (r[0] - t * d[0]).hypot(r[1] - t * d[1])
}

/// Whether `p` is in the closed triangle `t` (either orientation).
fn in_triangle2(p: P2, t: [P2; 3]) -> bool {
    let s = [0, 1, 2].map(|i| cross2(sub2(t[(i + 1) % 3], t[i]), sub2(p, t[i])));
    s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
}

/// Whether the closed segments `a b` and `c d` meet (proper crossings and touches).
fn segments_meet2(a: P2, b: P2, c: P2, d: P2) -> bool {
    let side = |p: P2, q: P2, r: P2| cross2(sub2(q, p), sub2(r, p));
    let (s1, s2) = (side(a, b, c), side(a, b, d));
    let (s3, s4) = (side(c, d, a), side(c, d, b));
    if s1 * s2 < 0.0 && s3 * s4 < 0.0 {
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

fn along(a: P3, d: P3, t: f64) -> P3 {
    [a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]]
}

/// Distance between the segments `a b` and `c e` (either may be a point): the closest
/// parameters, clamped to the segments.
pub(crate) fn segment_segment3(a: P3, b: P3, c: P3, e: P3) -> f64 {
    let (d1, d2, r) = (sub(b, a), sub(e, c), sub(a, c));
    let (aa, ee, f) = (dot(d1, d1), dot(d2, d2), dot(d2, r));
    let (s, t) = if aa == 0.0 && ee == 0.0 {
        (0.0, 0.0)
    } else if aa == 0.0 {
        (0.0, (f / ee).clamp(0.0, 1.0))
    } else {
        let cc = dot(d1, r);
        if ee == 0.0 {
            ((-cc / aa).clamp(0.0, 1.0), 0.0)
        } else {
            let bb = dot(d1, d2);
            let denom = aa * ee - bb * bb;
            let s = if denom > 0.0 {
                ((bb * f - cc * ee) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t = (bb * s + f) / ee;
            if t < 0.0 {
                ((-cc / aa).clamp(0.0, 1.0), 0.0)
            } else if t > 1.0 {
                (((bb - cc) / aa).clamp(0.0, 1.0), 1.0)
            } else {
                (s, t)
            }
        }
    };
    dist(along(a, d1, s), along(c, d2, t))
}

/// Distance from the segment `a b` (a point if `a == b`) to the triangle `t`.
pub(crate) fn segment_triangle3(a: P3, b: P3, t: [P3; 3]) -> f64 {
    let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
    let (da, db) = (dot(sub(a, t[0]), n), dot(sub(b, t[0]), n));
    if da * db <= 0.0 && da != db {
        // The segment meets the plane at x: inside the triangle, they meet.
        let x = along(a, sub(b, a), da / (da - db));
        let inside = (0..3).all(|i| {
            let edge = sub(t[(i + 1) % 3], t[i]);
            dot(cross(edge, sub(x, t[i])), n) >= 0.0
        });
        if inside {
            return 0.0;
        }
    }
    let mut d = dist(a, nearest_on_triangle(a, t)).min(dist(b, nearest_on_triangle(b, t)));
    for i in 0..3 {
        d = d.min(segment_segment3(a, b, t[i], t[(i + 1) % 3]));
    }
    d
}

/// Whether `p` is in the closed tetrahedron `t` (either orientation).
fn in_tetrahedron(p: P3, t: [P3; 4]) -> bool {
    let volume = |a: P3, b: P3, c: P3, d: P3| dot(sub(b, a), cross(sub(c, a), sub(d, a)));
    let s = [
        volume(p, t[1], t[2], t[3]),
        volume(t[0], p, t[2], t[3]),
        volume(t[0], t[1], p, t[3]),
        volume(t[0], t[1], t[2], p),
    ];
    s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
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
        assert_eq!(segment_triangle2([3.0, 3.0], [3.0, 3.0], t), 2f64.sqrt());
        // A segment through the triangle with both ends outside.
        assert_eq!(segment_triangle2([-1.0, 1.0], [5.0, 1.0], t), 0.0);
        // A segment beside the hypotenuse.
        assert!((segment_triangle2([5.0, 1.0], [1.0, 5.0], t) - 2f64.sqrt()).abs() < 1e-15);
        // A corner is nearest.
        assert_eq!(segment_triangle2([-1.0, -3.0], [-1.0, 3.0], t), 1.0);
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
    }
}
