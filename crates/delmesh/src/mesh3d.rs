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

use std::time::Instant;

use delmesh_boundary_recovery::{
    BoundaryRecovery3, Mesh3, MeshArrays3, Plc3, RecoveryHistory3, RecoveryMethod3, SurfaceTriangle,
};
use delmesh_point_gen::{GenerationReport3, PointGeneration3};

use crate::Error;

/// Options of the 3D pipeline; `Default` is the paper's method with its usual parameters.
#[derive(Clone, Debug)]
pub struct MeshOptions3 {
    /// How the surface is recovered.
    pub recovery: RecoveryMethod3,
    /// Field points from an external source (R9); those outside the domain are dropped.
    pub extra_points: Vec<[f64; 3]>,
    /// Automatic point generation (`None`: the surface and extra points only).
    pub generation: Option<PointGeneration3>,
    /// Most points boundary recovery may add before it gives up (`None`: its default bound).
    pub max_steiner_points: Option<usize>,
    /// At the end, triangulate the final points again and recover the refined surface, so the
    /// mesh is exactly Delaunay (see [`restore_delaunay`]).
    pub delaunay: bool,
}

impl Default for MeshOptions3 {
    fn default() -> Self {
        MeshOptions3 {
            recovery: RecoveryMethod3::Conforming,
            extra_points: Vec::new(),
            generation: Some(PointGeneration3::default()),
            max_steiner_points: None,
            delaunay: true,
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
    /// The recovery history of the Delaunay restoration, if it ran.
    pub restoration: Option<RecoveryHistory3>,
    /// Seconds spent in each stage, in order.
    pub timings: Vec<(&'static str, f64)>,
}

/// Runs the pipeline on `plc`.
///
/// # Errors
/// Invalid input (named in the input's numbering), a surface that could not be recovered, a
/// domain with no element, or a bad option.
pub fn mesh_plc3(plc: &Plc3, options: &MeshOptions3) -> Result<MeshRun3, Error> {
    let mut timings = Vec::new();
    let mut clock = Instant::now();
    let mut lap = |name: &'static str, timings: &mut Vec<(&'static str, f64)>| {
        timings.push((name, clock.elapsed().as_secs_f64()));
        clock = Instant::now();
    };
    let mut recovery =
        BoundaryRecovery3::new(options.recovery).with_points(options.extra_points.clone());
    if let Some(n) = options.max_steiner_points {
        recovery = recovery.max_steiner_points(n);
    }
    let mut mesh = recovery.run(plc)?;
    lap("boundary recovery", &mut timings);
    let generation = match &options.generation {
        Some(settings) => {
            let report = settings.run(&mut mesh, |_, from_nodes| from_nodes)?;
            lap("point generation", &mut timings);
            Some(report)
        }
        None => None,
    };
    let recovery_history = mesh.history.clone();
    let mut arrays = mesh.to_arrays();
    let mut restoration = None;
    if options.delaunay && generation.is_some() {
        mesh = restore_delaunay(&arrays, plc, options.max_steiner_points)?;
        restoration = Some(mesh.history.clone());
        lap("delaunay restoration", &mut timings);
        arrays = mesh.to_arrays();
    }
    lap("output arrays", &mut timings);
    Ok(MeshRun3 {
        recovery: recovery_history,
        mesh,
        arrays,
        generation,
        restoration,
        timings,
    })
}

/// The Delaunay tetrahedralisation of the points of `arrays`, conforming to its boundary
/// triangles: they become the input surface (keeping the markers and the input facets of `plc`,
/// whose holes and region seeds classify the cells), so recovery only splits the few that a
/// nearby interior point now hides. Point generation near protected faces and smoothing both
/// leave cells whose circumsphere holds a vertex; this puts every tetrahedron back to an empty
/// circumsphere.
///
/// # Errors
/// As [`BoundaryRecovery3::run`].
pub fn restore_delaunay(
    arrays: &MeshArrays3,
    plc: &Plc3,
    max_steiner_points: Option<usize>,
) -> Result<Mesh3, Error> {
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
    };
    let mut recovery = BoundaryRecovery3::new(RecoveryMethod3::Conforming);
    if let Some(n) = max_steiner_points {
        recovery = recovery.max_steiner_points(n);
    }
    Ok(recovery.run(&surface)?)
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
        if let Some(r) = &self.restoration {
            s.push_str(&format!(
                "delaunay restoration: {} surface points added ({} on edges, {} in faces)\n",
                r.points_added(),
                r.edge_points,
                r.face_points
            ));
        }
        s.push_str(&format!(
            "mesh: {} points, {} tetrahedra, {} boundary triangles\n",
            self.arrays.coords.len(),
            self.arrays.tets.len(),
            self.arrays.faces.len()
        ));
        s.push_str("time per stage:\n");
        for (name, t) in &self.timings {
            s.push_str(&format!("  {name:<26} {t:.6} s\n"));
        }
        let total: f64 = self.timings.iter().map(|t| t.1).sum();
        s.push_str(&format!("  {:<26} {total:.6} s\n", "total"));
        s
    }
}
