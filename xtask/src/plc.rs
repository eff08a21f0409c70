//! `cargo xtask cdt`: delmesh's Steiner-free 2D mesh (`delmesh mesh --recovery constrained
//! --no-points --no-smoothing`) against CGAL's constrained Delaunay triangulation.
//!
//! Inputs are seeded planar straight-line graphs: a star-shaped outer loop, star-shaped holes
//! (no hole seeds: nesting decides), and optionally random free points. Coordinates are random
//! doubles, so no four points are co-circular and the constrained Delaunay triangulation is
//! unique: delmesh's triangles must equal CGAL's (`xtask/cgal/cdt2.cpp`) one for one. The
//! table gives both tools' times (delmesh: its `mesh time:` line, the whole pipeline without
//! file I/O; CGAL: points, constraints and domain marking).

use std::collections::HashMap;
use std::fs;
use std::path::Path;
use std::process::Command;

use anyhow::{ensure, Context, Result};

use crate::cases::Rng;
use crate::{delmesh, reference, Ctx};

/// One input: outer loop vertices, holes, free points.
struct PlcCase {
    name: &'static str,
    outer: usize,
    holes: usize,
    points: usize,
}

const QUICK: &[PlcCase] = &[
    PlcCase {
        name: "star-holes-2k",
        outer: 2000,
        holes: 12,
        points: 0,
    },
    PlcCase {
        name: "star-holes-points-50k",
        outer: 1000,
        holes: 20,
        points: 50_000,
    },
];
const FULL: &[PlcCase] = &[
    PlcCase {
        name: "star-holes-100k",
        outer: 100_000,
        holes: 50,
        points: 0,
    },
    PlcCase {
        name: "star-holes-points-1m",
        outer: 5000,
        holes: 100,
        points: 1_000_000,
    },
];

/// A star-shaped loop around `c`: `n` vertices at random radii in `[r0, r1]`, angles
/// jittered within their sectors; counter-clockwise unless `cw`.
fn star(rng: &mut Rng, c: [f64; 2], n: usize, r0: f64, r1: f64, cw: bool) -> Vec<[f64; 2]> {
    let mut l: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * (i as f64 + 0.5 * rng.unit()) / n as f64;
            let r = r0 + (r1 - r0) * rng.unit();
            [c[0] + r * t.cos(), c[1] + r * t.sin()]
        })
        .collect();
    if cw {
        l.reverse();
    }
    l
}

/// The case's points and segments (0-based).
fn generate(case: &PlcCase, seed: u64) -> (Vec<[f64; 2]>, Vec<[u32; 2]>) {
    let mut rng = Rng::new(seed);
    let mut loops = vec![star(&mut rng, [0.0, 0.0], case.outer, 0.8, 1.0, false)];
    // Holes on a jittered lattice inside radius 0.55, each within its lattice cell.
    let side = (case.holes as f64).sqrt().ceil() as usize;
    let cell = 1.1 / side as f64;
    let mut placed = 0;
    'grid: for i in 0..side {
        for j in 0..side {
            if placed == case.holes {
                break 'grid;
            }
            let c = [
                -0.55 + (i as f64 + 0.5) * cell,
                -0.55 + (j as f64 + 0.5) * cell,
            ];
            let n = 5 + rng.below(20);
            loops.push(star(&mut rng, c, n, 0.15 * cell, 0.4 * cell, true));
            placed += 1;
        }
    }
    let mut points = Vec::new();
    let mut segments = Vec::new();
    for l in &loops {
        let base = points.len() as u32;
        let n = l.len() as u32;
        points.extend_from_slice(l);
        segments.extend((0..n).map(|k| [base + k, base + (k + 1) % n]));
    }
    for _ in 0..case.points {
        points.push([2.0 * rng.unit() - 1.0, 2.0 * rng.unit() - 1.0]);
    }
    (points, segments)
}

/// FORMAT: a 0-based `.poly` file with points, segments (marker 1) and no holes.
fn write_poly(path: &Path, points: &[[f64; 2]], segments: &[[u32; 2]]) -> Result<()> {
    let mut s = String::with_capacity(points.len() * 48);
    s.push_str(&format!("{} 2 0 0\n", points.len()));
    for (i, p) in points.iter().enumerate() {
        s.push_str(&format!("{i} {:?} {:?}\n", p[0], p[1]));
    }
    s.push_str(&format!("{} 1\n", segments.len()));
    for (i, e) in segments.iter().enumerate() {
        s.push_str(&format!("{i} {} {} 1\n", e[0], e[1]));
    }
    s.push_str("0\n");
    fs::write(path, s).with_context(|| format!("writing {}", path.display()))
}

/// Data lines of a Triangle text file, comments removed.
fn rows(path: &Path) -> Result<Vec<Vec<String>>> {
    let text = fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    Ok(text
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .map(|l| l.split_whitespace().map(str::to_string).collect::<Vec<_>>())
        .filter(|t| !t.is_empty())
        .collect())
}

/// delmesh's triangles in input numbering (its output drops unused points and renumbers:
/// vertices are mapped back by their exact coordinates), sorted.
fn delmesh_triangles(ele: &Path, points: &[[f64; 2]]) -> Result<Vec<[u32; 3]>> {
    let index: HashMap<(u64, u64), u32> = points
        .iter()
        .enumerate()
        .map(|(i, p)| ((p[0].to_bits(), p[1].to_bits()), i as u32))
        .collect();
    let node = rows(&ele.with_extension("node"))?;
    let mut input = Vec::with_capacity(node.len());
    for r in &node[1..] {
        let (x, y): (f64, f64) = (r[1].parse()?, r[2].parse()?);
        input.push(
            *index.get(&(x.to_bits(), y.to_bits())).with_context(|| {
                format!("delmesh output point ({x}, {y}) is not an input point")
            })?,
        );
    }
    let mut out = Vec::new();
    for r in &rows(ele)?[1..] {
        let mut t = [0u32; 3];
        for k in 0..3 {
            let v: usize = r[1 + k].parse()?;
            t[k] = input[v - 1]; // numbered from 1
        }
        t.sort_unstable();
        out.push(t);
    }
    out.sort_unstable();
    Ok(out)
}

/// Runs the comparison; errors if any case differs.
pub fn cdt(ctx: &Ctx, quick: bool) -> Result<()> {
    reference::ensure_tools()?;
    let driver = reference::build_cgal_program(&ctx.root, "cdt2")?;
    let bin = delmesh::build(&ctx.root)?;
    println!(
        "| case | points | segments | triangles | delmesh s | CGAL s | delmesh/CGAL | identical |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let mut failed = Vec::new();
    for (k, case) in (if quick { QUICK } else { FULL }).iter().enumerate() {
        let dir = ctx.runs.join(case.name);
        fs::create_dir_all(&dir)?;
        let (points, segments) = generate(case, 0xCD7_0000 + k as u64);
        let poly = dir.join(format!("{}.poly", case.name));
        write_poly(&poly, &points, &segments)?;
        let ele = dir.join(format!("{}.delmesh.ele", case.name));
        let out = Command::new(&bin)
            .arg("mesh")
            .arg(&poly)
            .arg("-o")
            .arg(&ele)
            .args([
                "--recovery",
                "constrained",
                "--no-points",
                "--no-smoothing",
                "--quiet",
                "--validate",
            ])
            .output()
            .context("running delmesh")?;
        let stderr = String::from_utf8_lossy(&out.stderr);
        ensure!(
            out.status.success(),
            "delmesh failed on {}: {}",
            case.name,
            stderr.trim()
        );
        // FORMAT: `mesh time: S s` on delmesh's stderr.
        let delmesh_secs: f64 = reference::find_value(&stderr, "mesh time:")
            .and_then(|v| v.split_whitespace().next())
            .context("no `mesh time:` line")?
            .parse()?;
        let cells = dir.join(format!("{}.cgal.cells", case.name));
        let cgal = Command::new(&driver).arg(&poly).arg(&cells).output()?;
        ensure!(
            cgal.status.success(),
            "CGAL failed: {}",
            String::from_utf8_lossy(&cgal.stderr)
        );
        let cgal_out = String::from_utf8_lossy(&cgal.stdout);
        let cgal_secs: f64 = reference::find_value(&cgal_out, "cgal_build_seconds")
            .context("no cgal_build_seconds")?
            .parse()?;
        let ours = delmesh_triangles(&ele, &points)?;
        let theirs: Vec<[u32; 3]> = rows(&cells)?
            .iter()
            .map(|r| Ok([r[0].parse()?, r[1].parse()?, r[2].parse()?]))
            .collect::<Result<_>>()?;
        let same = ours == theirs;
        if !same {
            failed.push(case.name);
        }
        println!(
            "| {} | {} | {} | {} | {:.3} | {:.3} | {:.2} | {} |",
            case.name,
            points.len(),
            segments.len(),
            ours.len(),
            delmesh_secs,
            cgal_secs,
            delmesh_secs / cgal_secs,
            if same {
                "yes".to_string()
            } else {
                format!("NO (CGAL {})", theirs.len())
            }
        );
    }
    ensure!(failed.is_empty(), "delmesh differs from CGAL on {failed:?}");
    println!("cdt: ok");
    Ok(())
}
