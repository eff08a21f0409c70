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
