//! Tests of the surface readers `.off`, `.stl`, `.obj`, Medit `.mesh` and gmsh `.msh`: small
//! hand-written files in the formats' variants, files written by gmsh 4.15 (`tests/data`), the
//! errors naming the line (or byte), round trips, and the choice of reader by extension.

use std::path::{Path, PathBuf};

use delmesh_io::{
    parse_medit, parse_msh, parse_obj, parse_off, parse_stl, read_msh, read_off, read_stl,
    read_surface, write_off, IoError, SurfaceFile,
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
    // One byte too many: the blocks no longer cover the file, the first header is blamed.
    bytes.push(0);
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
    let mut longer = good.clone();
    longer.push(0);
    assert_eq!(err(&longer).0, 80);
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
            MSH22.replace("2.2 0 8", "2.2 1 8"),
            2,
            "binary .msh files are not supported",
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

#[test]
fn binary_msh_is_refused_with_a_hint() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("b.msh");
    let mut bytes = b"$MeshFormat\n4.1 1 8\n".to_vec();
    bytes.extend_from_slice(&[1, 0, 0, 0, 0xff, 0xfe, b'\n']);
    bytes.extend_from_slice(b"$EndMeshFormat\n");
    std::fs::write(&path, bytes).unwrap();
    let e = read_msh(&path).unwrap_err();
    assert!(
        e.to_string()
            .contains("binary .msh files are not supported: save the mesh as ASCII"),
        "{e}"
    );
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
    assert!(matches!(e, IoError::UnknownFormat { .. }), "{e}");
    // Parse errors name the file that was read.
    let e = read_surface(&write("h.off", "OFF\n1 0 0\n0 0\n")).unwrap_err();
    assert_eq!(e.file(), dir.path().join("h.off"));
    assert_eq!(e.line(), Some(3));
    let e = read_surface(&dir.path().join("missing.stl")).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }), "{e}");
}
