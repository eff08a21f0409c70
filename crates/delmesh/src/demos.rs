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
//! | `figure4` | Fig. 4 | `figure4.vtu`, `figure4-voronoi.vtu`: 1000 seeded random points (alias `random2d`) |
//! | `figure8` | Fig. 5, 8 | a small PSLG whose edges are missing, recovered by mid-points: the recovery passes; `figure8-delaunay.svg` (before), `figure8.svg`/`.vtu` (after) |
//! | `figure7` | Fig. 7 | estuary coastline with islands: a-priori method, automatic points, smoothing |
//! | `figure10a` | Fig. 10a | two-element aerofoil meshed with the points of component meshes (R9) |
//! | `figure10b` | Fig. 10b | two-element aerofoil with automatic points (R10) |
//! | `figure11` | Fig. 11 | the point-generation passes on the aerofoil: `figure11-pass1.svg`, ... |
//! | `figure12` | Fig. 12 | rectangle clustered along its diagonal BD by a 2-triangle background mesh (R11) |
//! | `figure13` | Fig. 13 | a background mesh spelling "CFD" (R11) |
//! | `table2` | Fig. 9, Table 2 | the double ellipsoid with about 23,000 field points from offset shells: all points triangulated, then surface recovery; prints Table 2 beside the paper's |
//! | `figure9` | Fig. 9 | the double ellipsoid meshed end to end with automatic field points (R10) |
//! | `sphere` | | a sphere in a box |
//! | `cubic-hole` | | a cube with a cubic hole |
//! | `two-bodies` | | two bodies in a box |
//!
//! Each 2D mesh demo writes `NAME.vtu` and `NAME.svg`, each 3D one `NAME.vtu` and
//! `NAME.boundary.vtu`, and prints the run's summary (recovery and generation passes, quality,
//! time per stage).

use std::path::{Path, PathBuf};

use delmesh_io::{IoError, PointSet};

use crate::delaunay::DelaunayRun;
use crate::mesh2d::{mesh_plc, MeshOptions2, MeshRun2, Spacing};
use crate::mesh3d::{mesh_plc3, MeshOptions3, MeshRun3};
use crate::point_gen::{PointGeneration, PointGeneration3};
use crate::recovery::{Plc2, Plc3, RecoveryHistory3, RecoveryMethod, RecoveryStep};
use crate::{geometry, geometry3};
use crate::{Error, Triangulation2};

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
        name: "figure4",
        summary: "Fig. 4: 2D Delaunay triangulation and Voronoi cells of 1000 seeded random points",
    },
    Demo {
        name: "figure8",
        summary: "Fig. 5/8: boundary edges missing from the Delaunay triangulation, recovered by \
                  mid-point insertion pass by pass",
    },
    Demo {
        name: "figure7",
        summary: "Fig. 7: estuary coastline with islands; a-priori boundary points, automatic \
                  points, smoothing",
    },
    Demo {
        name: "figure10a",
        summary: "Fig. 10a: two-element aerofoil meshed with the points of component meshes",
    },
    Demo {
        name: "figure10b",
        summary: "Fig. 10b: two-element aerofoil with automatic point generation and smoothing",
    },
    Demo {
        name: "figure11",
        summary: "Fig. 11: the automatic point-generation passes on the aerofoil, one picture \
                  per pass",
    },
    Demo {
        name: "figure12",
        summary: "Fig. 12: rectangle with clustering along the diagonal BD from a 2-triangle \
                  background mesh",
    },
    Demo {
        name: "figure13",
        summary: "Fig. 13: a background mesh spelling \"CFD\" drives the spacing",
    },
    Demo {
        name: "table2",
        summary: "Fig. 9 / Table 2: double ellipsoid in a box with ~23,000 field points; surface \
                  recovery history printed beside the paper's",
    },
    Demo {
        name: "figure9",
        summary: "Fig. 9: double ellipsoid in a box, automatic field points, smoothing (3D)",
    },
    Demo {
        name: "sphere",
        summary: "3D: a sphere in a box, automatic field points",
    },
    Demo {
        name: "cubic-hole",
        summary: "3D: a cube with a cubic hole, automatic field points",
    },
    Demo {
        name: "two-bodies",
        summary: "3D: a sphere and an ellipsoid in a box, automatic field points",
    },
    Demo {
        name: "blocks",
        summary: "3D: three cubes sharing internal walls, a region each (several materials), \
                  automatic field points",
    },
];

/// The paper's Table 2 (double ellipsoid): `(row, value)` in the paper's order.
pub const PAPER_TABLE2: &[(&str, usize)] = &[
    ("surface points", 3309),
    ("field points", 22032),
    ("surface faces", 6614),
    ("surface edges", 9921),
    ("tetrahedra obtained", 139436),
    ("edge recovery iterations", 11),
    ("points to seal missing faces", 0),
    ("tetrahedra outside domain", 9483),
    ("tetrahedra inside domain", 131213),
    ("surface points added", 205),
    ("surface edges added", 205),
    ("additional surface faces", 410),
];

/// Resolution of the double ellipsoid demos ([`geometry3::double_ellipsoid`]).
pub const DOUBLE_ELLIPSOID_N: usize = geometry3::DOUBLE_ELLIPSOID_N;

/// α of the `figure9` demo: gives about 22,000 field points, as in the paper (21,929 at 0.57;
/// 0.55 gave 24,794 once candidates were visited in Hilbert order, 0.58 gives 20,029).
pub const FIGURE9_ALPHA: f64 = 0.57;

/// Points per aerofoil element in the aerofoil demos (the mesh has about 50,000 triangles).
pub const AEROFOIL_POINTS: usize = 760;

/// What a demo produced.
#[derive(Clone, Debug)]
pub struct DemoOutput {
    /// Summary: points, cells, time; for the mesh demos whose run the command line can
    /// repeat, a second line with the `delmesh mesh` command that meshes the written domain
    /// the same.
    pub summary: String,
    /// Text to print (Table 1, or a mesh run's passes and quality), if the demo has any.
    pub table: Option<String>,
    /// The files written, in order.
    pub written: Vec<PathBuf>,
    /// The mesh run, for the 2D mesh-generation demos.
    pub mesh: Option<MeshRun2>,
    /// The mesh run, for the 3D mesh-generation demos.
    pub mesh3: Option<MeshRun3>,
}

/// Runs demo `name`, writing its files into `dir` (created if missing).
///
/// # Errors
/// [`Error::UnknownDemo`] for a name not in [`DEMOS`]; [`Error::Io`] if `dir` or a file cannot
/// be written.
pub fn run(name: &str, dir: &Path) -> Result<DemoOutput, Error> {
    let known = DEMOS.iter().any(|d| d.name == name) || name == "random2d";
    if !known {
        return Err(Error::UnknownDemo {
            name: name.to_string(),
            available: DEMOS.iter().map(|d| d.name).collect::<Vec<_>>().join(", "),
        });
    }
    std::fs::create_dir_all(dir).map_err(|source| IoError::Io {
        file: dir.to_path_buf(),
        source,
    })?;
    match name {
        "figure1" | "figure4" | "random2d" => {
            let (run, table) = if name == "figure1" {
                let run = figure1()?;
                let table = run.voronoi_table();
                (run, Some(table))
            } else {
                (random2d()?, None)
            };
            let mut written = run.write(&dir.join(format!("{name}.vtu")))?;
            let voronoi = dir.join(format!("{name}-voronoi.vtu"));
            run.write_voronoi(&voronoi)?;
            written.push(voronoi);
            Ok(DemoOutput {
                summary: format!(
                    "{name}: {} points, {} cells, built in {:.6} s",
                    run.num_input_points(),
                    run.num_cells(),
                    run.build_seconds
                ),
                table,
                written,
                mesh: None,
                mesh3: None,
            })
        }
        "table2" | "figure9" | "sphere" | "cubic-hole" | "two-bodies" | "blocks" => {
            mesh3_demo(name, dir)
        }
        _ => mesh_demo(name, dir),
    }
}

/// The [`Plc2`] and options of mesh demo `name`.
///
/// # Errors
/// [`Error::UnknownDemo`] for a name that is not a mesh demo.
pub fn mesh_demo_setup(name: &str) -> Result<(Plc2, MeshOptions2), Error> {
    let mut options = MeshOptions2::default();
    let plc = match name {
        "figure8" => {
            options.generation = None;
            options.smoothing = None;
            geometry::figure8()
        }
        "figure7" => {
            options.recovery = RecoveryMethod::APriori;
            geometry::coastline()
        }
        "figure10a" => {
            options.generation = None;
            options.extra_points = geometry::component_mesh_points(AEROFOIL_POINTS);
            geometry::two_element_aerofoil(AEROFOIL_POINTS)
        }
        "figure10b" | "figure11" => geometry::two_element_aerofoil(AEROFOIL_POINTS),
        "figure12" => {
            let (plc, background) = geometry::figure12();
            options.spacing = Spacing::Background(background);
            plc
        }
        "figure13" => {
            let (plc, background) = geometry::figure13_cfd();
            options.spacing = Spacing::Background(background);
            plc
        }
        _ => {
            return Err(Error::UnknownDemo {
                name: name.to_string(),
                available: DEMOS.iter().map(|d| d.name).collect::<Vec<_>>().join(", "),
            })
        }
    };
    Ok((plc, options))
}

/// The `delmesh mesh` options that give 2D demo `name`'s mesh from the `.poly` file it writes
/// (with `--points` and the points file it writes beside it, for `figure10a`); `None` where
/// the demo's spacing comes from a background mesh the command line would need as a file.
pub fn cli_flags(name: &str) -> Option<String> {
    let flags = match name {
        "figure7" => " --recovery a-priori",
        "figure8" => " --no-points --no-smoothing",
        "figure10a" => " --no-points",
        "figure10b" | "figure11" => "",
        _ => return None,
    };
    Some(flags.into())
}

/// After demo `name` wrote its domain to `domain`: writes its extra points (`dim`
/// coordinates each, if any) as `NAME-points.node`, adds both to `written`, and returns the
/// summary's line with the `delmesh mesh` command that meshes them the same (`flags`; empty
/// if the command line cannot).
fn same_from_cli(
    dir: &Path,
    name: &str,
    domain: &Path,
    dim: usize,
    points: &[f64],
    flags: Option<String>,
    written: &mut Vec<PathBuf>,
) -> Result<String, Error> {
    written.push(domain.to_path_buf());
    let mut points_flag = String::new();
    if !points.is_empty() {
        let path = dir.join(format!("{name}-points.node"));
        delmesh_io::write_node(&path, dim, points, 1)?;
        points_flag = format!(" --points {}", path.display());
        written.push(path);
    }
    Ok(flags.map_or_else(String::new, |flags| {
        format!(
            "\nthe same mesh from the command line: delmesh mesh {}{flags}{points_flag} -o {name}.vtu",
            domain.display()
        )
    }))
}

fn mesh_demo(name: &str, dir: &Path) -> Result<DemoOutput, Error> {
    let (plc, options) = mesh_demo_setup(name)?;
    let mut written = Vec::new();
    if name == "figure8" {
        // The Delaunay triangulation of the boundary points, before recovery (Fig. 5).
        let tri = Triangulation2::new(&plc.points).map_err(|e| Error::Internal(e.to_string()))?;
        let coords: Vec<f64> = (0..plc.points.len())
            .flat_map(|i| tri.vertex(tri.vertex_of_input(i)))
            .collect();
        let cells = tri.cells_in_input_numbering();
        let edges: Vec<[u32; 2]> = plc.segments.iter().map(|s| [s.a, s.b]).collect();
        let markers: Vec<i32> = plc.segments.iter().map(|s| s.marker).collect();
        let path = dir.join("figure8-delaunay.svg");
        delmesh_io::write_svg(
            &path,
            &delmesh_io::SvgMesh {
                coords: &coords,
                triangles: &cells,
                segments: &edges,
                segment_markers: &markers,
                cell_values: None,
            },
            &delmesh_io::SvgOptions::default(),
        )?;
        written.push(path);
    }
    if name == "figure11" {
        // The mesh after 1, 2, 4 and 8 passes of point generation (no smoothing).
        for passes in [1, 2, 4, 8] {
            let mut opts = options.clone();
            opts.smoothing = None;
            opts.generation = opts.generation.map(|g| PointGeneration {
                max_passes: passes,
                ..g
            });
            let run = mesh_plc(&plc, &opts)?;
            written.extend(run.write(&dir.join(format!("figure11-pass{passes}.svg")))?);
        }
    }
    let run = mesh_plc(&plc, &options)?;
    written.extend(run.write(&dir.join(format!("{name}.vtu")))?);
    written.extend(run.write(&dir.join(format!("{name}.svg")))?);
    // The domain, for `delmesh mesh` to mesh again with other options or into other formats.
    let poly = dir.join(format!("{name}.poly"));
    delmesh_io::write_poly(&poly, &crate::mesh2d::poly_from_plc(&plc))?;
    let points: Vec<f64> = options.extra_points.iter().flatten().copied().collect();
    let again = same_from_cli(dir, name, &poly, 2, &points, cli_flags(name), &mut written)?;
    let total: f64 = run.timings.iter().map(|t| t.1).sum();
    Ok(DemoOutput {
        summary: format!(
            "{name}: {} points, {} triangles in {total:.6} s{again}",
            run.arrays.coords.len(),
            run.arrays.triangles.len()
        ),
        table: Some(run.summary()),
        written,
        mesh: Some(run),
        mesh3: None,
    })
}

/// The [`Plc3`] and options of 3D mesh demo `name`.
///
/// # Errors
/// [`Error::UnknownDemo`] for a name that is not a 3D mesh demo.
pub fn mesh3_demo_setup(name: &str) -> Result<(Plc3, MeshOptions3), Error> {
    let mut options = MeshOptions3::default();
    let plc = match name {
        "table2" => {
            options.generation = None;
            options.extra_points = geometry3::double_ellipsoid_shells(DOUBLE_ELLIPSOID_N);
            geometry3::double_ellipsoid(DOUBLE_ELLIPSOID_N)
        }
        "figure9" => {
            options.generation = Some(PointGeneration3 {
                alpha: FIGURE9_ALPHA,
                ..PointGeneration3::default()
            });
            geometry3::double_ellipsoid(DOUBLE_ELLIPSOID_N)
        }
        "sphere" => geometry3::sphere_in_box(8),
        "cubic-hole" => geometry3::cube_with_cubic_hole(10),
        "two-bodies" => geometry3::two_bodies(6),
        "blocks" => geometry3::blocks(3, 8),
        _ => {
            return Err(Error::UnknownDemo {
                name: name.to_string(),
                available: DEMOS.iter().map(|d| d.name).collect::<Vec<_>>().join(", "),
            })
        }
    };
    Ok((plc, options))
}

/// The `delmesh mesh` options that give 3D demo `name`'s mesh from the `.smesh` file it
/// writes (with `--points` and the points file it writes beside it, for `table2`).
pub fn cli_flags3(name: &str) -> Option<String> {
    match name {
        "table2" => Some(" --no-points".into()),
        "figure9" => Some(format!(" --alpha {FIGURE9_ALPHA}")),
        "sphere" | "cubic-hole" | "two-bodies" | "blocks" => Some(String::new()),
        _ => None,
    }
}

fn mesh3_demo(name: &str, dir: &Path) -> Result<DemoOutput, Error> {
    let (plc, options) = mesh3_demo_setup(name)?;
    let run = mesh_plc3(&plc, &options)?;
    let mut written = run.write(&dir.join(format!("{name}.vtu")))?;
    // The domain, for `delmesh mesh` to mesh again with other options or into other formats.
    let smesh = dir.join(format!("{name}.smesh"));
    delmesh_io::write_smesh(&smesh, &crate::mesh3d::surface_from_plc3(&plc))?;
    let points: Vec<f64> = options.extra_points.iter().flatten().copied().collect();
    let again = same_from_cli(
        dir,
        name,
        &smesh,
        3,
        &points,
        cli_flags3(name),
        &mut written,
    )?;
    let total: f64 = run.timings.iter().map(|t| t.1).sum();
    let mut table = run.summary();
    if name == "table2" {
        table.push_str(&table2_comparison(&run.recovery));
    }
    Ok(DemoOutput {
        summary: format!(
            "{name}: {} points, {} tetrahedra in {total:.6} s{again}",
            run.arrays.coords.len(),
            run.arrays.tets.len()
        ),
        table: Some(table),
        written,
        mesh: None,
        mesh3: Some(run),
    })
}

/// The paper's Table 2 beside delmesh's numbers for the same rows.
pub fn table2_comparison(h: &RecoveryHistory3) -> String {
    let iterations = h
        .steps
        .iter()
        .filter(|s| matches!(s, RecoveryStep::Edges { .. }))
        .count();
    let ours = [
        h.surface_points,
        h.field_points,
        h.surface_faces,
        h.surface_edges,
        h.initial_tetrahedra,
        iterations,
        h.face_points,
        h.tetrahedra_outside,
        h.tetrahedra_inside,
        h.points_added(),
        h.final_surface_edges.saturating_sub(h.surface_edges),
        h.final_surface_faces.saturating_sub(h.surface_faces),
    ];
    let mut s = format!(
        "\nTable 2, double ellipsoid: the paper (Weatherill) and delmesh\n{:<32} {:>10} {:>10}\n",
        "", "paper", "delmesh"
    );
    for ((label, paper), ours) in PAPER_TABLE2.iter().zip(ours) {
        s.push_str(&format!("{label:<32} {paper:>10} {ours:>10}\n"));
    }
    s.push_str(
        "(delmesh's surface includes its box far field; the paper's far field is not given)\n",
    );
    s
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
