//! `cargo xtask validate` and `cargo xtask bench`: delmesh next to CGAL and TetGen.
//!
//! For every case (see `cases::FAMILIES`) the three tools run on the same `.node`
//! file: delmesh once with `--validate` (the run whose output is checked) and then
//! `repeat` times each, interleaved (delmesh, CGAL, TetGen, delmesh, ...), for the
//! timings and peak memory. Then the outputs are read back as canonical cell sets
//! (`formats::CellSet`) and checked according to the case's `cases::Kind` in
//! [`check_case`]. Timings are reported, never asserted; any failed check makes the
//! command exit non-zero after printing the whole table.

use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{bail, ensure, Context, Result};

use crate::cases::{self, Case, Kind};
use crate::formats::{self, CellSet, Total};
use crate::report::{self, markdown_table, mb, ratio, secs};
use crate::{delmesh, exact, reference, Ctx};

/// The cases of `bench`.
pub const BENCH_CASES: &[&str] = &["uniform3d-1m", "uniform2d-1m", "grid3d-100"];
/// Runs per tool and case in full mode (`validate`, `bench`); quick mode runs once.
pub const FULL_REPEAT: usize = 3;

/// What the timing columns mean (printed under every table).
const TIMING_NOTE: &str = "\
Times are each tool's own measurement of the construction alone (no file reading or \
writing): delmesh: its `build time:` line (wall clock; delmesh sorts with rayon, on all \
cores unless RAYON_NUM_THREADS is set); CGAL: wall clock around the range `insert` \
(spatial sort and insertion, one thread); TetGen: its `Delaunay seconds` (clock(), i.e. \
CPU time of its one thread). Ratios below 1 mean delmesh is faster. Peak MB: GNU time's \
maximum resident set size of the whole run (read, build, write; delmesh without \
`--validate`).";
/// What the bytes-per-point column means (validate's table only).
const BPP_NOTE: &str = " B/pt: delmesh's peak bytes per input point.";

/// The paths of the built tools.
pub struct Tools {
    delmesh: PathBuf,
    cgal: PathBuf,
}

impl Tools {
    /// Installs the reference tools if needed, then builds delmesh (cargo) and the
    /// CGAL driver (g++) side by side.
    pub fn prepare(ctx: &Ctx) -> Result<Tools> {
        reference::ensure_tools()?;
        let (delmesh, cgal) = std::thread::scope(|s| {
            let cgal = s.spawn(|| reference::build_cgal_driver(&ctx.root));
            let delmesh = delmesh::build(&ctx.root);
            (delmesh, cgal.join())
        });
        let cgal = cgal.map_err(|_| anyhow::anyhow!("the CGAL build thread panicked"))??;
        let delmesh = delmesh?;
        delmesh::check_cli(&delmesh)?;
        Ok(Tools { delmesh, cgal })
    }
}

/// Timing samples of one tool on one case.
#[derive(Debug, Default, Clone)]
struct Samples {
    secs: Vec<f64>,
    rss_kb: Vec<u64>,
}

impl Samples {
    fn push(&mut self, secs: f64, rss_kb: Option<u64>) {
        self.secs.push(secs);
        self.rss_kb.extend(rss_kb);
    }

    fn median_secs(&self) -> Option<f64> {
        median(&self.secs)
    }

    fn median_rss_kb(&self) -> Option<u64> {
        let v: Vec<f64> = self.rss_kb.iter().map(|&k| k as f64).collect();
        median(&v).map(|m| m.round() as u64)
    }
}

/// Median of a sample (mean of the middle two for even sizes).
fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    })
}

/// Everything measured and checked on one case.
struct CaseResult {
    case: Case,
    points: usize,
    /// delmesh's cell count.
    cells: Option<usize>,
    /// Short verdict for the table.
    verdict: String,
    /// Failure messages, each naming the case.
    failures: Vec<String>,
    delmesh: Samples,
    cgal: Samples,
    /// `None` in 2D.
    tetgen: Option<Samples>,
}

impl CaseResult {
    fn row(&self) -> Vec<String> {
        let dm = self.delmesh.median_secs();
        let tg = self.tetgen.as_ref();
        let bpp = self.delmesh.median_rss_kb().map_or("-".into(), |k| {
            format!("{:.0}", k as f64 * 1024.0 / self.points as f64)
        });
        vec![
            self.case.name.clone(),
            self.case.kind.label().into(),
            self.points.to_string(),
            self.cells.map_or("-".into(), |c| c.to_string()),
            self.verdict.clone(),
            secs(dm),
            secs(self.cgal.median_secs()),
            secs(tg.and_then(Samples::median_secs)),
            ratio(dm, self.cgal.median_secs()),
            ratio(dm, tg.and_then(Samples::median_secs)),
            mb(self.delmesh.median_rss_kb()),
            mb(self.cgal.median_rss_kb()),
            mb(tg.and_then(Samples::median_rss_kb)),
            bpp,
        ]
    }
}

const HEADER: &[&str] = &[
    "case",
    "kind",
    "points",
    "cells",
    "check",
    "delmesh s",
    "CGAL s",
    "TetGen s",
    "dm/CGAL",
    "dm/TetGen",
    "delmesh MB",
    "CGAL MB",
    "TetGen MB",
    "dm B/pt",
];

/// Runs the tools on `case` and checks the outputs. Errors of the tools themselves
/// (a crash, a failed `--validate`) are returned as failures of the case.
fn run_case(ctx: &Ctx, tools: &Tools, case: &Case, repeat: usize) -> CaseResult {
    let node = case.node();
    let mut r = CaseResult {
        case: case.clone(),
        points: node.len(),
        cells: None,
        verdict: String::new(),
        failures: Vec::new(),
        delmesh: Samples::default(),
        cgal: Samples::default(),
        tetgen: (node.dim == 3).then(Samples::default),
    };
    match run_and_check(ctx, tools, &node, &mut r, repeat) {
        Ok(verdict) => r.verdict = verdict,
        Err(e) => {
            r.verdict = "FAILED (see below)".into();
            let msg = format!("{e:#}");
            if msg.starts_with(&format!("{}: ", case.name)) {
                r.failures.push(msg);
            } else {
                r.failures.push(format!("{}: {msg}", case.name));
            }
        }
    }
    r
}

fn run_and_check(
    ctx: &Ctx,
    tools: &Tools,
    node: &formats::NodeFile,
    r: &mut CaseResult,
    repeat: usize,
) -> Result<String> {
    let case = r.case.clone();
    let path = case.write_node(&ctx.cases, node)?;
    let work = ctx.runs.join(&case.name);
    fs::create_dir_all(&work)?;

    // The checked run. Its outputs are kept apart from the timing runs' ones.
    eprintln!("xtask: {}: delmesh --validate", case.name);
    let checked =
        delmesh::run(&tools.delmesh, &path, &work.join("checked"), true).context("delmesh")?;

    let load = report::load_average;
    let mut cgal_cells = PathBuf::new();
    let mut tetgen_cells = None;
    for i in 1..=repeat {
        let dm = delmesh::run(&tools.delmesh, &path, &work, false).context("delmesh")?;
        r.delmesh.push(dm.build_seconds, dm.peak_rss_kb);
        let cg = reference::run_cgal(
            &tools.cgal,
            &path,
            &work.join(format!("{}.cgal.cells", case.name)),
        )
        .context("CGAL")?;
        r.cgal.push(cg.build_seconds, cg.peak_rss_kb);
        cgal_cells = cg.cells_file;
        let mut line = format!(
            "xtask: {} run {i}/{repeat}: delmesh {:.3} s {} MB, CGAL {:.3} s {} MB",
            case.name,
            dm.build_seconds,
            mb(dm.peak_rss_kb),
            cg.build_seconds,
            mb(cg.peak_rss_kb)
        );
        if let Some(samples) = &mut r.tetgen {
            let tg = reference::run_tetgen(&path, &work).context("TetGen")?;
            samples.push(tg.build_seconds, tg.peak_rss_kb);
            line += &format!(
                ", TetGen {:.3} s {} MB",
                tg.build_seconds,
                mb(tg.peak_rss_kb)
            );
            tetgen_cells = Some(tg.cells_file);
        }
        eprintln!("{line} (load {})", load());
        // The timing runs' mesh is not needed: only the checked run's is compared.
        remove_delmesh_output(&dm.ele);
    }

    // Read everything back as cell sets over input indices, duplicates merged onto
    // their first occurrence.
    let arity = node.dim + 1;
    let dups = formats::duplicate_canonical_map(node);
    let mut dm = formats::read_ele(&checked.ele, arity, node.first_index)?;
    let mut numbering = None;
    r.cells = Some(dm.len());
    if let Some(map) = &dups {
        // delmesh itself must map duplicates to their first occurrence. A failure of
        // that numbering rule is recorded, and the cells are still compared after
        // merging, so the report tells the two kinds of error apart.
        if let Some((v, first)) = non_canonical_vertex(&dm, map) {
            numbering = Some(format!(
                "{}: delmesh's .ele numbers a vertex with input {v}, which repeats the \
                 earlier input {first}: duplicates must map to their first occurrence",
                case.name
            ));
        }
        dm = dm.remap(map)?;
    }
    let merge = |cells: CellSet| match &dups {
        Some(map) => cells.remap(map),
        None => Ok(cells),
    };
    let mut refs = vec![("CGAL", merge(formats::read_cells(&cgal_cells, arity)?)?)];
    if let Some(f) = tetgen_cells {
        refs.push(("TetGen", merge(formats::read_cells(&f, arity)?)?));
    }
    let verdict = check_case(&case, node, &dm, &refs, dups.is_some())?;
    if let Some(msg) = numbering {
        bail!("{msg} (the cells agree after merging: {verdict})");
    }
    // Passed: the (large) outputs are no longer needed. On failure they stay in
    // target/xtask/runs/<case>/ for inspection.
    remove_delmesh_output(&checked.ele);
    let _ = fs::remove_file(&cgal_cells);
    if node.dim == 3 {
        let _ = fs::remove_file(work.join(format!("{}.tetgen.cells", case.name)));
    }
    Ok(verdict)
}

/// Removes delmesh's `X.ele` and its `X.node` and `X.neigh` siblings.
fn remove_delmesh_output(ele: &Path) {
    for ext in ["ele", "node", "neigh"] {
        let _ = fs::remove_file(ele.with_extension(ext));
    }
}

/// The first vertex of `cells` that is not the first occurrence of its position,
/// with that first occurrence.
fn non_canonical_vertex(cells: &CellSet, map: &[u32]) -> Option<(u32, u32)> {
    cells
        .iter()
        .flatten()
        .find(|&&v| map.get(v as usize).is_some_and(|&m| m != v))
        .map(|&v| (v, map[v as usize]))
}

/// The checks of one case, by kind; `dm` and `refs` are canonical cell sets over input
/// indices with duplicates merged. Returns the verdict for the table, or an error
/// naming the case and what differs. (delmesh's own `--validate` already passed.)
pub fn check_case(
    case: &Case,
    node: &formats::NodeFile,
    dm: &CellSet,
    refs: &[(&str, CellSet)],
    merged: bool,
) -> Result<String> {
    let names: Vec<&str> = refs.iter().map(|r| r.0).collect();
    let suffix = if merged { " (dups merged)" } else { "" };
    match case.kind {
        Kind::GeneralPosition => {
            // The Delaunay triangulation is unique: the cell sets must be identical.
            for (name, cells) in refs {
                let diff = formats::compare(dm, cells)?;
                ensure!(
                    diff.is_empty(),
                    "{}: delmesh and {name} differ: {}",
                    case.name,
                    diff.describe("delmesh", name)
                );
            }
            Ok(format!("valid, identical to {}{suffix}", names.join(", ")))
        }
        Kind::Degenerate => {
            // Not unique. Checked: no flat cell; the same total measure as the
            // references and the hull; the same number of cells in 2D (every
            // triangulation of a planar point set has 2n - h - 2 triangles), but not in
            // 3D, where a co-spherical cube may be split into 5 or 6 tetrahedra; and
            // xtask's own exact check that every facet is locally Delaunay.
            let (total, flat) = formats::total_measure(node, dm);
            ensure!(
                flat == 0,
                "{}: delmesh has {flat} cells of zero measure",
                case.name
            );
            let mut other_counts = Vec::new();
            let mut identical = Vec::new();
            for (name, cells) in refs {
                if dm.len() != cells.len() {
                    ensure!(
                        node.dim == 3,
                        "{}: delmesh has {} triangles, {name} {}",
                        case.name,
                        dm.len(),
                        cells.len()
                    );
                    other_counts.push(format!("{name} has {} cells", cells.len()));
                }
                let (theirs, _) = formats::total_measure(node, cells);
                ensure!(
                    total.agrees(&theirs),
                    "{}: delmesh's cells measure {total}, {name}'s {theirs}",
                    case.name
                );
                // Not required, but worth knowing: the same tie-breaking as this tool.
                if formats::compare(dm, cells)?.is_empty() {
                    identical.push(*name);
                }
            }
            if let Some(hull) = case.gen.hull_total() {
                ensure!(
                    total.agrees(&hull),
                    "{}: delmesh's cells measure {total}, the hull {hull}",
                    case.name
                );
            }
            let local = exact::check_locally_delaunay(node, dm)
                .with_context(|| format!("{}: delmesh's cells", case.name))?;
            let mut parts = vec!["valid".to_string()];
            if local.is_some() {
                parts.push("locally Delaunay".into());
            }
            let exact = if matches!(total, Total::Exact { .. }) {
                "exact "
            } else {
                ""
            };
            if other_counts.is_empty() {
                parts.push(format!("count and {exact}measure = {}", names.join(", ")));
            } else {
                parts.push(format!("{exact}measure = {}", names.join(", ")));
                parts.push(format!("{} (both Delaunay)", other_counts.join(", ")));
            }
            if !identical.is_empty() {
                parts.push(format!("identical to {}", identical.join(", ")));
            }
            Ok(parts.join(", ") + suffix)
        } // Later, PLC kinds (mesh generation): boundary conformity, quality bounds and
          // comparison with `tetgen -pq` go here.
    }
}

/// Options of `validate`.
pub struct ValidateOptions {
    pub quick: bool,
    pub only: Vec<String>,
    pub report: Option<PathBuf>,
    /// The command line, for the report.
    pub command: String,
}

/// The cases `validate` runs: every family's quick or full sizes, or those `only`
/// names (a family name, or any `<family>-<size>` case name).
pub fn select_cases(quick: bool, only: &[String]) -> Result<Vec<Case>> {
    if only.is_empty() {
        return Ok(cases::FAMILIES
            .iter()
            .flat_map(|f| f.cases(quick))
            .collect());
    }
    let mut list = Vec::new();
    for name in only {
        match cases::FAMILIES.iter().find(|f| f.name == name) {
            Some(f) => list.extend(f.cases(quick)),
            None => list.push(cases::by_name(name)?),
        }
    }
    Ok(list)
}

fn finish(
    ctx: &Ctx,
    title: &str,
    table: String,
    results: &[CaseResult],
    command: &str,
    load_before: &str,
    report_file: Option<&Path>,
) -> Result<()> {
    let failures: Vec<&String> = results.iter().flat_map(|r| &r.failures).collect();
    let mut text = format!(
        "## {title}\n\n{}\n{table}\n{TIMING_NOTE}{}\n",
        report::environment(&ctx.root, command, load_before),
        if table.contains("B/pt") { BPP_NOTE } else { "" }
    );
    if !failures.is_empty() {
        text += "\nFAILED:\n\n";
        for f in &failures {
            text += &format!("- {f}\n");
        }
    }
    println!("\n{text}");
    if let Some(path) = report_file {
        fs::write(path, &text).with_context(|| format!("writing {}", path.display()))?;
        eprintln!("xtask: wrote {}", path.display());
    }
    if !failures.is_empty() {
        let list: Vec<&str> = failures.iter().map(|s| s.as_str()).collect();
        bail!(
            "{} of {} cases FAILED:\n  {}",
            results.iter().filter(|r| !r.failures.is_empty()).count(),
            results.len(),
            list.join("\n  ")
        );
    }
    Ok(())
}

/// `cargo xtask validate`.
pub fn validate(ctx: &Ctx, opts: &ValidateOptions) -> Result<()> {
    let list = select_cases(opts.quick, &opts.only)?;
    let tools = Tools::prepare(ctx)?;
    let load_before = report::load_average();
    let repeat = if opts.quick { 1 } else { FULL_REPEAT };
    let mut results = Vec::new();
    for case in &list {
        let r = run_case(ctx, &tools, case, repeat);
        for f in &r.failures {
            eprintln!("xtask: FAILED {f}");
        }
        results.push(r);
    }
    let rows: Vec<Vec<String>> = results.iter().map(CaseResult::row).collect();
    let mode = if opts.quick {
        "quick, one run per tool".to_string()
    } else {
        format!("median of {repeat} runs per tool")
    };
    let title = format!("Validation: delmesh vs CGAL and TetGen ({mode})");
    finish(
        ctx,
        &title,
        markdown_table(HEADER, &rows),
        &results,
        &opts.command,
        &load_before,
        opts.report.as_deref(),
    )?;
    println!("validate: ok ({} cases)", results.len());
    Ok(())
}

/// `cargo xtask bench`: the README table.
pub fn bench(ctx: &Ctx, report_file: Option<&Path>, command: &str) -> Result<()> {
    let list: Vec<Case> = BENCH_CASES
        .iter()
        .map(|n| cases::by_name(n))
        .collect::<Result<_>>()?;
    let tools = Tools::prepare(ctx)?;
    let load_before = report::load_average();
    let results: Vec<CaseResult> = list
        .iter()
        .map(|c| run_case(ctx, &tools, c, FULL_REPEAT))
        .collect();
    let rows: Vec<Vec<String>> = results.iter().map(bench_row).collect();
    let table = markdown_table(
        &[
            "input",
            "points",
            "delmesh s",
            "CGAL s",
            "TetGen s",
            "delmesh/CGAL",
            "delmesh/TetGen",
            "delmesh MB",
            "CGAL MB",
            "TetGen MB",
        ],
        &rows,
    );
    let title = format!("Benchmark: Delaunay construction, median of {FULL_REPEAT} runs");
    finish(
        ctx,
        &title,
        table,
        &results,
        command,
        &load_before,
        report_file,
    )
}

fn bench_row(r: &CaseResult) -> Vec<String> {
    let dm = r.delmesh.median_secs();
    let tg = r.tetgen.as_ref();
    let what = match r.case.gen {
        cases::Gen::Uniform { dim: 3, .. } => "uniform in a cube".to_string(),
        cases::Gen::Uniform { dim: 2, .. } => "uniform in a square".to_string(),
        cases::Gen::Grid { dim, k } => format!("grid {k}^{dim}"),
        _ => r.case.name.clone(),
    };
    let name = if r.failures.is_empty() {
        format!("{what} ({}D)", r.case.gen.dim())
    } else {
        format!("{what} ({}D) FAILED", r.case.gen.dim())
    };
    vec![
        name,
        r.points.to_string(),
        secs(dm),
        secs(r.cgal.median_secs()),
        secs(tg.and_then(Samples::median_secs)),
        ratio(dm, r.cgal.median_secs()),
        ratio(dm, tg.and_then(Samples::median_secs)),
        mb(r.delmesh.median_rss_kb()),
        mb(r.cgal.median_rss_kb()),
        mb(tg.and_then(Samples::median_rss_kb)),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node2(coords: &[f64]) -> formats::NodeFile {
        formats::NodeFile {
            dim: 2,
            first_index: 0,
            coords: coords.to_vec(),
            nattr: 0,
            attrs: vec![],
        }
    }

    fn tris(cells: &[[u32; 3]]) -> CellSet {
        CellSet::new(3, cells.iter().map(|c| [c[0], c[1], c[2], 0]).collect())
    }

    #[test]
    fn medians() {
        assert_eq!(median(&[]), None);
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0]), Some(2.5));
        let mut s = Samples::default();
        s.push(1.0, Some(10));
        s.push(3.0, None);
        s.push(2.0, Some(30));
        assert_eq!(s.median_secs(), Some(2.0));
        assert_eq!(s.median_rss_kb(), Some(20));
    }

    #[test]
    fn general_position_needs_identical_cells() {
        let case = cases::by_name("uniform2d-10k").unwrap();
        // The unit square split along either diagonal.
        let node = node2(&[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0]);
        let a = tris(&[[0, 1, 2], [0, 2, 3]]);
        let b = tris(&[[0, 1, 3], [1, 2, 3]]);
        let ok = check_case(&case, &node, &a, &[("CGAL", a.clone())], false).unwrap();
        assert_eq!(ok, "valid, identical to CGAL");
        let err = check_case(&case, &node, &a, &[("CGAL", b)], false)
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("uniform2d-10k: delmesh and CGAL differ"),
            "{err}"
        );
        assert!(
            err.contains("first difference: [0, 1, 2] is in delmesh, not in CGAL"),
            "{err}"
        );
    }

    #[test]
    fn degenerate_needs_count_and_measure() {
        let case = cases::by_name("grid2d-2").unwrap();
        let node = node2(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
        // Either diagonal of the co-circular square is fine.
        let a = tris(&[[0, 1, 3], [0, 3, 2]]);
        let b = tris(&[[0, 1, 2], [1, 3, 2]]);
        let ok = check_case(&case, &node, &a, &[("CGAL", b.clone())], false).unwrap();
        assert_eq!(
            ok,
            "valid, locally Delaunay, count and exact measure = CGAL"
        );
        // A missing triangle: count differs.
        let short = tris(&[[0, 1, 3]]);
        let err = check_case(&case, &node, &short, &[("CGAL", b.clone())], false)
            .unwrap_err()
            .to_string();
        assert!(err.contains("delmesh has 1 triangles, CGAL 2"), "{err}");
        let err = check_case(&case, &node, &short, &[], false)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("measure 1/2 (exact), the hull 1 (exact)"),
            "{err}"
        );
        // A 2x2 square and its centre: same count, wrong (overlapping) measure.
        let case = cases::by_name("grid2d-3").unwrap();
        let node = node2(&[0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 2.0, 2.0, 1.0, 1.0]);
        let good = tris(&[[0, 1, 4], [1, 3, 4], [3, 2, 4], [2, 0, 4]]);
        let bad = tris(&[[0, 1, 4], [1, 3, 4], [3, 2, 4], [0, 1, 2]]);
        assert!(check_case(&case, &node, &good, &[("CGAL", good.clone())], false).is_ok());
        let err = check_case(&case, &node, &bad, &[("CGAL", good)], false)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("delmesh's cells measure 5 (exact), CGAL's 4 (exact)"),
            "{err}"
        );
        // A grid cube split in 5 tetrahedra by delmesh and in 6 by CGAL: both are
        // Delaunay, so only the measure and the local Delaunay property must agree.
        let case = cases::by_name("grid3d-2").unwrap();
        let mut coords = Vec::new();
        for i in 0..8 {
            coords.extend([(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64]);
        }
        let node = formats::NodeFile {
            dim: 3,
            first_index: 0,
            coords,
            nattr: 0,
            attrs: vec![],
        };
        let tets = |c: &[[u32; 4]]| CellSet::new(4, c.to_vec());
        let five = tets(&[
            [0, 3, 5, 6],
            [0, 1, 3, 5],
            [0, 2, 3, 6],
            [0, 4, 5, 6],
            [3, 5, 6, 7],
        ]);
        let six = tets(&[
            [0, 1, 3, 7],
            [0, 1, 5, 7],
            [0, 2, 3, 7],
            [0, 2, 6, 7],
            [0, 4, 5, 7],
            [0, 4, 6, 7],
        ]);
        let ok = check_case(&case, &node, &five, &[("CGAL", six.clone())], false).unwrap();
        assert!(ok.contains("CGAL has 6 cells (both Delaunay)"), "{ok}");
        // Five tets that overlap: right count for a 5-split, wrong measure.
        let wrong = tets(&[
            [0, 3, 5, 6],
            [0, 1, 3, 5],
            [0, 2, 3, 6],
            [0, 4, 5, 6],
            [0, 1, 3, 7],
        ]);
        assert!(check_case(&case, &node, &wrong, &[("CGAL", six)], false).is_err());
    }

    #[test]
    fn finds_non_canonical_vertices() {
        let cells = tris(&[[0, 1, 2], [1, 2, 4]]);
        assert_eq!(non_canonical_vertex(&cells, &[0, 1, 2, 3, 4]), None);
        assert_eq!(non_canonical_vertex(&cells, &[0, 1, 2, 3, 1]), Some((4, 1)));
    }

    #[test]
    fn selects_cases() {
        let quick = select_cases(true, &[]).unwrap();
        assert!(quick.iter().any(|c| c.name == "grid3d-20"));
        assert!(!quick.iter().any(|c| c.name == "uniform3d-1m"));
        let full = select_cases(false, &[]).unwrap();
        assert!(full.iter().any(|c| c.name == "uniform3d-1m"));
        let only = select_cases(true, &["grid3d".into(), "sphere3d-500".into()]).unwrap();
        let names: Vec<&str> = only.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["grid3d-20", "sphere3d-500"]);
        assert!(select_cases(true, &["nope".into()]).is_err());
    }
}
