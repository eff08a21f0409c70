//! Deterministic generators of closed surfaces for `cargo xtask surfaces`: small
//! inputs that each stress one thing the real CGAL meshes do not isolate.
//!
//! Every generator returns an outward-oriented surface (triangles counterclockwise seen
//! from outside the solid: for a void, the triangles face into the void) with no
//! duplicate vertices, so the divergence theorem gives the solid's volume and the
//! Euler characteristic its genus. Randomness (the near-coplanar case) comes from
//! `cases::Rng` with a fixed seed: same name, same bytes.
//!
//! - `sphere-in-box`: a box far field around a spherical void, the CFD set-up;
//! - `cube-hole`: a cube with a cubic void (two boundary components, grid faces with
//!   co-spherical vertices);
//! - `two-bodies`: a torus and a ball apart (two components, genus 1 + 0);
//! - `near-coplanar`: a box whose top face is a grid with its interior vertices moved
//!   off the plane by at most 1e-7: nearly coplanar facets, the classic sliver source;
//! - `thin-slab`: a 1 x 1 x 0.002 box, faces much longer than the thickness;
//! - `wedge-5`, `wedge-1`: a prism whose cross-section has a 5 or 1 degree apex angle:
//!   a small dihedral angle between two facets along a whole edge.

use std::collections::HashMap;

use crate::cases::Rng;

use super::surface::Surface;

/// A generated case: its name and what it stresses (for the report).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Generated {
    pub name: &'static str,
    pub what: &'static str,
}

/// All generated cases.
pub const GENERATED: &[Generated] = &[
    Generated {
        name: "sphere-in-box",
        what: "box around a spherical void",
    },
    Generated {
        name: "cube-hole",
        what: "cube with a cubic void",
    },
    Generated {
        name: "two-bodies",
        what: "a torus and a ball",
    },
    Generated {
        name: "near-coplanar",
        what: "box, top facets 1e-7 off plane",
    },
    Generated {
        name: "thin-slab",
        what: "1 x 1 x 0.002 box",
    },
    Generated {
        name: "wedge-5",
        what: "prism, 5 degree dihedral edge",
    },
    Generated {
        name: "wedge-1",
        what: "prism, 1 degree dihedral edge",
    },
];

/// The surface of generated case `name`.
pub fn generate(name: &str) -> Option<Surface> {
    Some(match name {
        "sphere-in-box" => {
            let mut s = box_grid([-1.0; 3], [1.0; 3], [8; 3]);
            append(&mut s, inverted(icosphere([0.0; 3], 0.5, 3)));
            s
        }
        "cube-hole" => {
            let mut s = box_grid([0.0; 3], [3.0; 3], [6; 3]);
            append(&mut s, inverted(box_grid([1.0; 3], [2.0; 3], [2; 3])));
            s
        }
        "two-bodies" => {
            let mut s = torus(1.0, 0.35, 32, 12);
            append(&mut s, icosphere([2.5, 0.0, 0.0], 0.6, 2));
            s
        }
        "near-coplanar" => near_coplanar(16, 1e-7, 0x5EED_C0DE),
        "thin-slab" => box_grid([0.0; 3], [1.0, 1.0, 0.002], [20, 20, 1]),
        "wedge-5" => wedge(5.0, 12, 6),
        "wedge-1" => wedge(1.0, 12, 6),
        _ => return None,
    })
}

/// Points inside the voids of generated case `name` (TetGen's hole list; delmesh finds
/// voids by nesting).
pub fn holes(name: &str) -> Vec<[f64; 3]> {
    match name {
        "sphere-in-box" => vec![[0.0; 3]],
        "cube-hole" => vec![[1.5; 3]],
        _ => Vec::new(),
    }
}

/// Appends `b`'s points and triangles to `a` (disjoint components).
fn append(a: &mut Surface, b: Surface) {
    let base = a.points.len() as u32;
    a.points.extend(b.points);
    a.triangles
        .extend(b.triangles.iter().map(|t| t.map(|v| v + base)));
}

/// The same surface facing the other way (a void's boundary).
fn inverted(mut s: Surface) -> Surface {
    for t in &mut s.triangles {
        t.swap(1, 2);
    }
    s
}

/// `lo + (hi - lo) * i / n`, exactly `hi` at `i = n`.
fn lerp(lo: f64, hi: f64, i: usize, n: usize) -> f64 {
    if i == n {
        hi
    } else {
        lo + (hi - lo) * i as f64 / n as f64
    }
}

/// The surface of the box `[lo, hi]`, each face an `n[b] x n[c]` grid of squares split
/// along one diagonal, outward. Vertices are the boundary points of the lattice
/// `{0..=n[0]} x {0..=n[1]} x {0..=n[2]}`, shared by the faces that meet there.
pub fn box_grid(lo: [f64; 3], hi: [f64; 3], n: [usize; 3]) -> Surface {
    let mut s = Surface::default();
    let mut index: HashMap<[usize; 3], u32> = HashMap::new();
    let mut vertex = |s: &mut Surface, l: [usize; 3]| -> u32 {
        *index.entry(l).or_insert_with(|| {
            s.points
                .push([0, 1, 2].map(|k| lerp(lo[k], hi[k], l[k], n[k])));
            s.points.len() as u32 - 1
        })
    };
    for a in 0..3 {
        // (b, c) follow a cyclically, so e_b x e_c = e_a.
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        for side in [0, n[a]] {
            for i in 0..n[b] {
                for j in 0..n[c] {
                    let at = |di: usize, dj: usize| {
                        let mut l = [0; 3];
                        l[a] = side;
                        l[b] = i + di;
                        l[c] = j + dj;
                        l
                    };
                    let q = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)].map(|l| vertex(&mut s, l));
                    // Counterclockwise around +e_a; reversed on the low side.
                    let tris = [[q[0], q[1], q[2]], [q[0], q[2], q[3]]];
                    for mut t in tris {
                        if side == 0 {
                            t.swap(1, 2);
                        }
                        s.triangles.push(t);
                    }
                }
            }
        }
    }
    s
}

/// An icosahedron subdivided `levels` times (each triangle into four), projected onto
/// the sphere of `radius` around `centre`, outward.
pub fn icosphere(centre: [f64; 3], radius: f64, levels: usize) -> Surface {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut pts: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut next = Vec::with_capacity(tris.len() * 4);
        for &[a, b, c] in &tris {
            let mut m = |u: u32, v: u32| -> u32 {
                *mid.entry((u.min(v), u.max(v))).or_insert_with(|| {
                    let (p, q) = (pts[u as usize], pts[v as usize]);
                    pts.push([0, 1, 2].map(|k| 0.5 * (p[k] + q[k])));
                    pts.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    let points = pts
        .iter()
        .map(|p| {
            let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            [0, 1, 2].map(|k| centre[k] + radius * p[k] / l)
        })
        .collect();
    Surface {
        points,
        triangles: tris,
    }
}

/// A torus around the z axis (tube centre radius `big`, tube radius `small`), `nu`
/// steps around the axis and `nv` around the tube, outward.
pub fn torus(big: f64, small: f64, nu: usize, nv: usize) -> Surface {
    let tau = std::f64::consts::TAU;
    let mut s = Surface::default();
    for i in 0..nu {
        let u = tau * i as f64 / nu as f64;
        for j in 0..nv {
            let v = tau * j as f64 / nv as f64;
            let r = big + small * v.cos();
            s.points.push([r * u.cos(), r * u.sin(), small * v.sin()]);
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + j % nv) as u32;
    for i in 0..nu {
        for j in 0..nv {
            // d/du x d/dv points outwards for this parametrization.
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            s.triangles.push([a, b, c]);
            s.triangles.push([a, c, d]);
        }
    }
    s
}

/// The box \[0,1\]^2 x \[0, 0.25\] (`n x n` squares on top and bottom), whose top face's
/// interior vertices are moved up or down by at most `delta` (seeded): adjacent top
/// facets are nearly, but not exactly, coplanar.
fn near_coplanar(n: usize, delta: f64, seed: u64) -> Surface {
    let mut s = box_grid([0.0; 3], [1.0, 1.0, 0.25], [n, n, 2]);
    let mut rng = Rng::new(seed);
    for p in &mut s.points {
        let interior = p[0] > 0.0 && p[0] < 1.0 && p[1] > 0.0 && p[1] < 1.0;
        if p[2] == 0.25 && interior {
            p[2] += delta * (2.0 * rng.unit() - 1.0);
        }
    }
    s
}

/// A prism of height 0.5 over the triangle A = (0, 0), B = (1, -tan(θ/2)),
/// C = (1, tan(θ/2)) with apex angle θ = `degrees`: the facets through the edge at A
/// meet at the dihedral angle θ. Each cap is the triangular lattice with `n` steps per
/// side; the sides are `n x m` grids.
fn wedge(degrees: f64, n: usize, m: usize) -> Surface {
    let h = (degrees.to_radians() / 2.0).tan();
    let (a, b, c) = ([0.0, 0.0], [1.0, -h], [1.0, h]);
    let height = 0.5;
    let mut s = Surface::default();
    let mut index: HashMap<(usize, usize, usize), u32> = HashMap::new();
    // Lattice point (i, j) of the cap, i steps along AB and j along AC, at level k.
    let mut vertex = |s: &mut Surface, i: usize, j: usize, k: usize| -> u32 {
        *index.entry((i, j, k)).or_insert_with(|| {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            let xy = [0, 1].map(|d| a[d] + u * (b[d] - a[d]) + v * (c[d] - a[d]));
            s.points.push([xy[0], xy[1], lerp(0.0, height, k, m)]);
            s.points.len() as u32 - 1
        })
    };
    // Caps: (B - A) x (C - A) points along +z, so lattice triangles listed as
    // (i,j), (i+1,j), (i,j+1) are counterclockwise seen from +z (the top).
    for (k, top) in [(0, false), (m, true)] {
        for i in 0..n {
            for j in 0..n - i {
                let mut tris = vec![[(i, j), (i + 1, j), (i, j + 1)]];
                if i + j + 1 < n {
                    tris.push([(i + 1, j), (i + 1, j + 1), (i, j + 1)]);
                }
                for t in tris {
                    let mut v = t.map(|(i, j)| vertex(&mut s, i, j, k));
                    if !top {
                        v.swap(1, 2);
                    }
                    s.triangles.push(v);
                }
            }
        }
    }
    // The boundary of the cap counterclockwise: A -> B -> C -> A.
    let mut ring: Vec<(usize, usize)> = (0..n).map(|i| (i, 0)).collect();
    ring.extend((0..n).map(|t| (n - t, t)));
    ring.extend((0..n).map(|t| (0, n - t)));
    for w in 0..ring.len() {
        let (p, q) = (ring[w], ring[(w + 1) % ring.len()]);
        for k in 0..m {
            let p0 = vertex(&mut s, p.0, p.1, k);
            let q0 = vertex(&mut s, q.0, q.1, k);
            let q1 = vertex(&mut s, q.0, q.1, k + 1);
            let p1 = vertex(&mut s, p.0, p.1, k + 1);
            // (q - p) x e_z is the outward normal of a counterclockwise ring.
            s.triangles.push([p0, q0, q1]);
            s.triangles.push([p0, q1, p1]);
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::super::surface::check_closed;
    use super::*;

    fn close(a: f64, b: f64, rtol: f64) -> bool {
        (a - b).abs() <= rtol * b.abs()
    }

    #[test]
    fn every_case_is_closed_outward_and_of_the_right_topology() {
        // (name, volume, relative tolerance, Euler characteristic of the surface).
        let sphere = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        let tau = std::f64::consts::TAU;
        let torus_volume = tau * std::f64::consts::PI * 1.0 * 0.35 * 0.35;
        let expect = [
            ("sphere-in-box", 8.0 - sphere(0.5), 0.01, 4),
            ("cube-hole", 26.0, 1e-15, 4),
            ("two-bodies", torus_volume + sphere(0.6), 0.05, 2),
            ("near-coplanar", 0.25, 1e-6, 2),
            ("thin-slab", 0.002, 1e-12, 2),
            ("wedge-5", 0.5 * (2.5f64).to_radians().tan(), 1e-12, 2),
            ("wedge-1", 0.5 * (0.5f64).to_radians().tan(), 1e-12, 2),
        ];
        assert_eq!(expect.len(), GENERATED.len());
        for (name, volume, rtol, chi) in expect {
            let s = generate(name).unwrap();
            check_closed(&s).unwrap_or_else(|e| panic!("{name}: {e}"));
            let v = s.signed_volume();
            assert!(
                close(v, volume, rtol),
                "{name}: volume {v}, expected {volume}"
            );
            assert_eq!(s.euler_characteristic(), chi, "{name}");
            let (_, cleaning) = s.cleaned();
            assert!(cleaning.is_empty(), "{name}: {cleaning}");
        }
        assert!(generate("nope").is_none());
    }

    #[test]
    fn generators_are_deterministic_and_sized() {
        for g in GENERATED {
            assert_eq!(generate(g.name), generate(g.name), "{}", g.name);
        }
        let b = box_grid([0.0; 3], [1.0; 3], [2, 3, 4]);
        // 2 (xy + yz + zx) squares, two triangles each.
        assert_eq!(b.triangles.len(), 4 * (2 * 3 + 3 * 4 + 4 * 2));
        // The lattice's 3 x 4 x 5 points minus its 1 x 2 x 3 interior ones.
        assert_eq!(b.points.len(), 3 * 4 * 5 - 2 * 3);
        assert_eq!(icosphere([0.0; 3], 1.0, 2).triangles.len(), 320);
        let s = generate("near-coplanar").unwrap();
        let moved = s
            .points
            .iter()
            .filter(|p| p[2] != 0.25 && p[2] != 0.0 && (p[2] - 0.25).abs() < 1e-6)
            .count();
        assert_eq!(moved, 15 * 15);
    }
}
