//! 2D mesh-generation benchmarks (criterion): the whole pipeline on the two-element aerofoil
//! demo (Fig. 10b), stage by stage, and on a unit square filled with about 10^5 triangles,
//! next to the bare Delaunay triangulation of the same final points.
//!
//! `cargo bench --bench mesh2d`. The targets: the aerofoil under 0.1 s, the pipeline
//! within 3× of the bare triangulation. `cargo run --release -p delmesh --example pipeline2d`
//! prints the same comparison at 10^6 triangles.

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode};
use delmesh::demos::mesh_demo_setup;
use delmesh::mesh2d::{mesh_plc, MeshOptions2};
use delmesh::recovery::{BoundaryRecovery, Plc2, Segment};
use delmesh::Triangulation2;
use std::time::Duration;

fn square(k: usize) -> Plc2 {
    let mut points = Vec::with_capacity(4 * k);
    for side in 0..4 {
        for i in 0..k {
            let t = i as f64 / k as f64;
            points.push(match side {
                0 => [t, 0.0],
                1 => [1.0, t],
                2 => [1.0 - t, 1.0],
                _ => [0.0, 1.0 - t],
            });
        }
    }
    let n = points.len() as u32;
    let segments = (0..n)
        .map(|i| Segment {
            a: i,
            b: (i + 1) % n,
            marker: 1,
        })
        .collect();
    Plc2 {
        points,
        segments,
        ..Default::default()
    }
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("mesh2d");
    g.sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1));
    let (aerofoil, options) = mesh_demo_setup("figure10b").unwrap();
    g.bench_function("aerofoil/pipeline", |b| {
        b.iter(|| mesh_plc(&aerofoil, &options).unwrap())
    });
    let no_smoothing = MeshOptions2 {
        smoothing: None,
        ..options.clone()
    };
    g.bench_function("aerofoil/no-smoothing", |b| {
        b.iter(|| mesh_plc(&aerofoil, &no_smoothing).unwrap())
    });
    g.bench_function("aerofoil/recovery", |b| {
        b.iter(|| BoundaryRecovery::default().run(&aerofoil).unwrap())
    });
    let sq = square(200);
    let run = mesh_plc(&sq, &MeshOptions2::default()).unwrap();
    g.bench_function("square-100k/pipeline", |b| {
        b.iter(|| mesh_plc(&sq, &MeshOptions2::default()).unwrap())
    });
    let pts = run.arrays.coords.clone();
    g.bench_function("square-100k/bare-delaunay", |b| {
        b.iter(|| Triangulation2::new(&pts).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
