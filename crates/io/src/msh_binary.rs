//! Binary gmsh `.msh` files (versions 2.2 and 4.1), read into the same [`SurfaceFile`] as the
//! ASCII reader of [`crate::msh`] gives for the ASCII file of the same mesh.
//!
//! A binary file is recognised by its first section: `$MeshFormat`, then the line
//! `<version> 1 <data-size>`, then the binary integer 1, whose byte order gives the file's
//! (little and big endian are both read), then `$EndMeshFormat`. gmsh writes its machine's
//! native byte order; `<data-size>` is `sizeof(size_t)` in 4.1 (4 or 8 are read) and
//! `sizeof(double)`, 8, in 2.2.
//!
//! Layout, as written by gmsh 4.15 (every binary block is followed by a newline and the
//! section's `$End` line):
//! - `$PhysicalNames` is text, as in ASCII files (and read by the same code).
//! - 2.2 `$Nodes`: a text line with the count, then per node an `int` tag and 3 `double`s.
//!   `$Elements`: a text line with the count, then groups: an `int` header `type, count,
//!   #tags` followed by `count` elements of `int`s `number, tags..., nodes...`.
//! - 4.1 (all counts and node and element tags are `size_t`, entity tags and types `int`):
//!   `$Entities`: 4 counts, then points `tag, x, y, z, #physicals, physicals (int)...` and
//!   curves, surfaces, volumes `tag, 6 bounding-box doubles, #physicals, physicals...,
//!   #bounding entities, bounding entities (int)...`. `$Nodes`: 4 counts (blocks, nodes, min
//!   and max tag), then per block `int dim, int entity, int parametric, size_t count`, the
//!   `count` tags, then the `count` coordinate records (`x y z` and, for parametric nodes, `dim`
//!   more doubles). `$Elements`: 4 counts, then per block `int dim, int entity, int type,
//!   size_t count` and per element its tag and node tags.
//!
//! Elements whose types are skipped (points, lines, higher-order elements...) must still be
//! stepped over, so the reader knows the node count of every fixed-size gmsh element type
//! ([`node_count`]); a type it does not know is an error naming it. Other sections
//! (`$Periodic`, `$NodeData`, `$InterpolationScheme`...), whose layout is not needed, are
//! skipped by searching for the bytes `\n$End<Name>` followed by a line end: binary data could
//! in principle contain that sequence, but gmsh's sections never do in practice.
//!
//! Errors in binary data are [`IoError::Binary`] with the byte offset of the field and the
//! section with the line of its keyword (`byte 1234: node tag 7 is defined twice (in $Nodes,
//! line 12)`); errors in the text lines (`$MeshFormat`, the 2.2 count lines,
//! `$PhysicalNames`) are line-numbered [`IoError::Parse`]. Line numbers count the newline
//! bytes before the place, as a text editor or `grep -an` shows them. Facets get the line of
//! their `$Elements` keyword as [`SurfaceFacet::line`](crate::SurfaceFacet::line), since binary
//! elements have no line of their own. Coordinates must be finite, as in ASCII files.

use std::path::Path;

use crate::msh::{
    corners, node_block_range, not_a_section, parse_physical_names, parse_version, Lines, MshData,
    Pending, Version,
};
use crate::surface::SurfaceFile;
use crate::text::{parse_count, shorten};
use crate::IoError;

/// Whether `bytes` is a binary `.msh` file: its first line is `$MeshFormat` and the next has
/// file type `1`.
pub(crate) fn is_binary(bytes: &[u8]) -> bool {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let mut lines = bytes
        .split(|&b| b == b'\n')
        .map(|l| l.trim_ascii())
        .filter(|l| !l.is_empty());
    if lines.next() != Some(b"$MeshFormat") {
        return false;
    }
    let Some(format) = lines.next() else {
        return false;
    };
    format
        .split(|b| b.is_ascii_whitespace())
        .filter(|t| !t.is_empty())
        .nth(1)
        == Some(b"1")
}

/// The number of nodes of a gmsh element type, for every fixed-size type gmsh 4.15 knows
/// (`gmsh.model.mesh.getElementProperties`), plus the high-order prisms it names but cannot
/// build a basis for (types 90, 91, 106-117). `Err` with a reason for the others: the
/// variable-size polygons, polyhedra and X-FEM elements, whose size a binary file does not
/// give, and unknown types.
pub(crate) fn node_count(ty: i32) -> Result<usize, &'static str> {
    Ok(match ty {
        1 => 2,
        2 => 3,
        3 | 4 => 4,
        5 => 8,
        6 => 6,
        7 => 5,
        8 => 3,
        9 => 6,
        10 => 9,
        11 => 10,
        12 => 27,
        13 => 18,
        14 => 14,
        15 => 1,
        16 => 8,
        17 => 20,
        18 => 15,
        19 => 13,
        20 => 9,
        21 => 10,
        22 => 12,
        23 | 24 => 15,
        25 => 21,
        26 => 4,
        27 => 5,
        28 => 6,
        29 => 20,
        30 => 35,
        31 => 56,
        32 => 22,
        33 => 28,
        36 => 16,
        37 => 25,
        38 => 36,
        39 => 12,
        40 => 16,
        41 => 20,
        42 => 28,
        43 => 36,
        44 => 45,
        45 => 55,
        46 => 66,
        47 => 49,
        48 => 64,
        49 => 81,
        50 => 100,
        51 => 121,
        52 => 18,
        53 => 21,
        54 => 24,
        55 => 27,
        56 => 30,
        57 => 24,
        58 => 28,
        59 => 32,
        60 => 36,
        61 => 40,
        // Lines of order 6 to 10.
        62..=66 => (ty - 55) as usize,
        71 => 84,
        72 => 120,
        73 => 165,
        74 => 220,
        75 => 286,
        79 => 34,
        80 => 40,
        81 => 46,
        82 => 52,
        83 => 58,
        // One-node elements (a point per line, triangle, ..., prism).
        84..=89 => 1,
        // Complete prisms of order p = 3, 4 (90, 91) and 5..9 (106..110): (p+1)^2 (p+2) / 2.
        90 => 40,
        91 => 75,
        92 => 64,
        93 => 125,
        94 => 216,
        95 => 343,
        96 => 512,
        97 => 729,
        98 => 1000,
        99 => 32,
        100 => 44,
        101 => 56,
        102 => 68,
        103 => 80,
        104 => 92,
        105 => 104,
        106 => 126,
        107 => 196,
        108 => 288,
        109 => 405,
        110 => 550,
        // Incomplete prisms of order p = 3..9: 6 + 9 (p - 1).
        111..=117 => 6 + 9 * (ty - 109) as usize,
        118 => 30,
        119 => 55,
        120 => 91,
        121 => 140,
        122 => 204,
        123 => 285,
        124 => 385,
        125 => 21,
        126 => 29,
        127 => 37,
        128 => 45,
        129 => 53,
        130 => 61,
        131 => 69,
        132 => 1,
        137 => 16,
        34 | 35 | 69 | 133..=136 => {
            return Err("its elements (polygons, polyhedra, X-FEM elements) have no fixed size")
        }
        _ => return Err("it is not a gmsh element type this reader knows"),
    })
}

/// Parses a binary `.msh` file (`is_binary(bytes)`); `file` names it in messages.
pub(crate) fn parse(bytes: &[u8], file: &Path) -> Result<SurfaceFile, IoError> {
    let start = if bytes.starts_with(b"\xef\xbb\xbf") {
        3
    } else {
        0
    };
    let mut r = Reader {
        bytes,
        pos: start,
        file,
        big_endian: false,
        size_t: 8,
        section: "",
        section_line: 0,
        counted: (0, 1),
    };
    let mut data = MshData::default();
    // `is_binary` has seen `$MeshFormat` first; check it all the same.
    let (line, header) = r.header()?.unwrap_or((1, ""));
    if header != "$MeshFormat" {
        return Err(IoError::parse(
            file,
            line,
            "a binary .msh file must begin with $MeshFormat",
        ));
    }
    r.enter(header, line);
    let mut version = r.mesh_format()?;

    while let Some((line, header)) = r.header()? {
        r.enter(header, line);
        match header {
            "$MeshFormat" => version = r.mesh_format()?,
            "$PhysicalNames" => {
                let (first, text) = r.text_section("PhysicalNames")?;
                parse_physical_names(&mut Lines::new(text, file, first), &mut data)?;
            }
            "$Entities" => {
                if version != Version::V41 {
                    return Err(IoError::parse(file, line, "$Entities in a version 2 file"));
                }
                r.entities(&mut data)?;
            }
            "$Nodes" => match version {
                Version::V2 => r.nodes22(&mut data)?,
                Version::V41 => r.nodes41(&mut data)?,
            },
            "$Elements" => match version {
                Version::V2 => r.elements22(&mut data)?,
                Version::V41 => r.elements41(&mut data)?,
            },
            s if s.starts_with('$') && !s.starts_with("$End") => {
                r.skip_section(&s[1..])?;
            }
            other => return Err(IoError::parse(file, line, not_a_section(other))),
        }
    }
    Ok(data.finish(version))
}

/// A position in the bytes of a binary file, with the byte order and `size_t` width of its
/// `$MeshFormat` and the section being read (for messages).
struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
    file: &'a Path,
    big_endian: bool,
    /// Bytes of a 4.1 `size_t`: 4 or 8.
    size_t: usize,
    /// The keyword of the section being read, `""` before the first.
    section: &'a str,
    section_line: usize,
    /// `(offset, line)`: the newlines before `offset` are counted, for [`Reader::line_at`].
    counted: (usize, usize),
}

impl<'a> Reader<'a> {
    /// The 1-based line of byte `offset` (1 + the newline bytes before it).
    fn line_at(&mut self, offset: usize) -> usize {
        let offset = offset.min(self.bytes.len());
        if offset < self.counted.0 {
            self.counted = (0, 1);
        }
        let (from, line) = self.counted;
        let line = line
            + self.bytes[from..offset]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
        self.counted = (offset, line);
        line
    }

    fn enter(&mut self, section: &'a str, line: usize) {
        self.section = section;
        self.section_line = line;
    }

    /// A binary-data error at byte `offset`, naming the section being read.
    fn err(&self, offset: usize, message: impl std::fmt::Display) -> IoError {
        IoError::binary(
            self.file,
            offset as u64,
            format!("{message} {}", self.context("in")),
        )
    }

    /// `(in $Nodes, line 12)`: the section being read (`word`: "in", "after").
    fn context(&self, word: &str) -> String {
        if self.section.is_empty() {
            "(before the first section)".into()
        } else {
            format!("({word} {}, line {})", self.section, self.section_line)
        }
    }

    fn left(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// The next `n` bytes.
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], IoError> {
        if n > self.left() {
            return Err(self.err(self.pos, format!("unexpected end of file: expected {what}")));
        }
        let b = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(b)
    }

    /// Steps over `n` records of `size` bytes, or fails like [`Reader::need`].
    fn skip(&mut self, n: u64, size: usize, what: &str) -> Result<(), IoError> {
        self.need(n, size, what)?;
        self.pos += (n * size as u64) as usize;
        Ok(())
    }

    /// Checks that `n` records of `size` bytes (`what`, e.g. "nodes of 28 bytes") fit in the
    /// rest of the file, so that no count read from it makes the reader allocate or loop more
    /// than the file's size allows.
    fn need(&self, n: u64, size: usize, what: &str) -> Result<(), IoError> {
        let total = n.checked_mul(size as u64);
        if total.is_none_or(|t| t > self.left() as u64) {
            let take = match total {
                Some(t) => format!("{t} bytes"),
                None => "more than 2^64 bytes".into(),
            };
            return Err(self.err(
                self.pos,
                format!(
                    "{n} {what} take {take}, but only {} bytes are left in the file",
                    self.left()
                ),
            ));
        }
        Ok(())
    }

    fn int(&mut self, what: &str) -> Result<i32, IoError> {
        let b: [u8; 4] = self.take(4, what)?.try_into().expect("4 bytes");
        Ok(if self.big_endian {
            i32::from_be_bytes(b)
        } else {
            i32::from_le_bytes(b)
        })
    }

    /// A `size_t` (4.1), of the width of the `$MeshFormat`.
    fn size(&mut self, what: &str) -> Result<u64, IoError> {
        let b = self.take(self.size_t, what)?;
        let mut v = [0u8; 8];
        if self.big_endian {
            v[8 - b.len()..].copy_from_slice(b);
            Ok(u64::from_be_bytes(v))
        } else {
            v[..b.len()].copy_from_slice(b);
            Ok(u64::from_le_bytes(v))
        }
    }

    /// A finite coordinate (`axis`: "x", "y", "z"), as [`crate::text::parse_coord`] requires.
    fn coord(&mut self, axis: &str) -> Result<f64, IoError> {
        let at = self.pos;
        let b: [u8; 8] = self
            .take(8, &format!("the {axis} coordinate"))?
            .try_into()
            .expect("8 bytes");
        let v = if self.big_endian {
            f64::from_be_bytes(b)
        } else {
            f64::from_le_bytes(b)
        };
        if !v.is_finite() {
            return Err(self.err(at, format!("{axis} coordinate is not finite: {v}")));
        }
        Ok(v)
    }

    fn point(&mut self) -> Result<[f64; 3], IoError> {
        Ok([self.coord("x")?, self.coord("y")?, self.coord("z")?])
    }

    /// A non-negative `int` (a count of a 2.2 element group).
    fn count_int(&mut self, what: &str) -> Result<usize, IoError> {
        let at = self.pos;
        let v = self.int(what)?;
        usize::try_from(v).map_err(|_| self.err(at, format!("negative {what}: {v}")))
    }

    /// The next non-blank line after white space: its line, its offset and its text
    /// (trimmed; `None` if it is not printable text). `None` at the end of the file.
    fn text_line(&mut self) -> Option<(usize, usize, Option<&'a str>)> {
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if self.pos == self.bytes.len() {
            return None;
        }
        let start = self.pos;
        let end = self.bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(self.bytes.len(), |k| start + k);
        self.pos = (end + 1).min(self.bytes.len());
        let line = self.line_at(start);
        let text = std::str::from_utf8(&self.bytes[start..end])
            .ok()
            .map(str::trim)
            .filter(|t| !t.chars().any(|c| c.is_control() && c != '\t'));
        Some((line, start, text))
    }

    /// A text line that must be there (`what` was expected), with its line number.
    fn need_line(&mut self, what: &str) -> Result<(usize, &'a str), IoError> {
        match self.text_line() {
            Some((_, at, None)) => Err(self.err(at, format!("expected {what}, found binary data"))),
            Some((line, _, Some(t))) => Ok((line, t)),
            None => Err(IoError::parse(
                self.file,
                self.line_at(self.bytes.len()),
                format!("unexpected end of file: expected {what}"),
            )),
        }
    }

    /// The next section keyword (a text line), `None` at the end of the file.
    fn header(&mut self) -> Result<Option<(usize, &'a str)>, IoError> {
        match self.text_line() {
            Some((_, at, None)) => Err(IoError::binary(
                self.file,
                at as u64,
                format!(
                    "expected a section keyword such as $Nodes or $Elements, found binary data \
                     {}",
                    self.context("after")
                ),
            )),
            Some((line, _, Some(t))) => Ok(Some((line, t))),
            None => Ok(None),
        }
    }

    /// The `$End` line closing the current section, after its binary data.
    fn expect_end(&mut self) -> Result<(), IoError> {
        let end = format!("$End{}", &self.section[1..]);
        match self.text_line() {
            Some((_, _, Some(t))) if t == end => Ok(()),
            Some((_, at, t)) => Err(self.err(
                at,
                format!(
                    "expected '{end}', found {}: the section's counts and its data disagree",
                    t.map_or("binary data".into(), |t| format!("'{}'", shorten(t)))
                ),
            )),
            None => Err(self.err(
                self.bytes.len(),
                format!("unexpected end of file: expected '{end}'"),
            )),
        }
    }

    /// The rest of `$MeshFormat`: the format line, the byte-order integer and the `$End` line.
    fn mesh_format(&mut self) -> Result<Version, IoError> {
        let what = "the format line '<version> <file type> <size>'";
        let (l, text) = self.need_line(what)?;
        let toks: Vec<&str> = text.split_whitespace().collect();
        if toks.len() != 3 {
            return Err(IoError::parse(
                self.file,
                l,
                format!("expected 3 fields for {what}, found {}", toks.len()),
            ));
        }
        if toks[1] != "1" {
            return Err(IoError::parse(
                self.file,
                l,
                format!(
                    "file type '{}' in a binary file (its first $MeshFormat has file type 1)",
                    shorten(toks[1])
                ),
            ));
        }
        let version = parse_version(toks[0], self.file, l)?;
        let size = parse_count(toks[2], "data size", self.file, l)?;
        match (version, size) {
            (Version::V2, 8) => {}
            (Version::V41, 4 | 8) => self.size_t = size,
            (Version::V2, _) => {
                return Err(IoError::parse(
                    self.file,
                    l,
                    format!("data size {size} in a binary version 2 file: only 8 (the size of a double) is read"),
                ))
            }
            (Version::V41, _) => {
                return Err(IoError::parse(
                    self.file,
                    l,
                    format!("data size {size} in a binary version 4.1 file: only 4 and 8 (the size of size_t) are read"),
                ))
            }
        }
        // The integer 1, in the writer's byte order, right after the line's newline.
        let at = self.pos;
        let one = self.take(4, "the binary integer 1 that gives the byte order")?;
        self.big_endian = match one {
            [1, 0, 0, 0] => false,
            [0, 0, 0, 1] => true,
            _ => {
                return Err(self.err(
                    at,
                    format!(
                        "expected the binary integer 1 (bytes 01 00 00 00 or 00 00 00 01) that \
                         gives the byte order, found bytes {}",
                        one.iter()
                            .map(|b| format!("{b:02x}"))
                            .collect::<Vec<_>>()
                            .join(" ")
                    ),
                ))
            }
        };
        self.expect_end()?;
        Ok(version)
    }

    /// Finds `\n$End<name>` followed by a line end or the end of the file, from the current
    /// section's keyword line on; returns the offset of the newline and moves past the match.
    fn find_end(&mut self, name: &str) -> Result<usize, IoError> {
        let end = format!("\n$End{name}");
        let needle = end.as_bytes();
        // From the keyword line's newline, so that an empty section is found too.
        let mut from = self.pos.saturating_sub(1);
        while let Some(k) = self.bytes[from..]
            .windows(needle.len())
            .position(|w| w == needle)
        {
            let at = from + k;
            let after = at + needle.len();
            if self
                .bytes
                .get(after)
                .is_none_or(|b| b.is_ascii_whitespace())
            {
                self.pos = after;
                return Ok(at);
            }
            from = at + 1;
        }
        Err(self.err(
            self.bytes.len(),
            format!("unexpected end of file: expected '$End{name}'"),
        ))
    }

    /// Skips a section whose layout is not needed.
    fn skip_section(&mut self, name: &str) -> Result<(), IoError> {
        self.find_end(name).map(|_| ())
    }

    /// A text section (after its keyword line, up to and including its `$End` line), with the
    /// number of its first line.
    fn text_section(&mut self, name: &str) -> Result<(usize, &'a str), IoError> {
        let start = self.pos;
        let first = self.line_at(start);
        self.find_end(name)?;
        let text = std::str::from_utf8(&self.bytes[start..self.pos])
            .map_err(|e| self.err(start + e.valid_up_to(), "invalid UTF-8 in a text section"))?;
        Ok((first, text))
    }

    /// 4.1 `$Entities`: the first physical tag of each entity.
    fn entities(&mut self, data: &mut MshData) -> Result<(), IoError> {
        let mut counts = [0u64; 4];
        for c in &mut counts {
            *c = self.size("the number of entities")?;
        }
        for (dim, &n) in counts.iter().enumerate() {
            for _ in 0..n {
                let tag = self.int("an entity tag")?;
                // Points have a position, the others a bounding box.
                let doubles = if dim == 0 { 3 } else { 6 };
                self.skip(doubles, 8, "coordinates of 8 bytes")?;
                let n_phys = self.size("the number of physical tags")?;
                if n_phys > 0 {
                    self.need(n_phys, 4, "physical tags of 4 bytes")?;
                    let physical = self.int("a physical tag")?;
                    data.set_entity_physical(dim as i32, tag, physical);
                    self.skip(n_phys - 1, 4, "physical tags of 4 bytes")?;
                }
                if dim > 0 {
                    let n_bounding = self.size("the number of bounding entities")?;
                    self.skip(n_bounding, 4, "bounding entity tags of 4 bytes")?;
                }
            }
        }
        self.expect_end()
    }

    /// A node tag (of `int` or `size_t` `width`) at the current position.
    fn node_tag(&mut self, width: usize, what: &str) -> Result<u64, IoError> {
        if width == 4 {
            let at = self.pos;
            let t = self.int(what)?;
            u64::try_from(t).map_err(|_| self.err(at, format!("negative node tag {t}")))
        } else {
            self.size(what)
        }
    }

    /// 2.2 `$Nodes`: a text count line, then `int` tag and 3 doubles per node.
    fn nodes22(&mut self, data: &mut MshData) -> Result<(), IoError> {
        let (l, text) = self.need_line("the number of nodes")?;
        let n = parse_count(text, "number of nodes", self.file, l)?;
        self.need(n as u64, 4 + 24, "nodes of 28 bytes")?;
        for _ in 0..n {
            let at = self.pos;
            let tag = self.node_tag(4, "a node tag")?;
            let p = self.point()?;
            data.add_node(tag, p).map_err(|m| self.err(at, m))?;
        }
        self.expect_end()
    }

    /// 4.1 `$Nodes`: blocks of tags followed by their coordinates.
    fn nodes41(&mut self, data: &mut MshData) -> Result<(), IoError> {
        let blocks = self.size("the number of node blocks")?;
        for _ in 0..3 {
            self.size("the node counts")?;
        }
        for _ in 0..blocks {
            let at = self.pos;
            let dim = self.int("the entity dimension of a node block")?;
            self.int("the entity tag of a node block")?;
            let parametric = self.int("the parametric flag of a node block")?;
            let n = self.size("the number of nodes of a block")?;
            if !(0..=3).contains(&dim) || !(0..=1).contains(&parametric) {
                return Err(self.err(at, node_block_range(dim, parametric)));
            }
            let width = 3 + if parametric == 1 { dim as usize } else { 0 };
            let record = self.size_t + 8 * width;
            self.need(n, record, &format!("nodes of {record} bytes"))?;
            // Bounded by the file's size just above.
            let mut tags = Vec::with_capacity(n as usize);
            for _ in 0..n {
                tags.push((self.pos, self.node_tag(self.size_t, "a node tag")?));
            }
            for (at, tag) in tags {
                let p = self.point()?;
                self.skip(width as u64 - 3, 8, "parametric coordinates of 8 bytes")?;
                data.add_node(tag, p).map_err(|m| self.err(at, m))?;
            }
        }
        self.expect_end()
    }

    /// The node count of element type `ty` read at `at`, or the error.
    fn element_nodes(&self, ty: i32, at: usize) -> Result<usize, IoError> {
        node_count(ty).map_err(|why| {
            self.err(
                at,
                format!(
                    "element type {ty} cannot be read from a binary file: {why}, so its size \
                     is unknown"
                ),
            )
        })
    }

    /// `nn` node tags of `width` bytes, as point indices.
    fn element(&mut self, nn: usize, width: usize, data: &MshData) -> Result<Vec<u32>, IoError> {
        (0..nn)
            .map(|_| {
                let at = self.pos;
                let tag = if width == 4 {
                    let t = self.int("a node tag")?;
                    // A negative tag is no node's.
                    u64::try_from(t).map_err(|_| format!("node {t} is not defined in $Nodes"))
                } else {
                    Ok(self.size("a node tag")?)
                };
                tag.and_then(|t| data.node(t)).map_err(|m| self.err(at, m))
            })
            .collect()
    }

    /// 2.2 `$Elements`: a text count line, then groups of elements of one type.
    fn elements22(&mut self, data: &mut MshData) -> Result<(), IoError> {
        let (l, text) = self.need_line("the number of elements")?;
        let total = parse_count(text, "number of elements", self.file, l)?;
        let mut left = total;
        while left > 0 {
            let at = self.pos;
            let ty = self.int("the type of an element group")?;
            let n = self.count_int("number of elements of a group")?;
            let ntags = self.count_int("number of tags of a group")?;
            if n > left {
                return Err(self.err(
                    at,
                    format!(
                        "an element group of {n} elements, but {left} of the section's {total} \
                         are left"
                    ),
                ));
            }
            let nn = self.element_nodes(ty, at)?;
            // number, tags, nodes: all 4-byte ints.
            let record = ntags.saturating_add(1 + nn).saturating_mul(4);
            self.need(
                n as u64,
                record,
                &format!("elements of {record} bytes (type {ty}, {ntags} tags)"),
            )?;
            let keep = corners(ty.into()).is_some();
            for _ in 0..n {
                if !keep {
                    self.pos += record;
                    continue;
                }
                self.int("an element number")?;
                let tag = if ntags > 0 {
                    self.int("a physical tag")?
                } else {
                    0
                };
                self.skip(ntags.saturating_sub(1) as u64, 4, "tags of 4 bytes")?;
                let nodes = self.element(nn, 4, data)?;
                data.keep(
                    ty.into(),
                    Pending {
                        line: self.section_line,
                        nodes,
                        tag,
                    },
                );
            }
            left -= n;
        }
        self.expect_end()
    }

    /// 4.1 `$Elements`: blocks of elements of one entity and type.
    fn elements41(&mut self, data: &mut MshData) -> Result<(), IoError> {
        let blocks = self.size("the number of element blocks")?;
        for _ in 0..3 {
            self.size("the element counts")?;
        }
        for _ in 0..blocks {
            let at = self.pos;
            self.int("the entity dimension of an element block")?;
            let entity = self.int("the entity tag of an element block")?;
            let ty = self.int("the element type of a block")?;
            let n = self.size("the number of elements of a block")?;
            let nn = self.element_nodes(ty, at)?;
            let record = self.size_t * (1 + nn);
            let what = format!("elements of {record} bytes (type {ty})");
            if corners(ty.into()).is_none() {
                self.skip(n, record, &what)?;
                continue;
            }
            self.need(n, record, &what)?;
            for _ in 0..n {
                self.size("an element tag")?;
                let nodes = self.element(nn, self.size_t, data)?;
                data.keep(
                    ty.into(),
                    Pending {
                        line: self.section_line,
                        nodes,
                        tag: entity,
                    },
                );
            }
        }
        self.expect_end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_counts_of_the_documented_types() {
        // The table of the gmsh reference manual (types 1-31, 92, 93).
        let documented = [
            (1, 2),
            (2, 3),
            (3, 4),
            (4, 4),
            (5, 8),
            (6, 6),
            (7, 5),
            (8, 3),
            (9, 6),
            (10, 9),
            (11, 10),
            (12, 27),
            (13, 18),
            (14, 14),
            (15, 1),
            (16, 8),
            (17, 20),
            (18, 15),
            (19, 13),
            (20, 9),
            (21, 10),
            (22, 12),
            (23, 15),
            (24, 15),
            (25, 21),
            (26, 4),
            (27, 5),
            (28, 6),
            (29, 20),
            (30, 35),
            (31, 56),
            (92, 64),
            (93, 125),
        ];
        for (ty, n) in documented {
            assert_eq!(node_count(ty), Ok(n), "type {ty}");
        }
        assert_eq!(node_count(66), Ok(11));
        assert_eq!(node_count(90), Ok(40));
        assert_eq!(node_count(110), Ok(550));
        assert_eq!(node_count(111), Ok(24));
        assert_eq!(node_count(117), Ok(78));
        for ty in [0, -1, 67, 76, 138, 200, i32::MAX, 34, 135] {
            assert!(node_count(ty).is_err(), "type {ty}");
        }
    }

    #[test]
    fn binary_header_detection() {
        assert!(is_binary(
            b"$MeshFormat\n4.1 1 8\n\x01\0\0\0\n$EndMeshFormat\n"
        ));
        assert!(is_binary(b"\xef\xbb\xbf\n$MeshFormat\r\n2.2 1 8\r\n"));
        assert!(!is_binary(b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"));
        assert!(!is_binary(
            b"$Comments\n$EndComments\n$MeshFormat\n4.1 1 8\n"
        ));
        assert!(!is_binary(b"$MeshFormat"));
        assert!(!is_binary(b""));
    }
}
