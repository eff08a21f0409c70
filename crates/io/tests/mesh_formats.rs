//! Round trips of the 2D mesh-generation formats: the Triangle family with markers and region
//! attributes, `.vtu` with point fields, and the errors of their readers.

use delmesh_io::{
    read_msh, read_triangle_mesh, read_vtu, write_msh_2d, write_su2_2d, write_triangle_family,
    write_vtu, SimplexMesh, TriangleMeshOut,
};
use std::path::Path;

const COORDS: [f64; 10] = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.5, 0.5];
const TRIS: [u32; 12] = [0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4];

#[test]
fn triangle_family_with_markers_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let ele = dir.path().join("sq.ele");
    let written = write_triangle_family(
        &ele,
        &TriangleMeshOut {
            coords: &COORDS,
            triangles: &TRIS,
            point_markers: Some(&[1, 1, 2, 2, 0]),
            cell_attributes: Some(&[0.0, 0.0, 3.5, 3.5]),
            edges: &[[0, 1], [1, 2], [2, 3], [3, 0]],
            edge_markers: &[1, 1, 2, 2],
        },
        1,
    )
    .unwrap();
    assert_eq!(written.len(), 3);
    let edge = std::fs::read_to_string(dir.path().join("sq.edge")).unwrap();
    assert_eq!(edge, "4 1\n1 1 2 1\n2 2 3 1\n3 3 4 2\n4 4 1 2\n");
    let ele_text = std::fs::read_to_string(&ele).unwrap();
    assert!(ele_text.starts_with("4 3 1\n1 1 2 5 0\n"), "{ele_text}");
    let node = std::fs::read_to_string(dir.path().join("sq.node")).unwrap();
    assert!(node.starts_with("5 2 0 1\n1 0 0 1\n"), "{node}");
    let back = read_triangle_mesh(&ele).unwrap();
    assert_eq!(back.coords, COORDS);
    assert_eq!(back.cells, TRIS);
    assert!(back.point_fields.is_empty());
}

#[test]
fn su2_2d_snapshot_groups_edges_by_marker() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sq.su2");
    // Markers out of order (and one negative): the groups come out sorted, each edge in the
    // mesh's order.
    let mesh = TriangleMeshOut {
        coords: &COORDS,
        triangles: &TRIS,
        point_markers: None,
        cell_attributes: None,
        edges: &[[0, 1], [1, 2], [2, 3], [3, 0]],
        edge_markers: &[7, -1, 7, 2],
    };
    write_su2_2d(&path, &mesh).unwrap();
    insta::assert_snapshot!("square_su2_2d", std::fs::read_to_string(&path).unwrap());
    // A bad edge is refused before anything is written.
    let bad = TriangleMeshOut {
        edges: &[[0, 1], [1, 9], [2, 3], [3, 0]],
        ..mesh
    };
    let e = write_su2_2d(&dir.path().join("bad.su2"), &bad).unwrap_err();
    assert!(e.to_string().contains("does not exist"), "{e}");
    assert!(!dir.path().join("bad.su2").exists());
}

#[test]
fn msh_2d_snapshot_and_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sq.msh");
    // Two regions (3 keeps its number, 0.5 gets a free tag), markers 7, -1 and 2.
    let mesh = TriangleMeshOut {
        coords: &COORDS,
        triangles: &TRIS,
        point_markers: None,
        cell_attributes: Some(&[3.0, 0.5, 3.0, 0.5]),
        edges: &[[0, 1], [1, 2], [2, 3], [3, 0]],
        edge_markers: &[7, -1, 7, 2],
    };
    write_msh_2d(&path, &mesh).unwrap();
    insta::assert_snapshot!("square_msh_2d", std::fs::read_to_string(&path).unwrap());
    // This crate's reader takes the triangles as facets, their region's group as the marker.
    let back = read_msh(&path).unwrap();
    let corners: Vec<[f64; 3]> = COORDS.chunks(2).map(|p| [p[0], p[1], 0.0]).collect();
    assert_eq!(back.points, corners);
    let facets: Vec<(Vec<u32>, i32)> = back
        .facets
        .iter()
        .map(|f| (f.polygons[0].clone(), f.marker))
        .collect();
    assert_eq!(
        facets,
        [
            (vec![1, 2, 4], 4),
            (vec![3, 0, 4], 4),
            (vec![0, 1, 4], 3),
            (vec![2, 3, 4], 3)
        ]
    );
    let bad = TriangleMeshOut {
        cell_attributes: Some(&[3.0, f64::NAN, 3.0, 0.5]),
        ..mesh
    };
    let e = write_msh_2d(&dir.path().join("bad.msh"), &bad).unwrap_err();
    assert!(e.to_string().contains("triangle 1 is not finite"), "{e}");
    assert!(!dir.path().join("bad.msh").exists());
}

#[test]
fn a_background_mesh_in_triangle_format() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bg.node"),
        "4 2 1 0\n1 0 0 0.1\n2 1 0 0.2\n3 1 1 0.3\n4 0 1 0.4\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("bg.ele"), "2 3 0\n1 1 2 3\n2 1 3 4\n").unwrap();
    let m = read_triangle_mesh(&dir.path().join("bg.ele")).unwrap();
    assert_eq!(m.cells, vec![0, 1, 2, 0, 2, 3]);
    assert_eq!(
        m.point_fields,
        vec![("spacing".to_string(), vec![0.1, 0.2, 0.3, 0.4])]
    );
    std::fs::write(dir.path().join("bg.ele"), "2 3 0\n1 1 2 3\n2 1 3 7\n").unwrap();
    let e = read_triangle_mesh(&dir.path().join("bg.ele")).unwrap_err();
    assert!(
        e.to_string().contains("bg.ele:3: node 7 does not exist"),
        "{e}"
    );
}

#[test]
fn vtu_point_fields_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.vtu");
    let mesh = SimplexMesh {
        dim: 2,
        coords: &COORDS,
        cells: &TRIS,
        neighbors: None,
    };
    let mach = [0.5, 0.6, 0.7, 0.8, 2.0];
    write_vtu(&path, &mesh, &[("mach", &mach)], &[("region", &[1.0; 4])]).unwrap();
    let back = read_vtu(&path).unwrap();
    assert_eq!(back.dim, 2);
    assert_eq!(back.coords, COORDS);
    assert_eq!(back.cells, TRIS);
    // (The cell field comes back as a point field too, the mean of the cells around each point.)
    assert_eq!(
        back.point_fields,
        vec![
            ("mach".to_string(), mach.to_vec()),
            ("region".to_string(), vec![1.0; 5])
        ]
    );
}

#[test]
fn an_ascii_vtu_written_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.vtu");
    std::fs::write(
        &path,
        r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <UnstructuredGrid>
    <Piece NumberOfPoints="3" NumberOfCells="1">
      <PointData Scalars="spacing">
        <DataArray type="Float32" Name="spacing" format="ascii">0.5 0.25 0.125</DataArray>
      </PointData>
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 2 0 0 0 2 0</DataArray>
      </Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">3</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">5</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
"#,
    )
    .unwrap();
    let m = read_vtu(&path).unwrap();
    assert_eq!(m.cells, vec![0, 1, 2]);
    assert_eq!(m.point_fields[0].1, vec![0.5, 0.25, 0.125]);
    assert!(read_vtu(Path::new("/nonexistent/x.vtu")).is_err());
    std::fs::write(&path, "<VTKFile garbage").unwrap();
    assert!(read_vtu(&path).is_err());
}
