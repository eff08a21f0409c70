//! The `delmesh` command-line tool: Delaunay triangulations of point files, and demos.
//!
//! A thin layer over the library ([`delmesh::delaunay`], [`delmesh::demos`]) so that what the
//! tests exercise through the library is what users run. Results and tables go to stdout;
//! the run summary (including the `build time: S s` line that `cargo xtask` parses) and progress
//! go to stderr. Any error prints as one `error: <message>` line naming the file (and line, for
//! malformed input) and exits with status 1; command-line usage errors are clap's (status 2).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Result;
use clap::{Args, Parser, Subcommand, ValueEnum};
use delmesh::delaunay::{
    check_not_folders, check_not_input, check_output_dir, triangulate_file, DelaunayRun,
    OutputFormat,
};
use delmesh::demos;
use delmesh::io::AnyPoly;
use delmesh::mesh2d::{self, MeshOptions2, Spacing};
use delmesh::mesh3d::{self, MeshOptions3, Spacing3};
use delmesh::point_gen::{
    Adaptation, PointGeneration, PointGeneration3, QualityRefinement3, Source, Source3,
};
use delmesh::recovery::{RecoveryMethod, RecoveryMethod3};
use delmesh::smoothing::{Smoother, Smoother3};

/// How many duplicate pairs the summary lists.
const DUPLICATES_SHOWN: usize = 5;

/// Delaunay mesh generation for computational fluid dynamics.
#[derive(Parser, Debug)]
#[command(name = "delmesh", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Delaunay triangulation (2D) or tetrahedralisation (3D) of a point file.
    Delaunay(DelaunayArgs),
    /// Mesh a 2D domain (Triangle .poly) or the volume inside a 3D surface (.smesh, 3D .poly,
    /// .off, .stl, .obj, .ply, .mesh, .msh): boundary recovery, exterior deletion, automatic points,
    /// smoothing (the paper's whole method).
    Mesh(Box<MeshArgs>),
    /// Reproduce a figure of the paper; without NAME, list the demos.
    Demo(DemoArgs),
}

/// How boundary segments missing from the Delaunay triangulation are recovered.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum RecoveryArg {
    /// Insert mid-points of missing segments until all are present (the paper's R4).
    Stitch,
    /// One interior point per boundary edge first, then stitching (R5).
    APriori,
    /// Edge flips, no point added on the boundary (constrained Delaunay); in 3D, edge and
    /// face flips first, points only where flips stop short.
    Constrained,
}

#[derive(Args, Debug)]
#[command(group(clap::ArgGroup::new("field_mesh").args(["background", "adapt"])))]
struct MeshArgs {
    /// The domain: a Triangle .poly file (points, segments with markers, holes, regions with
    /// attributes and area limits, honoured when points are generated), or a
    /// closed 3D surface triangulation (.smesh, 3D .poly, .off, .stl, .obj, .ply, .mesh, .msh).
    /// Unlike Triangle, closed loops (surfaces) nested in each other alternate between domain
    /// and hole from the outside in, so a body inside a far field needs no hole seed; a
    /// region seed keeps the part it lies in.
    #[arg(value_name = "INPUT")]
    input: PathBuf,
    /// Output file(s), by extension. 2D: .vtu (ParaView), .ele (Triangle .node/.ele/.edge with
    /// markers), .msh (gmsh 4.1, markers and regions as physical groups), .su2 (SU2, boundary
    /// edges as marker_<m>), .svg (a picture). 3D: .vtu (+ X.boundary.vtu), .ele (TetGen .node/.ele/.face),
    /// .msh (gmsh 4.1), .mesh (Medit), .su2. Both: a path named polyMesh (e.g.
    /// case/constant/polyMesh, its parent folder existing) is an OpenFOAM mesh, a patch per
    /// marker (2D: one layer of prisms, front and back an empty patch). Repeat for several.
    #[arg(short, long, value_name = "OUT", required = true)]
    output: Vec<PathBuf>,
    /// Boundary recovery method.
    #[arg(long, value_enum, default_value = "stitch")]
    recovery: RecoveryArg,
    /// Point density: a candidate must be farther than alpha·spacing from the element's nodes.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    alpha: f64,
    /// Add at most this many points inside the domain automatically (generation and quality
    /// refinement together; the points recovery puts on the boundary are not counted).
    #[arg(long, value_name = "N")]
    max_points: Option<usize>,
    /// 2D: the spacing interpolated from an element's nodes is at least the candidate's
    /// distance to them over R, so small holes or features grade out instead of filling the
    /// domain at their spacing; `inf` is the paper's interpolation as it is.
    #[arg(
        long,
        value_name = "R",
        default_value_t = 64.0,
        allow_negative_numbers = true
    )]
    grading_limit: f64,
    /// No automatic points: mesh the boundary (and --points) only.
    #[arg(long)]
    no_points: bool,
    /// Extra points to triangulate with the boundary (.node or plain text); points outside the
    /// domain are dropped (the paper's points from component meshes).
    #[arg(long, value_name = "FILE")]
    points: Option<PathBuf>,
    /// Background mesh giving the spacing: a .vtu or legacy .vtk with a point field (see
    /// --field; any linear cells), or a Triangle .ele whose .node has one attribute.
    #[arg(long, value_name = "MESH", conflicts_with = "adapt")]
    background: Option<PathBuf>,
    /// Adapt to a previous solution: a .vtu or legacy .vtk mesh whose point field --field (e.g.
    /// pressure or Mach) is turned into spacing by its gradient, between --min-spacing and
    /// --max-spacing.
    #[arg(long, value_name = "MESH", requires_all = ["min_spacing", "max_spacing"])]
    adapt: Option<PathBuf>,
    /// The point field of --background (default `spacing`) or --adapt.
    #[arg(long, value_name = "NAME", requires = "field_mesh")]
    field: Option<String>,
    /// Smallest spacing of --adapt.
    #[arg(
        long,
        value_name = "H",
        allow_negative_numbers = true,
        requires = "adapt"
    )]
    min_spacing: Option<f64>,
    /// Largest spacing of --adapt.
    #[arg(
        long,
        value_name = "H",
        allow_negative_numbers = true,
        requires = "adapt"
    )]
    max_spacing: Option<f64>,
    /// A spacing source: spacing H0 within RADIUS of a point or a segment, growing by GROWTH
    /// per unit distance beyond; the spacing is the smallest of the field's and the sources'.
    /// 2D: `x,y,H0,RADIUS,GROWTH` or `x1,y1,x2,y2,H0,RADIUS,GROWTH`; 3D: `x,y,z,...` or
    /// `x1,y1,z1,x2,y2,z2,...`. Repeat for several.
    #[arg(long, value_name = "SPEC", allow_hyphen_values = true)]
    source: Vec<String>,
    /// Smoothing relaxation factor ω (paper: 0.05–0.25; default 0.25 in 2D, 0.2 in 3D).
    #[arg(long, allow_negative_numbers = true)]
    omega: Option<f64>,
    /// Smoothing passes N (paper: 20–50; default 24 in 2D, 4 in 3D, where the Delaunay
    /// restoration that follows re-triangulates the points).
    #[arg(long)]
    iterations: Option<usize>,
    /// No smoothing.
    #[arg(long)]
    no_smoothing: bool,
    /// Keep the smoothed connectivity (no Delaunay edge flips after smoothing; in 3D, no final
    /// Delaunay restoration).
    #[arg(long)]
    no_flips: bool,
    /// 3D: at the end, flip away tetrahedra whose smallest dihedral angle is below DEG degrees
    /// (e.g. 10 or 15) where edge and face flips improve the worst element around them (beyond
    /// the paper; the mesh is then no longer Delaunay where flips were made). With
    /// `--recovery constrained`, whose mesh is not Delaunay anyway, 0.0001 unless given: only
    /// elements flat to rounding.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    sliver_flips: Option<f64>,
    /// 3D: no radius–edge refinement (circumcentres of tetrahedra whose circumradius exceeds
    /// twice their shortest edge) after point generation.
    #[arg(long)]
    no_refinement: bool,
    /// 3D: the most points surface recovery may add before it stops with an error naming the
    /// facets that resisted.
    #[arg(long, value_name = "N")]
    max_steiner: Option<usize>,
    /// 3D: re-triangulate exactly coplanar neighbouring surface triangles with the same marker
    /// together (flipping their shared diagonals), as TetGen merges coplanar facets by default:
    /// fewer points on flat surfaces, but an input triangle is then not always a union of
    /// boundary faces. Without it only the triangles of one polygon facet are re-triangulated.
    /// Where even the merged surface would cost more than 20 points per surface point,
    /// triangles flat to rounding are merged too.
    #[arg(long)]
    merge_coplanar: bool,
    /// 3D: keep every input triangle even where that costs more than 20 points per surface
    /// point (at least 5,000): recovery then never merges coplanar facets, and stops with an
    /// error at `--max-steiner`'s bound. By default such a surface (a CAD part whose flat
    /// faces are fans of long thin triangles) is recovered again with coplanar facets merged,
    /// as `--merge-coplanar` does, and triangles flat to rounding too (thinner than 2^-40 of
    /// their coordinates); the summary says so.
    #[arg(long, conflicts_with = "merge_coplanar")]
    keep_facets: bool,
    /// 3D: remesh the surface at spacing H before meshing: each planar patch (exactly coplanar
    /// neighbouring triangles with one marker) with an edge longer than H is meshed in its
    /// plane, its boundary edges cut into equal pieces shared with the patch beyond (markers
    /// kept); the field points follow. For CAD surfaces (STL exports) whose long thin
    /// triangles otherwise make flat tetrahedra.
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    surface_spacing: Option<f64>,
    /// Write the run's report (passes, quality, time per stage) as JSON.
    #[arg(long, value_name = "FILE.json")]
    report: Option<PathBuf>,
    /// Check the mesh exactly (adjacency, orientation, constrained Delaunay; not the last
    /// after a 3D `--recovery constrained`, which is not Delaunay where it flipped) and print
    /// `validation: ok`.
    #[arg(long)]
    validate: bool,
    /// Print only the `mesh time:` line.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Args, Debug)]
struct DelaunayArgs {
    /// Input points: a TetGen/Triangle .node file, or plain text with `x y [z]` per line.
    #[arg(value_name = "INPUT")]
    input: PathBuf,
    /// Output mesh: .vtu (VTK XML, for ParaView) or .ele (writes X.node, X.ele and X.neigh,
    /// numbered like the input, as TetGen does).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
    /// Also write the Voronoi cells (2D) or faces of the bounded Voronoi cells (3D) as polygons
    /// to this .vtu file.
    #[arg(long, value_name = "CELLS.vtu")]
    voronoi: Option<PathBuf>,
    /// No progress bar, and no summary except the `build time:` line.
    #[arg(short, long)]
    quiet: bool,
    /// Check the result exactly (adjacency, orientation, empty circumspheres, Euler) and print
    /// `validation: ok`; exit with status 1 if any check fails.
    #[arg(long)]
    validate: bool,
}

#[derive(Args, Debug)]
struct DemoArgs {
    /// The demo to run (omit to list them).
    #[arg(value_name = "NAME")]
    name: Option<String>,
    /// Directory for the demo's output files (created if missing).
    #[arg(short, long, value_name = "DIR", default_value = "delmesh-demo-out")]
    output: PathBuf,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Ctrl-C (or a kill) while outputs are being written would leave their temporary files
    // beside them, as large as the mesh: they are removed (the outputs themselves are only
    // ever replaced whole). Without a handler the run still stops, only less tidily.
    let _ = ctrlc::set_handler(|| {
        delmesh::io::remove_temporary_files();
        eprintln!("error: interrupted");
        std::process::exit(130);
    });
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", message(&e));
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Delaunay(args) => delaunay(&args),
        Command::Mesh(args) => mesh(&args),
        Command::Demo(args) => demo(&args),
    }
}

/// The error and its causes in one line, skipping causes whose text the message already
/// contains (library errors include their cause's text).
fn message(e: &anyhow::Error) -> String {
    let mut msg = e.to_string();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !msg.contains(&text) {
            msg.push_str(": ");
            msg.push_str(&text);
        }
    }
    msg
}

/// Writes `text` to stdout; a closed pipe (`delmesh demo | head`) is not an error.
fn print_stdout(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(anyhow::Error::new(e).context("cannot write to standard output"))
        }
        _ => Ok(()),
    }
}

fn delaunay(args: &DelaunayArgs) -> Result<()> {
    // Check the output paths before spending time on the triangulation.
    let mut outputs = OutputFormat::from_path(&args.output)?.files(&args.output);
    check_output_dir(&args.output)?;
    if let Some(voronoi) = &args.voronoi {
        OutputFormat::check_voronoi_path(voronoi)?;
        check_output_dir(voronoi)?;
        if outputs.contains(voronoi) {
            anyhow::bail!(
                "{}: given both as the mesh output and as the --voronoi output",
                voronoi.display()
            );
        }
        outputs.push(voronoi.clone());
    }
    check_not_input(&args.input, &outputs)?;
    check_not_folders(&outputs)?;
    let run = triangulate_file(&args.input, !args.quiet)?;
    if args.quiet {
        eprintln!("build time: {:.6} s", run.build_seconds);
    } else {
        eprint!("{}", summary(&run));
    }
    if args.validate {
        let t0 = std::time::Instant::now();
        run.validate()
            .map_err(|e| anyhow::anyhow!("{}: validation failed: {e}", args.input.display()))?;
        eprintln!("validation: ok ({:.3} s)", t0.elapsed().as_secs_f64());
    }
    // The mesh and its Voronoi diagram are replaced together or not at all.
    let mut polygons = None;
    let written = delmesh::io::transaction(|| {
        let mut written = run.write(&args.output)?;
        if let Some(voronoi) = &args.voronoi {
            polygons = Some(run.write_voronoi(voronoi)?);
            written.push(voronoi.clone());
        }
        anyhow::Ok(written)
    })?;
    if !args.quiet {
        print_written(&written);
    }
    if polygons == Some(0) {
        // (3D: every point on the hull; the file is valid VTK with no cell.)
        eprintln!(
            "warning: the Voronoi file holds no polygon: no point lies strictly inside the \
             convex hull, so no Voronoi region is bounded"
        );
    }
    Ok(())
}

/// The run summary printed on stderr (one fact per line).
fn summary(run: &DelaunayRun) -> String {
    let (cells, facets) = if run.dim() == 2 {
        ("triangles", "edges")
    } else {
        ("tetrahedra", "triangles")
    };
    let duplicates = run.duplicates();
    let mut s = format!(
        "input: {}\ndimension: {}\npoints read: {}\nduplicates merged: {}\n",
        run.input.display(),
        run.dim(),
        run.num_input_points(),
        duplicates.len()
    );
    for (dup, original) in duplicates.iter().take(DUPLICATES_SHOWN) {
        s.push_str(&format!("  input {dup} repeats input {original}\n"));
    }
    if duplicates.len() > DUPLICATES_SHOWN {
        s.push_str(&format!(
            "  ... and {} more\n",
            duplicates.len() - DUPLICATES_SHOWN
        ));
    }
    s.push_str(&format!(
        "vertices: {}\ncells: {} {cells}\nhull facets: {} {facets}\nbuild time: {:.6} s\n",
        run.num_vertices(),
        run.num_cells(),
        run.num_hull_facets(),
        run.build_seconds
    ));
    s
}

fn print_written(paths: &[PathBuf]) {
    for p in paths {
        eprintln!("wrote: {}", p.display());
    }
}

fn demo(args: &DemoArgs) -> Result<()> {
    let Some(name) = &args.name else {
        let mut text = String::from("demos (run `delmesh demo NAME [-o DIR]`):\n");
        let width = demos::DEMOS.iter().map(|d| d.name.len()).max().unwrap_or(0);
        for d in demos::DEMOS {
            text.push_str(&format!("  {:width$}  {}\n", d.name, d.summary));
        }
        return print_stdout(&text);
    };
    let out = demos::run(name, &args.output)?;
    if let Some(table) = &out.table {
        print_stdout(table)?;
    }
    eprintln!("{}", out.summary);
    print_written(&out.written);
    Ok(())
}

fn mesh(args: &MeshArgs) -> Result<()> {
    for out in args.output.iter().chain(&args.report) {
        check_output_dir(out)?;
    }
    check_mesh_files(args)?;
    let is_poly = args
        .input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("poly"));
    let plc = if mesh3d::is_surface_input(&args.input) {
        return mesh3(args, mesh3d::read_plc3(&args.input)?);
    } else if is_poly {
        match delmesh::io::read_poly_any(&args.input)? {
            AnyPoly::TetGen(surface) => {
                return mesh3(args, mesh3d::plc3_from_surface(surface, &args.input)?)
            }
            AnyPoly::Triangle(poly) => mesh2d::plc_from_poly(&poly),
        }
    } else {
        // Anything else was read as a Triangle .poly, and a PLY or a .txt surface then failed
        // with a parse error on some line of it.
        let ext = args.input.extension().map_or_else(
            || "no extension".to_string(),
            |e| format!("'.{}'", e.to_string_lossy()),
        );
        anyhow::bail!(
            "{}: unknown input format ({ext}): `delmesh mesh` reads a Triangle .poly (2D) or a \
             surface ({})",
            args.input.display(),
            mesh3d::SURFACE_INPUTS
        );
    };
    for out in &args.output {
        if !delmesh_io::is_polymesh(out)
            && !matches!(
                out.extension().and_then(|e| e.to_str()),
                Some("vtu" | "ele" | "msh" | "su2" | "svg")
            )
        {
            anyhow::bail!(
                "{}: unsupported output format (supported: {})",
                out.display(),
                mesh2d::MESH_OUTPUTS
            );
        }
    }
    let mut options = MeshOptions2 {
        recovery: match args.recovery {
            RecoveryArg::Stitch => RecoveryMethod::Stitch,
            RecoveryArg::APriori => RecoveryMethod::APriori,
            RecoveryArg::Constrained => RecoveryMethod::Constrained,
        },
        ..MeshOptions2::default()
    };
    let mut points_first = 0;
    if let Some(path) = &args.points {
        let pts = delmesh::io::read_points(path)?;
        // Three columns are taken for a 2D mesh only in the plane z = 0 (as 2D meshes are
        // often written); a z elsewhere would be dropped silently.
        if pts.dim == 3 {
            if let Some(i) = (0..pts.len()).find(|&i| pts.coords[3 * i + 2] != 0.0) {
                anyhow::bail!(
                    "{}: point {} has z = {}: the field points of a 2D mesh must be 2D (or \
                     lie in the plane z = 0)",
                    path.display(),
                    i + pts.first_index as usize,
                    pts.coords[3 * i + 2]
                );
            }
        }
        options.extra_points = (0..pts.len()).map(|i| pts.point2(i)).collect();
        points_first = pts.first_index;
    }
    options.generation = (!args.no_points).then(|| PointGeneration {
        alpha: args.alpha,
        grading_limit: args.grading_limit,
        max_points: args.max_points.unwrap_or(usize::MAX),
        ..PointGeneration::default()
    });
    if let Some(path) = &args.background {
        options.spacing =
            Spacing::Background(mesh2d::read_background(path, args.field.as_deref())?);
    }
    if let Some(path) = &args.adapt {
        let field = args
            .field
            .as_deref()
            .ok_or_else(|| anyhow::anyhow!("--adapt needs --field NAME (the solution field)"))?;
        let adaptation = Adaptation::new(
            args.min_spacing.unwrap_or_default(),
            args.max_spacing.unwrap_or_default(),
        );
        options.spacing = Spacing::Background(mesh2d::read_adaptation(path, field, &adaptation)?);
    }
    for spec in &args.source {
        let (a, b, [h0, radius, growth]) = source_numbers(spec, 2)?;
        options.sources.push(Source {
            a: [a[0], a[1]],
            b: [b[0], b[1]],
            h0,
            radius,
            growth,
        });
    }
    options.smoothing = if args.no_smoothing {
        None
    } else {
        let mut smoother = Smoother::new().iterations(
            args.iterations
                .unwrap_or(delmesh::smoothing::DEFAULT_ITERATIONS),
        );
        if let Some(omega) = args.omega {
            smoother = smoother.omega(omega)?;
        }
        Some(smoother)
    };
    options.delaunay_flips = !args.no_flips;
    let first_extra = plc.points.len() as u64 + u64::from(plc.first_index);
    let run = mesh2d::mesh_plc(&plc, &options)
        .map_err(|e| name_the_file(e, args, first_extra, points_first))?;
    let total: f64 = run.timings.iter().map(|t| t.1).sum();
    if args.quiet {
        eprintln!("mesh time: {total:.6} s");
    } else {
        eprint!("input: {}\n{}", args.input.display(), run.summary());
    }
    if args.validate {
        // Smoothed points without the Delaunay flips after them need not be Delaunay.
        let check = if run.smoothing.is_some() && !options.delaunay_flips {
            run.mesh.cdt.validate_structure()
        } else {
            run.mesh.cdt.validate()
        };
        check.map_err(|e| anyhow::anyhow!("{}: validation failed: {e}", args.input.display()))?;
        eprintln!("validation: ok");
    }
    write_mesh_outputs(args, |out| Ok(run.write(out)?), &run.report_json())
}

/// A meshing error with the file it is about: the domain's, or for a point numbered from
/// `first_extra` on (past the domain's points) the `--points` file, whose points are numbered
/// from `points_first`, with the point numbered as there (it was blamed on the domain's file,
/// as a point the domain does not have).
fn name_the_file(
    e: delmesh::Error,
    args: &MeshArgs,
    first_extra: u64,
    points_first: u32,
) -> anyhow::Error {
    use delmesh::core::TriangulationError as T;
    use delmesh::recovery::RecoveryError as R;
    if let (Some(points), delmesh::Error::Recovery(R::Triangulation(t))) = (&args.points, &e) {
        let renumber = |index: usize| {
            (index as u64 >= first_extra)
                .then(|| (index as u64 - first_extra + u64::from(points_first)) as usize)
        };
        let moved = match *t {
            T::NonFinite { index, axis, value } => {
                renumber(index).map(|index| T::NonFinite { index, axis, value })
            }
            T::CoordinateRange {
                index,
                value,
                largest,
            } => renumber(index).map(|index| T::CoordinateRange {
                index,
                value,
                largest,
            }),
            _ => None,
        };
        if let Some(t) = moved {
            return anyhow::anyhow!("{}: {t}", points.display());
        }
    }
    anyhow::anyhow!("{}: {e}", args.input.display())
}

/// The numbers of a `--source` value for a `dim`-dimensional mesh: one point (a point source)
/// or two (a segment), then H0 > 0, RADIUS ≥ 0 and GROWTH ≥ 0, all finite.
fn source_numbers(spec: &str, dim: usize) -> Result<(Vec<f64>, Vec<f64>, [f64; 3])> {
    let bad = |why: String| anyhow::anyhow!("--source {spec}: {why}");
    let numbers = spec
        .split(',')
        .map(|t| {
            let t = t.trim();
            match t.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(bad(format!("`{t}` is not a finite number"))),
            }
        })
        .collect::<Result<Vec<f64>>>()?;
    let ends = match numbers.len() {
        n if n == dim + 3 => 1,
        n if n == 2 * dim + 3 => 2,
        n => {
            return Err(bad(format!(
                "{n} numbers; a {dim}D source takes {} (a point) or {} (a segment): \
                 coordinates, then H0,RADIUS,GROWTH",
                dim + 3,
                2 * dim + 3
            )))
        }
    };
    let a = numbers[..dim].to_vec();
    let b = numbers[(ends - 1) * dim..ends * dim].to_vec();
    let [h0, radius, growth] = [0, 1, 2].map(|k| numbers[ends * dim + k]);
    if h0 <= 0.0 {
        return Err(bad(format!("spacing H0 must be positive (got {h0:?})")));
    }
    if radius < 0.0 || growth < 0.0 {
        return Err(bad(format!(
            "RADIUS and GROWTH must not be negative (got {radius:?}, {growth:?})"
        )));
    }
    Ok((a, b, [h0, radius, growth]))
}

/// `delmesh mesh` on a 3D surface: recovery (Table 2), field points, Delaunay restoration.
fn mesh3(args: &MeshArgs, plc: delmesh::recovery::Plc3) -> Result<()> {
    for out in &args.output {
        let ext = out
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        if !delmesh_io::is_polymesh(out)
            && !matches!(
                ext.as_str(),
                "vtu" | "ele" | "node" | "face" | "msh" | "mesh" | "su2"
            )
        {
            anyhow::bail!(
                "{}: unsupported output format for a 3D mesh (supported: {})",
                out.display(),
                mesh3d::MESH3_OUTPUTS
            );
        }
        // Medit numbers regions with integers: a region attribute it cannot hold is refused
        // now, not after the meshing.
        if ext == "mesh" {
            let integer = |a: f64| {
                a.fract() == 0.0 && (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&a)
            };
            if let Some((k, r)) = plc
                .regions
                .iter()
                .enumerate()
                .find(|(_, r)| !integer(r.attribute))
            {
                anyhow::bail!(
                    "{}: region {k} has attribute {:?}, which Medit's integer region numbers \
                     cannot hold",
                    out.display(),
                    r.attribute
                );
            }
        }
    }
    let mut options = MeshOptions3 {
        recovery: match args.recovery {
            RecoveryArg::Stitch => RecoveryMethod3::Conforming,
            RecoveryArg::APriori => RecoveryMethod3::APriori,
            RecoveryArg::Constrained => RecoveryMethod3::Constrained,
        },
        max_steiner_points: args.max_steiner,
        merge_coplanar: args.merge_coplanar,
        coplanar_fallback: !args.keep_facets,
        surface_spacing: args.surface_spacing,
        delaunay: !args.no_flips,
        sliver_flips: args.sliver_flips,
        refinement: (!args.no_refinement).then(QualityRefinement3::default),
        smoothing: if args.no_smoothing {
            None
        } else {
            let mut smoother =
                Smoother3::new().iterations(args.iterations.unwrap_or(mesh3d::SMOOTHING_PASSES));
            if let Some(omega) = args.omega {
                smoother = smoother.omega(omega)?;
            }
            Some(smoother)
        },
        ..MeshOptions3::default()
    };
    let mut points_first = 0;
    if let Some(path) = &args.points {
        let pts = delmesh::io::read_points(path)?;
        if pts.dim != 3 {
            anyhow::bail!(
                "{}: the field points of a 3D mesh must be 3D",
                path.display()
            );
        }
        options.extra_points = (0..pts.len()).map(|i| pts.point3(i)).collect();
        points_first = pts.first_index;
    }
    options.generation = (!args.no_points).then(|| PointGeneration3 {
        alpha: args.alpha,
        max_points: args.max_points.unwrap_or(usize::MAX),
        ..PointGeneration3::default()
    });
    if let Some(path) = &args.background {
        options.spacing = Spacing3::Background(Box::new(mesh3d::read_background3(
            path,
            args.field.as_deref(),
        )?));
    }
    if let Some(path) = &args.adapt {
        let field = args
            .field
            .as_deref()
            .ok_or_else(|| anyhow::anyhow!("--adapt needs --field NAME (the solution field)"))?;
        let adaptation = Adaptation::new(
            args.min_spacing.unwrap_or_default(),
            args.max_spacing.unwrap_or_default(),
        );
        options.spacing = Spacing3::Background(Box::new(mesh3d::read_adaptation3(
            path,
            field,
            &adaptation,
        )?));
    }
    for spec in &args.source {
        let (a, b, [h0, radius, growth]) = source_numbers(spec, 3)?;
        options.sources.push(Source3 {
            a: [a[0], a[1], a[2]],
            b: [b[0], b[1], b[2]],
            h0,
            radius,
            growth,
        });
    }
    let first_extra = plc.points.len() as u64 + u64::from(plc.first_index);
    let run = mesh3d::mesh_plc3(&plc, &options)
        .map_err(|e| name_the_file(e, args, first_extra, points_first))?;
    let total: f64 = run.timings.iter().map(|t| t.1).sum();
    if args.quiet {
        eprintln!("mesh time: {total:.6} s");
    } else {
        eprint!("input: {}\n{}", args.input.display(), run.summary());
    }
    if args.validate {
        // A constrained recovery is not Delaunay next to the edges and faces it flipped in.
        // Nor are sliver flips, nor an incomplete restoration.
        let flipped = (run.recovery.method == RecoveryMethod3::Constrained
            && !run.recovery.constrained_fallback)
            || run
                .sliver_flips
                .is_some_and(|f| f.edge_flips + f.face_flips > 0)
            || matches!(
                run.restoration,
                Some(mesh3d::Restoration3::Incomplete { .. })
            );
        let check = if !flipped && (run.restoration.is_some() || options.generation.is_none()) {
            run.mesh.ct.validate()
        } else {
            run.mesh.ct.validate_structure()
        };
        check.map_err(|e| anyhow::anyhow!("{}: validation failed: {e}", args.input.display()))?;
        eprintln!("validation: ok");
    }
    write_mesh_outputs(args, |out| Ok(run.write(out)?), &run.report_json())
}

/// The files `delmesh mesh -o out` may write: the TetGen and Triangle families write three
/// files beside each other, a 3D `.vtu` its boundary beside it.
fn mesh_output_files(out: &Path) -> Vec<PathBuf> {
    if delmesh_io::is_polymesh(out) {
        return delmesh_io::POLYMESH_FILES
            .iter()
            .map(|f| out.join(f))
            .collect();
    }
    let ext = out
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match ext.as_str() {
        "ele" | "node" | "face" => ["node", "ele", "edge", "face"]
            .iter()
            .map(|e| out.with_extension(e))
            .collect(),
        "vtu" => vec![out.to_path_buf(), out.with_extension("boundary.vtu")],
        _ => vec![out.to_path_buf()],
    }
}

/// The `.node` file beside a `.poly` or `.smesh` file whose point section is empty (its points
/// are read from there).
fn node_companion(input: &Path) -> Option<PathBuf> {
    let ext = input.extension()?.to_str()?.to_ascii_lowercase();
    if ext != "poly" && ext != "smesh" {
        return None;
    }
    let text = std::fs::read_to_string(input).ok()?;
    let first = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .find(|l| !l.is_empty())?;
    (first.split_whitespace().next() == Some("0")).then(|| input.with_extension("node"))
}

/// Checks, before meshing, that no file `delmesh mesh` would write is one it reads (the
/// domain, the `.node` file its points are in, `--points`, `--background` with its `.node`,
/// `--adapt`), and that no two outputs are the same file: either would lose data silently.
fn check_mesh_files(args: &MeshArgs) -> Result<()> {
    let mut inputs = vec![args.input.clone()];
    inputs.extend(node_companion(&args.input));
    inputs.extend(args.points.iter().cloned());
    for field in [&args.background, &args.adapt].into_iter().flatten() {
        inputs.push(field.clone());
        if field
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("ele"))
        {
            inputs.push(field.with_extension("node"));
        }
    }
    // Each file written, with the option that names it.
    let mut outputs: Vec<(PathBuf, &Path)> = args
        .output
        .iter()
        .flat_map(|o| {
            mesh_output_files(o)
                .into_iter()
                .map(move |f| (f, o.as_path()))
        })
        .collect();
    outputs.extend(args.report.iter().map(|r| (r.clone(), r.as_path())));
    let files: Vec<PathBuf> = outputs.iter().map(|(f, _)| f.clone()).collect();
    for input in &inputs {
        check_not_input(input, &files)?;
    }
    check_not_folders(&files)?;
    // The same file named twice (an output that does not exist yet: by its folder and name).
    let key = |p: &Path| -> PathBuf {
        if let Ok(real) = p.canonicalize() {
            return real;
        }
        let dir = p
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        match (dir.canonicalize(), p.file_name()) {
            (Ok(d), Some(name)) => d.join(name),
            _ => p.to_path_buf(),
        }
    };
    let mut seen: Vec<(PathBuf, &Path)> = Vec::with_capacity(outputs.len());
    for (file, named_by) in outputs {
        let k = key(&file);
        if let Some((_, first)) = seen.iter().find(|(s, _)| *s == k) {
            anyhow::bail!(
                "{}: written by both {} and {}; choose different output names",
                file.display(),
                first.display(),
                named_by.display()
            );
        }
        seen.push((k, named_by));
    }
    Ok(())
}

/// Writes `delmesh mesh`'s outputs (each `-o` by `write`, then `--report`) and lists them.
fn write_mesh_outputs(
    args: &MeshArgs,
    write: impl Fn(&std::path::Path) -> Result<Vec<PathBuf>>,
    report_json: &str,
) -> Result<()> {
    // All replaced together or not at all: a full disk on the last file leaves every old one.
    let written = delmesh::io::transaction(|| {
        let mut written = Vec::new();
        for out in &args.output {
            written.extend(write(out)?);
        }
        if let Some(report) = &args.report {
            delmesh::io::write_atomic(report, |w| {
                w.write_all(report_json.as_bytes())
                    .map_err(|e| delmesh::io::IoError::Io {
                        file: report.clone(),
                        source: e,
                    })
            })?;
            written.push(report.clone());
        }
        anyhow::Ok(written)
    })?;
    if !args.quiet {
        print_written(&written);
    }
    Ok(())
}
