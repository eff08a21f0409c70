//! VTK XML unstructured-grid (`.vtu`) output through the `vtkio` crate, and input (by
//! [`crate::vtu_read`], which reads what vtkio does not).
//!
//! `.vtu` is what ParaView and VisIt open directly, so it is the format for looking at meshes,
//! quality fields and Voronoi cells. [`write_vtu`] writes triangle / tetrahedron meshes with
//! optional per-point and per-cell scalar fields; [`write_vtu_polygons`] writes polygons (2D
//! Voronoi cells, or the faces of 3D Voronoi cells). Data is stored as base64 binary `Float64`
//! (coordinates and fields are exact), little endian, uncompressed; 2D points get `z = 0`.
//! [`write_tet_mesh_vtu`] writes a 3D mesh with its markers and regions as a volume file and a
//! boundary file. The XML is built in memory by `vtkio` and written through [`write_atomic`].

use std::path::{Path, PathBuf};

use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, IOBuffer,
    Piece, UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

use crate::atomic::{transaction, write_atomic};
use crate::model::check_points;
use crate::tetmesh::{sibling, TetMeshOut};
use crate::{IoError, SimplexMesh};

/// A mesh read from a file, with named point fields: a background mesh (field `spacing`) or a
/// previous flow mesh (pressure, Mach number, ...).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FieldMesh {
    /// 2 if every z coordinate is 0, else 3.
    pub dim: usize,
    /// `dim` coordinates per point.
    pub coords: Vec<f64>,
    /// `dim + 1` 0-based point indices per cell (triangles in 2D, tetrahedra in 3D).
    pub cells: Vec<u32>,
    /// Scalar point fields by name; a vector field of `k` components gives `name_0`,
    /// `name_1`, ... (one scalar field per component).
    pub point_fields: Vec<(String, Vec<f64>)>,
    /// The file where the points and their fields are, and the number it gives its first
    /// point: the `.vtu` itself and 0, or a Triangle mesh's `.node` file and its base (0 or 1),
    /// so that messages name a point as its file does.
    pub points_file: (std::path::PathBuf, u32),
}

/// Reads a VTK XML unstructured grid (`.vtu`) with its point fields, in any data mode VTK writes
/// (the `vtu_read` module: ASCII, inline binary, appended raw or base64, compressed or not),
/// as triangles (2D: every z is 0) or tetrahedra: other linear cells are split into them (see
/// `split_cell`).
///
/// # Errors
/// A file that cannot be read or is not a `.vtu` of one piece, data that does not decode,
/// cells that are not linear, indices out of range.
pub fn read_vtu(path: &Path) -> Result<FieldMesh, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    let piece = crate::vtu_read::parse_vtu(&bytes).map_err(|m| IoError::invalid(path, m))?;
    field_mesh(path, piece)
}

/// Reads a legacy VTK file (`.vtk`, ASCII or binary, versions 2.0 to 5.1, as VTK, ParaView and
/// OpenFOAM's `foamToVTK` write them) of an unstructured grid, as [`read_vtu`] reads a `.vtu`
/// (the `vtk_legacy` module).
///
/// # Errors
/// As [`read_vtu`]; also another data set type.
pub fn read_vtk_legacy(path: &Path) -> Result<FieldMesh, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    let piece =
        crate::vtk_legacy::parse_vtk_legacy(&bytes).map_err(|m| IoError::invalid(path, m))?;
    field_mesh(path, piece)
}

/// The mesh of a read piece: its cells split into simplices, its point fields by component.
fn field_mesh(path: &Path, piece: crate::vtu_read::VtuPiece) -> Result<FieldMesh, IoError> {
    if piece.points.len() % 3 != 0 {
        return Err(IoError::invalid(
            path,
            "point coordinates are not 3 per point",
        ));
    }
    let xyz = piece.points;
    let n_points = xyz.len() / 3;
    if let Some(i) = xyz.iter().position(|x| !x.is_finite()) {
        return Err(IoError::invalid(
            path,
            format!("point {}: coordinate is not finite", i / 3),
        ));
    }
    let flat = xyz.chunks_exact(3).all(|p| p[2] == 0.0);
    let dim = if flat { 2 } else { 3 };
    let connectivity = &piece.connectivity;
    let mut cells = Vec::with_capacity(connectivity.len());
    // (point, mesh cell) for each corner of a mesh cell, for cell data.
    let spread = !piece.cell_data.is_empty();
    let mut corners: Vec<(u32, u32)> = Vec::new();
    let mut begin = 0usize;
    for (k, (&end, &ty)) in piece.offsets.iter().zip(&piece.types).enumerate() {
        let end = end as usize;
        if end < begin || end > connectivity.len() {
            return Err(IoError::invalid(
                path,
                format!("cell {k} ends at {end}, before it begins or past the connectivity"),
            ));
        }
        let mut nodes = Vec::with_capacity(end - begin);
        for &v in &connectivity[begin..end] {
            if !(v >= 0.0 && v < n_points as f64 && v.fract() == 0.0) {
                return Err(IoError::invalid(
                    path,
                    format!("cell {k} refers to point {v} but there are {n_points} points"),
                ));
            }
            nodes.push(v as u32);
        }
        begin = end;
        let before = cells.len();
        split_cell(ty, &nodes, dim, &mut cells).map_err(|m| {
            IoError::invalid(
                path,
                format!("cell {k} (VTK type {ty}, {} points): {m}", nodes.len()),
            )
        })?;
        // A cell of the mesh (not a point, line or face) spreads its cell data to its points.
        if cells.len() > before && spread {
            nodes.sort_unstable();
            nodes.dedup();
            corners.extend(nodes.iter().map(|&v| (v, k as u32)));
        }
    }
    let coords = if dim == 3 {
        xyz
    } else {
        xyz.chunks_exact(3).flat_map(|p| [p[0], p[1]]).collect()
    };
    let mut point_fields = Vec::new();
    for (name, comps, values) in piece.point_data {
        if values.len() != comps * n_points {
            continue;
        }
        if comps == 1 {
            point_fields.push((name, values));
        } else {
            for c in 0..comps {
                point_fields.push((
                    format!("{name}_{c}"),
                    values.iter().skip(c).step_by(comps).copied().collect(),
                ));
            }
        }
    }
    // Cell data (a finite-volume solver's cell-centred fields) as point fields: at each point
    // the mean of the cells around it; a point field of the same name is kept instead.
    let n_cells = piece.offsets.len();
    // The mesh cells around each point: `around[start[v]..start[v + 1]]`.
    let mut start = vec![0usize; if spread { n_points + 1 } else { 0 }];
    for &(v, _) in &corners {
        start[v as usize + 1] += 1;
    }
    for v in 1..start.len() {
        start[v] += start[v - 1];
    }
    let mut around = vec![0u32; corners.len()];
    let mut fill = start.clone();
    for &(v, k) in &corners {
        around[fill[v as usize]] = k;
        fill[v as usize] += 1;
    }
    for (name, comps, values) in piece.cell_data {
        if values.len() != comps * n_cells
            || point_fields
                .iter()
                .any(|(n, _)| *n == name || n.starts_with(&format!("{name}_")))
        {
            continue;
        }
        for c in 0..comps {
            let mean_of = |cells: &mut dyn Iterator<Item = usize>| {
                let (sum, n) = cells.fold((0.0, 0usize), |(s, n), k| {
                    (s + values[k * comps + c], n + 1)
                });
                sum / n as f64
            };
            // (A point in no cell, which nothing interpolates from, takes the mean.)
            let everywhere = mean_of(&mut (0..n_cells));
            let at_points: Vec<f64> = (0..n_points)
                .map(|v| match &around[start[v]..start[v + 1]] {
                    [] => everywhere,
                    cells => mean_of(&mut cells.iter().map(|&k| k as usize)),
                })
                .collect();
            let name = if comps == 1 {
                name.clone()
            } else {
                format!("{name}_{c}")
            };
            point_fields.push((name, at_points));
        }
    }
    Ok(FieldMesh {
        dim,
        coords,
        cells,
        point_fields,
        points_file: (path.to_path_buf(), 0),
    })
}

/// Appends the simplices of one `.vtu` cell to `out`: a mesh read for its point fields (a
/// background mesh, a flow solution to adapt to) is used to interpolate, so a solver's quads,
/// hexahedra, prisms and pyramids are split into triangles or tetrahedra (hexahedra into six
/// around a diagonal, prisms into three, pyramids into two; neighbours may split a shared
/// quadrilateral differently, which interpolation does not mind), and points and lines (and
/// faces in a 3D file) are left out. Quadratic and other cells are refused.
fn split_cell(ty: f64, v: &[u32], dim: usize, out: &mut Vec<u32>) -> Result<(), String> {
    let need = |n: usize| {
        if v.len() == n {
            Ok(())
        } else {
            Err(format!("{n} points expected"))
        }
    };
    let mut push = |corners: &[usize]| out.extend(corners.iter().map(|&c| v[c]));
    // Hexahedron corners in VTK's order (bottom 0-3, top 4-7): six tetrahedra around 0-6.
    let hexahedron = |push: &mut dyn FnMut(&[usize]), h: [usize; 8]| {
        for [a, b] in [[1, 2], [2, 3], [3, 7], [7, 4], [4, 5], [5, 1]] {
            push(&[h[0], h[a], h[b], h[6]]);
        }
    };
    // (A type that is not a whole number matches no cell type.)
    let whole = if ty.fract() == 0.0 && (0.0..=255.0).contains(&ty) {
        ty as u32
    } else {
        u32::MAX
    };
    match (dim, whole) {
        // Vertices, poly-vertices, lines, poly-lines.
        (_, 1..=4) => {}
        (2, 5) => {
            need(3)?;
            push(&[0, 1, 2]);
        }
        // Polygon and quad: a fan.
        (2, 7 | 9) => {
            if ty == 9.0 {
                need(4)?;
            } else if v.len() < 3 {
                return Err("a polygon needs 3 points".into());
            }
            for i in 1..v.len() - 1 {
                push(&[0, i, i + 1]);
            }
        }
        // Pixel: a quad with its corners in x-then-y order.
        (2, 8) => {
            need(4)?;
            push(&[0, 1, 3]);
            push(&[0, 3, 2]);
        }
        // Faces of a 3D mesh (a boundary written with the volume).
        (3, 5 | 7 | 8 | 9) => {}
        (3, 10) => {
            need(4)?;
            push(&[0, 1, 2, 3]);
        }
        (3, 11) => {
            need(8)?;
            hexahedron(&mut push, [0, 1, 3, 2, 4, 5, 7, 6]);
        }
        (3, 12) => {
            need(8)?;
            hexahedron(&mut push, [0, 1, 2, 3, 4, 5, 6, 7]);
        }
        // Wedge (prism): triangles 0-1-2 and 3-4-5.
        (3, 13) => {
            need(6)?;
            push(&[0, 1, 2, 5]);
            push(&[0, 1, 5, 4]);
            push(&[0, 4, 5, 3]);
        }
        // Pyramid: quadrilateral 0-3, apex 4.
        (3, 14) => {
            need(5)?;
            push(&[0, 1, 2, 4]);
            push(&[0, 2, 3, 4]);
        }
        _ => {
            return Err(if dim == 2 {
                "only triangles, quads, pixels and polygons (VTK types 5, 7, 8, 9) make a 2D mesh"
                    .into()
            } else {
                "only tetrahedra, hexahedra, voxels, wedges and pyramids (VTK types 10 to 14) \
                 make a 3D mesh"
                    .into()
            })
        }
    }
    Ok(())
}

/// Writes a triangle (2D) or tetrahedron (3D) mesh as a VTK XML UnstructuredGrid (`.vtu`),
/// with cell types `VTK_TRIANGLE` / `VTK_TETRA`. Atomic.
///
/// `point_data` and `cell_data` are named scalar fields with one value per point / per cell
/// (any `f64`, NaN included); the first of each kind is marked as the active scalars. The
/// neighbour array of `mesh`, if any, is not written.
pub fn write_vtu(
    path: &Path,
    mesh: &SimplexMesh<'_>,
    point_data: &[(&str, &[f64])],
    cell_data: &[(&str, &[f64])],
) -> Result<(), IoError> {
    mesh.check(path)?;
    let n_points = mesh.n_points();
    let n_cells = mesh.n_cells();
    let nv = mesh.dim + 1;
    let point_attrs = fields(path, "point", point_data, n_points)?;
    let cell_attrs = fields(path, "cell", cell_data, n_cells)?;

    let cell_type = if mesh.dim == 2 {
        CellType::Triangle
    } else {
        CellType::Tetra
    };
    let cells = Cells {
        cell_verts: VertexNumbers::XML {
            connectivity: mesh.cells.iter().map(|&v| u64::from(v)).collect(),
            offsets: (1..=n_cells).map(|c| (c * nv) as u64).collect(),
        },
        types: vec![cell_type; n_cells],
    };
    let piece = UnstructuredGridPiece {
        points: IOBuffer::F64(points3(mesh.dim, mesh.coords)),
        cells,
        data: Attributes {
            point: point_attrs,
            cell: cell_attrs,
        },
    };
    export(path, piece)
}

/// Writes polygons as a VTK XML UnstructuredGrid (`.vtu`) of `VTK_POLYGON` cells: 2D Voronoi
/// cells, or the faces of 3D Voronoi cells. Atomic.
///
/// `coords` holds `dim` (2 or 3) coordinates per point. The polygons are flat, as VTK stores
/// them: polygon `k` is `corners[ends[k - 1]..ends[k]]` (from 0 for the first), at least 3
/// 0-based point indices in order around it; polygons may share points. `cell_data` holds
/// named scalar fields with one value per polygon (for 3D Voronoi faces, e.g. the id of the
/// cell each face belongs to).
pub fn write_vtu_polygons(
    path: &Path,
    dim: usize,
    coords: &[f64],
    ends: &[usize],
    corners: &[u32],
    cell_data: &[(&str, &[f64])],
) -> Result<(), IoError> {
    check_points(path, dim, coords)?;
    let n_points = coords.len() / dim;
    let mut start = 0;
    for (i, &end) in ends.iter().enumerate() {
        if end > corners.len() || end < start + 3 {
            return Err(IoError::invalid(
                path,
                format!(
                    "polygon {i} has {} vertices, at least 3 are needed",
                    end.min(corners.len()).saturating_sub(start)
                ),
            ));
        }
        if let Some(&v) = corners[start..end]
            .iter()
            .find(|&&v| v as usize >= n_points)
        {
            return Err(IoError::invalid(
                path,
                format!("polygon {i} refers to point {v} but there are only {n_points} points"),
            ));
        }
        start = end;
    }
    if start != corners.len() {
        return Err(IoError::invalid(
            path,
            format!(
                "{} corners follow the last polygon's end",
                corners.len() - start
            ),
        ));
    }
    let cell_attrs = fields(path, "cell", cell_data, ends.len())?;
    let connectivity = corners.iter().map(|&v| u64::from(v)).collect();
    let offsets = ends.iter().map(|&e| e as u64).collect();
    let piece = UnstructuredGridPiece {
        points: IOBuffer::F64(points3(dim, coords)),
        cells: Cells {
            cell_verts: VertexNumbers::XML {
                connectivity,
                offsets,
            },
            types: vec![CellType::Polygon; ends.len()],
        },
        data: Attributes {
            point: Vec::new(),
            cell: cell_attrs,
        },
    };
    export(path, piece)
}

/// Writes a tetrahedral mesh as two `.vtu` files: `X.vtu` with the tetrahedra (cell field
/// `region` if the mesh has regions, point field `marker` if it has point markers) and
/// `X.boundary.vtu` with the boundary triangles (`VTK_TRIANGLE`, cell field `marker`) on the
/// same points, so ParaView can show the surface patches by marker over the volume. `X` is
/// `path` without a `.vtu` extension. Markers are `Int32`, regions `Float64`. Returns the two
/// paths. Everything is checked before the first file is written; each file is atomic.
pub fn write_tet_mesh_vtu(path: &Path, mesh: &TetMeshOut<'_>) -> Result<Vec<PathBuf>, IoError> {
    write_tet_mesh_vtu_with(path, mesh, &[], &[])
}

/// [`write_tet_mesh_vtu`] with extra scalar fields: `point_data` on the points of both files,
/// `cell_data` (one value per tetrahedron) on the tetrahedra.
///
/// # Errors
/// As [`write_tet_mesh_vtu`], or a field of the wrong length or with a non-finite value.
pub fn write_tet_mesh_vtu_with(
    path: &Path,
    mesh: &TetMeshOut<'_>,
    point_data: &[(&str, &[f64])],
    cell_data: &[(&str, &[f64])],
) -> Result<Vec<PathBuf>, IoError> {
    mesh.check(path)?;
    let volume = sibling(path, &["vtu"], "vtu");
    let boundary = sibling(path, &["vtu"], "boundary.vtu");
    let points: Vec<f64> = mesh.coords.iter().flatten().copied().collect();
    let mut point_attrs: Vec<Attribute> = mesh
        .point_markers
        .map(|m| int_field("marker", m))
        .into_iter()
        .collect();
    point_attrs.extend(fields(path, "point", point_data, mesh.coords.len())?);
    let mut cell_attrs = match mesh.regions {
        Some(r) => fields(path, "cell", &[("region", r)], mesh.tets.len())?,
        None => Vec::new(),
    };
    cell_attrs.extend(fields(path, "cell", cell_data, mesh.tets.len())?);
    let piece = UnstructuredGridPiece {
        points: IOBuffer::F64(points.clone()),
        cells: fixed_cells(mesh.tets.iter().flatten(), 4, CellType::Tetra),
        data: Attributes {
            point: point_attrs.clone(),
            cell: cell_attrs,
        },
    };
    let boundary_piece = UnstructuredGridPiece {
        points: IOBuffer::F64(points),
        cells: fixed_cells(mesh.faces.iter().flatten(), 3, CellType::Triangle),
        data: Attributes {
            point: point_attrs,
            cell: vec![int_field("marker", mesh.face_markers)],
        },
    };
    // The two files are replaced together or not at all.
    transaction(|| {
        export(&volume, piece)?;
        export(&boundary, boundary_piece)
    })?;
    Ok(vec![volume, boundary])
}

/// The declarations of the cells' index arrays as vtkio writes them, and as VTK does.
const SIGNED_INDICES: [(&str, &str); 2] = [
    (
        r#"type="UInt64" Name="connectivity""#,
        r#"type="Int64" Name="connectivity""#,
    ),
    (
        r#"type="UInt64" Name="offsets""#,
        r#"type="Int64" Name="offsets""#,
    ),
];

/// What vtkio writes, fixed on the way to the file:
/// - the cells' `connectivity` and `offsets` are declared `Int64`, VTK's own index type, not
///   vtkio's `UInt64`: ParaView reads both, but meshio (NumPy, which mixes unsigned and signed
///   integers as floats) turned the cells of a `UInt64` file into floats and failed on
///   polygons. The values, all below 2^63, are the same bytes either way;
/// - the first I/O error is kept: vtkio reports a failed write (a full disk) as an XML
///   "deserialization error".
///
/// Until both declarations have gone by, the last bytes written are held back in case one
/// is split between two writes; after them everything passes straight through.
struct Fixups<'a> {
    inner: &'a mut dyn std::io::Write,
    held: Vec<u8>,
    /// Which declarations have gone by.
    fixed: [bool; 2],
    error: Option<std::io::Error>,
}

impl<'a> Fixups<'a> {
    fn new(inner: &'a mut dyn std::io::Write) -> Self {
        Fixups {
            inner,
            held: Vec::new(),
            fixed: [false; 2],
            error: None,
        }
    }

    /// Writes what is still held (at the end).
    fn finish(&mut self) -> std::io::Result<()> {
        let held = std::mem::take(&mut self.held);
        let done = self.inner.write_all(&held);
        self.keep(done)
    }

    fn keep<T>(&mut self, done: std::io::Result<T>) -> std::io::Result<T> {
        done.map_err(|e| {
            let copy = std::io::Error::new(e.kind(), e.to_string());
            self.error.get_or_insert(e);
            copy
        })
    }

    fn pass(&mut self, buf: &[u8]) -> std::io::Result<()> {
        if self.fixed == [true; 2] {
            self.finish()?;
            let done = self.inner.write_all(buf);
            return self.keep(done);
        }
        self.held.extend_from_slice(buf);
        for (k, (unsigned, signed)) in SIGNED_INDICES.iter().enumerate() {
            let (unsigned, signed) = (unsigned.as_bytes(), signed.as_bytes());
            if self.fixed[k] {
                continue;
            }
            if let Some(at) = self
                .held
                .windows(unsigned.len())
                .position(|w| w == unsigned)
            {
                self.held
                    .splice(at..at + unsigned.len(), signed.iter().copied());
                self.fixed[k] = true;
            }
        }
        // A declaration split between this write and the next starts in the last bytes.
        let keep = if self.fixed == [true; 2] {
            0
        } else {
            SIGNED_INDICES[0].0.len()
        };
        let out = self.held.len().saturating_sub(keep);
        let done = self.inner.write_all(&self.held[..out]);
        self.keep(done)?;
        self.held.drain(..out);
        Ok(())
    }
}

impl std::io::Write for Fixups<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.pass(buf).map(|()| buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        // (What is held waits for `finish`: flushing it could split a declaration.)
        let done = self.inner.flush();
        self.keep(done)
    }
}

/// Cells of `nv` vertices each, all of one type.
fn fixed_cells<'a>(vertices: impl Iterator<Item = &'a u32>, nv: usize, ty: CellType) -> Cells {
    let connectivity: Vec<u64> = vertices.map(|&v| u64::from(v)).collect();
    let n = connectivity.len() / nv;
    Cells {
        cell_verts: VertexNumbers::XML {
            connectivity,
            offsets: (1..=n).map(|c| (c * nv) as u64).collect(),
        },
        types: vec![ty; n],
    }
}

/// An `Int32` scalar field (markers).
fn int_field(name: &str, values: &[i32]) -> Attribute {
    Attribute::DataArray(DataArray {
        name: name.to_string(),
        elem: ElementType::Scalars {
            num_comp: 1,
            lookup_table: None,
        },
        data: IOBuffer::I32(values.to_vec()),
    })
}

/// Pads 2D coordinates with `z = 0`; copies 3D ones.
fn points3(dim: usize, coords: &[f64]) -> Vec<f64> {
    if dim == 3 {
        return coords.to_vec();
    }
    let mut out = Vec::with_capacity(coords.len() / 2 * 3);
    for p in coords.chunks_exact(2) {
        out.extend_from_slice(&[p[0], p[1], 0.0]);
    }
    out
}

/// Turns named scalar fields into VTK attributes, checking there is one value per `kind`.
fn fields(
    path: &Path,
    kind: &str,
    data: &[(&str, &[f64])],
    expected: usize,
) -> Result<Vec<Attribute>, IoError> {
    let mut out = Vec::with_capacity(data.len());
    for (i, &(name, values)) in data.iter().enumerate() {
        if values.len() != expected {
            return Err(IoError::invalid(
                path,
                format!(
                    "{kind} field '{name}' has {} values, expected one per {kind} ({expected})",
                    values.len()
                ),
            ));
        }
        if data[..i].iter().any(|&(other, _)| other == name) {
            return Err(IoError::invalid(
                path,
                format!("{kind} field name '{name}' is used twice"),
            ));
        }
        out.push(Attribute::DataArray(DataArray {
            name: name.to_string(),
            elem: ElementType::Scalars {
                num_comp: 1,
                lookup_table: None,
            },
            data: IOBuffer::F64(values.to_vec()),
        }));
    }
    Ok(out)
}

/// Serialises one inline piece as a `.vtu` file at `path`, atomically.
fn export(path: &Path, piece: UnstructuredGridPiece) -> Result<(), IoError> {
    let empty = piece.cells.types.is_empty();
    let vtk = Vtk {
        version: Version::new((1, 0)),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::UnstructuredGrid {
            meta: None,
            pieces: vec![Piece::Inline(Box::new(piece))],
        },
    };
    let vtk_error = |e| match e {
        vtkio::Error::IO(source) => IoError::io(path, source),
        other => IoError::Vtk {
            file: path.to_path_buf(),
            message: other.to_string(),
        },
    };
    if !empty {
        return write_atomic(path, |w| {
            let mut out = Fixups::new(w);
            let done = vtk.write_xml(&mut out).map(|()| out.finish());
            match out.error {
                Some(e) => Err(IoError::io(path, e)),
                None => done.map_err(vtk_error)?.map_err(|e| IoError::io(path, e)),
            }
        });
    }
    // vtkio leaves `NumberOfCells` out of a piece without cells, which VTK (ParaView) and
    // delmesh's own reader refuse: it is put back (the 3D Voronoi faces of a set with no
    // bounded region).
    let mut xml = Vec::new();
    vtk.write_xml(&mut xml).map_err(vtk_error)?;
    let mut xml = String::from_utf8_lossy(&xml).into_owned();
    for (unsigned, signed) in SIGNED_INDICES {
        xml = xml.replacen(unsigned, signed, 1);
    }
    if !xml.contains("NumberOfCells=") {
        xml = xml.replacen("<Piece ", "<Piece NumberOfCells=\"0\" ", 1);
    }
    write_atomic(path, |w| {
        w.write_all(xml.as_bytes())
            .map_err(|e| IoError::io(path, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A device that takes `room` bytes, then is full.
    struct Full {
        room: usize,
    }

    impl std::io::Write for Full {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.room == 0 {
                return Err(std::io::ErrorKind::StorageFull.into());
            }
            let n = buf.len().min(self.room);
            self.room -= n;
            Ok(n)
        }

        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_full_disk_is_kept_as_the_io_error() {
        let mut device = Full { room: 100 };
        let mut out = Fixups::new(&mut device);
        use std::io::Write;
        assert!(out.write_all(&[b'x'; 150]).is_err());
        assert!(out.write_all(b"more").is_err());
        let kept = out.error.expect("the first error");
        assert_eq!(kept.kind(), std::io::ErrorKind::StorageFull);
    }

    #[test]
    fn index_arrays_are_declared_signed_however_the_writes_are_cut() {
        let xml = concat!(
            r#"<Points><DataArray type="UInt64" Name="ids">AAAA</DataArray></Points>"#,
            r#"<Cells><DataArray type="UInt64" Name="connectivity" format="binary">QUInt64"#,
            r#"type="UInt64" Name="connectivity""#,
            r#"</DataArray><DataArray type="UInt64" Name="offsets" format="binary">"#,
            r#"type="UInt64" Name="connectivity"</DataArray></Cells>"#
        );
        let expected = xml
            .replacen(
                r#"type="UInt64" Name="connectivity""#,
                r#"type="Int64" Name="connectivity""#,
                1,
            )
            .replacen(
                r#"type="UInt64" Name="offsets""#,
                r#"type="Int64" Name="offsets""#,
                1,
            );
        for cut in [1, 2, 3, 7, 13, 50, 1000] {
            let mut file = Vec::new();
            let mut out = Fixups::new(&mut file);
            for piece in xml.as_bytes().chunks(cut) {
                std::io::Write::write_all(&mut out, piece).unwrap();
            }
            out.finish().unwrap();
            assert_eq!(String::from_utf8(file).unwrap(), expected, "cut {cut}");
        }
    }
}
