//! 3D spacing fields: exact interpolation of linear fields, the nearest-point clamp outside,
//! adaptation to a shock (with exact gradation), sources, and errors that name the node or
//! tetrahedron.

use delmesh_delaunay_core::Triangulation3;
use delmesh_point_gen::{Adaptation, BackgroundMesh3, Source3, SpacingError3, SpacingField3};
use rand::{Rng, SeedableRng};

/// The box `[0, 2] × [0, 1] × [0, 1]` split into six tetrahedra around its diagonal.
fn kuhn_box() -> (Vec<[f64; 3]>, Vec<[u32; 4]>) {
    grid_mesh([3, 2, 2], [2.0, 1.0, 1.0])
}

/// A grid of `n[0] × n[1] × n[2]` nodes over `[0, size]`, each cube split into six
/// tetrahedra sharing its main diagonal.
fn grid_mesh(n: [usize; 3], size: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[u32; 4]>) {
    let id = |i: usize, j: usize, k: usize| ((k * n[1] + j) * n[0] + i) as u32;
    let mut points = Vec::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                points.push([
                    size[0] * i as f64 / (n[0] - 1) as f64,
                    size[1] * j as f64 / (n[1] - 1) as f64,
                    size[2] * k as f64 / (n[2] - 1) as f64,
                ]);
            }
        }
    }
    let mut tets = Vec::new();
    for k in 0..n[2] - 1 {
        for j in 0..n[1] - 1 {
            for i in 0..n[0] - 1 {
                let corner = |b: usize| id(i + (b & 1), j + ((b >> 1) & 1), k + (b >> 2));
                // The six monotone paths from corner 0 to corner 7.
                for (a, b) in [(1, 2), (2, 1), (1, 4), (4, 1), (2, 4), (4, 2)] {
                    tets.push([corner(0), corner(a), corner(a | b), corner(7)]);
                }
            }
        }
    }
    (points, tets)
}

fn linear(p: [f64; 3]) -> f64 {
    1.0 + p[0] + 2.0 * p[1] + 3.0 * p[2]
}

#[test]
fn a_linear_field_is_interpolated_exactly() {
    let (points, tets) = kuhn_box();
    let h: Vec<f64> = points.iter().map(|&p| linear(p)).collect();
    let bg = BackgroundMesh3::new(points, tets, h).unwrap();
    let mut rng = rand::rngs::StdRng::seed_from_u64(3);
    for _ in 0..500 {
        let p = [rng.gen::<f64>() * 2.0, rng.gen(), rng.gen()];
        assert!((bg.spacing_at(p) - linear(p)).abs() < 1e-12, "{p:?}");
    }
    for p in [[0.0; 3], [2.0, 1.0, 1.0], [1.0, 0.5, 0.5], [2.0, 0.0, 0.3]] {
        assert!((bg.spacing_at(p) - linear(p)).abs() < 1e-12, "{p:?}");
    }
}

#[test]
fn a_linear_field_on_a_delaunay_mesh_of_random_points() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(11);
    let mut points: Vec<[f64; 3]> = (0..8)
        .map(|b| [(b & 1) as f64, ((b >> 1) & 1) as f64, (b >> 2) as f64])
        .collect();
    points.extend((0..400).map(|_| [rng.gen(), rng.gen(), rng.gen()]));
    let tri = Triangulation3::new(&points).unwrap();
    let tets: Vec<[u32; 4]> = tri
        .cells_in_input_numbering()
        .chunks_exact(4)
        .map(|t| [t[0], t[1], t[2], t[3]])
        .collect();
    let h: Vec<f64> = points.iter().map(|&p| linear(p)).collect();
    let bg = BackgroundMesh3::new(points, tets, h).unwrap();
    for _ in 0..2000 {
        let p = [rng.gen(), rng.gen(), rng.gen()];
        assert!((bg.spacing_at(p) - linear(p)).abs() < 1e-11, "{p:?}");
    }
}

#[test]
fn outside_the_value_at_the_nearest_point_of_the_mesh() {
    let (points, tets) = kuhn_box();
    let h: Vec<f64> = points.iter().map(|&p| linear(p)).collect();
    let bg = BackgroundMesh3::new(points, tets, h).unwrap();
    // (outside point, nearest point of the box): a face, an edge, a corner, far away.
    for (p, q) in [
        ([3.0, 0.5, 0.25], [2.0, 0.5, 0.25]),
        ([1.0, -2.0, 0.5], [1.0, 0.0, 0.5]),
        ([0.5, 3.0, 4.0], [0.5, 1.0, 1.0]),
        ([-1.0, -1.0, -1.0], [0.0, 0.0, 0.0]),
        ([1e6, 0.75, 0.5], [2.0, 0.75, 0.5]),
        ([2.5, 0.5, -1e5], [2.0, 0.5, 0.0]),
    ] {
        assert!(
            (bg.spacing_at(p) - linear(q)).abs() < 1e-9,
            "{p:?}: {} vs {}",
            bg.spacing_at(p),
            linear(q)
        );
    }
}

#[test]
fn adaptation_refines_a_shock() {
    // A tanh shock across x = 0.5 on an 11³ grid.
    let (points, tets) = grid_mesh([11, 11, 11], [1.0; 3]);
    let field: Vec<f64> = points
        .iter()
        .map(|p| ((p[0] - 0.5) * 40.0).tanh())
        .collect();
    let adaptation = Adaptation::new(0.005, 0.1);
    let bg = BackgroundMesh3::from_solution(points, tets, &field, &adaptation).unwrap();
    let at_shock = bg.spacing_at([0.5, 0.5, 0.5]);
    let near = bg.spacing_at([0.45, 0.3, 0.7]);
    let far = bg.spacing_at([0.02, 0.5, 0.5]);
    assert!(at_shock < 0.01, "{at_shock}");
    assert!(near < far, "{near} {far}");
    assert!(far > 5.0 * at_shock, "{far}");
    let h = bg.node_spacing();
    assert!(h.iter().all(|&h| (0.005..=0.1).contains(&h)));
    // Gradation holds exactly on every edge.
    for t in bg.tetrahedra() {
        for i in 0..4 {
            for j in 0..4 {
                let (a, b) = (t[i] as usize, t[j] as usize);
                let (p, q) = (bg.points()[a], bg.points()[b]);
                let d =
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
                assert!(h[a] <= h[b] + adaptation.growth * d + 1e-15);
            }
        }
    }
    // Symmetric in y and z, as the field is.
    let s = |p: [f64; 3]| bg.spacing_at(p);
    assert!((s([0.3, 0.2, 0.6]) - s([0.3, 0.6, 0.2])).abs() < 1e-12);
}

#[test]
fn flat_and_linear_fields() {
    let (points, tets) = kuhn_box();
    let field = vec![7.0; points.len()];
    let bg =
        BackgroundMesh3::from_solution(points, tets, &field, &Adaptation::new(0.1, 0.4)).unwrap();
    assert!(bg.node_spacing().iter().all(|&h| h == 0.4));
    // A linear field has the same gradient everywhere: the smallest spacing everywhere.
    let (points, tets) = kuhn_box();
    let field: Vec<f64> = points.iter().map(|&p| linear(p)).collect();
    let bg =
        BackgroundMesh3::from_solution(points, tets, &field, &Adaptation::new(0.1, 0.4)).unwrap();
    assert!(bg.node_spacing().iter().all(|&h| (h - 0.1).abs() < 1e-12));
}

#[test]
fn sources_and_the_boundary_field() {
    let line = Source3 {
        a: [0.0, 0.0, 0.0],
        b: [1.0, 0.0, 0.0],
        h0: 0.01,
        radius: 0.1,
        growth: 0.2,
    };
    let point = Source3 {
        a: [0.0, 0.0, 5.0],
        b: [0.0, 0.0, 5.0],
        h0: 0.02,
        radius: 0.0,
        growth: 0.5,
    };
    let field = SpacingField3::boundary()
        .with_source(line)
        .with_source(point);
    assert!(field.uses_node_values());
    assert_eq!(field.spacing([0.5, 0.05, 0.05], 1.0), 0.01);
    assert!((field.spacing([0.5, 0.6, 0.8], 1.0) - (0.01 + 0.2 * 0.9)).abs() < 1e-12);
    assert!((field.spacing([0.0, 0.0, 4.9], 1.0) - (0.02 + 0.5 * 0.1)).abs() < 1e-12);
    assert_eq!(field.spacing([0.5, 50.0, 0.0], 0.3), 0.3);
    let (points, tets) = kuhn_box();
    let n = points.len();
    let bg = SpacingField3::background(BackgroundMesh3::new(points, tets, vec![1.0; n]).unwrap());
    assert!(!bg.uses_node_values());
    assert_eq!(bg.spacing([1.0, 0.5, 0.5], 99.0), 1.0);
}

#[test]
fn bad_background_meshes_are_named() {
    let pts = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let tet = vec![[0, 1, 2, 3]];
    assert_eq!(
        BackgroundMesh3::new(pts.clone(), vec![[0, 1, 2, 9]], vec![1.0; 4]).unwrap_err(),
        SpacingError3::BadNode {
            tetrahedron: 0,
            node: 9,
            n_nodes: 4
        }
    );
    for (h, text) in [
        (-1.0, "node 2: spacing -1 is not positive and finite"),
        (0.0, "node 2: spacing 0 is not positive and finite"),
        (f64::NAN, "node 2: spacing NaN is not positive and finite"),
        (
            f64::INFINITY,
            "node 2: spacing inf is not positive and finite",
        ),
    ] {
        let e = BackgroundMesh3::new(pts.clone(), tet.clone(), vec![1.0, 1.0, h, 1.0]).unwrap_err();
        assert_eq!(e.to_string(), text);
    }
    let mut bad = pts.clone();
    bad[3][1] = f64::NAN;
    assert_eq!(
        BackgroundMesh3::new(bad, tet.clone(), vec![1.0; 4])
            .unwrap_err()
            .to_string(),
        "node 3: coordinate is not finite"
    );
    // Coplanar: zero volume, found exactly.
    let flat = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.3, 0.3, 0.0]];
    assert_eq!(
        BackgroundMesh3::new(flat, vec![[0, 1, 2, 3], [0, 1, 2, 2]], vec![1.0; 4]).unwrap_err(),
        SpacingError3::Degenerate(0)
    );
    assert_eq!(
        BackgroundMesh3::new(pts.clone(), tet.clone(), vec![1.0; 3])
            .unwrap_err()
            .to_string(),
        "4 nodes but 3 spacing values"
    );
    assert_eq!(
        BackgroundMesh3::new(pts.clone(), vec![], vec![1.0; 4]).unwrap_err(),
        SpacingError3::Empty
    );
    // Adaptation: bounds, growth, field values.
    for a in [
        Adaptation::new(1.0, 0.5),
        Adaptation::new(0.0, 0.5),
        Adaptation::new(0.1, f64::INFINITY),
        Adaptation {
            growth: -0.1,
            ..Adaptation::new(0.1, 0.5)
        },
    ] {
        assert!(matches!(
            BackgroundMesh3::from_solution(pts.clone(), tet.clone(), &[0.0; 4], &a),
            Err(SpacingError3::Bounds { .. })
        ));
    }
    let e = BackgroundMesh3::from_solution(
        pts.clone(),
        tet.clone(),
        &[0.0, f64::NAN, 0.0, 0.0],
        &Adaptation::new(0.1, 0.5),
    )
    .unwrap_err();
    assert_eq!(e.to_string(), "node 1: field value NaN is not finite");
    assert!(matches!(
        BackgroundMesh3::from_solution(pts, tet, &[0.0; 3], &Adaptation::new(0.1, 0.5)),
        Err(SpacingError3::Lengths(_))
    ));
}

/// The point of triangle `t` nearest to `p`: the nearest of the candidates (the corners, the
/// projections onto the edges' lines when they fall on the edges, the projection onto the
/// plane when it falls inside, by the normal equations).
fn nearest_on_triangle(p: [f64; 3], t: [[f64; 3]; 3]) -> [f64; 3] {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut candidates = t.to_vec();
    for i in 0..3 {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        let s = dot(sub(p, a), sub(b, a)) / dot(sub(b, a), sub(b, a));
        if (0.0..=1.0).contains(&s) {
            candidates.push([0, 1, 2].map(|k| a[k] + s * (b[k] - a[k])));
        }
    }
    let (e1, e2, w) = (sub(t[1], t[0]), sub(t[2], t[0]), sub(p, t[0]));
    let (a11, a12, a22) = (dot(e1, e1), dot(e1, e2), dot(e2, e2));
    let (b1, b2) = (dot(w, e1), dot(w, e2));
    let det = a11 * a22 - a12 * a12;
    let (u, v) = ((b1 * a22 - b2 * a12) / det, (a11 * b2 - a12 * b1) / det);
    if u >= 0.0 && v >= 0.0 && u + v <= 1.0 {
        candidates.push([0, 1, 2].map(|k| t[0][k] + u * e1[k] + v * e2[k]));
    }
    candidates
        .into_iter()
        .min_by(|a, b| dot(sub(*a, p), sub(*a, p)).total_cmp(&dot(sub(*b, p), sub(*b, p))))
        .unwrap()
}

#[test]
fn outside_a_delaunay_mesh_the_nearest_point_is_found() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(5);
    let points: Vec<[f64; 3]> = (0..150)
        .map(|_| [rng.gen(), rng.gen(), rng.gen()])
        .collect();
    let tri = Triangulation3::new(&points).unwrap();
    let tets: Vec<[u32; 4]> = tri
        .cells_in_input_numbering()
        .chunks_exact(4)
        .map(|t| [t[0], t[1], t[2], t[3]])
        .collect();
    let h: Vec<f64> = points.iter().map(|&p| linear(p)).collect();
    let bg = BackgroundMesh3::new(points.clone(), tets.clone(), h).unwrap();
    for _ in 0..300 {
        // Outside the unit cube, so outside the mesh.
        let mut p = [rng.gen::<f64>(), rng.gen::<f64>(), rng.gen::<f64>()];
        let axis = rng.gen_range(0..3);
        p[axis] = if rng.gen() {
            -0.3 * rng.gen::<f64>()
        } else {
            1.0 + 0.3 * rng.gen::<f64>()
        };
        let nearest = tets
            .iter()
            .flat_map(|t| (0..4).map(move |s| [t[(s + 1) % 4], t[(s + 2) % 4], t[(s + 3) % 4]]))
            .map(|f| nearest_on_triangle(p, f.map(|v| points[v as usize])))
            .min_by(|a, b| {
                let d = |q: &[f64; 3]| (0..3).map(|k| (q[k] - p[k]).powi(2)).sum::<f64>();
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        assert!(
            (bg.spacing_at(p) - linear(nearest)).abs() < 1e-9,
            "{p:?}: {} vs {}",
            bg.spacing_at(p),
            linear(nearest)
        );
    }
}

#[test]
fn inside_a_hole_of_the_mesh_the_nearest_point_is_on_the_hole() {
    // An 11³ grid without the tetrahedra inside [0.3, 0.7]³.
    let (points, tets) = grid_mesh([11, 11, 11], [1.0; 3]);
    let tets: Vec<[u32; 4]> = tets
        .into_iter()
        .filter(|t| {
            let c = [0, 1, 2].map(|k| t.iter().map(|&v| points[v as usize][k]).sum::<f64>() / 4.0);
            !c.iter().all(|&x| (0.3..0.7).contains(&x))
        })
        .collect();
    let h: Vec<f64> = points.iter().map(|&p| linear(p)).collect();
    let bg = BackgroundMesh3::new(points, tets, h).unwrap();
    assert!((bg.spacing_at([0.55, 0.5, 0.5]) - linear([0.7, 0.5, 0.5])).abs() < 1e-12);
    assert!((bg.spacing_at([0.5, 0.42, 0.37]) - linear([0.5, 0.42, 0.3])).abs() < 1e-12);
    assert!((bg.spacing_at([0.2, 0.5, 0.5]) - linear([0.2, 0.5, 0.5])).abs() < 1e-12);
}
