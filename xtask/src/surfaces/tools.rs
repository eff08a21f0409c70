//! Running delmesh and TetGen on surfaces, and getting the CGAL meshes.
//!
//! Every tool run goes through [`run_timed`]: `/usr/bin/time -v -o F timeout -k 10 S
//! program args`, so each tool's wall time, CPU time and peak memory of the whole run
//! (reading, meshing, writing) are measured the same way, by GNU time, and a run that
//! hangs is stopped after `S` seconds (`timeout` signals its own process group, so the
//! tool goes too). The rusage GNU time reports for `timeout` includes the tool it waited
//! for.
//!
//! External output parsed here (each marked "FORMAT:"): GNU time's `-v` report, TetGen's
//! `-d` report of intersecting facets, delmesh's error line, and the layout of CGAL's
//! `data.tar.gz`.

use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{bail, ensure, Context, Result};

use crate::reference::{self, find_value, GNU_TIME};

/// Where Debian's `libcgal-demo` puts CGAL's example data.
pub const CGAL_DATA_TARBALL: &str = "/usr/share/doc/libcgal-dev/data.tar.gz";
/// The Debian package that ships it.
pub const CGAL_DATA_PACKAGE: &str = "libcgal-demo";

/// One timed run of a tool.
#[derive(Debug, Clone, Default)]
pub struct Timed {
    /// Exit status 0.
    pub success: bool,
    /// Stopped by the time limit.
    pub timed_out: bool,
    /// `exit N`, `signal N` or `timeout after S s`.
    pub status: String,
    /// GNU time's elapsed wall-clock time, seconds.
    pub wall: Option<f64>,
    /// User + system CPU time, seconds.
    pub cpu: Option<f64>,
    /// Peak resident set size, KiB.
    pub rss_kb: Option<u64>,
    pub stdout: String,
    pub stderr: String,
}

/// What GNU time `-v` reported.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GnuTime {
    pub wall: Option<f64>,
    pub cpu: Option<f64>,
    pub rss_kb: Option<u64>,
    pub exit: Option<i32>,
    pub signal: Option<i32>,
}

/// FORMAT: GNU time 1.9 `-v` report lines (tab-indented): `User time (seconds): 0.05`,
/// `System time (seconds): 0.00`, `Elapsed (wall clock) time (h:mm:ss or m:ss): 0:00.27`
/// (or `1:02:03`), `Maximum resident set size (kbytes): 14140`, `Exit status: 0`, and
/// first, when the command was killed, `Command terminated by signal 6`.
pub fn parse_gnu_time(text: &str) -> GnuTime {
    let num = |key: &str| find_value(text, key).and_then(|v| v.parse::<f64>().ok());
    let wall = find_value(text, "Elapsed (wall clock) time (h:mm:ss or m:ss):").and_then(|v| {
        v.split(':').try_fold(0.0, |acc, part| {
            part.parse::<f64>().ok().map(|x| acc * 60.0 + x)
        })
    });
    let cpu = match (num("User time (seconds):"), num("System time (seconds):")) {
        (Some(u), Some(s)) => Some(u + s),
        _ => None,
    };
    GnuTime {
        wall,
        cpu,
        rss_kb: find_value(text, "Maximum resident set size (kbytes):")
            .and_then(|v| v.parse().ok()),
        exit: find_value(text, "Exit status:").and_then(|v| v.parse().ok()),
        signal: find_value(text, "Command terminated by signal").and_then(|v| v.parse().ok()),
    }
}

/// Runs `program args` under GNU time and `timeout` (see the module docs), capturing
/// its output. `time_file` receives GNU time's report.
pub fn run_timed(
    program: &Path,
    args: &[OsString],
    time_file: &Path,
    limit_secs: u64,
) -> Result<Timed> {
    let _ = fs::remove_file(time_file);
    let out = Command::new(GNU_TIME)
        .arg("-v")
        .arg("-o")
        .arg(time_file)
        .args(["timeout", "-k", "10"])
        .arg(limit_secs.to_string())
        .arg(program)
        .args(args)
        .output()
        .with_context(|| format!("running {} under GNU time", program.display()))?;
    let report = fs::read_to_string(time_file).unwrap_or_default();
    let t = parse_gnu_time(&report);
    // `timeout` exits with 124 when the limit hit (137 if the tool needed a KILL).
    let timed_out = matches!(t.exit.or(out.status.code()), Some(124 | 137)) && t.signal.is_none();
    let status = if timed_out {
        format!("timeout after {limit_secs} s")
    } else if let Some(s) = t.signal {
        format!("signal {s}")
    } else {
        format!("exit {}", t.exit.or(out.status.code()).unwrap_or(-1))
    };
    Ok(Timed {
        success: out.status.success() && t.signal.is_none(),
        timed_out,
        status,
        wall: t.wall,
        cpu: t.cpu,
        rss_kb: t.rss_kb,
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    })
}

/// The last non-empty line of a tool's stderr (delmesh's `error: ...`), shortened.
pub fn last_line(text: &str) -> String {
    let line = text
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("");
    let line = line.trim();
    if line.chars().count() > 300 {
        line.chars().take(300).collect::<String>() + "..."
    } else {
        line.to_string()
    }
}

/// FORMAT: `tetgen -pd X` (TetGen 1.5) ends its report with `No faces are intersecting.`
/// or `!! Found N pairs of faces are intersecting.`; `None` when neither appears.
pub fn parse_intersections(stdout: &str) -> Option<usize> {
    if stdout.contains("No faces are intersecting") {
        return Some(0);
    }
    let rest = stdout.split("Found ").nth(1)?;
    let (n, tail) = rest.split_once(' ')?;
    tail.starts_with("pairs of faces are intersecting")
        .then(|| n.parse().ok())
        .flatten()
}

/// One pair of intersecting facets in `tetgen -pd`'s report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IntersectingPair {
    /// TetGen's facet numbers (from 1, in the order of the input's faces).
    pub facets: [u64; 2],
    /// The two triangles' corners, in the input's vertex numbering.
    pub triangles: [[u32; 3]; 2],
}

/// FORMAT: `tetgen -pd X` (TetGen 1.5) lists each pair as
/// `  Facet #2612 intersects facet #2622 at triangles:` followed by the line
/// `    ( 633, 1393,  634) and (1394,  631,  634)`.
pub fn parse_intersecting_pairs(stdout: &str) -> Vec<IntersectingPair> {
    let mut pairs = Vec::new();
    let mut lines = stdout.lines();
    while let Some(line) = lines.next() {
        let Some(rest) = line.trim().strip_prefix("Facet #") else {
            continue;
        };
        let Some((a, tail)) = rest.split_once(" intersects facet #") else {
            continue;
        };
        let b = tail.split_whitespace().next().unwrap_or("");
        let (Ok(a), Ok(b)) = (a.parse::<u64>(), b.parse::<u64>()) else {
            continue;
        };
        let corners: Vec<u32> = lines
            .next()
            .unwrap_or("")
            .split(|c: char| !c.is_ascii_digit())
            .filter(|t| !t.is_empty())
            .filter_map(|t| t.parse().ok())
            .collect();
        if let [p, q, r, u, v, w] = corners[..] {
            pairs.push(IntersectingPair {
                facets: [a, b],
                triangles: [[p, q, r], [u, v, w]],
            });
        }
    }
    pairs
}

/// FORMAT: the facet numbers in one of delmesh's error lines: every integer after the first
/// `facet` (`facets that resisted: 3060, 3061 and 5 more`, `facets 12 and 40 intersect`),
/// except a count followed by `more`. Numbers before it (the file name, `(58060 points
/// added)`) are not facets.
pub fn named_facets(message: &str) -> Vec<u64> {
    let lower = message.to_ascii_lowercase();
    let Some(start) = lower.find("facet") else {
        return Vec::new();
    };
    let tail = &lower[start..];
    let mut out = Vec::new();
    let mut words = tail
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|w| !w.is_empty())
        .peekable();
    while let Some(w) = words.next() {
        if let Ok(n) = w.parse::<u64>() {
            if words.peek() != Some(&"more") {
                out.push(n);
            }
        }
    }
    out
}

/// FORMAT: delmesh's input checks name intersecting facets in their message (`facets 12
/// and 40 intersect`, ...): the word `intersect` followed somewhere by a number. This is
/// how a diagnosis is told from another failure such as `the surface could not be
/// recovered`.
pub fn names_intersection(message: &str) -> bool {
    let lower = message.to_ascii_lowercase();
    lower.contains("intersect") && lower.chars().any(|c| c.is_ascii_digit())
}

/// Fails unless `bin` has the 3D `mesh` options this command uses.
pub fn check_delmesh_cli(bin: &Path) -> Result<()> {
    let out = Command::new(bin)
        .args(["mesh", "--help"])
        .output()
        .with_context(|| format!("running {} mesh --help", bin.display()))?;
    let help = String::from_utf8_lossy(&out.stdout);
    for opt in ["--no-points", "--report", "--quiet", ".off"] {
        ensure!(
            help.contains(opt),
            "{} mesh has no `{opt}`, which `cargo xtask surfaces` needs",
            bin.display()
        );
    }
    Ok(())
}

fn find_meshes_dir(dir: &Path) -> Option<PathBuf> {
    for entry in fs::read_dir(dir).ok()?.flatten() {
        let p = entry.path();
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n == "meshes") && p.join("elephant.off").is_file() {
                return Some(p);
            }
            if let Some(found) = find_meshes_dir(&p) {
                return Some(found);
            }
        }
    }
    None
}

/// Makes CGAL's `data/meshes/*.off` available under `target/xtask/cgal-data/` and
/// returns that folder. The tarball comes from Debian's `libcgal-demo`: installed with
/// apt-get when missing and running as root, otherwise (or if that fails) fetched with
/// `apt-get download` and unpacked with `dpkg-deb -x` into `target/xtask/cgal-demo/`.
/// Nothing of it is committed.
pub fn cgal_meshes(xtask_dir: &Path) -> Result<PathBuf> {
    let out = xtask_dir.join("cgal-data");
    let stamp = out.join("unpacked");
    if stamp.is_file() {
        if let Some(dir) = find_meshes_dir(&out) {
            return Ok(dir);
        }
    }
    let tarball = cgal_tarball(xtask_dir)?;
    let _ = fs::remove_dir_all(&out);
    fs::create_dir_all(&out)?;
    eprintln!(
        "xtask: unpacking the .off meshes of {} into {}",
        tarball.display(),
        out.display()
    );
    // FORMAT: the tarball holds `data/meshes/<name>.off` (CGAL 5.5); only the `.off`
    // files of a `meshes` folder are extracted, wherever it is.
    reference::run_checked(
        Command::new("tar")
            .arg("-xzf")
            .arg(&tarball)
            .arg("-C")
            .arg(&out)
            .args(["--wildcards", "*meshes/*.off"]),
    )?;
    let dir = find_meshes_dir(&out).with_context(|| {
        format!(
            "{} has no meshes/elephant.off after unpacking {}",
            out.display(),
            tarball.display()
        )
    })?;
    fs::write(&stamp, tarball.display().to_string())?;
    Ok(dir)
}

/// The path of `data.tar.gz`, installing or downloading `libcgal-demo` if needed.
fn cgal_tarball(xtask_dir: &Path) -> Result<PathBuf> {
    let system = PathBuf::from(CGAL_DATA_TARBALL);
    if system.is_file() {
        return Ok(system);
    }
    let private = xtask_dir.join("cgal-demo");
    let local = private.join(CGAL_DATA_TARBALL.trim_start_matches('/'));
    if local.is_file() {
        return Ok(local);
    }
    if reference::is_root() {
        eprintln!("xtask: {CGAL_DATA_TARBALL} missing; apt-get install -y {CGAL_DATA_PACKAGE}");
        let install = || {
            reference::run_checked(
                Command::new("apt-get")
                    .args(["install", "-y", "-q", "--no-install-recommends"])
                    .arg(CGAL_DATA_PACKAGE)
                    .env("DEBIAN_FRONTEND", "noninteractive")
                    // apt's progress must not mix with the tables on stdout.
                    .stdout(std::io::stderr()),
            )
        };
        let ok = install().is_ok()
            || (reference::run_checked(
                Command::new("apt-get")
                    .args(["update", "-q"])
                    .stdout(std::io::stderr()),
            )
            .is_ok()
                && install().is_ok());
        if ok && system.is_file() {
            return Ok(system);
        }
        eprintln!("xtask: installing {CGAL_DATA_PACKAGE} failed; trying apt-get download");
    }
    fs::create_dir_all(&private)?;
    let status = Command::new("apt-get")
        .args(["download", CGAL_DATA_PACKAGE])
        .current_dir(&private)
        .stdout(std::io::stderr())
        .status()
        .context("running apt-get download")?;
    if !status.success() {
        bail!(
            "{CGAL_DATA_TARBALL} is missing and `apt-get download {CGAL_DATA_PACKAGE}` failed \
             ({status}); install it with:\n  sudo apt-get install {CGAL_DATA_PACKAGE}"
        );
    }
    let deb = fs::read_dir(&private)?
        .flatten()
        .map(|e| e.path())
        .find(|p| {
            p.extension().is_some_and(|e| e == "deb")
                && p.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with(CGAL_DATA_PACKAGE))
        })
        .with_context(|| format!("apt-get download left no .deb in {}", private.display()))?;
    reference::run_checked(Command::new("dpkg-deb").arg("-x").arg(&deb).arg(&private))?;
    let _ = fs::remove_file(&deb);
    ensure!(
        local.is_file(),
        "{} does not contain {CGAL_DATA_TARBALL}",
        deb.display()
    );
    Ok(local)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_gnu_time_reports() {
        let ok = "\tCommand being timed: \"timeout -k 10 60 tetgen -pQ a.off\"\n\
                  \tUser time (seconds): 0.05\n\tSystem time (seconds): 0.01\n\
                  \tElapsed (wall clock) time (h:mm:ss or m:ss): 1:02.50\n\
                  \tMaximum resident set size (kbytes): 14140\n\tExit status: 0\n";
        let t = parse_gnu_time(ok);
        assert_eq!(t.wall, Some(62.5));
        assert!((t.cpu.unwrap() - 0.06).abs() < 1e-12);
        assert_eq!((t.rss_kb, t.exit, t.signal), (Some(14140), Some(0), None));
        let long = "\tElapsed (wall clock) time (h:mm:ss or m:ss): 1:02:03\n";
        assert_eq!(parse_gnu_time(long).wall, Some(3723.0));
        let killed = "Command terminated by signal 6\n\tExit status: 0\n";
        assert_eq!(parse_gnu_time(killed).signal, Some(6));
        assert_eq!(parse_gnu_time(""), GnuTime::default());
    }

    #[test]
    fn parses_tetgen_intersection_reports() {
        let clean = "Detecting self-intersecting facets...\n\nNo faces are intersecting.\n\n\
                     Self-intersection seconds:  0.100642\n";
        assert_eq!(parse_intersections(clean), Some(0));
        let elk = "  Facet #2613 intersects facet #2622 at triangles:\n\
                   \x20   (1393,  633,  445) and (1394,  631,  634)\n\n\
                   !! Found 9 pairs of faces are intersecting.\n";
        assert_eq!(parse_intersections(elk), Some(9));
        assert_eq!(parse_intersections("Opening a.off.\n"), None);
    }

    #[test]
    fn parses_intersecting_pairs_and_named_facets() {
        let elk = "Detecting self-intersecting facets...\n\
                   \x20 Facet #670 intersects facet #2878 at triangles:\n\
                   \x20   ( 409,  425,  423) and (1493,  409, 1494)\n\
                   \x20 Facet #2612 intersects facet #2622 at triangles:\n\
                   \x20   ( 633, 1393,  634) and (1394,  631,  634)\n\n\
                   !! Found 2 pairs of faces are intersecting.\n";
        let pairs = parse_intersecting_pairs(elk);
        assert_eq!(pairs.len(), 2);
        assert_eq!(pairs[1].facets, [2612, 2622]);
        assert_eq!(pairs[1].triangles, [[633, 1393, 634], [1394, 631, 634]]);
        assert!(parse_intersecting_pairs("No faces are intersecting.\n").is_empty());
        assert_eq!(
            named_facets(
                "error: /x/cow2.off: the surface could not be recovered (58060 points added); \
                 facets that resisted: 3060, 3061 and 5 more"
            ),
            [3060, 3061]
        );
        assert_eq!(
            named_facets("error: a.off: facets 12 and 40 intersect"),
            [12, 40]
        );
        assert!(named_facets("error: a.off: no element is inside the domain").is_empty());
    }

    #[test]
    fn tells_diagnoses_from_other_errors() {
        assert!(names_intersection(
            "error: cow.off: facets 12 and 40 intersect (the surface must not cross itself)"
        ));
        assert!(names_intersection(
            "error: x.off: self-intersecting surface: facet 3 meets facet 9"
        ));
        assert!(!names_intersection(
            "error: cow.off: the surface could not be recovered (58060 points added); \
             facets that resisted: 3060"
        ));
        assert!(!names_intersection("the surface intersects itself"));
        assert_eq!(last_line("a\nerror: b\n\n"), "error: b");
    }

    #[test]
    fn timed_runs_report_status_and_limits() {
        if !Path::new(GNU_TIME).is_file() || !reference::on_path("timeout") {
            eprintln!("GNU time or timeout missing; skipping");
            return;
        }
        let dir = std::env::temp_dir().join(format!("xtask-timed-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let tf = dir.join("t.time");
        let sh = Path::new("/bin/sh");
        let arg = |s: &str| vec![OsString::from("-c"), OsString::from(s)];
        let t = run_timed(sh, &arg("echo out; echo err >&2"), &tf, 10).unwrap();
        assert!(t.success, "{t:?}");
        assert_eq!((t.stdout.as_str(), t.stderr.as_str()), ("out\n", "err\n"));
        assert!(t.wall.is_some() && t.rss_kb.is_some(), "{t:?}");
        let t = run_timed(sh, &arg("exit 3"), &tf, 10).unwrap();
        assert!(!t.success && !t.timed_out);
        assert_eq!(t.status, "exit 3");
        let t = run_timed(sh, &arg("kill -ABRT $$"), &tf, 10).unwrap();
        assert_eq!(t.status, "signal 6");
        let t = run_timed(sh, &arg("sleep 5"), &tf, 1).unwrap();
        assert!(t.timed_out && !t.success, "{t:?}");
        assert_eq!(t.status, "timeout after 1 s");
        fs::remove_dir_all(&dir).unwrap();
    }
}
