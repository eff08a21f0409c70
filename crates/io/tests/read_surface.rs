//! Tests of the surface readers `.off`, `.stl`, `.obj`, `.ply`, Medit `.mesh` and gmsh `.msh`: small
//! hand-written files in the formats' variants, files written by gmsh 4.15 (`tests/data`), the
//! errors naming the line (or byte), round trips, and the choice of reader by extension.

use std::path::{Path, PathBuf};

use delmesh_io::{
    parse_medit, parse_msh, parse_msh_bytes, parse_obj, parse_off, parse_stl, read_msh, read_off,
    read_stl, read_surface, write_off, IoError, SurfaceFile,
};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The single polygon of each facet.
fn polygons(s: &SurfaceFile) -> Vec<Vec<u32>> {
    s.facets
        .iter()
        .map(|f| {
            assert_eq!(f.polygons.len(), 1);
            f.polygons[0].clone()
        })
        .collect()
}

fn markers(s: &SurfaceFile) -> Vec<i32> {
    s.facets.iter().map(|f| f.marker).collect()
}

/// `(line, message)` of a parse error.
fn parse_error(r: Result<SurfaceFile, IoError>) -> (usize, String) {
    match r {
        Err(IoError::Parse { line, message, .. }) => (line, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

fn binary_error(r: Result<SurfaceFile, IoError>) -> (u64, String) {
    match r {
        Err(IoError::Binary {
            offset, message, ..
        }) => (offset, message),
        other => panic!("expected a binary-file error, got {other:?}"),
    }
}

// ---------------------------------------------------------------------------------- OFF

const TETRA_OFF: &str = "\
# a tetrahedron
OFF
4 4 6
0 0 0
1 0 0
0 1 0
0 0 1
3 0 2 1
3 0 1 3
3 1 2 3
3 0 3 2
";

#[test]
fn off_variants() {
    let off = |t: &str| parse_off(t, Path::new("t.off"));
    let s = off(TETRA_OFF).unwrap();
    assert_eq!(s.points[3], [0.0, 0.0, 1.0]);
    assert_eq!(polygons(&s)[1], [0, 1, 3]);
    assert_eq!(s.facets[0].line, 8);
    assert_eq!((s.first_index, s.point_markers.clone()), (0, None));
    assert!(s.is_triangulated());

    // Counts on the keyword's line; COFF colours after the coordinates and after the face
    // indices; a quadrilateral.
    let s = off(
        "COFF 5 2 0\n0 0 0 255 0 0 1\n1 0 0 1 1 1 1\n1 1 0 0 0 0 0\n0 1 0 0 0 0 0\n\
                 0 0 1 0 0 0 0\n4 0 1 2 3 0.5 0.5 0.5\n3 0 1 4 255 0 0\n",
    )
    .unwrap();
    assert_eq!(polygons(&s), [vec![0, 1, 2, 3], vec![0, 1, 4]]);
    assert_eq!(s.points[1], [1.0, 0.0, 0.0]);
    // No keyword at all; NOFF; two counts.
    assert_eq!(
        off("3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
            .unwrap()
            .facets
            .len(),
        1
    );
    let s = off("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n").unwrap();
    assert_eq!(s.points.len(), 3);

    // Errors.
    let cases: Vec<(String, usize, &str)> = vec![
        (
            TETRA_OFF.replace("3 0 1 3", "3 0 1 4"),
            9,
            "point 4 does not exist (points are numbered 0 to 3)",
        ),
        (
            TETRA_OFF.replace("3 0 1 3", "3 0 1"),
            9,
            "face of 3 vertices needs 4 fields, found 3",
        ),
        (
            TETRA_OFF.replace("3 0 1 3", "2 0 1"),
            9,
            "face has 2 corners, at least 3 are needed",
        ),
        (
            TETRA_OFF.replace("3 0 1 3", "3 0 -1 3"),
            9,
            "point -1 does not exist",
        ),
        (
            TETRA_OFF.replace("1 0 0\n", "1 inf 0\n"),
            5,
            "y coordinate is not finite: 'inf'",
        ),
        (
            TETRA_OFF.replace("1 0 0\n", "1 0\n"),
            5,
            "expected at least 3 fields for a vertex, found 2",
        ),
        (
            TETRA_OFF.replace("4 4 6", "4 5 6"),
            11,
            "unexpected end of file: expected 5 faces (found 4)",
        ),
        (
            TETRA_OFF.replace("4 4 6", "4 3 6"),
            11,
            "extra data after the 3 faces declared on line 3",
        ),
        (
            TETRA_OFF.replace("4 4 6", "4 4 6 1"),
            3,
            "expected the counts",
        ),
        (
            TETRA_OFF.replace("OFF", "4OFF"),
            2,
            "only 3D OFF files are supported",
        ),
        (
            TETRA_OFF.replace("OFF", "OFF BINARY"),
            2,
            "binary OFF is not supported",
        ),
        (TETRA_OFF.replace("OFF", "PLY"), 2, "expected an OFF header"),
        (
            "OFF\n".into(),
            1,
            "unexpected end of file: expected the counts",
        ),
    ];
    for (text, line, message) in cases {
        let (l, m) = parse_error(off(&text));
        assert!(
            l == line && m.contains(message),
            "expected {line}: {message}\n     got {l}: {m}"
        );
    }
}

#[test]
fn off_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.off");
    let points = [
        [0.1 + 0.2, -0.0, 1e-310],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let faces = [vec![0, 2, 1], vec![0, 1, 3, 2]];
    write_off(&path, &points, &faces).unwrap();
    let s = read_off(&path).unwrap();
    assert_eq!(polygons(&s), faces);
    let bits = |p: &[[f64; 3]]| p.iter().flatten().map(|c| c.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&s.points), bits(&points));
    // Triangles as arrays work too; bad input is refused before writing.
    write_off(&path, &points, &[[0u32, 1, 2]]).unwrap();
    let e = write_off(&dir.path().join("bad.off"), &points, &[[0u32, 1, 4]]).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}: face 0 refers to point 4 but there are 4 points",
            dir.path().join("bad.off").display()
        )
    );
    let e = write_off(&dir.path().join("bad.off"), &points, &[vec![0u32, 1]]).unwrap_err();
    assert!(e.to_string().contains("at least 3"), "{e}");
    assert!(!dir.path().join("bad.off").exists());
}

// ---------------------------------------------------------------------------------- STL

const TWO_SOLIDS: &str = "\
solid first part
  facet normal 0 0 -1
    outer loop
      vertex 0 0 0
      vertex 0 1 0
      vertex 1 0 0
    endloop
  endfacet
  facet normal 0 0 -1
    outer loop
      vertex 1 0 0
      vertex 0 1 0
      vertex 1 1 -0
    endloop
  endfacet
endsolid first part
SOLID lid
FACET NORMAL 0 0 1
OUTER LOOP
VERTEX 0 0 -0.0
VERTEX 1 0 0
VERTEX 0 0 1
ENDLOOP
ENDFACET
ENDSOLID
";

/// A binary STL file of `tris` with the given 80-byte header start.
fn binary_stl(header: &[u8], tris: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut b = vec![b' '; 80];
    b[..header.len()].copy_from_slice(header);
    b.extend_from_slice(&(tris.len() as u32).to_le_bytes());
    for t in tris {
        b.extend_from_slice(&[0u8; 12]); // normal
        for p in t {
            for c in p {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b.extend_from_slice(&[0u8; 2]); // attribute
    }
    b
}

#[test]
fn ascii_stl_merges_points_and_numbers_solids() {
    let s = parse_stl(TWO_SOLIDS.as_bytes(), Path::new("s.stl")).unwrap();
    // 0 0 0 and 0 0 -0.0 are one point; 1 1 -0 equals 1 1 0 (not present otherwise).
    assert_eq!(s.points.len(), 5);
    assert_eq!(polygons(&s), [vec![0, 1, 2], vec![2, 1, 3], vec![0, 2, 4]]);
    assert_eq!(markers(&s), [1, 1, 2]);
    assert_eq!(
        s.marker_names,
        [(1, "first part".to_string()), (2, "lid".to_string())]
    );
    assert_eq!(
        s.facets.iter().map(|f| f.line).collect::<Vec<_>>(),
        [2, 9, 18]
    );
    // Solids of one name share its marker (concatenated exports, each solid named alike,
    // gave one marker per solid, all called the same); unnamed solids have their own.
    let renamed = TWO_SOLIDS.replace("SOLID lid", "solid first part");
    let three = format!(
        "{renamed}{}",
        TWO_SOLIDS.replace("solid first part\n", "solid\n")
    );
    let s = parse_stl(three.as_bytes(), Path::new("s.stl")).unwrap();
    assert_eq!(markers(&s), [1, 1, 1, 2, 2, 3]);
    assert_eq!(
        s.marker_names,
        [(1, "first part".to_string()), (3, "lid".to_string())]
    );

    let stl = |t: String| parse_error(parse_stl(t.as_bytes(), Path::new("s.stl")));
    let cases: Vec<(String, usize, &str)> = vec![
        (
            TWO_SOLIDS.replace(
                "vertex 0 1 0\n      vertex 1 0 0",
                "vertex 0 1 0\n      endloop",
            ),
            6,
            "expected 'vertex', found 'endloop'",
        ),
        (
            TWO_SOLIDS.replace("vertex 1 1 -0", "vertex 1 1 NaN"),
            13,
            "z coordinate is not finite: 'NaN'",
        ),
        (
            TWO_SOLIDS.replace("vertex 1 1 -0", "vertex 1 1"),
            14,
            "non-numeric token 'endloop' for the z coordinate",
        ),
        (
            TWO_SOLIDS.replace("normal 0 0 -1", "normal 0 x -1"),
            2,
            "non-numeric token 'x' for the normal y",
        ),
        (
            TWO_SOLIDS.replace("ENDSOLID\n", ""),
            25,
            "unexpected end of file: expected 'facet' or 'endsolid'",
        ),
        (
            TWO_SOLIDS.replace("SOLID lid", "lid"),
            17,
            "expected 'solid' or the end of the file after 'endsolid', found 'lid'",
        ),
        (
            TWO_SOLIDS[..200].to_string(),
            12,
            "expected 'vertex', found 'vert'",
        ),
        (
            TWO_SOLIDS[..TWO_SOLIDS.find("endloop").unwrap()].to_string(),
            7,
            "unexpected end of file: expected 'endloop'",
        ),
    ];
    for (text, line, message) in cases {
        let (l, m) = stl(text);
        assert!(
            l == line && m.contains(message),
            "expected {line}: {message}\n     got {l}: {m}"
        );
    }
}

#[test]
fn binary_stl_solids_one_after_another() {
    // gmsh's `Mesh.StlOneSolidPerSurface` with `Mesh.Binary`: complete binary files in a row.
    let first = [
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
    ];
    let second = [[[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]];
    let mut bytes = binary_stl(b"solid surface 1", &first);
    bytes.extend(binary_stl(b"solid surface 2", &second));
    let s = parse_stl(&bytes, Path::new("b.stl")).unwrap();
    assert_eq!(s.points.len(), 5);
    assert_eq!(polygons(&s), [vec![0, 1, 2], vec![1, 3, 2], vec![0, 2, 4]]);
    assert_eq!(markers(&s), [1, 1, 2]);
    assert_eq!(
        s.facets.iter().map(|f| f.line).collect::<Vec<_>>(),
        [1, 2, 3]
    );
    // A bad corner in the second block is reported at its byte offset in the file.
    let mut bad = bytes.clone();
    let at = 2 * 84 + 3 * 50 - 50 + 12;
    bad[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let (offset, message) = binary_error(parse_stl(&bad, Path::new("b.stl")));
    assert_eq!(offset, at as u64);
    assert!(message.contains("triangle 3: corner 1"), "{message}");
    // One byte too few: the blocks no longer cover the file, the first header is blamed.
    bytes.pop();
    let (offset, message) = binary_error(parse_stl(&bytes, Path::new("b.stl")));
    assert_eq!(offset, 80);
    assert!(message.contains("declares 2 triangles"), "{message}");
}

#[test]
fn binary_stl_even_with_a_solid_header() {
    let tris = [
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, -0.0]],
    ];
    for header in [&b"solid but binary"[..], b"made by some CAD"] {
        let s = parse_stl(&binary_stl(header, &tris), Path::new("b.stl")).unwrap();
        assert_eq!(s.points.len(), 4);
        assert_eq!(polygons(&s), [vec![0, 1, 2], vec![1, 3, 2]]);
        assert_eq!(markers(&s), [0, 0]);
        assert_eq!(s.facets[1].line, 2);
    }
    // f32 values are kept exactly.
    let s = parse_stl(
        &binary_stl(b"", &[[[0.1, 0.2, 0.3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]]),
        Path::new("b.stl"),
    )
    .unwrap();
    assert_eq!(
        s.points[0],
        [f64::from(0.1f32), f64::from(0.2f32), f64::from(0.3f32)]
    );

    // Truncated, too long, too short, non-finite: errors with the byte offset.
    let good = binary_stl(b"solid x", &tris);
    let err = |bytes: &[u8]| match parse_stl(bytes, Path::new("b.stl")) {
        Err(IoError::Binary {
            offset, message, ..
        }) => (offset, message),
        other => panic!("expected a binary error, got {other:?}"),
    };
    let (offset, message) = err(&good[..good.len() - 1]);
    assert_eq!(offset, 80);
    assert_eq!(message, "the binary STL header declares 2 triangles, which take 184 bytes, but the file has 183 bytes");
    // Padding shorter than a header after the triangles is ignored (some writers add it), and
    // a count left at 0 is read off the size of whole triangles.
    let mut longer = good.clone();
    longer.extend_from_slice(&[0; 7]);
    let padded = parse_stl(&longer, Path::new("b.stl")).unwrap();
    assert_eq!(
        polygons(&padded),
        polygons(&parse_stl(&good, Path::new("b.stl")).unwrap())
    );
    // A count one short is not taken for padding: the triangle left out would open the surface.
    let mut short = binary_stl(b"solid x", &tris[..1]);
    short.extend_from_slice(&good[84 + 50..]);
    let (offset, message) = err(&short);
    assert_eq!(offset, 80);
    assert_eq!(message, "the binary STL header declares 1 triangles, which take 134 bytes, but the file has 184 bytes");
    let mut uncounted = good.clone();
    uncounted[80..84].copy_from_slice(&[0; 4]);
    assert_eq!(
        parse_stl(&uncounted, Path::new("b.stl"))
            .unwrap()
            .facets
            .len(),
        2
    );
    uncounted.push(0);
    assert_eq!(err(&uncounted[..uncounted.len() - 2]).0, 80);
    assert_eq!(err(b"abc").0, 0);
    let nan = binary_stl(
        b"",
        &[[[0.0, 0.0, 0.0], [1.0, f32::NAN, 0.0], [0.0, 1.0, 0.0]]],
    );
    let (offset, message) = err(&nan);
    assert_eq!(offset, 84 + 24);
    assert!(
        message.starts_with("triangle 1: corner 2 has a non-finite coordinate"),
        "{message}"
    );
    let e = parse_stl(&nan, Path::new("b.stl")).unwrap_err();
    assert!(
        e.to_string().starts_with("b.stl: byte 108: triangle 1"),
        "{e}"
    );
    assert_eq!(e.line(), None);
}

#[test]
fn gmsh_written_stl_files() {
    // The same 40 triangles of a 2 x 1 x 1 box, as three named solids and as binary.
    let ascii = read_stl(&data("gmsh_box_ascii.stl")).unwrap();
    let binary = read_stl(&data("gmsh_box_binary.stl")).unwrap();
    assert_eq!(ascii.facets.len(), 40);
    assert_eq!(ascii.points, binary.points);
    assert_eq!(polygons(&ascii), polygons(&binary));
    assert_eq!(
        ascii.marker_names,
        [
            (1, "inlet".into()),
            (2, "outlet".into()),
            (3, "walls".into())
        ]
    );
    assert_eq!(markers(&ascii).iter().filter(|&&m| m == 3).count(), 32);
    // A closed surface: every edge is shared by exactly two triangles (merging worked).
    let mut edges = std::collections::HashMap::new();
    for p in polygons(&binary) {
        for k in 0..3 {
            let (a, b) = (p[k], p[(k + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    assert!(edges.values().all(|&n| n == 2), "{edges:?}");
    // Euler's formula for a sphere: V - E + F = 2.
    assert_eq!(binary.points.len() as i64 - edges.len() as i64 + 40, 2);
}

// ---------------------------------------------------------------------------------- OBJ

#[test]
fn obj_faces_groups_and_relative_indices() {
    let text = "\
# a square and a triangle
mtllib parts.mtl
o thing
v 0 0 0
v 1 0 0
v 1 1 0 1.0
v 0 1 0 0.5 0.5 0.5
vt 0 0
vn 0 0 1
f 1 2 3 4
g wall side
usemtl steel
f 1/1 2/1/1 -1//1
v 0 0 1
g lid
f -1 1 2
s off
l 1 2
g wall side
f 4 3 5
";
    let s = parse_obj(text, Path::new("m.obj")).unwrap();
    assert_eq!(s.points.len(), 5);
    assert_eq!(s.first_index, 1);
    assert_eq!(
        polygons(&s),
        [
            vec![0, 1, 2, 3],
            vec![0, 1, 3],
            vec![4, 0, 1],
            vec![3, 2, 4]
        ]
    );
    assert_eq!(markers(&s), [0, 1, 2, 1]);
    assert_eq!(
        s.marker_names,
        [(1, "wall side".to_string()), (2, "lid".to_string())]
    );
    assert_eq!(s.facets[2].line, 16);

    // Without groups, materials are the markers.
    let s = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nusemtl a\nf 1 2 3\nusemtl b\nf 3 2 1\nusemtl a\nf 1 3 2\n", Path::new("m.obj")).unwrap();
    assert_eq!(markers(&s), [0, 1, 2, 1]);
    assert_eq!(s.marker_names, [(1, "a".to_string()), (2, "b".to_string())]);

    let base = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let cases = [
        (
            "f 1 2 4\n",
            4,
            "point 4 does not exist (points are numbered 1 to 3)",
        ),
        ("f 1 2 0\n", 4, "vertex index 0 (indices start at 1)"),
        (
            "f 1 2 -4\n",
            4,
            "relative vertex index -4 goes before the first vertex (3 defined so far)",
        ),
        ("f 1 2\n", 4, "face has 2 corners, at least 3 are needed"),
        ("f 1 2 x/1\n", 4, "expected a vertex index in 'x/1'"),
        ("v 1 2\n", 4, "expected 'v x y z', found 3 fields"),
        ("v 1 2 nan\n", 4, "z coordinate is not finite"),
    ];
    for (tail, line, message) in cases {
        let (l, m) = parse_error(parse_obj(&format!("{base}{tail}"), Path::new("m.obj")));
        assert!(
            l == line && m.contains(message),
            "expected {line}: {message}\n     got {l}: {m}"
        );
    }
}

#[test]
fn obj_lines_continue_after_a_backslash() {
    // A face split over three lines (the backslash alone or at the end of a token), and an
    // error after it numbered by its own line.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 \\\n 2 \\\n 3\nf 1 2\\\n4\n";
    let bad = format!("{text}f 1 2 x\n");
    let (line, message) = parse_error(parse_obj(&bad, Path::new("m.obj")));
    assert_eq!(
        (line, message.as_str()),
        (10, "expected a vertex index in 'x'")
    );
    let s = parse_obj(text, Path::new("m.obj")).unwrap();
    assert_eq!(polygons(&s), [vec![0, 1, 2], vec![0, 1, 3]]);
    assert_eq!(s.facets[1].line, 8);
    // A lone backslash on the last line (nothing to continue with) is no line, not a panic.
    let s = parse_obj(&format!("{text}\\\n"), Path::new("m.obj")).unwrap();
    assert_eq!(s.facets.len(), 2);
}

// ---------------------------------------------------------------------------------- Medit

#[test]
fn medit_free_format_and_skipped_sections() {
    let text = "\
MeshVersionFormatted 1
# comment
Dimension
3
Vertices 4
0 0 0 1   1 0 0 1
0 1 0 2
0 0 1 2
Edges 1 1 2 0
Corners
2 1 2
Triangles
2
1 3 2 7
1 2 4 8
Quadrilaterals 1
1 2 3 4 9
Tetrahedra
1
1 2 3 4 5
End
";
    let s = parse_medit(text, Path::new("m.mesh")).unwrap();
    assert_eq!(s.points.len(), 4);
    assert_eq!(s.point_markers, Some(vec![1, 1, 2, 2]));
    assert_eq!(
        polygons(&s),
        [vec![0, 2, 1], vec![0, 1, 3], vec![0, 1, 2, 3]]
    );
    assert_eq!(markers(&s), [7, 8, 9]);
    assert_eq!(
        s.facets.iter().map(|f| f.line).collect::<Vec<_>>(),
        [14, 15, 17]
    );
    assert_eq!(s.tetrahedra, [[0, 1, 2, 3]]);
    assert_eq!(s.tetrahedron_regions, [5]);

    let e = |t: String| parse_error(parse_medit(&t, Path::new("m.mesh")));
    let cases = [
        (
            text.replace("1 2 4 8", "1 2 5 8"),
            15,
            "point 5 does not exist (points are numbered 1 to 4)",
        ),
        (
            text.replace("0 0 1 2\n", "0 0 1\n"),
            9,
            "expected an integer for the reference of a vertex, found 'Edges'",
        ),
        (
            text.replace("Dimension\n3", "Dimension 2"),
            3,
            "Dimension 2: only 3D Medit meshes are read",
        ),
        (
            text.replace("Corners", "Wedges"),
            10,
            "unknown Medit keyword 'Wedges'",
        ),
        (
            text.replace("0 1 0 2", "0 1 e 2"),
            7,
            "non-numeric token 'e' for the z coordinate",
        ),
        (
            text.replace("Tetrahedra\n1", "Tetrahedra\n2"),
            21,
            "expected an integer for the corner 1 of a tetrahedron, found 'End'",
        ),
        (
            text[..text.find("1 2 4 8").unwrap()].to_string(),
            14,
            "unexpected end of file: expected corner 1 of a triangle",
        ),
        (
            text.replace("Vertices 4", "Vertices -4"),
            5,
            "expected a non-negative integer for the number of vertices",
        ),
    ];
    for (t, line, message) in cases {
        let (l, m) = e(t);
        assert!(
            l == line && m.contains(message),
            "expected {line}: {message}\n     got {l}: {m}"
        );
    }
}

#[test]
fn gmsh_written_medit_file() {
    let s = read_surface(&data("gmsh_box.mesh")).unwrap();
    assert_eq!((s.facets.len(), s.tetrahedra.len()), (40, 43));
    let msh = read_msh(&data("gmsh_box22.msh")).unwrap();
    assert_eq!(s.points.len(), msh.points.len());
}

// ---------------------------------------------------------------------------------- gmsh

#[test]
fn gmsh_written_msh_files_agree() {
    let v22 = read_msh(&data("gmsh_box22.msh")).unwrap();
    let v41 = read_msh(&data("gmsh_box41.msh")).unwrap();
    let par = read_msh(&data("gmsh_box41_parametric.msh")).unwrap();
    for s in [&v22, &v41, &par] {
        assert_eq!(s.facets.len(), 40);
        assert_eq!(s.tetrahedra.len(), 43);
        assert!(s.tetrahedron_regions.iter().all(|&r| r == 3));
        assert_eq!(
            s.marker_names,
            [
                (7, "inlet".into()),
                (8, "outlet".into()),
                (9, "walls".into())
            ]
        );
        let m = markers(s);
        assert_eq!(
            [7, 8, 9].map(|k| m.iter().filter(|&&x| x == k).count()),
            [4, 4, 32]
        );
    }
    // Same points, triangles and tetrahedra whatever the version (the node tags are the same).
    assert_eq!(v22.points, v41.points);
    assert_eq!(v41.points, par.points);
    assert_eq!(polygons(&v22), polygons(&v41));
    assert_eq!(v22.tetrahedra, v41.tetrahedra);
    assert_eq!(markers(&v22), markers(&v41));
}

const MSH22: &str = "\
$MeshFormat
2.2 0 8
$EndMeshFormat
$Comments
anything $Nodes
$EndComments
$Nodes
4
10 0 0 0
20 1 0 0
30 0 1 0
40 0 0 1
$EndNodes
$Elements
4
1 15 2 0 1 10
2 1 2 5 1 10 20
3 2 2 6 1 10 30 20
4 4 0 10 20 30 40
$EndElements
";

#[test]
fn msh22_tags_and_skipped_elements() {
    let s = parse_msh(MSH22, Path::new("m.msh")).unwrap();
    assert_eq!(s.points.len(), 4);
    assert_eq!(polygons(&s), [vec![0, 2, 1]]);
    assert_eq!(markers(&s), [6]);
    assert_eq!(s.facets[0].line, 18);
    assert_eq!(s.tetrahedra, [[0, 1, 2, 3]]);
    assert_eq!(s.tetrahedron_regions, [0]);
    assert!(s.marker_names.is_empty());

    let e = |t: String| parse_error(parse_msh(&t, Path::new("m.msh")));
    let cases = [
        (
            MSH22.replace("10 30 20\n", "10 30 50\n"),
            18,
            "node 50 is not defined in $Nodes",
        ),
        (
            MSH22.replace("10 30 20\n", "10 30\n"),
            18,
            "expected 8 fields for an element of type 2 with 2 tags, found 7",
        ),
        (
            MSH22.replace("3 2 2 6 1", "3 2 99 6 1"),
            18,
            "expected 105 fields for an element of type 2 with 99 tags, found 8",
        ),
        (
            MSH22.replace("40 0 0 1", "30 0 0 1"),
            12,
            "node tag 30 is defined twice",
        ),
        (
            MSH22.replace("40 0 0 1", "40 0 0 nan"),
            12,
            "z coordinate is not finite",
        ),
        (
            MSH22.replace("40 0 0 1", "40 0 0"),
            12,
            "expected 4 fields for a node",
        ),
        (
            MSH22.replace("$EndNodes", "$EndNode"),
            13,
            "expected '$EndNodes', found '$EndNode'",
        ),
        (
            format!(
                "$Comments\n$EndComments\n{}",
                MSH22.replace("2.2 0 8", "2.2 1 8")
            ),
            4,
            "a binary .msh file must begin with $MeshFormat",
        ),
        (
            MSH22.replace("2.2 0 8", "4 0 8"),
            2,
            "gmsh format 4 is not supported: save the mesh in format 4.1 or 2.2",
        ),
        (
            MSH22.replace("2.2 0 8", "3.0 0 8"),
            2,
            "unsupported gmsh format version '3.0'",
        ),
        (
            MSH22.replace("$EndComments", ""),
            20,
            "unexpected end of file: expected '$EndComments'",
        ),
        (
            MSH22.replace("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n", ""),
            4,
            "$Nodes before $MeshFormat",
        ),
        (
            MSH22.replace("$Elements\n4", "$Elements\n5"),
            20,
            "found '$EndElements': fewer records than the section's count",
        ),
        (
            "$NOD\n1\n1 0 0 0\n$ENDNOD\n".into(),
            1,
            "gmsh format 1 is not supported",
        ),
        ("".into(), 1, "no $MeshFormat section"),
        (
            "hello\n".into(),
            1,
            "expected a section such as $MeshFormat",
        ),
    ];
    for (t, line, message) in cases {
        let (l, m) = e(t);
        assert!(
            l == line && m.contains(message),
            "expected {line}: {message}\n     got {l}: {m}"
        );
    }
}

const MSH41: &str = "\
$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 4 \"far  field\"
3 2 \"air\"
$EndPhysicalNames
$Entities
1 0 2 1
1 0 0 0 0
1 0 0 0 1 1 0 1 4 0
2 0 0 0 1 0 1 0 0
1 0 0 0 1 1 1 1 2 1 1
$EndEntities
$Nodes
2 4 1 4
3 1 0 3
1
2
3
0 0 0
1 0 0
0 1 0
2 2 1 1
4
0 0 1 0.5 0.5
$EndNodes
$Elements
3 3 1 3
2 1 2 1
1 1 3 2
2 2 2 1
2 1 2 4
3 1 4 1
3 1 2 3 4
$EndElements
";

#[test]
fn msh41_entities_map_to_physical_tags() {
    let s = parse_msh(MSH41, Path::new("m.msh")).unwrap();
    assert_eq!(s.points[3], [0.0, 0.0, 1.0]);
    assert_eq!(polygons(&s), [vec![0, 2, 1], vec![0, 1, 3]]);
    // Surface 1 is in physical group 4; surface 2 in none.
    assert_eq!(markers(&s), [4, 0]);
    assert_eq!(s.marker_names, [(4, "far  field".to_string())]);
    assert_eq!(s.tetrahedra, [[0, 1, 2, 3]]);
    assert_eq!(s.tetrahedron_regions, [2]);

    // Without $Entities every marker is 0.
    let start = MSH41.find("$Entities").unwrap();
    let end = MSH41.find("$Nodes").unwrap();
    let bare = format!("{}{}", &MSH41[..start], &MSH41[end..]);
    assert_eq!(
        markers(&parse_msh(&bare, Path::new("m.msh")).unwrap()),
        [0, 0]
    );

    let e = |t: String| parse_error(parse_msh(&t, Path::new("m.msh")));
    let cases = [
        (
            MSH41.replace("0 0 1 0.5 0.5", "0 0 1 0.5"),
            27,
            "expected 5 fields for node coordinates, found 4",
        ),
        (
            MSH41.replace("1 1 3 2\n", "1 1 3\n"),
            32,
            "expected 4 fields for an element of type 2, found 3",
        ),
        (
            MSH41.replace("3 1 2 3 4\n", "3 1 2 3 9\n"),
            36,
            "node 9 is not defined in $Nodes",
        ),
        (
            MSH41.replace("2 4 \"far  field\"", "2 4 far"),
            6,
            "physical name in '2 4 far' is not quoted",
        ),
        // Miscounted blocks show where the counts stop matching the data.
        (
            MSH41.replace("2 2 2 1\n", "2 2 2 2\n"),
            36,
            "expected 4 fields for an element block",
        ),
        (
            MSH41.replace("3 1 0 3\n", "3 1 0 4\n"),
            22,
            "expected 1 fields for a node tag, found 3",
        ),
        (
            MSH41.replace("1 0 2 1\n", "1 0 2\n"),
            10,
            "expected 4 fields for the entity counts, found 3",
        ),
    ];
    for (t, line, message) in cases {
        let (l, m) = e(t);
        assert!(
            l == line && m.contains(message),
            "expected {line}: {message}\n     got {l}: {m}"
        );
    }
}

// --------------------------------------------------------------------------- gmsh binary

/// The gmsh-written binary files and their ASCII twins (same geometry, same options).
const BINARY_TWINS: [(&str, &str); 7] = [
    ("gmsh_box22.msh", "gmsh_box22_binary.msh"),
    ("gmsh_box41.msh", "gmsh_box41_binary.msh"),
    (
        "gmsh_box41_parametric.msh",
        "gmsh_box41_parametric_binary.msh",
    ),
    ("gmsh_box22_order2.msh", "gmsh_box22_order2_binary.msh"),
    ("gmsh_box41_order2.msh", "gmsh_box41_order2_binary.msh"),
    ("gmsh_periodic22.msh", "gmsh_periodic22_binary.msh"),
    ("gmsh_periodic41.msh", "gmsh_periodic41_binary.msh"),
];

/// The 1-based line of the `$Elements` keyword of a file.
fn elements_line(bytes: &[u8]) -> usize {
    let at = bytes
        .windows(10)
        .position(|w| w == b"\n$Elements")
        .expect("an $Elements section");
    2 + bytes[..at].iter().filter(|&&b| b == b'\n').count()
}

/// `s` with every facet's line set to 0.
fn without_lines(mut s: SurfaceFile) -> SurfaceFile {
    for f in &mut s.facets {
        f.line = 0;
    }
    s
}

fn point_bits(s: &SurfaceFile) -> Vec<[u64; 3]> {
    s.points.iter().map(|p| p.map(f64::to_bits)).collect()
}

#[test]
fn gmsh_binary_files_read_as_their_ascii_twins() {
    for (ascii, binary) in BINARY_TWINS {
        let bytes = std::fs::read(data(binary)).unwrap();
        assert!(bytes.starts_with(b"$MeshFormat\n") && bytes[15..20] == *b" 1 8\n");
        let mut a = read_msh(&data(ascii)).unwrap();
        let b = read_msh(&data(binary)).unwrap();
        // Binary facets carry the line of the `$Elements` keyword.
        let line = elements_line(&bytes);
        assert!(b.facets.iter().all(|f| f.line == line), "{binary}");
        if binary.contains("order2") {
            // gmsh writes ASCII coordinates with 16 significant digits (`%.16g`), which does
            // not round-trip every double: some mid-edge nodes are 1 ulp off. The ASCII
            // values are the binary ones so rounded.
            assert_ne!(point_bits(&a), point_bits(&b));
            assert_eq!(a.points.len(), b.points.len());
            for (p, q) in a.points.iter().zip(&b.points) {
                for d in 0..3 {
                    let rounded: f64 = format!("{:.15e}", q[d]).parse().unwrap();
                    assert_eq!(rounded.to_bits(), p[d].to_bits(), "{binary}: {q:?}");
                }
            }
            a.points.clone_from(&b.points);
        }
        assert_eq!(point_bits(&a), point_bits(&b), "{binary}");
        assert_eq!(without_lines(a), without_lines(b.clone()), "{binary}");
        // Something was read: the order-2 files give only points (their elements are skipped).
        assert!(b.points.len() >= 22, "{binary}");
        if binary.contains("order2") {
            assert!(b.facets.is_empty() && b.tetrahedra.is_empty());
        } else if binary == "gmsh_periodic22_binary.msh" {
            // With Mesh.SaveAll, gmsh writes every 2.2 element once, with physical tag 0.
            assert_eq!((b.facets.len(), b.tetrahedra.len()), (40, 43));
            assert!(markers(&b).iter().all(|&m| m == 0));
            assert!(b.tetrahedron_regions.iter().all(|&r| r == 0));
        } else {
            assert_eq!((b.facets.len(), b.tetrahedra.len()), (40, 43), "{binary}");
            assert_eq!(
                [7, 8, 9].map(|k| markers(&b).iter().filter(|&&x| x == k).count()),
                [4, 4, 32],
                "{binary}"
            );
            assert!(b.tetrahedron_regions.iter().all(|&r| r == 3));
            assert_eq!(b.marker_names.len(), 3);
        }
        if binary.contains("periodic") {
            // The sections and element types skipped are there.
            let has = |s: &[u8]| bytes.windows(s.len()).any(|w| w == s);
            assert!(has(b"\n$Periodic\n") && has(b"\n$NodeData\n"), "{binary}");
        }
    }
    // Parametric or not, 2.2 or 4.1: the same mesh.
    let v22 = read_msh(&data("gmsh_box22_binary.msh")).unwrap();
    let v41 = read_msh(&data("gmsh_box41_parametric_binary.msh")).unwrap();
    assert_eq!(point_bits(&v22), point_bits(&v41));
    assert_eq!(polygons(&v22), polygons(&v41));
    assert_eq!(v22.tetrahedra, v41.tetrahedra);
    // read_surface takes them by the extension.
    assert_eq!(
        read_surface(&data("gmsh_box41_binary.msh"))
            .unwrap()
            .facets
            .len(),
        40
    );
}

/// The offsets at which a prefix of `bytes` is a complete file: the ends of its `$End` lines
/// (with or without their newline).
fn complete_prefixes(bytes: &[u8]) -> Vec<usize> {
    let mut ends = Vec::new();
    for (k, w) in bytes.windows(5).enumerate() {
        if w == b"\n$End" {
            let len = bytes[k + 1..].iter().position(|&b| b == b'\n').unwrap();
            ends.push(k + 1 + len);
            ends.push(k + 2 + len);
        }
    }
    ends
}

#[test]
fn truncated_binary_msh_files_are_errors() {
    for (_, binary) in BINARY_TWINS {
        let bytes = std::fs::read(data(binary)).unwrap();
        let complete = complete_prefixes(&bytes);
        assert!(complete.contains(&bytes.len()));
        for end in 0..=bytes.len() {
            let r = parse_msh_bytes(&bytes[..end], Path::new("t.msh"));
            assert_eq!(
                r.is_ok(),
                complete.contains(&end),
                "{binary} cut at byte {end}: {r:?}"
            );
        }
    }
}

/// A binary `.msh` file under construction, with the offsets of labelled fields.
struct Bin {
    bytes: Vec<u8>,
    big: bool,
    size_t: usize,
    marks: Vec<(&'static str, usize)>,
}

impl Bin {
    /// The `$MeshFormat` section of a binary file.
    fn new(version: &str, big: bool, size_t: usize) -> Bin {
        let mut b = Bin {
            bytes: Vec::new(),
            big,
            size_t,
            marks: Vec::new(),
        };
        b.text(&format!("$MeshFormat\n{version} 1 {size_t}\n"));
        b.mark("one");
        b.int(1);
        b.text("\n$EndMeshFormat\n");
        b
    }

    fn text(&mut self, t: &str) -> &mut Self {
        self.bytes.extend_from_slice(t.as_bytes());
        self
    }

    fn int(&mut self, v: i32) -> &mut Self {
        let b = if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        self.bytes.extend_from_slice(&b);
        self
    }

    fn ints(&mut self, v: &[i32]) -> &mut Self {
        for &x in v {
            self.int(x);
        }
        self
    }

    fn size(&mut self, v: u64) -> &mut Self {
        let b = if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        let b = if self.big {
            &b[8 - self.size_t..]
        } else {
            &b[..self.size_t]
        };
        self.bytes.extend_from_slice(b);
        self
    }

    fn sizes(&mut self, v: &[u64]) -> &mut Self {
        for &x in v {
            self.size(x);
        }
        self
    }

    fn f64s(&mut self, v: &[f64]) -> &mut Self {
        for &x in v {
            let b = if self.big {
                x.to_be_bytes()
            } else {
                x.to_le_bytes()
            };
            self.bytes.extend_from_slice(&b);
        }
        self
    }

    fn mark(&mut self, label: &'static str) -> &mut Self {
        self.marks.push((label, self.bytes.len()));
        self
    }

    fn at(&self, label: &str) -> usize {
        self.marks.iter().find(|m| m.0 == label).unwrap().1
    }

    /// The 1-based line of a labelled offset.
    fn line(&self, label: &str) -> usize {
        1 + self.bytes[..self.at(label)]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    }
}

/// [`MSH41`] in binary.
fn msh41_binary(big: bool, size_t: usize) -> Bin {
    let mut b = Bin::new("4.1", big, size_t);
    b.text("$PhysicalNames\n2\n2 4 \"far  field\"\n3 2 \"air\"\n$EndPhysicalNames\n");
    b.mark("$Entities").text("$Entities\n").sizes(&[1, 0, 2, 1]);
    b.int(1).f64s(&[0.0; 3]).size(0);
    b.int(1).f64s(&[0., 0., 0., 1., 1., 0.]);
    b.mark("surface 1 physicals").size(1).int(4).size(0);
    b.int(2).f64s(&[0., 0., 0., 1., 0., 1.]).size(0).size(0);
    b.int(1).f64s(&[0., 0., 0., 1., 1., 1.]);
    b.size(2).ints(&[2, 1]).size(1).int(1);
    b.text("\n$EndEntities\n");
    b.mark("$Nodes").text("$Nodes\n").mark("node counts");
    b.sizes(&[2, 4, 1, 4]);
    b.mark("node block 1")
        .ints(&[3, 1, 0])
        .mark("node block 1 count");
    b.size(3)
        .mark("node tags 1")
        .size(1)
        .size(2)
        .mark("tag 3")
        .size(3);
    b.mark("x1").f64s(&[0., 0., 0., 1., 0., 0., 0., 1., 0.]);
    b.mark("node block 2").ints(&[2, 2, 1]).size(1).size(4);
    b.f64s(&[0., 0.]).mark("z4").f64s(&[1., 0.5, 0.5]);
    b.text("\n$EndNodes\n");
    b.mark("$Elements")
        .text("$Elements\n")
        .mark("element blocks");
    b.sizes(&[3, 3, 1, 3]);
    b.ints(&[2, 1, 2]).size(1).sizes(&[1, 1, 3, 2]);
    b.ints(&[2, 2, 2]).size(1).sizes(&[2, 1, 2, 4]);
    b.mark("block 3")
        .ints(&[3, 1])
        .mark("type 3")
        .int(4)
        .size(1);
    b.sizes(&[3, 1, 2, 3]).mark("tet node 4").size(4);
    b.text("\n$EndElements\n");
    b
}

/// [`MSH22`] in binary (one group per element, as gmsh writes them).
fn msh22_binary(big: bool) -> Bin {
    let mut b = Bin::new("2.2", big, 8);
    b.text("$Comments\nanything $Nodes\n$EndComments\n");
    b.mark("$Nodes")
        .text("$Nodes\n")
        .mark("node count")
        .text("4\n");
    for (k, (tag, p)) in [
        (10, [0., 0., 0.]),
        (20, [1., 0., 0.]),
        (30, [0., 1., 0.]),
        (40, [0., 0., 1.]),
    ]
    .into_iter()
    .enumerate()
    {
        b.mark(["tag 1", "tag 2", "tag 3", "tag 4"][k])
            .int(tag)
            .f64s(&p);
    }
    b.text("\n$EndNodes\n");
    b.mark("$Elements").text("$Elements\n4\n");
    b.mark("group 1").ints(&[15, 1, 2]).ints(&[1, 0, 1, 10]);
    b.ints(&[1, 1, 2]).ints(&[2, 5, 1, 10, 20]);
    b.mark("group 3")
        .ints(&[2, 1, 2])
        .ints(&[3, 6, 1, 10, 30, 20]);
    b.mark("group 4").ints(&[4, 1, 0]).ints(&[4, 10, 20, 30]);
    b.mark("tet node 4").int(40);
    b.text("\n$EndElements\n");
    b
}

fn parse_bin(b: &[u8]) -> Result<SurfaceFile, IoError> {
    parse_msh_bytes(b, Path::new("b.msh"))
}

#[test]
fn binary_msh_both_byte_orders_and_size_t_widths() {
    let ascii = without_lines(parse_msh(MSH41, Path::new("m.msh")).unwrap());
    for (big, size_t) in [(false, 8), (true, 8), (false, 4), (true, 4)] {
        let b = msh41_binary(big, size_t);
        let s = parse_bin(&b.bytes).unwrap();
        let line = b.line("$Elements");
        assert!(s.facets.iter().all(|f| f.line == line));
        assert_eq!(without_lines(s), ascii, "big endian {big}, size_t {size_t}");
    }
    let ascii = without_lines(parse_msh(MSH22, Path::new("m.msh")).unwrap());
    for big in [false, true] {
        let s = parse_bin(&msh22_binary(big).bytes).unwrap();
        assert_eq!(without_lines(s), ascii, "big endian {big}");
    }
    // parse_msh takes a binary file that is valid UTF-8 (all bytes < 128) too.
    let mut b = Bin::new("2.2", false, 8);
    b.text("$Nodes\n4\n");
    for (tag, p) in [
        (1, [0., 0., 0.]),
        (2, [2., 0., 0.]),
        (3, [0., 2., 0.]),
        (4, [0., 0., 2.]),
    ] {
        b.int(tag).f64s(&p);
    }
    b.text("\n$EndNodes\n$Elements\n1\n")
        .ints(&[2, 1, 1, 1, 5, 1, 2, 3]);
    b.text("\n$EndElements\n");
    let b = b.bytes;
    let text = String::from_utf8(b.clone()).unwrap();
    let s = parse_msh(&text, Path::new("m.msh")).unwrap();
    assert_eq!((polygons(&s), markers(&s)), (vec![vec![0, 1, 2]], vec![5]));
    assert_eq!(s, parse_bin(&b).unwrap());
    // read_msh reads binary files.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("b.msh");
    std::fs::write(&path, &b).unwrap();
    assert_eq!(read_msh(&path).unwrap(), parse_bin(&b).unwrap());
}

/// `b` with the bytes at `label` replaced.
fn patched(b: &Bin, label: &str, with: &[u8]) -> Vec<u8> {
    let at = b.at(label);
    let mut v = b.bytes.clone();
    v[at..at + with.len()].copy_from_slice(with);
    v
}

#[test]
fn binary_msh_errors_name_the_byte_and_the_section() {
    let b41 = msh41_binary(false, 8);
    let b22 = msh22_binary(false);
    let nodes41 = format!("(in $Nodes, line {})", b41.line("$Nodes"));
    let elements41 = format!("(in $Elements, line {})", b41.line("$Elements"));
    let nodes22 = format!("(in $Nodes, line {})", b22.line("$Nodes"));
    let elements22 = format!("(in $Elements, line {})", b22.line("$Elements"));
    let huge = u64::MAX.to_le_bytes();
    let tet_end = b41.at("tet node 4") + 8;
    assert_eq!(tet_end + 14, b41.bytes.len());
    let cases: Vec<(Vec<u8>, usize, String)> = vec![
        (
            patched(&b41, "one", &[2, 0, 0, 0]),
            b41.at("one"),
            "expected the binary integer 1 (bytes 01 00 00 00 or 00 00 00 01) that gives the \
             byte order, found bytes 02 00 00 00 (in $MeshFormat, line 1)"
                .into(),
        ),
        (
            patched(&b41, "node block 1 count", &huge),
            b41.at("node tags 1"),
            format!(
                "18446744073709551615 nodes of 32 bytes take more than 2^64 bytes, but only {} \
                 bytes are left in the file {nodes41}",
                b41.bytes.len() - b41.at("node tags 1")
            ),
        ),
        (
            patched(&b41, "node block 1 count", &(1u64 << 40).to_le_bytes()),
            b41.at("node tags 1"),
            format!(
                "1099511627776 nodes of 32 bytes take 35184372088832 bytes, but only {} bytes \
                 are left in the file {nodes41}",
                b41.bytes.len() - b41.at("node tags 1")
            ),
        ),
        (
            patched(&b41, "surface 1 physicals", &huge),
            b41.at("surface 1 physicals") + 8,
            "physical tags of 4 bytes take more than 2^64 bytes".into(),
        ),
        (
            patched(&b41, "z4", &f64::NAN.to_le_bytes()),
            b41.at("z4"),
            format!("z coordinate is not finite: NaN {nodes41}"),
        ),
        (
            patched(&b41, "x1", &f64::NEG_INFINITY.to_le_bytes()),
            b41.at("x1"),
            format!("x coordinate is not finite: -inf {nodes41}"),
        ),
        (
            patched(&b41, "tag 3", &2u64.to_le_bytes()),
            b41.at("tag 3"),
            format!("node tag 2 is defined twice {nodes41}"),
        ),
        (
            patched(&b41, "node block 1", &7i32.to_le_bytes()),
            b41.at("node block 1"),
            format!("entity dimension 7 or parametric flag 0 out of range (0-3, 0-1) {nodes41}"),
        ),
        (
            patched(&b41, "tet node 4", &9u64.to_le_bytes()),
            b41.at("tet node 4"),
            format!("node 9 is not defined in $Nodes {elements41}"),
        ),
        (
            patched(&b41, "type 3", &76i32.to_le_bytes()),
            b41.at("block 3"),
            format!(
                "element type 76 cannot be read from a binary file: it is not a gmsh element \
                 type this reader knows, so its size is unknown {elements41}"
            ),
        ),
        (
            patched(&b41, "type 3", &34i32.to_le_bytes()),
            b41.at("block 3"),
            "element type 34 cannot be read from a binary file: its elements (polygons, \
             polyhedra, X-FEM elements) have no fixed size"
                .into(),
        ),
        // Fewer blocks than written: the `$End` line is not where the counts say.
        (
            patched(&b41, "element blocks", &2u64.to_le_bytes()),
            b41.at("block 3"),
            format!(
                "expected '$EndElements', found binary data: the section's counts and its data \
                 disagree {elements41}"
            ),
        ),
        (
            b41.bytes[..b41.at("node counts")].to_vec(),
            b41.at("node counts"),
            format!("unexpected end of file: expected the number of node blocks {nodes41}"),
        ),
        (
            b41.bytes[..tet_end - 3].to_vec(),
            b41.at("block 3") + 20,
            format!(
                "1 elements of 40 bytes (type 4) take 40 bytes, but only 37 bytes are left in \
                 the file {elements41}"
            ),
        ),
        (
            b41.bytes[..b41.at("node block 2") + 6].to_vec(),
            b41.at("node block 2") + 4,
            format!("unexpected end of file: expected the entity tag of a node block {nodes41}"),
        ),
        (
            [&b41.bytes[..], b"$NodeData\n1\n\"x\"\n"].concat(),
            b41.bytes.len() + 16,
            format!(
                "unexpected end of file: expected '$EndNodeData' (in $NodeData, line {})",
                b41.line("$Elements") + 3
            ),
        ),
        (
            [
                &b22.bytes[..b22.at("node count")],
                b"99\n",
                &b22.bytes[b22.at("node count") + 2..],
            ]
            .concat(),
            b22.at("node count") + 3,
            format!(
                "99 nodes of 28 bytes take 2772 bytes, but only {} bytes are left in the file \
                 {nodes22}",
                b22.bytes.len() - b22.at("node count") - 2
            ),
        ),
        (
            patched(&b22, "tag 2", &(-20i32).to_le_bytes()),
            b22.at("tag 2"),
            format!("negative node tag -20 {nodes22}"),
        ),
        (
            patched(&b22, "group 3", &[2, 0, 0, 0, 9, 0, 0, 0]),
            b22.at("group 3"),
            format!(
                "an element group of 9 elements, but 2 of the section's 4 are left {elements22}"
            ),
        ),
        (
            patched(&b22, "group 1", &76i32.to_le_bytes()),
            b22.at("group 1"),
            "element type 76 cannot be read from a binary file".into(),
        ),
        (
            patched(&b22, "tet node 4", &(-40i32).to_le_bytes()),
            b22.at("tet node 4"),
            format!("node -40 is not defined in $Nodes {elements22}"),
        ),
    ];
    for (bytes, offset, message) in cases {
        let (o, m) = binary_error(parse_bin(&bytes));
        assert!(
            o == offset as u64 && m.contains(&message),
            "expected byte {offset}: {message}\n     got byte {o}: {m}"
        );
    }

    // The text lines of a binary file give line-numbered errors.
    let text_cases: Vec<(Vec<u8>, usize, &str)> = vec![
        (
            Bin::new("2.2", false, 4).bytes,
            2,
            "data size 4 in a binary version 2 file: only 8 (the size of a double) is read",
        ),
        (
            Bin::new("4.1", false, 16).bytes,
            2,
            "data size 16 in a binary version 4.1 file: only 4 and 8",
        ),
        (
            Bin::new("4.0", false, 8).bytes,
            2,
            "gmsh format 4.0 is not supported: save the mesh in format 4.1 or 2.2",
        ),
        (
            patched(&b22, "node count", b"x\n"),
            b22.line("node count"),
            "expected a non-negative integer for the number of nodes, found 'x'",
        ),
        (
            [&Bin::new("2.2", false, 8).bytes[..], b"$Entities\n"].concat(),
            5,
            "$Entities in a version 2 file",
        ),
        (
            [
                &Bin::new("4.1", false, 8).bytes[..],
                b"$PhysicalNames\n1\n2 4 far\n$EndPhysicalNames\n",
            ]
            .concat(),
            7,
            "physical name in '2 4 far' is not quoted",
        ),
        (
            [&Bin::new("4.1", false, 8).bytes[..], b"\nhello\n"].concat(),
            6,
            "expected a section such as $MeshFormat, $Nodes or $Elements, found 'hello'",
        ),
    ];
    for (bytes, line, message) in text_cases {
        let (l, m) = parse_error(parse_bin(&bytes));
        assert!(
            l == line && m.contains(message),
            "expected {line}: {message}\n     got {l}: {m}"
        );
    }
    // A tiny valid file: the format alone.
    let s = parse_bin(&Bin::new("4.1", true, 8).bytes).unwrap();
    assert!(s.points.is_empty() && s.facets.is_empty());
}

// ------------------------------------------------------------------------- by extension

#[test]
fn read_surface_picks_the_reader() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    assert_eq!(read_surface(&write("a.obj", tri)).unwrap().facets.len(), 1);
    assert_eq!(
        read_surface(&write("b.OFF", TETRA_OFF))
            .unwrap()
            .facets
            .len(),
        4
    );
    assert_eq!(
        read_surface(&write("c.stl", TWO_SOLIDS))
            .unwrap()
            .facets
            .len(),
        3
    );
    assert_eq!(
        read_surface(&write("d.msh", MSH22)).unwrap().facets.len(),
        1
    );
    assert_eq!(
        read_surface(&write(
            "e.smesh",
            "3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n1 0\n3 0 1 2\n0\n"
        ))
        .unwrap()
        .facets
        .len(),
        1
    );
    assert_eq!(
        read_surface(&write(
            "f.mesh",
            "MeshVersionFormatted 2\nDimension 3\nEnd\n"
        ))
        .unwrap()
        .points
        .len(),
        0
    );
    let e = read_surface(&write("g.ply", "ply\n")).unwrap_err();
    assert!(e.to_string().contains("no 'end_header'"), "{e}");
    let e = read_surface(&write("g.step", "ISO-10303-21;\n")).unwrap_err();
    assert!(matches!(e, IoError::UnknownFormat { .. }), "{e}");
    // Parse errors name the file that was read.
    let e = read_surface(&write("h.off", "OFF\n1 0 0\n0 0\n")).unwrap_err();
    assert_eq!(e.file(), dir.path().join("h.off"));
    assert_eq!(e.line(), Some(3));
    let e = read_surface(&dir.path().join("missing.stl")).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }), "{e}");
}

/// PLY as scanners and Meshlab write it: ASCII with extra vertex properties, quads, a list
/// property after the indices and an element of its own (skipped); binary in both byte
/// orders, with any index and count types; errors naming the line or byte.
#[test]
fn ply_ascii_and_binary() {
    use delmesh_io::parse_ply;
    let ascii = "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 4\n\
                 property float x\nproperty float y\nproperty float z\nproperty uchar red\n\
                 element face 2\nproperty list uchar int vertex_indices\nproperty uchar flags\n\
                 element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
                 0 0 0 255\n1 0 0 0\n0 1 0 0\n\n0 0 1 0\n3 0 1 2 7\n4 0 1 3 2 7\n0 1\n";
    let s = parse_ply(ascii.as_bytes(), Path::new("a.ply")).unwrap();
    let points = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    assert_eq!(s.points, points);
    assert_eq!(polygons(&s), [vec![0, 1, 2], vec![0, 1, 3, 2]]);
    assert_eq!(markers(&s), [0, 0]);
    assert_eq!(s.facets[1].line, 22);
    for big in [false, true] {
        let mut b = format!(
            "ply\nformat binary_{}_endian 1.0\nelement vertex 4\nproperty double x\n\
             property double y\nproperty double z\nelement face 2\n\
             property list ushort uint vertex_index\nend_header\n",
            if big { "big" } else { "little" }
        )
        .into_bytes();
        for p in points {
            for x in p {
                b.extend(if big {
                    x.to_be_bytes()
                } else {
                    x.to_le_bytes()
                });
            }
        }
        for f in [&[0u32, 1, 2][..], &[0, 1, 3, 2]] {
            let n = f.len() as u16;
            b.extend(if big {
                n.to_be_bytes()
            } else {
                n.to_le_bytes()
            });
            for &i in f {
                b.extend(if big {
                    i.to_be_bytes()
                } else {
                    i.to_le_bytes()
                });
            }
        }
        let s = parse_ply(&b, Path::new("b.ply")).unwrap();
        assert_eq!(s.points, points);
        assert_eq!(polygons(&s), [vec![0, 1, 2], vec![0, 1, 3, 2]]);
        let (at, msg) = binary_error(parse_ply(&b[..b.len() - 3], Path::new("b.ply")));
        assert!(
            at > 100 && msg.contains("ends before its last element"),
            "{msg}"
        );
    }
    let bad = ascii.replace("4 0 1 3 2 7", "4 0 1 9 2 7");
    let (line, msg) = parse_error(parse_ply(bad.as_bytes(), Path::new("a.ply")));
    assert_eq!(line, 22);
    assert!(msg.contains("point 9 does not exist"), "{msg}");
    let (_, msg) = parse_error(parse_ply(b"ply\nformat ascii 1.0\n", Path::new("a.ply")));
    assert!(msg.contains("end_header"), "{msg}");
    let (line, _) = parse_error(parse_ply(b"OFF\n", Path::new("a.ply")));
    assert_eq!(line, 1);
}
