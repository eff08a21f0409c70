//! Plain-text point lists (`x y` or `x y z` per line), and [`read_points`], which picks the
//! reader from the file extension.
//!
//! This is the lowest-common-denominator input: whatever produced the points (a script, a CAD
//! export, a spreadsheet saved as whitespace-separated text) can hand them to delmesh without
//! writing a `.node` header. Columns are whitespace-separated; `#` starts a comment; blank lines
//! are skipped; every data line must have the same number of columns (2 or 3), which sets the
//! dimension. Errors name the file and the 1-based line.

use std::path::Path;

use crate::node::read_node;
use crate::text::{data_lines, last_line, parse_coord, read_text};
use crate::{IoError, PointSet};

/// Extensions of mesh or geometry formats that are not point lists; [`read_points`] refuses them
/// instead of reporting a confusing parse error on their first line.
const NOT_POINT_LISTS: &[&str] = &[
    "ele", "neigh", "face", "edge", "poly", "smesh", "vtu", "vtk", "vtp", "msh", "stl", "obj",
    "ply", "off", "mesh", "su2",
];

/// Reads points from `path`, choosing the format from the extension: `.node` is read as a
/// TetGen/Triangle node file ([`read_node`]); mesh formats that are not point lists (`.ele`,
/// `.poly`, `.vtu`, `.stl`, ...) are an [`IoError::UnknownFormat`]; anything else is read as
/// plain text ([`read_xyz`]).
pub fn read_points(path: &Path) -> Result<PointSet, IoError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("node") => read_node(path),
        Some(e) if NOT_POINT_LISTS.contains(&e) => Err(IoError::UnknownFormat {
            file: path.to_path_buf(),
        }),
        _ => read_xyz(path),
    }
}

/// Reads a plain-text point list (`x y` or `x y z` per line).
pub fn read_xyz(path: &Path) -> Result<PointSet, IoError> {
    let text = read_text(path)?;
    parse_xyz(&text, path)
}

/// Parses the text of a plain point list; `file` is only used in error messages.
///
/// A file without any data line is an error (its dimension would be unknown).
pub fn parse_xyz(text: &str, file: &Path) -> Result<PointSet, IoError> {
    const AXES: [&str; 3] = ["x", "y", "z"];
    let mut dim = 0;
    let mut first_line = 0;
    let mut coords = Vec::new();
    for (line, toks) in data_lines(text) {
        if dim == 0 {
            if toks.len() != 2 && toks.len() != 3 {
                return Err(IoError::parse(
                    file,
                    line,
                    format!("expected 2 or 3 columns (x y [z]), found {}", toks.len()),
                ));
            }
            dim = toks.len();
            first_line = line;
        } else if toks.len() != dim {
            return Err(IoError::parse(
                file,
                line,
                format!(
                    "expected {dim} columns like line {first_line}, found {}",
                    toks.len()
                ),
            ));
        }
        for (tok, axis) in toks.iter().zip(AXES) {
            coords.push(parse_coord(tok, axis, file, line)?);
        }
    }
    if dim == 0 {
        return Err(IoError::parse(
            file,
            last_line(text),
            "no points found (expected lines 'x y' or 'x y z')",
        ));
    }
    Ok(PointSet {
        dim,
        coords,
        first_index: 0,
        attributes: Vec::new(),
        markers: None,
    })
}
