//! 3D smoothing and quality benchmarks (criterion) on the Delaunay tetrahedralisation of a
//! jittered body-centred cubic lattice in the unit cube (about 10^5 points, 6·10^5
//! tetrahedra, boundary fixed): one pass and five passes of `Smoother3`, without and with the
//! default dihedral guard, and `QualityReport3`. The cost of a pass is the difference of the
//! five-pass and one-pass times over four (the one-pass time includes the set-up: checks,
//! spatial order, adjacency and colouring).
//!
//! `cargo bench --bench smoothing3`

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode};
use delmesh::smoothing::{DihedralGuard, QualityReport3, Smoother3};
use delmesh_delaunay_core::{Triangulation3, VertexId};
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::time::Duration;

type Mesh = (Vec<[f64; 3]>, Vec<[u32; 4]>, Vec<bool>);

/// Lattice points with `k` cells per axis, interior ones jittered by a fifth of a cell, and
/// the cell centres, jittered too; Delaunay, hull points fixed.
fn spaced(k: usize) -> Mesh {
    let mut rng = StdRng::seed_from_u64(2024);
    let h = 1.0 / k as f64;
    let mut input = Vec::new();
    for l in 0..=k {
        for j in 0..=k {
            for i in 0..=k {
                let on = [i, j, l];
                input.push(on.map(|c| {
                    let x = c as f64 * h;
                    if c == 0 || c == k {
                        x
                    } else {
                        x + rng.gen_range(-0.2..0.2) * h
                    }
                }));
                if i < k && j < k && l < k {
                    input.push(on.map(|c| (c as f64 + 0.5 + rng.gen_range(-0.2..0.2)) * h));
                }
            }
        }
    }
    let tri = Triangulation3::new(&input).unwrap();
    let pts: Vec<[f64; 3]> = (0..tri.num_vertices() as u32)
        .map(|v| tri.vertex(VertexId(v)))
        .collect();
    let tets = tri
        .cells()
        .map(|c| {
            let v = tri.cell(c);
            [v[0].0, v[1].0, v[2].0, v[3].0]
        })
        .collect();
    let mut fixed = vec![false; pts.len()];
    for c in tri.all_cells().filter(|&c| tri.is_ghost(c)) {
        for v in tri.cell(c).iter().filter(|v| !v.is_ghost()) {
            fixed[v.index()] = true;
        }
    }
    (pts, tets, fixed)
}

fn bench(c: &mut Criterion) {
    let (pts, tets, fixed) = spaced(37);
    eprintln!("{} points, {} tetrahedra", pts.len(), tets.len());
    let mut g = c.benchmark_group("smoothing3");
    g.sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1));
    for (name, guard) in [
        ("off", DihedralGuard::Off),
        ("floor20", DihedralGuard::Floor(20.0)),
    ] {
        for passes in [1usize, 5] {
            let s = Smoother3::new()
                .dihedral_guard(guard)
                .unwrap()
                .iterations(passes);
            g.bench_function(format!("spaced-100k/{name}/{passes}-pass"), |b| {
                b.iter_batched_ref(
                    || pts.clone(),
                    |p| s.smooth(p, &tets, &fixed).unwrap(),
                    criterion::BatchSize::LargeInput,
                )
            });
        }
    }
    g.bench_function("spaced-100k/quality-report", |b| {
        b.iter(|| QualityReport3::of_tetrahedra(&pts, &tets))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
