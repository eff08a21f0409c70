//! gmsh `.msh` files: read in versions 2.2 and 4.1, ASCII or binary; written in version 4.1
//! ASCII.
//!
//! gmsh is the most widely used open mesher in CFD, and its `.msh` is read by many solvers
//! (OpenFOAM's `gmshToFoam`, SU2 via converters, Code_Saturne, Fluidity...). Boundary
//! conditions travel as *physical groups*: a boundary marker here is a physical tag.
//!
//! Reading (surface triangles as facets, tetrahedra as a volume mesh):
//! - sections `$MeshFormat` (version `2.x` or `4.1`; gmsh 4.0 files are refused with a hint to
//!   save in 4.1 or 2.2), `$PhysicalNames` (optional; names of dimension 2 become marker
//!   names), `$Entities` (4.1), `$Nodes`, `$Elements`. Other sections (`$Periodic`,
//!   `$NodeData`, `$Comments`...) are skipped up to their `$End` line.
//! - file type 0 is read here, line by line; a file whose first section is a `$MeshFormat` of
//!   file type 1 is binary and read by [`crate::msh_binary`], which gives the same
//!   [`SurfaceFile`] as this reader gives for the ASCII file of the same mesh (the only
//!   difference: a binary facet's `line` is that of its `$Elements` keyword). [`read_msh`] and
//!   [`parse_msh_bytes`] take either; [`parse_msh`], which takes text, also reads a binary file
//!   whose bytes happen to be valid UTF-8.
//! - element types 2 (3-node triangle) and 3 (4-node quadrangle) become facets, type 4
//!   (4-node tetrahedron) tetrahedra; other types (points, lines, higher-order elements) are
//!   skipped.
//! - markers: in 2.2 an element's first tag is its physical tag (0 or no tags: marker 0); in
//!   4.1 an element block's entity is looked up in `$Entities` and its first physical tag is
//!   the marker (no physical tag, or no `$Entities`: 0). Tetrahedra get their region the same
//!   way. A surface group named `marker_<m>` with `m <= 0` (how this writer names them) is
//!   marker `m`.
//! - node tags may be any positive integers in any order; points are numbered in file order.
//!   Records are read one per line, as gmsh and every other writer we know write them.
//!
//! Writing (version 4.1): `$MeshFormat`, `$PhysicalNames`, `$Entities` with one surface entity
//! per face marker (tags 1, 2, ... in increasing marker order) and one volume entity per region
//! (likewise), each in a physical group of its own, `$Nodes` (one block, on the first volume
//! entity, tags 1..n), `$Elements` (a block of triangles, type 2, per surface entity, then a
//! block of tetrahedra, type 4, per volume entity; element tags 1.. in that order, so the
//! triangles come out grouped by marker). A marker `m > 0` is physical tag `m`, named by
//! [`TetMeshOut::marker_names`] or `marker_<m>`; a region `r` that is a positive integer is
//! volume physical tag `r`, named `region_<r>`. Markers `<= 0` and other regions (gmsh physical
//! tags must be positive) get the next free tags, and keep their value in their name
//! (`marker_0`, `region_0.5`).
//!
//! 2D meshes ([`write_msh_2d`]) are written the same way a dimension down: one curve entity
//! per edge marker (its edges as 2-node lines, type 1), one surface entity per region (its
//! triangles, type 2), the nodes on the first surface entity with z = 0.

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use crate::atomic::write_atomic;
use crate::msh_binary;
use crate::surface::{SurfaceFacet, SurfaceFile};
use crate::tetmesh::TetMeshOut;
use crate::text::{format_f64, parse_coord, parse_count, parse_int, shorten, write_f64};
use crate::triangle::TriangleMeshOut;
use crate::IoError;

/// Reads a gmsh `.msh` file (version 2.2 or 4.1, ASCII or binary).
pub fn read_msh(path: &Path) -> Result<SurfaceFile, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    parse_msh_bytes(&bytes, path)
}

/// Parses the bytes of a `.msh` file, ASCII or binary (version 2.2 or 4.1), choosing by the
/// file type in its `$MeshFormat` line; `file` names it in messages.
pub fn parse_msh_bytes(bytes: &[u8], file: &Path) -> Result<SurfaceFile, IoError> {
    if msh_binary::is_binary(bytes) {
        return msh_binary::parse(bytes, file);
    }
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let valid = e.valid_up_to();
        let line = 1 + bytes[..valid].iter().filter(|&&b| b == b'\n').count();
        IoError::parse(file, line, "file is not valid UTF-8 text")
    })?;
    parse_ascii(text, file)
}

/// The `.msh` versions read.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Version {
    V2,
    V41,
}

/// The version of a `$MeshFormat` line's first field, or the error for the versions not read.
pub(crate) fn parse_version(token: &str, file: &Path, line: usize) -> Result<Version, IoError> {
    match token {
        "4.1" => Ok(Version::V41),
        v if v == "2" || v.starts_with("2.") => Ok(Version::V2),
        v if v == "4" || v.starts_with("4.0") => Err(IoError::parse(
            file,
            line,
            format!("gmsh format {v} is not supported: save the mesh in format 4.1 or 2.2"),
        )),
        v => Err(IoError::parse(
            file,
            line,
            format!("unsupported gmsh format version '{}'", shorten(v)),
        )),
    }
}

/// Non-blank lines with their 1-based numbers.
pub(crate) struct Lines<'t> {
    inner: std::iter::Enumerate<crate::text::TextLines<'t>>,
    file: &'t Path,
    /// The number of the text's first line (1 for a whole file).
    first: usize,
    last: usize,
}

impl<'t> Lines<'t> {
    /// The lines of `text`, numbered from `first`.
    pub(crate) fn new(text: &'t str, file: &'t Path, first: usize) -> Self {
        Lines {
            inner: crate::text::text_lines(text).enumerate(),
            file,
            first,
            last: first + crate::text::text_lines(text).count().max(1) - 1,
        }
    }

    fn next_opt(&mut self) -> Option<(usize, &'t str)> {
        let first = self.first;
        self.inner
            .by_ref()
            .map(|(i, l)| (i + first, l.trim()))
            .find(|(_, l)| !l.is_empty())
    }

    fn next(&mut self, what: &str) -> Result<(usize, &'t str), IoError> {
        self.next_opt().ok_or_else(|| {
            IoError::parse(
                self.file,
                self.last,
                format!("unexpected end of file: expected {what}"),
            )
        })
    }

    /// The next record of a section: its line, its text and its fields. A section keyword
    /// instead means the section's count was larger than its records.
    fn record(&mut self, what: &str) -> Result<(usize, &'t str, Vec<&'t str>), IoError> {
        let (line, raw) = self.next(what)?;
        if raw.starts_with('$') {
            return Err(IoError::parse(
                self.file,
                line,
                format!(
                    "expected {what}, found '{}': fewer records than the section's count",
                    shorten(raw)
                ),
            ));
        }
        Ok((line, raw, raw.split_whitespace().collect()))
    }

    /// The next record, split into exactly `n` fields (or at least `n` with `at_least`).
    fn fields(
        &mut self,
        what: &str,
        n: usize,
        at_least: bool,
    ) -> Result<(usize, Vec<&'t str>), IoError> {
        let (line, _, toks) = self.record(what)?;
        if toks.len() < n || (!at_least && toks.len() > n) {
            return Err(IoError::parse(
                self.file,
                line,
                format!(
                    "expected {}{n} fields for {what}, found {}",
                    if at_least { "at least " } else { "" },
                    toks.len()
                ),
            ));
        }
        Ok((line, toks))
    }

    fn expect_end(&mut self, section: &str) -> Result<(), IoError> {
        let end = format!("$End{section}");
        let (line, raw) = self.next(&format!("'{end}'"))?;
        if raw != end {
            return Err(IoError::parse(
                self.file,
                line,
                format!("expected '{end}', found '{}'", shorten(raw)),
            ));
        }
        Ok(())
    }
}

/// An element read before its markers are known: which entity (4.1) or physical tag (2.2).
pub(crate) struct Pending {
    pub(crate) line: usize,
    pub(crate) nodes: Vec<u32>,
    /// 2.2: the physical tag. 4.1: the entity tag.
    pub(crate) tag: i32,
}

/// The number of corners of the element types read: 2 (triangle) and 3 (quadrangle) become
/// facets, 4 (tetrahedron) tetrahedra; `None` for the types skipped.
pub(crate) fn corners(ty: i64) -> Option<usize> {
    match ty {
        2 => Some(3),
        3 | 4 => Some(4),
        _ => None,
    }
}

/// What the ASCII and the binary readers collect, turned into a [`SurfaceFile`] by
/// [`MshData::finish`]. The methods' errors are messages without a place: each reader adds
/// its own (a line, a byte offset).
#[derive(Default)]
pub(crate) struct MshData {
    points: Vec<[f64; 3]>,
    node_index: HashMap<u64, u32>,
    marker_names: Vec<(i32, String)>,
    /// (dim, entity tag) -> first physical tag (4.1).
    entity_physical: HashMap<(i32, i32), i32>,
    facets: Vec<Pending>,
    tets: Vec<Pending>,
}

impl MshData {
    /// Adds node `tag` at `p` (the next point); an error if the tag is already taken.
    pub(crate) fn add_node(&mut self, tag: u64, p: [f64; 3]) -> Result<(), String> {
        if self
            .node_index
            .insert(tag, self.points.len() as u32)
            .is_some()
        {
            return Err(format!("node tag {tag} is defined twice"));
        }
        self.points.push(p);
        Ok(())
    }

    /// The point index of node `tag`.
    pub(crate) fn node(&self, tag: u64) -> Result<u32, String> {
        self.node_index
            .get(&tag)
            .copied()
            .ok_or_else(|| format!("node {tag} is not defined in $Nodes"))
    }

    /// Records that entity `(dim, tag)` (4.1) is in physical group `physical` (its first).
    pub(crate) fn set_entity_physical(&mut self, dim: i32, tag: i32, physical: i32) {
        self.entity_physical.insert((dim, tag), physical);
    }

    /// Keeps an element of type `ty` (one [`corners`] knows).
    pub(crate) fn keep(&mut self, ty: i64, p: Pending) {
        match ty {
            4 => self.tets.push(p),
            _ => self.facets.push(p),
        }
    }

    /// The surface file: markers looked up (4.1: element entity -> first physical tag of the
    /// entity, 0 if none; 2.2: the element's physical tag), names sorted by marker.
    pub(crate) fn finish(self, version: Version) -> SurfaceFile {
        let MshData {
            points,
            mut marker_names,
            entity_physical,
            facets,
            tets,
            ..
        } = self;
        // delmesh writes a marker m <= 0 as the next free physical tag, named `marker_<m>`
        // (gmsh's tags are positive): read back as m, so that its files round-trip.
        let renamed: HashMap<i32, i32> = marker_names
            .iter()
            .filter_map(|(tag, name)| {
                let m: i32 = name.strip_prefix("marker_")?.parse().ok()?;
                (m <= 0 && m != *tag).then_some((*tag, m))
            })
            .collect();
        let physical = |dim: i32, tag: i32| match version {
            Version::V2 => tag,
            Version::V41 => entity_physical.get(&(dim, tag)).copied().unwrap_or(0),
        };
        let marker = |dim: i32, tag: i32| {
            let t = physical(dim, tag);
            match dim {
                2 => renamed.get(&t).copied().unwrap_or(t),
                _ => t,
            }
        };
        for (tag, _) in &mut marker_names {
            *tag = renamed.get(tag).copied().unwrap_or(*tag);
        }
        marker_names.sort();
        SurfaceFile {
            points,
            facets: facets
                .into_iter()
                .map(|p| SurfaceFacet {
                    marker: marker(2, p.tag),
                    polygons: vec![p.nodes],
                    holes: Vec::new(),
                    line: p.line,
                })
                .collect(),
            tetrahedron_regions: tets.iter().map(|p| marker(3, p.tag)).collect(),
            tetrahedra: tets
                .iter()
                .map(|p| [p.nodes[0], p.nodes[1], p.nodes[2], p.nodes[3]])
                .collect(),
            marker_names,
            first_index: 1,
            ..SurfaceFile::default()
        }
    }
}

/// The body of a `$PhysicalNames` section (the line after the keyword to `$EndPhysicalNames`),
/// which binary files also write as text: names of dimension 2 become marker names.
pub(crate) fn parse_physical_names(ls: &mut Lines<'_>, data: &mut MshData) -> Result<(), IoError> {
    let file = ls.file;
    let (l, toks) = ls.fields("the number of physical names", 1, false)?;
    let n = parse_count(toks[0], "number of physical names", file, l)?;
    for _ in 0..n {
        let what = "a physical name '<dim> <tag> \"name\"'";
        let (l, raw, toks) = ls.record(what)?;
        if toks.len() < 3 {
            return Err(IoError::parse(
                file,
                l,
                format!(
                    "expected at least 3 fields for {what}, found {}",
                    toks.len()
                ),
            ));
        }
        let dim: i32 = parse_int(toks[0], "dimension", file, l)?;
        let tag: i32 = parse_int(toks[1], "physical tag", file, l)?;
        // The name is everything between the first and the last quote, spaces kept.
        let name = match (raw.find('"'), raw.rfind('"')) {
            (Some(a), Some(b)) if b > a && raw[..a].split_whitespace().count() == 2 => {
                &raw[a + 1..b]
            }
            _ => {
                return Err(IoError::parse(
                    file,
                    l,
                    format!("physical name in '{}' is not quoted", shorten(raw)),
                ))
            }
        };
        if dim == 2 {
            data.marker_names.push((tag, name.to_string()));
        }
    }
    ls.expect_end("PhysicalNames")
}

/// Parses the text of a `.msh` file (version 2.2 or 4.1); `file` names it in messages. A
/// binary file whose bytes happen to be valid UTF-8 is read as binary (see
/// [`parse_msh_bytes`], which takes any bytes).
pub fn parse_msh(text: &str, file: &Path) -> Result<SurfaceFile, IoError> {
    if msh_binary::is_binary(text.as_bytes()) {
        return msh_binary::parse(text.as_bytes(), file);
    }
    parse_ascii(text, file)
}

fn parse_ascii(text: &str, file: &Path) -> Result<SurfaceFile, IoError> {
    let err = |line: usize, message: String| IoError::parse(file, line, message);
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut ls = Lines::new(text, file, 1);
    let mut version = None;
    let mut data = MshData::default();

    while let Some((line, raw)) = ls.next_opt() {
        let need_version =
            |v: Option<Version>| v.ok_or_else(|| err(line, format!("{raw} before $MeshFormat")));
        match raw {
            "$MeshFormat" => {
                let (l, toks) =
                    ls.fields("the format line '<version> <file type> <size>'", 3, false)?;
                if toks[1] != "0" {
                    return Err(if toks[1] == "1" {
                        // A binary file is recognised by its first section (`is_binary`).
                        err(
                            l,
                            "binary file type in a $MeshFormat that is not the first section: \
                             a binary .msh file must begin with $MeshFormat"
                                .into(),
                        )
                    } else {
                        err(l, format!("unknown file type '{}'", shorten(toks[1])))
                    });
                }
                version = Some(parse_version(toks[0], file, l)?);
                ls.expect_end("MeshFormat")?;
            }
            "$PhysicalNames" => parse_physical_names(&mut ls, &mut data)?,
            "$Entities" => {
                if need_version(version)? != Version::V41 {
                    return Err(err(line, "$Entities in a version 2 file".into()));
                }
                let (l, toks) = ls.fields("the entity counts", 4, false)?;
                let mut counts = [0usize; 4];
                for (c, t) in counts.iter_mut().zip(&toks) {
                    *c = parse_count(t, "number of entities", file, l)?;
                }
                for (dim, &n) in counts.iter().enumerate() {
                    // Points have a position, the others a bounding box.
                    let skip = if dim == 0 { 3 } else { 6 };
                    for _ in 0..n {
                        let (l, toks) = ls.fields("an entity", 2 + skip, true)?;
                        let tag: i32 = parse_int(toks[0], "entity tag", file, l)?;
                        let n_phys =
                            parse_count(toks[1 + skip], "number of physical tags", file, l)?;
                        if n_phys > 0 {
                            let t = toks.get(2 + skip).ok_or_else(|| {
                                err(l, "missing physical tag of the entity".into())
                            })?;
                            let physical = parse_int(t, "physical tag", file, l)?;
                            data.set_entity_physical(dim as i32, tag, physical);
                        }
                    }
                }
                ls.expect_end("Entities")?;
            }
            "$Nodes" => {
                let v = need_version(version)?;
                let add = |data: &mut MshData, l: usize, tag: &str, xyz: &[&str]| {
                    let tag: u64 = parse_int(tag, "node tag", file, l)?;
                    let p = [
                        parse_coord(xyz[0], "x", file, l)?,
                        parse_coord(xyz[1], "y", file, l)?,
                        parse_coord(xyz[2], "z", file, l)?,
                    ];
                    data.add_node(tag, p).map_err(|m| err(l, m))
                };
                if v == Version::V2 {
                    let (l, toks) = ls.fields("the number of nodes", 1, false)?;
                    let n = parse_count(toks[0], "number of nodes", file, l)?;
                    for _ in 0..n {
                        let (l, toks) = ls.fields("a node '<tag> <x> <y> <z>'", 4, false)?;
                        add(&mut data, l, toks[0], &toks[1..])?;
                    }
                } else {
                    let (l, toks) = ls.fields("the node counts", 4, false)?;
                    let blocks = parse_count(toks[0], "number of node blocks", file, l)?;
                    for _ in 0..blocks {
                        let (l, toks) = ls.fields(
                            "a node block '<dim> <entity> <parametric> <#nodes>'",
                            4,
                            false,
                        )?;
                        let dim = parse_count(toks[0], "entity dimension", file, l)?;
                        let parametric = parse_count(toks[2], "parametric flag", file, l)?;
                        let n = parse_count(toks[3], "number of nodes", file, l)?;
                        if dim > 3 || parametric > 1 {
                            return Err(err(l, node_block_range(dim, parametric)));
                        }
                        let mut tags = Vec::with_capacity(n.min(text.len() / 2));
                        for _ in 0..n {
                            let (l, toks) = ls.fields("a node tag", 1, false)?;
                            tags.push((l, toks[0]));
                        }
                        let width = 3 + if parametric == 1 { dim } else { 0 };
                        for (_, tag) in tags {
                            let (l, toks) = ls.fields("node coordinates", width, false)?;
                            add(&mut data, l, tag, &toks)?;
                        }
                    }
                }
                ls.expect_end("Nodes")?;
            }
            "$Elements" => {
                let v = need_version(version)?;
                let lookup = |data: &MshData, l: usize, toks: &[&str]| {
                    toks.iter()
                        .map(|t| {
                            let tag: u64 = parse_int(t, "node tag", file, l)?;
                            data.node(tag).map_err(|m| err(l, m))
                        })
                        .collect::<Result<Vec<u32>, IoError>>()
                };
                if v == Version::V2 {
                    let (l, toks) = ls.fields("the number of elements", 1, false)?;
                    let n = parse_count(toks[0], "number of elements", file, l)?;
                    for _ in 0..n {
                        let (l, toks) =
                            ls.fields("an element '<tag> <type> <#tags> <tags> <nodes>'", 3, true)?;
                        let ty: i64 = parse_int(toks[1], "element type", file, l)?;
                        let ntags = parse_count(toks[2], "number of tags", file, l)?;
                        let Some(nn) = corners(ty) else { continue };
                        if ntags > toks.len() || toks.len() != 3 + ntags + nn {
                            return Err(err(
                                l,
                                format!(
                                    "expected {} fields for an element of type {ty} with \
                                     {ntags} tags, found {}",
                                    3usize.saturating_add(ntags).saturating_add(nn),
                                    toks.len()
                                ),
                            ));
                        }
                        let tag = match ntags {
                            0 => 0,
                            _ => parse_int(toks[3], "physical tag", file, l)?,
                        };
                        let nodes = lookup(&data, l, &toks[3 + ntags..])?;
                        data.keep(
                            ty,
                            Pending {
                                line: l,
                                nodes,
                                tag,
                            },
                        );
                    }
                } else {
                    let (l, toks) = ls.fields("the element counts", 4, false)?;
                    let blocks = parse_count(toks[0], "number of element blocks", file, l)?;
                    for _ in 0..blocks {
                        let (l, toks) = ls.fields(
                            "an element block '<dim> <entity> <type> <#elements>'",
                            4,
                            false,
                        )?;
                        let entity: i32 = parse_int(toks[1], "entity tag", file, l)?;
                        let ty: i64 = parse_int(toks[2], "element type", file, l)?;
                        let n = parse_count(toks[3], "number of elements", file, l)?;
                        let nn = corners(ty);
                        for _ in 0..n {
                            let (l, toks) = ls.fields("an element", 1, true)?;
                            let Some(nn) = nn else { continue };
                            if toks.len() != 1 + nn {
                                return Err(err(
                                    l,
                                    format!(
                                        "expected {} fields for an element of type {ty}, found {}",
                                        1 + nn,
                                        toks.len()
                                    ),
                                ));
                            }
                            let nodes = lookup(&data, l, &toks[1..])?;
                            data.keep(
                                ty,
                                Pending {
                                    line: l,
                                    nodes,
                                    tag: entity,
                                },
                            );
                        }
                    }
                }
                ls.expect_end("Elements")?;
            }
            s if s.starts_with("$NOD") || s.starts_with("$ELM") => {
                return Err(err(
                    line,
                    "gmsh format 1 is not supported: save the mesh in format 4.1 or 2.2".into(),
                ));
            }
            s if s.starts_with('$') && !s.starts_with("$End") => {
                let end = format!("$End{}", &s[1..]);
                loop {
                    let (_, l) = ls.next(&format!("'{end}'"))?;
                    if l == end {
                        break;
                    }
                }
            }
            other => return Err(err(line, not_a_section(other))),
        }
    }
    let Some(version) = version else {
        return Err(err(
            ls.last,
            "no $MeshFormat section: not a gmsh .msh file".into(),
        ));
    };
    Ok(data.finish(version))
}

/// The message for a 4.1 node block whose dimension or parametric flag is out of range.
pub(crate) fn node_block_range(
    dim: impl std::fmt::Display,
    parametric: impl std::fmt::Display,
) -> String {
    format!("entity dimension {dim} or parametric flag {parametric} out of range (0-3, 0-1)")
}

/// The message for a line where a section keyword was expected.
pub(crate) fn not_a_section(found: &str) -> String {
    format!(
        "expected a section such as $MeshFormat, $Nodes or $Elements, found '{}'",
        shorten(found)
    )
}

/// Gives each distinct key (a marker, a region) a positive physical tag: its own value when
/// that is a positive integer (`own`), else the next tag after the largest such value.
/// `None` if the free tags run out (values up to `i32::MAX` already taken).
fn physical_tags(own: &[Option<i32>]) -> Option<Vec<i32>> {
    let mut next = own.iter().flatten().copied().max().unwrap_or(0);
    own.iter()
        .map(|o| match o {
            Some(t) => Some(*t),
            None => {
                next = next.checked_add(1)?;
                Some(next)
            }
        })
        .collect()
}

/// The physical tags of boundary markers (a marker `m > 0` is tag `m`) and of regions (a
/// positive integer region is its own tag); `None` when no free tag is left.
fn group_tags(markers: &[i32], regions: &[f64]) -> Option<(Vec<i32>, Vec<i32>)> {
    let markers = physical_tags(
        &markers
            .iter()
            .map(|&m| (m > 0).then_some(m))
            .collect::<Vec<_>>(),
    )?;
    let regions = physical_tags(
        &regions
            .iter()
            .map(|&r| {
                (r.fract() == 0.0 && r >= 1.0 && r <= f64::from(i32::MAX)).then_some(r as i32)
            })
            .collect::<Vec<_>>(),
    )?;
    Some((markers, regions))
}

/// The error of [`group_tags`]'s `None`.
fn no_free_tag(path: &Path) -> IoError {
    IoError::invalid(
        path,
        "no free physical tag is left for the markers <= 0 or non-integer regions (tags up to \
         2147483647 are taken)",
    )
}

/// One line of `$Entities`: the entity's tag, bounding box and physical group (if any), with
/// no bounding entities.
fn entity_line(
    w: &mut dyn Write,
    tag: usize,
    b: [f64; 6],
    phys: Option<i32>,
) -> std::io::Result<()> {
    write!(w, "{tag}")?;
    for x in b {
        w.write_all(b" ")?;
        write_f64(w, x)?;
    }
    match phys {
        Some(p) => writeln!(w, " 1 {p} 0"),
        None => writeln!(w, " 0 0"),
    }
}

/// Bounding box of some points (of `dim` coordinates each in `coords`; z = 0 in 2D), as gmsh's
/// `$Entities` wants it.
fn bbox(coords: &[f64], dim: usize, nodes: impl Iterator<Item = u32>) -> [f64; 6] {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for v in nodes {
        let p = &coords[dim * v as usize..][..dim];
        for d in 0..3 {
            let x = p.get(d).copied().unwrap_or(0.0);
            b[d] = b[d].min(x);
            b[3 + d] = b[3 + d].max(x);
        }
    }
    if b[0] > b[3] {
        [0.0; 6]
    } else {
        b
    }
}

/// Writes a tetrahedral mesh as a gmsh 4.1 ASCII `.msh` file, with physical groups for face
/// markers and regions (see the module documentation for the numbering). Atomic.
pub fn write_msh(path: &Path, mesh: &TetMeshOut<'_>) -> Result<(), IoError> {
    mesh.check(path)?;
    write_simplices(
        path,
        &Simplices {
            dim: 3,
            coords: mesh.coords.as_flattened(),
            boundary: mesh.faces.as_flattened(),
            markers: mesh.face_markers,
            cells: mesh.tets.as_flattened(),
            region: &|k| mesh.region(k),
            marker_name: &|m| mesh.marker_name(m),
        },
    )
}

/// Writes a 2D triangle mesh as a gmsh 4.1 ASCII `.msh` file: a curve entity and physical group
/// (dimension 1) per edge marker, a surface entity and physical group (dimension 2) per region
/// (the triangles' attributes; 0 without), z = 0 (see the module documentation for the tags
/// and names). Point markers are not written. Atomic.
pub fn write_msh_2d(path: &Path, mesh: &TriangleMeshOut<'_>) -> Result<(), IoError> {
    mesh.check(path)?;
    write_simplices(
        path,
        &Simplices {
            dim: 2,
            coords: mesh.coords,
            boundary: mesh.edges.as_flattened(),
            markers: mesh.edge_markers,
            cells: mesh.triangles,
            region: &|k| mesh.cell_attributes.map_or(0.0, |a| a[k]),
            marker_name: &|m| format!("marker_{m}"),
        },
    )
}

/// A checked mesh as both writers hand it over: `dim` (2 or 3) coordinates per point, boundary
/// simplices of `dim` points with a marker each, cells of `dim + 1` points with a region each.
struct Simplices<'a> {
    dim: usize,
    coords: &'a [f64],
    boundary: &'a [u32],
    markers: &'a [i32],
    cells: &'a [u32],
    region: &'a dyn Fn(usize) -> f64,
    marker_name: &'a dyn Fn(i32) -> String,
}

/// The gmsh file of `mesh`: one entity of dimension `dim - 1` per distinct marker (tags 1, 2,
/// ... in increasing order), one of dimension `dim` per distinct region (regions compared with
/// -0 == 0), each in a physical group of its own; the nodes on the first cell entity.
fn write_simplices(path: &Path, mesh: &Simplices<'_>) -> Result<(), IoError> {
    let dim = mesh.dim;
    let n_cells = mesh.cells.len() / (dim + 1);
    let region = |k: usize| (mesh.region)(k) + 0.0;
    let mut markers = mesh.markers.to_vec();
    markers.sort_unstable();
    markers.dedup();
    let mut regions: Vec<f64> = (0..n_cells).map(region).collect();
    regions.sort_by(f64::total_cmp);
    regions.dedup();
    let (marker_tags, region_tags) =
        group_tags(&markers, &regions).ok_or_else(|| no_free_tag(path))?;
    // Element indices per entity, in input order.
    let mut boundary_of = vec![Vec::new(); markers.len()];
    for (k, m) in mesh.markers.iter().enumerate() {
        boundary_of[markers.binary_search(m).expect("a marker of the list")].push(k);
    }
    let mut cells_of = vec![Vec::new(); regions.len()];
    for k in 0..n_cells {
        let r = region(k);
        cells_of[regions
            .binary_search_by(|x| x.total_cmp(&r))
            .expect("a region of the list")]
        .push(k);
    }
    let coords = mesh.coords;
    let np = coords.len() / dim;
    write_atomic(path, |w| {
        (|| -> std::io::Result<()> {
            writeln!(w, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;
            writeln!(w, "$PhysicalNames\n{}", markers.len() + regions.len())?;
            for (&m, t) in markers.iter().zip(&marker_tags) {
                writeln!(w, "{} {t} \"{}\"", dim - 1, (mesh.marker_name)(m))?;
            }
            for (&r, t) in regions.iter().zip(&region_tags) {
                writeln!(w, "{dim} {t} \"region_{}\"", format_f64(r))?;
            }
            writeln!(w, "$EndPhysicalNames")?;
            // Without cells, one cell entity without physical group still holds the nodes.
            let mut counts = [0; 4];
            counts[dim - 1] = markers.len();
            counts[dim] = regions.len().max(1);
            let [c0, c1, c2, c3] = counts;
            writeln!(w, "$Entities\n{c0} {c1} {c2} {c3}")?;
            for (s, elements) in boundary_of.iter().enumerate() {
                let nodes = elements
                    .iter()
                    .flat_map(|&k| &mesh.boundary[dim * k..][..dim]);
                let b = bbox(coords, dim, nodes.copied());
                entity_line(w, s + 1, b, Some(marker_tags[s]))?;
            }
            if regions.is_empty() {
                entity_line(w, 1, bbox(coords, dim, 0..np as u32), None)?;
            }
            for (v, elements) in cells_of.iter().enumerate() {
                let nodes = elements
                    .iter()
                    .flat_map(|&k| &mesh.cells[(dim + 1) * k..][..dim + 1]);
                let b = bbox(coords, dim, nodes.copied());
                entity_line(w, v + 1, b, Some(region_tags[v]))?;
            }
            writeln!(w, "$EndEntities")?;

            writeln!(w, "$Nodes")?;
            if np == 0 {
                writeln!(w, "0 0 0 0")?;
            } else {
                writeln!(w, "1 {np} 1 {np}\n{dim} 1 0 {np}")?;
                for i in 1..=np {
                    writeln!(w, "{i}")?;
                }
                for p in coords.chunks_exact(dim) {
                    write_f64(w, p[0])?;
                    for &c in &p[1..] {
                        w.write_all(b" ")?;
                        write_f64(w, c)?;
                    }
                    w.write_all(if dim == 2 { b" 0\n" } else { b"\n" })?;
                }
            }
            writeln!(w, "$EndNodes")?;

            // Element types: line 1, triangle 2, tetrahedron 4.
            let type_of = |points: usize| [0, 0, 1, 2, 4][points];
            let n_elements = mesh.markers.len() + n_cells;
            let n_blocks = markers.len() + regions.len();
            writeln!(
                w,
                "$Elements\n{n_blocks} {n_elements} {} {n_elements}",
                u8::from(n_elements > 0)
            )?;
            let mut tag = 0u64;
            // Per block: its entity's dimension, its elements, their nodes (flat) and how many
            // each has.
            let blocks = boundary_of
                .iter()
                .map(|e| (dim - 1, e, mesh.boundary, dim))
                .chain(cells_of.iter().map(|e| (dim, e, mesh.cells, dim + 1)));
            let mut entity = [0usize; 4];
            for (d, elements, nodes, per) in blocks {
                entity[d] += 1;
                writeln!(w, "{d} {} {} {}", entity[d], type_of(per), elements.len())?;
                for &k in elements {
                    tag += 1;
                    write!(w, "{tag}")?;
                    for &v in &nodes[per * k..][..per] {
                        write!(w, " {}", u64::from(v) + 1)?;
                    }
                    w.write_all(b"\n")?;
                }
            }
            writeln!(w, "$EndElements")
        })()
        .map_err(|e| IoError::io(path, e))
    })
}
