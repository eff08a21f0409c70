//! Times the whole 2D pipeline against the bare Delaunay triangulation of its final points.
//!
//! `cargo run --release -p delmesh --example pipeline2d -- [K] [aerofoil N]`
//!
//! - `K` (default 700): a unit square with K boundary points per side, filled by automatic
//!   point generation (about 1.3·K² triangles... K = 700 gives about 10^6) and smoothed;
//! - `aerofoil N`: the two-element aerofoil demo with N points per element.
//!
//! Prints the time of each stage, then the time `Triangulation2::new` takes on the same final
//! points (best of 3), and the ratio. The target: the pipeline within 3× of the bare
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

fn main() -> Result<(), delmesh::Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let plc = if args.first().map(String::as_str) == Some("aerofoil") {
        let n = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(200);
        delmesh::geometry::two_element_aerofoil(n)
    } else {
        square(args.first().and_then(|s| s.parse().ok()).unwrap_or(700))
    };
    let run = mesh_plc(&plc, &MeshOptions2::default())?;
    print!("{}", run.summary());
    let total: f64 = run.timings.iter().map(|t| t.1).sum();
    let points = run.arrays.coords.clone();
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let t0 = Instant::now();
        let tri = Triangulation2::new(&points).expect("the mesh points triangulate");
        best = best.min(t0.elapsed().as_secs_f64());
        std::hint::black_box(tri.num_vertices());
    }
    println!(
        "pipeline {total:.4} s; bare Delaunay of the {} final points {best:.4} s; ratio {:.2}",
        points.len(),
        total / best
    );
    Ok(())
}
