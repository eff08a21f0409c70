//! Measures what 3D Laplacian smoothing does to dihedral angles with and without the sliver
//! guard, on three meshes of the unit cube (boundary fixed):
//! - `uniform`: the Delaunay tetrahedralisation of uniform random points (many slivers);
//! - `spaced`: the Delaunay tetrahedralisation of a jittered body-centred cubic lattice, the
//!   well-spaced kind of point set that mesh generation produces;
//! - `kuhn`: a cube grid split into Kuhn tetrahedra with its interior points jittered.
//!
//! For each guard it prints the smoothing statistics, the wall time and (on Linux) the CPU time
//! of all threads, which a busy machine inflates less, and the resulting smallest
//! dihedral angle, sliver count, low-angle bins and means. This is how the default of
//! `Smoother3` was chosen (see the `laplace3` module docs).
//!
//! `cargo run --release -p delmesh-smoothing --example dihedral_guard [points [mesh]]`
//! (about 20 000 points and all three meshes by default).

use delmesh_delaunay_core::{Triangulation3, VertexId};
use delmesh_smoothing::{DihedralGuard, QualityReport3, Smoother3};
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::time::Instant;

type Mesh = (Vec<[f64; 3]>, Vec<[u32; 4]>, Vec<bool>);

fn delaunay(input: &[[f64; 3]]) -> Mesh {
    let tri = Triangulation3::new(input).unwrap();
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

fn uniform(n: usize, rng: &mut StdRng) -> Mesh {
    let mut input: Vec<[f64; 3]> = (0..n).map(|_| [rng.gen(), rng.gen(), rng.gen()]).collect();
    // The cube's corners, so the hull is the cube.
    for c in 0..8 {
        input.push([0, 1, 2].map(|k| f64::from((c >> k) & 1)));
    }
    delaunay(&input)
}

fn spaced(n: usize, rng: &mut StdRng) -> Mesh {
    let k = ((n as f64 / 2.0).cbrt().round() as usize).max(2);
    let h = 1.0 / k as f64;
    let mut input = Vec::new();
    for l in 0..=k {
        for j in 0..=k {
            for i in 0..=k {
                let on = [i, j, l];
                // Boundary lattice points stay on the faces of the cube; interior ones move.
                let p = on.map(|c| {
                    let x = c as f64 * h;
                    if c == 0 || c == k {
                        x
                    } else {
                        x + rng.gen_range(-0.2..0.2) * h
                    }
                });
                input.push(p);
                if i < k && j < k && l < k {
                    input.push(on.map(|c| (c as f64 + 0.5 + rng.gen_range(-0.2..0.2)) * h));
                }
            }
        }
    }
    delaunay(&input)
}

fn kuhn(n: usize, rng: &mut StdRng) -> Mesh {
    let k = (n as f64).cbrt().round() as usize;
    let h = 1.0 / k as f64;
    let id = |i: usize, j: usize, l: usize| ((l * (k + 1) + j) * (k + 1) + i) as u32;
    let (mut pts, mut fixed) = (Vec::new(), Vec::new());
    for l in 0..=k {
        for j in 0..=k {
            for i in 0..=k {
                let edge = [i, j, l].iter().any(|&c| c == 0 || c == k);
                pts.push([i, j, l].map(|c| c as f64 * h));
                fixed.push(edge);
            }
        }
    }
    let mut tets = Vec::new();
    for l in 0..k {
        for j in 0..k {
            for i in 0..k {
                for (perm, even) in [
                    ([0, 1, 2], true),
                    ([0, 2, 1], false),
                    ([1, 0, 2], false),
                    ([1, 2, 0], true),
                    ([2, 0, 1], true),
                    ([2, 1, 0], false),
                ] {
                    let mut c = [i, j, l];
                    let mut t = [id(i, j, l); 4];
                    for (s, &axis) in perm.iter().enumerate() {
                        c[axis] += 1;
                        t[s + 1] = id(c[0], c[1], c[2]);
                    }
                    if !even {
                        t.swap(2, 3);
                    }
                    tets.push(t);
                }
            }
        }
    }
    // Jitter, undoing any move that would invert a tetrahedron of the point's star.
    let mut star = vec![Vec::new(); pts.len()];
    for (t, tet) in tets.iter().enumerate() {
        for &v in tet {
            star[v as usize].push(t);
        }
    }
    for v in 0..pts.len() {
        if fixed[v] {
            continue;
        }
        let old = pts[v];
        for x in &mut pts[v] {
            *x += rng.gen_range(-0.3..0.3) * h;
        }
        let ok = star[v].iter().all(|&t| {
            let p = tets[t].map(|u| pts[u as usize]);
            delmesh_predicates::orient3d(p[0], p[1], p[2], p[3]).is_positive()
        });
        if !ok {
            pts[v] = old;
        }
    }
    (pts, tets, fixed)
}

/// CPU time of the process so far (user + system, all threads), where `/proc` tells it.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let fields: Vec<&str> = stat[stat.rfind(')')? + 2..].split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn line(name: &str, q: &QualityReport3, extra: &str) {
    println!(
        "  {name:<14} min {:6.2}°  slivers {:5}  <10° {:5}  10-20° {:6}  mean-min {:6.2}°  \
         mean r/e {:.3}  max r/e {:8.2}  {extra}",
        q.min_dihedral,
        q.slivers,
        q.min_dihedral_histogram[0] + q.min_dihedral_histogram[1],
        q.min_dihedral_histogram[2],
        q.mean_min_dihedral,
        q.mean_radius_edge,
        q.max_radius_edge,
    );
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(20_000);
    let guards = [
        ("off", DihedralGuard::Off),
        ("floor 5", DihedralGuard::Floor(5.0)),
        ("floor 10", DihedralGuard::Floor(10.0)),
        ("floor 15", DihedralGuard::Floor(15.0)),
        ("floor 20", DihedralGuard::Floor(20.0)),
        ("floor 30", DihedralGuard::Floor(30.0)),
        ("no decrease", DihedralGuard::NoDecrease),
    ];
    type Build = fn(usize, &mut StdRng) -> Mesh;
    let meshes: [(&str, Build); 3] = [("uniform", uniform), ("spaced", spaced), ("kuhn", kuhn)];
    let only = std::env::args().nth(2);
    for (name, build) in meshes {
        if only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let mut rng = StdRng::seed_from_u64(2024);
        let (pts, tets, fixed) = build(n, &mut rng);
        println!(
            "{name}: {} points ({} free), {} tetrahedra",
            pts.len(),
            fixed.iter().filter(|f| !**f).count(),
            tets.len()
        );
        line("input", &QualityReport3::of_tetrahedra(&pts, &tets), "");
        for (label, guard) in guards {
            let mut p = pts.clone();
            let (t0, c0) = (Instant::now(), cpu_seconds());
            let stats = Smoother3::new()
                .dihedral_guard(guard)
                .unwrap()
                .smooth(&mut p, &tets, &fixed)
                .unwrap();
            let dt = t0.elapsed().as_secs_f64();
            let cpu = match (c0, cpu_seconds()) {
                (Some(a), Some(b)) => format!(" (cpu {:.2} s)", b - a),
                _ => String::new(),
            };
            let q = QualityReport3::of_tetrahedra(&p, &tets);
            line(label, &q, &format!("{dt:.2} s{cpu}, {stats}"));
        }
    }
}
