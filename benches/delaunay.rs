//! Construction benchmarks (criterion): delmesh's 2D and 3D Delaunay at 10^4–10^6 uniform
//! points, the degenerate 3D grid, and the `delaunator` crate on the same 2D points.
//!
//! `cargo bench --bench delaunay` (all sizes; 10^6 takes minutes), or
//! `cargo bench --bench delaunay -- 'n=100000'` for one size.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode};
use delmesh_delaunay_core::{Triangulation2, Triangulation3};
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::time::Duration;

fn uniform<const N: usize>(n: usize) -> Vec<[f64; N]> {
    let mut rng = StdRng::seed_from_u64(42);
    (0..n).map(|_| std::array::from_fn(|_| rng.gen())).collect()
}

fn configure<'a>(
    c: &'a mut Criterion,
    name: &str,
) -> criterion::BenchmarkGroup<'a, criterion::measurement::WallTime> {
    let mut g = c.benchmark_group(name);
    g.sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1));
    g
}

fn bench_2d(c: &mut Criterion) {
    let mut g = configure(c, "delaunay_2d_uniform");
    for n in [10_000usize, 100_000, 1_000_000] {
        let pts = uniform::<2>(n);
        g.bench_with_input(
            BenchmarkId::new("delmesh", format!("n={n}")),
            &pts,
            |b, pts| b.iter(|| Triangulation2::new(pts).unwrap()),
        );
        let flat: Vec<delaunator::Point> = pts
            .iter()
            .map(|p| delaunator::Point { x: p[0], y: p[1] })
            .collect();
        g.bench_with_input(
            BenchmarkId::new("delaunator", format!("n={n}")),
            &flat,
            |b, pts| b.iter(|| delaunator::triangulate(pts)),
        );
    }
    g.finish();
}

fn bench_3d(c: &mut Criterion) {
    let mut g = configure(c, "delaunay_3d_uniform");
    for n in [10_000usize, 100_000, 1_000_000] {
        let pts = uniform::<3>(n);
        g.bench_with_input(
            BenchmarkId::new("delmesh", format!("n={n}")),
            &pts,
            |b, pts| b.iter(|| Triangulation3::new(pts).unwrap()),
        );
    }
    g.finish();
}

fn bench_3d_grid(c: &mut Criterion) {
    let mut g = configure(c, "delaunay_3d_grid");
    for k in [22usize, 46, 100] {
        let pts: Vec<[f64; 3]> = (0..k * k * k)
            .map(|i| [(i % k) as f64, (i / k % k) as f64, (i / k / k) as f64])
            .collect();
        g.bench_with_input(
            BenchmarkId::new("delmesh", format!("n={}", k * k * k)),
            &pts,
            |b, pts| b.iter(|| Triangulation3::new(pts).unwrap()),
        );
    }
    g.finish();
}

criterion_group!(benches, bench_2d, bench_3d, bench_3d_grid);
criterion_main!(benches);
