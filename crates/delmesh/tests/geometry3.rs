//! The 3D demo surfaces: each is closed (every edge used once in each direction), has no
//! duplicate points, no degenerate triangles (exact predicates) and no self-intersections
//! (exact predicates), its closed surfaces have outward normals (positive divergence-theorem
//! volume) and enclose the analytic volume up to the discretisation error, planar box sides
//! are strictly Delaunay in their plane (and so appear in the Delaunay tetrahedralization of
//! the surface points), the double ellipsoid's vertices lie on its analytic surface, and the
//! counts, shapes and missing faces are snapshotted.

use std::collections::HashMap;
use std::f64::consts::PI;

use delmesh::geometry3::{
    box_surface, cube_with_cubic_hole, double_ellipsoid, icosphere, sphere_in_box, two_bodies,
    DoubleEllipsoid, Surface3, DOUBLE_ELLIPSOID_N,
};
use delmesh::recovery::Plc3;
use delmesh::Triangulation3;
use delmesh_predicates::{incircle, orient2d, orient3d, Sign};

type P = [f64; 3];

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: P, b: P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The triangles of each closed surface (connected component through shared points), in
/// order of first appearance.
fn components(plc: &Plc3) -> Vec<Vec<usize>> {
    let n = plc.points.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for t in &plc.triangles {
        for k in 1..3 {
            let (a, b) = (
                find(&mut parent, t.v[0] as usize),
                find(&mut parent, t.v[k] as usize),
            );
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut order: HashMap<usize, usize> = HashMap::new();
    let mut out: Vec<Vec<usize>> = Vec::new();
    for (k, t) in plc.triangles.iter().enumerate() {
        let root = find(&mut parent, t.v[0] as usize);
        let next = out.len();
        let c = *order.entry(root).or_insert(next);
        if c == out.len() {
            out.push(Vec::new());
        }
        out[c].push(k);
    }
    out
}

/// Every directed edge exactly once and its reverse exactly once; every point used.
fn assert_closed(name: &str, plc: &Plc3) {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for t in &plc.triangles {
        for k in 0..3 {
            *directed.entry((t.v[k], t.v[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &count) in &directed {
        assert_eq!(count, 1, "{name}: edge {a}→{b} used {count} times");
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "{name}: edge {a}→{b} has no reverse"
        );
    }
    let mut used = vec![false; plc.points.len()];
    for t in &plc.triangles {
        for &v in &t.v {
            used[v as usize] = true;
        }
    }
    assert!(used.iter().all(|&u| u), "{name}: unused points");
}

fn assert_no_duplicates(name: &str, plc: &Plc3) {
    let mut pts = plc.points.clone();
    pts.sort_by(|a, b| a.partial_cmp(b).unwrap());
    for w in pts.windows(2) {
        assert_ne!(w[0], w[1], "{name}: duplicate point");
    }
}

/// Exactly collinear in 3D iff collinear in all three coordinate-plane projections.
fn degenerate(a: P, b: P, c: P) -> bool {
    [(0, 1), (1, 2), (2, 0)]
        .iter()
        .all(|&(i, j)| orient2d([a[i], a[j]], [b[i], b[j]], [c[i], c[j]]) == Sign::Zero)
}

fn corners(plc: &Plc3, t: usize) -> [P; 3] {
    plc.triangles[t].v.map(|v| plc.points[v as usize])
}

fn volume(plc: &Plc3, tris: &[usize]) -> f64 {
    let o = corners(plc, tris[0])[0];
    tris.iter()
        .map(|&t| {
            let [a, b, c] = corners(plc, t);
            dot(sub(a, o), cross(sub(b, o), sub(c, o)))
        })
        .sum::<f64>()
        / 6.0
}

fn bbox(pts: impl IntoIterator<Item = P>) -> (P, P) {
    pts.into_iter().fold(
        ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        |(lo, hi), p| {
            (
                [0, 1, 2].map(|k| lo[k].min(p[k])),
                [0, 1, 2].map(|k| hi[k].max(p[k])),
            )
        },
    )
}

/// Whether segment `de` meets triangle `abc` (exact; coplanar segments are left out: only
/// box sides are coplanar, and they are checked to be Delaunay triangulations instead).
fn segment_meets_triangle(d: P, e: P, [a, b, c]: [P; 3]) -> bool {
    let (sd, se) = (orient3d(a, b, c, d), orient3d(a, b, c, e));
    if sd == se {
        return false; // same side, or both in the plane
    }
    let s = [
        orient3d(d, e, a, b),
        orient3d(d, e, b, c),
        orient3d(d, e, c, a),
    ];
    !(s.contains(&Sign::Positive) && s.contains(&Sign::Negative))
}

/// No two triangles of the surface `tris` meet except along shared edges and points.
fn assert_no_self_intersection(name: &str, plc: &Plc3, tris: &[usize]) {
    let (lo, hi) = bbox(tris.iter().flat_map(|&t| corners(plc, t)));
    let mean_edge = tris
        .iter()
        .map(|&t| {
            let [a, b, _] = corners(plc, t);
            dot(sub(b, a), sub(b, a)).sqrt()
        })
        .sum::<f64>()
        / tris.len() as f64;
    let dims = [0, 1, 2].map(|k| (((hi[k] - lo[k]) / (2.0 * mean_edge)).ceil() as usize).max(1));
    let cell = |p: P, k: usize| {
        (((p[k] - lo[k]) / (hi[k] - lo[k]) * dims[k] as f64) as usize).min(dims[k] - 1)
    };
    let mut grid: HashMap<[usize; 3], Vec<usize>> = HashMap::new();
    for &t in tris {
        let (tlo, thi) = bbox(corners(plc, t));
        for x in cell(tlo, 0)..=cell(thi, 0) {
            for y in cell(tlo, 1)..=cell(thi, 1) {
                for z in cell(tlo, 2)..=cell(thi, 2) {
                    grid.entry([x, y, z]).or_default().push(t);
                }
            }
        }
    }
    let mut pairs: Vec<(usize, usize)> = grid
        .values()
        .flat_map(|ts| {
            ts.iter()
                .enumerate()
                .flat_map(move |(i, &s)| ts[i + 1..].iter().map(move |&t| (s.min(t), s.max(t))))
        })
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    for (s, t) in pairs {
        let (vs, vt) = (plc.triangles[s].v, plc.triangles[t].v);
        let (ps, pt) = (corners(plc, s), corners(plc, t));
        let shared: Vec<usize> = (0..3).filter(|&i| vt.contains(&vs[i])).collect();
        let hit = match shared.len() {
            0 => (0..3).any(|i| {
                segment_meets_triangle(ps[i], ps[(i + 1) % 3], pt)
                    || segment_meets_triangle(pt[i], pt[(i + 1) % 3], ps)
            }),
            1 => {
                // Only the edges opposite the shared point can cross the other triangle.
                let i = shared[0];
                let j = (0..3).find(|&j| vt[j] == vs[i]).unwrap();
                segment_meets_triangle(ps[(i + 1) % 3], ps[(i + 2) % 3], pt)
                    || segment_meets_triangle(pt[(j + 1) % 3], pt[(j + 2) % 3], ps)
            }
            2 => {
                // Folded onto each other: coplanar with both far points on one side.
                let i = (0..3).find(|i| !shared.contains(i)).unwrap();
                let j = (0..3).find(|&j| !vs.contains(&vt[j])).unwrap();
                let (a, b) = (ps[shared[0]], ps[shared[1]]);
                orient3d(a, b, ps[i], pt[j]) == Sign::Zero
                    && dot(
                        cross(sub(b, a), sub(ps[i], a)),
                        cross(sub(b, a), sub(pt[j], a)),
                    ) > 0.0
            }
            _ => true, // the same triangle twice
        };
        assert!(!hit, "{name}: triangles {s} and {t} intersect");
    }
}

/// The smallest angle of a triangle, in degrees.
fn min_angle(p: [P; 3]) -> f64 {
    (0..3)
        .map(|k| {
            let (u, v) = (sub(p[(k + 1) % 3], p[k]), sub(p[(k + 2) % 3], p[k]));
            let c = dot(cross(u, v), cross(u, v)).sqrt();
            c.atan2(dot(u, v)).to_degrees()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Checks every property of a demo surface; `volumes` are the analytic volumes of its closed
/// surfaces in order, `tolerance` their largest relative error. Returns a summary line.
fn check(name: &str, plc: &Plc3, volumes: &[f64], tolerance: f64) -> String {
    assert_closed(name, plc);
    assert_no_duplicates(name, plc);
    for (k, t) in plc.triangles.iter().enumerate() {
        let [a, b, c] = t.v.map(|v| plc.points[v as usize]);
        assert!(!degenerate(a, b, c), "{name}: triangle {k} is degenerate");
    }
    let comps = components(plc);
    assert_eq!(comps.len(), volumes.len(), "{name}: closed surfaces");
    let mut line = format!(
        "{name}: {} points, {} triangles, {} facets",
        plc.points.len(),
        plc.triangles.len(),
        plc.triangles.iter().map(|t| t.facet).max().unwrap() + 1
    );
    let mut boxes = Vec::new();
    for (c, (tris, &exact)) in comps.iter().zip(volumes).enumerate() {
        let v = volume(plc, tris);
        assert!(
            v > 0.0,
            "{name}: surface {c} is not oriented outwards ({v})"
        );
        let rel = (v - exact) / exact;
        assert!(
            rel.abs() <= tolerance,
            "{name}: surface {c} encloses {v}, not {exact} (relative {rel:e})"
        );
        // Inscribed in convex pieces: never more than the analytic volume.
        assert!(v <= exact * (1.0 + 1e-12), "{name}: surface {c} too big");
        assert_no_self_intersection(name, plc, tris);
        let mut markers: Vec<i32> = tris.iter().map(|&t| plc.triangles[t].marker).collect();
        markers.sort_unstable();
        markers.dedup();
        let points: std::collections::BTreeSet<u32> =
            tris.iter().flat_map(|&t| plc.triangles[t].v).collect();
        let angle = tris
            .iter()
            .map(|&t| min_angle(corners(plc, t)))
            .fold(f64::INFINITY, f64::min);
        let mean = tris
            .iter()
            .map(|&t| min_angle(corners(plc, t)))
            .sum::<f64>()
            / tris.len() as f64;
        let error = if rel.abs() < 1e-12 {
            "exact".to_string()
        } else {
            format!("{:.2e}", rel.abs())
        };
        line += &format!(
            "\n  surface {c}: markers {markers:?}, {} points, {} triangles, volume error {error}, \
             min angle {angle:.1}°, mean of minima {mean:.1}°",
            points.len(),
            tris.len(),
        );
        boxes.push(bbox(points.iter().map(|&v| plc.points[v as usize])));
    }
    // Against the Delaunay tetrahedralization of the surface points: the far field's
    // triangles are all there (its sides are strictly Delaunay, on the hull); the bodies'
    // missing triangles and edges are counted (what boundary recovery would have to do).
    let tri = Triangulation3::new(&plc.points).unwrap();
    let v = |i: u32| tri.vertex_of_input(i as usize);
    let missing: Vec<usize> = comps
        .iter()
        .map(|tris| {
            tris.iter()
                .filter(|&&t| {
                    let [a, b, c] = plc.triangles[t].v;
                    !tri.has_triangle(v(a), v(b), v(c))
                })
                .count()
        })
        .collect();
    assert_eq!(missing[0], 0, "{name}: far-field triangles missing");
    let mut edges: Vec<(u32, u32)> = plc
        .triangles
        .iter()
        .flat_map(|t| {
            (0..3).map(move |k| (t.v[k].min(t.v[(k + 1) % 3]), t.v[k].max(t.v[(k + 1) % 3])))
        })
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let missing_edges = edges
        .iter()
        .filter(|&&(a, b)| !tri.has_edge(v(a), v(b)))
        .count();
    line += &format!(
        "\n  Delaunay tetrahedralization of the surface points: {} cells; missing triangles per \
         surface {missing:?}, missing edges {missing_edges} of {}",
        tri.num_cells(),
        edges.len()
    );
    // The first surface (the far field) contains the others, which are disjoint.
    for (i, b) in boxes.iter().enumerate().skip(1) {
        assert!(
            (0..3).all(|k| boxes[0].0[k] < b.0[k] && b.1[k] < boxes[0].1[k]),
            "{name}: surface {i} is not inside the far field"
        );
        for c in boxes.iter().skip(i + 1) {
            let nested = (0..3).all(|k| b.0[k] < c.0[k] && c.1[k] < b.1[k]);
            let apart = (0..3).any(|k| b.1[k] < c.0[k] || c.1[k] < b.0[k]);
            assert!(nested || apart, "{name}: bodies may touch");
        }
    }
    line
}

/// The volume of the Hermes body: the fuselage's exactly, plus the canopy's part outside it
/// integrated over `(x, y)` (midpoint rule) from the analytic z-intervals.
fn hermes_volume() -> f64 {
    let d = DoubleEllipsoid::HERMES;
    let fuselage = 2.0 / 3.0 * PI * d.half_length * d.half_span * (d.upper + d.lower);
    let c = d.canopy.unwrap();
    let (nx, ny) = (1600, 800);
    let (x0, dx) = (
        c.centre[0] - c.semi_axes[0],
        2.0 * c.semi_axes[0] / nx as f64,
    );
    let (y0, dy) = (-c.semi_axes[1], 2.0 * c.semi_axes[1] / ny as f64);
    let mut excess = 0.0;
    for i in 0..nx {
        let x = x0 + (i as f64 + 0.5) * dx;
        for j in 0..ny {
            let y = y0 + (j as f64 + 0.5) * dy;
            let u =
                1.0 - ((x - c.centre[0]) / c.semi_axes[0]).powi(2) - (y / c.semi_axes[1]).powi(2);
            if u <= 0.0 {
                continue;
            }
            let (clo, chi) = (
                c.centre[1] - c.semi_axes[2] * u.sqrt(),
                c.centre[1] + c.semi_axes[2] * u.sqrt(),
            );
            let w = 1.0 - (x / d.half_length).powi(2) - (y / d.half_span).powi(2);
            let (flo, fhi) = if w > 0.0 {
                (-d.lower * w.sqrt(), d.upper * w.sqrt())
            } else {
                (0.0, 0.0)
            };
            let overlap = (chi.min(fhi) - clo.max(flo)).max(0.0);
            excess += (chi - clo - overlap) * dx * dy;
        }
    }
    fuselage + excess
}

#[test]
fn demo_surfaces_are_closed_oriented_and_of_the_right_volume() {
    let sphere = 4.0 / 3.0 * PI;
    let text = [
        check(
            "double_ellipsoid",
            &double_ellipsoid(DOUBLE_ELLIPSOID_N),
            &[360.0, hermes_volume()],
            5e-3,
        ),
        check("sphere_in_box", &sphere_in_box(8), &[216.0, sphere], 1e-2),
        check(
            "cube_with_cubic_hole",
            &cube_with_cubic_hole(10),
            &[8.0, 0.512],
            1e-12,
        ),
        check(
            "two_bodies",
            &two_bodies(6),
            &[288.0, sphere * 0.125, sphere * 0.7 * 0.35 * 0.35],
            2e-2,
        ),
    ];
    insta::assert_snapshot!(text.join("\n"));
}

#[test]
fn the_double_ellipsoid_lies_on_its_analytic_surface_with_the_crease_on_edges() {
    let d = DoubleEllipsoid::HERMES;
    let plc = double_ellipsoid(DOUBLE_ELLIPSOID_N);
    let mut marker_of_point: HashMap<u32, Vec<i32>> = HashMap::new();
    for t in plc.triangles.iter().filter(|t| t.marker != 1) {
        for &v in &t.v {
            marker_of_point.entry(v).or_default().push(t.marker);
            let p = plc.points[v as usize];
            let (f, c) = (d.fuselage_level(p), d.canopy_level(p));
            match t.marker {
                2 => assert!(
                    f.abs() < 1e-12 && c > -1e-12,
                    "fuselage point {p:?}: {f} {c}"
                ),
                3 => assert!(c.abs() < 1e-12 && f > -1e-12, "canopy point {p:?}: {f} {c}"),
                m => panic!("unexpected marker {m}"),
            }
        }
    }
    // The crease: points used by both parts lie on both surfaces, and form a closed loop.
    let crease: Vec<u32> = marker_of_point
        .iter()
        .filter(|(_, m)| m.contains(&2) && m.contains(&3))
        .map(|(&v, _)| v)
        .collect();
    assert!(crease.len() > 20, "{} crease points", crease.len());
    // Body symmetric about y = 0 up to rounding, and within its bounding box.
    let (lo, hi) = bbox(crease.iter().map(|&v| plc.points[v as usize]));
    assert!(lo[1] < 0.0 && hi[1] > 0.0 && lo[2] > 0.0);
    // Deterministic.
    assert_eq!(plc, double_ellipsoid(DOUBLE_ELLIPSOID_N));
    // The volume converges to the analytic one at second order in the spacing.
    let exact = hermes_volume();
    let error = |n: usize| {
        let s = d.surface(d.girth() / n as f64, [2, 3]);
        (exact - s.signed_volume()) / exact
    };
    let (coarse, fine) = (error(DOUBLE_ELLIPSOID_N / 2), error(DOUBLE_ELLIPSOID_N));
    assert!(
        fine > 0.0 && (3.0..5.5).contains(&(coarse / fine)),
        "{coarse:e} {fine:e}"
    );
}

#[test]
fn box_sides_are_strictly_delaunay_in_their_plane() {
    for (lo, hi, divisions) in [
        ([-5.0, -3.0, -3.0], [5.0, 3.0, 3.0], [13, 8, 7]),
        ([0.0; 3], [1.0; 3], [2; 3]),
        ([-0.4; 3], [0.4; 3], [6, 4, 10]),
    ] {
        let s: Surface3 = box_surface(lo, hi, divisions, 7);
        let exact: f64 = (0..3).map(|k| hi[k] - lo[k]).product();
        assert!((s.signed_volume() - exact).abs() < 1e-12 * exact);
        // Divisions are rounded up to even numbers: points per side edge.
        for (k, d) in divisions.iter().enumerate() {
            let n = d.div_ceil(2) * 2;
            let on_edge = s
                .points
                .iter()
                .filter(|p| (0..3).all(|j| j == k || p[j] == lo[j]))
                .count();
            assert_eq!(on_edge, n + 1, "axis {k}");
        }
        for facet in 0..6u32 {
            let (q, side) = ((facet / 2) as usize, facet % 2);
            let (u, v) = ((q + 1) % 3, (q + 2) % 3);
            let tris: Vec<[u32; 3]> = s
                .triangles
                .iter()
                .filter(|t| t.facet == facet)
                .map(|t| t.v)
                .collect();
            let plane = if side == 0 { lo[q] } else { hi[q] };
            let flat = |i: u32| {
                let p = s.points[i as usize];
                assert_eq!(p[q], plane, "a side's points are in its plane exactly");
                [p[u], p[v]]
            };
            // Counter-clockwise in (u, v) is outward on the upper side.
            let ccw = |t: [u32; 3]| {
                if side == 1 {
                    t
                } else {
                    [t[0], t[2], t[1]]
                }
            };
            let mut opposite: HashMap<(u32, u32), u32> = HashMap::new();
            for &t in &tris {
                let t = ccw(t);
                assert_eq!(orient2d(flat(t[0]), flat(t[1]), flat(t[2])), Sign::Positive);
                for k in 0..3 {
                    opposite.insert((t[k], t[(k + 1) % 3]), t[(k + 2) % 3]);
                }
            }
            for (&(a, b), &c) in &opposite {
                if let Some(&d) = opposite.get(&(b, a)) {
                    assert_eq!(
                        incircle(flat(a), flat(b), flat(c), flat(d)),
                        Sign::Negative,
                        "facet {facet}: edge {a}-{b} is not strictly Delaunay"
                    );
                }
            }
        }
    }
}

#[test]
fn icosphere_counts_and_convergence() {
    let mut last = f64::INFINITY;
    for f in 1..=6 {
        let s = icosphere([0.5, -1.0, 2.0], 2.0, f, 1);
        assert_eq!(s.points.len(), 10 * f * f + 2);
        assert_eq!(s.triangles.len(), 20 * f * f);
        for p in &s.points {
            let r = dot(sub(*p, [0.5, -1.0, 2.0]), sub(*p, [0.5, -1.0, 2.0])).sqrt();
            assert!((r - 2.0).abs() < 1e-12);
        }
        let error = 4.0 / 3.0 * PI * 8.0 - s.signed_volume();
        assert!(error > 0.0 && error < last, "frequency {f}: {error}");
        last = error;
    }
}

#[test]
fn the_checks_catch_broken_surfaces() {
    let fails = |f: &(dyn Fn() + std::panic::RefUnwindSafe)| std::panic::catch_unwind(f).is_err();
    let good = sphere_in_box(3);
    let sphere: Vec<usize> = components(&good)[1].clone();
    assert!(!fails(&|| assert_no_self_intersection(
        "good", &good, &sphere
    )));
    // A sphere point pushed through to the other side: its triangles cross the far side.
    let mut pierced = good.clone();
    let v = pierced.triangles[sphere[0]].v[0] as usize;
    pierced.points[v] = pierced.points[v].map(|c| -1.5 * c);
    assert!(fails(&|| assert_no_self_intersection(
        "pierced", &pierced, &sphere
    )));
    // One triangle turned over.
    let mut flipped = good.clone();
    flipped.triangles[sphere[0]].v.swap(0, 1);
    assert!(fails(&|| assert_closed("flipped", &flipped)));
}
