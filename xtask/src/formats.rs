//! Text formats shared by the validation side: TetGen/Triangle `.node` and `.ele`
//! files, and xtask's own `.cells` format, plus cell-set comparison.
//!
//! `.cells` is the common currency of every reference and comparison step: one line
//! per finite cell (triangle in 2D, tetrahedron in 3D), its vertices as 0-based
//! input indices separated by single spaces, each line sorted ascending, lines sorted
//! lexicographically, no header. Two triangulations of the same input are the same
//! exactly when their `.cells` files are byte-identical. The CGAL driver
//! (`xtask/cgal/delaunay.cpp`) writes it directly; TetGen's and delmesh's `.ele`
//! output is converted into it here.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::fs;
use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::{bail, ensure, Context, Result};

/// Padding value for the unused fourth slot of a triangle.
const PAD: u32 = u32::MAX;

/// Iterates the non-empty, comment-stripped lines of a TetGen/Triangle text file as
/// (1-based line number, whitespace-split fields). `#` starts a comment anywhere.
fn data_lines(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(i, line)| {
        let line = line.split('#').next().unwrap_or("");
        let fields: Vec<&str> = line
            .split(|c: char| c.is_ascii_whitespace() || c == ',')
            .filter(|f| !f.is_empty())
            .collect();
        (!fields.is_empty()).then_some((i + 1, fields))
    })
}

fn parse_field<T: std::str::FromStr>(field: &str, line: usize, path: &Path) -> Result<T> {
    field
        .parse()
        .ok()
        .with_context(|| format!("{}:{line}: bad number `{field}`", path.display()))
}

/// A parsed `.node` file.
#[derive(Debug, Clone)]
pub struct NodeFile {
    /// 2 or 3.
    pub dim: usize,
    /// Index of the first point as written in the file (0 or 1 in practice).
    pub first_index: i64,
    /// Coordinates, `dim` per point, in file order (so point `i` is 0-based index `i`).
    pub coords: Vec<f64>,
    /// Attributes per point (`nattr` in the header).
    pub nattr: usize,
    /// Attributes, `nattr` per point.
    pub attrs: Vec<f64>,
}

impl NodeFile {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.coords.len() / self.dim
    }

    /// Coordinates of 0-based point `i`.
    pub fn point(&self, i: usize) -> &[f64] {
        &self.coords[i * self.dim..(i + 1) * self.dim]
    }
}

/// Reads a TetGen/Triangle `.node` file. Format: first non-comment line
/// `<n> <dim> <nattr> <nmarkers>`, then `n` lines `<idx> x y [z] [attr...] [marker]`
/// with consecutive indices starting at 0 or 1.
pub fn read_node(path: &Path) -> Result<NodeFile> {
    let text = fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = data_lines(&text);
    let (hl, header) = lines
        .next()
        .with_context(|| format!("{}: empty", path.display()))?;
    let n: usize = parse_field(header[0], hl, path)?;
    let dim: usize = match header.get(1) {
        Some(f) => parse_field(f, hl, path)?,
        None => 3,
    };
    let nattr: usize = match header.get(2) {
        Some(f) => parse_field(f, hl, path)?,
        None => 0,
    };
    ensure!(
        dim == 2 || dim == 3,
        "{}: dimension {dim} is not 2 or 3",
        path.display()
    );
    let mut node = NodeFile {
        dim,
        first_index: 0,
        coords: Vec::with_capacity(n * dim),
        nattr,
        attrs: Vec::with_capacity(n * nattr),
    };
    for (k, (ln, fields)) in lines.take(n).enumerate() {
        ensure!(
            fields.len() > dim + nattr,
            "{}:{ln}: too few fields",
            path.display()
        );
        let idx: i64 = parse_field(fields[0], ln, path)?;
        if k == 0 {
            node.first_index = idx;
        }
        ensure!(
            idx == node.first_index + k as i64,
            "{}:{ln}: index {idx} is not consecutive",
            path.display()
        );
        for f in &fields[1..=dim] {
            node.coords.push(parse_field(f, ln, path)?);
        }
        for f in &fields[dim + 1..dim + 1 + nattr] {
            node.attrs.push(parse_field(f, ln, path)?);
        }
    }
    ensure!(
        node.len() == n,
        "{}: header says {n} points, found {}",
        path.display(),
        node.len()
    );
    Ok(node)
}

/// Writes a 0-based `.node` file with no markers. Coordinates use Rust's `{}`
/// formatting, which is the shortest string that parses back to the same `f64`, so
/// every reader (strtod, Rust's `parse`) sees exactly the generated points.
/// `attrs` holds `nattr` values per point.
pub fn write_node(
    path: &Path,
    dim: usize,
    coords: &[f64],
    nattr: usize,
    attrs: &[f64],
) -> Result<()> {
    let n = coords.len() / dim;
    ensure!(attrs.len() == n * nattr, "attribute count mismatch");
    let file = fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    writeln!(w, "{n} {dim} {nattr} 0")?;
    let mut line = String::new();
    for i in 0..n {
        line.clear();
        write!(line, "{i}")?;
        for c in &coords[i * dim..(i + 1) * dim] {
            write!(line, " {c}")?;
        }
        for a in &attrs[i * nattr..(i + 1) * nattr] {
            write!(line, " {a}")?;
        }
        line.push('\n');
        w.write_all(line.as_bytes())?;
    }
    w.flush()?;
    Ok(())
}

/// A canonical set of cells: every cell sorted ascending, the list sorted
/// lexicographically. Triangles are stored with a padding fourth slot.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CellSet {
    /// 3 (triangles) or 4 (tetrahedra).
    pub arity: usize,
    cells: Vec<[u32; 4]>,
}

impl CellSet {
    /// Builds a canonical set from cells in any order and orientation. For arity 3
    /// only the first three entries of each cell are used.
    pub fn new(arity: usize, mut cells: Vec<[u32; 4]>) -> Self {
        assert!(arity == 3 || arity == 4);
        for c in &mut cells {
            if arity == 3 {
                c[3] = PAD;
            }
            c.sort_unstable();
        }
        cells.sort_unstable();
        CellSet { arity, cells }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// The cells, each with `arity` vertices.
    pub fn iter(&self) -> impl Iterator<Item = &[u32]> + '_ {
        self.cells.iter().map(move |c| &c[..self.arity])
    }

    /// Renames every vertex `v` to `map[v]` and re-canonicalizes.
    pub fn remap(&self, map: &[u32]) -> Result<CellSet> {
        let mut cells = self.cells.clone();
        for c in &mut cells {
            for v in &mut c[..self.arity] {
                *v = *map
                    .get(*v as usize)
                    .with_context(|| format!("vertex {v} out of range"))?;
            }
        }
        Ok(CellSet::new(self.arity, cells))
    }

    /// Writes the `.cells` format.
    pub fn write(&self, path: &Path) -> Result<()> {
        let file =
            fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
        let mut w = BufWriter::with_capacity(1 << 20, file);
        let mut line = String::new();
        for c in self.iter() {
            line.clear();
            for (k, v) in c.iter().enumerate() {
                if k > 0 {
                    line.push(' ');
                }
                write!(line, "{v}")?;
            }
            line.push('\n');
            w.write_all(line.as_bytes())?;
        }
        w.flush()?;
        Ok(())
    }
}

/// Splits one line of an integer-only file (`.ele`, `.cells`) into its numbers,
/// appended to `out`: fields are separated by ASCII whitespace or commas, `#` starts a
/// comment. A hand-rolled byte scanner: a 10^6-point tetrahedralization has 6.5
/// million lines, and this is several times faster than splitting into strings.
/// Returns the offending field on anything but an optionally signed decimal integer.
fn int_fields(line: &[u8], out: &mut Vec<i64>) -> Result<(), String> {
    out.clear();
    let mut i = 0;
    while i < line.len() {
        let b = line[i];
        if b == b'#' {
            break;
        }
        if b.is_ascii_whitespace() || b == b',' {
            i += 1;
            continue;
        }
        let start = i;
        while i < line.len()
            && !(line[i].is_ascii_whitespace() || line[i] == b',' || line[i] == b'#')
        {
            i += 1;
        }
        let field = &line[start..i];
        let (neg, digits) = match field.first() {
            Some(b'-') => (true, &field[1..]),
            Some(b'+') => (false, &field[1..]),
            _ => (false, field),
        };
        let bad = || String::from_utf8_lossy(field).into_owned();
        if digits.is_empty() || digits.len() > 18 || !digits.iter().all(u8::is_ascii_digit) {
            return Err(bad());
        }
        let v = digits
            .iter()
            .fold(0i64, |acc, &d| acc * 10 + i64::from(d - b'0'));
        out.push(if neg { -v } else { v });
    }
    Ok(())
}

/// Iterates the lines of `bytes` that hold numbers, as (1-based line number, numbers).
pub(crate) fn int_lines<'a>(
    bytes: &'a [u8],
    path: &'a Path,
) -> impl Iterator<Item = Result<(usize, Vec<i64>)>> + 'a {
    let mut fields = Vec::with_capacity(8);
    bytes
        .split(|&b| b == b'\n')
        .enumerate()
        .filter_map(move |(i, line)| match int_fields(line, &mut fields) {
            Err(f) => Some(Err(anyhow::anyhow!(
                "{}:{}: bad integer `{f}`",
                path.display(),
                i + 1
            ))),
            Ok(()) if fields.is_empty() => None,
            Ok(()) => Some(Ok((i + 1, fields.clone()))),
        })
}

/// Reads a `.cells` file (see the module docs); the arity is taken from the first
/// line (an empty file gives an empty set of arity `default_arity`). The content is
/// re-canonicalized, so a hand-edited file still compares correctly.
pub fn read_cells(path: &Path, default_arity: usize) -> Result<CellSet> {
    let bytes = fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let mut arity = 0;
    let mut cells = Vec::with_capacity(bytes.len() / 24);
    for line in int_lines(&bytes, path) {
        let (ln, f) = line?;
        if arity == 0 {
            arity = f.len();
            ensure!(
                arity == 3 || arity == 4,
                "{}: cells of {arity} vertices",
                path.display()
            );
        }
        ensure!(
            f.len() == arity,
            "{}:{ln}: {} vertices, expected {arity}",
            path.display(),
            f.len()
        );
        cells.push(to_cell(&f, 0, path, ln)?);
    }
    Ok(CellSet::new(
        if arity == 0 { default_arity } else { arity },
        cells,
    ))
}

/// The first up-to-4 numbers of `f`, minus `shift`, as a padded cell.
fn to_cell(f: &[i64], shift: i64, path: &Path, ln: usize) -> Result<[u32; 4]> {
    let mut c = [PAD; 4];
    for (slot, &v) in c.iter_mut().zip(f) {
        let v = v - shift;
        ensure!(
            (0..PAD as i64).contains(&v),
            "{}:{ln}: vertex {} out of range",
            path.display(),
            v + shift
        );
        *slot = v as u32;
    }
    Ok(c)
}

/// Reads a TetGen/Triangle `.ele` file and returns its cells as 0-based indices.
///
/// FORMAT (TetGen `.ele`, Triangle `.ele`, delmesh's `.ele`): first non-comment line
/// `<ncells> <nodes per cell> <nattr>`, then `<idx> v1 v2 ... [attrs]`. The vertex
/// numbers follow the numbering of the `.node` file the mesh refers to, so
/// `node_first_index` (0 or 1) is subtracted. Only the first `arity` vertices are
/// used (corner nodes of second-order elements come first).
pub fn read_ele(path: &Path, arity: usize, node_first_index: i64) -> Result<CellSet> {
    let bytes = fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = int_lines(&bytes, path);
    let (hl, header) = lines
        .next()
        .with_context(|| format!("{}: empty", path.display()))??;
    let n = usize::try_from(header[0])
        .with_context(|| format!("{}:{hl}: negative cell count", path.display()))?;
    let per = header.get(1).copied().unwrap_or(arity as i64);
    ensure!(
        per >= arity as i64,
        "{}: {per} nodes per cell, need {arity}",
        path.display()
    );
    let mut cells = Vec::with_capacity(n);
    for line in lines.take(n) {
        let (ln, f) = line?;
        ensure!(f.len() > arity, "{}:{ln}: too few fields", path.display());
        cells.push(to_cell(&f[1..=arity], node_first_index, path, ln)?);
    }
    ensure!(
        cells.len() == n,
        "{}: header says {n} cells, found {}",
        path.display(),
        cells.len()
    );
    Ok(CellSet::new(arity, cells))
}

/// For inputs with coincident points: maps every 0-based index to the smallest index
/// with exactly the same coordinates. `None` when all points are distinct. Tools keep
/// an arbitrary member of each coincident group, so cell sets are compared after
/// [`CellSet::remap`] with this map.
pub fn duplicate_canonical_map(node: &NodeFile) -> Option<Vec<u32>> {
    let mut first: HashMap<Vec<u64>, u32> = HashMap::with_capacity(node.len());
    let mut map = Vec::with_capacity(node.len());
    let mut any = false;
    for i in 0..node.len() {
        // +0.0 and -0.0 are the same point: normalize before hashing bits.
        let key: Vec<u64> = node.point(i).iter().map(|&x| (x + 0.0).to_bits()).collect();
        let e = *first.entry(key).or_insert(i as u32);
        any |= e != i as u32;
        map.push(e);
    }
    any.then_some(map)
}

/// Result of comparing two cell sets.
#[derive(Debug, Default)]
pub struct CellDiff {
    /// Cells present only in the first set.
    pub only_a: usize,
    /// Cells present only in the second set.
    pub only_b: usize,
    /// The first few differing cells in sorted order, each with `true` when it is in
    /// the first set (and missing from the second).
    pub examples: Vec<(bool, Vec<u32>)>,
}

impl CellDiff {
    /// True when the two sets are identical.
    pub fn is_empty(&self) -> bool {
        self.only_a == 0 && self.only_b == 0
    }

    /// One line naming the sets `a` and `b`: the counts and the first differing cell
    /// tuple, e.g. `3 cells only in delmesh, 3 only in CGAL; first difference: [0, 4,
    /// 7, 9] is in delmesh, not in CGAL`.
    pub fn describe(&self, a: &str, b: &str) -> String {
        if self.is_empty() {
            return "identical".into();
        }
        let mut s = format!(
            "{} cells only in {a}, {} only in {b}",
            self.only_a, self.only_b
        );
        if let Some((in_a, cell)) = self.examples.first() {
            let (has, lacks) = if *in_a { (a, b) } else { (b, a) };
            s += &format!("; first difference: {cell:?} is in {has}, not in {lacks}");
        }
        s
    }
}

/// Compares two canonical cell sets by a merge walk.
pub fn compare(a: &CellSet, b: &CellSet) -> Result<CellDiff> {
    if a.arity != b.arity {
        bail!("comparing cells of {} and {} vertices", a.arity, b.arity);
    }
    let mut d = CellDiff::default();
    let (mut i, mut j) = (0, 0);
    let note = |d: &mut CellDiff, in_a: bool, c: &[u32]| {
        if d.examples.len() < 8 {
            d.examples.push((in_a, c.to_vec()));
        }
    };
    while i < a.cells.len() || j < b.cells.len() {
        match (a.cells.get(i), b.cells.get(j)) {
            (Some(x), Some(y)) if x == y => {
                i += 1;
                j += 1;
            }
            (Some(x), Some(y)) if x < y => {
                d.only_a += 1;
                note(&mut d, true, &x[..a.arity]);
                i += 1;
            }
            (Some(x), None) => {
                d.only_a += 1;
                note(&mut d, true, &x[..a.arity]);
                i += 1;
            }
            (_, Some(y)) => {
                d.only_b += 1;
                note(&mut d, false, &y[..b.arity]);
                j += 1;
            }
            (None, None) => unreachable!(),
        }
    }
    Ok(d)
}

/// Sum of the absolute measures (areas in 2D, volumes in 3D) of the cells, and the
/// number of cells whose measure is exactly zero. A valid triangulation of a point
/// set covers its convex hull, so the sum equals the hull's measure.
pub fn measure_sum(node: &NodeFile, cells: &CellSet) -> (f64, usize) {
    let fact = if cells.arity == 3 { 2.0 } else { 6.0 };
    let mut sum = 0.0;
    let mut flat = 0;
    for c in cells.iter() {
        let m = cell_det(node, c).abs() / fact;
        if m == 0.0 {
            flat += 1;
        }
        sum += m;
    }
    (sum, flat)
}

/// Largest coordinate magnitude for which [`total_measure`] works in exact integer
/// arithmetic: differences stay below 2^25, a 3x3 determinant below 2^78, and a sum
/// over 2^32 cells below 2^110, all inside `i128`.
const EXACT_COORD_LIMIT: f64 = (1u64 << 24) as f64;

/// The total measure (area/volume) of a set of cells.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Total {
    /// Integer coordinates: `dim!` times the total measure, exactly (a sum of absolute
    /// determinants).
    Exact { scaled: i128, dim: usize },
    /// Otherwise: floating point, compensated (Neumaier) summation.
    Approx(f64),
}

/// Relative tolerance of [`Total::agrees`] when a side is not exact.
pub const MEASURE_RTOL: f64 = 1e-12;

impl Total {
    /// The measure as a float.
    pub fn value(&self) -> f64 {
        match *self {
            Total::Exact { scaled, dim } => scaled as f64 / if dim == 3 { 6.0 } else { 2.0 },
            Total::Approx(v) => v,
        }
    }

    /// Equal exactly (both exact) or within [`MEASURE_RTOL`] relative.
    pub fn agrees(&self, other: &Total) -> bool {
        match (self, other) {
            (Total::Exact { scaled: a, dim: da }, Total::Exact { scaled: b, dim: db }) => {
                a == b && da == db
            }
            _ => {
                let (a, b) = (self.value(), other.value());
                (a - b).abs() <= MEASURE_RTOL * a.abs().max(b.abs())
            }
        }
    }

    /// The exact total of the box [0, side]^dim (a grid's hull).
    pub fn of_cube(side: u64, dim: usize) -> Total {
        let fact = if dim == 3 { 6 } else { 2 };
        Total::Exact {
            scaled: i128::from(side).pow(dim as u32) * fact,
            dim,
        }
    }
}

impl std::fmt::Display for Total {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Total::Exact { scaled, dim } => {
                let fact = if dim == 3 { 6 } else { 2 };
                if scaled % fact == 0 {
                    write!(f, "{} (exact)", scaled / fact)
                } else {
                    write!(f, "{scaled}/{fact} (exact)")
                }
            }
            Total::Approx(v) => write!(f, "{v:.17e}"),
        }
    }
}

/// Total measure of `cells`, and the number of cells of measure exactly zero.
///
/// Exact when every coordinate is an integer of magnitude at most 2^24 (grids):
/// determinants in `i128`. Otherwise the same sum in floating point with compensated
/// summation; each determinant is then rounded (a flat cell may show a tiny nonzero
/// measure), so compare with [`Total::agrees`].
pub fn total_measure(node: &NodeFile, cells: &CellSet) -> (Total, usize) {
    let integral = node
        .coords
        .iter()
        .all(|&x| x.fract() == 0.0 && x.abs() <= EXACT_COORD_LIMIT);
    let dim = node.dim;
    let mut flat = 0;
    if integral {
        let mut scaled: i128 = 0;
        for c in cells.iter() {
            let p0 = node.point(c[0] as usize);
            let d = |v: u32| -> [i128; 3] {
                let mut r = [0; 3];
                for (k, (a, b)) in node.point(v as usize).iter().zip(p0).enumerate() {
                    r[k] = (*a as i64 - *b as i64) as i128;
                }
                r
            };
            let det = if cells.arity == 3 {
                let (a, b) = (d(c[1]), d(c[2]));
                a[0] * b[1] - a[1] * b[0]
            } else {
                let (a, b, e) = (d(c[1]), d(c[2]), d(c[3]));
                a[0] * (b[1] * e[2] - b[2] * e[1]) - a[1] * (b[0] * e[2] - b[2] * e[0])
                    + a[2] * (b[0] * e[1] - b[1] * e[0])
            };
            if det == 0 {
                flat += 1;
            }
            scaled += det.abs();
        }
        return (Total::Exact { scaled, dim }, flat);
    }
    // Neumaier's variant of Kahan summation.
    let (mut sum, mut comp) = (0.0f64, 0.0f64);
    let fact = if cells.arity == 3 { 2.0 } else { 6.0 };
    for c in cells.iter() {
        let m = cell_det(node, c).abs() / fact;
        if m == 0.0 {
            flat += 1;
        }
        let t = sum + m;
        comp += if sum.abs() >= m {
            (sum - t) + m
        } else {
            (m - t) + sum
        };
        sum = t;
    }
    (Total::Approx(sum + comp), flat)
}

/// The determinant of cell `c`'s edge vectors from its first vertex, in floating point
/// (`dim!` times its signed measure).
fn cell_det(node: &NodeFile, c: &[u32]) -> f64 {
    let p0 = node.point(c[0] as usize);
    let d = |v: u32| -> [f64; 3] {
        let mut r = [0.0; 3];
        for (k, (a, b)) in node.point(v as usize).iter().zip(p0).enumerate() {
            r[k] = a - b;
        }
        r
    };
    if c.len() == 3 {
        let (a, b) = (d(c[1]), d(c[2]));
        a[0] * b[1] - a[1] * b[0]
    } else {
        let (a, b, e) = (d(c[1]), d(c[2]), d(c[3]));
        a[0] * (b[1] * e[2] - b[2] * e[1]) - a[1] * (b[0] * e[2] - b[2] * e[0])
            + a[2] * (b[0] * e[1] - b[1] * e[0])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_finds_differences() {
        let a = CellSet::new(3, vec![[2, 1, 0, 0], [1, 2, 3, 0]]);
        let b = CellSet::new(3, vec![[0, 1, 2, 9], [1, 3, 4, 0]]);
        let d = compare(&a, &b).unwrap();
        assert_eq!((d.only_a, d.only_b), (1, 1));
        assert!(compare(&a, &a).unwrap().is_empty());
    }

    #[test]
    fn node_and_cells_round_trip() {
        let dir = std::env::temp_dir().join(format!("xtask-formats-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let coords = [0.1, 0.2, 1e-300, 3.0, -0.0, 0.30000000000000004];
        write_node(&dir.join("a.node"), 2, &coords, 0, &[]).unwrap();
        let node = read_node(&dir.join("a.node")).unwrap();
        assert_eq!(node.coords, coords);
        assert_eq!(node.first_index, 0);
        let cells = CellSet::new(3, vec![[2, 0, 1, 0]]);
        cells.write(&dir.join("a.cells")).unwrap();
        assert_eq!(fs::read_to_string(dir.join("a.cells")).unwrap(), "0 1 2\n");
        assert_eq!(read_cells(&dir.join("a.cells"), 4).unwrap(), cells);
        fs::write(dir.join("b.ele"), "# c\n1 3 0\n 1  3 1 2 # tri\n").unwrap();
        assert_eq!(read_ele(&dir.join("b.ele"), 3, 1).unwrap(), cells);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn integer_fields() {
        let mut v = Vec::new();
        assert!(int_fields(b" 1\t-2,+3  # 4 5", &mut v).is_ok());
        assert_eq!(v, [1, -2, 3]);
        assert!(int_fields(b"   # only a comment", &mut v).is_ok());
        assert!(v.is_empty());
        assert_eq!(int_fields(b"1 2.5 3", &mut v), Err("2.5".to_string()));
        assert_eq!(int_fields(b"1 - 3", &mut v), Err("-".to_string()));
        assert!(int_fields(b"12345678901234567890", &mut v).is_err());
    }

    #[test]
    fn ele_files_are_checked() {
        let dir = std::env::temp_dir().join(format!("xtask-ele-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.ele");
        // 1-based, with an attribute column and CRLF line ends.
        fs::write(&p, "2 4 1\r\n1 4 3 2 1 7\r\n2 2 3 4 5 7\r\n").unwrap();
        let cells = read_ele(&p, 4, 1).unwrap();
        let got: Vec<&[u32]> = cells.iter().collect();
        assert_eq!(got, [&[0, 1, 2, 3][..], &[1, 2, 3, 4][..]]);
        // Vertex 0 in a 1-based mesh is out of range.
        fs::write(&p, "1 4 0\n1 0 1 2 3\n").unwrap();
        assert!(read_ele(&p, 4, 1).is_err());
        // Fewer cells than the header says.
        fs::write(&p, "2 3 0\n0 0 1 2\n").unwrap();
        let err = read_ele(&p, 3, 0).unwrap_err().to_string();
        assert!(err.contains("header says 2 cells, found 1"), "{err}");
        fs::write(&p, "1 3 0\n0 0 x 2\n").unwrap();
        let err = read_ele(&p, 3, 0).unwrap_err().to_string();
        assert!(err.contains(":2: bad integer `x`"), "{err}");
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn describe_names_first_difference() {
        let a = CellSet::new(3, vec![[0, 1, 2, 0], [1, 2, 3, 0]]);
        let b = CellSet::new(3, vec![[0, 1, 3, 0], [1, 2, 3, 0]]);
        let d = compare(&a, &b).unwrap();
        assert_eq!(
            d.describe("delmesh", "CGAL"),
            "1 cells only in delmesh, 1 only in CGAL; first difference: [0, 1, 2] is in \
             delmesh, not in CGAL"
        );
        let d = compare(&b, &a).unwrap();
        assert!(d
            .describe("delmesh", "CGAL")
            .ends_with("[0, 1, 2] is in CGAL, not in delmesh"));
        assert_eq!(compare(&a, &a).unwrap().describe("x", "y"), "identical");
    }

    #[test]
    fn totals_exact_and_approximate() {
        let mut node = NodeFile {
            dim: 3,
            first_index: 0,
            coords: vec![
                0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0,
            ],
            nattr: 0,
            attrs: vec![],
        };
        // The corner tet (volume 1/6) and a flat one (4 points in z = 0).
        let cells = CellSet::new(4, vec![[0, 1, 2, 3], [0, 1, 2, 4]]);
        let (t, flat) = total_measure(&node, &cells);
        assert_eq!(t, Total::Exact { scaled: 1, dim: 3 });
        assert_eq!(flat, 1);
        assert_eq!(t.to_string(), "1/6 (exact)");
        assert!(t.agrees(&Total::Approx(1.0 / 6.0)));
        assert!(!t.agrees(&Total::Exact { scaled: 2, dim: 3 }));
        assert_eq!(Total::of_cube(2, 3).to_string(), "8 (exact)");
        // Non-integer coordinates: floating point, compared with a relative tolerance.
        node.coords[3] = 0.5;
        let (t, _) = total_measure(&node, &cells);
        assert!(matches!(t, Total::Approx(_)));
        assert!(t.agrees(&Total::Approx(1.0 / 12.0 * (1.0 + 1e-13))));
        assert!(!t.agrees(&Total::Approx(1.0 / 12.0 * (1.0 + 1e-11))));
    }

    #[test]
    fn duplicates_map_to_smallest_index() {
        let node = NodeFile {
            dim: 2,
            first_index: 0,
            coords: vec![0.0, 1.0, 2.0, 2.0, -0.0, 1.0],
            nattr: 0,
            attrs: vec![],
        };
        assert_eq!(duplicate_canonical_map(&node), Some(vec![0, 1, 0]));
    }
}
