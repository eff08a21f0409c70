//! Times the whole 2D pipeline against the bare Delaunay triangulation of its final points.
//!
//! `cargo run --release -p delmesh --example pipeline2d -- [K | aerofoil N] [--repeat R]`
//!
//! - `K` (default 700): a unit square with K boundary points per side, filled by automatic
//!   point generation (K = 700 gives about 5·10^5 triangles, K = 1000 about 10^6) and smoothed;
//! - `aerofoil N`: the two-element aerofoil demo with N points per element (N = 760, the
//!   demo's, gives about 50,000 triangles);
//! - `--repeat R` (default 1): runs the pipeline R times and prints each stage's best and
//!   median time (the machine is shared: the best is the least disturbed run).
//!
//! Prints the last run's summary, then the time `Triangulation2::new` takes on the same final
//! points (best of 3), and the ratio of the best pipeline time to it. The targets: the
//! aerofoil at about 50,000 triangles under 0.1 s, the pipeline within 3× of the bare
//! triangulation at 10^6 triangles.

use std::time::Instant;

use delmesh::mesh2d::{mesh_plc, MeshOptions2};
use delmesh::recovery::{Plc2, Segment};
use delmesh::Triangulation2;

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

fn best(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), delmesh::Error> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut repeat = 1usize;
    if let Some(k) = args.iter().position(|a| a == "--repeat") {
        repeat = args
            .get(k + 1)
            .and_then(|s| s.parse().ok())
            .unwrap_or(1)
            .max(1);
        args.drain(k..(k + 2).min(args.len()));
    }
    let plc = if args.first().map(String::as_str) == Some("aerofoil") {
        let n = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(200);
        delmesh::geometry::two_element_aerofoil(n)
    } else {
        square(args.first().and_then(|s| s.parse().ok()).unwrap_or(700))
    };
    let mut stages: Vec<(&'static str, Vec<f64>)> = Vec::new();
    let mut totals = Vec::new();
    let mut last = None;
    for _ in 0..repeat {
        let run = mesh_plc(&plc, &MeshOptions2::default())?;
        for (k, &(name, t)) in run.timings.iter().enumerate() {
            if stages.len() <= k {
                stages.push((name, Vec::new()));
            }
            stages[k].1.push(t);
        }
        totals.push(run.timings.iter().map(|t| t.1).sum::<f64>());
        last = Some(run);
    }
    let run = last.expect("at least one run");
    print!("{}", run.summary());
    if repeat > 1 {
        println!("time per stage over {repeat} runs (best, median):");
        for (name, t) in &stages {
            println!("  {name:<26} {:.4} s  {:.4} s", best(t), median(t));
        }
        println!(
            "  {:<26} {:.4} s  {:.4} s",
            "total",
            best(&totals),
            median(&totals)
        );
    }
    let total = best(&totals);
    let points = run.arrays.coords.clone();
    let mut bare = f64::INFINITY;
    for _ in 0..3 {
        let t0 = Instant::now();
        let tri = Triangulation2::new(&points).expect("the mesh points triangulate");
        bare = bare.min(t0.elapsed().as_secs_f64());
        std::hint::black_box(tri.num_vertices());
    }
    println!(
        "pipeline {total:.4} s (best of {repeat}); bare Delaunay of the {} final points {bare:.4} s \
         (best of 3); ratio {:.2}",
        points.len(),
        total / bare
    );
    Ok(())
}
