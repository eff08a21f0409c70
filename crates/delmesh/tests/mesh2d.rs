//! The 2D pipeline end to end on the paper's demos: every output mesh has every input segment,
//! nothing outside the domain, the domain's exact area, positive orientation, the constrained
//! Delaunay property (checked exactly), and smoothing never inverted anything.

use delmesh::demos::mesh_demo_setup;
use delmesh::mesh2d::{mesh_plc, MeshOptions2, MeshRun2};
use delmesh::recovery::{Plc2, RecoveryMethod, RegionSeed};
use delmesh::smoothing::Smoother;
use delmesh_predicates::{orient2d, Sign};
use std::collections::HashMap;

/// The domain's area from its segments: loops are oriented (outer counter-clockwise, holes
/// clockwise), so the shoelace sum over all segments is the area.
fn plc_area(plc: &Plc2) -> f64 {
    plc.segments
        .iter()
        .map(|s| {
            let (p, q) = (plc.points[s.a as usize], plc.points[s.b as usize]);
            p[0] * q[1] - p[1] * q[0]
        })
        .sum::<f64>()
        / 2.0
}

fn check_run(run: &MeshRun2, plc: &Plc2, name: &str) {
    check_run_of_area(run, plc, name, plc_area(plc));
}

/// [`check_run`] for a domain of the given area (a domain with walls, whose loops overlap).
fn check_run_of_area(run: &MeshRun2, plc: &Plc2, name: &str, exact: f64) {
    run.mesh
        .cdt
        .validate()
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let a = &run.arrays;
    // Orientation and area.
    let mut area = 0.0;
    for t in &a.triangles {
        let p = t.map(|v| a.coords[v as usize]);
        assert_eq!(orient2d(p[0], p[1], p[2]), Sign::Positive, "{name}");
        area += 0.5
            * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
    }
    assert!(
        (area - exact).abs() <= 1e-9 * exact.abs(),
        "{name}: area {area} vs {exact}"
    );
    // Every input segment is covered by boundary edges that are edges of the mesh: the
    // pieces of each segment join its two ends.
    let mut edges: HashMap<(u32, u32), ()> = HashMap::new();
    for t in &a.triangles {
        for k in 0..3 {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            edges.insert((u.min(v), u.max(v)), ());
        }
    }
    // Directed edges of the triangles (counter-clockwise): a boundary edge with a triangle on
    // one side only has it on its left (the domain on the left, the outward normal (dy, −dx)).
    let mut directed: HashMap<(u32, u32), ()> = HashMap::new();
    for t in &a.triangles {
        for k in 0..3 {
            directed.insert((t[k], t[(k + 1) % 3]), ());
        }
    }
    for e in &a.edges {
        assert!(
            edges.contains_key(&(e[0].min(e[1]), e[0].max(e[1]))),
            "{name}: boundary edge {e:?} is not an edge of a triangle"
        );
        let (left, right) = (
            directed.contains_key(&(e[0], e[1])),
            directed.contains_key(&(e[1], e[0])),
        );
        assert!(
            left || !right,
            "{name}: boundary edge {e:?} has the domain on its right"
        );
    }
    let mut length_of: HashMap<u32, f64> = HashMap::new();
    for e in &run.mesh.edges {
        let t = run.mesh.cdt.triangulation();
        let (p, q) = (t.vertex(e.a), t.vertex(e.b));
        *length_of.entry(e.segment).or_default() += (p[0] - q[0]).hypot(p[1] - q[1]);
    }
    for (k, s) in plc.segments.iter().enumerate() {
        let (p, q) = (plc.points[s.a as usize], plc.points[s.b as usize]);
        let len = (p[0] - q[0]).hypot(p[1] - q[1]);
        let got = length_of.get(&(k as u32)).copied().unwrap_or(0.0);
        assert!(
            (got - len).abs() <= 1e-9 * len,
            "{name}: segment {k} covered {got} of {len}"
        );
    }
}

#[test]
fn every_mesh_demo_passes_the_checks() {
    for name in [
        "figure8",
        "figure7",
        "figure10a",
        "figure10b",
        "figure12",
        "figure13",
    ] {
        let (plc, options) = mesh_demo_setup(name).unwrap();
        let run = mesh_plc(&plc, &options).unwrap();
        check_run(&run, &plc, name);
        assert!(run.arrays.triangles.len() > 10, "{name}");
    }
}

#[test]
fn all_recovery_methods_with_and_without_smoothing() {
    let (plc, _) = mesh_demo_setup("figure10b").unwrap();
    for recovery in [
        RecoveryMethod::Stitch,
        RecoveryMethod::APriori,
        RecoveryMethod::Constrained,
    ] {
        for smoothing in [None, Some(Smoother::new())] {
            let options = MeshOptions2 {
                recovery,
                smoothing,
                ..MeshOptions2::default()
            };
            let run = mesh_plc(&plc, &options).unwrap();
            check_run(&run, &plc, &format!("{recovery:?}"));
        }
    }
}

/// A closed polygon through `points`, appended to `plc` (an index of an earlier point where it
/// passes through it).
fn polygon(plc: &mut Plc2, points: &[[f64; 2]]) {
    let ids: Vec<u32> = points
        .iter()
        .map(|p| match plc.points.iter().position(|q| q == p) {
            Some(i) => i as u32,
            None => {
                plc.points.push(*p);
                plc.points.len() as u32 - 1
            }
        })
        .collect();
    for (k, &a) in ids.iter().enumerate() {
        let b = ids[(k + 1) % ids.len()];
        plc.segments
            .push(delmesh::recovery::Segment { a, b, marker: 1 });
    }
}

#[test]
fn boundary_edges_bound_elements_with_the_domain_on_their_left() {
    // A square with a notch cut out by a hole seed: the square's edge under the notch lies
    // between the hole and the outside, and bounds nothing (it was written, with its marker,
    // as a boundary edge of no triangle). A second hole given counter-clockwise: its edges
    // are written clockwise, with the domain on their left (they kept the input direction).
    let mut plc = Plc2::default();
    polygon(
        &mut plc,
        &[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]],
    );
    plc.points.push([1.5, 0.5]);
    for (a, b) in [(2, 5), (5, 1)] {
        plc.segments
            .push(delmesh::recovery::Segment { a, b, marker: 2 });
    }
    polygon(&mut plc, &[[0.5, 1.0], [1.5, 1.0], [1.0, 1.5]]);
    plc.holes = vec![[1.5, 0.2], [1.0, 1.2]];
    for smoothing in [None, Some(Smoother::new())] {
        let options = MeshOptions2 {
            smoothing,
            ..MeshOptions2::default()
        };
        let run = mesh_plc(&plc, &options).unwrap();
        // The domain: 4 less the two triangles of area 1/4.
        check_run_of_area(&run, &plc, "notch", 3.5);
        // The boundary is 2 + 2 + 2 + 1 below the notch, the notch's 2 sides and the hole's 3.
        let a = &run.arrays;
        let length: f64 = a
            .edges
            .iter()
            .map(|e| {
                let (p, q) = (a.coords[e[0] as usize], a.coords[e[1] as usize]);
                (p[0] - q[0]).hypot(p[1] - q[1])
            })
            .sum();
        let expected = 7.0 + 2.0 * 0.5f64.hypot(0.5) + 1.0 + 2.0 * 0.5f64.hypot(0.5);
        assert!((length - expected).abs() < 1e-12, "{length} vs {expected}");
    }
}

#[test]
fn regions_walled_in_twice_follow_the_nesting_of_loops() {
    // Two squares [0,2]² and [1,3]² cut at their crossings, as a CAD "fragment" writes them:
    // the overlap [1,2]² is two boundaries from outside, so a hole by nesting (area 6), as a
    // hole touching the boundary at two vertices must be; a region seed keeps it (area 7).
    let mut plc = Plc2::default();
    polygon(
        &mut plc,
        &[[0., 0.], [2., 0.], [2., 1.], [2., 2.], [1., 2.], [0., 2.]],
    );
    polygon(
        &mut plc,
        &[[1., 1.], [2., 1.], [3., 1.], [3., 3.], [1., 3.], [1., 2.]],
    );
    let run = mesh_plc(&plc, &MeshOptions2::default()).unwrap();
    check_run_of_area(&run, &plc, "fragment", 6.0);
    plc.regions.push(delmesh::recovery::RegionSeed {
        point: [1.5, 1.5],
        attribute: 2.0,
        max_area: None,
    });
    for recovery in [RecoveryMethod::Stitch, RecoveryMethod::Constrained] {
        let options = MeshOptions2 {
            recovery,
            ..MeshOptions2::default()
        };
        let run = mesh_plc(&plc, &options).unwrap();
        check_run_of_area(&run, &plc, &format!("seeded {recovery:?}"), 7.0);
    }
    // A hole spanning a channel, touching its walls at two vertices, and one touching the
    // boundary at one vertex.
    let mut plc = Plc2::default();
    polygon(
        &mut plc,
        &[[0., 0.], [2., 0.], [4., 0.], [4., 2.], [2., 2.], [0., 2.]],
    );
    polygon(&mut plc, &[[2., 0.], [1., 1.], [2., 2.], [3., 1.]]);
    let run = mesh_plc(&plc, &MeshOptions2::default()).unwrap();
    check_run_of_area(&run, &plc, "spanning hole", 6.0);
    let mut plc = Plc2::default();
    polygon(
        &mut plc,
        &[[0., 0.], [2., 0.], [4., 0.], [4., 4.], [0., 4.]],
    );
    polygon(&mut plc, &[[2., 0.], [1., 1.], [2., 2.], [3., 1.]]);
    let run = mesh_plc(&plc, &MeshOptions2::default()).unwrap();
    check_run_of_area(&run, &plc, "touching hole", 14.0);
}

#[test]
fn tiny_holes_grade_out_instead_of_filling_the_domain() {
    // Three square holes 1e-5 across in a unit square: every element whose nodes lie on the
    // holes took their spacing however large it was, and generation filled the square at
    // 1e-5 until memory ran out. With the grading limit: about 40,000 points (release).
    let mut plc = Plc2::default();
    polygon(&mut plc, &[[0., 0.], [1., 0.], [1., 1.], [0., 1.]]);
    for c in [[0.25, 0.25], [0.75, 0.25], [0.5, 0.75]] {
        let h = 1e-5;
        let [x, y] = c;
        polygon(&mut plc, &[[x, y], [x, y + h], [x + h, y + h], [x + h, y]]);
        plc.holes.push([x + h / 2.0, y + h / 2.0]);
    }
    let run = mesh_plc(&plc, &MeshOptions2::default()).unwrap();
    check_run(&run, &plc, "tiny holes");
    let n = run.arrays.coords.len();
    assert!(n < 100_000, "{n} points");
    // The limit is a setting: below 1 is an error.
    let options = MeshOptions2 {
        generation: Some(delmesh::point_gen::PointGeneration {
            grading_limit: 0.5,
            ..Default::default()
        }),
        ..MeshOptions2::default()
    };
    let err = mesh_plc(&plc, &options).unwrap_err().to_string();
    assert!(err.contains("grading limit"), "{err}");
}

/// A closed loop of `k` points per side around the square `[lo, hi]²`, counter-clockwise or
/// clockwise, appended to `plc`.
fn square_loop(plc: &mut Plc2, lo: f64, hi: f64, k: usize, clockwise: bool) {
    let first = plc.points.len() as u32;
    let w = hi - lo;
    for side in 0..4 {
        for i in 0..k {
            let t = lo + w * i as f64 / k as f64;
            let u = hi + lo - t;
            plc.points.push(match side {
                0 => [t, lo],
                1 => [hi, t],
                2 => [u, hi],
                _ => [lo, u],
            });
        }
    }
    let n = 4 * k as u32;
    for i in 0..n {
        let (a, b) = (first + i, first + (i + 1) % n);
        let (a, b) = if clockwise { (b, a) } else { (a, b) };
        plc.segments
            .push(delmesh::recovery::Segment { a, b, marker: 1 });
    }
}

#[test]
fn a_mesh_large_enough_to_be_renumbered_passes_the_checks() {
    // About 100,000 triangles: generation renumbers the mesh along a space-filling curve
    // (from 65,536 elements on), so this checks the pipeline across renumberings.
    let mut plc = Plc2::default();
    square_loop(&mut plc, 0.0, 1.0, 320, false);
    square_loop(&mut plc, 0.4, 0.6, 64, true);
    plc.holes.push([0.5, 0.5]);
    let run = mesh_plc(&plc, &MeshOptions2::default()).unwrap();
    check_run(&run, &plc, "square with a hole");
    let t = run.mesh.cdt.triangulation();
    assert!(t.num_cells() > 80_000, "{} triangles", t.num_cells());
    // Renumbered: the vertices of most triangles are near each other in the numbering (in
    // generation order, 94% of the vertex pairs of the 10^6-triangle square were 2048 apart).
    let near = t
        .cells()
        .filter(|&c| {
            let v = t.cell(c);
            (v[0].index() as i64 - v[1].index() as i64).unsigned_abs() < 2048
        })
        .count();
    assert!(near * 2 > t.num_cells(), "{near} of {}", t.num_cells());
}

#[test]
fn the_aerofoil_quality_target() {
    // The target: minimum angle at least 25° after generation and smoothing, away from
    // the boundary's own small angles (the trailing edges): measured on elements with no
    // vertex on the boundary.
    let (plc, options) = mesh_demo_setup("figure10b").unwrap();
    let run = mesh_plc(&plc, &options).unwrap();
    let a = &run.arrays;
    let mut worst = 180.0f64;
    for t in &a.triangles {
        if t.iter().any(|&v| a.on_boundary[v as usize]) {
            continue;
        }
        let p = t.map(|v| a.coords[v as usize]);
        for k in 0..3 {
            let (o, u, w) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            let (ux, uy, wx, wy) = (u[0] - o[0], u[1] - o[1], w[0] - o[0], w[1] - o[1]);
            worst = worst.min(
                (ux * wy - uy * wx)
                    .abs()
                    .atan2(ux * wx + uy * wy)
                    .to_degrees(),
            );
        }
    }
    assert!(worst >= 25.0, "interior minimum angle {worst:.2}°");
}

#[test]
fn demo_counts_and_quality_snapshot() {
    let mut text = String::new();
    for name in ["figure8", "figure7", "figure12", "figure13"] {
        let (plc, options) = mesh_demo_setup(name).unwrap();
        let run = mesh_plc(&plc, &options).unwrap();
        let missing: Vec<usize> = run.recovery.passes.iter().map(|p| p.missing).collect();
        let generated: Vec<usize> = run
            .generation
            .as_ref()
            .map(|g| g.passes.iter().map(|p| p.accepted).collect())
            .unwrap_or_default();
        text.push_str(&format!(
            "{name}: {} points, {} triangles, {} boundary edges; missing per recovery pass {missing:?}; \
             points per generation pass {generated:?}; refinement {}; min angle {:.1}°, mean of minima {:.1}°\n",
            run.arrays.coords.len(),
            run.arrays.triangles.len(),
            run.arrays.edges.len(),
            run.refined,
            run.quality.min_angle,
            run.quality.mean_min_angle,
        ));
    }
    insta::assert_snapshot!(text);
}

#[test]
fn a_domain_far_from_unit_size_gives_the_unit_mesh_scaled() {
    // 2^±450 across, squared lengths and areas leave the range of f64: the pipeline meshes
    // the domain scaled by a power of two, so the mesh is exactly the unit one's, scaled.
    let mut unit = Plc2::default();
    square_loop(&mut unit, 0.0, 1.0, 24, false);
    square_loop(&mut unit, 0.375, 0.625, 6, true);
    unit.holes.push([0.5, 0.5]);
    let reference = mesh_plc(&unit, &MeshOptions2::default()).unwrap();
    check_run(&reference, &unit, "unit square with a hole");
    assert!(reference.generation.as_ref().unwrap().passes.len() > 1);
    for e in [-450, -300, 300, 450] {
        let f = 2f64.powi(e);
        let mut plc = unit.clone();
        for p in plc.points.iter_mut().chain(&mut plc.holes) {
            *p = p.map(|x| x * f);
        }
        let run = mesh_plc(&plc, &MeshOptions2::default()).unwrap();
        let scaled: Vec<[f64; 2]> = (reference.arrays.coords.iter())
            .map(|p| p.map(|x| x * f))
            .collect();
        assert_eq!(run.arrays.triangles, reference.arrays.triangles, "2^{e}");
        assert_eq!(run.arrays.coords, scaled, "2^{e}");
        let (q, r) = (&run.quality, &reference.quality);
        assert_eq!(
            (q.min_angle, q.max_angle),
            (r.min_angle, r.max_angle),
            "2^{e}"
        );
        assert_eq!(q.total_area, r.total_area * f * f, "2^{e}");
        // The mesh itself answers in the caller's units.
        let t = run.mesh.cdt.triangulation();
        for (v, p) in run.arrays.vertex.iter().zip(&run.arrays.coords) {
            assert_eq!(t.vertex(*v), *p, "2^{e}");
        }
    }
}

#[test]
fn regional_area_limits_bound_every_element() {
    // Two regions side by side, the right one with a hole, limited to 0.002 and 0.05 (as a
    // .poly file's regional attributes give them to Triangle's -a): every element is within
    // its region's limit, whatever the recovery, with and without smoothing.
    let mut plc = Plc2::default();
    polygon(
        &mut plc,
        &[
            [0.0, 0.0],
            [2.0, 0.0],
            [4.0, 0.0],
            [4.0, 2.0],
            [2.0, 2.0],
            [0.0, 2.0],
        ],
    );
    polygon(&mut plc, &[[2.5, 0.5], [2.5, 1.0], [3.0, 1.0], [3.0, 0.5]]);
    plc.segments.push(delmesh::recovery::Segment {
        a: 1,
        b: 4,
        marker: 2,
    });
    let limits = [(1.0, 0.002), (2.0, 0.05)];
    plc.regions = [[1.0, 1.0], [3.5, 1.5]]
        .iter()
        .zip(limits)
        .map(|(&point, (attribute, max_area))| RegionSeed {
            point,
            attribute,
            max_area: Some(max_area),
        })
        .collect();
    for recovery in [
        RecoveryMethod::Stitch,
        RecoveryMethod::APriori,
        RecoveryMethod::Constrained,
    ] {
        for smoothing in [None, Some(Smoother::new())] {
            let options = MeshOptions2 {
                recovery,
                smoothing,
                ..MeshOptions2::default()
            };
            let name = format!("{recovery:?}, smoothing {}", smoothing.is_some());
            let run = mesh_plc(&plc, &options).unwrap();
            check_run_of_area(&run, &plc, &name, 8.0 - 0.25);
            let a = &run.arrays;
            let mut count = [0usize; 2];
            for (t, region) in a.triangles.iter().zip(&a.regions) {
                let k = limits
                    .iter()
                    .position(|l| l.0 == *region)
                    .expect("a seeded region");
                let p = t.map(|v| a.coords[v as usize]);
                let area = 0.5
                    * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                        - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
                assert!(
                    area <= limits[k].1,
                    "{name}: area {area} in region {region}"
                );
                count[k] += 1;
            }
            // Filled, not just split: at least the count the limit needs, not many times it
            // (the second region grades from the first one's fine boundary).
            assert!(count[0] >= 2000 && count[0] < 5000, "{name}: {count:?}");
            assert!(count[1] >= 75 && count[1] < 600, "{name}: {count:?}");
            // The first region's boundary is spaced like its interior: no element spans a
            // whole original segment.
            assert!(run.area_limited.is_some());
            assert_eq!(run.area_limit_exceeded, 0, "{name}");
            assert!(run.arrays.edges.len() > 100, "{name}");
        }
    }
    // A point budget too small for the limits: the triangles left too large are counted and
    // the summary warns (it said nothing).
    let mut options = MeshOptions2::default();
    if let Some(g) = options.generation.as_mut() {
        g.max_points = 10;
    }
    let run = mesh_plc(&plc, &options).unwrap();
    assert!(run.area_limit_exceeded > 0);
    assert!(
        run.summary().contains(&format!(
            "warning: {} triangles are still larger",
            run.area_limit_exceeded
        )),
        "{}",
        run.summary()
    );
    // Without point generation the limits are not applied (a recovery only); a limit that
    // is not positive is an error naming the region.
    let options = MeshOptions2 {
        generation: None,
        ..MeshOptions2::default()
    };
    let run = mesh_plc(&plc, &options).unwrap();
    assert_eq!(run.area_limited, None);
    plc.regions[1].max_area = Some(0.0);
    let err = mesh_plc(&plc, &MeshOptions2::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("region 1") && err.contains("maximum area"),
        "{err}"
    );
    // A limit asking for more elements than 32-bit ids hold is refused up front, naming the
    // region (1e-12 in a 2 × 2 region: 4e12 elements), not run out of memory.
    plc.regions[1].max_area = Some(0.05);
    plc.regions[0].max_area = Some(1e-12);
    let err = mesh_plc(&plc, &MeshOptions2::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("region 0") && err.contains("2^30"), "{err}");
}

#[test]
fn a_priori_points_rounded_onto_a_boundary_edge_are_refused() {
    // A dangling segment starting one ulp from the square's corner: the a-priori point of the
    // 1e-16 piece of the bottom edge rounds onto a boundary edge, where the walk could end in
    // the cell on either side. It used to be placed there, and recovery then failed
    // ("segment 2 could not be recovered after 45 splits"), depending on where the walk
    // started.
    let mut plc = Plc2::default();
    polygon(&mut plc, &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    plc.points.push([0.9999999999999999, 0.0]);
    plc.points.push([0.7, 0.6]);
    plc.segments.push(delmesh::recovery::Segment {
        a: 4,
        b: 5,
        marker: 1,
    });
    for generation in [false, true] {
        let mut options = MeshOptions2 {
            recovery: RecoveryMethod::APriori,
            ..MeshOptions2::default()
        };
        if !generation {
            options.generation = None;
        }
        let run = mesh_plc(&plc, &options).unwrap();
        // (The dangling segment adds no area.)
        check_run_of_area(&run, &plc, "slot corner", 1.0);
    }
}

/// A spacing source smaller than the elements and off their centroids (in a corner of a
/// coarse square) was ignored (the α test at the centroids refused every candidate); once
/// generation started near one, thin triangles piled up along the boundary edge next to it
/// (areas rounding to 0). Now the α test takes the finest spacing a source asks anywhere in
/// the element, and the boundary edges are split to the sources' spacing along them.
#[test]
fn a_corner_source_refines_the_boundary_and_the_elements_next_to_it() {
    use delmesh::point_gen::Source;
    let mut plc = Plc2::default();
    square_loop(&mut plc, 0.0, 10.0, 1, false);
    square_loop(&mut plc, 4.0, 6.0, 1, true);
    plc.holes.push([5.0, 5.0]);
    for growth in [1.0, 0.1] {
        let source = Source {
            a: [0.5, 0.5],
            b: [0.5, 0.5],
            h0: 0.01,
            radius: 1.0,
            growth,
        };
        let options = MeshOptions2 {
            sources: vec![source],
            ..MeshOptions2::default()
        };
        let run = mesh_plc(&plc, &options).unwrap();
        let name = format!("corner source, growth {growth}");
        check_run(&run, &plc, &name);
        let a = &run.arrays;
        let near = a
            .coords
            .iter()
            .filter(|p| (p[0] - 0.5).hypot(p[1] - 0.5) < 1.0)
            .count();
        assert!(near > 5000, "{name}: {near} points within the radius");
        for e in &a.edges {
            let (p, q) = (a.coords[e[0] as usize], a.coords[e[1] as usize]);
            let length = (p[0] - q[0]).hypot(p[1] - q[1]);
            assert!(
                length <= source.finest_on(p, q) * (1.0 + 1e-9),
                "{name}: boundary edge {p:?} {q:?} longer than the spacing on it"
            );
        }
        assert!(
            run.quality.min_angle > 14.0,
            "{name}: min angle {}",
            run.quality.min_angle
        );
    }
}

/// A background mesh finer than the boundary's edges splits them (as sources do): a unit square
/// of four edges under a spacing of 0.05 had fans of thin triangles from its corners (smallest
/// angle 4.5°). A background graded along x grades the boundary too; kept as given with
/// `split_boundary` off.
#[test]
fn a_background_mesh_finer_than_the_boundary_splits_it() {
    use delmesh::mesh2d::Spacing;
    use delmesh::point_gen::BackgroundMesh2;
    let mut plc = Plc2::default();
    square_loop(&mut plc, 0.0, 1.0, 1, false);
    let corners = vec![[-1.0, -1.0], [2.0, -1.0], [2.0, 2.0], [-1.0, 2.0]];
    let triangles = vec![[0, 1, 2], [0, 2, 3]];
    let background = |h: [f64; 4]| {
        Spacing::Background(
            BackgroundMesh2::new(corners.clone(), triangles.clone(), h.to_vec()).unwrap(),
        )
    };
    // Constant 0.05: twenty equal pieces a side.
    let options = MeshOptions2 {
        spacing: background([0.05; 4]),
        ..MeshOptions2::default()
    };
    let run = mesh_plc(&plc, &options).unwrap();
    check_run(&run, &plc, "background 0.05");
    assert_eq!(run.arrays.edges.len(), 80);
    assert!(run.quality.min_angle > 28.0, "{}", run.quality.min_angle);
    // Graded: 0.02 at x = -1 to 0.2 at x = 2, so 0.08 to 0.14 across the square. The bottom
    // edge's pieces grow with x and stay within a factor 1.5 of the spacing at their middle.
    let options = MeshOptions2 {
        spacing: background([0.02, 0.2, 0.2, 0.02]),
        ..MeshOptions2::default()
    };
    let run = mesh_plc(&plc, &options).unwrap();
    check_run(&run, &plc, "graded background");
    let a = &run.arrays;
    let mut pieces: Vec<[f64; 2]> = a
        .edges
        .iter()
        .map(|e| [a.coords[e[0] as usize], a.coords[e[1] as usize]])
        .filter(|[p, q]| p[1] == 0.0 && q[1] == 0.0)
        .map(|[p, q]| [p[0].min(q[0]), p[0].max(q[0])])
        .collect();
    pieces.sort_by(|u, v| u[0].total_cmp(&v[0]));
    assert!((8..=12).contains(&pieces.len()), "{} pieces", pieces.len());
    let mut x = 0.0;
    for &[lo, hi] in &pieces {
        assert_eq!(lo, x, "the bottom edge's pieces join");
        x = hi;
        let mid = 0.5 * (lo + hi);
        let h = 0.02 + 0.06 * (mid + 1.0);
        let piece = hi - lo;
        assert!(
            piece < 1.5 * h && piece > h / 1.5,
            "piece {piece} at x = {mid}, spacing {h}"
        );
    }
    assert_eq!(x, 1.0);
    let length = |p: &[f64; 2]| p[1] - p[0];
    assert!(length(&pieces[0]) < length(&pieces[pieces.len() - 1]));
    assert!(run.quality.min_angle > 28.0, "{}", run.quality.min_angle);
    // Off: the boundary as given.
    let options = MeshOptions2 {
        spacing: background([0.05; 4]),
        split_boundary: false,
        ..MeshOptions2::default()
    };
    let run = mesh_plc(&plc, &options).unwrap();
    check_run(&run, &plc, "background, boundary kept");
    assert_eq!(run.arrays.edges.len(), 4);
}

/// At a small α a centroid rounds onto the square's top edge (the convex hull): refused like
/// one on any boundary edge (it was an error, "lies outside the triangulated region").
#[test]
fn a_small_alpha_fills_a_square_with_a_hole() {
    let mut plc = Plc2::default();
    square_loop(&mut plc, 0.0, 10.0, 1, false);
    square_loop(&mut plc, 4.0, 6.0, 1, true);
    plc.holes.push([5.0, 5.0]);
    let options = MeshOptions2 {
        generation: Some(delmesh::point_gen::PointGeneration {
            alpha: 0.01,
            ..Default::default()
        }),
        ..MeshOptions2::default()
    };
    let run = mesh_plc(&plc, &options).unwrap();
    check_run(&run, &plc, "alpha 0.01");
    assert!(run.arrays.coords.len() > 10_000);
}

#[test]
fn max_points_bounds_generation_and_refinement_together() {
    use delmesh::point_gen::{PointGeneration, Source};
    let mut plc = Plc2::default();
    square_loop(&mut plc, 0.0, 1.0, 1, false);
    let source = Source {
        a: [0.5, 0.5],
        b: [0.5, 0.5],
        h0: 0.01,
        radius: 0.1,
        growth: 0.1,
    };
    for max_points in [0, 10, 100] {
        let options = MeshOptions2 {
            sources: vec![source],
            generation: Some(PointGeneration {
                max_points,
                ..PointGeneration::default()
            }),
            ..MeshOptions2::default()
        };
        let run = mesh_plc(&plc, &options).unwrap();
        let added = run.generation.as_ref().unwrap().points_added() + run.refined;
        assert!(
            added <= max_points,
            "{added} added with a budget of {max_points}"
        );
        check_run(&run, &plc, "budget");
    }
}

#[test]
fn a_circumcentre_rounded_next_to_a_boundary_edge_is_refused() {
    // One skinny triangle's circumcentre is the midpoint of a boundary segment, which rounding
    // put 3e-13 inside the domain: quality refinement inserted it there, leaving a triangle of
    // area 4e-13 with a 180° angle on the segment (unsmoothed; smoothing hid it, not always).
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/refinement-near-segment.poly"
    );
    let plc = delmesh::mesh2d::read_plc(std::path::Path::new(path)).unwrap();
    let options = MeshOptions2 {
        smoothing: None,
        ..MeshOptions2::default()
    };
    let run = mesh_plc(&plc, &options).unwrap();
    // (Its loops are not oriented: the area is that of its 19 cells of 3.7 × 3.7.)
    check_run_of_area(&run, &plc, "refinement near a segment", 19.0 * 3.7 * 3.7);
    assert!(run.refined > 0);
    assert!(run.quality.min_angle > 10.0, "{}", run.quality.min_angle);
    assert!(run.quality.max_angle < 170.0, "{}", run.quality.max_angle);
}

#[test]
fn a_coordinate_range_error_names_the_input_coordinates() {
    // A square from 1e8 to 1e150 is scaled before it is meshed; the error named the scaled
    // coordinates (1.2e-142 and 1.2).
    let mut plc = Plc2::default();
    polygon(
        &mut plc,
        &[[1e8, 1e8], [1e150, 1e8], [1e150, 1e150], [1e8, 1e150]],
    );
    let err = mesh_plc(&plc, &MeshOptions2::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("coordinate 1e8") && err.contains("largest coordinate magnitude 1e150"),
        "{err}"
    );
}

#[test]
fn a_segment_source_with_far_ends_gives_the_mesh_of_its_part_in_the_domain() {
    // The diagonal of the unit square as a source, and the same line from -1e100 to 1e100:
    // every point of the square projects inside both, so the spacing, and the mesh, are the
    // same. The projection a + t (b − a) lost the points' digits: the distance was 0 (and
    // the side tests of far points were wrong), 2086 points instead of 601.
    use delmesh::point_gen::Source;
    let mut plc = Plc2::default();
    square_loop(&mut plc, 0.0, 1.0, 1, false);
    let run = |a: [f64; 2], b: [f64; 2]| {
        let options = MeshOptions2 {
            sources: vec![Source {
                a,
                b,
                h0: 0.02,
                radius: 0.05,
                growth: 0.2,
            }],
            ..MeshOptions2::default()
        };
        mesh_plc(&plc, &options).unwrap()
    };
    let near = run([0.0, 0.0], [1.0, 1.0]);
    check_run(&near, &plc, "diagonal source");
    let far = run([-1e100, -1e100], [1e100, 1e100]);
    assert_eq!(far.arrays.coords.len(), near.arrays.coords.len());
    assert_eq!(far.arrays.triangles, near.arrays.triangles);
    // Farther, the exact cross products would overflow: refused (it gave a wrong mesh).
    let options = MeshOptions2 {
        sources: vec![Source {
            a: [-1e160, -1e160],
            b: [1e160, 1e160],
            h0: 0.02,
            radius: 0.05,
            growth: 0.2,
        }],
        ..MeshOptions2::default()
    };
    let err = mesh_plc(&plc, &options).unwrap_err().to_string();
    assert!(err.contains("source 1: an end"), "{err}");
}
