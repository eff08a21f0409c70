//! `.vtu` input as other tools write it: every data mode of VTK 9's XML writer (ASCII, inline
//! binary, appended raw and base64; uncompressed, zlib, LZ4, LZMA; 32- and 64-bit headers;
//! several compressed blocks; big-endian) and meshio's three modes, on one small mesh of 9
//! points and 8 triangles with a scalar `spacing` and a 3-component `velocity` point field
//! (`tests/data/vtu/`, written by VTK 9.7 and meshio 5.3).

use delmesh_io::read_vtu;
use std::path::{Path, PathBuf};

fn fixtures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/vtu");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vtu"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 14);
    files
}

#[test]
fn every_data_mode_of_vtk_and_meshio_reads_the_same_mesh() {
    let points: Vec<[f64; 2]> = (0..9)
        .map(|k| [0.5 * (k % 3) as f64, 0.5 * (k / 3) as f64])
        .collect();
    let mut triangles = Vec::new();
    for j in 0..2 {
        for i in 0..2 {
            let a = j * 3 + i;
            triangles.extend([a, a + 1, a + 4, a, a + 4, a + 3]);
        }
    }
    for file in fixtures() {
        let name = file.file_name().unwrap().to_string_lossy().to_string();
        let m = read_vtu(&file).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(m.dim, 2, "{name}");
        let coords: Vec<[f64; 2]> = m.coords.chunks(2).map(|p| [p[0], p[1]]).collect();
        assert_eq!(coords, points, "{name}");
        assert_eq!(m.cells, triangles, "{name}");
        let field = |n: &str| {
            m.point_fields
                .iter()
                .find(|(f, _)| f == n)
                .unwrap_or_else(|| panic!("{name}: no field {n}"))
                .1
                .clone()
        };
        // (meshio's ASCII writes 12 significant digits.)
        let spacing = field("spacing");
        for (k, h) in spacing.iter().enumerate() {
            let want = 0.1 + 0.01 * k as f64;
            assert!((h - want).abs() <= 1e-12 * want, "{name}: {h} for {want}");
        }
        assert_eq!(
            field("velocity_0"),
            points.iter().map(|p| p[0]).collect::<Vec<_>>(),
            "{name}"
        );
        assert_eq!(
            field("velocity_1"),
            points.iter().map(|p| -p[1]).collect::<Vec<_>>(),
            "{name}"
        );
        assert_eq!(
            field("velocity_2"),
            (0..9).map(|k| 0.25 * k as f64).collect::<Vec<_>>(),
            "{name}"
        );
    }
}

/// Cut short or with a byte changed anywhere, a file is read or refused with a message naming
/// it; nothing panics.
#[test]
fn damaged_files_are_errors_not_panics() {
    let dir = tempfile::tempdir().unwrap();
    let mut refused = 0;
    for file in fixtures() {
        let bytes = std::fs::read(&file).unwrap();
        let name = file.file_name().unwrap().to_string_lossy().to_string();
        let mut try_bytes = |b: &[u8]| {
            let path = dir.path().join(&name);
            std::fs::write(&path, b).unwrap();
            if let Err(e) = read_vtu(&path) {
                assert!(e.to_string().contains(name.as_str()), "{e}");
                refused += 1;
            }
        };
        for cut in [bytes.len() / 3, bytes.len() / 2, bytes.len() - 20] {
            try_bytes(&bytes[..cut]);
        }
        let step = (bytes.len() / 97).max(1);
        for at in (0..bytes.len()).step_by(step) {
            for x in [0x00, 0x3c, 0xff] {
                let mut b = bytes.clone();
                b[at] = x;
                try_bytes(&b);
            }
        }
    }
    assert!(refused > 1000, "{refused}");
}

/// `tests/data/<dir>/<name>`.
fn data(dir: &str, name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(dir)
        .join(name)
}

fn cells_fixture(name: &str) -> PathBuf {
    data("vtu-cells", name)
}

/// A solver's mesh of quads, hexahedra, prisms and pyramids (a flow solution to adapt to) is
/// read as triangles or tetrahedra covering the same area or volume; points, lines and (in 3D)
/// faces are left out; quadratic cells are refused.
#[test]
fn linear_cells_are_split_into_simplices() {
    let m = read_vtu(&cells_fixture("mixed-2d.vtu")).unwrap();
    assert_eq!(m.dim, 2);
    // Quad, pixel and polygon: 2 triangles each, and 2 triangles; the line and vertex left out.
    assert_eq!(m.cells.len(), 8 * 3);
    let area: f64 = m
        .cells
        .chunks(3)
        .map(|t| {
            let p = |k: usize| [m.coords[2 * t[k] as usize], m.coords[2 * t[k] as usize + 1]];
            let (a, b, c) = (p(0), p(1), p(2));
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs()
        })
        .sum();
    assert_eq!(area, 4.0);

    let m = read_vtu(&cells_fixture("mixed-3d.vtu")).unwrap();
    assert_eq!(m.dim, 3);
    // Hexahedron and voxel 6 each, wedge 3, pyramid 2, tetrahedron 1, the collapsed
    // hexahedron 6 (of no volume); the triangle left out.
    assert_eq!(m.cells.len(), 24 * 4);
    let volume: f64 = m
        .cells
        .chunks(4)
        .map(|t| {
            let p = |k: usize| {
                let i = 3 * t[k] as usize;
                [m.coords[i], m.coords[i + 1], m.coords[i + 2]]
            };
            let (a, b, c, d) = (p(0), p(1), p(2), p(3));
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let w = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
            (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]))
                .abs()
                / 6.0
        })
        .sum();
    // Two unit cubes, half a cube, a pyramid of height 1 on a unit square, a tetrahedron.
    let expected = 2.0 + 0.5 + 1.0 / 3.0 + 0.5 / 6.0;
    assert!((volume - expected).abs() < 1e-12, "{volume} vs {expected}");

    let e = read_vtu(&cells_fixture("quadratic-2d.vtu")).unwrap_err();
    assert!(
        e.to_string()
            .contains("cell 0 (VTK type 22, 6 points): only triangles, quads"),
        "{e}"
    );
}

/// A cell type that is not a whole number (5.5) is no cell type, not a triangle.
#[test]
fn a_fractional_cell_type_is_refused() {
    let dir = std::env::temp_dir().join(format!("delmesh-vtu-type-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("t.vtu");
    let vtu = |ty: &str| {
        format!(
            r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <UnstructuredGrid>
    <Piece NumberOfPoints="3" NumberOfCells="1">
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray>
      </Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">3</DataArray>
        <DataArray type="Float64" Name="types" format="ascii">{ty}</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
"#
        )
    };
    std::fs::write(&path, vtu("5")).unwrap();
    assert_eq!(read_vtu(&path).unwrap().cells, vec![0, 1, 2]);
    std::fs::write(&path, vtu("5.5")).unwrap();
    let e = read_vtu(&path).unwrap_err().to_string();
    assert!(e.contains("cell 0 (VTK type 5.5, 3 points)"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

fn legacy(name: &str) -> PathBuf {
    data("vtk-legacy", name)
}

/// Legacy `.vtk` files as VTK 9 writes them (versions 4.2 and 5.1, ASCII and binary): the same
/// mesh and fields as the `.vtu` files, and a 3D mesh of mixed cells split as there.
#[test]
fn legacy_vtk_files_read_as_the_xml_ones() {
    let reference = read_vtu(&fixtures()[0]).unwrap();
    for name in [
        "vtk-legacy-ascii.vtk",
        "vtk-legacy-binary.vtk",
        "vtk-legacy-51.vtk",
        "vtk-legacy-51-binary.vtk",
    ] {
        let m = delmesh_io::read_vtk_legacy(&legacy(name)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(m.dim, 2, "{name}");
        assert_eq!(m.coords, reference.coords, "{name}");
        assert_eq!(m.cells, reference.cells, "{name}");
        for field in ["spacing", "velocity_0", "velocity_1", "velocity_2"] {
            let get = |m: &delmesh_io::FieldMesh| {
                m.point_fields
                    .iter()
                    .find(|(f, _)| f == field)
                    .unwrap_or_else(|| panic!("{name}: no {field}"))
                    .1
                    .clone()
            };
            // (ASCII legacy files carry about 7 significant digits.)
            for (a, b) in get(&m).iter().zip(get(&reference)) {
                assert!(
                    (a - b).abs() <= 1e-6 * b.abs(),
                    "{name} {field}: {a} vs {b}"
                );
            }
        }
    }
    let vtu = read_vtu(&cells_fixture("mixed-3d.vtu")).unwrap();
    for name in ["mixed-3d-42-binary.vtk", "mixed-3d-51.vtk"] {
        let m = delmesh_io::read_vtk_legacy(&legacy(name)).unwrap();
        assert_eq!(m.cells, vtu.cells, "{name}");
        assert_eq!(m.coords, vtu.coords, "{name}");
    }
    // Damaged: an error naming the file, never a panic.
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "vtk-legacy-binary.vtk",
        "vtk-legacy-51.vtk",
        "mixed-3d-42-binary.vtk",
    ] {
        let bytes = std::fs::read(legacy(name)).unwrap();
        let path = dir.path().join(name);
        for at in (0..bytes.len()).step_by(7) {
            for x in [b'0', b'\n', 0xff] {
                let mut b = bytes.clone();
                b[at] = x;
                std::fs::write(&path, &b).unwrap();
                if let Err(e) = delmesh_io::read_vtk_legacy(&path) {
                    assert!(e.to_string().contains(name), "{e}");
                }
            }
            std::fs::write(&path, &bytes[..at]).unwrap();
            if let Err(e) = delmesh_io::read_vtk_legacy(&path) {
                assert!(e.to_string().contains(name), "{e}");
            }
        }
    }
}

/// A finite-volume solver's cell-centred fields (cell data only) become point fields, each
/// point the mean of the cells around it, so that `--adapt --field mach` finds them; a point
/// field of the same name wins.
#[test]
fn cell_data_becomes_point_data() {
    for name in ["cell-data.vtu", "cell-data.vtk"] {
        let path = cells_fixture(name);
        let m = if name.ends_with("vtu") {
            read_vtu(&path)
        } else {
            delmesh_io::read_vtk_legacy(&path)
        }
        .unwrap_or_else(|e| panic!("{e}"));
        let field = |n: &str| {
            m.point_fields
                .iter()
                .find(|(f, _)| f == n)
                .unwrap_or_else(|| panic!("{name}: no {n}"))
                .1
                .clone()
        };
        // Cell k has mach k; the cells around each point of the 3 x 3 grid.
        let mut around = vec![Vec::new(); 9];
        for (k, t) in m.cells.chunks(3).enumerate() {
            for &v in t {
                around[v as usize].push(k as f64);
            }
        }
        let mean: Vec<f64> = around
            .iter()
            .map(|a| a.iter().sum::<f64>() / a.len() as f64)
            .collect();
        assert_eq!(field("mach"), mean, "{name}");
        assert_eq!(field("momentum_0"), vec![1.0; 9], "{name}");
        assert_eq!(
            field("momentum_1"),
            mean.iter().map(|x| -x).collect::<Vec<_>>(),
            "{name}"
        );
        assert!(field("spacing").iter().all(|&h| h < 1.0), "{name}");
        assert_eq!(
            m.point_fields
                .iter()
                .filter(|(f, _)| f == "spacing")
                .count(),
            1
        );
    }
}

/// Counts and sizes beyond any memory (a damaged or hostile header) are errors, not panics or
/// huge allocations.
#[test]
fn huge_counts_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let huge = ["18446744073709551615", "4294967296", "1099511627776", "-1"];
    let cases: Vec<(PathBuf, &str)> = vec![
        (legacy("vtk-legacy-ascii.vtk"), "POINTS 9"),
        (legacy("vtk-legacy-ascii.vtk"), "CELLS 8"),
        (legacy("vtk-legacy-ascii.vtk"), "CELL_TYPES 8"),
        (legacy("vtk-legacy-ascii.vtk"), "POINT_DATA 9"),
        (legacy("vtk-legacy-ascii.vtk"), "spacing 1 9"),
        (legacy("vtk-legacy-51.vtk"), "CELLS 9"),
        (fixtures()[0].clone(), "NumberOfPoints=\"9\""),
        (fixtures()[0].clone(), "NumberOfCells=\"8\""),
    ];
    for (file, what) in cases {
        let text = String::from_utf8_lossy(&std::fs::read(&file).unwrap()).into_owned();
        assert!(text.contains(what), "{what}");
        for h in huge {
            let changed = if what.contains('"') {
                let key = what.split('=').next().unwrap();
                text.replacen(what, &format!("{key}=\"{h}\""), 1)
            } else {
                let (head, _) = what.rsplit_once(' ').unwrap();
                text.replacen(what, &format!("{head} {h}"), 1)
            };
            let path = dir.path().join(file.file_name().unwrap());
            std::fs::write(&path, &changed).unwrap();
            let read = if path.extension().unwrap() == "vtk" {
                delmesh_io::read_vtk_legacy(&path)
            } else {
                read_vtu(&path)
            };
            assert!(read.is_err(), "{what} -> {h}");
        }
    }
}
