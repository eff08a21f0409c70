//! Tests of the plain-text point reader and of `read_points`' dispatch on the extension.

use std::path::Path;

use delmesh_io::{parse_xyz, read_points, read_xyz, IoError};

fn parse_err(text: &str) -> (usize, String) {
    match parse_xyz(text, Path::new("pts.xyz")) {
        Err(IoError::Parse { line, message, .. }) => (line, message),
        other => panic!("expected a parse error for {text:?}, got {other:?}"),
    }
}

#[test]
fn two_and_three_columns() {
    let p = parse_xyz("# pts\n0 0\n1 0.5\n\n-2 3 # c\n", Path::new("a.txt")).unwrap();
    assert_eq!(p.dim, 2);
    assert_eq!(p.len(), 3);
    assert_eq!(p.first_index, 0);
    assert_eq!(p.coords, vec![0.0, 0.0, 1.0, 0.5, -2.0, 3.0]);
    assert!(p.attributes.is_empty());
    assert_eq!(p.markers, None);

    let p = parse_xyz("1 2 3\r\n4 5 6\r\n", Path::new("a.xyz")).unwrap();
    assert_eq!(p.dim, 3);
    assert_eq!(p.point3(1), [4.0, 5.0, 6.0]);
}

#[test]
fn errors_name_the_line() {
    let cases: &[(&str, usize, &str)] = &[
        ("", 1, "no points found"),
        ("# a\n# b\n\n", 3, "no points found"),
        ("1\n", 1, "expected 2 or 3 columns"),
        (
            "# c\n1 2 3 4\n",
            2,
            "expected 2 or 3 columns (x y [z]), found 4",
        ),
        (
            "1 2\n3 4\n5 6 7\n",
            3,
            "expected 2 columns like line 1, found 3",
        ),
        (
            "\n1 2 3\n4 5\n",
            3,
            "expected 3 columns like line 2, found 2",
        ),
        (
            "1 2\n3 y\n",
            2,
            "non-numeric token 'y' for the y coordinate",
        ),
        ("1 2 3\n3 4 NaN\n", 2, "z coordinate is not finite"),
        ("inf 2\n", 1, "x coordinate is not finite"),
    ];
    for &(text, line, needle) in cases {
        let (got_line, message) = parse_err(text);
        assert_eq!(got_line, line, "line for {text:?} ({message})");
        assert!(
            message.contains(needle),
            "{text:?}: {message:?} lacks {needle:?}"
        );
    }
    let err = parse_xyz("1 2\n3\n", Path::new("dir/pts.xyz")).unwrap_err();
    assert_eq!(
        err.to_string(),
        "dir/pts.xyz:2: expected 2 columns like line 1, found 1"
    );
}

#[test]
fn garbage_never_panics() {
    let good = "0 0 0\n1e-300 -0 5\n0.1 0.2 0.3\n";
    for end in 0..=good.len() {
        let _ = parse_xyz(&good[..end], Path::new("g.xyz"));
    }
    for text in [
        "\u{0}", "- -", "1e", "e1 2", ". .", "+ -", "0x10 1", "1,2", "中 文",
    ] {
        let _ = parse_xyz(text, Path::new("g.xyz"));
    }
}

#[test]
fn read_points_dispatches_on_extension() {
    let dir = tempfile::tempdir().unwrap();
    let xyz = dir.path().join("p.xyz");
    std::fs::write(&xyz, "0 0\n1 1\n").unwrap();
    assert_eq!(read_points(&xyz).unwrap(), read_xyz(&xyz).unwrap());

    let txt = dir.path().join("p.TXT");
    std::fs::write(&txt, "0 0 1\n").unwrap();
    assert_eq!(read_points(&txt).unwrap().dim, 3);

    let no_ext = dir.path().join("points");
    std::fs::write(&no_ext, "0 0 1\n").unwrap();
    assert_eq!(read_points(&no_ext).unwrap().len(), 1);

    let node = dir.path().join("p.NODE");
    std::fs::write(&node, "1 2 0 0\n1 5 6\n").unwrap();
    let p = read_points(&node).unwrap();
    assert_eq!(p.first_index, 1);
    assert_eq!(p.coords, vec![5.0, 6.0]);

    let vtu = dir.path().join("mesh.vtu");
    std::fs::write(&vtu, "<VTKFile/>").unwrap();
    let err = read_points(&vtu).unwrap_err();
    assert!(matches!(err, IoError::UnknownFormat { .. }), "{err:?}");
    assert_eq!(err.file(), vtu);

    let err = read_points(&dir.path().join("missing.xyz")).unwrap_err();
    assert!(matches!(err, IoError::Io { .. }), "{err:?}");
}
