//! The paper's whole 2D pipeline: `delmesh mesh domain.poly -o mesh.vtu` as a library call.
//!
//! [`Plc2`] → boundary recovery and exterior deletion ([`BoundaryRecovery`]) → automatic points
//! ([`PointGeneration`] against a [`SpacingField`]) → Laplacian smoothing ([`Smoother`]) with
//! the Delaunay property restored by flips → quality report → output. One [`Mesh2`] value flows
//! through; every stage is timed ([`MeshRun2::timings`]).
//!
//! ```
//! use delmesh::mesh2d::{mesh_plc, MeshOptions2};
//! use delmesh::recovery::{Plc2, Segment};
//! let points = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
//! let segments = (0..4).map(|i| Segment { a: i, b: (i + 1) % 4, marker: 1 }).collect();
//! let plc = Plc2 { points, segments, ..Default::default() };
//! // Four boundary points 1 apart give a spacing of 1: α = 0.3 asks for points 0.3 apart.
//! let generation = Some(delmesh::point_gen::PointGeneration { alpha: 0.3, ..Default::default() });
//! let run = mesh_plc(&plc, &MeshOptions2 { generation, ..Default::default() })?;
//! assert!(run.arrays.triangles.len() > 2);
//! assert!((run.mesh.area() - 1.0).abs() < 1e-12);
//! # Ok::<(), delmesh::Error>(())
//! ```

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use delmesh_boundary_recovery::{
    BoundaryRecovery, Mesh2, MeshArrays, Plc2, RecoveryHistory, RecoveryMethod, RegionSeed,
    Segment, SegmentSplits,
};
use delmesh_delaunay_core::VertexId;
use delmesh_io::PolyFile;
use delmesh_point_gen::{
    Adaptation, AreaLimits, BackgroundMesh2, GenerationReport, PointGeneration, QualityRefinement,
    Source, SpacingError, SpacingField,
};
use delmesh_predicates::{orient2d, Sign};
use delmesh_smoothing::{QualityReport, SmoothStats, Smoother, Stars};
use rayon::prelude::*;

use crate::sources::check_sources2;
use crate::{units, Error};

/// Where the spacing of automatic point generation comes from.
#[derive(Clone, Debug, Default)]
pub enum Spacing {
    /// Interpolated from the boundary spacing (the paper's default, R10).
    #[default]
    Boundary,
    /// From a background mesh whose nodes carry spacing values (R11).
    Background(BackgroundMesh2),
}

/// Options of the 2D pipeline; `Default` is the paper's method with its usual parameters.
#[derive(Clone, Debug)]
pub struct MeshOptions2 {
    /// How missing boundary segments are recovered.
    pub recovery: RecoveryMethod,
    /// Extra points to triangulate with the boundary (R9); those outside the domain are dropped.
    pub extra_points: Vec<[f64; 2]>,
    /// Automatic point generation (`None`: the boundary and extra points only).
    pub generation: Option<PointGeneration>,
    /// Quality refinement after generation (`None`: none; needs generation).
    pub refinement: Option<QualityRefinement>,
    /// The spacing field's base.
    pub spacing: Spacing,
    /// Analytic sources refining the spacing.
    pub sources: Vec<Source>,
    /// Whether boundary edges longer than the spacing that sources or a background mesh ask
    /// for along them are split before point generation
    /// ([`SpacingField::boundary_splits`]; default true: generation cannot fill the domain
    /// next to an edge much longer than the spacing there, and thin triangles pile up along
    /// it: a unit square under a background spacing of 0.05 had a smallest angle of 4.5°).
    /// Off, the boundary is kept as given (a surface patch whose edges its neighbours share).
    /// The boundary's own spacing (the paper's default field) never splits it.
    pub split_boundary: bool,
    /// Laplacian smoothing (`None`: no smoothing).
    pub smoothing: Option<Smoother>,
    /// After smoothing, restore the (constrained) Delaunay property by edge flips.
    pub delaunay_flips: bool,
}

impl Default for MeshOptions2 {
    fn default() -> Self {
        MeshOptions2 {
            recovery: RecoveryMethod::Stitch,
            extra_points: Vec::new(),
            generation: Some(PointGeneration::default()),
            refinement: Some(QualityRefinement::default()),
            spacing: Spacing::Boundary,
            sources: Vec::new(),
            split_boundary: true,
            smoothing: Some(Smoother::new()),
            delaunay_flips: true,
        }
    }
}

/// The result of the 2D pipeline.
#[derive(Clone, Debug)]
pub struct MeshRun2 {
    /// The mesh (triangulation, boundary edges, regions, spacing).
    pub mesh: Mesh2,
    /// The mesh as flat arrays (what the writers take).
    pub arrays: MeshArrays,
    /// The recovery passes.
    pub recovery: RecoveryHistory,
    /// The point generation passes, if generation ran.
    pub generation: Option<GenerationReport>,
    /// What smoothing did, if it ran.
    pub smoothing: Option<SmoothStats>,
    /// Edge flips made after smoothing.
    pub flips: usize,
    /// Points added by quality refinement.
    pub refined: usize,
    /// Points added at the centroids of elements larger than their region's area limit
    /// ([`RegionSeed::max_area`]), before and after smoothing; `None` when no region has a
    /// limit or no points are generated.
    pub area_limited: Option<usize>,
    /// Elements still larger than their region's area limit at the end: generation's
    /// `max_points` ran out before they were split; 0 without limits.
    pub area_limit_exceeded: usize,
    /// Input points outside the background mesh (they took the spacing of its nearest
    /// point): a background for another domain, or in other units, is a likely mistake.
    pub outside_background: usize,
    /// Quality of the final mesh.
    pub quality: QualityReport,
    /// Seconds spent in each stage, in order.
    pub timings: Vec<(&'static str, f64)>,
}

/// Runs the pipeline on `plc`. A domain far from ordinary magnitudes is meshed scaled by a
/// power of two and handed back in its own units ([`crate::units`]): the same mesh, exactly,
/// as the scaled problem's.
///
/// # Errors
/// Invalid input (crossing segments, bad seeds, non-finite coordinates; named in the input's
/// numbering), coordinates beyond double precision's range ([`Error::OutOfRange`]), a domain
/// with no element, or a bad option.
pub fn mesh_plc(plc: &Plc2, options: &MeshOptions2) -> Result<MeshRun2, Error> {
    units::check_range(&plc.points, plc.first_index)?;
    if options.generation.is_some() {
        check_sources2(&options.sources, &plc.points)?;
    }
    let e = units::normalising_exponent(&plc.points);
    if e == 0 {
        return mesh_plc_as_given(plc, options);
    }
    let (plc, options) = units::scale_problem2(plc, options, e);
    let mut run = mesh_plc_as_given(&plc, &options).map_err(|err| units::unscale_error(err, e))?;
    units::unscale_run2(&mut run, -e)?;
    Ok(run)
}

/// [`mesh_plc`] on the problem as it is (no rescaling).
fn mesh_plc_as_given(plc: &Plc2, options: &MeshOptions2) -> Result<MeshRun2, Error> {
    let mut timings = Vec::new();
    let mut clock = Instant::now();
    let mut lap = |name: &'static str, timings: &mut Vec<(&'static str, f64)>| {
        timings.push((name, clock.elapsed().as_secs_f64()));
        clock = Instant::now();
    };
    // Regional area limits are honoured when points are generated: the boundary next to such
    // a region is split, generation's spacing capped there, and too large elements split.
    let limits = (options.generation.is_some() && plc.has_area_limits())
        .then(|| AreaLimits::new(plc.area_limits()));
    let mut recovery = BoundaryRecovery::new(options.recovery)
        .with_points(options.extra_points.clone())
        .with_area_limits(limits.is_some());
    let background = matches!(options.spacing, Spacing::Background(_));
    if options.generation.is_some()
        && (background || !options.sources.is_empty())
        && options.split_boundary
    {
        // The boundary is split where the field asks for finer spacing than its edges; not
        // where it would take more than 2^21 points (a background of 1e-300 or 1e-6 took 9 s
        // and 950 MB before generation refused it; a boundary that fine asks for more
        // elements inside than can be indexed unless the field grades very steeply):
        // generation then says the field is too fine.
        let field = spacing_field(options);
        // (A segment naming a missing point is recovery's error to report.)
        let point = |i: u32| plc.points.get(i as usize).copied();
        let asked: f64 = plc
            .segments
            .iter()
            .filter_map(|s| Some(field.spacings_along(point(s.a)?, point(s.b)?)))
            .sum();
        if asked <= MAX_BOUNDARY_SPLITS {
            recovery = recovery.with_segment_splits(SegmentSplits(Arc::new(move |a, b| {
                field.boundary_splits(a, b)
            })));
        }
    }
    let mut mesh = recovery.run(plc)?;
    lap("boundary recovery", &mut timings);
    let mut refined = 0;
    let mut area_limited = limits.as_ref().map(|_| 0);
    let generation = match &options.generation {
        Some(settings) => {
            let mut field = spacing_field(options);
            if limits.is_some() {
                field = field.with_area_limits(&plc.area_limits());
            }
            let report = settings.run(&mut mesh, &field)?;
            lap("point generation", &mut timings);
            if let Some(refinement) = &options.refinement {
                let budget = settings.max_points.saturating_sub(report.points_added());
                refined = refinement.run_capped(&mut mesh, budget)?;
                lap("quality refinement", &mut timings);
            }
            if let (Some(limits), Some(n)) = (&limits, &mut area_limited) {
                let budget = settings
                    .max_points
                    .saturating_sub(report.points_added() + refined);
                *n += limits.run(&mut mesh, budget)?;
                lap("area limits", &mut timings);
            }
            Some(report)
        }
        None => None,
    };
    let mut flips = 0;
    let smoothing = match &options.smoothing {
        Some(smoother) => {
            // Only what smoothing reads: the vertices and their stars, in the triangulation's
            // numbering.
            let tri = mesh.cdt.triangulation();
            let n = tri.num_vertices();
            let mut coords: Vec<[f64; 2]> = (0..n as u32)
                .into_par_iter()
                .map(|v| tri.vertex(VertexId(v)))
                .collect();
            let stars = Stars::build(n, mesh.smoothing_rings())
                .map_err(|e| Error::Internal(format!("the mesh's stars: {e}")))?;
            let stats = smoother.smooth_stars(&mut coords, &stars)?;
            // The smoother keeps every element positive, so the triangulation accepts the moves.
            mesh.cdt
                .move_all_vertices(&coords)
                .map_err(|e| Error::Internal(format!("smoothing moved a vertex badly: {e}")))?;
            lap("smoothing", &mut timings);
            if options.delaunay_flips {
                flips = mesh.cdt.make_delaunay();
                lap("delaunay flips", &mut timings);
            }
            // Moves change areas: the limits are checked again.
            if let (Some(limits), Some(n), Some(settings), Some(report)) =
                (&limits, &mut area_limited, &options.generation, &generation)
            {
                let budget = settings
                    .max_points
                    .saturating_sub(report.points_added() + refined + *n);
                *n += limits.run(&mut mesh, budget)?;
                lap("area limits after smoothing", &mut timings);
            }
            Some(stats)
        }
        None => None,
    };
    let area_limit_exceeded = limits.as_ref().map_or(0, |l| l.too_large(&mesh).len());
    let outside_background = match (&options.spacing, &options.generation) {
        (Spacing::Background(bg), Some(_)) => {
            plc.points.par_iter().filter(|&&p| !bg.covers(p)).count()
        }
        _ => 0,
    };
    let arrays = mesh.to_arrays();
    let quality = QualityReport::of_mesh(&arrays.coords, &arrays.triangles, &arrays.neighbours);
    lap("quality and output arrays", &mut timings);
    Ok(MeshRun2 {
        recovery: mesh.history.clone(),
        mesh,
        arrays,
        generation,
        smoothing,
        flips,
        refined,
        area_limited,
        area_limit_exceeded,
        outside_background,
        quality,
        timings,
    })
}

/// `spacing` (one per point) with each value that is not positive and finite (points no stage
/// gave one: 2D `--points` of a run without automatic points, 3D points the last recovery or
/// restoration added) replaced by the mean length of the point's `edges` (`length(u, v)`), so
/// that a `.vtu` output always carries the whole field and can serve as the next run's
/// background mesh. 2D and 3D alike.
pub(crate) fn fill_spacing(
    mut spacing: Vec<f64>,
    edges: impl Iterator<Item = (usize, usize)>,
    length: impl Fn(usize, usize) -> f64,
) -> Vec<f64> {
    let missing = |h: f64| !(h > 0.0 && h.is_finite());
    if !spacing.iter().any(|&h| missing(h)) {
        return spacing;
    }
    let mut sum = vec![0.0f64; spacing.len()];
    let mut count = vec![0u32; spacing.len()];
    for (u, v) in edges {
        if missing(spacing[u]) || missing(spacing[v]) {
            let d = length(u, v);
            for w in [u, v] {
                sum[w] += d;
                count[w] += 1;
            }
        }
    }
    for (k, h) in spacing.iter_mut().enumerate() {
        if missing(*h) && count[k] > 0 {
            *h = sum[k] / f64::from(count[k]);
        }
    }
    spacing
}

/// The most points splitting the boundary for a spacing field may add (see
/// [`MeshOptions2::split_boundary`]).
const MAX_BOUNDARY_SPLITS: f64 = (1u64 << 21) as f64;

/// The spacing field `options` ask for: the boundary's or a background mesh's, refined by the
/// sources.
fn spacing_field(options: &MeshOptions2) -> SpacingField {
    let field = match &options.spacing {
        Spacing::Boundary => SpacingField::boundary(),
        Spacing::Background(bg) => SpacingField::background(bg.clone()),
    };
    options.sources.iter().fold(field, |f, s| f.with_source(*s))
}

/// Reads a Triangle `.poly` file as a [`Plc2`].
///
/// # Errors
/// The file cannot be read or is malformed (file and line in the message).
pub fn read_plc(path: &Path) -> Result<Plc2, Error> {
    Ok(plc_from_poly(&delmesh_io::read_poly(path)?))
}

/// The [`Plc2`] of a parsed `.poly` file.
pub fn plc_from_poly(poly: &PolyFile) -> Plc2 {
    let n = poly.points.len();
    Plc2 {
        points: (0..n).map(|i| poly.points.point2(i)).collect(),
        point_markers: poly.points.markers.clone().unwrap_or_default(),
        segments: poly
            .segments
            .iter()
            .zip(&poly.segment_markers)
            .map(|(s, &marker)| Segment {
                a: s[0],
                b: s[1],
                marker,
            })
            .collect(),
        holes: poly.holes.clone(),
        regions: poly
            .regions
            .iter()
            .map(|r| RegionSeed {
                point: r.point,
                attribute: r.attribute,
                max_area: r.max_area,
            })
            .collect(),
        first_index: poly.first_index,
    }
}

/// The `.poly` contents of a [`Plc2`], numbered as it is (the inverse of [`plc_from_poly`]):
/// [`delmesh_io::write_poly`] writes a file that reads back as the same problem.
pub fn poly_from_plc(plc: &Plc2) -> PolyFile {
    PolyFile {
        points: delmesh_io::PointSet {
            dim: 2,
            coords: plc.points.iter().flatten().copied().collect(),
            first_index: plc.first_index,
            attributes: Vec::new(),
            markers: (!plc.point_markers.is_empty()).then(|| plc.point_markers.clone()),
        },
        segments: plc.segments.iter().map(|s| [s.a, s.b]).collect(),
        segment_markers: plc.segments.iter().map(|s| s.marker).collect(),
        holes: plc.holes.clone(),
        regions: plc
            .regions
            .iter()
            .map(|r| delmesh_io::PolyRegion {
                point: r.point,
                attribute: r.attribute,
                max_area: r.max_area,
            })
            .collect(),
        first_index: plc.first_index,
    }
}

/// The output formats of [`MeshRun2::write`], by extension.
pub const MESH_OUTPUTS: &str =
    ".vtu, .ele, .msh, .su2, .svg, or a directory named polyMesh (OpenFOAM)";

impl MeshRun2 {
    /// Writes the mesh to `out`, the format chosen by its extension: `.vtu` (cell data `region`,
    /// point data `marker` and `spacing`), `.ele` (the Triangle family `X.node`, `X.ele`,
    /// `X.edge` with boundary markers and region attributes, numbered from 1), `.msh` (gmsh 4.1:
    /// boundary edges and triangles in physical groups by marker and region), `.su2` (the SU2
    /// solver's mesh, the boundary edges under `MARKER_TAG= marker_<m>` per marker) or `.svg` (a
    /// picture); a path named `polyMesh` is an OpenFOAM mesh directory (one layer of prisms, the
    /// boundary edges in patches `marker_<m>`, see [`delmesh_io::write_foam_2d`]). Returns the
    /// files written.
    ///
    /// # Errors
    /// An unsupported extension, or a file that cannot be written.
    pub fn write(&self, out: &Path) -> Result<Vec<PathBuf>, Error> {
        let a = &self.arrays;
        let coords: Vec<f64> = a.coords.iter().flatten().copied().collect();
        let cells: Vec<u32> = a.triangles.iter().flatten().copied().collect();
        // What the Triangle family, gmsh, SU2 and OpenFOAM writers take (each writes what its
        // format holds).
        let mesh = delmesh_io::TriangleMeshOut {
            coords: &coords,
            triangles: &cells,
            point_markers: Some(&a.point_markers),
            cell_attributes: Some(&a.regions),
            edges: &a.edges,
            edge_markers: &a.edge_markers,
        };
        if delmesh_io::is_polymesh(out) {
            return Ok(delmesh_io::write_foam_2d(out, &mesh)?);
        }
        let ext = out
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        match ext.as_str() {
            "vtu" => {
                let simplices = delmesh_io::SimplexMesh {
                    dim: 2,
                    coords: &coords,
                    cells: &cells,
                    neighbors: None,
                };
                let markers: Vec<f64> = a.point_markers.iter().map(|&m| f64::from(m)).collect();
                let spacing: Vec<f64> = a
                    .vertex
                    .iter()
                    .map(|v| {
                        self.mesh
                            .spacing
                            .get(v.index())
                            .copied()
                            .unwrap_or(f64::NAN)
                    })
                    .collect();
                let edges = a
                    .triangles
                    .iter()
                    .flat_map(|t| (0..3).map(move |k| (t[k] as usize, t[(k + 1) % 3] as usize)));
                let spacing = fill_spacing(spacing, edges, |u, v| {
                    let (p, q) = (a.coords[u], a.coords[v]);
                    (p[0] - q[0]).hypot(p[1] - q[1])
                });
                let quality = min_angles(a);
                delmesh_io::write_vtu(
                    out,
                    &simplices,
                    &[("marker", &markers), ("spacing", &spacing)],
                    &[("region", &a.regions), ("min_angle", &quality)],
                )?;
                Ok(vec![out.to_path_buf()])
            }
            "ele" => Ok(delmesh_io::write_triangle_family(out, &mesh, 1)?),
            "msh" => {
                delmesh_io::write_msh_2d(out, &mesh)?;
                Ok(vec![out.to_path_buf()])
            }
            "su2" => {
                delmesh_io::write_su2_2d(out, &mesh)?;
                Ok(vec![out.to_path_buf()])
            }
            "svg" => {
                delmesh_io::write_svg(
                    out,
                    &delmesh_io::SvgMesh {
                        coords: &coords,
                        triangles: &cells,
                        segments: &a.edges,
                        segment_markers: &a.edge_markers,
                        cell_values: None,
                    },
                    &delmesh_io::SvgOptions::default(),
                )?;
                Ok(vec![out.to_path_buf()])
            }
            _ => Err(Error::UnsupportedFormat {
                file: out.to_path_buf(),
                ext: if ext.is_empty() {
                    "(none)".into()
                } else {
                    format!(".{ext}")
                },
                supported: MESH_OUTPUTS,
            }),
        }
    }

    /// The run's summary as text: recovery and generation passes, smoothing, quality, timings.
    pub fn summary(&self) -> String {
        let mut s = String::new();
        s.push_str(&format!(
            "boundary recovery ({:?}): {} points added\n{}",
            self.recovery.method,
            self.recovery.points_added(),
            self.recovery
        ));
        if let Some(g) = &self.generation {
            s.push_str(&format!(
                "point generation: {} points added\n{g}",
                g.points_added()
            ));
            s.push_str(&format!(
                "quality refinement: {} points added\n",
                self.refined
            ));
        }
        if let Some(n) = self.area_limited {
            s.push_str(&format!(
                "regional area limits: {n} points added at centroids\n"
            ));
            if self.area_limit_exceeded > 0 {
                s.push_str(&format!(
                    "warning: {} triangles are still larger than their region's limit (the \
                     --max-points budget ran out)\n",
                    self.area_limit_exceeded
                ));
            }
        }
        if self.outside_background > 0 {
            s.push_str(&format!(
                "warning: {} input points lie outside the background mesh (they take the \
                 spacing of its nearest point): is it a mesh of this domain, in the same \
                 units?\n",
                self.outside_background
            ));
        }
        if let Some(st) = &self.smoothing {
            s.push_str(&format!("smoothing: {st}\n"));
            s.push_str(&format!("delaunay flips after smoothing: {}\n", self.flips));
        }
        s.push_str(&format!(
            "mesh: {} points, {} triangles, {} boundary edges\n",
            self.arrays.coords.len(),
            self.arrays.triangles.len(),
            self.arrays.edges.len()
        ));
        s.push_str(&format!("{}", self.quality));
        let total: f64 = self.timings.iter().map(|t| t.1).sum();
        s.push_str("time per stage:\n");
        for (name, t) in &self.timings {
            s.push_str(&format!("  {name:<26} {t:.6} s\n"));
        }
        s.push_str(&format!("  {:<26} {total:.6} s\n", "total"));
        s
    }

    /// The run's report as JSON (`--report report.json`).
    pub fn report_json(&self) -> String {
        let passes = |v: Vec<String>| format!("[{}]", v.join(", "));
        let recovery = passes(
            self.recovery
                .passes
                .iter()
                .map(|p| {
                    format!(
                        "{{\"points\": {}, \"triangles\": {}, \"boundary_edges\": {}, \"missing\": {}, \"inserted\": {}}}",
                        p.points, p.triangles, p.boundary_edges, p.missing, p.inserted
                    )
                })
                .collect(),
        );
        let generation = self.generation.as_ref().map_or("null".to_string(), |g| {
            passes(
                g.passes
                    .iter()
                    .map(|p| {
                        format!(
                            "{{\"candidates\": {}, \"accepted\": {}, \"elements\": {}}}",
                            p.candidates, p.accepted, p.elements
                        )
                    })
                    .collect(),
            )
        });
        let timings = self
            .timings
            .iter()
            .map(|(n, t)| format!("\"{n}\": {t}"))
            .collect::<Vec<_>>()
            .join(", ");
        format!(
            "{{\n  \"points\": {},\n  \"triangles\": {},\n  \"boundary_edges\": {},\n  \"recovery\": {{\"method\": \"{:?}\", \"duplicates_merged\": {}, \"passes\": {recovery}}},\n  \"generation\": {generation},\n  \"flips_after_smoothing\": {},\n  \"area_limit_points\": {},\n  \"area_limit_exceeded\": {},\n  \"points_outside_background\": {},\n  \"quality\": {},\n  \"seconds\": {{{timings}}}\n}}\n",
            self.arrays.coords.len(),
            self.arrays.triangles.len(),
            self.arrays.edges.len(),
            self.recovery.method,
            self.recovery.merged_points.len(),
            self.flips,
            self.area_limited
                .map_or_else(|| "null".to_string(), |n| n.to_string()),
            self.area_limit_exceeded,
            self.outside_background,
            self.quality.to_json()
        )
    }
}

/// The smallest angle of each triangle, in degrees (a cell field for the `.vtu` output).
fn min_angles(a: &MeshArrays) -> Vec<f64> {
    a.triangles
        .iter()
        .map(|t| {
            let p = t.map(|v| a.coords[v as usize]);
            (0..3)
                .map(|k| {
                    let (o, u, w) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
                    let (ux, uy, wx, wy) = (u[0] - o[0], u[1] - o[1], w[0] - o[0], w[1] - o[1]);
                    (ux * wy - uy * wx)
                        .abs()
                        .atan2(ux * wx + uy * wy)
                        .to_degrees()
                })
                .fold(180.0, f64::min)
        })
        .collect()
}

/// Reads a background mesh for [`Spacing::Background`]: a `.vtu` with a point field
/// `field` (default `spacing`), or a Triangle `.ele` (with its `.node`, one attribute).
///
/// # Errors
/// The file cannot be read, has no such field, or its values are not valid spacings.
pub fn read_background(path: &Path, field: Option<&str>) -> Result<BackgroundMesh2, Error> {
    let ((points, triangles, values), at) = read_field(path, field.unwrap_or("spacing"))?;
    BackgroundMesh2::new(points, triangles, values).map_err(|e| match e {
        // About the cells: named by the cells' file (a `.ele` beside its `.node`).
        SpacingError::Empty | SpacingError::Degenerate(_) | SpacingError::BadNode { .. } => {
            Error::Spacing {
                file: path.to_path_buf(),
                source: e,
            }
        }
        e => spacing_error(e, at),
    })
}

/// A bad background or solution mesh, its node named as the file that holds it numbers it
/// (a Triangle mesh's values are in its `.node` file, numbered from 0 or 1).
fn spacing_error(e: SpacingError, (file, first): (PathBuf, u32)) -> Error {
    let source = match e {
        SpacingError::BadValue { node, what } => SpacingError::BadValue {
            node: node + first as usize,
            what,
        },
        other => other,
    };
    Error::Spacing { file, source }
}

/// Reads a previous mesh and turns its point field `field` into spacing by its gradient
/// (mesh adaptation, R11).
///
/// # Errors
/// As [`read_background`].
pub fn read_adaptation(
    path: &Path,
    field: &str,
    adaptation: &Adaptation,
) -> Result<BackgroundMesh2, Error> {
    let ((points, triangles, values), at) = read_field(path, field)?;
    BackgroundMesh2::from_solution(points, triangles, &values, adaptation)
        .map_err(|e| spacing_error(e, at))
}

type FieldData = (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<f64>);

/// The mesh and field of `path`, with the file its points are in and the number of its first
/// point.
fn read_field(path: &Path, field: &str) -> Result<(FieldData, (PathBuf, u32)), Error> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let mesh = match ext.as_str() {
        "vtu" => delmesh_io::read_vtu(path)?,
        "vtk" => delmesh_io::read_vtk_legacy(path)?,
        "ele" => delmesh_io::read_triangle_mesh(path)?,
        _ => {
            return Err(Error::UnsupportedMeshInput {
                file: path.to_path_buf(),
                ext: format!(".{ext}"),
                supported: ".vtu, .vtk, .ele",
            })
        }
    };
    if mesh.dim != 2 {
        return Err(Error::MeshDimension {
            file: path.to_path_buf(),
            dim: mesh.dim,
            expected: 2,
        });
    }
    let values = point_field(&mesh, field, path)?;
    let points: Vec<[f64; 2]> = mesh.coords.chunks_exact(2).map(|p| [p[0], p[1]]).collect();
    // Cells of no area (a solver's collapsed quads, split) hold nothing to interpolate.
    let triangles = mesh
        .cells
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .filter(|t: &[u32; 3]| {
            let p = t.map(|v| points[v as usize]);
            orient2d(p[0], p[1], p[2]) != Sign::Zero
        })
        .collect();
    Ok((
        (points, triangles, values.clone()),
        mesh.points_file.clone(),
    ))
}

/// The point field `field` of a mesh read from `path`, or an error listing the fields it has.
pub(crate) fn point_field<'a>(
    mesh: &'a delmesh_io::FieldMesh,
    field: &str,
    path: &Path,
) -> Result<&'a Vec<f64>, Error> {
    mesh.point_fields
        .iter()
        .find(|(n, _)| n == field)
        .map(|(_, v)| v)
        .ok_or_else(|| {
            let names: Vec<&str> = mesh.point_fields.iter().map(|(n, _)| n.as_str()).collect();
            Error::MissingField {
                file: path.to_path_buf(),
                field: field.to_string(),
                available: if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                },
            }
        })
}
