//! Object File Format (`.off`, from Geomview): points and polygons, read and written.
//!
//! OFF is the simplest polygon-surface format and the one geometry-processing tools (CGAL,
//! Meshlab, libigl) exchange most readily, so it is a convenient way to hand delmesh a closed
//! surface and to dump one for inspection.
//!
//! Layout, as Geomview documents it: a header keyword `OFF`, optionally prefixed by `ST`, `C`
//! and `N` (`COFF`, `NOFF`, `STCNOFF`: vertices carry texture coordinates, colours, normals),
//! then `<#vertices> <#faces> [<#edges>]` (on the keyword's line or the next), then one vertex
//! per line, `x y z` followed by anything (normals, colours: ignored), then one face per line,
//! `<n> <v1> ... <vn>` with 0-based indices followed by an optional colour (ignored). `#`
//! starts a comment. The keyword may be omitted (the file then starts with the counts).
//!
//! Assumptions: vertices and faces are one per line (Geomview also allows free format; no
//! tool we know writes it); `4OFF`/`nOFF` (4D and n-D points) and `OFF BINARY` are refused.
//! Faces have no markers (they read as 0).

use std::path::Path;

use crate::atomic::write_atomic;
use crate::surface::{check_polygon_size, SurfaceFacet, SurfaceFile};
use crate::text::{
    parse_count, parse_int, parse_point3, point_ref, read_text, shorten, write_f64, LineCursor,
};
use crate::IoError;

/// Reads an `.off` file.
pub fn read_off(path: &Path) -> Result<SurfaceFile, IoError> {
    let text = read_text(path)?;
    parse_off(&text, path)
}

/// Parses the text of an `.off` file; `file` is only used in error messages.
pub fn parse_off(text: &str, file: &Path) -> Result<SurfaceFile, IoError> {
    let err = |line: usize, message: String| IoError::parse(file, line, message);
    let mut cur = LineCursor::new(text, file);
    let (hline, header) = cur.next("the OFF header")?;
    let key = header[0];
    let counts_on_header = if let Some(prefix) = key
        .len()
        .checked_sub(3)
        .filter(|&i| key.is_char_boundary(i) && key[i..].eq_ignore_ascii_case("OFF"))
        .map(|i| &key[..i])
    {
        if prefix.contains(['4', 'n']) {
            return Err(err(
                hline,
                format!("'{key}': only 3D OFF files are supported"),
            ));
        }
        if !prefix
            .chars()
            .all(|c| "STCN".contains(c.to_ascii_uppercase()))
        {
            return Err(err(
                hline,
                format!("unknown OFF header keyword '{}'", shorten(key)),
            ));
        }
        if header
            .get(1)
            .is_some_and(|t| t.eq_ignore_ascii_case("binary"))
        {
            return Err(err(
                hline,
                "binary OFF is not supported; save the file as ASCII OFF".into(),
            ));
        }
        header[1..].to_vec()
    } else if key.parse::<usize>().is_ok() {
        header.clone()
    } else {
        return Err(err(
            hline,
            format!(
                "expected an OFF header ('OFF', 'COFF', 'NOFF', ...), found '{}'",
                shorten(key)
            ),
        ));
    };
    let (cline, counts) = if counts_on_header.is_empty() {
        cur.next("the counts '<#vertices> <#faces> <#edges>'")?
    } else {
        (hline, counts_on_header)
    };
    if !(2..=3).contains(&counts.len()) {
        return Err(err(
            cline,
            format!(
                "expected the counts '<#vertices> <#faces> [<#edges>]', found {} fields",
                counts.len()
            ),
        ));
    }
    let nv = parse_count(counts[0], "number of vertices", file, cline)?;
    let nf = parse_count(counts[1], "number of faces", file, cline)?;
    if let Some(t) = counts.get(2) {
        parse_count(t, "number of edges", file, cline)?;
    }

    let mut points = Vec::with_capacity(nv.min(text.len() / 6));
    for k in 0..nv {
        let (line, toks) = cur.next(format_args!("{nv} vertices (found {k})"))?;
        if toks.len() < 3 {
            return Err(err(
                line,
                format!(
                    "expected at least 3 fields for a vertex, found {}",
                    toks.len()
                ),
            ));
        }
        points.push(parse_point3(&toks, file, line)?);
    }
    let mut facets = Vec::with_capacity(nf.min(text.len() / 8));
    for k in 0..nf {
        let (line, toks) = cur.next(format_args!("{nf} faces (found {k})"))?;
        let n = parse_count(toks[0], "number of face vertices", file, line)?;
        check_polygon_size(n, "face", file, line)?;
        if n >= toks.len() {
            return Err(err(
                line,
                format!(
                    "face of {n} vertices needs {} fields, found {}",
                    n.saturating_add(1),
                    toks.len()
                ),
            ));
        }
        let polygon = toks[1..=n]
            .iter()
            .map(|t| point_ref(parse_int(t, "face vertex", file, line)?, 0, nv, file, line))
            .collect::<Result<Vec<u32>, IoError>>()?;
        facets.push(SurfaceFacet {
            polygons: vec![polygon],
            holes: Vec::new(),
            marker: 0,
            line,
        });
    }
    if let Some((line, _)) = cur.next_opt() {
        return Err(err(
            line,
            format!("extra data after the {nf} faces declared on line {cline}"),
        ));
    }
    Ok(SurfaceFile {
        points,
        facets,
        ..SurfaceFile::default()
    })
}

/// Writes points and polygons (each at least 3 0-based point indices; `[u32; 3]` triangles or
/// `Vec<u32>` polygons) as an `.off` file. Coordinates read back bit-exactly. Atomic.
pub fn write_off<P: AsRef<[u32]>>(
    path: &Path,
    points: &[[f64; 3]],
    faces: &[P],
) -> Result<(), IoError> {
    let np = points.len();
    if let Some(i) = points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(IoError::invalid(
            path,
            format!("point {i} has a non-finite coordinate"),
        ));
    }
    for (k, f) in faces.iter().enumerate() {
        let f = f.as_ref();
        if f.len() < 3 {
            return Err(IoError::invalid(
                path,
                format!("face {k} has {} vertices, at least 3 are needed", f.len()),
            ));
        }
        if let Some(&v) = f.iter().find(|&&v| v as usize >= np) {
            return Err(IoError::invalid(
                path,
                format!("face {k} refers to point {v} but there are {np} points"),
            ));
        }
    }
    write_atomic(path, |w| {
        (|| -> std::io::Result<()> {
            writeln!(w, "OFF\n{np} {} 0", faces.len())?;
            for p in points {
                write_f64(w, p[0])?;
                for &c in &p[1..] {
                    w.write_all(b" ")?;
                    write_f64(w, c)?;
                }
                w.write_all(b"\n")?;
            }
            for f in faces {
                let f = f.as_ref();
                write!(w, "{}", f.len())?;
                for v in f {
                    write!(w, " {v}")?;
                }
                w.write_all(b"\n")?;
            }
            Ok(())
        })()
        .map_err(|e| IoError::io(path, e))
    })
}
