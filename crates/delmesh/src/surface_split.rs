//! Surface triangles split to a spacing before the 3D pipeline runs: next to a region with a
//! volume limit (as TetGen splits the boundary its `-a` refinement encroaches), and everywhere
//! a spacing for the surface is asked ([`MeshOptions3::surface_spacing`]).
//!
//! A surface triangle much larger than the spacing asked makes the tetrahedra on it flat: a
//! 12-triangle unit cube limited to 1e-4 gave 72,796 slivers in 270,158 tetrahedra, and a
//! CAD cylinder whose sides are triangles 80 times longer than wide gives half its tetrahedra
//! under 5°. So every triangle to split is meshed in its own plane by the 2D pipeline at its
//! spacing, each edge split into the same equal pieces for both triangles sharing it, so that
//! the new surface conforms. New triangles keep their triangle's marker and facet. For volume
//! limits, a first recovery (of the surface alone) tells which regions each facet bounds
//! ([`facet_caps`]).
//!
//! [`MeshOptions3::surface_spacing`]: crate::mesh3d::MeshOptions3::surface_spacing

use rustc_hash::FxHashMap as HashMap;

use delmesh_boundary_recovery::{
    first_occurrences, Mesh3, Plc2, Plc3, RecoveryMethod, Segment, SurfaceTriangle,
};
use delmesh_delaunay_core::VertexId;
use delmesh_point_gen::{graded_splits, PointGeneration, Source, Source3};
use rayon::prelude::*;

use crate::geometry3::{cross, dist, dot, sub};
use crate::mesh2d::{mesh_plc, MeshOptions2};
use crate::Error;
use delmesh_predicates::{orient3d, Sign};

/// The finest spacing asked of each facet (by facet id): the smallest cap (by region index) of
/// the regions on either side of its faces in `mesh`; facets with none are left out.
pub(crate) fn facet_caps(mesh: &Mesh3, caps: &[f64]) -> HashMap<u32, f64> {
    let mut facet_of: HashMap<[VertexId; 3], u32> =
        HashMap::with_capacity_and_hasher(mesh.faces.len(), Default::default());
    for f in &mesh.faces {
        let mut v = f.v;
        v.sort_unstable();
        facet_of.insert(v, f.facet);
    }
    let mut out = HashMap::default();
    let tri = mesh.ct.triangulation();
    for c in mesh.elements() {
        let Some(&cap) = caps.get(mesh.ct.tag(c) as usize).filter(|h| h.is_finite()) else {
            continue;
        };
        let v = tri.cell(c);
        for skip in 0..4 {
            let mut key = [1, 2, 3].map(|k| v[(skip + k) % 4]);
            key.sort_unstable();
            if let Some(&f) = facet_of.get(&key) {
                let o = out.entry(f).or_insert(f64::INFINITY);
                *o = cap.min(*o);
            }
        }
    }
    out
}

/// `plc`'s triangles on the first of each set of exactly equal points, as the surface checks
/// merge them: an exporter that repeats points at seams (or a surface split before, one copy
/// per patch) gives the triangles on either side of an edge different corners, and each side
/// would split its copy of the edge on its own.
fn on_first_occurrences(plc: &Plc3) -> Vec<SurfaceTriangle> {
    let first = first_occurrences(&plc.points);
    plc.triangles
        .iter()
        .map(|t| SurfaceTriangle {
            v: t.v.map(|i| first[i as usize]),
            ..*t
        })
        .collect()
}

/// `plc` with every triangle whose cap (`cap_of(k)` for triangle `k`: a spacing, or infinite
/// for none) is smaller than its edges split to that spacing; `None` if no triangle needs it.
/// Points repeated in `plc` are taken as one ([`on_first_occurrences`]).
///
/// # Errors
/// Only if meshing a triangle in its plane fails, which would be a bug.
pub(crate) fn split_surface(
    plc: &Plc3,
    cap_of: impl Fn(usize) -> f64 + Sync,
) -> Result<Option<Plc3>, Error> {
    let tris = on_first_occurrences(plc);
    // Pieces of each edge (by sorted ends): enough for the finest triangle on it.
    let mut pieces: HashMap<(u32, u32), usize> = HashMap::default();
    for (k, t) in tris.iter().enumerate() {
        let cap = cap_of(k);
        if !cap.is_finite() {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
            let len = dist(plc.points[a as usize], plc.points[b as usize]);
            // (At most 2^16 pieces; a spacing that asks for more is refused before this.)
            let n = (len / cap).ceil().clamp(1.0, 65536.0) as usize;
            let e = pieces.entry((a.min(b), a.max(b))).or_insert(1);
            *e = (*e).max(n);
        }
    }
    // (A triangle whose edges are all within its cap needs no point inside either.)
    if pieces.values().all(|&n| n == 1) {
        return Ok(None);
    }
    let mut out = Plc3 {
        triangles: Vec::with_capacity(plc.triangles.len()),
        ..plc.clone()
    };
    // The points inside each split edge, from its smaller end (shared by both triangles).
    // (In edge order, so that the numbering, and the mesh, do not depend on the hash.)
    let mut edges: Vec<((u32, u32), usize)> = pieces.into_iter().collect();
    edges.sort_unstable();
    let mut inside: HashMap<(u32, u32), Vec<u32>> = HashMap::default();
    for &((a, b), n) in &edges {
        let (pa, pb) = (plc.points[a as usize], plc.points[b as usize]);
        let ids = (1..n)
            .map(|j| {
                out.points.push(lerp(pa, pb, j as f64 / n as f64));
                out.points.len() as u32 - 1
            })
            .collect();
        inside.insert((a, b), ids);
    }
    // Each triangle's ring (corners with the points inside its edges), meshed in parallel.
    let ring_of = |t: &SurfaceTriangle| {
        let mut ring: Vec<u32> = Vec::new();
        for k in 0..3 {
            let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
            ring.push(a);
            if let Some(ids) = inside.get(&(a.min(b), a.max(b))) {
                if a < b {
                    ring.extend_from_slice(ids);
                } else {
                    ring.extend(ids.iter().rev());
                }
            }
        }
        ring
    };
    let points = &out.points;
    let meshes: Vec<Option<RingMesh>> = tris
        .par_iter()
        .enumerate()
        .map(|(k, t)| {
            let cap = cap_of(k);
            let ring = ring_of(t);
            // A triangle with no cap whose edge a neighbour's cap split is meshed too (at the
            // spacing of its edges), or the surface would have a hanging point there: a wall
            // between a limited region and an unlimited one made the surface "not closed".
            if ring.len() == 3 {
                return Ok(None);
            }
            let p = t.v.map(|i| plc.points[i as usize]);
            let triangles = mesh_in_plane(
                points,
                &ring,
                p,
                &SurfaceSizing {
                    h: cap,
                    sources: &[],
                },
            )?;
            Ok(Some((ring, triangles)))
        })
        .collect::<Result<_, Error>>()?;
    for (t, meshed) in tris.iter().zip(meshes) {
        let Some((ring, triangles)) = meshed else {
            out.triangles.push(*t);
            continue;
        };
        let mut new = NewPoints::default();
        for v in triangles {
            let v = v.map(|x| match x {
                Corner::Ring(k) => ring[k],
                Corner::New(q) => new.id(q, &mut out.points),
            });
            out.triangles.push(SurfaceTriangle { v, ..*t });
        }
    }
    mark_new_points(&mut out);
    Ok(Some(out))
}

/// Gives the points a split added marker 0, when the surface's points have markers (a Medit
/// file's): the surface checks refused "353 point markers given for 758 points".
fn mark_new_points(plc: &mut Plc3) {
    if !plc.point_markers.is_empty() {
        plc.point_markers.resize(plc.points.len(), 0);
    }
}

/// Most surface triangles a surface spacing may ask for (before the field points): 2^24.
pub(crate) const MAX_SPACED_TRIANGLES: f64 = (1u64 << 24) as f64;

/// Checks that `h` can split `plc`'s surface: a positive length (infinity splits nothing) that
/// asks for at most 2^16 pieces of an edge and about [`MAX_SPACED_TRIANGLES`] triangles (a
/// triangle of area `a` takes about `a / (h²·√3/4)` equilateral ones). `plc`'s points must be
/// in range and its triangles name existing points.
///
/// # Errors
/// [`Error::SurfaceSpacing`], saying why.
pub(crate) fn check_surface_spacing(plc: &Plc3, h: f64) -> Result<(), Error> {
    let refuse = |reason: String| Err(Error::SurfaceSpacing { value: h, reason });
    if h.is_nan() || h <= 0.0 {
        return refuse("must be a positive length".into());
    }
    let (mut longest, mut triangles) = (0.0f64, 0.0);
    for t in &plc.triangles {
        let p = t.v.map(|i| plc.points[i as usize]);
        for k in 0..3 {
            longest = longest.max(dist(p[k], p[(k + 1) % 3]));
        }
        let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        triangles += 0.5 * dot(n, n).sqrt() / (h * h * 3f64.sqrt() / 4.0) + 1.0;
    }
    if longest / h > 65536.0 {
        return refuse(format!(
            "a surface edge {longest:e} long would be split into more than 65,536 pieces"
        ));
    }
    if triangles > MAX_SPACED_TRIANGLES {
        return refuse(format!(
            "the surface would be split into about {triangles:.1e} triangles (at most {MAX_SPACED_TRIANGLES:.1e}); give a larger spacing"
        ));
    }
    Ok(())
}

/// A ring (or a patch's points) and the triangles of its mesh in its plane.
type RingMesh = (Vec<u32>, Vec<[Corner; 3]>);

/// A corner of a triangle meshed in its plane: a point of the ring, or a new one.
#[derive(Clone, Copy)]
enum Corner {
    Ring(usize),
    New([f64; 3]),
}

/// The new points of one in-plane mesh, each added to the surface once however many of its
/// triangles share it (they were added once per triangle corner, and merged back as
/// duplicates by recovery, which reported them as the user's).
#[derive(Default)]
struct NewPoints(HashMap<[u64; 3], u32>);

impl NewPoints {
    /// The id of `q` in `points`, adding it the first time.
    fn id(&mut self, q: [f64; 3], points: &mut Vec<[f64; 3]>) -> u32 {
        *self.0.entry(q.map(f64::to_bits)).or_insert_with(|| {
            points.push(q);
            points.len() as u32 - 1
        })
    }
}

/// The spacing a surface is remeshed to: a uniform spacing `h` (infinite: none) and the
/// volume's spacing sources, whichever is finer.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SurfaceSizing<'a> {
    /// The uniform spacing ([`MeshOptions3::surface_spacing`]; infinite for none).
    ///
    /// [`MeshOptions3::surface_spacing`]: crate::mesh3d::MeshOptions3::surface_spacing
    pub h: f64,
    /// The sources.
    pub sources: &'a [Source3],
}

impl SurfaceSizing<'_> {
    /// The spacing asked at `p`.
    fn at(&self, p: [f64; 3]) -> f64 {
        self.sources.iter().fold(self.h, |h, s| h.min(s.spacing(p)))
    }

    /// Whether some edge of the triangle `p` is longer than the spacing asked somewhere on it.
    fn too_coarse(&self, p: [[f64; 3]; 3]) -> bool {
        let finest = self
            .sources
            .iter()
            .fold(self.h, |h, s| h.min(s.finest_on_triangle(p)));
        (0..3).any(|k| dist(p[k], p[(k + 1) % 3]) > finest)
    }

    /// Where to split the edge `a b` (see [`graded_splits`]): uniform pieces for `h` alone.
    fn edge_splits(&self, a: [f64; 3], b: [f64; 3]) -> Vec<f64> {
        let length = dist(a, b);
        let finest = self
            .sources
            .iter()
            .fold(self.h, |h, s| h.min(s.finest_on_segment(a, b)));
        if length.is_nan() || length <= finest {
            return Vec::new();
        }
        let growth = self.sources.iter().fold(0.0f64, |g, s| g.max(s.growth));
        graded_splits(length, |t| self.at(lerp(a, b, t)), growth)
    }

    /// The sizing as 2D sources in the plane through `origin` with the orthonormal axes
    /// `u`, `w` and normal `n`. A 3D source at height `z` off the plane (the least over a
    /// segment source) asks, at in-plane distance `d`, for at least
    /// `h0 + growth·max(z − r, d − r, 0)`: the 2D source at its projection with spacing
    /// `h0 + growth·max(z − r, 0)` within radius `max(r, z)` asks for no more than that.
    fn in_plane(&self, origin: [f64; 3], u: [f64; 3], w: [f64; 3], n: [f64; 3]) -> Vec<Source> {
        let to_2d = |q: [f64; 3]| {
            let d = sub(q, origin);
            [dot(d, u), dot(d, w)]
        };
        let mut out = Vec::with_capacity(self.sources.len() + 1);
        if self.h.is_finite() {
            out.push(Source {
                a: [0.0; 2],
                b: [0.0; 2],
                h0: self.h,
                radius: f64::MAX.sqrt(),
                growth: 0.0,
            });
        }
        for s in self.sources {
            let (za, zb) = (dot(sub(s.a, origin), n), dot(sub(s.b, origin), n));
            let z = if za * zb <= 0.0 {
                0.0
            } else {
                za.abs().min(zb.abs())
            };
            out.push(Source {
                a: to_2d(s.a),
                b: to_2d(s.b),
                h0: s.h0 + s.growth * (z - s.radius).max(0.0),
                radius: s.radius.max(z),
                growth: s.growth,
            });
        }
        out
    }
}

/// The triangles (ordered as the 3D triangle `p`) of the 2D mesh of the polygon `ring` (in
/// `points`) in the plane of `p`, filled to `sizing`; the ring's points stay as they are
/// (recovery by flips adds none).
fn mesh_in_plane(
    points: &[[f64; 3]],
    ring: &[u32],
    p: [[f64; 3]; 3],
    sizing: &SurfaceSizing,
) -> Result<Vec<[Corner; 3]>, Error> {
    let m = ring.len();
    let loop_segments: Vec<(usize, usize)> = (0..m).map(|k| (k, (k + 1) % m)).collect();
    mesh_in_plane_with(points, ring, &loop_segments, p, sizing)
}

/// The triangles (ordered as the 3D triangle `p`) of the 2D mesh, in the plane of `p`, of the
/// points `ids` (in `points`) with the segments `segments` (pairs of positions in `ids`) as
/// its boundary, filled to `sizing`; the points `ids` stay as they are (recovery by flips
/// adds none, and the sources split no edge: they are shared with the neighbours) and are
/// `Corner::Ring(position)`.
fn mesh_in_plane_with(
    points: &[[f64; 3]],
    ids: &[u32],
    segments: &[(usize, usize)],
    p: [[f64; 3]; 3],
    sizing: &SurfaceSizing,
) -> Result<Vec<[Corner; 3]>, Error> {
    // A frame in the plane: u along the first edge, w = n × u, so (u, w, n) is right-handed
    // and counter-clockwise in the frame is the triangle's own orientation.
    let u = normalise(sub(p[1], p[0]));
    let n = normalise(cross(sub(p[1], p[0]), sub(p[2], p[0])));
    let w = cross(n, u);
    let to_2d = |q: [f64; 3]| {
        let d = sub(q, p[0]);
        [dot(d, u), dot(d, w)]
    };
    // Rounding in the projection leaves 1e-48 where a point on the frame's axis has 0: beside
    // coordinates of 1e-1, a range the exact predicates refuse ("coordinate -2.05e-48 is more
    // than 2^142 times smaller"). Such remainders, far below the projection's own rounding,
    // are zero.
    let mut local: Vec<[f64; 2]> = ids.iter().map(|&i| to_2d(points[i as usize])).collect();
    let extent = local.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    for x in local.iter_mut().flatten() {
        if x.abs() < extent * 2f64.powi(-100) {
            *x = 0.0;
        }
    }
    let plc = Plc2 {
        points: local,
        segments: segments
            .iter()
            .map(|&(a, b)| Segment {
                a: a as u32,
                b: b as u32,
                marker: 1,
            })
            .collect(),
        ..Plc2::default()
    };
    // Smoothing moves every point on no segment (a patch's own vertices inside it, which must
    // stay where the surface has them): none then.
    let mut on_segment = vec![false; ids.len()];
    for &(a, b) in segments {
        (on_segment[a], on_segment[b]) = (true, true);
    }
    let defaults = MeshOptions2::default();
    let options = MeshOptions2 {
        recovery: RecoveryMethod::Constrained,
        generation: Some(PointGeneration::default()),
        sources: sizing.in_plane(p[0], u, w, n),
        split_boundary: false,
        smoothing: defaults.smoothing.filter(|_| on_segment.iter().all(|&s| s)),
        ..defaults
    };
    let run = mesh_plc(&plc, &options)?;
    let a = &run.arrays;
    // The given points come back first, as given (they join this mesh to its neighbours'):
    // two of them merged would shift every index.
    if a.coords.get(..ids.len()) != Some(&plc.points[..]) {
        return Err(Error::Internal(format!(
            "a surface split to a spacing lost a point of its edges ({} of {})",
            a.coords.len().min(ids.len()),
            ids.len()
        )));
    }
    let corner = |i: u32| {
        let i = i as usize;
        if i < ids.len() {
            Corner::Ring(i)
        } else {
            let [x, y] = a.coords[i];
            Corner::New([0, 1, 2].map(|k| p[0][k] + x * u[k] + y * w[k]))
        }
    };
    Ok(a.triangles.iter().map(|t| t.map(corner)).collect())
}

/// `plc`'s surface remeshed at spacing `h` ([`MeshOptions3::surface_spacing`]): the surface is
/// cut into planar patches (triangles joined across edges of exactly two triangles that are
/// exactly coplanar, with one marker and turning the same way), and each patch with an edge
/// longer than `h` is meshed in its plane by the 2D pipeline at spacing `h`, its boundary
/// edges cut into equal pieces shared with the patch beyond. A patch is meshed whole, not
/// triangle by triangle: a CAD part's flat face is a fan of thin triangles from one corner,
/// and meshing each would pack points into every sharp corner of the fan. Its points, the
/// corners of its triangles, stay; its triangles get its marker and its smallest facet
/// number. `None` if no edge is longer than `h`. `plc` must have passed the surface checks.
///
/// [`MeshOptions3::surface_spacing`]: crate::mesh3d::MeshOptions3::surface_spacing
///
/// # Errors
/// Only if meshing a patch in its plane fails, which would be a bug.
pub(crate) fn remesh_surface(plc: &Plc3, sizing: &SurfaceSizing) -> Result<Option<Plc3>, Error> {
    let tris = &on_first_occurrences(plc);
    let point = |i: u32| plc.points[i as usize];
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    // Which triangles have an edge longer than the spacing asked on them.
    let coarse: Vec<bool> = tris
        .par_iter()
        .map(|t| sizing.too_coarse(t.v.map(point)))
        .collect();
    if !coarse.contains(&true) {
        return Ok(None);
    }
    // The triangles on each edge, and each edge's direction in them.
    let mut on_edge: HashMap<(u32, u32), Vec<(u32, bool)>> =
        HashMap::with_capacity_and_hasher(tris.len() * 2, Default::default());
    for (k, t) in tris.iter().enumerate() {
        for j in 0..3 {
            let (a, b) = (t.v[j], t.v[(j + 1) % 3]);
            on_edge
                .entry(key(a, b))
                .or_default()
                .push((k as u32, a < b));
        }
    }
    // Two triangles on an edge are one patch if they are the edge's only two, exactly coplanar,
    // with one marker, and turn the same way (the edge runs opposite ways in them).
    let joined = |ts: &[(u32, bool)]| -> bool {
        let [(s, ds), (t, dt)] = ts else {
            return false;
        };
        let (s, t) = (&tris[*s as usize], &tris[*t as usize]);
        if s.marker != t.marker || ds == dt {
            return false;
        }
        let p = s.v.map(point);
        t.v.iter()
            .all(|&v| s.v.contains(&v) || orient3d(p[0], p[1], p[2], point(v)) == Sign::Zero)
    };
    let mut patch = vec![u32::MAX; tris.len()];
    let mut patches: Vec<Vec<u32>> = Vec::new();
    for start in 0..tris.len() {
        if patch[start] != u32::MAX {
            continue;
        }
        let id = patches.len() as u32;
        let mut members = vec![start as u32];
        patch[start] = id;
        let mut at = 0;
        while at < members.len() {
            let t = &tris[members[at] as usize];
            at += 1;
            for j in 0..3 {
                let ts = &on_edge[&key(t.v[j], t.v[(j + 1) % 3])];
                if joined(ts) {
                    for &(u, _) in ts {
                        if patch[u as usize] == u32::MAX {
                            patch[u as usize] = id;
                            members.push(u);
                        }
                    }
                }
            }
        }
        members.sort_unstable();
        patches.push(members);
    }
    let mut out = Plc3 {
        triangles: Vec::with_capacity(tris.len()),
        ..plc.clone()
    };
    // The points inside each edge on a patch's boundary, from its smaller end (shared by the
    // patches on either side), in edge order so that the numbering does not depend on the hash.
    let mut edges: Vec<(u32, u32)> = on_edge
        .iter()
        .filter(|(_, ts)| !joined(ts))
        .map(|(&e, _)| e)
        .collect();
    edges.sort_unstable();
    let mut inside: HashMap<(u32, u32), Vec<u32>> =
        HashMap::with_capacity_and_hasher(edges.len(), Default::default());
    let splits: Vec<Vec<f64>> = edges
        .par_iter()
        .map(|&(a, b)| sizing.edge_splits(point(a), point(b)))
        .collect();
    for ((a, b), ts) in edges.into_iter().zip(splits) {
        let (pa, pb) = (point(a), point(b));
        let ids = ts
            .into_iter()
            .map(|t| {
                out.points.push(lerp(pa, pb, t));
                out.points.len() as u32 - 1
            })
            .collect();
        inside.insert((a, b), ids);
    }
    // Each patch: its corners, the points inside its boundary edges, and those edges' pieces.
    let points = &out.points;
    let meshes: Vec<Option<RingMesh>> = patches
        .par_iter()
        .map(|members| {
            if !members.iter().any(|&t| coarse[t as usize]) {
                return Ok(None);
            }
            let mut corners: Vec<u32> = members.iter().flat_map(|&t| tris[t as usize].v).collect();
            corners.sort_unstable();
            corners.dedup();
            let at = |i: u32| corners.binary_search(&i).expect("a corner of the patch");
            let mut ids = corners.clone();
            let mut segments = Vec::new();
            let mut seen = rustc_hash::FxHashSet::default();
            for &t in members {
                let v = tris[t as usize].v;
                for j in 0..3 {
                    let (a, b) = (v[j], v[(j + 1) % 3]);
                    let Some(within) = inside.get(&key(a, b)) else {
                        continue;
                    };
                    if !seen.insert(key(a, b)) {
                        continue;
                    }
                    let mut chain = vec![at(a.min(b))];
                    for &q in within {
                        chain.push(ids.len());
                        ids.push(q);
                    }
                    chain.push(at(a.max(b)));
                    segments.extend(chain.windows(2).map(|w| (w[0], w[1])));
                }
            }
            // The frame of the patch's largest triangle (its normal is the most accurate).
            let area = |t: &u32| {
                let p = tris[*t as usize].v.map(point);
                let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
                dot(n, n)
            };
            let largest = members
                .iter()
                .max_by(|a, b| area(a).total_cmp(&area(b)))
                .expect("a patch has a triangle");
            let frame = tris[*largest as usize].v.map(point);
            let triangles = mesh_in_plane_with(points, &ids, &segments, frame, sizing)?;
            // The patch's mesh must cover the patch: its area, to rounding. If not (a patch
            // whose loops the 2D exterior deletion reads otherwise), each triangle is meshed
            // alone, with the same points on its edges.
            let at = |c: &Corner| match *c {
                Corner::Ring(k) => points[ids[k] as usize],
                Corner::New(q) => q,
            };
            let meshed: f64 = triangles
                .iter()
                .map(|t| triangle_area(t.each_ref().map(at)))
                .sum();
            let given: f64 = members
                .iter()
                .map(|&t| triangle_area(tris[t as usize].v.map(point)))
                .sum();
            if (meshed - given).abs() <= 1e-9 * given {
                return Ok(Some((ids, triangles)));
            }
            let (mut ids, mut triangles) = (Vec::new(), Vec::new());
            for &t in members {
                let v = tris[t as usize].v;
                let mut ring = Vec::new();
                for j in 0..3 {
                    let (a, b) = (v[j], v[(j + 1) % 3]);
                    ring.push(a);
                    if let Some(within) = inside.get(&key(a, b)) {
                        if a < b {
                            ring.extend_from_slice(within);
                        } else {
                            ring.extend(within.iter().rev());
                        }
                    }
                }
                let base = ids.len();
                let own = mesh_in_plane(points, &ring, v.map(point), sizing)?;
                ids.extend_from_slice(&ring);
                triangles.extend(own.into_iter().map(|c| {
                    c.map(|x| match x {
                        Corner::Ring(k) => Corner::Ring(base + k),
                        new => new,
                    })
                }));
            }
            Ok(Some((ids, triangles)))
        })
        .collect::<Result<_, Error>>()?;
    for (members, meshed) in patches.iter().zip(meshes) {
        let Some((ids, triangles)) = meshed else {
            out.triangles
                .extend(members.iter().map(|&t| tris[t as usize]));
            continue;
        };
        let first = tris[members[0] as usize];
        let facet = members.iter().map(|&t| tris[t as usize].facet).min();
        let mut new = NewPoints::default();
        for v in triangles {
            let v = v.map(|x| match x {
                Corner::Ring(k) => ids[k],
                Corner::New(q) => new.id(q, &mut out.points),
            });
            out.triangles.push(SurfaceTriangle {
                v,
                marker: first.marker,
                facet: facet.unwrap_or(first.facet),
            });
        }
    }
    mark_new_points(&mut out);
    Ok(Some(out))
}

fn triangle_area(p: [[f64; 3]; 3]) -> f64 {
    let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    0.5 * dot(n, n).sqrt()
}

fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]))
}

fn normalise(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    a.map(|x| x / l)
}
