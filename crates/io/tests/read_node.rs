//! Tests of the `.node` reader: good files in every variant (0/1-based, attributes, markers,
//! comments), every error path with the line it must name, and garbage that must not panic.

use std::path::Path;

use delmesh_io::{parse_node, read_node, read_points, IoError, PointSet};

fn parse(text: &str) -> Result<PointSet, IoError> {
    parse_node(text, Path::new("points.node"))
}

/// Parses `text`, expects a parse error, and returns `(line, message)`.
fn parse_err(text: &str) -> (usize, String) {
    match parse(text) {
        Err(IoError::Parse {
            file,
            line,
            message,
        }) => {
            assert_eq!(file, Path::new("points.node"));
            (line, message)
        }
        other => panic!("expected a parse error for {text:?}, got {other:?}"),
    }
}

#[test]
fn zero_based_2d_plain() {
    let p = parse("3 2 0 0\n0 0 0\n1 1.5 0\n2 0 -2.25\n").unwrap();
    assert_eq!(p.dim, 2);
    assert_eq!(p.len(), 3);
    assert!(!p.is_empty());
    assert_eq!(p.first_index, 0);
    assert_eq!(p.coords, vec![0.0, 0.0, 1.5, 0.0, 0.0, -2.25]);
    assert!(p.attributes.is_empty());
    assert_eq!(p.markers, None);
    assert_eq!(p.point2(1), [1.5, 0.0]);
    assert_eq!(p.point3(2), [0.0, -2.25, 0.0]);
}

#[test]
fn one_based_3d_with_attributes_markers_and_comments() {
    let text = "\
# TetGen node file
# written by hand

  4  3  2  1   # header with trailing comment
1  0 0 0   10 100   5
2  1 0 0   11 101  -1 # a comment after the data
# a comment between points

3  0 1 0   12 102   0
4  0 0 1e2 13 103   7
";
    let p = parse(text).unwrap();
    assert_eq!(p.dim, 3);
    assert_eq!(p.len(), 4);
    assert_eq!(p.first_index, 1);
    assert_eq!(p.point3(3), [0.0, 0.0, 100.0]);
    assert_eq!(p.point2(3), [0.0, 0.0]);
    assert_eq!(
        p.attributes,
        vec![
            vec![10.0, 11.0, 12.0, 13.0],
            vec![100.0, 101.0, 102.0, 103.0]
        ]
    );
    assert_eq!(p.markers, Some(vec![5, -1, 0, 7]));
}

#[test]
fn short_header_defaults_attributes_and_markers_to_zero() {
    let p = parse("2 2\n1 0 0\n2 1 1\n").unwrap();
    assert_eq!(p.len(), 2);
    assert_eq!(p.first_index, 1);
    let p = parse("1 3 1\n0 1 2 3 4.5\n").unwrap();
    assert_eq!(p.attributes, vec![vec![4.5]]);
    assert_eq!(p.markers, None);
}

#[test]
fn windows_line_endings_and_bom() {
    let p = parse("\u{feff}2 2 0 0\r\n0 1 2\r\n1 3 4\r\n").unwrap();
    assert_eq!(p.coords, vec![1.0, 2.0, 3.0, 4.0]);
}

#[test]
fn empty_point_set() {
    let p = parse("0 3 0 0\n").unwrap();
    assert!(p.is_empty());
    assert_eq!(p.dim, 3);
    let p = parse("# nothing\n0 2 2 1\n").unwrap();
    assert!(p.is_empty());
    assert_eq!(p.attributes, vec![Vec::<f64>::new(), Vec::new()]);
    assert_eq!(p.markers, Some(vec![]));
}

#[test]
fn error_display_names_file_and_line() {
    let err = parse("2 2 0 1\n0 0 0 1\n1 1\n").unwrap_err();
    assert_eq!(err.line(), Some(3));
    assert_eq!(err.file(), Path::new("points.node"));
    let shown = err.to_string();
    assert!(
        shown.starts_with("points.node:3: expected 4 fields, found 2"),
        "{shown}"
    );
}

#[test]
fn attributes_and_markers_a_line_leaves_out_read_as_zero() {
    // As Triangle reads them: the header declares two attributes and a marker, the second
    // line gives one attribute and no marker, the third neither.
    let p = parse("3 2 2 1\n0 0 0 5 6 1\n1 1 0 7\n2 0 1\n").unwrap();
    assert_eq!(p.attributes, vec![vec![5.0, 7.0, 0.0], vec![6.0, 0.0, 0.0]]);
    assert_eq!(p.markers, Some(vec![1, 0, 0]));
    // More fields than declared are still an error (a header that miscounts them).
    assert!(parse("1 2 0 0\n0 0 0 9\n").is_err());
}

#[test]
fn every_error_names_its_line() {
    let cases: &[(&str, usize, &str)] = &[
        // (text, expected line, part of the message)
        ("", 1, "missing header"),
        ("# only a comment\n\n", 2, "missing header"),
        ("3\n", 1, "expected 2 to 4 header fields"),
        ("3 2 0 0 9\n", 1, "expected 2 to 4 header fields"),
        ("# c\nthree 2 0 0\n", 2, "number of points"),
        (
            "-1 2 0 0\n",
            1,
            "non-negative integer for the number of points",
        ),
        (
            "1 4 0 0\n0 1 2 3 4\n",
            1,
            "dimension must be 2 or 3, found 4",
        ),
        ("1 1 0 0\n0 1\n", 1, "dimension must be 2 or 3, found 1"),
        ("1 2.0 0 0\n0 1 2\n", 1, "dimension"),
        ("1 2 0 2\n0 1 2 3 4\n", 1, "boundary markers must be 0 or 1"),
        ("1 2 x 0\n", 1, "number of attributes"),
        (
            "1 2 99999999 0\n0 1 2\n",
            1,
            "implausible number of attributes",
        ),
        ("2 2 0 0\n0 1 2\n1 3\n", 3, "expected 3 fields, found 2"),
        ("2 2 0 0\n0 1 2\n1 3 4 5\n", 3, "expected 3 fields, found 4"),
        (
            "2 2 0 0\n0 1 2\n\n# gap\n1 3 x\n",
            5,
            "non-numeric token 'x' for the y coordinate",
        ),
        ("1 3 0 0\n0 1 2 zz\n", 2, "for the z coordinate"),
        ("1 2 0 0\n0 nan 2\n", 2, "x coordinate is not finite"),
        ("1 2 0 0\n0 1 inf\n", 2, "y coordinate is not finite"),
        (
            "1 3 0 0\n0 1 2 -infinity\n",
            2,
            "z coordinate is not finite",
        ),
        ("1 2 0 0\n0 1e999 2\n", 2, "x coordinate is not finite"),
        (
            "1 2 1 0\n0 1 2 abc\n",
            2,
            "non-numeric token 'abc' for attribute 1",
        ),
        (
            "1 2 0 1\n0 1 2 1.5\n",
            2,
            "boundary marker must be an integer, found '1.5'",
        ),
        (
            "1 2 0 0\n2 1 2\n",
            2,
            "first point index must be 0 or 1, found 2",
        ),
        (
            "1 2 0 0\n-1 1 2\n",
            2,
            "first point index must be 0 or 1, found -1",
        ),
        ("1 2 0 0\n0.0 1 2\n", 2, "point index must be an integer"),
        (
            "3 2 0 0\n1 0 0\n2 1 1\n4 2 2\n",
            4,
            "point index 4 is not consecutive: expected 3",
        ),
        (
            "3 2 0 0\n0 0 0\n0 1 1\n2 2 2\n",
            3,
            "point index 0 is not consecutive: expected 1",
        ),
        (
            "3 2 0 0\n0 0 0\n1 1 1\n",
            3,
            "declares 3 points but the file has only 2",
        ),
        (
            "3 2 0 0\n0 0 0\n1 1 1\n# trailing comment\n\n",
            5,
            "declares 3 points but the file has only 2",
        ),
        (
            "1 2 0 0\n0 0 0\n1 1 1\n",
            3,
            "extra data after the 1 points",
        ),
    ];
    for &(text, line, needle) in cases {
        let (got_line, message) = parse_err(text);
        assert_eq!(got_line, line, "line for {text:?} ({message})");
        assert!(
            message.contains(needle),
            "message for {text:?} is {message:?}, expected it to contain {needle:?}"
        );
    }
}

#[test]
fn long_garbage_tokens_are_shortened_in_messages() {
    let token = "g".repeat(10_000);
    let (_, message) = parse_err(&format!("1 2 0 0\n0 {token} 1\n"));
    assert!(message.len() < 200, "{message}");
}

/// A small deterministic generator, so the garbage test needs no extra dependency.
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

#[test]
fn garbage_and_truncated_input_never_panics() {
    let good = "# header\n5 3 2 1\n1 0 0 0 1 2 3\n2 1e-300 -0 5 4 5 -6\n3 0.1 0.2 0.3 7 8 9\n\
                4 1 1 1 1 1 1 # c\n5 -1 -1 -1 0 0 0\n";
    assert_eq!(parse(good).unwrap().len(), 5);
    // Every prefix (truncation) of a good file.
    for end in 0..=good.len() {
        if good.is_char_boundary(end) {
            let _ = parse(&good[..end]);
        }
    }
    // Single-byte corruptions of a good file.
    let alphabet = b" \n\t#-+.eE0123456789xnaif\r";
    let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
    for _ in 0..3000 {
        let mut bytes = good.as_bytes().to_vec();
        let pos = (rng.next() % bytes.len() as u64) as usize;
        bytes[pos] = alphabet[(rng.next() % alphabet.len() as u64) as usize];
        let text = String::from_utf8(bytes).unwrap();
        let _ = parse(&text);
    }
    // Pure noise, including huge numbers in the header.
    for _ in 0..3000 {
        let len = (rng.next() % 80) as usize;
        let text: String = (0..len)
            .map(|_| alphabet[(rng.next() % alphabet.len() as u64) as usize] as char)
            .collect();
        let _ = parse(&text);
    }
    for text in [
        "18446744073709551615 3 0 0\n0 1 2 3\n",
        "18446744073709551616 3 0 0\n",
        "99999999999999999 2 0 0\n",
        "1 3 18446744073709551615 1\n0 1 2 3\n",
        "1 3 0 18446744073709551615\n",
        "1 2 0 0\n9223372036854775807 1 2\n",
        "2 2 0 0\n1 1 2\n9223372036854775807 1 2\n",
        "1 2 0 1\n0 1 2 99999999999\n",
        "\u{0}\u{1}\u{2}",
        "é ü 中文",
        "#",
        "\n\n\n",
    ] {
        let _ = parse(text);
    }
}

#[test]
fn read_node_from_disk_and_errors_name_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.node");
    std::fs::write(&path, "2 2 0 0\n1 0.5 0.25\n2 3 4\n").unwrap();
    let p = read_node(&path).unwrap();
    assert_eq!(p.first_index, 1);
    assert_eq!(p.coords, vec![0.5, 0.25, 3.0, 4.0]);
    assert_eq!(read_points(&path).unwrap(), p);

    std::fs::write(&path, "2 2 0 0\n1 0.5 0.25\n").unwrap();
    let err = read_node(&path).unwrap_err();
    assert_eq!(err.file(), path);
    assert!(err
        .to_string()
        .starts_with(&format!("{}:2: ", path.display())));

    // Not UTF-8: an error on the right line, not a panic.
    std::fs::write(&path, b"1 2 0 0\n0 1 \xff\n").unwrap();
    let err = read_node(&path).unwrap_err();
    assert_eq!(err.line(), Some(2), "{err}");

    let missing = dir.path().join("missing.node");
    let err = read_node(&missing).unwrap_err();
    assert!(matches!(err, IoError::Io { .. }), "{err:?}");
    assert_eq!(err.file(), missing);
}
