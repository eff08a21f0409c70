//! Edges and triangles made part of a 3D triangulation by flips (`flip_in_edge`,
//! `flip_in_face`), flips undone, and insertion by splitting followed by Delaunay flips.

mod common;

use common::{grid3, uniform3};
use delmesh_delaunay_core::{
    ConstrainedTriangulation3, FlipIn, StarSearch, Triangulation3, VertexId,
};
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::collections::BTreeSet;

/// The cells as sorted input-index quadruples (ghost cells as `usize::MAX`).
fn cell_set(tri: &Triangulation3) -> BTreeSet<[usize; 4]> {
    tri.all_cells()
        .map(|c| {
            let mut q = [usize::MAX; 4];
            for (k, &v) in tri.cell(c).iter().enumerate() {
                if !v.is_ghost() {
                    q[k] = tri.input_index(v);
                }
            }
            q.sort_unstable();
            q
        })
        .collect()
}

fn has_edge(tri: &Triangulation3, a: VertexId, b: VertexId) -> bool {
    let mut star = Vec::new();
    StarSearch::default()
        .find(tri, a, &mut star, |v| v.contains(&b))
        .is_some()
}

fn no_lock(_: VertexId, _: VertexId) -> bool {
    false
}

#[test]
fn missing_edges_are_flipped_in_or_left_as_they_were() {
    let (mut present, mut stuck) = (0, 0);
    for seed in 0..4u64 {
        let pts = uniform3(300, seed);
        let mut ct = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
        let mut rng = StdRng::seed_from_u64(seed + 50);
        let n = ct.triangulation().num_vertices() as u32;
        for _ in 0..300 {
            let (a, b) = (VertexId(rng.gen_range(0..n)), VertexId(rng.gen_range(0..n)));
            if a == b || has_edge(ct.triangulation(), a, b) {
                continue;
            }
            let before = cell_set(ct.triangulation());
            let mut touched = Vec::new();
            match ct.flip_in_edge(a, b, &no_lock, 64, &mut touched) {
                FlipIn::Present(flips) => {
                    assert!(flips > 0);
                    assert!(has_edge(ct.triangulation(), a, b));
                    assert!(!touched.is_empty());
                    ct.validate_structure().unwrap();
                    present += 1;
                }
                FlipIn::Stuck(_) => {
                    // Undone: the very same cells.
                    assert_eq!(cell_set(ct.triangulation()), before);
                    stuck += 1;
                }
            }
            ct.keep_flips();
            // Back to the Delaunay tetrahedralisation for the next try.
            ct = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
        }
    }
    // Short random segments often need only a few flips; long ones cross too much.
    assert!(
        present > 20 && stuck > 20,
        "{present} present, {stuck} stuck"
    );
}

#[test]
fn a_locked_edge_is_never_flipped_away() {
    let pts = uniform3(200, 7);
    let tri = Triangulation3::new(&pts).unwrap();
    let mut ct = ConstrainedTriangulation3::new(tri.clone());
    // Lock every edge of the Delaunay tetrahedralisation: no 3-2 or 4-4 flip may then run,
    // and every edge must still be there whatever the flips-in did.
    let mut edges = BTreeSet::new();
    for c in tri.cells() {
        let v = tri.cell(c);
        for i in 0..4 {
            for j in i + 1..4 {
                edges.insert((v[i].min(v[j]), v[i].max(v[j])));
            }
        }
    }
    let locked = |a: VertexId, b: VertexId| edges.contains(&(a.min(b), a.max(b)));
    let mut rng = StdRng::seed_from_u64(3);
    let n = tri.num_vertices() as u32;
    for _ in 0..200 {
        let (a, b) = (VertexId(rng.gen_range(0..n)), VertexId(rng.gen_range(0..n)));
        if a != b && !has_edge(ct.triangulation(), a, b) {
            ct.flip_in_edge(a, b, &locked, 64, &mut Vec::new());
            ct.keep_flips();
        }
    }
    ct.validate_structure().unwrap();
    for &(a, b) in &edges {
        assert!(has_edge(ct.triangulation(), a, b), "{a:?} {b:?}");
    }
}

/// Four points of a square in the plane z = 0 with an apex above and below: the Delaunay
/// tetrahedralisation holds one diagonal of the square (the perturbation's choice); the
/// other is reached only by a 4-4 flip.
#[test]
fn the_other_diagonal_of_a_coplanar_square_takes_a_four_four_flip() {
    let pts = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 1.0],
        [0.5, 0.5, -1.0],
    ];
    let tri = Triangulation3::new(&pts).unwrap();
    let v = |i: usize| tri.vertex_of_input(i);
    let (d0, d1) = if has_edge(&tri, v(0), v(2)) {
        ((v(0), v(2)), (v(1), v(3)))
    } else {
        ((v(1), v(3)), (v(0), v(2)))
    };
    assert!(!has_edge(&tri, d1.0, d1.1));
    let before = cell_set(&tri);
    let mut ct = ConstrainedTriangulation3::new(tri);
    let mark = ct.flip_mark();
    let outcome = ct.flip_in_edge(d1.0, d1.1, &no_lock, 8, &mut Vec::new());
    assert_eq!(outcome, FlipIn::Present(1));
    assert!(!has_edge(ct.triangulation(), d0.0, d0.1));
    ct.validate_structure().unwrap();
    // And back.
    assert_eq!(ct.undo_flips(mark, &mut Vec::new()), FlipIn::Stuck(1));
    assert_eq!(cell_set(ct.triangulation()), before);
}

/// A square pyramid: the base is on the hull, so the cells around its diagonal include two
/// ghost cells; the other diagonal comes by the hull's 4-4 flip.
#[test]
fn the_other_diagonal_of_a_hull_square_takes_a_four_four_flip() {
    let pts = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 1.0],
    ];
    let tri = Triangulation3::new(&pts).unwrap();
    let v = |i: usize| tri.vertex_of_input(i);
    let missing = if has_edge(&tri, v(0), v(2)) {
        (v(1), v(3))
    } else {
        (v(0), v(2))
    };
    let mut ct = ConstrainedTriangulation3::new(tri);
    let outcome = ct.flip_in_edge(missing.0, missing.1, &no_lock, 8, &mut Vec::new());
    assert_eq!(outcome, FlipIn::Present(1));
    ct.validate_structure().unwrap();
    assert_eq!(ct.triangulation().num_cells(), 2);
    assert_eq!(ct.triangulation().num_hull_facets(), 6);
}

#[test]
fn missing_triangles_with_present_edges_are_flipped_in() {
    let mut found = 0;
    for seed in 0..6u64 {
        let pts = uniform3(400, seed);
        let tri = Triangulation3::new(&pts).unwrap();
        // Triangles a b c whose three edges are present but which are not faces.
        let mut edges = BTreeSet::new();
        for c in tri.cells() {
            let v = tri.cell(c);
            for i in 0..4 {
                for j in 0..4 {
                    if i != j {
                        edges.insert((v[i], v[j]));
                    }
                }
            }
        }
        let mut ct = ConstrainedTriangulation3::new(tri.clone());
        let mut star = Vec::new();
        let mut stars = StarSearch::default();
        for &(a, b) in edges.iter().take(4000) {
            for &(b2, c) in edges.range((b, VertexId(0))..(b, VertexId(u32::MAX))) {
                debug_assert_eq!(b2, b);
                if c == a || !edges.contains(&(c, a)) {
                    continue;
                }
                let t = ct.triangulation();
                if stars
                    .find(t, a, &mut star, |v| v.contains(&b) && v.contains(&c))
                    .is_some()
                    || !(has_edge(t, a, b) && has_edge(t, b, c) && has_edge(t, c, a))
                {
                    continue;
                }
                let before = cell_set(ct.triangulation());
                match ct.flip_in_face(a, b, c, &no_lock, 32, &mut Vec::new()) {
                    FlipIn::Present(_) => {
                        found += 1;
                        let t = ct.triangulation();
                        assert!(stars
                            .find(t, a, &mut star, |v| v.contains(&b) && v.contains(&c))
                            .is_some());
                        ct.validate_structure().unwrap();
                        ct.keep_flips();
                    }
                    FlipIn::Stuck(_) => {
                        assert_eq!(cell_set(ct.triangulation()), before);
                    }
                }
            }
        }
    }
    assert!(found > 10, "{found}");
}

/// Inserting by splitting the cell, face or edge a point lies in, then flipping to the
/// Delaunay property, gives the Delaunay tetrahedralisation: the same cells as Bowyer–Watson.
#[test]
fn insertion_by_splitting_and_flips_matches_bowyer_watson() {
    for seed in 0..4u64 {
        let pts = uniform3(600, seed);
        let (first, rest) = pts.split_at(300);
        let mut ct = ConstrainedTriangulation3::new(Triangulation3::new(first).unwrap());
        for &p in rest {
            let v = ct.insert_splitting(p, VertexId(0)).unwrap().unwrap();
            let faces = ct
                .last_new_cells()
                .iter()
                .flat_map(|&c| (0..4).map(move |i| delmesh_delaunay_core::FacetRef::new(c, i)))
                .collect();
            let flips = ct.make_delaunay_from_locked(faces, |_| true, &no_lock, &mut Vec::new());
            assert!(flips.left.is_empty(), "seed {seed}, {v:?}: {flips:?}");
        }
        ct.validate().unwrap();
        let bw = Triangulation3::new(&pts).unwrap();
        assert_eq!(cell_set(ct.triangulation()), cell_set(&bw), "seed {seed}");
    }
}

/// Points on the faces and edges of a grid's cells (and on its hull, and just beyond it) are
/// inserted by splitting what they lie on; the result is a valid tetrahedralisation.
#[test]
fn splitting_insertion_on_faces_edges_and_beyond_the_hull() {
    let pts = grid3(4);
    let mut ct = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
    let new = [
        [1.5, 1.0, 1.0],   // on a grid edge
        [1.5, 1.5, 1.0],   // on a grid face's diagonal or face
        [0.5, 0.0, 0.5],   // on the hull plane y = 0
        [1.25, 2.0, -0.5], // beyond the hull
        [1.3, 1.4, 1.6],   // inside a cell
    ];
    for p in new {
        assert!(
            ct.insert_splitting(p, VertexId(0)).unwrap().is_some(),
            "{p:?}"
        );
        ct.validate_structure().unwrap();
    }
    assert_eq!(ct.triangulation().num_vertices(), 64 + new.len());
    // At an existing vertex: nothing.
    assert_eq!(
        ct.insert_splitting([1.0, 1.0, 1.0], VertexId(0)).unwrap(),
        None
    );
}

/// On a grid (cospherical points everywhere), growing insertion is Bowyer–Watson's where the
/// cells are Delaunay, so it ends Delaunay; a mesh made non-Delaunay by flips still gets a
/// valid insertion.
#[test]
fn growing_insertion_on_a_grid_and_after_flips() {
    let pts = grid3(4);
    let mut ct = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
    let mut rng = StdRng::seed_from_u64(5);
    for _ in 0..150 {
        // Half-integer coordinates: on grid faces, edges and planes.
        let p = [0, 1, 2].map(|_| f64::from(rng.gen_range(1..6)) * 0.5);
        ct.insert_growing(p, VertexId(0)).unwrap();
    }
    ct.validate().unwrap();
    // Flip some edges in (the mesh is then not Delaunay), then insert again.
    let n = ct.triangulation().num_vertices() as u32;
    for _ in 0..100 {
        let (a, b) = (VertexId(rng.gen_range(0..n)), VertexId(rng.gen_range(0..n)));
        if a != b {
            ct.flip_in_edge(a, b, &no_lock, 16, &mut Vec::new());
            ct.keep_flips();
        }
    }
    for _ in 0..100 {
        let p = [0, 1, 2].map(|_| rng.gen_range(0.2..2.8));
        ct.insert_growing(p, VertexId(0)).unwrap();
        ct.validate_structure().unwrap();
    }
}
