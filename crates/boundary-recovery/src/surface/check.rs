//! [`check_surface`]: the checks, in the order they run (each stage relies on the ones before,
//! and the first stage that finds offenders reports all of its own).

use super::bvh::Boxes;
use super::error::{
    EdgeName, Listed, PointOnTriangle, SurfaceError, TJunctions, TriangleName, TrianglePair,
};
use super::intersect::{collinear, intersecting_pairs, points_on_triangles, triangle_box, P};
use super::volume::{signed_volume, wind, Surface, Winding};
use super::{CheckedSurface, Junction, SurfaceComponent, SurfaceEdge};
use crate::plc3::{Plc3, SurfaceTriangle};
use crate::union_find::UnionFind;
use delmesh_predicates::{orient3d, Sign, COORDINATE_RANGE};
use rayon::prelude::*;

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
        if let Some(k) = (0..3).find(|&k| p[k] != 0.0 && q[k].abs() < COORDINATE_RANGE.0) {
            return Err(range_error(i, p[k]));
        }
        scaled.push(q);
    }
    Ok((scale, scaled))
}

/// For each point, the first point with exactly its coordinates (found by sorting the
/// coordinates' bits, -0 read as +0): the point each exact duplicate is merged into.
pub fn first_occurrences(points: &[[f64; 3]]) -> Vec<u32> {
    let key = |i: u32| points[i as usize].map(|x| (x + 0.0).to_bits());
    let mut order: Vec<u32> = (0..points.len() as u32).collect();
    order.sort_unstable_by_key(|&i| (key(i), i));
    let mut first: Vec<u32> = (0..points.len() as u32).collect();
    for same in order.chunk_by(|&i, &j| key(i) == key(j)) {
        for &i in same {
            first[i as usize] = same[0];
        }
    }
    first
}

/// Checks that `plc` is a set of closed, orientable, non-intersecting triangle surfaces,
/// orients each consistently, and finds their edges, volumes and nesting.
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
///    write a triangle twice are rare enough that saying so is better. (Two closed solids
///    written one after the other give their common face twice, with opposite orientations:
///    the `delmesh` facade keeps one copy of such a pair when both have one marker, a wall,
///    and says so, before these checks);
/// 5. every edge is used by at least two triangles: an edge of one triangle only is an open
///    boundary, an error listing the edges and their facets. An edge of three or more
///    triangles is a [`Junction`]: where an internal wall between two regions of the domain
///    meets other walls or the outer surface (two blocks sharing a face, as TetGen and gmsh
///    accept for several materials). An edge of two triangles must be traversed in opposite
///    directions. Where two traverse it the same way, triangles are reversed (the fewer of each
///    sheet joined across such edges, listed in [`CheckedSurface::reoriented`]) until none do:
///    CAD meshers orient each patch by its own parametrisation (gmsh does), and the orientation
///    carries nothing the surface needs, since that of each closed surface as a whole is free.
///    Only a one-sided surface cannot be so oriented (an error naming the edges, as given);
/// 6. the points where sheets of the surface touch (the triangles around them form more than
///    one fan: two bodies meeting at a corner, a cone's apex on another body) are found with a
///    union–find over triangle corners across edges, junctions included; they are accepted, as
///    sheets meeting along an edge are (a junction), and the nesting below probes other points;
/// 7. no point lies on a triangle it is not a corner of, and no two triangles intersect other
///    than in what they share, decided exactly (`orient3d`/`orient2d`, no tolerance) for the
///    pairs whose bounding boxes overlap (found through a bounding-volume hierarchy): triangles with no
///    common corner must have no common point (six segment–triangle tests, coplanar overlaps
///    included); triangles sharing a corner must not meet beyond it (their cones at that
///    corner are compared); triangles sharing an edge must not fold onto each other (coplanar
///    with their third corners on the same side of the edge);
/// 8. each connected component without junctions (a closed surface) gets its signed volume
///    `Σ det(a − o, b − o, c − o) / 6` (divergence theorem; `o` the middle of its bounding box;
///    compensated summation). Its sign, the orientation, is certified by a rigorous error
///    bound, and recomputed with exact floating-point expansions when the bound cannot tell
///    (a surface of almost no volume).
///
/// **Nesting.** Once the checks pass, the components are closed surfaces pairwise disjoint but
/// for the points where they touch, so a component lies inside another iff any one of its
/// other points does, and the components around one component form a chain. Each component's
/// first point where it touches no other (or, if it touches others at every corner, the centre
/// of its first triangle) is tested against the others by
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
/// **Walls.** A surface with junctions bounds several regions, and a ray crossing a wall
/// passes from one region of the domain to another, not out of it: neither volumes nor nesting
/// are computed for it ([`CheckedSurface::has_walls`]). The mesher's flood fill decides, on the
/// tetrahedra, with the same rule: a region is in the domain when the fewest surfaces crossed
/// to reach it from outside is odd.
///
/// # Errors
/// The first failing stage's [`SurfaceError`], listing its offenders.
pub fn check_surface(plc: &Plc3) -> Result<CheckedSurface, SurfaceError> {
    let base = u64::from(plc.first_index);
    let n_input = plc.points.len();
    if plc.triangles.is_empty() {
        return Err(SurfaceError::NoTriangles { points: n_input });
    }
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

    // Merge exact duplicates: each maps to its first occurrence.
    let first = first_occurrences(&plc.points);
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
    let mut tv: Vec<[u32; 3]> = plc
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

    let facet_of = |t: u32| u64::from(plc.triangles[t as usize].facet) + base;
    let edge_name = |lo: u32, group: &[(u32, u32, bool)]| {
        let hi = group[0].0;
        let points = if group[0].2 { [lo, hi] } else { [hi, lo] };
        EdgeName {
            points: points.map(point_name),
            facets: group.iter().map(|g| facet_of(g.1)).collect(),
        }
    };
    let listed = |mut v: Vec<(u32, EdgeName)>| {
        v.sort_by_key(|x| x.0);
        Listed::of(v.into_iter().map(|x| x.1).collect())
    };
    // A second pass runs after triangles were reoriented.
    let mut reoriented: Option<Vec<u32>> = None;
    let nv = points.len();
    let mut junctions: Vec<Junction> = Vec::new();
    let edges = loop {
        let (start, mut uses) = edge_uses(&tv, nv);
        let (mut open, mut flipped) = (Vec::new(), Vec::new());
        junctions.clear();
        // The triangles on each side of each manifold edge, and whether both traverse it the
        // same way.
        let mut pairs = Vec::with_capacity(uses.len() / 2);
        let mut edges = Vec::with_capacity(uses.len() / 2);
        for lo in 0..nv {
            let around = &mut uses[start[lo] as usize..start[lo + 1] as usize];
            around.sort_unstable_by_key(|x| (x.0, x.1));
            let lo = lo as u32;
            for group in around.chunk_by(|x, y| x.0 == y.0) {
                match group.len() {
                    1 => open.push((group[0].1, edge_name(lo, group), [lo, group[0].0])),
                    2 => {
                        let same = group[0].2 == group[1].2;
                        pairs.push((group[0].1, group[1].1, same));
                        if same {
                            flipped.push((group[0].1, edge_name(lo, group)));
                        } else {
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
                    }
                    _ => junctions.push(Junction {
                        v: [lo, group[0].0],
                        triangles: group.iter().map(|g| g.1).collect(),
                    }),
                }
            }
        }
        if !open.is_empty() {
            open.sort_by_key(|x| x.0);
            // The listed edges with a point strictly inside (exact collinearity, then between
            // the ends along an axis where they differ): a T-junction, named as such.
            let t_junctions = open
                .iter()
                .take(Listed::<EdgeName>::MAX_SHOWN)
                .filter_map(|&(_, _, [a, b])| {
                    let (pa, pb) = (spts[a as usize], spts[b as usize]);
                    let k = (0..3).find(|&k| pa[k] != pb[k])?;
                    let inside = (0..spts.len() as u32).into_par_iter().find_first(|&v| {
                        let x = spts[v as usize];
                        pa[k].min(pb[k]) < x[k] && x[k] < pa[k].max(pb[k]) && collinear(pa, pb, x)
                    })?;
                    Some((point_name(inside), [point_name(a), point_name(b)]))
                })
                .collect();
            return Err(SurfaceError::OpenEdges {
                edges: listed(open.into_iter().map(|x| (x.0, x.1)).collect()),
                t_junctions: TJunctions(t_junctions),
            });
        }
        if flipped.is_empty() {
            break edges;
        }
        match (&reoriented, orientation_flips(tv.len(), &pairs)) {
            (None, Some(flips)) => {
                for &t in &flips {
                    tv[t as usize].swap(1, 2);
                }
                reoriented = Some(flips);
            }
            _ => {
                return Err(SurfaceError::InconsistentOrientation {
                    edges: listed(flipped),
                })
            }
        }
    };
    let reoriented = reoriented.unwrap_or_default();

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
    for j in &junctions {
        for &t in &j.triangles[1..] {
            for v in j.v {
                fans.union(corner(j.triangles[0], v), corner(t, v));
            }
            parts.union(j.triangles[0], t);
        }
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
        // Pairs in one plane: most often a face two bodies share, given by each (cut along
        // different diagonals), which the message then says.
        let in_plane = |i: u32, j: u32| {
            let [a, b, c] = tv[i as usize].map(|v| spts[v as usize]);
            tv[j as usize]
                .iter()
                .all(|&v| orient3d(a, b, c, spts[v as usize]) == Sign::Zero)
        };
        return Err(SurfaceError::SelfIntersection {
            coplanar: crossing.iter().filter(|&&(i, j)| in_plane(i, j)).count(),
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
    let mut walled = vec![false; members.len()];
    for j in &junctions {
        walled[triangle_component[j.triangles[0] as usize] as usize] = true;
    }
    let mut components: Vec<SurfaceComponent> = members
        .into_iter()
        .zip(walled)
        .map(|(tris, walls)| {
            if walls {
                // Several regions: no one enclosed volume (see `SurfaceComponent::walls`).
                return SurfaceComponent {
                    triangles: tris,
                    volume: 0.0,
                    outward: false,
                    depth: 0,
                    parent: None,
                    walls,
                };
            }
            let own: Vec<[u32; 3]> = tris.iter().map(|&t| tv[t as usize]).collect();
            let (v, sign) = signed_volume(&spts, &own);
            debug_assert!(sign != Sign::Zero, "a closed embedded surface has volume");
            SurfaceComponent {
                triangles: tris,
                volume: v * unscale * unscale * unscale,
                outward: sign == Sign::Positive,
                depth: 0,
                parent: None,
                walls,
            }
        })
        .collect();

    // Nesting: the components are closed surfaces disjoint but for the points where they
    // touch, so one is inside another iff any of its other points is. A surface with walls
    // has no winding number: its nesting is left to the flood fill of the mesh.
    if junctions.is_empty() {
        let surface = Surface {
            pts: &spts,
            tris: &tv,
            component: &triangle_component,
        };
        let mut winding = Winding::new(components.len());
        let containers: Vec<Vec<u32>> = (0..components.len())
            .map(|c| {
                let probe = probe_point(&spts, &tv, &components[c].triangles, &is_pinched);
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
        reoriented,
        triangles,
        edges,
        junctions,
        triangle_component,
        components,
        first_index: plc.first_index,
        scale,
        scaled: spts,
        corners: tv,
        boxes,
    })
}

/// A point of the closed surface made of `triangles` that no other surface touches: a corner
/// where the surface is not pinched, or, if every corner is, the centre of the first triangle
/// (inside it, so on no other surface: the triangles do not intersect).
fn probe_point(spts: &[P], tv: &[[u32; 3]], triangles: &[u32], pinched: &[bool]) -> P {
    let mut corners = triangles.iter().flat_map(|&t| tv[t as usize]);
    if let Some(v) = corners.find(|&v| !pinched[v as usize]) {
        return spts[v as usize];
    }
    let [a, b, c] = tv[triangles[0] as usize].map(|v| spts[v as usize]);
    std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0)
}

/// The directed uses `(other end, triangle, lo → hi?)` of each undirected edge of the
/// triangles, bucketed by its lower end (a counting sort): the uses of the edges at `lo` are
/// `uses[start[lo]..start[lo + 1]]`.
fn edge_uses(tv: &[[u32; 3]], nv: usize) -> (Vec<u32>, Vec<(u32, u32, bool)>) {
    let mut start = vec![0u32; nv + 1];
    for t in tv {
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
    (start, uses)
}

/// The triangles to reverse so that every closed surface is consistently oriented, given the
/// pairs of triangles across each edge `(t1, t2, both traverse it the same way?)`; in each
/// component the fewer triangles are reversed (on a tie, those not oriented as its first).
/// `None` if a component is one-sided (no flips make it consistent). Sorted.
fn orientation_flips(n: usize, pairs: &[(u32, u32, bool)]) -> Option<Vec<u32>> {
    let mut start = vec![0usize; n + 1];
    for &(a, b, _) in pairs {
        start[a as usize + 1] += 1;
        start[b as usize + 1] += 1;
    }
    for t in 0..n {
        start[t + 1] += start[t];
    }
    let mut next = vec![(0u32, false); start[n]];
    let mut fill = start.clone();
    for &(a, b, same) in pairs {
        next[fill[a as usize]] = (b, same);
        fill[a as usize] += 1;
        next[fill[b as usize]] = (a, same);
        fill[b as usize] += 1;
    }
    // Whether each triangle is reversed relative to the first of its component.
    let mut reversed: Vec<Option<bool>> = vec![None; n];
    let mut flips = Vec::new();
    for seed in 0..n {
        if reversed[seed].is_some() {
            continue;
        }
        reversed[seed] = Some(false);
        let mut component = vec![seed as u32];
        let mut k = 0;
        while k < component.len() {
            let t = component[k] as usize;
            let r = reversed[t] == Some(true);
            for &(u, same) in &next[start[t]..start[t + 1]] {
                // Across an edge traversed the same way, exactly one of the two is reversed.
                let want = r != same;
                match reversed[u as usize] {
                    None => {
                        reversed[u as usize] = Some(want);
                        component.push(u);
                    }
                    Some(got) if got != want => return None,
                    Some(_) => {}
                }
            }
            k += 1;
        }
        let n_reversed = component
            .iter()
            .filter(|&&t| reversed[t as usize] == Some(true))
            .count();
        let flip = n_reversed <= component.len() - n_reversed;
        flips.extend(
            component
                .into_iter()
                .filter(|&t| (reversed[t as usize] == Some(true)) == flip),
        );
    }
    flips.sort_unstable();
    Some(flips)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fewer_triangles_of_each_component_are_reversed() {
        // Component {0, 1, 2}: 1 is reversed relative to 0 and 2. Component {3, 4}: a tie,
        // so 4 (not oriented as 3) is reversed.
        let pairs = [(0, 1, true), (1, 2, true), (0, 2, false), (3, 4, true)];
        assert_eq!(orientation_flips(5, &pairs), Some(vec![1, 4]));
        // Two against one: the one goes, even when it comes first.
        let pairs = [(0, 1, true), (0, 2, true), (1, 2, false)];
        assert_eq!(orientation_flips(3, &pairs), Some(vec![0]));
    }

    #[test]
    fn a_one_sided_cycle_cannot_be_oriented() {
        // Around a cycle of three triangles, an odd number of edges traversed the same way.
        let pairs = [(0, 1, true), (1, 2, false), (2, 0, false)];
        assert_eq!(orientation_flips(3, &pairs), None);
    }

    /// The unit cube, 12 triangles oriented outward.
    fn cube() -> (Vec<P>, Vec<[u32; 3]>) {
        let p = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        let t = vec![
            [0, 2, 1],
            [1, 2, 3],
            [4, 5, 6],
            [5, 7, 6],
            [0, 1, 4],
            [1, 5, 4],
            [2, 6, 3],
            [3, 6, 7],
            [0, 4, 2],
            [2, 4, 6],
            [1, 3, 5],
            [3, 7, 5],
        ];
        (p, t)
    }

    #[test]
    fn patches_oriented_each_their_own_way_are_accepted() {
        // As gmsh writes an extrusion: the faces z = 0 and x = 0 (triangles 0, 1, 8, 9) keep
        // the orientation of their own parametrisation, inward.
        let (p, mut t) = cube();
        let right = check_surface(&Plc3::from_triangles(p.clone(), &t)).unwrap();
        for k in [0, 1, 8, 9] {
            t[k].swap(1, 2);
        }
        let s = check_surface(&Plc3::from_triangles(p.clone(), &t)).unwrap();
        assert_eq!(s.reoriented, vec![0, 1, 8, 9]);
        assert_eq!(s.edges, right.edges);
        assert_eq!(s.components, right.components);
        assert!(s.components[0].outward && s.components[0].volume == 1.0);
        // Eight of twelve reversed: the other four are, and the cube comes out inward.
        for t in t.iter_mut() {
            t.swap(1, 2);
        }
        let s = check_surface(&Plc3::from_triangles(p, &t)).unwrap();
        assert_eq!(s.reoriented, vec![0, 1, 8, 9]);
        assert!(!s.components[0].outward && s.components[0].volume == -1.0);
    }
}
