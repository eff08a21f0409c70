//! SU2 native mesh files (`.su2`, ASCII), written: the input of the SU2 CFD solver.
//!
//! 3D ([`write_su2`]): `NDIME= 3`; `NELEM= <n>` and one line per tetrahedron `10 a b c d <index>` (VTK
//! type 10; 0-based point indices, the trailing element index as SU2 itself writes it);
//! `NPOIN= <n>` and one line per point `x y z <index>`; `NMARK= <k>` and, per boundary marker,
//! `MARKER_TAG= <name>`, `MARKER_ELEMS= <m>` and its triangles `5 a b c` (VTK type 5).
//! Markers are written in increasing order, each named by [`TetMeshOut::marker_names`] or
//! `marker_<m>`; the names are what the solver's configuration file refers to
//! (`MARKER_EULER= ( wing )`), so characters a marker list cannot hold become `_` (see
//! `marker_tags`). A single-zone SU2 mesh has
//! no cell zones: regions and point markers are not written.
//!
//! 2D ([`write_su2_2d`]): `NDIME= 2`; triangles `5 a b c <index>`; points `x y <index>`; per
//! edge marker `MARKER_TAG= marker_<m>` and its edges `3 a b` (VTK type 3, a line). 2D inputs
//! (Triangle's `.poly`) number their markers without naming them.

use std::io::Write;
use std::path::Path;

use crate::atomic::write_atomic;
use crate::tetmesh::TetMeshOut;
use crate::text::write_f64;
use crate::triangle::TriangleMeshOut;
use crate::IoError;

/// Writes a tetrahedral mesh as an SU2 `.su2` file, one `MARKER_TAG` per face marker. Atomic.
pub fn write_su2(path: &Path, mesh: &TetMeshOut<'_>) -> Result<(), IoError> {
    mesh.check(path)?;
    let markers = mesh.distinct_markers();
    let names = marker_tags(&markers, |m| mesh.marker_name(m));
    write_atomic(path, |w| {
        su2_body(w, mesh, &markers, &names).map_err(|e| IoError::io(path, e))
    })
}

/// The `MARKER_TAG` of each marker: its name with each character a configuration file's
/// marker list cannot hold (white space, `,()=;%`) replaced by `_` (gmsh's STL solid name
/// "Created by Gmsh" was refused, after all the meshing), `marker_<m>` if it has none, and
/// `_<m>` appended to a name an earlier marker already has.
fn marker_tags(markers: &[i32], name: impl Fn(i32) -> String) -> Vec<String> {
    let mut tags: Vec<String> = Vec::with_capacity(markers.len());
    for &m in markers {
        let given: String = name(m)
            .chars()
            .map(|c| {
                if c.is_whitespace() || ",()=;%".contains(c) {
                    '_'
                } else {
                    c
                }
            })
            .collect();
        let mut tag = if given.is_empty() {
            format!("marker_{m}")
        } else {
            given
        };
        if tags.contains(&tag) {
            tag = format!("{tag}_{m}");
        }
        tags.push(tag);
    }
    tags
}

fn su2_body(
    w: &mut dyn Write,
    mesh: &TetMeshOut<'_>,
    markers: &[i32],
    names: &[String],
) -> std::io::Result<()> {
    writeln!(w, "NDIME= 3\nNELEM= {}", mesh.tets.len())?;
    for (k, t) in mesh.tets.iter().enumerate() {
        writeln!(w, "10 {} {} {} {} {k}", t[0], t[1], t[2], t[3])?;
    }
    writeln!(w, "NPOIN= {}", mesh.coords.len())?;
    for (i, p) in mesh.coords.iter().enumerate() {
        for &c in p {
            write_f64(w, c)?;
            w.write_all(b" ")?;
        }
        writeln!(w, "{i}")?;
    }
    writeln!(w, "NMARK= {}", markers.len())?;
    for (&m, name) in markers.iter().zip(names) {
        let count = mesh.face_markers.iter().filter(|&&x| x == m).count();
        writeln!(w, "MARKER_TAG= {name}\nMARKER_ELEMS= {count}")?;
        for (t, _) in mesh
            .faces
            .iter()
            .zip(mesh.face_markers)
            .filter(|&(_, &x)| x == m)
        {
            writeln!(w, "5 {} {} {}", t[0], t[1], t[2])?;
        }
    }
    Ok(())
}

/// Writes a 2D triangle mesh as an SU2 `.su2` file: its boundary edges grouped by marker, one
/// `MARKER_TAG= marker_<m>` each, in increasing order of `m`. Regions and point markers are not
/// written. Atomic.
pub fn write_su2_2d(path: &Path, mesh: &TriangleMeshOut<'_>) -> Result<(), IoError> {
    mesh.check(path)?;
    // The edges by marker (stable: each marker's edges in the mesh's order).
    let mut by_marker: Vec<usize> = (0..mesh.edges.len()).collect();
    by_marker.sort_by_key(|&e| mesh.edge_markers[e]);
    write_atomic(path, |w| {
        su2_body_2d(w, mesh, &by_marker).map_err(|e| IoError::io(path, e))
    })
}

fn su2_body_2d(
    w: &mut dyn Write,
    mesh: &TriangleMeshOut<'_>,
    by_marker: &[usize],
) -> std::io::Result<()> {
    writeln!(w, "NDIME= 2\nNELEM= {}", mesh.triangles.len() / 3)?;
    for (k, t) in mesh.triangles.chunks_exact(3).enumerate() {
        writeln!(w, "5 {} {} {} {k}", t[0], t[1], t[2])?;
    }
    writeln!(w, "NPOIN= {}", mesh.coords.len() / 2)?;
    for (i, p) in mesh.coords.chunks_exact(2).enumerate() {
        for &c in p {
            write_f64(w, c)?;
            w.write_all(b" ")?;
        }
        writeln!(w, "{i}")?;
    }
    let groups: Vec<&[usize]> = by_marker
        .chunk_by(|&a, &b| mesh.edge_markers[a] == mesh.edge_markers[b])
        .collect();
    writeln!(w, "NMARK= {}", groups.len())?;
    for group in groups {
        let m = mesh.edge_markers[group[0]];
        writeln!(w, "MARKER_TAG= marker_{m}\nMARKER_ELEMS= {}", group.len())?;
        for &e in group {
            let [a, b] = mesh.edges[e];
            writeln!(w, "3 {a} {b}")?;
        }
    }
    Ok(())
}
