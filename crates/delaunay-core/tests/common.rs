//! Point-set generators shared by the kernel's tests (seeded, deterministic).
#![allow(dead_code, unreachable_pub, missing_docs)]

use rand::{rngs::StdRng, Rng, SeedableRng};

pub fn uniform2(n: usize, seed: u64) -> Vec<[f64; 2]> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..n).map(|_| [rng.gen(), rng.gen()]).collect()
}

pub fn uniform3(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..n).map(|_| [rng.gen(), rng.gen(), rng.gen()]).collect()
}

pub fn grid2(k: usize) -> Vec<[f64; 2]> {
    (0..k * k)
        .map(|i| [(i % k) as f64, (i / k) as f64])
        .collect()
}

pub fn grid3(k: usize) -> Vec<[f64; 3]> {
    (0..k * k * k)
        .map(|i| [(i % k) as f64, (i / k % k) as f64, (i / k / k) as f64])
        .collect()
}

/// Points exactly on a circle: Pythagorean triples scaled to radius 5·13·17 = 1105, which has
/// many integer points, plus their reflections.
pub fn circle_points() -> Vec<[f64; 2]> {
    let r2: i64 = 1105 * 1105;
    let mut pts = Vec::new();
    for x in -1105i64..=1105 {
        let y2 = r2 - x * x;
        let y = (y2 as f64).sqrt().round() as i64;
        if y * y == y2 {
            pts.push([x as f64, y as f64]);
            if y != 0 {
                pts.push([x as f64, -y as f64]);
            }
        }
    }
    pts
}

/// Integer points exactly on the sphere x² + y² + z² = 45², many of them co-spherical.
pub fn sphere_points() -> Vec<[f64; 3]> {
    let r2: i64 = 45 * 45;
    let mut pts = Vec::new();
    for x in -45i64..=45 {
        for y in -45i64..=45 {
            let z2 = r2 - x * x - y * y;
            if z2 < 0 {
                continue;
            }
            let z = (z2 as f64).sqrt().round() as i64;
            if z * z == z2 {
                pts.push([x as f64, y as f64, z as f64]);
                if z != 0 {
                    pts.push([x as f64, y as f64, -z as f64]);
                }
            }
        }
    }
    pts
}

/// Gaussian-like clusters (sums of uniforms) around a few centres.
pub fn clustered3(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut rng = StdRng::seed_from_u64(seed);
    let centres: Vec<[f64; 3]> = (0..5).map(|_| [rng.gen(), rng.gen(), rng.gen()]).collect();
    (0..n)
        .map(|i| {
            let c = centres[i % centres.len()];
            let mut g = || (0..4).map(|_| rng.gen::<f64>() - 0.5).sum::<f64>() * 0.01;
            [c[0] + g(), c[1] + g(), c[2] + g()]
        })
        .collect()
}
