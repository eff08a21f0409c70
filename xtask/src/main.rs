//! `cargo xtask`: project automation for delmesh.
//!
//! Commands (run `cargo xtask help`):
//! - `ref-check [CASE...]`: self-test of the reference side. Installs TetGen and
//!   CGAL if needed, builds the CGAL driver, generates cases into
//!   `target/xtask/cases/`, runs CGAL and (3D) TetGen on them, prints a Markdown
//!   table and checks that the tools agree where the Delaunay triangulation is unique.
//! - `ref-bench [--repeat N] [CASE...]`: timing and peak memory of the reference
//!   tools (median of N runs): the numbers delmesh has to beat.
//! - `gen [--out DIR] CASE...`: just write the cases' `.node` files.
//! - `cases`: list the case catalog.
//!
//! Every command works from a table of cases (`cases::CATALOG` entries picked by
//! name), so a `validate` command is another table plus a loop like `ref_check`'s.
//! Arguments are parsed by hand to keep the dependencies at `anyhow` alone.

mod cases;
mod formats;
mod reference;

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use cases::Case;
use reference::RefRun;

const HELP: &str = "\
usage: cargo xtask <command> [args]

commands:
  ref-check [CASE...]             run CGAL and TetGen on CASEs (default: uniform3d-100k,
                                  uniform2d-100k, grid3d-20, dups3d-10k), print a table,
                                  check that they agree where Delaunay is unique
  ref-bench [--repeat N] [CASE...]
                                  median-of-N build time and peak memory of the reference
                                  tools (default N=3; default cases: uniform3d-100k,
                                  uniform3d-1m, uniform2d-100k, uniform2d-1m, grid3d-100)
  gen [--out DIR] CASE...         write the cases' .node files (default DIR target/xtask/cases)
  cases                           list the case catalog
  help                            this text
";

/// Cases of `ref-check`: one line per case.
const REF_CHECK: &[&str] = &[
    "uniform3d-100k",
    "uniform2d-100k",
    "grid3d-20",
    "dups3d-10k",
];
/// Cases of `ref-bench`.
const REF_BENCH: &[&str] = &[
    "uniform3d-100k",
    "uniform3d-1m",
    "uniform2d-100k",
    "uniform2d-1m",
    "grid3d-100",
];

/// Paths every command uses.
struct Ctx {
    /// Workspace root.
    root: PathBuf,
    /// `target/xtask/cases`: generated `.node` files.
    cases: PathBuf,
    /// `target/xtask/runs`: tool outputs, one folder per case.
    runs: PathBuf,
}

impl Ctx {
    fn new() -> Result<Self> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .context("xtask has no parent folder")?
            .to_path_buf();
        let base = root.join("target/xtask");
        Ok(Ctx {
            cases: base.join("cases"),
            runs: base.join("runs"),
            root,
        })
    }
}

fn main() {
    if let Err(e) = run() {
        eprintln!("xtask: error: {e:#}");
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((cmd, rest)) = args.split_first() else {
        print!("{HELP}");
        return Ok(());
    };
    let ctx = Ctx::new()?;
    match cmd.as_str() {
        "ref-check" => ref_check(&ctx, &case_list(rest, REF_CHECK)?),
        "ref-bench" => {
            let (repeat, rest) = take_option(rest, "--repeat")?;
            let repeat = repeat
                .map(|r| r.parse::<usize>())
                .transpose()?
                .unwrap_or(3)
                .max(1);
            ref_bench(&ctx, &case_list(&rest, REF_BENCH)?, repeat)
        }
        "gen" => {
            let (out, rest) = take_option(rest, "--out")?;
            let dir = out.map(PathBuf::from).unwrap_or_else(|| ctx.cases.clone());
            for c in case_list(&rest, &[])? {
                println!("{}", c.write(&dir)?.display());
            }
            Ok(())
        }
        "cases" => {
            for c in cases::CATALOG {
                println!(
                    "{:16} {}D {:>9} points  {:?}",
                    c.name,
                    c.gen.dim(),
                    c.gen.len(),
                    c.gen
                );
            }
            Ok(())
        }
        "help" | "-h" | "--help" => {
            print!("{HELP}");
            Ok(())
        }
        other => bail!("unknown command `{other}`\n{HELP}"),
    }
}

/// Splits `--name VALUE` (or `--name=VALUE`) out of `args`.
fn take_option(args: &[String], name: &str) -> Result<(Option<String>, Vec<String>)> {
    let mut value = None;
    let mut rest = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if a == name {
            value = Some(
                it.next()
                    .with_context(|| format!("{name} needs a value"))?
                    .clone(),
            );
        } else if let Some(v) = a.strip_prefix(name).and_then(|v| v.strip_prefix('=')) {
            value = Some(v.to_string());
        } else {
            rest.push(a.clone());
        }
    }
    Ok((value, rest))
}

/// The named cases, or `default` when none are named.
fn case_list(names: &[String], default: &[&str]) -> Result<Vec<Case>> {
    if let Some(flag) = names.iter().find(|n| n.starts_with('-')) {
        bail!("unknown option `{flag}`");
    }
    if names.is_empty() {
        if default.is_empty() {
            bail!("name at least one case (see `cargo xtask cases`)");
        }
        return default.iter().map(|n| cases::by_name(n)).collect();
    }
    names.iter().map(|n| cases::by_name(n)).collect()
}

/// A reference tool.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Tool {
    Cgal,
    TetGen,
}

impl Tool {
    fn name(self) -> &'static str {
        match self {
            Tool::Cgal => "CGAL",
            Tool::TetGen => "TetGen",
        }
    }

    /// The tools that handle a case of this dimension.
    fn for_dim(dim: usize) -> &'static [Tool] {
        if dim == 3 {
            &[Tool::Cgal, Tool::TetGen]
        } else {
            &[Tool::Cgal]
        }
    }

    fn run(self, driver: &Path, node: &Path, workdir: &Path) -> Result<RefRun> {
        match self {
            Tool::Cgal => {
                std::fs::create_dir_all(workdir)?;
                let stem = node.file_stem().unwrap_or_default().to_string_lossy();
                reference::run_cgal(driver, node, &workdir.join(format!("{stem}.cgal.cells")))
            }
            Tool::TetGen => reference::run_tetgen(node, workdir),
        }
    }
}

/// How to read the timing columns.
const TIMING_NOTE: &str = "build s: the tool's own timing of the construction only (CGAL: wall \
clock; TetGen: clock(), i.e. CPU time). cpu s: CPU time of the construction. peak MB: CGAL: \
VmHWM right after construction (includes the parsed input); TetGen: GNU time's maximum RSS of \
the whole run.";

fn secs(s: Option<f64>) -> String {
    s.map_or("-".into(), |s| format!("{s:.3}"))
}

fn mb(kb: Option<u64>) -> String {
    kb.map_or("-".into(), |k| format!("{:.1}", k as f64 / 1024.0))
}

/// Prints a Markdown table with aligned columns.
fn print_table(header: &[&str], rows: &[Vec<String>]) {
    let mut width: Vec<usize> = header.iter().map(|h| h.len()).collect();
    for r in rows {
        for (w, c) in width.iter_mut().zip(r) {
            *w = (*w).max(c.len());
        }
    }
    let line = |cells: Vec<&str>| {
        let padded: Vec<String> = cells
            .iter()
            .zip(&width)
            .map(|(c, w)| format!("{c:w$}"))
            .collect();
        println!("| {} |", padded.join(" | "));
    };
    line(header.to_vec());
    println!(
        "|{}|",
        width
            .iter()
            .map(|w| "-".repeat(w + 2))
            .collect::<Vec<_>>()
            .join("|")
    );
    for r in rows {
        line(r.iter().map(String::as_str).collect());
    }
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

/// Checks one tool's cells for sanity: no flat cells, and the measures sum to the
/// hull's when that is known. Returns a short verdict.
fn sanity(case: &Case, node: &formats::NodeFile, cells: &formats::CellSet) -> Result<String> {
    let (sum, flat) = formats::measure_sum(node, cells);
    if flat > 0 {
        bail!("{}: {flat} cells of zero measure", case.name);
    }
    match case.gen.hull_measure() {
        Some(hull) if (sum - hull).abs() > 1e-9 * hull => {
            bail!("{}: cells cover {sum}, the hull is {hull}", case.name)
        }
        Some(_) => Ok("covers hull".into()),
        None => Ok("no flat cells".into()),
    }
}

fn ref_check(ctx: &Ctx, list: &[Case]) -> Result<()> {
    reference::ensure_tools()?;
    let driver = reference::build_cgal_driver(&ctx.root)?;
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for case in list {
        let node_path = case.write(&ctx.cases)?;
        let node = formats::read_node(&node_path)?;
        let dups = formats::duplicate_canonical_map(&node);
        let workdir = ctx.runs.join(case.name);
        let mut results: Vec<(Tool, formats::CellSet)> = Vec::new();
        for &tool in Tool::for_dim(node.dim) {
            eprintln!("xtask: {} on {}", tool.name(), case.name);
            let r = tool.run(&driver, &node_path, &workdir)?;
            let mut cells = formats::read_cells(&r.cells_file, node.dim + 1)?;
            if let Some(map) = &dups {
                cells = cells.remap(map)?;
            }
            let verdict = sanity(case, &node, &cells).unwrap_or_else(|e| {
                failures.push(format!("{e:#}"));
                "FAILED".into()
            });
            rows.push(vec![
                case.name.to_string(),
                node.len().to_string(),
                tool.name().into(),
                r.cells.to_string(),
                format!("{:.3}", r.build_seconds),
                secs(r.build_cpu_seconds),
                mb(r.peak_rss_kb),
                verdict,
            ]);
            results.push((tool, cells));
        }
        if let [(ta, a), (tb, b)] = results.as_slice() {
            let diff = formats::compare(a, b)?;
            let (what, ok) = if diff.is_empty() {
                ("identical".to_string(), true)
            } else {
                // Co-spherical input: the Delaunay triangulation is not unique and the
                // tools break ties differently, so a difference is allowed there.
                (
                    format!("{} vs {} cells differ", diff.only_a, diff.only_b),
                    !case.gen.unique_delaunay(),
                )
            };
            let note = if dups.is_some() {
                " (after merging duplicates)"
            } else {
                ""
            };
            let pair = format!("{} = {}?", ta.name(), tb.name());
            eprintln!("xtask: {}: {pair} {what}{note}", case.name);
            let mut row = vec![case.name.to_string(), String::new(), pair];
            row.extend(std::iter::repeat_n(String::new(), 4));
            row.push(if ok {
                format!("{what}{note}")
            } else {
                format!("FAILED: {what}")
            });
            rows.push(row);
            if !ok {
                failures.push(format!(
                    "{}: {} and {} disagree: {what}{note}; e.g. {:?}",
                    case.name,
                    ta.name(),
                    tb.name(),
                    diff.examples
                ));
            }
        }
    }
    println!();
    print_table(
        &[
            "case", "points", "tool", "cells", "build s", "cpu s", "peak MB", "check",
        ],
        &rows,
    );
    println!("\n{TIMING_NOTE}");
    if !failures.is_empty() {
        bail!("ref-check failed:\n  {}", failures.join("\n  "));
    }
    println!("\nref-check: ok");
    Ok(())
}

/// Median, and the "min-max" range, of a non-empty sample.
fn stats(v: &mut [f64]) -> (f64, String) {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    };
    (median, format!("{:.3}-{:.3}", v[0], v[n - 1]))
}

fn ref_bench(ctx: &Ctx, list: &[Case], repeat: usize) -> Result<()> {
    reference::ensure_tools()?;
    let driver = reference::build_cgal_driver(&ctx.root)?;
    let load_before = load_average();
    let mut rows = Vec::new();
    for case in list {
        let node_path = case.write(&ctx.cases)?;
        let workdir = ctx.runs.join(case.name);
        for &tool in Tool::for_dim(case.gen.dim()) {
            let (mut wall, mut cpu, mut rss) = (Vec::new(), Vec::new(), Vec::new());
            let mut cells = 0;
            for i in 0..repeat {
                let r = tool.run(&driver, &node_path, &workdir)?;
                eprintln!(
                    "xtask: {} {} run {}/{repeat}: {:.3} s (cpu {}), {} MB (load {})",
                    case.name,
                    tool.name(),
                    i + 1,
                    r.build_seconds,
                    secs(r.build_cpu_seconds),
                    mb(r.peak_rss_kb),
                    load_average()
                );
                wall.push(r.build_seconds);
                cpu.extend(r.build_cpu_seconds);
                rss.extend(r.peak_rss_kb.map(|k| k as f64));
                cells = r.cells;
            }
            let (wall_med, wall_range) = stats(&mut wall);
            let cpu_med = if cpu.is_empty() {
                "-".into()
            } else {
                format!("{:.3}", stats(&mut cpu).0)
            };
            let rss_med = if rss.is_empty() {
                "-".into()
            } else {
                format!("{:.1}", stats(&mut rss).0 / 1024.0)
            };
            rows.push(vec![
                case.name.to_string(),
                case.gen.len().to_string(),
                tool.name().into(),
                cells.to_string(),
                format!("{wall_med:.3}"),
                wall_range,
                cpu_med,
                rss_med,
            ]);
        }
    }
    println!();
    let build = format!("build s (median of {repeat})");
    print_table(
        &[
            "case", "points", "tool", "cells", &build, "min-max", "cpu s", "peak MB",
        ],
        &rows,
    );
    println!("\n{TIMING_NOTE}");
    println!(
        "load average before: {load_before}, after: {} (2 cores)",
        load_average()
    );
    Ok(())
}
