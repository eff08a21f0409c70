//! [`check_surface`]: the checks, in the order they run (each stage relies on the ones before,
//! and the first stage that finds offenders reports all of its own).

use super::error::{
    EdgeName, Listed, PointOnTriangle, SurfaceError, TriangleName, TrianglePair, VertexName,
};
use super::grid::Grid;
use super::intersect::{collinear, intersecting_pairs, points_on_triangles, triangle_box, P};
use super::volume::{signed_volume, Columns, Surface, Winding};
use super::{CheckedSurface, SurfaceComponent, SurfaceEdge};
use crate::plc3::{Plc3, SurfaceTriangle};
use delmesh_predicates::{Sign, COORDINATE_RANGE};
use std::collections::HashMap;

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

/// Checks `plc` (see the [module docs](super)).
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

    // Merge exact duplicates: each maps to its first occurrence.
    let mut first: HashMap<[u64; 3], u32> = HashMap::with_capacity(n_input);
    let mut vertex_of_input = Vec::with_capacity(n_input);
    let mut input_index = Vec::new();
    let mut merged = Vec::new();
    for (i, p) in plc.points.iter().enumerate() {
        let key = p.map(|x| (x + 0.0).to_bits());
        let next = input_index.len() as u32;
        let v = *first.entry(key).or_insert(next);
        if v == next {
            input_index.push(i as u32);
        } else {
            merged.push((i as u32, input_index[v as usize]));
        }
        vertex_of_input.push(v);
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

    // Edges: directed uses, grouped by the undirected edge.
    let mut uses: Vec<(u64, u32, bool)> = Vec::with_capacity(3 * tv.len());
    for (k, t) in tv.iter().enumerate() {
        for i in 0..3 {
            let (u, w) = (t[i], t[(i + 1) % 3]);
            let key = u64::from(u.min(w)) << 32 | u64::from(u.max(w));
            uses.push((key, k as u32, u < w));
        }
    }
    uses.sort_unstable();
    let facet_of = |t: u32| u64::from(plc.triangles[t as usize].facet) + base;
    let edge_name = |key: u64, group: &[(u64, u32, bool)]| {
        let (lo, hi) = ((key >> 32) as u32, key as u32);
        let points = if group[0].2 { [lo, hi] } else { [hi, lo] };
        EdgeName {
            points: points.map(point_name),
            facets: group.iter().map(|g| facet_of(g.1)).collect(),
        }
    };
    let (mut open, mut non_manifold, mut flipped) = (Vec::new(), Vec::new(), Vec::new());
    let mut edges = Vec::with_capacity(uses.len() / 2);
    for group in uses.chunk_by(|x, y| x.0 == y.0) {
        let key = group[0].0;
        match group.len() {
            1 => open.push((group[0].1, edge_name(key, group))),
            2 if group[0].2 == group[1].2 => flipped.push((group[0].1, edge_name(key, group))),
            2 => {
                let (fwd, back) = if group[0].2 {
                    (group[0].1, group[1].1)
                } else {
                    (group[1].1, group[0].1)
                };
                edges.push(SurfaceEdge {
                    v: [(key >> 32) as u32, key as u32],
                    triangles: [fwd, back],
                });
            }
            _ => non_manifold.push((group[0].1, edge_name(key, group))),
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
    let mut corners: Vec<(u32, u32, u32)> = (0..3 * tv.len() as u32)
        .map(|c| (tv[c as usize / 3][c as usize % 3], fans.find(c), c / 3))
        .collect();
    corners.sort_unstable();
    let mut pinched = Vec::new();
    for around in corners.chunk_by(|x, y| x.0 == y.0) {
        if around.first().map(|x| x.1) != around.last().map(|x| x.1) {
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
    let boxes: Vec<_> = tv.iter().map(|&t| triangle_box(&spts, t)).collect();
    let grid = Grid::new(&boxes);
    let on = points_on_triangles(&spts, 0..spts.len() as u32, &tv, &boxes, &grid);
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
    let crossing = intersecting_pairs(&spts, &tv, &boxes, &grid);
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
    let columns = Columns::new(&spts, &tv);
    let surface = Surface {
        pts: &spts,
        tris: &tv,
        component: &triangle_component,
    };
    let mut winding = Winding::new(components.len());
    let containers: Vec<Vec<u32>> = (0..components.len())
        .map(|c| {
            let probe = spts[tv[components[c].triangles[0] as usize][0] as usize];
            let on = columns.wind(surface, c as u32, probe, false, &mut winding);
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
        columns,
    })
}
