//! Tests of the `.vtu` writers: a snapshot of a tiny file, and round trips read back with
//! `vtkio` checking point and cell counts, cell types, coordinates and field values.

use std::path::Path;

use delmesh_io::{write_vtu, write_vtu_polygons, IoError, SimplexMesh};
use vtkio::model::{Attribute, CellType, DataSet, IOBuffer, Piece, UnstructuredGridPiece, Vtk};

const SQUARE: [f64; 8] = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0];
const TRIS: [u32; 6] = [0, 1, 2, 0, 2, 3];

fn square_mesh() -> SimplexMesh<'static> {
    SimplexMesh {
        dim: 2,
        coords: &SQUARE,
        cells: &TRIS,
        neighbors: None,
    }
}

/// Reads a `.vtu` file back with vtkio and returns its single unstructured-grid piece.
fn read_piece(path: &Path) -> UnstructuredGridPiece {
    let vtk = Vtk::import(path).unwrap();
    match vtk.data {
        DataSet::UnstructuredGrid { pieces, .. } => {
            assert_eq!(pieces.len(), 1);
            match pieces.into_iter().next().unwrap() {
                Piece::Inline(piece) => *piece,
                other => panic!("expected an inline piece, got {other:?}"),
            }
        }
        other => panic!("expected an unstructured grid, got {other:?}"),
    }
}

fn f64s(buf: &IOBuffer) -> Vec<f64> {
    match buf {
        IOBuffer::F64(v) => v.clone(),
        other => panic!("expected Float64 data, got {other:?}"),
    }
}

fn field<'a>(attrs: &'a [Attribute], name: &str) -> &'a IOBuffer {
    attrs
        .iter()
        .find_map(|a| match a {
            Attribute::DataArray(d) if d.name == name => Some(&d.data),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no field {name} in {attrs:?}"))
}

#[test]
fn tiny_vtu_snapshot() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("square.vtu");
    let quality = [0.5, 0.25];
    write_vtu(&path, &square_mesh(), &[], &[("quality", &quality)]).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    // vtkio writes the XML on one line; one tag per line makes the snapshot reviewable.
    insta::assert_snapshot!("square_vtu", text.replace("><", ">\n<"));
    // Writing the same thing again gives the same bytes.
    let again = dir.path().join("again.vtu");
    write_vtu(&again, &square_mesh(), &[], &[("quality", &quality)]).unwrap();
    assert_eq!(std::fs::read_to_string(&again).unwrap(), text);
}

#[test]
fn triangle_round_trip_with_fields() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tri.vtu");
    let height = [0.0, 1e-300, -0.0, f64::NAN];
    let id = [7.0, 8.0];
    let area = [0.5, 0.5];
    write_vtu(
        &path,
        &square_mesh(),
        &[("height", &height)],
        &[("id", &id), ("area", &area)],
    )
    .unwrap();
    let piece = read_piece(&path);
    assert_eq!(piece.num_points(), 4);
    assert_eq!(piece.cells.num_cells(), 2);
    assert_eq!(piece.cells.types, vec![CellType::Triangle; 2]);
    assert_eq!(
        f64s(&piece.points),
        [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0]
    );
    let (connectivity, offsets) = piece.cells.cell_verts.clone().into_xml();
    assert_eq!(connectivity, [0, 1, 2, 0, 2, 3]);
    assert_eq!(offsets, [3, 6]);
    let h = f64s(field(&piece.data.point, "height"));
    assert_eq!(
        h[..3].iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        [0.0f64.to_bits(), 1e-300f64.to_bits(), (-0.0f64).to_bits()]
    );
    assert!(h[3].is_nan());
    assert_eq!(f64s(field(&piece.data.cell, "id")), id);
    assert_eq!(f64s(field(&piece.data.cell, "area")), area);
}

#[test]
fn tetra_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tets.vtu");
    let coords = [
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0,
    ];
    let cells = [0, 1, 2, 3, 1, 2, 3, 4];
    let mesh = SimplexMesh {
        dim: 3,
        coords: &coords,
        cells: &cells,
        neighbors: None,
    };
    write_vtu(&path, &mesh, &[], &[]).unwrap();
    let piece = read_piece(&path);
    assert_eq!(piece.num_points(), 5);
    assert_eq!(piece.cells.num_cells(), 2);
    assert_eq!(piece.cells.types, vec![CellType::Tetra; 2]);
    assert_eq!(f64s(&piece.points), coords);
}

/// Polygons as the flat `ends` and `corners` of `write_vtu_polygons`.
fn flat(polygons: &[Vec<u32>]) -> (Vec<usize>, Vec<u32>) {
    let corners: Vec<u32> = polygons.concat();
    let ends = polygons
        .iter()
        .scan(0, |end, p| {
            *end += p.len();
            Some(*end)
        })
        .collect();
    (ends, corners)
}

#[test]
fn polygons_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("voronoi.vtu");
    // A square and a pentagon sharing an edge, in 2D.
    let coords = [
        0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 2.0, 0.0, 2.5, 0.5, 2.0, 1.0,
    ];
    let polygons = vec![vec![0, 1, 2, 3], vec![1, 4, 5, 6, 2]];
    let site = [10.0, 11.0];
    let (ends, corners) = flat(&polygons);
    write_vtu_polygons(&path, 2, &coords, &ends, &corners, &[("site", &site)]).unwrap();
    let piece = read_piece(&path);
    assert_eq!(piece.num_points(), 7);
    assert_eq!(piece.cells.num_cells(), 2);
    assert_eq!(piece.cells.types, vec![CellType::Polygon; 2]);
    let (connectivity, offsets) = piece.cells.cell_verts.clone().into_xml();
    assert_eq!(connectivity, [0, 1, 2, 3, 1, 4, 5, 6, 2]);
    assert_eq!(offsets, [4, 9]);
    assert_eq!(f64s(field(&piece.data.cell, "site")), site);

    // 3D polygons (faces of a polyhedron) too.
    let path3 = dir.path().join("faces.vtu");
    let coords3 = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let faces = vec![vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![0, 3, 2]];
    let (ends, corners) = flat(&faces);
    write_vtu_polygons(&path3, 3, &coords3, &ends, &corners, &[]).unwrap();
    let piece = read_piece(&path3);
    assert_eq!(piece.num_points(), 4);
    assert_eq!(piece.cells.num_cells(), 4);
}

#[test]
fn empty_mesh_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty.vtu");
    let mesh = SimplexMesh {
        dim: 3,
        coords: &[],
        cells: &[],
        neighbors: None,
    };
    write_vtu(&path, &mesh, &[], &[]).unwrap();
    let piece = read_piece(&path);
    assert_eq!(piece.num_points(), 0);
    assert_eq!(piece.cells.num_cells(), 0);
    // The piece says it has no cells (vtkio left `NumberOfCells` out, which VTK and
    // delmesh's own reader refuse): the 3D Voronoi faces of 4 points, none bounded.
    let faces = dir.path().join("no-faces.vtu");
    write_vtu_polygons(&faces, 3, &[], &[], &[], &[("point", &[])]).unwrap();
    let text = std::fs::read_to_string(&faces).unwrap();
    assert!(text.contains("<Piece NumberOfCells=\"0\""), "{text}");
    for p in [&path, &faces] {
        let m = delmesh_io::read_vtu(p).unwrap();
        assert_eq!(m.coords.len(), 0);
    }
}

#[test]
fn invalid_input_leaves_the_target_alone() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("keep.vtu");
    std::fs::write(&path, "old").unwrap();
    let check = |result: Result<(), IoError>, needle: &str| {
        let err = result.unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
        assert!(err.to_string().contains(needle), "{err} lacks {needle:?}");
    };
    let short = [1.0];
    check(
        write_vtu(&path, &square_mesh(), &[("h", &short)], &[]),
        "point field 'h' has 1 values, expected one per point (4)",
    );
    check(
        write_vtu(&path, &square_mesh(), &[], &[("q", &short)]),
        "cell field 'q' has 1 values, expected one per cell (2)",
    );
    let two = [1.0, 2.0];
    check(
        write_vtu(&path, &square_mesh(), &[], &[("q", &two), ("q", &two)]),
        "used twice",
    );
    let bad = [0, 1, 9, 0, 2, 3];
    let mesh = SimplexMesh {
        cells: &bad,
        ..square_mesh()
    };
    check(write_vtu(&path, &mesh, &[], &[]), "refers to point 9");
    check(
        write_vtu_polygons(&path, 2, &SQUARE, &[2], &[0, 1], &[]),
        "polygon 0 has 2 vertices",
    );
    check(
        write_vtu_polygons(&path, 2, &SQUARE, &[3, 6], &[0, 1, 2, 0, 1, 4], &[]),
        "polygon 1 refers to point 4",
    );
    check(
        write_vtu_polygons(&path, 2, &SQUARE, &[3, 9], &[0, 1, 2, 0, 1, 3], &[]),
        "polygon 1 has 3 vertices",
    );
    check(
        write_vtu_polygons(&path, 2, &SQUARE, &[3], &[0, 1, 2, 3], &[]),
        "1 corners follow the last polygon's end",
    );
    check(
        write_vtu_polygons(&path, 1, &SQUARE, &[], &[], &[]),
        "dimension must be 2 or 3",
    );
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 1);

    let missing = dir.path().join("nope").join("x.vtu");
    let err = write_vtu(&missing, &square_mesh(), &[], &[]).unwrap_err();
    assert!(matches!(err, IoError::Io { .. }), "{err:?}");
}
