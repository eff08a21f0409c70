//! Times 3D smoothing alone on the double ellipsoid demo's mesh (`figure9`, before smoothing).
//!
//! `cargo run --release -p delmesh --example smooth3_probe -- [R]`
//!
//! Meshes the demo once without smoothing, then smooths copies of its points R times (default
//! 15) with the demo's smoother and prints the best and median seconds, with a checksum of the
//! smoothed points: a change that should not alter the decisions must keep it.

use delmesh::demos::mesh3_demo_setup;
use delmesh::mesh3d::mesh_plc3;
use std::time::Instant;

fn main() -> Result<(), delmesh::Error> {
    let (plc, mut options) = mesh3_demo_setup("figure9")?;
    let smoother = options.smoothing.take().expect("the demo smooths");
    options.delaunay = false;
    let mesh = mesh_plc3(&plc, &options)?.arrays;
    let repeat: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(15)
        .max(1);
    let mut times = Vec::with_capacity(repeat);
    let mut checksum = 0.0;
    for run in 0..repeat {
        let mut points = mesh.coords.clone();
        let t0 = Instant::now();
        let stats = smoother.smooth(&mut points, &mesh.tets, &mesh.on_boundary)?;
        times.push(t0.elapsed().as_secs_f64());
        if run == 0 {
            println!(
                "{} points, {} tetrahedra: {stats}",
                points.len(),
                mesh.tets.len()
            );
        }
        checksum = points
            .iter()
            .map(|p| p[0] + 2.0 * p[1] + 3.0 * p[2])
            .sum::<f64>();
    }
    times.sort_by(f64::total_cmp);
    println!(
        "smoothing: best {:.4} s, median {:.4} s over {repeat} runs; checksum {checksum:.12}",
        times[0],
        times[repeat / 2]
    );
    Ok(())
}
