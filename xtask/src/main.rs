//! `cargo xtask`: project automation for delmesh.
//!
//! Commands (run `cargo xtask help`):
//! - `validate [--quick] [--only NAME]... [--report FILE.md]`: builds delmesh (release)
//!   and the CGAL driver, runs delmesh, CGAL and (3D) TetGen on every case of
//!   `cases::FAMILIES` and checks that delmesh agrees with them (exactly where the
//!   Delaunay triangulation is unique); prints a Markdown table with timings and peak
//!   memory. Exits non-zero when a check fails. `--quick` is the CI variant.
//! - `bench [--report FILE.md]`: the README's timing table (10^6 points in 3D and 2D,
//!   a 100^3 grid), median of 3 runs, with the command that produced it.
//! - `ref-check [CASE...]`: self-test of the reference side alone (CGAL vs TetGen).
//! - `ref-bench [--repeat N] [CASE...]`: timing and peak memory of the reference
//!   tools alone.
//! - `cdt [--quick]`: delmesh's Steiner-free 2D mesh of seeded polygons with holes against
//!   CGAL's constrained Delaunay triangulation (identical triangles required), with times.
//! - `surfaces [--quick] [--only NAME]... [--report FILE.md]`: delmesh's 3D meshes of
//!   closed surfaces (CGAL's example meshes, unpacked from Debian's `libcgal-demo`, and
//!   generated ones) next to TetGen's: surface recovery alone and the full pipeline,
//!   with exact checks of delmesh's meshes and a quality summary of both tools' (see
//!   `surfaces`). `--quick` is the CI variant.
//! - `gen [--out DIR] CASE...`: just write the cases' `.node` files.
//! - `cases`: list the case families.
//!
//! Where external output is parsed: `reference` (CGAL driver's stdout, TetGen's
//! stdout and files, GNU time's report), `delmesh` (delmesh's stderr), `formats`
//! (`.node`, `.ele`, `.cells` files), `surfaces` (`.off` files, TetGen's and delmesh's
//! `.node/.ele/.face` meshes, delmesh's JSON report, `tetgen -pd`, GNU time `-v`); each
//! place is marked "FORMAT:".
//! Arguments are parsed by hand to keep the dependencies small (`anyhow`, and `robust`
//! for exact orientation tests).

mod cases;
mod delmesh;
mod exact;
mod formats;
mod plc;
mod reference;
mod report;
mod surfaces;
mod validate;

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use cases::Case;
use reference::RefRun;
use report::{load_average, mb, secs};

const HELP: &str = "\
usage: cargo xtask <command> [args]

commands:
  validate [--quick] [--only NAME]... [--report FILE.md]
                                  build delmesh and run it, CGAL and TetGen (3D) on every
                                  case (`--quick`: the small sizes, one run per tool; else
                                  all sizes, median of 3 runs), check that delmesh agrees,
                                  print a Markdown table (also written to FILE.md); NAME is
                                  a family (uniform3d) or a case (uniform3d-50k)
  bench [--report FILE.md]        README timing table: uniform3d-1m, uniform2d-1m,
                                  grid3d-100, median of 3 runs
  ref-check [CASE...]             run CGAL and TetGen on CASEs (default: uniform3d-100k,
                                  uniform2d-100k, grid3d-20, dups3d-10k), print a table,
                                  check that they agree where Delaunay is unique
  ref-bench [--repeat N] [CASE...]
                                  median-of-N build time and peak memory of the reference
                                  tools (default N=3; default cases: uniform3d-100k,
                                  uniform3d-1m, uniform2d-100k, uniform2d-1m, grid3d-100)
  cdt [--quick]                   2D constrained Delaunay meshes of seeded polygons with
                                  holes (and free points): delmesh's triangles must equal
                                  CGAL's; prints both tools' times
  surfaces [--quick] [--only NAME]... [--report FILE.md]
                                  3D meshes of closed surfaces (CGAL's example meshes,
                                  installed from Debian's libcgal-demo when missing, and
                                  generated ones): `delmesh mesh --no-points` vs `tetgen
                                  -pQ` and `-pMQ` (surface recovery), `delmesh mesh` vs
                                  `tetgen -pqQ` (quality mesh); checks delmesh's meshes
                                  exactly, prints Markdown tables (also written to
                                  FILE.md); NAME is a case (elephant, sphere-in-box; an
                                  unknown NAME lists them); `--quick`: a small subset
  gen [--out DIR] CASE...         write the cases' .node files (default DIR target/xtask/cases)
  cases                           list the case families and their sizes
  help                            this text

A CASE is <family>-<size>, e.g. uniform3d-100k, grid3d-20 (see `cargo xtask cases`).
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
pub struct Ctx {
    /// Workspace root.
    pub root: PathBuf,
    /// `target/xtask/cases`: generated `.node` files.
    pub cases: PathBuf,
    /// `target/xtask/runs`: tool outputs, one folder per case.
    pub runs: PathBuf,
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
    let command = command_line(&args);
    match cmd.as_str() {
        "validate" => {
            let opts = parse_validate_args(rest, command)?;
            validate::validate(&ctx, &opts)
        }
        "surfaces" => {
            let (quick, only, report) = parse_run_args("surfaces", rest)?;
            let opts = surfaces::SurfacesOptions {
                quick,
                only,
                report,
                command,
            };
            surfaces::surfaces(&ctx, &opts)
        }
        "bench" => {
            let (report, rest) = take_option(rest, "--report")?;
            if let Some(a) = rest.first() {
                bail!("bench: unknown argument `{a}`\n{HELP}");
            }
            validate::bench(&ctx, report.as_deref().map(Path::new), &command)
        }
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
        "cdt" => {
            let quick = rest.iter().any(|a| a == "--quick");
            if let Some(a) = rest.iter().find(|a| *a != "--quick") {
                bail!("cdt: unknown argument `{a}`\n{HELP}");
            }
            plc::cdt(&ctx, quick)
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
            for f in cases::FAMILIES {
                let labels = |sizes: &[usize]| -> String {
                    let l: Vec<String> = sizes
                        .iter()
                        .map(|&s| {
                            let name = f.case(s).name;
                            name[f.name.len() + 1..].to_string()
                        })
                        .collect();
                    l.join(",")
                };
                println!(
                    "{:10} {}D {:10} quick: {:10} full: {:16} {:?}",
                    f.name,
                    f.gen.dim(),
                    f.kind.label(),
                    labels(f.quick),
                    labels(f.full),
                    f.gen
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

/// Arguments of `validate`: `--quick`, `--only NAME` (repeatable), `--report FILE`
/// (`--opt=VALUE` works too).
fn parse_validate_args(args: &[String], command: String) -> Result<validate::ValidateOptions> {
    let (quick, only, report) = parse_run_args("validate", args)?;
    Ok(validate::ValidateOptions {
        quick,
        only,
        report,
        command,
    })
}

/// The arguments `validate` and `surfaces` share: `--quick`, `--only NAME`
/// (repeatable), `--report FILE` (`--opt=VALUE` works too); `cmd` names the command in
/// errors.
fn parse_run_args(cmd: &str, args: &[String]) -> Result<(bool, Vec<String>, Option<PathBuf>)> {
    let (mut quick, mut only, mut report) = (false, Vec::new(), None);
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let (key, inline) = match a.split_once('=') {
            Some((k, v)) => (k, Some(v.to_string())),
            None => (a.as_str(), None),
        };
        let mut value = || {
            inline
                .clone()
                .or_else(|| it.next().cloned())
                .with_context(|| format!("{key} needs a value"))
        };
        match key {
            "--quick" if inline.is_none() => quick = true,
            "--only" => only.push(value()?),
            "--report" => report = Some(PathBuf::from(value()?)),
            _ => bail!("{cmd}: unknown argument `{a}`\n{HELP}"),
        }
    }
    Ok((quick, only, report))
}

/// `cargo xtask <args>`, quoted for a POSIX shell where needed: the exact command
/// printed with a report.
fn command_line(args: &[String]) -> String {
    let mut s = String::from("cargo xtask");
    for a in args {
        let plain = !a.is_empty()
            && a.chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_./=,:+@%".contains(c));
        if plain {
            s = s + " " + a;
        } else {
            s = s + " '" + &a.replace('\'', "'\\''") + "'";
        }
    }
    s
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
clock; TetGen: clock(), i.e. CPU time). cpu s: CPU time of the construction. peak MB: GNU \
time's maximum RSS of the whole run (read, build, write).";

/// Prints a Markdown table with aligned columns.
fn print_table(header: &[&str], rows: &[Vec<String>]) {
    print!("{}", report::markdown_table(header, rows));
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
        let workdir = ctx.runs.join(&case.name);
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
                    case.kind == cases::Kind::Degenerate,
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
                    "{}: {} and {} disagree{note}: {}",
                    case.name,
                    ta.name(),
                    tb.name(),
                    diff.describe(ta.name(), tb.name())
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
        let workdir = ctx.runs.join(&case.name);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn command_line_is_quoted_for_the_shell() {
        let args: Vec<String> = ["validate", "--only", "grid3d", "--report", "my report.md"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        assert_eq!(
            command_line(&args),
            "cargo xtask validate --only grid3d --report 'my report.md'"
        );
        assert_eq!(command_line(&["it's".into()]), "cargo xtask 'it'\\''s'");
    }

    #[test]
    fn validate_arguments() {
        let args = |a: &[&str]| -> Vec<String> { a.iter().map(|s| s.to_string()).collect() };
        let o = parse_validate_args(
            &args(&[
                "--quick",
                "--only",
                "grid3d",
                "--only=dups2d",
                "--report",
                "r.md",
            ]),
            "c".into(),
        )
        .unwrap();
        assert!(o.quick);
        assert_eq!(o.only, ["grid3d", "dups2d"]);
        assert_eq!(o.report, Some(PathBuf::from("r.md")));
        let o = parse_validate_args(&[], "c".into()).unwrap();
        assert!(!o.quick && o.only.is_empty() && o.report.is_none());
        for bad in [&["--only"][..], &["--fast"], &["--quick=1"], &["grid3d"]] {
            assert!(
                parse_validate_args(&args(bad), "c".into()).is_err(),
                "{bad:?}"
            );
        }
    }

    #[test]
    fn surfaces_arguments() {
        let args = |a: &[&str]| -> Vec<String> { a.iter().map(|s| s.to_string()).collect() };
        let (quick, only, report) = parse_run_args(
            "surfaces",
            &args(&[
                "--only=elephant",
                "--quick",
                "--only",
                "cow",
                "--report=s.md",
            ]),
        )
        .unwrap();
        assert!(quick);
        assert_eq!(only, ["elephant", "cow"]);
        assert_eq!(report, Some(PathBuf::from("s.md")));
        let err = parse_run_args("surfaces", &args(&["--fast"]))
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("surfaces: unknown argument `--fast`"),
            "{err}"
        );
    }

    #[test]
    fn options_are_split_out() {
        let args: Vec<String> = ["a", "--report=x.md", "b"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let (v, rest) = take_option(&args, "--report").unwrap();
        assert_eq!(v.as_deref(), Some("x.md"));
        assert_eq!(rest, ["a", "b"]);
        assert!(take_option(&["--report".to_string()], "--report").is_err());
    }
}
