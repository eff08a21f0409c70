//! Markdown output shared by the commands: tables, number formatting, and the
//! description of the machine and tools a table was produced on.

use std::path::Path;
use std::process::Command;

/// A Markdown table with aligned columns (ends with a newline).
pub fn markdown_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut width: Vec<usize> = header.iter().map(|h| h.len()).collect();
    for r in rows {
        for (w, c) in width.iter_mut().zip(r) {
            *w = (*w).max(c.len());
        }
    }
    let line = |cells: &mut dyn Iterator<Item = &str>| {
        let padded: Vec<String> = cells.zip(&width).map(|(c, w)| format!("{c:w$}")).collect();
        format!("| {} |\n", padded.join(" | "))
    };
    let mut s = line(&mut header.iter().copied());
    let rules: Vec<String> = width.iter().map(|w| "-".repeat(w + 2)).collect();
    s += &format!("|{}|\n", rules.join("|"));
    for r in rows {
        s += &line(&mut r.iter().map(String::as_str));
    }
    s
}

/// Seconds with 3 decimals, `-` when unknown.
pub fn secs(s: Option<f64>) -> String {
    s.map_or("-".into(), |s| format!("{s:.3}"))
}

/// KiB as MB with one decimal, `-` when unknown.
pub fn mb(kb: Option<u64>) -> String {
    kb.map_or("-".into(), |k| format!("{:.1}", k as f64 / 1024.0))
}

/// `a / b` with 2 decimals, `-` when either is unknown.
pub fn ratio(a: Option<f64>, b: Option<f64>) -> String {
    match (a, b) {
        (Some(a), Some(b)) if b > 0.0 => format!("{:.2}", a / b),
        _ => "-".into(),
    }
}

/// The 1, 5 and 15 minute load averages.
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

/// First line of a command's stdout, if it runs and succeeds.
fn first_line(program: &str, args: &[&str], dir: &Path) -> Option<String> {
    let out = Command::new(program)
        .args(args)
        .current_dir(dir)
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text.lines().next()?.trim().to_string();
    (out.status.success() && !line.is_empty()).then_some(line)
}

/// Markdown lines describing where and with what a table was produced: the exact
/// command, the commit, the CPU and core count, the tool versions, and the load.
pub fn environment(root: &Path, command: &str, load_before: &str) -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let threads = std::env::var("RAYON_NUM_THREADS")
        .map(|t| format!("RAYON_NUM_THREADS={t}"))
        .unwrap_or_else(|_| format!("all {cores} cores (RAYON_NUM_THREADS unset)"));
    format!(
        "{}\n\
         Tools: CGAL {} (Debian libcgal-dev, EPICK kernel, range insertion), TetGen {} \
         (Debian tetgen, `tetgen -NF`), delmesh threads: {threads}\n",
        machine(root, command, load_before),
        package_version("libcgal-dev", root),
        package_version("tetgen", root),
    )
}

/// The command, commit, machine and load lines of [`environment`], for tables that
/// describe their tools themselves.
pub fn machine(root: &Path, command: &str, load_before: &str) -> String {
    let commit = first_line("git", &["rev-parse", "--short", "HEAD"], root)
        .map(|c| {
            let dirty = first_line("git", &["status", "--porcelain"], root).is_some();
            if dirty {
                format!("{c} + uncommitted changes")
            } else {
                c
            }
        })
        .unwrap_or_else(|| "?".into());
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find_map(|l| l.strip_prefix("model name"))
                .map(|l| l.trim_start_matches([' ', '\t', ':']).to_string())
        })
        .unwrap_or_else(|| "?".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!(
        "Command: `{command}` (delmesh at {commit})\n\n\
         Machine: {cpu}, {cores} cores; load average (1/5/15 min) before: {load_before}, \
         after: {}\n",
        load_average(),
    )
}

/// The installed version of a Debian package, `?` when unknown.
pub fn package_version(pkg: &str, root: &Path) -> String {
    // FORMAT: dpkg-query prints the installed version, e.g. `5.5.1-2`.
    first_line("dpkg-query", &["-W", "-f", "${Version}\\n", pkg], root)
        .unwrap_or_else(|| "?".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_aligned() {
        let t = markdown_table(
            &["a", "long header"],
            &[vec!["wide cell".into(), "1".into()]],
        );
        assert_eq!(
            t,
            "| a         | long header |\n\
             |-----------|-------------|\n\
             | wide cell | 1           |\n"
        );
    }

    #[test]
    fn number_formats() {
        assert_eq!(secs(Some(1.23456)), "1.235");
        assert_eq!(secs(None), "-");
        assert_eq!(mb(Some(2048)), "2.0");
        assert_eq!(ratio(Some(1.0), Some(4.0)), "0.25");
        assert_eq!(ratio(Some(1.0), None), "-");
        assert_eq!(ratio(Some(1.0), Some(0.0)), "-");
    }
}
