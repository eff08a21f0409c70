//! Stereolithography `.stl` surfaces, ASCII and binary (read only).
//!
//! STL is what every CAD package exports, so it is the surface format CFD users have most
//! often. It stores each triangle with its own three corners: the reader merges corners with
//! exactly equal coordinates (compared bit for bit, with `-0.0` equal to `0.0`; no tolerance,
//! which would silently change the geometry) into one point, numbering points in order of first
//! appearance and keeping the triangles in file order. Degenerate triangles (two corners that
//! merge) are kept: judging the geometry is the mesh generator's job.
//!
//! - ASCII: `solid [name]`, then `facet normal nx ny nz` / `outer loop` / three
//!   `vertex x y z` / `endloop` / `endfacet`, then `endsolid [name]`; keywords are matched
//!   without regard to case, and several solids may follow each other (as in the multi-patch
//!   files of OpenFOAM's tools). Solid names become marker names: the k-th distinct name (or
//!   unnamed solid) is marker k, and solids named alike share it. Coordinates are parsed as
//!   `f64`. Normals must be numbers but are otherwise ignored (they are recomputed from the corners by every consumer).
//! - Binary: an 80-byte header, a little-endian `u32` triangle count, then 50 bytes per
//!   triangle (normal and three corners as `f32`, a `u16` attribute that is ignored). All
//!   triangles get marker 0; since the file has no lines, a facet's `line` is its 1-based
//!   triangle number and errors give the byte offset. Several binary solids may follow each
//!   other (gmsh writes one per surface so): when the blocks' headers and counts add up to the
//!   file's size exactly, the triangles of the k-th block get marker k, as in ASCII files.
//!
//! Which kind a file is: the file is binary when its size is exactly `84 + 50 × count`, unless it
//! is plain text (no NUL byte) starting with `solid` (a real binary file has NUL bytes in the
//! count or the attributes); otherwise text starting with `solid` is ASCII, and anything else is
//! taken as binary, so a truncated binary file is reported as such, even one whose header starts
//! with "solid".

use std::collections::HashMap;
use std::path::Path;

use crate::surface::{SurfaceFacet, SurfaceFile};
use crate::text::{parse_coord, shorten, Scanner};
use crate::IoError;

/// Reads an ASCII or binary `.stl` file.
pub fn read_stl(path: &Path) -> Result<SurfaceFile, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    parse_stl(&bytes, path)
}

/// Parses the bytes of an ASCII or binary STL file; `file` is only used in error messages.
pub fn parse_stl(bytes: &[u8], file: &Path) -> Result<SurfaceFile, IoError> {
    let declared = (bytes.len() >= 84).then(|| {
        u64::from(u32::from_le_bytes([
            bytes[80], bytes[81], bytes[82], bytes[83],
        ]))
    });
    let blocks = binary_blocks(bytes);
    let text_like = starts_with_solid(bytes) && !bytes.contains(&0);
    if text_like {
        parse_ascii(&String::from_utf8_lossy(bytes), file)
    } else if let Some(blocks) = blocks {
        parse_binary(bytes, &blocks, file)
    } else {
        match declared {
            None => Err(IoError::binary(
                file,
                0,
                format!(
                    "{} bytes: too short for a binary STL file (at least 84 bytes) and not an \
                     ASCII one (which starts with 'solid')",
                    bytes.len()
                ),
            )),
            Some(n) => Err(IoError::binary(
                file,
                80,
                format!(
                    "the binary STL header declares {n} triangles, which take {} bytes, but the \
                     file has {} bytes",
                    84 + 50 * n,
                    bytes.len()
                ),
            )),
        }
    }
}

/// The binary solids the file is made of, as (offset of the block's header, triangle count),
/// when their headers and counts cover the file (one block for an ordinary file). Fewer bytes
/// than a header after the last block are padding some writers add, and ignored, but for
/// exactly one triangle's 50 (a count one short, an error); a file
/// whose only header counts 0 triangles but whose size is that of whole triangles holds
/// those (a writer that never went back to fill the count in).
fn binary_blocks(bytes: &[u8]) -> Option<Vec<(usize, usize)>> {
    let mut blocks = Vec::new();
    let mut at = 0usize;
    while at < bytes.len() {
        if !blocks.is_empty() && bytes.len() - at < 84 {
            // Exactly one more triangle is not padding: a count one short (read as padding,
            // the surface had a hole and was reported as open).
            if bytes.len() - at == 50 {
                return None;
            }
            break;
        }
        let count = bytes.get(at + 80..at + 84)?;
        let mut n = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as usize;
        if at == 0 && n == 0 {
            let rest = bytes.len() - 84;
            if rest > 0 && rest % 50 == 0 {
                n = rest / 50;
            }
        }
        let end = (at + 84).checked_add(n.checked_mul(50)?)?;
        if end > bytes.len() {
            return None;
        }
        blocks.push((at, n));
        at = end;
    }
    (!blocks.is_empty()).then_some(blocks)
}

/// Whether the bytes start (after white space) with the keyword `solid`.
fn starts_with_solid(bytes: &[u8]) -> bool {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    let rest = &bytes[start..];
    rest.len() >= 5
        && rest[..5].eq_ignore_ascii_case(b"solid")
        && rest.get(5).is_none_or(|b| b.is_ascii_whitespace())
}

/// Gives each distinct point (bit for bit, `-0.0 == 0.0`) one index, in order of appearance.
#[derive(Default)]
struct PointMerger {
    points: Vec<[f64; 3]>,
    index: HashMap<[u64; 3], u32>,
}

impl PointMerger {
    fn add(&mut self, p: [f64; 3]) -> u32 {
        // Adding +0.0 turns -0.0 into +0.0 and changes nothing else.
        let key = p.map(|c| (c + 0.0).to_bits());
        let next = self.points.len() as u32;
        *self.index.entry(key).or_insert_with(|| {
            self.points.push(p);
            next
        })
    }
}

/// The triangles of the binary `blocks` (see [`binary_blocks`]): marker 0 for a single block,
/// else the block's 1-based number.
fn parse_binary(
    bytes: &[u8],
    blocks: &[(usize, usize)],
    file: &Path,
) -> Result<SurfaceFile, IoError> {
    let n = blocks.iter().map(|b| b.1).sum();
    let mut merger = PointMerger::default();
    let mut facets = Vec::with_capacity(n);
    let records = blocks.iter().enumerate().flat_map(|(b, &(at, count))| {
        let marker = if blocks.len() > 1 { b as i32 + 1 } else { 0 };
        let start = at + 84;
        bytes[start..start + 50 * count]
            .chunks_exact(50)
            .enumerate()
            .map(move |(i, rec)| (marker, start + 50 * i, rec))
    });
    for (k, (marker, offset, rec)) in records.enumerate() {
        let f32_at = |i: usize| {
            f64::from(f32::from_le_bytes([
                rec[i],
                rec[i + 1],
                rec[i + 2],
                rec[i + 3],
            ]))
        };
        let mut tri = [0u32; 3];
        for (j, corner) in tri.iter_mut().enumerate() {
            let at = 12 + 12 * j;
            let p = [f32_at(at), f32_at(at + 4), f32_at(at + 8)];
            if p.iter().any(|c| !c.is_finite()) {
                return Err(IoError::binary(
                    file,
                    (offset + at) as u64,
                    format!(
                        "triangle {}: corner {} has a non-finite coordinate {p:?}",
                        k + 1,
                        j + 1
                    ),
                ));
            }
            *corner = merger.add(p);
        }
        facets.push(SurfaceFacet {
            polygons: vec![tri.to_vec()],
            holes: Vec::new(),
            marker,
            line: k + 1,
        });
    }
    Ok(SurfaceFile {
        points: merger.points,
        facets,
        ..SurfaceFile::default()
    })
}

fn parse_ascii(text: &str, file: &Path) -> Result<SurfaceFile, IoError> {
    let mut sc = Scanner::new(text, false);
    // Expects the keyword `word` next; returns its line.
    let expect = |sc: &mut Scanner<'_>, word: &str| -> Result<usize, IoError> {
        match sc.next_token() {
            Some((line, t)) if t.eq_ignore_ascii_case(word) => Ok(line),
            Some((line, t)) => Err(IoError::parse(
                file,
                line,
                format!("expected '{word}', found '{}'", shorten(t)),
            )),
            None => Err(IoError::parse(
                file,
                sc.line(),
                format!("unexpected end of file: expected '{word}'"),
            )),
        }
    };
    let number = |sc: &mut Scanner<'_>, axis: &str, finite: bool| -> Result<f64, IoError> {
        let Some((line, t)) = sc.next_token() else {
            return Err(IoError::parse(
                file,
                sc.line(),
                format!("unexpected end of file: expected the {axis} coordinate"),
            ));
        };
        if finite {
            parse_coord(t, axis, file, line)
        } else {
            t.parse::<f64>().map_err(|_| {
                IoError::parse(
                    file,
                    line,
                    format!("non-numeric token '{}' for the {axis}", shorten(t)),
                )
            })
        }
    };

    let mut merger = PointMerger::default();
    let mut facets = Vec::new();
    let mut marker_names: Vec<(i32, String)> = Vec::new();
    let mut markers = 0i32;
    expect(&mut sc, "solid")?;
    loop {
        // Solids of one name share its marker (concatenated exports of one tool all name
        // their solid alike; a patch is known by its name); a solid without one has its own.
        let name = sc.rest_of_line();
        let solid = match marker_names
            .iter()
            .find(|(_, n)| !name.is_empty() && n == name)
        {
            Some(&(m, _)) => m,
            None => {
                markers += 1;
                if !name.is_empty() {
                    marker_names.push((markers, name.to_string()));
                }
                markers
            }
        };
        loop {
            let Some((line, t)) = sc.next_token() else {
                return Err(IoError::parse(
                    file,
                    sc.line(),
                    "unexpected end of file: expected 'facet' or 'endsolid'",
                ));
            };
            if t.eq_ignore_ascii_case("endsolid") {
                sc.rest_of_line();
                break;
            }
            if !t.eq_ignore_ascii_case("facet") {
                return Err(IoError::parse(
                    file,
                    line,
                    format!("expected 'facet' or 'endsolid', found '{}'", shorten(t)),
                ));
            }
            expect(&mut sc, "normal")?;
            for axis in ["normal x", "normal y", "normal z"] {
                number(&mut sc, axis, false)?;
            }
            expect(&mut sc, "outer")?;
            expect(&mut sc, "loop")?;
            let mut tri = [0u32; 3];
            for corner in &mut tri {
                expect(&mut sc, "vertex")?;
                let p = [
                    number(&mut sc, "x", true)?,
                    number(&mut sc, "y", true)?,
                    number(&mut sc, "z", true)?,
                ];
                *corner = merger.add(p);
            }
            expect(&mut sc, "endloop")?;
            expect(&mut sc, "endfacet")?;
            facets.push(SurfaceFacet {
                polygons: vec![tri.to_vec()],
                holes: Vec::new(),
                marker: solid,
                line,
            });
        }
        match sc.next_token() {
            None => break,
            Some((_, t)) if t.eq_ignore_ascii_case("solid") => {}
            Some((line, t)) => {
                return Err(IoError::parse(
                    file,
                    line,
                    format!(
                        "expected 'solid' or the end of the file after 'endsolid', found '{}'",
                        shorten(t)
                    ),
                ))
            }
        }
    }
    Ok(SurfaceFile {
        points: merger.points,
        facets,
        marker_names,
        ..SurfaceFile::default()
    })
}
