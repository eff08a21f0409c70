//! Times one construction: `cargo run --release -p delmesh-delaunay-core --example build_time -- 3 1000000`.
use delmesh_delaunay_core::*;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dim: usize = args.get(1).map_or(3, |s| s.parse().unwrap());
    let n: usize = args.get(2).map_or(1_000_000, |s| s.parse().unwrap());
    let grid = args.get(3).is_some_and(|s| s == "grid");
    let mut s = 12345u64;
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    if dim == 3 {
        let pts: Vec<[f64; 3]> = if grid {
            let k = (n as f64).cbrt().round() as usize;
            (0..k * k * k)
                .map(|i| [(i % k) as f64, (i / k % k) as f64, (i / k / k) as f64])
                .collect()
        } else {
            (0..n).map(|_| [rnd(), rnd(), rnd()]).collect()
        };
        let t0 = Instant::now();
        let t = Triangulation3::new(&pts).unwrap();
        let dt = t0.elapsed().as_secs_f64();
        println!("3D n={} cells={} time={dt:.3}s", pts.len(), t.num_cells());
        if args.iter().any(|a| a == "validate") {
            t.validate().unwrap();
            println!("valid");
        }
    } else {
        let pts: Vec<[f64; 2]> = if grid {
            let k = (n as f64).sqrt().round() as usize;
            (0..k * k)
                .map(|i| [(i % k) as f64, (i / k) as f64])
                .collect()
        } else {
            (0..n).map(|_| [rnd(), rnd()]).collect()
        };
        let t0 = Instant::now();
        let t = Triangulation2::new(&pts).unwrap();
        let dt = t0.elapsed().as_secs_f64();
        println!("2D n={} cells={} time={dt:.3}s", pts.len(), t.num_cells());
        if args.iter().any(|a| a == "validate") {
            t.validate().unwrap();
            println!("valid");
        }
    }
}
