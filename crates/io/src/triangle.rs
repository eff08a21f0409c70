//! Triangle's output family with boundary markers and region attributes: `X.node` (points
//! and markers), `X.ele` (triangles and their region attribute), `X.edge` (boundary edges and
//! markers), and the reader of such a `.node/.ele` pair (a background mesh or a previous mesh
//! whose points carry attributes).

use std::path::{Path, PathBuf};

use crate::atomic::{transaction, write_atomic};
use crate::model::{check_first_index, check_points};
use crate::node::read_node;
use crate::text::{data_lines, last_line, read_text, shorten, write_f64};
use crate::vtu::FieldMesh;
use crate::IoError;

/// A 2D triangle mesh with markers and attributes, as written by [`write_triangle_family`].
#[derive(Clone, Copy, Debug)]
pub struct TriangleMeshOut<'a> {
    /// `2 * n_points` coordinates.
    pub coords: &'a [f64],
    /// `3 * n_triangles` 0-based point indices, counter-clockwise.
    pub triangles: &'a [u32],
    /// A boundary marker per point, if any.
    pub point_markers: Option<&'a [i32]>,
    /// A region attribute per triangle, if any.
    pub cell_attributes: Option<&'a [f64]>,
    /// Boundary edges (0-based point indices).
    pub edges: &'a [[u32; 2]],
    /// A marker per boundary edge.
    pub edge_markers: &'a [i32],
}

impl TriangleMeshOut<'_> {
    /// Checks that the arrays are consistent; `file` is the destination named in errors.
    pub(crate) fn check(&self, file: &Path) -> Result<(), IoError> {
        check_points(file, 2, self.coords)?;
        let np = self.coords.len() / 2;
        let nt = self.triangles.len() / 3;
        let bad = |m: String| Err(IoError::invalid(file, m));
        if self.triangles.len() % 3 != 0 {
            return bad("triangle array length is not a multiple of 3".into());
        }
        if let Some(v) = self.triangles.iter().find(|&&v| v as usize >= np) {
            return bad(format!(
                "a triangle refers to point {v} but there are {np} points"
            ));
        }
        if self.point_markers.is_some_and(|m| m.len() != np) {
            return bad("one point marker per point is needed".into());
        }
        if let Some(a) = self.cell_attributes {
            if a.len() != nt {
                return bad("one attribute per triangle is needed".into());
            }
            if let Some(k) = a.iter().position(|x| !x.is_finite()) {
                return bad(format!("the attribute of triangle {k} is not finite"));
            }
        }
        if self.edges.len() != self.edge_markers.len() {
            return bad("one marker per edge is needed".into());
        }
        if let Some(e) = self
            .edges
            .iter()
            .find(|e| e[0] as usize >= np || e[1] as usize >= np)
        {
            return bad(format!("edge {e:?} refers to a point that does not exist"));
        }
        Ok(())
    }
}

/// Writes `X.node`, `X.ele` and `X.edge` beside `ele_path` (`X` is the path without its `.ele`
/// extension), numbered from `first_index` (0 or 1). Returns the paths written. The three
/// files are replaced together or not at all (a [`crate::transaction`]); everything is checked
/// before the first is written.
pub fn write_triangle_family(
    ele_path: &Path,
    mesh: &TriangleMeshOut<'_>,
    first_index: u32,
) -> Result<Vec<PathBuf>, IoError> {
    mesh.check(ele_path)?;
    check_first_index(ele_path, first_index)?;
    let stem = if ele_path.extension().is_some_and(|e| e == "ele") {
        ele_path.with_extension("")
    } else {
        ele_path.to_path_buf()
    };
    let with_ext = |ext: &str| {
        let mut s = stem.clone().into_os_string();
        s.push(".");
        s.push(ext);
        PathBuf::from(s)
    };
    let base = u64::from(first_index);
    let (node, ele, edge) = (with_ext("node"), with_ext("ele"), with_ext("edge"));
    transaction(|| write_files(mesh, base, [&node, &ele, &edge]))?;
    Ok(vec![node, ele, edge])
}

/// The files of [`write_triangle_family`]: `.node`, `.ele`, `.edge`, numbered from `base`.
fn write_files(
    mesh: &TriangleMeshOut<'_>,
    base: u64,
    [node, ele, edge]: [&Path; 3],
) -> Result<(), IoError> {
    let (np, nt) = (mesh.coords.len() / 2, mesh.triangles.len() / 3);
    write_atomic(node, |w| {
        (|| -> std::io::Result<()> {
            writeln!(w, "{np} 2 0 {}", u8::from(mesh.point_markers.is_some()))?;
            for (i, p) in mesh.coords.chunks_exact(2).enumerate() {
                write!(w, "{} ", i as u64 + base)?;
                write_f64(w, p[0])?;
                w.write_all(b" ")?;
                write_f64(w, p[1])?;
                if let Some(m) = mesh.point_markers {
                    write!(w, " {}", m[i])?;
                }
                w.write_all(b"\n")?;
            }
            Ok(())
        })()
        .map_err(|e| IoError::io(node, e))
    })?;
    write_atomic(ele, |w| {
        (|| -> std::io::Result<()> {
            writeln!(w, "{nt} 3 {}", u8::from(mesh.cell_attributes.is_some()))?;
            for (k, t) in mesh.triangles.chunks_exact(3).enumerate() {
                write!(
                    w,
                    "{} {} {} {}",
                    k as u64 + base,
                    u64::from(t[0]) + base,
                    u64::from(t[1]) + base,
                    u64::from(t[2]) + base
                )?;
                if let Some(a) = mesh.cell_attributes {
                    w.write_all(b" ")?;
                    write_f64(w, a[k])?;
                }
                w.write_all(b"\n")?;
            }
            Ok(())
        })()
        .map_err(|e| IoError::io(ele, e))
    })?;
    write_atomic(edge, |w| {
        (|| -> std::io::Result<()> {
            writeln!(w, "{} 1", mesh.edges.len())?;
            for (k, (e, m)) in mesh.edges.iter().zip(mesh.edge_markers).enumerate() {
                writeln!(
                    w,
                    "{} {} {} {m}",
                    k as u64 + base,
                    u64::from(e[0]) + base,
                    u64::from(e[1]) + base
                )?;
            }
            Ok(())
        })()
        .map_err(|e| IoError::io(edge, e))
    })
}

/// Reads `X.node` and `X.ele` (given the `.ele` path) as a [`FieldMesh`]. The points'
/// attributes become point fields: a single attribute is named `spacing` (the background-mesh
/// convention), several are named `attribute0`, `attribute1`, ... Extra values on `.ele` lines
/// (region attributes) are ignored.
pub fn read_triangle_mesh(ele_path: &Path) -> Result<FieldMesh, IoError> {
    let node_path = ele_path.with_extension("node");
    let points = read_node(&node_path)?;
    let text = read_text(ele_path)?;
    let err = |line: usize, m: String| IoError::parse(ele_path, line, m);
    let mut lines = data_lines(&text);
    let Some((hline, header)) = lines.next() else {
        return Err(err(
            last_line(&text),
            "missing header '<#triangles> 3 <#attributes>'".into(),
        ));
    };
    let n: usize = header[0].parse().map_err(|_| {
        err(
            hline,
            format!("bad number of triangles '{}'", shorten(header[0])),
        )
    })?;
    if header.get(1).is_some_and(|&k| k != "3") {
        return Err(err(hline, "only 3-node triangles are supported".into()));
    }
    let base = i64::from(points.first_index);
    let np = points.len() as i64;
    let mut cells = Vec::with_capacity(n.min(text.len() / 8) * 3);
    let mut found = 0;
    for (line, toks) in lines {
        if found == n {
            return Err(err(line, format!("extra data after the {n} triangles")));
        }
        if toks.len() < 4 {
            return Err(err(
                line,
                format!("expected at least 4 fields, found {}", toks.len()),
            ));
        }
        for t in &toks[1..4] {
            let v: i64 = t
                .parse()
                .map_err(|_| err(line, format!("bad node index '{}'", shorten(t))))?;
            if v < base || v - base >= np {
                return Err(err(
                    line,
                    format!("node {v} does not exist in {}", node_path.display()),
                ));
            }
            cells.push((v - base) as u32);
        }
        found += 1;
    }
    if found < n {
        return Err(err(
            last_line(&text),
            format!("unexpected end of file: {n} triangles declared, {found} found"),
        ));
    }
    let point_fields = if points.attributes.len() == 1 {
        vec![("spacing".to_string(), points.attributes[0].clone())]
    } else {
        points
            .attributes
            .iter()
            .enumerate()
            .map(|(k, a)| (format!("attribute{k}"), a.clone()))
            .collect()
    };
    Ok(FieldMesh {
        dim: points.dim,
        coords: points.coords,
        cells,
        point_fields,
        points_file: (node_path, points.first_index),
    })
}
