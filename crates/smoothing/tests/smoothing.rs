//! Smoothing never inverts an element, never moves a fixed point, conserves the area of a mesh
//! with a fixed boundary, and improves a jittered grid; the quality report is stable.

use delmesh_predicates::{orient2d, Sign};
use delmesh_smoothing::{QualityReport, SmoothError, Smoother, Stars};
use proptest::prelude::*;
use rand::{rngs::StdRng, Rng, SeedableRng};

/// A k × k grid of unit squares split into triangles, interior points jittered by up to
/// `jitter` (≤ 0.25 keeps every triangle positive), boundary points fixed.
fn jittered_grid(k: usize, jitter: f64, seed: u64) -> (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<bool>) {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut pts = Vec::new();
    let mut fixed = Vec::new();
    for j in 0..=k {
        for i in 0..=k {
            let edge = i == 0 || j == 0 || i == k || j == k;
            let (dx, dy) = if edge || jitter == 0.0 {
                (0.0, 0.0)
            } else {
                (
                    rng.gen_range(-jitter..jitter),
                    rng.gen_range(-jitter..jitter),
                )
            };
            pts.push([i as f64 + dx, j as f64 + dy]);
            fixed.push(edge);
        }
    }
    let id = |i: usize, j: usize| (j * (k + 1) + i) as u32;
    let mut tris = Vec::new();
    for j in 0..k {
        for i in 0..k {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (pts, tris, fixed)
}

fn all_positive(pts: &[[f64; 2]], tris: &[[u32; 3]]) -> bool {
    tris.iter().all(|t| {
        let p = t.map(|v| pts[v as usize]);
        orient2d(p[0], p[1], p[2]) == Sign::Positive
    })
}

#[test]
fn a_jittered_grid_gets_better_and_keeps_its_area() {
    let (mut pts, tris, fixed) = jittered_grid(20, 0.25, 1);
    assert!(all_positive(&pts, &tris));
    let before = QualityReport::of_triangles(&pts, &tris);
    let original = pts.clone();
    let stats = Smoother::new().smooth(&mut pts, &tris, &fixed).unwrap();
    assert!(stats.moved > 0);
    assert!(all_positive(&pts, &tris));
    let after = QualityReport::of_triangles(&pts, &tris);
    assert!(
        after.min_angle > before.min_angle + 5.0,
        "{} → {}",
        before.min_angle,
        after.min_angle
    );
    assert!((after.total_area - 400.0).abs() < 1e-9);
    for (i, &f) in fixed.iter().enumerate() {
        if f {
            assert_eq!(pts[i], original[i]);
        }
    }
}

#[test]
fn a_point_that_plain_laplace_would_push_out_stays_inside() {
    // A non-convex star: the centre's neighbours' mean lies outside its star polygon, so a
    // full Laplacian step (ω = 1) would invert elements.
    // The neighbours' mean is (0.5, 0), beyond the reflex vertex (-0.5, 0).
    let pts0 = vec![
        [-1.0, 0.0], // centre
        [3.0, -1.0],
        [-0.5, 0.0], // reflex vertex
        [3.0, 1.0],
        [-1.5, 1.0],
        [-1.5, -1.0],
    ];
    let tris = vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5], [0, 5, 1]];
    let mut pts = pts0.clone();
    assert!(all_positive(&pts, &tris));
    let fixed = [false, true, true, true, true, true];
    Smoother::new()
        .omega(1.0)
        .unwrap()
        .iterations(50)
        .smooth(&mut pts, &tris, &fixed)
        .unwrap();
    assert!(all_positive(&pts, &tris));
}

#[test]
fn an_unflagged_point_on_the_border_stays_fixed() {
    // No point is flagged, but the border points' triangles do not close around them: they are
    // boundary and must not move (the domain keeps its shape and area).
    let (mut pts, tris, fixed) = jittered_grid(12, 0.2, 3);
    let original = pts.clone();
    let none = vec![false; pts.len()];
    let stats = Smoother::new().smooth(&mut pts, &tris, &none).unwrap();
    assert!(stats.moved > 0);
    for (i, &border) in fixed.iter().enumerate() {
        if border {
            assert_eq!(pts[i], original[i], "border point {i} moved");
        }
    }
    assert!(all_positive(&pts, &tris));
    assert!((QualityReport::of_triangles(&pts, &tris).total_area - 144.0).abs() < 1e-9);
}

#[test]
fn the_same_result_whatever_the_number_of_threads() {
    // Large enough that each colour is split into parallel chunks.
    let (pts, tris, fixed) = jittered_grid(90, 0.25, 11);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut p = pts.clone();
        let stats = pool.install(|| Smoother::new().smooth(&mut p, &tris, &fixed).unwrap());
        (p, stats)
    };
    let (one, stats_one) = run(1);
    for threads in [2, 3] {
        let (many, stats_many) = run(threads);
        assert_eq!(stats_one, stats_many);
        assert!(one
            .iter()
            .zip(&many)
            .all(|(a, b)| a[0].to_bits() == b[0].to_bits() && a[1].to_bits() == b[1].to_bits()));
    }
}

#[test]
fn bad_input_is_an_error() {
    assert_eq!(Smoother::new().omega(0.0), Err(SmoothError::BadOmega(0.0)));
    assert!(Smoother::new().omega(f64::NAN).is_err());
    let (mut pts, tris, fixed) = jittered_grid(2, 0.0, 0);
    assert!(Smoother::new()
        .smooth(&mut pts, &tris, &fixed[..3])
        .is_err());
    let bad = vec![[0, 1, 99]];
    assert!(Smoother::new().smooth(&mut pts, &bad, &fixed).is_err());
    let clockwise = vec![[0, 2, 1]];
    assert!(Smoother::new()
        .smooth(&mut pts, &clockwise, &fixed)
        .is_err());
    pts[4] = [f64::NAN, 0.0];
    assert!(Smoother::new().smooth(&mut pts, &tris, &fixed).is_err());
}

/// The stars of a k × k grid as `jittered_grid` triangulates it: each interior point's six
/// neighbours counter-clockwise (boundary points get none).
fn grid_stars(k: usize) -> Stars {
    let id = |i: usize, j: usize| (j * (k + 1) + i) as u32;
    let (mut start, mut ring) = (vec![0u32], Vec::new());
    for j in 0..=k {
        for i in 0..=k {
            if i > 0 && j > 0 && i < k && j < k {
                ring.extend([
                    id(i + 1, j),
                    id(i + 1, j + 1),
                    id(i, j + 1),
                    id(i - 1, j),
                    id(i - 1, j - 1),
                    id(i, j - 1),
                ]);
            }
            start.push(ring.len() as u32);
        }
    }
    Stars::from_rings(start, ring).unwrap()
}

#[test]
fn stars_given_smooth_as_the_triangles_do() {
    let (pts, tris, fixed) = jittered_grid(30, 0.25, 7);
    let (mut by_triangles, mut by_stars) = (pts.clone(), pts.clone());
    let a = Smoother::new()
        .smooth(&mut by_triangles, &tris, &fixed)
        .unwrap();
    let b = Smoother::new()
        .smooth_stars(&mut by_stars, &grid_stars(30))
        .unwrap();
    // The same moves, summed from another neighbour first: equal up to rounding.
    assert_eq!(
        (a.passes, a.moved, a.reduced, a.skipped),
        (b.passes, b.moved, b.reduced, b.skipped)
    );
    let apart = by_triangles
        .iter()
        .zip(&by_stars)
        .map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()))
        .fold(0.0, f64::max);
    assert!(apart < 1e-12, "{apart}");
    assert!(a.moved > 0 && all_positive(&by_stars, &tris));
}

#[test]
fn bad_stars_are_an_error() {
    let bad = |start: Vec<u32>, ring: Vec<u32>| {
        matches!(
            Stars::from_rings(start, ring),
            Err(SmoothError::BadInput(_))
        )
    };
    assert!(bad(vec![], vec![]));
    assert!(bad(vec![1, 3], vec![1, 2, 3]));
    assert!(bad(vec![0, 2], vec![1, 2, 3]));
    assert!(bad(vec![0, 3, 2, 3], vec![1, 2, 0]));
    // A ring naming a point out of range, its own point, or too short.
    assert!(bad(vec![0, 3, 3, 3], vec![1, 2, 7]));
    assert!(bad(vec![0, 3, 3, 3], vec![1, 0, 2]));
    assert!(bad(vec![0, 2, 2, 2], vec![1, 2]));
    // Clockwise: the star's triangles are not positive.
    let (mut pts, _, _) = jittered_grid(2, 0.0, 1);
    let clockwise = Stars::from_rings(
        (0..=9).map(|i| if i <= 4 { 0 } else { 6 }).collect(),
        vec![1, 0, 3, 7, 8, 5],
    )
    .unwrap();
    assert!(Smoother::new().smooth_stars(&mut pts, &clockwise).is_err());
    // More stars than points.
    assert!(Smoother::new()
        .smooth_stars(&mut pts[..4], &grid_stars(2))
        .is_err());
}

#[test]
fn quality_report_snapshot() {
    let (pts, tris, _) = jittered_grid(3, 0.3, 7);
    let q = QualityReport::of_triangles(&pts, &tris);
    insta::assert_snapshot!(format!("{q}{}", q.to_json()));
    assert_eq!(QualityReport::of_triangles(&pts, &[]).elements, 0);
}

#[test]
fn quality_report_matches_a_direct_computation_whatever_the_threads() {
    // More triangles than one parallel task takes.
    let (pts, tris, _) = jittered_grid(130, 0.25, 5);
    let angles = |t: &[u32; 3]| -> [f64; 3] {
        let p = t.map(|v| pts[v as usize]);
        std::array::from_fn(|k| {
            let (o, u, w) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            let (ux, uy, wx, wy) = (u[0] - o[0], u[1] - o[1], w[0] - o[0], w[1] - o[1]);
            (ux * wy - uy * wx)
                .abs()
                .atan2(ux * wx + uy * wy)
                .to_degrees()
        })
    };
    let area = |t: &[u32; 3]| {
        let p = t.map(|v| pts[v as usize]);
        0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
            - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]))
    };
    let mins: Vec<f64> = tris
        .iter()
        .map(|t| angles(t).into_iter().fold(180.0, f64::min))
        .collect();
    let max = tris.iter().flat_map(angles).fold(0.0, f64::max);
    let mut sides: std::collections::BTreeMap<(u32, u32), Vec<usize>> = Default::default();
    for (k, t) in tris.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            sides.entry((a.min(b), a.max(b))).or_default().push(k);
        }
    }
    let ratios: Vec<f64> = sides
        .values()
        .filter(|s| s.len() == 2)
        .map(|s| {
            let (x, y) = (area(&tris[s[0]]).abs(), area(&tris[s[1]]).abs());
            x.max(y) / x.min(y)
        })
        .collect();
    let reports: Vec<QualityReport> = [1, 3]
        .iter()
        .map(|&n| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap();
            pool.install(|| QualityReport::of_triangles(&pts, &tris))
        })
        .collect();
    assert_eq!(reports[0], reports[1]);
    let q = &reports[0];
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
    assert!(close(
        q.min_angle,
        mins.iter().copied().fold(180.0, f64::min)
    ));
    assert!(close(q.max_angle, max));
    assert!(close(
        q.mean_min_angle,
        mins.iter().sum::<f64>() / mins.len() as f64
    ));
    assert_eq!(q.min_angle_histogram.iter().sum::<usize>(), tris.len());
    assert!(close(
        q.max_neighbour_area_ratio,
        ratios.iter().copied().fold(1.0, f64::max)
    ));
    assert!(close(
        q.mean_neighbour_area_ratio,
        ratios.iter().sum::<f64>() / ratios.len() as f64
    ));
    assert!(close(q.total_area, 130.0 * 130.0));
    // With the neighbours given: the same figures.
    let across: Vec<[u32; 3]> = tris
        .iter()
        .enumerate()
        .map(|(k, t)| {
            std::array::from_fn(|e| {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                let side = &sides[&(a.min(b), a.max(b))];
                side.iter()
                    .find(|&&o| o != k)
                    .map_or(u32::MAX, |&o| o as u32)
            })
        })
        .collect();
    let m = QualityReport::of_mesh(&pts, &tris, &across);
    assert_eq!(
        (m.min_angle, m.max_angle, m.mean_min_angle),
        (q.min_angle, q.max_angle, q.mean_min_angle)
    );
    assert_eq!(m.max_neighbour_area_ratio, q.max_neighbour_area_ratio);
    assert!(close(
        m.mean_neighbour_area_ratio,
        q.mean_neighbour_area_ratio
    ));
}

/// The smallest angle (degrees) of the triangles with at least one free point.
fn free_min_angle(pts: &[[f64; 2]], tris: &[[u32; 3]], fixed: &[bool]) -> f64 {
    tris.iter()
        .filter(|t| t.iter().any(|&v| !fixed[v as usize]))
        .map(|t| QualityReport::of_triangles(pts, &[*t]).min_angle)
        .fold(180.0, f64::min)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]
    #[test]
    fn smoothing_never_sharpens_below_thirty_degrees(seed in 0u64..10_000, k in 2usize..10, jitter in 0.0f64..0.25, omega in 0.05f64..1.0) {
        // Each move keeps its star's smallest angle at least as large as before, or at least
        // 30°: so the smallest angle of the triangles that can change never falls below
        // min(its start value, 30°).
        let (mut pts, tris, fixed) = jittered_grid(k, jitter, seed);
        prop_assume!(all_positive(&pts, &tris));
        let before = free_min_angle(&pts, &tris, &fixed);
        Smoother::new().omega(omega).unwrap().iterations(20).smooth(&mut pts, &tris, &fixed).unwrap();
        let after = free_min_angle(&pts, &tris, &fixed);
        prop_assert!(after >= before.min(30.0) - 1e-9, "{before} -> {after}");
    }

    #[test]
    fn smoothing_never_inverts(seed in 0u64..10_000, k in 2usize..12, jitter in 0.0f64..0.25, omega in 0.01f64..1.0) {
        let (mut pts, tris, fixed) = jittered_grid(k, jitter, seed);
        prop_assume!(all_positive(&pts, &tris));
        let original = pts.clone();
        Smoother::new().omega(omega).unwrap().iterations(20).smooth(&mut pts, &tris, &fixed).unwrap();
        prop_assert!(all_positive(&pts, &tris));
        for (i, &f) in fixed.iter().enumerate() {
            if f {
                prop_assert_eq!(pts[i], original[i]);
            }
        }
        let area: f64 = QualityReport::of_triangles(&pts, &tris).total_area;
        prop_assert!((area - (k * k) as f64).abs() < 1e-9 * (k * k) as f64);
    }
}

#[test]
fn neighbour_ratios_of_flat_triangles_are_not_nan() {
    // Two triangles whose floating-point areas are 0 (so thin that rounding flattens them;
    // here flat), and an ordinary triangle beside one of them: the ratios were 0/0 (NaN).
    let pts = [[0.0, 0.0], [1.0, 0.0], [0.5, 0.0], [0.25, 0.0], [0.5, 1.0]];
    let tris = [[0, 1, 2], [1, 0, 3], [0, 2, 4]];
    let q = QualityReport::of_triangles(&pts, &tris);
    assert_eq!(q.max_neighbour_area_ratio, f64::INFINITY);
    assert_eq!(q.mean_neighbour_area_ratio, f64::INFINITY);
    let q = QualityReport::of_triangles(&pts, &tris[..2]);
    assert_eq!(q.max_neighbour_area_ratio, 1.0);
}
