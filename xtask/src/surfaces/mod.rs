//! `cargo xtask surfaces`: delmesh's 3D meshes of closed surfaces next to TetGen's.
//!
//! Inputs: real surfaces from CGAL's example data (Debian `libcgal-demo`, unpacked at run
//! time under `target/xtask/`, see `tools::cgal_meshes`) and small generated ones
//! (`gen`). For each case, in `target/xtask/surfaces/<case>/`:
//!
//! 1. recovery only: `delmesh mesh X.off --no-points -o X.ele --report X.json` against
//!    `tetgen -pQ X.off` (`-p`: tetrahedralize the surface, recovering it with Steiner
//!    points where needed; `-Q`: quiet) and `tetgen -pMQ X.off` (`-M`: do not merge
//!    coplanar facets; by default TetGen merges facets coplanar within 1e-8 and
//!    re-triangulates them, an easier problem than recovering every input triangle, and
//!    one that moves nearly coplanar facets, which the checks below show);
//! 2. the full pipeline: `delmesh mesh X.off -o X.ele --report X.json` against
//!    `tetgen -pqQ X.off` (`-q`: quality mesh, radius-edge ratio bound 2);
//! 3. checks on delmesh's outputs (`mesh::check_mesh`: exact orientation, volume, coverage
//!    of every input facet, Euler characteristic, the boundary of the complex), on the
//!    report's bookkeeping, and on the expectation of the case: a surface that is closed
//!    and embedded must be recovered by delmesh (above all when TetGen recovers it: the
//!    issue's target); one that intersects itself must be *diagnosed*, i.e. delmesh must
//!    exit non-zero naming the intersecting facets. `tetgen -pd` (detect intersecting
//!    facets) runs on every input as the independent witness of which is which.
//!    TetGen's outputs get the same checks, reported but not asserted: they show the
//!    checks themselves are sound.
//!
//! TetGen 1.5 aborts (`terminate called after throwing an instance of 'int'`) on CGAL's
//! `.off` files that begin with `#` comment lines, so when TetGen fails on the raw file
//! it is run again on xtask's cleaned copy (comments gone, duplicate vertices merged,
//! unused vertices and degenerate triangles dropped), and the table says so. delmesh
//! always reads the raw file.
//!
//! Timings (GNU time, the whole run of each tool) are reported, never asserted; failed
//! checks make the command exit non-zero after the tables, each naming its case.

mod gen;
mod json;
mod mesh;
mod surface;
mod tools;

use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use crate::report::{self, markdown_table, mb};
use crate::{delmesh, reference, Ctx};

use json::Json;
use mesh::{CheckReport, Quality};
use surface::Surface;
use tools::Timed;

/// Options of `surfaces`.
pub struct SurfacesOptions {
    pub quick: bool,
    pub only: Vec<String>,
    pub report: Option<PathBuf>,
    /// The command line, for the report.
    pub command: String,
}

/// What a case's input should lead to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Expect {
    /// Closed and embedded: delmesh must mesh it.
    Mesh,
    /// Intersects itself: delmesh must refuse it, naming the intersecting facets.
    Diagnose,
}

/// Where a case's surface comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// `data/meshes/<name>.off` of CGAL's example data.
    Cgal,
    /// `gen::generate(name)`.
    Generated,
}

/// One case.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Case {
    pub name: &'static str,
    pub source: Source,
    pub expect: Expect,
    /// Part of `--quick`.
    pub quick: bool,
}

const fn cgal(name: &'static str, expect: Expect, quick: bool) -> Case {
    Case {
        name,
        source: Source::Cgal,
        expect,
        quick,
    }
}

/// The CGAL meshes, smallest first within each group. `sphere966` is small and has the
/// `#` header TetGen cannot read, so `--quick` exercises the cleaned-input path.
/// `diplodocus` intersects itself too (TetGen `-d`: 87 pairs) and has duplicate vertices.
pub const CGAL_CASES: &[Case] = &[
    cgal("elephant", Expect::Mesh, true),
    cgal("knot1", Expect::Mesh, true),
    cgal("fandisk", Expect::Mesh, true),
    cgal("sphere966", Expect::Mesh, true),
    cgal("eight", Expect::Mesh, false),
    cgal("couplingdown", Expect::Mesh, false),
    cgal("femur", Expect::Mesh, false),
    cgal("cheese", Expect::Mesh, false),
    cgal("turbine", Expect::Mesh, false),
    cgal("armadillo", Expect::Mesh, false),
    cgal("bunny00", Expect::Mesh, false),
    cgal("elk", Expect::Diagnose, false),
    cgal("cow", Expect::Diagnose, false),
    cgal("bull", Expect::Diagnose, false),
    cgal("camel", Expect::Diagnose, false),
    cgal("man", Expect::Diagnose, false),
    cgal("diplodocus", Expect::Diagnose, false),
];

/// Every case: the generated ones (all in `--quick`), then the CGAL meshes.
pub fn all_cases() -> Vec<Case> {
    let mut v: Vec<Case> = gen::GENERATED
        .iter()
        .map(|g| Case {
            name: g.name,
            source: Source::Generated,
            expect: Expect::Mesh,
            quick: true,
        })
        .collect();
    v.extend_from_slice(CGAL_CASES);
    v
}

/// The cases to run: `only` names (each must exist), else all or the quick subset.
pub fn select(quick: bool, only: &[String]) -> Result<Vec<Case>> {
    let all = all_cases();
    if only.is_empty() {
        return Ok(all.into_iter().filter(|c| !quick || c.quick).collect());
    }
    only.iter()
        .map(|name| {
            all.iter()
                .find(|c| c.name == name)
                .copied()
                .with_context(|| {
                    let names: Vec<&str> = all.iter().map(|c| c.name).collect();
                    format!("no surface case `{name}`; cases: {}", names.join(", "))
                })
        })
        .collect()
}

/// Time limit of one tool run, seconds.
fn limit(quick: bool) -> u64 {
    if quick {
        300
    } else {
        1800
    }
}

/// One run of one tool on one stage, and what was read back from it.
#[derive(Debug, Clone, Default)]
struct Run {
    timed: Timed,
    /// Exit 0 and the mesh read back.
    ok: bool,
    /// Why not, shortly (the tool's error line, or the reading error).
    why: String,
    steiner: Option<u64>,
    points: Option<usize>,
    tets: Option<usize>,
    /// delmesh: its boundary-recovery stage (report).
    recovery_secs: Option<f64>,
    quality: Option<Quality>,
    checks: Option<CheckReport>,
}

impl Run {
    fn recovered(&self) -> String {
        if self.ok {
            "yes".into()
        } else if self.timed.timed_out {
            "no (timeout)".into()
        } else {
            format!("no ({})", self.timed.status)
        }
    }

    fn tets_per_sec(&self) -> String {
        match (self.tets, self.timed.wall) {
            (Some(t), Some(w)) if w > 0.0 => format!("{:.0}", t as f64 / w),
            _ => "-".into(),
        }
    }

    fn checks_cell(&self) -> String {
        self.checks_cell_as("FAILED")
    }

    /// The checks' verdict, `bad` prefixing the failed checks' names.
    fn checks_cell_as(&self, bad: &str) -> String {
        match &self.checks {
            None => "-".into(),
            Some(c) if c.failures.is_empty() => format!("ok (χ={})", c.euler),
            Some(c) => {
                let mut names: Vec<&str> = c
                    .failures
                    .iter()
                    .map(|f| f.split(':').next().unwrap_or("?"))
                    .collect();
                names.dedup();
                format!("{bad}: {}", names.join(", "))
            }
        }
    }
}

/// Everything about one case.
struct Outcome {
    case: Case,
    /// Input vertices and triangles (cleaned), χ of the surface, bodies.
    input: Option<(usize, usize, i64, usize)>,
    /// `tetgen -pd`: intersecting pairs.
    intersections: Option<usize>,
    /// The input facets (0-based, in the raw file's order, delmesh's numbering) of those
    /// pairs.
    intersecting: Vec<u64>,
    /// How TetGen was fed: `raw` or `cleaned (...)`.
    tetgen_input: String,
    rec_dm: Option<Run>,
    /// `delmesh --merge-coplanar`: coplanar facets re-triangulated (checked per planar patch).
    rec_dmm: Option<Run>,
    /// `delmesh --recovery constrained`: flips first (against `tetgen -pMQ`).
    rec_dmc: Option<Run>,
    /// `delmesh --recovery constrained --merge-coplanar` (against `tetgen -pQ`).
    rec_dmcm: Option<Run>,
    rec_tg: Option<Run>,
    /// `tetgen -pMQ`: no merging of coplanar facets, so every input triangle must be
    /// recovered, as delmesh does.
    rec_tgm: Option<Run>,
    full_dm: Option<Run>,
    full_tg: Option<Run>,
    failures: Vec<String>,
    notes: Vec<String>,
}

/// Number of connected components (bodies' boundaries) of a surface.
fn components(s: &Surface) -> usize {
    let mut parent: Vec<u32> = (0..s.points.len() as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    for t in &s.triangles {
        for k in 1..3 {
            let (a, b) = (find(&mut parent, t[0]), find(&mut parent, t[k]));
            parent[a as usize] = b;
        }
    }
    let mut roots: Vec<u32> = s
        .triangles
        .iter()
        .map(|t| find(&mut parent, t[0]))
        .collect();
    roots.sort_unstable();
    roots.dedup();
    roots.len()
}

fn os(s: impl Into<OsString>) -> OsString {
    s.into()
}

/// What a delmesh run is for.
#[derive(Clone, Copy, PartialEq, Eq)]
enum DmStage {
    /// `--no-points`: surface recovery alone.
    Recovery,
    /// `--no-points --merge-coplanar` (checked per planar patch).
    RecoveryMerged,
    /// `--no-points --recovery constrained`.
    RecoveryConstrained,
    /// `--no-points --recovery constrained --merge-coplanar` (checked per planar patch).
    RecoveryConstrainedMerged,
    /// The full pipeline (quality measured).
    Full,
}

impl DmStage {
    /// Whether coplanar facets are merged (coverage is checked per planar patch).
    fn merged(self) -> bool {
        matches!(
            self,
            DmStage::RecoveryMerged | DmStage::RecoveryConstrainedMerged
        )
    }
}

/// Runs delmesh on `input` for `stage` (see [`run_delmesh`]), reads its mesh back and checks
/// it; the mesh files are removed when every check passed.
fn checked_delmesh(
    bin: &Path,
    input: &Path,
    dir: &Path,
    name: &str,
    stage: DmStage,
    limit: u64,
    surface: &Surface,
) -> Result<Run> {
    let (mut run, ele) = run_delmesh(bin, input, dir, name, stage, limit)?;
    let patches = if stage == DmStage::Full {
        mesh::Patches::Flat
    } else if stage.merged() {
        mesh::Patches::Planar
    } else {
        mesh::Patches::Triangles
    };
    read_back(&mut run, &ele, surface, stage == DmStage::Full, patches);
    if run.checks.as_ref().is_some_and(|c| c.failures.is_empty()) && run.why.is_empty() {
        remove_mesh(&ele);
    }
    Ok(run)
}

/// Runs delmesh on `input`, writing `<dir>/<name>.ele` (and `.node`, `.face`) and
/// `<dir>/<name>.json`, with the options of `stage`.
fn run_delmesh(
    bin: &Path,
    input: &Path,
    dir: &Path,
    name: &str,
    stage: DmStage,
    limit: u64,
) -> Result<(Run, PathBuf)> {
    let recovery_only = stage != DmStage::Full;
    fs::create_dir_all(dir)?;
    let ele = dir.join(format!("{name}.ele"));
    let json = dir.join(format!("{name}.json"));
    for p in [
        &json,
        &ele,
        &ele.with_extension("node"),
        &ele.with_extension("face"),
    ] {
        let _ = fs::remove_file(p);
    }
    let mut args = vec![os("mesh"), os(input), os("-o"), os(&ele)];
    args.extend([os("--report"), os(&json), os("--quiet")]);
    if recovery_only {
        args.push(os("--no-points"));
    }
    if stage.merged() {
        args.push(os("--merge-coplanar"));
    }
    if matches!(
        stage,
        DmStage::RecoveryConstrained | DmStage::RecoveryConstrainedMerged
    ) {
        args.extend([os("--recovery"), os("constrained")]);
    }
    let timed = tools::run_timed(bin, &args, &dir.join(format!("{name}.time")), limit)?;
    let mut run = Run {
        timed,
        ..Run::default()
    };
    if !run.timed.success {
        run.why = tools::last_line(&run.timed.stderr);
        return Ok((run, ele));
    }
    // FORMAT: delmesh's report (crates/delmesh/src/mesh3d.rs `report_json`): `points`,
    // `tetrahedra`, `recovery.{surface_points, edge_points, face_points}`, `flat_split` and
    // `seconds["boundary recovery"]`.
    let report = fs::read_to_string(&json)
        .with_context(|| format!("reading {}", json.display()))
        .and_then(|t| Json::parse(&t));
    match report {
        Ok(j) => {
            // Every point added to the input's, as TetGen's count: recovery's and the
            // centroids of flat elements (`flat_split`, absent from older reports).
            let flat = j.count(&["flat_split"]).unwrap_or(0);
            let steiner = j
                .count(&["recovery", "edge_points"])
                .and_then(|e| j.count(&["recovery", "face_points"]).map(|f| e + f + flat));
            run.steiner = steiner.ok();
            run.recovery_secs = j.number(&["seconds", "boundary recovery"]).ok();
            run.points = j.count(&["points"]).ok().map(|p| p as usize);
            run.tets = j.count(&["tetrahedra"]).ok().map(|t| t as usize);
            if recovery_only {
                if let (Ok(p), Ok(s), Some(st)) = (
                    j.count(&["points"]),
                    j.count(&["recovery", "surface_points"]),
                    run.steiner,
                ) {
                    if p != s + st {
                        run.why = format!(
                            "report: {p} points, but {s} surface points + {st} Steiner points"
                        );
                    }
                }
            }
        }
        Err(e) => run.why = format!("report: {e:#}"),
    }
    Ok((run, ele))
}

/// Runs `tetgen <switches> <dir>/<file>` (TetGen writes `<stem>.1.*` beside it).
fn run_tetgen(switches: &str, input: &Path, dir: &Path, limit: u64) -> Result<(Run, PathBuf)> {
    fs::create_dir_all(dir)?;
    let file = input.file_name().context("input has no name")?;
    let local = dir.join(file);
    if fs::canonicalize(input).ok() != fs::canonicalize(&local).ok() {
        fs::copy(input, &local).with_context(|| format!("copying to {}", local.display()))?;
    }
    let stem = local
        .file_stem()
        .unwrap_or_default()
        .to_string_lossy()
        .into_owned();
    let ele = dir.join(format!("{stem}.1.ele"));
    for ext in ["node", "ele", "face", "edge", "smesh"] {
        let _ = fs::remove_file(dir.join(format!("{stem}.1.{ext}")));
    }
    let time_file = dir.join(format!("{stem}.tetgen.time"));
    let timed = tools::run_timed(
        Path::new("tetgen"),
        &[os(switches), os(&local)],
        &time_file,
        limit,
    )?;
    let why = if timed.success {
        String::new()
    } else {
        let line = tools::last_line(&timed.stderr);
        if line.is_empty() {
            timed.status.clone()
        } else {
            line
        }
    };
    Ok((
        Run {
            timed,
            why,
            ..Run::default()
        },
        ele,
    ))
}

/// Reads a successful run's mesh back, checks it against `input` (`patches`: how coverage
/// groups the input triangles, see [`mesh::check_mesh_with`]) and measures its quality
/// (`quality`: only for the full pipeline).
fn read_back(run: &mut Run, ele: &Path, input: &Surface, quality: bool, patches: mesh::Patches) {
    if !run.timed.success {
        return;
    }
    match mesh::read_tet_mesh(ele) {
        Ok(m) => {
            run.points.get_or_insert(m.points.len());
            if run.tets.is_some_and(|t| t != m.tets.len()) {
                run.why = format!(
                    "report: {} tetrahedra, the .ele has {}",
                    run.tets.unwrap_or(0),
                    m.tets.len()
                );
            }
            run.tets = Some(m.tets.len());
            if run.points.is_some_and(|p| p != m.points.len()) {
                run.why = format!(
                    "report: {} points, the .node has {}",
                    run.points.unwrap_or(0),
                    m.points.len()
                );
            }
            run.checks = Some(mesh::check_mesh_with(&m, input, patches));
            if quality {
                run.quality = mesh::quality(&m);
            }
            run.ok = true;
        }
        Err(e) => run.why = format!("reading the mesh: {e:#}"),
    }
}

/// The TetGen outputs are large; the `.ele` files of passing runs are not kept.
fn remove_mesh(ele: &Path) {
    for ext in ["node", "ele", "face", "edge", "smesh"] {
        let _ = fs::remove_file(ele.with_extension(ext));
    }
}

fn run_case(ctx: &Ctx, bin: &Path, meshes: Option<&Path>, case: Case, lim: u64) -> Outcome {
    let mut o = Outcome {
        case,
        input: None,
        intersections: None,
        intersecting: Vec::new(),
        tetgen_input: String::new(),
        rec_dm: None,
        rec_dmm: None,
        rec_dmc: None,
        rec_dmcm: None,
        rec_tg: None,
        rec_tgm: None,
        full_dm: None,
        full_tg: None,
        failures: Vec::new(),
        notes: Vec::new(),
    };
    if let Err(e) = run_case_inner(ctx, bin, meshes, lim, &mut o) {
        o.failures.push(format!("{}: {e:#}", case.name));
    }
    o
}

fn run_case_inner(
    ctx: &Ctx,
    bin: &Path,
    meshes: Option<&Path>,
    lim: u64,
    o: &mut Outcome,
) -> Result<()> {
    let case = o.case;
    let name = case.name;
    let dir = ctx.runs.join("surfaces").join(name);
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir)?;
    let raw_path = dir.join(format!("{name}.off"));
    match case.source {
        Source::Cgal => {
            let src = meshes
                .context("the CGAL meshes are not available")?
                .join(format!("{name}.off"));
            fs::copy(&src, &raw_path).with_context(|| format!("copying {}", src.display()))?;
        }
        Source::Generated => {
            let s = gen::generate(name).context("unknown generated case")?;
            surface::write_off(&raw_path, &s)?;
        }
    }
    let raw = surface::read_off(&raw_path)?;
    let (input, cleaning, kept) = raw.cleaned_with_map();
    let edges = input.edge_report();
    if !edges.is_closed_oriented() {
        o.notes.push(format!(
            "{name}: the input is not a closed, consistently oriented surface ({} border \
             edges, {} edges of 3+ triangles, {} flipped); the volume check uses |volume|",
            edges.border, edges.nonmanifold, edges.flipped
        ));
    }
    if !cleaning.is_empty() {
        o.notes
            .push(format!("{name}: xtask's cleaned copy: {cleaning}"));
    }
    o.input = Some((
        input.points.len(),
        input.triangles.len(),
        input.euler_characteristic(),
        components(&input),
    ));
    let clean_path = dir.join(format!("{name}-clean.off"));
    surface::write_off(&clean_path, &input)?;

    // The witness: does the surface intersect itself?
    eprintln!("xtask: {name}: tetgen -pd (intersecting facets)");
    let (d, _) = run_tetgen("-pd", &clean_path, &dir.join("tetgen-d"), lim)?;
    o.intersections = tools::parse_intersections(&d.timed.stdout);
    o.intersecting = raw_facets(
        &tools::parse_intersecting_pairs(&d.timed.stdout),
        &input,
        &kept,
    );
    let _ = fs::remove_dir_all(dir.join("tetgen-d"));
    match (case.expect, o.intersections) {
        (Expect::Mesh, Some(n)) if n > 0 => o.failures.push(format!(
            "{name}: expected a closed embedded surface, but tetgen -pd finds {n} pairs of \
             intersecting faces (fix the case list)"
        )),
        (Expect::Diagnose, Some(0)) => o.failures.push(format!(
            "{name}: expected a self-intersecting surface, but tetgen -pd finds none (fix the \
             case list)"
        )),
        _ => {}
    }

    // 1. Recovery only.
    eprintln!("xtask: {name}: delmesh mesh --no-points");
    let dm = checked_delmesh(
        bin,
        &raw_path,
        &dir.join("recovery-delmesh"),
        name,
        DmStage::Recovery,
        lim,
        &input,
    )?;
    eprintln!("xtask: {name}: tetgen -pQ");
    let tg_dir = dir.join("recovery-tetgen");
    // Voids need TetGen's hole list, which only its own formats carry.
    let holes = match case.source {
        Source::Generated => gen::holes(name),
        Source::Cgal => Vec::new(),
    };
    let (mut tg_input, mut tg_points_in) = if holes.is_empty() {
        o.tetgen_input = "raw".into();
        (raw_path.clone(), raw.points.len())
    } else {
        let smesh = dir.join(format!("{name}.smesh"));
        surface::write_smesh(&smesh, &input, &holes)?;
        o.tetgen_input = format!(".smesh with {} hole point", holes.len());
        (smesh, input.points.len())
    };
    let (mut tg, mut tg_ele) = run_tetgen("-pQ", &tg_input, &tg_dir, lim)?;
    if !tg.timed.success && holes.is_empty() {
        let first = tg.why.clone();
        eprintln!("xtask: {name}: tetgen -pQ failed on the raw file ({first}); cleaned copy");
        (tg, tg_ele) = run_tetgen("-pQ", &clean_path, &tg_dir, lim)?;
        tg_input = clean_path.clone();
        tg_points_in = input.points.len();
        o.tetgen_input = format!("cleaned (raw: {})", short_status(&first));
    }
    read_back(&mut tg, &tg_ele, &input, false, mesh::Patches::Triangles);
    if tg.ok {
        tg.steiner = tg.points.map(|p| p.saturating_sub(tg_points_in) as u64);
        remove_mesh(&tg_ele);
    }
    // The same without merging coplanar facets (TetGen's default merges facets coplanar
    // within its -T tolerance 1e-8 and re-triangulates them, so it need not recover their
    // edges and moves nearly coplanar ones).
    eprintln!("xtask: {name}: tetgen -pMQ");
    let (mut tgm, tgm_ele) = run_tetgen("-pMQ", &tg_input, &dir.join("recovery-tetgen-M"), lim)?;
    read_back(&mut tgm, &tgm_ele, &input, false, mesh::Patches::Triangles);
    if tgm.ok {
        tgm.steiner = tgm.points.map(|p| p.saturating_sub(tg_points_in) as u64);
    }
    remove_mesh(&tgm_ele);
    o.rec_tgm = Some(tgm);
    let dm_ok = dm.ok;
    let tg_ok = tg.ok;
    o.rec_dm = Some(dm);
    o.rec_tg = Some(tg);
    // delmesh re-triangulating coplanar facets, as TetGen's default does (against -pQ), and
    // the constrained recovery (flips first), as TetGen's is, without and with merging.
    if dm_ok {
        for (stage, what, folder, slot) in [
            (
                DmStage::RecoveryMerged,
                "--merge-coplanar",
                "recovery-delmesh-merged",
                &mut o.rec_dmm,
            ),
            (
                DmStage::RecoveryConstrained,
                "--recovery constrained",
                "recovery-delmesh-constrained",
                &mut o.rec_dmc,
            ),
            (
                DmStage::RecoveryConstrainedMerged,
                "--recovery constrained --merge-coplanar",
                "recovery-delmesh-constrained-merged",
                &mut o.rec_dmcm,
            ),
        ] {
            eprintln!("xtask: {name}: delmesh mesh --no-points {what}");
            *slot = Some(checked_delmesh(
                bin,
                &raw_path,
                &dir.join(folder),
                name,
                stage,
                lim,
                &input,
            )?);
        }
    }

    // 2. Full pipeline, for the tools that recovered the surface.
    // A self-intersecting input has no meaningful full pipeline.
    if dm_ok && case.expect == Expect::Mesh {
        eprintln!("xtask: {name}: delmesh mesh");
        o.full_dm = Some(checked_delmesh(
            bin,
            &raw_path,
            &dir.join("full-delmesh"),
            name,
            DmStage::Full,
            lim,
            &input,
        )?);
    }
    if tg_ok {
        eprintln!("xtask: {name}: tetgen -pqQ");
        let (mut tg, ele) = run_tetgen("-pqQ", &tg_input, &dir.join("full-tetgen"), lim)?;
        read_back(&mut tg, &ele, &input, true, mesh::Patches::Triangles);
        if tg.ok {
            tg.steiner = tg.points.map(|p| p.saturating_sub(tg_points_in) as u64);
        }
        remove_mesh(&ele);
        o.full_tg = Some(tg);
    }
    judge(o);
    Ok(())
}

/// The raw file's facet numbers of TetGen's intersecting pairs. TetGen read the cleaned
/// copy (`input`, whose triangle `k` is raw triangle `kept[k]`): a pair's triangles are
/// looked up by their corners, or else by TetGen's facet number (from 1).
fn raw_facets(pairs: &[tools::IntersectingPair], input: &Surface, kept: &[u32]) -> Vec<u64> {
    let by_corners: std::collections::HashMap<[u32; 3], usize> = input
        .triangles
        .iter()
        .enumerate()
        .map(|(k, &t)| (surface::sorted3(t), k))
        .collect();
    let mut out: Vec<u64> = pairs
        .iter()
        .flat_map(|p| (0..2).map(move |i| (p.triangles[i], p.facets[i])))
        .filter_map(|(t, facet)| {
            let k = by_corners
                .get(&surface::sorted3(t))
                .copied()
                .or_else(|| (facet as usize).checked_sub(1))?;
            kept.get(k).map(|&r| u64::from(r))
        })
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

fn short_status(why: &str) -> String {
    if why.contains("terminate called") {
        "abort".into()
    } else {
        why.chars().take(40).collect()
    }
}

/// What delmesh's error line names, against TetGen's intersecting facets: `(true,
/// text)` when it names at least one of them (or TetGen listed none to compare with).
fn diagnosis(msg: &str, intersecting: &[u64]) -> (bool, String) {
    let named = tools::named_facets(msg);
    if named.is_empty() {
        return (false, "names no facet".into());
    }
    let hits = named
        .iter()
        .filter(|f| intersecting.binary_search(f).is_ok())
        .count();
    let shown: Vec<String> = named.iter().take(5).map(u64::to_string).collect();
    let more = if named.len() > 5 { ", ..." } else { "" };
    let text = format!(
        "names facets {}{more}, {hits} of {} among the {} facets of TetGen's intersecting pairs",
        shown.join(", "),
        named.len(),
        intersecting.len()
    );
    (hits > 0 || intersecting.is_empty(), text)
}

/// Turns the runs of a case into its failures (and notes for TetGen's own).
fn judge(o: &mut Outcome) {
    let name = o.case.name;
    let tg_recovers = [&o.rec_tg, &o.rec_tgm]
        .iter()
        .any(|r| r.as_ref().is_some_and(|r| r.ok));
    let dm = o.rec_dm.as_ref().expect("recovery ran");
    match o.case.expect {
        Expect::Diagnose => {
            let msg = tools::last_line(&dm.timed.stderr);
            let pairs = o.intersections.map_or("?".into(), |n| n.to_string());
            let (names_them, what) = diagnosis(&msg, &o.intersecting);
            if dm.timed.success {
                o.failures.push(format!(
                    "{name}: the surface intersects itself (tetgen -pd: {pairs} pairs), but \
                     delmesh meshed it (exit 0, {} tetrahedra) instead of naming the \
                     intersecting facets",
                    dm.tets.unwrap_or(0)
                ));
            } else if !(tools::names_intersection(&msg) && names_them) {
                o.failures.push(format!(
                    "{name}: the surface intersects itself (tetgen -pd: {pairs} pairs); delmesh \
                     failed ({}, {} s) without a diagnosis of intersecting facets (its message \
                     {what}): `{msg}`",
                    dm.timed.status,
                    dm.timed.wall.map_or("?".into(), |w| format!("{w:.1}"))
                ));
            }
        }
        Expect::Mesh => {
            for (stage, run) in [
                ("recovery", &o.rec_dm),
                ("recovery --merge-coplanar", &o.rec_dmm),
                ("recovery --recovery constrained", &o.rec_dmc),
                (
                    "recovery --recovery constrained --merge-coplanar",
                    &o.rec_dmcm,
                ),
                ("full pipeline", &o.full_dm),
            ] {
                let Some(run) = run else { continue };
                if !run.ok {
                    let target = if tg_recovers && stage == "recovery" {
                        " although TetGen recovers it"
                    } else {
                        ""
                    };
                    o.failures.push(format!(
                        "{name}: {stage}: delmesh failed{target} ({}): `{}`",
                        run.timed.status, run.why
                    ));
                    continue;
                }
                if !run.why.is_empty() {
                    o.failures.push(format!("{name}: {stage}: {}", run.why));
                }
                if let Some(c) = &run.checks {
                    for f in &c.failures {
                        o.failures
                            .push(format!("{name}: {stage}: delmesh's mesh: {f}"));
                    }
                }
            }
        }
    }
    for (what, run) in [
        ("tetgen -pQ", &o.rec_tg),
        ("tetgen -pMQ", &o.rec_tgm),
        ("tetgen -pqQ", &o.full_tg),
    ] {
        if let Some(c) = run.as_ref().and_then(|r| r.checks.as_ref()) {
            if !c.short.is_empty() {
                o.notes.push(format!(
                    "{name}: {what}'s mesh differs from the input (not asserted): {}",
                    c.short.join(", ")
                ));
            }
        }
    }
}

fn opt<T: ToString>(v: Option<T>) -> String {
    v.map_or("-".into(), |x| x.to_string())
}

fn s3(v: Option<f64>) -> String {
    v.map_or("-".into(), |x| format!("{x:.2}"))
}

fn verdict(o: &Outcome, run: &Option<Run>) -> String {
    match (o.case.expect, run) {
        (_, None) => "-".into(),
        (Expect::Diagnose, Some(r)) if r.timed.success => "FAILED: meshed".into(),
        (Expect::Diagnose, Some(r)) => {
            let msg = tools::last_line(&r.timed.stderr);
            if tools::names_intersection(&msg) {
                "diagnosed".into()
            } else {
                "FAILED: not diagnosed".into()
            }
        }
        (Expect::Mesh, Some(r)) if !r.ok => "FAILED: not meshed".into(),
        (Expect::Mesh, Some(r)) if !r.why.is_empty() => "FAILED: report".into(),
        (Expect::Mesh, Some(r)) => r.checks_cell(),
    }
}

const RECOVERY_HEADER: &[&str] = &[
    "case",
    "input V/F",
    "χ",
    "TetGen -d",
    "delmesh",
    "dm Steiner",
    "dm tets",
    "dm wall s",
    "dm recovery s",
    "dm MB",
    "dm -m Steiner",
    "dm -m recovery s",
    "dm -c Steiner",
    "dm -c recovery s",
    "dm -cm Steiner",
    "dm -cm tets",
    "dm -cm wall s",
    "dm -cm recovery s",
    "TetGen",
    "tg Steiner",
    "tg tets",
    "tg wall s",
    "tg MB",
    "tg -M Steiner",
    "tg -M tets",
    "tg -M wall s",
    "delmesh checks",
    "dm -m checks",
    "dm -c checks",
    "dm -cm checks",
    "TetGen checks",
    "TetGen -M checks",
];

fn recovery_row(o: &Outcome) -> Vec<String> {
    let (dm, tg, tgm) = (o.rec_dm.as_ref(), o.rec_tg.as_ref(), o.rec_tgm.as_ref());
    let dmm = o.rec_dmm.as_ref();
    let (vf, chi) = match o.input {
        Some((v, f, chi, bodies)) => (
            format!("{v}/{f}"),
            if bodies > 1 {
                format!("{chi} ({bodies} bodies)")
            } else {
                chi.to_string()
            },
        ),
        None => ("-".into(), "-".into()),
    };
    let tetgen = tg.map_or("-".into(), |r| {
        if o.tetgen_input == "raw" || o.tetgen_input.is_empty() {
            r.recovered()
        } else {
            format!("{} [{}]", r.recovered(), o.tetgen_input)
        }
    });
    let steiner = |r: Option<&Run>| match r {
        Some(r) if !r.ok => r.recovered(),
        _ => opt(r.and_then(|r| r.steiner)),
    };
    let (dmc, dmcm) = (o.rec_dmc.as_ref(), o.rec_dmcm.as_ref());
    vec![
        o.case.name.into(),
        vf,
        chi,
        opt(o.intersections),
        dm.map_or("-".into(), Run::recovered),
        opt(dm.and_then(|r| r.steiner)),
        opt(dm.and_then(|r| r.tets)),
        s3(dm.and_then(|r| r.timed.wall)),
        s3(dm.and_then(|r| r.recovery_secs)),
        mb(dm.and_then(|r| r.timed.rss_kb)),
        steiner(dmm),
        s3(dmm.and_then(|r| r.recovery_secs)),
        steiner(dmc),
        s3(dmc.and_then(|r| r.recovery_secs)),
        steiner(dmcm),
        opt(dmcm.and_then(|r| r.tets)),
        s3(dmcm.and_then(|r| r.timed.wall)),
        s3(dmcm.and_then(|r| r.recovery_secs)),
        tetgen,
        opt(tg.and_then(|r| r.steiner)),
        opt(tg.and_then(|r| r.tets)),
        s3(tg.and_then(|r| r.timed.wall)),
        mb(tg.and_then(|r| r.timed.rss_kb)),
        steiner(tgm),
        opt(tgm.and_then(|r| r.tets)),
        s3(tgm.and_then(|r| r.timed.wall)),
        verdict(o, &o.rec_dm),
        verdict(o, &o.rec_dmm),
        verdict(o, &o.rec_dmc),
        verdict(o, &o.rec_dmcm),
        tg.map_or("-".into(), |r| r.checks_cell_as("differs")),
        tgm.map_or("-".into(), |r| r.checks_cell_as("differs")),
    ]
}

const FULL_HEADER: &[&str] = &[
    "case",
    "dm points",
    "dm tets",
    "dm wall s",
    "dm cpu s",
    "dm tets/s",
    "dm dihedral °",
    "dm slivers",
    "dm max R/e",
    "dm R/e>2",
    "tg points",
    "tg tets",
    "tg wall s",
    "tg cpu s",
    "tg tets/s",
    "tg dihedral °",
    "tg slivers",
    "tg max R/e",
    "tg R/e>2",
    "delmesh checks",
];

/// An angle in degrees: two decimals, or two significant digits when tiny.
fn degrees(a: f64) -> String {
    if a > 0.0 && a < 0.01 {
        format!("{a:.1e}")
    } else {
        format!("{a:.2}")
    }
}

/// A ratio that may be huge (or infinite, for a tetrahedron flat in floating point).
fn big(x: f64) -> String {
    if !x.is_finite() {
        "inf".into()
    } else if x >= 1e4 {
        format!("{x:.1e}")
    } else {
        format!("{x:.1}")
    }
}

fn quality_cells(r: Option<&Run>) -> [String; 4] {
    match r.and_then(|r| r.quality) {
        Some(q) => [
            format!("{}-{}", degrees(q.min_dihedral), degrees(q.max_dihedral)),
            q.slivers.to_string(),
            big(q.max_radius_edge),
            q.radius_edge_over_2.to_string(),
        ],
        None => std::array::from_fn(|_| "-".into()),
    }
}

fn full_row(o: &Outcome) -> Vec<String> {
    let (dm, tg) = (o.full_dm.as_ref(), o.full_tg.as_ref());
    let tool = |r: Option<&Run>| -> Vec<String> {
        let mut v = vec![
            opt(r.and_then(|r| r.points)),
            match r {
                Some(r) if !r.ok => r.recovered(),
                _ => opt(r.and_then(|r| r.tets)),
            },
            s3(r.and_then(|r| r.timed.wall)),
            s3(r.and_then(|r| r.timed.cpu)),
            r.map_or("-".into(), Run::tets_per_sec),
        ];
        v.extend(quality_cells(r));
        v
    };
    let mut row = vec![o.case.name.to_string()];
    row.extend(tool(dm));
    row.extend(tool(tg));
    row.push(verdict(o, &o.full_dm));
    row
}

const NOTE: &str = "\
Recovery: `delmesh mesh X.off --no-points -o X.ele --report X.json --quiet`, `tetgen -pQ X` \
and `tetgen -pMQ X` (-M: coplanar facets are not merged, so every input triangle must be \
recovered, as delmesh does; TetGen's default merges facets coplanar within its -T \
tolerance 1e-8 and re-triangulates them, so it need not recover their shared edges, and \
moves the nearly coplanar ones); `dm -m`: `delmesh mesh X.off --no-points --merge-coplanar`, \
which re-triangulates exactly coplanar neighbouring triangles by flipping their diagonals \
(the one to compare with `tetgen -pQ`; its coverage is checked per planar patch of the input: \
triangles joined across edges where both lie exactly in one plane); `dm -c`: `--no-points --recovery constrained` (flips first, points only where flips stop short, as TetGen's constrained recovery: compare with `tetgen -pMQ`), `dm -cm`: the same with `--merge-coplanar` (compare with `tetgen -pQ`). Full pipeline: `delmesh mesh X.off -o X.ele --report X.json \
--quiet` (automatic points, Delaunay restoration) and `tetgen -pqQ X` (radius-edge bound 2). \
X is the raw .off, except `[.smesh with 1 hole point]` (a void, which an .off cannot mark \
for TetGen; delmesh finds it by nesting) and `[cleaned (raw: abort)]` (TetGen 1.5 aborts on \
CGAL's `#` comment lines; it reads xtask's plain copy, duplicates merged). delmesh/TetGen: \
yes when the tool exits 0 and its mesh reads back. Steiner: delmesh's report \
(`edge_points + face_points + flat_split`: recovery's points and the centroids of flat \
elements inside); TetGen: output points - input points. TetGen -d: pairs of \
intersecting input triangles found by `tetgen -pd` (the witness for which inputs intersect \
themselves). wall s, cpu s (user + system), MB (peak RSS): GNU time on the whole run, \
reading and writing included; dm recovery s: delmesh's own time of its boundary-recovery \
stage (report). tets/s: tetrahedra over wall time. Quality, computed by xtask from each \
tool's .node/.ele: dihedral angles min-max (degrees), slivers: tetrahedra with a dihedral \
angle under 5 degrees, R/e: circumradius over shortest edge (inf: flat in floating point \
though positive in exact arithmetic), R/e>2: how many exceed 2. Checks, the same code for \
both tools (asserted on delmesh's meshes; on TetGen's only reported, `differs`): exact \
orientation (robust orient3d), the .face file is the boundary of the tetrahedra, volume = \
the volume the input encloses (divergence theorem, relative 1e-9), every boundary face lies \
on an input triangle and covers its area (relative 1e-9), input vertices kept bit for bit, \
V-E+F-T = χ(surface)/2 (shown as χ). A self-intersecting input must be diagnosed: delmesh \
exits non-zero with a message about intersecting facets that names at least one of the \
facets in TetGen's intersecting pairs. Timings are reported, never asserted.";

/// `cargo xtask surfaces`.
pub fn surfaces(ctx: &Ctx, opts: &SurfacesOptions) -> Result<()> {
    let list = select(opts.quick, &opts.only)?;
    reference::ensure_tools()?;
    if !reference::on_path("timeout") {
        bail!("`timeout` (coreutils) is missing");
    }
    let xtask_dir = ctx.root.join("target/xtask");
    let meshes = if list.iter().any(|c| c.source == Source::Cgal) {
        Some(tools::cgal_meshes(&xtask_dir)?)
    } else {
        None
    };
    let bin = delmesh::build(&ctx.root)?;
    tools::check_delmesh_cli(&bin)?;
    let lim = limit(opts.quick);
    let load_before = report::load_average();
    let mut outcomes = Vec::new();
    for &case in &list {
        let o = run_case(ctx, &bin, meshes.as_deref(), case, lim);
        for f in &o.failures {
            eprintln!("xtask: FAILED {f}");
        }
        eprintln!(
            "xtask: {} done (load {})",
            case.name,
            report::load_average()
        );
        outcomes.push(o);
    }
    let rec: Vec<Vec<String>> = outcomes.iter().map(recovery_row).collect();
    let full: Vec<Vec<String>> = outcomes
        .iter()
        .filter(|o| o.case.expect == Expect::Mesh)
        .map(full_row)
        .collect();
    let mode = if opts.quick {
        "quick subset"
    } else {
        "all cases"
    };
    let mut text = format!(
        "## Surfaces: delmesh vs TetGen on closed surfaces ({mode}, one run per tool)\n\n{}\n\
         Tools: TetGen {} (Debian tetgen), CGAL data {} (Debian {}), delmesh threads: {}\n\n\
         ### Surface recovery\n\n{}\n### Full pipeline (quality meshes)\n\n{}\n{NOTE}\n",
        report::machine(&ctx.root, &opts.command, &load_before),
        report::package_version("tetgen", &ctx.root),
        report::package_version(tools::CGAL_DATA_PACKAGE, &ctx.root),
        tools::CGAL_DATA_PACKAGE,
        std::env::var("RAYON_NUM_THREADS").unwrap_or_else(|_| "all cores".into()),
        markdown_table(RECOVERY_HEADER, &rec),
        markdown_table(FULL_HEADER, &full),
    );
    let notes: Vec<&String> = outcomes.iter().flat_map(|o| &o.notes).collect();
    if !notes.is_empty() {
        text += "\nNotes:\n\n";
        for n in notes {
            text += &format!("- {n}\n");
        }
    }
    let failures: Vec<&String> = outcomes.iter().flat_map(|o| &o.failures).collect();
    if !failures.is_empty() {
        text += "\nFAILED:\n\n";
        for f in &failures {
            text += &format!("- {f}\n");
        }
    }
    println!("\n{text}");
    if let Some(path) = &opts.report {
        fs::write(path, &text).with_context(|| format!("writing {}", path.display()))?;
        eprintln!("xtask: wrote {}", path.display());
    }
    if !failures.is_empty() {
        let failed = outcomes.iter().filter(|o| !o.failures.is_empty()).count();
        let list: Vec<&str> = failures.iter().map(|s| s.as_str()).collect();
        bail!(
            "{failed} of {} surface cases FAILED:\n  {}",
            outcomes.len(),
            list.join("\n  ")
        );
    }
    println!("surfaces: ok ({} cases)", outcomes.len());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn case_selection() {
        let quick = select(true, &[]).unwrap();
        let names: Vec<&str> = quick.iter().map(|c| c.name).collect();
        for n in ["sphere-in-box", "elephant", "knot1", "fandisk"] {
            assert!(names.contains(&n), "{n}");
        }
        assert!(!names.contains(&"bunny00"));
        assert!(quick.iter().all(|c| c.expect == Expect::Mesh));
        let all = select(false, &[]).unwrap();
        assert!(all.len() > quick.len());
        let mut seen: Vec<&str> = all.iter().map(|c| c.name).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), all.len(), "case names are unique");
        let only = select(true, &["cow".into(), "wedge-1".into()]).unwrap();
        assert_eq!(only[0].expect, Expect::Diagnose);
        assert_eq!(only[1].source, Source::Generated);
        let err = select(false, &["nope".into()]).unwrap_err().to_string();
        assert!(err.contains("no surface case `nope`"), "{err}");
    }

    #[test]
    fn formats_numbers() {
        assert_eq!(degrees(0.0012), "1.2e-3");
        assert_eq!(degrees(0.0), "0.00");
        assert_eq!(degrees(179.999), "180.00");
        assert_eq!(big(f64::INFINITY), "inf");
        assert_eq!(big(97424881868753.3), "9.7e13");
        assert_eq!(big(2.04), "2.0");
    }

    /// TetGen honours the hole point of a `.smesh` (it meshes the void of an `.off`).
    #[test]
    fn tetgen_reads_the_hole_of_a_smesh() {
        if !reference::on_path("tetgen") || !Path::new(reference::GNU_TIME).is_file() {
            eprintln!("tetgen or GNU time missing; skipping");
            return;
        }
        let dir = std::env::temp_dir().join(format!("xtask-smesh-{}", std::process::id()));
        let s = gen::generate("cube-hole").unwrap();
        let path = dir.join("cube-hole.smesh");
        surface::write_smesh(&path, &s, &gen::holes("cube-hole")).unwrap();
        let (run, ele) = run_tetgen("-pQ", &path, &dir, 60).unwrap();
        assert!(run.timed.success, "{run:?}");
        let m = mesh::read_tet_mesh(&ele).unwrap();
        assert!((m.volume() - 26.0).abs() < 1e-12, "{}", m.volume());
        assert_eq!(m.points.len(), s.points.len());
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn counts_bodies() {
        let s = gen::generate("two-bodies").unwrap();
        assert_eq!(components(&s), 2);
        assert_eq!(components(&gen::generate("wedge-1").unwrap()), 1);
    }
}
