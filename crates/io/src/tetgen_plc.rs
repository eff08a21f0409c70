//! TetGen's piecewise linear complexes: `.smesh` and 3D `.poly` files (read and write), the
//! input of TetGen and the most complete of the surface formats (polygonal facets with holes,
//! markers, hole and region seeds).
//!
//! Both files have four parts (`#` comments and blank lines skipped, as in `.node` files):
//! 1. a `.node` section: `<#points> 3 <#attributes> <#markers 0|1>` and the point lines; a
//!    header with 0 points (`0 3 0 0`) means the points are in the `.node` file beside this one
//!    (`X.smesh` → `X.node`). Point attributes are read but not kept.
//! 2. facets, `<#facets> <#markers 0|1>` then
//!    - `.smesh`: one line per facet, `<#corners> <c1> ... <cn> [marker]`;
//!    - `.poly`: per facet a header `<#polygons> [<#holes>] [marker]` (the hole count defaults
//!      to 0; the marker is read only when the facet header says there are markers), then
//!      one line per polygon `<#corners> <c1> ... <cn>`, then one line per facet hole
//!      `<i> <x> <y> <z>`. A polygon of 1 or 2 corners is a point or segment in the facet.
//! 3. holes, `<#holes>` then `<i> <x> <y> <z>`;
//! 4. regions (optional), `<#regions>` then `<i> <x> <y> <z> <attribute> [<max volume>]`
//!    (TetGen's "region number" is the attribute, its "region attribute" the volume
//!    constraint; a constraint `<= 0` means none).
//!
//! Corners use the points' numbering (from 0 or 1, set by the first point) and are stored
//! 0-based. Triangle's 2D `.poly` files look the same in part 1 except for the dimension:
//! [`read_poly_any`] reads either kind.

use std::io::Write;
use std::path::Path;

use crate::atomic::write_atomic;
use crate::model::check_first_index;
use crate::node::{parse_node_section, read_node};
use crate::poly::{parse_poly, parse_poly_with};
use crate::surface::{SurfaceFacet, SurfaceFile, SurfaceRegion};
use crate::text::{
    parse_coord, parse_count, parse_int, parse_point3, point_ref, read_text, write_f64, LineCursor,
};
use crate::{IoError, PointSet, PolyFile};

/// A `.poly` file of either dimension: Triangle's 2D planar graph or TetGen's 3D PLC.
#[derive(Clone, Debug, PartialEq)]
pub enum AnyPoly {
    /// A 2D `.poly` file (dimension 2 in its node section).
    Triangle(PolyFile),
    /// A 3D `.poly` file (dimension 3 in its node section).
    TetGen(SurfaceFile),
}

/// Which facet section a TetGen file has.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Smesh,
    Poly,
}

/// Reads a TetGen `.smesh` file (and the `.node` file beside it if its node section is empty).
pub fn read_smesh(path: &Path) -> Result<SurfaceFile, IoError> {
    let text = read_text(path)?;
    parse_plc(&text, path, Kind::Smesh, read_sibling_node)
}

/// Parses the text of a `.smesh` file; `file` names it in messages. A file whose points are in
/// a separate `.node` file cannot be parsed from text alone: use [`read_smesh`].
pub fn parse_smesh(text: &str, file: &Path) -> Result<SurfaceFile, IoError> {
    parse_plc(text, file, Kind::Smesh, no_sibling)
}

/// Reads a TetGen 3D `.poly` file (and the `.node` file beside it if its node section is
/// empty). A 2D file is an error naming [`crate::read_poly`]; [`read_poly_any`] reads both.
pub fn read_tetgen_poly(path: &Path) -> Result<SurfaceFile, IoError> {
    let text = read_text(path)?;
    parse_plc(&text, path, Kind::Poly, read_sibling_node)
}

/// Parses the text of a TetGen 3D `.poly` file; `file` names it in messages.
pub fn parse_tetgen_poly(text: &str, file: &Path) -> Result<SurfaceFile, IoError> {
    parse_plc(text, file, Kind::Poly, no_sibling)
}

/// Reads a `.poly` file of either dimension, deciding by the dimension in its node section
/// header (`<#points> <dimension> ...`): 3 is TetGen's 3D PLC, anything else is read as
/// Triangle's 2D planar graph.
pub fn read_poly_any(path: &Path) -> Result<AnyPoly, IoError> {
    let text = read_text(path)?;
    if is_3d(&text) {
        parse_plc(&text, path, Kind::Poly, read_sibling_node).map(AnyPoly::TetGen)
    } else {
        parse_poly_with(&text, path, read_sibling_node).map(AnyPoly::Triangle)
    }
}

/// Parses the text of a `.poly` file of either dimension (see [`read_poly_any`]).
pub fn parse_poly_any(text: &str, file: &Path) -> Result<AnyPoly, IoError> {
    if is_3d(text) {
        parse_tetgen_poly(text, file).map(AnyPoly::TetGen)
    } else {
        parse_poly(text, file).map(AnyPoly::Triangle)
    }
}

fn is_3d(text: &str) -> bool {
    crate::text::data_lines(text)
        .next()
        .is_some_and(|(_, toks)| toks.get(1) == Some(&"3"))
}

fn read_sibling_node(file: &Path) -> Result<PointSet, IoError> {
    read_node(&file.with_extension("node"))
}

fn no_sibling(file: &Path) -> Result<PointSet, IoError> {
    Err(IoError::invalid(
        file,
        "the points are in a separate .node file; read the file from disk, not from text",
    ))
}

fn parse_plc(
    text: &str,
    file: &Path,
    kind: Kind,
    sibling_node: impl Fn(&Path) -> Result<PointSet, IoError>,
) -> Result<SurfaceFile, IoError> {
    let err = |line: usize, message: String| IoError::parse(file, line, message);
    let mut cur = LineCursor::new(text, file);

    // Part 1: points.
    let Some((hline, header)) = cur.lines().peek().cloned() else {
        return Err(cur.eof("the point header '<#points> 3 <#attributes> <#markers>'"));
    };
    let n = parse_count(header[0], "number of points", file, hline)?;
    let points = if n == 0 {
        cur.next_opt();
        if header.get(1).is_some_and(|&d| d != "3") {
            return Err(err(
                hline,
                format!("dimension must be 3, found '{}'", header[1]),
            ));
        }
        sibling_node(file)?
    } else {
        parse_node_section(cur.lines(), text, file)?.0
    };
    if points.dim != 3 {
        return Err(err(
            hline,
            format!(
                "points of dimension {}; a TetGen PLC is 3D (read 2D .poly files with read_poly)",
                points.dim
            ),
        ));
    }
    let np = points.len();
    let base = i64::from(points.first_index);
    let corner = |tok: &str, line: usize| -> Result<u32, IoError> {
        point_ref(parse_int(tok, "corner", file, line)?, base, np, file, line)
    };
    let polygon = |toks: &[&str], line: usize, what: &str| -> Result<Vec<u32>, IoError> {
        let nc = parse_count(toks[0], "number of corners", file, line)?;
        if nc == 0 {
            return Err(err(line, format!("{what} has no corners")));
        }
        if nc >= toks.len() {
            return Err(err(
                line,
                format!(
                    "{what} of {nc} corners needs {} fields, found {}",
                    nc.saturating_add(1),
                    toks.len()
                ),
            ));
        }
        toks[1..=nc].iter().map(|t| corner(t, line)).collect()
    };

    // Part 2: facets.
    let (fline, fh) = cur.next("the facet header '<#facets> <#markers 0|1>'")?;
    let n_facets = parse_count(fh[0], "number of facets", file, fline)?;
    let fmark = match fh.get(1) {
        Some(t) => parse_count(t, "number of facet markers", file, fline)?,
        None => 0,
    };
    if fmark > 1 || fh.len() > 2 {
        return Err(err(
            fline,
            "facet header must be '<#facets> <#markers 0|1>'".into(),
        ));
    }
    let mut facets = Vec::with_capacity(n_facets.min(text.len() / 8));
    for k in 0..n_facets {
        let (line, toks) = cur.next(format_args!("{n_facets} facets (found {k})"))?;
        let facet = match kind {
            Kind::Smesh => {
                let poly = polygon(&toks, line, "facet")?;
                let want = 1 + poly.len() + fmark;
                if toks.len() != want {
                    return Err(err(
                        line,
                        format!(
                            "expected {want} fields for a facet of {} corners{}, found {}",
                            poly.len(),
                            if fmark == 1 { " and a marker" } else { "" },
                            toks.len()
                        ),
                    ));
                }
                let marker = if fmark == 1 {
                    parse_int(toks[want - 1], "facet marker", file, line)?
                } else {
                    0
                };
                SurfaceFacet {
                    polygons: vec![poly],
                    holes: Vec::new(),
                    marker,
                    line,
                }
            }
            Kind::Poly => {
                if toks.len() > 2 + fmark {
                    return Err(err(
                        line,
                        format!(
                            "expected at most {} fields for a facet header '<#polygons> \
                             [<#holes>]{}', found {}",
                            2 + fmark,
                            if fmark == 1 { " [<marker>]" } else { "" },
                            toks.len()
                        ),
                    ));
                }
                let n_poly = parse_count(toks[0], "number of polygons", file, line)?;
                if n_poly == 0 {
                    return Err(err(line, "a facet needs at least one polygon".into()));
                }
                let n_holes = match toks.get(1) {
                    Some(t) => parse_count(t, "number of facet holes", file, line)?,
                    None => 0,
                };
                let marker = match toks.get(2) {
                    Some(t) => parse_int(t, "facet marker", file, line)?,
                    None => 0,
                };
                let mut polygons = Vec::with_capacity(n_poly.min(text.len() / 4));
                for p in 0..n_poly {
                    let (pl, pt) = cur.next(format_args!(
                        "polygon {} of {n_poly} of the facet on line {line}",
                        p + 1
                    ))?;
                    let poly = polygon(&pt, pl, "polygon")?;
                    if pt.len() != 1 + poly.len() {
                        return Err(err(
                            pl,
                            format!(
                                "expected {} fields for a polygon of {} corners, found {}",
                                1 + poly.len(),
                                poly.len(),
                                pt.len()
                            ),
                        ));
                    }
                    polygons.push(poly);
                }
                let mut holes = Vec::with_capacity(n_holes.min(text.len() / 8));
                for h in 0..n_holes {
                    let (hl, ht) = cur.next(format_args!(
                        "hole {} of {n_holes} of the facet on line {line}",
                        h + 1
                    ))?;
                    holes.push(seed_point(&ht, hl, file, "facet hole")?);
                }
                SurfaceFacet {
                    polygons,
                    holes,
                    marker,
                    line,
                }
            }
        };
        facets.push(facet);
    }

    // Part 3: holes.
    let (hline, hh) = cur.next("the hole header '<#holes>'")?;
    if hh.len() != 1 {
        return Err(err(hline, "hole header must be '<#holes>'".into()));
    }
    let n_holes = parse_count(hh[0], "number of holes", file, hline)?;
    let mut holes = Vec::with_capacity(n_holes.min(text.len() / 8));
    for k in 0..n_holes {
        let (line, toks) = cur.next(format_args!("{n_holes} holes (found {k})"))?;
        holes.push(seed_point(&toks, line, file, "hole")?);
    }

    // Part 4: regions (optional).
    let mut regions = Vec::new();
    if let Some((rline, rh)) = cur.next_opt() {
        if rh.len() != 1 {
            return Err(err(rline, "region header must be '<#regions>'".into()));
        }
        let n_regions = parse_count(rh[0], "number of regions", file, rline)?;
        for k in 0..n_regions {
            let (line, toks) = cur.next(format_args!("{n_regions} regions (found {k})"))?;
            if !(5..=6).contains(&toks.len()) {
                return Err(err(
                    line,
                    format!(
                        "expected 5 or 6 fields for a region '<i> <x> <y> <z> <attribute> \
                         [<max volume>]', found {}",
                        toks.len()
                    ),
                ));
            }
            let point = parse_point3(&toks[1..4], file, line)?;
            let attribute = parse_coord(toks[4], "attribute", file, line)?;
            let max_volume = match toks.get(5) {
                Some(t) => Some(parse_coord(t, "max volume", file, line)?).filter(|&v| v > 0.0),
                None => None,
            };
            regions.push(SurfaceRegion {
                point,
                attribute,
                max_volume,
            });
        }
    }
    if let Some((line, _)) = cur.next_opt() {
        return Err(err(line, "extra data after the regions".into()));
    }

    Ok(SurfaceFile {
        points: points
            .coords
            .chunks_exact(3)
            .map(|p| [p[0], p[1], p[2]])
            .collect(),
        point_markers: points.markers,
        facets,
        holes,
        regions,
        first_index: points.first_index,
        ..SurfaceFile::default()
    })
}

/// A hole or facet-hole line `<i> <x> <y> <z>`.
fn seed_point(toks: &[&str], line: usize, file: &Path, what: &str) -> Result<[f64; 3], IoError> {
    if toks.len() != 4 {
        return Err(IoError::parse(
            file,
            line,
            format!(
                "expected 4 fields for a {what} '<i> <x> <y> <z>', found {}",
                toks.len()
            ),
        ));
    }
    parse_point3(&toks[1..], file, line)
}

/// Writes a TetGen `.smesh` file: the points (with their markers, if any), one facet line per
/// facet with its marker, the holes and, if any, the regions, numbered from
/// `surface.first_index` (0 or 1). Coordinates read back bit-exactly. Atomic.
///
/// Every facet must be a single polygon without holes (that is what `.smesh` can hold; use
/// [`write_tetgen_poly`] otherwise). Tetrahedra and marker names are not written.
pub fn write_smesh(path: &Path, surface: &SurfaceFile) -> Result<(), IoError> {
    check_plc(path, surface)?;
    if let Some((k, _)) = surface
        .facets
        .iter()
        .enumerate()
        .find(|(_, f)| f.polygons.len() != 1 || !f.holes.is_empty())
    {
        return Err(IoError::invalid(
            path,
            format!(
                "facet {k} has several polygons or holes, which .smesh cannot hold; write a \
                 .poly file"
            ),
        ));
    }
    write_atomic(path, |w| {
        write_plc(w, surface, Kind::Smesh).map_err(|e| IoError::io(path, e))
    })
}

/// Writes a TetGen 3D `.poly` file: points with markers, facets with their polygons, holes and
/// markers, holes, regions, numbered from `surface.first_index` (0 or 1). Atomic.
pub fn write_tetgen_poly(path: &Path, surface: &SurfaceFile) -> Result<(), IoError> {
    check_plc(path, surface)?;
    write_atomic(path, |w| {
        write_plc(w, surface, Kind::Poly).map_err(|e| IoError::io(path, e))
    })
}

/// Checks what both TetGen writers need.
fn check_plc(path: &Path, s: &SurfaceFile) -> Result<(), IoError> {
    check_first_index(path, s.first_index)?;
    let bad = |m: String| Err(IoError::invalid(path, m));
    let np = s.points.len();
    if let Some(i) = s
        .points
        .iter()
        .position(|p| p.iter().any(|c| !c.is_finite()))
    {
        return bad(format!("point {i} has a non-finite coordinate"));
    }
    if s.point_markers.as_ref().is_some_and(|m| m.len() != np) {
        return bad("one point marker per point is needed".into());
    }
    for (k, f) in s.facets.iter().enumerate() {
        if f.polygons.is_empty() || f.polygons.iter().any(Vec::is_empty) {
            return bad(format!("facet {k} has an empty polygon or no polygon"));
        }
        if let Some(&v) = f.polygons.iter().flatten().find(|&&v| v as usize >= np) {
            return bad(format!(
                "facet {k} refers to point {v} but there are {np} points"
            ));
        }
        if f.holes.iter().flatten().any(|c| !c.is_finite()) {
            return bad(format!("facet {k} has a hole with a non-finite coordinate"));
        }
    }
    let seeds = s.holes.iter().flatten().copied();
    let regions = s
        .regions
        .iter()
        .flat_map(|r| r.point.into_iter().chain([r.attribute]));
    if seeds.chain(regions).any(|c| !c.is_finite()) {
        return bad("a hole or region seed has a non-finite value".into());
    }
    if let Some(r) = s
        .regions
        .iter()
        .find(|r| r.max_volume.is_some_and(|v| !(v > 0.0 && v.is_finite())))
    {
        return bad(format!(
            "region at {:?} has a max volume that is not positive and finite",
            r.point
        ));
    }
    Ok(())
}

fn write_point(w: &mut dyn Write, i: u64, p: &[f64; 3]) -> std::io::Result<()> {
    write!(w, "{i}")?;
    for &c in p {
        w.write_all(b" ")?;
        write_f64(w, c)?;
    }
    Ok(())
}

fn write_plc(w: &mut dyn Write, s: &SurfaceFile, kind: Kind) -> std::io::Result<()> {
    let base = u64::from(s.first_index);
    let markers = s.point_markers.as_deref();
    writeln!(w, "{} 3 0 {}", s.points.len(), u8::from(markers.is_some()))?;
    for (i, p) in s.points.iter().enumerate() {
        write_point(w, i as u64 + base, p)?;
        if let Some(m) = markers {
            write!(w, " {}", m[i])?;
        }
        w.write_all(b"\n")?;
    }
    writeln!(w, "{} 1", s.facets.len())?;
    let corners = |w: &mut dyn Write, poly: &[u32]| -> std::io::Result<()> {
        write!(w, "{}", poly.len())?;
        for &v in poly {
            write!(w, " {}", u64::from(v) + base)?;
        }
        Ok(())
    };
    for f in &s.facets {
        match kind {
            Kind::Smesh => {
                corners(w, &f.polygons[0])?;
                writeln!(w, " {}", f.marker)?;
            }
            Kind::Poly => {
                writeln!(w, "{} {} {}", f.polygons.len(), f.holes.len(), f.marker)?;
                for poly in &f.polygons {
                    corners(w, poly)?;
                    w.write_all(b"\n")?;
                }
                for (k, h) in f.holes.iter().enumerate() {
                    write_point(w, k as u64 + base, h)?;
                    w.write_all(b"\n")?;
                }
            }
        }
    }
    writeln!(w, "{}", s.holes.len())?;
    for (k, h) in s.holes.iter().enumerate() {
        write_point(w, k as u64 + base, h)?;
        w.write_all(b"\n")?;
    }
    if !s.regions.is_empty() {
        writeln!(w, "{}", s.regions.len())?;
        for (k, r) in s.regions.iter().enumerate() {
            write_point(w, k as u64 + base, &r.point)?;
            w.write_all(b" ")?;
            write_f64(w, r.attribute)?;
            w.write_all(b" ")?;
            write_f64(w, r.max_volume.unwrap_or(-1.0))?;
            w.write_all(b"\n")?;
        }
    }
    Ok(())
}
