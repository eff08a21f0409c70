//! Seeded point-set generators for validation and benchmarks, and the table of case
//! families built from them.
//!
//! Every case writes a 0-based `.node` file (see `formats::write_node`) whose
//! coordinates are printed round-trip exact, so every tool reads bit-identical
//! points. Randomness comes from a self-written splitmix64 generator so that xtask
//! needs no `rand` dependency and a case's file never changes across platforms or
//! dependency upgrades: same name, same bytes.
//!
//! The validation table is [`FAMILIES`]: one entry per kind of input (generator with
//! its dimension, what can be checked on it, sizes for `--quick` and full runs). A
//! concrete [`Case`] is a family at one size, named `<family>-<size>` (`uniform3d-100k`,
//! `grid3d-20`). To add inputs, add a [`Gen`] variant if needed and a [`FAMILIES`]
//! entry; to add a new kind of check (e.g. mesh generation from a PLC), add a [`Kind`]
//! variant and its checks in `validate::check_case`.

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
    /// `n` points uniform in \[0,1\]^2 x \[0, thickness\]: flat, badly shaped tets.
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

    /// The same generator with its size parameter (the side `k` for grids, the number
    /// of points otherwise) set to `size`.
    pub fn with_size(mut self, size: usize) -> Gen {
        match &mut self {
            Gen::Grid { k, .. } => *k = size,
            Gen::Uniform { n, .. } | Gen::Blobs { n, .. } | Gen::Sphere { n } => *n = size,
            Gen::Slab { n, .. } | Gen::Duplicates { n, .. } => *n = size,
        }
        self
    }

    /// The measure (volume/area) of the convex hull when it is known exactly.
    pub fn hull_measure(&self) -> Option<f64> {
        match *self {
            Gen::Grid { dim, k } => Some(((k - 1) as f64).powi(dim as i32)),
            _ => None,
        }
    }

    /// [`Gen::hull_measure`] as an exact total, for comparison with
    /// `formats::total_measure`.
    pub fn hull_total(&self) -> Option<formats::Total> {
        match *self {
            Gen::Grid { dim, k } => Some(formats::Total::of_cube(k as u64 - 1, dim)),
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

/// What can be asserted about a case, i.e. which checks `validate` runs on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// No dim+2 points are exactly co-spherical (with probability one), so the Delaunay
    /// triangulation is unique: delmesh's cell set must equal CGAL's and TetGen's
    /// exactly (after merging duplicate points).
    GeneralPosition,
    /// Exactly co-spherical points (grids): the Delaunay triangulation is not unique
    /// and each tool breaks ties its own way. Checked: delmesh's own exact validation,
    /// the same number of cells as the reference tools, and the same total measure.
    Degenerate,
    // Later: PLC inputs for mesh generation (boundary recovery, refinement). Their
    // checks (boundary conformity, quality bounds, comparison with `tetgen -pq`) go in
    // `validate::check_case`, next to the two kinds above.
}

impl Kind {
    /// Short label for tables.
    pub fn label(self) -> &'static str {
        match self {
            Kind::GeneralPosition => "general",
            Kind::Degenerate => "degenerate",
        }
    }
}

/// One row of the validation table: a generator at several sizes.
#[derive(Debug, Clone, Copy)]
pub struct Family {
    /// Case names are `<name>-<size label>`.
    pub name: &'static str,
    /// Generator, with its dimension; its size parameter is replaced by each size below.
    pub gen: Gen,
    /// What the checks may assume.
    pub kind: Kind,
    /// Base PRNG seed (each size gets its own seed derived from it).
    pub seed: u64,
    /// Sizes (points, or the side for grids) run by `validate --quick`.
    pub quick: &'static [usize],
    /// Sizes run by `validate` (full mode).
    pub full: &'static [usize],
}

impl Family {
    /// The family at size `size`.
    pub fn case(&self, size: usize) -> Case {
        Case {
            name: match self.gen {
                // A grid's size is its side: `grid3d-100`, not `grid3d-100k`-like labels.
                Gen::Grid { .. } => format!("{}-{size}", self.name),
                _ => format!("{}-{}", self.name, size_label(size)),
            },
            gen: self.gen.with_size(size),
            kind: self.kind,
            seed: self.seed.wrapping_mul(1_000_003).wrapping_add(size as u64),
        }
    }

    /// Its cases in quick or full mode.
    pub fn cases(&self, quick: bool) -> Vec<Case> {
        let sizes = if quick { self.quick } else { self.full };
        sizes.iter().map(|&s| self.case(s)).collect()
    }
}

const K: usize = 1_000;
const M: usize = 1_000_000;

/// The validation table. Full sizes include the quick ones.
pub const FAMILIES: &[Family] = &[
    Family {
        name: "uniform3d",
        gen: Gen::Uniform { dim: 3, n: 0 },
        kind: Kind::GeneralPosition,
        seed: 1,
        quick: &[10 * K, 100 * K],
        full: &[10 * K, 100 * K, M],
    },
    Family {
        name: "uniform2d",
        gen: Gen::Uniform { dim: 2, n: 0 },
        kind: Kind::GeneralPosition,
        seed: 2,
        quick: &[100 * K],
        full: &[100 * K, M],
    },
    Family {
        name: "blobs3d",
        gen: Gen::Blobs {
            dim: 3,
            n: 0,
            blobs: 8,
            sigma: 0.02,
        },
        kind: Kind::GeneralPosition,
        seed: 3,
        quick: &[100 * K],
        full: &[100 * K, M],
    },
    // Rounded to doubles, the points are only nearly co-spherical: general position,
    // but every insphere test is close to zero, which exercises the exact fallbacks.
    Family {
        name: "sphere3d",
        gen: Gen::Sphere { n: 0 },
        kind: Kind::GeneralPosition,
        seed: 4,
        quick: &[10 * K],
        full: &[10 * K, 100 * K],
    },
    Family {
        name: "grid3d",
        gen: Gen::Grid { dim: 3, k: 0 },
        kind: Kind::Degenerate,
        seed: 0,
        quick: &[20],
        full: &[20, 100],
    },
    Family {
        name: "grid2d",
        gen: Gen::Grid { dim: 2, k: 0 },
        kind: Kind::Degenerate,
        seed: 0,
        quick: &[100],
        full: &[100, 1000],
    },
    Family {
        name: "slab3d",
        gen: Gen::Slab {
            n: 0,
            thickness: 1e-3,
        },
        kind: Kind::GeneralPosition,
        seed: 5,
        quick: &[10 * K],
        full: &[10 * K, 100 * K],
    },
    Family {
        name: "dups3d",
        gen: Gen::Duplicates {
            dim: 3,
            n: 0,
            permille: 50,
        },
        kind: Kind::GeneralPosition,
        seed: 6,
        quick: &[10 * K],
        full: &[10 * K, 100 * K],
    },
    Family {
        name: "dups2d",
        gen: Gen::Duplicates {
            dim: 2,
            n: 0,
            permille: 50,
        },
        kind: Kind::GeneralPosition,
        seed: 7,
        quick: &[10 * K],
        full: &[10 * K, 100 * K],
    },
];

/// `10k`, `1m`, or the plain number.
pub fn size_label(size: usize) -> String {
    if size >= M && size % M == 0 {
        format!("{}m", size / M)
    } else if size >= K && size % K == 0 {
        format!("{}k", size / K)
    } else {
        size.to_string()
    }
}

/// Inverse of [`size_label`].
pub fn parse_size(label: &str) -> Option<usize> {
    let (digits, scale) = match label.as_bytes().last()? {
        b'k' => (&label[..label.len() - 1], K),
        b'm' => (&label[..label.len() - 1], M),
        _ => (label, 1),
    };
    digits.parse::<usize>().ok()?.checked_mul(scale)
}

/// A family at one size: a named, seeded input.
#[derive(Debug, Clone)]
pub struct Case {
    /// File stem and the name used on the command line.
    pub name: String,
    /// Generator and its parameters.
    pub gen: Gen,
    /// Which checks apply.
    pub kind: Kind,
    /// PRNG seed (unused by grids).
    pub seed: u64,
}

impl Case {
    /// The points, as if read back from the case's `.node` file (the writer is
    /// round-trip exact).
    pub fn node(&self) -> formats::NodeFile {
        formats::NodeFile {
            dim: self.gen.dim(),
            first_index: 0,
            coords: self.gen.points(self.seed),
            nattr: 0,
            attrs: vec![],
        }
    }

    /// Writes `<dir>/<name>.node` and returns its path. Always regenerates: writing
    /// even 10^6 points takes well under a second, and a cache could go stale when a
    /// generator changes.
    pub fn write(&self, dir: &Path) -> Result<PathBuf> {
        self.write_node(dir, &self.node())
    }

    /// Writes `node` (this case's points, from [`Case::node`]) as `<dir>/<name>.node`.
    pub fn write_node(&self, dir: &Path, node: &formats::NodeFile) -> Result<PathBuf> {
        fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let path = dir.join(format!("{}.node", self.name));
        formats::write_node(&path, node.dim, &node.coords, 0, &[])?;
        Ok(path)
    }
}

/// Looks a case up by name: `<family>-<size>` for any family of [`FAMILIES`] and any
/// size (`uniform3d-100k`, `grid3d-35`, `sphere3d-2m`).
pub fn by_name(name: &str) -> Result<Case> {
    name.rsplit_once('-')
        .and_then(|(fam, size)| {
            let f = FAMILIES.iter().find(|f| f.name == fam)?;
            Some(f.case(parse_size(size).filter(|&s| s > 0)?))
        })
        .with_context(|| {
            let names: Vec<&str> = FAMILIES.iter().map(|f| f.name).collect();
            format!(
                "unknown case `{name}`: expected <family>-<size> (e.g. uniform3d-100k, \
                 grid3d-20) with family one of {}",
                names.join(", ")
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every case of every family, quick and full sizes.
    fn catalog() -> Vec<Case> {
        let mut all = Vec::new();
        for f in FAMILIES {
            for &s in f.full.iter().chain(f.quick) {
                let c = f.case(s);
                if !all.iter().any(|a: &Case| a.name == c.name) {
                    all.push(c);
                }
            }
        }
        all
    }

    #[test]
    fn generators_are_deterministic_and_sized() {
        for c in catalog().iter().filter(|c| c.gen.len() <= 100_000) {
            let a = c.gen.points(c.seed);
            assert_eq!(a.len(), c.gen.len() * c.gen.dim(), "{}", c.name);
            assert_eq!(a, c.gen.points(c.seed), "{}", c.name);
            assert!(a.iter().all(|x| x.is_finite()), "{}", c.name);
        }
    }

    #[test]
    fn duplicates_case_has_duplicates() {
        let c = by_name("dups3d-10k").unwrap();
        let map = formats::duplicate_canonical_map(&c.node()).expect("duplicates");
        let dups = map
            .iter()
            .enumerate()
            .filter(|&(i, &m)| m as usize != i)
            .count();
        assert!((300..700).contains(&dups), "{dups}");
    }

    #[test]
    fn names_round_trip() {
        for c in catalog() {
            let again = by_name(&c.name).unwrap();
            assert_eq!((again.gen, again.seed, again.kind), (c.gen, c.seed, c.kind));
        }
        assert_eq!(by_name("grid3d-20").unwrap().gen.len(), 8000);
        assert_eq!(by_name("grid2d-1000").unwrap().name, "grid2d-1000");
        assert_eq!(by_name("uniform2d-1m").unwrap().gen.len(), 1_000_000);
        assert_eq!(by_name("sphere3d-2500").unwrap().gen.len(), 2500);
        for bad in [
            "uniform3d",
            "cube-10k",
            "uniform3d-",
            "uniform3d-0",
            "grid3d-x",
        ] {
            assert!(by_name(bad).is_err(), "{bad}");
        }
        assert_eq!(size_label(1_000_000), "1m");
        assert_eq!(size_label(2_500), "2500");
        assert_eq!(parse_size("100k"), Some(100_000));
    }

    #[test]
    fn full_sizes_include_quick_ones() {
        for f in FAMILIES {
            assert!(f.quick.iter().all(|s| f.full.contains(s)), "{}", f.name);
            let g = f.gen.with_size(7);
            let expected = match g {
                Gen::Grid { dim, .. } => 7usize.pow(dim as u32),
                _ => 7,
            };
            assert_eq!(g.len(), expected, "{}", f.name);
        }
    }

    #[test]
    fn rng_unit_range() {
        let mut r = Rng::new(1);
        assert!((0..10_000)
            .map(|_| r.unit())
            .all(|x| (0.0..1.0).contains(&x)));
    }
}
