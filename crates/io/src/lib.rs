//! File input and output for delmesh: point sets in, meshes out.
//!
//! This crate is the only place delmesh touches mesh and point files. It depends on no other
//! delmesh crate: readers return and writers take plain arrays ([`PointSet`], [`SimplexMesh`]),
//! so the core algorithms stay free of I/O and any front end can use the formats.
//!
//! | format | read | write |
//! | --- | --- | --- |
//! | TetGen/Triangle `.node` | [`read_node`], [`parse_node`] | [`write_node`] |
//! | TetGen/Triangle `.ele`, `.neigh` | | [`write_ele`], [`write_neigh`], [`write_tetgen_family`] |
//! | plain text `x y [z]` | [`read_xyz`], [`parse_xyz`] | |
//! | VTK XML `.vtu` | [`read_vtu`] (triangles/tetrahedra + point fields) | [`write_vtu`], [`write_vtu_polygons`] |
//! | Triangle `.poly` (2D PSLG) | [`read_poly`], [`parse_poly`] | [`write_poly`] |
//! | Triangle `.node/.ele/.edge` with markers | [`read_triangle_mesh`] | [`write_triangle_family`] |
//! | SVG picture of a 2D mesh | | [`write_svg`] |
//!
//! [`read_points`] picks the reader from the extension.
//!
//! Guarantees:
//! - Readers never panic, whatever the input; every error is an [`IoError`] naming the file and,
//!   for malformed text, the 1-based line (`points.node:12: expected 4 fields, found 3`).
//!   Non-finite coordinates are rejected.
//! - Writers check their input before touching the file system, and write atomically
//!   ([`write_atomic`]): on error the destination keeps its old contents.
//! - Numbers in text files are written in shortest round-trip form: reading a written `.node`
//!   file gives back the same `f64` bits.
//!
//! ```
//! use std::path::Path;
//!
//! let text = "# two points, numbered from 1\n2 2 0 0\n1 0 0\n2 1 0.5\n";
//! let points = delmesh_io::parse_node(text, Path::new("in.node"))?;
//! assert_eq!((points.len(), points.first_index), (2, 1));
//! assert_eq!(points.point2(1), [1.0, 0.5]);
//!
//! let err = delmesh_io::parse_node("2 2 0 0\n1 0 0\n", Path::new("in.node")).unwrap_err();
//! assert_eq!(
//!     err.to_string(),
//!     "in.node:2: unexpected end of file: the header (line 1) declares 2 points but the file has only 1"
//! );
//! # Ok::<(), delmesh_io::IoError>(())
//! ```

mod atomic;
mod error;
mod model;
mod node;
mod poly;
mod svg;
mod text;
mod triangle;
mod vtu;
mod xyz;

pub use atomic::write_atomic;
pub use error::IoError;
pub use model::{PointSet, SimplexMesh};
pub use node::{parse_node, read_node, write_ele, write_neigh, write_node, write_tetgen_family};
pub use poly::{parse_poly, read_poly, write_poly, PolyFile, PolyRegion};
pub use svg::{write_svg, SvgMesh, SvgOptions};
pub use triangle::{read_triangle_mesh, write_triangle_family, TriangleMeshOut};
pub use vtu::{read_vtu, write_vtu, write_vtu_polygons, FieldMesh};
pub use xyz::{parse_xyz, read_points, read_xyz};
