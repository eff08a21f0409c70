//! Medit / INRIA `.mesh` files (ASCII), read and written: the format of the INRIA tools
//! (Medit, MMG, which adapts meshes for CFD) and one that gmsh and many solvers read.
//!
//! A file is a sequence of keywords and free-format numbers (line breaks do not matter; `#`
//! starts a comment): `MeshVersionFormatted 1|2`, `Dimension 3`, then sections, each a keyword,
//! a count and that many records, and `End`. Indices are 1-based and every record ends with an
//! integer reference.
//! - read: `Vertices` (`x y z ref`: the refs become point markers), `Triangles` (`a b c ref`)
//!   and `Quadrilaterals` (`a b c d ref`) as facets whose marker is the ref, and `Tetrahedra`
//!   (`a b c d ref`, the ref being the region), so a volume mesh can be read back. Other
//!   standard sections (`Edges`, `Corners`, `Ridges`, `Required*`, `Normals`, `Tangents`,
//!   `Hexahedra`, `Prisms`, ...) are skipped by their known record sizes; an unknown keyword is an
//!   error, since its size cannot be known. Keywords are matched without regard to case.
//! - write: `MeshVersionFormatted 2`, `Dimension 3`, `Vertices` (point markers as refs, 0
//!   without), `Triangles` (face markers as refs), `Tetrahedra` (regions as refs, which must
//!   be integers), `End`.
//!
//! Binary `.meshb` files are not read.

use std::io::Write;
use std::path::Path;

use crate::atomic::write_atomic;
use crate::surface::{SurfaceFacet, SurfaceFile};
use crate::tetmesh::TetMeshOut;
use crate::text::{
    parse_coord, parse_count, parse_int, point_ref, read_text, shorten, write_f64, Scanner,
};
use crate::IoError;

/// Reads a Medit `.mesh` file.
pub fn read_medit(path: &Path) -> Result<SurfaceFile, IoError> {
    let text = read_text(path)?;
    parse_medit(&text, path)
}

/// Sections skipped when reading, with the number of values per record.
const SKIPPED: &[(&str, usize)] = &[
    ("Edges", 3),
    ("Corners", 1),
    ("Ridges", 1),
    ("RequiredVertices", 1),
    ("RequiredEdges", 1),
    ("RequiredTriangles", 1),
    ("RequiredQuadrilaterals", 1),
    ("RequiredTetrahedra", 1),
    ("Hexahedra", 9),
    ("Prisms", 7),
    ("Pyramids", 6),
    ("Normals", 3),
    ("Tangents", 3),
    ("NormalAtVertices", 2),
    ("NormalAtTriangleVertices", 3),
    ("NormalAtQuadrilateralVertices", 3),
    ("TangentAtVertices", 2),
    ("TangentAtEdges", 3),
];

/// Reads tokens with line numbers and turns running out into an "unexpected end of file".
struct Reader<'t> {
    sc: Scanner<'t>,
    file: &'t Path,
}

impl<'t> Reader<'t> {
    fn token(&mut self, what: &str) -> Result<(usize, &'t str), IoError> {
        let line = self.sc.line();
        self.sc.next_token().ok_or_else(|| {
            IoError::parse(
                self.file,
                line,
                format!("unexpected end of file: expected {what}"),
            )
        })
    }

    fn count(&mut self, what: &str) -> Result<usize, IoError> {
        let (line, t) = self.token(what)?;
        parse_count(t, what, self.file, line)
    }

    fn int<T: std::str::FromStr>(&mut self, what: &str) -> Result<(usize, T), IoError> {
        let (line, t) = self.token(what)?;
        Ok((line, parse_int(t, what, self.file, line)?))
    }

    fn coord(&mut self, axis: &str) -> Result<f64, IoError> {
        let (line, t) = self.token(&format!("the {axis} coordinate"))?;
        parse_coord(t, axis, self.file, line)
    }

    /// `n` point references (1-based) and the record's reference; returns the first line too.
    fn record<const N: usize>(
        &mut self,
        what: &str,
        n_points: usize,
    ) -> Result<(usize, [u32; N], i32), IoError> {
        let mut v = [0u32; N];
        let mut first = 0;
        for (j, slot) in v.iter_mut().enumerate() {
            let (line, raw) = self.int::<i64>(&format!("corner {} of a {what}", j + 1))?;
            if j == 0 {
                first = line;
            }
            *slot = point_ref(raw, 1, n_points, self.file, line)?;
        }
        let (_, r) = self.int::<i32>(&format!("reference of a {what}"))?;
        Ok((first, v, r))
    }
}

/// Parses the text of a Medit `.mesh` file; `file` is only used in error messages.
pub fn parse_medit(text: &str, file: &Path) -> Result<SurfaceFile, IoError> {
    let mut rd = Reader {
        sc: Scanner::new(text, true),
        file,
    };
    let mut out = SurfaceFile {
        first_index: 1,
        ..SurfaceFile::default()
    };
    let mut markers = Vec::new();
    let mut have_vertices = false;
    while let Some((line, key)) = rd.sc.next_token() {
        let is = |k: &str| key.eq_ignore_ascii_case(k);
        let cap = |n: usize| n.min(text.len() / 8);
        if is("End") {
            break;
        } else if is("MeshVersionFormatted") {
            let (l, v) = rd.int::<i64>("mesh version")?;
            if !(1..=4).contains(&v) {
                return Err(IoError::parse(file, l, format!("unknown mesh version {v}")));
            }
        } else if is("Dimension") {
            let (l, d) = rd.int::<i64>("dimension")?;
            if d != 3 {
                return Err(IoError::parse(
                    file,
                    l,
                    format!("Dimension {d}: only 3D Medit meshes are read"),
                ));
            }
        } else if is("Vertices") {
            if have_vertices {
                return Err(IoError::parse(file, line, "a second Vertices section"));
            }
            have_vertices = true;
            let n = rd.count("number of vertices")?;
            out.points.reserve(cap(n));
            for _ in 0..n {
                out.points
                    .push([rd.coord("x")?, rd.coord("y")?, rd.coord("z")?]);
                markers.push(rd.int::<i32>("reference of a vertex")?.1);
            }
        } else if is("Triangles") || is("Quadrilaterals") {
            let n = rd.count("number of elements")?;
            out.facets.reserve(cap(n));
            let np = out.points.len();
            for _ in 0..n {
                let (l, polygon, marker) = if is("Triangles") {
                    let (l, v, r) = rd.record::<3>("triangle", np)?;
                    (l, v.to_vec(), r)
                } else {
                    let (l, v, r) = rd.record::<4>("quadrilateral", np)?;
                    (l, v.to_vec(), r)
                };
                out.facets.push(SurfaceFacet {
                    polygons: vec![polygon],
                    holes: Vec::new(),
                    marker,
                    line: l,
                });
            }
        } else if is("Tetrahedra") {
            let n = rd.count("number of tetrahedra")?;
            out.tetrahedra.reserve(cap(n));
            let np = out.points.len();
            for _ in 0..n {
                let (_, v, r) = rd.record::<4>("tetrahedron", np)?;
                out.tetrahedra.push(v);
                out.tetrahedron_regions.push(r);
            }
        } else if let Some(&(name, width)) = SKIPPED.iter().find(|(k, _)| is(k)) {
            let n = rd.count(&format!("number of {name}"))?;
            for _ in 0..n {
                for _ in 0..width {
                    rd.token(&format!("a value of the {name} section"))?;
                }
            }
        } else {
            return Err(IoError::parse(
                file,
                line,
                format!("unknown Medit keyword '{}'", shorten(key)),
            ));
        }
    }
    out.point_markers = have_vertices.then_some(markers);
    Ok(out)
}

/// Writes a tetrahedral mesh as a Medit `.mesh` file (1-based; point markers, face markers and
/// regions as references). Regions must be integers. Atomic.
pub fn write_medit(path: &Path, mesh: &TetMeshOut<'_>) -> Result<(), IoError> {
    mesh.check(path)?;
    let regions = mesh.integer_regions(path)?;
    write_atomic(path, |w| {
        medit_body(w, mesh, &regions).map_err(|e| IoError::io(path, e))
    })
}

fn medit_body(w: &mut dyn Write, mesh: &TetMeshOut<'_>, regions: &[i32]) -> std::io::Result<()> {
    writeln!(w, "MeshVersionFormatted 2\n\nDimension 3\n")?;
    writeln!(w, "Vertices\n{}", mesh.coords.len())?;
    for (i, p) in mesh.coords.iter().enumerate() {
        for &c in p {
            write_f64(w, c)?;
            w.write_all(b" ")?;
        }
        writeln!(w, "{}", mesh.point_markers.map_or(0, |m| m[i]))?;
    }
    if !mesh.faces.is_empty() {
        writeln!(w, "\nTriangles\n{}", mesh.faces.len())?;
        for (t, m) in mesh.faces.iter().zip(mesh.face_markers) {
            writeln!(
                w,
                "{} {} {} {m}",
                u64::from(t[0]) + 1,
                u64::from(t[1]) + 1,
                u64::from(t[2]) + 1
            )?;
        }
    }
    if !mesh.tets.is_empty() {
        writeln!(w, "\nTetrahedra\n{}", mesh.tets.len())?;
        for (t, r) in mesh.tets.iter().zip(regions) {
            writeln!(
                w,
                "{} {} {} {} {r}",
                u64::from(t[0]) + 1,
                u64::from(t[1]) + 1,
                u64::from(t[2]) + 1,
                u64::from(t[3]) + 1
            )?;
        }
    }
    writeln!(w, "\nEnd")
}
