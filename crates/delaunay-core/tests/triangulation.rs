//! The kernel's contract on many kinds of point sets: `validate()` (adjacency symmetry,
//! orientation, exact empty circumsphere with the perturbation, Euler's relation), the exact
//! global emptiness check on small sets, hull and volume conservation, duplicates, errors.

mod common;

use common::*;
use delmesh_delaunay_core::*;
use delmesh_predicates::{orient2d, orient3d, Sign};
use proptest::prelude::*;

fn area(t: &Triangulation2) -> f64 {
    t.cells()
        .map(|c| {
            let v: Vec<[f64; 2]> = t.cell(c).iter().map(|&v| t.vertex(v)).collect();
            0.5 * ((v[1][0] - v[0][0]) * (v[2][1] - v[0][1])
                - (v[1][1] - v[0][1]) * (v[2][0] - v[0][0]))
        })
        .sum()
}

/// Six times the total volume (exact for integer coordinates of moderate size).
fn volume6(t: &Triangulation3) -> f64 {
    t.cells()
        .map(|c| {
            let v: Vec<[f64; 3]> = t.cell(c).iter().map(|&v| t.vertex(v)).collect();
            let d = |i: usize| [v[i][0] - v[0][0], v[i][1] - v[0][1], v[i][2] - v[0][2]];
            let (a, b, e) = (d(1), d(2), d(3));
            a[0] * (b[1] * e[2] - b[2] * e[1]) - a[1] * (b[0] * e[2] - b[2] * e[0])
                + a[2] * (b[0] * e[1] - b[1] * e[0])
        })
        .sum()
}

/// Every input point is a vertex or a reported duplicate of one with the same coordinates.
fn check_vertices<D: Dim>(t: &Triangulation<D>, pts: &[D::Point]) {
    assert_eq!(t.num_input_points(), pts.len());
    let dups: std::collections::HashMap<usize, usize> = t.duplicates().iter().copied().collect();
    for (i, p) in pts.iter().enumerate() {
        let v = t.vertex_of_input(i);
        assert_eq!(&t.vertex(v), p, "input {i}");
        if let Some(&orig) = dups.get(&i) {
            assert_eq!(t.input_index(v), orig);
        } else {
            assert_eq!(t.input_index(v), i);
        }
    }
    assert_eq!(t.num_vertices() + t.duplicates().len(), pts.len());
}

/// Builds, validates (globally too for small sets) and checks the vertex bookkeeping.
fn check_set<D: Dim>(pts: &[D::Point]) -> Triangulation<D> {
    let t = Triangulation::<D>::new(pts).unwrap();
    t.validate().unwrap();
    if pts.len() <= 100 {
        t.validate_globally().unwrap();
    }
    check_vertices(&t, pts);
    t
}

#[test]
fn random_sets_are_delaunay() {
    for (n, seed) in [(3, 1), (4, 2), (10, 3), (100, 4), (2000, 5)] {
        check_set::<D2>(&uniform2(n, seed));
    }
    for (n, seed) in [(4, 1), (5, 2), (10, 3), (100, 4), (3000, 5)] {
        check_set::<D3>(&uniform3(n, seed));
    }
}

#[test]
fn grids_are_triangulated_consistently() {
    // Every unit square (cube) is co-circular (co-spherical): only the perturbation decides.
    let pts = grid2(30);
    let t = Triangulation2::new(&pts).unwrap();
    t.validate().unwrap();
    assert_eq!(t.num_cells(), 2 * 29 * 29);
    assert_eq!(area(&t), 29.0 * 29.0);
    let pts = grid3(12);
    let t = Triangulation3::new(&pts).unwrap();
    t.validate().unwrap();
    assert_eq!(volume6(&t), 6.0 * 11.0f64.powi(3));
    let small = grid3(4);
    let t = Triangulation3::new(&small).unwrap();
    t.validate_globally().unwrap();
}

#[test]
fn cocircular_and_cospherical_sets() {
    let pts = circle_points();
    assert!(pts.len() > 30, "{}", pts.len());
    let t = Triangulation2::new(&pts).unwrap();
    t.validate().unwrap();
    t.validate_globally().unwrap();
    // All points on the hull: h = n, T = n − 2.
    assert_eq!(t.num_hull_facets(), pts.len());
    assert_eq!(t.num_cells(), pts.len() - 2);

    let pts = sphere_points();
    assert!(pts.len() > 100, "{}", pts.len());
    let t = Triangulation3::new(&pts).unwrap();
    t.validate().unwrap();
    t.validate_globally().unwrap();
    check_vertices(&t, &pts);
}

#[test]
fn clustered_and_extreme_scales() {
    let pts = clustered3(4000, 9);
    Triangulation3::new(&pts).unwrap().validate().unwrap();
    for scale in [1e-200, 1e-30, 1e30, 1e250] {
        let pts: Vec<[f64; 3]> = uniform3(500, 10)
            .iter()
            .map(|p| p.map(|x| x * scale))
            .collect();
        let t = Triangulation3::new(&pts).unwrap();
        t.validate().unwrap();
        check_vertices(&t, &pts);
        let pts: Vec<[f64; 2]> = uniform2(500, 11)
            .iter()
            .map(|p| p.map(|x| x * scale))
            .collect();
        let t = Triangulation2::new(&pts).unwrap();
        t.validate().unwrap();
        check_vertices(&t, &pts);
    }
    // Far from the origin: large coordinates, tiny differences.
    let pts: Vec<[f64; 3]> = uniform3(500, 12)
        .iter()
        .map(|p| p.map(|x| 1e6 + x * 1e-3))
        .collect();
    Triangulation3::new(&pts).unwrap().validate().unwrap();
}

#[test]
fn thin_slab_and_nearly_coplanar() {
    let pts: Vec<[f64; 3]> = uniform3(3000, 13)
        .iter()
        .map(|p| [p[0], p[1], p[2] * 1e-9])
        .collect();
    Triangulation3::new(&pts).unwrap().validate().unwrap();
    // A plane of grid points plus one point off it.
    let mut pts: Vec<[f64; 3]> = grid2(15).iter().map(|p| [p[0], p[1], 0.0]).collect();
    pts.push([7.3, 7.1, 1.0]);
    let t = Triangulation3::new(&pts).unwrap();
    t.validate().unwrap();
    t.validate_globally().unwrap();
}

#[test]
fn duplicates_are_merged_and_reported() {
    let mut pts = uniform2(200, 14);
    let copies: Vec<[f64; 2]> = pts[..50].to_vec();
    pts.extend(copies);
    pts.push([0.0, 0.0]);
    pts.push([-0.0, 0.0]); // the same point as the previous one
    let t = Triangulation2::new(&pts).unwrap();
    t.validate().unwrap();
    check_vertices(&t, &pts);
    assert_eq!(t.duplicates().len(), 51);
    for &(dup, orig) in t.duplicates() {
        assert_eq!(pts[dup], pts[orig]);
        // The first occurrence is the original, whatever the insertion order.
        assert!(orig < dup);
        assert!(pts[..orig].iter().all(|p| p != &pts[dup]));
    }
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let e = Triangulation2::new(&[[0.0, 0.0], [1.0, f64::NAN], [0.0, 1.0]]);
    assert!(
        matches!(e, Err(TriangulationError::NonFinite { index: 1, axis: 1, value }) if value.is_nan())
    );
    let e = Triangulation3::new(&[
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [0.0, f64::INFINITY, 0.0],
        [0.0, 0.0, 1.0],
    ]);
    assert!(matches!(
        e,
        Err(TriangulationError::NonFinite {
            index: 2,
            axis: 1,
            ..
        })
    ));
    assert!(matches!(
        Triangulation2::new(&[[0.0, 0.0], [1.0, 1.0]]),
        Err(TriangulationError::TooFewPoints { distinct: 2, .. })
    ));
    assert!(matches!(
        Triangulation2::new(&[[0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]),
        Err(TriangulationError::TooFewPoints { distinct: 1, .. })
    ));
    assert!(matches!(
        Triangulation2::new(&[]),
        Err(TriangulationError::TooFewPoints { distinct: 0, .. })
    ));
    let line: Vec<[f64; 2]> = (0..10).map(|i| [i as f64, 2.0 * i as f64]).collect();
    assert!(matches!(
        Triangulation2::new(&line),
        Err(TriangulationError::Degenerate {
            what: "collinear",
            ..
        })
    ));
    let plane: Vec<[f64; 3]> = grid2(5).iter().map(|p| [p[0], p[1], p[0] + p[1]]).collect();
    assert!(matches!(
        Triangulation3::new(&plane),
        Err(TriangulationError::Degenerate {
            what: "coplanar",
            ..
        })
    ));
    let line3: Vec<[f64; 3]> = (0..10).map(|i| [i as f64, 1.0, 2.0 * i as f64]).collect();
    assert!(matches!(
        Triangulation3::new(&line3),
        Err(TriangulationError::Degenerate {
            what: "collinear",
            ..
        })
    ));
    assert!(matches!(
        Triangulation2::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1e-300, 1.0]]),
        Err(TriangulationError::CoordinateRange { index: 3, .. })
    ));
    // A subnormal coordinate scales to zero: still refused, not flushed (it was, and the
    // triangulation of (-1, 5e-324) (1, 0) (1, 2) (-1, 2) came out Delaunay only for y = 0).
    let tiny = [[-1.0, 5e-324], [1.0, 0.0], [1.0, 2.0], [-1.0, 2.0]];
    assert!(matches!(
        Triangulation2::new(&tiny),
        Err(TriangulationError::CoordinateRange { index: 0, .. })
    ));
    let mut t = Triangulation2::new(&tiny[1..]).unwrap();
    assert!(matches!(
        t.insert([-1.0, 5e-324]),
        Err(TriangulationError::CoordinateRange { .. })
    ));
}

#[test]
fn error_messages_name_the_point() {
    let e = Triangulation2::new(&[[0.0, 0.0], [1.0, f64::NAN], [0.0, 1.0]]).unwrap_err();
    assert_eq!(e.to_string(), "point 1: coordinate 1 is not finite (NaN)");
    // Subnormal coordinates: the largest magnitude itself is out of range.
    let e = Triangulation2::new(&[[0.0, 0.0], [1e-320, 0.0], [0.0, 1e-320]]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "point 1: coordinate magnitude 1e-320 is outside the range 2^-1000 to 2^1000 that \
         exact predicates handle"
    );
}

#[test]
fn incremental_insertion_and_queries() {
    let pts = uniform3(300, 15);
    let mut t = Triangulation3::new(&pts[..100]).unwrap();
    for (k, p) in pts[100..].iter().enumerate() {
        let ins = t.insert(*p).unwrap();
        assert_eq!(ins, Insertion::Inserted(ins.vertex()));
        assert_eq!(t.input_index(ins.vertex()), 100 + k);
    }
    t.validate().unwrap();
    assert_eq!(
        t.insert(pts[7]).unwrap(),
        Insertion::Duplicate(t.vertex_of_input(7))
    );
    assert_eq!(t.duplicates(), &[(300, 7)]);
    assert!(t.insert([f64::NAN, 0.0, 0.0]).is_err());
    // Every edge and facet of every cell is found by the queries, and absent ones are not.
    for c in t.cells().take(50) {
        let v = t.cell(c);
        assert!(t.has_edge(v[0], v[1]));
        assert!(t.has_triangle(v[0], v[1], v[2]));
        assert!(t.cells_around_vertex(v[3]).contains(&c));
        assert!(t.cells_around(&[v[1], v[3]]).contains(&c));
    }
    let v0 = VertexId(0);
    let star = t.cells_around_vertex(v0);
    let linked: std::collections::HashSet<VertexId> = star
        .iter()
        .flat_map(|&c| t.cell(c).iter().copied())
        .collect();
    for w in 0..t.num_vertices() as u32 {
        let w = VertexId(w);
        assert_eq!(t.has_edge(v0, w), w != v0 && linked.contains(&w), "{w:?}");
    }
    // Locating an existing point finds its vertex.
    assert_eq!(t.locate(pts[42]), Location::Vertex(t.vertex_of_input(42)));
}

#[test]
fn hull_facets_match_a_convex_hull_check() {
    // A hull facet has every point on its inner side (or on it).
    let pts = uniform3(400, 16);
    let t = Triangulation3::new(&pts).unwrap();
    for c in t.all_cells().filter(|&c| t.is_ghost(c)) {
        let f: Vec<[f64; 3]> = t
            .cell(c)
            .iter()
            .filter(|v| !v.is_ghost())
            .map(|&v| t.vertex(v))
            .collect();
        let signs: std::collections::HashSet<Sign> = pts
            .iter()
            .map(|&p| orient3d(f[0], f[1], f[2], p))
            .filter(|&s| s != Sign::Zero)
            .collect();
        assert_eq!(signs.len(), 1, "hull facet with points on both sides");
    }
    let pts = uniform2(400, 17);
    let t = Triangulation2::new(&pts).unwrap();
    let hull = t.all_cells().filter(|&c| t.is_ghost(c)).count();
    for c in t.all_cells().filter(|&c| t.is_ghost(c)) {
        let f: Vec<[f64; 2]> = t
            .cell(c)
            .iter()
            .filter(|v| !v.is_ghost())
            .map(|&v| t.vertex(v))
            .collect();
        let signs: std::collections::HashSet<Sign> = pts
            .iter()
            .map(|&p| orient2d(f[0], f[1], p))
            .filter(|&s| s != Sign::Zero)
            .collect();
        assert_eq!(signs.len(), 1);
    }
    assert_eq!(t.num_cells(), 2 * 400 - 2 - hull);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Random small sets with coordinates on a coarse lattice: many collinear, co-circular
    /// and duplicate points. Either a clear error, or a valid Delaunay triangulation.
    #[test]
    fn lattice_sets_2d(coords in prop::collection::vec((0i32..6, 0i32..6), 0..40)) {
        let pts: Vec<[f64; 2]> = coords.iter().map(|&(x, y)| [x as f64, y as f64]).collect();
        match Triangulation2::new(&pts) {
            Ok(t) => {
                t.validate().unwrap();
                t.validate_globally().unwrap();
                check_vertices(&t, &pts);
            }
            Err(TriangulationError::TooFewPoints { .. } | TriangulationError::Degenerate { .. }) => {}
            Err(e) => panic!("{e}"),
        }
    }

    #[test]
    fn lattice_sets_3d(coords in prop::collection::vec((0i32..4, 0i32..4, 0i32..4), 0..50)) {
        let pts: Vec<[f64; 3]> = coords.iter().map(|&(x, y, z)| [x as f64, y as f64, z as f64]).collect();
        match Triangulation3::new(&pts) {
            Ok(t) => {
                t.validate().unwrap();
                t.validate_globally().unwrap();
                check_vertices(&t, &pts);
            }
            Err(TriangulationError::TooFewPoints { .. } | TriangulationError::Degenerate { .. }) => {}
            Err(e) => panic!("{e}"),
        }
    }

    #[test]
    fn random_float_sets_3d(coords in prop::collection::vec((-1e3f64..1e3, -1e3f64..1e3, -1e3f64..1e3), 4..200)) {
        let pts: Vec<[f64; 3]> = coords.iter().map(|&(x, y, z)| [x, y, z]).collect();
        let t = Triangulation3::new(&pts).unwrap();
        t.validate().unwrap();
        // The cells fill the convex hull: hull facets and cells agree on the boundary.
        check_vertices(&t, &pts);
    }
}

#[test]
fn huge_degenerate_cavity_uses_the_hashed_linking() {
    // All points on one sphere, then its centre: the centre's cavity is every cell, with more
    // boundary vertices than the dense ridge table takes.
    let pts = sphere_points();
    assert!(pts.len() > 256, "{}", pts.len());
    let mut t = Triangulation3::new(&pts).unwrap();
    t.insert([0.0, 0.0, 0.0]).unwrap();
    t.validate().unwrap();
    // Every hull facet now forms a tetrahedron with the centre.
    assert_eq!(t.num_cells(), t.num_hull_facets());
    let mut t2 = Triangulation2::new(&circle_points()).unwrap();
    t2.insert([0.0, 0.0]).unwrap();
    t2.validate().unwrap();
    assert_eq!(t2.num_cells(), circle_points().len());
}

/// The finite cells as sets of vertex coordinates: comparable across input orders.
fn cells_by_coords<D: Dim>(pts: &[D::Point]) -> std::collections::BTreeSet<Vec<Vec<u64>>> {
    let t = Triangulation::<D>::new(pts).unwrap();
    t.validate().unwrap();
    t.cells()
        .map(|c| {
            let mut v: Vec<Vec<u64>> = t
                .cell(c)
                .iter()
                .map(|&v| t.vertex(v).as_ref().iter().map(|x| x.to_bits()).collect())
                .collect();
            v.sort_unstable();
            v
        })
        .collect()
}

/// The same points reversed and shuffled triangulate to the same cells.
fn check_order_independent<D: Dim>(pts: &[D::Point]) -> usize {
    let base = cells_by_coords::<D>(pts);
    let mut reversed = pts.to_vec();
    reversed.reverse();
    let mut shuffled = pts.to_vec();
    let n = shuffled.len();
    for i in 0..n {
        shuffled.swap(i, (i * 7919 + 13) % n);
    }
    assert_eq!(cells_by_coords::<D>(&reversed), base);
    assert_eq!(cells_by_coords::<D>(&shuffled), base);
    base.len()
}

/// The perturbation ranks points by their coordinates, so a degenerate set gets the same
/// triangulation whatever the input order.
#[test]
fn degenerate_sets_do_not_depend_on_input_order() {
    assert_eq!(
        check_order_independent::<D3>(&grid3(6)),
        6 * 5 * 5 * 5,
        "six tetrahedra per cube"
    );
    check_order_independent::<D3>(&sphere_points());
    check_order_independent::<D2>(&grid2(12));
    check_order_independent::<D2>(&circle_points());
}

/// Every unit square of a grid is co-circular; the lexicographic perturbation cuts all of
/// them by the same diagonal, from (x, y + 1) to (x + 1, y), as CGAL does. (Catches a test
/// that resolves ties without the perturbation: that one is consistent too, but different.)
#[test]
fn grid_squares_are_cut_by_the_perturbation_s_diagonal() {
    let t = Triangulation2::new(&grid2(9)).unwrap();
    for c in t.cells() {
        let v: Vec<[f64; 2]> = t.cell(c).iter().map(|&v| t.vertex(v)).collect();
        for i in 0..3 {
            let (a, b) = (v[i], v[(i + 1) % 3]);
            if (a[0] - b[0]).abs() == 1.0 && (a[1] - b[1]).abs() == 1.0 {
                assert_eq!(
                    a[0] - b[0],
                    b[1] - a[1],
                    "edge {a:?}-{b:?} is the other diagonal"
                );
            }
        }
    }
}

/// The finite cells as sorted tuples of input indices.
fn input_cells<D: Dim>(t: &Triangulation<D>) -> std::collections::BTreeSet<Vec<usize>> {
    t.cells()
        .map(|c| {
            let mut k: Vec<usize> = t.cell(c).iter().map(|&v| t.input_index(v)).collect();
            k.sort_unstable();
            k
        })
        .collect()
}

#[test]
fn renumbering_keeps_the_triangulation_in_2d_and_3d() {
    let mut t2 = Triangulation2::new(&uniform2(3000, 11)).unwrap();
    let before = input_cells(&t2);
    t2.renumber();
    t2.validate().unwrap();
    assert_eq!(input_cells(&t2), before);

    // Co-spherical grid points: the perturbation decides, by coordinates, not by numbers.
    for points in [uniform3(3000, 12), grid3(9)] {
        let mut t3 = Triangulation3::new(&points).unwrap();
        let before = input_cells(&t3);
        let map = t3.renumber();
        t3.validate().unwrap();
        assert_eq!(input_cells(&t3), before);
        assert_eq!(t3.num_cells(), before.len());
        for (i, &p) in points.iter().enumerate() {
            assert_eq!(t3.vertex(t3.vertex_of_input(i)), p);
        }
        let kept = map.cell.iter().filter(|&&c| c != u32::MAX).count();
        assert_eq!(kept, t3.all_cells().count());
    }
}

#[test]
fn edge_queries_agree_with_the_cells_around_an_edge() {
    // A fan centre of 400 triangles next to an ordinary jittered grid, plus hull vertices
    // (ghost cells in the turn): every pair's answer, with no hint, a right hint, a stale one.
    let mut pts2: Vec<[f64; 2]> = (0..400)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 400.0;
            [a.cos(), a.sin()]
        })
        .collect();
    pts2.push([0.0, 0.0]);
    for i in 0..6 {
        for j in 0..6 {
            let h = ((i * 7 + j * 3) % 5) as f64 * 0.013;
            pts2.push([1.5 + 0.2 * i as f64 + h, -0.5 + 0.2 * j as f64 - h]);
        }
    }
    let mut t2 = Triangulation2::new(&pts2).unwrap();
    let n = t2.num_vertices() as u32;
    let check = |t: &Triangulation2| {
        for a in 0..n {
            for b in 0..n {
                let (a, b) = (VertexId(a), VertexId(b));
                let want = a != b && !t.cells_around(&[a, b]).is_empty();
                let got = t.edge_cell(a, b, None);
                assert_eq!(got.is_some(), want, "edge {a:?} {b:?}");
                assert_eq!(t.has_edge(a, b), want);
                if let Some(c) = got {
                    assert!(t.cell(c).contains(&a) && t.cell(c).contains(&b));
                    assert_eq!(t.edge_cell(a, b, Some(c)), Some(c));
                }
            }
        }
    };
    check(&t2);
    // Hints that no longer hold the edge, or are free slots, after more insertions.
    let hints: Vec<(VertexId, VertexId, CellId)> = t2
        .cells()
        .flat_map(|c| {
            let v = t2.cell(c).to_vec();
            [(v[0], v[1], c), (v[1], v[2], c)]
        })
        .collect();
    for k in 0..50 {
        let a = 0.3 * std::f64::consts::TAU * k as f64 / 50.0;
        t2.insert([0.5 * a.cos(), 0.5 * a.sin()]).unwrap();
    }
    for &(a, b, c) in &hints {
        let want = !t2.cells_around(&[a, b]).is_empty();
        assert_eq!(t2.edge_cell(a, b, Some(c)).is_some(), want);
    }
    // 3D (the search over the vertex's star).
    let pts3: Vec<[f64; 3]> = (0..60)
        .map(|k| {
            let x = k as f64;
            [
                (x * 0.37).sin(),
                (x * 0.71).cos(),
                (x * 0.13).sin() * (x * 0.5).cos(),
            ]
        })
        .collect();
    let t3 = Triangulation3::new(&pts3).unwrap();
    for a in 0..t3.num_vertices() as u32 {
        for b in 0..t3.num_vertices() as u32 {
            let (a, b) = (VertexId(a), VertexId(b));
            let want = a != b && !t3.cells_around(&[a, b]).is_empty();
            assert_eq!(t3.has_edge(a, b), want, "edge {a:?} {b:?}");
        }
    }
}

#[test]
fn a_construction_its_caller_stops_is_cancelled() {
    let pts = uniform3(5000, 11);
    let mut calls = 0;
    let stopped = Triangulation3::with_progress_until(&pts, |done, _| {
        calls += 1;
        done < 2000
    });
    assert!(matches!(stopped, Err(TriangulationError::Cancelled)));
    assert!(calls >= 2, "{calls}");
    let whole = Triangulation3::with_progress_until(&pts, |_, _| true).unwrap();
    whole.validate().unwrap();
    assert_eq!(
        whole.num_cells(),
        Triangulation3::new(&pts).unwrap().num_cells()
    );
}
