//! SU2 native mesh files (`.su2`, ASCII), written: the input of the SU2 CFD solver.
//!
//! Layout: `NDIME= 3`; `NELEM= <n>` and one line per tetrahedron `10 a b c d <index>` (VTK
//! type 10; 0-based point indices, the trailing element index as SU2 itself writes it);
//! `NPOIN= <n>` and one line per point `x y z <index>`; `NMARK= <k>` and, per boundary marker,
//! `MARKER_TAG= <name>`, `MARKER_ELEMS= <m>` and its triangles `5 a b c` (VTK type 5).
//! Markers are written in increasing order, each named by [`TetMeshOut::marker_names`] or
//! `marker_<m>`; the names are what the solver's configuration file refers to
//! (`MARKER_EULER= ( wing )`), so they must not contain white space. A single-zone SU2 mesh has
//! no cell zones: regions and point markers are not written.

use std::io::Write;
use std::path::Path;

use crate::atomic::write_atomic;
use crate::tetmesh::TetMeshOut;
use crate::text::write_f64;
use crate::IoError;

/// Writes a tetrahedral mesh as an SU2 `.su2` file, one `MARKER_TAG` per face marker. Atomic.
pub fn write_su2(path: &Path, mesh: &TetMeshOut<'_>) -> Result<(), IoError> {
    mesh.check(path)?;
    let markers = mesh.distinct_markers();
    let names: Vec<String> = markers.iter().map(|&m| mesh.marker_name(m)).collect();
    for (i, name) in names.iter().enumerate() {
        if name.chars().any(char::is_whitespace) {
            return Err(IoError::invalid(
                path,
                format!("SU2 marker name {name:?} contains white space"),
            ));
        }
        if names[..i].contains(name) {
            return Err(IoError::invalid(
                path,
                format!("two markers are both named {name:?}"),
            ));
        }
    }
    write_atomic(path, |w| {
        su2_body(w, mesh, &markers, &names).map_err(|e| IoError::io(path, e))
    })
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
