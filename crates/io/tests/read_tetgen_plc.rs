//! Tests of the TetGen PLC readers and writers (`.smesh`, 3D `.poly`) and of the `.poly`
//! dispatch by dimension: good files in their variants, errors naming the line, round trips.

use std::path::Path;

use delmesh_io::{
    parse_poly, parse_poly_any, parse_smesh, parse_tetgen_poly, read_poly_any, read_smesh,
    read_surface, read_tetgen_poly, write_smesh, write_tetgen_poly, AnyPoly, IoError, SurfaceFacet,
    SurfaceFile, SurfaceRegion,
};

/// A unit cube as six quadrilateral facets, numbered from 1, with point and facet markers, a
/// hole and two regions (the second without a volume constraint).
const CUBE_SMESH: &str = "\
# part 1: nodes
8 3 0 1
1 0 0 0 10
2 1 0 0 10
3 1 1 0 10
4 0 1 0 10
5 0 0 1 20
6 1 0 1 20
7 1 1 1 20
8 0 1 1 20
# part 2: facets
6 1
4 1 2 3 4 1
4 5 6 7 8 2
4 1 2 6 5 3
4 2 3 7 6 3
4 3 4 8 7 3
4 4 1 5 8 -4
# part 3: holes
1
1 0.5 0.5 0.5
# part 4: regions
2
1 0.1 0.1 0.1 7 0.01
2 0.9 0.9 0.9 8
";

fn smesh(text: &str) -> Result<SurfaceFile, IoError> {
    parse_smesh(text, Path::new("cube.smesh"))
}

/// Parses `text` as `.smesh`, expects a parse error, returns `(line, message)`.
fn smesh_err(text: &str) -> (usize, String) {
    match smesh(text) {
        Err(IoError::Parse { line, message, .. }) => (line, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

fn quad(v: [u32; 4], marker: i32, line: usize) -> SurfaceFacet {
    SurfaceFacet {
        polygons: vec![v.to_vec()],
        holes: vec![],
        marker,
        line,
    }
}

#[test]
fn smesh_cube_with_markers_holes_and_regions() {
    let s = smesh(CUBE_SMESH).unwrap();
    assert_eq!(s.first_index, 1);
    assert_eq!(s.points.len(), 8);
    assert_eq!(s.points[6], [1.0, 1.0, 1.0]);
    assert_eq!(s.point_markers, Some(vec![10, 10, 10, 10, 20, 20, 20, 20]));
    assert_eq!(s.facets.len(), 6);
    assert_eq!(s.facets[0], quad([0, 1, 2, 3], 1, 13));
    assert_eq!(s.facets[5], quad([3, 0, 4, 7], -4, 18));
    assert_eq!(s.holes, vec![[0.5, 0.5, 0.5]]);
    assert_eq!(
        s.regions,
        vec![
            SurfaceRegion {
                point: [0.1, 0.1, 0.1],
                attribute: 7.0,
                max_volume: Some(0.01)
            },
            SurfaceRegion {
                point: [0.9, 0.9, 0.9],
                attribute: 8.0,
                max_volume: None
            },
        ]
    );
    assert!(s.tetrahedra.is_empty() && !s.is_triangulated());
}

#[test]
fn smesh_without_markers_regions_or_comments() {
    let s = smesh("3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n1 0\n3 0 1 2\n0\n").unwrap();
    assert_eq!(s.first_index, 0);
    assert_eq!(s.point_markers, None);
    assert_eq!(s.facets[0].polygons, vec![vec![0, 1, 2]]);
    assert_eq!(s.facets[0].marker, 0);
    assert!(s.regions.is_empty() && s.holes.is_empty());
    assert!(s.is_triangulated());
}

#[test]
fn smesh_points_in_the_node_file_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tri.node"),
        "3 3 0 1\n1 0 0 0 5\n2 1 0 0 5\n3 0 1 0 6\n",
    )
    .unwrap();
    let path = dir.path().join("tri.smesh");
    std::fs::write(&path, "0 3 0 0\n1 1\n3 1 2 3 9\n0\n").unwrap();
    let s = read_smesh(&path).unwrap();
    assert_eq!(s.points.len(), 3);
    assert_eq!(s.first_index, 1);
    assert_eq!(s.point_markers, Some(vec![5, 5, 6]));
    assert_eq!(s.facets[0].polygons, vec![vec![0, 1, 2]]);
    assert_eq!(s.facets[0].line, 3);
    // From text alone the .node file cannot be found.
    let e = parse_smesh("0 3 0 0\n1 1\n3 1 2 3 9\n0\n", &path).unwrap_err();
    assert!(matches!(e, IoError::InvalidInput { .. }), "{e}");
    // A missing .node file is an I/O error naming it.
    std::fs::remove_file(dir.path().join("tri.node")).unwrap();
    let e = read_smesh(&path).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }), "{e}");
    assert_eq!(e.file(), dir.path().join("tri.node"));
}

#[test]
fn smesh_errors_name_the_line() {
    let cases: Vec<(String, usize, &str)> =
        vec![
        (
            CUBE_SMESH.replace("4 5 6 7 8 2", "4 5 6 7 9 2"),
            14,
            "point 9 does not exist (points are numbered 1 to 8)",
        ),
        (
            CUBE_SMESH.replace("4 5 6 7 8 2", "4 5 6 7 2"),
            14,
            "expected 6 fields for a facet of 4 corners and a marker, found 5",
        ),
        (
            CUBE_SMESH.replace("4 5 6 7 8 2", "5 5 6 7 8 2"),
            14,
            "expected 7 fields for a facet of 5 corners and a marker, found 6",
        ),
        (
            CUBE_SMESH.replace("4 5 6 7 8 2", "99999999999999999999 5 6 7 8 2"),
            14,
            "expected a non-negative integer for the number of corners",
        ),
        (
            CUBE_SMESH.replace("4 5 6 7 8 2", "0"),
            14,
            "facet has no corners",
        ),
        (
            CUBE_SMESH.replace("4 5 6 7 8 2", "4 5 6 7 8 x"),
            14,
            "expected an integer for the facet marker, found 'x'",
        ),
        (
            CUBE_SMESH.replace("3 1 1 0 10", "3 1 nan 0 10"),
            5,
            "y coordinate is not finite: 'nan'",
        ),
        (
            CUBE_SMESH.replace("1 0.5 0.5 0.5", "1 0.5 0.5"),
            21,
            "expected 4 fields for a hole '<i> <x> <y> <z>', found 3",
        ),
        (
            CUBE_SMESH.replace("2 0.9 0.9 0.9 8", "2 0.9 0.9 0.9"),
            25,
            "expected 5 or 6 fields for a region",
        ),
        (
            CUBE_SMESH.replace("6 1\n", "6 2\n"),
            12,
            "facet header must be '<#facets> <#markers 0|1>'",
        ),
        (format!("{CUBE_SMESH}1\n"), 26, "extra data after the regions"),
        (
            CUBE_SMESH[..CUBE_SMESH.find("4 2 3 7 6").unwrap()].to_string(),
            15,
            "unexpected end of file: expected 6 facets (found 3)",
        ),
        (
            CUBE_SMESH[..CUBE_SMESH.find("# part 3").unwrap()].to_string(),
            18,
            "unexpected end of file: expected the hole header '<#holes>'",
        ),
        (
            "3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n1 0\n3 0 1 2\n0\n".into(),
            1,
            "points of dimension 2; a TetGen PLC is 3D",
        ),
        (
            "9 3 0 0\n1 0 0 0\n".into(),
            2,
            "unexpected end of file: the header (line 1) declares 9 points but the file has only 1",
        ),
        (String::new(), 1, "unexpected end of file: expected the point header"),
    ];
    for (text, line, message) in cases {
        let (l, m) = smesh_err(&text);
        assert!(
            l == line && m.contains(message),
            "expected {line}: {message}\n     got {l}: {m}"
        );
    }
}

/// A square facet with a square hole in it (two polygons and a facet hole), a triangle made of
/// a segment and an isolated point polygon, and a two-polygon facet without a marker field.
const POLY3: &str = "\
12 3 0 0
0 0 0 0
1 4 0 0
2 4 4 0
3 0 4 0
4 1 1 0
5 3 1 0
6 3 3 0
7 1 3 0
8 0 0 4
9 2 2 2
10 4 0 4
11 4 4 4
3 1
2 1 5      # two polygons, one hole, marker 5
4 0 1 2 3
4 4 5 6 7
1 2 2 0
2 0
3 0 1 8
2 9 10    # a segment inside the facet
1
1 11
1
1 2 2 -1
";

#[test]
fn tetgen_poly_facets_with_polygons_and_holes() {
    let s = parse_tetgen_poly(POLY3, Path::new("p.poly")).unwrap();
    assert_eq!(s.first_index, 0);
    assert_eq!(s.facets.len(), 3);
    assert_eq!(
        s.facets[0],
        SurfaceFacet {
            polygons: vec![vec![0, 1, 2, 3], vec![4, 5, 6, 7]],
            holes: vec![[2.0, 2.0, 0.0]],
            marker: 5,
            line: 15,
        }
    );
    assert_eq!(s.facets[1].polygons, vec![vec![0, 1, 8], vec![9, 10]]);
    assert_eq!((s.facets[1].marker, s.facets[1].line), (0, 19));
    assert_eq!(s.facets[2].polygons, vec![vec![11]]);
    assert_eq!(s.holes, vec![[2.0, 2.0, -1.0]]);
    assert!(s.regions.is_empty());

    let e = |text: String| {
        parse_tetgen_poly(&text, Path::new("p.poly"))
            .unwrap_err()
            .to_string()
    };
    assert_eq!(
        e(POLY3.replace("4 4 5 6 7", "4 4 5 6 7 8")),
        "p.poly:17: expected 5 fields for a polygon of 4 corners, found 6"
    );
    assert_eq!(
        e(POLY3.replace("1 2 2 0\n", "1 2 2\n")),
        "p.poly:18: expected 4 fields for a facet hole '<i> <x> <y> <z>', found 3"
    );
    assert_eq!(
        e(POLY3.replace("2 1 5  ", "2 1 5 7")),
        "p.poly:15: expected at most 3 fields for a facet header '<#polygons> [<#holes>] \
         [<marker>]', found 4"
    );
    assert_eq!(
        e(POLY3.replace("2 1 5  ", "0 1 5  ")),
        "p.poly:15: a facet needs at least one polygon"
    );
    assert_eq!(
        e(POLY3.replace("3 0 1 8", "3 0 1 12")),
        "p.poly:20: point 12 does not exist (points are numbered 0 to 11)"
    );
    let cut = &POLY3[..POLY3.find("1 2 2 0").unwrap()];
    assert_eq!(
        e(cut.to_string()),
        "p.poly:17: unexpected end of file: expected hole 1 of 1 of the facet on line 15"
    );
}

#[test]
fn poly_dispatch_by_dimension() {
    let three = parse_poly_any(POLY3, Path::new("p.poly")).unwrap();
    assert!(matches!(three, AnyPoly::TetGen(ref s) if s.facets.len() == 3));
    let two_d = "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n";
    let two = parse_poly_any(two_d, Path::new("q.poly")).unwrap();
    assert!(matches!(two, AnyPoly::Triangle(ref p) if p.segments.len() == 3));
    // The 2D reader points to the 3D one, and the other way round.
    let e = parse_poly(POLY3, Path::new("p.poly")).unwrap_err();
    assert!(e.to_string().contains("read_tetgen_poly"), "{e}");
    let e = parse_tetgen_poly(two_d, Path::new("q.poly")).unwrap_err();
    assert!(
        e.to_string().contains("read 2D .poly files with read_poly"),
        "{e}"
    );

    let dir = tempfile::tempdir().unwrap();
    let p3 = dir.path().join("p.poly");
    std::fs::write(&p3, POLY3).unwrap();
    let q2 = dir.path().join("q.poly");
    std::fs::write(&q2, two_d).unwrap();
    assert_eq!(read_poly_any(&p3).unwrap(), three);
    assert_eq!(read_poly_any(&q2).unwrap(), two);
    assert_eq!(read_surface(&p3).unwrap(), read_tetgen_poly(&p3).unwrap());
    assert!(read_surface(&q2).is_err());
}

/// The file with every facet's source line set to 0, to compare what was written with what is
/// read back (the writers lay lines out their own way).
fn without_lines(mut s: SurfaceFile) -> SurfaceFile {
    for f in &mut s.facets {
        f.line = 0;
    }
    s
}

#[test]
fn smesh_and_poly_round_trips_are_exact() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = smesh(CUBE_SMESH).unwrap();
    s.points[1] = [0.1 + 0.2, 1e-300, -0.0];
    let path = dir.path().join("out.smesh");
    write_smesh(&path, &s).unwrap();
    let back = read_smesh(&path).unwrap();
    assert_eq!(without_lines(back.clone()), without_lines(s.clone()));
    assert_eq!(back.points[1][2].to_bits(), (-0.0f64).to_bits());

    let p = parse_tetgen_poly(POLY3, Path::new("p.poly")).unwrap();
    let path = dir.path().join("out.poly");
    write_tetgen_poly(&path, &p).unwrap();
    assert_eq!(
        without_lines(read_tetgen_poly(&path).unwrap()),
        without_lines(p.clone())
    );
    // A .poly facet with two polygons does not fit a .smesh file.
    let e = write_smesh(&dir.path().join("no.smesh"), &p).unwrap_err();
    assert!(
        e.to_string().contains("facet 0 has several polygons"),
        "{e}"
    );
    // Bad indices are refused before writing.
    let mut bad = s.clone();
    bad.facets[2].polygons[0][1] = 8;
    let e = write_smesh(&dir.path().join("no.smesh"), &bad).unwrap_err();
    assert!(
        e.to_string()
            .contains("facet 2 refers to point 8 but there are 8 points"),
        "{e}"
    );
    assert!(!dir.path().join("no.smesh").exists());
}
