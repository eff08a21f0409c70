//! TetGen's output family for a tetrahedral mesh with markers and regions: `X.node` (points and
//! their boundary markers), `X.ele` (tetrahedra and their region attribute), `X.face`
//! (boundary triangles and their markers), as TetGen writes them with `-A` and `-f`/`-F`.
//!
//! These files are read by TetView, by meshio, and by the many research codes that grew up
//! around TetGen, and they are the plainest way to diff a delmesh mesh against TetGen's.
//! Layouts: `.node` `<#points> 3 0 <0|1>` then `<i> x y z [marker]`; `.ele` `<#tets> 4 <0|1>`
//! then `<i> a b c d [region]`; `.face` `<#faces> 1` then `<i> a b c <marker>`. Everything is
//! numbered from the chosen first index (0 or 1), and coordinates read back bit-exactly.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::atomic::{settle, stage};
use crate::model::check_first_index;
use crate::tetmesh::{sibling, TetMeshOut};
use crate::text::{write_f64, write_u64};
use crate::IoError;

/// Writes `X.node`, `X.ele` and `X.face` for `path` (`X` is `path` without a `.node`, `.ele` or
/// `.face` extension), numbered from `first_index` (0 or 1). Returns the paths written, in that
/// order. Everything is checked before the first file is written; each file is atomic.
pub fn write_tetgen_mesh(
    path: &Path,
    mesh: &TetMeshOut<'_>,
    first_index: u32,
) -> Result<Vec<PathBuf>, IoError> {
    mesh.check(path)?;
    check_first_index(path, first_index)?;
    let [node, ele, face] =
        ["node", "ele", "face"].map(|e| sibling(path, &["node", "ele", "face"], e));
    let base = u64::from(first_index);
    // The three files are independent: written side by side, so that their syncs to disk
    // overlap (on a small mesh they take longer than the writing); renamed together, once all
    // three are on disk.
    let write_node = || {
        stage(&node, |w| {
            node_body(w, mesh, base).map_err(|e| IoError::io(&node, e))
        })
    };
    let write_face = || {
        stage(&face, |w| {
            face_body(w, mesh, base).map_err(|e| IoError::io(&face, e))
        })
    };
    let write_ele = || {
        stage(&ele, |w| {
            ele_body(w, mesh, base).map_err(|e| IoError::io(&ele, e))
        })
    };
    let (node_done, face_done, ele_done) = std::thread::scope(|scope| {
        let node_thread = scope.spawn(write_node);
        let face_thread = scope.spawn(write_face);
        let ele_done = write_ele();
        (node_thread.join(), face_thread.join(), ele_done)
    });
    let mut staged = Vec::with_capacity(3);
    for done in [node_done, face_done] {
        match done {
            Ok(done) => staged.push(done?),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    }
    staged.push(ele_done?);
    settle(staged)?;
    Ok(vec![node, ele, face])
}

fn node_body(w: &mut dyn Write, mesh: &TetMeshOut<'_>, base: u64) -> std::io::Result<()> {
    let markers = mesh.point_markers;
    writeln!(
        w,
        "{} 3 0 {}",
        mesh.coords.len(),
        u8::from(markers.is_some())
    )?;
    for (i, p) in mesh.coords.iter().enumerate() {
        write_u64(w, i as u64 + base)?;
        for &c in p {
            w.write_all(b" ")?;
            write_f64(w, c)?;
        }
        if let Some(m) = markers {
            write!(w, " {}", m[i])?;
        }
        w.write_all(b"\n")?;
    }
    Ok(())
}

fn ele_body(w: &mut dyn Write, mesh: &TetMeshOut<'_>, base: u64) -> std::io::Result<()> {
    writeln!(
        w,
        "{} 4 {}",
        mesh.tets.len(),
        u8::from(mesh.regions.is_some())
    )?;
    for (k, t) in mesh.tets.iter().enumerate() {
        write_u64(w, k as u64 + base)?;
        for &v in t {
            w.write_all(b" ")?;
            write_u64(w, u64::from(v) + base)?;
        }
        if let Some(r) = mesh.regions {
            w.write_all(b" ")?;
            write_f64(w, r[k])?;
        }
        w.write_all(b"\n")?;
    }
    Ok(())
}

fn face_body(w: &mut dyn Write, mesh: &TetMeshOut<'_>, base: u64) -> std::io::Result<()> {
    writeln!(w, "{} 1", mesh.faces.len())?;
    for (k, (t, m)) in mesh.faces.iter().zip(mesh.face_markers).enumerate() {
        write_u64(w, k as u64 + base)?;
        for &v in t {
            w.write_all(b" ")?;
            write_u64(w, u64::from(v) + base)?;
        }
        writeln!(w, " {m}")?;
    }
    Ok(())
}
