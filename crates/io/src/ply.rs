//! Stanford `.ply` surfaces (read): points and polygons, ASCII or binary.
//!
//! PLY is how scanned surfaces are passed around (the Stanford bunny, Meshlab, Open3D,
//! Blender's exports). A header declares elements, each with typed properties:
//! `element vertex N` with `property <type> x`, `y`, `z` (others, such as normals and colours,
//! skipped), `element face M` with `property list <count type> <index type> vertex_indices`
//! (or `vertex_index`), and any other element (edges, materials), skipped. The data follows
//! `end_header`: one element per line in `ascii`, packed values in `binary_little_endian` and
//! `binary_big_endian`. Faces have no markers (they read as 0); indices are 0-based.

use std::path::Path;

use crate::surface::{check_polygon_size, SurfaceFacet, SurfaceFile};
use crate::text::shorten;
use crate::vtu_read::Scalar;
use crate::IoError;

/// Reads a `.ply` file.
pub fn read_ply(path: &Path) -> Result<SurfaceFile, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    parse_ply(&bytes, path)
}

/// A property of an element: a number, or a list (count type, item type).
#[derive(Clone, Copy)]
enum Property {
    Number(Scalar),
    List(Scalar, Scalar),
}

struct Element {
    name: String,
    count: usize,
    properties: Vec<(String, Property)>,
}

fn scalar(name: &str) -> Option<Scalar> {
    Some(match name {
        "char" | "int8" => Scalar::I8,
        "uchar" | "uint8" => Scalar::U8,
        "short" | "int16" => Scalar::I16,
        "ushort" | "uint16" => Scalar::U16,
        "int" | "int32" => Scalar::I32,
        "uint" | "uint32" => Scalar::U32,
        "float" | "float32" => Scalar::F32,
        "double" | "float64" => Scalar::F64,
        _ => return None,
    })
}

/// Parses the bytes of a `.ply` file; `file` is only used in error messages.
pub fn parse_ply(bytes: &[u8], file: &Path) -> Result<SurfaceFile, IoError> {
    let err = |line: usize, m: String| IoError::parse(file, line, m);
    // The header, line by line, up to `end_header`.
    let mut at = 0;
    let mut line_no = 0;
    let mut next_line = |at: &mut usize| -> Option<(usize, String)> {
        let rest = bytes.get(*at..).filter(|r| !r.is_empty())?;
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        *at += (end + 1).min(rest.len());
        line_no += 1;
        Some((
            line_no,
            String::from_utf8_lossy(&rest[..end]).trim().to_string(),
        ))
    };
    match next_line(&mut at) {
        Some((_, l)) if l == "ply" => {}
        _ => {
            return Err(err(
                1,
                "not a PLY file (the first line is not 'ply')".into(),
            ))
        }
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut header_end = None;
    while let Some((l, line)) = next_line(&mut at) {
        let f: Vec<&str> = line.split_whitespace().collect();
        match f.first().copied() {
            None | Some("comment") | Some("obj_info") => {}
            Some("format") => {
                format = Some(match f.get(1).copied() {
                    Some("ascii") => None,
                    Some("binary_little_endian") => Some(false),
                    Some("binary_big_endian") => Some(true),
                    other => return Err(err(l, format!("unknown format {other:?}"))),
                });
            }
            Some("element") => {
                let (Some(name), Some(count)) = (f.get(1), f.get(2).and_then(|c| c.parse().ok()))
                else {
                    return Err(err(
                        l,
                        format!("'{}': 'element <name> <count>' expected", shorten(&line)),
                    ));
                };
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            Some("property") => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| err(l, "a property before any element".into()))?;
                let bad = || err(l, format!("'{}': unknown property type", shorten(&line)));
                let (name, property) = if f.get(1) == Some(&"list") {
                    let count = f.get(2).and_then(|t| scalar(t)).ok_or_else(bad)?;
                    let item = f.get(3).and_then(|t| scalar(t)).ok_or_else(bad)?;
                    (f.get(4), Property::List(count, item))
                } else {
                    (
                        f.get(2),
                        Property::Number(f.get(1).and_then(|t| scalar(t)).ok_or_else(bad)?),
                    )
                };
                let name = name.ok_or_else(|| err(l, "a property without a name".into()))?;
                element.properties.push((name.to_string(), property));
            }
            Some("end_header") => {
                header_end = Some(l);
                break;
            }
            Some(other) => return Err(err(l, format!("unknown header line '{}'", shorten(other)))),
        }
    }
    let header_lines = header_end.ok_or_else(|| err(line_no, "no 'end_header'".into()))?;
    let format = format.ok_or_else(|| err(header_lines, "no 'format' line".into()))?;

    let mut out = SurfaceFile {
        first_index: 0,
        ..SurfaceFile::default()
    };
    let mut data = Data {
        bytes,
        at,
        line: header_lines,
        big_endian: format,
        text: String::new(),
        cursor: 0,
        file,
    };
    // One record's values, and the range of them each property holds (reused).
    let (mut values, mut spans) = (Vec::new(), Vec::new());
    for element in &elements {
        let position = |name: &str| element.properties.iter().position(|(n, _)| n == name);
        let (xyz, indices) = match element.name.as_str() {
            "vertex" => {
                let p = ["x", "y", "z"].map(position);
                if p.iter().any(Option::is_none) {
                    return Err(err(
                        header_lines,
                        "the vertex element has no x, y and z".into(),
                    ));
                }
                (Some(p.map(|k| k.expect("checked"))), None)
            }
            "face" => {
                let k = position("vertex_indices")
                    .or_else(|| position("vertex_index"))
                    .ok_or_else(|| {
                        err(
                            header_lines,
                            "the face element has no vertex_indices list".into(),
                        )
                    })?;
                (None, Some(k))
            }
            _ => (None, None),
        };
        // (An element without properties has nothing to read in binary: a count of 10^12
        // would only loop.)
        if element.properties.is_empty() && format.is_some() {
            continue;
        }
        for number in 0..element.count {
            data.record(&element.properties, &mut values, &mut spans)?;
            let record = |k: usize| &values[spans[k]..spans[k + 1]];
            if let Some([x, y, z]) = xyz {
                let p = [record(x)[0], record(y)[0], record(z)[0]];
                if p.iter().any(|c| !c.is_finite()) {
                    return Err(data.error(format!(
                        "vertex {number} has a coordinate that is not finite"
                    )));
                }
                out.points.push(p);
            }
            if let Some(k) = indices {
                let n_points = elements
                    .iter()
                    .find(|e| e.name == "vertex")
                    .map_or(0, |e| e.count);
                let mut polygon = Vec::with_capacity(record(k).len());
                for &v in record(k) {
                    if !(v >= 0.0 && v < n_points as f64 && v.fract() == 0.0) {
                        return Err(data.error(format!(
                            "face {number}: point {v} does not exist (points are numbered 0 to {})",
                            n_points.saturating_sub(1)
                        )));
                    }
                    polygon.push(v as u32);
                }
                let line = if format.is_none() {
                    data.line
                } else {
                    number + 1
                };
                check_polygon_size(polygon.len(), "a face", file, line)?;
                out.facets.push(SurfaceFacet {
                    polygons: vec![polygon],
                    holes: Vec::new(),
                    marker: 0,
                    line,
                });
            }
        }
    }
    Ok(out)
}

/// The data after the header, read record by record.
struct Data<'a> {
    bytes: &'a [u8],
    at: usize,
    /// The line of the last record read (ASCII).
    line: usize,
    /// `None` for ASCII, else whether binary data is big-endian.
    big_endian: Option<bool>,
    /// The record's line (ASCII), and where its next token starts.
    text: String,
    cursor: usize,
    file: &'a Path,
}

impl Data<'_> {
    fn error(&self, m: String) -> IoError {
        match self.big_endian {
            None => IoError::parse(self.file, self.line, m),
            Some(_) => IoError::binary(self.file, self.at as u64, m),
        }
    }

    /// One element's values into `values`, property `k`'s numbers (one, or a list's items) at
    /// `spans[k]..spans[k + 1]`.
    fn record(
        &mut self,
        properties: &[(String, Property)],
        values: &mut Vec<f64>,
        spans: &mut Vec<usize>,
    ) -> Result<(), IoError> {
        if self.big_endian.is_none() {
            // The next line that is not blank.
            loop {
                let rest = self.bytes.get(self.at..).unwrap_or_default();
                if rest.is_empty() {
                    return Err(self.error("the file ends before its last element".into()));
                }
                let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
                self.text.clear();
                self.text.push_str(&String::from_utf8_lossy(&rest[..end]));
                self.cursor = 0;
                self.at += (end + 1).min(rest.len());
                self.line += 1;
                if !self.text.trim().is_empty() {
                    break;
                }
            }
        }
        values.clear();
        spans.clear();
        spans.push(0);
        for (_, property) in properties {
            match *property {
                Property::Number(t) => values.push(self.value(t)?),
                Property::List(count, item) => {
                    let n = self.value(count)?;
                    if !(n >= 0.0 && n.fract() == 0.0 && n < 1e6) {
                        return Err(self.error(format!("a list of {n} items")));
                    }
                    for _ in 0..n as usize {
                        values.push(self.value(item)?);
                    }
                }
            }
            spans.push(values.len());
        }
        if self.big_endian.is_none() && self.token().is_some() {
            return Err(self.error("more values than the element's properties".into()));
        }
        Ok(())
    }

    /// The byte range of the next token of the record's line (ASCII), moving past it.
    fn token(&mut self) -> Option<std::ops::Range<usize>> {
        let rest = &self.text[self.cursor..];
        let start = self.cursor + (rest.len() - rest.trim_start().len());
        let len = self.text[start..]
            .find(char::is_whitespace)
            .unwrap_or(self.text.len() - start);
        self.cursor = start + len;
        (len > 0).then_some(start..start + len)
    }

    fn value(&mut self, t: Scalar) -> Result<f64, IoError> {
        match self.big_endian {
            None => {
                let token = self.token().ok_or_else(|| {
                    self.error("fewer values than the element's properties".into())
                })?;
                let token = &self.text[token];
                token
                    .parse()
                    .map_err(|_| self.error(format!("'{}' is not a number", shorten(token))))
            }
            Some(big) => {
                let size = t.size();
                let bytes = self
                    .bytes
                    .get(self.at..self.at + size)
                    .ok_or_else(|| self.error("the file ends before its last element".into()))?;
                self.at += size;
                Ok(t.read(bytes, big))
            }
        }
    }
}
