//! Tests of the OpenFOAM polyMesh writers: a snapshot of the unit cube in six tetrahedra, and
//! the files read back by a small parser here and checked as OpenFOAM checks them (`checkMesh`
//! read the meshes of real runs the same way): internal faces in upper triangular order, every
//! cell closed with its faces turned outwards (the divergence theorem gives its volume), the
//! patches covering the boundary; then the 2D prisms, and the refusals.

use std::path::Path;

use delmesh_io::{is_polymesh, write_foam, write_foam_2d, TetMeshOut, TriangleMeshOut};

mod common;

use common::{cube, FACES, FACE_MARKERS};

/// A polyMesh read back.
struct Foam {
    points: Vec<[f64; 3]>,
    faces: Vec<Vec<usize>>,
    owner: Vec<usize>,
    neighbour: Vec<usize>,
    /// Name, type, number of faces, first face.
    patches: Vec<(String, String, usize, usize)>,
}

/// The entries of a polyMesh list file: the lines between the `(` after the count and the
/// last `)`.
fn entries(text: &str) -> Vec<&str> {
    let body = &text[text.find("\n}\n").expect("a FoamFile header") + 3..];
    let mut lines = body.lines().map(str::trim).filter(|l| !l.is_empty());
    let n: usize = lines.next().unwrap().parse().unwrap();
    assert_eq!(lines.next(), Some("("));
    let items: Vec<&str> = lines.by_ref().take(n).collect();
    assert_eq!(lines.next(), Some(")"));
    items
}

fn read_foam(dir: &Path) -> Foam {
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    let numbers = |s: &str| -> Vec<f64> {
        s.split(|c: char| c == '(' || c == ')' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .map(|t| t.parse().unwrap())
            .collect()
    };
    let points = entries(&read("points"))
        .iter()
        .map(|l| {
            let v = numbers(l);
            [v[0], v[1], v[2]]
        })
        .collect();
    let faces = entries(&read("faces"))
        .iter()
        .map(|l| {
            let (n, rest) = l.split_once('(').unwrap();
            let v: Vec<usize> = numbers(rest).iter().map(|&x| x as usize).collect();
            assert_eq!(v.len(), n.parse::<usize>().unwrap(), "{l}");
            v
        })
        .collect();
    let labels = |f: &str| -> Vec<usize> {
        entries(&read(f))
            .iter()
            .map(|l| l.parse().unwrap())
            .collect()
    };
    let boundary = read("boundary");
    let mut patches = Vec::new();
    let mut lines = boundary.lines().map(str::trim);
    while let Some(l) = lines.next() {
        if lines.clone().next() == Some("{") && !l.starts_with("FoamFile") {
            let mut fields = std::collections::HashMap::new();
            for f in lines.by_ref().skip(1).take_while(|f| *f != "}") {
                let (k, v) = f.split_once(char::is_whitespace).unwrap();
                fields.insert(k.to_string(), v.trim().trim_end_matches(';').to_string());
            }
            patches.push((
                l.to_string(),
                fields["type"].clone(),
                fields["nFaces"].parse().unwrap(),
                fields["startFace"].parse().unwrap(),
            ));
        }
    }
    Foam {
        points,
        faces,
        owner: labels("owner"),
        neighbour: labels("neighbour"),
        patches,
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Checks the mesh as `checkMesh` does, and returns each cell's volume.
fn check(m: &Foam) -> Vec<f64> {
    let n_cells = m.owner.iter().chain(&m.neighbour).max().unwrap() + 1;
    assert_eq!(m.owner.len(), m.faces.len());
    // Upper triangular order: internal faces by owner, then neighbour, owner the lower cell.
    for (f, (&o, &n)) in m.owner.iter().zip(&m.neighbour).enumerate() {
        assert!(o < n, "face {f}: owner {o}, neighbour {n}");
    }
    let pairs: Vec<(usize, usize)> = m
        .owner
        .iter()
        .copied()
        .zip(m.neighbour.iter().copied())
        .collect();
    assert!(pairs.windows(2).all(|w| w[0] < w[1]), "{pairs:?}");
    // The patches are the boundary faces, one run each, in order.
    let mut start = m.neighbour.len();
    for (name, _, n, s) in &m.patches {
        assert_eq!(*s, start, "{name}");
        start += n;
    }
    assert_eq!(start, m.faces.len());
    // Each face's area vector (a fan from its first point), out of its owner and into its
    // neighbour: closed cells, and volumes by the divergence theorem.
    let mut closure = vec![[0.0; 3]; n_cells];
    let mut volume = vec![0.0; n_cells];
    for (f, face) in m.faces.iter().enumerate() {
        let p: Vec<[f64; 3]> = face.iter().map(|&v| m.points[v]).collect();
        let mut area = [0.0; 3];
        let mut centre = [0.0; 3];
        for k in 1..p.len() - 1 {
            let a = cross(sub(p[k], p[0]), sub(p[k + 1], p[0]));
            for i in 0..3 {
                area[i] += 0.5 * a[i];
            }
        }
        for q in &p {
            for i in 0..3 {
                centre[i] += q[i] / p.len() as f64;
            }
        }
        let flux = (centre[0] * area[0] + centre[1] * area[1] + centre[2] * area[2]) / 3.0;
        let mut add = |cell: usize, sign: f64| {
            for i in 0..3 {
                closure[cell][i] += sign * area[i];
            }
            volume[cell] += sign * flux;
        };
        add(m.owner[f], 1.0);
        if let Some(&n) = m.neighbour.get(f) {
            add(n, -1.0);
        }
    }
    for (c, a) in closure.iter().enumerate() {
        assert!(
            a.iter().all(|x| x.abs() < 1e-12),
            "cell {c} is not closed: {a:?}"
        );
    }
    volume
}

#[test]
fn cube_snapshot_and_checks() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("constant/polyMesh");
    assert!(is_polymesh(&dir));
    let written = write_foam(&dir, &cube()).unwrap();
    let names: Vec<String> = written
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "points",
            "faces",
            "owner",
            "neighbour",
            "boundary",
            "cellZones"
        ]
    );
    let all: String = written
        .iter()
        .map(|p| {
            format!(
                "==> {} <==\n{}",
                p.file_name().unwrap().to_string_lossy(),
                std::fs::read_to_string(p).unwrap()
            )
        })
        .collect();
    insta::assert_snapshot!("cube_foam", all);
    let m = read_foam(&dir);
    let volume = check(&m);
    assert_eq!(volume.len(), 6);
    assert!(
        volume.iter().all(|v| (v - 1.0 / 6.0).abs() < 1e-14),
        "{volume:?}"
    );
    let patches: Vec<(&str, usize)> = m
        .patches
        .iter()
        .map(|(n, t, k, _)| {
            assert_eq!(t, "patch");
            (n.as_str(), *k)
        })
        .collect();
    assert_eq!(
        patches,
        [
            ("marker_0", 2),
            ("inlet", 2),
            ("outlet", 2),
            ("marker_3", 4),
            ("marker_4", 2)
        ]
    );
    // The cube's six internal faces, each between two tetrahedra.
    assert_eq!(m.neighbour.len(), 6);
}

#[test]
fn faces_without_a_marker_go_to_default_faces_and_one_region_has_no_zones() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("polyMesh");
    let mesh = TetMeshOut {
        faces: &FACES[..10],
        face_markers: &FACE_MARKERS[..10],
        regions: Some(&[3.0; 6]),
        ..cube()
    };
    // Over a mesh with zones: its zone files go, since they would number these cells.
    write_foam(&dir, &cube()).unwrap();
    std::fs::write(dir.join("faceZones"), "old").unwrap();
    std::fs::write(dir.join("notes.txt"), "the user's").unwrap();
    let written = write_foam(&dir, &mesh).unwrap();
    assert_eq!(written.len(), 5, "{written:?}");
    assert!(!dir.join("cellZones").exists() && !dir.join("faceZones").exists());
    assert!(dir.join("notes.txt").exists());
    let m = read_foam(&dir);
    check(&m);
    let last = m.patches.last().unwrap();
    assert_eq!((last.0.as_str(), last.2), ("defaultFaces", 2));
}

#[test]
fn triangles_become_one_layer_of_prisms() {
    // A 2 × 1 rectangle in four triangles around its centre, two regions; the bottom edge is
    // marker 5, the others 1, but for one edge left without a marker.
    let coords = [0.0, 0.0, 2.0, 0.0, 2.0, 1.0, 0.0, 1.0, 1.0, 0.5];
    let triangles = [0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4];
    let edges = [[0, 1], [1, 2], [2, 3]];
    let markers = [5, 1, 1];
    let regions = [1.0, 1.0, 2.0, 2.0];
    let mesh = TriangleMeshOut {
        coords: &coords,
        triangles: &triangles,
        point_markers: None,
        cell_attributes: Some(&regions),
        edges: &edges,
        edge_markers: &markers,
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("polyMesh");
    let written = write_foam_2d(&dir, &mesh).unwrap();
    assert_eq!(written.len(), 6);
    let m = read_foam(&dir);
    let volume = check(&m);
    // Depth: the mean edge length of the triangles (the four sides, and the eight edges to
    // the centre, √1.25 long).
    let d = (6.0 + 8.0 * 1.25f64.sqrt()) / 12.0;
    let total: f64 = volume.iter().sum();
    assert!((total - 2.0 * d).abs() < 1e-12, "{total} {d}");
    assert!(volume.iter().all(|&v| v > 0.0));
    let patches: Vec<(&str, &str, usize)> = m
        .patches
        .iter()
        .map(|(n, t, k, _)| (n.as_str(), t.as_str(), *k))
        .collect();
    assert_eq!(
        patches,
        [
            ("marker_1", "patch", 2),
            ("marker_5", "patch", 1),
            ("defaultFaces", "patch", 1),
            ("frontAndBack", "empty", 8)
        ]
    );
    let zones = std::fs::read_to_string(dir.join("cellZones")).unwrap();
    assert!(
        zones.contains("region_1\n") && zones.contains("region_2\n"),
        "{zones}"
    );
    assert!(!dir.join("faceZones").exists());
    // A marked edge between two triangles (a wake, a wall between regions): an internal face
    // kept as the face zone of its marker.
    let (edges, markers) = ([[0, 1], [1, 2], [2, 3], [4, 0]], [5, 1, 1, 7]);
    let written = write_foam_2d(
        &dir,
        &TriangleMeshOut {
            edges: &edges,
            edge_markers: &markers,
            ..mesh
        },
    )
    .unwrap();
    assert_eq!(written.len(), 7);
    let m = read_foam(&dir);
    check(&m);
    let zones = std::fs::read_to_string(dir.join("faceZones")).unwrap();
    // The edge from the centre to corner 0 is shared by the first and last triangles: the
    // internal face between cells 0 and 3.
    let face = (0..m.neighbour.len())
        .find(|&f| (m.owner[f], m.neighbour[f]) == (0, 3))
        .unwrap();
    assert!(
        zones.contains(&format!(
            "marker_7\n{{\n    type faceZone;\nfaceLabels      List<label> 1\n(\n{face}\n)"
        )) && zones.contains("flipMap         List<bool> 1\n(\n0\n)"),
        "{zones}"
    );
}

#[test]
fn names_are_made_words_and_non_manifold_faces_are_refused_before_writing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("polyMesh");
    // Names OpenFOAM cannot take have those characters replaced (STL solid names such as
    // gmsh's "Created by Gmsh" were refused).
    for (name, word) in [
        ("in let", "in_let"),
        ("a;b", "a_b"),
        ("x{", "x_"),
        ("(p)", "_p_"),
        ("Created by Gmsh", "Created_by_Gmsh"),
        ("123", "patch_123"),
    ] {
        let names = [(1, name)];
        let mesh = TetMeshOut {
            marker_names: &names,
            ..cube()
        };
        write_foam(&dir, &mesh).unwrap();
        let boundary = std::fs::read_to_string(dir.join("boundary")).unwrap();
        assert!(boundary.contains(&format!("\n    {word}\n")), "{boundary}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
    let names = [(1, "wall"), (2, "wall")];
    let mesh = TetMeshOut {
        marker_names: &names,
        ..cube()
    };
    // Two markers of one name (it was refused, after all the meshing): the second is told
    // apart by its number.
    write_foam(&dir, &mesh).unwrap();
    let boundary = std::fs::read_to_string(dir.join("boundary")).unwrap();
    assert!(
        boundary.contains("\n    wall\n") && boundary.contains("\n    wall_2\n"),
        "{boundary}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
    // Three tetrahedra on one face.
    let tets = [[0, 1, 3, 7], [0, 1, 7, 5], [0, 1, 3, 7]];
    let mesh = TetMeshOut {
        tets: &tets,
        regions: None,
        ..cube()
    };
    let e = write_foam(&dir, &mesh).unwrap_err();
    assert!(e.to_string().contains("cells 0, 1, 2 share a face"), "{e}");
    assert!(!dir.exists());
    // A file where the folder would be is kept.
    std::fs::write(&dir, "the user's").unwrap();
    let e = write_foam(&dir, &cube()).unwrap_err();
    assert!(e.to_string().contains("this is a file"), "{e}");
    assert_eq!(std::fs::read_to_string(&dir).unwrap(), "the user's");
}
