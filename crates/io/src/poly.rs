//! Triangle's `.poly` format: a planar straight-line graph (points, segments with boundary
//! markers, holes, regional attributes), the input of 2D mesh generation.
//!
//! Layout (`#` comments, blank lines skipped): a `.node` section (`<#points> 2 <#attributes>
//! <#markers>` and the point lines; `0` points means they are in the sibling `.node` file),
//! then `<#segments> <#markers 0|1>` and lines `<i> <a> <b> [marker]`, then `<#holes>` and
//! lines `<i> <x> <y>`, then optionally `<#regions>` and lines `<i> <x> <y> <attribute>
//! [<max area>]`. Segment end points use the points' numbering (from 0 or 1) and are stored
//! 0-based. 3D `.poly` files (TetGen's PLCs) are read by [`crate::read_tetgen_poly`];
//! [`crate::read_poly_any`] reads either dimension.

use std::path::Path;

use crate::atomic::write_atomic;
use crate::node::{parse_node, read_node};
use crate::text::{data_lines, last_line, parse_coord, read_text, shorten, write_f64};
use crate::{IoError, PointSet};

/// A region seed of a `.poly` file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolyRegion {
    /// A point inside the region.
    pub point: [f64; 2],
    /// The regional attribute.
    pub attribute: f64,
    /// The area constraint, if any (a negative or missing value means none).
    pub max_area: Option<f64>,
}

/// The contents of a `.poly` file.
#[derive(Clone, Debug, PartialEq)]
pub struct PolyFile {
    /// The points (dimension 2).
    pub points: PointSet,
    /// Segments as 0-based point indices.
    pub segments: Vec<[u32; 2]>,
    /// One boundary marker per segment (0 when the file has none).
    pub segment_markers: Vec<i32>,
    /// Hole seeds.
    pub holes: Vec<[f64; 2]>,
    /// Region seeds.
    pub regions: Vec<PolyRegion>,
    /// The file's numbering of points and segments (0 or 1).
    pub first_index: u32,
}

/// Reads a Triangle `.poly` file.
pub fn read_poly(path: &Path) -> Result<PolyFile, IoError> {
    let text = read_text(path)?;
    parse_poly_with(&text, path, |p| read_node(&p.with_extension("node")))
}

/// Parses the text of a `.poly` file; `file` names it in messages. A file whose points are
/// in a separate `.node` file cannot be parsed from text alone: use [`read_poly`].
pub fn parse_poly(text: &str, file: &Path) -> Result<PolyFile, IoError> {
    parse_poly_with(text, file, |p| {
        Err(IoError::invalid(
            p,
            "the points are in a separate .node file; read the file with read_poly",
        ))
    })
}

/// Parses a 2D `.poly` text, reading the points from `sibling_node(file)` when its node section
/// is empty.
pub(crate) fn parse_poly_with(
    text: &str,
    file: &Path,
    sibling_node: impl Fn(&Path) -> Result<PointSet, IoError>,
) -> Result<PolyFile, IoError> {
    let err = |line: usize, message: String| IoError::parse(file, line, message);
    let lines: Vec<(usize, Vec<&str>)> = data_lines(text).collect();
    let eof = |what: &str| {
        err(
            last_line(text),
            format!("unexpected end of file: expected {what}"),
        )
    };
    let int = |tok: &str, line: usize, what: &str| -> Result<i64, IoError> {
        tok.parse::<i64>().map_err(|_| {
            err(
                line,
                format!(
                    "expected an integer for the {what}, found '{}'",
                    shorten(tok)
                ),
            )
        })
    };
    let Some((hline, header)) = lines.first() else {
        return Err(eof("the point header"));
    };
    let n = int(header[0], *hline, "number of points")?;
    if let Some(dim) = header.get(1) {
        if *dim == "3" {
            return Err(err(
                *hline,
                "3D .poly file (a TetGen PLC): read it with read_tetgen_poly or read_poly_any"
                    .into(),
            ));
        }
    }
    if n < 0 {
        return Err(err(*hline, format!("negative number of points {n}")));
    }
    let n = n as usize;
    let (points, mut next) = if n == 0 {
        (sibling_node(file)?, 1)
    } else {
        let Some(&(end_line, _)) = lines.get(n) else {
            // Let the .node parser report the short file.
            return Err(parse_node(text, file)
                .err()
                .unwrap_or_else(|| eof("points")));
        };
        let end = crate::text::end_of_line(text, end_line);
        (parse_node(&text[..end], file)?, n + 1)
    };
    if points.dim != 2 {
        return Err(err(
            *hline,
            format!("points of dimension {}; a .poly file is 2D", points.dim),
        ));
    }
    let np = points.len();
    let base = i64::from(points.first_index);

    // Segments.
    let Some((sline, sheader)) = lines.get(next) else {
        return Err(eof("the segment header '<#segments> <#markers>'"));
    };
    next += 1;
    let nseg = int(sheader[0], *sline, "number of segments")?;
    let smark = match sheader.get(1) {
        Some(t) => int(t, *sline, "number of segment markers")?,
        None => 0,
    };
    if nseg < 0 || !(0..=1).contains(&smark) || sheader.len() > 2 {
        return Err(err(
            *sline,
            "segment header must be '<#segments> <#markers 0|1>'".into(),
        ));
    }
    let mut segments = Vec::new();
    let mut segment_markers = Vec::new();
    for k in 0..nseg as usize {
        let Some((line, toks)) = lines.get(next + k) else {
            return Err(eof(&format!("{nseg} segments (found {k})")));
        };
        // A marker the line leaves out reads as 0, as Triangle reads it.
        let want = 3 + smark as usize;
        if toks.len() < 3 || toks.len() > want {
            return Err(err(
                *line,
                format!("expected {want} fields for a segment, found {}", toks.len()),
            ));
        }
        int(toks[0], *line, "segment index")?;
        let mut ends = [0u32; 2];
        for e in 0..2 {
            let v = int(toks[1 + e], *line, "segment end point")?;
            if v < base || v - base >= np as i64 {
                return Err(err(
                    *line,
                    format!(
                        "segment end point {v} does not exist (points are numbered {base} to {})",
                        base + np as i64 - 1
                    ),
                ));
            }
            ends[e] = (v - base) as u32;
        }
        segments.push(ends);
        segment_markers.push(if let (1, Some(&tok)) = (smark, toks.get(3)) {
            let m = int(tok, *line, "segment marker")?;
            // (Markers are 32-bit, as Triangle's and every writer's.)
            i32::try_from(m).map_err(|_| {
                err(
                    *line,
                    format!("segment marker {m} is out of the range of 32-bit integers"),
                )
            })?
        } else {
            0
        });
    }
    next += nseg as usize;

    // Holes.
    let Some((hl, hheader)) = lines.get(next) else {
        return Err(eof("the hole header '<#holes>'"));
    };
    next += 1;
    let nholes = int(hheader[0], *hl, "number of holes")?;
    if nholes < 0 || hheader.len() != 1 {
        return Err(err(*hl, "hole header must be '<#holes>'".into()));
    }
    let mut holes = Vec::new();
    for k in 0..nholes as usize {
        let Some((line, toks)) = lines.get(next + k) else {
            return Err(eof(&format!("{nholes} holes (found {k})")));
        };
        if toks.len() != 3 {
            return Err(err(
                *line,
                format!("expected 3 fields for a hole, found {}", toks.len()),
            ));
        }
        holes.push([
            parse_coord(toks[1], "x", file, *line)?,
            parse_coord(toks[2], "y", file, *line)?,
        ]);
    }
    next += nholes as usize;

    // Regions (optional).
    let mut regions = Vec::new();
    if let Some((rl, rheader)) = lines.get(next) {
        next += 1;
        let nreg = int(rheader[0], *rl, "number of regions")?;
        if nreg < 0 || rheader.len() != 1 {
            return Err(err(*rl, "region header must be '<#regions>'".into()));
        }
        for k in 0..nreg as usize {
            let Some((line, toks)) = lines.get(next + k) else {
                return Err(eof(&format!("{nreg} regions (found {k})")));
            };
            if !(4..=5).contains(&toks.len()) {
                return Err(err(
                    *line,
                    format!("expected 4 or 5 fields for a region, found {}", toks.len()),
                ));
            }
            let attribute = parse_coord(toks[3], "attribute", file, *line)?;
            let max_area = match toks.get(4) {
                Some(t) => {
                    let a = parse_coord(t, "max area", file, *line)?;
                    (a > 0.0).then_some(a)
                }
                None => None,
            };
            regions.push(PolyRegion {
                point: [
                    parse_coord(toks[1], "x", file, *line)?,
                    parse_coord(toks[2], "y", file, *line)?,
                ],
                attribute,
                max_area,
            });
        }
        next += nreg as usize;
    }
    if let Some((line, _)) = lines.get(next) {
        return Err(err(*line, "extra data after the regions".into()));
    }
    Ok(PolyFile {
        first_index: points.first_index,
        points,
        segments,
        segment_markers,
        holes,
        regions,
    })
}

/// Writes a `.poly` file (points with their markers, segments with markers, holes, regions),
/// numbered from `poly.first_index`. Coordinates read back bit-exactly. Atomic.
pub fn write_poly(path: &Path, poly: &PolyFile) -> Result<(), IoError> {
    if poly.points.dim != 2 || poly.segment_markers.len() != poly.segments.len() {
        return Err(IoError::invalid(
            path,
            "a .poly file needs 2D points and one marker per segment",
        ));
    }
    let np = poly.points.len();
    if let Some(s) = poly
        .segments
        .iter()
        .find(|s| s[0] as usize >= np || s[1] as usize >= np)
    {
        return Err(IoError::invalid(
            path,
            format!("segment {:?} refers to a point that does not exist", s),
        ));
    }
    let base = u64::from(poly.first_index);
    write_atomic(path, |w| {
        (|| -> std::io::Result<()> {
            let markers = poly.points.markers.as_ref();
            writeln!(w, "{np} 2 0 {}", u8::from(markers.is_some()))?;
            for i in 0..np {
                let p = poly.points.point2(i);
                write!(w, "{} ", i as u64 + base)?;
                write_f64(w, p[0])?;
                w.write_all(b" ")?;
                write_f64(w, p[1])?;
                if let Some(m) = markers {
                    write!(w, " {}", m[i])?;
                }
                w.write_all(b"\n")?;
            }
            writeln!(w, "{} 1", poly.segments.len())?;
            for (k, (s, m)) in poly.segments.iter().zip(&poly.segment_markers).enumerate() {
                writeln!(
                    w,
                    "{} {} {} {m}",
                    k as u64 + base,
                    u64::from(s[0]) + base,
                    u64::from(s[1]) + base
                )?;
            }
            writeln!(w, "{}", poly.holes.len())?;
            for (k, h) in poly.holes.iter().enumerate() {
                write!(w, "{} ", k as u64 + base)?;
                write_f64(w, h[0])?;
                w.write_all(b" ")?;
                write_f64(w, h[1])?;
                w.write_all(b"\n")?;
            }
            if !poly.regions.is_empty() {
                writeln!(w, "{}", poly.regions.len())?;
                for (k, r) in poly.regions.iter().enumerate() {
                    write!(w, "{} ", k as u64 + base)?;
                    write_f64(w, r.point[0])?;
                    w.write_all(b" ")?;
                    write_f64(w, r.point[1])?;
                    w.write_all(b" ")?;
                    write_f64(w, r.attribute)?;
                    w.write_all(b" ")?;
                    write_f64(w, r.max_area.unwrap_or(-1.0))?;
                    w.write_all(b"\n")?;
                }
            }
            Ok(())
        })()
        .map_err(|e| IoError::io(path, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = "# a square with a hole\n\
        8 2 0 1\n1 0 0 1\n2 4 0 1\n3 4 4 1\n4 0 4 1\n5 1 1 2\n6 3 1 2\n7 3 3 2\n8 1 3 2\n\
        8 1\n1 1 2 5\n2 2 3 5\n3 3 4 5\n4 4 1 5\n5 5 8 6\n6 8 7 6\n7 7 6 6\n8 6 5 6\n\
        1\n1 2 2\n1\n1 0.5 0.5 7 -1\n";

    #[test]
    fn reads_a_square_with_a_hole_and_round_trips() {
        let p = parse_poly(SQUARE, Path::new("sq.poly")).unwrap();
        assert_eq!(p.first_index, 1);
        assert_eq!(p.points.len(), 8);
        assert_eq!(p.segments[0], [0, 1]);
        assert_eq!(p.segments[4], [4, 7]);
        assert_eq!(p.segment_markers[4], 6);
        assert_eq!(p.holes, vec![[2.0, 2.0]]);
        assert_eq!(p.regions[0].attribute, 7.0);
        assert_eq!(p.regions[0].max_area, None);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.poly");
        write_poly(&path, &p).unwrap();
        assert_eq!(read_poly(&path).unwrap(), p);
    }

    #[test]
    fn old_mac_and_windows_line_ends_read_the_same() {
        let p = parse_poly(SQUARE, Path::new("sq.poly")).unwrap();
        for ends in ["\r", "\r\n"] {
            let text = SQUARE.replace('\n', ends);
            assert_eq!(
                parse_poly(&text, Path::new("sq.poly")).unwrap(),
                p,
                "{ends:?}"
            );
            // Line numbers count the same lines.
            let bad = text.replace("5 5 8 6", "5 5 9 6");
            let e = parse_poly(&bad, Path::new("sq.poly")).unwrap_err();
            assert!(e.to_string().starts_with("sq.poly:16: "), "{e}");
        }
    }

    #[test]
    fn errors_name_the_line() {
        let bad = SQUARE.replace("5 5 8 6", "5 5 9 6");
        let e = parse_poly(&bad, Path::new("sq.poly")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "sq.poly:16: segment end point 9 does not exist (points are numbered 1 to 8)"
        );
        let e = parse_poly("4 2 0 0\n0 0 0\n1 1 0\n", Path::new("s.poly")).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("s.poly:3: unexpected end of file"),
            "{e}"
        );
        let e = parse_poly("3 3 0 0\n", Path::new("t.poly")).unwrap_err();
        assert!(e.to_string().contains("3D .poly"), "{e}");
        let cut = &SQUARE[..SQUARE.find("1\n1 2 2").unwrap()];
        let e = parse_poly(cut, Path::new("c.poly")).unwrap_err();
        assert!(e.to_string().contains("hole header"), "{e}");
        let e = parse_poly(&SQUARE.replace("1 1 2 5", "1 1"), Path::new("d.poly")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "d.poly:12: expected 4 fields for a segment, found 2"
        );
        // A marker the line leaves out reads as 0, as Triangle reads it.
        let p = parse_poly(&SQUARE.replace("1 1 2 5", "1 1 2"), Path::new("d.poly")).unwrap();
        assert_eq!(p.segment_markers[0], 0);
        let e = parse_poly(
            &SQUARE.replace("5 5 8 6", "5 5 8 2147483648"),
            Path::new("m.poly"),
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "m.poly:16: segment marker 2147483648 is out of the range of 32-bit integers"
        );
        for garbage in [
            "",
            "x",
            "3 2 0 0\n0 a b\n",
            "\u{0}\u{1}",
            "1 2 0 0\n0 0 0\n-1 0\n",
        ] {
            assert!(parse_poly(garbage, Path::new("g.poly")).is_err());
        }
    }
}
