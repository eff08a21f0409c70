//! Spacing fields: exact interpolation, clamping outside, adaptation to a shock, sources,
//! errors.

use delmesh_point_gen::{Adaptation, BackgroundMesh2, Source, SpacingError, SpacingField};

fn square(values: [f64; 4]) -> BackgroundMesh2 {
    BackgroundMesh2::new(
        vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]],
        vec![[0, 1, 3], [1, 2, 3]],
        values.to_vec(),
    )
    .unwrap()
}

#[test]
fn a_linear_field_is_interpolated_exactly() {
    // h = 1 + x + 2y at the corners: linear, so every triangle reproduces it.
    let bg = square([1.0, 3.0, 5.0, 3.0]);
    for p in [[0.5, 0.25], [1.9, 0.9], [1.0, 0.5], [0.0, 0.0], [2.0, 1.0]] {
        let want = 1.0 + p[0] + 2.0 * p[1];
        assert!((bg.spacing_at(p) - want).abs() < 1e-12, "{p:?}");
    }
    // Outside: the value at the nearest part of the mesh.
    assert!((bg.spacing_at([3.0, 0.5]) - bg.spacing_at([2.0, 0.5])).abs() < 0.3);
    assert!(bg.spacing_at([-5.0, -5.0]) > 0.0);
}

#[test]
fn figure12_clusters_along_the_diagonal() {
    let bg = square([0.2, 0.01, 0.2, 0.01]);
    let on_diagonal = bg.spacing_at([1.0, 0.5]);
    let near_a = bg.spacing_at([0.2, 0.1]);
    assert!(on_diagonal < 0.02 && near_a > 0.1, "{on_diagonal} {near_a}");
}

#[test]
fn adaptation_refines_a_shock() {
    // A tanh shock along x = 0.5 on a 21 × 21 grid.
    let k = 21;
    let mut points = Vec::new();
    let mut field = Vec::new();
    for j in 0..k {
        for i in 0..k {
            let (x, y) = (i as f64 / (k - 1) as f64, j as f64 / (k - 1) as f64);
            points.push([x, y]);
            field.push(((x - 0.5) * 40.0).tanh());
        }
    }
    let mut tris = Vec::new();
    for j in 0..k - 1 {
        for i in 0..k - 1 {
            let a = (j * k + i) as u32;
            tris.push([a, a + 1, a + k as u32 + 1]);
            tris.push([a, a + k as u32 + 1, a + k as u32]);
        }
    }
    let bg =
        BackgroundMesh2::from_solution(points, tris, &field, &Adaptation::new(0.005, 0.1)).unwrap();
    let at_shock = bg.spacing_at([0.5, 0.5]);
    let far = bg.spacing_at([0.02, 0.5]);
    assert!(at_shock < 0.01, "{at_shock}");
    assert!(far > 5.0 * at_shock, "{far}");
    assert!(bg
        .node_spacing()
        .iter()
        .all(|&h| (0.005..=0.1).contains(&h)));
}

#[test]
fn sources_and_the_boundary_field() {
    let field = SpacingField::boundary().with_source(Source {
        a: [0.0, 0.0],
        b: [1.0, 0.0],
        h0: 0.01,
        radius: 0.1,
        growth: 0.2,
    });
    assert!(field.uses_node_values());
    assert_eq!(field.spacing([0.5, 0.05], 1.0), 0.01);
    assert!((field.spacing([0.5, 1.1], 1.0) - (0.01 + 0.2 * 1.0)).abs() < 1e-12);
    assert_eq!(field.spacing([0.5, 50.0], 0.3), 0.3);
    let bg = SpacingField::background(square([1.0; 4]));
    assert!(!bg.uses_node_values());
    assert_eq!(bg.spacing([1.0, 0.5], 99.0), 1.0);
}

#[test]
fn bad_background_meshes_are_named() {
    let pts = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    assert_eq!(
        BackgroundMesh2::new(pts.clone(), vec![[0, 1, 5]], vec![1.0; 3]).unwrap_err(),
        SpacingError::BadNode {
            triangle: 0,
            node: 5,
            n_nodes: 3
        }
    );
    let e = BackgroundMesh2::new(pts.clone(), vec![[0, 1, 2]], vec![1.0, -1.0, 1.0]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "node 1: spacing -1 is not positive and finite"
    );
    assert_eq!(
        BackgroundMesh2::new(
            vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]],
            vec![[0, 1, 2]],
            vec![1.0; 3]
        )
        .unwrap_err(),
        SpacingError::Degenerate(0)
    );
    assert!(BackgroundMesh2::from_solution(
        pts,
        vec![[0, 1, 2]],
        &[0.0; 3],
        &Adaptation::new(1.0, 0.5)
    )
    .is_err());
}

/// A background mesh's boundary splits: pieces as many as the edge is long in spacings
/// (rounded), graded as the spacing is; and the length in spacings, which the pipeline checks
/// before splitting (a background of 1e-300 would cut an edge into a million pieces).
#[test]
fn a_background_splits_boundary_edges_by_their_length_in_spacings() {
    let field = SpacingField::background(square([0.1; 4]));
    let ts = field.boundary_splits([0.0, 0.0], [2.0, 0.0]);
    assert_eq!(ts.len(), 19);
    for (k, t) in ts.iter().enumerate() {
        assert!((t - (k + 1) as f64 / 20.0).abs() < 1e-9, "{ts:?}");
    }
    assert!((field.spacings_along([0.0, 0.0], [2.0, 0.0]) - 20.0).abs() < 1e-9);
    // Within one and a half spacings: whole.
    assert!(field.boundary_splits([0.0, 0.0], [0.14, 0.0]).is_empty());
    // Graded 0.05 to 0.25 along x: the pieces grow along the edge.
    let field = SpacingField::background(square([0.05, 0.25, 0.25, 0.05]));
    let ts = field.boundary_splits([0.0, 0.0], [2.0, 0.0]);
    let pieces: Vec<f64> = std::iter::once(0.0)
        .chain(ts.iter().copied())
        .chain(std::iter::once(1.0))
        .collect::<Vec<_>>()
        .windows(2)
        .map(|w| 2.0 * (w[1] - w[0]))
        .collect();
    assert!(pieces.windows(2).all(|w| w[1] > w[0]), "{pieces:?}");
    let field = SpacingField::background(square([1e-300; 4]));
    assert!(field.spacings_along([0.0, 0.0], [2.0, 0.0]) > 1e299);
}
