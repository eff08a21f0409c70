//! End-to-end tests of the `delmesh` binary: run it as a user would and check its files, its
//! messages and its exit status.
//!
//! They live in this crate rather than in the workspace's top-level `tests/` because Cargo sets
//! `CARGO_BIN_EXE_delmesh` only for the tests of the package that owns the binary. The library
//! behind the commands is tested in depth in the top-level `tests/pipeline.rs`; here the
//! concern is the command line itself: arguments, the summary format (the `build time:` line is
//! parsed by `cargo xtask`), `error: ...` messages with exit status 1, and the demos, including
//! the paper's Table 1.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `delmesh args...` in `dir`.
fn delmesh(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_delmesh"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the delmesh binary runs")
}

fn stdout(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8(out.stderr.clone()).unwrap()
}

/// Asserts success and returns stderr (the summary).
fn ok(out: &Output) -> String {
    let err = stderr(out);
    assert!(
        out.status.success(),
        "status {:?}, stderr:\n{err}",
        out.status
    );
    err
}

/// Asserts exit status 1 with stderr ending in one `error: ...` line and returns that line.
fn fails(out: &Output) -> String {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(1), "stderr:\n{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.matches("error: ").count(), 1, "{err}");
    let last = err.lines().last().unwrap_or("");
    assert!(last.starts_with("error: "), "{err}");
    last.to_string()
}

/// A small deterministic point cloud in general position (a 2D or 3D lattice, jittered).
fn points(dim: usize, n: usize) -> Vec<Vec<f64>> {
    let mut state = 12345u64;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n).map(|_| (0..dim).map(|_| next()).collect()).collect()
}

fn write_node(dir: &Path, name: &str, dim: usize, pts: &[Vec<f64>], first: usize) -> PathBuf {
    let mut text = format!("{} {dim} 0 0\n", pts.len());
    for (i, p) in pts.iter().enumerate() {
        text.push_str(&(i + first).to_string());
        for x in p {
            text.push_str(&format!(" {x:?}"));
        }
        text.push('\n');
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The value of a `key: value` summary line.
fn field<'a>(summary: &'a str, key: &str) -> &'a str {
    summary
        .lines()
        .find_map(|l| l.strip_prefix(&format!("{key}: ")))
        .unwrap_or_else(|| panic!("no '{key}:' line in\n{summary}"))
}

/// The leading integer of a summary value (`"1990 triangles"` → 1990).
fn count(summary: &str, key: &str) -> usize {
    field(summary, key)
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

/// Checks the exact `build time: 0.123456 s` format.
fn check_build_time(summary: &str) {
    let value = field(summary, "build time");
    let secs = value.strip_suffix(" s").expect("build time ends in ' s'");
    let (whole, frac) = secs.split_once('.').expect("a decimal point");
    assert!(whole.chars().all(|c| c.is_ascii_digit()) && !whole.is_empty());
    assert_eq!(frac.len(), 6, "{value}");
    assert!(frac.chars().all(|c| c.is_ascii_digit()));
}

/// The data lines of a TetGen-style file as integers (for `.ele` / `.neigh`).
fn int_rows(path: &Path) -> Vec<Vec<i64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map(|l| l.split_whitespace().map(|t| t.parse().unwrap()).collect())
        .collect()
}

#[test]
fn help_lists_the_commands() {
    let dir = tempfile::tempdir().unwrap();
    let out = delmesh(dir.path(), &["--help"]);
    let text = stdout(&out);
    assert!(out.status.success());
    assert!(text.contains("delaunay") && text.contains("demo"), "{text}");
    let out = delmesh(dir.path(), &["delaunay", "--help"]);
    let text = stdout(&out);
    for opt in [
        "<INPUT>",
        "--output <OUT>",
        "--voronoi <CELLS.vtu>",
        "--quiet",
    ] {
        assert!(text.contains(opt), "{opt} missing in\n{text}");
    }
}

#[test]
fn delaunay_2d_to_vtu_prints_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    write_node(dir.path(), "pts.node", 2, &points(2, 300), 1);
    let out = delmesh(
        dir.path(),
        &[
            "delaunay",
            "pts.node",
            "-o",
            "mesh.vtu",
            "--voronoi",
            "cells.vtu",
        ],
    );
    let summary = ok(&out);
    assert_eq!(field(&summary, "input"), "pts.node");
    assert_eq!(field(&summary, "dimension"), "2");
    assert_eq!(count(&summary, "points read"), 300);
    assert_eq!(count(&summary, "duplicates merged"), 0);
    assert_eq!(count(&summary, "vertices"), 300);
    assert!(field(&summary, "cells").ends_with(" triangles"));
    assert!(field(&summary, "hull facets").ends_with(" edges"));
    let (cells, hull) = (count(&summary, "cells"), count(&summary, "hull facets"));
    assert_eq!(cells, 2 * 300 - hull - 2);
    check_build_time(&summary);
    assert!(summary.contains("wrote: mesh.vtu\n"), "{summary}");
    assert!(summary.contains("wrote: cells.vtu\n"), "{summary}");

    let xml = std::fs::read_to_string(dir.path().join("mesh.vtu")).unwrap();
    assert!(xml.contains("NumberOfPoints=\"300\""));
    assert!(xml.contains(&format!("NumberOfCells=\"{cells}\"")));
    let voronoi = std::fs::read_to_string(dir.path().join("cells.vtu")).unwrap();
    assert!(
        voronoi.contains("NumberOfCells=\"300\""),
        "one cell per point"
    );
}

#[test]
fn voronoi_regions_of_a_2d_lattice_share_their_corners() {
    // A 6 × 6 grid: each region is the unit square around its point (clipped to the box half
    // a spacing beyond the points), and neighbouring regions share their corners: the 7 × 7
    // lattice of square corners, not four copies of each.
    let dir = tempfile::tempdir().unwrap();
    let grid: Vec<Vec<f64>> = (0..36)
        .map(|k| vec![f64::from(k % 6), f64::from(k / 6)])
        .collect();
    write_node(dir.path(), "grid.node", 2, &grid, 1);
    ok(&delmesh(
        dir.path(),
        &["delaunay", "grid.node", "-o", "g.vtu", "--voronoi", "v.vtu"],
    ));
    let xml = std::fs::read_to_string(dir.path().join("v.vtu")).unwrap();
    assert!(xml.contains("NumberOfPoints=\"49\""), "{xml}");
    assert!(xml.contains("NumberOfCells=\"36\""), "{xml}");
}

#[test]
fn delaunay_2d_to_ele_numbers_from_the_input_first_index() {
    let dir = tempfile::tempdir().unwrap();
    write_node(dir.path(), "pts.node", 2, &points(2, 100), 1);
    let out = delmesh(dir.path(), &["delaunay", "pts.node", "-o", "out/mesh.ele"]);
    // The output folder does not exist: an error naming it, before any work is done.
    let msg = fails(&out);
    assert_eq!(
        msg,
        "error: out/mesh.ele: folder 'out' does not exist",
        "{}",
        stderr(&out)
    );
    assert_eq!(stderr(&out).lines().count(), 1);

    std::fs::create_dir(dir.path().join("out")).unwrap();
    let out = delmesh(dir.path(), &["delaunay", "pts.node", "-o", "out/mesh.ele"]);
    let summary = ok(&out);
    let cells = count(&summary, "cells");
    for f in ["out/mesh.node", "out/mesh.ele", "out/mesh.neigh"] {
        assert!(summary.contains(&format!("wrote: {f}\n")), "{summary}");
    }
    let node = int_rows_head(&dir.path().join("out/mesh.node"));
    assert_eq!(node, ("100 2 0 0".to_string(), "1".to_string()));
    let ele = int_rows(&dir.path().join("out/mesh.ele"));
    assert_eq!(ele[0], vec![cells as i64, 3, 0]);
    assert_eq!(ele.len(), cells + 1);
    assert_eq!(ele[1][0], 1);
    assert!(ele[1..]
        .iter()
        .all(|r| r[1..].iter().all(|&v| (1..=100).contains(&v))));
    let neigh = int_rows(&dir.path().join("out/mesh.neigh"));
    assert_eq!(neigh[0], vec![cells as i64, 3]);
    assert_eq!(neigh.len(), cells + 1);
    assert_eq!(neigh[1][0], 1);
    assert!(neigh[1..].iter().all(|r| r[1..]
        .iter()
        .all(|&n| n == -1 || (1..=cells as i64).contains(&n))));
}

#[test]
fn delaunay_carries_the_input_attributes_and_markers() {
    // Triangle's `.node` with two attributes and boundary markers: both outputs keep them.
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("5 2 2 1\n");
    for (i, (x, y)) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.4, 0.6)]
        .iter()
        .enumerate()
    {
        let marker = i32::from(i < 4) * (i as i32 + 1);
        text.push_str(&format!("{i} {x} {y} {} -{i}.5 {marker}\n", 10 * i));
    }
    std::fs::write(dir.path().join("pts.node"), text).unwrap();
    ok(&delmesh(
        dir.path(),
        &["delaunay", "pts.node", "-o", "m.ele"],
    ));
    let node = std::fs::read_to_string(dir.path().join("m.node")).unwrap();
    let rows: Vec<&str> = node.lines().collect();
    assert_eq!(rows[0], "5 2 2 1");
    assert_eq!(rows[3], "2 1 1 20 -2.5 3");
    assert_eq!(rows[5], "4 0.4 0.6 40 -4.5 0");
    ok(&delmesh(
        dir.path(),
        &["delaunay", "pts.node", "-o", "m.vtu"],
    ));
    let xml = std::fs::read_to_string(dir.path().join("m.vtu")).unwrap();
    for name in ["attribute_1", "attribute_2", "marker"] {
        assert!(xml.contains(&format!("Name=\"{name}\"")), "{name}: {xml}");
    }
}

#[cfg(target_os = "linux")]
#[test]
fn a_spacing_needing_more_memory_than_is_left_is_refused_at_once() {
    // A 2 × 1 rectangle and a background spacing of 1e-4 everywhere: about 4.6e8 triangles,
    // fewer than can be indexed (2^30) but far more than fit in the 2 GB address space the
    // run is given: refused before generation starts, not aborted when an allocation fails.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("domain.poly"),
        "4 2 0 0\n1 0 0\n2 2 0\n3 2 1\n4 0 1\n4 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n0\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("bg.node"),
        "4 2 1 0\n1 -1 -1 1e-4\n2 3 -1 1e-4\n3 3 2 1e-4\n4 -1 2 1e-4\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("bg.ele"), "2 3 0\n1 1 2 3\n2 1 3 4\n").unwrap();
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v 2000000 && exec '{}' mesh domain.poly -o m.vtu --background bg.ele",
            env!("CARGO_BIN_EXE_delmesh")
        ))
        .current_dir(dir.path())
        .output()
        .unwrap();
    let msg = fails(&out);
    assert!(
        msg.contains("asks for about 4.6e8 elements") && msg.contains("this process has left"),
        "{msg}"
    );
    assert!(!dir.path().join("m.vtu").exists());
}

#[test]
fn a_background_mesh_beside_the_domain_is_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("domain.poly"),
        "4 2 0 0\n1 0 0\n2 2 0\n3 2 1\n4 0 1\n4 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n0\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("bg.ele"), "2 3 0\n1 1 2 3\n2 1 3 4\n").unwrap();
    let warning = "warning: 4 input points lie outside the background mesh";
    // Over the domain (its corners on the background's edges): no warning.
    for (x0, x1, y0, y1, warned) in [(0, 2, 0, 1, false), (5, 6, 5, 6, true)] {
        std::fs::write(
            dir.path().join("bg.node"),
            format!(
                "4 2 1 0\n1 {x0} {y0} 0.2\n2 {x1} {y0} 0.2\n3 {x1} {y1} 0.2\n4 {x0} {y1} 0.2\n"
            ),
        )
        .unwrap();
        let out = delmesh(
            dir.path(),
            &[
                "mesh",
                "domain.poly",
                "-o",
                "m.vtu",
                "--background",
                "bg.ele",
            ],
        );
        let summary = ok(&out);
        assert_eq!(summary.contains(warning), warned, "{summary}");
    }
}

#[test]
fn an_empty_3d_voronoi_file_is_warned_about() {
    // An octahedron's six points are all on the hull: no bounded Voronoi region.
    let dir = tempfile::tempdir().unwrap();
    let octahedron: Vec<Vec<f64>> = (0..6)
        .map(|k| {
            let mut p = vec![0.0; 3];
            p[k % 3] = if k < 3 { 1.0 } else { -1.0 };
            p
        })
        .collect();
    write_node(dir.path(), "o.node", 3, &octahedron, 1);
    let out = delmesh(
        dir.path(),
        &["delaunay", "o.node", "-o", "o.vtu", "--voronoi", "v.vtu"],
    );
    ok(&out);
    assert!(
        stderr(&out).contains("warning: the Voronoi file holds no polygon"),
        "{}",
        stderr(&out)
    );
}

/// The header line and the first point's index of a `.node` file.
fn int_rows_head(path: &Path) -> (String, String) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    let first = lines
        .next()
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
        .to_string();
    (header, first)
}

#[test]
fn delaunay_3d_to_ele_and_vtu_with_voronoi() {
    let dir = tempfile::tempdir().unwrap();
    write_node(dir.path(), "cloud.node", 3, &points(3, 200), 0);
    let out = delmesh(
        dir.path(),
        &[
            "delaunay",
            "cloud.node",
            "-o",
            "tets.ele",
            "--voronoi",
            "faces.vtu",
        ],
    );
    let summary = ok(&out);
    assert_eq!(field(&summary, "dimension"), "3");
    assert!(field(&summary, "cells").ends_with(" tetrahedra"));
    assert!(field(&summary, "hull facets").ends_with(" triangles"));
    check_build_time(&summary);
    let cells = count(&summary, "cells");
    let (header, first) = int_rows_head(&dir.path().join("tets.node"));
    assert_eq!((header.as_str(), first.as_str()), ("200 3 0 0", "0"));
    let ele = int_rows(&dir.path().join("tets.ele"));
    assert_eq!(ele[0], vec![cells as i64, 4, 0]);
    assert_eq!(ele[1][0], 0);
    assert!(ele[1..]
        .iter()
        .all(|r| r.len() == 5 && r[1..].iter().all(|&v| (0..200).contains(&v))));
    let neigh = int_rows(&dir.path().join("tets.neigh"));
    assert_eq!(neigh.len(), cells + 1);
    let faces = std::fs::metadata(dir.path().join("faces.vtu")).unwrap();
    assert!(faces.len() > 1000, "Voronoi file of {} bytes", faces.len());

    let out = delmesh(
        dir.path(),
        &["delaunay", "cloud.node", "-o", "tets.vtu", "-q"],
    );
    let quiet = ok(&out);
    assert_eq!(quiet.lines().count(), 1, "{quiet}");
    check_build_time(&quiet);
    let xml = std::fs::read_to_string(dir.path().join("tets.vtu")).unwrap();
    assert!(xml.contains(&format!("NumberOfCells=\"{cells}\"")));
}

#[test]
fn plain_text_input() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("pts.txt"), "0 0\n1 0\n0 1\n1 1.5\n").unwrap();
    let out = delmesh(dir.path(), &["delaunay", "pts.txt", "-o", "m.ele"]);
    let summary = ok(&out);
    assert_eq!(count(&summary, "cells"), 2);
    assert_eq!(int_rows(&dir.path().join("m.ele"))[1][0], 0);
}

#[test]
fn nan_input_names_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.node"),
        "# points\n4 2 0 0\n1 0 0\n2 1 0\n3 nan 1\n4 0 1\n",
    )
    .unwrap();
    let out = delmesh(dir.path(), &["delaunay", "bad.node", "-o", "m.vtu"]);
    let msg = fails(&out);
    assert!(msg.starts_with("error: bad.node:5: "), "{msg}");
    assert!(msg.contains("not finite"), "{msg}");
    assert!(!dir.path().join("m.vtu").exists());
}

#[test]
fn missing_input_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = delmesh(dir.path(), &["delaunay", "nope.node", "-o", "m.vtu"]);
    let msg = fails(&out);
    assert!(msg.starts_with("error: nope.node: "), "{msg}");
}

#[test]
fn unknown_mesh_input_format_is_named() {
    // A STEP file (or any extension `mesh` does not read) was parsed as a Triangle .poly and
    // failed on some line of it.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("part.step"), "ISO-10303-21;\nHEADER;\n").unwrap();
    let msg = fails(&delmesh(dir.path(), &["mesh", "part.step", "-o", "m.vtu"]));
    assert_eq!(
        msg,
        "error: part.step: unknown input format ('.step'): `delmesh mesh` reads a Triangle .poly \
         (2D) or a surface (.smesh, .poly (3D), .off, .stl, .obj, .ply, .mesh, .msh)"
    );
    std::fs::write(dir.path().join("domain"), "3 2 0 0\n").unwrap();
    let msg = fails(&delmesh(dir.path(), &["mesh", "domain", "-o", "m.vtu"]));
    assert!(
        msg.contains("domain: unknown input format (no extension)"),
        "{msg}"
    );
    assert!(!dir.path().join("m.vtu").exists());
}

#[test]
fn unknown_output_extension_is_an_error_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    write_node(dir.path(), "pts.node", 2, &points(2, 10), 0);
    let out = delmesh(dir.path(), &["delaunay", "pts.node", "-o", "mesh.stl"]);
    let msg = fails(&out);
    assert_eq!(
        msg,
        "error: mesh.stl: unsupported output format '.stl' (supported: .vtu, .ele)"
    );
    let out = delmesh(
        dir.path(),
        &["delaunay", "pts.node", "-o", "m.vtu", "--voronoi", "v.ele"],
    );
    let msg = fails(&out);
    assert!(
        msg.contains("v.ele: unsupported output format '.ele' (supported: .vtu)"),
        "{msg}"
    );
    assert!(!dir.path().join("m.vtu").exists());
}

#[test]
fn duplicates_are_reported() {
    let dir = tempfile::tempdir().unwrap();
    let mut pts = points(2, 10);
    pts.push(pts[2].clone());
    pts.push(pts[7].clone());
    write_node(dir.path(), "dups.node", 2, &pts, 1);
    let out = delmesh(dir.path(), &["delaunay", "dups.node", "-o", "m.vtu"]);
    let summary = ok(&out);
    assert_eq!(count(&summary, "points read"), 12);
    assert_eq!(count(&summary, "duplicates merged"), 2);
    assert_eq!(count(&summary, "vertices"), 10);
    assert!(
        summary.contains("  input 11 repeats input 3\n"),
        "{summary}"
    );
    assert!(
        summary.contains("  input 12 repeats input 8\n"),
        "{summary}"
    );
}

#[test]
fn collinear_input_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("line.xyz"), "0 0\n1 1\n2 2\n3 3\n").unwrap();
    let out = delmesh(dir.path(), &["delaunay", "line.xyz", "-o", "m.vtu"]);
    let msg = fails(&out);
    assert_eq!(
        msg,
        "error: line.xyz: all 4 distinct points are collinear: no 2D triangulation exists"
    );
}

#[test]
fn demo_without_name_lists_the_demos() {
    let dir = tempfile::tempdir().unwrap();
    let out = delmesh(dir.path(), &["demo"]);
    ok(&out);
    let text = stdout(&out);
    for demo in delmesh::demos::DEMOS {
        assert!(text.contains(demo.name), "{text}");
    }
    let out = delmesh(dir.path(), &["demo", "figure99"]);
    let msg = fails(&out);
    assert!(
        msg.contains("unknown demo 'figure99'") && msg.contains("figure1"),
        "{msg}"
    );
}

#[test]
fn demo_random2d_writes_its_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = delmesh(dir.path(), &["demo", "random2d"]);
    ok(&out);
    for f in ["random2d.vtu", "random2d-voronoi.vtu"] {
        let path = dir.path().join("delmesh-demo-out").join(f);
        assert!(std::fs::metadata(&path).unwrap().len() > 1000, "{f}");
    }
}

/// One row of Table 1: the forming points of a Voronoi vertex and the forming points of each
/// neighbouring Voronoi vertex (`None` for `*`).
type Row = (Vec<u32>, Vec<Option<Vec<u32>>>);

/// Parses a Table 1 text (ours or the paper's) into rows keyed by forming points, so that two
/// tables numbering their Voronoi vertices differently compare equal. Lines that do not start
/// with a number (headers, rules) are skipped; fields may be separated by spaces, tabs, commas
/// or `|`.
fn table_rows(text: &str) -> BTreeSet<Row> {
    let mut forming_of: BTreeMap<String, Vec<u32>> = BTreeMap::new();
    let mut raw: Vec<(Vec<u32>, Vec<String>)> = Vec::new();
    for line in text.lines() {
        let toks: Vec<&str> = line
            .split(|c: char| c.is_whitespace() || c == ',' || c == '|')
            .filter(|t| !t.is_empty())
            .collect();
        if toks.is_empty() || toks[0].parse::<u32>().is_err() {
            continue;
        }
        assert_eq!(toks.len(), 7, "a 2D Table 1 row has 7 fields: {line:?}");
        let mut forming: Vec<u32> = toks[1..4].iter().map(|t| t.parse().unwrap()).collect();
        forming.sort_unstable();
        forming_of.insert(toks[0].to_string(), forming.clone());
        raw.push((forming, toks[4..].iter().map(|t| t.to_string()).collect()));
    }
    raw.into_iter()
        .map(|(forming, ns)| {
            let mut ns: Vec<Option<Vec<u32>>> = ns
                .iter()
                .map(|n| (n != "*").then(|| forming_of[n].clone()))
                .collect();
            ns.sort();
            (forming, ns)
        })
        .collect()
}

fn workspace_file(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

#[test]
fn demo_figure1_prints_the_papers_table_1() {
    let dir = tempfile::tempdir().unwrap();
    let out = delmesh(dir.path(), &["demo", "figure1", "-o", "tmp"]);
    ok(&out);
    let ours = stdout(&out);
    for f in ["figure1.vtu", "figure1-voronoi.vtu"] {
        assert!(dir.path().join("tmp").join(f).exists(), "{f}");
    }
    let paper = std::fs::read_to_string(workspace_file("data/figure1-table1.txt")).unwrap();
    let (ours_rows, paper_rows) = (table_rows(&ours), table_rows(&paper));
    assert!(!paper_rows.is_empty());
    assert_eq!(ours_rows, paper_rows, "ours:\n{ours}\npaper:\n{paper}");
    insta::assert_snapshot!("figure1_table", ours);
}

#[test]
fn outputs_never_overwrite_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_node(dir.path(), "pts.node", 2, &points(2, 10), 1);
    let before = std::fs::read(&input).unwrap();
    // `-o pts.ele` would write pts.node, the input itself.
    let out = delmesh(dir.path(), &["delaunay", "pts.node", "-o", "pts.ele"]);
    let msg = fails(&out);
    assert!(
        msg.starts_with("error: pts.node: writing this file would overwrite the input"),
        "{msg}"
    );
    assert_eq!(stderr(&out).lines().count(), 1);
    assert_eq!(std::fs::read(&input).unwrap(), before);
    assert!(!dir.path().join("pts.ele").exists());

    let out = delmesh(
        dir.path(),
        &["delaunay", "pts.node", "-o", "m.vtu", "--voronoi", "m.vtu"],
    );
    let msg = fails(&out);
    assert!(
        msg.contains("m.vtu: given both as the mesh output and as the --voronoi output"),
        "{msg}"
    );
}

#[test]
fn mesh_outputs_never_overwrite_what_the_run_reads() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A .poly whose points are in the .node beside it, extra points, and a report.
    std::fs::write(d.join("sq.node"), "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n").unwrap();
    std::fs::write(
        d.join("sq.poly"),
        "0 2 0 0\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n",
    )
    .unwrap();
    std::fs::write(d.join("p.node"), "1 2 0 0\n1 0.5 0.5\n").unwrap();
    let read = |f: &str| std::fs::read(d.join(f)).unwrap();
    let before: Vec<Vec<u8>> = ["sq.node", "sq.poly", "p.node"].map(read).to_vec();
    for (args, culprit) in [
        (
            &["-o", "sq.ele"][..],
            "sq.node: writing this file would overwrite the input",
        ),
        (
            &["--points", "p.node", "-o", "p.ele"][..],
            "p.node: writing",
        ),
        (
            &["-o", "m.vtu", "--report", "sq.poly"][..],
            "sq.poly: writing",
        ),
        (
            &["-o", "m.ele", "--report", "m.node"][..],
            "m.node: written by both m.ele and m.node",
        ),
        (
            &["-o", "m.vtu", "-o", "./m.vtu"][..],
            "written by both m.vtu and ./m.vtu",
        ),
    ] {
        let mut all = vec!["mesh", "sq.poly"];
        all.extend_from_slice(args);
        let msg = fails(&delmesh(d, &all));
        assert!(msg.contains(culprit), "{args:?}: {msg}");
        assert!(!d.join("m.vtu").exists() && !d.join("m.ele").exists());
    }
    assert_eq!(["sq.node", "sq.poly", "p.node"].map(read).to_vec(), before);
    // Running again over its own outputs is fine.
    for _ in 0..2 {
        ok(&delmesh(
            d,
            &["mesh", "sq.poly", "-o", "out.ele", "--report", "r.json"],
        ));
    }
}

#[test]
fn validate_flag_checks_the_result() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("grid.node");
    let mut text = String::from("64 3 0 0\n");
    for i in 0..64 {
        text.push_str(&format!("{i} {} {} {}\n", i % 4, i / 4 % 4, i / 16));
    }
    std::fs::write(&input, text).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_delmesh"))
        .args(["delaunay", input.to_str().unwrap(), "-o"])
        .arg(dir.path().join("grid-out.ele"))
        .args(["--quiet", "--validate"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(stderr.contains("validation: ok"), "{stderr}");
    assert!(stderr.contains("build time: "), "{stderr}");
}

/// A 4 × 4 square with a 2 × 2 square hole (by nesting), numbered from 1, with markers.
const SQUARE_POLY: &str = "# square with a hole\n\
    8 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n5 1 1\n6 1 3\n7 3 3\n8 3 1\n\
    8 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n5 5 6 2\n6 6 7 2\n7 7 8 2\n8 8 5 2\n0\n";

#[test]
fn mesh_a_poly_file_to_every_format() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("sq.poly"), SQUARE_POLY).unwrap();
    std::fs::create_dir(dir.path().join("foam")).unwrap();
    let out = delmesh(
        dir.path(),
        &[
            "mesh",
            "sq.poly",
            "-o",
            "m.vtu",
            "-o",
            "m.ele",
            "-o",
            "m.svg",
            "-o",
            "m.su2",
            "-o",
            "m.msh",
            "-o",
            "foam/polyMesh",
            "--report",
            "r.json",
            "--validate",
            "--alpha",
            "0.5",
        ],
    );
    let err = ok(&out);
    for key in [
        "boundary recovery",
        "point generation",
        "smoothing",
        "validation: ok",
        "time per stage",
    ] {
        assert!(err.contains(key), "{key}: {err}");
    }
    for f in ["m.vtu", "m.node", "m.ele", "m.edge", "m.svg", "r.json"] {
        assert!(dir.path().join(f).is_file(), "{f}");
    }
    let edge = std::fs::read_to_string(dir.path().join("m.edge")).unwrap();
    assert!(
        edge.lines()
            .skip(1)
            .all(|l| l.ends_with(" 1") || l.ends_with(" 2")),
        "{edge}"
    );
    let report = std::fs::read_to_string(dir.path().join("r.json")).unwrap();
    assert!(
        report.contains("\"quality\"") && report.contains("\"generation\""),
        "{report}"
    );
    let ele = int_rows(&dir.path().join("m.ele"));
    assert!(ele.len() > 8, "{ele:?}");
    // SU2: the same triangles and points (0-based), the boundary edges of .edge under one
    // marker tag per marker.
    let su2 = std::fs::read_to_string(dir.path().join("m.su2")).unwrap();
    let node = std::fs::read_to_string(dir.path().join("m.node")).unwrap();
    let edges = int_rows(&dir.path().join("m.edge"));
    let count = |key: &str| -> usize {
        let line = su2.lines().find(|l| l.starts_with(key)).expect(key);
        line[key.len()..].trim().parse().unwrap()
    };
    assert!(su2.starts_with("NDIME= 2\n"), "{su2}");
    assert_eq!(count("NELEM="), ele[0][0] as usize);
    let points: usize = node.split_whitespace().next().unwrap().parse().unwrap();
    assert_eq!(count("NPOIN="), points);
    assert_eq!(count("NMARK="), 2);
    let first_triangle = &ele[1];
    let su2_first: Vec<i64> = su2
        .lines()
        .nth(2)
        .unwrap()
        .split(' ')
        .map(|t| t.parse().unwrap())
        .collect();
    assert_eq!(su2_first[0], 5);
    assert_eq!(
        su2_first[1..4],
        first_triangle[1..4]
            .iter()
            .map(|v| v - 1)
            .collect::<Vec<_>>()[..]
    );
    for marker in [1, 2] {
        let tag = su2.find(&format!("MARKER_TAG= marker_{marker}\n")).unwrap();
        let n: usize = su2[tag..].lines().nth(1).unwrap()["MARKER_ELEMS=".len()..]
            .trim()
            .parse()
            .unwrap();
        let mut from_su2: Vec<(i64, i64)> = su2[tag..]
            .lines()
            .skip(2)
            .take(n)
            .map(|l| {
                let t: Vec<i64> = l.split(' ').map(|t| t.parse().unwrap()).collect();
                assert_eq!(t[0], 3, "{l}");
                (t[1].min(t[2]), t[1].max(t[2]))
            })
            .collect();
        let mut from_edge: Vec<(i64, i64)> = edges[1..]
            .iter()
            .filter(|e| e[3] == marker)
            .map(|e| ((e[1] - 1).min(e[2] - 1), (e[1] - 1).max(e[2] - 1)))
            .collect();
        from_su2.sort_unstable();
        from_edge.sort_unstable();
        assert_eq!(from_su2, from_edge, "marker {marker}");
    }
    // gmsh: the same triangles (read back as facets), both markers' groups.
    let msh = delmesh::io::read_msh(&dir.path().join("m.msh")).unwrap();
    assert_eq!(msh.facets.len(), ele[0][0] as usize);
    assert_eq!(msh.points.len(), points);
    let text = std::fs::read_to_string(dir.path().join("m.msh")).unwrap();
    assert!(
        text.contains("1 1 \"marker_1\"\n1 2 \"marker_2\"\n"),
        "{text}"
    );
    // OpenFOAM: a prism per triangle; the boundary edges of each marker as faces of its patch,
    // the two planes as the empty patch.
    let foam = std::fs::read_to_string(dir.path().join("foam/polyMesh/boundary")).unwrap();
    for marker in [1, 2] {
        let n = edges[1..].iter().filter(|e| e[3] == marker).count();
        let at = foam.find(&format!("marker_{marker}\n")).expect("the patch");
        assert!(
            foam[at..].contains(&format!("nFaces          {n};")),
            "{foam}"
        );
    }
    let planes = format!(
        "frontAndBack\n    {{\n        type            empty;\n        nFaces          {};",
        2 * ele[0][0]
    );
    assert!(foam.contains(&planes), "{foam}");

    // The mesh's own spacing field drives a second run (a background mesh), and a previous
    // solution field drives adaptation.
    let out = delmesh(
        dir.path(),
        &["mesh", "sq.poly", "-o", "b.vtu", "--background", "m.vtu"],
    );
    ok(&out);
    let out = delmesh(
        dir.path(),
        &[
            "mesh",
            "sq.poly",
            "-o",
            "a.vtu",
            "--adapt",
            "m.vtu",
            "--field",
            "spacing",
            "--min-spacing",
            "0.05",
            "--max-spacing",
            "0.5",
        ],
    );
    ok(&out);
    // The paper's points from component meshes, without automatic points: those points have
    // a spacing in the .vtu too (it was NaN there, and the file was refused as a background).
    std::fs::write(
        dir.path().join("pts.txt"),
        "0.5 0.5\n3.5 0.5\n3.5 3.5\n0.5 2\n2 3.5\n",
    )
    .unwrap();
    let out = delmesh(
        dir.path(),
        &[
            "mesh",
            "sq.poly",
            "--no-points",
            "--points",
            "pts.txt",
            "-o",
            "pn.vtu",
        ],
    );
    ok(&out);
    let spacing = delmesh_io::read_vtu(&dir.path().join("pn.vtu")).unwrap();
    let (_, values) = spacing
        .point_fields
        .iter()
        .find(|(name, _)| name == "spacing")
        .expect("a spacing field");
    assert_eq!(values.len(), 13);
    assert!(
        values.iter().all(|h| *h > 0.0 && h.is_finite()),
        "{values:?}"
    );
    let out = delmesh(
        dir.path(),
        &["mesh", "sq.poly", "-o", "pb.vtu", "--background", "pn.vtu"],
    );
    ok(&out);
    // A field, or adaptation's bounds, without the mesh they belong to is refused (--field
    // alone was ignored: the boundary's spacing was used without a word).
    for extra in [
        &["--field", "spacing"][..],
        &["--min-spacing", "0.05", "--max-spacing", "0.5"],
        &["--background", "m.vtu", "--min-spacing", "0.05"],
    ] {
        let mut args = vec!["mesh", "sq.poly", "-o", "f.vtu"];
        args.extend_from_slice(extra);
        // (A usage error: clap's exit status 2 and its usage text.)
        let out = delmesh(dir.path(), &args);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {err}");
        assert!(
            err.contains("required arguments were not provided"),
            "{err}"
        );
        assert!(err.contains("--adapt <MESH>"), "{extra:?}: {err}");
        assert!(!dir.path().join("f.vtu").exists());
    }
}

#[test]
fn mesh_recovery_methods_and_options() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("sq.poly"), SQUARE_POLY).unwrap();
    for method in ["stitch", "a-priori", "constrained"] {
        let out = delmesh(
            dir.path(),
            &[
                "mesh",
                "sq.poly",
                "-o",
                "c.vtu",
                "--recovery",
                method,
                "--validate",
                "--no-smoothing",
            ],
        );
        assert!(ok(&out).contains("validation: ok"));
    }
    // The smoothed connectivity kept (--no-flips) need not be Delaunay: validation checks the
    // rest (it failed on the empty-circle test, and nothing was written).
    let out = delmesh(
        dir.path(),
        &[
            "mesh",
            "sq.poly",
            "-o",
            "k.ele",
            "--alpha",
            "0.1",
            "--no-flips",
            "--validate",
        ],
    );
    assert!(ok(&out).contains("validation: ok"));
    assert!(dir.path().join("k.ele").exists());
    let out = delmesh(
        dir.path(),
        &["mesh", "sq.poly", "-o", "n.ele", "--no-points", "-q"],
    );
    let err = ok(&out);
    assert!(err.starts_with("mesh time: "), "{err}");
    // No automatic points: only the 8 input points.
    let node = std::fs::read_to_string(dir.path().join("n.node")).unwrap();
    assert!(node.starts_with("8 2 0 1\n"), "{node}");
}

#[test]
fn mesh_errors_name_the_file() {
    let dir = tempfile::tempdir().unwrap();
    // Two crossing diagonals inside the square.
    let crossing = SQUARE_POLY
        .replace("8 1\n1 1 2 1", "10 1\n1 1 2 1")
        .replace("8 8 5 2\n0\n", "8 8 5 2\n9 5 7 3\n10 6 8 3\n0\n");
    std::fs::write(dir.path().join("x.poly"), crossing).unwrap();
    let msg = fails(&delmesh(dir.path(), &["mesh", "x.poly", "-o", "x.vtu"]));
    assert!(
        msg.contains("x.poly") && msg.contains("segments 9 and 10 intersect"),
        "{msg}"
    );
    std::fs::write(
        dir.path().join("bad.poly"),
        SQUARE_POLY.replace("5 5 6 2", "5 5 60 2"),
    )
    .unwrap();
    let msg = fails(&delmesh(dir.path(), &["mesh", "bad.poly", "-o", "x.vtu"]));
    assert!(
        msg.contains("bad.poly:16: segment end point 60 does not exist"),
        "{msg}"
    );
    std::fs::write(dir.path().join("sq.poly"), SQUARE_POLY).unwrap();
    let msg = fails(&delmesh(dir.path(), &["mesh", "sq.poly", "-o", "x.stl"]));
    assert!(msg.contains("x.stl"), "{msg}");
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "sq.poly", "-o", "x.vtu", "--omega", "2"],
    ));
    assert!(msg.contains("omega"), "{msg}");
    // A value is echoed as short as it was given (Display wrote 1e300 in 301 digits).
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "sq.poly", "-o", "x.vtu", "--omega", "1e300"],
    ));
    assert!(msg.contains("(got 1e300)"), "{msg}");
    // A bad point of --points is named in that file (it was blamed on the domain's file, as
    // a point 10 it does not have).
    std::fs::write(dir.path().join("p.txt"), "2 2\n1.5 1e-300\n").unwrap();
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "sq.poly", "-o", "x.vtu", "--points", "p.txt"],
    ));
    assert!(msg.contains("p.txt: point 1: coordinate 1e-300"), "{msg}");
    // An output that cannot be written is refused before anything is: a folder where a file
    // goes, a report into a missing folder (the outputs before it were replaced, then the
    // run failed).
    std::fs::create_dir(dir.path().join("f.su2")).unwrap();
    std::fs::write(dir.path().join("keep.vtu"), "old").unwrap();
    for extra in [["-o", "f.su2"], ["--report", "none/r.json"]] {
        let mut args = vec!["mesh", "sq.poly", "-o", "keep.vtu"];
        args.extend(extra);
        let msg = fails(&delmesh(dir.path(), &args));
        assert!(msg.contains(extra[1]), "{msg}");
        assert_eq!(
            std::fs::read_to_string(dir.path().join("keep.vtu")).unwrap(),
            "old"
        );
    }
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "sq.poly", "-o", "x.vtu", "--alpha=-1"],
    ));
    assert!(msg.contains("alpha"), "{msg}");
    // A tiny α asks for as many elements as a tiny spacing: refused at once (it ran out of
    // memory).
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "sq.poly", "-o", "x.vtu", "--alpha", "1e-9"],
    ));
    assert!(msg.contains("alpha") && msg.contains("2^30"), "{msg}");
    // A background mesh in a format read only as a domain.
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "sq.poly", "-o", "x.vtu", "--background", "sq.poly"],
    ));
    assert!(
        msg.contains("sq.poly: cannot read a background or solution mesh from a '.poly' file"),
        "{msg}"
    );
}

#[test]
fn demo_figure8_writes_the_mesh_before_and_after_recovery() {
    let dir = tempfile::tempdir().unwrap();
    let out = delmesh(dir.path(), &["demo", "figure8", "-o", "d"]);
    let err = ok(&out);
    assert!(stdout(&out).contains("missing"), "{}", stdout(&out));
    for f in ["figure8-delaunay.svg", "figure8.svg", "figure8.vtu"] {
        assert!(dir.path().join("d").join(f).is_file(), "{f}: {err}");
    }
}

#[test]
fn a_mesh_demo_writes_its_domain_and_the_command_that_meshes_it_the_same() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "figure7",
        "figure8",
        "figure10a",
        "figure10b",
        "table2",
        "cubic-hole",
        "blocks",
    ] {
        let out = delmesh(dir.path(), &["demo", name, "-o", "d"]);
        let err = ok(&out);
        let line = err
            .lines()
            .find_map(|l| l.strip_prefix("the same mesh from the command line: delmesh "))
            .unwrap_or_else(|| panic!("{name}: {err}"));
        let mut args: Vec<&str> = line.split_whitespace().collect();
        let o = args.iter().position(|&a| a == "-o").unwrap();
        args[o + 1] = "again.vtu";
        ok(&delmesh(dir.path(), &args));
        let demo = std::fs::read(dir.path().join("d").join(format!("{name}.vtu"))).unwrap();
        let again = std::fs::read(dir.path().join("again.vtu")).unwrap();
        assert!(demo == again, "{name}: {line}");
    }
}

/// The surface of the unit cube, 2 triangles per side, counter-clockwise seen from outside, as
/// OFF text.
fn cube_off(scale: f64) -> String {
    let mut s = String::from("OFF\n8 12 0\n");
    for i in 0..8 {
        let c = [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64];
        s.push_str(&format!(
            "{} {} {}\n",
            c[0] * scale,
            c[1] * scale,
            c[2] * scale
        ));
    }
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    for q in quads {
        s.push_str(&format!(
            "3 {} {} {}\n3 {} {} {}\n",
            q[0], q[1], q[2], q[0], q[2], q[3]
        ));
    }
    s
}

#[test]
fn mesh_a_surface_to_every_3d_format() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cube.off"), cube_off(1.0)).unwrap();
    std::fs::create_dir_all(dir.path().join("case/constant")).unwrap();
    let summary = ok(&delmesh(
        dir.path(),
        &[
            "mesh",
            "cube.off",
            "-o",
            "m.vtu",
            "-o",
            "m.ele",
            "-o",
            "m.msh",
            "-o",
            "m.mesh",
            "-o",
            "m.su2",
            "-o",
            "case/constant/polyMesh",
            "--alpha",
            "0.4",
            "--report",
            "r.json",
            "--validate",
        ],
    ));
    assert!(summary.contains("Edge recovery history"), "{summary}");
    assert!(summary.contains("validation: ok"), "{summary}");
    for f in [
        "m.vtu",
        "m.boundary.vtu",
        "m.node",
        "m.ele",
        "m.face",
        "m.msh",
        "m.mesh",
        "m.su2",
        "r.json",
    ] {
        assert!(dir.path().join(f).exists(), "{f} missing; {summary}");
    }
    // The .ele header names the tetrahedra; the .face file the 12 input triangles' pieces.
    let ele = std::fs::read_to_string(dir.path().join("m.ele")).unwrap();
    let n_tets: usize = ele.split_whitespace().next().unwrap().parse().unwrap();
    assert!(n_tets > 12, "{ele}");
    let report = std::fs::read_to_string(dir.path().join("r.json")).unwrap();
    assert!(report.contains("\"tetrahedra\": "), "{report}");
    assert!(report.contains("\"slivers\""), "{report}");
    // OpenFOAM: a cell per tetrahedron, the faces of the 12 input triangles' pieces in one
    // patch (the cube has one marker), four faces per cell counted once or twice.
    let foam = dir.path().join("case/constant/polyMesh");
    let owner = std::fs::read_to_string(foam.join("owner")).unwrap();
    let note = format!("nCells:{n_tets} ");
    assert!(owner.contains(&note), "{owner}");
    let face = std::fs::read_to_string(dir.path().join("m.face")).unwrap();
    let n_faces: usize = face.split_whitespace().next().unwrap().parse().unwrap();
    let boundary = std::fs::read_to_string(foam.join("boundary")).unwrap();
    assert!(
        boundary.contains(&format!("nFaces          {n_faces};")),
        "{boundary}"
    );
    assert!(
        owner.contains(&format!("nInternalFaces:{}\"", (4 * n_tets - n_faces) / 2)),
        "{owner}"
    );
}

/// The unit cube as an ASCII STL of three solids: `inlet` (x = 0), `outlet` (x = 1), `walls`.
fn cube_stl_solids() -> String {
    let corner = |i: usize| [i & 1, (i >> 1) & 1, (i >> 2) & 1];
    let faces: [([usize; 3], &str); 12] = [
        ([0, 4, 6], "inlet"),
        ([0, 6, 2], "inlet"),
        ([1, 7, 5], "outlet"),
        ([1, 3, 7], "outlet"),
        ([0, 5, 4], "walls"),
        ([0, 1, 5], "walls"),
        ([2, 6, 7], "walls"),
        ([2, 7, 3], "walls"),
        ([0, 2, 3], "walls"),
        ([0, 3, 1], "walls"),
        ([4, 7, 6], "walls"),
        ([4, 5, 7], "walls"),
    ];
    let mut s = String::new();
    for solid in ["inlet", "outlet", "walls"] {
        s.push_str(&format!("solid {solid}\n"));
        for (f, _) in faces.iter().filter(|(_, n)| *n == solid) {
            s.push_str(" facet normal 0 0 0\n  outer loop\n");
            for &v in f {
                let [x, y, z] = corner(v);
                s.push_str(&format!("   vertex {x} {y} {z}\n"));
            }
            s.push_str("  endloop\n endfacet\n");
        }
        s.push_str(&format!("endsolid {solid}\n"));
    }
    s
}

#[test]
fn an_stl_of_named_solids_gives_openfoam_patches_of_those_names() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("duct.stl"), cube_stl_solids()).unwrap();
    std::fs::create_dir_all(dir.path().join("case/constant")).unwrap();
    ok(&delmesh(
        dir.path(),
        &[
            "mesh",
            "duct.stl",
            "-o",
            "case/constant/polyMesh",
            "--alpha",
            "0.3",
        ],
    ));
    let boundary =
        std::fs::read_to_string(dir.path().join("case/constant/polyMesh/boundary")).unwrap();
    let names: Vec<&str> = boundary
        .lines()
        .filter(|l| l.starts_with("    ") && !l.starts_with("     ") && !l.contains(';'))
        .map(str::trim)
        .filter(|l| !l.is_empty() && *l != "{" && *l != "}")
        .collect();
    assert_eq!(names, ["inlet", "outlet", "walls"], "{boundary}");
    // No polyMesh folder in a folder that does not exist: refused before meshing.
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "duct.stl", "-o", "nocase/constant/polyMesh"],
    ));
    assert!(msg.contains("nocase/constant"), "{msg}");
    // Nor over a file named polyMesh, which is kept.
    std::fs::write(dir.path().join("polyMesh"), "the user's").unwrap();
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "duct.stl", "-o", "polyMesh"],
    ));
    assert!(
        msg.contains("polyMesh") && msg.contains("is a file"),
        "{msg}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("polyMesh")).unwrap(),
        "the user's"
    );
}

#[test]
fn mesh_3d_input_errors_name_the_file_and_facets() {
    let dir = tempfile::tempdir().unwrap();
    // An open surface: the cube without its last triangle.
    let text = cube_off(1.0);
    let open: String = text.replace("8 12 0", "8 11 0");
    let open = open.lines().take(2 + 8 + 11).collect::<Vec<_>>().join("\n");
    std::fs::write(dir.path().join("open.off"), open).unwrap();
    let msg = fails(&delmesh(dir.path(), &["mesh", "open.off", "-o", "m.vtu"]));
    assert!(
        msg.contains("open.off") && msg.contains("not closed"),
        "{msg}"
    );
    // A malformed file names its line.
    std::fs::write(
        dir.path().join("bad.off"),
        "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    let msg = fails(&delmesh(dir.path(), &["mesh", "bad.off", "-o", "m.vtu"]));
    assert!(msg.contains("bad.off:4"), "{msg}");
    // A 2D-only output format for a 3D input is refused before any work.
    std::fs::write(dir.path().join("cube.off"), cube_off(1.0)).unwrap();
    let msg = fails(&delmesh(dir.path(), &["mesh", "cube.off", "-o", "m.svg"]));
    assert!(msg.contains("m.svg"), "{msg}");
}

#[test]
fn demo_table2_prints_the_papers_table_beside_delmeshs() {
    let dir = tempfile::tempdir().unwrap();
    let out = delmesh(dir.path(), &["demo", "table2", "-o", "."]);
    ok(&out);
    let text = stdout(&out);
    assert!(text.contains("Edge recovery history"), "{text}");
    assert!(text.contains("surface points added"), "{text}");
    assert!(text.contains("205"), "{text}");
    assert!(dir.path().join("table2.vtu").exists());
}

#[test]
fn a_region_medit_cannot_number_is_refused_before_meshing() {
    let dir = tempfile::tempdir().unwrap();
    let mut poly = String::from("8 3 0 0\n");
    for (i, p) in [
        "0 0 0", "1 0 0", "1 1 0", "0 1 0", "0 0 1", "1 0 1", "1 1 1", "0 1 1",
    ]
    .iter()
    .enumerate()
    {
        poly.push_str(&format!("{} {p}\n", i + 1));
    }
    poly.push_str("6 1\n");
    for f in [
        "1 2 3 4", "5 6 7 8", "1 2 6 5", "2 3 7 6", "3 4 8 7", "4 1 5 8",
    ] {
        poly.push_str(&format!("1 0 1\n4 {f}\n"));
    }
    poly.push_str("0\n1\n1 0.5 0.5 0.5 1.5\n");
    std::fs::write(dir.path().join("cube.poly"), poly).unwrap();
    // (The .mesh writer refused it, after the meshing and the .vtu.)
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "cube.poly", "-o", "c.vtu", "-o", "c.mesh"],
    ));
    assert!(msg.contains("region 0 has attribute 1.5"), "{msg}");
    assert!(!dir.path().join("c.vtu").exists());
    ok(&delmesh(dir.path(), &["mesh", "cube.poly", "-o", "c.vtu"]));
}

#[test]
fn mesh_3d_with_a_background_mesh_and_adaptation() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cube.off"), cube_off(1.0)).unwrap();
    // A coarse background of the cube: 6 tetrahedra around the diagonal 0-7, spacing fine at
    // x = 0 and coarse at x = 1; the same values as a "mach" field for adaptation.
    let corners: Vec<f64> = (0..8)
        .flat_map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
        .collect();
    let tets: Vec<u32> = vec![
        0, 1, 3, 7, 0, 3, 2, 7, 0, 2, 6, 7, 0, 6, 4, 7, 0, 4, 5, 7, 0, 5, 1, 7,
    ];
    let spacing: Vec<f64> = (0..8)
        .map(|i| if i & 1 == 0 { 0.12 } else { 0.6 })
        .collect();
    let mach: Vec<f64> = (0..8).map(|i| if i & 1 == 0 { 0.5 } else { 3.0 }).collect();
    let mesh = delmesh::io::SimplexMesh {
        dim: 3,
        coords: &corners,
        cells: &tets,
        neighbors: None,
    };
    delmesh::io::write_vtu(
        &dir.path().join("bg.vtu"),
        &mesh,
        &[("spacing", &spacing), ("mach", &mach)],
        &[],
    )
    .unwrap();
    let count_left = |file: &str| {
        let m = delmesh::io::read_vtu(&dir.path().join(file)).unwrap();
        let xs: Vec<f64> = m.coords.chunks(3).map(|p| p[0]).collect();
        (xs.iter().filter(|&&x| x < 0.5).count(), xs.len())
    };
    ok(&delmesh(
        dir.path(),
        &[
            "mesh",
            "cube.off",
            "--background",
            "bg.vtu",
            "-o",
            "bg-out.vtu",
        ],
    ));
    let (left, all) = count_left("bg-out.vtu");
    assert!(
        2 * left > all + all / 5,
        "{left} of {all} points at x < 0.5"
    );
    ok(&delmesh(
        dir.path(),
        &[
            "mesh",
            "cube.off",
            "--adapt",
            "bg.vtu",
            "--field",
            "mach",
            "--min-spacing",
            "0.1",
            "--max-spacing",
            "0.5",
            "-o",
            "ad.vtu",
        ],
    ));
    let msg = fails(&delmesh(
        dir.path(),
        &[
            "mesh",
            "cube.off",
            "--background",
            "bg.vtu",
            "--field",
            "nope",
            "-o",
            "x.vtu",
        ],
    ));
    assert!(msg.contains("nope") && msg.contains("bg.vtu"), "{msg}");
    // A spacing far too fine for any mesh ends the run with a message, in 3D and 2D.
    let tiny = [1e-300; 8];
    delmesh::io::write_vtu(
        &dir.path().join("tiny.vtu"),
        &mesh,
        &[("spacing", &tiny)],
        &[],
    )
    .unwrap();
    let square = delmesh::io::SimplexMesh {
        dim: 2,
        coords: &[-1.0, -1.0, 11.0, -1.0, -1.0, 11.0],
        cells: &[0, 1, 2],
        neighbors: None,
    };
    delmesh::io::write_vtu(
        &dir.path().join("tiny2.vtu"),
        &square,
        &[("spacing", &tiny[..3])],
        &[],
    )
    .unwrap();
    std::fs::write(dir.path().join("sq.poly"), SQUARE_POLY).unwrap();
    for (domain, bg) in [("cube.off", "tiny.vtu"), ("sq.poly", "tiny2.vtu")] {
        let msg = fails(&delmesh(
            dir.path(),
            &["mesh", domain, "--background", bg, "-o", "x.vtu"],
        ));
        assert!(msg.contains("2^30") && msg.contains("1.000e-300"), "{msg}");
    }
    // A solver's mesh of hexahedra, prisms, pyramids (and a collapsed hexahedron, of no
    // volume) and a 2D one of quads and polygons serve as background meshes.
    let cells = Path::new(env!("CARGO_MANIFEST_DIR")).join("../io/tests/data/vtu-cells");
    for (domain, bg) in [("cube.off", "mixed-3d.vtu"), ("sq.poly", "mixed-2d.vtu")] {
        let bg = cells.join(bg);
        let bg = bg.to_str().unwrap();
        ok(&delmesh(
            dir.path(),
            &["mesh", domain, "--background", bg, "-o", "mixed.vtu"],
        ));
    }
    // A bad value in a Triangle background is named in its .node file's numbering.
    std::fs::write(
        dir.path().join("neg.node"),
        "3 2 1 0\n1 -1 -1 0.5\n2 11 -1 -0.5\n3 -1 11 0.5\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("neg.ele"), "1 3 0\n1 1 2 3\n").unwrap();
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "sq.poly", "--background", "neg.ele", "-o", "x.vtu"],
    ));
    assert_eq!(
        msg,
        "error: neg.node: node 2: spacing -0.5 is not positive and finite"
    );
    // A 2D background for the 3D domain, and the 3D one for a 2D domain: named as such.
    for (domain, bg, dims) in [
        ("cube.off", "tiny2.vtu", "2D mesh, but the domain is 3D"),
        ("sq.poly", "bg.vtu", "3D mesh, but the domain is 2D"),
    ] {
        let msg = fails(&delmesh(
            dir.path(),
            &["mesh", domain, "--background", bg, "-o", "x.vtu"],
        ));
        assert!(msg.contains(bg) && msg.contains(dims), "{msg}");
    }
}

#[test]
fn mesh_with_spacing_sources() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("sq.poly"), SQUARE_POLY).unwrap();
    std::fs::write(dir.path().join("cube.off"), cube_off(1.0)).unwrap();
    // Points of a mesh's .vtu within `r` of `c`, and all of them.
    let near = |file: &str, dim: usize, c: &[f64], r: f64| {
        let m = delmesh::io::read_vtu(&dir.path().join(file)).unwrap();
        let close = m
            .coords
            .chunks(m.dim)
            .filter(|p| (0..dim).map(|k| (p[k] - c[k]).powi(2)).sum::<f64>() < r * r)
            .count();
        (close, m.coords.len() / m.dim)
    };

    // 2D: a point source in a corner and a segment source along the far side.
    ok(&delmesh(
        dir.path(),
        &["mesh", "sq.poly", "-o", "plain.vtu"],
    ));
    let out = delmesh(
        dir.path(),
        &[
            "mesh",
            "sq.poly",
            "-o",
            "src.vtu",
            "--validate",
            "--source",
            "0.5,0.5,0.04,0.1,0.3",
            "--source",
            "3.6,0.4,3.6,3.6,0.1,0,0.5",
        ],
    );
    assert!(ok(&out).contains("validation: ok"));
    let (before, all_before) = near("plain.vtu", 2, &[0.5, 0.5], 0.3);
    let (after, all_after) = near("src.vtu", 2, &[0.5, 0.5], 0.3);
    assert!(
        after > 5 * before.max(1),
        "{before} -> {after} points near the source"
    );
    assert!(
        all_after > all_before + after,
        "{all_before} -> {all_after}"
    );

    // 3D: a point source at the cube's centre.
    ok(&delmesh(dir.path(), &["mesh", "cube.off", "-o", "c0.vtu"]));
    ok(&delmesh(
        dir.path(),
        &[
            "mesh",
            "cube.off",
            "-o",
            "c1.vtu",
            "--source",
            "0.5,0.5,0.5,0.05,0.1,0.5",
        ],
    ));
    let (before, _) = near("c0.vtu", 3, &[0.5, 0.5, 0.5], 0.15);
    let (after, _) = near("c1.vtu", 3, &[0.5, 0.5, 0.5], 0.15);
    assert!(
        after > 5 * before.max(1),
        "{before} -> {after} points near the 3D source"
    );

    // Bad specifications are refused before any work, naming the value.
    for (input, spec, why) in [
        ("sq.poly", "1,2,3", "3 numbers"),
        ("sq.poly", "0.5,0.5,0,0.1,0.3", "H0 must be positive"),
        ("sq.poly", "0.5,0.5,0.1,-1,0.3", "must not be negative"),
        ("sq.poly", "0.5,x,0.1,0.1,0.3", "`x` is not a finite number"),
        (
            "sq.poly",
            "0.5,0.5,nan,0.1,0.3",
            "`nan` is not a finite number",
        ),
        ("cube.off", "0.5,0.5,0.1,0.1,0.3", "a 3D source takes 6"),
    ] {
        let msg = fails(&delmesh(
            dir.path(),
            &["mesh", input, "-o", "bad.vtu", "--source", spec],
        ));
        assert!(
            msg.contains(&format!("--source {spec}")) && msg.contains(why),
            "{msg}"
        );
        assert!(!dir.path().join("bad.vtu").exists());
    }
}

#[test]
fn a_binary_gmsh_surface_meshes_as_its_ascii_twin() {
    // The same gmsh 4.15 mesh of a 2 x 1 x 1 box saved as binary and as ASCII (io's test
    // data): the same points bit for bit, so the same mesh, physical groups and all.
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../io/tests/data");
    let dir = tempfile::tempdir().unwrap();
    for (input, out) in [
        ("gmsh_box41.msh", "a.msh"),
        ("gmsh_box41_binary.msh", "b.msh"),
    ] {
        let input = data.join(input);
        ok(&delmesh(
            dir.path(),
            &["mesh", input.to_str().unwrap(), "-o", out, "--validate"],
        ));
    }
    let (a, b) = (
        std::fs::read_to_string(dir.path().join("a.msh")).unwrap(),
        std::fs::read_to_string(dir.path().join("b.msh")).unwrap(),
    );
    assert_eq!(a, b);
    assert!(a.contains("\"inlet\"") && a.contains("\"walls\""), "{a}");
}

#[test]
fn field_points_on_a_segment_or_off_the_plane_and_bad_option_values() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("sq.poly"), SQUARE_POLY).unwrap();
    std::fs::write(dir.path().join("cube.off"), cube_off(1.0)).unwrap();
    // A field point inside a boundary segment splits it (it was "segment 1 could not be
    // recovered after 0 splits"), in every recovery.
    std::fs::write(dir.path().join("on.xy"), "2 0\n1 2\n2 2\n").unwrap();
    for recovery in ["stitch", "a-priori", "constrained"] {
        let out = delmesh(
            dir.path(),
            &[
                "mesh",
                "sq.poly",
                "--points",
                "on.xy",
                "--recovery",
                recovery,
                "--validate",
                "-o",
                "on.ele",
            ],
        );
        assert!(ok(&out).contains("validation: ok"), "{recovery}");
        let node = std::fs::read_to_string(dir.path().join("on.node")).unwrap();
        // The input's 8 points, then the field points in their order.
        let ninth = node.lines().nth(9).unwrap();
        assert!(
            ninth.split_whitespace().skip(1).take(2).eq(["2", "0"]),
            "{ninth}"
        );
    }
    // Three columns for a 2D mesh: only in the plane z = 0.
    std::fs::write(dir.path().join("z.xyz"), "2 2 0\n2 2.5 0.5\n").unwrap();
    let msg = fails(&delmesh(
        dir.path(),
        &["mesh", "sq.poly", "--points", "z.xyz", "-o", "z.ele"],
    ));
    assert!(msg.contains("z.xyz: point 1 has z = 0.5"), "{msg}");
    // Negative and NaN values reach the checks (clap took `-1` for an option).
    for (args, why) in [
        (["sq.poly", "--alpha", "-1"], "alpha must be positive"),
        (["cube.off", "--sliver-flips", "nan"], "--sliver-flips"),
        (["cube.off", "--sliver-flips", "-5"], "--sliver-flips"),
    ] {
        let mut all = vec!["mesh"];
        all.extend(args);
        all.extend(["-o", "bad.vtu"]);
        let msg = fails(&delmesh(dir.path(), &all));
        assert!(msg.contains(why), "{args:?}: {msg}");
    }
}

#[test]
fn a_medit_surface_with_point_references_takes_a_surface_spacing() {
    // The split points had no marker beside the file's per-vertex references: "the surface
    // split to it fails the surface checks (a bug in delmesh): 4 point markers given for ...".
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("t.mesh"),
        "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n\
         Triangles\n4\n1 3 2 1\n1 2 4 2\n2 3 4 3\n1 4 3 4\nEnd\n",
    )
    .unwrap();
    let out = delmesh(
        dir.path(),
        &["mesh", "t.mesh", "-o", "t.ele", "--surface-spacing", "0.3"],
    );
    ok(&out);
    let node = std::fs::read_to_string(dir.path().join("t.node")).unwrap();
    let points: usize = node.split_whitespace().next().unwrap().parse().unwrap();
    assert!(points > 4, "{node}");
}

#[test]
fn a_gmsh_fillet_box_takes_a_surface_spacing() {
    // A box with filleted edges, surface-meshed by gmsh and written by meshio (binary PLY).
    // Meshing one of its planar patches in its own plane, rounding in the projection left
    // -2e-48 where a point on the frame's axis has 0, which the in-plane triangulation
    // refused beside coordinates of 0.08 (blamed on the input's point 3).
    let dir = tempfile::tempdir().unwrap();
    let surface = workspace_file("data/fillet-box-gmsh.ply");
    let out = delmesh(
        dir.path(),
        &[
            "mesh",
            surface.to_str().unwrap(),
            "-o",
            "f.ele",
            "--no-points",
            "--surface-spacing",
            "0.05",
            "--validate",
        ],
    );
    assert!(ok(&out).contains("validation: ok"));
}
