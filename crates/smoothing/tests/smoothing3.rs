//! 3D smoothing never inverts a tetrahedron, never moves a fixed point, conserves the volume of
//! a mesh with a fixed boundary, improves a jittered grid and keeps its dihedral guard; the
//! tetrahedral quality report gives the exact angles of known shapes and is stable.

use delmesh_delaunay_core::{Triangulation3, VertexId};
use delmesh_predicates::{orient3d, Sign};
use delmesh_smoothing::{
    DihedralGuard, QualityReport3, SmoothError, Smoother3, REGULAR_DIHEDRAL, SLIVER_ANGLE,
};
use proptest::prelude::*;
use rand::{rngs::StdRng, Rng, SeedableRng};

type Mesh = (Vec<[f64; 3]>, Vec<[u32; 4]>, Vec<bool>);

fn positive(pts: &[[f64; 3]], t: &[u32; 4]) -> bool {
    let p = t.map(|v| pts[v as usize]);
    orient3d(p[0], p[1], p[2], p[3]) == Sign::Positive
}

fn all_positive(pts: &[[f64; 3]], tets: &[[u32; 4]]) -> bool {
    tets.iter().all(|t| positive(pts, t))
}

/// A k × k × k grid of unit cubes, each split into the six Kuhn tetrahedra (one per order of
/// the axes along the cube's main diagonal: the split matches across faces), positively
/// oriented; boundary points fixed, interior ones jittered by up to `jitter` per axis.
fn kuhn_grid(k: usize, jitter: f64, seed: u64) -> Mesh {
    let mut rng = StdRng::seed_from_u64(seed);
    let id = |i: usize, j: usize, l: usize| ((l * (k + 1) + j) * (k + 1) + i) as u32;
    let (mut pts, mut fixed) = (Vec::new(), Vec::new());
    for l in 0..=k {
        for j in 0..=k {
            for i in 0..=k {
                let edge = [i, j, l].iter().any(|&c| c == 0 || c == k);
                let mut p = [i as f64, j as f64, l as f64];
                if !edge && jitter > 0.0 {
                    for c in &mut p {
                        *c += rng.gen_range(-jitter..jitter);
                    }
                }
                pts.push(p);
                fixed.push(edge);
            }
        }
    }
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut tets = Vec::new();
    for l in 0..k {
        for j in 0..k {
            for i in 0..k {
                for perm in perms {
                    let mut c = [i, j, l];
                    let mut t = [id(c[0], c[1], c[2]); 4];
                    for (s, &axis) in perm.iter().enumerate() {
                        c[axis] += 1;
                        t[s + 1] = id(c[0], c[1], c[2]);
                    }
                    // Odd orders of the axes give negative tetrahedra.
                    let p = t.map(|v| [0, 1, 2].map(|a| (v as usize / (k + 1).pow(a)) % (k + 1)));
                    let p = p.map(|q| q.map(|x| x as f64));
                    if orient3d(p[0], p[1], p[2], p[3]) != Sign::Positive {
                        t.swap(2, 3);
                    }
                    tets.push(t);
                }
            }
        }
    }
    (pts, tets, fixed)
}

/// The Delaunay tetrahedralisation of `n` random points in the unit cube, hull points fixed.
fn delaunay_cloud(n: usize, seed: u64) -> Mesh {
    let mut rng = StdRng::seed_from_u64(seed);
    let input: Vec<[f64; 3]> = (0..n).map(|_| [rng.gen(), rng.gen(), rng.gen()]).collect();
    let tri = Triangulation3::new(&input).unwrap();
    let pts: Vec<[f64; 3]> = (0..tri.num_vertices() as u32)
        .map(|v| tri.vertex(VertexId(v)))
        .collect();
    let tets: Vec<[u32; 4]> = tri
        .cells()
        .map(|c| {
            let v = tri.cell(c);
            [v[0].0, v[1].0, v[2].0, v[3].0]
        })
        .collect();
    let mut fixed = vec![false; pts.len()];
    for c in tri.all_cells().filter(|&c| tri.is_ghost(c)) {
        for v in tri.cell(c).iter().filter(|v| !v.is_ghost()) {
            fixed[v.index()] = true;
        }
    }
    (pts, tets, fixed)
}

/// Moves each free point by up to `scale` per axis at random, undoing any move that would
/// leave a tetrahedron around it non-positive.
fn jitter(mesh: &mut Mesh, scale: f64, seed: u64) {
    let (pts, tets, fixed) = mesh;
    let mut rng = StdRng::seed_from_u64(seed);
    let mut star = vec![Vec::new(); pts.len()];
    for (k, t) in tets.iter().enumerate() {
        for &v in t {
            star[v as usize].push(k);
        }
    }
    for v in 0..pts.len() {
        if fixed[v] {
            continue;
        }
        let old = pts[v];
        for x in &mut pts[v] {
            *x += rng.gen_range(-scale..scale);
        }
        if !star[v].iter().all(|&k| positive(pts, &tets[k])) {
            pts[v] = old;
        }
    }
}

/// The smallest dihedral angle of the tetrahedra.
fn min_dihedral(pts: &[[f64; 3]], tets: &[[u32; 4]]) -> f64 {
    QualityReport3::of_tetrahedra(pts, tets).min_dihedral
}

#[test]
fn regular_tetrahedron_report() {
    let pts = [
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, -1.0],
        [1.0, -1.0, -1.0],
        [-1.0, -1.0, 1.0],
    ];
    let tets = [[0, 1, 2, 3]];
    assert!(all_positive(&pts, &tets));
    let q = QualityReport3::of_tetrahedra(&pts, &tets);
    let want = (1.0f64 / 3.0).acos().to_degrees();
    assert!((q.min_dihedral - want).abs() < 1e-12, "{}", q.min_dihedral);
    assert!((q.max_dihedral - want).abs() < 1e-12, "{}", q.max_dihedral);
    assert!((REGULAR_DIHEDRAL - want).abs() < 1e-12);
    // Edge 2√2: volume (2√2)³ / (6√2) = 8/3; circumradius √3, so √3 / 2√2 = √6/4.
    assert!((q.total_volume - 8.0 / 3.0).abs() < 1e-14);
    assert_eq!(q.min_volume, q.max_volume);
    assert!((q.mean_radius_edge - 6f64.sqrt() / 4.0).abs() < 1e-15);
    assert_eq!(q.min_dihedral_histogram, [0, 0, 0, 0, 0, 0, 0, 1]);
    assert_eq!((q.slivers, q.non_positive, q.elements), (0, 0, 1));
    // No shared face.
    assert_eq!(q.max_neighbour_volume_ratio, 1.0);
}

#[test]
fn sliver_report() {
    // Two skew edges of length 2 at heights ∓h over the square (±1, 0), (0, ±1): the classic
    // sliver. The four side edges have dihedral angle acos(1 / (1 + 4h²)), the two others
    // 2·atan(1 / 2h); circumcentre at the origin, radius √(1 + h²); shortest edge √(2 + 4h²).
    let h: f64 = 0.025;
    let pts = [
        [-1.0, 0.0, -h],
        [1.0, 0.0, -h],
        [0.0, 1.0, h],
        [0.0, -1.0, h],
    ];
    let tets = [[0, 1, 2, 3]];
    assert!(all_positive(&pts, &tets));
    let q = QualityReport3::of_tetrahedra(&pts, &tets);
    let side = (1.0 / (1.0 + 4.0 * h * h)).acos().to_degrees();
    let top = 2.0 * (1.0 / (2.0 * h)).atan().to_degrees();
    assert!(side < SLIVER_ANGLE && side > 4.0, "{side}");
    assert!(
        (q.min_dihedral - side).abs() < 1e-9,
        "{} {side}",
        q.min_dihedral
    );
    assert!(
        (q.max_dihedral - top).abs() < 1e-9,
        "{} {top}",
        q.max_dihedral
    );
    assert!((q.total_volume - 4.0 * h / 3.0).abs() < 1e-15);
    let ratio = (1.0 + h * h).sqrt() / (2.0 + 4.0 * h * h).sqrt();
    assert!((q.max_radius_edge - ratio).abs() < 1e-12);
    // A radius–edge ratio of about 0.71 would pass as good: the dihedral angles are what
    // catches a sliver.
    assert!(q.max_radius_edge < 0.75);
    assert_eq!(q.slivers, 1);
    assert_eq!(q.min_dihedral_histogram[0], 1);
}

#[test]
fn report_counts_inverted_and_neighbours() {
    let pts = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -3.0],
    ];
    // Two tetrahedra on the face 0 1 2, of volumes 1/6 and 1/2; then one flipped.
    let tets = [[0, 1, 2, 3], [0, 2, 1, 4]];
    let q = QualityReport3::of_tetrahedra(&pts, &tets);
    assert_eq!(q.non_positive, 0);
    assert!((q.max_neighbour_volume_ratio - 3.0).abs() < 1e-12);
    assert!((q.mean_neighbour_volume_ratio - 3.0).abs() < 1e-12);
    assert!((q.total_volume - 2.0 / 3.0).abs() < 1e-15);
    let q = QualityReport3::of_tetrahedra(&pts, &[[0, 1, 2, 3], [0, 1, 2, 4]]);
    assert_eq!(q.non_positive, 1);
    assert!((q.min_volume + 0.5).abs() < 1e-15);
    // A point out of range shows up instead of being hidden.
    let q = QualityReport3::of_tetrahedra(&pts, &[[0, 1, 2, 99]]);
    assert_eq!((q.non_positive, q.slivers), (1, 1));
    assert!(q.total_volume.is_nan());
    assert!(q.to_json().contains("\"total_volume\": null"));
    assert_eq!(QualityReport3::of_tetrahedra(&pts, &[]).elements, 0);
}

#[test]
fn a_jittered_grid_gets_better_and_keeps_its_volume() {
    let (mut pts, tets, fixed) = kuhn_grid(6, 0.3, 3);
    assert!(all_positive(&pts, &tets));
    let before = QualityReport3::of_tetrahedra(&pts, &tets);
    let original = pts.clone();
    for guard in [
        DihedralGuard::Off,
        DihedralGuard::Floor(20.0),
        DihedralGuard::NoDecrease,
    ] {
        pts.clone_from(&original);
        let stats = Smoother3::new()
            .dihedral_guard(guard)
            .unwrap()
            .smooth(&mut pts, &tets, &fixed)
            .unwrap();
        assert!(stats.moved > 0);
        assert!(all_positive(&pts, &tets));
        let after = QualityReport3::of_tetrahedra(&pts, &tets);
        assert!(
            after.min_dihedral > before.min_dihedral + 2.0,
            "{guard:?}: {} → {}",
            before.min_dihedral,
            after.min_dihedral
        );
        assert!(
            after.mean_min_dihedral > before.mean_min_dihedral + 2.0,
            "{guard:?}: {} → {}",
            before.mean_min_dihedral,
            after.mean_min_dihedral
        );
        assert!(after.mean_radius_edge < before.mean_radius_edge);
        assert!((after.total_volume - 216.0).abs() < 1e-10);
        for (i, &f) in fixed.iter().enumerate() {
            if f {
                assert_eq!(pts[i], original[i]);
            }
        }
    }
}

#[test]
fn the_unjittered_grid_is_a_fixed_point() {
    // Every interior point of the Kuhn grid is the mean of its 14 neighbours.
    let (mut pts, tets, fixed) = kuhn_grid(3, 0.0, 0);
    let original = pts.clone();
    let stats = Smoother3::new().smooth(&mut pts, &tets, &fixed).unwrap();
    assert_eq!(stats.passes, 1);
    assert_eq!(pts, original);
}

#[test]
fn a_point_that_plain_laplace_would_push_out_stays_inside() {
    // The centre's star is a non-convex bipyramid: the mean of its neighbours lies beyond the
    // reflex vertex, so a full step (ω = 1) would invert tetrahedra.
    let ring = [
        [3.0, -1.0],
        [-0.5, 0.0],
        [3.0, 1.0],
        [-1.5, 1.0],
        [-1.5, -1.0],
    ];
    let mut pts = vec![[-1.0, 0.0, 0.0]];
    pts.extend(ring.iter().map(|q| [q[0], q[1], 0.0]));
    pts.push([-1.0, 0.0, 1.0]);
    pts.push([-1.0, 0.0, -1.0]);
    let mut tets = Vec::new();
    for i in 0..5u32 {
        let (a, b) = (1 + i, 1 + (i + 1) % 5);
        tets.push([0, a, b, 6]);
        tets.push([0, b, a, 7]);
    }
    assert!(all_positive(&pts, &tets));
    let mut fixed = vec![true; pts.len()];
    fixed[0] = false;
    let stats = Smoother3::new()
        .omega(1.0)
        .unwrap()
        .dihedral_guard(DihedralGuard::Off)
        .unwrap()
        .iterations(50)
        .smooth(&mut pts, &tets, &fixed)
        .unwrap();
    assert!(stats.reduced + stats.skipped > 0, "{stats}");
    assert!(all_positive(&pts, &tets));
}

#[test]
fn bad_input_is_an_error() {
    assert_eq!(Smoother3::new().omega(0.0), Err(SmoothError::BadOmega(0.0)));
    assert!(Smoother3::new().omega(1.5).is_err());
    assert!(Smoother3::new().omega(f64::NAN).is_err());
    for f in [0.0, -1.0, 180.0, f64::NAN, f64::INFINITY] {
        assert!(Smoother3::new()
            .dihedral_guard(DihedralGuard::Floor(f))
            .is_err());
    }
    let s = Smoother3::new();
    let (mut pts, tets, fixed) = kuhn_grid(2, 0.0, 0);
    let err = |r: Result<_, SmoothError>| match r {
        Err(SmoothError::BadInput(m)) => m,
        other => panic!("expected an error, got {other:?}"),
    };
    let m = err(s.smooth(&mut pts, &tets, &fixed[..3]));
    assert!(m.contains("fixed flags"), "{m}");
    let m = err(s.smooth(&mut pts, &[[0, 1, 2, 99]], &fixed));
    assert!(m.contains("out of range"), "{m}");
    let mut flipped = tets.clone();
    flipped[5].swap(0, 1);
    let m = err(s.smooth(&mut pts, &flipped, &fixed));
    assert!(
        m.contains("tetrahedron 5") && m.contains("not positively"),
        "{m}"
    );
    // Flat and repeated-vertex tetrahedra are not positive either.
    assert!(s.smooth(&mut pts, &[[0, 1, 2, 2]], &fixed).is_err());
    assert!(s.smooth(&mut pts, &[[0, 1, 2, 3]], &fixed).is_err()); // 0 1 2 collinear
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut p = pts.clone();
        p[13] = [bad, 0.0, 0.0];
        let m = err(s.smooth(&mut p, &tets, &fixed));
        assert!(m.contains("point 13"), "{m}");
    }
    // Nothing to do is fine.
    assert_eq!(s.smooth(&mut pts, &[], &fixed).unwrap().passes, 0);
    assert_eq!(s.smooth(&mut [], &[], &[]).unwrap().passes, 0);
}

#[test]
fn far_scales_smooth_as_ordinary_ones() {
    // Beyond the magnitudes the predicates take exactly, the smoother works on a copy scaled
    // by a power of two: the moves are the ordinary ones, scaled.
    let mut mesh = delaunay_cloud(600, 21);
    jitter(&mut mesh, 0.02, 22);
    let (pts, tets, fixed) = mesh;
    let run = |scale: f64| {
        let mut p: Vec<[f64; 3]> = pts.iter().map(|q| q.map(|x| x * scale)).collect();
        let stats = Smoother3::new()
            .iterations(5)
            .smooth(&mut p, &tets, &fixed)
            .unwrap();
        let p: Vec<[f64; 3]> = p.iter().map(|q| q.map(|x| x / scale)).collect();
        (p, stats)
    };
    let ordinary = run(1.0);
    assert!(ordinary.1.moved > 0);
    for e in [250, 600, -250, -600] {
        assert_eq!(run(2f64.powi(e)), ordinary, "scale 2^{e}");
    }
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let mut mesh = delaunay_cloud(1500, 11);
    jitter(&mut mesh, 0.02, 12);
    let (pts, tets, fixed) = mesh;
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut p = pts.clone();
            let stats = Smoother3::new()
                .iterations(5)
                .smooth(&mut p, &tets, &fixed)
                .unwrap();
            let report = QualityReport3::of_tetrahedra(&p, &tets).to_json();
            (p, stats, report)
        })
    };
    let one = run(1);
    assert!(one.1.moved > 0);
    assert_eq!(one, run(3));
}

#[test]
fn quality_report_snapshot() {
    let (pts, tets, _) = kuhn_grid(3, 0.4, 7);
    assert!(all_positive(&pts, &tets));
    let q = QualityReport3::of_tetrahedra(&pts, &tets);
    insta::assert_snapshot!(format!("{q}{}", q.to_json()));
}

/// The Delaunay tetrahedralisation of a body-centred cubic lattice with `k` cells per axis in
/// the unit cube, jittered (boundary points stay on the faces): well spaced, like the points
/// of mesh generation, with a few slivers as Delaunay meshes of such points have.
fn spaced_lattice(k: usize, seed: u64) -> Mesh {
    let mut rng = StdRng::seed_from_u64(seed);
    let h = 1.0 / k as f64;
    let mut input = Vec::new();
    for l in 0..=k {
        for j in 0..=k {
            for i in 0..=k {
                let on = [i, j, l];
                input.push(on.map(|c| {
                    let x = c as f64 * h;
                    if c == 0 || c == k {
                        x
                    } else {
                        x + rng.gen_range(-0.2..0.2) * h
                    }
                }));
                if i < k && j < k && l < k {
                    input.push(on.map(|c| (c as f64 + 0.5 + rng.gen_range(-0.2..0.2)) * h));
                }
            }
        }
    }
    let tri = Triangulation3::new(&input).unwrap();
    let pts: Vec<[f64; 3]> = (0..tri.num_vertices() as u32)
        .map(|v| tri.vertex(VertexId(v)))
        .collect();
    let tets = tri
        .cells()
        .map(|c| {
            let v = tri.cell(c);
            [v[0].0, v[1].0, v[2].0, v[3].0]
        })
        .collect();
    let mut fixed = vec![false; pts.len()];
    for c in tri.all_cells().filter(|&c| tri.is_ghost(c)) {
        for v in tri.cell(c).iter().filter(|v| !v.is_ghost()) {
            fixed[v.index()] = true;
        }
    }
    (pts, tets, fixed)
}

#[test]
fn the_dihedral_guard_keeps_smoothing_from_making_slivers() {
    let (pts, tets, fixed) = spaced_lattice(6, 5);
    let before = QualityReport3::of_tetrahedra(&pts, &tets);
    let run = |guard| {
        let mut p = pts.clone();
        Smoother3::new()
            .dihedral_guard(guard)
            .unwrap()
            .smooth(&mut p, &tets, &fixed)
            .unwrap();
        assert!(all_positive(&p, &tets));
        QualityReport3::of_tetrahedra(&p, &tets)
    };
    let off = run(DihedralGuard::Off);
    let guarded = run(DihedralGuard::Floor(20.0));
    eprintln!("before {before}\noff {off}\nguarded {guarded}");
    // Plain smoothing improves the mean but makes slivers; the guard does not.
    assert!(off.mean_min_dihedral > before.mean_min_dihedral);
    assert!(
        off.slivers > before.slivers,
        "{} {}",
        off.slivers,
        before.slivers
    );
    assert!(guarded.slivers <= before.slivers);
    assert!(guarded.min_dihedral >= before.min_dihedral.min(20.0) - 1e-9);
    assert!(guarded.mean_min_dihedral > before.mean_min_dihedral);
}

fn guard_strategy() -> impl Strategy<Value = DihedralGuard> {
    prop_oneof![
        Just(DihedralGuard::Off),
        (1.0f64..40.0).prop_map(DihedralGuard::Floor),
        Just(DihedralGuard::NoDecrease),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    #[test]
    fn smoothing_never_inverts(
        seed in 0u64..10_000,
        n in 8usize..160,
        scale in 0.0f64..0.2,
        omega in 0.01f64..1.0,
        passes in 1usize..12,
        guard in guard_strategy(),
    ) {
        let mut mesh = delaunay_cloud(n, seed);
        jitter(&mut mesh, scale, seed + 1);
        let (mut pts, tets, fixed) = mesh;
        prop_assert!(all_positive(&pts, &tets));
        let original = pts.clone();
        let before = QualityReport3::of_tetrahedra(&pts, &tets);
        Smoother3::new()
            .omega(omega).unwrap()
            .iterations(passes)
            .dihedral_guard(guard).unwrap()
            .smooth(&mut pts, &tets, &fixed)
            .unwrap();
        prop_assert!(all_positive(&pts, &tets));
        for (i, &f) in fixed.iter().enumerate() {
            if f {
                prop_assert_eq!(pts[i], original[i]);
            }
        }
        let after = QualityReport3::of_tetrahedra(&pts, &tets);
        prop_assert!((after.total_volume - before.total_volume).abs() < 1e-12);
        // The guard bounds the worst angle: it never drops below min(floor, worst before).
        let bound = match guard {
            DihedralGuard::Off => 0.0,
            DihedralGuard::Floor(f) => f.min(before.min_dihedral),
            DihedralGuard::NoDecrease => before.min_dihedral,
        };
        prop_assert!(after.min_dihedral >= bound - 1e-9, "{} < {}", after.min_dihedral, bound);
    }
}

#[test]
fn min_dihedral_helper_agrees_with_report() {
    let (pts, tets, _) = kuhn_grid(1, 0.0, 0);
    // The Kuhn tetrahedron's smallest dihedral angle is 45°.
    assert!((min_dihedral(&pts, &tets) - 45.0).abs() < 1e-12);
}
