//! Tests of the `.node` / `.ele` / `.neigh` writers: snapshots of a two-triangle mesh, bit-exact
//! round trips, input checks, and the atomic-write guarantees seen from the public API.

use std::path::{Path, PathBuf};

use delmesh_io::{
    read_node, write_ele, write_neigh, write_node, write_tetgen_family, IoError, SimplexMesh,
};

/// The unit square split along its diagonal 0-2.
const SQUARE: [f64; 8] = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0];
const TRIS: [u32; 6] = [0, 1, 2, 0, 2, 3];
/// Neighbour of each triangle across the edge opposite each local vertex.
const NEIGH: [i64; 6] = [-1, 1, -1, -1, -1, 0];

fn square_mesh() -> SimplexMesh<'static> {
    SimplexMesh {
        dim: 2,
        coords: &SQUARE,
        cells: &TRIS,
        neighbors: Some(&NEIGH),
    }
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn two_triangles_one_based_snapshots() {
    let dir = tempfile::tempdir().unwrap();
    let ele = dir.path().join("square.ele");
    let written = write_tetgen_family(&ele, &square_mesh(), 1).unwrap();
    let names: Vec<_> = written
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["square.node", "square.ele", "square.neigh"]);
    assert!(written.iter().all(|p| p.parent() == Some(dir.path())));
    assert_eq!(
        entries(dir.path()),
        ["square.ele", "square.neigh", "square.node"]
    );

    insta::assert_snapshot!("square_1_node", read(&written[0]));
    insta::assert_snapshot!("square_1_ele", read(&written[1]));
    insta::assert_snapshot!("square_1_neigh", read(&written[2]));

    // The .node file reads back as the same points.
    let p = read_node(&written[0]).unwrap();
    assert_eq!(p.first_index, 1);
    assert_eq!(p.coords, SQUARE);
}

#[test]
fn two_triangles_zero_based_snapshots() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = square_mesh();
    let node = dir.path().join("square.node");
    let ele = dir.path().join("square.ele");
    let neigh = dir.path().join("square.neigh");
    write_node(&node, 2, mesh.coords, 0).unwrap();
    write_ele(&ele, &mesh, 0).unwrap();
    write_neigh(&neigh, &mesh, 0).unwrap();
    insta::assert_snapshot!("square_0_node", read(&node));
    insta::assert_snapshot!("square_0_ele", read(&ele));
    insta::assert_snapshot!("square_0_neigh", read(&neigh));
}

#[test]
fn family_without_neighbours_and_name_handling() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = SimplexMesh {
        neighbors: None,
        ..square_mesh()
    };
    // `mesh.1.ele` keeps its `.1`; a path without `.ele` gets the extensions appended.
    let written = write_tetgen_family(&dir.path().join("mesh.1.ele"), &mesh, 0).unwrap();
    assert_eq!(
        written,
        [
            dir.path().join("mesh.1.node"),
            dir.path().join("mesh.1.ele")
        ]
    );
    let written = write_tetgen_family(&dir.path().join("out"), &mesh, 0).unwrap();
    assert_eq!(
        written,
        [dir.path().join("out.node"), dir.path().join("out.ele")]
    );
    assert_eq!(
        entries(dir.path()),
        ["mesh.1.ele", "mesh.1.node", "out.ele", "out.node"]
    );
}

#[test]
fn tetrahedra() {
    let dir = tempfile::tempdir().unwrap();
    let coords = [
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0,
    ];
    let cells = [0, 1, 2, 3, 1, 2, 3, 4];
    let neighbors = [1, -1, -1, -1, -1, -1, -1, 0];
    let mesh = SimplexMesh {
        dim: 3,
        coords: &coords,
        cells: &cells,
        neighbors: Some(&neighbors),
    };
    let written = write_tetgen_family(&dir.path().join("tets.ele"), &mesh, 1).unwrap();
    assert_eq!(read(&written[1]), "2 4 0\n1 1 2 3 4\n2 2 3 4 5\n");
    assert_eq!(read(&written[2]), "2 4\n1 2 -1 -1 -1\n2 -1 -1 -1 1\n");
    let p = read_node(&written[0]).unwrap();
    assert_eq!((p.dim, p.len(), p.first_index), (3, 5, 1));
    assert_eq!(p.coords, coords);
}

#[test]
fn node_round_trip_is_bit_exact() {
    let awkward = [
        1e-300,
        -0.0,
        0.1 + 0.2,
        1e300,
        -1e300,
        5e-324,
        f64::MIN_POSITIVE,
        f64::MAX,
        f64::MIN,
        f64::EPSILON,
        1.0 / 3.0,
        -2.0 / 3.0,
        123_456_789.0 + 1.0 / 7.0,
        1e16,
        9_007_199_254_740_992.0 + 2.0,
        1e-5,
        9.999_999_999_999_999e-6,
        std::f64::consts::PI,
    ];
    let dir = tempfile::tempdir().unwrap();
    for dim in [2, 3] {
        let n = awkward.len() / dim * dim;
        for first_index in [0, 1] {
            let path = dir.path().join(format!("awkward{dim}{first_index}.node"));
            write_node(&path, dim, &awkward[..n], first_index).unwrap();
            let p = read_node(&path).unwrap();
            assert_eq!((p.dim, p.first_index), (dim, first_index));
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&p.coords), bits(&awkward[..n]));
        }
    }
    // Extreme magnitudes are written with an exponent, not hundreds of digits.
    let text = read(&dir.path().join("awkward20.node"));
    assert!(text.lines().all(|l| l.len() < 80), "{text}");
    assert!(text.contains(" 1e-300 -0\n"), "{text}");
}

#[test]
fn invalid_input_is_rejected_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.node");
    let check = |result: Result<(), IoError>, needle: &str| {
        let err = result.unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
        assert!(err.to_string().contains(needle), "{err} lacks {needle:?}");
    };
    check(
        write_node(&path, 4, &[0.0; 8], 0),
        "dimension must be 2 or 3",
    );
    check(
        write_node(&path, 2, &[0.0; 3], 0),
        "not a multiple of the dimension",
    );
    check(
        write_node(&path, 2, &[0.0, 1.0, f64::NAN, 0.0], 0),
        "coordinate 0 of point 1 is not finite",
    );
    check(
        write_node(&path, 2, &[0.0, 1.0], 2),
        "first index must be 0 or 1",
    );

    let ele = dir.path().join("bad.ele");
    let bad_cells = [0, 1, 4];
    let mesh = SimplexMesh {
        cells: &bad_cells,
        neighbors: None,
        ..square_mesh()
    };
    check(write_ele(&ele, &mesh, 0), "cell 0 refers to point 4");
    let short_cells = [0, 1];
    let mesh = SimplexMesh {
        cells: &short_cells,
        neighbors: None,
        ..square_mesh()
    };
    check(write_ele(&ele, &mesh, 0), "not a multiple of 3");
    let bad_neigh = [-1, 2, -1, -1, -1, 0];
    let mesh = SimplexMesh {
        neighbors: Some(&bad_neigh),
        ..square_mesh()
    };
    check(write_neigh(&ele, &mesh, 0), "cell 0 has neighbour 2");
    let mesh = SimplexMesh {
        neighbors: Some(&NEIGH[..3]),
        ..square_mesh()
    };
    check(write_ele(&ele, &mesh, 0), "neighbour array has 3 entries");
    let mesh = SimplexMesh {
        neighbors: None,
        ..square_mesh()
    };
    check(write_neigh(&ele, &mesh, 0), "no neighbour array");
    let err = write_tetgen_family(&dir.path().join("fam.ele"), &mesh, 7).unwrap_err();
    assert!(matches!(err, IoError::InvalidInput { .. }));

    assert!(entries(dir.path()).is_empty(), "{:?}", entries(dir.path()));
}

#[test]
fn failed_write_does_not_clobber_the_target() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("keep.node");
    std::fs::write(&path, "old\n").unwrap();
    // Invalid input: the old file stays.
    assert!(write_node(&path, 2, &[f64::INFINITY, 0.0], 0).is_err());
    assert_eq!(read(&path), "old\n");
    // A good write replaces it and leaves no temp file behind.
    write_node(&path, 2, &[1.0, 2.0], 0).unwrap();
    assert_eq!(read(&path), "1 2 0 0\n0 1 2\n");
    assert_eq!(entries(dir.path()), ["keep.node"]);
}

#[test]
fn writing_into_a_missing_directory_is_an_io_error() {
    let dir = tempfile::tempdir().unwrap();
    let path: PathBuf = dir.path().join("nope").join("x.node");
    let err = write_node(&path, 2, &[1.0, 2.0], 0).unwrap_err();
    assert!(matches!(err, IoError::Io { .. }), "{err:?}");
    assert_eq!(err.file(), path);
    assert!(err.to_string().starts_with(&path.display().to_string()));
    let err =
        write_tetgen_family(&dir.path().join("nope").join("m.ele"), &square_mesh(), 0).unwrap_err();
    assert!(matches!(err, IoError::Io { .. }), "{err:?}");
    assert!(entries(dir.path()).is_empty());
}
