//! 3D boundary recovery end to end: every input facet is the union of output boundary faces,
//! nothing outside the domain, the enclosed volume, positive orientation and the constrained
//! Delaunay property, on closed surfaces (boxes, spheres, nested and separate bodies).

use delmesh_boundary_recovery::{
    check_surface, tet_volume, BoundaryRecovery3, Mesh3, Plc3, RecoveryError, RecoveryMethod3,
    RecoveryStep, RegionSeed3, SurfaceTriangle,
};
use delmesh_delaunay_core::{FlipIn, Triangulation3, VertexId};
use delmesh_predicates::{orient3d, Sign};
use proptest::prelude::*;
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Adds a closed surface (points and triangles in local numbering) with one marker.
fn add_surface(plc: &mut Plc3, points: &[[f64; 3]], triangles: &[[u32; 3]], marker: i32) {
    let base = plc.points.len() as u32;
    plc.points.extend_from_slice(points);
    for t in triangles {
        let facet = plc.triangles.len() as u32;
        plc.triangles.push(SurfaceTriangle {
            v: t.map(|i| i + base),
            marker,
            facet,
        });
    }
}

/// The surface of the box `lo..hi`, `n` divisions per edge, triangles counter-clockwise seen
/// from outside (`outward`) or from inside.
fn box_surface(
    lo: [f64; 3],
    hi: [f64; 3],
    n: usize,
    outward: bool,
) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut index: HashMap<[usize; 3], u32> = HashMap::new();
    let mut id = |g: [usize; 3], points: &mut Vec<[f64; 3]>| {
        *index.entry(g).or_insert_with(|| {
            points.push([0, 1, 2].map(|k| lo[k] + (hi[k] - lo[k]) * g[k] as f64 / n as f64));
            points.len() as u32 - 1
        })
    };
    let mut triangles = Vec::new();
    // Each face: the fixed axis, its side; (u, v) the other two axes in right-handed order.
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let g = |a: usize, b: usize| {
                        let mut g = [0; 3];
                        g[axis] = side;
                        g[u] = a;
                        g[v] = b;
                        g
                    };
                    let q = [g(i, j), g(i + 1, j), g(i + 1, j + 1), g(i, j + 1)]
                        .map(|g| id(g, &mut points));
                    // u × v = +axis: counter-clockwise seen from +axis.
                    let out_here = (side == n) == outward;
                    let (t1, t2) = if (i + j) % 2 == 0 {
                        ([q[0], q[1], q[2]], [q[0], q[2], q[3]])
                    } else {
                        ([q[0], q[1], q[3]], [q[1], q[2], q[3]])
                    };
                    for t in [t1, t2] {
                        triangles.push(if out_here { t } else { [t[0], t[2], t[1]] });
                    }
                }
            }
        }
    }
    (points, triangles)
}

/// An icosphere: the icosahedron subdivided `level` times, projected on the sphere,
/// counter-clockwise seen from outside.
fn icosphere(centre: [f64; 3], r: f64, level: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut pts: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut next = Vec::new();
        for t in &tris {
            let mut m = [0u32; 3];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let key = (a.min(b), a.max(b));
                m[k] = *mid.entry(key).or_insert_with(|| {
                    let (p, q) = (pts[a as usize], pts[b as usize]);
                    pts.push([0, 1, 2].map(|i| 0.5 * (p[i] + q[i])));
                    pts.len() as u32 - 1
                });
            }
            next.push([t[0], m[0], m[2]]);
            next.push([t[1], m[1], m[0]]);
            next.push([t[2], m[2], m[1]]);
            next.push(m);
        }
        tris = next;
    }
    let points = pts
        .iter()
        .map(|p| {
            let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            [0, 1, 2].map(|k| centre[k] + r * p[k] / l)
        })
        .collect();
    (points, tris)
}

/// Signed volume enclosed by a closed triangulated surface (divergence theorem).
fn enclosed_volume(points: &[[f64; 3]], tris: &[[u32; 3]]) -> f64 {
    let o = points[0];
    tris.iter()
        .map(|t| {
            tet_volume(
                o,
                points[t[0] as usize],
                points[t[1] as usize],
                points[t[2] as usize],
            )
        })
        .sum()
}

fn area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
}

/// How boundary faces must cover the input.
#[derive(Clone, Copy, PartialEq)]
enum Coverage {
    /// Each input facet is the union of the boundary faces of that facet.
    Facets,
    /// Each plane (with one marker) of the input is covered by boundary faces of that marker
    /// lying in it, with the same area: what re-triangulating coplanar facets promises.
    Planes,
}

/// Everything a recovered mesh must satisfy.
fn check(plc: &Plc3, mesh: &Mesh3, volume: f64) {
    check_with(plc, mesh, volume, Coverage::Facets);
}

/// The plane of a triangle (unit normal and offset, rounded) with its marker: the key of
/// [`Coverage::Planes`] (the test surfaces' planes are far apart).
fn plane_key(p: [[f64; 3]; 3], marker: i32) -> (i32, [i64; 4]) {
    let u = [0, 1, 2].map(|k| p[1][k] - p[0][k]);
    let v = [0, 1, 2].map(|k| p[2][k] - p[0][k]);
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let n = n.map(|x| x / l);
    let d = n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2];
    let r = |x: f64| (x * 1e6).round() as i64;
    // The plane whichever way the triangle turns (faces on the domain's boundary face out).
    let key = [r(n[0]), r(n[1]), r(n[2]), r(d)];
    let first = key[..3].iter().copied().find(|&x| x != 0).unwrap_or(0);
    (marker, if first < 0 { key.map(|x| -x) } else { key })
}

/// Everything a recovered mesh must satisfy, with the given coverage of the input.
fn check_with(plc: &Plc3, mesh: &Mesh3, volume: f64, coverage: Coverage) {
    // A constrained recovery is not Delaunay next to what it flipped in.
    let flipped =
        mesh.history.method == RecoveryMethod3::Constrained && !mesh.history.constrained_fallback;
    if flipped {
        mesh.ct.validate_structure().expect("positive, symmetric");
    } else {
        mesh.ct
            .validate()
            .expect("constrained Delaunay, positive, symmetric");
    }
    let arrays = mesh.to_arrays();
    // Volume.
    let v: f64 = arrays
        .tets
        .iter()
        .map(|t| {
            let p = t.map(|i| arrays.coords[i as usize]);
            assert_eq!(
                orient3d(p[0], p[1], p[2], p[3]),
                Sign::Positive,
                "tetrahedron {t:?} not positive"
            );
            tet_volume(p[0], p[1], p[2], p[3])
        })
        .sum();
    assert!(
        (v - volume).abs() <= 1e-9 * volume.abs(),
        "volume {v} vs enclosed {volume}"
    );
    // Every facet is the union of its boundary faces: same area. A face on the domain's
    // boundary faces out of its element; one inside it (a wall) as the input facet does.
    let mut by_facet: HashMap<u32, f64> = HashMap::new();
    let mut triangle_of: HashMap<u32, usize> = HashMap::new();
    for (k, t) in plc.triangles.iter().enumerate() {
        triangle_of.entry(t.facet).or_insert(k);
    }
    let mut inside_of: HashMap<[u32; 3], u32> = HashMap::new();
    for (t, n) in arrays.tets.iter().zip(&arrays.neighbours) {
        for k in 0..4 {
            if n[k] == u32::MAX {
                let mut f = [t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]];
                f.sort_unstable();
                inside_of.insert(f, t[k]);
            }
        }
    }
    for (t, &f) in arrays.faces.iter().zip(&arrays.face_facets) {
        let p = t.map(|i| arrays.coords[i as usize]);
        *by_facet.entry(f).or_default() += area(p[0], p[1], p[2]);
        let mut key = *t;
        key.sort_unstable();
        if let Some(&o) = inside_of.get(&key) {
            let q = arrays.coords[o as usize];
            assert_eq!(
                orient3d(p[0], p[1], p[2], q),
                Sign::Negative,
                "face {t:?} faces into the domain"
            );
            continue;
        }
        // Orientation agrees with the input facet's normal.
        let q = plc.triangles[triangle_of[&f]]
            .v
            .map(|i| plc.points[i as usize]);
        let n = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ]
        };
        let (m, k) = (n(p[0], p[1], p[2]), n(q[0], q[1], q[2]));
        assert!(
            m[0] * k[0] + m[1] * k[1] + m[2] * k[2] > 0.0,
            "face {t:?} flipped"
        );
    }
    if coverage == Coverage::Facets {
        for (f, t) in plc.triangles.iter().enumerate() {
            let q = t.v.map(|i| plc.points[i as usize]);
            let want = area(q[0], q[1], q[2]);
            let got = by_facet.get(&(f as u32)).copied().unwrap_or(0.0);
            assert!(
                (got - want).abs() <= 1e-9 * want,
                "facet {f}: faces cover {got}, facet area {want}"
            );
        }
    } else {
        let mut want: HashMap<(i32, [i64; 4]), f64> = HashMap::new();
        for t in &plc.triangles {
            let q = t.v.map(|i| plc.points[i as usize]);
            *want.entry(plane_key(q, t.marker)).or_default() += area(q[0], q[1], q[2]);
        }
        let mut got: HashMap<(i32, [i64; 4]), f64> = HashMap::new();
        for (t, f) in arrays.faces.iter().zip(&mesh.faces) {
            let p = t.map(|i| arrays.coords[i as usize]);
            *got.entry(plane_key(p, f.marker)).or_default() += area(p[0], p[1], p[2]);
        }
        assert_eq!(want.len(), got.len(), "the faces lie in the input's planes");
        for (k, w) in &want {
            let g = got.get(k).copied().unwrap_or(0.0);
            assert!(
                (g - w).abs() <= 1e-9 * w,
                "plane {k:?}: faces cover {g}, input {w}"
            );
        }
    }
    // The boundary faces are exactly the protected faces.
    assert_eq!(mesh.ct.protected_faces().len(), mesh.faces.len());
    // Neighbour rows: symmetric, across the very face, and none across a face only at the
    // boundary of the output, which is then a boundary face.
    let key = |t: [u32; 4], k: usize| {
        let mut f: Vec<u32> = (0..4).filter(|&m| m != k).map(|m| t[m]).collect();
        f.sort_unstable();
        f
    };
    let boundary: std::collections::HashSet<Vec<u32>> = arrays
        .faces
        .iter()
        .map(|f| {
            let mut f = f.to_vec();
            f.sort_unstable();
            f
        })
        .collect();
    assert_eq!(arrays.neighbours.len(), arrays.tets.len());
    for (t, row) in arrays.neighbours.iter().enumerate() {
        for (k, &u) in row.iter().enumerate() {
            let face = key(arrays.tets[t], k);
            if u == u32::MAX {
                assert!(
                    boundary.contains(&face),
                    "tetrahedron {t} face {k}: open, not boundary"
                );
                continue;
            }
            let back = arrays.neighbours[u as usize]
                .iter()
                .position(|&w| w == t as u32);
            let back = back.expect("neighbour rows symmetric");
            assert_eq!(key(arrays.tets[u as usize], back), face);
        }
    }
}

#[test]
fn cube_alone() {
    let (p, t) = box_surface([0.0; 3], [1.0; 3], 3, true);
    let mut plc = Plc3::default();
    add_surface(&mut plc, &p, &t, 1);
    let mesh = BoundaryRecovery3::default().run(&plc).unwrap();
    check(&plc, &mesh, 1.0);
    // Each grid square's four corners are co-circular: where the perturbation chose the other
    // diagonal than the input, the diagonal's mid-point is needed, nothing more.
    assert!(mesh.history.points_added() <= 6 * 9, "{}", mesh.history);
    assert_eq!(mesh.history.face_points, 0, "{}", mesh.history);
}

#[test]
fn seeds_outside_every_surface_are_reported() {
    // A hole seed and a region seed beyond the cube (a wrong coordinate, other units) do
    // nothing: the history names them; the seeds inside are not named as outside.
    let (p, t) = box_surface([0.0; 3], [1.0; 3], 2, true);
    let mut plc = Plc3::default();
    add_surface(&mut plc, &p, &t, 1);
    plc.first_index = 1;
    plc.holes = vec![[5.0, 5.0, 5.0]];
    plc.regions = [
        ([0.5, 0.5, 0.5], 2.0),
        ([-3.0, 0.5, 0.5], 2.0),
        ([0.25, 0.25, 0.25], 4.0),
    ]
    .map(|(point, attribute)| RegionSeed3 {
        point,
        attribute,
        max_volume: None,
    })
    .to_vec();
    let mesh = BoundaryRecovery3::default().run(&plc).unwrap();
    check(&plc, &mesh, 1.0);
    assert_eq!(mesh.history.seeds_outside, [("region", 2), ("hole", 1)]);
    // Seeds 1 and 3 name one region with two attributes: the last wins, with a warning.
    assert_eq!(
        mesh.history.seeds_overridden,
        [(("region", 1), ("region", 3))]
    );
    assert!(
        mesh.history
            .to_string()
            .contains("warning: hole seed 1 lies outside the domain"),
        "{}",
        mesh.history
    );
}

#[test]
fn duplicate_points_are_merged_and_reported_in_the_history() {
    // A cube whose first triangle names a copy of its first corner.
    let (mut p, mut t) = box_surface([0.0; 3], [1.0; 3], 1, true);
    let copied = t[0][0];
    p.push(p[copied as usize]);
    t[0][0] = p.len() as u32 - 1;
    let mut plc = Plc3::default();
    add_surface(&mut plc, &p, &t, 1);
    plc.first_index = 1;
    let mesh = BoundaryRecovery3::default().run(&plc).unwrap();
    check(&plc, &mesh, 1.0);
    let dup = p.len() as u64; // 1-based
    assert_eq!(
        mesh.history.merged_points,
        vec![(dup, u64::from(copied) + 1)]
    );
    let shown = format!("points {dup} into {}", copied + 1);
    assert!(
        mesh.history.to_string().contains(&shown),
        "{}",
        mesh.history
    );
}

/// A sphere (icosphere, level 2) off-centre in a 4×4×4 box, and the volume between them.
fn sphere_in_box() -> (Plc3, f64) {
    let mut plc = Plc3::default();
    let (p, t) = box_surface([-2.0; 3], [2.0; 3], 4, true);
    add_surface(&mut plc, &p, &t, 1);
    let (q, s) = icosphere([0.1, 0.05, -0.02], 0.7, 2);
    add_surface(&mut plc, &q, &s, 2);
    (plc, 64.0 - enclosed_volume(&q, &s))
}

#[test]
fn a_recovery_its_caller_stops_is_cancelled() {
    let (plc, _) = sphere_in_box();
    let stop = Arc::new(AtomicBool::new(true));
    let stopped = BoundaryRecovery3::default()
        .cancel_on(stop.clone())
        .run(&plc);
    assert!(
        matches!(stopped, Err(RecoveryError::Cancelled)),
        "{stopped:?}"
    );
    // Not set: the flag changes nothing.
    stop.store(false, Ordering::Relaxed);
    let mesh = BoundaryRecovery3::default()
        .cancel_on(stop)
        .run(&plc)
        .unwrap();
    let plain = BoundaryRecovery3::default().run(&plc).unwrap();
    assert_eq!(mesh.to_arrays().tets, plain.to_arrays().tets);
}

#[test]
fn a_recovery_starts_from_a_given_tetrahedralisation_of_its_points_only() {
    let (plc, _) = sphere_in_box();
    let plain = BoundaryRecovery3::default()
        .trusted_surface()
        .run(&plc)
        .unwrap();
    let given = Triangulation3::new(&plc.points).unwrap();
    let from = BoundaryRecovery3::default()
        .trusted_surface()
        .run_on(&plc, given)
        .unwrap();
    assert_eq!(from.to_arrays().tets, plain.to_arrays().tets);
    // Of other points (one moved, or one fewer): set aside, the points are triangulated.
    let mut moved = plc.points.clone();
    moved[3][0] += 1e-3;
    for other in [moved, plc.points[1..].to_vec()] {
        let given = Triangulation3::new(&other).unwrap();
        let from = BoundaryRecovery3::default()
            .trusted_surface()
            .run_on(&plc, given)
            .unwrap();
        assert_eq!(from.to_arrays().tets, plain.to_arrays().tets);
    }
}

#[test]
fn sphere_in_a_box() {
    let (plc, volume) = sphere_in_box();
    let mesh = BoundaryRecovery3::default().run(&plc).unwrap();
    check(&plc, &mesh, volume);
    println!("{}", mesh.history);
}

/// A 3×3×3 box with a unit cubic hole in the middle, and 2,000 random field points in the
/// outer box, the hole included.
fn cube_with_cubic_hole_and_field() -> (Plc3, Vec<[f64; 3]>) {
    let mut plc = Plc3::default();
    let (p, t) = box_surface([0.0; 3], [3.0; 3], 6, true);
    add_surface(&mut plc, &p, &t, 1);
    let (q, s) = box_surface([1.0; 3], [2.0; 3], 2, true);
    add_surface(&mut plc, &q, &s, 2);
    let mut rng = StdRng::seed_from_u64(7);
    let field = (0..2000)
        .map(|_| [0, 1, 2].map(|_| rng.gen_range(0.01..2.99)))
        .collect();
    (plc, field)
}

#[test]
fn cube_with_cubic_hole_and_field_points() {
    let (plc, field) = cube_with_cubic_hole_and_field();
    let mesh = BoundaryRecovery3::default()
        .with_points(field)
        .run(&plc)
        .unwrap();
    check(&plc, &mesh, 27.0 - 1.0);
    assert!(
        mesh.history.points_added() > 0,
        "field points hide surface edges"
    );
    assert!(mesh
        .history
        .steps
        .iter()
        .any(|s| matches!(s, RecoveryStep::Edges { missing_edges, .. } if *missing_edges > 0)));
    println!("{}", mesh.history);
}

#[test]
fn two_bodies_and_a_hole_seed() {
    let mut plc = Plc3::default();
    let (p, t) = box_surface([-3.0, -2.0, -2.0], [3.0, 2.0, 2.0], 4, true);
    add_surface(&mut plc, &p, &t, 1);
    let (q, s) = icosphere([-1.2, 0.0, 0.0], 0.8, 2);
    let v1 = enclosed_volume(&q, &s);
    add_surface(&mut plc, &q, &s, 2);
    let (q, s) = box_surface([0.6, -0.5, -0.5], [1.6, 0.5, 0.5], 2, false);
    add_surface(&mut plc, &q, &s, 3);
    let mesh = BoundaryRecovery3::default().run(&plc).unwrap();
    check(&plc, &mesh, 96.0 - v1 - 1.0);
    // A hole seed in the far field removes everything.
    plc.holes.push([2.5, 1.5, 1.5]);
    assert!(matches!(
        BoundaryRecovery3::default().run(&plc),
        Err(RecoveryError::EmptyDomain)
    ));
}

#[test]
fn budget_exhaustion_is_an_error_naming_facets() {
    let mut plc = Plc3::default();
    let (p, t) = box_surface([0.0; 3], [3.0; 3], 6, true);
    add_surface(&mut plc, &p, &t, 1);
    let mut rng = StdRng::seed_from_u64(3);
    let field: Vec<[f64; 3]> = (0..3000)
        .map(|_| [0, 1, 2].map(|_| rng.gen_range(0.01..2.99)))
        .collect();
    let err = BoundaryRecovery3::default()
        .coplanar_fallback(false)
        .with_points(field.clone())
        .max_steiner_points(3)
        .run(&plc)
        .unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("facets that resisted"), "{msg}");
    // By default the faces of the box are merged after the 3 points, and need no more.
    let merged = BoundaryRecovery3::default()
        .with_points(field)
        .max_steiner_points(3)
        .run(&plc)
        .unwrap();
    assert_eq!(merged.history.coplanar_merged_after, Some(3));
    check_with(&plc, &merged, 27.0, Coverage::Planes);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    /// Random field points around a randomly placed sphere inside a box.
    #[test]
    fn random_field_points_keep_the_surface(seed in 0u64..1000, n in 50usize..800) {
        let mut rng = StdRng::seed_from_u64(seed);
        let mut plc = Plc3::default();
        let (p, t) = box_surface([0.0; 3], [2.0; 3], 3, true);
        add_surface(&mut plc, &p, &t, 1);
        let c = [0, 1, 2].map(|_| rng.gen_range(0.8..1.2));
        let (q, s) = icosphere(c, rng.gen_range(0.3..0.6), 1);
        let vs = enclosed_volume(&q, &s);
        add_surface(&mut plc, &q, &s, 2);
        let field: Vec<[f64; 3]> = (0..n).map(|_| [0, 1, 2].map(|_| rng.gen_range(0.0..2.0))).collect();
        let mesh = BoundaryRecovery3::default().with_points(field).run(&plc).unwrap();
        check(&plc, &mesh, 8.0 - vs);
    }
}

#[test]
fn a_priori_points_beside_every_face() {
    use delmesh_boundary_recovery::RecoveryMethod3;
    let (plc, volume) = sphere_in_box();
    let mesh = BoundaryRecovery3::new(RecoveryMethod3::APriori)
        .run(&plc)
        .unwrap();
    check(&plc, &mesh, volume);
    let h = &mesh.history;
    // Two triangles of a box square share their circumcircle, so their points coincide.
    assert!(h.a_priori_points + h.a_priori_rejected <= plc.triangles.len());
    assert!(h.a_priori_points > plc.triangles.len() / 2, "{h}");
    println!("{h}");
}

#[test]
fn a_priori_recovery_of_a_cube_with_a_needle_face() {
    // The top face split at a point a hair off its edge y = 0: the needle's a-priori search
    // never ended (its sphere, 1e20 across, wrapped the grid's cell count). Now the needle is
    // left to checking and the cube is recovered.
    for (x, height) in [(0.5, 1e-11), (0.3, 1e-14), (0.9, 1e-16)] {
        let mut points: Vec<[f64; 3]> = (0..8)
            .map(|c| [0, 1, 2].map(|k| f64::from((c >> k) & 1)))
            .collect();
        points.push([x, height, 1.0]);
        let triangles = [
            [0, 2, 3],
            [0, 3, 1],
            [0, 1, 5],
            [0, 5, 4],
            [2, 6, 7],
            [2, 7, 3],
            [0, 4, 6],
            [0, 6, 2],
            [1, 3, 7],
            [1, 7, 5],
            [4, 5, 8],
            [5, 7, 8],
            [8, 7, 6],
            [4, 8, 6],
        ];
        let mut plc = Plc3::default();
        add_surface(&mut plc, &points, &triangles, 1);
        let mesh = BoundaryRecovery3::new(RecoveryMethod3::APriori)
            .run(&plc)
            .unwrap();
        check(&plc, &mesh, 1.0);
        assert!(mesh.history.a_priori_rejected >= 1, "{}", mesh.history);
    }
}

#[test]
fn field_points_on_the_surface_are_left_out() {
    let (p, t) = box_surface([0.0; 3], [1.0; 3], 2, true);
    let mut plc = Plc3::default();
    add_surface(&mut plc, &p, &t, 1);
    let field = vec![
        [0.3, 0.4, 0.0],  // on a face
        [1.0, 0.25, 0.5], // on an edge of a face's triangles
        [0.5, 0.5, 0.5],  // inside
        [0.2, 0.7, 0.6],  // inside
    ];
    let mesh = BoundaryRecovery3::default()
        .with_points(field)
        .run(&plc)
        .unwrap();
    assert_eq!(mesh.history.field_points_on_surface, 2, "{}", mesh.history);
    assert_eq!(mesh.history.field_points, 2);
    check(&plc, &mesh, 1.0);
}

#[test]
fn merged_coplanar_facets_are_retriangulated_and_need_no_points() {
    // A cube with a cubic hole, both of grid squares: every square's corners are co-circular,
    // so recovering the input's diagonals needs points wherever the tetrahedralisation chose
    // the other one; flipping those diagonals needs none.
    let mut plc = Plc3::default();
    let (p, t) = box_surface([0.0; 3], [3.0; 3], 6, true);
    add_surface(&mut plc, &p, &t, 1);
    let (q, s) = box_surface([1.0; 3], [2.0; 3], 2, true);
    add_surface(&mut plc, &q, &s, 2);
    let kept = BoundaryRecovery3::default().run(&plc).unwrap();
    check(&plc, &kept, 26.0);
    assert_eq!(kept.history.planar_flips, 0, "one facet per triangle");
    assert!(kept.history.points_added() > 0, "{}", kept.history);
    let merged = BoundaryRecovery3::default()
        .merge_coplanar(true)
        .run(&plc)
        .unwrap();
    check_with(&plc, &merged, 26.0, Coverage::Planes);
    assert!(merged.history.planar_flips > 0, "{}", merged.history);
    assert_eq!(merged.history.points_added(), 0, "{}", merged.history);
    assert!(merged
        .history
        .to_string()
        .contains("diagonals flipped in planar patches"));
}

#[test]
fn the_triangles_of_one_polygon_facet_are_retriangulated_without_merging() {
    // Each grid square is one (quadrilateral) facet, triangulated into two triangles.
    let (p, t) = box_surface([0.0; 3], [1.0; 3], 4, true);
    let mut plc = Plc3::default();
    add_surface(&mut plc, &p, &t, 1);
    for (k, tr) in plc.triangles.iter_mut().enumerate() {
        tr.facet = (k / 2) as u32;
    }
    let mesh = BoundaryRecovery3::default().run(&plc).unwrap();
    check_with(&plc, &mesh, 1.0, Coverage::Planes);
    assert!(mesh.history.planar_flips > 0, "{}", mesh.history);
    assert_eq!(mesh.history.points_added(), 0, "{}", mesh.history);
    // Every square is still covered by boundary faces of its own facet.
    let arrays = mesh.to_arrays();
    let mut by_facet: HashMap<u32, f64> = HashMap::new();
    for (t, &f) in arrays.faces.iter().zip(&arrays.face_facets) {
        let q = t.map(|i| arrays.coords[i as usize]);
        *by_facet.entry(f).or_default() += area(q[0], q[1], q[2]);
    }
    assert_eq!(by_facet.len(), plc.triangles.len() / 2);
    for a in by_facet.values() {
        assert!((a - 1.0 / 16.0).abs() < 1e-12, "a square's faces cover {a}");
    }
}

#[test]
fn no_flip_across_a_bend_or_between_markers() {
    // A sphere has no coplanar neighbours; a box whose triangles all carry different markers
    // has no flippable pair.
    let (q, s) = icosphere([0.0; 3], 1.0, 2);
    let sphere = enclosed_volume(&q, &s);
    let mut plc = Plc3::default();
    add_surface(&mut plc, &q, &s, 1);
    let mesh = BoundaryRecovery3::default()
        .merge_coplanar(true)
        .run(&plc)
        .unwrap();
    assert_eq!(mesh.history.planar_flips, 0);
    check(&plc, &mesh, sphere);
    let (p, t) = box_surface([0.0; 3], [1.0; 3], 3, true);
    let mut plc = Plc3::default();
    for (k, tri) in t.iter().enumerate() {
        plc.triangles.push(SurfaceTriangle {
            v: *tri,
            marker: k as i32,
            facet: k as u32,
        });
    }
    plc.points = p;
    let mesh = BoundaryRecovery3::default()
        .merge_coplanar(true)
        .run(&plc)
        .unwrap();
    assert_eq!(mesh.history.planar_flips, 0);
    check(&plc, &mesh, 1.0);
}

/// A box of grid squares whose points inside each face are moved at random within the face's
/// plane (exactly: the fixed coordinate is untouched), so the faces' diagonals are neither
/// co-circular ties nor Delaunay. Each coordinate moves less than 0.15 of a square: a corner
/// then moves less than 0.22 of it, and the three corners of a triangle (half a square, each
/// corner at least 0.7 of a square from the line through the other two) cannot fold it over.
/// (It was 0.3: seed 818, n = 5 folded a triangle over a point of its face.)
fn jittered_box(seed: u64, n: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let (mut p, t) = box_surface([0.0; 3], [1.0; 3], n, true);
    let mut rng = StdRng::seed_from_u64(seed);
    let h = 0.15 / n as f64;
    for q in &mut p {
        let on_side: Vec<usize> = (0..3).filter(|&k| q[k] == 0.0 || q[k] == 1.0).collect();
        if on_side.len() == 1 {
            for (k, x) in q.iter_mut().enumerate() {
                if k != on_side[0] {
                    *x += rng.gen_range(-h..h);
                }
            }
        }
    }
    (p, t)
}

/// Every box the property tests below can draw is a valid surface (they draw 10 at random per
/// run; a folded one failed a run once).
#[test]
fn every_jittered_box_is_a_valid_surface() {
    for n in 2..6 {
        for seed in 0..1000 {
            let (p, t) = jittered_box(seed, n);
            let mut plc = Plc3::default();
            add_surface(&mut plc, &p, &t, 1);
            if let Err(e) = check_surface(&plc) {
                panic!("seed {seed}, n {n}: {e}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10))]
    /// Planar flips keep the surface on random flat faces, merged or not, and merging never
    /// needs more points.
    #[test]
    fn planar_flips_keep_jittered_faces(seed in 0u64..1000, n in 2usize..6) {
        let (p, t) = jittered_box(seed, n);
        let mut plc = Plc3::default();
        add_surface(&mut plc, &p, &t, 1);
        let kept = BoundaryRecovery3::default().run(&plc).unwrap();
        check(&plc, &kept, 1.0);
        let merged = BoundaryRecovery3::default().merge_coplanar(true).run(&plc).unwrap();
        check_with(&plc, &merged, 1.0, Coverage::Planes);
        prop_assert!(merged.history.planar_flips > 0);
        prop_assert!(merged.history.points_added() <= kept.history.points_added());
    }
}

#[test]
fn a_trusted_surface_naming_a_missing_point_is_an_error() {
    // The checks are skipped, and two triangles share a facet (so the planar flips look at
    // it): the bad corner is still reported, not a panic.
    let (p, t) = box_surface([0.0; 3], [1.0; 3], 1, true);
    let mut plc = Plc3::default();
    add_surface(&mut plc, &p, &t, 1);
    for tr in &mut plc.triangles {
        tr.facet = 0;
    }
    plc.triangles[3].v[1] = 99;
    let err = BoundaryRecovery3::default()
        .trusted_surface()
        .run(&plc)
        .unwrap_err();
    assert!(
        matches!(err, RecoveryError::BadFacetPoint { point: 99, .. }),
        "{err}"
    );
}

/// The conforming and the constrained recovery of `plc`, both checked; the constrained one
/// adds no more points (when it fell back on the conforming one, exactly as many).
fn both_recoveries(plc: &Plc3, volume: f64, field: &[[f64; 3]]) -> (Mesh3, Mesh3) {
    // Every input triangle kept (no merging of coplanar facets, however many points).
    let conforming = BoundaryRecovery3::default()
        .coplanar_fallback(false)
        .with_points(field.to_vec())
        .run(plc)
        .unwrap();
    check(plc, &conforming, volume);
    let constrained = BoundaryRecovery3::new(RecoveryMethod3::Constrained)
        .coplanar_fallback(false)
        .with_points(field.to_vec())
        .run(plc)
        .unwrap();
    check(plc, &constrained, volume);
    let (a, b) = (
        conforming.history.points_added(),
        constrained.history.points_added(),
    );
    if constrained.history.constrained_fallback {
        assert_eq!(a, b, "{}", constrained.history);
    } else {
        assert!(
            b <= a,
            "constrained {b} > conforming {a}: {}",
            constrained.history
        );
    }
    (conforming, constrained)
}

#[test]
fn constrained_recovery_of_boxes_spheres_and_holes() {
    let (p, t) = box_surface([0.0; 3], [1.0; 3], 3, true);
    let mut plc = Plc3::default();
    add_surface(&mut plc, &p, &t, 1);
    let (_, cube) = both_recoveries(&plc, 1.0, &[]);
    assert!(!cube.history.constrained_fallback, "{}", cube.history);

    let (plc, volume) = sphere_in_box();
    both_recoveries(&plc, volume, &[]);

    let (plc, field) = cube_with_cubic_hole_and_field();
    let (conforming, constrained) = both_recoveries(&plc, 26.0, &field);
    assert!(
        constrained.history.flipped_in > 0,
        "{}",
        constrained.history
    );
    assert!(
        constrained.history.points_added() < conforming.history.points_added(),
        "{}",
        constrained.history
    );
    let shown = constrained.history.to_string();
    assert!(
        shown.contains("Edges and faces recovered by flips:"),
        "{shown}"
    );
}

/// A closed cylinder of long, thin side triangles (height 12, radius 1, 24 around, no ring in
/// between: the kind of surface a CAD exporter makes). The conforming recovery must split
/// the long edges many times; flips recover them with few points.
#[test]
fn constrained_recovery_of_a_cylinder_of_thin_triangles() {
    let n = 24u32;
    let mut p: Vec<[f64; 3]> = Vec::new();
    for z in [0.0, 12.0] {
        for k in 0..n {
            let a = 2.0 * std::f64::consts::PI * f64::from(k) / f64::from(n);
            p.push([a.cos(), a.sin(), z]);
        }
    }
    p.push([0.0, 0.0, 0.0]);
    p.push([0.0, 0.0, 12.0]);
    let (bottom, top) = (2 * n, 2 * n + 1);
    let mut t = Vec::new();
    for k in 0..n {
        let k1 = (k + 1) % n;
        t.push([k, k1, n + k1]);
        t.push([k, n + k1, n + k]);
        t.push([bottom, k1, k]);
        t.push([top, n + k, n + k1]);
    }
    let mut plc = Plc3::default();
    add_surface(&mut plc, &p, &t, 1);
    let volume = enclosed_volume(&p, &t);
    let (conforming, constrained) = both_recoveries(&plc, volume, &[]);
    assert!(!constrained.history.constrained_fallback);
    assert!(
        4 * constrained.history.points_added() < conforming.history.points_added(),
        "constrained {} against conforming {}",
        constrained.history,
        conforming.history
    );
}

/// A cylinder of `n` sides and `m` rings whose flat caps are fans from one rim vertex: long
/// thin triangles whose corners are co-circular, as CAD exporters write them.
fn fan_capped_cylinder(n: u32, height: f64, m: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut p = Vec::new();
    for j in 0..=m {
        for k in 0..n {
            let a = 2.0 * std::f64::consts::PI * f64::from(k) / f64::from(n);
            p.push([a.cos(), a.sin(), height * f64::from(j) / f64::from(m)]);
        }
    }
    let at = |j: u32, k: u32| j * n + k % n;
    let mut t = Vec::new();
    for j in 0..m {
        for k in 0..n {
            t.push([at(j, k), at(j, k + 1), at(j + 1, k + 1)]);
            t.push([at(j, k), at(j + 1, k + 1), at(j + 1, k)]);
        }
    }
    for k in 1..n - 1 {
        t.push([at(0, 0), at(0, k + 1), at(0, k)]);
        t.push([at(m, 0), at(m, k), at(m, k + 1)]);
    }
    (p, t)
}

/// Where flips and the points added after them do not finish (the caps of a fan-capped
/// cylinder, unmerged: every fan edge crosses edges of the caps' own co-circular
/// triangulation, in one plane), the constrained recovery gives way to the conforming one,
/// whose result it then is; that one needs more than the 10,000 points the bound once was.
#[test]
fn a_constrained_recovery_that_does_not_finish_falls_back_on_the_conforming_one() {
    let (p, t) = fan_capped_cylinder(128, 1.0, 4);
    let mut plc = Plc3::default();
    add_surface(&mut plc, &p, &t, 1);
    let volume = enclosed_volume(&p, &t);
    let (conforming, constrained) = both_recoveries(&plc, volume, &[]);
    assert!(conforming.history.points_added() > 10_000);
    // (If flips learn to finish this one, pick another input that exercises the fallback.)
    assert!(
        constrained.history.constrained_fallback,
        "{}",
        constrained.history
    );
    assert!(constrained
        .history
        .to_string()
        .contains("the conforming recovery follows"));
    // Merged, its caps need no point at all.
    let merged = BoundaryRecovery3::new(RecoveryMethod3::Constrained)
        .merge_coplanar(true)
        .run(&plc)
        .unwrap();
    check_with(&plc, &merged, volume, Coverage::Planes);
    assert_eq!(merged.history.points_added(), 0, "{}", merged.history);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10))]
    /// The constrained recovery on random flat faces (merged or not) and on random field
    /// points around a sphere.
    #[test]
    fn constrained_recovery_keeps_random_surfaces(seed in 0u64..1000, n in 2usize..6) {
        let (p, t) = jittered_box(seed, n);
        let mut plc = Plc3::default();
        add_surface(&mut plc, &p, &t, 1);
        both_recoveries(&plc, 1.0, &[]);
        let merged = BoundaryRecovery3::new(RecoveryMethod3::Constrained)
            .merge_coplanar(true)
            .run(&plc)
            .unwrap();
        check_with(&plc, &merged, 1.0, Coverage::Planes);

        let mut rng = StdRng::seed_from_u64(seed);
        let mut plc = Plc3::default();
        let (p, t) = box_surface([0.0; 3], [2.0; 3], 3, true);
        add_surface(&mut plc, &p, &t, 1);
        let c = [0, 1, 2].map(|_| rng.gen_range(0.8..1.2));
        let (q, s) = icosphere(c, rng.gen_range(0.3..0.6), 1);
        let vs = enclosed_volume(&q, &s);
        add_surface(&mut plc, &q, &s, 2);
        let field: Vec<[f64; 3]> =
            (0..60 * n).map(|_| [0, 1, 2].map(|_| rng.gen_range(0.0..2.0))).collect();
        both_recoveries(&plc, 8.0 - vs, &field);
    }
}

/// The pyramid of [`an_element_lying_flat_on_a_facet_is_taken_out`] (points `p q r s` and
/// apex `e`, its triangles), recovered, then the edge `r s` flipped in: the flat element
/// `p q r s` lies on the two base triangles, of one facet (`one_facet`) or of two, with one
/// marker (`one_marker`) or two.
fn pyramid_with_a_flat_element(
    one_facet: bool,
    one_marker: bool,
) -> (Mesh3, [[f64; 3]; 5], [[u32; 3]; 6]) {
    let points = [
        [1.0, -0.5, 0.0],
        [1.0, 0.5, 0.0],
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 1e-12],
        [1.0, 0.0, 3.0],
    ];
    let tris = [
        [0, 2, 1],
        [1, 3, 0],
        [2, 0, 4],
        [1, 2, 4],
        [3, 1, 4],
        [0, 3, 4],
    ];
    let plc = Plc3 {
        points: points.to_vec(),
        triangles: tris
            .iter()
            .enumerate()
            .map(|(k, &v)| SurfaceTriangle {
                v,
                marker: if one_marker || k > 0 { 1 } else { 2 },
                facet: if one_facet { k.saturating_sub(1) } else { k } as u32,
            })
            .collect(),
        ..Plc3::default()
    };
    let mut mesh = BoundaryRecovery3::new(RecoveryMethod3::Conforming)
        .run(&plc)
        .expect("recovered");
    assert_eq!(mesh.history.points_added(), 0);
    assert_eq!(flat_elements(&mesh), 0);
    let v = |i: usize| mesh.ct.triangulation().vertex_of_input(i);
    let (r, s) = (v(2), v(3));
    let made = mesh
        .ct
        .flip_in_edge(r, s, &|_: VertexId, _: VertexId| false, 4, &mut Vec::new());
    assert_eq!(made, FlipIn::Present(1), "one 2-3 flip");
    assert_eq!(flat_elements(&mesh), 1, "the flip made the flat element");
    assert_eq!(mesh.num_elements(), 3);
    (mesh, points, tris)
}

/// Elements of volume under 10^-9 (the flat one of [`pyramid_with_a_flat_element`]).
fn flat_elements(mesh: &Mesh3) -> usize {
    let tri = mesh.ct.triangulation();
    mesh.elements()
        .filter(|&c| {
            let v = tri.cell(c);
            let p = [0, 1, 2, 3].map(|k| tri.vertex(v[k]));
            tet_volume(p[0], p[1], p[2], p[3]).abs() < 1e-9
        })
        .count()
}

/// A pyramid whose base is one facet of two triangles on the diagonal `p q`, `s` lifted
/// 10^-12 off the plane: after recovery, a 2-3 flip making the edge `r s` (as Delaunay
/// restoration flips near the surface do) leaves the flat element `p q r s` lying on both base
/// triangles. Taking it out swaps the base's diagonal, keeps the volume and covers the base as
/// before. Where the two triangles are two facets of one marker it goes too (the surface moves
/// by its volume); where they have two markers, it stays (the line between them would move).
#[test]
fn an_element_lying_flat_on_a_facet_is_taken_out() {
    let (mut two, _, _) = pyramid_with_a_flat_element(false, false);
    assert_eq!(two.remove_flat_surface_elements(), 0);
    let (mut two, _, _) = pyramid_with_a_flat_element(false, true);
    assert_eq!(two.remove_flat_surface_elements(), 1);
    assert_eq!(flat_elements(&two), 0);
    let (mut mesh, points, tris) = pyramid_with_a_flat_element(true, true);
    let volume = enclosed_volume(&points, &tris);
    assert_eq!(mesh.remove_flat_surface_elements(), 1);
    assert_eq!(flat_elements(&mesh), 0);
    assert_eq!(mesh.num_elements(), 2);
    assert!((mesh.volume() - volume).abs() <= 1e-12 * volume);
    // The base is now the triangles on the diagonal r s, oriented as the input's (outward),
    // and every boundary face is a face of an element, with the element on its inner side.
    let mut base: Vec<[u32; 3]> = mesh
        .faces
        .iter()
        .filter(|f| f.facet == 0)
        .map(|f| {
            let mut v = f.v.map(|u| mesh.ct.triangulation().input_index(u) as u32);
            let first = (0..3).min_by_key(|&k| v[k]).unwrap_or(0);
            v.rotate_left(first);
            v
        })
        .collect();
    base.sort_unstable();
    assert_eq!(base, vec![[0, 2, 3], [1, 3, 2]]);
    // The protected faces are the boundary faces.
    let sorted = |mut v: [VertexId; 3]| {
        v.sort_unstable();
        v
    };
    let mut protected: Vec<_> = mesh.ct.protected_faces().into_iter().map(sorted).collect();
    let mut faces: Vec<_> = mesh.faces.iter().map(|f| sorted(f.v)).collect();
    protected.sort_unstable();
    faces.sort_unstable();
    assert_eq!(protected, faces);
    let tri = mesh.ct.triangulation();
    for f in &mesh.faces {
        let p = f.v.map(|u| tri.vertex(u));
        let inner = mesh.elements().find_map(|c| {
            let v = tri.cell(c);
            let d = v.iter().find(|u| !f.v.contains(u))?;
            (v.iter().filter(|u| f.v.contains(u)).count() == 3).then_some(*d)
        });
        let d = inner.expect("a boundary face is a face of an element");
        assert_eq!(
            orient3d(p[0], p[1], p[2], tri.vertex(d)),
            Sign::Negative,
            "the element is on the inner side of {:?}",
            f.v
        );
    }
}

#[test]
fn flat_surface_tetrahedra_deep_in_the_domain_are_left_to_field_points() {
    // All the points of a fine icosphere lie on one sphere: two neighbouring surface triangles
    // nearly coplanar make a flat tetrahedron whose circumsphere is the sphere itself, which
    // any field point removes. When field points follow, recovery leaves those to them instead
    // of splitting the edge under each (2,384 surface points here, for nothing; at level 5
    // no two neighbours are flat enough); without field points to follow, it still splits.
    let (p, t) = icosphere([0.0; 3], 1.0, 6);
    let mut plc = Plc3::default();
    add_surface(&mut plc, &p, &t, 1);
    let volume = enclosed_volume(&p, &t);
    let alone = BoundaryRecovery3::default().run(&plc).unwrap();
    let followed = BoundaryRecovery3::default()
        .field_points_follow(true)
        .run(&plc)
        .unwrap();
    check(&plc, &followed, volume);
    assert!(alone.history.points_added() > 1000, "{}", alone.history);
    assert_eq!(followed.history.points_added(), 0, "{}", followed.history);
}
