//! The paper's 3D pipeline: `delmesh mesh surface.smesh -o mesh.vtu` as a library call.
//!
//! [`Plc3`] → surface recovery and exterior deletion ([`BoundaryRecovery3`], the history of the
//! paper's Table 2) → automatic field points ([`PointGeneration3`]) → output arrays. One
//! [`Mesh3`] value flows through; every stage is timed ([`MeshRun3::timings`]).
//!
//! ```
//! use delmesh::mesh3d::{mesh_plc3, MeshOptions3};
//! use delmesh::recovery::Plc3;
//! // A unit tetrahedron, its faces counter-clockwise seen from outside.
//! let points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
//! let plc = Plc3::from_triangles(points, &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]);
//! let run = mesh_plc3(&plc, &MeshOptions3::default())?;
//! assert!((run.mesh.volume() - 1.0 / 6.0).abs() < 1e-15);
//! # Ok::<(), delmesh::Error>(())
//! ```

use rustc_hash::FxHashMap as HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use delmesh_boundary_recovery::{
    check_surface, BoundaryRecovery3, Mesh3, MeshArrays3, Plc3, PolygonFacet, RecoveryError,
    RecoveryHistory3, RecoveryMethod3, RecoveryStep, RegionSeed3, SurfaceTriangle, OUTSIDE,
};
use delmesh_delaunay_core::{
    ConstrainedTriangulation3, FacetRef, Flips3, Improvement3, Triangulation3, VertexId,
};
use delmesh_io::{SurfaceFile, TetMeshOut};
use delmesh_point_gen::{
    Adaptation, BackgroundMesh3, GenerationReport3, PointGenError, PointGeneration3,
    QualityRefinement3, Source3, SpacingField3, VolumeLimits,
};
use delmesh_predicates::{orient3d, Sign};
use delmesh_smoothing::{
    dihedral_range, min_dihedral_cosine, QualityReport3, SmoothStats, Smoother3,
};
use rayon::prelude::*;

use crate::geometry3::{cross, dot, sub};
use crate::sources::check_sources3;
use crate::surface_split::{
    check_surface_spacing, facet_caps, remesh_surface, split_surface, SurfaceSizing,
    MAX_SPACED_TRIANGLES,
};
use crate::{units, Error};

/// Where the spacing of 3D point generation comes from.
#[derive(Clone, Debug, Default)]
pub enum Spacing3 {
    /// Interpolated from the surface spacing (the paper's default, R10).
    #[default]
    Boundary,
    /// From a background mesh whose nodes carry spacing values (R11), e.g. made from a previous
    /// solution ([`read_adaptation3`]).
    Background(Box<BackgroundMesh3>),
}

/// Smoothing passes of the 3D pipeline. Below the paper's 20–50: the Delaunay restoration that
/// follows smoothing flips the mesh into the (constrained) Delaunay tetrahedralisation of the
/// points, so what counts is where the points end up. On
/// the double ellipsoid (`figure9`, `--example pipeline3d -- figure9 --iterations N`) the final
/// mesh after 0, 2, 4, 6, 10 and 30 passes has 419, 175, 145, 159, 165 and 171 slivers
/// (dihedral < 5°) and a mean smallest dihedral of 42.83°, 44.24°, 44.76°, 44.95°, 45.04° and
/// 45.02° (at c394b6b, α = 0.57; at c50a56e, α = 0.55: 499, 192, 183, 176, 163, 161 slivers):
/// four passes get most of it, in about half the time of ten.
pub const SMOOTHING_PASSES: usize = 4;

/// Passes of [`MeshOptions3::sliver_flips`] (each looks again at the elements still below
/// the angle; most are done after two or three).
const SLIVER_FLIP_PASSES: usize = 8;

/// A mesh of the constrained recovery (not Delaunay, so no restoration follows) gets the
/// sliver flips below this smallest dihedral angle (degrees) when none are asked for: such
/// tetrahedra are flat to rounding (nearly coplanar surface points of a rotated box, joined
/// across a face by the first tetrahedralisation: volumes of 1e-18 in a unit cube), and
/// flips remove those they can. Not those with two faces on the surface: they fill a fold
/// of two surface triangles that is concave to rounding, a (tiny) part of the domain that
/// only a point could divide (with `--no-points` they stay; adversarial runs of rotated grid
/// boxes and tori: 13 → 1, 235 → 14).
const FLAT_TO_ROUNDING_DEGREES: f64 = 1e-4;

/// Options of the 3D pipeline; `Default` is the paper's method with its usual parameters.
#[derive(Clone, Debug)]
pub struct MeshOptions3 {
    /// How the surface is recovered.
    pub recovery: RecoveryMethod3,
    /// Field points from an external source (R9); those outside the domain are dropped.
    pub extra_points: Vec<[f64; 3]>,
    /// Automatic point generation (`None`: the surface and extra points only).
    pub generation: Option<PointGeneration3>,
    /// The spacing field's base.
    pub spacing: Spacing3,
    /// Analytic sources refining the spacing.
    pub sources: Vec<Source3>,
    /// Most points boundary recovery may add before it gives up (`None`: its default bound).
    pub max_steiner_points: Option<usize>,
    /// Let recovery re-triangulate exactly coplanar neighbouring triangles of different input
    /// facets (same marker) together, as TetGen merges coplanar facets by default
    /// ([`BoundaryRecovery3::merge_coplanar`]).
    pub merge_coplanar: bool,
    /// Merge coplanar facets after all where the facets as given would cost too many points
    /// ([`BoundaryRecovery3::coplanar_fallback`], default on); off, every input triangle is
    /// kept and recovery stops with an error at the bound.
    pub coplanar_fallback: bool,
    /// Remesh the surface at this spacing before recovery (`None`: the surface as given, the
    /// paper's method): each planar patch (exactly coplanar neighbours with one marker) with
    /// an edge longer than it is meshed whole in its plane, its boundary edges cut into equal
    /// pieces shared with the patch beyond; each patch is the union of its new triangles, which
    /// keep its marker (an input triangle is not, where its patch has several). A CAD
    /// surface's long thin triangles (an STL export) otherwise make flat tetrahedra however
    /// many field points are added; the field points' spacing follows the new surface's.
    pub surface_spacing: Option<f64>,
    /// Whether a background mesh (or an adaptation's) asking for a finer spacing than the
    /// surface's triangles splits them first, in rounds that halve them until each is within
    /// 1.5 times the finest spacing the background asks on it (sampled), by the same in-plane
    /// meshing as volume limits (default true): a 12-triangle unit cube under a background
    /// spacing of 0.1 kept its triangles, and generation and refinement piled thousands of
    /// points against them. Off, or where the surface would need more than 2^24 triangles,
    /// the surface is meshed as given.
    pub split_surface: bool,
    /// Radius–edge refinement after point generation (`None`: none; needs generation).
    pub refinement: Option<QualityRefinement3>,
    /// Laplacian smoothing of the field points (`None`: no smoothing).
    pub smoothing: Option<Smoother3>,
    /// At the end, restore the constrained Delaunay property that smoothing and generation
    /// next to the boundary break (see [`restore_after_smoothing`]).
    pub delaunay: bool,
    /// At the very end, flip away elements whose smallest dihedral angle is below this many
    /// degrees where flips improve them (beyond the paper; the mesh is then no longer
    /// Delaunay there): see [`ConstrainedTriangulation3::improve_by_flips`]. `None`: no flips,
    /// but for a mesh of the constrained recovery, which gets those below 0.0001° (flat to
    /// rounding; see `FLAT_TO_ROUNDING_DEGREES`).
    ///
    /// [`ConstrainedTriangulation3::improve_by_flips`]: delmesh_delaunay_core::ConstrainedTriangulation3::improve_by_flips
    pub sliver_flips: Option<f64>,
}

impl Default for MeshOptions3 {
    fn default() -> Self {
        MeshOptions3 {
            recovery: RecoveryMethod3::Conforming,
            extra_points: Vec::new(),
            generation: Some(PointGeneration3::default()),
            spacing: Spacing3::Boundary,
            sources: Vec::new(),
            max_steiner_points: None,
            merge_coplanar: false,
            coplanar_fallback: true,
            surface_spacing: None,
            split_surface: true,
            refinement: Some(QualityRefinement3::default()),
            smoothing: Some(Smoother3::new().iterations(SMOOTHING_PASSES)),
            delaunay: true,
            sliver_flips: None,
        }
    }
}

/// The result of the 3D pipeline.
#[derive(Clone, Debug)]
pub struct MeshRun3 {
    /// The mesh (tetrahedralisation, boundary faces, regions, spacing).
    pub mesh: Mesh3,
    /// The mesh as flat arrays (what the writers take).
    pub arrays: MeshArrays3,
    /// The recovery history (the paper's Table 2).
    pub recovery: RecoveryHistory3,
    /// The point generation passes, if generation ran.
    pub generation: Option<GenerationReport3>,
    /// How the Delaunay property was restored at the end, if it was.
    pub restoration: Option<Restoration3>,
    /// Points added by quality refinement.
    pub refined: usize,
    /// Points added at the centroids of tetrahedra larger than their region's volume limit
    /// ([`RegionSeed3::max_volume`]), before smoothing and after the restoration; `None` when
    /// no region has a limit or no points are generated.
    pub volume_limited: Option<usize>,
    /// Tetrahedra still larger than their region's volume limit at the end: their centroids
    /// refused where a new element would break the Delaunay property next to the surface, or,
    /// without the restoration (`delaunay: false`), grown by smoothing; 0 without limits.
    pub volume_limit_exceeded: usize,
    /// Elements lying flat on the surface taken out after the restoration
    /// ([`Mesh3::remove_flat_surface_elements`]).
    pub flat_removed: usize,
    /// Points put at the centroids of elements lying flat inside the domain, after the
    /// restoration or, without generation, after recovery ([`Mesh3::split_flat_elements`]).
    pub flat_split: usize,
    /// Triangles given twice, with opposite orientations and one marker, whose second copy
    /// was dropped: each is an internal wall ([`walls_from_duplicates`]).
    pub duplicate_walls: usize,
    /// What smoothing did, if it ran.
    pub smoothing: Option<SmoothStats>,
    /// What the sliver flips did ([`MeshOptions3::sliver_flips`]), if they ran.
    pub sliver_flips: Option<Improvement3>,
    /// Quality before smoothing (after point generation), if smoothing ran.
    pub quality_before_smoothing: Option<QualityReport3>,
    /// Quality of the final mesh.
    pub quality: QualityReport3,
    /// Seconds spent in each stage, in order.
    pub timings: Vec<(&'static str, f64)>,
    /// The input's names of facet markers ([`Plc3::marker_names`]), written where a format
    /// names its groups (gmsh physical names).
    pub marker_names: Vec<(i32, String)>,
}

/// Runs the pipeline on `plc`. A domain far from ordinary magnitudes is meshed scaled by a
/// power of two and handed back in its own units ([`crate::units`]): the same mesh, exactly,
/// as the scaled problem's.
///
/// # Errors
/// Invalid input (named in the input's numbering), coordinates beyond double precision's range
/// ([`Error::OutOfRange`]), a surface that could not be recovered, a domain with no element,
/// or a bad option.
pub fn mesh_plc3(plc: &Plc3, options: &MeshOptions3) -> Result<MeshRun3, Error> {
    units::check_range(&plc.points, plc.first_index)?;
    if let Some(d) = options
        .sliver_flips
        .filter(|d| !(d.is_finite() && *d >= 0.0))
    {
        return Err(Error::BadOption {
            option: "--sliver-flips",
            reason: format!(
                "the angle must be a finite number of degrees, not negative (got {d:?})"
            ),
        });
    }
    let sources = options.generation.is_some() && !options.sources.is_empty();
    if sources {
        check_sources3(&options.sources, &plc.points)?;
    }
    if options.surface_spacing.is_some() || sources {
        // Checked here, in the caller's units, on the surface as given (so that errors name
        // the input's triangles): the surface is remeshed before recovery.
        check_surface(plc).map_err(RecoveryError::from)?;
    }
    if let Some(h) = options.surface_spacing {
        check_surface_spacing(plc, h)?;
    }
    let e = units::normalising_exponent(&plc.points);
    if e == 0 {
        return mesh_plc3_as_given(plc, options);
    }
    let asked = options.surface_spacing;
    let (plc, options) = units::scale_problem3(plc, options, e);
    let mut run = mesh_plc3_as_given(&plc, &options).map_err(|err| match (err, asked) {
        (Error::SurfaceSpacing { reason, .. }, Some(value)) => {
            Error::SurfaceSpacing { value, reason }
        }
        (err, _) => units::unscale_error(err, e),
    })?;
    units::unscale_run3(&mut run, -e)?;
    Ok(run)
}

/// Triangles given twice with opposite orientations and one marker: two closed solids written
/// one after the other (an STL of each material, concatenated) give their common face so, once
/// for each. The second copy is dropped, and the face is an internal wall between the two
/// solids (see [`delmesh_boundary_recovery::check_surface`] on walls). Copies are found by the
/// exact coordinates of their corners, since the points of each solid are their own. Any other
/// repetition (the same orientation, two markers, three copies) is left for the surface checks
/// to report. Returns the surface without the dropped copies (`None`: none) and how many.
/// A triangle naming a point that does not exist leaves the surface as it is, for the checks
/// to name.
pub fn walls_from_duplicates(plc: &Plc3) -> (Option<Plc3>, usize) {
    let n = plc.points.len();
    if plc
        .triangles
        .iter()
        .any(|t| t.v.iter().any(|&v| v as usize >= n))
    {
        return (None, 0);
    }
    // (0.0 and -0.0 are one coordinate.)
    let key = |v: u32| plc.points[v as usize].map(|x| (x + 0.0).to_bits());
    let mut keyed: Vec<([[u64; 3]; 3], usize)> = plc
        .triangles
        .par_iter()
        .enumerate()
        .map(|(k, t)| {
            let mut corners = t.v.map(key);
            corners.sort_unstable();
            (corners, k)
        })
        .collect();
    keyed.par_sort_unstable();
    let mut keep = vec![true; plc.triangles.len()];
    let mut dropped = 0;
    for copies in keyed.chunk_by(|x, y| x.0 == y.0) {
        let [(_, first), (_, second)] = copies[..] else {
            continue;
        };
        let (a, b) = (&plc.triangles[first], &plc.triangles[second]);
        // Opposite: b runs a's corners backwards, from whichever corner.
        let (x, y) = (a.v.map(key), b.v.map(key));
        let opposite = (0..3).any(|r| (0..3).all(|m| y[m] == x[(r + 3 - m) % 3]));
        if opposite && a.marker == b.marker {
            keep[second] = false;
            dropped += 1;
        }
    }
    if dropped == 0 {
        return (None, 0);
    }
    let mut kept = plc.clone();
    kept.triangles = plc
        .triangles
        .iter()
        .zip(&keep)
        .filter(|x| *x.1)
        .map(|x| *x.0)
        .collect();
    (Some(kept), dropped)
}

/// [`mesh_plc3`] on the problem as it is (no rescaling).
fn mesh_plc3_as_given(plc: &Plc3, options: &MeshOptions3) -> Result<MeshRun3, Error> {
    let (deduplicated, duplicate_walls) = walls_from_duplicates(plc);
    let plc = deduplicated.as_ref().unwrap_or(plc);
    let mut timings = Vec::new();
    let mut clock = Instant::now();
    let mut lap = |name: &'static str, timings: &mut Vec<(&'static str, f64)>| {
        timings.push((name, clock.elapsed().as_secs_f64()));
        clock = Instant::now();
    };
    // The surface split to the spacing asked (checked by `mesh_plc3`), and where sources ask
    // for finer spacing than its triangles: generation cannot fill the volume next to a
    // surface triangle finer than the triangle, and flat tetrahedra pile up on it.
    let sizing = SurfaceSizing {
        h: options.surface_spacing.unwrap_or(f64::INFINITY),
        sources: if options.generation.is_some() {
            &options.sources
        } else {
            &[]
        },
    };
    let spaced;
    let mut remeshed = false;
    let plc = if sizing.h != f64::INFINITY || !sizing.sources.is_empty() {
        let split = remesh_surface(plc, &sizing)?;
        lap("surface spacing", &mut timings);
        match split {
            Some(p) => {
                spaced = p;
                remeshed = true;
                &spaced
            }
            None => plc,
        }
    } else {
        plc
    };
    // A background mesh finer than the surface splits it, each triangle to the finest spacing
    // the background asks on it (as volume limits do, below).
    let background_split;
    let plc = match (&options.spacing, &options.generation) {
        (Spacing3::Background(bg), Some(_)) if options.split_surface => {
            // In rounds, each triangle to at most half its size: the surface grades as the
            // background does (one split to the finest spacing on a large triangle was
            // uniform across it).
            let mut split: Option<Plc3> = None;
            for _ in 0..BACKGROUND_SPLIT_ROUNDS {
                let now = split.as_ref().unwrap_or(plc);
                let (caps, asked) = background_caps(bg, now);
                // A background too fine for any mesh (1e-300) would split the surface until
                // memory ran out: kept as it is, generation then says the field is too fine.
                if asked > MAX_SPACED_TRIANGLES {
                    split = None;
                    break;
                }
                match split_surface(now, |k| caps[k])? {
                    Some(next) => split = Some(next),
                    None => break,
                }
            }
            lap("surface spacing", &mut timings);
            match split {
                Some(p) => {
                    background_split = p;
                    remeshed = true;
                    &background_split
                }
                None => plc,
            }
        }
        _ => plc,
    };
    // Regional volume limits are honoured when points are generated: generation's spacing is
    // capped there, and too large tetrahedra are split.
    let base = u64::from(plc.first_index);
    for (k, r) in plc.regions.iter().enumerate() {
        if let Some(value) = r.max_volume.filter(|v| v.is_nan() || *v <= 0.0) {
            let region = k as u64 + base;
            return Err(PointGenError::BadVolumeLimit { region, value }.into());
        }
    }
    let limits = (options.generation.is_some() && plc.has_volume_limits())
        .then(|| VolumeLimits::new(plc.volume_limits()));
    let mut volume_limited = limits.as_ref().map(|_| 0);
    let mut recovery = BoundaryRecovery3::new(options.recovery)
        .with_points(options.extra_points.clone())
        .merge_coplanar(options.merge_coplanar)
        .coplanar_fallback(options.coplanar_fallback)
        // Flat tetrahedra on the surface are left to the field points only where enough may
        // come to reach them all (a cap of 20 left a sphere's 3,000 there as slivers).
        .field_points_follow(
            options
                .generation
                .as_ref()
                .is_some_and(|g| g.max_points >= plc.points.len().max(1)),
        );
    if let Some(n) = options.max_steiner_points {
        recovery = recovery.max_steiner_points(n);
    }
    let mut mesh = recovery
        .run(plc)
        .map_err(|e| match (e, options.surface_spacing) {
            // Walls of a thin gap, each meshed in its own plane, no longer face each other point
            // for point: a conforming recovery then needs points at the gap's width.
            (e @ RecoveryError::SurfaceNotRecovered { .. }, Some(h)) => Error::SurfaceSpacing {
                value: h,
                reason: format!(
                    "{e}; where the split surface's walls are closer than the spacing, try \
                 --recovery constrained or a-priori, or a smaller spacing"
                ),
            },
            (e @ RecoveryError::SurfaceNotRecovered { .. }, None)
                if options.recovery != RecoveryMethod3::Constrained =>
            {
                Error::ConformingRecovery(e)
            }
            // The surface as given passed these checks (`mesh_plc3`).
            (e @ RecoveryError::Surface(_), Some(h)) if remeshed => Error::SurfaceSpacing {
                value: h,
                reason: format!(
                    "the surface split to it fails the surface checks (a bug in delmesh; \
                     without --surface-spacing the surface is meshed as given): {e}"
                ),
            },
            (e @ RecoveryError::Surface(_), None) if remeshed => Error::Internal(format!(
                "the surface split for the spacing sources or background mesh fails the \
                 surface checks: {e}"
            )),
            (e, _) => e.into(),
        })?;
    // The surface next to a limited region is split to its spacing (see `surface_split`),
    // once the recovery has told which regions each facet bounds; then recovered again.
    let split;
    let plc = match &limits {
        Some(limits) => {
            if let Some((tag, volume, elements)) =
                limits.asking_too_much(&mesh, MAX_LIMITED_ELEMENTS)
            {
                return Err(PointGenError::VolumeLimitTooSmall {
                    region: (tag.max(1) - 1) as u64 + base,
                    max_volume: plc.volume_limits()[tag],
                    volume,
                    elements,
                }
                .into());
            }
            let caps = facet_caps(&mesh, &limits.spacing_caps());
            let cap_of = |t: &SurfaceTriangle| caps.get(&t.facet).copied();
            match split_surface(plc, |k| cap_of(&plc.triangles[k]).unwrap_or(f64::INFINITY))? {
                Some(p) => {
                    split = p;
                    mesh = recovery.run(&split)?;
                    &split
                }
                None => plc,
            }
        }
        None => plc,
    };
    lap("boundary recovery", &mut timings);
    let mut refined = 0;
    let generation = match &options.generation {
        Some(settings) => {
            let mut field = match &options.spacing {
                Spacing3::Boundary => SpacingField3::boundary(),
                Spacing3::Background(bg) => SpacingField3::background((**bg).clone()),
            };
            for s in &options.sources {
                field = field.with_source(*s);
            }
            let caps = limits
                .as_ref()
                .map_or_else(Vec::new, VolumeLimits::spacing_caps);
            let report = settings.run_capped(&mut mesh, &field, &caps)?;
            lap("point generation", &mut timings);
            if let Some(refinement) = &options.refinement {
                let budget = settings.max_points.saturating_sub(report.points_added());
                refined = refinement.run_capped(&mut mesh, budget)?;
                lap("quality refinement", &mut timings);
            }
            if let (Some(limits), Some(n)) = (&limits, &mut volume_limited) {
                let budget = settings
                    .max_points
                    .saturating_sub(report.points_added() + refined);
                // (The restoration after smoothing makes the mesh Delaunay again.)
                *n += limits.run(&mut mesh, budget, false);
                lap("volume limits", &mut timings);
            }
            Some(report)
        }
        None => None,
    };
    // Without generation no restoration follows: the recovered mesh's flat elements inside
    // are split now (those on the surface stay: a recovery-only mesh keeps each input
    // triangle as recovered).
    let mut flat_split = 0;
    if generation.is_none() {
        flat_split = mesh.split_flat_elements();
        lap("flat elements", &mut timings);
    }
    let recovery_history = mesh.history.clone();
    let mut arrays = mesh.to_arrays();
    lap("output arrays", &mut timings);
    let smoother = options.smoothing.filter(|_| generation.is_some());
    let restore = options.delaunay && generation.is_some();
    // The quality before smoothing is measured from a copy, during the Delaunay restoration
    // (whose triangulation is sequential, so the second thread is free for it).
    let before = smoother.map(|_| arrays.coords.clone());
    let mut smoothing = None;
    if let Some(s) = &smoother {
        smoothing = Some(s.smooth(&mut arrays.coords, &arrays.tets, &arrays.on_boundary)?);
        lap("smoothing", &mut timings);
    }
    let measure_before = || {
        before
            .as_ref()
            .map(|coords| QualityReport3::of_mesh(coords, &arrays.tets, &arrays.neighbours))
    };
    let (quality_before_smoothing, restoration) = if restore {
        let (q, r) = rayon::join(measure_before, || {
            // After a constrained recovery, faces next to the edges and faces it flipped in
            // fail the insphere test by design: flips only, no split, no retriangulation.
            let flips_only = recovery_history.method == RecoveryMethod3::Constrained
                && !recovery_history.constrained_fallback;
            if flips_only {
                Ok(restore_by_flips(&mut mesh, &arrays))
            } else {
                restore_after_smoothing(&mut mesh, &arrays, plc, options.max_steiner_points)
            }
        });
        (q, Some(r?))
    } else {
        (measure_before(), None)
    };
    // Moves change volumes: the limits are checked again once the mesh is Delaunay again.
    if let (Some(limits), Some(n), Some(settings), Some(report), Some(_)) = (
        &limits,
        &mut volume_limited,
        &options.generation,
        &generation,
        &restoration,
    ) {
        let budget = settings
            .max_points
            .saturating_sub(report.points_added() + refined + *n);
        let delaunay = (recovery_history.method != RecoveryMethod3::Constrained
            || recovery_history.constrained_fallback)
            && !matches!(restoration, Some(Restoration3::Incomplete { .. }));
        *n += limits.run(&mut mesh, budget, delaunay);
    }
    let volume_limit_exceeded = limits.as_ref().map_or(0, |l| l.exceeding(&mesh));
    let mut flat_removed = 0;
    if restoration.is_some() {
        flat_removed = mesh.remove_flat_surface_elements();
        flat_split = mesh.split_flat_elements();
        arrays = mesh.to_arrays();
        lap("delaunay restoration", &mut timings);
    } else if quality_before_smoothing.is_some() {
        lap("quality", &mut timings);
    }
    let mut sliver_flips = None;
    let constrained = recovery_history.method == RecoveryMethod3::Constrained
        && !recovery_history.constrained_fallback;
    let degrees = options
        .sliver_flips
        .or(constrained.then_some(FLAT_TO_ROUNDING_DEGREES));
    if let Some(degrees) = degrees {
        // Without the restoration the smoothed coordinates are in the arrays only (smoothing
        // keeps every element positive, so the move is accepted).
        let moved = restoration.is_some()
            || smoothing.is_none()
            || mesh
                .ct
                .move_vertices(&smoothing_moves(&mesh, &arrays))
                .is_ok();
        if moved {
            // Larger is better: minus the cosine of the smallest dihedral angle.
            sliver_flips = Some(mesh.ct.improve_by_flips(
                -degrees.to_radians().cos(),
                |p| -min_dihedral_cosine(p),
                |tag| tag != OUTSIDE,
                SLIVER_FLIP_PASSES,
            ));
            arrays = mesh.to_arrays();
        }
        lap("sliver flips", &mut timings);
    }
    let quality = QualityReport3::of_mesh(&arrays.coords, &arrays.tets, &arrays.neighbours);
    lap("quality", &mut timings);
    Ok(MeshRun3 {
        recovery: recovery_history,
        mesh,
        arrays,
        generation,
        restoration,
        refined,
        volume_limited,
        volume_limit_exceeded,
        flat_removed,
        flat_split,
        duplicate_walls,
        smoothing,
        sliver_flips,
        quality_before_smoothing,
        quality,
        timings,
        marker_names: plc.marker_names.clone(),
    })
}

/// Tetrahedra at most that volume limits may ask for: cell ids are 32-bit, and the
/// triangulation holds the hull's cells besides the domain's.
const MAX_LIMITED_ELEMENTS: f64 = (1u64 << 30) as f64;

/// How [`mesh_plc3`] restored the Delaunay property after point generation and smoothing.
#[derive(Clone, Debug)]
pub enum Restoration3 {
    /// In the mesh itself: flips, and where they stopped short, edges split at their
    /// mid-points (each split followed by flips again).
    Flips {
        /// The flips (`failing`: the faces that failed before the first flip; `left`: none,
        /// except after a constrained recovery, whose mesh keeps them: see
        /// [`restore_by_flips`]).
        flips: Flips3,
        /// Edges split at their mid-points.
        split_edges: usize,
        /// Of `split_edges`, the boundary edges: their new vertex is on the surface, and the
        /// boundary faces on them were split in two.
        surface_points: usize,
        /// Smoothing moves undone: where flips and splits stalled, vertices of the cells on
        /// the faces left went back where smoothing found them (see
        /// [`restore_after_smoothing`]).
        undone: usize,
    },
    /// The splits did not converge (see [`restore_after_smoothing`]), so the final points
    /// were triangulated again and the surface recovered again ([`restore_delaunay`]), with
    /// this history.
    Retriangulated {
        /// The second recovery.
        history: RecoveryHistory3,
    },
    /// The splits did not converge and triangulating the points again failed too (its
    /// surface recovery did not finish, `reason`): the mesh is kept as the flips and splits
    /// left it, valid with every boundary face in place, but the faces `flips.left` still fail
    /// the insphere test (beyond the paper: the mesh is not Delaunay there).
    Incomplete {
        /// The flips, with the faces left failing.
        flips: Flips3,
        /// Edges split at their mid-points.
        split_edges: usize,
        /// Of `split_edges`, the boundary edges.
        surface_points: usize,
        /// Why triangulating again failed.
        reason: String,
    },
}

/// After a constrained recovery, moves the smoothed points (`arrays.coords`) in `mesh` and
/// flips every face that fails the insphere test where a flip applies; the faces left (next
/// to the boundary edges and faces that recovery flipped in, which a constrained mesh keeps)
/// are reported, not split.
pub fn restore_by_flips(mesh: &mut Mesh3, arrays: &MeshArrays3) -> Restoration3 {
    let moves = smoothing_moves(mesh, arrays);
    // Smoothing keeps every element positive, so the move is accepted; if it were not, the
    // smoothed points are dropped and the recovered mesh flipped as it is.
    let _ = mesh.ct.move_vertices(&moves);
    Restoration3::Flips {
        flips: mesh.ct.make_delaunay(|_| true),
        split_edges: 0,
        surface_points: 0,
        undone: 0,
    }
}

/// The vertices smoothing moved, each with its new place (`arrays` is `mesh.to_arrays()`
/// with the smoothed coordinates).
fn smoothing_moves(mesh: &Mesh3, arrays: &MeshArrays3) -> Vec<(VertexId, [f64; 3])> {
    let tri = mesh.ct.triangulation();
    arrays
        .vertex
        .iter()
        .zip(&arrays.coords)
        .filter(|&(&v, &p)| tri.vertex(v) != p)
        .map(|(&v, &p)| (v, p))
        .collect()
}

/// The most rounds of edge splits (each followed by flips) before [`restore_after_smoothing`]
/// falls back on triangulating the points again.
pub const MAX_SPLIT_ROUNDS: usize = 32;

/// The most rounds of undoing smoothing moves (each followed by flips) once the splits of
/// [`restore_after_smoothing`] stall.
pub const UNDO_ROUNDS: usize = 4;

/// Makes `mesh` constrained Delaunay again after smoothing moved its points to
/// `arrays.coords` (`arrays` is `mesh.to_arrays()` with the smoothed coordinates). The points
/// are moved in the mesh and the faces that fail the insphere test are flipped
/// ([`delmesh_delaunay_core::ConstrainedTriangulation3::make_delaunay`]; never across a
/// boundary face, so no element leaves its region). Flips can stop short in 3D, typically at a boundary
/// edge with only two elements around it whose shared face fails: such an edge is split at
/// its mid-point ([`Mesh3::split_edge`], as the paper's recovery splits a missing edge) and
/// the flips go on. Also mends the faces that point generation left failing next to the
/// boundary. Where interior points crowd the surface the splits do not converge: after four
/// rounds without fewer failing faces than ever, after more splits than one and a half times
/// the faces the first flips left (plus 64), or after [`MAX_SPLIT_ROUNDS`] rounds. Then the
/// vertices of the cells on the faces left that smoothing moved go back where it found them
/// (each only if no cell around it inverts) and the flips go on, up to [`UNDO_ROUNDS`]
/// times: a face that smoothing made fail often passes again (bunny00 stalled on one face,
/// and triangulating again took 1.1 s of its 3 s). Only if faces are still left is `mesh`
/// replaced by [`restore_delaunay`]'s. That one starts beside the splits (on another thread)
/// as soon as the first flips leave a face, and is stopped when the splits finish: where they
/// do not, its time is not added to theirs. It does not triangulate the points again: it
/// starts from a copy of the mesh's tetrahedralisation as the first flips left it, made
/// Delaunay by flips with no face protected (the same tetrahedralisation, several times
/// faster: armadillo's 84,686 points in 12 ms of flips against 219 ms of construction).
///
/// # Errors
/// As [`restore_delaunay`], when it is needed.
pub fn restore_after_smoothing(
    mesh: &mut Mesh3,
    arrays: &MeshArrays3,
    plc: &Plc3,
    max_steiner_points: Option<usize>,
) -> Result<Restoration3, Error> {
    let moves = smoothing_moves(mesh, arrays);
    // Where smoothing found each vertex it moved (the last resort puts some back).
    let found: HashMap<VertexId, [f64; 3]> = moves
        .iter()
        .map(|&(v, _)| (v, mesh.ct.triangulation().vertex(v)))
        .collect();
    // Smoothing keeps every element positive (exactly), so the move is accepted; if it were
    // not, the flips could not start and the mesh is rebuilt.
    if mesh.ct.move_vertices(&moves).is_err() {
        let again = restore_delaunay_until(arrays, plc, max_steiner_points, None, None);
        return retriangulated(mesh, arrays, again, None);
    }
    // Every cell is in scope: a split boundary edge changes cells outside the domain too.
    let flips = mesh.ct.make_delaunay(|_| true);
    if flips.left.is_empty() {
        return Ok(Restoration3::Flips {
            flips,
            split_edges: 0,
            surface_points: 0,
            undone: 0,
        });
    }
    // The flips stopped short. Edge splits may finish in the mesh, or not: recovering the
    // surface again starts at once beside them (it is what takes long) and is stopped if they
    // do.
    let stop = Arc::new(AtomicBool::new(false));
    // The mesh's tetrahedralisation as the flips left it, for the re-triangulation to start
    // from (the splits change the mesh meanwhile), with the only faces that may fail the
    // insphere test: those the flips left, and the protected ones.
    let seeds = flips
        .left
        .iter()
        .copied()
        .chain(mesh.ct.protected_facets())
        .collect();
    let start = (mesh.ct.triangulation().clone(), seeds);
    let (in_place, again) = rayon::join(
        || {
            let done = split_in_place(mesh, flips, &found);
            if done.is_ok() {
                stop.store(true, Ordering::Relaxed);
            }
            done
        },
        || {
            restore_delaunay_until(
                arrays,
                plc,
                max_steiner_points,
                Some(stop.clone()),
                Some(start),
            )
        },
    );
    match in_place {
        Ok(done) => Ok(done),
        Err(kept) => retriangulated(mesh, arrays, again, Some(kept)),
    }
}

/// The flips, edge splits and undone smoothing moves of [`restore_after_smoothing`] after its
/// first flips (`flips`) left faces failing: the restoration if they finish, else the flips
/// with the faces left, the edges split and the surface points among them.
fn split_in_place(
    mesh: &mut Mesh3,
    mut flips: Flips3,
    found: &HashMap<VertexId, [f64; 3]>,
) -> Result<Restoration3, (Flips3, usize, usize)> {
    let all = |_tag: u32| true;
    let mut total = Flips3 {
        failing: flips.failing,
        ..Flips3::default()
    };
    let (mut split_edges, mut surface_points) = (0, 0);
    let (mut fewest, mut stale) = (usize::MAX, 0);
    let budget = flips.left.len() + flips.left.len() / 2 + 64;
    let mut index = mesh.face_index();
    for round in 0..=MAX_SPLIT_ROUNDS {
        total.two_three += flips.two_three;
        total.three_two += flips.three_two;
        total.four_four += flips.four_four;
        if flips.left.is_empty() {
            return Ok(Restoration3::Flips {
                flips: total,
                split_edges,
                surface_points,
                undone: 0,
            });
        }
        // Where interior points crowd the surface, splits make as many failing faces as
        // they mend: the rounds stop after four without a new low, or before the splits
        // would exceed one and a half times the faces the flips first left (plus 64).
        if flips.left.len() < fewest {
            (fewest, stale) = (flips.left.len(), 0);
        } else {
            stale += 1;
        }
        if round == MAX_SPLIT_ROUNDS || stale >= 4 || split_edges + flips.left.len() > budget {
            break;
        }
        let mut next = flips.left.clone();
        for &f in &flips.left {
            // An earlier split of this round may have removed the face already.
            if !mesh.ct.face_fails(f, all) {
                continue;
            }
            // (Splitting another edge of the face instead only moves the failing face to
            // the new vertex: measured.)
            let [x, y] = mesh.ct.edges_to_split(f)[0];
            if let Ok(Some(v)) = mesh.split_edge(x, y, &mut index) {
                split_edges += 1;
                surface_points += usize::from(mesh.on_surface[v.index()]);
                for &c in mesh.ct.last_new_cells() {
                    next.extend((0..4).map(|i| FacetRef::new(c, i)));
                }
            }
        }
        flips = mesh.ct.make_delaunay_from(next, all);
    }
    let undone = undo_smoothing_near(mesh, &mut flips, &mut total, found);
    if flips.left.is_empty() {
        return Ok(Restoration3::Flips {
            flips: total,
            split_edges,
            surface_points,
            undone,
        });
    }
    total.left = flips.left;
    Err((total, split_edges, surface_points))
}

/// `mesh` replaced by `again`, the mesh [`restore_delaunay`] made, with the spacing generation
/// gave its points; if that failed, the mesh as the flips and splits left it (`kept`: the
/// flips, the edges split, the surface points), valid but not Delaunay everywhere.
fn retriangulated(
    mesh: &mut Mesh3,
    arrays: &MeshArrays3,
    again: Result<Mesh3, Error>,
    kept: Option<(Flips3, usize, usize)>,
) -> Result<Restoration3, Error> {
    match (again, kept) {
        (Ok(mut restored), _) => {
            // The points keep the spacing generation gave them (the recovery that rebuilt
            // the mesh knows the surface's only).
            for (i, &v) in arrays.vertex.iter().enumerate() {
                if let Some(&h) = mesh.spacing.get(v.index()).filter(|h| h.is_finite()) {
                    let w = restored.ct.triangulation().vertex_of_input(i);
                    restored.set_interior_spacing(w, h);
                }
            }
            *mesh = restored;
            Ok(Restoration3::Retriangulated {
                history: mesh.history.clone(),
            })
        }
        // The flipped and split mesh is valid: better kept, with the faces left counted and
        // a warning, than the user's run lost.
        (Err(e), Some((flips, split_edges, surface_points))) => Ok(Restoration3::Incomplete {
            flips,
            split_edges,
            surface_points,
            reason: e.to_string(),
        }),
        (Err(e), None) => Err(e),
    }
}

/// The last resort of [`restore_after_smoothing`] once its splits stall: each vertex of the
/// cells on the faces `flips.left` that smoothing moved goes back to where smoothing found it
/// (`found`), if no cell around it inverts, and the faces around the vertices put back are
/// flipped again; up to [`UNDO_ROUNDS`] rounds, while faces are left and a vertex goes back.
/// `flips` becomes the last flips (added to `total`). Returns the moves undone.
fn undo_smoothing_near(
    mesh: &mut Mesh3,
    flips: &mut Flips3,
    total: &mut Flips3,
    found: &HashMap<VertexId, [f64; 3]>,
) -> usize {
    let mut star = Vec::new();
    let mut undone = 0;
    for _ in 0..UNDO_ROUNDS {
        let tri = mesh.ct.triangulation();
        let mut back: Vec<(VertexId, [f64; 3])> = Vec::new();
        for &f in &flips.left {
            let cells = std::iter::once(f.cell()).chain(tri.neighbor(f.cell(), f.facet()));
            for c in cells {
                for &u in tri.cell(c) {
                    match found.get(&u) {
                        Some(&p) if tri.vertex(u) != p => back.push((u, p)),
                        _ => {}
                    }
                }
            }
        }
        back.sort_unstable_by_key(|b| b.0);
        back.dedup_by_key(|b| b.0);
        let mut faces = flips.left.clone();
        let mut moved = 0;
        for (u, p) in back {
            if mesh.ct.move_vertex(u, p, &mut star) {
                moved += 1;
                faces.extend(
                    star.iter()
                        .flat_map(|&c| (0..4).map(move |i| FacetRef::new(c, i))),
                );
            }
        }
        if moved == 0 {
            break;
        }
        undone += moved;
        *flips = mesh.ct.make_delaunay_from(faces, |_| true);
        total.two_three += flips.two_three;
        total.three_two += flips.three_two;
        total.four_four += flips.four_four;
        if flips.left.is_empty() {
            break;
        }
    }
    undone
}

/// The Delaunay tetrahedralisation of the points of `arrays`, conforming to its boundary
/// triangles: they become the input surface (keeping the markers and the input facets of `plc`,
/// whose holes and region seeds classify the cells), so recovery only splits the few that a
/// nearby interior point now hides. Point generation near protected faces and smoothing both
/// leave cells whose circumsphere holds a vertex; this puts every tetrahedron back to an empty
/// circumsphere. Slower than the flips of [`restore_after_smoothing`], which fall back on it
/// only where they cannot finish.
///
/// # Errors
/// [`Error::Restoration`] with [`BoundaryRecovery3::run`]'s error.
pub fn restore_delaunay(
    arrays: &MeshArrays3,
    plc: &Plc3,
    max_steiner_points: Option<usize>,
) -> Result<Mesh3, Error> {
    restore_delaunay_until(arrays, plc, max_steiner_points, None, None)
}

/// [`restore_delaunay`], stopped with [`RecoveryError::Cancelled`] (as
/// [`Error::Restoration`]) soon after `stop` is set; starting from `start`, a
/// tetrahedralisation of the points of `arrays` (the mesh's) with the faces that may fail the
/// insphere test, when flips make it Delaunay.
fn restore_delaunay_until(
    arrays: &MeshArrays3,
    plc: &Plc3,
    max_steiner_points: Option<usize>,
    stop: Option<Arc<AtomicBool>>,
    start: Option<(Triangulation3, Vec<FacetRef>)>,
) -> Result<Mesh3, Error> {
    if stop.as_ref().is_some_and(|s| s.load(Ordering::Relaxed)) {
        return Err(Error::Restoration(RecoveryError::Cancelled));
    }
    let surface = Plc3 {
        points: arrays.coords.clone(),
        point_markers: arrays.point_markers.clone(),
        triangles: arrays
            .faces
            .iter()
            .zip(&arrays.face_markers)
            .zip(&arrays.face_facets)
            .map(|((&v, &marker), &facet)| SurfaceTriangle { v, marker, facet })
            .collect(),
        holes: plc.holes.clone(),
        regions: plc.regions.clone(),
        first_index: plc.first_index,
        marker_names: Vec::new(),
    };
    // The domain's side of each boundary triangle, from the tetrahedron on it.
    let mut opposite: HashMap<[u32; 3], u32> =
        HashMap::with_capacity_and_hasher(2 * arrays.faces.len(), Default::default());
    let on = &arrays.on_boundary;
    for t in &arrays.tets {
        if t.iter().filter(|&&v| on[v as usize]).count() < 3 {
            continue; // no face of it is on the boundary
        }
        for k in 0..4 {
            let mut f = [t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]];
            if f.iter().all(|&v| on[v as usize]) {
                f.sort_unstable();
                opposite.insert(f, t[k]);
            }
        }
    }
    let sides = arrays
        .faces
        .iter()
        .map(|t| {
            let mut key = *t;
            key.sort_unstable();
            opposite.get(&key).map_or(0.0, |&d| {
                let p = [t[0], t[1], t[2], d].map(|i| arrays.coords[i as usize]);
                match orient3d(p[0], p[1], p[2], p[3]) {
                    Sign::Positive => 1.0,
                    Sign::Negative => -1.0,
                    Sign::Zero => 0.0,
                }
            })
        })
        .collect();
    let mut recovery = BoundaryRecovery3::new(RecoveryMethod3::Conforming)
        .trusted_surface()
        // The surface is the mesh's own boundary, already recovered once: merging nearly
        // coplanar facets (the fallback for costly input surfaces) would move that boundary,
        // and looking for them took a tenth of the restoration on cheese and turbine.
        .coplanar_fallback(false)
        .with_domain_sides(sides);
    if let Some(n) = max_steiner_points {
        recovery = recovery.max_steiner_points(n);
    }
    // (Stopped here too: building the surface took a while, and the flips and what follows
    // them up to recovery's own checks take longer.)
    if stop.as_ref().is_some_and(|s| s.load(Ordering::Relaxed)) {
        return Err(Error::Restoration(RecoveryError::Cancelled));
    }
    let start = start.and_then(|(t, seeds)| delaunay_by_flips(t, seeds, arrays));
    if let Some(stop) = stop {
        recovery = recovery.cancel_on(stop);
    }
    match start {
        Some(tri) => recovery.run_on(&surface, tri),
        None => recovery.run(&surface),
    }
    .map_err(Error::Restoration)
}

/// `tri`, a tetrahedralisation of the points of `arrays` (the mesh's, as it was when they
/// were taken) whose faces pass the insphere test but for some of `seeds`, made Delaunay by
/// flips with no face protected: the tetrahedralisation that triangulating the points again
/// would build, in a fraction of the time (armadillo's 84,686 points: 219 ms to triangulate).
/// `None` if its input points are not those of `arrays` in order, or if the flips stop short.
fn delaunay_by_flips(
    tri: Triangulation3,
    seeds: Vec<FacetRef>,
    arrays: &MeshArrays3,
) -> Option<Triangulation3> {
    let same = tri.num_input_points() == arrays.vertex.len()
        && arrays
            .vertex
            .iter()
            .enumerate()
            .all(|(k, &v)| tri.input_index(v) == k);
    if !same {
        return None;
    }
    let mut ct = ConstrainedTriangulation3::new(tri);
    ct.make_delaunay_from(seeds, |_| true)
        .left
        .is_empty()
        .then(|| ct.into_triangulation())
}

impl MeshRun3 {
    /// A readable summary: the recovery history (Table 2), the generation passes, the mesh
    /// size and the time per stage.
    pub fn summary(&self) -> String {
        let mut s = String::new();
        s.push_str(&format!("{}", self.recovery));
        if let Some(g) = &self.generation {
            s.push_str(&format!(
                "point generation: {} points added, {} refused\n{g}",
                g.points_added(),
                g.refused()
            ));
        }
        if self.generation.is_some() {
            s.push_str(&format!(
                "quality refinement: {} points added\n",
                self.refined
            ));
        }
        if let Some(n) = self.volume_limited {
            s.push_str(&format!(
                "regional volume limits: {n} points added at centroids\n"
            ));
            if self.volume_limit_exceeded > 0 {
                s.push_str(&format!(
                    "warning: {} tetrahedra are still larger than their region's limit (their \
                     centroids refused where the mesh would not stay Delaunay next to the \
                     surface)\n",
                    self.volume_limit_exceeded
                ));
            }
        }
        match &self.restoration {
            Some(Restoration3::Flips {
                flips: f,
                split_edges,
                surface_points,
                undone,
            }) => s.push_str(&format!(
                "delaunay restoration: {} faces failed; {} flips (2-3: {}, 3-2: {}, 4-4: {}), \
                 {} edges split ({} on the surface){}{}\n",
                f.failing,
                f.flips(),
                f.two_three,
                f.three_two,
                f.four_four,
                split_edges,
                surface_points,
                if *undone > 0 {
                    format!(", {undone} smoothing moves undone")
                } else {
                    String::new()
                },
                if f.left.is_empty() {
                    String::new()
                } else {
                    format!(
                        "; {} faces by the constrained boundary kept as they are",
                        f.left.len()
                    )
                }
            )),
            Some(Restoration3::Incomplete {
                flips: f,
                split_edges,
                surface_points,
                reason,
            }) => s.push_str(&format!(
                "delaunay restoration incomplete: {} faces failed; {} flips, {} edges split ({} \
                 on the surface); triangulating again failed ({reason}), so the mesh is kept as \
                 flipped: warning: {} faces still fail the insphere test (the mesh is valid, \
                 not Delaunay there)\n",
                f.failing,
                f.flips(),
                split_edges,
                surface_points,
                f.left.len()
            )),
            Some(Restoration3::Retriangulated { history }) => s.push_str(&format!(
                "delaunay restoration: triangulated again, {} surface points added ({} on \
                 edges, {} in faces)\n",
                history.points_added(),
                history.edge_points,
                history.face_points
            )),
            None => {}
        }
        if self.flat_removed > 0 {
            s.push_str(&format!(
                "flat elements on the surface taken out (facet diagonal swapped): {}\n",
                self.flat_removed
            ));
        }
        if self.flat_split > 0 {
            s.push_str(&format!(
                "flat elements inside split at their centroids: {}\n",
                self.flat_split
            ));
        }
        if self.duplicate_walls > 0 {
            s.push_str(&format!(
                "triangles given twice (opposite orientations, one marker) kept once as \
                 internal walls: {}\n",
                self.duplicate_walls
            ));
        }
        if let (Some(st), Some(q)) = (&self.smoothing, &self.quality_before_smoothing) {
            s.push_str(&format!(
                "smoothing: {st}\n  before: min dihedral {:.2}°, max {:.2}°, {} slivers under 5°\n",
                q.min_dihedral, q.max_dihedral, q.slivers
            ));
        }
        if let Some(f) = &self.sliver_flips {
            s.push_str(&format!(
                "sliver flips: {} edges and {} faces flipped away; elements below the angle {} -> {}\n",
                f.edge_flips, f.face_flips, f.below_before, f.below_after
            ));
        }
        s.push_str(&format!(
            "mesh: {} points, {} tetrahedra, {} boundary triangles\n",
            self.arrays.coords.len(),
            self.arrays.tets.len(),
            self.arrays.faces.len()
        ));
        s.push_str(&format!("{}", self.quality));
        s.push_str("time per stage:\n");
        for (name, t) in &self.timings {
            s.push_str(&format!("  {name:<26} {t:.6} s\n"));
        }
        let total: f64 = self.timings.iter().map(|t| t.1).sum();
        s.push_str(&format!("  {:<26} {total:.6} s\n", "total"));
        s
    }
}

/// The input extensions [`read_plc3`] reads (a `.poly` is 3D when its nodes are).
pub const SURFACE_INPUTS: &str = ".smesh, .poly (3D), .off, .stl, .obj, .ply, .mesh, .msh";

/// The output formats of [`MeshRun3::write`], by extension.
pub const MESH3_OUTPUTS: &str =
    ".vtu, .ele (.node/.ele/.face), .msh, .mesh, .su2, or a directory named polyMesh (OpenFOAM)";

/// The surface of a [`Plc3`] as a file's contents (for [`delmesh_io::write_smesh`]): each
/// triangle a facet of its own, with its marker; holes, regions and marker names as they are,
/// numbered from 1. (A facet made of several triangles becomes several facets: the demos'
/// meshes are the same either way, tested.)
pub fn surface_from_plc3(plc: &Plc3) -> delmesh_io::SurfaceFile {
    delmesh_io::SurfaceFile {
        points: plc.points.clone(),
        point_markers: (!plc.point_markers.is_empty()).then(|| plc.point_markers.clone()),
        facets: plc
            .triangles
            .iter()
            .map(|t| delmesh_io::SurfaceFacet {
                polygons: vec![t.v.to_vec()],
                holes: Vec::new(),
                marker: t.marker,
                line: 0,
            })
            .collect(),
        holes: plc.holes.clone(),
        regions: plc
            .regions
            .iter()
            .map(|r| delmesh_io::SurfaceRegion {
                point: r.point,
                attribute: r.attribute,
                max_volume: r.max_volume,
            })
            .collect(),
        marker_names: plc.marker_names.clone(),
        tetrahedra: Vec::new(),
        tetrahedron_regions: Vec::new(),
        first_index: 1,
    }
}

/// Whether `path` names a 3D surface input by its extension (a `.poly` file is decided by its
/// contents, see [`read_plc3`]).
pub fn is_surface_input(path: &Path) -> bool {
    matches!(
        extension(path).as_str(),
        "smesh" | "off" | "stl" | "obj" | "ply" | "mesh" | "msh"
    )
}

fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}

/// Reads a surface file (by extension, see [`SURFACE_INPUTS`]) as a [`Plc3`].
///
/// # Errors
/// The file cannot be read or is malformed (file and line in the message), or it has a
/// polygonal facet that cannot be triangulated (named with its line).
pub fn read_plc3(path: &Path) -> Result<Plc3, Error> {
    let surface = delmesh_io::read_surface(path)?;
    plc3_from_surface(surface, path)
}

/// The [`Plc3`] of a parsed surface file: triangles keep their facet's marker and number;
/// polygonal facets (with holes) are triangulated in their plane. The file's arrays move into
/// the result (no copy).
///
/// # Errors
/// A polygonal facet that is not planar or cannot be triangulated (named in the file's
/// numbering).
pub fn plc3_from_surface(surface: SurfaceFile, path: &Path) -> Result<Plc3, Error> {
    let SurfaceFile {
        points,
        point_markers,
        facets,
        holes,
        regions,
        marker_names,
        first_index,
        ..
    } = surface;
    let facets: Vec<PolygonFacet> = facets
        .into_iter()
        .map(|f| PolygonFacet {
            polygons: f.polygons,
            holes: f.holes,
            marker: f.marker,
        })
        .collect();
    let mut plc =
        Plc3::from_polygon_facets(points, &facets, first_index).map_err(|e| Error::Input {
            file: path.to_path_buf(),
            message: e.to_string(),
        })?;
    plc.point_markers = point_markers.unwrap_or_default();
    plc.marker_names = marker_names;
    plc.holes = holes;
    plc.regions = regions
        .iter()
        .map(|r| RegionSeed3 {
            point: r.point,
            attribute: r.attribute,
            max_volume: r.max_volume,
        })
        .collect();
    Ok(plc)
}

impl MeshRun3 {
    /// Writes the mesh to `out`, the format chosen by its extension (see [`MESH3_OUTPUTS`]):
    /// `.vtu` (tetrahedra with cell data `region`, and `X.boundary.vtu` with the boundary
    /// triangles and their `marker`), `.ele` (TetGen's `X.node`, `X.ele`, `X.face` with markers
    /// and region attributes, numbered from 1), `.msh` (gmsh 4.1 with physical groups),
    /// `.mesh` (Medit), `.su2`; a path named `polyMesh` is an OpenFOAM mesh directory (a patch
    /// per marker, see [`delmesh_io::write_foam`]). Returns the files written.
    ///
    /// # Errors
    /// An unsupported extension, or a file that cannot be written.
    pub fn write(&self, out: &Path) -> Result<Vec<PathBuf>, Error> {
        let a = &self.arrays;
        let names: Vec<(i32, &str)> = self
            .marker_names
            .iter()
            .map(|(m, n)| (*m, n.as_str()))
            .collect();
        let mesh = TetMeshOut {
            coords: &a.coords,
            tets: &a.tets,
            regions: Some(&a.regions),
            faces: &a.faces,
            face_markers: &a.face_markers,
            point_markers: Some(&a.point_markers),
            marker_names: &names,
        };
        if delmesh_io::is_polymesh(out) {
            return Ok(delmesh_io::write_foam(out, &mesh)?);
        }
        match extension(out).as_str() {
            "vtu" => {
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
                const EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
                let edges = a
                    .tets
                    .iter()
                    .flat_map(|t| EDGES.map(|(i, j)| (t[i] as usize, t[j] as usize)));
                let spacing = crate::mesh2d::fill_spacing(spacing, edges, |u, v| {
                    crate::geometry3::dist(a.coords[u], a.coords[v])
                });
                // (A point in no tetrahedron would have none: the field is left out then.)
                let point_data: Vec<(&str, &[f64])> = if spacing.iter().all(|h| h.is_finite()) {
                    vec![("spacing", &spacing)]
                } else {
                    Vec::new()
                };
                let dihedral = min_dihedrals(a);
                Ok(delmesh_io::write_tet_mesh_vtu_with(
                    out,
                    &mesh,
                    &point_data,
                    &[("min_dihedral", &dihedral)],
                )?)
            }
            "ele" | "node" | "face" | "msh" | "mesh" | "su2" => {
                Ok(delmesh_io::write_tet_mesh(out, &mesh)?)
            }
            ext => Err(Error::UnsupportedFormat {
                file: out.to_path_buf(),
                ext: if ext.is_empty() {
                    "(none)".into()
                } else {
                    format!(".{ext}")
                },
                supported: MESH3_OUTPUTS,
            }),
        }
    }

    /// The run's report as JSON (`--report report.json`): the recovery history (Table 2),
    /// the generation passes, sizes and seconds per stage.
    pub fn report_json(&self) -> String {
        let list = |v: Vec<String>| format!("[{}]", v.join(", "));
        let history = |h: &RecoveryHistory3| {
            let steps = list(
                h.steps
                    .iter()
                    .map(|s| match *s {
                        RecoveryStep::Edges {
                            points,
                            tetrahedra,
                            surface_edges,
                            missing_edges,
                        } => format!(
                            "{{\"edges\": {{\"points\": {points}, \"tetrahedra\": {tetrahedra}, \"surface_edges\": {surface_edges}, \"missing_edges\": {missing_edges}}}}}"
                        ),
                        RecoveryStep::Faces {
                            surface_faces,
                            missing_faces,
                        } => format!(
                            "{{\"faces\": {{\"surface_faces\": {surface_faces}, \"missing_faces\": {missing_faces}}}}}"
                        ),
                    })
                    .collect(),
            );
            format!(
                "{{\"surface_points\": {}, \"field_points\": {}, \"duplicates_merged\": {}, \"surface_faces\": {}, \"planar_flips\": {}, \"surface_edges\": {}, \"initial_tetrahedra\": {}, \"steps\": {steps}, \"edge_points\": {}, \"face_points\": {}, \"final_surface_edges\": {}, \"final_surface_faces\": {}, \"flips\": {}, \"flipped_in\": {}, \"constrained_fallback\": {}, \"coplanar_merged_after\": {}, \"merged_to_single_precision\": {}, \"tetrahedra_outside\": {}, \"tetrahedra_inside\": {}}}",
                h.surface_points,
                h.field_points,
                h.merged_points.len(),
                h.surface_faces,
                h.planar_flips,
                h.surface_edges,
                h.initial_tetrahedra,
                h.edge_points,
                h.face_points,
                h.final_surface_edges,
                h.final_surface_faces,
                h.flips,
                h.flipped_in,
                h.constrained_fallback,
                h.coplanar_merged_after
                    .map_or_else(|| "null".to_string(), |n| n.to_string()),
                h.merged_to_single_precision,
                h.tetrahedra_outside,
                h.tetrahedra_inside
            )
        };
        let generation = self.generation.as_ref().map_or("null".to_string(), |g| {
            list(
                g.passes
                    .iter()
                    .map(|p| {
                        format!(
                            "{{\"candidates\": {}, \"accepted\": {}, \"refused\": {}, \"elements\": {}}}",
                            p.candidates, p.accepted, p.refused, p.elements
                        )
                    })
                    .collect(),
            )
        });
        let restoration = match &self.restoration {
            Some(Restoration3::Flips {
                flips: f,
                split_edges,
                surface_points,
                undone,
            }) => format!(
                "{{\"method\": \"flips\", \"failing\": {}, \"two_three\": {}, \
                 \"three_two\": {}, \"four_four\": {}, \"split_edges\": {split_edges}, \
                 \"surface_points\": \
                 {surface_points}, \"undone\": {undone}, \"left\": {}, \"recovery\": null}}",
                f.failing,
                f.two_three,
                f.three_two,
                f.four_four,
                f.left.len()
            ),
            Some(Restoration3::Retriangulated { history: h }) => format!(
                "{{\"method\": \"retriangulated\", \"recovery\": {}}}",
                history(h)
            ),
            Some(Restoration3::Incomplete {
                flips: f,
                split_edges,
                surface_points,
                reason,
            }) => format!(
                "{{\"method\": \"incomplete\", \"failing\": {}, \"two_three\": {}, \
                 \"three_two\": {}, \"four_four\": {}, \"split_edges\": {split_edges}, \
                 \"surface_points\": {surface_points}, \"left\": {}, \"reason\": {}, \
                 \"recovery\": null}}",
                f.failing,
                f.two_three,
                f.three_two,
                f.four_four,
                f.left.len(),
                json_string(reason)
            ),
            None => "null".to_string(),
        };
        let sliver_flips = match &self.sliver_flips {
            Some(f) => format!(
                "{{\"edge_flips\": {}, \"face_flips\": {}, \"below_before\": {}, \"below_after\": {}}}",
                f.edge_flips, f.face_flips, f.below_before, f.below_after
            ),
            None => "null".to_string(),
        };
        let timings = self
            .timings
            .iter()
            .map(|(n, t)| format!("\"{n}\": {t}"))
            .collect::<Vec<_>>()
            .join(", ");
        format!(
            "{{\n  \"points\": {},\n  \"tetrahedra\": {},\n  \"boundary_triangles\": {},\n  \"recovery\": {},\n  \"generation\": {generation},\n  \"restoration\": {restoration},\n  \"flat_removed\": {},\n  \"flat_split\": {},\n  \"duplicate_walls\": {},\n  \"sliver_flips\": {sliver_flips},\n  \"quality_before_smoothing\": {},\n  \"quality\": {},\n  \"seconds\": {{{timings}}}\n}}\n",
            self.arrays.coords.len(),
            self.arrays.tets.len(),
            self.arrays.faces.len(),
            history(&self.recovery),
            self.flat_removed,
            self.flat_split,
            self.duplicate_walls,
            self.quality_before_smoothing
                .as_ref()
                .map_or("null".to_string(), QualityReport3::to_json),
            self.quality.to_json(),
        )
    }
}

/// Reads a 3D background mesh for [`Spacing3::Background`]: a `.vtu` of tetrahedra with the
/// point field `field` (default `spacing`).
///
/// # Errors
/// The file cannot be read, is not 3D, has no such field, or its values are not valid spacings.
pub fn read_background3(path: &Path, field: Option<&str>) -> Result<BackgroundMesh3, Error> {
    let (points, tets, values) = read_field3(path, field.unwrap_or("spacing"))?;
    BackgroundMesh3::new(points, tets, values).map_err(|e| Error::Spacing3 {
        file: path.to_path_buf(),
        source: e,
    })
}

/// Reads a previous 3D mesh (`.vtu`) and turns its point field `field` (e.g. Mach or pressure)
/// into spacing by its gradient: mesh adaptation (R11).
///
/// # Errors
/// As [`read_background3`].
pub fn read_adaptation3(
    path: &Path,
    field: &str,
    adaptation: &Adaptation,
) -> Result<BackgroundMesh3, Error> {
    let (points, tets, values) = read_field3(path, field)?;
    BackgroundMesh3::from_solution(points, tets, &values, adaptation).map_err(|e| Error::Spacing3 {
        file: path.to_path_buf(),
        source: e,
    })
}

type FieldData3 = (Vec<[f64; 3]>, Vec<[u32; 4]>, Vec<f64>);

fn read_field3(path: &Path, field: &str) -> Result<FieldData3, Error> {
    let mesh = match extension(path).as_str() {
        "vtu" => delmesh_io::read_vtu(path)?,
        "vtk" => delmesh_io::read_vtk_legacy(path)?,
        ext => {
            return Err(Error::UnsupportedMeshInput {
                file: path.to_path_buf(),
                ext: format!(".{ext}"),
                supported: ".vtu, .vtk",
            })
        }
    };
    if mesh.dim != 3 {
        return Err(Error::MeshDimension {
            file: path.to_path_buf(),
            dim: mesh.dim,
            expected: 3,
        });
    }
    let values = crate::mesh2d::point_field(&mesh, field, path)?;
    let points: Vec<[f64; 3]> = mesh
        .coords
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    // Cells of no volume (a solver's collapsed hexahedra, split) hold nothing to interpolate.
    let tets = mesh
        .cells
        .chunks_exact(4)
        .map(|t| [t[0], t[1], t[2], t[3]])
        .filter(|t: &[u32; 4]| {
            let p = t.map(|v| points[v as usize]);
            orient3d(p[0], p[1], p[2], p[3]) != Sign::Zero
        })
        .collect();
    Ok((points, tets, values.clone()))
}

/// The most rounds of background splits (each halves a triangle at most: 8 rounds take a
/// triangle 256 spacings long to the spacing).
const BACKGROUND_SPLIT_ROUNDS: usize = 8;

/// For each surface triangle, the cap [`split_surface`] splits it to in one round (and the
/// number of equilateral triangles the background asks for over the whole surface): half its
/// longest edge where that is over four times the finest spacing `background` asks on it (the
/// rounds grade), else that spacing; or infinity (no split) where no edge is longer than one
/// and a half times it (as 2D boundary edges stay whole: a surface made at about the
/// background's spacing is kept).
/// The spacing is sampled at its corners, edge mid-points and centroid, then on a finer grid
/// where the triangle is larger than it.
fn background_caps(background: &BackgroundMesh3, plc: &Plc3) -> (Vec<f64>, f64) {
    let caps: Vec<(f64, f64)> = plc
        .triangles
        .par_iter()
        .map(|t| {
            let p = t.v.map(|i| plc.points[i as usize]);
            let at = |w: [f64; 3]| {
                background
                    .spacing_at([0, 1, 2].map(|k| w[0] * p[0][k] + w[1] * p[1][k] + w[2] * p[2][k]))
            };
            // Barycentric grid of k subdivisions.
            let finest = |k: usize| {
                let mut h = f64::INFINITY;
                for i in 0..=k {
                    for j in 0..=k - i {
                        let (a, b) = (i as f64 / k as f64, j as f64 / k as f64);
                        h = h.min(at([a, b, 1.0 - a - b]));
                    }
                }
                h.min(at([1.0 / 3.0; 3]))
            };
            let longest = (0..3)
                .map(|k| crate::geometry3::dist(p[k], p[(k + 1) % 3]))
                .fold(0.0, f64::max);
            let mut h = finest(2);
            if longest > h {
                let k = (2.0 * longest / h).ceil().clamp(2.0, 16.0) as usize;
                h = h.min(finest(k));
            }
            let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
            let asked = 0.5 * dot(n, n).sqrt() / (h * h * 3f64.sqrt() / 4.0);
            let cap = if longest > 4.0 * h {
                0.5 * longest
            } else if longest > 1.5 * h {
                h
            } else {
                f64::INFINITY
            };
            (cap, asked)
        })
        .collect();
    let asked = caps.iter().map(|c| c.1).sum();
    (caps.into_iter().map(|c| c.0).collect(), asked)
}

/// The smallest dihedral angle of each tetrahedron, in degrees (a cell field for `.vtu`).
fn min_dihedrals(a: &MeshArrays3) -> Vec<f64> {
    a.tets
        .iter()
        .map(|t| dihedral_range(&t.map(|v| a.coords[v as usize])).0)
        .map(|d| if d.is_finite() { d } else { 0.0 })
        .collect()
}

/// `text` as a JSON string literal.
fn json_string(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for ch in text.chars() {
        match ch {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
