//! The constrained 2D triangulation: Lawson insertion, Sloan segment insertion, flips after
//! moves; every result validated exactly (constrained Delaunay, orientation, adjacency).

mod common;

use common::{grid2, uniform2};
use delmesh_delaunay_core::{
    CellId, ConstrainedTriangulation2, ConstraintError, Insertion, Triangulation2, VertexId,
};
use delmesh_predicates::{orient2d, Sign};
use proptest::prelude::*;
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::collections::BTreeSet;

/// The vertices of cell `c` in input numbering, sorted.
fn input_triple(tri: &Triangulation2, c: CellId) -> [usize; 3] {
    let mut t = [0; 3];
    for (k, &v) in tri.cell(c).iter().enumerate() {
        t[k] = tri.input_index(v);
    }
    t.sort_unstable();
    t
}

/// The finite cells as sorted vertex triples in input numbering.
fn cell_set(tri: &Triangulation2) -> BTreeSet<[usize; 3]> {
    tri.cells().map(|c| input_triple(tri, c)).collect()
}

fn crosses(p: &[[f64; 2]], s: (usize, usize), t: (usize, usize)) -> bool {
    let o = |a: usize, b: usize, c: usize| orient2d(p[a], p[b], p[c]);
    let opp = |x: Sign, y: Sign| x != y && x != Sign::Zero && y != Sign::Zero;
    if s.0 == t.0 || s.0 == t.1 || s.1 == t.0 || s.1 == t.1 {
        return false;
    }
    opp(o(s.0, s.1, t.0), o(s.0, s.1, t.1)) && opp(o(t.0, t.1, s.0), o(t.0, t.1, s.1))
}

/// Random non-crossing segments between the points (greedy).
fn random_segments(p: &[[f64; 2]], tries: usize, seed: u64) -> Vec<(usize, usize)> {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut segs: Vec<(usize, usize)> = Vec::new();
    for _ in 0..tries {
        let a = rng.gen_range(0..p.len());
        let b = rng.gen_range(0..p.len());
        if a != b
            && !segs
                .iter()
                .any(|&s| crosses(p, s, (a, b)) || s == (a, b) || s == (b, a))
        {
            segs.push((a, b));
        }
    }
    segs
}

/// Inserts `p`; a point outside the hull is refused (and skipped here).
fn insert_inside(cdt: &mut ConstrainedTriangulation2, p: [f64; 2]) {
    match cdt.insert(p) {
        Ok(_) | Err(ConstraintError::OutsideHull { .. }) => {}
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn lawson_insertion_gives_the_delaunay_triangulation() {
    // A box first, so every later point is inside the hull.
    let mut pts = vec![[-1.0, -1.0], [2.0, -1.0], [2.0, 2.0], [-1.0, 2.0]];
    pts.extend(uniform2(2000, 7));
    let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts[..4]).unwrap());
    for &p in &pts[4..] {
        assert!(matches!(cdt.insert(p).unwrap(), Insertion::Inserted(_)));
    }
    cdt.validate().unwrap();
    let bw = Triangulation2::new(&pts).unwrap();
    assert_eq!(cell_set(cdt.triangulation()), cell_set(&bw));
}

#[test]
fn lawson_insertion_on_a_grid_matches_bowyer_watson() {
    // Co-circular everywhere and points exactly on edges: the perturbation must agree.
    let pts = grid2(12);
    // The hull points first (insertion refuses points on the hull), then the interior.
    let on_hull = |p: &[f64; 2]| p[0] == 0.0 || p[1] == 0.0 || p[0] == 11.0 || p[1] == 11.0;
    let (mut ordered, inner): (Vec<[f64; 2]>, Vec<[f64; 2]>) = pts.iter().partition(|p| on_hull(p));
    let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&ordered).unwrap());
    for &p in &inner {
        cdt.insert(p).unwrap();
    }
    ordered.extend(inner);
    let pts = ordered;
    cdt.validate().unwrap();
    assert_eq!(
        cell_set(cdt.triangulation()),
        cell_set(&Triangulation2::new(&pts).unwrap())
    );
}

#[test]
fn segments_inserted_by_flips_are_present_and_constrained_delaunay() {
    for seed in 0..5 {
        let pts = uniform2(400, seed);
        let segs = random_segments(&pts, 300, seed + 100);
        let tri = Triangulation2::new(&pts).unwrap();
        let mut cdt = ConstrainedTriangulation2::new(tri);
        // Vertex ids never change once given.
        let ids: Vec<VertexId> = (0..pts.len())
            .map(|i| cdt.triangulation().vertex_of_input(i))
            .collect();
        let v = |i: usize| ids[i];
        for &(a, b) in &segs {
            let (va, vb) = (v(a), v(b));
            cdt.insert_segment(va, vb).unwrap();
        }
        cdt.validate().unwrap();
        for &(a, b) in &segs {
            assert!(
                cdt.find_edge(v(a), v(b)).is_some(),
                "segment {a} {b} missing"
            );
        }
        assert_eq!(cdt.constrained_edges().len(), segs.len());
        // More points keep every segment (no point falls on one) and the CDT property.
        for p in uniform2(500, seed + 1000) {
            insert_inside(&mut cdt, p);
        }
        cdt.validate().unwrap();
        for &(a, b) in &segs {
            assert!(cdt.find_edge(v(a), v(b)).is_some());
        }
    }
}

#[test]
fn segment_order_does_not_matter() {
    let pts = uniform2(300, 3);
    let segs = random_segments(&pts, 25, 4);
    let build = |order: &[(usize, usize)]| {
        let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
        for &(a, b) in order {
            let t = cdt.triangulation();
            let (va, vb) = (t.vertex_of_input(a), t.vertex_of_input(b));
            cdt.insert_segment(va, vb).unwrap();
        }
        cell_set(cdt.triangulation())
    };
    let mut reversed = segs.clone();
    reversed.reverse();
    assert_eq!(build(&segs), build(&reversed));
}

#[test]
fn a_segment_through_a_vertex_or_across_a_constraint_is_an_error() {
    let pts = grid2(5);
    let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
    let v = |t: &ConstrainedTriangulation2, i: usize| t.triangulation().vertex_of_input(i);
    // (0,0) → (4,0) passes through (1,0), (2,0), (3,0).
    let (a, b) = (v(&cdt, 0), v(&cdt, 4));
    assert!(matches!(
        cdt.insert_segment(a, b),
        Err(ConstraintError::VertexOnSegment { .. })
    ));
    // (0,1) → (4,2) then (1,3) → (3,0) crosses it.
    let (a, b) = (v(&cdt, 5), v(&cdt, 14));
    cdt.insert_segment(a, b).unwrap();
    let (c, d) = (v(&cdt, 16), v(&cdt, 3));
    let before = cell_set(cdt.triangulation());
    assert!(matches!(
        cdt.insert_segment(c, d),
        Err(ConstraintError::CrossesConstraint { .. })
    ));
    assert_eq!(before, cell_set(cdt.triangulation()));
    cdt.validate().unwrap();
}

#[test]
fn a_point_on_a_constrained_edge_splits_it() {
    let pts = [[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [1.0, 3.0]];
    let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
    let t = cdt.triangulation();
    let (a, c) = (t.vertex_of_input(0), t.vertex_of_input(2));
    cdt.insert_segment(a, c).unwrap();
    let m = cdt.insert([2.0, 2.0]).unwrap().vertex();
    cdt.validate().unwrap();
    assert!(cdt.find_edge(a, m).is_some() && cdt.find_edge(m, c).is_some());
    assert_eq!(cdt.constrained_edges().len(), 2);
    assert!(matches!(
        cdt.insert([5.0, 1.0]),
        Err(ConstraintError::OutsideHull { .. })
    ));
    assert!(matches!(
        cdt.insert([4.0, 1.0]),
        Err(ConstraintError::OutsideHull { .. })
    ));
    assert!(matches!(
        cdt.insert([1.0, 3.0]),
        Ok(Insertion::Duplicate(_))
    ));
}

/// Constructed points (mesh generation's centroids and circumcentres): one rounded onto or
/// beyond the hull is refused, not an error; one within 2^-142 of an axis is flushed onto it
/// rather than refused as out of range (found by the adversarial sweep: a centroid on the
/// top edge of a square at α 0.001, one 1.5e-43 from x = 0 under a spacing source).
#[test]
fn a_constructed_point_on_the_hull_is_refused_and_a_tiny_coordinate_flushed() {
    let pts = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
    let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
    let hint = CellId(0);
    for p in [[1.0, 2.0], [3.0, 1.0], [2.0, 1.0]] {
        assert_eq!(
            cdt.insert_near_if(p, hint, |_, _, _| true),
            Ok(None),
            "{p:?}"
        );
        // Input points there stay an error.
        assert!(matches!(
            cdt.insert(p),
            Err(ConstraintError::OutsideHull { .. })
        ));
    }
    assert!(matches!(
        cdt.insert([1.5e-43, 1.0]),
        Err(ConstraintError::Triangulation(_))
    ));
    // Flushed onto x = 0, the hull: refused.
    assert_eq!(
        cdt.insert_near_if([1.5e-43, 1.0], hint, |_, _, _| true),
        Ok(None)
    );
    // A square around the origin: a point 1e-300 below the axis y = 0 goes in on it.
    let pts = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
    let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
    let v = cdt
        .insert_near_if([0.5, -1e-300], CellId(0), |_, _, _| true)
        .unwrap()
        .unwrap()
        .vertex();
    assert_eq!(cdt.triangulation().vertex(v), [0.5, 0.0]);
    cdt.validate().unwrap();
}

/// A constructed point goes in from a cell only if the straight line from the cell's centroid
/// to it crosses no constrained edge (quality refinement's circumcentres: one behind the
/// boundary could not remove the cell, and the walk to it could cross the whole mesh).
#[test]
fn a_point_goes_in_from_a_cell_only_if_the_cell_sees_it() {
    let pts = uniform2(300, 3);
    let segs = random_segments(&pts, 25, 4);
    let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
    for &(a, b) in &segs {
        let v = |i: usize| cdt.triangulation().vertex_of_input(i);
        let (va, vb) = (v(a), v(b));
        cdt.insert_segment(va, vb).unwrap();
    }
    let t = cdt.triangulation();
    let edges: Vec<([f64; 2], [f64; 2])> = cdt
        .constrained_edges()
        .iter()
        .map(|&(a, b)| (t.vertex(a), t.vertex(b)))
        .collect();
    let cells: Vec<CellId> = t.cells().collect();
    let mut rng = StdRng::seed_from_u64(5);
    let (mut seen, mut hidden) = (0, 0);
    for _ in 0..400 {
        let c = cells[rng.gen_range(0..cells.len())];
        // Inside the hull of the 300 points.
        let p = [rng.gen_range(0.1..0.9), rng.gen_range(0.1..0.9)];
        let t = cdt.triangulation();
        let corner = |k: usize| t.vertex(t.cell(c)[k]);
        let q = [0, 1].map(|i| (corner(0)[i] + corner(1)[i] + corner(2)[i]) / 3.0);
        let opposite = |x: Sign, y: Sign| x != y && x != Sign::Zero && y != Sign::Zero;
        let blocked = edges.iter().any(|&(a, b)| {
            opposite(orient2d(q, p, a), orient2d(q, p, b))
                && opposite(orient2d(a, b, q), orient2d(a, b, p))
        });
        let mut trial = cdt.clone();
        let inserted = trial.insert_visible_if(p, c, |_, _, _| true).unwrap();
        assert_eq!(inserted.is_some(), !blocked, "cell {c:?}, point {p:?}");
        if blocked {
            hidden += 1;
        } else {
            trial.validate().unwrap();
            seen += 1;
        }
    }
    assert!(seen > 40 && hidden > 40, "{seen} seen, {hidden} hidden");

    // A grid (lines through vertices, points on edges) with a wall x = 4 from y = 1 to 6.
    let pts = grid2(9);
    let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
    let at = |cdt: &ConstrainedTriangulation2, x: f64, y: f64| {
        let i = pts.iter().position(|&p| p == [x, y]).unwrap();
        cdt.triangulation().vertex_of_input(i)
    };
    for y in 1..6 {
        let (a, b) = (at(&cdt, 4.0, y as f64), at(&cdt, 4.0, y as f64 + 1.0));
        cdt.insert_segment(a, b).unwrap();
    }
    let t = cdt.triangulation();
    let west = t
        .cells()
        .find(|&c| {
            t.cell(c)
                .iter()
                .all(|&v| t.vertex(v)[0] <= 3.0 && t.vertex(v)[1] >= 3.0)
        })
        .unwrap();
    let corners = t
        .cell(west)
        .iter()
        .map(|&v| t.vertex(v))
        .collect::<Vec<_>>();
    for (p, visible) in [
        ([6.5, 3.5], false),
        ([4.5, 2.0], false),
        ([2.5, 7.5], true),
        ([1.0, 1.5], true),
        ([4.0, 7.5], true),
        // On a vertex: a duplicate, found.
        ([2.0, 2.0], true),
        // On the hull, or beyond it: refused, as by `insert_near_if`.
        ([0.0, 3.5], false),
        ([-1.0, 3.5], false),
    ] {
        let mut trial = cdt.clone();
        let got = trial.insert_visible_if(p, west, |_, _, _| true).unwrap();
        assert_eq!(got.is_some(), visible, "{p:?} from {corners:?}");
        trial.validate().unwrap();
    }
    // Points on the line of the wall, beyond its ends, and on its vertices: never a panic.
    for y in [0.0, 0.5, 1.0, 3.0, 6.0, 7.0, 8.0] {
        let mut trial = cdt.clone();
        trial
            .insert_visible_if([4.0, y], west, |_, _, _| true)
            .unwrap();
        trial.validate().unwrap();
    }
}

#[test]
fn moves_that_invert_are_refused_and_flips_restore_delaunay() {
    let pts = uniform2(500, 11);
    let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
    let t = cdt.triangulation();
    // An interior vertex moved onto a far-away hull corner would invert its star.
    let inner = (0..t.num_vertices() as u32)
        .map(VertexId)
        .find(|&v| {
            let p = t.vertex(v);
            (p[0] - 0.5).abs() < 0.1 && (p[1] - 0.5).abs() < 0.1
        })
        .unwrap();
    assert!(matches!(
        cdt.move_vertices(&[(inner, [0.99, 0.99])]),
        Err(ConstraintError::InvalidMove { .. })
    ));
    cdt.validate().unwrap();
    // Small random moves of interior vertices, then flips: the result is Delaunay again and
    // equal to the Delaunay triangulation of the moved points.
    let mut rng = StdRng::seed_from_u64(5);
    let mut moved = 0;
    for v in 0..cdt.triangulation().num_vertices() as u32 {
        let v = VertexId(v);
        let p = cdt.triangulation().vertex(v);
        let q = [
            p[0] + rng.gen_range(-0.01..0.01),
            p[1] + rng.gen_range(-0.01..0.01),
        ];
        if cdt.move_vertices(&[(v, q)]).is_ok() {
            moved += 1;
        }
    }
    assert!(moved > 300, "{moved}");
    let flips = cdt.make_delaunay();
    assert!(flips > 0);
    cdt.validate().unwrap();
    let t = cdt.triangulation();
    let now: Vec<[f64; 2]> = (0..t.num_input_points())
        .map(|i| t.vertex(t.vertex_of_input(i)))
        .collect();
    assert_eq!(cell_set(t), cell_set(&Triangulation2::new(&now).unwrap()));
}

#[test]
fn moving_all_vertices_at_once_checks_every_star() {
    let pts = uniform2(400, 12);
    let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
    let t = cdt.triangulation();
    let here: Vec<[f64; 2]> = (0..t.num_vertices() as u32)
        .map(|v| t.vertex(VertexId(v)))
        .collect();
    // Every vertex where it is: nothing changes.
    cdt.move_all_vertices(&here).unwrap();
    assert_eq!(cdt.triangulation().vertex(VertexId(7)), here[7]);
    // One position per vertex, no fewer.
    assert!(matches!(
        cdt.move_all_vertices(&here[1..]),
        Err(ConstraintError::InvalidMove { .. })
    ));
    // Interior vertices shrunk a little towards the centre keep every cell positive; the hull
    // stays (a hull vertex cannot move).
    let hull: Vec<bool> = (0..here.len() as u32)
        .map(|v| {
            let t = cdt.triangulation();
            t.cells_around_vertex(VertexId(v))
                .iter()
                .any(|&c| t.is_ghost(c))
        })
        .collect();
    let shrunk: Vec<[f64; 2]> = here
        .iter()
        .zip(&hull)
        .map(|(p, &h)| {
            if h {
                *p
            } else {
                [0.5 + 0.999 * (p[0] - 0.5), 0.5 + 0.999 * (p[1] - 0.5)]
            }
        })
        .collect();
    cdt.move_all_vertices(&shrunk).unwrap();
    cdt.make_delaunay();
    cdt.validate().unwrap();
    let t = cdt.triangulation();
    assert!((0..here.len()).all(|v| t.vertex(VertexId(v as u32)) == shrunk[v]));
    // An interior vertex sent to a far corner inverts its star: refused, nothing moves, and
    // the vertex is named.
    let inner = (0..here.len())
        .find(|&v| !hull[v] && (shrunk[v][0] - 0.5).abs() < 0.1 && (shrunk[v][1] - 0.5).abs() < 0.1)
        .unwrap();
    let mut bad = shrunk.clone();
    bad[inner] = [0.99, 0.99];
    assert_eq!(
        cdt.move_all_vertices(&bad),
        Err(ConstraintError::InvalidMove {
            vertex: VertexId(inner as u32)
        })
    );
    let t = cdt.triangulation();
    assert!((0..here.len()).all(|v| t.vertex(VertexId(v as u32)) == shrunk[v]));
    cdt.validate().unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn random_constrained_sets_validate(seed in 0u64..1000, n in 20usize..200) {
        let pts = uniform2(n, seed);
        let segs = random_segments(&pts, n, seed ^ 0xABCD);
        let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
        for &(a, b) in &segs {
            let t = cdt.triangulation();
            let (va, vb) = (t.vertex_of_input(a), t.vertex_of_input(b));
            cdt.insert_segment(va, vb).unwrap();
        }
        for p in uniform2(n, seed + 1) {
            insert_inside(&mut cdt, p);
        }
        prop_assert!(cdt.validate().is_ok());
        prop_assert_eq!(cdt.constrained_edges().len(), segs.len());
    }
}

/// The constrained edges as sorted pairs of input indices.
fn constrained_set(cdt: &ConstrainedTriangulation2) -> BTreeSet<(usize, usize)> {
    let t = cdt.triangulation();
    cdt.constrained_edges()
        .into_iter()
        .map(|(a, b)| {
            let (a, b) = (t.input_index(a), t.input_index(b));
            (a.min(b), a.max(b))
        })
        .collect()
}

/// Each finite cell (sorted input triple) with its tag.
fn tag_set(cdt: &ConstrainedTriangulation2) -> BTreeSet<([usize; 3], u32)> {
    let t = cdt.triangulation();
    t.cells()
        .map(|c| (input_triple(t, c), cdt.tag(c)))
        .collect()
}

#[test]
fn renumbering_keeps_cells_constraints_and_tags_and_insertion_goes_on() {
    for seed in 0..3 {
        let mut pts = vec![[-1.0, -1.0], [2.0, -1.0], [2.0, 2.0], [-1.0, 2.0]];
        pts.extend(uniform2(600, seed));
        pts.push(pts[9]); // a duplicate: both inputs name one vertex
        let segs = random_segments(&pts, 200, seed + 7);
        let mut cdt = ConstrainedTriangulation2::new(Triangulation2::new(&pts).unwrap());
        for &(a, b) in &segs {
            let t = cdt.triangulation();
            let (va, vb) = (t.vertex_of_input(a), t.vertex_of_input(b));
            cdt.insert_segment(va, vb).unwrap();
        }
        let cells: Vec<_> = cdt.triangulation().cells().collect();
        for (k, &c) in cells.iter().enumerate() {
            cdt.set_tag(c, (k % 5) as u32);
        }
        let old_vertex: Vec<VertexId> = (0..pts.len())
            .map(|i| cdt.triangulation().vertex_of_input(i))
            .collect();
        let (before, constraints) = (tag_set(&cdt), constrained_set(&cdt));
        let slots = cdt.num_cell_slots();

        let map = cdt.renumber();
        cdt.validate().unwrap();
        assert_eq!(tag_set(&cdt), before);
        assert_eq!(constrained_set(&cdt), constraints);
        assert_eq!(cdt.num_cell_slots(), slots, "no free slots to drop in 2D");
        let t = cdt.triangulation();
        for (i, &v) in old_vertex.iter().enumerate() {
            assert_eq!(t.vertex_of_input(i), map.vertex(v), "input {i}");
            assert_eq!(t.vertex(map.vertex(v)), pts[i]);
        }
        let mut seen = map.vertex.clone();
        seen.sort_unstable();
        assert!(seen.iter().enumerate().all(|(k, &v)| v as usize == k));
        // Neighbouring cells are close in the new numbering: most vertex pairs of a cell are
        // within a small window (random order would put nearly all of them far apart).
        let n = t.num_vertices();
        let near = t
            .cells()
            .filter(|&c| {
                let v = t.cell(c);
                (v[0].index() as i64 - v[1].index() as i64).unsigned_abs() < (n / 8) as u64
            })
            .count();
        assert!(
            near * 10 > t.cells().count() * 7,
            "{near} of {}",
            t.cells().count()
        );

        // Insertion and segments go on in the new numbering.
        for p in uniform2(300, seed + 50) {
            insert_inside(&mut cdt, p);
        }
        cdt.validate().unwrap();
        assert_eq!(constrained_set(&cdt), constraints);
    }
}
