//! The Voronoi dual: Table 1's structure (forming points, neighbours, `*` on the hull), 2D
//! regions that tile their box, 3D faces equidistant from the two points they separate; on a
//! lattice (co-spherical points) each corner once and no face without area.

mod common;

use common::*;
use delmesh_delaunay_core::*;
use std::collections::HashMap;

#[test]
fn table_structure_is_the_dual_of_the_triangulation() {
    let pts = uniform2(60, 21);
    let t = Triangulation2::new(&pts).unwrap();
    let vd = VoronoiDiagram::new(&t);
    assert_eq!(vd.len(), t.num_cells());
    let mut stars = 0;
    for i in 0..vd.len() {
        let f = vd.forming_points(i);
        assert!(f.windows(2).all(|w| w[0] < w[1]));
        // The circumcentre is equidistant from the forming points.
        let c = vd.circumcenter(i);
        let d: Vec<f64> = f
            .iter()
            .map(|&k| (pts[k as usize][0] - c[0]).hypot(pts[k as usize][1] - c[1]))
            .collect();
        assert!((d[0] - d[1]).abs() < 1e-9 * d[0] && (d[0] - d[2]).abs() < 1e-9 * d[0]);
        for n in vd.neighbors(i) {
            match n {
                None => stars += 1,
                Some(j) => {
                    // Neighbours share two forming points, and the relation is symmetric.
                    let g = vd.forming_points(*j as usize);
                    assert_eq!(f.iter().filter(|x| g.contains(x)).count(), 2);
                    assert!(vd.neighbors(*j as usize).contains(&Some(i as u32)));
                }
            }
        }
    }
    assert_eq!(stars, t.num_hull_facets());
    let table = vd.table(1);
    assert_eq!(table.lines().count(), vd.len() + 1);
}

#[test]
fn voronoi_regions_tile_the_box() {
    let pts = uniform2(300, 22);
    let t = Triangulation2::new(&pts).unwrap();
    let (lo, hi) = ([-0.1, -0.1], [1.1, 1.1]);
    let cells = t.voronoi_cells(lo, hi);
    assert_eq!(cells.len(), pts.len());
    let mut total = 0.0;
    for cell in &cells {
        let poly = &cell.polygon;
        assert!(poly.len() >= 3, "point {} has an empty region", cell.point);
        let a: f64 = (0..poly.len())
            .map(|k| {
                let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
                p[0] * q[1] - p[1] * q[0]
            })
            .sum::<f64>()
            / 2.0;
        assert!(a > 0.0, "region of {} is not counter-clockwise", cell.point);
        total += a;
        // Every corner is at least as close to its point as to any other point.
        let me = pts[cell.point];
        for c in poly {
            let dm = (c[0] - me[0]).hypot(c[1] - me[1]);
            for p in pts.iter().step_by(7) {
                assert!(dm <= (c[0] - p[0]).hypot(c[1] - p[1]) + 1e-9);
            }
        }
    }
    assert!(
        (total - 1.44).abs() < 1e-9,
        "regions cover {total}, box is 1.44"
    );
}

/// Checks that the clipped 2D regions of `pts` tile `[lo, hi]`: each is counter-clockwise
/// and strictly contains its point (exact orientations of its corners, so no edge of zero
/// length either: co-circular points' triangles give one corner), and their areas add up to
/// the box's (relative `1e-12`).
fn assert_regions_tile(pts: &[[f64; 2]], lo: [f64; 2], hi: [f64; 2]) {
    let t = Triangulation2::new(pts).unwrap();
    let cells = t.voronoi_cells(lo, hi);
    let mut total = 0.0;
    for cell in &cells {
        let poly = &cell.polygon;
        let n = poly.len();
        assert!(n >= 3, "{pts:?}: point {} has no region", cell.point);
        let site = pts[cell.point];
        for k in 0..n {
            let (p, q) = (poly[k], poly[(k + 1) % n]);
            assert!(
                delmesh_predicates::orient2d(p, q, site) == delmesh_predicates::Sign::Positive,
                "{pts:?}: region of {} does not contain it: {poly:?}",
                cell.point
            );
        }
        total += (0..n)
            .map(|k| {
                let (p, q) = (poly[k], poly[(k + 1) % n]);
                (p[0] - lo[0]) * (q[1] - lo[1]) - (p[1] - lo[1]) * (q[0] - lo[0])
            })
            .sum::<f64>()
            / 2.0;
    }
    let area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    assert!(
        (total - area).abs() <= 1e-12 * area,
        "{pts:?}: regions cover {total}, the box {area}"
    );
}

/// The CLI's box: the bounding box enlarged by 10% on each side.
fn enlarged_box(pts: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in pts {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    for k in 0..2 {
        let m = 0.1 * (hi[k] - lo[k]);
        lo[k] -= m;
        hi[k] += m;
    }
    (lo, hi)
}

#[test]
fn unbounded_regions_with_far_circumcentres_tile_the_box() {
    // An obtuse triangle: its circumcentre (−41.2, 73.5) is far left of the box, and the region
    // of (23, 25) is a wedge of nearly a half-turn from it. The ray truncation used to close
    // that wedge through a point outside it (a self-intersecting polygon of area −132.7).
    let pts = [[23.0, 25.0], [39.0, 80.0], [39.0, 67.0]];
    let (lo, hi) = enlarged_box(&pts);
    assert_regions_tile(&pts, lo, hi);
    // Two points 5e-13 apart next to one 4e4 away: the circumcentre is 2.5e4 off the box's
    // side, the two clustered points' regions are half-planes.
    let pts = [
        [7e-13, 3.0000000000000003e-13],
        [2e-13, 3.0000000000000003e-13],
        [22000.0, 38000.0],
    ];
    let (lo, hi) = enlarged_box(&pts);
    assert_regions_tile(&pts, lo, hi);
    // Random small integer sets (about 1 in 150 failed).
    let mut rng = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(31);
    let mut tested = 0;
    for _ in 0..3000 {
        let n = rand::Rng::gen_range(&mut rng, 3..=8);
        let pts: Vec<[f64; 2]> = (0..n)
            .map(|_| {
                [
                    f64::from(rand::Rng::gen_range(&mut rng, 0..=100)),
                    f64::from(rand::Rng::gen_range(&mut rng, 0..=100)),
                ]
            })
            .collect();
        let mut distinct = pts.clone();
        distinct.sort_by(|a, b| a.partial_cmp(b).unwrap());
        distinct.dedup();
        if Triangulation2::new(&distinct).is_err() {
            continue; // collinear
        }
        let (lo, hi) = enlarged_box(&distinct);
        assert_regions_tile(&distinct, lo, hi);
        tested += 1;
    }
    assert!(tested > 2900);
}

/// Asserts that every Voronoi vertex of `vd` is equidistant from its forming points within
/// `1e-9` of the distance, and that no input point is closer to it than they are (by more).
fn assert_centres_equidistant<D: Dim>(vd: &VoronoiDiagram<D>, pts: &[D::Point]) {
    let dist = |p: &D::Point, q: &D::Point| {
        p.as_ref()
            .iter()
            .zip(q.as_ref())
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    for i in 0..vd.len() {
        let o = vd.circumcenter(i);
        let d: Vec<f64> = vd
            .forming_points(i)
            .iter()
            .map(|&k| dist(&o, &pts[k as usize]))
            .collect();
        let nearest = pts
            .iter()
            .map(|p| dist(&o, p))
            .fold(f64::INFINITY, f64::min);
        assert!(
            d.iter().all(|r| (r - d[0]).abs() <= 1e-9 * d[0]) && nearest >= d[0] * (1.0 - 1e-9),
            "vertex {i} {o:?} of {:?}: distances {d:?}, nearest point {nearest}",
            vd.forming_points(i)
        );
    }
}

#[test]
fn circumcentres_of_cells_spanning_many_scales_are_accurate() {
    // Three points within 1e-12 and two 1e5–1e6 away. From a far point the edge vectors to the
    // cluster round to the same vector, and the floating-point centre was that far point. The
    // exact centres of the tetrahedra (computed with Python's fractions, correctly rounded):
    let pts = [
        [
            5.250011572292198e-13,
            4.32224626990782e-13,
            9.042839633242201e-13,
        ],
        [
            3.2069038530630267e-13,
            5.468077433143392e-14,
            7.255828799024899e-13,
        ],
        [
            9.001377704234459e-13,
            7.320068357623053e-13,
            5.975216204070308e-13,
        ],
        [88385.4015923462, 363581.9555532492, 374484.9564899955],
        [605541.7884953943, 970406.8915713335, 976457.2905077733],
    ];
    let exact: [([u32; 4], [f64; 3]); 5] = [
        (
            [0, 1, 2, 3],
            [-11368131.532341419, 8705387.200640356, -5394671.791956129],
        ),
        (
            [0, 1, 2, 4],
            [3471170.370679039, -2658122.139965033, 1647220.990582546],
        ),
        (
            [0, 1, 3, 4],
            [2163157.7579381578, -2046533.6971039306, 1850575.1557530416],
        ),
        (
            [0, 2, 3, 4],
            [2124519.312724006, -1398934.8451397014, 1230950.312371019],
        ),
        (
            [1, 2, 3, 4],
            [2134332.9753310033, -1563416.5317767262, 1388326.964618863],
        ),
    ];
    // Within 1.5e-14 of the centre's largest coordinate.
    let close = |c: &[f64], e: &[f64]| {
        let size = e.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        c.iter()
            .zip(e)
            .all(|(x, y)| (x - y).abs() <= 1.5e-14 * size)
    };
    let t = Triangulation3::new(&pts).unwrap();
    let vd = VoronoiDiagram::new(&t);
    assert!(vd.len() >= 2);
    for i in 0..vd.len() {
        let (_, e) = exact
            .iter()
            .find(|(f, _)| f.as_slice() == vd.forming_points(i))
            .expect("a tetrahedron of the five points");
        assert!(
            close(&vd.circumcenter(i), e),
            "{:?}: {:?}",
            vd.forming_points(i),
            vd.circumcenter(i)
        );
    }
    // The bounded region of point 0 (inside the hull) has these centres as its corners.
    let shared = t.voronoi_faces_shared();
    assert!(!shared.is_empty());
    for v in &shared.vertices {
        assert!(exact.iter().any(|(_, e)| close(v, e)), "{v:?}");
    }
    // 2D: two points 5e-13 apart and one at (22000, 38000); exact centre (4.5e-13, 25368.42…).
    let pts = [
        [7e-13, 3.0000000000000003e-13],
        [2e-13, 3.0000000000000003e-13],
        [22000.0, 38000.0],
    ];
    let t = Triangulation2::new(&pts).unwrap();
    let c = VoronoiDiagram::new(&t).circumcenter(0);
    assert!(close(&c, &[4.5e-13, 25368.42105263158]), "{c:?}");
    // Clusters in [0, 1e-12] next to points in [0, 1e6]: 500 + 500 in 2D, 50 + 250 in 3D.
    let mut rng = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(32);
    let mut coordinate =
        |k: usize| rand::Rng::gen::<f64>(&mut rng) * if k % 2 == 0 { 1e-12 } else { 1e6 };
    let pts: Vec<[f64; 2]> = (0..1000)
        .map(|k| [coordinate(k / 500), coordinate(k / 500)])
        .collect();
    let t = Triangulation2::new(&pts).unwrap();
    assert_centres_equidistant(&VoronoiDiagram::new(&t), &pts);
    let (lo, hi) = enlarged_box(&pts);
    assert_regions_tile(&pts, lo, hi);
    let pts: Vec<[f64; 3]> = (0..300)
        .map(|k| {
            let s = usize::from(k >= 50);
            [coordinate(s), coordinate(s), coordinate(s)]
        })
        .collect();
    let t = Triangulation3::new(&pts).unwrap();
    assert_centres_equidistant(&VoronoiDiagram::new(&t), &pts);
}

#[test]
fn bounded_3d_regions_have_equidistant_faces() {
    let pts = uniform3(400, 23);
    let t = Triangulation3::new(&pts).unwrap();
    let faces = t.voronoi_faces();
    assert!(!faces.is_empty());
    let dist = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    for f in &faces {
        assert!(f.polygon.len() >= 3);
        for &c in &f.polygon {
            let (a, b) = (dist(c, pts[f.point]), dist(c, pts[f.neighbor]));
            assert!((a - b).abs() <= 1e-8 * a.max(1.0));
        }
    }
    // Each bounded region is closed: every face's neighbour owns the reverse face if bounded.
    let owners: std::collections::HashSet<usize> = faces.iter().map(|f| f.point).collect();
    let pairs: std::collections::HashSet<(usize, usize)> =
        faces.iter().map(|f| (f.point, f.neighbor)).collect();
    for f in &faces {
        if owners.contains(&f.neighbor) {
            assert!(pairs.contains(&(f.neighbor, f.point)));
        }
    }
}

#[test]
fn shared_3d_faces_store_each_circumcentre_once() {
    let pts = uniform3(3000, 5);
    let t = Triangulation3::new(&pts).unwrap();
    let shared = t.voronoi_faces_shared();
    assert!(!shared.is_empty());
    // One vertex per tetrahedron at most, and each used: the faces index them all.
    assert!(shared.vertices.len() <= t.num_cells());
    let mut used = vec![false; shared.vertices.len()];
    for k in 0..shared.len() {
        assert!(shared.face(k).len() >= 3);
        for &i in shared.face(k) {
            used[i as usize] = true;
        }
    }
    assert!(used.iter().all(|&u| u));
    assert_eq!(shared.ends.last(), Some(&shared.corners.len()));
    // The per-face form is the same diagram.
    let faces = t.voronoi_faces();
    assert_eq!(faces.len(), shared.len());
    for (k, f) in faces.iter().enumerate() {
        assert_eq!([f.point, f.neighbor], shared.sides[k]);
        let corners: Vec<[f64; 3]> = shared
            .face(k)
            .iter()
            .map(|&i| shared.vertices[i as usize])
            .collect();
        assert_eq!(f.polygon, corners);
    }
    // The same whatever the number of threads.
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| t.voronoi_faces_shared());
    assert_eq!(one, shared);
}

#[test]
fn nearly_collinear_and_coplanar_points_have_finite_circumcentres() {
    // (0.1 i, 0.3 i) rounded: collinear in exact arithmetic only by rounding, so every
    // triangle is a sliver whose floating-point determinant can come out 0 (a NaN centre).
    let pts: Vec<[f64; 2]> = (0..100)
        .map(|i| [0.1 * f64::from(i), 0.3 * f64::from(i)])
        .collect();
    let t = Triangulation2::new(&pts).unwrap();
    let vd = VoronoiDiagram::new(&t);
    assert!(!vd.is_empty());
    for i in 0..vd.len() {
        let c = vd.circumcenter(i);
        assert!(c.iter().all(|x| x.is_finite()), "{i}: {c:?}");
        // Far away, but equidistant from its three points (the denominator's sign is right).
        let d: Vec<f64> = vd
            .forming_points(i)
            .iter()
            .map(|&k| (pts[k as usize][0] - c[0]).hypot(pts[k as usize][1] - c[1]))
            .collect();
        assert!(
            d.iter().all(|r| (r - d[0]).abs() <= 1e-6 * d[0]),
            "{i}: {d:?}"
        );
    }
    // The same in 3D: a 30 × 30 grid on the plane z = 0.3 y, rounded off it.
    let pts: Vec<[f64; 3]> = (0..900)
        .map(|k| {
            let (i, j) = (f64::from(k / 30), f64::from(k % 30));
            [0.1 * i, 0.1 * j, 0.03 * j]
        })
        .collect();
    let t = Triangulation3::new(&pts).expect("not coplanar in floating point");
    let vd = VoronoiDiagram::new(&t);
    for i in 0..vd.len() {
        let c = vd.circumcenter(i);
        assert!(c.iter().all(|x| x.is_finite()), "{i}: {c:?}");
    }
}

#[test]
fn far_from_unit_magnitudes_have_finite_regions_and_centres() {
    // The squares of edges near 1e±160 overflow or vanish in f64; the centres and the rays of
    // unbounded regions are computed so that neither happens.
    for s in [1.0, 1e-300, 1e-160, 1e160, 1e300] {
        let t = Triangulation2::new(&[[0.0, 0.0], [s, 0.0], [0.0, s]]).unwrap();
        let vd = VoronoiDiagram::new(&t);
        assert_eq!(vd.circumcenter(0), [0.5 * s, 0.5 * s], "{s}");
        let (lo, hi) = ([-0.1 * s, -0.1 * s], [1.1 * s, 1.1 * s]);
        let cells = t.voronoi_cells(lo, hi);
        let mut total = 0.0;
        for cell in &cells {
            let poly = &cell.polygon;
            assert!(
                poly.iter().flatten().all(|x| x.is_finite()),
                "{s}: {poly:?}"
            );
            // The area in units of s² (so that it neither overflows nor vanishes).
            total += (0..poly.len())
                .map(|k| {
                    let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
                    (p[0] / s) * (q[1] / s) - (p[1] / s) * (q[0] / s)
                })
                .sum::<f64>()
                / 2.0;
        }
        assert!(
            (total - 1.44).abs() < 1e-12,
            "{s}: the regions cover {total}"
        );
        let t =
            Triangulation3::new(&[[0.0, 0.0, 0.0], [s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]])
                .unwrap();
        let vd = VoronoiDiagram::new(&t);
        let c = vd.circumcenter(0);
        assert!(c.iter().all(|x| (x / s - 0.5).abs() < 1e-12), "{s}: {c:?}");
    }
}

/// A constructed point's bits, to compare corners exactly.
fn bits<const N: usize>(p: [f64; N]) -> [u64; N] {
    p.map(f64::to_bits)
}

#[test]
fn lattice_regions_list_each_corner_once() {
    // A 6 × 6 grid: the two triangles of each unit square have one circumcentre, which 34 of
    // the 36 regions listed twice in a row (all but the two grid corners no diagonal reaches).
    // Each region is the unit square around its point, its four corners once each, and the
    // CLI's box (10% larger than the grid's) clips none.
    let pts = grid2(6);
    let t = Triangulation2::new(&pts).unwrap();
    let (lo, hi) = enlarged_box(&pts);
    assert_eq!((lo, hi), ([-0.5, -0.5], [5.5, 5.5]));
    let cells = t.voronoi_cells(lo, hi);
    assert_eq!(cells.len(), 36);
    for cell in &cells {
        let [x, y] = pts[cell.point];
        let mut corners = cell.polygon.clone();
        corners.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(
            corners,
            [
                [x - 0.5, y - 0.5],
                [x - 0.5, y + 0.5],
                [x + 0.5, y - 0.5],
                [x + 0.5, y + 0.5]
            ],
            "region of {:?}: {:?}",
            pts[cell.point],
            cell.polygon
        );
    }
    // Counter-clockwise, each containing its point, areas adding up to the box's (36); and so
    // in a box that cuts the outer regions.
    assert_regions_tile(&pts, lo, hi);
    assert_regions_tile(&pts, [-0.3, -0.7], [5.2, 5.9]);
}

#[test]
fn lattice_3d_regions_are_unit_cubes() {
    // A 4 × 4 × 4 grid: the 2 × 2 × 2 points inside the hull have for regions the unit cubes
    // around them, 6 square faces each (48), whose corners are the centres of the lattice's
    // 27 cubes. The tetrahedra also have the diagonals of the squares (whose rings have two
    // centres, of the two cubes sharing the square) and of the cubes (one centre): 64 of the
    // 112 faces had no area.
    let pts = grid3(4);
    let t = Triangulation3::new(&pts).unwrap();
    let shared = t.voronoi_faces_shared();
    assert_eq!(shared.len(), 48);
    let mut centres: Vec<[u64; 3]> = shared.vertices.iter().map(|&v| bits(v)).collect();
    centres.sort_unstable();
    centres.dedup();
    assert_eq!(centres.len(), 27);
    assert_eq!(shared.vertices.len(), 27);
    assert!(shared
        .vertices
        .iter()
        .flatten()
        .all(|x| [0.5, 1.5, 2.5].contains(x)));
    let mut faces_of: HashMap<usize, Vec<usize>> = HashMap::new();
    for k in 0..shared.len() {
        let [p, q] = shared.sides[k];
        let (a, b) = (pts[p], pts[q]);
        // The point on the other side is one step along an axis, the face the square between.
        let distance: f64 = (0..3).map(|i| (a[i] - b[i]).abs()).sum();
        assert_eq!(distance, 1.0, "{a:?} {b:?}");
        let face = shared.face(k);
        assert_eq!(face.len(), 4, "{a:?} {b:?}: {face:?}");
        for (j, &c) in face.iter().enumerate() {
            let c = shared.vertices[c as usize];
            let next = shared.vertices[face[(j + 1) % 4] as usize];
            assert!(
                (0..3).all(|i| (c[i] - a[i]).abs() == 0.5 && (c[i] - b[i]).abs() <= 0.5),
                "{a:?} {b:?}: corner {c:?}"
            );
            // Consecutive corners are the ends of a side of the square.
            assert_eq!((0..3).filter(|&i| c[i] != next[i]).count(), 1);
        }
        faces_of.entry(p).or_default().push(q);
    }
    assert_eq!(faces_of.len(), 8);
    for (p, neighbors) in &faces_of {
        assert!(
            pts[*p].iter().all(|&x| x == 1.0 || x == 2.0),
            "{:?}",
            pts[*p]
        );
        assert_eq!(neighbors.len(), 6, "{:?}", pts[*p]);
    }
}

#[test]
fn non_degenerate_regions_keep_every_circumcentre() {
    // Random points have no four co-circular (five co-spherical): nothing is merged, a region
    // has one corner per cell around its point and every edge at a point inside the hull has
    // a face, whose corners are the centres of the tetrahedra around the edge.
    let pts = uniform2(300, 24);
    let t = Triangulation2::new(&pts).unwrap();
    let vd = VoronoiDiagram::new(&t);
    let centre: HashMap<CellId, [u64; 2]> = (0..vd.len())
        .map(|i| (vd.cell(i), bits(vd.circumcenter(i))))
        .collect();
    // A box around every circumcentre: the regions of points inside the hull are not clipped.
    let (mut lo, mut hi) = enlarged_box(&pts);
    for i in 0..vd.len() {
        let c = vd.circumcenter(i);
        for k in 0..2 {
            lo[k] = lo[k].min(c[k] - 1.0);
            hi[k] = hi[k].max(c[k] + 1.0);
        }
    }
    let mut inside = 0;
    for cell in t.voronoi_cells(lo, hi) {
        let star = t.cells_around_vertex(t.vertex_of_input(cell.point));
        if star.iter().any(|&c| t.is_ghost(c)) {
            continue;
        }
        let mut expected: Vec<[u64; 2]> = star.iter().map(|c| centre[c]).collect();
        let mut corners: Vec<[u64; 2]> = cell.polygon.iter().map(|&p| bits(p)).collect();
        expected.sort_unstable();
        corners.sort_unstable();
        assert_eq!(corners, expected, "region of {}", cell.point);
        inside += 1;
    }
    assert!(inside > 250, "{inside} points inside the hull");

    let pts = uniform3(500, 25);
    let t = Triangulation3::new(&pts).unwrap();
    let vd = VoronoiDiagram::new(&t);
    let centre: HashMap<CellId, [u64; 3]> = (0..vd.len())
        .map(|i| (vd.cell(i), bits(vd.circumcenter(i))))
        .collect();
    let mut expected: HashMap<[usize; 2], Vec<[u64; 3]>> = HashMap::new();
    for v in (0..t.num_vertices()).map(|v| VertexId(v as u32)) {
        let star = t.cells_around_vertex(v);
        if star.iter().any(|&c| t.is_ghost(c)) {
            continue;
        }
        for w in star.iter().flat_map(|&c| t.cell(c).to_vec()) {
            if w != v {
                let mut ring: Vec<[u64; 3]> =
                    t.cells_around(&[v, w]).iter().map(|c| centre[c]).collect();
                ring.sort_unstable();
                expected.insert([t.input_index(v), t.input_index(w)], ring);
            }
        }
    }
    let faces = t.voronoi_faces();
    let got: HashMap<[usize; 2], Vec<[u64; 3]>> = faces
        .iter()
        .map(|f| {
            let mut corners: Vec<[u64; 3]> = f.polygon.iter().map(|&p| bits(p)).collect();
            corners.sort_unstable();
            ([f.point, f.neighbor], corners)
        })
        .collect();
    assert_eq!(got.len(), faces.len());
    assert!(got.len() > 1000, "{} faces", got.len());
    assert!(
        got == expected,
        "the faces are not the rings of centres around the edges"
    );
}
