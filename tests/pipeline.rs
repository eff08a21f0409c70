//! End-to-end tests of the library pipeline: point file → `delmesh::delaunay::triangulate_file`
//! → mesh and Voronoi files, read back and checked.
//!
//! These exercise the same code as `delmesh delaunay` (the CLI is a thin layer over it, tested in
//! `crates/delmesh/tests/cli.rs`), but through the library, so they can inspect the run and the
//! errors' variants. Every output is parsed back: numbering from the input's first index, counts
//! matching the triangulation, neighbour symmetry, coordinates round-tripping bit-exactly.

use std::path::{Path, PathBuf};

use delmesh::delaunay::{triangulate_file, DelaunayMesh, OutputFormat};
use delmesh::Error;
use rand::{Rng, SeedableRng};

/// Writes a `.node` file of `points` (each `dim` long) numbered from `first`.
fn write_node(dir: &Path, name: &str, dim: usize, points: &[Vec<f64>], first: usize) -> PathBuf {
    let mut text = format!("# test points\n{} {dim} 0 0\n", points.len());
    for (i, p) in points.iter().enumerate() {
        text.push_str(&(i + first).to_string());
        for x in p {
            text.push_str(&format!(" {x:?}"));
        }
        text.push('\n');
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn random_points(dim: usize, n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    (0..n)
        .map(|_| (0..dim).map(|_| rng.gen::<f64>()).collect())
        .collect()
}

/// The data lines of a TetGen-style file, as whitespace-separated tokens (comments dropped).
fn table(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split_whitespace().map(str::to_string).collect())
        .collect()
}

fn ints(row: &[String]) -> Vec<i64> {
    row.iter().map(|t| t.parse().unwrap()).collect()
}

/// Checks `X.node`, `X.ele`, `X.neigh` written for `points` numbered from `first`, and returns
/// the number of cells.
fn check_tetgen_family(ele: &Path, dim: usize, points: &[Vec<f64>], first: i64) -> usize {
    let nv = dim + 1;
    // .node: every input point, in input order, bit-exact, numbered from `first`.
    let nodes = delmesh_io::read_node(&ele.with_extension("node")).unwrap();
    assert_eq!(nodes.dim, dim);
    assert_eq!(i64::from(nodes.first_index), first);
    let flat: Vec<f64> = points.iter().flatten().copied().collect();
    assert_eq!(nodes.coords, flat);

    // .ele: header `<#cells> <nv> 0`, cells numbered from `first`, vertices in range.
    let ele_rows = table(ele);
    let header = ints(&ele_rows[0]);
    let n_cells = header[0] as usize;
    assert_eq!(header[1], nv as i64);
    assert_eq!(ele_rows.len(), n_cells + 1);
    for (k, row) in ele_rows[1..].iter().enumerate() {
        let row = ints(row);
        assert_eq!(row.len(), nv + 1);
        assert_eq!(row[0], k as i64 + first);
        for &v in &row[1..] {
            assert!(
                (first..first + points.len() as i64).contains(&v),
                "vertex {v}"
            );
        }
    }

    // .neigh: same count and numbering; -1 on the hull; symmetric.
    let neigh_rows = table(&ele.with_extension("neigh"));
    assert_eq!(ints(&neigh_rows[0]), vec![n_cells as i64, nv as i64]);
    assert_eq!(neigh_rows.len(), n_cells + 1);
    let neigh: Vec<Vec<i64>> = neigh_rows[1..].iter().map(|r| ints(r)).collect();
    let mut hull = 0;
    for (k, row) in neigh.iter().enumerate() {
        assert_eq!(row[0], k as i64 + first);
        for &n in &row[1..] {
            if n == -1 {
                hull += 1;
                continue;
            }
            assert!(
                (first..first + n_cells as i64).contains(&n),
                "neighbour {n}"
            );
            let back = &neigh[(n - first) as usize][1..];
            assert!(back.contains(&(k as i64 + first)), "cell {k} ↔ {n}");
        }
    }
    assert!(hull > 0);
    n_cells
}

#[test]
fn two_d_node_to_vtu_and_ele_numbered_from_one() {
    let dir = tempfile::tempdir().unwrap();
    let points = random_points(2, 500, 1);
    let input = write_node(dir.path(), "pts.node", 2, &points, 1);
    let run = triangulate_file(&input, false).unwrap();
    assert_eq!(run.dim(), 2);
    assert_eq!(run.first_index, 1);
    assert_eq!(run.input, input);
    assert_eq!(run.num_input_points(), 500);
    assert_eq!(run.num_vertices(), 500);
    assert!(run.duplicates().is_empty());
    assert!(run.build_seconds >= 0.0);
    // Euler for a triangulated convex polygon: T = 2n − h − 2.
    assert_eq!(run.num_cells(), 2 * 500 - run.num_hull_facets() - 2);
    let DelaunayMesh::D2(tri) = &run.mesh else {
        panic!("expected a 2D mesh")
    };
    tri.validate().unwrap();

    let vtu = dir.path().join("mesh.vtu");
    assert_eq!(run.write(&vtu).unwrap(), vec![vtu.clone()]);
    let xml = std::fs::read_to_string(&vtu).unwrap();
    assert!(xml.contains("NumberOfPoints=\"500\""), "{xml:.300}");
    assert!(
        xml.contains(&format!("NumberOfCells=\"{}\"", run.num_cells())),
        "{xml:.300}"
    );

    let ele = dir.path().join("mesh.ele");
    let written = run.write(&ele).unwrap();
    assert_eq!(
        written,
        vec![
            dir.path().join("mesh.node"),
            ele.clone(),
            dir.path().join("mesh.neigh")
        ]
    );
    assert_eq!(check_tetgen_family(&ele, 2, &points, 1), run.num_cells());
}

#[test]
fn three_d_node_to_ele_numbered_from_zero() {
    let dir = tempfile::tempdir().unwrap();
    let points = random_points(3, 400, 2);
    let input = write_node(dir.path(), "pts.node", 3, &points, 0);
    let run = triangulate_file(&input, false).unwrap();
    assert_eq!((run.dim(), run.first_index), (3, 0));
    assert_eq!(run.num_vertices(), 400);
    let DelaunayMesh::D3(tri) = &run.mesh else {
        panic!("expected a 3D mesh")
    };
    tri.validate().unwrap();

    let ele = dir.path().join("tets.ele");
    run.write(&ele).unwrap();
    assert_eq!(check_tetgen_family(&ele, 3, &points, 0), run.num_cells());

    let vtu = dir.path().join("tets.vtu");
    run.write(&vtu).unwrap();
    let xml = std::fs::read_to_string(&vtu).unwrap();
    assert!(xml.contains("NumberOfPoints=\"400\""));
    assert!(xml.contains(&format!("NumberOfCells=\"{}\"", run.num_cells())));
}

#[test]
fn plain_text_input_counts_from_zero() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("pts.xyz");
    std::fs::write(&input, "0 0\n1 0\n0 1\n1 1\n0.5 0.25\n").unwrap();
    let run = triangulate_file(&input, true).unwrap();
    assert_eq!((run.dim(), run.first_index, run.num_cells()), (2, 0, 4));
    let ele = dir.path().join("out.ele");
    run.write(&ele).unwrap();
    let rows = table(&ele);
    assert_eq!(ints(&rows[1])[0], 0);
}

#[test]
fn two_d_matches_delaunator_cell_count() {
    // Random points are in general position, so the Delaunay triangulation is unique.
    let dir = tempfile::tempdir().unwrap();
    let points = random_points(2, 2000, 3);
    let input = write_node(dir.path(), "pts.node", 2, &points, 0);
    let run = triangulate_file(&input, false).unwrap();
    let dpts: Vec<delaunator::Point> = points
        .iter()
        .map(|p| delaunator::Point { x: p[0], y: p[1] })
        .collect();
    let reference = delaunator::triangulate(&dpts);
    assert_eq!(run.num_cells(), reference.len());

    let canonical = |tris: Vec<[u32; 3]>| {
        let mut t: Vec<[u32; 3]> = tris
            .into_iter()
            .map(|mut c| {
                c.sort_unstable();
                c
            })
            .collect();
        t.sort_unstable();
        t
    };
    let DelaunayMesh::D2(tri) = &run.mesh else {
        panic!("2D")
    };
    let ours = canonical(
        tri.cells_in_input_numbering()
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
    );
    let theirs = canonical(
        reference
            .triangles
            .chunks_exact(3)
            .map(|c| [c[0] as u32, c[1] as u32, c[2] as u32])
            .collect(),
    );
    assert_eq!(ours, theirs);
}

#[test]
fn voronoi_outputs_2d_and_3d() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_node(dir.path(), "p2.node", 2, &random_points(2, 200, 4), 1);
    let run = triangulate_file(&input, false).unwrap();
    let out = dir.path().join("cells2.vtu");
    // One clipped cell per point: the box encloses all points.
    assert_eq!(run.write_voronoi(&out).unwrap(), 200);
    let xml = std::fs::read_to_string(&out).unwrap();
    assert!(xml.contains("NumberOfCells=\"200\""));
    assert!(xml.contains("Name=\"point\""));

    let input = write_node(dir.path(), "p3.node", 3, &random_points(3, 300, 5), 0);
    let run = triangulate_file(&input, false).unwrap();
    let out = dir.path().join("faces3.vtu");
    let n_faces = run.write_voronoi(&out).unwrap();
    assert!(n_faces > 100, "{n_faces} faces");
    let xml = std::fs::read_to_string(&out).unwrap();
    assert!(xml.contains(&format!("NumberOfCells=\"{n_faces}\"")));
    assert!(xml.contains("Name=\"point\"") && xml.contains("Name=\"neighbor\""));

    let err = run
        .write_voronoi(&dir.path().join("faces.ele"))
        .unwrap_err();
    assert!(matches!(err, Error::UnsupportedFormat { .. }), "{err}");
}

#[test]
fn duplicates_are_merged_and_reported_in_file_numbering() {
    let dir = tempfile::tempdir().unwrap();
    let mut points = random_points(2, 20, 6);
    points.push(points[3].clone());
    points.push(points[0].clone());
    let input = write_node(dir.path(), "dups.node", 2, &points, 1);
    let run = triangulate_file(&input, false).unwrap();
    assert_eq!(run.num_input_points(), 22);
    assert_eq!(run.num_vertices(), 20);
    assert_eq!(run.duplicates(), vec![(21, 4), (22, 1)]);
    // Outputs still list all 22 input points so the numbering matches the input.
    let ele = dir.path().join("dups-mesh.ele");
    run.write(&ele).unwrap();
    check_tetgen_family(&ele, 2, &points, 1);
}

#[test]
fn bad_inputs_are_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();

    let nan = dir.path().join("nan.node");
    std::fs::write(&nan, "3 2\n1 0 0\n2 NaN 1\n3 1 1\n").unwrap();
    let err = triangulate_file(&nan, false).unwrap_err();
    let Error::Io(io) = &err else {
        panic!("expected an I/O error, got {err:?}")
    };
    assert_eq!(io.line(), Some(3));
    assert!(
        err.to_string()
            .starts_with(&format!("{}:3:", nan.display())),
        "{err}"
    );

    let missing = dir.path().join("missing.node");
    let err = triangulate_file(&missing, false).unwrap_err();
    assert!(err.to_string().contains("missing.node"), "{err}");
    assert_eq!(err.file(), Some(missing.as_path()));

    let line = dir.path().join("line.node");
    std::fs::write(&line, "4 2\n0 0 0\n1 1 1\n2 2 2\n3 3 3\n").unwrap();
    let err = triangulate_file(&line, false).unwrap_err();
    assert!(matches!(err, Error::Triangulation { .. }), "{err:?}");
    assert_eq!(
        err.to_string(),
        format!(
            "{}: all 4 distinct points are collinear: no 2D triangulation exists",
            line.display()
        )
    );

    let plane = dir.path().join("plane.node");
    std::fs::write(&plane, "4 3\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 1 1 0\n").unwrap();
    let err = triangulate_file(&plane, false).unwrap_err();
    assert!(err.to_string().contains("coplanar"), "{err}");

    let too_few = dir.path().join("two.node");
    std::fs::write(&too_few, "2 2\n0 0 0\n1 1 1\n").unwrap();
    let err = triangulate_file(&too_few, false).unwrap_err();
    assert!(err.to_string().contains("needs at least 3"), "{err}");
}

#[test]
fn unknown_output_extension_is_an_error_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_node(dir.path(), "p.node", 2, &random_points(2, 10, 7), 0);
    let run = triangulate_file(&input, false).unwrap();
    for name in ["mesh.stl", "mesh"] {
        let out = dir.path().join(name);
        let err = run.write(&out).unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains(".vtu, .ele"), "{msg}");
        assert!(!out.exists());
    }
    let err = run.write(&dir.path().join("mesh.stl")).unwrap_err();
    assert!(err.to_string().contains("'.stl'"), "{err}");
    assert_eq!(
        OutputFormat::from_path(Path::new("a.VTU")).unwrap(),
        OutputFormat::Vtu
    );
}

#[test]
fn missing_output_folder_is_detected_up_front() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("absent").join("mesh.ele");
    let err = delmesh::delaunay::check_output_dir(&out).unwrap_err();
    assert!(err.to_string().contains("does not exist"), "{err}");
    assert_eq!(err.file(), Some(out.as_path()));
    delmesh::delaunay::check_output_dir(&dir.path().join("mesh.ele")).unwrap();
    delmesh::delaunay::check_output_dir(Path::new("mesh.ele")).unwrap();
}

#[test]
fn writing_never_overwrites_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_node(dir.path(), "pts.node", 2, &random_points(2, 10, 8), 1);
    let before = std::fs::read(&input).unwrap();
    let run = triangulate_file(&input, false).unwrap();
    let err = run.write(&dir.path().join("pts.ele")).unwrap_err();
    assert!(matches!(err, Error::OverwritesInput { .. }), "{err:?}");
    assert_eq!(std::fs::read(&input).unwrap(), before);
    assert!(!dir.path().join("pts.ele").exists());
}
