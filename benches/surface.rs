//! Construction benchmarks on nearly and exactly degenerate 3D inputs, where the exact stages
//! of the predicates (not their filters) decide the time: points on a sphere (every insphere
//! test is close to zero) and the points of a surface mesh (an icosphere, nearly co-spherical
//! locally, plus a structured grid on the faces of a box, exactly co-circular).
//!
//! `cargo bench --bench surface` runs the criterion groups. For instruction counts, one
//! construction of one case without criterion:
//!
//! ```text
//! cargo bench --bench surface --no-run
//! valgrind --tool=callgrind target/release/deps/surface-HASH --once sphere-10000
//! ```
//!
//! Cases for `--once`: `sphere-N` (N points on the unit sphere), `surface` (icosphere of
//! level 4, 2,562 points, plus 10×10 points on each face of a box, 3,162 points in all), and
//! for comparison `uniform-N` (uniform in the unit cube) and `grid-K` (the grid `{0..K-1}³`).

use criterion::{BenchmarkId, Criterion, SamplingMode};
use delmesh_delaunay_core::Triangulation3;
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::time::{Duration, Instant};

/// `n` points on the unit sphere: normalised Gaussian vectors (Box–Muller), rounded to `f64`.
fn sphere(n: usize) -> Vec<[f64; 3]> {
    let mut rng = StdRng::seed_from_u64(4);
    let mut gauss = move || {
        let u: f64 = rng.gen_range(f64::EPSILON..1.0);
        let v: f64 = rng.gen();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    };
    (0..n)
        .map(|_| loop {
            let p = [gauss(), gauss(), gauss()];
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            if r > 1e-3 {
                break p.map(|x| x / r);
            }
        })
        .collect()
}

/// The vertices of an icosphere: the icosahedron subdivided `level` times, every new vertex
/// pushed onto the unit sphere (`10·4^level + 2` points).
fn icosphere(level: usize) -> Vec<[f64; 3]> {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<[f64; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .into_iter()
    .map(normalise)
    .collect();
    let mut f: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: usize, b: usize, v: &mut Vec<[f64; 3]>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (v[a], v[b]);
                v.push(normalise([p[0] + q[0], p[1] + q[1], p[2] + q[2]]));
                v.len() - 1
            })
        };
        let mut next = Vec::with_capacity(4 * f.len());
        for [a, b, c] in f {
            let ab = midpoint(a, b, &mut v);
            let bc = midpoint(b, c, &mut v);
            let ca = midpoint(c, a, &mut v);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    v
}

fn normalise(p: [f64; 3]) -> [f64; 3] {
    let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    p.map(|x| x / r)
}

/// An icosphere of level 4 (2,562 points) inside the box `[-1.5, 1.5]³` with a 10×10 grid of
/// points on each face (cell centres, 600 points): the points of a surface mesh of a sphere in
/// a box, locally nearly co-spherical on the sphere and exactly co-circular on the faces.
fn surface() -> Vec<[f64; 3]> {
    let mut pts = icosphere(4);
    let t = |i: usize| -1.5 + 3.0 * (i as f64 + 0.5) / 10.0;
    for axis in 0..3 {
        for side in [-1.5, 1.5] {
            for i in 0..10 {
                for j in 0..10 {
                    let mut p = [0.0; 3];
                    p[axis] = side;
                    p[(axis + 1) % 3] = t(i);
                    p[(axis + 2) % 3] = t(j);
                    pts.push(p);
                }
            }
        }
    }
    pts
}

fn case(name: &str) -> Option<Vec<[f64; 3]>> {
    if name == "surface" {
        return Some(surface());
    }
    if let Some(n) = name.strip_prefix("sphere-") {
        return Some(sphere(n.parse().ok()?));
    }
    if let Some(n) = name.strip_prefix("uniform-") {
        let mut rng = StdRng::seed_from_u64(42);
        return Some((0..n.parse().ok()?).map(|_| rng.gen()).collect());
    }
    // The integer grid {0..k-1}³, as in `cargo bench --bench delaunay`.
    let k: usize = name.strip_prefix("grid-")?.parse().ok()?;
    Some(
        (0..k * k * k)
            .map(|i| [(i % k) as f64, (i / k % k) as f64, (i / k / k) as f64])
            .collect(),
    )
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("delaunay_3d_degenerate");
    g.sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1));
    for name in ["surface", "sphere-10000", "sphere-100000"] {
        let pts = case(name).expect("known case");
        g.bench_with_input(BenchmarkId::new("delmesh", name), &pts, |b, pts| {
            b.iter(|| Triangulation3::new(pts).unwrap())
        });
    }
    g.finish();
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--once") {
        let name = args.get(i + 1).map_or("surface", String::as_str);
        let pts = case(name).unwrap_or_else(|| panic!("unknown case {name}"));
        let t0 = Instant::now();
        let t = Triangulation3::new(&pts).unwrap();
        let dt = t0.elapsed().as_secs_f64();
        println!(
            "{name}: {} points, {} cells, {dt:.3} s",
            pts.len(),
            t.num_cells()
        );
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c);
    c.final_summary();
}
