//! `delmesh delaunay`: the Delaunay triangulation of a point file, and its outputs.
//!
//! The CLI, the demos and the end-to-end tests all go through this module, so what the tool
//! does and what is tested are the same code: [`triangulate_file`] reads the points, builds a
//! 2D or 3D triangulation by the file's dimension (timing the construction alone, which is the
//! number compared against TetGen and CGAL), and returns a [`DelaunayRun`] that writes the
//! mesh ([`DelaunayRun::write`]) and the Voronoi cells ([`DelaunayRun::write_voronoi`]).
//!
//! Output numbering follows the input file: `.vtu` files list every input point in file order
//! (duplicates included, so point `k` of the `.vtu` is line `k` of the input), and the TetGen
//! family (`.node`, `.ele`, `.neigh`) counts from the input's first index, as TetGen does.

use std::path::{Path, PathBuf};
use std::time::Instant;

use delmesh_delaunay_core::{Dim, Triangulation, Triangulation2, Triangulation3};
use delmesh_io::{PointSet, SimplexMesh};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::Error;
use rustc_hash::FxHashMap as HashMap;

/// Inputs with more points than this get a progress bar (when progress is asked for).
pub const PROGRESS_THRESHOLD: usize = 200_000;

/// The extensions [`DelaunayRun::write`] accepts, for messages.
const MESH_FORMATS: &str = ".vtu, .ele";
/// The extensions [`DelaunayRun::write_voronoi`] accepts, for messages.
const VORONOI_FORMATS: &str = ".vtu";

/// How far the box that clips 2D Voronoi cells extends beyond the points' bounding box, as a
/// fraction of its size, on each side.
const VORONOI_MARGIN: f64 = 0.1;

/// A mesh output format, chosen by the output path's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// `.vtu`: VTK XML unstructured grid, for ParaView / VisIt.
    Vtu,
    /// `.ele`: the TetGen / Triangle family `X.node`, `X.ele`, `X.neigh`.
    TetGen,
}

impl OutputFormat {
    /// The format [`DelaunayRun::write`] uses for `out` (extension compared case-insensitively).
    ///
    /// # Errors
    /// [`Error::UnsupportedFormat`] for any other extension, naming it and the supported ones.
    pub fn from_path(out: &Path) -> Result<Self, Error> {
        match extension(out).as_deref() {
            Some("vtu") => Ok(OutputFormat::Vtu),
            Some("ele") => Ok(OutputFormat::TetGen),
            _ => Err(unsupported(out, MESH_FORMATS)),
        }
    }

    /// The files [`DelaunayRun::write`] writes for `out` in this format, in order.
    pub fn files(self, out: &Path) -> Vec<PathBuf> {
        match self {
            OutputFormat::Vtu => vec![out.to_path_buf()],
            OutputFormat::TetGen => ["node", "ele", "neigh"]
                .iter()
                .map(|ext| out.with_extension(ext))
                .collect(),
        }
    }

    /// Checks that `out` is a path [`DelaunayRun::write_voronoi`] can write (`.vtu`).
    ///
    /// # Errors
    /// [`Error::UnsupportedFormat`] for any other extension.
    pub fn check_voronoi_path(out: &Path) -> Result<(), Error> {
        match extension(out).as_deref() {
            Some("vtu") => Ok(()),
            _ => Err(unsupported(out, VORONOI_FORMATS)),
        }
    }
}

/// Checks that the folder `out` is to be written in exists, so that a long run does not fail
/// only when it comes to writing its result.
///
/// # Errors
/// [`Error::Io`] naming `out` if its parent folder is missing or not a folder, or if `out`
/// names a polyMesh folder that is a file.
pub fn check_output_dir(out: &Path) -> Result<(), Error> {
    // An OpenFOAM polyMesh output is itself a folder, made if missing.
    if delmesh_io::is_polymesh(out) && out.exists() && !out.is_dir() {
        return Err(Error::Io(delmesh_io::IoError::InvalidInput {
            file: out.to_path_buf(),
            message: "an OpenFOAM mesh is written into a folder named polyMesh, and this is a file"
                .into(),
        }));
    }
    let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) else {
        return Ok(()); // the current folder
    };
    if parent.is_dir() {
        return Ok(());
    }
    Err(Error::Io(delmesh_io::IoError::Io {
        file: out.to_path_buf(),
        source: std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!("folder '{}' does not exist", parent.display()),
        ),
    }))
}

/// Checks that none of the files `outputs` a run will write is a folder: outputs are written
/// one after another, so one that fails last would leave the others replaced by a run that
/// then exits with an error.
///
/// # Errors
/// [`Error::Io`] naming the first output that is a folder.
pub fn check_not_folders(outputs: &[PathBuf]) -> Result<(), Error> {
    match outputs.iter().find(|f| f.is_dir()) {
        Some(f) => Err(Error::Io(delmesh_io::IoError::InvalidInput {
            file: f.clone(),
            message: "this output is a folder; delmesh writes a file there".into(),
        })),
        None => Ok(()),
    }
}

/// Checks that none of `outputs` is the file `input` (which a TetGen-family output beside its
/// `.node` input would silently replace).
///
/// # Errors
/// [`Error::OverwritesInput`] naming the output that is the input.
pub fn check_not_input(input: &Path, outputs: &[PathBuf]) -> Result<(), Error> {
    let Ok(input_real) = input.canonicalize() else {
        return Ok(()); // no such input file: nothing to protect
    };
    for out in outputs {
        if out.canonicalize().is_ok_and(|o| o == input_real) {
            return Err(Error::OverwritesInput {
                input: input.to_path_buf(),
                output: out.clone(),
            });
        }
    }
    Ok(())
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

fn unsupported(out: &Path, supported: &'static str) -> Error {
    let ext = match out.extension() {
        Some(e) => format!(".{}", e.to_string_lossy()),
        None => "(none)".to_string(),
    };
    Error::UnsupportedFormat {
        file: out.to_path_buf(),
        ext,
        supported,
    }
}

/// A 2D or 3D Delaunay triangulation: which one is decided by the input file.
#[derive(Clone, Debug)]
pub enum DelaunayMesh {
    /// Triangles.
    D2(Triangulation2),
    /// Tetrahedra.
    D3(Triangulation3),
}

/// Runs `$body` with `$t` bound to the triangulation, whatever its dimension.
macro_rules! with_tri {
    ($mesh:expr, $t:ident => $body:expr) => {
        match $mesh {
            DelaunayMesh::D2($t) => $body,
            DelaunayMesh::D3($t) => $body,
        }
    };
}

/// The result of triangulating a point file: the triangulation, where its points came from and
/// how long the construction took.
#[derive(Clone, Debug)]
pub struct DelaunayRun {
    /// The triangulation.
    pub mesh: DelaunayMesh,
    /// The index of the input's first point (`.node` files: 0 or 1; other formats: 0). Output
    /// files and messages number points from it.
    pub first_index: u32,
    /// The input file (or, for generated points, the name they go by in messages).
    pub input: PathBuf,
    /// Wall-clock seconds spent building the triangulation (reading and writing excluded).
    pub build_seconds: f64,
    /// The input points' attributes (per attribute, one value per input point), carried to
    /// the outputs.
    pub attributes: Vec<Vec<f64>>,
    /// The input points' boundary markers, if the input has them, carried to the outputs.
    pub markers: Option<Vec<i32>>,
}

/// Reads the points of `input` ([`delmesh_io::read_points`]: `.node` or plain `x y [z]` text)
/// and builds their Delaunay triangulation, 2D or 3D by the file's dimension.
///
/// With `progress`, inputs of more than [`PROGRESS_THRESHOLD`] points show a progress bar on
/// stderr (only when stderr is a terminal).
///
/// # Errors
/// A missing or malformed file ([`Error::Io`], with the line), or points that admit no
/// triangulation ([`Error::Triangulation`]: too few, all collinear or coplanar, ...).
pub fn triangulate_file(input: &Path, progress: bool) -> Result<DelaunayRun, Error> {
    let points = delmesh_io::read_points(input)?;
    DelaunayRun::from_points(&points, input, progress)
}

impl DelaunayRun {
    /// Builds the triangulation of `points`; `input` names them in messages and in
    /// [`DelaunayRun::input`]. See [`triangulate_file`].
    ///
    /// # Errors
    /// [`Error::Dimension`] unless `points.dim` is 2 or 3; [`Error::Triangulation`] if the points
    /// admit no triangulation.
    pub fn from_points(points: &PointSet, input: &Path, progress: bool) -> Result<Self, Error> {
        let progress = progress && points.len() > PROGRESS_THRESHOLD;
        let err = |e| Error::triangulation(input, e, points.first_index);
        let (mesh, build_seconds) = match points.dim {
            2 => {
                let pts: Vec<[f64; 2]> = points
                    .coords
                    .chunks_exact(2)
                    .map(|p| [p[0], p[1]])
                    .collect();
                let (t, s) = build(&pts, progress).map_err(err)?;
                (DelaunayMesh::D2(t), s)
            }
            3 => {
                let pts: Vec<[f64; 3]> = points
                    .coords
                    .chunks_exact(3)
                    .map(|p| [p[0], p[1], p[2]])
                    .collect();
                let (t, s) = build(&pts, progress).map_err(err)?;
                (DelaunayMesh::D3(t), s)
            }
            dim => {
                return Err(Error::Dimension {
                    file: input.to_path_buf(),
                    dim,
                })
            }
        };
        Ok(DelaunayRun {
            mesh,
            first_index: points.first_index,
            input: input.to_path_buf(),
            build_seconds,
            attributes: points.attributes.clone(),
            markers: points.markers.clone(),
        })
    }

    /// Space dimension: 2 or 3.
    pub fn dim(&self) -> usize {
        match self.mesh {
            DelaunayMesh::D2(_) => 2,
            DelaunayMesh::D3(_) => 3,
        }
    }

    /// Number of input points, duplicates included.
    pub fn num_input_points(&self) -> usize {
        with_tri!(&self.mesh, t => t.num_input_points())
    }

    /// Number of vertices (distinct points).
    pub fn num_vertices(&self) -> usize {
        with_tri!(&self.mesh, t => t.num_vertices())
    }

    /// Number of cells: triangles (2D) or tetrahedra (3D).
    pub fn num_cells(&self) -> usize {
        with_tri!(&self.mesh, t => t.num_cells())
    }

    /// Number of convex-hull facets: edges (2D) or triangles (3D).
    pub fn num_hull_facets(&self) -> usize {
        with_tri!(&self.mesh, t => t.num_hull_facets())
    }

    /// Input points that repeat an earlier one, as `(duplicate, original)` pairs numbered from
    /// [`DelaunayRun::first_index`] (the file's numbering), sorted.
    pub fn duplicates(&self) -> Vec<(usize, usize)> {
        let shift = self.first_index as usize;
        with_tri!(&self.mesh, t => t.duplicates())
            .iter()
            .map(|&(d, o)| (d + shift, o + shift))
            .collect()
    }

    /// Coordinates of all input points in input order, flat (`dim` per point), duplicates
    /// included (they repeat their original's coordinates, which are equal).
    pub fn input_coords(&self) -> Vec<f64> {
        with_tri!(&self.mesh, t => input_coords(t))
    }

    /// Writes the mesh to `out`, the format chosen by its extension ([`OutputFormat`]):
    ///
    /// - `.vtu`: all input points in input order and the cells (triangles or tetrahedra)
    ///   indexing them; the input's point attributes as point fields `attribute_1`, ... and its
    ///   boundary markers as `marker`;
    /// - `.ele`: `X.node` (all input points, with their attributes and markers), `X.ele` and
    ///   `X.neigh` beside it, numbered from the input's first index as TetGen does.
    ///
    /// Returns the files written. Each file is replaced atomically.
    ///
    /// # Errors
    /// [`Error::UnsupportedFormat`] for another extension, or [`Error::OverwritesInput`] if an
    /// output file is the input file (nothing is written in either case); [`Error::Io`] if a
    /// file cannot be written.
    pub fn write(&self, out: &Path) -> Result<Vec<PathBuf>, Error> {
        let format = OutputFormat::from_path(out)?;
        check_not_input(&self.input, &format.files(out))?;
        let coords = self.input_coords();
        let (cells, neighbors) = with_tri!(&self.mesh, t => {
            let neighbors = match format {
                OutputFormat::TetGen => Some(t.neighbors_in_cell_order()),
                OutputFormat::Vtu => None,
            };
            (t.cells_in_input_numbering(), neighbors)
        });
        let mesh = SimplexMesh {
            dim: self.dim(),
            coords: &coords,
            cells: &cells,
            neighbors: neighbors.as_deref(),
        };
        match format {
            OutputFormat::Vtu => {
                // The input's attributes and markers as point fields.
                let names: Vec<String> = (1..=self.attributes.len())
                    .map(|k| format!("attribute_{k}"))
                    .collect();
                let markers: Option<Vec<f64>> = self
                    .markers
                    .as_ref()
                    .map(|m| m.iter().map(|&x| f64::from(x)).collect());
                let mut fields: Vec<(&str, &[f64])> = names
                    .iter()
                    .map(String::as_str)
                    .zip(self.attributes.iter().map(Vec::as_slice))
                    .collect();
                if let Some(m) = &markers {
                    fields.push(("marker", m));
                }
                delmesh_io::write_vtu(out, &mesh, &fields, &[])?;
                Ok(vec![out.to_path_buf()])
            }
            OutputFormat::TetGen => Ok(delmesh_io::write_tetgen_family_with(
                &out.with_extension("ele"),
                &mesh,
                self.first_index,
                &delmesh_io::NodeData {
                    attributes: &self.attributes,
                    markers: self.markers.as_deref(),
                },
            )?),
        }
    }

    /// Writes the Voronoi diagram to `out` (`.vtu`) as polygons, and returns how many.
    ///
    /// - 2D: one polygon per distinct input point, its Voronoi cell clipped to the points'
    ///   bounding box enlarged by 10% on each side; cell data `point` is the point's index in
    ///   the input file's numbering (duplicates share their original's cell).
    /// - 3D: one polygon per face of each bounded Voronoi cell (points strictly inside the
    ///   convex hull; no face without area, as co-spherical points make); cell data `point` is
    ///   the point whose cell the face bounds and `neighbor` the point on the other side, both
    ///   in the input file's numbering. An interior face is thus written twice, once per side.
    ///
    /// Polygon corners (circumcentres, or clipping points) are the file's points, no polygon
    /// listing one twice, each circumcentre once, shared by the regions (2D) or faces (3D) it
    /// bounds.
    ///
    /// # Errors
    /// [`Error::UnsupportedFormat`] unless `out` ends in `.vtu`, or [`Error::Io`].
    pub fn write_voronoi(&self, out: &Path) -> Result<usize, Error> {
        OutputFormat::check_voronoi_path(out)?;
        check_not_input(&self.input, &[out.to_path_buf()])?;
        let shift = f64::from(self.first_index);
        let (mut coords, mut ends, mut corners) = (Vec::new(), Vec::new(), Vec::new());
        let mut point_ids = Vec::new();
        let mut neighbor_ids = Vec::new();
        match &self.mesh {
            DelaunayMesh::D2(t) => {
                let (lo, hi) = voronoi_box(t);
                // Corners equal to the bit are one point: regions share their circumcentres
                // (the kernel computes each from the same triangle for every region), and
                // clipping points where two regions' computations agree.
                let mut point_of: HashMap<[u64; 2], u32> = HashMap::default();
                let mut keys = Vec::new();
                for cell in t.voronoi_cells(lo, hi) {
                    // (+ 0.0 makes −0.0 the same point as 0.0.)
                    keys.clear();
                    keys.extend(cell.polygon.iter().map(|p| p.map(|x| (x + 0.0).to_bits())));
                    keys.dedup();
                    if keys.len() > 1 && keys.first() == keys.last() {
                        keys.pop();
                    }
                    if keys.len() < 3 {
                        continue;
                    }
                    for key in &keys {
                        let next = u32::try_from(coords.len() / 2).unwrap_or(u32::MAX);
                        let k = *point_of.entry(*key).or_insert_with(|| {
                            coords.extend(key.map(f64::from_bits));
                            next
                        });
                        corners.push(k);
                    }
                    ends.push(corners.len());
                    point_ids.push(cell.point as f64 + shift);
                }
            }
            DelaunayMesh::D3(t) => {
                // Polygons of at least 3 distinct corners: faces without area (the duals of
                // diagonals through co-spherical points) are left out by the kernel.
                let faces = t.voronoi_faces_shared();
                coords = faces.vertices.iter().flatten().copied().collect();
                point_ids = faces.sides.iter().map(|s| s[0] as f64 + shift).collect();
                neighbor_ids = faces.sides.iter().map(|s| s[1] as f64 + shift).collect();
                (ends, corners) = (faces.ends, faces.corners);
            }
        }
        let mut cell_data: Vec<(&str, &[f64])> = vec![("point", &point_ids)];
        if self.dim() == 3 {
            cell_data.push(("neighbor", &neighbor_ids));
        }
        delmesh_io::write_vtu_polygons(out, self.dim(), &coords, &ends, &corners, &cell_data)?;
        Ok(ends.len())
    }

    /// The kernel's exact validation: neighbour symmetry, orientation, the empty-circumsphere
    /// property with the symbolic perturbation, incidence and Euler's relation.
    ///
    /// # Errors
    /// The first broken invariant (a bug in delmesh).
    pub fn validate(&self) -> Result<(), delmesh_delaunay_core::ValidationError> {
        with_tri!(&self.mesh, t => t.validate())
    }

    /// The paper's Table 1 for this triangulation: one row per Voronoi vertex with its forming
    /// points (numbered from [`DelaunayRun::first_index`]) and neighbouring Voronoi vertices.
    pub fn voronoi_table(&self) -> String {
        with_tri!(&self.mesh, t => {
            delmesh_delaunay_core::VoronoiDiagram::new(t).table(self.first_index)
        })
    }
}

/// Builds the triangulation of `points`, timing the construction alone; shows a progress bar
/// on stderr if `progress`.
fn build<D: Dim>(
    points: &[D::Point],
    progress: bool,
) -> Result<(Triangulation<D>, f64), delmesh_delaunay_core::TriangulationError> {
    let bar = progress.then(|| {
        let bar =
            ProgressBar::with_draw_target(Some(points.len() as u64), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "{prefix} [{elapsed_precise}] {wide_bar} {human_pos}/{human_len} points ({eta} left)",
        ) {
            bar.set_style(style);
        }
        bar.set_prefix(format!("{}D Delaunay", D::N));
        bar
    });
    let start = Instant::now();
    let result = Triangulation::<D>::with_progress(points, |done, _| {
        if let Some(bar) = &bar {
            bar.set_position(done as u64);
        }
    });
    let seconds = start.elapsed().as_secs_f64();
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    Ok((result?, seconds))
}

fn input_coords<D: Dim>(t: &Triangulation<D>) -> Vec<f64> {
    let mut coords = Vec::with_capacity(t.num_input_points() * D::N);
    for i in 0..t.num_input_points() {
        coords.extend_from_slice(t.vertex(t.vertex_of_input(i)).as_ref());
    }
    coords
}

/// The box clipping 2D Voronoi cells: the vertices' bounding box, enlarged by
/// [`VORONOI_MARGIN`] of its size on each side.
fn voronoi_box(t: &Triangulation2) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for v in 0..t.num_vertices() {
        let p = t.vertex(delmesh_delaunay_core::VertexId(v as u32));
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    for k in 0..2 {
        let margin = VORONOI_MARGIN * (hi[k] - lo[k]);
        lo[k] -= margin;
        hi[k] += margin;
    }
    (lo, hi)
}
