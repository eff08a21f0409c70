//! Seeded point-set generators for validation and benchmarks, and the catalog of
//! named cases built from them.
//!
//! Every case writes a 0-based `.node` file (see `formats::write_node`) whose
//! coordinates are printed round-trip exact, so every tool reads bit-identical
//! points. Randomness comes from a self-written splitmix64 generator so that xtask
//! needs no `rand` dependency and a case's file never changes across platforms or
//! dependency upgrades: same name, same bytes.
//!
//! A command that needs cases (ref-check, ref-bench, and later validate) is a table
//! of [`Case`] entries; add a new kind of input by adding a [`Gen`] variant and a
//! catalog entry.

use std::f64::consts::TAU;
use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use crate::formats;

/// splitmix64 (Steele, Lea, Flood 2014): tiny, fast, and good enough for test data.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), 53 random bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform integer in [0, n) (n > 0; modulo bias is irrelevant here).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// Standard normal (Box-Muller, one value per call).
    pub fn normal(&mut self) -> f64 {
        let u = 1.0 - self.unit(); // (0, 1]
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (TAU * v).cos()
    }
}

/// How a case's points are generated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Gen {
    /// `n` points uniform in the unit cube (dim 3) or unit square (dim 2).
    Uniform { dim: usize, n: usize },
    /// `n` points in `blobs` Gaussian clusters of standard deviation `sigma`, centres
    /// uniform in [0.2, 0.8]^dim: strongly varying density.
    Blobs {
        dim: usize,
        n: usize,
        blobs: usize,
        sigma: f64,
    },
    /// `n` points on the unit sphere (normalized Gaussian vectors): all points on the
    /// hull and nearly co-spherical, though not exactly (the coordinates are rounded).
    Sphere { n: usize },
    /// The integer grid {0..k-1}^dim: exactly co-spherical/co-circular, the Delaunay
    /// triangulation is not unique.
    Grid { dim: usize, k: usize },
    /// `n` points uniform in [0,1]^2 x [0, thickness]: flat, badly shaped tets.
    Slab { n: usize, thickness: f64 },
    /// `n` uniform points of which about `permille`/1000 are exact copies of an
    /// earlier point, interleaved at random positions.
    Duplicates {
        dim: usize,
        n: usize,
        permille: usize,
    },
}

impl Gen {
    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        match *self {
            Gen::Uniform { dim, .. } | Gen::Blobs { dim, .. } | Gen::Grid { dim, .. } => dim,
            Gen::Duplicates { dim, .. } => dim,
            Gen::Sphere { .. } | Gen::Slab { .. } => 3,
        }
    }

    /// Number of points written.
    pub fn len(&self) -> usize {
        match *self {
            Gen::Uniform { n, .. } | Gen::Blobs { n, .. } | Gen::Sphere { n } => n,
            Gen::Slab { n, .. } | Gen::Duplicates { n, .. } => n,
            Gen::Grid { dim, k } => k.pow(dim as u32),
        }
    }

    /// True when no dim+2 points are (exactly) co-spherical, with probability one, so
    /// the Delaunay triangulation is unique and every correct tool must produce the
    /// same cell set (after merging duplicates). False for grids.
    pub fn unique_delaunay(&self) -> bool {
        !matches!(self, Gen::Grid { .. })
    }

    /// The measure (volume/area) of the convex hull when it is known exactly.
    pub fn hull_measure(&self) -> Option<f64> {
        match *self {
            Gen::Grid { dim, k } => Some(((k - 1) as f64).powi(dim as i32)),
            _ => None,
        }
    }

    /// Generates the coordinates, `dim` per point.
    pub fn points(&self, seed: u64) -> Vec<f64> {
        let mut rng = Rng::new(seed);
        let dim = self.dim();
        let mut c = Vec::with_capacity(self.len() * dim);
        match *self {
            Gen::Uniform { n, .. } => c.extend((0..n * dim).map(|_| rng.unit())),
            Gen::Blobs {
                n, blobs, sigma, ..
            } => {
                let centres: Vec<f64> = (0..blobs * dim).map(|_| 0.2 + 0.6 * rng.unit()).collect();
                for _ in 0..n {
                    let b = rng.below(blobs);
                    for d in 0..dim {
                        c.push(centres[b * dim + d] + sigma * rng.normal());
                    }
                }
            }
            Gen::Sphere { n } => {
                while c.len() < 3 * n {
                    let v = [rng.normal(), rng.normal(), rng.normal()];
                    let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    if r > 1e-6 {
                        c.extend(v.iter().map(|x| x / r));
                    }
                }
            }
            Gen::Grid { dim, k } => {
                for i in 0..k.pow(dim as u32) {
                    let mut r = i;
                    for _ in 0..dim {
                        c.push((r % k) as f64);
                        r /= k;
                    }
                }
            }
            Gen::Slab { n, thickness } => {
                for _ in 0..n {
                    c.push(rng.unit());
                    c.push(rng.unit());
                    c.push(thickness * rng.unit());
                }
            }
            Gen::Duplicates { n, permille, .. } => {
                for i in 0..n {
                    if i > 0 && rng.below(1000) < permille {
                        let j = rng.below(i);
                        for d in 0..dim {
                            c.push(c[j * dim + d]);
                        }
                    } else {
                        c.extend((0..dim).map(|_| rng.unit()));
                    }
                }
            }
        }
        c
    }
}

/// A named, seeded input.
#[derive(Debug, Clone, Copy)]
pub struct Case {
    /// File stem and the name used on the command line.
    pub name: &'static str,
    /// Generator and its parameters.
    pub gen: Gen,
    /// PRNG seed (unused by grids).
    pub seed: u64,
}

impl Case {
    /// Writes `<dir>/<name>.node` and returns its path. Always regenerates: writing
    /// even 10^6 points takes well under a second, and a cache could go stale when a
    /// generator changes.
    pub fn write(&self, dir: &Path) -> Result<PathBuf> {
        fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let path = dir.join(format!("{}.node", self.name));
        formats::write_node(&path, self.gen.dim(), &self.gen.points(self.seed), 0, &[])?;
        Ok(path)
    }
}

const fn case(name: &'static str, seed: u64, gen: Gen) -> Case {
    Case { name, gen, seed }
}

/// Every named case. Commands pick from here by name.
pub const CATALOG: &[Case] = &[
    case("uniform3d-10k", 11, Gen::Uniform { dim: 3, n: 10_000 }),
    case("uniform3d-100k", 12, Gen::Uniform { dim: 3, n: 100_000 }),
    case(
        "uniform3d-1m",
        13,
        Gen::Uniform {
            dim: 3,
            n: 1_000_000,
        },
    ),
    case("uniform2d-10k", 21, Gen::Uniform { dim: 2, n: 10_000 }),
    case("uniform2d-100k", 22, Gen::Uniform { dim: 2, n: 100_000 }),
    case(
        "uniform2d-1m",
        23,
        Gen::Uniform {
            dim: 2,
            n: 1_000_000,
        },
    ),
    case(
        "blobs3d-100k",
        31,
        Gen::Blobs {
            dim: 3,
            n: 100_000,
            blobs: 8,
            sigma: 0.02,
        },
    ),
    case(
        "blobs2d-100k",
        32,
        Gen::Blobs {
            dim: 2,
            n: 100_000,
            blobs: 8,
            sigma: 0.02,
        },
    ),
    case("sphere-10k", 41, Gen::Sphere { n: 10_000 }),
    case("sphere-100k", 42, Gen::Sphere { n: 100_000 }),
    case("grid3d-20", 0, Gen::Grid { dim: 3, k: 20 }),
    case("grid3d-100", 0, Gen::Grid { dim: 3, k: 100 }),
    case("grid2d-300", 0, Gen::Grid { dim: 2, k: 300 }),
    case(
        "slab3d-100k",
        51,
        Gen::Slab {
            n: 100_000,
            thickness: 1e-3,
        },
    ),
    case(
        "dups3d-10k",
        61,
        Gen::Duplicates {
            dim: 3,
            n: 10_000,
            permille: 50,
        },
    ),
    case(
        "dups2d-10k",
        62,
        Gen::Duplicates {
            dim: 2,
            n: 10_000,
            permille: 50,
        },
    ),
];

/// Looks a case up by name.
pub fn by_name(name: &str) -> Result<Case> {
    CATALOG
        .iter()
        .copied()
        .find(|c| c.name == name)
        .with_context(|| {
            let names: Vec<&str> = CATALOG.iter().map(|c| c.name).collect();
            format!("unknown case `{name}`; known: {}", names.join(", "))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generators_are_deterministic_and_sized() {
        for c in CATALOG.iter().filter(|c| c.gen.len() <= 100_000) {
            let a = c.gen.points(c.seed);
            assert_eq!(a.len(), c.gen.len() * c.gen.dim(), "{}", c.name);
            assert_eq!(a, c.gen.points(c.seed), "{}", c.name);
            assert!(a.iter().all(|x| x.is_finite()), "{}", c.name);
        }
    }

    #[test]
    fn duplicates_case_has_duplicates() {
        let c = by_name("dups3d-10k").unwrap();
        let node = formats::NodeFile {
            dim: 3,
            first_index: 0,
            coords: c.gen.points(c.seed),
            nattr: 0,
            attrs: vec![],
        };
        let map = formats::duplicate_canonical_map(&node).expect("duplicates");
        let dups = map
            .iter()
            .enumerate()
            .filter(|&(i, &m)| m as usize != i)
            .count();
        assert!((300..700).contains(&dups), "{dups}");
    }

    #[test]
    fn rng_unit_range() {
        let mut r = Rng::new(1);
        assert!((0..10_000)
            .map(|_| r.unit())
            .all(|x| (0.0..1.0).contains(&x)));
    }
}
