//! Closed triangulated surfaces on the xtask side: reading and writing `.off`, cleaning
//! a raw file for TetGen, and the quantities the mesh checks compare against (enclosed
//! volume, Euler characteristic, orientation consistency).
//!
//! xtask reads the inputs itself, independently of delmesh's reader, so that the checks
//! of `cargo xtask surfaces` compare delmesh's output with what the file says rather
//! than with what delmesh understood of it.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::fs;
use std::path::Path;

#[cfg(test)]
use anyhow::bail;
use anyhow::{ensure, Context, Result};

/// A triangulated surface: points and 0-based triangles.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Surface {
    pub points: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

/// What [`Surface::cleaned_with_map`] changed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Cleaning {
    /// Vertices at exactly the coordinates of an earlier one, merged into it.
    pub merged: usize,
    /// Vertices no triangle uses, dropped.
    pub unused: usize,
    /// Triangles with two equal corners after merging, dropped.
    pub degenerate: usize,
}

impl Cleaning {
    /// True when the cleaned surface is the input.
    pub fn is_empty(&self) -> bool {
        *self == Cleaning::default()
    }
}

impl std::fmt::Display for Cleaning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut parts = Vec::new();
        for (n, what) in [
            (self.merged, "duplicate vertices merged"),
            (self.unused, "unused vertices dropped"),
            (self.degenerate, "degenerate triangles dropped"),
        ] {
            if n > 0 {
                parts.push(format!("{n} {what}"));
            }
        }
        if parts.is_empty() {
            write!(f, "nothing to clean")
        } else {
            write!(f, "{}", parts.join(", "))
        }
    }
}

/// Sum with Neumaier's compensation (volumes and areas of large meshes).
#[derive(Debug, Clone, Copy, Default)]
pub struct Sum {
    sum: f64,
    comp: f64,
}

impl Sum {
    pub fn add(&mut self, x: f64) {
        let t = self.sum + x;
        self.comp += if self.sum.abs() >= x.abs() {
            (self.sum - t) + x
        } else {
            (x - t) + self.sum
        };
        self.sum = t;
    }

    pub fn value(&self) -> f64 {
        self.sum + self.comp
    }
}

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Area of the triangle `a b c`.
pub fn triangle_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    0.5 * norm(cross(sub(b, a), sub(c, a)))
}

/// Exact-bits key of a point (+0.0 and -0.0 are the same point).
pub fn point_key(p: [f64; 3]) -> [u64; 3] {
    p.map(|x| (x + 0.0).to_bits())
}

/// Sorted copy of a triangle's corners (an orientation-free key).
pub fn sorted3(t: [u32; 3]) -> [u32; 3] {
    let mut s = t;
    s.sort_unstable();
    s
}

impl Surface {
    /// Axis-aligned bounding box (min, max).
    pub fn bbox(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &self.points {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (lo, hi)
    }

    /// Length of the bounding box diagonal.
    pub fn diagonal(&self) -> f64 {
        let (lo, hi) = self.bbox();
        norm(sub(hi, lo))
    }

    fn corner(&self, t: [u32; 3]) -> [[f64; 3]; 3] {
        t.map(|v| self.points[v as usize])
    }

    /// Total area.
    #[cfg(test)]
    pub fn area(&self) -> f64 {
        let mut s = Sum::default();
        for &t in &self.triangles {
            let [a, b, c] = self.corner(t);
            s.add(triangle_area(a, b, c));
        }
        s.value()
    }

    /// The signed volume enclosed, by the divergence theorem: the sum over triangles of
    /// `a · (b × c) / 6` (positive when the triangles are oriented outwards, i.e.
    /// counterclockwise seen from outside). Points are taken relative to the bounding box
    /// centre to limit cancellation.
    pub fn signed_volume(&self) -> f64 {
        let (lo, hi) = self.bbox();
        let c = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        let mut s = Sum::default();
        for &t in &self.triangles {
            let [a, b, d] = self.corner(t).map(|p| sub(p, c));
            s.add(dot(a, cross(b, d)) / 6.0);
        }
        s.value()
    }

    /// Counts of the edges used by 1, 2 (the closed-manifold case) and more triangles,
    /// and the number of edges whose two triangles traverse it in the same direction
    /// (inconsistent orientation).
    pub fn edge_report(&self) -> EdgeReport {
        let mut uses: HashMap<(u32, u32), (u32, i32)> = HashMap::new();
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let e = uses.entry((a.min(b), a.max(b))).or_insert((0, 0));
                e.0 += 1;
                e.1 += if a < b { 1 } else { -1 };
            }
        }
        let mut r = EdgeReport::default();
        for &(n, dir) in uses.values() {
            match n {
                1 => r.border += 1,
                2 if dir != 0 => r.flipped += 1,
                2 => {}
                _ => r.nonmanifold += 1,
            }
        }
        r.edges = uses.len();
        r
    }

    /// V − E + F over the vertices used by triangles.
    pub fn euler_characteristic(&self) -> i64 {
        let e = self.edge_report().edges as i64;
        let mut used = vec![false; self.points.len()];
        for t in &self.triangles {
            for &v in t {
                used[v as usize] = true;
            }
        }
        let v = used.iter().filter(|&&u| u).count() as i64;
        v - e + self.triangles.len() as i64
    }

    /// [`Surface::cleaned_with_map`] without the map.
    #[cfg(test)]
    pub fn cleaned(&self) -> (Surface, Cleaning) {
        let (s, c, _) = self.cleaned_with_map();
        (s, c)
    }

    /// The surface with exactly coincident vertices merged onto their first occurrence,
    /// unused vertices dropped and triangles with two equal corners dropped, numbered
    /// compactly in first-occurrence order; with the index in `self` of every kept triangle.
    pub fn cleaned_with_map(&self) -> (Surface, Cleaning, Vec<u32>) {
        let mut first: HashMap<[u64; 3], u32> = HashMap::with_capacity(self.points.len());
        let mut canon = Vec::with_capacity(self.points.len());
        let mut c = Cleaning::default();
        for (i, &p) in self.points.iter().enumerate() {
            let e = *first.entry(point_key(p)).or_insert(i as u32);
            if e != i as u32 {
                c.merged += 1;
            }
            canon.push(e);
        }
        let mut triangles = Vec::with_capacity(self.triangles.len());
        let mut kept = Vec::with_capacity(self.triangles.len());
        for (k, t) in self.triangles.iter().enumerate() {
            let m = t.map(|v| canon[v as usize]);
            if m[0] == m[1] || m[1] == m[2] || m[0] == m[2] {
                c.degenerate += 1;
            } else {
                triangles.push(m);
                kept.push(k as u32);
            }
        }
        // Surviving vertices keep their relative order, so a clean surface maps to itself.
        let mut used = vec![false; self.points.len()];
        for t in &triangles {
            for &v in t {
                used[v as usize] = true;
            }
        }
        let mut new_index = vec![u32::MAX; self.points.len()];
        let mut points = Vec::new();
        for (i, &p) in self.points.iter().enumerate() {
            if used[i] {
                new_index[i] = points.len() as u32;
                points.push(p);
            }
        }
        for t in &mut triangles {
            *t = t.map(|v| new_index[v as usize]);
        }
        c.unused = self.points.len() - c.merged - points.len();
        (Surface { points, triangles }, c, kept)
    }
}

/// See [`Surface::edge_report`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct EdgeReport {
    pub edges: usize,
    /// Edges of one triangle (a hole in the surface).
    pub border: usize,
    /// Edges of three or more triangles.
    pub nonmanifold: usize,
    /// Edges whose two triangles run along it in the same direction.
    pub flipped: usize,
}

impl EdgeReport {
    /// Closed, manifold along edges, and consistently oriented.
    pub fn is_closed_oriented(&self) -> bool {
        self.border == 0 && self.nonmanifold == 0 && self.flipped == 0
    }
}

/// Reads an `.off` file.
///
/// FORMAT (Geomview OFF, as CGAL writes it): `#` starts a comment anywhere and blank
/// lines are skipped (CGAL's files start with a block of `#` lines, which TetGen 1.5's
/// reader cannot handle); an optional keyword ending in `OFF` (`OFF`, `COFF`, `NOFF`,
/// ...); `<#vertices> <#faces> [<#edges>]` on the keyword's line or the next; one vertex
/// per line, `x y z` then anything (colours, normals: ignored); one face per line,
/// `<n> <v1> ... <vn>` (0-based) then anything (a colour). Only triangles are accepted,
/// which is what every case uses.
pub fn read_off(path: &Path) -> Result<Surface> {
    let text = fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    parse_off(&text).with_context(|| format!("parsing {}", path.display()))
}

/// The text of an `.off` file as a [`Surface`] (see [`read_off`]).
pub fn parse_off(text: &str) -> Result<Surface> {
    let mut lines = text.lines().enumerate().filter_map(|(i, l)| {
        let l = l.split('#').next().unwrap_or("");
        let f: Vec<&str> = l.split_whitespace().collect();
        (!f.is_empty()).then_some((i + 1, f))
    });
    let (mut ln, mut f) = lines.next().context("empty file")?;
    let key = f[0];
    if key.len() >= 3 && key[key.len() - 3..].eq_ignore_ascii_case("off") {
        ensure!(
            key[..key.len() - 3]
                .chars()
                .all(|c| "STCN".contains(c.to_ascii_uppercase())),
            "line {ln}: unsupported OFF variant `{key}`"
        );
        ensure!(
            f.get(1).is_none_or(|t| !t.eq_ignore_ascii_case("binary")),
            "line {ln}: binary OFF"
        );
        f.remove(0);
        if f.is_empty() {
            (ln, f) = lines.next().context("no counts after the OFF keyword")?;
        }
    }
    ensure!(f.len() >= 2, "line {ln}: expected `<#vertices> <#faces>`");
    let count = |s: &str| -> Result<usize> {
        s.parse()
            .ok()
            .with_context(|| format!("line {ln}: bad count `{s}`"))
    };
    let (nv, nf) = (count(f[0])?, count(f[1])?);
    let mut s = Surface {
        points: Vec::with_capacity(nv),
        triangles: Vec::with_capacity(nf),
    };
    for _ in 0..nv {
        let (ln, f) = lines
            .next()
            .context("fewer vertices than the header says")?;
        ensure!(f.len() >= 3, "line {ln}: a vertex needs x y z");
        let mut p = [0.0; 3];
        for k in 0..3 {
            p[k] = f[k]
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .with_context(|| format!("line {ln}: bad coordinate `{}`", f[k]))?;
        }
        s.points.push(p);
    }
    for _ in 0..nf {
        let (ln, f) = lines.next().context("fewer faces than the header says")?;
        let ints: Vec<u64> = f
            .iter()
            .take(4)
            .map(|t| t.parse::<u64>())
            .collect::<Result<_, _>>()
            .ok()
            .with_context(|| format!("line {ln}: bad face"))?;
        ensure!(
            ints.len() == 4 && ints[0] == 3,
            "line {ln}: only triangles are supported (`{}`)",
            f.join(" ")
        );
        let mut t = [0u32; 3];
        for k in 0..3 {
            let v = ints[k + 1];
            ensure!(
                (v as usize) < nv,
                "line {ln}: vertex {v} does not exist ({nv} vertices)"
            );
            t[k] = v as u32;
        }
        s.triangles.push(t);
    }
    Ok(s)
}

/// Writes `s` as a plain `.off` file: `OFF`, the counts, then vertices and triangles, no
/// comments; coordinates printed shortest-round-trip so every reader gets the same
/// doubles.
pub fn write_off(path: &Path, s: &Surface) -> Result<()> {
    let mut out = String::with_capacity(s.points.len() * 60 + s.triangles.len() * 24);
    let _ = writeln!(out, "OFF\n{} {} 0", s.points.len(), s.triangles.len());
    for p in &s.points {
        let _ = writeln!(out, "{:?} {:?} {:?}", p[0], p[1], p[2]);
    }
    for t in &s.triangles {
        let _ = writeln!(out, "3 {} {} {}", t[0], t[1], t[2]);
    }
    if let Some(dir) = path.parent() {
        fs::create_dir_all(dir)?;
    }
    fs::write(path, out).with_context(|| format!("writing {}", path.display()))
}

/// Writes `s` as a TetGen `.smesh` file with hole points (TetGen's `.off` reader has no
/// way to say that a closed inner surface bounds a void, so without them TetGen meshes
/// the void too).
///
/// FORMAT (TetGen 1.5 `.smesh`): `<#points> 3 0 0` and `<i> x y z` (0-based, which sets
/// the facets' numbering), `<#facets> 0` and `3 a b c`, `<#holes>` and `<i> x y z`, then
/// `0` regions.
pub fn write_smesh(path: &Path, s: &Surface, holes: &[[f64; 3]]) -> Result<()> {
    let mut out = String::with_capacity(s.points.len() * 64 + s.triangles.len() * 24);
    let _ = writeln!(out, "{} 3 0 0", s.points.len());
    for (i, p) in s.points.iter().enumerate() {
        let _ = writeln!(out, "{i} {:?} {:?} {:?}", p[0], p[1], p[2]);
    }
    let _ = writeln!(out, "{} 0", s.triangles.len());
    for t in &s.triangles {
        let _ = writeln!(out, "3 {} {} {}", t[0], t[1], t[2]);
    }
    let _ = writeln!(out, "{}", holes.len());
    for (i, h) in holes.iter().enumerate() {
        let _ = writeln!(out, "{i} {:?} {:?} {:?}", h[0], h[1], h[2]);
    }
    out.push_str("0\n");
    if let Some(dir) = path.parent() {
        fs::create_dir_all(dir)?;
    }
    fs::write(path, out).with_context(|| format!("writing {}", path.display()))
}

/// Fails unless `s` is a closed, edge-manifold, consistently oriented surface.
#[cfg(test)]
pub fn check_closed(s: &Surface) -> Result<EdgeReport> {
    let r = s.edge_report();
    if !r.is_closed_oriented() {
        bail!(
            "the surface is not closed and consistently oriented: {} border edges, {} \
             edges of 3+ triangles, {} edges with both triangles in the same direction",
            r.border,
            r.nonmanifold,
            r.flipped
        );
    }
    Ok(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube [0,1]^3, outward, as CGAL writes it (comments, blank lines).
    pub(crate) const CUBE_OFF: &str = "\
# Output of a CGAL tool
#CBP
# ENDCBP

OFF
8 12 0

# 8 vertices
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1

# 12 facets
3 0 2 1
3 0 3 2
3 4 5 6
3 4 6 7
3 0 1 5
3 0 5 4
3 1 2 6 255 0 0
3 1 6 5
3 2 3 7
3 2 7 6
3 3 0 4
3 3 4 7
";

    #[test]
    fn reads_cgal_off_and_measures() {
        let s = parse_off(CUBE_OFF).unwrap();
        assert_eq!((s.points.len(), s.triangles.len()), (8, 12));
        assert_eq!(s.triangles[6], [1, 2, 6]);
        assert_eq!(s.signed_volume(), 1.0);
        assert_eq!(s.area(), 6.0);
        assert_eq!(s.euler_characteristic(), 2);
        assert!(check_closed(&s).is_ok());
        let mut flipped = s.clone();
        flipped.triangles[0] = [0, 1, 2];
        let r = flipped.edge_report();
        assert_eq!(r.flipped, 3);
        assert!(check_closed(&flipped).is_err());
        let mut open = s.clone();
        open.triangles.pop();
        assert_eq!(open.edge_report().border, 3);
    }

    #[test]
    fn off_headers_and_errors() {
        let s = parse_off("OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
        assert_eq!(s.triangles, [[0, 1, 2]]);
        let s = parse_off("3 1\n0 0 0 1 1 1\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
        assert_eq!(s.points[0], [0.0, 0.0, 0.0]);
        let s = parse_off("COFF\n3 1 0\n0 0 0 9\n1 0 0 9\n0 1 0 9\n3 2 1 0\n").unwrap();
        assert_eq!(s.triangles, [[2, 1, 0]]);
        for (bad, why) in [
            ("OFF\n3 1 0\n0 0 0\n1 0 0\n", "fewer vertices"),
            (
                "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2 0\n",
                "only triangles",
            ),
            (
                "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
                "does not exist",
            ),
            (
                "OFF\n3 1 0\n0 0 x\n1 0 0\n0 1 0\n3 0 1 2\n",
                "bad coordinate",
            ),
            ("OFF BINARY\n", "binary"),
            ("4OFF\n", "unsupported OFF variant"),
            ("", "empty"),
        ] {
            let err = format!("{:#}", parse_off(bad).unwrap_err());
            assert!(err.contains(why), "{bad:?}: {err}");
        }
    }

    #[test]
    fn round_trip_and_cleaning() {
        let dir = std::env::temp_dir().join(format!("xtask-off-{}", std::process::id()));
        let mut s = parse_off(CUBE_OFF).unwrap();
        s.points[3] = [0.1, 1.0 / 3.0, -0.0];
        let p = dir.join("a.off");
        write_off(&p, &s).unwrap();
        assert_eq!(read_off(&p).unwrap(), s);
        fs::remove_dir_all(&dir).unwrap();

        // A copy of vertex 1 used by one triangle, an unused vertex, and a triangle that
        // degenerates once the copy is merged.
        let mut raw = parse_off(CUBE_OFF).unwrap();
        raw.points.push([1.0, 0.0, 0.0]); // 8 = copy of 1
        raw.points.push([5.0, 5.0, 5.0]); // 9, unused
        raw.triangles[0] = [0, 2, 8];
        raw.triangles.push([1, 8, 2]);
        let (clean, c) = raw.cleaned();
        assert_eq!(
            c,
            Cleaning {
                merged: 1,
                unused: 1,
                degenerate: 1
            }
        );
        assert_eq!(
            c.to_string(),
            "1 duplicate vertices merged, 1 unused vertices dropped, 1 degenerate triangles dropped"
        );
        assert_eq!((clean.points.len(), clean.triangles.len()), (8, 12));
        let (_, _, kept) = raw.cleaned_with_map();
        assert_eq!(kept, (0..12).collect::<Vec<u32>>());
        assert!(check_closed(&clean).is_ok());
        assert_eq!(clean.signed_volume(), 1.0);
        let (again, c) = clean.cleaned();
        assert!(c.is_empty());
        assert_eq!(again, clean);
    }
}
