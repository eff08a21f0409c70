//! The plain-data types this crate reads and writes: [`PointSet`] and [`SimplexMesh`].
//!
//! `delmesh-io` deliberately does not depend on the other delmesh crates; these types are flat
//! arrays that any of them can produce or consume without conversion cost, and writers check
//! them (dimension, lengths, index ranges, finiteness) before touching the file system.

use std::path::Path;

use crate::IoError;

/// Points read from a file, dimension 2 or 3.
#[derive(Debug, Clone, PartialEq)]
pub struct PointSet {
    /// Dimension of the points: 2 or 3.
    pub dim: usize,
    /// `dim * len()` coordinates, flat (`x0 y0 [z0] x1 y1 [z1] ...`), in file order.
    pub coords: Vec<f64>,
    /// Index of the first point in the file (`.node`: 0 or 1; plain text: 0).
    pub first_index: u32,
    /// Per attribute, one value per point (empty when the file has no attributes).
    pub attributes: Vec<Vec<f64>>,
    /// Boundary markers, one per point, if the file has them.
    pub markers: Option<Vec<i32>>,
}

impl PointSet {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.coords.len().checked_div(self.dim).unwrap_or(0)
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The x and y coordinates of point `i` (0-based position in the file, whatever
    /// `first_index` is); for 3D points the z coordinate is dropped.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    pub fn point2(&self, i: usize) -> [f64; 2] {
        let p = &self.coords[i * self.dim..(i + 1) * self.dim];
        [p[0], p[1]]
    }

    /// The coordinates of point `i` (0-based position in the file) as a 3D point; 2D points get
    /// `z = 0`.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    pub fn point3(&self, i: usize) -> [f64; 3] {
        let p = &self.coords[i * self.dim..(i + 1) * self.dim];
        [p[0], p[1], p.get(2).copied().unwrap_or(0.0)]
    }
}

/// A simplicial mesh as plain arrays: cells are triangles (3) or tetrahedra (4) indexing `coords`.
#[derive(Debug, Clone, Copy)]
pub struct SimplexMesh<'a> {
    /// Dimension: 2 (triangles) or 3 (tetrahedra).
    pub dim: usize,
    /// `dim * n_points` coordinates, flat.
    pub coords: &'a [f64],
    /// `(dim + 1) * n_cells` vertex indices, 0-based indices into the points.
    pub cells: &'a [u32],
    /// `(dim + 1) * n_cells` entries: entry `i` of a cell is the neighbour across the face
    /// opposite its local vertex `i` (0-based cell index), or -1 for none.
    pub neighbors: Option<&'a [i64]>,
}

impl SimplexMesh<'_> {
    /// Number of points (`coords.len() / dim`; 0 for an invalid dimension).
    pub fn n_points(&self) -> usize {
        self.coords.len().checked_div(self.dim).unwrap_or(0)
    }

    /// Number of cells (`cells.len() / (dim + 1)`).
    pub fn n_cells(&self) -> usize {
        self.cells.len() / self.dim.saturating_add(1)
    }

    /// Checks that the arrays are consistent; `file` is the destination named in errors.
    pub(crate) fn check(&self, file: &Path) -> Result<(), IoError> {
        check_points(file, self.dim, self.coords)?;
        let nv = self.dim + 1;
        if self.cells.len() % nv != 0 {
            return Err(IoError::invalid(
                file,
                format!(
                    "cell array has {} entries, not a multiple of {nv}",
                    self.cells.len()
                ),
            ));
        }
        let n_points = self.n_points();
        if let Some(pos) = self.cells.iter().position(|&v| v as usize >= n_points) {
            return Err(IoError::invalid(
                file,
                format!(
                    "cell {} refers to point {} but there are only {n_points} points",
                    pos / nv,
                    self.cells[pos]
                ),
            ));
        }
        if let Some(neighbors) = self.neighbors {
            if neighbors.len() != self.cells.len() {
                return Err(IoError::invalid(
                    file,
                    format!(
                        "neighbour array has {} entries, expected {} ({nv} per cell)",
                        neighbors.len(),
                        self.cells.len()
                    ),
                ));
            }
            let n_cells = self.n_cells() as i64;
            if let Some(pos) = neighbors.iter().position(|&n| n < -1 || n >= n_cells) {
                return Err(IoError::invalid(
                    file,
                    format!(
                        "cell {} has neighbour {} but there are only {n_cells} cells (-1 means none)",
                        pos / nv,
                        neighbors[pos]
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Checks a flat coordinate array: dimension 2 or 3, length a multiple of it, all finite.
pub(crate) fn check_points(file: &Path, dim: usize, coords: &[f64]) -> Result<(), IoError> {
    if dim != 2 && dim != 3 {
        return Err(IoError::invalid(
            file,
            format!("dimension must be 2 or 3, found {dim}"),
        ));
    }
    if coords.len() % dim != 0 {
        return Err(IoError::invalid(
            file,
            format!(
                "coordinate array has {} entries, not a multiple of the dimension {dim}",
                coords.len()
            ),
        ));
    }
    if let Some(pos) = coords.iter().position(|c| !c.is_finite()) {
        return Err(IoError::invalid(
            file,
            format!(
                "coordinate {} of point {} is not finite ({})",
                pos % dim,
                pos / dim,
                coords[pos]
            ),
        ));
    }
    Ok(())
}

/// Checks that `first_index` is 0 or 1, the only bases TetGen and Triangle accept.
pub(crate) fn check_first_index(file: &Path, first_index: u32) -> Result<(), IoError> {
    if first_index > 1 {
        return Err(IoError::invalid(
            file,
            format!("first index must be 0 or 1, found {first_index}"),
        ));
    }
    Ok(())
}
