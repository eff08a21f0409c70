//! Moving vertices of a 3D constrained triangulation and restoring the Delaunay property by
//! 2-3 and 3-2 flips.

mod common;

use common::{grid3, uniform3};
use delmesh_delaunay_core::{ConstrainedTriangulation3, ConstraintError, Triangulation3, VertexId};
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::collections::BTreeSet;

/// The cells as sorted input-index quadruples.
fn cell_set(tri: &Triangulation3) -> BTreeSet<[usize; 4]> {
    tri.cells()
        .map(|c| {
            let mut q = [0usize; 4];
            for (k, &v) in tri.cell(c).iter().enumerate() {
                q[k] = tri.input_index(v);
            }
            q.sort_unstable();
            q
        })
        .collect()
}

/// Random moves of every vertex by up to `step` per axis, each kept only if it inverts nothing.
fn jiggle(ct: &mut ConstrainedTriangulation3, step: f64, seed: u64) -> usize {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut moved = 0;
    for v in 0..ct.triangulation().num_vertices() as u32 {
        let v = VertexId(v);
        let p = ct.triangulation().vertex(v);
        let q = p.map(|x| x + rng.gen_range(-step..step));
        if ct.move_vertices(&[(v, q)]).is_ok() {
            moved += 1;
        }
    }
    moved
}

fn moved_points(tri: &Triangulation3) -> Vec<[f64; 3]> {
    (0..tri.num_input_points())
        .map(|i| tri.vertex(tri.vertex_of_input(i)))
        .collect()
}

#[test]
fn a_move_that_inverts_is_refused_and_changes_nothing() {
    let pts = uniform3(400, 3);
    let mut ct = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
    let t = ct.triangulation();
    let inner = (0..t.num_vertices() as u32)
        .map(VertexId)
        .find(|&v| t.vertex(v).iter().all(|x| (x - 0.5).abs() < 0.15))
        .unwrap();
    let before = t.vertex(inner);
    assert!(matches!(
        ct.move_vertices(&[(inner, [0.99, 0.99, 0.99])]),
        Err(ConstraintError::InvalidMove { vertex }) if vertex == inner
    ));
    assert_eq!(ct.triangulation().vertex(inner), before);
    ct.validate().unwrap();
}

#[test]
fn flips_after_small_moves_give_the_delaunay_triangulation_of_the_moved_points() {
    for seed in 0..6u64 {
        let pts = uniform3(1500, seed);
        let mut ct = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
        let moved = jiggle(&mut ct, 0.004, seed + 100);
        assert!(moved > 1000, "{moved}");
        ct.validate_structure().unwrap();
        let flips = ct.make_delaunay(|_| true);
        assert!(
            flips.failing > 0 && flips.two_three + flips.three_two > 0,
            "{flips:?}"
        );
        // (Flips can stop short in 3D, but not on these.)
        assert!(flips.left.is_empty(), "seed {seed}: {flips:?}");
        ct.validate().unwrap();
        let t = ct.triangulation();
        assert_eq!(
            cell_set(t),
            cell_set(&Triangulation3::new(&moved_points(t)).unwrap()),
            "seed {seed}: {flips:?}"
        );
    }
}

#[test]
fn flips_on_a_jiggled_grid_list_exactly_the_faces_they_could_not_mend() {
    // A lattice is co-spherical everywhere: the perturbation decides every test, and some
    // faces end up needing a flip that 2-3 and 3-2 flips cannot make.
    let pts: Vec<[f64; 3]> = grid3(9);
    let mut ct = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
    jiggle(&mut ct, 0.2, 7);
    let flips = ct.make_delaunay(|_| true);
    assert!(
        flips.two_three + flips.three_two > flips.failing / 2,
        "{flips:?}"
    );
    assert!(flips.left.len() * 100 < flips.failing, "{flips:?}");
    ct.validate_structure().unwrap();
    // Each face left fails, and a second pass over every face finds those and nothing else.
    assert!(flips.left.iter().all(|&f| ct.face_fails(f, |_| true)));
    let again = ct.make_delaunay(|_| true);
    assert_eq!(again.two_three + again.three_two, 0);
    assert_eq!(again.failing, flips.left.len());
    assert_eq!(again.left, flips.left);
}

#[test]
fn protected_faces_and_cells_out_of_scope_are_never_flipped() {
    let pts = uniform3(800, 21);
    let mut ct = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
    // Protect every face of the cells touching the lower half's top layer, and put the cells
    // above z = 0.7 out of scope.
    let t = ct.triangulation();
    let cells: Vec<_> = t.cells().collect();
    let mut protected = Vec::new();
    for &c in &cells {
        let v = t.cell(c);
        let z = v.iter().map(|&u| t.vertex(u)[2]).sum::<f64>() / 4.0;
        if (0.4..0.45).contains(&z) {
            for i in 0..4 {
                protected.push(t.neighbor_facet(c, i));
            }
        }
    }
    for &f in &protected {
        ct.protect(f);
    }
    for &c in &cells {
        let t = ct.triangulation();
        let z = t.cell(c).iter().map(|&u| t.vertex(u)[2]).sum::<f64>() / 4.0;
        if z > 0.7 {
            ct.set_tag(c, 1);
        }
    }
    let faces_before: BTreeSet<[VertexId; 3]> = sorted_faces(&ct.protected_faces());
    let outside_before = tagged(&ct, 1);
    jiggle(&mut ct, 0.005, 22);
    let flips = ct.make_delaunay(|tag| tag == 0);
    assert!(flips.two_three + flips.three_two > 0);
    ct.validate_structure().unwrap();
    assert_eq!(sorted_faces(&ct.protected_faces()), faces_before);
    assert_eq!(tagged(&ct, 1), outside_before);
}

fn sorted_faces(faces: &[[VertexId; 3]]) -> BTreeSet<[VertexId; 3]> {
    faces
        .iter()
        .map(|f| {
            let mut f = *f;
            f.sort_unstable();
            f
        })
        .collect()
}

/// The cells with tag `tag`, as sorted vertex quadruples.
fn tagged(ct: &ConstrainedTriangulation3, tag: u32) -> BTreeSet<[VertexId; 4]> {
    let t = ct.triangulation();
    t.all_cells()
        .filter(|&c| ct.tag(c) == tag && !t.is_ghost(c))
        .map(|c| {
            let mut q = [VertexId(0); 4];
            q.copy_from_slice(t.cell(c));
            q.sort_unstable();
            q
        })
        .collect()
}

#[test]
fn splitting_a_protected_edge_splits_its_faces_and_keeps_them_protected() {
    let pts = uniform3(300, 9);
    let mut ct = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
    // An interior cell made a region of its own: its faces protected, its tag 1.
    let t = ct.triangulation();
    let c = t
        .cells()
        .find(|&c| {
            t.cell(c)
                .iter()
                .all(|&v| t.vertex(v).iter().all(|x| (x - 0.5).abs() < 0.3))
        })
        .unwrap();
    let [x, y, w1, w2] = [0, 1, 2, 3].map(|k| t.cell(c)[k]);
    for i in 0..4 {
        let f = ct.triangulation().neighbor_facet(c, i);
        ct.protect(f);
    }
    ct.set_tag(c, 1);
    let (px, py) = (ct.triangulation().vertex(x), ct.triangulation().vertex(y));
    let mid = [0, 1, 2].map(|k| 0.5 * (px[k] + py[k]));
    let (v, split) = ct.split_edge(x, y, mid).unwrap().unwrap();
    let mut expected_split = vec![w1, w2];
    expected_split.sort_unstable();
    assert_eq!(split, expected_split);
    // The two faces on the edge are split in halves; the other two stay.
    assert_eq!(
        sorted_faces(&ct.protected_faces()),
        sorted_faces(&[
            [y, w1, w2],
            [x, w1, w2],
            [x, v, w1],
            [v, y, w1],
            [x, v, w2],
            [v, y, w2]
        ])
    );
    ct.validate_structure().unwrap();
    // The region is now the two cells joining the new vertex to the faces that stayed.
    let t = ct.triangulation();
    let region: Vec<_> = t.cells().filter(|&c| ct.tag(c) == 1).collect();
    assert_eq!(region.len(), 2);
    for c in region {
        assert!(t.cell(c).contains(&v) && t.cell(c).contains(&w1) && t.cell(c).contains(&w2));
    }
    // Splitting an edge that is not one changes nothing.
    let before = ct.triangulation().num_cells();
    assert!(ct.split_edge(x, y, mid).unwrap().is_none());
    assert_eq!(ct.triangulation().num_cells(), before);
}

#[test]
fn renumbering_keeps_protected_faces_and_tags_with_their_cells() {
    let pts = uniform3(600, 21);
    let mut ct = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
    // Protect some faces and tag cells by their first vertex's input index, all in input
    // numbering, which renumbering keeps.
    let t = ct.triangulation();
    let cells: Vec<_> = t.cells().collect();
    let mut faces = BTreeSet::new();
    for &c in cells.iter().step_by(7) {
        let v = t.cell(c);
        faces.insert({
            let mut f = [v[0], v[1], v[2]].map(|u| t.input_index(u));
            f.sort_unstable();
            f
        });
    }
    let tagged = |ct: &ConstrainedTriangulation3| {
        let t = ct.triangulation();
        t.cells()
            .map(|c| {
                let mut q: Vec<usize> = t.cell(c).iter().map(|&u| t.input_index(u)).collect();
                q.sort_unstable();
                (q, ct.tag(c))
            })
            .collect::<BTreeSet<_>>()
    };
    let protected = |ct: &ConstrainedTriangulation3| {
        let t = ct.triangulation();
        ct.protected_faces()
            .into_iter()
            .map(|f| {
                let mut f = f.map(|u| t.input_index(u));
                f.sort_unstable();
                f
            })
            .collect::<BTreeSet<_>>()
    };
    for f in &faces {
        let t = ct.triangulation();
        let [a, b, c] = f.map(|i| t.vertex_of_input(i));
        assert!(ct.protect_face(a, b, c));
    }
    for c in cells {
        let first = ct
            .triangulation()
            .input_index(ct.triangulation().cell(c)[0]);
        ct.set_tag(c, first as u32 % 5);
    }
    let (before_cells, before_tags) = (cell_set(ct.triangulation()), tagged(&ct));
    assert_eq!(protected(&ct), faces);
    ct.renumber();
    assert_eq!(cell_set(ct.triangulation()), before_cells);
    assert_eq!(tagged(&ct), before_tags);
    assert_eq!(protected(&ct), faces);
    assert!(ct.validate().is_ok());
    // Flips and moves go on after it.
    assert!(jiggle(&mut ct, 0.002, 4) > 0);
    let flips = ct.make_delaunay(|_| true);
    assert_eq!(protected(&ct), faces);
    assert!(flips.left.len() <= flips.failing);
}

#[test]
fn one_vertex_moves_exactly_when_moving_it_alone_is_valid() {
    let pts = uniform3(400, 5);
    let mut whole = ConstrainedTriangulation3::new(Triangulation3::new(&pts).unwrap());
    let mut single = whole.clone();
    let mut rng = StdRng::seed_from_u64(9);
    let mut star = Vec::new();
    let (mut moved, mut refused) = (0, 0);
    for v in 0..whole.triangulation().num_vertices() as u32 {
        let v = VertexId(v);
        let p = whole.triangulation().vertex(v);
        let q = p.map(|x| x + rng.gen_range(-0.05..0.05));
        let valid = whole.move_vertices(&[(v, q)]).is_ok();
        assert_eq!(single.move_vertex(v, q, &mut star), valid, "vertex {}", v.0);
        assert_eq!(
            single.triangulation().vertex(v),
            whole.triangulation().vertex(v)
        );
        if valid {
            moved += 1;
        } else {
            refused += 1;
        }
    }
    assert!(
        moved > 40 && refused > 40,
        "{moved} moved, {refused} refused"
    );
    single.validate_structure().unwrap();
}
