//! The delmesh side of validation: building the release CLI and running
//! `delmesh delaunay IN.node -o OUT.ele --quiet [--validate]` on a case.
//!
//! External output parsed here (marked "FORMAT:" below):
//! - delmesh's stderr with `--quiet`: the line `build time: <seconds> s` (construction
//!   only) and, with `--validate`, a line `validation: ok ...` (the kernel's exact check
//!   of adjacency, orientation, empty spheres under the symbolic perturbation, and the
//!   Euler characteristic; delmesh exits with status 1 when it fails);
//! - delmesh's `.ele` output (read by `formats::read_ele`): numbered from the input's
//!   first index like TetGen's, duplicates mapped to their first occurrence;
//! - GNU time's report, via `reference::output_timed`.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{ensure, Context, Result};

use crate::reference;

/// Builds `target/release/delmesh` with `cargo build --release -p delmesh` (run from
/// the workspace root) and returns its path.
pub fn build(root: &Path) -> Result<PathBuf> {
    // Under `cargo xtask`, CARGO names the cargo that is running us.
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    eprintln!("xtask: cargo build --release -p delmesh");
    let status = Command::new(&cargo)
        .args(["build", "--release", "-p", "delmesh"])
        .current_dir(root)
        .status()
        .context("running cargo build")?;
    ensure!(status.success(), "cargo build --release -p delmesh failed");
    // CARGO_TARGET_DIR may move the target folder; the default is `<root>/target`.
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|t| if t.is_relative() { root.join(t) } else { t })
        .unwrap_or_else(|| root.join("target"));
    let bin = target.join("release/delmesh");
    ensure!(bin.is_file(), "{} was not built", bin.display());
    Ok(bin)
}

/// Fails unless this delmesh accepts `--validate`, so that a CLI without it is a
/// clear error up front rather than a usage error per case.
pub fn check_cli(bin: &Path) -> Result<()> {
    let out = Command::new(bin)
        .args(["delaunay", "--help"])
        .output()
        .with_context(|| format!("running {} delaunay --help", bin.display()))?;
    let help = String::from_utf8_lossy(&out.stdout);
    ensure!(
        help.contains("--validate"),
        "{} has no `delaunay --validate` option, which `cargo xtask validate` needs",
        bin.display()
    );
    Ok(())
}

/// One run of delmesh.
#[derive(Debug, Clone)]
pub struct DelmeshRun {
    /// The `build time:` it printed (construction only, wall clock).
    pub build_seconds: f64,
    /// GNU time's peak RSS of the whole run, KiB.
    pub peak_rss_kb: Option<u64>,
    /// The `.ele` it wrote.
    pub ele: PathBuf,
}

/// Runs `delmesh delaunay node -o <workdir>/<stem>.delmesh.ele --quiet [--validate]`
/// under GNU time. With `validate`, a failed validation (exit status 1) is an error
/// quoting delmesh's message.
pub fn run(bin: &Path, node: &Path, workdir: &Path, validate: bool) -> Result<DelmeshRun> {
    std::fs::create_dir_all(workdir)?;
    let stem = node
        .file_stem()
        .context("node file has no name")?
        .to_string_lossy()
        .into_owned();
    let ele = workdir.join(format!("{stem}.delmesh.ele"));
    let time_file = workdir.join(format!("{stem}.delmesh.time"));
    let mut args: Vec<&OsStr> = vec![
        OsStr::new("delaunay"),
        node.as_os_str(),
        OsStr::new("-o"),
        ele.as_os_str(),
        OsStr::new("--quiet"),
    ];
    if validate {
        args.push(OsStr::new("--validate"));
    }
    let (out, rss) = reference::output_timed(bin, &args, &time_file, true)?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    let what = if validate {
        "delmesh --validate"
    } else {
        "delmesh"
    };
    ensure!(
        out.status.success(),
        "{what} failed on {} ({}): {}",
        node.display(),
        out.status,
        stderr.trim()
    );
    let build_seconds = parse_build_time(&stderr)
        .with_context(|| format!("delmesh printed no `build time: S s` line:\n{stderr}"))?;
    if validate {
        ensure!(
            validation_ok(&stderr),
            "delmesh --validate exited 0 without `validation: ok`:\n{stderr}"
        );
    }
    Ok(DelmeshRun {
        build_seconds,
        peak_rss_kb: rss,
        ele,
    })
}

/// FORMAT: delmesh prints `build time: 0.123456 s` on stderr.
fn parse_build_time(stderr: &str) -> Option<f64> {
    let v = reference::find_value(stderr, "build time:")?;
    v.strip_suffix('s')?.trim().parse().ok()
}

/// FORMAT: with `--validate`, delmesh prints a line `validation: ok` on success,
/// possibly followed by details such as the time taken: `validation: ok (0.118 s)`.
fn validation_ok(stderr: &str) -> bool {
    stderr.lines().any(|l| {
        l.trim()
            .strip_prefix("validation: ok")
            .is_some_and(|rest| rest.is_empty() || rest.starts_with(' '))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_delmesh_stderr() {
        let quiet = "build time: 0.123456 s\nvalidation: ok\n";
        assert_eq!(parse_build_time(quiet), Some(0.123456));
        assert!(validation_ok(quiet));
        assert!(validation_ok("build time: 1 s\nvalidation: ok (0.118 s)\n"));
        assert!(!validation_ok("validation: okay?\n"));
        assert_eq!(parse_build_time("build time: 2 s"), Some(2.0));
        assert_eq!(parse_build_time("build time: fast"), None);
        assert_eq!(parse_build_time("vertices: 3\n"), None);
        assert!(!validation_ok(
            "build time: 1 s\nvalidation: failed: cell 3\n"
        ));
    }
}
