//! `delmesh demo`: small runs that reproduce figures and tables of the paper.
//!
//! Each demo builds a triangulation from built-in data (so it works from any directory, with no
//! input file), writes its mesh and Voronoi cells as `.vtu` files for ParaView, and may return a
//! text table. They double as end-to-end checks: the `figure1` table is compared with the
//! paper's Table 1 in the tests.
//!
//! | demo | paper | output |
//! | --- | --- | --- |
//! | `figure1` | Fig. 1, Table 1 | Table 1 (Voronoi vertices, forming points, neighbours); `figure1.vtu`, `figure1-voronoi.vtu` |
//! | `random2d` | Fig. 4 | `random2d.vtu`, `random2d-voronoi.vtu`: 1000 seeded random points |

use std::path::{Path, PathBuf};

use delmesh_io::{IoError, PointSet};

use crate::delaunay::DelaunayRun;
use crate::Error;

/// The nine points of the paper's Figure 1 (`data/figure1.node`), built into the binary.
pub const FIGURE1_NODE: &str = include_str!("../../../data/figure1.node");

/// Number of points of the `random2d` demo.
pub const RANDOM2D_POINTS: usize = 1000;
/// Seed of the `random2d` demo's points.
pub const RANDOM2D_SEED: u64 = 0x00DE_1A04;

/// A demo: its name (the argument of `delmesh demo`) and what it shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Demo {
    /// The name passed to `delmesh demo`.
    pub name: &'static str,
    /// One line on what it reproduces and writes.
    pub summary: &'static str,
}

/// All demos, in the order `delmesh demo` lists them.
pub const DEMOS: &[Demo] = &[
    Demo {
        name: "figure1",
        summary: "Fig. 1 / Table 1: the 9 points' Delaunay triangulation and Voronoi diagram; \
                  prints Table 1 (Voronoi vertices, forming points, neighbours)",
    },
    Demo {
        name: "random2d",
        summary: "Fig. 4: 2D Delaunay triangulation and Voronoi cells of 1000 seeded random points",
    },
];

/// What a demo produced.
#[derive(Clone, Debug)]
pub struct DemoOutput {
    /// The triangulation built.
    pub run: DelaunayRun,
    /// Text to print (the `figure1` table), if the demo has any.
    pub table: Option<String>,
    /// The files written, in order.
    pub written: Vec<PathBuf>,
}

/// Runs demo `name`, writing its files into `dir` (created if missing).
///
/// # Errors
/// [`Error::UnknownDemo`] for a name not in [`DEMOS`]; [`Error::Io`] if `dir` or a file cannot
/// be written.
pub fn run(name: &str, dir: &Path) -> Result<DemoOutput, Error> {
    let (run, table) = match name {
        "figure1" => {
            let run = figure1()?;
            let table = run.voronoi_table();
            (run, Some(table))
        }
        "random2d" => (random2d()?, None),
        _ => {
            return Err(Error::UnknownDemo {
                name: name.to_string(),
                available: DEMOS.iter().map(|d| d.name).collect::<Vec<_>>().join(", "),
            })
        }
    };
    std::fs::create_dir_all(dir).map_err(|source| IoError::Io {
        file: dir.to_path_buf(),
        source,
    })?;
    let mut written = run.write(&dir.join(format!("{name}.vtu")))?;
    let voronoi = dir.join(format!("{name}-voronoi.vtu"));
    run.write_voronoi(&voronoi)?;
    written.push(voronoi);
    Ok(DemoOutput {
        run,
        table,
        written,
    })
}

/// The triangulation of the paper's Figure 1 points ([`FIGURE1_NODE`]).
///
/// # Errors
/// Only if the built-in data were broken.
pub fn figure1() -> Result<DelaunayRun, Error> {
    let name = Path::new("figure1.node");
    let points = delmesh_io::parse_node(FIGURE1_NODE, name)?;
    DelaunayRun::from_points(&points, name, false)
}

/// The paper's Table 1, as computed by delmesh for the Figure 1 points.
///
/// # Errors
/// Only if the built-in data were broken.
pub fn figure1_table() -> Result<String, Error> {
    Ok(figure1()?.voronoi_table())
}

/// The triangulation of the `random2d` demo: [`RANDOM2D_POINTS`] points in the unit square.
///
/// # Errors
/// None in practice (the points are random, so not collinear).
pub fn random2d() -> Result<DelaunayRun, Error> {
    let points = random_points(2, RANDOM2D_POINTS, RANDOM2D_SEED);
    DelaunayRun::from_points(&points, Path::new("random2d"), false)
}

/// `n` points uniform in the unit square (`dim` 2) or cube (`dim` 3), from a fixed-seed
/// SplitMix64 generator: the same points on every platform and every version.
pub fn random_points(dim: usize, n: usize, seed: u64) -> PointSet {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        // 53 random bits → [0, 1).
        (z >> 11) as f64 / (1u64 << 53) as f64
    };
    PointSet {
        dim,
        coords: (0..n * dim).map(|_| next()).collect(),
        first_index: 0,
        attributes: Vec::new(),
        markers: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_points_are_deterministic_and_in_range() {
        let a = random_points(2, 100, 7);
        assert_eq!(a, random_points(2, 100, 7));
        assert_ne!(a, random_points(2, 100, 8));
        assert!(a.coords.iter().all(|&x| (0.0..1.0).contains(&x)));
    }

    #[test]
    fn random2d_builds() {
        let run = random2d().unwrap();
        assert_eq!(run.num_vertices(), RANDOM2D_POINTS);
        assert!(run.num_cells() > RANDOM2D_POINTS);
    }
}
