//! [`check_surface`]: the checks, in the order they run (each stage relies on the ones before,
//! and the first stage that finds offenders reports all of its own).

use super::bvh::Boxes;
use super::error::{
    EdgeName, Listed, PointOnTriangle, SurfaceError, TriangleName, TrianglePair, VertexName,
};
use super::intersect::{collinear, intersecting_pairs, points_on_triangles, triangle_box, P};
use super::volume::{signed_volume, wind, Surface, Winding};
use super::{CheckedSurface, SurfaceComponent, SurfaceEdge};
use crate::plc3::{Plc3, SurfaceTriangle};
use delmesh_predicates::{Sign, COORDINATE_RANGE};

/// Union–find with path halving.
struct UnionFind(Vec<u32>);

impl UnionFind {
    fn new(n: usize) -> UnionFind {
        UnionFind((0..n as u32).collect())
    }

    fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let up = self.0[self.0[x as usize] as usize];
            self.0[x as usize] = up;
            x = up;
        }
        x
    }

    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.0[hi as usize] = lo;
        }
    }
}

/// The power-of-two scale bringing the largest coordinate magnitude into `[0.5, 1)` and the
/// scaled points; checks that every coordinate is finite and, scaled, either zero or at least
/// the predicates' smallest exact magnitude.
pub(crate) fn scaled_points(points: &[P], base: u64) -> Result<(f64, Vec<P>), SurfaceError> {
    let mut largest = 0.0f64;
    for (i, p) in points.iter().enumerate() {
        if p.iter().any(|x| !x.is_finite()) {
            return Err(SurfaceError::NonFinite {
                point: i as u64 + base,
            });
        }
        largest = p.iter().fold(largest, |m, x| m.max(x.abs()));
    }
    let scale = if largest == 0.0 {
        1.0
    } else {
        2f64.powi(-(largest.log2().floor() as i32 + 1))
    };
    let range_error = |i: usize, value: f64| SurfaceError::CoordinateRange {
        point: i as u64 + base,
        value,
        largest,
    };
    if !scale.is_normal() || !(1.0 / scale).is_normal() {
        let i = points
            .iter()
            .position(|p| p.iter().any(|x| x.abs() == largest))
            .unwrap_or(0);
        return Err(range_error(i, largest));
    }
    let mut scaled = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        let q = p.map(|x| x * scale);
        if let Some(k) = (0..3).find(|&k| q[k] != 0.0 && q[k].abs() < COORDINATE_RANGE.0) {
            return Err(range_error(i, p[k]));
        }
        scaled.push(q);
    }
    Ok((scale, scaled))
}

/// Checks that `plc` is a set of closed, consistently oriented, non-intersecting triangle
/// surfaces, and finds their edges, volumes and nesting.
///
/// What it does, in order (the first stage that finds offenders reports all of
/// its own; see [`SurfaceError`] for the messages):
/// 1. coordinates are finite and within the exact predicates' range (after scaling by a power
///    of two, which is exact); corner indices exist;
/// 2. exactly duplicate points are merged, each into its first occurrence, and reported in
///    [`CheckedSurface::merged`] (not an error: exporters repeat points at patch seams);
/// 3. degenerate triangles are errors: a repeated corner (after merging) or three exactly
///    collinear corners;
/// 4. duplicated triangles (the same three corners, either orientation) are errors. A closed
///    surface has each triangle once; the copies may carry different markers (which boundary
///    condition is meant?), and a copy with the opposite orientation is a zero-thickness wall,
///    which changes the domain. Silently dropping them could hide either, and exporters that
///    write a triangle twice are rare enough that saying so is better;
/// 5. every edge is used by exactly two triangles (non-manifold edges and open boundaries are
///    errors listing the edges and their facets) that traverse it in opposite directions
///    (inconsistent orientation names the edge and both facets). The orientation of each closed
///    surface as a whole is free;
/// 6. the triangles around each point form a single fan: two sheets touching at a point are an
///    error (found with a union–find over triangle corners across edges);
/// 7. no point lies on a triangle it is not a corner of, and no two triangles intersect other
///    than in what they share, decided exactly (`orient3d`/`orient2d`, no tolerance) for the
///    pairs whose bounding boxes overlap (found through a bounding-volume hierarchy): triangles with no
///    common corner must have no common point (six segment–triangle tests, coplanar overlaps
///    included); triangles sharing a corner must not meet beyond it (their cones at that
///    corner are compared); triangles sharing an edge must not fold onto each other (coplanar
///    with their third corners on the same side of the edge);
/// 8. each connected component (a closed surface) gets its signed volume
///    `Σ det(a − o, b − o, c − o) / 6` (divergence theorem; `o` the middle of its bounding box;
///    compensated summation). Its sign, the orientation, is certified by a rigorous error
///    bound, and recomputed with exact floating-point expansions when the bound cannot tell
///    (a surface of almost no volume).
///
/// **Nesting.** Once the checks pass, the components are pairwise disjoint closed surfaces, so
/// a component lies inside another iff any one of its points does, and the components around
/// one component form a chain. Each component's first point is tested against the others by
/// the winding number of an exactly counted ray: along `+x` from the point moved by the
/// infinitesimal `(0, ε, ε²)`. Whether it crosses a triangle is `orient2d` in the `(y, z)`
/// projection, a zero resolved by the first non-zero term of the perturbation (which never
/// vanishes for an edge that projects to a segment), and whether the crossing is ahead is
/// `orient3d`. Rays through edges, vertices or along faces are so counted consistently (two
/// triangles sharing an edge get the same answer for it): no direction is unlucky, there is
/// no retry. A component's depth is the number of components around it; the domain (without
/// hole seeds) is what lies inside an odd number of surfaces:
/// [`CheckedSurface::domain_volume`].
///
/// # Errors
/// The first failing stage's [`SurfaceError`], listing its offenders.
pub fn check_surface(plc: &Plc3) -> Result<CheckedSurface, SurfaceError> {
    let base = u64::from(plc.first_index);
    let n_input = plc.points.len();
    let (scale, scaled_input) = scaled_points(&plc.points, base)?;
    for (what, seeds) in [
        ("hole", plc.holes.clone()),
        ("region", plc.regions.iter().map(|r| r.point).collect()),
    ] {
        if let Some(i) = seeds.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
            return Err(SurfaceError::BadSeed {
                what,
                index: i as u64 + base,
            });
        }
    }
    if !plc.point_markers.is_empty() && plc.point_markers.len() != n_input {
        return Err(SurfaceError::PointMarkerCount {
            markers: plc.point_markers.len(),
            points: n_input,
        });
    }

    // Merge exact duplicates: each maps to its first occurrence (sorting by the coordinates'
    // bits, -0 read as +0).
    let key = |i: usize| plc.points[i].map(|x| (x + 0.0).to_bits());
    let mut order: Vec<u32> = (0..n_input as u32).collect();
    order.sort_unstable_by_key(|&i| (key(i as usize), i));
    let mut first = vec![0u32; n_input];
    for same in order.chunk_by(|&i, &j| key(i as usize) == key(j as usize)) {
        for &i in same {
            first[i as usize] = same[0];
        }
    }
    let mut vertex_of_input = vec![0u32; n_input];
    let mut input_index = Vec::new();
    let mut merged = Vec::new();
    for i in 0..n_input {
        let f = first[i] as usize;
        if f == i {
            vertex_of_input[i] = input_index.len() as u32;
            input_index.push(i as u32);
        } else {
            vertex_of_input[i] = vertex_of_input[f];
            merged.push((i as u32, f as u32));
        }
    }
    let points: Vec<P> = input_index
        .iter()
        .map(|&i| plc.points[i as usize])
        .collect();
    let spts: Vec<P> = input_index
        .iter()
        .map(|&i| scaled_input[i as usize])
        .collect();
    let point_name = |v: u32| u64::from(input_index[v as usize]) + base;

    // Corner indices.
    for t in &plc.triangles {
        if let Some(&v) = t.v.iter().find(|&&v| v as usize >= n_input) {
            return Err(SurfaceError::BadIndex {
                facet: u64::from(t.facet) + base,
                point: u64::from(v) + base,
                n_points: n_input,
            });
        }
    }
    let tname = |k: usize| {
        let t = &plc.triangles[k];
        TriangleName {
            facet: u64::from(t.facet) + base,
            points: t.v.map(|v| u64::from(v) + base),
        }
    };
    let tv: Vec<[u32; 3]> = plc
        .triangles
        .iter()
        .map(|t| t.v.map(|v| vertex_of_input[v as usize]))
        .collect();

    // Degenerate triangles.
    let repeated: Vec<_> = (0..tv.len())
        .filter(|&k| {
            let [a, b, c] = tv[k];
            a == b || b == c || a == c
        })
        .map(tname)
        .collect();
    if !repeated.is_empty() {
        return Err(SurfaceError::RepeatedCorner {
            triangles: Listed::of(repeated),
        });
    }
    let flat: Vec<_> = (0..tv.len())
        .filter(|&k| {
            let [a, b, c] = tv[k].map(|v| spts[v as usize]);
            collinear(a, b, c)
        })
        .map(tname)
        .collect();
    if !flat.is_empty() {
        return Err(SurfaceError::Collinear {
            triangles: Listed::of(flat),
        });
    }

    // Duplicated triangles (same corner set, either orientation).
    let mut by_set: Vec<([u32; 3], u32)> = tv
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let mut s = *t;
            s.sort_unstable();
            (s, k as u32)
        })
        .collect();
    by_set.sort_unstable();
    let mut dups: Vec<(u32, u32)> = Vec::new(); // (duplicate, first)
    for w in by_set.chunk_by(|x, y| x.0 == y.0) {
        for x in &w[1..] {
            dups.push((x.1, w[0].1));
        }
    }
    if !dups.is_empty() {
        dups.sort_unstable();
        return Err(SurfaceError::DuplicateTriangles {
            pairs: Listed::of(
                dups.iter()
                    .map(|&(d, f)| TrianglePair {
                        first: tname(f as usize),
                        second: tname(d as usize),
                    })
                    .collect(),
            ),
        });
    }

    // Edges: the directed uses `(other end, triangle, lo → hi?)` of each undirected edge,
    // bucketed by its lower end (a counting sort), then sorted within each bucket.
    let nv = points.len();
    let mut start = vec![0u32; nv + 1];
    for t in &tv {
        for i in 0..3 {
            start[t[i].min(t[(i + 1) % 3]) as usize + 1] += 1;
        }
    }
    for v in 0..nv {
        start[v + 1] += start[v];
    }
    let mut uses = vec![(0u32, 0u32, false); 3 * tv.len()];
    let mut fill = start.clone();
    for (k, t) in tv.iter().enumerate() {
        for i in 0..3 {
            let (u, w) = (t[i], t[(i + 1) % 3]);
            let lo = u.min(w) as usize;
            uses[fill[lo] as usize] = (u.max(w), k as u32, u < w);
            fill[lo] += 1;
        }
    }
    drop(fill);
    let facet_of = |t: u32| u64::from(plc.triangles[t as usize].facet) + base;
    let edge_name = |lo: u32, group: &[(u32, u32, bool)]| {
        let hi = group[0].0;
        let points = if group[0].2 { [lo, hi] } else { [hi, lo] };
        EdgeName {
            points: points.map(point_name),
            facets: group.iter().map(|g| facet_of(g.1)).collect(),
        }
    };
    let (mut open, mut non_manifold, mut flipped) = (Vec::new(), Vec::new(), Vec::new());
    let mut edges = Vec::with_capacity(uses.len() / 2);
    for lo in 0..nv {
        let around = &mut uses[start[lo] as usize..start[lo + 1] as usize];
        around.sort_unstable_by_key(|x| (x.0, x.1));
        let lo = lo as u32;
        for group in around.chunk_by(|x, y| x.0 == y.0) {
            match group.len() {
                1 => open.push((group[0].1, edge_name(lo, group))),
                2 if group[0].2 == group[1].2 => {
                    flipped.push((group[0].1, edge_name(lo, group)));
                }
                2 => {
                    let (fwd, back) = if group[0].2 {
                        (group[0].1, group[1].1)
                    } else {
                        (group[1].1, group[0].1)
                    };
                    edges.push(SurfaceEdge {
                        v: [lo, group[0].0],
                        triangles: [fwd, back],
                    });
                }
                _ => non_manifold.push((group[0].1, edge_name(lo, group))),
            }
        }
    }
    let listed = |mut v: Vec<(u32, EdgeName)>| {
        v.sort_by_key(|x| x.0);
        Listed::of(v.into_iter().map(|x| x.1).collect())
    };
    if !non_manifold.is_empty() {
        return Err(SurfaceError::NonManifoldEdges {
            edges: listed(non_manifold),
        });
    }
    if !open.is_empty() {
        return Err(SurfaceError::OpenEdges {
            edges: listed(open),
        });
    }
    if !flipped.is_empty() {
        return Err(SurfaceError::InconsistentOrientation {
            edges: listed(flipped),
        });
    }

    // Fans around each vertex: corners `3t + i` joined across the edges at their vertex; and
    // components: triangles joined across edges.
    let corner = |t: u32, v: u32| {
        let i = tv[t as usize]
            .iter()
            .position(|&u| u == v)
            .expect("an edge's triangle contains its ends: a bug in delmesh");
        3 * t + i as u32
    };
    let mut fans = UnionFind::new(3 * tv.len());
    let mut parts = UnionFind::new(tv.len());
    for e in &edges {
        let [t1, t2] = e.triangles;
        for v in e.v {
            fans.union(corner(t1, v), corner(t2, v));
        }
        parts.union(t1, t2);
    }
    // A point is pinched when its corners have more than one root.
    let mut root_at = vec![u32::MAX; nv];
    let mut is_pinched = vec![false; nv];
    for c in 0..3 * tv.len() as u32 {
        let (v, r) = (tv[c as usize / 3][c as usize % 3] as usize, fans.find(c));
        if root_at[v] == u32::MAX {
            root_at[v] = r;
        } else if root_at[v] != r {
            is_pinched[v] = true;
        }
    }
    let mut pinched = Vec::new();
    if is_pinched.contains(&true) {
        let mut corners: Vec<(u32, u32, u32)> = (0..3 * tv.len() as u32)
            .map(|c| (tv[c as usize / 3][c as usize % 3], c, c / 3))
            .filter(|x| is_pinched[x.0 as usize])
            .map(|(v, c, t)| (v, fans.find(c), t))
            .collect();
        corners.sort_unstable();
        for around in corners.chunk_by(|x, y| x.0 == y.0) {
            let fans: Vec<Vec<u64>> = around
                .chunk_by(|x, y| x.1 == y.1)
                .map(|fan| {
                    let mut f: Vec<u64> = fan.iter().map(|x| facet_of(x.2)).collect();
                    f.sort_unstable();
                    f.dedup();
                    f
                })
                .collect();
            pinched.push(VertexName {
                point: point_name(around[0].0),
                fans,
            });
        }
    }
    if !pinched.is_empty() {
        pinched.sort_by_key(|x| x.point);
        return Err(SurfaceError::NonManifoldVertices {
            vertices: Listed::of(pinched),
        });
    }

    // Geometry: points on triangles, then intersecting pairs.
    let boxes = Boxes::new(tv.iter().map(|&t| triangle_box(&spts, t)).collect());
    let on = points_on_triangles(&spts, 0..spts.len() as u32, &tv, &boxes);
    if !on.is_empty() {
        return Err(SurfaceError::PointOnTriangle {
            hits: Listed::of(
                on.iter()
                    .map(|&(v, t)| PointOnTriangle {
                        point: point_name(v),
                        triangle: tname(t as usize),
                    })
                    .collect(),
            ),
        });
    }
    let crossing = intersecting_pairs(&spts, &tv, &boxes);
    if !crossing.is_empty() {
        return Err(SurfaceError::SelfIntersection {
            pairs: Listed::of(
                crossing
                    .iter()
                    .map(|&(i, j)| TrianglePair {
                        first: tname(i as usize),
                        second: tname(j as usize),
                    })
                    .collect(),
            ),
        });
    }

    // Components, numbered in the order of their first triangle.
    let mut id_of_root = vec![u32::MAX; tv.len()];
    let mut triangle_component = Vec::with_capacity(tv.len());
    let mut members: Vec<Vec<u32>> = Vec::new();
    for t in 0..tv.len() as u32 {
        let r = parts.find(t) as usize;
        if id_of_root[r] == u32::MAX {
            id_of_root[r] = members.len() as u32;
            members.push(Vec::new());
        }
        triangle_component.push(id_of_root[r]);
        members[id_of_root[r] as usize].push(t);
    }
    let unscale = 1.0 / scale;
    let mut components: Vec<SurfaceComponent> = members
        .into_iter()
        .map(|tris| {
            let own: Vec<[u32; 3]> = tris.iter().map(|&t| tv[t as usize]).collect();
            let (v, sign) = signed_volume(&spts, &own);
            debug_assert!(sign != Sign::Zero, "a closed embedded surface has volume");
            SurfaceComponent {
                triangles: tris,
                volume: v * unscale * unscale * unscale,
                outward: sign == Sign::Positive,
                depth: 0,
                parent: None,
            }
        })
        .collect();

    // Nesting: the components are disjoint closed surfaces, so one is inside another iff any
    // of its points is.
    let surface = Surface {
        pts: &spts,
        tris: &tv,
        component: &triangle_component,
    };
    let mut winding = Winding::new(components.len());
    let containers: Vec<Vec<u32>> = (0..components.len())
        .map(|c| {
            let probe = spts[tv[components[c].triangles[0] as usize][0] as usize];
            let on = wind(surface, &boxes, c as u32, probe, false, &mut winding);
            debug_assert!(on.is_none(), "components are disjoint");
            winding.take_nonzero()
        })
        .collect();
    for (c, around) in containers.iter().enumerate() {
        components[c].depth = around.len() as u32;
        components[c].parent = around
            .iter()
            .copied()
            .max_by_key(|&p| containers[p as usize].len());
    }

    let triangles = plc
        .triangles
        .iter()
        .zip(&tv)
        .map(|(t, &v)| SurfaceTriangle {
            v,
            marker: t.marker,
            facet: t.facet,
        })
        .collect();
    Ok(CheckedSurface {
        points,
        input_index,
        vertex_of_input,
        merged,
        triangles,
        edges,
        triangle_component,
        components,
        first_index: plc.first_index,
        scale,
        scaled: spts,
        corners: tv,
        boxes,
    })
}
