//! Reading VTK XML unstructured grids (`.vtu`) as VTK, ParaView, meshio and solvers write them.
//!
//! vtkio, which writes delmesh's `.vtu` files, reads only part of what VTK's own writer makes:
//! not appended raw binary data (ParaView's and SU2's usual output: its XML parser meets the
//! raw bytes), not compressed data of more than one block, not compressed inline binary data
//! (whose header is base64-encoded apart from its blocks), and not meshio's ASCII files.
//! Background meshes and solutions to adapt to come from those tools, so this reader takes
//! every data mode of VTK's XML writer: `ascii`, inline `binary` (base64) and `appended` (raw
//! or base64), uncompressed or compressed with zlib, LZ4 or LZMA, 32- or 64-bit headers,
//! either byte order. The XML around the data is plain (elements, attributes, text,
//! comments): a small scanner reads it up to the appended data, whose arrays are found by
//! their offsets.

use std::io::Read;

/// Counts (points, cells, components) at least this large are refused: no memory holds them,
/// and products of smaller ones cannot overflow.
pub(crate) const MAX_COUNT: usize = 1 << 40;

/// The arrays of the single piece of a `.vtu` file, as numbers.
pub(crate) struct VtuPiece {
    /// Three coordinates per point.
    pub(crate) points: Vec<f64>,
    /// The cells' point indices, cell after cell.
    pub(crate) connectivity: Vec<f64>,
    /// Where each cell ends in `connectivity`.
    pub(crate) offsets: Vec<f64>,
    /// VTK cell type of each cell.
    pub(crate) types: Vec<f64>,
    /// Point data arrays: name, components, values (point after point).
    pub(crate) point_data: Vec<(String, usize, Vec<f64>)>,
    /// Cell data arrays: name, components, values (cell after cell).
    pub(crate) cell_data: Vec<(String, usize, Vec<f64>)>,
}

/// Reads the piece of a `.vtu` file given as bytes; errors are messages for the file.
pub(crate) fn parse_vtu(bytes: &[u8]) -> Result<VtuPiece, String> {
    let appended = appended_data(bytes)?;
    let end = appended.as_ref().map_or(bytes.len(), |a| a.tag_start);
    let xml = std::str::from_utf8(&bytes[..end])
        .map_err(|e| format!("the XML is not valid UTF-8 text (byte {})", e.valid_up_to()))?;
    let events = scan(xml)?;

    let mut format = Format::default();
    let mut piece: Option<(usize, usize)> = None;
    let mut pieces = 0;
    let mut grid = false;
    let mut stack: Vec<&str> = Vec::new();
    let mut arrays: Vec<Array> = Vec::new();
    for event in &events {
        match event {
            Event::Start {
                name,
                attributes,
                empty,
            } => {
                let get = |key: &str| {
                    attributes
                        .iter()
                        .find(|(k, _)| *k == key)
                        .map(|(_, v)| v.as_str())
                };
                match *name {
                    "VTKFile" => {
                        if let Some(t) = get("type") {
                            if t != "UnstructuredGrid" {
                                return Err(format!(
                                    "a VTK {t} file, not an unstructured grid (.vtu)"
                                ));
                            }
                        }
                        format = Format::of(&get)?;
                    }
                    "UnstructuredGrid" => grid = true,
                    "Piece" => {
                        pieces += 1;
                        let count = |key: &str| -> Result<usize, String> {
                            let v = get(key).ok_or(format!("<Piece> has no {key}"))?;
                            v.trim()
                                .parse()
                                .ok()
                                .filter(|&c: &usize| c < MAX_COUNT)
                                .ok_or(format!("<Piece> {key}=\"{v}\" is not a count"))
                        };
                        piece = Some((count("NumberOfPoints")?, count("NumberOfCells")?));
                    }
                    "DataArray" => {
                        let section = stack.last().copied().unwrap_or("").to_string();
                        arrays.push(Array::of(&get, section)?);
                    }
                    _ => {}
                }
                if !empty {
                    stack.push(name);
                }
            }
            Event::End(name) => {
                if stack.pop() != Some(*name) {
                    return Err(format!("</{name}> closes no open element"));
                }
            }
            Event::Text(text) => {
                if stack.last() == Some(&"DataArray") {
                    if let Some(a) = arrays.last_mut() {
                        a.text.push_str(text);
                    }
                }
            }
        }
    }
    if !grid {
        return Err("no <UnstructuredGrid> element: not a .vtu file".into());
    }
    if pieces != 1 {
        return Err(format!("{pieces} pieces; one is supported"));
    }
    let (n_points, n_cells) = piece.expect("one piece");
    let mut offsets: Vec<usize> = arrays.iter().filter_map(|a| a.offset).collect();
    offsets.sort_unstable();
    offsets.dedup();
    let data = |a: &Array, count: usize| -> Result<Vec<f64>, String> {
        let values = a
            .values(&format, appended.as_ref(), &offsets)
            .map_err(|e| format!("data array '{}': {e}", a.name))?;
        if values.len() != count {
            return Err(format!(
                "data array '{}' has {} values; {count} expected",
                a.name,
                values.len()
            ));
        }
        Ok(values)
    };
    let find = |section: &str, name: Option<&str>| {
        arrays
            .iter()
            .find(|a| a.section == section && name.is_none_or(|n| a.name == n))
            .ok_or_else(|| match name {
                Some(n) => format!("no '{n}' data array in <{section}>"),
                None => format!("no data array in <{section}>"),
            })
    };
    let points_array = find("Points", None)?;
    if points_array.components != 3 {
        return Err(format!(
            "points have {} components; 3 expected",
            points_array.components
        ));
    }
    let points = data(points_array, 3 * n_points)?;
    let offsets_of_cells = data(find("Cells", Some("offsets"))?, n_cells)?;
    let total = offsets_of_cells.last().copied().unwrap_or(0.0);
    if !(total >= 0.0 && total.fract() == 0.0 && total < 1e15) {
        return Err(format!("the last cell ends at {total}, not a valid index"));
    }
    let connectivity = data(find("Cells", Some("connectivity"))?, total as usize)?;
    let types = data(find("Cells", Some("types"))?, n_cells)?;
    let mut point_data = Vec::new();
    for a in arrays.iter().filter(|a| a.section == "PointData") {
        point_data.push((
            a.name.clone(),
            a.components,
            data(a, a.components * n_points)?,
        ));
    }
    let mut cell_data = Vec::new();
    for a in arrays.iter().filter(|a| a.section == "CellData") {
        cell_data.push((
            a.name.clone(),
            a.components,
            data(a, a.components * n_cells)?,
        ));
    }
    Ok(VtuPiece {
        points,
        connectivity,
        offsets: offsets_of_cells,
        types,
        point_data,
        cell_data,
    })
}

/// The `<AppendedData>` block: where its tag starts, its encoding, and its data (after `_`).
struct Appended<'a> {
    tag_start: usize,
    base64: bool,
    data: &'a [u8],
}

fn appended_data(bytes: &[u8]) -> Result<Option<Appended<'_>>, String> {
    let Some(tag_start) = find(bytes, b"<AppendedData", 0) else {
        return Ok(None);
    };
    let close = find(bytes, b">", tag_start).ok_or("<AppendedData> is not closed")?;
    let tag = String::from_utf8_lossy(&bytes[tag_start..close]);
    let base64 = !tag.contains("\"raw\"") && !tag.contains("'raw'");
    let underscore = find(bytes, b"_", close).ok_or("<AppendedData> has no '_' mark")?;
    let start = underscore + 1;
    let end = rfind(bytes, b"</AppendedData>")
        .filter(|&e| e >= start)
        .ok_or("<AppendedData> is not closed")?;
    Ok(Some(Appended {
        tag_start,
        base64,
        data: &bytes[start..end],
    }))
}

fn find(hay: &[u8], needle: &[u8], from: usize) -> Option<usize> {
    hay.get(from..)?
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|i| i + from)
}

fn rfind(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).rposition(|w| w == needle)
}

/// The file-wide encoding settings of `<VTKFile>`.
#[derive(Default)]
struct Format {
    header64: bool,
    big_endian: bool,
    compressor: Option<Compressor>,
}

#[derive(Clone, Copy)]
enum Compressor {
    ZLib,
    Lz4,
    Lzma,
}

impl Format {
    fn of<'a>(get: &impl Fn(&str) -> Option<&'a str>) -> Result<Format, String> {
        let header64 = match get("header_type") {
            None | Some("UInt32") => false,
            Some("UInt64") => true,
            Some(other) => return Err(format!("header_type \"{other}\" is not supported")),
        };
        let big_endian = match get("byte_order") {
            None | Some("LittleEndian") => false,
            Some("BigEndian") => true,
            Some(other) => return Err(format!("byte_order \"{other}\" is not supported")),
        };
        let compressor = match get("compressor") {
            None | Some("") => None,
            Some("vtkZLibDataCompressor") => Some(Compressor::ZLib),
            Some("vtkLZ4DataCompressor") => Some(Compressor::Lz4),
            Some("vtkLZMADataCompressor") => Some(Compressor::Lzma),
            Some(other) => return Err(format!("compressor \"{other}\" is not supported")),
        };
        Ok(Format {
            header64,
            big_endian,
            compressor,
        })
    }

    /// The header integer `k` of a data block.
    fn header(&self, block: &[u8], k: usize) -> Result<usize, String> {
        let size = if self.header64 { 8 } else { 4 };
        let bytes = block
            .get(k * size..(k + 1) * size)
            .ok_or("the data ends inside its header")?;
        let mut value = 0u64;
        for i in 0..size {
            let b = if self.big_endian {
                bytes[i]
            } else {
                bytes[size - 1 - i]
            };
            value = value << 8 | u64::from(b);
        }
        usize::try_from(value).map_err(|_| "a header size does not fit in memory".into())
    }

    /// The bytes of one array's data: a header (the byte count, or the compressed blocks'
    /// sizes) then the data or the blocks.
    fn unpack(&self, block: &[u8]) -> Result<Vec<u8>, String> {
        let h = if self.header64 { 8 } else { 4 };
        let Some(compressor) = self.compressor else {
            let n = self.header(block, 0)?;
            let data = block
                .get(h..)
                .and_then(|d| d.get(..n))
                .ok_or("the data is shorter than its header says")?;
            return Ok(data.to_vec());
        };
        let blocks = self.header(block, 0)?;
        let block_size = self.header(block, 1)?;
        let last_size = self.header(block, 2)?;
        let mut at = (3 + blocks)
            .checked_mul(h)
            .ok_or("too many compressed blocks")?;
        let mut out = Vec::new();
        for k in 0..blocks {
            let size = self.header(block, 3 + k)?;
            let compressed = block
                .get(at..)
                .and_then(|d| d.get(..size))
                .ok_or("the compressed data is shorter than its header says")?;
            at += size;
            let expected = if k + 1 == blocks && last_size != 0 {
                last_size
            } else {
                block_size
            };
            let before = out.len();
            decompress(compressor, compressed, expected, &mut out)?;
            if out.len() - before != expected {
                return Err(format!(
                    "a compressed block gave {} bytes; {expected} expected",
                    out.len() - before
                ));
            }
        }
        Ok(out)
    }
}

fn decompress(
    compressor: Compressor,
    data: &[u8],
    expected: usize,
    out: &mut Vec<u8>,
) -> Result<(), String> {
    match compressor {
        Compressor::ZLib => {
            flate2::read::ZlibDecoder::new(data)
                .take(expected as u64 + 1)
                .read_to_end(out)
                .map_err(|e| format!("zlib: {e}"))?;
        }
        Compressor::Lz4 => {
            let block =
                lz4_flex::block::decompress(data, expected).map_err(|e| format!("LZ4: {e}"))?;
            out.extend_from_slice(&block);
        }
        Compressor::Lzma => {
            let mut reader = std::io::BufReader::new(data);
            lzma_rs::xz_decompress(&mut reader, out).map_err(|e| format!("LZMA: {e}"))?;
        }
    }
    Ok(())
}

/// A `<DataArray>`: its attributes, and its text for the inline formats.
struct Array {
    section: String,
    name: String,
    scalar: Scalar,
    components: usize,
    mode: Mode,
    offset: Option<usize>,
    text: String,
}

#[derive(Clone, Copy, PartialEq)]
enum Mode {
    Ascii,
    Binary,
    Appended,
}

impl Array {
    fn of<'a>(get: &impl Fn(&str) -> Option<&'a str>, section: String) -> Result<Array, String> {
        let name = get("Name").unwrap_or("").to_string();
        let what = |m: String| format!("data array '{name}': {m}");
        let scalar =
            Scalar::of(get("type").ok_or_else(|| what("no type".into()))?).ok_or_else(|| {
                what(format!(
                    "type \"{}\" is not a number type",
                    get("type").unwrap_or("")
                ))
            })?;
        let components = match get("NumberOfComponents") {
            None => 1,
            Some(c) => c
                .trim()
                .parse()
                .ok()
                .filter(|&c| c > 0 && c < 1 << 16)
                .ok_or_else(|| what(format!("NumberOfComponents=\"{c}\"")))?,
        };
        let mode = match get("format") {
            Some("ascii") => Mode::Ascii,
            Some("binary") => Mode::Binary,
            Some("appended") => Mode::Appended,
            other => {
                return Err(what(format!(
                    "format {other:?} is not ascii, binary or appended"
                )))
            }
        };
        let offset = match (mode, get("offset")) {
            (Mode::Appended, Some(o)) => Some(
                o.trim()
                    .parse()
                    .map_err(|_| what(format!("offset=\"{o}\"")))?,
            ),
            (Mode::Appended, None) => return Err(what("appended data without an offset".into())),
            _ => None,
        };
        Ok(Array {
            section,
            name,
            scalar,
            components,
            mode,
            offset,
            text: String::new(),
        })
    }

    fn values(
        &self,
        format: &Format,
        appended: Option<&Appended<'_>>,
        offsets: &[usize],
    ) -> Result<Vec<f64>, String> {
        let bytes = match self.mode {
            Mode::Ascii => {
                return self
                    .text
                    .split_ascii_whitespace()
                    .map(|t| {
                        t.parse::<f64>()
                            .map_err(|_| format!("'{}' is not a number", crate::text::shorten(t)))
                    })
                    .collect();
            }
            Mode::Binary => format.unpack(&base64(self.text.as_bytes())?)?,
            Mode::Appended => {
                let a = appended.ok_or("appended data, but the file has no <AppendedData>")?;
                let at = self.offset.expect("appended arrays have an offset");
                let rest = a
                    .data
                    .get(at..)
                    .ok_or("its offset is past the appended data")?;
                if a.base64 {
                    // Up to the next array's data (base64 cannot be decoded from the middle).
                    let next = offsets
                        .iter()
                        .find(|&&o| o > at)
                        .map_or(rest.len(), |&o| o - at);
                    format.unpack(&base64(&rest[..next.min(rest.len())])?)?
                } else {
                    format.unpack(rest)?
                }
            }
        };
        self.scalar.decode(&bytes, format.big_endian)
    }
}

/// The number types of VTK data arrays.
#[derive(Clone, Copy)]
pub(crate) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

impl Scalar {
    fn of(name: &str) -> Option<Scalar> {
        Some(match name {
            "Int8" | "Char" => Scalar::I8,
            "UInt8" | "UChar" => Scalar::U8,
            "Int16" => Scalar::I16,
            "UInt16" => Scalar::U16,
            "Int32" => Scalar::I32,
            "UInt32" => Scalar::U32,
            "Int64" => Scalar::I64,
            "UInt64" => Scalar::U64,
            "Float32" => Scalar::F32,
            "Float64" => Scalar::F64,
            _ => return None,
        })
    }

    pub(crate) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::I64 | Scalar::U64 | Scalar::F64 => 8,
        }
    }

    /// The values of `bytes` (whole values only) as numbers.
    pub(crate) fn decode(self, bytes: &[u8], big_endian: bool) -> Result<Vec<f64>, String> {
        let size = self.size();
        if bytes.len() % size != 0 {
            return Err(format!(
                "{} bytes of data, not a whole number of {size}-byte values",
                bytes.len()
            ));
        }
        Ok(bytes
            .chunks_exact(size)
            .map(|c| self.read(c, big_endian))
            .collect())
    }

    /// The value in `c`, which holds exactly [`Self::size`] bytes.
    #[inline]
    pub(crate) fn read(self, c: &[u8], big_endian: bool) -> f64 {
        let size = self.size();
        let mut b = [0u8; 8];
        b[..size].copy_from_slice(c);
        if big_endian {
            b[..size].reverse();
        }
        match self {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::I64 => i64::from_le_bytes(b) as f64,
            Scalar::U64 => u64::from_le_bytes(b) as f64,
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        }
    }
}

/// Decodes base64 text, whitespace ignored. VTK encodes a compressed array's header apart from
/// its blocks, so padding (`=`) may end a group in the middle: each group of four is decoded
/// on its own and the bytes joined.
fn base64(text: &[u8]) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    let mut group = [0u8; 4];
    let mut n = 0;
    for &c in text {
        if c.is_ascii_whitespace() {
            continue;
        }
        group[n] = c;
        n += 1;
        if n < 4 {
            continue;
        }
        n = 0;
        let mut bits = 0u32;
        let mut pad = 0;
        for &g in &group {
            let v = match g {
                b'A'..=b'Z' => g - b'A',
                b'a'..=b'z' => g - b'a' + 26,
                b'0'..=b'9' => g - b'0' + 52,
                b'+' => 62,
                b'/' => 63,
                b'=' => {
                    pad += 1;
                    0
                }
                _ => return Err(format!("'{}' is not a base64 character", g as char)),
            };
            if pad > 0 && g != b'=' {
                return Err("base64 padding in the middle of a group".into());
            }
            bits = bits << 6 | u32::from(v);
        }
        if pad > 2 {
            return Err("a base64 group of padding only".into());
        }
        let bytes = bits.to_be_bytes();
        out.extend_from_slice(&bytes[1..4 - pad]);
    }
    if n != 0 {
        return Err("base64 text whose length is not a multiple of 4".into());
    }
    Ok(out)
}

/// XML as the scanner sees it.
enum Event<'a> {
    Start {
        name: &'a str,
        attributes: Vec<(&'a str, String)>,
        /// `<name ... />`.
        empty: bool,
    },
    End(&'a str),
    Text(&'a str),
}

/// The elements and text of `xml` (declarations, comments and `<!...>` skipped).
fn scan(xml: &str) -> Result<Vec<Event<'_>>, String> {
    let mut events = Vec::new();
    let mut rest = xml;
    while let Some(lt) = rest.find('<') {
        if lt > 0 {
            events.push(Event::Text(&rest[..lt]));
        }
        rest = &rest[lt..];
        let skip_to = |end: &str| -> Result<usize, String> {
            rest.find(end)
                .map(|i| i + end.len())
                .ok_or_else(|| format!("'{}' is not closed", crate::text::shorten(rest)))
        };
        if rest.starts_with("<!--") {
            rest = &rest[skip_to("-->")?..];
        } else if rest.starts_with("<?") {
            rest = &rest[skip_to("?>")?..];
        } else if rest.starts_with("<!") {
            rest = &rest[skip_to(">")?..];
        } else if let Some(close) = rest.strip_prefix("</") {
            let gt = close.find('>').ok_or("an end tag is not closed")?;
            events.push(Event::End(close[..gt].trim()));
            rest = &close[gt + 1..];
        } else {
            // A start tag: its end is the first '>' outside quotes.
            let body = &rest[1..];
            let mut quote = None;
            let gt = body
                .char_indices()
                .find(|&(_, c)| match quote {
                    Some(q) => {
                        if c == q {
                            quote = None;
                        }
                        false
                    }
                    None => {
                        if c == '"' || c == '\'' {
                            quote = Some(c);
                        }
                        c == '>'
                    }
                })
                .map(|(i, _)| i)
                .ok_or("a start tag is not closed")?;
            let (inner, empty) = match body[..gt].strip_suffix('/') {
                Some(s) => (s, true),
                None => (&body[..gt], false),
            };
            let inner = inner.trim();
            let name_end = inner
                .find(|c: char| c.is_ascii_whitespace())
                .unwrap_or(inner.len());
            let name = &inner[..name_end];
            let attributes =
                attributes(&inner[name_end..]).map_err(|e| format!("<{name}>: {e}"))?;
            events.push(Event::Start {
                name,
                attributes,
                empty,
            });
            rest = &body[gt + 1..];
        }
    }
    if !rest.trim().is_empty() {
        events.push(Event::Text(rest));
    }
    Ok(events)
}

/// `key="value"` pairs (either quote), entities in values decoded.
fn attributes(mut s: &str) -> Result<Vec<(&str, String)>, String> {
    let mut out = Vec::new();
    loop {
        s = s.trim_start();
        if s.is_empty() {
            return Ok(out);
        }
        let eq = s
            .find('=')
            .ok_or_else(|| format!("attribute '{}' has no value", s.trim()))?;
        let key = s[..eq].trim();
        let after = s[eq + 1..].trim_start();
        let q = after
            .chars()
            .next()
            .filter(|&c| c == '"' || c == '\'')
            .ok_or_else(|| format!("attribute {key} is not quoted"))?;
        let end = after[1..]
            .find(q)
            .ok_or_else(|| format!("attribute {key} is not closed"))?;
        let value = after[1..1 + end]
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&quot;", "\"")
            .replace("&apos;", "'")
            .replace("&amp;", "&");
        out.push((key, value));
        s = &after[end + 2..];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_groups_decode_on_their_own() {
        // "Ma" padded, then "n" padded: two encodings joined, as VTK writes header and blocks.
        assert_eq!(base64(b"TWE=\nbg==").unwrap(), b"Man");
        assert_eq!(base64(b"TWFu").unwrap(), b"Man");
        assert!(base64(b"TWF").is_err());
        assert!(base64(b"T=Fu").is_err());
        assert!(base64(b"TW!u").is_err());
    }

    #[test]
    fn the_scanner_reads_attributes_comments_and_empty_elements() {
        let events =
            scan("<?xml version=\"1.0\"?><!-- c --><A x='1 > 0' y=\"&amp;\"><B/>text</A>").unwrap();
        let Event::Start {
            name, attributes, ..
        } = &events[0]
        else {
            panic!()
        };
        assert_eq!(*name, "A");
        assert_eq!(attributes[0], ("x", "1 > 0".to_string()));
        assert_eq!(attributes[1], ("y", "&".to_string()));
        assert!(matches!(
            events[1],
            Event::Start {
                name: "B",
                empty: true,
                ..
            }
        ));
        assert!(matches!(events[2], Event::Text("text")));
        assert!(matches!(events[3], Event::End("A")));
    }
}
