//! TetGen / Triangle text formats: `.node` (points; read and write), `.ele` (cells; write) and
//! `.neigh` (cell neighbours; write).
//!
//! These are the formats TetGen and Triangle read and write, so delmesh can exchange points and
//! meshes with them and with the many tools that speak them. Reading is strict, because a
//! silently misread point file gives a wrong mesh: every malformed line is an error that names the
//! file, the 1-based line and what is wrong, and no input makes the reader panic or allocate
//! more than the file's size suggests.
//!
//! `.node` layout: first data line `<#points> <dimension 2|3> [<#attributes>] [<#boundary markers
//! 0|1>]` (the last two default to 0, as in Triangle), then one line per point
//! `<index> <x> <y> [<z>] [attributes...] [marker]`. `#` starts a comment anywhere on a line and
//! blank lines are skipped. Indices are consecutive from 0 or 1 (the first one decides).

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::atomic::{transaction, write_atomic};
use crate::model::{check_first_index, check_points};
use crate::text::{data_lines, last_line, parse_coord, read_text, shorten, write_f64, DataLines};
use crate::{IoError, PointSet, SimplexMesh};

const AXES: [&str; 3] = ["x", "y", "z"];

/// Reads a TetGen/Triangle `.node` file.
pub fn read_node(path: &Path) -> Result<PointSet, IoError> {
    let text = read_text(path)?;
    parse_node(&text, path)
}

/// Parses the text of a `.node` file; `file` is only used in error messages.
pub fn parse_node(text: &str, file: &Path) -> Result<PointSet, IoError> {
    let mut lines = data_lines(text).peekable();
    let (points, hline) = parse_node_section(&mut lines, text, file)?;
    if let Some((line, _)) = lines.next() {
        return Err(IoError::parse(
            file,
            line,
            format!(
                "extra data after the {} points declared in the header (line {hline})",
                points.len()
            ),
        ));
    }
    Ok(points)
}

/// Parses a `.node` header and its point lines from `lines`, leaving the iterator after the
/// last point: a whole `.node` file, or the first section of a `.poly`/`.smesh` file. Returns
/// the points and the header's line number.
pub(crate) fn parse_node_section(
    lines: &mut std::iter::Peekable<DataLines<'_>>,
    text: &str,
    file: &Path,
) -> Result<(PointSet, usize), IoError> {
    let err = |line: usize, message: String| IoError::parse(file, line, message);
    let Some((hline, header)) = lines.next() else {
        return Err(err(
            last_line(text),
            "missing header line '<#points> <dimension> <#attributes> <#boundary markers>'"
                .to_string(),
        ));
    };
    if !(2..=4).contains(&header.len()) {
        return Err(err(
            hline,
            format!(
                "expected 2 to 4 header fields (<#points> <dimension> [<#attributes>] \
                 [<#boundary markers>]), found {}",
                header.len()
            ),
        ));
    }
    let count = |i: usize, what: &str| -> Result<usize, IoError> {
        match header.get(i) {
            None => Ok(0),
            Some(tok) => tok.parse::<usize>().map_err(|_| {
                err(
                    hline,
                    format!(
                        "expected a non-negative integer for the {what}, found '{}'",
                        shorten(tok)
                    ),
                )
            }),
        }
    };
    let n = count(0, "number of points")?;
    let dim = count(1, "dimension")?;
    let n_attr = count(2, "number of attributes")?;
    let n_mark = count(3, "number of boundary markers")?;
    if dim != 2 && dim != 3 {
        return Err(err(hline, format!("dimension must be 2 or 3, found {dim}")));
    }
    if n_mark > 1 {
        return Err(err(
            hline,
            format!("number of boundary markers must be 0 or 1, found {n_mark}"),
        ));
    }
    if n_attr > text.len() {
        return Err(err(
            hline,
            format!(
                "implausible number of attributes {n_attr} for a file of {} bytes",
                text.len()
            ),
        ));
    }
    let n_fields = 1 + dim + n_attr + n_mark;

    // Never trust the header for allocation: a point line takes at least 2 bytes per field.
    let cap = n.min(text.len() / (2 * n_fields));
    let mut coords = Vec::with_capacity(cap * dim);
    let mut attr_flat = Vec::with_capacity(cap * n_attr);
    let mut markers = Vec::with_capacity(if n_mark == 1 { cap } else { 0 });
    let mut first_index = 0i64;
    let mut found = 0usize;

    while found < n {
        let Some((line, toks)) = lines.next() else {
            return Err(err(
                last_line(text),
                format!(
                    "unexpected end of file: the header (line {hline}) declares {n} points \
                     but the file has only {found}"
                ),
            ));
        };
        // Attributes and the marker the line leaves out read as 0, as Triangle reads them;
        // the index and coordinates must be there.
        if toks.len() < 1 + dim || toks.len() > n_fields {
            return Err(err(
                line,
                format!(
                    "expected {n_fields} fields, found {} (index, {dim} coordinates, \
                     {n_attr} attributes, {n_mark} boundary markers)",
                    toks.len()
                ),
            ));
        }
        let index: i64 = toks[0].parse().map_err(|_| {
            err(
                line,
                format!(
                    "point index must be an integer, found '{}'",
                    shorten(toks[0])
                ),
            )
        })?;
        if found == 0 {
            if index != 0 && index != 1 {
                return Err(err(
                    line,
                    format!("first point index must be 0 or 1, found {index}"),
                ));
            }
            first_index = index;
        } else {
            let expected = first_index + found as i64;
            if index != expected {
                return Err(err(
                    line,
                    format!("point index {index} is not consecutive: expected {expected}"),
                ));
            }
        }
        for (d, axis) in AXES.iter().enumerate().take(dim) {
            coords.push(parse_coord(toks[1 + d], axis, file, line)?);
        }
        for a in 0..n_attr {
            let Some(&tok) = toks.get(1 + dim + a) else {
                attr_flat.push(0.0);
                continue;
            };
            let value = tok.parse::<f64>().map_err(|_| {
                err(
                    line,
                    format!(
                        "non-numeric token '{}' for attribute {}",
                        shorten(tok),
                        a + 1
                    ),
                )
            })?;
            attr_flat.push(value);
        }
        if n_mark == 1 {
            let marker = match toks.get(n_fields - 1) {
                None => 0,
                Some(&tok) => tok.parse::<i32>().map_err(|_| {
                    err(
                        line,
                        format!(
                            "boundary marker must be an integer, found '{}'",
                            shorten(tok)
                        ),
                    )
                })?,
            };
            markers.push(marker);
        }
        found += 1;
    }

    let attributes = (0..n_attr)
        .map(|a| attr_flat.iter().skip(a).step_by(n_attr).copied().collect())
        .collect();
    let points = PointSet {
        dim,
        coords,
        first_index: first_index as u32,
        attributes,
        markers: (n_mark == 1).then_some(markers),
    };
    Ok((points, hline))
}

/// Writes points as a `.node` file: header `<n> <dim> 0 0`, then `<i> x y [z]` numbered from
/// `first_index` (0 or 1). Coordinates are written so they read back bit-exactly. Atomic.
///
/// Errors if `dim` is not 2 or 3, `coords.len()` is not a multiple of it, a coordinate is not
/// finite, or `first_index` is not 0 or 1.
pub fn write_node(
    path: &Path,
    dim: usize,
    coords: &[f64],
    first_index: u32,
) -> Result<(), IoError> {
    write_node_with(path, dim, coords, first_index, &NodeData::default())
}

/// What a `.node` file carries besides the coordinates: per attribute one value per point,
/// and a boundary marker per point if any (as [`PointSet`] holds them when read).
#[derive(Clone, Copy, Debug, Default)]
pub struct NodeData<'a> {
    /// Per attribute, one value per point.
    pub attributes: &'a [Vec<f64>],
    /// A boundary marker per point, if any.
    pub markers: Option<&'a [i32]>,
}

impl NodeData<'_> {
    /// Errors unless every attribute and the markers have one value per point.
    fn check(&self, path: &Path, n: usize) -> Result<(), IoError> {
        if let Some(a) = self.attributes.iter().position(|a| a.len() != n) {
            return Err(IoError::invalid(
                path,
                format!("attribute {} has not one value per point ({n})", a + 1),
            ));
        }
        if self.markers.is_some_and(|m| m.len() != n) {
            return Err(IoError::invalid(
                path,
                format!("the boundary markers are not one per point ({n})"),
            ));
        }
        Ok(())
    }
}

/// [`write_node`] with the points' attributes and boundary markers: header
/// `<n> <dim> <#attributes> <0|1>`, then `<i> x y [z] [attributes] [marker]`.
///
/// # Errors
/// As [`write_node`], or attributes or markers not one per point.
pub fn write_node_with(
    path: &Path,
    dim: usize,
    coords: &[f64],
    first_index: u32,
    data: &NodeData<'_>,
) -> Result<(), IoError> {
    check_points(path, dim, coords)?;
    check_first_index(path, first_index)?;
    data.check(path, coords.len() / dim)?;
    write_atomic(path, |w| {
        node_body(w, dim, coords, first_index, data).map_err(|e| IoError::io(path, e))
    })
}

fn node_body(
    w: &mut dyn Write,
    dim: usize,
    coords: &[f64],
    first_index: u32,
    data: &NodeData<'_>,
) -> std::io::Result<()> {
    let n = coords.len() / dim;
    writeln!(
        w,
        "{n} {dim} {} {}",
        data.attributes.len(),
        u8::from(data.markers.is_some())
    )?;
    for (i, p) in coords.chunks_exact(dim).enumerate() {
        write!(w, "{}", i as u64 + u64::from(first_index))?;
        for &c in p {
            w.write_all(b" ")?;
            write_f64(w, c)?;
        }
        for a in data.attributes {
            w.write_all(b" ")?;
            write_f64(w, a[i])?;
        }
        if let Some(m) = data.markers {
            write!(w, " {}", m[i])?;
        }
        w.write_all(b"\n")?;
    }
    Ok(())
}

/// Writes the cells of `mesh` as an `.ele` file: header `<#cells> <3|4> 0`, then
/// `<i> v0 v1 v2 [v3]`. Cells *and* vertex indices are numbered from `first_index` (0 or 1), so
/// the file matches a `.node` file written with the same `first_index`. Atomic.
pub fn write_ele(path: &Path, mesh: &SimplexMesh<'_>, first_index: u32) -> Result<(), IoError> {
    mesh.check(path)?;
    check_first_index(path, first_index)?;
    write_atomic(path, |w| {
        ele_body(w, mesh, first_index).map_err(|e| IoError::io(path, e))
    })
}

fn ele_body(w: &mut dyn Write, mesh: &SimplexMesh<'_>, first_index: u32) -> std::io::Result<()> {
    let nv = mesh.dim + 1;
    let base = u64::from(first_index);
    writeln!(w, "{} {nv} 0", mesh.n_cells())?;
    for (i, cell) in mesh.cells.chunks_exact(nv).enumerate() {
        write!(w, "{}", i as u64 + base)?;
        for &v in cell {
            write!(w, " {}", u64::from(v) + base)?;
        }
        w.write_all(b"\n")?;
    }
    Ok(())
}

/// Writes the neighbours of `mesh` as a `.neigh` file: header `<#cells> <3|4>`, then
/// `<i> n0 n1 n2 [n3]` where `nj` is the cell across the face opposite vertex `j`, numbered from
/// `first_index`, or -1 for none. Atomic.
///
/// Errors with [`IoError::InvalidInput`] if the mesh has no neighbour array.
pub fn write_neigh(path: &Path, mesh: &SimplexMesh<'_>, first_index: u32) -> Result<(), IoError> {
    mesh.check(path)?;
    check_first_index(path, first_index)?;
    let Some(neighbors) = mesh.neighbors else {
        return Err(IoError::invalid(path, "the mesh has no neighbour array"));
    };
    write_atomic(path, |w| {
        neigh_body(w, mesh.dim + 1, neighbors, first_index).map_err(|e| IoError::io(path, e))
    })
}

fn neigh_body(
    w: &mut dyn Write,
    nv: usize,
    neighbors: &[i64],
    first_index: u32,
) -> std::io::Result<()> {
    let base = i64::from(first_index);
    writeln!(w, "{} {nv}", neighbors.len() / nv)?;
    for (i, cell) in neighbors.chunks_exact(nv).enumerate() {
        write!(w, "{}", i as u64 + u64::from(first_index))?;
        for &n in cell {
            if n < 0 {
                w.write_all(b" -1")?;
            } else {
                write!(w, " {}", n + base)?;
            }
        }
        w.write_all(b"\n")?;
    }
    Ok(())
}

/// Writes `X.node`, `X.ele` and, if the mesh has neighbours, `X.neigh` beside `ele_path`
/// (`X` is `ele_path` without its `.ele` extension; any other extension is kept), all numbered
/// from `first_index`. Returns the paths written, in that order.
///
/// The mesh is checked before anything is written. Each file is written atomically, but the
/// family is not: if a later file fails, the earlier ones are already in place.
pub fn write_tetgen_family(
    ele_path: &Path,
    mesh: &SimplexMesh<'_>,
    first_index: u32,
) -> Result<Vec<PathBuf>, IoError> {
    write_tetgen_family_with(ele_path, mesh, first_index, &NodeData::default())
}

/// [`write_tetgen_family`] with the points' attributes and boundary markers in `X.node`
/// (see [`write_node_with`]).
///
/// # Errors
/// As [`write_tetgen_family`], or attributes or markers not one per point.
pub fn write_tetgen_family_with(
    ele_path: &Path,
    mesh: &SimplexMesh<'_>,
    first_index: u32,
    data: &NodeData<'_>,
) -> Result<Vec<PathBuf>, IoError> {
    mesh.check(ele_path)?;
    check_first_index(ele_path, first_index)?;
    data.check(ele_path, mesh.n_points())?;
    let base = if ele_path.extension().is_some_and(|e| e == "ele") {
        ele_path.with_extension("")
    } else {
        ele_path.to_path_buf()
    };
    let with_ext = |ext: &str| {
        let mut s = base.clone().into_os_string();
        s.push(".");
        s.push(ext);
        PathBuf::from(s)
    };
    let node_path = with_ext("node");
    let ele_path = with_ext("ele");
    let mut written = vec![node_path, ele_path];
    if mesh.neighbors.is_some() {
        written.push(with_ext("neigh"));
    }
    // Replaced together or not at all.
    transaction(|| {
        write_node_with(&written[0], mesh.dim, mesh.coords, first_index, data)?;
        write_ele(&written[1], mesh, first_index)?;
        match written.get(2) {
            Some(neigh) => write_neigh(neigh, mesh, first_index),
            None => Ok(()),
        }
    })?;
    Ok(written)
}
