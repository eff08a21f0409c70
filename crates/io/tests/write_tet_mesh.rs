//! Tests of the tetrahedral-mesh writers (gmsh `.msh`, Medit `.mesh`, SU2, the TetGen family,
//! `.vtu` pairs): snapshots of a unit cube in six tetrahedra, round trips through this crate's
//! readers (or vtkio), and the input checks that must fail before any file is written.

use std::path::Path;

use delmesh_io::{
    read_medit, read_msh, read_node, write_medit, write_msh, write_su2, write_tet_mesh,
    write_tet_mesh_vtu, write_tetgen_mesh, IoError, TetMeshOut,
};
use vtkio::model::{Attribute, CellType, DataSet, IOBuffer, Piece, Vtk};

mod common;

use common::{cube, CUBE, FACES, FACE_MARKERS, POINT_MARKERS, REGIONS, TETS};

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The face triangles of marker `m`, sorted, so orders can be compared.
fn faces_with(faces: &[[u32; 3]], markers: &[i32], m: i32) -> Vec<[u32; 3]> {
    let mut v: Vec<[u32; 3]> = faces
        .iter()
        .zip(markers)
        .filter(|&(_, &x)| x == m)
        .map(|(f, _)| *f)
        .collect();
    v.sort();
    v
}

#[test]
fn msh_snapshot_and_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cube.msh");
    write_msh(&path, &cube()).unwrap();
    let text = read(&path);
    insta::assert_snapshot!("cube_msh", text);

    let back = read_msh(&path).unwrap();
    assert_eq!(back.points, CUBE);
    assert_eq!(back.tetrahedra, TETS);
    assert_eq!(back.tetrahedron_regions, vec![1, 1, 1, 2, 2, 2]);
    assert_eq!(back.facets.len(), 12);
    // Marker 0 is not a valid physical tag: it becomes the next free tag, 5, named marker_0,
    // which the reader takes back as marker 0.
    let markers: Vec<i32> = back.facets.iter().map(|f| f.marker).collect();
    let faces: Vec<[u32; 3]> = back
        .facets
        .iter()
        .map(|f| f.polygons[0].clone().try_into().unwrap())
        .collect();
    for m in [1, 2, 3, 4, 0] {
        assert_eq!(
            faces_with(&faces, &markers, m),
            faces_with(&FACES, &FACE_MARKERS, m),
            "marker {m}"
        );
    }
    // The triangles come out grouped by marker (in increasing order: 0 first), in input
    // order within a marker.
    assert_eq!(markers, [0, 0, 1, 1, 2, 2, 3, 3, 3, 3, 4, 4]);
    assert_eq!(
        back.marker_names,
        [
            (0, "marker_0".to_string()),
            (1, "inlet".to_string()),
            (2, "outlet".to_string()),
            (3, "marker_3".to_string()),
            (4, "marker_4".to_string()),
        ]
    );
}

#[test]
fn msh_without_regions_or_faces_still_has_an_entity_for_the_nodes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bare.msh");
    let mesh = TetMeshOut {
        coords: &CUBE,
        tets: &TETS[..1],
        ..TetMeshOut::default()
    };
    write_msh(&path, &mesh).unwrap();
    let back = read_msh(&path).unwrap();
    assert_eq!(back.tetrahedra, &TETS[..1]);
    // Region 0 is not a valid physical tag either: it gets tag 1, named region_0.
    assert_eq!(back.tetrahedron_regions, [1]);
    assert!(read(&path).contains("3 1 \"region_0\""));

    let points_only = TetMeshOut {
        coords: &CUBE,
        ..TetMeshOut::default()
    };
    write_msh(&path, &points_only).unwrap();
    let text = read(&path);
    assert!(
        text.contains("$Entities\n0 0 0 1\n1 0 0 0 1 1 1 0 0\n$EndEntities"),
        "{text}"
    );
    assert_eq!(read_msh(&path).unwrap().points, CUBE);
}

#[test]
fn msh_refuses_markers_when_no_physical_tag_is_free() {
    let dir = tempfile::tempdir().unwrap();
    let markers = [i32::MAX, 0];
    let faces = [FACES[0], FACES[1]];
    let mesh = TetMeshOut {
        faces: &faces,
        face_markers: &markers,
        ..cube()
    };
    let e = write_msh(&dir.path().join("m.msh"), &mesh).unwrap_err();
    assert!(e.to_string().contains("no free physical tag"), "{e}");
    assert!(entries(dir.path()).is_empty());
}

#[test]
fn medit_snapshot_and_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cube.mesh");
    write_medit(&path, &cube()).unwrap();
    insta::assert_snapshot!("cube_mesh", read(&path));
    let back = read_medit(&path).unwrap();
    assert_eq!(back.points, CUBE);
    assert_eq!(back.point_markers.as_deref(), Some(&POINT_MARKERS[..]));
    assert_eq!(back.tetrahedra, TETS);
    assert_eq!(back.tetrahedron_regions, [1, 1, 1, 2, 2, 2]);
    let faces: Vec<Vec<u32>> = back.facets.iter().map(|f| f.polygons[0].clone()).collect();
    let markers: Vec<i32> = back.facets.iter().map(|f| f.marker).collect();
    assert_eq!(faces, FACES.map(|f| f.to_vec()));
    assert_eq!(markers, FACE_MARKERS);
    assert_eq!(back.facets[0].line, 18);
    assert_eq!(back.first_index, 1);
}

#[test]
fn medit_needs_integer_regions() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cube.mesh");
    let regions = [1.0, 1.5, 1.0, 2.0, 2.0, 2.0];
    let mesh = TetMeshOut {
        regions: Some(&regions),
        ..cube()
    };
    let e = write_medit(&path, &mesh).unwrap_err();
    assert!(
        matches!(e, IoError::InvalidInput { .. })
            && e.to_string().contains("region 1.5 of tetrahedron 1"),
        "{e}"
    );
    assert!(entries(dir.path()).is_empty());
}

#[test]
fn tetgen_family_snapshots() {
    let dir = tempfile::tempdir().unwrap();
    let written = write_tetgen_mesh(&dir.path().join("cube.ele"), &cube(), 1).unwrap();
    assert_eq!(entries(dir.path()), ["cube.ele", "cube.face", "cube.node"]);
    assert_eq!(written.len(), 3);
    insta::assert_snapshot!("cube_1_face", read(&written[2]));
    let ele = read(&written[1]);
    assert!(
        ele.starts_with("6 4 1\n1 1 2 4 8 1\n2 1 2 8 6 1\n"),
        "{ele}"
    );
    let points = read_node(&written[0]).unwrap();
    assert_eq!(points.first_index, 1);
    assert_eq!(points.markers.as_deref(), Some(&POINT_MARKERS[..]));
    assert_eq!(points.point3(7), [1.0, 1.0, 1.0]);

    // Zero-based, without regions or point markers.
    let mesh = TetMeshOut {
        regions: None,
        point_markers: None,
        ..cube()
    };
    let written = write_tetgen_mesh(&dir.path().join("zero"), &mesh, 0).unwrap();
    assert!(read(&written[0]).starts_with("8 3 0 0\n0 0 0 0\n"));
    assert!(read(&written[1]).starts_with("6 4 0\n0 0 1 3 7\n"));
    assert!(read(&written[2]).starts_with("12 1\n0 0 4 6 1\n"));
}

#[test]
fn su2_snapshot() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cube.su2");
    write_su2(&path, &cube()).unwrap();
    insta::assert_snapshot!("cube_su2", read(&path));
    // Names a configuration file's marker list cannot hold are made tags (they were refused,
    // after all the meshing): characters replaced, a repeated name told apart by its marker.
    for (names, tags) in [
        (&[(1, "in let")][..], &["in_let"][..]),
        (&[(1, "a(b),c=d")], &["a_b__c_d"]),
        (&[(1, "wall"), (2, "wall")], &["wall", "wall_2"]),
    ] {
        let mesh = TetMeshOut {
            marker_names: names,
            ..cube()
        };
        let path = dir.path().join("named.su2");
        write_su2(&path, &mesh).unwrap();
        let text = read(&path);
        for tag in tags {
            assert!(text.contains(&format!("MARKER_TAG= {tag}\n")), "{text}");
        }
        std::fs::remove_file(&path).unwrap();
    }
    assert_eq!(entries(dir.path()), ["cube.su2"]);
}

fn piece(path: &Path) -> vtkio::model::UnstructuredGridPiece {
    match Vtk::import(path).unwrap().data {
        DataSet::UnstructuredGrid { pieces, .. } => match pieces.into_iter().next().unwrap() {
            Piece::Inline(p) => *p,
            other => panic!("{other:?}"),
        },
        other => panic!("{other:?}"),
    }
}

fn field<'a>(attrs: &'a [Attribute], name: &str) -> &'a IOBuffer {
    attrs
        .iter()
        .find_map(|a| match a {
            Attribute::DataArray(d) if d.name == name => Some(&d.data),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no field {name}"))
}

#[test]
fn vtu_volume_and_boundary_files() {
    let dir = tempfile::tempdir().unwrap();
    let written = write_tet_mesh_vtu(&dir.path().join("cube.vtu"), &cube()).unwrap();
    assert_eq!(entries(dir.path()), ["cube.boundary.vtu", "cube.vtu"]);

    let volume = piece(&written[0]);
    assert_eq!(volume.cells.types, vec![CellType::Tetra; 6]);
    let (conn, _) = volume.cells.cell_verts.into_xml();
    assert_eq!(
        conn,
        TETS.iter()
            .flatten()
            .map(|&v| u64::from(v))
            .collect::<Vec<_>>()
    );
    assert_eq!(
        field(&volume.data.cell, "region"),
        &IOBuffer::F64(REGIONS.to_vec())
    );
    assert_eq!(
        field(&volume.data.point, "marker"),
        &IOBuffer::I32(POINT_MARKERS.to_vec())
    );

    let boundary = piece(&written[1]);
    assert_eq!(boundary.cells.types, vec![CellType::Triangle; 12]);
    assert_eq!(
        field(&boundary.data.cell, "marker"),
        &IOBuffer::I32(FACE_MARKERS.to_vec())
    );
    assert_eq!(
        boundary.points,
        IOBuffer::F64(CUBE.iter().flatten().copied().collect())
    );
}

#[test]
fn write_tet_mesh_picks_the_format() {
    let dir = tempfile::tempdir().unwrap();
    for (name, n_files) in [
        ("a.vtu", 2),
        ("b.ele", 3),
        ("c.msh", 1),
        ("d.mesh", 1),
        ("e.su2", 1),
        ("case/constant/polyMesh", 6),
    ] {
        let written = write_tet_mesh(&dir.path().join(name), &cube()).unwrap();
        assert_eq!(written.len(), n_files, "{name}");
        assert!(written.iter().all(|p| p.exists()));
    }
    let e = write_tet_mesh(&dir.path().join("f.stl"), &cube()).unwrap_err();
    assert!(matches!(e, IoError::UnknownFormat { .. }), "{e}");
}

#[test]
fn bad_meshes_are_refused_before_any_file_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let bad_tets = [[0, 1, 2, 8]];
    let short_markers = [1, 2];
    let nan = [[0.0, f64::NAN, 0.0]];
    let one_region = [1.0];
    let names = [(1, "a\"b")];
    let twice = [(1, "a"), (1, "b")];
    let cases: Vec<(TetMeshOut<'_>, &str)> = vec![
        (
            TetMeshOut {
                tets: &bad_tets,
                regions: None,
                ..cube()
            },
            "tetrahedron 0 [0, 1, 2, 8] refers to a point that does not exist (8 points)",
        ),
        (
            TetMeshOut {
                face_markers: &short_markers,
                ..cube()
            },
            "2 face markers for 12 boundary triangles",
        ),
        (
            TetMeshOut {
                coords: &nan,
                tets: &[],
                faces: &[],
                face_markers: &[],
                point_markers: None,
                regions: None,
                ..cube()
            },
            "point 0 has a non-finite coordinate",
        ),
        (
            TetMeshOut {
                regions: Some(&one_region),
                ..cube()
            },
            "1 regions for 6 tetrahedra",
        ),
        (
            TetMeshOut {
                marker_names: &names,
                ..cube()
            },
            "quote",
        ),
        (
            TetMeshOut {
                marker_names: &twice,
                ..cube()
            },
            "marker 1 is named twice",
        ),
    ];
    for (mesh, message) in cases {
        for name in ["m.vtu", "m.ele", "m.msh", "m.mesh", "m.su2"] {
            let e = write_tet_mesh(&dir.path().join(name), &mesh).unwrap_err();
            assert!(
                matches!(e, IoError::InvalidInput { .. }) && e.to_string().contains(message),
                "{name}: {e}"
            );
        }
    }
    assert!(entries(dir.path()).is_empty());
}
