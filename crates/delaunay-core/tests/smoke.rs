//! Quick checks while developing (kept: cheap regression tests).
use delmesh_delaunay_core::*;
use rand::{rngs::StdRng, Rng, SeedableRng};

#[test]
fn random_2d_small() {
    let mut rng = StdRng::seed_from_u64(1);
    for n in [3, 4, 5, 10, 50, 300] {
        let pts: Vec<[f64; 2]> = (0..n).map(|_| [rng.gen(), rng.gen()]).collect();
        let t = Triangulation2::new(&pts).unwrap();
        t.validate().unwrap();
        t.validate_globally().unwrap();
    }
}

#[test]
fn random_3d_small() {
    let mut rng = StdRng::seed_from_u64(2);
    for n in [4, 5, 10, 50, 300] {
        let pts: Vec<[f64; 3]> = (0..n).map(|_| [rng.gen(), rng.gen(), rng.gen()]).collect();
        let t = Triangulation3::new(&pts).unwrap();
        t.validate().unwrap();
        t.validate_globally().unwrap();
    }
}

#[test]
fn grids() {
    let mut pts = Vec::new();
    for i in 0..12 {
        for j in 0..12 {
            pts.push([i as f64, j as f64]);
        }
    }
    let t = Triangulation2::new(&pts).unwrap();
    t.validate().unwrap();
    t.validate_globally().unwrap();
    assert_eq!(t.num_cells(), 2 * 11 * 11);
    let mut pts = Vec::new();
    for i in 0..7 {
        for j in 0..7 {
            for k in 0..7 {
                pts.push([i as f64, j as f64, k as f64]);
            }
        }
    }
    let t = Triangulation3::new(&pts).unwrap();
    t.validate().unwrap();
    t.validate_globally().unwrap();
}
