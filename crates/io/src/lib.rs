//! File input and output for delmesh: point sets in, meshes out.
//!
//! This crate is the only place delmesh touches mesh and point files. It depends on no other
//! delmesh crate: readers return and writers take plain arrays ([`PointSet`], [`SimplexMesh`],
//! [`SurfaceFile`], [`TetMeshOut`]), so the core algorithms stay free of I/O and any front end
//! can use the formats.
//!
//! | format | read | write |
//! | --- | --- | --- |
//! | TetGen/Triangle `.node` | [`read_node`], [`parse_node`] | [`write_node`], [`write_node_with`] (attributes, markers) |
//! | TetGen/Triangle `.ele`, `.neigh` | | [`write_ele`], [`write_neigh`], [`write_tetgen_family`], [`write_tetgen_family_with`] |
//! | plain text `x y [z]` | [`read_xyz`], [`parse_xyz`] | |
//! | VTK XML `.vtu` | [`read_vtu`] (every data mode VTK writes; linear cells as triangles/tetrahedra, point and cell fields as point fields) | [`write_vtu`], [`write_vtu_polygons`], [`write_tet_mesh_vtu`] (3D mesh + `.boundary.vtu`) |
//! | legacy VTK `.vtk` (2.0–5.1, ASCII or binary) | [`read_vtk_legacy`] (as [`read_vtu`]) | |
//! | Triangle `.poly` (2D PSLG) | [`read_poly`], [`parse_poly`] | [`write_poly`] |
//! | Triangle `.node/.ele/.edge` with markers | [`read_triangle_mesh`] | [`write_triangle_family`] |
//! | SVG picture of a 2D mesh | | [`write_svg`] |
//! | TetGen `.smesh` (3D surface) | [`read_smesh`], [`parse_smesh`] | [`write_smesh`] |
//! | TetGen `.poly` (3D PLC) | [`read_tetgen_poly`], [`parse_tetgen_poly`]; either dimension: [`read_poly_any`], [`parse_poly_any`] | [`write_tetgen_poly`] |
//! | Geomview `.off` | [`read_off`], [`parse_off`] | [`write_off`] |
//! | `.stl`, ASCII and binary | [`read_stl`], [`parse_stl`] | |
//! | Wavefront `.obj` | [`read_obj`], [`parse_obj`] | |
//! | Stanford `.ply`, ASCII and binary | [`read_ply`], [`parse_ply`] | |
//! | Medit `.mesh` | [`read_medit`], [`parse_medit`] (surface and tetrahedra) | [`write_medit`] |
//! | gmsh `.msh` 2.2 / 4.1, ASCII and binary | [`read_msh`], [`parse_msh`], [`parse_msh_bytes`] (surface and tetrahedra) | [`write_msh`], 2D [`write_msh_2d`] (4.1 ASCII) |
//! | SU2 `.su2` (3D, 2D) | | [`write_su2`], [`write_su2_2d`] |
//! | OpenFOAM `constant/polyMesh` (3D; 2D as one layer of prisms) | | [`write_foam`], [`write_foam_2d`] |
//! | TetGen `.node/.ele/.face` with markers and regions | | [`write_tetgen_mesh`] |
//!
//! [`read_points`] picks a point reader, [`read_surface`] a surface reader and
//! [`write_tet_mesh`] a tetrahedral-mesh writer from the extension.
//!
//! Guarantees:
//! - Readers never panic, whatever the input; every error is an [`IoError`] naming the file and,
//!   for malformed text, the 1-based line (`points.node:12: expected 4 fields, found 3`; binary
//!   files: the byte offset). Non-finite coordinates are rejected.
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
#![forbid(unsafe_code)]

mod atomic;
mod error;
mod foam;
mod medit;
mod model;
mod msh;
mod msh_binary;
mod node;
mod obj;
mod off;
mod ply;
mod poly;
mod stl;
mod su2;
mod surface;
mod svg;
mod tetgen_mesh;
mod tetgen_plc;
mod tetmesh;
mod text;
mod triangle;
mod vtk_legacy;
mod vtu;
mod vtu_read;
mod xyz;

pub use atomic::{remove_temporary_files, transaction, write_atomic};
pub use error::IoError;
pub use foam::{is_polymesh, write_foam, write_foam_2d, POLYMESH_FILES};
pub use medit::{parse_medit, read_medit, write_medit};
pub use model::{PointSet, SimplexMesh};
pub use msh::{parse_msh, parse_msh_bytes, read_msh, write_msh, write_msh_2d};
pub use node::{
    parse_node, read_node, write_ele, write_neigh, write_node, write_node_with,
    write_tetgen_family, write_tetgen_family_with, NodeData,
};
pub use obj::{parse_obj, read_obj};
pub use off::{parse_off, read_off, write_off};
pub use ply::{parse_ply, read_ply};
pub use poly::{parse_poly, read_poly, write_poly, PolyFile, PolyRegion};
pub use stl::{parse_stl, read_stl};
pub use su2::{write_su2, write_su2_2d};
pub use surface::{read_surface, SurfaceFacet, SurfaceFile, SurfaceRegion};
pub use svg::{write_svg, SvgMesh, SvgOptions};
pub use tetgen_mesh::write_tetgen_mesh;
pub use tetgen_plc::{
    parse_poly_any, parse_smesh, parse_tetgen_poly, read_poly_any, read_smesh, read_tetgen_poly,
    write_smesh, write_tetgen_poly, AnyPoly,
};
pub use tetmesh::{write_tet_mesh, TetMeshOut};
pub use triangle::{read_triangle_mesh, write_triangle_family, TriangleMeshOut};
pub use vtu::{
    read_vtk_legacy, read_vtu, write_tet_mesh_vtu, write_tet_mesh_vtu_with, write_vtu,
    write_vtu_polygons, FieldMesh,
};
pub use xyz::{parse_xyz, read_points, read_xyz};
