//! Re-triangulation of planar patches of the surface before recovery, by diagonal flips.
//!
//! Where two surface triangles `a b c` and `b a d` lie exactly in one plane, the region they
//! cover is the same whichever diagonal (`a b` or `c d`) splits it, so the diagonal need not be
//! recovered as it is: it may be flipped. Two kinds of flip are made, both only across an edge
//! whose two triangles are exactly coplanar (exact `orient3d`), carry the same marker, turn the
//! same way and form a strictly convex quadrilateral:
//!
//! 1. **Delaunay flips** (Lawson's): `a b` is flipped when `d` lies strictly inside the circle
//!    through `a, b, c`. The patch becomes the Delaunay triangulation of its points in its plane
//!    (constrained to the edges where the surface bends), whose edges the tetrahedralisation
//!    holds unless a point off the plane is close by.
//! 2. **Flips to the tetrahedralisation's choice**: `a b` is flipped when it is not an edge of
//!    the tetrahedralisation and `c d` is. After the Delaunay flips only ties are left (four
//!    co-circular points, such as the squares of a structured grid), where the
//!    tetrahedralisation's symbolic perturbation picked the other diagonal.
//!
//! Without either, every such edge would be recovered by splitting it, and in a flat patch a
//! split edge's halves are no better placed than the edge was: the splits cascade (a box far
//! field made of a regular grid took hundreds of Steiner points; it now takes none).
//!
//! Flips stay within one input facet (the triangles of a polygon facet, which delmesh
//! triangulated itself), unless merging of coplanar facets is asked for, as TetGen does by
//! default: then any two coplanar triangles with the same marker may be re-triangulated. The
//! covered surface, its markers and its points are unchanged, exactly.
//!
//! Recovery's fallback for a surface too costly as given ([`Patches::NearlyCoplanar`]) also
//! merges triangles that are only flat to rounding ([`nearly_flat`]: thinner than `2^-40` of
//! their coordinates), as rounding leaves the flat faces of a CAD part turned into a general
//! position: the surface then moves by less than that thickness. Only where nothing else
//! recovers a single-precision surface (binary STL) is the tolerance `2^-20`. For nearly co-circular points
//! the Delaunay flips, which follow the circle test in the (nearly) common plane, need not
//! agree with the tetrahedralisation; the flips to its choice mend most of that, not always
//! all.
//!
//! Termination: a Delaunay flip strictly lowers the lifted triangulation of the (planar) patch,
//! and a flip to the tetrahedralisation's choice turns a missing edge into a present one while
//! the tetrahedralisation stays as it is. Delaunay flips of nearly coplanar points have no such
//! bound (their circle test depends on the point off the plane it uses): at most 16 per
//! surface edge, plus 100,000, are made.

use crate::plc3::SurfaceTriangle;
use crate::recovery3::{cross, dot, sub};
use delmesh_delaunay_core::{StarSearch, Triangulation3, VertexId};
use delmesh_predicates::{insphere, orient2d, orient3d, Sign};
use rustc_hash::FxHashMap as HashMap;

/// Which coplanar triangles may be re-triangulated together.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Patches {
    /// Only triangles of one input facet.
    OneFacet,
    /// Any coplanar neighbours with the same marker.
    Coplanar,
    /// Any neighbours with the same marker that are coplanar or nearly so ([`nearly_flat`]
    /// with this tolerance): the surface then moves by less than the tolerance.
    NearlyCoplanar(Flatness),
}

/// How flat nearly coplanar triangles must be to be merged ([`nearly_flat`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Flatness {
    /// Thinner than `2^-40` of their coordinates: what rounding a point turned into a general
    /// position in double precision leaves.
    Double,
    /// Thinner than `2^-20` of their coordinates: what single precision (binary STL) leaves;
    /// only for inputs whose every coordinate is a single-precision number.
    Single,
}

impl Flatness {
    /// The tolerance, relative to the coordinates.
    fn relative(self) -> f64 {
        match self {
            Flatness::Double => 2f64.powi(-40),
            Flatness::Single => 2f64.powi(-20),
        }
    }

    /// The most two merged triangles may bend: their thickness over their width, about the
    /// angle in radians. Rounding to single precision bends the needle triangles of a CAD
    /// cylinder's cap by up to a few degrees; to double precision, by a few billionths.
    fn bend(self) -> f64 {
        match self {
            Flatness::Double => 2f64.powi(-20),
            Flatness::Single => 2f64.powi(-3),
        }
    }
}

/// Whether the tetrahedron `a b c d` is flat to rounding: its thickness (the height over its
/// largest face) is at most `flatness` of its largest coordinate (see [`Flatness`]), and at
/// most [`Flatness::bend`] of that face's width (twice its area over the longest edge), so
/// that the triangles bend by less than about that many radians; exactly coplanar points
/// always pass. Merging such triangles moves the surface by less than that thickness.
/// (Without the bend test, the sides of a hexagonal prism of radius 1 and length 1e12,
/// meeting at 120° but thinner than 2^-40 of the coordinates, were merged and the prism lost
/// 11% of its volume.)
pub(crate) fn nearly_flat(
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    d: [f64; 3],
    flatness: Flatness,
) -> bool {
    if orient3d(a, b, c, d) == Sign::Zero {
        return true;
    }
    let (u, v, w) = (sub(b, a), sub(c, a), sub(d, a));
    let six_volume = dot(cross(u, v), w).abs();
    let norm = |n: [f64; 3]| dot(n, n).sqrt();
    let largest_face = [
        cross(u, v),
        cross(u, w),
        cross(v, w),
        cross(sub(c, b), sub(d, b)),
    ]
    .map(norm)
    .into_iter()
    .fold(0.0, f64::max);
    let scale = [a, b, c, d]
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let longest = [u, v, w, sub(c, b), sub(d, b), sub(d, c)]
        .map(norm)
        .into_iter()
        .fold(0.0, f64::max);
    six_volume <= flatness.relative() * scale * largest_face
        && six_volume * longest <= flatness.bend() * largest_face * largest_face
}

/// The surface's triangles with its planar diagonals flipped (see the module docs), and the
/// number of flips; `None` (nothing copied) when no diagonal can be flipped. `points` are the
/// input points, `triangles` index them; `tri` is the tetrahedralisation of (at least) those
/// points.
pub(crate) fn flip_planar_diagonals(
    points: &[[f64; 3]],
    triangles: &[SurfaceTriangle],
    tri: &Triangulation3,
    patches: Patches,
) -> Option<(Vec<SurfaceTriangle>, usize)> {
    if patches == Patches::OneFacet {
        // Nothing to do unless some facet has several triangles (a triangle soup has none).
        let mut facets: Vec<u32> = triangles.iter().map(|t| t.facet).collect();
        facets.sort_unstable();
        if facets.windows(2).all(|w| w[0] != w[1]) {
            return None;
        }
    }
    // A corner that names no point is the caller's error to report (a trusted surface skips
    // the checks): nothing is flipped.
    let n = points.len().min(tri.num_input_points());
    if triangles.iter().flat_map(|t| t.v).any(|i| i as usize >= n) {
        return None;
    }
    let vertex = |i: u32| tri.vertex_of_input(i as usize);
    // Surface edges (by vertex, lower first) and the triangles on each; edges of more than two
    // triangles are never flipped.
    let mut edges: HashMap<(VertexId, VertexId), [u32; 2]> = HashMap::default();
    let key = |a: VertexId, b: VertexId| if a < b { (a, b) } else { (b, a) };
    const NONE: u32 = u32::MAX;
    const MANY: u32 = u32::MAX - 1;
    for (t, tr) in triangles.iter().enumerate() {
        for k in 0..3 {
            let e = key(vertex(tr.v[k]), vertex(tr.v[(k + 1) % 3]));
            let slot = edges.entry(e).or_insert([NONE, NONE]);
            if slot[0] == NONE {
                slot[0] = t as u32;
            } else if slot[1] == NONE {
                slot[1] = t as u32;
            } else {
                *slot = [MANY, MANY];
            }
        }
    }
    let corners = box_corners(points);
    let coplanar = |a, b, c, d| match patches {
        Patches::NearlyCoplanar(flatness) => nearly_flat(a, b, c, d, flatness),
        _ => orient3d(a, b, c, d) == Sign::Zero,
    };
    let mut flips = 0;
    let mut stars = StarSearch::default();
    let mut star = Vec::new();
    let mut in_tri =
        |a: VertexId, b: VertexId| stars.find(tri, a, &mut star, |v| v.contains(&b)).is_some();
    // The edges worth looking at: those between two coplanar triangles allowed to merge (one
    // exact test per edge), and later the edges of the triangles a flip made.
    let p = |i: u32| points[i as usize];
    let mut maybe: Vec<(VertexId, VertexId)> = edges
        .iter()
        .filter(|&(&e, &[t1, t2])| {
            t1 < MANY
                && t2 < MANY
                && Quad::of(triangles, t1 as usize, t2 as usize, e, &vertex).is_some_and(|q| {
                    let (s1, s2) = (triangles[q.t1], triangles[q.t2]);
                    s1.marker == s2.marker
                        && (patches != Patches::OneFacet || s1.facet == s2.facet)
                        && coplanar(p(q.a), p(q.b), p(q.c), p(q.d))
                })
        })
        .map(|(&e, _)| e)
        .collect();
    if maybe.is_empty() {
        return None;
    }
    maybe.sort_unstable();
    let mut triangles = triangles.to_vec();
    let mut near_budget = 16 * edges.len() + 100_000;
    for stage in [Stage::Delaunay, Stage::Tetrahedralisation] {
        let mut queue = maybe.clone();
        while let Some(e) = queue.pop() {
            let Some(&[t1, t2]) = edges.get(&e) else {
                continue;
            };
            if t1 >= MANY || t2 >= MANY {
                continue;
            }
            let Some(q) = Quad::of(&triangles, t1 as usize, t2 as usize, e, &vertex) else {
                continue;
            };
            let (s1, s2) = (triangles[q.t1], triangles[q.t2]);
            if s1.marker != s2.marker || (patches == Patches::OneFacet && s1.facet != s2.facet) {
                continue;
            }
            let (pa, pb, pc, pd) = (p(q.a), p(q.b), p(q.c), p(q.d));
            if edges.contains_key(&key(vertex(q.c), vertex(q.d)))
                || !coplanar(pa, pb, pc, pd)
                || !flippable(pa, pb, pc, pd)
            {
                continue;
            }
            let flip = match stage {
                // The circle test of nearly coplanar points depends on the point off their
                // plane it takes, so that no lifting bounds those flips: they stop after a
                // budget (and the exact ones then end as above).
                Stage::Delaunay => {
                    let exact = orient3d(pa, pb, pc, pd) == Sign::Zero;
                    let flip = (exact || near_budget > 0) && in_circle(pa, pb, pc, pd, &corners);
                    if flip && !exact {
                        near_budget -= 1;
                    }
                    flip
                }
                Stage::Tetrahedralisation => !in_tri(e.0, e.1) && in_tri(vertex(q.c), vertex(q.d)),
            };
            if !flip {
                continue;
            }
            // a b c, b a d  ->  a d c, d b c (both turn as before).
            triangles[q.t1].v = [q.a, q.d, q.c];
            triangles[q.t2].v = [q.d, q.b, q.c];
            edges.remove(&e);
            let (va, vb, vc, vd) = (vertex(q.a), vertex(q.b), vertex(q.c), vertex(q.d));
            edges.insert(key(vc, vd), [q.t1 as u32, q.t2 as u32]);
            // b c moves from t1 to t2, a d from t2 to t1.
            for (x, y, from, to) in [(vb, vc, q.t1, q.t2), (va, vd, q.t2, q.t1)] {
                if let Some(slot) = edges.get_mut(&key(x, y)) {
                    for s in slot.iter_mut() {
                        if *s == from as u32 {
                            *s = to as u32;
                        }
                    }
                }
            }
            let around = [key(va, vc), key(vc, vb), key(vb, vd), key(vd, va)];
            queue.extend(around);
            maybe.extend(around);
            maybe.push(key(vc, vd));
            flips += 1;
        }
        maybe.sort_unstable();
        maybe.dedup();
    }
    (flips > 0).then_some((triangles, flips))
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Stage {
    Delaunay,
    Tetrahedralisation,
}

/// Two triangles `t1 = a b c` and `t2 = b a d` on the edge `a b` (input point indices).
struct Quad {
    t1: usize,
    t2: usize,
    a: u32,
    b: u32,
    c: u32,
    d: u32,
}

impl Quad {
    /// The quadrilateral around edge `e` (by vertex), `None` unless the two triangles run the
    /// edge in opposite directions (a consistently oriented pair).
    fn of(
        triangles: &[SurfaceTriangle],
        t1: usize,
        t2: usize,
        e: (VertexId, VertexId),
        vertex: &impl Fn(u32) -> VertexId,
    ) -> Option<Quad> {
        let f = triangles[t1].v;
        let g = triangles[t2].v;
        let k = (0..3).find(|&k| {
            let (x, y) = (vertex(f[k]), vertex(f[(k + 1) % 3]));
            (x, y) == e || (y, x) == e
        })?;
        let (a, b, c) = (f[k], f[(k + 1) % 3], f[(k + 2) % 3]);
        let j =
            (0..3).find(|&j| vertex(g[j]) == vertex(b) && vertex(g[(j + 1) % 3]) == vertex(a))?;
        Some(Quad {
            t1,
            t2,
            a,
            b,
            c,
            d: g[(j + 2) % 3],
        })
    }
}

/// Whether `a b c` and `b a d`, in one plane (or nearly: the caller decides), turn the same
/// way in it, and `a c b d` is a strictly convex quadrilateral (so that `a d c`, `d b c` cover
/// the same region). Exact on the projection to the plane of two coordinate axes.
fn flippable(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> bool {
    // Drop the coordinate along which the plane's normal is largest: the projection is then an
    // affine bijection of the plane, so orientations keep their signs (up to one common sign).
    let n = cross(sub(b, a), sub(c, a));
    let drop = (0..3)
        .max_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs()))
        .unwrap_or(2);
    let pr = |p: [f64; 3]| match drop {
        0 => [p[1], p[2]],
        1 => [p[2], p[0]],
        _ => [p[0], p[1]],
    };
    let (a, b, c, d) = (pr(a), pr(b), pr(c), pr(d));
    let s = orient2d(a, b, c);
    s != Sign::Zero && orient2d(b, a, d) == s && orient2d(a, d, c) == s && orient2d(d, b, c) == s
}

/// Whether `d` (in the plane of `a, b, c`) lies strictly inside the circle through `a, b, c`:
/// the exact in-sphere test against the sphere through `a, b, c` and a point `e` off their
/// plane (whose intersection with the plane is that circle). `e` is a corner of the points'
/// bounding box: not all eight lie in one plane.
fn in_circle(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3], corners: &[[f64; 3]; 8]) -> bool {
    let n = cross(sub(b, a), sub(c, a));
    let mut order: [usize; 8] = std::array::from_fn(|i| i);
    let height = |e: [f64; 3]| dot(n, sub(e, a)).abs();
    order.sort_by(|&i, &j| height(corners[j]).total_cmp(&height(corners[i])));
    for i in order {
        let e = corners[i];
        let side = orient3d(a, b, c, e);
        if side != Sign::Zero {
            let s = insphere(a, b, c, e, d);
            return if side == Sign::Positive {
                s == Sign::Positive
            } else {
                s == Sign::Negative
            };
        }
    }
    false
}

fn box_corners(points: &[[f64; 3]]) -> [[f64; 3]; 8] {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    std::array::from_fn(|i| [0, 1, 2].map(|k| if i >> k & 1 == 0 { lo[k] } else { hi[k] }))
}
