//! Exact intersection tests between surface triangles, and the searches (over the hierarchy of
//! the triangles' boxes) that find the pairs to test.
//!
//! All decisions are signs of `orient3d` and `orient2d` on the input coordinates (scaled by a
//! power of two, which changes no sign). Triangles are closed sets; what counts as an
//! intersection depends on what the two triangles share:
//!
//! - **nothing**: any common point. Two closed triangles meet iff an edge of one meets the
//!   other (an extreme point of the convex set `T₁ ∩ T₂` lies on the boundary of one of them),
//!   so the test is six segment–triangle tests. A segment crossing a plane meets the triangle
//!   iff no two of `orient3d(p, q, a, b)`, `(p, q, b, c)`, `(p, q, c, a)` have strictly opposite
//!   signs; a segment in the plane is a 2D test in a projection where the triangle is not
//!   degenerate (the projection is then a bijection of the plane, so 2D signs are exact).
//! - **one corner `v`**: they intersect beyond `v` iff their cones at `v` do (both sets are
//!   convex and contain `v`, so a second common point `x` brings the whole segment `v x`, which
//!   starts inside both cones). Not coplanar: the cone of `T₁` meets the plane of `T₂` in one
//!   ray, found from the sides of `T₁`'s other corners, and the ray must lie in `T₂`'s wedge:
//!   its side of each wedge line is read off a plane through that line and a corner of `T₁`
//!   off `T₂`'s plane. Coplanar: two 2D wedges overlap iff one contains a bounding ray of the
//!   other.
//! - **an edge**: they overlap beyond it iff they are coplanar and their third corners lie on
//!   the same side of the edge (folded onto each other).

use super::bvh::{overlap, Aabb, Boxes};
use delmesh_predicates::Sign;
use rayon::prelude::*;

/// `orient3d`, answering zero without arithmetic when the four points share a coordinate
/// exactly (they lie in an axis-aligned plane: flat faces of boxes, symmetry planes), which is
/// otherwise the exact predicate's slowest case.
#[inline]
pub(crate) fn orient3d(a: P, b: P, c: P, d: P) -> Sign {
    if (0..3).any(|k| a[k] == b[k] && a[k] == c[k] && a[k] == d[k]) {
        return Sign::Zero;
    }
    delmesh_predicates::orient3d(a, b, c, d)
}

/// `orient2d`, answering zero without arithmetic when the three points share a coordinate.
#[inline]
pub(crate) fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    if (0..2).any(|k| a[k] == b[k] && a[k] == c[k]) {
        return Sign::Zero;
    }
    delmesh_predicates::orient2d(a, b, c)
}

pub(crate) type P = [f64; 3];

/// Whether two signs are strictly opposite (neither zero).
#[inline]
fn opposite(s: Sign, t: Sign) -> bool {
    matches!(
        (s, t),
        (Sign::Positive, Sign::Negative) | (Sign::Negative, Sign::Positive)
    )
}

/// Drops coordinate `k`.
#[inline]
pub(crate) fn project(p: P, k: usize) -> [f64; 2] {
    match k {
        0 => [p[1], p[2]],
        1 => [p[2], p[0]],
        _ => [p[0], p[1]],
    }
}

/// The axes ordered by the size of the triangle's normal component in floating point, largest
/// first: the projection most likely to be far from degenerate comes first.
#[inline]
fn axes_by_normal(a: P, b: P, c: P) -> [usize; 3] {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        (u[1] * w[2] - u[2] * w[1]).abs(),
        (u[2] * w[0] - u[0] * w[2]).abs(),
        (u[0] * w[1] - u[1] * w[0]).abs(),
    ];
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| n[j].total_cmp(&n[i]));
    order
}

/// An axis whose projection keeps the (non-degenerate) triangle non-degenerate: the largest
/// normal component in floating point, checked exactly. `None` for collinear points.
pub(crate) fn projection_axis(a: P, b: P, c: P) -> Option<usize> {
    axes_by_normal(a, b, c)
        .into_iter()
        .find(|&k| orient2d(project(a, k), project(b, k), project(c, k)) != Sign::Zero)
}

/// Whether three points lie exactly on one line: every axis projection is degenerate.
pub(crate) fn collinear(a: P, b: P, c: P) -> bool {
    projection_axis(a, b, c).is_none()
}

/// Given collinear `a, b, x` with `a ≠ b`: whether `x` lies on the closed segment `a b`.
#[inline]
fn on_closed_segment2(a: [f64; 2], b: [f64; 2], x: [f64; 2]) -> bool {
    let k = if a[0] != b[0] { 0 } else { 1 };
    a[k].min(b[k]) <= x[k] && x[k] <= a[k].max(b[k])
}

/// Whether the closed segments `p q` and `r s` (each of positive length) share a point.
fn segments_meet2(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> bool {
    let (o1, o2) = (orient2d(p, q, r), orient2d(p, q, s));
    let (o3, o4) = (orient2d(r, s, p), orient2d(r, s, q));
    if opposite(o1, o2) && opposite(o3, o4) {
        return true;
    }
    (o1 == Sign::Zero && on_closed_segment2(p, q, r))
        || (o2 == Sign::Zero && on_closed_segment2(p, q, s))
        || (o3 == Sign::Zero && on_closed_segment2(r, s, p))
        || (o4 == Sign::Zero && on_closed_segment2(r, s, q))
}

/// Whether `x` lies in the closed non-degenerate triangle `a b c` (2D).
#[inline]
fn in_closed_triangle2(a: [f64; 2], b: [f64; 2], c: [f64; 2], x: [f64; 2]) -> bool {
    let s = orient2d(a, b, c);
    [orient2d(a, b, x), orient2d(b, c, x), orient2d(c, a, x)]
        .into_iter()
        .all(|o| o == s || o == Sign::Zero)
}

/// Whether the point `x` lies on the closed triangle `t` (exactly).
pub(crate) fn point_on_triangle(t: [P; 3], x: P) -> bool {
    if orient3d(t[0], t[1], t[2], x) != Sign::Zero {
        return false;
    }
    let Some(k) = projection_axis(t[0], t[1], t[2]) else {
        return false;
    };
    in_closed_triangle2(
        project(t[0], k),
        project(t[1], k),
        project(t[2], k),
        project(x, k),
    )
}

/// Segment `p q` and triangle `t`, all four points in one plane: 2D test in the projection
/// along `axis` (where `t` is not degenerate).
fn coplanar_segment_triangle(p: P, q: P, t: [P; 3], axis: usize) -> bool {
    let [a, b, c] = t.map(|x| project(x, axis));
    let (p2, q2) = (project(p, axis), project(q, axis));
    in_closed_triangle2(a, b, c, p2)
        || in_closed_triangle2(a, b, c, q2)
        || segments_meet2(p2, q2, a, b)
        || segments_meet2(p2, q2, b, c)
        || segments_meet2(p2, q2, c, a)
}

/// Segment `p q` (not in the plane of `t`, and not strictly on one side of it: `sp`, `sq` are
/// the sides of its ends) meets the closed triangle `t`.
fn crossing_segment_triangle(p: P, q: P, t: [P; 3]) -> bool {
    let s = [
        orient3d(p, q, t[0], t[1]),
        orient3d(p, q, t[1], t[2]),
        orient3d(p, q, t[2], t[0]),
    ];
    !(opposite(s[0], s[1]) || opposite(s[1], s[2]) || opposite(s[2], s[0]))
}

/// Whether two closed triangles with no corner in common share any point.
pub(crate) fn triangles_meet(t1: [P; 3], t2: [P; 3]) -> bool {
    let d2 = t2.map(|x| orient3d(t1[0], t1[1], t1[2], x));
    if d2[0] != Sign::Zero && d2[0] == d2[1] && d2[1] == d2[2] {
        return false;
    }
    let d1 = t1.map(|x| orient3d(t2[0], t2[1], t2[2], x));
    if d1[0] != Sign::Zero && d1[0] == d1[1] && d1[1] == d1[2] {
        return false;
    }
    if d2.iter().all(|&s| s == Sign::Zero) {
        // Coplanar: the polygon test, edges of each against the other.
        let Some(axis) = projection_axis(t1[0], t1[1], t1[2]) else {
            return false;
        };
        let [a, b, c] = t1.map(|x| project(x, axis));
        let [d, e, f] = t2.map(|x| project(x, axis));
        return in_closed_triangle2(a, b, c, d)
            || in_closed_triangle2(d, e, f, a)
            || [(a, b), (b, c), (c, a)].into_iter().any(|(p, q)| {
                segments_meet2(p, q, d, e)
                    || segments_meet2(p, q, e, f)
                    || segments_meet2(p, q, f, d)
            });
    }
    // Not coplanar: an edge of one meets the other.
    let edge_meets = |tp: [P; 3], sides: [Sign; 3], other: [P; 3]| {
        (0..3).any(|i| {
            let j = (i + 1) % 3;
            let (si, sj) = (sides[i], sides[j]);
            if si != Sign::Zero && si == sj {
                false
            } else if si == Sign::Zero && sj == Sign::Zero {
                projection_axis(other[0], other[1], other[2])
                    .is_some_and(|axis| coplanar_segment_triangle(tp[i], tp[j], other, axis))
            } else {
                crossing_segment_triangle(tp[i], tp[j], other)
            }
        })
    };
    edge_meets(t1, d1, t2) || edge_meets(t2, d2, t1)
}

/// Whether two triangles sharing exactly the corner `v` (`(v, a1, b1)` and `(v, a2, b2)`)
/// meet anywhere else.
pub(crate) fn meet_beyond_vertex(v: P, a1: P, b1: P, a2: P, b2: P) -> bool {
    let sa = orient3d(v, a2, b2, a1);
    let sb = orient3d(v, a2, b2, b1);
    if sa == Sign::Zero && sb == Sign::Zero {
        // Coplanar: 2D wedges at v.
        let Some(axis) = projection_axis(v, a1, b1) else {
            return false;
        };
        let [v, mut a1, mut b1, mut a2, mut b2] = [v, a1, b1, a2, b2].map(|x| project(x, axis));
        if orient2d(v, a1, b1) == Sign::Negative {
            std::mem::swap(&mut a1, &mut b1);
        }
        if orient2d(v, a2, b2) == Sign::Negative {
            std::mem::swap(&mut a2, &mut b2);
        }
        // Direction d (from v) in the closed counter-clockwise wedge (a, b), angle below π.
        let in_wedge = |a: [f64; 2], b: [f64; 2], d: [f64; 2]| {
            orient2d(v, a, d) != Sign::Negative && orient2d(v, d, b) != Sign::Negative
        };
        return in_wedge(a1, b1, a2) || in_wedge(a1, b1, b2) || in_wedge(a2, b2, a1);
    }
    if sa == sb {
        // T1 touches the plane of T2 only at v.
        return false;
    }
    // The cone of T1 meets the plane of T2 in the ray from v through x, a point of the edge
    // a1 b1 (a1 or b1 itself when that corner is on the plane). w is a corner of T1 off the
    // plane; the side of x relative to the plane through v, y, w (y a corner of T2) is its side
    // of the line v y within T2's plane.
    let (w, other) = if sa != Sign::Zero { (a1, b1) } else { (b1, a1) };
    let side_x = |y: P| orient3d(v, y, w, other);
    let c1 = side_x(a2);
    let c2 = side_x(b2);
    (c1 == Sign::Zero || c1 == orient3d(v, a2, w, b2))
        && (c2 == Sign::Zero || c2 == orient3d(v, b2, w, a2))
}

/// Whether two triangles sharing the edge `u w` (third corners `a` and `b`) overlap beyond it:
/// coplanar with `a` and `b` on the same side of the edge.
pub(crate) fn meet_beyond_edge(u: P, w: P, a: P, b: P) -> bool {
    if orient3d(u, w, a, b) != Sign::Zero {
        return false;
    }
    let Some(axis) = projection_axis(u, w, a) else {
        return false;
    };
    let (u, w) = (project(u, axis), project(w, axis));
    orient2d(u, w, project(a, axis)) == orient2d(u, w, project(b, axis))
}

/// Whether triangles `i` and `j` (corner indices `ti`, `tj`) intersect other than in what they
/// share. Identical triangles are never passed here.
pub(crate) fn pair_intersects(pts: &[P], ti: [u32; 3], tj: [u32; 3]) -> bool {
    let p = |v: u32| pts[v as usize];
    let mut shared = [(0usize, 0usize); 3];
    let mut n = 0;
    for (a, &u) in ti.iter().enumerate() {
        if let Some(b) = tj.iter().position(|&w| w == u) {
            shared[n] = (a, b);
            n += 1;
        }
    }
    match n {
        0 => triangles_meet(ti.map(p), tj.map(p)),
        1 => {
            let (a, b) = shared[0];
            meet_beyond_vertex(
                p(ti[a]),
                p(ti[(a + 1) % 3]),
                p(ti[(a + 2) % 3]),
                p(tj[(b + 1) % 3]),
                p(tj[(b + 2) % 3]),
            )
        }
        2 => {
            let third = |t: [u32; 3], x: usize, y: usize| t[3 - x - y];
            let (u, w) = (ti[shared[0].0], ti[shared[1].0]);
            meet_beyond_edge(
                p(u),
                p(w),
                p(third(ti, shared[0].0, shared[1].0)),
                p(third(tj, shared[0].1, shared[1].1)),
            )
        }
        _ => false,
    }
}

/// The bounding box of a triangle.
pub(crate) fn triangle_box(pts: &[P], t: [u32; 3]) -> Aabb {
    let [a, b, c] = t.map(|v| pts[v as usize]);
    (
        std::array::from_fn(|k| a[k].min(b[k]).min(c[k])),
        std::array::from_fn(|k| a[k].max(b[k]).max(c[k])),
    )
}

/// All intersecting triangle pairs `(i, j)`, `i < j`, sorted: the exact test on every pair
/// whose boxes overlap.
pub(crate) fn intersecting_pairs(pts: &[P], tris: &[[u32; 3]], boxes: &Boxes) -> Vec<(u32, u32)> {
    // One traversal per leaf: its box covers its (at most four) triangles' boxes. Leaves are
    // independent, so they are searched in parallel; the sort makes the order thread-free.
    let leaves: Vec<(&Aabb, &[u32])> = boxes.bvh().leaves().collect();
    let mut out: Vec<(u32, u32)> = leaves
        .par_iter()
        .map_init(
            || (Vec::new(), Vec::new()),
            |(stack, near), &(leaf_box, items)| {
                near.clear();
                boxes.overlapping(leaf_box, stack, |j| near.push(j));
                let mut found = Vec::new();
                for &i in items {
                    let bi = &boxes.boxes[i as usize];
                    for &j in near.iter() {
                        if j > i
                            && overlap(bi, &boxes.boxes[j as usize])
                            && pair_intersects(pts, tris[i as usize], tris[j as usize])
                        {
                            found.push((i, j));
                        }
                    }
                }
                found
            },
        )
        .flatten()
        .collect();
    out.sort_unstable();
    out
}

/// All `(point, triangle)` pairs where a point (of `points`, indices into `pts`) lies on a
/// closed triangle it is not a corner of, sorted by point then triangle.
pub(crate) fn points_on_triangles(
    pts: &[P],
    points: impl Iterator<Item = u32>,
    tris: &[[u32; 3]],
    boxes: &Boxes,
) -> Vec<(u32, u32)> {
    let points: Vec<u32> = points.collect();
    let mut out: Vec<(u32, u32)> = points
        .par_chunks(1024)
        .map_init(Vec::new, |stack, chunk| {
            let mut found = Vec::new();
            for &v in chunk {
                let x = pts[v as usize];
                boxes.overlapping(&(x, x), stack, |t| {
                    let tri = tris[t as usize];
                    if !tri.contains(&v) && point_on_triangle(tri.map(|u| pts[u as usize]), x) {
                        found.push((v, t));
                    }
                });
            }
            found
        })
        .flatten()
        .collect();
    out.sort_unstable();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const O: P = [0.0, 0.0, 0.0];

    #[test]
    fn disjoint_crossing_and_touching() {
        let t1 = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        // Pierces the interior.
        assert!(triangles_meet(
            t1,
            [[0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [3.0, 3.0, 0.5]]
        ));
        // Above, apart.
        assert!(!triangles_meet(
            t1,
            [[0.5, 0.5, 0.1], [0.5, 0.7, 1.0], [3.0, 3.0, 0.5]]
        ));
        // A corner touching the interior; an edge touching an edge.
        assert!(triangles_meet(
            t1,
            [[0.5, 0.5, 0.0], [0.5, 0.7, 1.0], [3.0, 3.0, 0.5]]
        ));
        assert!(triangles_meet(
            t1,
            [[1.0, 1.0, -1.0], [1.0, 1.0, 1.0], [3.0, 3.0, 0.0]]
        ));
        // Edge in the plane, crossing the triangle (neither end inside).
        assert!(triangles_meet(
            t1,
            [[-1.0, 1.0, 0.0], [3.0, 1.0, 0.0], [3.0, 3.0, 1.0]]
        ));
        // Edge in the plane, just missing.
        assert!(!triangles_meet(
            t1,
            [[1.5, 1.5, 0.0], [3.0, 1.5, 0.0], [3.0, 3.0, 1.0]]
        ));
        // Coplanar: overlapping, one inside the other, apart.
        assert!(triangles_meet(
            t1,
            [[1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [3.0, 0.0, 0.0]]
        ));
        assert!(triangles_meet(
            t1,
            [[0.1, 0.1, 0.0], [0.5, 0.1, 0.0], [0.1, 0.5, 0.0]]
        ));
        assert!(!triangles_meet(
            t1,
            [[1.1, 1.1, 0.0], [3.0, 1.1, 0.0], [1.1, 3.0, 0.0]]
        ));
    }

    #[test]
    fn sharing_a_vertex() {
        let (a1, b1) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // Coplanar, opposite wedges: only v.
        assert!(!meet_beyond_vertex(
            O,
            a1,
            b1,
            [-1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0]
        ));
        // Coplanar, wedges sharing a bounding ray: overlap along an edge.
        assert!(meet_beyond_vertex(
            O,
            a1,
            b1,
            [2.0, 0.0, 0.0],
            [0.0, -1.0, 0.0]
        ));
        // Coplanar, touching along opposite rays only: just v.
        assert!(!meet_beyond_vertex(
            O,
            a1,
            b1,
            [-1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0]
        ));
        // Coplanar, one wedge inside the other.
        assert!(meet_beyond_vertex(
            O,
            a1,
            b1,
            [1.0, 1.0, 0.0],
            [1.0, 2.0, 0.0]
        ));
        assert!(meet_beyond_vertex(
            O,
            [1.0, 1.0, 0.0],
            [1.0, 2.0, 0.0],
            a1,
            b1
        ));
        // Not coplanar, folded through the other's interior.
        assert!(meet_beyond_vertex(
            O,
            a1,
            b1,
            [1.0, 1.0, 1.0],
            [1.0, 1.0, -1.0]
        ));
        // Not coplanar, beside each other (a cube corner).
        assert!(!meet_beyond_vertex(
            O,
            a1,
            b1,
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0]
        ));
        // Not coplanar: T1 crosses T2's plane on a ray outside T2's wedge.
        assert!(!meet_beyond_vertex(
            O,
            a1,
            b1,
            [-1.0, -1.0, 1.0],
            [-1.0, -1.0, -1.0]
        ));
        // An edge of T1 lying in T2, along T2's bounding ray or inside its wedge.
        assert!(meet_beyond_vertex(
            O,
            a1,
            b1,
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0]
        ));
        assert!(meet_beyond_vertex(
            O,
            a1,
            [0.0, 1.0, 1.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 0.0]
        ));
        // An edge of T1 in T2's plane, outside the wedge.
        assert!(!meet_beyond_vertex(
            O,
            a1,
            b1,
            [0.0, -1.0, 0.0],
            [0.0, -1.0, 1.0]
        ));
    }

    #[test]
    fn sharing_an_edge() {
        let (u, w) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        assert!(!meet_beyond_edge(u, w, [0.0, 1.0, 0.0], [0.0, -1.0, 0.0]));
        assert!(meet_beyond_edge(u, w, [0.0, 1.0, 0.0], [0.5, 2.0, 0.0]));
        assert!(!meet_beyond_edge(u, w, [0.0, 1.0, 0.0], [0.5, 2.0, 1e-300]));
        assert!(!meet_beyond_edge(u, w, [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]));
    }

    #[test]
    fn points_on_triangles() {
        let t = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        assert!(point_on_triangle(t, [0.5, 0.5, 0.0]));
        assert!(point_on_triangle(t, [1.0, 1.0, 0.0]));
        assert!(!point_on_triangle(t, [1.0, 1.0 + f64::EPSILON, 0.0]));
        assert!(!point_on_triangle(t, [0.5, 0.5, 1e-300]));
    }

    // ----- an independent oracle: exact linear feasibility -----

    /// A rational number, `n / d` with `d > 0`, reduced.
    #[derive(Clone, Copy, Debug, PartialEq)]
    struct Q(i128, i128);

    fn gcd(a: i128, b: i128) -> i128 {
        if b == 0 {
            a.abs()
        } else {
            gcd(b, a % b)
        }
    }

    impl Q {
        fn new(n: i128, d: i128) -> Q {
            let g = gcd(n, d).max(1) * d.signum();
            Q(n / g, d / g)
        }
        fn sub(self, o: Q) -> Q {
            Q::new(self.0 * o.1 - o.0 * self.1, self.1 * o.1)
        }
        fn mul(self, o: Q) -> Q {
            Q::new(self.0 * o.0, self.1 * o.1)
        }
        fn div(self, o: Q) -> Q {
            Q::new(self.0 * o.1, self.1 * o.0)
        }
    }

    /// Whether `A x = b`, `x ≥ 0` has a solution (`A` given by columns): some set of linearly
    /// independent columns solves it with non-negative weights (a basic feasible solution).
    fn feasible(columns: &[Vec<i64>], b: &[i64]) -> bool {
        let m = b.len();
        (1u32..1 << columns.len()).any(|mask| {
            let chosen: Vec<&Vec<i64>> = (0..columns.len())
                .filter(|k| mask >> k & 1 == 1)
                .map(|k| &columns[k])
                .collect();
            let n = chosen.len();
            // Augmented matrix, Gauss–Jordan elimination over the rationals.
            let mut a: Vec<Vec<Q>> = (0..m)
                .map(|r| {
                    let mut row: Vec<Q> = chosen.iter().map(|c| Q(i128::from(c[r]), 1)).collect();
                    row.push(Q(i128::from(b[r]), 1));
                    row
                })
                .collect();
            let mut rank = 0;
            for col in 0..n {
                let Some(piv) = (rank..m).find(|&r| a[r][col].0 != 0) else {
                    return false; // dependent columns: a smaller set covers it
                };
                a.swap(rank, piv);
                let p = a[rank][col];
                for x in &mut a[rank] {
                    *x = x.div(p);
                }
                let pivot_row = a[rank].clone();
                for (r, row) in a.iter_mut().enumerate() {
                    if r != rank && row[col].0 != 0 {
                        let f = row[col];
                        for (x, &y) in row.iter_mut().zip(&pivot_row) {
                            *x = x.sub(f.mul(y));
                        }
                    }
                }
                rank += 1;
            }
            // Consistent, and the unique solution is non-negative.
            (rank..m).all(|r| a[r][n].0 == 0) && (0..n).all(|r| a[r][n].0 >= 0)
        })
    }

    type I = [i64; 3];

    fn sub3(a: I, b: I) -> I {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    /// Oracle: do closed triangles `p`, `q` (no shared corner) meet? `Σλp = Σμq`, `Σλ = Σμ = 1`.
    fn oracle_meet(p: [I; 3], q: [I; 3]) -> bool {
        let mut cols = Vec::new();
        for x in p {
            cols.push(vec![1, 0, x[0], x[1], x[2]]);
        }
        for x in q {
            cols.push(vec![0, 1, -x[0], -x[1], -x[2]]);
        }
        feasible(&cols, &[1, 1, 0, 0, 0])
    }

    /// Oracle: do the cones at `v` of `(v, a1, b1)` and `(v, a2, b2)` share a ray?
    fn oracle_cones(v: I, a1: I, b1: I, a2: I, b2: I) -> bool {
        let [a1, b1, a2, b2] = [a1, b1, a2, b2].map(|x| sub3(x, v));
        let col = |w: i64, x: I, s: i64| vec![w, s * x[0], s * x[1], s * x[2]];
        feasible(
            &[col(1, a1, 1), col(1, b1, 1), col(0, a2, -1), col(0, b2, -1)],
            &[1, 0, 0, 0],
        )
    }

    /// Oracle: do the wedges along edge `u w` towards `a` and `b` overlap? `σ(w − u) + (a − u)
    /// = t(b − u)` with `σ` free and `t ≥ 0`.
    fn oracle_wedges(u: I, w: I, a: I, b: I) -> bool {
        let (e, a, b) = (sub3(w, u), sub3(a, u), sub3(b, u));
        let neg = |x: I| vec![-x[0], -x[1], -x[2]];
        feasible(&[e.to_vec(), neg(e), b.to_vec()], &a)
    }

    /// Oracle: is `x` on the closed triangle `t`?
    fn oracle_on(t: [I; 3], x: I) -> bool {
        let cols: Vec<Vec<i64>> = t.iter().map(|p| vec![1, p[0], p[1], p[2]]).collect();
        feasible(&cols, &[1, x[0], x[1], x[2]])
    }

    fn non_collinear(t: [I; 3]) -> bool {
        let (u, w) = (sub3(t[1], t[0]), sub3(t[2], t[0]));
        u[1] * w[2] != u[2] * w[1] || u[2] * w[0] != u[0] * w[2] || u[0] * w[1] != u[1] * w[0]
    }

    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        #[test]
        fn pair_tests_agree_with_linear_feasibility(
            cells in proptest::sample::subsequence((0i64..64).collect::<Vec<_>>(), 7).prop_shuffle(),
            ti in proptest::sample::subsequence((0usize..7).collect::<Vec<_>>(), 3).prop_shuffle(),
            tj in proptest::sample::subsequence((0usize..7).collect::<Vec<_>>(), 3).prop_shuffle(),
        ) {
            // Seven distinct points of the 4 × 4 × 4 grid (spacing 1/4 in floating point).
            let pool: Vec<I> = cells.iter().map(|&c| [c % 4, c / 4 % 4, c / 16]).collect();
            let (ti, tj) = ([ti[0], ti[1], ti[2]], [tj[0], tj[1], tj[2]]);
            let (pi, pj) = (ti.map(|k| pool[k]), tj.map(|k| pool[k]));
            prop_assume!(non_collinear(pi) && non_collinear(pj));
            let pts: Vec<P> = pool.iter().map(|p| p.map(|x| x as f64 * 0.25)).collect();
            let shared: Vec<usize> = ti.iter().copied().filter(|k| tj.contains(k)).collect();
            prop_assume!(shared.len() < 3);
            let got = pair_intersects(&pts, ti.map(|k| k as u32), tj.map(|k| k as u32));
            let want = match shared.len() {
                0 => oracle_meet(pi, pj),
                1 => {
                    let v = shared[0];
                    let o1: Vec<usize> = ti.iter().copied().filter(|&k| k != v).collect();
                    let o2: Vec<usize> = tj.iter().copied().filter(|&k| k != v).collect();
                    oracle_cones(pool[v], pool[o1[0]], pool[o1[1]], pool[o2[0]], pool[o2[1]])
                }
                _ => {
                    let a = ti.iter().copied().find(|k| !tj.contains(k)).expect("third");
                    let b = tj.iter().copied().find(|k| !ti.contains(k)).expect("third");
                    oracle_wedges(pool[shared[0]], pool[shared[1]], pool[a], pool[b])
                }
            };
            prop_assert_eq!(got, want, "{:?} {:?}", pi, pj);
            // Symmetric, and independent of the corners' order.
            let rotated = |t: [usize; 3]| [t[1], t[2], t[0]].map(|k| k as u32);
            let reversed = |t: [usize; 3]| [t[0], t[2], t[1]].map(|k| k as u32);
            prop_assert_eq!(pair_intersects(&pts, tj.map(|k| k as u32), ti.map(|k| k as u32)), want);
            prop_assert_eq!(pair_intersects(&pts, rotated(ti), reversed(tj)), want);
            // A corner of one on the other, off the shared corners.
            for (t, x) in [(ti, tj), (tj, ti)] {
                for &k in &x {
                    if !t.contains(&k) {
                        let on = point_on_triangle(t.map(|c| pts[c]), pts[k]);
                        prop_assert_eq!(on, oracle_on(t.map(|c| pool[c]), pool[k]));
                    }
                }
            }
        }
    }
}
