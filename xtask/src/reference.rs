//! The external reference side of validation: installing and running TetGen and a
//! small CGAL driver on `.node` inputs, and turning their output into `.cells` files
//! (see `formats`) plus the build time and peak memory each tool reports.
//!
//! External output formats parsed here (each marked "FORMAT:" below):
//! - the CGAL driver's stdout (`cgal_build_seconds`, `cgal_build_cpu_seconds`,
//!   `cgal_cells`, `cgal_peak_rss_kb` lines), defined by `xtask/cgal/delaunay.cpp`;
//! - TetGen 1.5's terminal output (`Delaunay seconds:` line, duplicate warnings);
//! - TetGen's `.ele` and `.node` output files;
//! - GNU time's `-v` report (`Maximum resident set size (kbytes):`).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::SystemTime;

use anyhow::{bail, ensure, Context, Result};

use crate::formats::{self, CellSet};

/// Debian packages providing the reference tools.
const PACKAGES: &[&str] = &["tetgen", "libcgal-dev", "time", "g++"];
/// A header that exists exactly when CGAL is installed.
const CGAL_HEADER: &str = "/usr/include/CGAL/Delaunay_triangulation_3.h";
/// GNU time, used for every tool's peak memory (whole run: read, build, write).
pub const GNU_TIME: &str = "/usr/bin/time";

/// What a reference tool reports for one run.
#[derive(Debug, Clone)]
pub struct RefRun {
    /// Construction time as measured by the tool itself (excludes reading the input
    /// and writing the output): wall-clock for the CGAL driver; for TetGen, which only
    /// reports `clock()` time, this is CPU time.
    pub build_seconds: f64,
    /// CPU time of the construction when known (CGAL driver: process CPU time;
    /// TetGen: its printed time). Robust to a loaded machine for these
    /// single-threaded tools, unlike wall-clock.
    pub build_cpu_seconds: Option<f64>,
    /// Number of finite cells.
    pub cells: usize,
    /// Peak resident memory of the whole run (reading, construction, writing) in KiB,
    /// from GNU time, when it could be measured. (Without GNU time the CGAL driver's
    /// own figure is used: its peak right after construction.)
    pub peak_rss_kb: Option<u64>,
    /// The cells in `.cells` format.
    pub cells_file: PathBuf,
}

pub(crate) fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .map(|paths| std::env::split_paths(&paths).any(|d| d.join(program).is_file()))
        .unwrap_or(false)
}

pub(crate) fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

pub(crate) fn run_checked(cmd: &mut Command) -> Result<()> {
    let status = cmd.status().with_context(|| format!("running {cmd:?}"))?;
    ensure!(status.success(), "{cmd:?} failed: {status}");
    Ok(())
}

/// Makes sure `tetgen`, the CGAL headers, `g++` and GNU time are installed. When one
/// is missing and we run as root, installs them with apt-get; otherwise fails with
/// the command to run.
pub fn ensure_tools() -> Result<()> {
    let missing = |t: &(&str, bool)| !t.1;
    let checks = [
        ("tetgen", on_path("tetgen")),
        ("CGAL headers", Path::new(CGAL_HEADER).is_file()),
        ("g++", on_path("g++")),
        ("GNU time", Path::new(GNU_TIME).is_file()),
    ];
    if !checks.iter().any(missing) {
        return Ok(());
    }
    let names: Vec<&str> = checks.iter().filter(|t| missing(t)).map(|t| t.0).collect();
    let command = format!(
        "apt-get update && apt-get install -y {}",
        PACKAGES.join(" ")
    );
    if !is_root() {
        bail!(
            "missing {}; install them with:\n  sudo {command}",
            names.join(", ")
        );
    }
    eprintln!("xtask: missing {}; running `{command}`", names.join(", "));
    run_checked(Command::new("apt-get").arg("update"))?;
    run_checked(
        Command::new("apt-get")
            .args(["install", "-y"])
            .args(PACKAGES)
            .env("DEBIAN_FRONTEND", "noninteractive"),
    )?;
    ensure!(
        on_path("tetgen") && Path::new(CGAL_HEADER).is_file(),
        "install did not provide the tools"
    );
    Ok(())
}

fn mtime(p: &Path) -> Option<SystemTime> {
    fs::metadata(p).and_then(|m| m.modified()).ok()
}

/// Compiler flags of the CGAL driver. -frounding-math: CGAL's own CMake setup adds it
/// for GCC (the interval-arithmetic filters of the predicates depend on it).
const CXX_FLAGS: &[&str] = &["-O3", "-DNDEBUG", "-std=c++17", "-frounding-math"];
/// Libraries: GMP/MPFR back the exact fallback of the predicates.
const CXX_LIBS: &[&str] = &["-lmpfr", "-lgmp"];

/// Compiles `xtask/cgal/delaunay.cpp` into `target/xtask/cgal-delaunay` when the
/// binary is missing, older than the source, or built with other flags (recorded in
/// `cgal-delaunay.flags`), and returns the binary's path.
pub fn build_cgal_driver(root: &Path) -> Result<PathBuf> {
    build_cgal_program(root, "delaunay")
}

/// Compiles `xtask/cgal/<name>.cpp` into `target/xtask/cgal-<name>` (see
/// [`build_cgal_driver`]).
pub fn build_cgal_program(root: &Path, name: &str) -> Result<PathBuf> {
    let src = root.join(format!("xtask/cgal/{name}.cpp"));
    let out_dir = root.join("target/xtask");
    let bin = out_dir.join(format!("cgal-{name}"));
    let stamp = out_dir.join(format!("cgal-{name}.flags"));
    let flags = format!("g++ {} {}", CXX_FLAGS.join(" "), CXX_LIBS.join(" "));
    let src_time = mtime(&src).with_context(|| format!("missing {}", src.display()))?;
    let fresh = mtime(&bin).is_some_and(|b| b >= src_time);
    if fresh && fs::read_to_string(&stamp).ok().as_deref() == Some(flags.as_str()) {
        return Ok(bin);
    }
    fs::create_dir_all(&out_dir)?;
    let tmp = out_dir.join(format!("cgal-{name}.tmp"));
    eprintln!("xtask: compiling {} (takes ~30 s)", src.display());
    run_checked(
        Command::new("g++")
            .args(CXX_FLAGS)
            .arg("-o")
            .arg(&tmp)
            .arg(&src)
            .args(CXX_LIBS),
    )?;
    fs::rename(&tmp, &bin)?;
    fs::write(&stamp, flags)?;
    Ok(bin)
}

/// FORMAT: finds `<key> <value>` (whitespace-separated, first match) in a tool's
/// stdout.
pub fn find_value<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    text.lines()
        .find_map(|l| l.trim().strip_prefix(key))
        .map(str::trim)
}

/// Runs `program args` (stdout captured, stderr inherited unless `capture_stderr`),
/// under GNU time `-v -o time_file` when GNU time is installed, and returns the output
/// and the peak RSS GNU time measured. The exit status is the program's (GNU time
/// passes it through).
pub fn output_timed(
    program: &Path,
    args: &[&std::ffi::OsStr],
    time_file: &Path,
    capture_stderr: bool,
) -> Result<(std::process::Output, Option<u64>)> {
    let timed = Path::new(GNU_TIME).is_file();
    let mut cmd = if timed {
        let _ = fs::remove_file(time_file);
        let mut c = Command::new(GNU_TIME);
        c.arg("-v").arg("-o").arg(time_file).arg(program);
        c
    } else {
        Command::new(program)
    };
    cmd.args(args);
    if !capture_stderr {
        cmd.stderr(Stdio::inherit());
    }
    let out = cmd
        .output()
        .with_context(|| format!("running {}", program.display()))?;
    let rss = if timed {
        parse_gnu_time_rss(time_file)
    } else {
        None
    };
    Ok((out, rss))
}

/// Runs the CGAL driver on `node`, writing `out_cells` (and `<out_cells>.time`, GNU
/// time's report).
pub fn run_cgal(driver: &Path, node: &Path, out_cells: &Path) -> Result<RefRun> {
    let time_file = out_cells.with_extension("time");
    let (out, rss) = output_timed(
        driver,
        &[node.as_os_str(), out_cells.as_os_str()],
        &time_file,
        false,
    )?;
    ensure!(
        out.status.success(),
        "{} {} failed: {}",
        driver.display(),
        node.display(),
        out.status
    );
    let text = String::from_utf8_lossy(&out.stdout);
    // FORMAT: the driver prints exactly the four lines below (see delaunay.cpp).
    let get = |key: &str| {
        find_value(&text, key).with_context(|| format!("CGAL driver printed no `{key}`:\n{text}"))
    };
    let own_rss: u64 = get("cgal_peak_rss_kb")?.parse()?;
    Ok(RefRun {
        build_seconds: get("cgal_build_seconds")?.parse()?,
        build_cpu_seconds: Some(get("cgal_build_cpu_seconds")?.parse()?),
        cells: get("cgal_cells")?.parse()?,
        peak_rss_kb: Some(rss.unwrap_or(own_rss)),
        cells_file: out_cells.to_path_buf(),
    })
}

/// FORMAT: GNU time `-v` writes `\tMaximum resident set size (kbytes): N`.
pub fn parse_gnu_time_rss(path: &Path) -> Option<u64> {
    let text = fs::read_to_string(path).ok()?;
    find_value(&text, "Maximum resident set size (kbytes):")?
        .parse()
        .ok()
}

/// Runs `tetgen` with `switches` on `node` (inside `workdir`), optionally under GNU
/// time, and returns its stdout and the peak RSS.
fn tetgen(switches: &str, node: &Path, time_file: Option<&Path>) -> Result<(String, Option<u64>)> {
    let mut cmd = match time_file {
        Some(tf) => {
            let mut c = Command::new(GNU_TIME);
            c.arg("-v").arg("-o").arg(tf).arg("tetgen");
            c
        }
        None => Command::new("tetgen"),
    };
    let out = cmd
        .arg(switches)
        .arg(node)
        .stderr(Stdio::inherit())
        .output();
    let out = out.with_context(|| format!("running tetgen {switches} {}", node.display()))?;
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    ensure!(
        out.status.success(),
        "tetgen {switches} {} failed: {}\n{text}",
        node.display(),
        out.status
    );
    Ok((text, time_file.and_then(parse_gnu_time_rss)))
}

/// Runs TetGen's plain Delaunay tetrahedralization of the point set in `node` (3D
/// only) inside `workdir`, and writes `workdir/<stem>.tetgen.cells`.
///
/// Switches: a bare `.node` input (no `-p`) makes TetGen tetrahedralize the point set
/// itself. `-N` suppresses the output `.node`, `-F` the `.face` file; `.edge` and
/// `.neigh` are not written without `-e`/`-n`. So `tetgen -NF x.node` writes only
/// `x.1.ele`. Without `-V` its terminal output is a short summary that still includes
/// its own `Delaunay seconds:` timing, which covers sorting and insertion but not
/// reading or writing files.
///
/// Duplicates: TetGen drops coincident points ("Point #i is coincident with #j.
/// Ignored!"), then renumbers the remaining points compactly ("Jettisoning redundant
/// points.") and the `.ele` refers to that renumbering. When that happens the input is
/// run a second time, with each point carrying its 0-based index as a node
/// attribute and with the output `.node` enabled, which gives the map back to input
/// indices. Timing and memory always come from the first, unmodified run.
pub fn run_tetgen(node: &Path, workdir: &Path) -> Result<RefRun> {
    let input = formats::read_node(node)?;
    ensure!(
        input.dim == 3,
        "tetgen is 3D only; {} is {}D",
        node.display(),
        input.dim
    );
    fs::create_dir_all(workdir)?;
    let stem = node
        .file_stem()
        .context("node file has no name")?
        .to_string_lossy()
        .into_owned();
    // TetGen writes its output next to its input, so give it a private copy. A hard
    // link or symlink would do, but a copy keeps workdir self-contained and stops
    // TetGen from ever writing beside the original.
    let local = workdir.join(format!("{stem}.node"));
    let copied = fs::canonicalize(node).ok() != fs::canonicalize(&local).ok();
    if copied {
        fs::copy(node, &local).with_context(|| format!("copying to {}", local.display()))?;
    }
    let ele = workdir.join(format!("{stem}.1.ele"));
    let _ = fs::remove_file(&ele);
    let time_file = workdir.join(format!("{stem}.tetgen.time"));
    let timed = Path::new(GNU_TIME).is_file().then_some(time_file.as_path());
    let (stdout, peak_rss_kb) = tetgen("-NF", &local, timed)?;

    // FORMAT: TetGen 1.5 prints `Delaunay seconds:  0.008848` after inserting the
    // vertices (with or without -V). It is measured with clock(), i.e. CPU time:
    // under load its `Total running seconds` matches GNU time's user time, not wall.
    let build_seconds: f64 = find_value(&stdout, "Delaunay seconds:")
        .with_context(|| format!("no `Delaunay seconds:` in tetgen output:\n{stdout}"))?
        .parse()?;
    let merged = stdout.contains("Jettisoning") || stdout.contains("is coincident with");

    let cells = if merged {
        tetgen_cells_with_index_map(&input, workdir, &stem)?
    } else {
        // FORMAT: `.ele` vertex numbers follow the input's own first index.
        formats::read_ele(&ele, 4, input.first_index)?
    };
    let cells_file = workdir.join(format!("{stem}.tetgen.cells"));
    cells.write(&cells_file)?;
    // The `.cells` file holds everything needed; TetGen's own files are large
    // (10^6 points: ~250 MB of `.ele`), so only keep them on failure.
    for f in [&ele, &workdir.join(format!("{stem}-idx.node"))] {
        let _ = fs::remove_file(f);
    }
    for ext in ["1.node", "1.ele"] {
        let _ = fs::remove_file(workdir.join(format!("{stem}-idx.{ext}")));
    }
    if copied {
        let _ = fs::remove_file(&local);
    }
    Ok(RefRun {
        build_seconds,
        build_cpu_seconds: Some(build_seconds),
        cells: cells.len(),
        peak_rss_kb,
        cells_file,
    })
}

/// Second TetGen run for inputs with duplicates: every point carries its 0-based input
/// index as its only attribute, and TetGen writes its (renumbered) `.node`, whose
/// attribute column maps output numbers back to input indices.
fn tetgen_cells_with_index_map(
    input: &formats::NodeFile,
    workdir: &Path,
    stem: &str,
) -> Result<CellSet> {
    let tagged = workdir.join(format!("{stem}-idx.node"));
    let index: Vec<f64> = (0..input.len()).map(|i| i as f64).collect();
    formats::write_node(&tagged, input.dim, &input.coords, 1, &index)?;
    // -Q: quiet; no -N, so `<stem>-idx.1.node` is written.
    tetgen("-QF", &tagged, None)?;
    let out_node = formats::read_node(&workdir.join(format!("{stem}-idx.1.node")))?;
    ensure!(out_node.nattr >= 1, "tetgen dropped the index attribute");
    // FORMAT: attributes are plain decimals; integer values below 2^53 stay exact.
    let map: Vec<u32> = (0..out_node.len())
        .map(|i| out_node.attrs[i * out_node.nattr] as u32)
        .collect();
    let cells = formats::read_ele(
        &workdir.join(format!("{stem}-idx.1.ele")),
        4,
        out_node.first_index,
    )?;
    cells.remap(&map)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cases::Gen;

    /// Writes `coords` as a 1-based `.node` file with a comment line.
    fn write_one_based(path: &Path, coords: &[f64]) {
        let mut text = format!("# 1-based\n{} 3 0 0\n", coords.len() / 3);
        for (i, p) in coords.chunks(3).enumerate() {
            text += &format!("{} {} {} {}\n", i + 1, p[0], p[1], p[2]);
        }
        fs::write(path, text).unwrap();
    }

    /// TetGen's output must map back to the same 0-based cells whatever the input's
    /// first index, with and without duplicates (which TetGen renumbers away).
    #[test]
    fn tetgen_numbering_is_normalized() {
        if !on_path("tetgen") {
            eprintln!("tetgen not installed; skipping");
            return;
        }
        let dir = std::env::temp_dir().join(format!("xtask-tetgen-{}", std::process::id()));
        for (name, gen) in [
            ("plain", Gen::Uniform { dim: 3, n: 500 }),
            (
                "dups",
                Gen::Duplicates {
                    dim: 3,
                    n: 500,
                    permille: 100,
                },
            ),
        ] {
            let coords = gen.points(7);
            let zero = dir.join(format!("{name}0.node"));
            fs::create_dir_all(&dir).unwrap();
            formats::write_node(&zero, 3, &coords, 0, &[]).unwrap();
            let one = dir.join(format!("{name}1.node"));
            write_one_based(&one, &coords);
            let node = formats::read_node(&zero).unwrap();
            let canon = |r: RefRun| {
                let cells = formats::read_cells(&r.cells_file, 4).unwrap();
                match formats::duplicate_canonical_map(&node) {
                    Some(map) => cells.remap(&map).unwrap(),
                    None => cells,
                }
            };
            let a = canon(run_tetgen(&zero, &dir.join("w0")).unwrap());
            let b = canon(run_tetgen(&one, &dir.join("w1")).unwrap());
            assert!(a.len() > 1000, "{name}: {} cells", a.len());
            assert_eq!(a, b, "{name}");
            let (vol, flat) = formats::measure_sum(&node, &a);
            assert_eq!(flat, 0, "{name}");
            assert!(vol > 0.8 && vol < 1.0, "{name}: volume {vol}");
        }
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn finds_values_in_tool_output() {
        let text = "Opening a.node.\nDelaunay seconds:  0.008848\n\tMaximum resident set size (kbytes): 4236\n";
        assert_eq!(find_value(text, "Delaunay seconds:"), Some("0.008848"));
        assert_eq!(
            find_value(text, "Maximum resident set size (kbytes):"),
            Some("4236")
        );
        assert_eq!(find_value(text, "cgal_cells"), None);
    }
}
