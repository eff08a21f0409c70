//! [`TetMeshOut`], the plain-data tetrahedral mesh every 3D mesh writer takes, its checks, and
//! [`write_tet_mesh`], which picks the writer from the file extension.
//!
//! A CFD volume mesh is more than tetrahedra: solvers need the boundary triangles with their
//! markers (to apply wall, inlet, far-field conditions) and the region (cell zone) of every
//! tetrahedron. Each writer puts these where its format expects them; the checks here run
//! before any file is touched, so a bad mesh never leaves half a family of files behind.
//!
//! Orientation is written as given: every format here (VTK, gmsh, Medit, SU2, TetGen) expects
//! tetrahedra `[a, b, c, d]` with `d` on the side of `abc` that its right-hand normal points to
//! (positive volume); boundary triangles usually face out of the domain.

use std::path::{Path, PathBuf};

use crate::IoError;

/// A tetrahedral mesh with boundary triangles, markers and regions, as plain arrays.
#[derive(Clone, Copy, Debug, Default)]
pub struct TetMeshOut<'a> {
    /// Point coordinates.
    pub coords: &'a [[f64; 3]],
    /// Tetrahedra, 0-based point indices.
    pub tets: &'a [[u32; 4]],
    /// A region attribute (cell zone) per tetrahedron, if any. Formats with integer zones
    /// (Medit, gmsh physical groups) need integral values (see each writer).
    pub regions: Option<&'a [f64]>,
    /// Boundary triangles, 0-based point indices.
    pub faces: &'a [[u32; 3]],
    /// A boundary marker per boundary triangle.
    pub face_markers: &'a [i32],
    /// A boundary marker per point, if any.
    pub point_markers: Option<&'a [i32]>,
    /// Names of face markers (`(marker, name)`), used where the format names boundaries (gmsh
    /// physical names, SU2 `MARKER_TAG`); a marker without a name is called `marker_<m>`.
    pub marker_names: &'a [(i32, &'a str)],
}

impl TetMeshOut<'_> {
    /// Checks that the arrays are consistent; `file` is the destination named in errors.
    pub(crate) fn check(&self, file: &Path) -> Result<(), IoError> {
        let bad = |m: String| Err(IoError::invalid(file, m));
        let np = self.coords.len();
        if let Some(i) = self
            .coords
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))
        {
            return bad(format!("point {i} has a non-finite coordinate"));
        }
        if np > u32::MAX as usize {
            return bad(format!("{np} points do not fit 32-bit indices"));
        }
        let out_of_range = |v: &u32| *v as usize >= np;
        if let Some(k) = self.tets.iter().position(|t| t.iter().any(out_of_range)) {
            return bad(format!(
                "tetrahedron {k} {:?} refers to a point that does not exist ({np} points)",
                self.tets[k]
            ));
        }
        if let Some(k) = self.faces.iter().position(|t| t.iter().any(out_of_range)) {
            return bad(format!(
                "boundary triangle {k} {:?} refers to a point that does not exist ({np} points)",
                self.faces[k]
            ));
        }
        if let Some(r) = self.regions {
            if r.len() != self.tets.len() {
                return bad(format!(
                    "{} regions for {} tetrahedra: one per tetrahedron is needed",
                    r.len(),
                    self.tets.len()
                ));
            }
            if let Some(k) = r.iter().position(|x| !x.is_finite()) {
                return bad(format!("region of tetrahedron {k} is not finite"));
            }
        }
        if self.face_markers.len() != self.faces.len() {
            return bad(format!(
                "{} face markers for {} boundary triangles: one per triangle is needed",
                self.face_markers.len(),
                self.faces.len()
            ));
        }
        if self.point_markers.is_some_and(|m| m.len() != np) {
            return bad("one point marker per point is needed".into());
        }
        for (i, &(m, name)) in self.marker_names.iter().enumerate() {
            if self.marker_names[..i].iter().any(|&(o, _)| o == m) {
                return bad(format!("marker {m} is named twice"));
            }
            if name.is_empty() || name.chars().any(|c| c.is_control() || c == '"') {
                return bad(format!(
                    "name {name:?} of marker {m} is empty or has a quote or control character"
                ));
            }
        }
        Ok(())
    }

    /// The region of tetrahedron `k` (0 without regions).
    pub(crate) fn region(&self, k: usize) -> f64 {
        self.regions.map_or(0.0, |r| r[k])
    }

    /// The regions as integers, for formats whose zones are integers; an error names the first
    /// tetrahedron whose region is not an integer in `i32` range.
    pub(crate) fn integer_regions(&self, file: &Path) -> Result<Vec<i32>, IoError> {
        (0..self.tets.len())
            .map(|k| {
                let r = self.region(k);
                if r.fract() == 0.0 && (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&r) {
                    Ok(r as i32)
                } else {
                    Err(IoError::invalid(
                        file,
                        format!(
                            "region {r} of tetrahedron {k} is not an integer; this format \
                             numbers regions with integers"
                        ),
                    ))
                }
            })
            .collect()
    }

    /// The name of face marker `m`: its given name or `marker_<m>`.
    pub(crate) fn marker_name(&self, m: i32) -> String {
        self.marker_names
            .iter()
            .find(|&&(o, _)| o == m)
            .map_or_else(|| format!("marker_{m}"), |&(_, n)| n.to_string())
    }

    /// The distinct face markers, sorted.
    pub(crate) fn distinct_markers(&self) -> Vec<i32> {
        let mut m = self.face_markers.to_vec();
        m.sort_unstable();
        m.dedup();
        m
    }
}

/// Path `stem.ext`, where `stem` is `path` without its extension if that is one of `strip`.
pub(crate) fn sibling(path: &Path, strip: &[&str], ext: &str) -> PathBuf {
    let stem = match path.extension().and_then(|e| e.to_str()) {
        Some(e) if strip.contains(&e) => path.with_extension(""),
        _ => path.to_path_buf(),
    };
    let mut s = stem.into_os_string();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Writes a tetrahedral mesh, choosing the format from the extension of `path`: `.vtu`
/// ([`crate::write_tet_mesh_vtu`], two files), `.node`/`.ele`/`.face` (the TetGen family,
/// [`crate::write_tetgen_mesh`], numbered from 1), `.msh` ([`crate::write_msh`], gmsh 4.1),
/// `.mesh` ([`crate::write_medit`]), `.su2` ([`crate::write_su2`]); a path named `polyMesh`
/// is an OpenFOAM mesh directory ([`crate::write_foam`]). Returns the files written.
pub fn write_tet_mesh(path: &Path, mesh: &TetMeshOut<'_>) -> Result<Vec<PathBuf>, IoError> {
    if crate::is_polymesh(path) {
        return crate::write_foam(path, mesh);
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("vtu") => crate::write_tet_mesh_vtu(path, mesh),
        Some("node" | "ele" | "face") => crate::write_tetgen_mesh(path, mesh, 1),
        Some("msh") => crate::write_msh(path, mesh).map(|()| vec![path.to_path_buf()]),
        Some("mesh") => crate::write_medit(path, mesh).map(|()| vec![path.to_path_buf()]),
        Some("su2") => crate::write_su2(path, mesh).map(|()| vec![path.to_path_buf()]),
        _ => Err(IoError::UnknownFormat {
            file: path.to_path_buf(),
        }),
    }
}
