//! The surface next to a region with a volume limit, split to that region's spacing before
//! the 3D pipeline runs (as TetGen splits the boundary its `-a` refinement encroaches).
//!
//! A surface triangle much larger than the spacing a volume limit asks for makes the
//! tetrahedra on it flat: a 12-triangle unit cube limited to 1e-4 gave 72,796 slivers in
//! 270,158 tetrahedra. So a first recovery (of the surface alone) tells which regions each
//! facet bounds; every triangle of a facet next to a limited region is then meshed in its own
//! plane by the 2D pipeline at that region's spacing ([`spacing_for_volume`]), each edge split
//! into the same equal pieces for both triangles sharing it, so that the new surface
//! conforms. New triangles keep their triangle's marker and facet.

use std::collections::HashMap;

use delmesh_boundary_recovery::{Mesh3, Plc2, Plc3, RecoveryMethod, Segment, SurfaceTriangle};
use delmesh_delaunay_core::VertexId;
use delmesh_point_gen::{PointGeneration, Source};
use rayon::prelude::*;

use crate::geometry3::{cross, dist, dot, sub};
use crate::mesh2d::{mesh_plc, MeshOptions2};
use crate::Error;

/// The finest spacing asked of each facet (by facet id): the smallest cap (by region index) of
/// the regions on either side of its faces in `mesh`; facets with none are left out.
pub(crate) fn facet_caps(mesh: &Mesh3, caps: &[f64]) -> HashMap<u32, f64> {
    let mut facet_of: HashMap<[VertexId; 3], u32> = HashMap::with_capacity(mesh.faces.len());
    for f in &mesh.faces {
        let mut v = f.v;
        v.sort_unstable();
        facet_of.insert(v, f.facet);
    }
    let mut out = HashMap::new();
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

/// `plc` with every triangle of a facet whose cap (`facet_caps`) is finite and smaller than
/// its edges split to that spacing; `None` if no triangle needs it.
///
/// # Errors
/// Only if meshing a triangle in its plane fails, which would be a bug.
pub(crate) fn split_surface(
    plc: &Plc3,
    facet_caps: &HashMap<u32, f64>,
) -> Result<Option<Plc3>, Error> {
    let cap_of = |t: &SurfaceTriangle| facet_caps.get(&t.facet).copied().unwrap_or(f64::INFINITY);
    // Pieces of each edge (by sorted ends): enough for the finest triangle on it.
    let mut pieces: HashMap<(u32, u32), usize> = HashMap::new();
    for t in &plc.triangles {
        let cap = cap_of(t);
        if !cap.is_finite() {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
            let len = dist(plc.points[a as usize], plc.points[b as usize]);
            // (At most 2^16 pieces; a limit that asks for more is refused before this.)
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
    let mut inside: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
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
    let meshes: Vec<Option<RingMesh>> = plc
        .triangles
        .par_iter()
        .map(|t| {
            let cap = cap_of(t);
            let ring = ring_of(t);
            if !cap.is_finite() || ring.len() == 3 {
                return Ok(None);
            }
            let p = t.v.map(|i| plc.points[i as usize]);
            let triangles = mesh_in_plane(points, &ring, p, cap)?;
            Ok(Some((ring, triangles)))
        })
        .collect::<Result<_, Error>>()?;
    for (t, meshed) in plc.triangles.iter().zip(meshes) {
        let Some((ring, triangles)) = meshed else {
            out.triangles.push(*t);
            continue;
        };
        for v in triangles {
            let v = v.map(|x| match x {
                Corner::Ring(k) => ring[k],
                Corner::New(q) => {
                    out.points.push(q);
                    out.points.len() as u32 - 1
                }
            });
            out.triangles.push(SurfaceTriangle { v, ..*t });
        }
    }
    Ok(Some(out))
}

/// A triangle's ring and the triangles of its mesh in its plane.
type RingMesh = (Vec<u32>, Vec<[Corner; 3]>);

/// A corner of a triangle meshed in its plane: a point of the ring, or a new one.
#[derive(Clone, Copy)]
enum Corner {
    Ring(usize),
    New([f64; 3]),
}

/// The triangles (ordered as the 3D triangle `p`) of the 2D mesh of the polygon `ring` (in
/// `points`) in the plane of `p`, filled at spacing `cap`; the ring's points stay as they are
/// (recovery by flips adds none).
fn mesh_in_plane(
    points: &[[f64; 3]],
    ring: &[u32],
    p: [[f64; 3]; 3],
    cap: f64,
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
    let m = ring.len() as u32;
    let plc = Plc2 {
        points: ring.iter().map(|&i| to_2d(points[i as usize])).collect(),
        segments: (0..m)
            .map(|k| Segment {
                a: k,
                b: (k + 1) % m,
                marker: 1,
            })
            .collect(),
        ..Plc2::default()
    };
    let centre = [0, 1].map(|k| plc.points.iter().map(|q| q[k]).sum::<f64>() / f64::from(m));
    let options = MeshOptions2 {
        recovery: RecoveryMethod::Constrained,
        generation: Some(PointGeneration::default()),
        sources: vec![Source {
            a: centre,
            b: centre,
            h0: cap,
            radius: f64::MAX.sqrt(),
            growth: 0.0,
        }],
        ..MeshOptions2::default()
    };
    let run = mesh_plc(&plc, &options)?;
    let a = &run.arrays;
    // The ring comes back first, as given (it is what joins this triangle's mesh to its
    // neighbours'): two of its points merged would shift every index.
    if a.coords.get(..ring.len()) != Some(&plc.points[..]) {
        return Err(Error::Internal(format!(
            "a surface triangle split for a volume limit lost a point of its edges ({} of {})",
            a.coords.len().min(ring.len()),
            ring.len()
        )));
    }
    let corner = |i: u32| {
        let i = i as usize;
        if i < ring.len() {
            Corner::Ring(i)
        } else {
            let [x, y] = a.coords[i];
            Corner::New([0, 1, 2].map(|k| p[0][k] + x * u[k] + y * w[k]))
        }
    };
    Ok(a.triangles.iter().map(|t| t.map(corner)).collect())
}

fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]))
}

fn normalise(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    a.map(|x| x / l)
}
