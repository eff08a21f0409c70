//! [`BoundaryRecovery3`]: from a [`Plc3`] to a boundary-conforming tetrahedral [`Mesh3`]
//! (the paper's §4.1 in 3D: R6, R8, R9).
//!
//! The surface points (and any field points given) are triangulated; then the paper's edge and
//! face checking runs until every surface triangle is a union of faces of the tetrahedralisation:
//!
//! 0. **Planar patches.** Where two surface triangles of one polygon facet (or, with
//!    [`BoundaryRecovery3::merge_coplanar`], of any two facets with the same marker) lie exactly
//!    in one plane, their shared diagonal is flipped to the Delaunay one, or to the one the
//!    tetrahedralisation holds (see [`crate::planar`]): the region is the same, and the diagonal
//!    the input happened to have need not be recovered.
//! 1. **Edges.** Every surface edge (a *segment*) must be a union of tetrahedron edges. Each
//!    missing sub-segment is split, and the passes repeat until none is missing. The split is
//!    the mid-point, except next to an input vertex, where it is the point at the power-of-two
//!    distance from that vertex nearest the middle (the concentric shells of Ruppert and
//!    Shewchuk): segments that meet at a small angle are then split at equal distances from
//!    their shared vertex and stop hiding each other's sub-segments, which is what makes the
//!    splitting end.
//! 2. **Faces.** Each surface triangle (a *facet*) is divided into sub-faces: the Delaunay
//!    triangulation, in the facet's plane, of its corners, the points on its edges and the points
//!    added inside it, constrained to its sub-segments. Where the tetrahedralisation chose the
//!    other diagonal of a (nearly) co-circular quadrilateral, the sub-faces follow it. A missing
//!    sub-face gets the paper's centroid point, and the edges are checked again (a point on a
//!    face can hide a nearby sub-segment).
//! 3. **Flat tetrahedra on the surface.** Four nearly co-circular surface points make a flat
//!    tetrahedron whose two pairs of faces both lie on the surface. Within one facet the pair
//!    of sub-faces that leaves it outside the domain is chosen; across the edge between two
//!    nearly coplanar facets that edge is split once (the point lies in its circumsphere), so
//!    the mesh does not keep it as a sliver.
//!
//! Away from input vertices a missing sub-segment is split at the foot of the perpendicular
//! from the vertex that hides it most, rather than at its mid-point, when that foot is well
//! inside: one split then frees both halves (fewer points than the paper's rule).
//!
//! Every point added lies on the input surface (to rounding): sub-segment points are placed by
//! their parameter along the input edge, face points by barycentric coordinates in the input
//! triangle, so no error accumulates. The number of added points is bounded
//! ([`BoundaryRecovery3::max_steiner_points`]); past the bound, or when a sub-segment gets
//! shorter than double precision can split, recovery stops with an error naming the facets
//! that resisted instead of looping.
//!
//! **Coplanar fallback** ([`BoundaryRecovery3::coplanar_fallback`], on by default): a surface
//! whose triangles as given would cost more than [`costly_bound`] points, and that has
//! coplanar (or, to rounding, nearly coplanar) neighbours with one marker, is recovered again
//! from the same first tetrahedralisation with them merged, as TetGen merges coplanar facets
//! by default. Should that fail too, the triangles as given get the whole bound after all;
//! and should they fail, a surface all of single precision (binary STL) is merged to its own
//! rounding, with a warning (the surface moves by less than `2^-20` of its coordinates).
//!
//! **Constrained recovery** ([`RecoveryMethod3::Constrained`], beyond the paper): each missing
//! sub-segment, then each missing sub-face, is first made present by flips
//! ([`ConstrainedTriangulation3::flip_in_edge`], [`ConstrainedTriangulation3::flip_in_face`];
//! never removing a sub-segment or a sub-face found present); a point is added, as above, only
//! where the flips stop short: by Bowyer–Watson where the cells around it are still Delaunay,
//! else by splitting what it lies in, then flipping back to the Delaunay property where that
//! removes no sub-segment ([`ConstrainedTriangulation3::insert_growing`]). Most surfaces then need far fewer points
//! (a CAD surface of long thin triangles: tens instead of thousands), and the mesh is not
//! Delaunay next to what was flipped in. Splitting after flips is not bound to end as the
//! Delaunay splitting is: where a sub-segment would get shorter than 1/1024 of its segment,
//! more points than 4 per surface point (plus 1,000) are added, or three face rounds in a row
//! each leave more faces missing, the conforming recovery runs instead, from the same first
//! tetrahedralisation ([`RecoveryHistory3::constrained_fallback`]).
//!
//! The recovered faces are then protected ([`ConstrainedTriangulation3`]) and the cells are
//! classified by the flood fill of [`crate::classify3`].

use crate::apriori3::a_priori_points;
use crate::classify::{overridden_message, SeedName};
use crate::classify3::{classify3, OUTSIDE};
use crate::error::RecoveryError;
use crate::planar::{flip_planar_diagonals, Flatness, Patches};
use crate::plc3::Plc3;
use crate::recovery::merged_list;
use crate::surface::{check_surface, CheckedSurface, PointLocation};
use delmesh_delaunay_core::{
    find_face_in, CellId, ConstrainedTriangulation2, ConstrainedTriangulation3, FacetRef, FlipIn,
    Insertion, StarSearch, Triangulation2, Triangulation3, TriangulationError, VertexId,
};
use delmesh_predicates::{orient2d, orient3d, Sign};
use rayon::prelude::*;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};
use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// How the surface is recovered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RecoveryMethod3 {
    /// The paper's a-posteriori edge and face checking (R6).
    #[default]
    Conforming,
    /// A point for every boundary face first (R7), then edge and face checking for what is
    /// left.
    APriori,
    /// Beyond the paper: missing edges and faces are first recovered by flips, which add no
    /// point (a constrained, not conforming, recovery: the mesh is not Delaunay next to
    /// them); a point is added only where the flips stop short. If that does not finish (a
    /// sub-segment under 1/1024 of its edge, more than 4 points per surface point plus 1,000,
    /// or three face rounds in a row each leaving more faces missing), the conforming method
    /// runs instead.
    Constrained,
}

/// One step of the recovery history: the rows of the paper's Table 2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RecoveryStep {
    /// One pass of edge checking.
    Edges {
        /// Vertices in the triangulation at the start of the pass.
        points: usize,
        /// Tetrahedra (finite cells, exterior included) at the start of the pass.
        tetrahedra: usize,
        /// Surface edges (sub-segments) to be present.
        surface_edges: usize,
        /// Of those, how many were missing.
        missing_edges: usize,
    },
    /// One pass of face checking.
    Faces {
        /// Surface sub-faces to be present.
        surface_faces: usize,
        /// Of those, how many were missing.
        missing_faces: usize,
    },
}

/// What 3D recovery did, in the shape of the paper's Table 2.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RecoveryHistory3 {
    /// The method used.
    pub method: RecoveryMethod3,
    /// Distinct surface points of the input.
    pub surface_points: usize,
    /// Field points given with the surface (after duplicates are merged).
    pub field_points: usize,
    /// Input points that repeat an earlier one exactly, merged into it: (duplicate, first),
    /// in the input's numbering.
    pub merged_points: Vec<(u64, u64)>,
    /// Input triangles reversed to orient their closed surface consistently.
    pub reoriented_triangles: usize,
    /// Surface edges where three or more triangles meet: internal walls between regions
    /// (see [`crate::Junction`]).
    pub junction_edges: usize,
    /// Surface triangles of the input.
    pub surface_faces: usize,
    /// Diagonals flipped in planar patches of the surface before recovery (the triangles of
    /// one polygon facet, or with [`BoundaryRecovery3::merge_coplanar`] any coplanar
    /// neighbours with the same marker): the re-triangulated surface is what is recovered.
    pub planar_flips: usize,
    /// Edges of the input surface.
    pub surface_edges: usize,
    /// Tetrahedra of the first triangulation (all points, before recovery).
    pub initial_tetrahedra: usize,
    /// The passes, in order.
    pub steps: Vec<RecoveryStep>,
    /// Points added on surface edges.
    pub edge_points: usize,
    /// Points added inside surface faces.
    pub face_points: usize,
    /// A-priori points placed beside the surface (APriori only).
    pub a_priori_points: usize,
    /// Surface triangles for which no a-priori point was found (APriori only).
    pub a_priori_rejected: usize,
    /// Field points left out because they lie exactly on the surface.
    pub field_points_on_surface: usize,
    /// Flat tetrahedra spanning two sub-faces of one facet that the choice of sub-faces put
    /// outside the domain.
    pub flat_tetrahedra_moved_out: usize,
    /// Flat tetrahedra in the domain spanning a surface edge, broken by splitting the edge
    /// (these points are counted in `edge_points`).
    pub flat_tetrahedra_split: usize,
    /// Sub-segments at the end (surface edges of the mesh).
    pub final_surface_edges: usize,
    /// Sub-faces at the end (boundary triangles of the mesh).
    pub final_surface_faces: usize,
    /// Flips made to recover edges and faces (Constrained only).
    pub flips: usize,
    /// Edges and faces recovered by flips alone (Constrained only).
    pub flipped_in: usize,
    /// The constrained recovery did not finish (see [`RecoveryMethod3::Constrained`]), and
    /// the conforming one ran instead (its passes and points are the ones reported).
    pub constrained_fallback: bool,
    /// Recovery of the facets as given was stopped after this many points (too many), and
    /// coplanar neighbours with one marker were merged instead
    /// ([`BoundaryRecovery3::coplanar_fallback`]; the passes and points reported are those of
    /// the merged surface).
    pub coplanar_merged_after: Option<usize>,
    /// Even the merged surface and the facets as given with the whole bound failed, and the
    /// surface, all of single precision (as binary STL is), was merged to its own rounding
    /// (triangles thinner than `2^-20` of their coordinates): the surface moved by less than
    /// that.
    pub merged_to_single_precision: bool,
    /// Tetrahedra outside the domain (and in holes) after classification.
    pub tetrahedra_outside: usize,
    /// Tetrahedra inside the domain after classification.
    pub tetrahedra_inside: usize,
    /// Hole and region seeds outside every closed surface, which do nothing: `("hole" |
    /// "region", number)` in the input's numbering (as in 2D).
    pub seeds_outside: Vec<SeedName>,
    /// Seeds another seed overrides, as (overridden, winner), as in 2D.
    pub seeds_overridden: Vec<(SeedName, SeedName)>,
}

impl RecoveryHistory3 {
    /// Points added on the surface, in total.
    pub fn points_added(&self) -> usize {
        self.edge_points + self.face_points
    }
}

impl fmt::Display for RecoveryHistory3 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let row = |f: &mut fmt::Formatter<'_>, label: &str, n: usize| -> fmt::Result {
            writeln!(f, "{label:<40}{n:>10}")
        };
        writeln!(f, "INPUT DATA")?;
        row(f, "No. of surface points:", self.surface_points)?;
        row(f, "No. of field points:", self.field_points)?;
        if self.field_points_on_surface > 0 {
            row(
                f,
                "  left out, on the surface:",
                self.field_points_on_surface,
            )?;
        }
        if !self.merged_points.is_empty() {
            row(f, "  duplicates merged:", self.merged_points.len())?;
            writeln!(f, "    {}", merged_list(&self.merged_points))?;
        }
        row(f, "No. of surface faces:", self.surface_faces)?;
        if self.reoriented_triangles > 0 {
            row(f, "  reoriented:", self.reoriented_triangles)?;
        }
        if self.junction_edges > 0 {
            row(f, "  wall junction edges:", self.junction_edges)?;
        }
        if self.planar_flips > 0 {
            row(
                f,
                "  diagonals flipped in planar patches:",
                self.planar_flips,
            )?;
        }
        row(f, "No. of surface edges:", self.surface_edges)?;
        if self.method == RecoveryMethod3::APriori {
            row(f, "No. of a-priori points:", self.a_priori_points)?;
            row(f, "  faces left to checking:", self.a_priori_rejected)?;
        }
        row(f, "No. of tetrahedra obtained:", self.initial_tetrahedra)?;
        if let Some(n) = self.coplanar_merged_after {
            writeln!(
                f,
                "Recovery of the facets as given stopped after {n} points: coplanar facets with one marker were merged"
            )?;
        }
        if self.merged_to_single_precision {
            writeln!(
                f,
                "warning: triangles flat to single precision (2^-20) were merged too: the surface moved by up to that"
            )?;
        }
        if self.method == RecoveryMethod3::Constrained {
            if self.constrained_fallback {
                writeln!(
                    f,
                    "Recovery by flips did not finish: the conforming recovery follows"
                )?;
            } else {
                row(f, "Edges and faces recovered by flips:", self.flipped_in)?;
                row(f, "  flips:", self.flips)?;
            }
        }
        writeln!(
            f,
            "After triangulation of all points: Edge recovery history"
        )?;
        let header = |f: &mut fmt::Formatter<'_>| {
            writeln!(
                f,
                "{:>9} {:>9} {:>11} {:>14} {:>14}",
                "Iteration", "Points", "Tetrahedra", "Surface Edges", "Missing Edges"
            )
        };
        header(f)?;
        let mut iteration = 0;
        let mut pending_faces: Option<(usize, usize)> = None;
        let mut points_before_faces = 0;
        for step in &self.steps {
            match *step {
                RecoveryStep::Edges {
                    points,
                    tetrahedra,
                    surface_edges,
                    missing_edges,
                } => {
                    if let Some((missing, _)) = pending_faces.take() {
                        writeln!(
                            f,
                            "To seal {missing} missing faces add: {} points",
                            points - points_before_faces
                        )?;
                        header(f)?;
                    }
                    iteration += 1;
                    writeln!(
                        f,
                        "{iteration:>9} {points:>9} {tetrahedra:>11} {surface_edges:>14} {missing_edges:>14}"
                    )?;
                    points_before_faces = points;
                }
                RecoveryStep::Faces {
                    surface_faces,
                    missing_faces,
                } => {
                    if missing_faces == 0 {
                        writeln!(f, "To seal missing faces add: 0 points")?;
                        writeln!(f, "All {surface_faces} surface faces recovered")?;
                    } else {
                        pending_faces = Some((missing_faces, surface_faces));
                    }
                }
            }
        }
        row(
            f,
            "No. of tetrahedra outside domain:",
            self.tetrahedra_outside,
        )?;
        row(
            f,
            "No. of tetrahedra inside domain:",
            self.tetrahedra_inside,
        )?;
        writeln!(f, "SUMMARY")?;
        row(f, "No. of surface points added:", self.points_added())?;
        row(f, "  on edges:", self.edge_points)?;
        row(f, "  inside faces:", self.face_points)?;
        row(
            f,
            "No. of surface edges added:",
            self.final_surface_edges.saturating_sub(self.surface_edges),
        )?;
        row(
            f,
            "No. of additional surface faces:",
            self.final_surface_faces.saturating_sub(self.surface_faces),
        )?;
        row(
            f,
            "No. of surface points:",
            self.surface_points + self.points_added(),
        )?;
        row(f, "No. of field points:", self.field_points)?;
        row(f, "No. of surface faces:", self.final_surface_faces)?;
        row(f, "No. of surface edges:", self.final_surface_edges)?;
        row(f, "No. of tetrahedra:", self.tetrahedra_inside)?;
        for (what, k) in &self.seeds_outside {
            writeln!(
                f,
                "warning: {what} seed {k} lies outside the domain (outside every closed \
                 surface) and does nothing"
            )?;
        }
        for &(seed, by) in &self.seeds_overridden {
            writeln!(f, "warning: {}", overridden_message(seed, by))?;
        }
        Ok(())
    }
}

/// A boundary triangle of the mesh: a sub-face of an input surface triangle, oriented like it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoundaryFace {
    /// The corners, in the input triangle's orientation.
    pub v: [VertexId; 3],
    /// The input triangle's boundary marker.
    pub marker: i32,
    /// The input facet (0-based) it belongs to.
    pub facet: u32,
}

/// A boundary-conforming tetrahedralisation of a [`Plc3`]: the value the later stages (point
/// generation, smoothing, output) work on.
///
/// It keeps the whole tetrahedralisation of the convex hull; cells outside the domain are tagged
/// [`OUTSIDE`] and never reported as elements, and the boundary faces are protected, so points
/// inserted inside the domain stay inside it.
#[derive(Clone, Debug)]
pub struct Mesh3 {
    /// The tetrahedralisation with its protected boundary faces; cell tags are region indices.
    pub ct: ConstrainedTriangulation3,
    /// The boundary faces.
    pub faces: Vec<BoundaryFace>,
    /// Spacing at each vertex (by vertex index), NaN where recovery knows none.
    pub spacing: Vec<f64>,
    /// Whether each vertex (by vertex index) lies on the surface.
    pub on_surface: Vec<bool>,
    /// Attribute of each region index (index 0: the default region, 0.0).
    pub region_attributes: Vec<f64>,
    /// Boundary marker of each input point (0 when none).
    pub point_markers: Vec<i32>,
    /// Number of input points (vertices with a smaller input index are input points).
    pub n_input_points: usize,
    /// The recovery history.
    pub history: RecoveryHistory3,
}

/// Boundary recovery of a [`Plc3`]; see the module docs.
#[derive(Clone, Debug)]
pub struct BoundaryRecovery3 {
    method: RecoveryMethod3,
    extra_points: Vec<[f64; 3]>,
    max_steiner: Option<usize>,
    /// Per surface triangle, the side of the domain (+1 along the normal, −1 against, 0
    /// unknown): where the a-priori points go. Derived from the surface checks when empty.
    sides: Vec<f64>,
    /// Skip the input checks (the surface is known good, e.g. a recovered one).
    trusted: bool,
    /// Re-triangulate coplanar neighbours of different input facets together.
    merge_coplanar: bool,
    /// Merge coplanar facets when the facets as given cost too many points.
    coplanar_fallback: bool,
    /// Points will be generated in the domain after recovery.
    field_points_follow: bool,
    /// Once set, the run stops with [`RecoveryError::Cancelled`].
    cancel: Option<Arc<AtomicBool>>,
}

impl Default for BoundaryRecovery3 {
    fn default() -> Self {
        Self::new(RecoveryMethod3::default())
    }
}

/// An input edge and the vertices on it, ordered by their parameter from `a` to `b`.
#[derive(Clone, Debug)]
struct Seg {
    a: u32,
    b: u32,
    /// `(t, vertex, witness)`: the vertex at `a + t (b - a)`; first `(0, a, _)`, last
    /// `(1, b, _)`. The witness of point `k` is a cell slot that held the sub-segment from it
    /// to point `k + 1` when that was last found ([`NO_CELL`] if not yet): most survive a
    /// change near the sub-segment, and one look at that slot then confirms it without a star
    /// search.
    pts: Vec<(f64, VertexId, CellId)>,
}

/// No cell: a sub-segment not yet found.
const NO_CELL: CellId = CellId(u32::MAX);

/// An input triangle, the vertices added inside it, and its current sub-faces.
#[derive(Clone, Debug)]
struct Fac {
    corners: [u32; 3],
    /// Segment of edge `k` (corner `k` to corner `k + 1`), and whether it runs the other way.
    segs: [(u32, bool); 3],
    /// Points added inside: barycentric coordinates and vertex.
    interior: Vec<([f64; 3], VertexId)>,
    marker: i32,
    facet: u32,
    /// Sub-faces (counter-clockwise like the input triangle) at the last check.
    subfaces: Vec<[VertexId; 3]>,
    /// Whether `subfaces` must be recomputed (points were added on the facet).
    stale: bool,
    /// The value of `State::changes` when every sub-face was last found present (0: not
    /// since its sub-faces last changed).
    complete_at: u64,
}

/// Recovery in progress.
struct State<'a> {
    /// Once set, the rounds stop with [`RecoveryError::Cancelled`].
    cancel: Option<Arc<AtomicBool>>,
    ct: ConstrainedTriangulation3,
    plc: &'a Plc3,
    segs: Vec<Seg>,
    facs: Vec<Fac>,
    /// The facets (positions in `facs`) having each segment as an edge.
    seg_facets: Vec<Vec<u32>>,
    spacing: Vec<f64>,
    on_surface: Vec<bool>,
    stars: StarSearch,
    star: Vec<CellId>,
    /// A second search and buffer, for the second half of the parallel edge checks.
    stars2: StarSearch,
    star2: Vec<CellId>,
    /// Sub-segments shorter than this cannot be split (beyond double precision).
    shortest: f64,
    budget: usize,
    added: usize,
    /// Insertions so far, plus one: the clock of `touched`.
    changes: u64,
    /// For each vertex, the value of `changes` when an insertion last changed its star (a
    /// cell containing it was replaced). An edge or face of the triangulation can only be
    /// destroyed by an insertion whose cavity holds all its vertices, and one that is missing
    /// can only appear with a new vertex, so checks look again only where this is recent.
    touched: Vec<u64>,
    /// The value of `changes` at the last edge check.
    edges_checked_at: u64,
    /// The number of vertices at the last edge check (vertices numbered from it on are new).
    edges_checked_vertices: usize,
    /// Recover by flips first ([`RecoveryMethod3::Constrained`]).
    constrained: bool,
    /// Whether some segment has more than two facets: the surface has internal walls.
    walls: bool,
    /// Every sub-segment, by [`edge_key`]: flips never remove these edges.
    locked: HashSet<u64>,
    /// Scratch: the vertices of the cells flips changed.
    flip_touched: Vec<VertexId>,
    /// Leave flat tetrahedra reaching deep into the domain to the field points
    /// ([`BoundaryRecovery3::field_points_follow`]).
    field_points_follow: bool,
}

impl BoundaryRecovery3 {
    /// Recovery with the given method.
    pub fn new(method: RecoveryMethod3) -> Self {
        BoundaryRecovery3 {
            method,
            extra_points: Vec::new(),
            max_steiner: None,
            sides: Vec::new(),
            trusted: false,
            merge_coplanar: false,
            coplanar_fallback: true,
            field_points_follow: false,
            cancel: None,
        }
    }

    /// Stops the run with [`RecoveryError::Cancelled`] soon after `flag` is set (it is looked
    /// at every 1,024 points of the Delaunay construction and before each round of recovery): for a recovery run beside another attempt that may make it unnecessary.
    pub fn cancel_on(mut self, flag: Arc<AtomicBool>) -> Self {
        self.cancel = Some(flag);
        self
    }

    /// Lets recovery re-triangulate coplanar neighbouring triangles of different input facets
    /// (same marker, exactly in one plane) by flipping their shared diagonals, as TetGen merges
    /// coplanar facets by default: the covered surface, its markers and points are unchanged,
    /// but an input triangle is then not always a union of boundary faces. Without it, only the
    /// triangles of one (polygon) facet are re-triangulated. See the `planar` module. The
    /// fallback of [`Self::coplanar_fallback`] still applies, with triangles flat to rounding
    /// merged too.
    pub fn merge_coplanar(mut self, merge: bool) -> Self {
        self.merge_coplanar = merge;
        self
    }

    /// Whether recovery may merge coplanar facets after all (as [`Self::merge_coplanar`], and
    /// triangles flat to rounding too) when the facets as given would cost more than
    /// [`costly_bound`] points (on by default; with [`Self::merge_coplanar`], when the exactly
    /// coplanar facets merged would).
    ///
    /// A CAD surface whose planar faces are fans of long thin triangles needs a great many
    /// points to make every thin triangle a union of Delaunay faces: a 240-sided cylinder with
    /// fans for caps took 74,497, and a 360-sided one more than the 100,000-point bound, while
    /// its merged caps and sides need none (TetGen merges coplanar facets by default for this
    /// reason). Off, recovery keeps every input triangle (the paper's method as it is) and
    /// stops with an error at the bound.
    pub fn coplanar_fallback(mut self, on: bool) -> Self {
        self.coplanar_fallback = on;
        self
    }

    /// Says that points will be generated inside the domain after recovery (off by default).
    /// Recovery then leaves to them the flat tetrahedra on the surface whose circumsphere
    /// rises deep into the domain (see [`DEEP_CAP`]) instead of splitting the surface edge
    /// under them: the first field point above such a tetrahedron removes it. The surface
    /// triangles of a fine sphere, all on one sphere, made thousands of such splits (81,920
    /// triangles: 9,012 points on the surface, and more slivers in the final mesh, not fewer).
    pub fn field_points_follow(mut self, follow: bool) -> Self {
        self.field_points_follow = follow;
        self
    }

    /// Skips the input checks of [`check_surface`]: for a surface that came out of an earlier
    /// recovery (whose added points lie on the input surface only to rounding).
    pub fn trusted_surface(mut self) -> Self {
        self.trusted = true;
        self
    }

    /// For the a-priori method: the side of the domain of each surface triangle (+1 along its
    /// normal, −1 against it, 0 unknown: either side). Without it, either side is used.
    pub fn with_domain_sides(mut self, sides: Vec<f64>) -> Self {
        self.sides = sides;
        self
    }

    /// Adds field points from an external source (R9); those that fall outside the domain are
    /// dropped with the exterior.
    pub fn with_points(mut self, points: Vec<[f64; 3]>) -> Self {
        self.extra_points = points;
        self
    }

    /// The most points recovery may add before it gives up with
    /// [`RecoveryError::SurfaceNotRecovered`] (default: 50 per surface point, at least
    /// 100,000: splitting ends, the bound only keeps a pathological input from exhausting
    /// memory; a 96-sided cylinder with fans for caps needs 10,120 for 480 points).
    pub fn max_steiner_points(mut self, n: usize) -> Self {
        self.max_steiner = Some(n);
        self
    }

    /// Checks the surface ([`check_surface`]: closed, manifold, orientable (triangles are
    /// reoriented where needed), free of self-intersections), recovers it and classifies the
    /// exterior.
    ///
    /// # Errors
    /// A surface that fails the checks (naming the facets), a surface that could not be
    /// recovered within the bound, or a domain with no element inside.
    pub fn run(&self, plc: &Plc3) -> Result<Mesh3, RecoveryError> {
        self.run_from(plc, None)
    }

    /// [`BoundaryRecovery3::run`] starting from `tri`, the Delaunay tetrahedralisation of
    /// `plc`'s points (input point `i` at point `i` of `plc`), instead of building it: for
    /// points that are already triangulated (the Delaunay restoration after smoothing gets
    /// their tetrahedralisation from the mesh by flips, several times faster). With field
    /// points, the a-priori method, or a `tri` whose input points are not `plc`'s, `tri` is
    /// set aside and the points are triangulated as [`BoundaryRecovery3::run`] does.
    ///
    /// # Errors
    /// As [`BoundaryRecovery3::run`].
    pub fn run_on(&self, plc: &Plc3, tri: Triangulation3) -> Result<Mesh3, RecoveryError> {
        self.run_from(plc, Some(tri))
    }

    /// [`BoundaryRecovery3::run`], from `given` if it fits (see [`BoundaryRecovery3::run_on`]).
    fn run_from(&self, plc: &Plc3, given: Option<Triangulation3>) -> Result<Mesh3, RecoveryError> {
        if is_set(&self.cancel) {
            return Err(RecoveryError::Cancelled);
        }
        let given = given.filter(|t| {
            self.extra_points.is_empty()
                && self.method != RecoveryMethod3::APriori
                && t.num_input_points() == plc.points.len()
                && plc
                    .points
                    .iter()
                    .enumerate()
                    .all(|(i, &p)| t.vertex(t.vertex_of_input(i)) == p)
        });
        // With no field points and no a-priori points, the triangulation is of the surface
        // points alone: it is built on the second thread while the surface is checked.
        let alone = given.is_none()
            && !self.trusted
            && self.extra_points.is_empty()
            && self.method != RecoveryMethod3::APriori
            && plc.points.iter().flatten().all(|x| x.is_finite());
        let (checked, early) = if self.trusted {
            (None, None)
        } else if alone {
            let (c, t) = rayon::join(|| check_surface(plc), || self.triangulate(&plc.points));
            (Some(c?), Some(t))
        } else {
            (Some(check_surface(plc)?), None)
        };
        let n_input = plc.points.len();
        if let Some(i) = plc
            .points
            .iter()
            .chain(&self.extra_points)
            .position(|p| p.iter().any(|x| !x.is_finite()))
        {
            return Err(RecoveryError::NonFinite {
                point: i as u64 + u64::from(plc.first_index),
            });
        }
        // Field points exactly on the surface would sit inside a surface triangle, which could
        // then never be a face of the mesh: they are left out (and counted).
        let extra: Vec<[f64; 3]> = match &checked {
            Some(c) => self
                .extra_points
                .iter()
                .copied()
                .filter(|&p| !matches!(c.locate(p), Some(PointLocation::OnSurface { .. })))
                .collect(),
            None => self.extra_points.clone(),
        };
        let dropped_on_surface = self.extra_points.len() - extra.len();
        let mut points = plc.points.clone();
        points.extend_from_slice(&extra);
        let derived = match (&checked, self.sides.is_empty()) {
            (Some(c), true) => domain_sides(c),
            _ => Vec::new(),
        };
        let sides: &[f64] = if self.sides.is_empty() {
            &derived
        } else {
            &self.sides
        };
        let mut a_priori_rejected = 0;
        if self.method == RecoveryMethod3::APriori {
            if let Some(t) = plc
                .triangles
                .iter()
                .find(|t| t.v.iter().any(|&i| i as usize >= n_input))
            {
                return Err(RecoveryError::BadFacetPoint {
                    facet: u64::from(t.facet) + u64::from(plc.first_index),
                    point: u64::from(*t.v.iter().max().unwrap_or(&0)) + u64::from(plc.first_index),
                    n_points: n_input,
                });
            }
            let derived = match (&checked, self.sides.is_empty()) {
                (Some(c), true) => domain_sides(c),
                _ => Vec::new(),
            };
            let sides = if self.sides.is_empty() {
                &derived
            } else {
                &self.sides
            };
            let side = |k: usize| sides.get(k).copied().unwrap_or(0.0);
            let near_surface =
                |q: [f64; 3], d: f64| checked.as_ref().is_some_and(|c| c.within(q, d));
            let (placed, rejected) =
                a_priori_points(&plc.points, &extra, &plc.triangles, side, near_surface);
            a_priori_rejected = rejected;
            points.extend(placed);
        }
        let tri = match (early, given) {
            (Some(t), _) => t?,
            (None, Some(t)) => t,
            (None, None) => self.triangulate(&points)?,
        };
        if is_set(&self.cancel) {
            return Err(RecoveryError::Cancelled);
        }
        // Planar patches re-triangulated by flips before recovery (see `planar`).
        let patches = if self.merge_coplanar {
            Patches::Coplanar
        } else {
            Patches::OneFacet
        };
        let planar = |patches| flip_planar_diagonals(&plc.points, &plc.triangles, &tri, patches);
        // The surface with coplanar facets merged, and those flat to rounding, when that
        // differs from the surface as given: what recovery falls back on if the facets as
        // given cost too many points. Both flip passes only read the triangulation: side by
        // side.
        let (flipped, merged) = rayon::join(
            || planar(patches),
            || {
                self.coplanar_fallback
                    .then(|| planar(Patches::NearlyCoplanar(Flatness::Double)))
                    .flatten()
            },
        );
        let planar_flips = flipped.as_ref().map_or(0, |f| f.1);
        let merged =
            merged.filter(|(m, _)| m != flipped.as_ref().map_or(&plc.triangles, |(t, _)| t));
        let with_triangles = |triangles| Plc3 {
            triangles,
            ..plc.clone()
        };
        let retriangulated;
        let plc = match flipped {
            Some((triangles, _)) => {
                retriangulated = with_triangles(triangles);
                &retriangulated
            }
            None => plc,
        };
        let merged = merged.map(|(triangles, flips)| (with_triangles(triangles), flips));
        let constrained = self.method == RecoveryMethod3::Constrained;
        // A constrained recovery that does not finish is followed by the conforming one (both
        // within the cap when there is a merged surface to fall back on).
        let fallback = constrained.then(|| tri.clone());
        let mut state = State::new(tri, plc, self.max_steiner, constrained, self.cancel.clone())?;
        state.field_points_follow = self.field_points_follow;
        // Vertices by where their point came from (duplicates merged).
        let n_extra = extra.len();
        let from = |lo: usize, hi: usize| {
            (0..state.ct.triangulation().num_vertices())
                .filter(|&v| {
                    let i = state.ct.triangulation().input_index(VertexId(v as u32));
                    (lo..hi).contains(&i) && !state.on_surface[v]
                })
                .count()
        };
        let (field_points, a_priori) = (
            from(n_input, n_input + n_extra),
            from(n_input + n_extra, usize::MAX),
        );
        let mut history = RecoveryHistory3 {
            method: self.method,
            surface_points: state.on_surface.iter().filter(|&&s| s).count(),
            field_points,
            surface_faces: plc.triangles.len(),
            surface_edges: state.segs.len(),
            initial_tetrahedra: state.ct.triangulation().num_cells(),
            a_priori_points: a_priori,
            a_priori_rejected,
            field_points_on_surface: dropped_on_surface,
            merged_points: checked.as_ref().map_or_else(Vec::new, |c| {
                let base = u64::from(plc.first_index);
                c.merged
                    .iter()
                    .map(|&(d, first)| (u64::from(d) + base, u64::from(first) + base))
                    .collect()
            }),
            reoriented_triangles: checked.as_ref().map_or(0, |c| c.reoriented.len()),
            junction_edges: checked.as_ref().map_or(0, |c| c.junctions.len()),
            planar_flips,
            ..Default::default()
        };
        // With a merged surface to fall back on, the facets as given get a smaller budget.
        let cap = match merged {
            Some(_) => costly_bound(history.surface_points),
            None => usize::MAX,
        };
        let initial = history.clone();
        let outcome = state.recover_all(fallback, self.max_steiner, cap, sides, &mut history);
        // When the facets as given fail: the merged surface (all bound), the facets as given
        // with all the bound if they had less, and for a surface of single precision (binary
        // STL) the surface merged to its own rounding, in that order. Each starts from the
        // same first tetrahedralisation, built again (the construction is deterministic).
        let single = plc
            .points
            .iter()
            .flatten()
            .all(|&x| f64::from(x as f32) == x);
        let coarse;
        let (mut state, plc) = match outcome {
            Ok(state) => (state, plc),
            Err(first @ RecoveryError::SurfaceNotRecovered { .. })
                if self.coplanar_fallback && (merged.is_some() || single) =>
            {
                let added = match &first {
                    RecoveryError::SurfaceNotRecovered { added, .. } => *added,
                    _ => 0,
                };
                let merged_history = RecoveryHistory3 {
                    coplanar_merged_after: Some(added),
                    ..initial.clone()
                };
                let mut failure = None;
                let mut recovered = None;
                if let Some((merged, flips)) = &merged {
                    // Coplanar neighbours with one marker merged, as TetGen does by default.
                    history = RecoveryHistory3 {
                        planar_flips: *flips,
                        ..merged_history.clone()
                    };
                    let tri = Triangulation3::new(&points)?;
                    match self.attempt(tri, merged, usize::MAX, sides, &mut history) {
                        Ok(state) => recovered = Some((state, merged)),
                        Err(e @ RecoveryError::SurfaceNotRecovered { .. }) => failure = Some(e),
                        Err(e) => return Err(e),
                    }
                }
                if recovered.is_none() && cap < usize::MAX {
                    history = initial;
                    let tri = Triangulation3::new(&points)?;
                    match self.attempt(tri, plc, usize::MAX, sides, &mut history) {
                        Ok(state) => recovered = Some((state, plc)),
                        Err(e @ RecoveryError::SurfaceNotRecovered { .. }) => failure = Some(e),
                        Err(e) => return Err(e),
                    }
                }
                match recovered {
                    Some(done) => done,
                    None => {
                        let tri = Triangulation3::new(&points)?;
                        let near = flip_planar_diagonals(
                            &plc.points,
                            &plc.triangles,
                            &tri,
                            Patches::NearlyCoplanar(Flatness::Single),
                        )
                        .filter(|(t, _)| {
                            single
                                && merged.as_ref().map_or(&plc.triangles, |m| &m.0.triangles) != t
                        });
                        let Some((triangles, flips)) = near else {
                            return Err(failure.unwrap_or(first));
                        };
                        coarse = Plc3 {
                            triangles,
                            ..plc.clone()
                        };
                        history = RecoveryHistory3 {
                            planar_flips: flips,
                            merged_to_single_precision: true,
                            ..merged_history
                        };
                        (
                            self.attempt(tri, &coarse, usize::MAX, sides, &mut history)?,
                            &coarse,
                        )
                    }
                }
            }
            Err(e) => return Err(e),
        };
        history.final_surface_edges = state.segs.iter().map(|s| s.pts.len() - 1).sum();

        // Protect the recovered faces, then classify.
        let mut faces = Vec::new();
        for fac in &state.facs {
            for &t in &fac.subfaces {
                faces.push(BoundaryFace {
                    v: t,
                    marker: fac.marker,
                    facet: fac.facet,
                });
            }
        }
        let facets = state.face_refs(&faces);
        debug_assert!(
            facets.iter().all(Option::is_some),
            "every recovered face is present: a bug"
        );
        let mut ct = state.ct;
        ct.unprotect_all();
        for f in facets.into_iter().flatten() {
            ct.protect(f);
        }

        history.final_surface_faces = faces.len();
        let (region_attributes, seeds) = classify3(&mut ct, plc)?;
        history.seeds_outside = seeds.outside;
        history.seeds_overridden = seeds.overridden;
        for c in ct.triangulation().cells() {
            if ct.tag(c) == OUTSIDE {
                history.tetrahedra_outside += 1;
            } else {
                history.tetrahedra_inside += 1;
            }
        }
        let mut point_markers = plc.point_markers.clone();
        point_markers.resize(n_input, 0);
        Ok(Mesh3 {
            ct,
            faces,
            spacing: state.spacing,
            on_surface: state.on_surface,
            region_attributes,
            point_markers,
            n_input_points: n_input,
            history,
        })
    }
}

impl BoundaryRecovery3 {
    /// The Delaunay tetrahedralisation of `points`, stopped if the caller cancels.
    fn triangulate(&self, points: &[[f64; 3]]) -> Result<Triangulation3, RecoveryError> {
        Triangulation3::with_progress_until(points, |_, _| !is_set(&self.cancel)).map_err(|e| {
            match e {
                TriangulationError::Cancelled => RecoveryError::Cancelled,
                e => e.into(),
            }
        })
    }

    /// A recovery of `plc`'s triangles in `tri`, from scratch (a constrained one followed by
    /// the conforming one if it does not finish), adding at most `cap` points.
    fn attempt<'p>(
        &self,
        tri: Triangulation3,
        plc: &'p Plc3,
        cap: usize,
        sides: &[f64],
        history: &mut RecoveryHistory3,
    ) -> Result<State<'p>, RecoveryError> {
        let constrained = self.method == RecoveryMethod3::Constrained;
        let fallback = constrained.then(|| tri.clone());
        let mut state = State::new(tri, plc, self.max_steiner, constrained, self.cancel.clone())?;
        state.field_points_follow = self.field_points_follow;
        history.surface_edges = state.segs.len();
        state.recover_all(fallback, self.max_steiner, cap, sides, history)
    }
}

/// How many points the facets as given may cost, for `surface_points` distinct surface points,
/// before recovery merges coplanar facets instead ([`BoundaryRecovery3::coplanar_fallback`]):
/// 20 per surface point, at least 5,000. Every surface of `cargo xtask surfaces` needs under 12
/// per point (cheese, the most), so none of them is merged.
pub fn costly_bound(surface_points: usize) -> usize {
    (20 * surface_points).max(5_000)
}

/// The shortest sub-segment, as a fraction of its segment, that the constrained recovery
/// splits; finer, it gives up and the conforming recovery runs instead.
const CONSTRAINED_FINEST: f64 = 1.0 / 1024.0;

/// Face rounds in a row with more missing faces after which the constrained attempt stops.
const CONSTRAINED_GROWING_ROUNDS: usize = 3;

/// Flips tried for one missing edge or face before a point is added instead.
const MAX_FLIPS: usize = 32;

/// The order in which a round's sub-segments `(segment, position)` (sorted) are split: the
/// segments in rounds of doubling size (64, 64, 128, 256, …) drawn pseudo-randomly, each round
/// in segment order, and within a segment the highest position first (so earlier positions
/// stay valid). Splitting in segment order alone, neighbour after neighbour, is quadratic on
/// symmetric surfaces: a pipe's quadrilaterals between two rings of points all lie on one
/// sphere, and each mid-point in turn re-made the whole ring's tetrahedra (30,000 splits took
/// 5 s, 1.8 s so); random rounds cut such regions up first, as BRIO does for a triangulation,
/// and the order within a round keeps the insertions near each other.
fn splitting_order(mut splits: Vec<(u32, u32)>) -> Vec<(u32, u32)> {
    // A fixed pseudo-random permutation of the segments (the run stays deterministic).
    let mix = |s: u32| (u64::from(s) ^ 0x5851_F42D).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let mut segments: Vec<u32> = splits.iter().map(|m| m.0).collect();
    segments.dedup();
    segments.sort_unstable_by_key(|&s| (mix(s), s));
    let round: HashMap<u32, u32> = segments
        .iter()
        .enumerate()
        .map(|(i, &s)| (s, u64::BITS - (i as u64 / 64 + 1).leading_zeros()))
        .collect();
    splits.sort_unstable_by_key(|&(s, k)| (round[&s], s, std::cmp::Reverse(k)));
    splits
}

/// Whether a cancel flag (see [`BoundaryRecovery3::cancel_on`]) is given and set.
fn is_set(cancel: &Option<Arc<AtomicBool>>) -> bool {
    cancel.as_ref().is_some_and(|c| c.load(Ordering::Relaxed))
}

/// An edge's key in [`State::locked`]: its two vertices, lower first.
fn edge_key(a: VertexId, b: VertexId) -> u64 {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    u64::from(lo.0) << 32 | u64::from(hi.0)
}

/// Rounds of breaking flat tetrahedra on the surface (each followed by edge and face checking).
const MAX_SLIVER_ROUNDS: usize = 1;

/// A facet's domain side when the domain is on both: an internal wall between two regions.
const BOTH_SIDES: f64 = 2.0;

/// A flat tetrahedron on the surface whose circumsphere rises on the domain side to this many
/// times its longest edge is left to the field points when they follow
/// ([`BoundaryRecovery3::field_points_follow`]): the first layer of field points lies well
/// within that height (about one spacing, the edges' length, off the surface).
const DEEP_CAP: f64 = 2.0;

/// A tetrahedron on the surface with a dihedral angle under this many degrees is flat.
const FLAT_DIHEDRAL: f64 = 1.0;

/// The surface is flat across an edge where its two triangles' normals differ by less than
/// this many degrees.
const FLAT_SURFACE: f64 = 0.5;

/// The smallest dihedral angle of a tetrahedron, in degrees (a measure, not a decision about
/// topology).
fn min_dihedral(p: [[f64; 3]; 4]) -> f64 {
    let normal = |i: usize, j: usize, k: usize| {
        let n = cross(sub(p[j], p[i]), sub(p[k], p[i]));
        let l = dot(n, n).sqrt();
        [n[0] / l, n[1] / l, n[2] / l]
    };
    let n = [
        normal(1, 2, 3),
        normal(0, 3, 2),
        normal(0, 1, 3),
        normal(0, 2, 1),
    ];
    let mut smallest = 180.0f64;
    for i in 0..4 {
        for j in i + 1..4 {
            let c = -dot(n[i], n[j]);
            smallest = smallest.min(c.clamp(-1.0, 1.0).acos().to_degrees());
        }
    }
    if smallest.is_nan() {
        0.0
    } else {
        smallest
    }
}

/// Whether the circumsphere of the flat tetrahedron `p` (the corners `u w x y` of two surface
/// triangles sharing `u w`; `n` the normal of the first, `side` its domain side as in
/// `domain_sides`) rises on the domain side of the surface to at least [`DEEP_CAP`] times the
/// tetrahedron's longest edge: its centre lies that far in, less its radius. For the triangles
/// of a sphere, all on one sphere, it is the sphere itself; for nearly co-circular corners on a
/// flat surface, a ball about the size of the triangles. Floating point: a heuristic choice,
/// not a topological one.
fn reaches_deep(p: [[f64; 3]; 4], n: [f64; 3], side: f64) -> bool {
    let Some(c) = delmesh_predicates::circumcenter3(p[0], p[1], p[2], p[3]) else {
        return false;
    };
    let radius = dist(c, p[0]);
    let mut longest = 0.0f64;
    for i in 0..4 {
        for j in i + 1..4 {
            longest = longest.max(dist(p[i], p[j]));
        }
    }
    // The centre's height above the first triangle's plane, along the domain side.
    let height = dot(sub(c, p[0]), n) / dot(n, n).sqrt();
    let inward = if side == BOTH_SIDES {
        height.abs()
    } else if side > 0.0 {
        height
    } else {
        -height
    };
    radius + inward >= DEEP_CAP * longest
}

/// The `(segment, position, cell)` of each sub-segment `(a, b, segment, position)` of `edges`
/// (sorted by `a`): a cell of `tri` that holds it, or [`NO_CELL`] if it is missing. One search
/// of the star of each lower end `a`, stopped once every other end is found.
fn missing_in(
    tri: &Triangulation3,
    stars: &mut StarSearch,
    star: &mut Vec<CellId>,
    edges: &[(VertexId, VertexId, u32, u32)],
) -> Vec<(u32, u32, CellId)> {
    let mut out = Vec::with_capacity(edges.len());
    let mut found: Vec<CellId> = Vec::new();
    for group in edges.chunk_by(|x, y| x.0 == y.0) {
        found.clear();
        found.resize(group.len(), NO_CELL);
        let mut left = group.len();
        stars.find_cell(tri, group[0].0, star, |c, cell| {
            for (e, seen) in group.iter().zip(found.iter_mut()) {
                if *seen == NO_CELL && cell.contains(&e.1) {
                    *seen = c;
                    left -= 1;
                }
            }
            left == 0
        });
        out.extend(group.iter().zip(&found).map(|(e, &c)| (e.2, e.3, c)));
    }
    out
}

/// Whether the four vertices are a cell of `tri` (`star`: a buffer for the search).
fn is_tetrahedron(
    stars: &mut StarSearch,
    tri: &Triangulation3,
    t: [VertexId; 4],
    star: &mut Vec<CellId>,
) -> bool {
    // The tetrahedron is one of the two cells on its face t0 t1 t2: find one of them (the search
    // stops there), then look at it and at its neighbour across that face.
    let Some(c) = stars.find(tri, t[0], star, |v| v.contains(&t[1]) && v.contains(&t[2])) else {
        return false;
    };
    let v = tri.cell(c);
    if v.contains(&t[3]) {
        return true;
    }
    let Some(i) = (0..4).find(|&k| !t[..3].contains(&v[k])) else {
        return false;
    };
    tri.neighbor(c, i)
        .is_some_and(|n| tri.cell(n).contains(&t[3]))
}

/// The side of the domain of each surface triangle, by the nesting of the closed surfaces:
/// just inside a surface at even depth (the far field, a hollow body's cavity wall) is domain,
/// just inside one at odd depth (a body) is not. +1 is along the input triangle's normal
/// (reversed for the triangles the check reoriented). None (every side unknown) for a surface
/// with walls, which has no nesting.
fn domain_sides(c: &CheckedSurface) -> Vec<f64> {
    if c.has_walls() {
        return Vec::new();
    }
    let mut sides: Vec<f64> = c
        .triangle_component
        .iter()
        .map(|&k| {
            let comp = &c.components[k as usize];
            let inside = if comp.outward { -1.0 } else { 1.0 };
            if comp.depth % 2 == 0 {
                inside
            } else {
                -inside
            }
        })
        .collect();
    for &t in &c.reoriented {
        sides[t as usize] = -sides[t as usize];
    }
    sides
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(a, b);
    dot(d, d).sqrt()
}

fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [
        a[0] + t * (b[0] - a[0]),
        a[1] + t * (b[1] - a[1]),
        a[2] + t * (b[2] - a[2]),
    ]
}

impl<'a> State<'a> {
    /// Recovers every edge and face, then breaks the flat tetrahedra on the surface. A
    /// constrained recovery that does not finish is followed by the conforming one from
    /// `fallback` (the same first tetrahedralisation), with `history` as it was at the start.
    /// Neither adds more than `cap` points.
    fn recover_all(
        mut self,
        fallback: Option<Triangulation3>,
        max_steiner: Option<usize>,
        cap: usize,
        sides: &[f64],
        history: &mut RecoveryHistory3,
    ) -> Result<Self, RecoveryError> {
        self.budget = self.budget.min(cap);
        let initial = fallback.is_some().then(|| history.clone());
        let attempt = self
            .recover(history)
            .and_then(|()| self.break_flat_tetrahedra(sides, history));
        match (attempt, fallback.zip(initial)) {
            (Ok(()), _) => Ok(self),
            (Err(_), Some((tri, initial))) => {
                let mut state = State::new(tri, self.plc, max_steiner, false, self.cancel.clone())?;
                state.budget = state.budget.min(cap);
                state.field_points_follow = self.field_points_follow;
                *history = RecoveryHistory3 {
                    constrained_fallback: true,
                    ..initial
                };
                state.recover(history)?;
                state.break_flat_tetrahedra(sides, history)?;
                Ok(state)
            }
            (Err(e), None) => Err(e),
        }
    }

    fn new(
        tri: Triangulation3,
        plc: &'a Plc3,
        max_steiner: Option<usize>,
        constrained: bool,
        cancel: Option<Arc<AtomicBool>>,
    ) -> Result<Self, RecoveryError> {
        let n = plc.points.len();
        let first = u64::from(plc.first_index);
        let v = |i: u32| tri.vertex_of_input(i as usize);
        let mut seg_of: HashMap<(u32, u32), u32> = HashMap::default();
        let mut segs: Vec<Seg> = Vec::new();
        let mut facs = Vec::with_capacity(plc.triangles.len());
        for t in &plc.triangles {
            if let Some(&bad) = t.v.iter().find(|&&i| i as usize >= n) {
                return Err(RecoveryError::BadFacetPoint {
                    facet: u64::from(t.facet) + first,
                    point: u64::from(bad) + first,
                    n_points: n,
                });
            }
            let cv = t.v.map(v);
            if cv[0] == cv[1] || cv[1] == cv[2] || cv[0] == cv[2] {
                return Err(RecoveryError::DegenerateFacet {
                    facet: u64::from(t.facet) + first,
                });
            }
            let mut fs = [(0u32, false); 3];
            for (k, slot) in fs.iter_mut().enumerate() {
                let (p, q) = (t.v[k], t.v[(k + 1) % 3]);
                // Segments are keyed by vertex (duplicate input points share one).
                let (vp, vq) = (v(p), v(q));
                let key = (vp.0.min(vq.0), vp.0.max(vq.0));
                let id = *seg_of.entry(key).or_insert_with(|| {
                    segs.push(Seg {
                        a: p,
                        b: q,
                        pts: vec![(0.0, vp, NO_CELL), (1.0, vq, NO_CELL)],
                    });
                    segs.len() as u32 - 1
                });
                *slot = (id, v(segs[id as usize].a) != vp);
            }
            facs.push(Fac {
                corners: t.v,
                segs: fs,
                interior: Vec::new(),
                marker: t.marker,
                facet: t.facet,
                subfaces: vec![cv],
                stale: false,
                complete_at: 0,
            });
        }
        let mut seg_facets = vec![Vec::new(); segs.len()];
        for (f, fac) in facs.iter().enumerate() {
            for &(s, _) in &fac.segs {
                seg_facets[s as usize].push(f as u32);
            }
        }
        // The paper's dp: mean length of the surface edges at each surface point.
        let nv = tri.num_vertices();
        let mut sum = vec![0.0f64; nv];
        let mut count = vec![0u32; nv];
        let mut on_surface = vec![false; nv];
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for s in &segs {
            let (pa, pb) = (plc.points[s.a as usize], plc.points[s.b as usize]);
            let len = dist(pa, pb);
            for (e, p) in [(s.a, pa), (s.b, pb)] {
                let i = v(e).index();
                sum[i] += len;
                count[i] += 1;
                on_surface[i] = true;
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        let spacing = sum
            .iter()
            .zip(&count)
            .map(|(&s, &c)| if c > 0 { s / f64::from(c) } else { f64::NAN })
            .collect();
        let n_surface = on_surface.iter().filter(|&&s| s).count();
        let walls = seg_facets.iter().any(|f| f.len() > 2);
        let locked = if constrained {
            segs.iter()
                .map(|s| edge_key(s.pts[0].1, s.pts[1].1))
                .collect()
        } else {
            HashSet::default()
        };
        Ok(State {
            cancel,
            ct: ConstrainedTriangulation3::new(tri),
            plc,
            segs,
            facs,
            seg_facets,
            spacing,
            on_surface,
            stars: StarSearch::default(),
            stars2: StarSearch::default(),
            star2: Vec::new(),
            star: Vec::new(),
            shortest: dist(lo, hi) * 2f64.powi(-40),
            budget: {
                let bound = max_steiner.unwrap_or((50 * n_surface).max(100_000));
                // Flips leave few points to add; many more mean they are not finishing.
                if constrained {
                    bound.min(4 * n_surface + 1000)
                } else {
                    bound
                }
            },
            added: 0,
            changes: 1,
            touched: vec![1; nv],
            edges_checked_at: 0,
            edges_checked_vertices: 0,
            locked,
            constrained,
            walls,
            flip_touched: Vec::new(),
            field_points_follow: false,
        })
    }

    fn point(&self, i: u32) -> [f64; 3] {
        self.plc.points[i as usize]
    }

    fn first(&self) -> u64 {
        u64::from(self.plc.first_index)
    }

    /// The facet of the triangulation that is each face (`None` where it is not one), one star
    /// search per distinct lowest vertex.
    fn face_refs(&mut self, faces: &[BoundaryFace]) -> Vec<Option<FacetRef>> {
        let mut order: Vec<(VertexId, u32)> = faces
            .iter()
            .enumerate()
            .map(|(i, f)| (*f.v.iter().min().unwrap_or(&f.v[0]), i as u32))
            .collect();
        order.sort_unstable();
        let mut out = vec![None; faces.len()];
        let mut star = std::mem::take(&mut self.star);
        let mut current = VertexId::GHOST;
        for (a, i) in order {
            if a != current {
                current = a;
                self.stars.star(self.ct.triangulation(), a, &mut star);
            }
            let [x, y, z] = faces[i as usize].v;
            out[i as usize] = find_face_in(self.ct.triangulation(), &star, x, y, z);
        }
        self.star = star;
        out
    }

    /// Inserts a surface point with a spacing value, walking from vertex `near`; `None` if it
    /// rounds onto a vertex.
    fn add_vertex(
        &mut self,
        p: [f64; 3],
        spacing: f64,
        near: VertexId,
    ) -> Result<Option<VertexId>, RecoveryError> {
        // A field or a-priori point exactly where the surface needs one (rounding put it on
        // the sub-segment or sub-face being split): it becomes that surface point.
        let mut promoted = false;
        let inserted = if self.constrained {
            // Flips made the mesh non-Delaunay in places: Bowyer-Watson where the cells are
            // Delaunay, else split what the point lies in; then flip.
            let v = self.ct.insert_growing(p, near)?;
            if v.is_some() {
                let faces = self
                    .ct
                    .last_new_cells()
                    .iter()
                    .flat_map(|&c| (0..4).map(move |i| FacetRef::new(c, i)))
                    .collect();
                let locked = &self.locked;
                let is_locked = |x: VertexId, y: VertexId| locked.contains(&edge_key(x, y));
                self.flip_touched
                    .extend_from_slice(self.ct.triangulation().last_cavity_vertices());
                self.ct.make_delaunay_from_locked(
                    faces,
                    |_| true,
                    &is_locked,
                    &mut self.flip_touched,
                );
            }
            v
        } else {
            match self.ct.insert_near(p, near)? {
                Insertion::Inserted(v) => Some(v),
                Insertion::Duplicate(d) if self.on_surface.get(d.index()) == Some(&false) => {
                    promoted = true;
                    Some(d)
                }
                Insertion::Duplicate(_) => None,
            }
        };
        match inserted {
            Some(v) => {
                if self.spacing.len() <= v.index() {
                    self.spacing.resize(v.index() + 1, f64::NAN);
                    self.on_surface.resize(v.index() + 1, false);
                }
                self.spacing[v.index()] = spacing;
                self.on_surface[v.index()] = true;
                self.added += 1;
                // The new cells are the star of `v`; their vertices are the cavity's.
                self.changes += 1;
                let n = self.ct.triangulation().num_vertices();
                if self.touched.len() < n {
                    self.touched.resize(n, 0);
                }
                self.touched[v.index()] = self.changes;
                if self.constrained {
                    self.note_flips();
                } else if promoted {
                    // No cell changed, but what the point is did: the checks around it again.
                    let mut star = std::mem::take(&mut self.star);
                    self.stars.star(self.ct.triangulation(), v, &mut star);
                    for &c in &star {
                        for &u in self.ct.triangulation().cell(c) {
                            if !u.is_ghost() {
                                self.touched[u.index()] = self.changes;
                            }
                        }
                    }
                    self.star = star;
                } else {
                    for &u in self.ct.triangulation().last_cavity_vertices() {
                        if !u.is_ghost() {
                            self.touched[u.index()] = self.changes;
                        }
                    }
                }
                Ok(Some(v))
            }
            None => Ok(None),
        }
    }

    /// Marks the vertices of the cells the last flips changed (in `flip_touched`) as touched.
    fn note_flips(&mut self) {
        if self.flip_touched.is_empty() {
            return;
        }
        self.changes += 1;
        for &u in &self.flip_touched {
            if !u.is_ghost() {
                self.touched[u.index()] = self.changes;
            }
        }
        self.flip_touched.clear();
    }

    /// Tries to make the missing edge `u w` present by flips (never removing a sub-segment or
    /// a protected face); whether it is.
    fn flip_in_edge(&mut self, u: VertexId, w: VertexId, history: &mut RecoveryHistory3) -> bool {
        let locked = &self.locked;
        let is_locked = |x: VertexId, y: VertexId| locked.contains(&edge_key(x, y));
        let outcome = self
            .ct
            .flip_in_edge(u, w, &is_locked, MAX_FLIPS, &mut self.flip_touched);
        self.note_flips();
        self.count_flips(outcome, history)
    }

    /// Tries to make the missing sub-face `t` present by flips, its missing edges first; whether
    /// it is (then it is protected).
    fn flip_in_subface(&mut self, t: [VertexId; 3], history: &mut RecoveryHistory3) -> bool {
        let mark = self.ct.flip_mark();
        let present = self.flip_in_subface_edges(t, history) && {
            let locked = &self.locked;
            let is_locked = |x: VertexId, y: VertexId| locked.contains(&edge_key(x, y));
            let outcome = self.ct.flip_in_face(
                t[0],
                t[1],
                t[2],
                &is_locked,
                MAX_FLIPS,
                &mut self.flip_touched,
            );
            self.count_flips(outcome, history)
        };
        if present {
            self.ct.protect_face(t[0], t[1], t[2]);
            self.ct.keep_flips();
        } else {
            // The edges flipped in for it are taken back too.
            self.ct.undo_flips(mark, &mut self.flip_touched);
        }
        self.note_flips();
        present
    }

    /// Makes the missing edges of sub-face `t` present by flips; whether all are.
    fn flip_in_subface_edges(&mut self, t: [VertexId; 3], history: &mut RecoveryHistory3) -> bool {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let tri = self.ct.triangulation();
            let present = self
                .stars
                .find(tri, a, &mut self.star, |v| v.contains(&b))
                .is_some();
            if !present && !self.flip_in_edge(a, b, history) {
                return false;
            }
        }
        true
    }

    /// Adds the flips of `outcome` to the history; whether the edge or face is present.
    fn count_flips(&self, outcome: FlipIn, history: &mut RecoveryHistory3) -> bool {
        match outcome {
            FlipIn::Present(n) => {
                history.flips += n;
                history.flipped_in += usize::from(n > 0);
                true
            }
            FlipIn::Stuck(n) => {
                history.flips += n;
                false
            }
        }
    }

    /// Protects every sub-face present now (and no other face), so that flips keep them.
    fn protect_present_subfaces(&mut self) {
        let faces: Vec<BoundaryFace> = self
            .facs
            .iter()
            .flat_map(|fac| {
                fac.subfaces.iter().map(|&v| BoundaryFace {
                    v,
                    marker: fac.marker,
                    facet: fac.facet,
                })
            })
            .collect();
        let refs = self.face_refs(&faces);
        self.ct.unprotect_all();
        for f in refs.into_iter().flatten() {
            self.ct.protect(f);
        }
    }

    /// Flat tetrahedra on the surface: moved out of the domain by the choice of sub-faces where
    /// they span one facet, and (conforming recovery) broken by a split where they span a
    /// surface edge, followed by edge and face checking.
    fn break_flat_tetrahedra(
        &mut self,
        sides: &[f64],
        history: &mut RecoveryHistory3,
    ) -> Result<(), RecoveryError> {
        let by_flood_fill;
        let sides = if self.walls && sides.is_empty() {
            by_flood_fill = self.sides_by_flood_fill();
            &by_flood_fill
        } else {
            sides
        };
        let mut last = usize::MAX;
        for _ in 0..MAX_SLIVER_ROUNDS {
            history.flat_tetrahedra_moved_out += self.move_flat_tetrahedra_out(sides);
            if self.constrained {
                break;
            }
            let todo = self.edges_under_flat_tetrahedra(sides);
            // Splitting must make progress; where it does not (or there is nothing to do), stop.
            if todo.is_empty() || todo.len() >= last {
                break;
            }
            last = todo.len();
            let splits = todo.iter().map(|&(si, k)| (si as u32, k as u32)).collect();
            for (si, k) in splitting_order(splits) {
                self.split_subsegment(si as usize, k as usize)?;
                history.edge_points += 1;
            }
            history.flat_tetrahedra_split += todo.len();
            self.recover(history)?;
        }
        Ok(())
    }

    /// The domain's side of each facet (as `domain_sides` gives it, [`BOTH_SIDES`] for a wall
    /// between two regions, 0 where no tetrahedron on either side is in the domain) by the
    /// exterior deletion's rule applied to the recovered tetrahedralisation: the tetrahedra
    /// grouped across faces that are not sub-faces, a group in the domain when closed surfaces
    /// and walls enclose it an odd number of times (`classify::flood_fill`; hole seeds aside).
    /// For a surface with walls, where the nesting of closed surfaces does not say which side
    /// is inside.
    fn sides_by_flood_fill(&self) -> Vec<f64> {
        let tri = self.ct.triangulation();
        let sorted = |mut t: [VertexId; 3]| {
            t.sort_unstable();
            t
        };
        // Each sub-face by its sorted corners: its facet, and its corners as oriented there.
        let mut subface: HashMap<[VertexId; 3], (u32, [VertexId; 3])> = HashMap::default();
        for (f, fac) in self.facs.iter().enumerate() {
            for &t in &fac.subfaces {
                subface.insert(sorted(t), (f as u32, t));
            }
        }
        let face = |c: CellId, i: usize| {
            let v = tri.cell(c);
            sorted([v[(i + 1) % 4], v[(i + 2) % 4], v[(i + 3) % 4]])
        };
        let cells: Vec<CellId> = tri.all_cells().collect();
        let components = crate::classify::flood_fill(
            &cells,
            4,
            |c, i| subface.contains_key(&face(c, i)),
            |c, i| tri.neighbor_facet(c, i).cell(),
            |c| tri.is_ghost(c),
            Some(&|c, i| crate::classify3::face_corners(tri.cell(c), i)),
        );
        // Whether a tetrahedron of the domain lies along each facet's normal, and against it.
        let mut along = vec![false; self.facs.len()];
        let mut against = vec![false; self.facs.len()];
        for &c in &cells {
            if tri.is_ghost(c) || !components.inside[components.of_cell[c.index()] as usize] {
                continue;
            }
            for i in 0..4 {
                if let Some(&(f, t)) = subface.get(&face(c, i)) {
                    let q = [t[0], t[1], t[2], tri.cell(c)[i]].map(|v| tri.vertex(v));
                    if orient3d(q[0], q[1], q[2], q[3]) == Sign::Positive {
                        along[f as usize] = true;
                    } else {
                        against[f as usize] = true;
                    }
                }
            }
        }
        along
            .iter()
            .zip(&against)
            .map(|(&a, &b)| match (a, b) {
                (true, true) => BOTH_SIDES,
                (true, false) => 1.0,
                (false, true) => -1.0,
                (false, false) => 0.0,
            })
            .collect()
    }

    /// Edge and face checking until every sub-face is present.
    fn recover(&mut self, history: &mut RecoveryHistory3) -> Result<(), RecoveryError> {
        // Face rounds in a row that ended with more missing faces than the one before.
        let (mut growing, mut last_missing) = (0, usize::MAX);
        loop {
            self.stop_if_cancelled()?;
            self.recover_edges(history)?;
            let missing = self.check_faces();
            let n_faces: usize = self.facs.iter().map(|f| f.subfaces.len()).sum();
            history.steps.push(RecoveryStep::Faces {
                surface_faces: n_faces,
                missing_faces: missing.len(),
            });
            if missing.is_empty() {
                return Ok(());
            }
            // After flips, the points put into missing faces are not bound to end as
            // Delaunay ones are: where the missing faces keep multiplying, the constrained
            // attempt stops early rather than at its point budget.
            growing = if missing.len() > last_missing {
                growing + 1
            } else {
                0
            };
            last_missing = missing.len();
            if self.constrained && growing >= CONSTRAINED_GROWING_ROUNDS {
                return Err(self.not_recovered(missing.iter().map(|m| m.0).collect()));
            }
            let missing = if self.constrained {
                self.protect_present_subfaces();
                let mut left = Vec::new();
                for (f, t) in missing {
                    if !self.flip_in_subface(t, history) {
                        left.push((f, t));
                    }
                }
                left
            } else {
                missing
            };
            for (f, t) in missing {
                if self.split_face(f, t)? {
                    history.face_points += 1;
                } else {
                    history.edge_points += 1;
                }
            }
        }
    }

    /// [`RecoveryError::Cancelled`] once the caller has set the cancel flag.
    fn stop_if_cancelled(&self) -> Result<(), RecoveryError> {
        if is_set(&self.cancel) {
            return Err(RecoveryError::Cancelled);
        }
        Ok(())
    }

    /// Mid-point / shell insertion until every sub-segment is present.
    fn recover_edges(&mut self, history: &mut RecoveryHistory3) -> Result<(), RecoveryError> {
        loop {
            self.stop_if_cancelled()?;
            let missing = self.missing_subsegments();
            history.steps.push(RecoveryStep::Edges {
                points: self.ct.triangulation().num_vertices(),
                tetrahedra: self.ct.triangulation().num_cells(),
                surface_edges: self.segs.iter().map(|s| s.pts.len() - 1).sum(),
                missing_edges: missing.len(),
            });
            if missing.is_empty() {
                return Ok(());
            }
            let missing = if self.constrained {
                let mut left = Vec::new();
                for (s, k) in missing {
                    let pts = &self.segs[s as usize].pts;
                    let (u, w) = (pts[k as usize].1, pts[k as usize + 1].1);
                    if !self.flip_in_edge(u, w, history) {
                        left.push((s, k));
                    }
                    self.ct.keep_flips();
                }
                left
            } else {
                missing
            };
            for (s, k) in splitting_order(missing) {
                self.split_subsegment(s as usize, k as usize)?;
                history.edge_points += 1;
            }
        }
    }

    /// `(segment, position)` of every missing sub-segment, sorted.
    ///
    /// Only sub-segments with an end touched since the last check are looked at: the others
    /// were present then (every missing one was split since) and still are.
    fn missing_subsegments(&mut self) -> Vec<(u32, u32)> {
        let since = self.edges_checked_at;
        self.edges_checked_at = self.changes;
        let born = self.edges_checked_vertices;
        self.edges_checked_vertices = self.ct.triangulation().num_vertices();
        let tri = self.ct.triangulation();
        // Still in the cell slot that last held it.
        let held = |c: CellId, a: VertexId, b: VertexId| {
            c.index() < tri.num_cell_slots() && tri.is_live(c) && {
                let v = tri.cell(c);
                v.contains(&a) && v.contains(&b)
            }
        };
        let mut by_vertex: Vec<(VertexId, VertexId, u32, u32)> = Vec::new();
        for (s, seg) in self.segs.iter().enumerate() {
            for (k, w) in seg.pts.windows(2).enumerate() {
                let (a, b) = (w[0].1, w[1].1);
                let new = a.index() >= born || b.index() >= born;
                if !new && (self.touched[a.index()] <= since || self.touched[b.index()] <= since) {
                    continue;
                }
                if held(w[0].2, a, b) {
                    continue;
                }
                let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                by_vertex.push((lo, hi, s as u32, k as u32));
            }
        }
        by_vertex.sort_unstable();
        // The two halves (cut between lower ends) are checked on two threads.
        let mut cut = by_vertex.len() / 2;
        while cut > 0 && cut < by_vertex.len() && by_vertex[cut].0 == by_vertex[cut - 1].0 {
            cut += 1;
        }
        let (first, second) = by_vertex.split_at(cut);
        let (mut found, more) = if by_vertex.len() < 4096 {
            (
                missing_in(tri, &mut self.stars, &mut self.star, &by_vertex),
                Vec::new(),
            )
        } else {
            rayon::join(
                || missing_in(tri, &mut self.stars, &mut self.star, first),
                || missing_in(tri, &mut self.stars2, &mut self.star2, second),
            )
        };
        found.extend(more);
        let mut missing = Vec::new();
        for (s, k, c) in found {
            if c == NO_CELL {
                missing.push((s, k));
            } else {
                self.segs[s as usize].pts[k as usize].2 = c;
            }
        }
        missing.sort_unstable();
        missing
    }

    /// Splits sub-segment `k` of segment `s` (between its points `k` and `k + 1`).
    fn split_subsegment(&mut self, s: usize, k: usize) -> Result<(), RecoveryError> {
        // (What the split reads of the segment: copying all its points made splitting a
        // segment into n pieces quadratic.)
        let seg = &self.segs[s];
        let (pa, pb) = (self.point(seg.a), self.point(seg.b));
        let last = seg.pts.len() - 1;
        let ((t0, u, _), (t1, w, _)) = (seg.pts[k], seg.pts[k + 1]);
        let (first, end) = (seg.pts[0].1, seg.pts[last].1);
        let length = dist(pa, pb);
        let sub_length = (t1 - t0) * length;
        // Splits after flips are not bound to end as the Delaunay ones are: the constrained
        // attempt gives up on a segment divided this finely.
        let too_fine = self.constrained && t1 - t0 < CONSTRAINED_FINEST;
        if sub_length < self.shortest || self.added >= self.budget || too_fine {
            return Err(self.not_recovered(self.facets_of_segment(s)));
        }
        // Concentric shells: measured from an input vertex at one end, a power of two.
        let shell = |from_t: f64, towards: f64| {
            let r = 2f64.powf((sub_length * 0.5).log2().round());
            from_t + towards * r / length
        };
        let t = match (k == 0, k + 1 == last) {
            (true, false) => shell(0.0, 1.0),
            (false, true) => shell(1.0, -1.0),
            _ => self
                .projection_split(u, w)
                .map_or(0.5 * (t0 + t1), |f| t0 + f * (t1 - t0)),
        };
        let t = if t > t0 && t < t1 { t } else { 0.5 * (t0 + t1) };
        let p = lerp(pa, pb, t);
        let (da, db) = (self.spacing[first.index()], self.spacing[end.index()]);
        let Some(v) = self.add_vertex(p, da + t * (db - da), u)? else {
            return Err(self.not_recovered(self.facets_of_segment(s)));
        };
        if self.constrained {
            self.locked.remove(&edge_key(u, w));
            self.locked.insert(edge_key(u, v));
            self.locked.insert(edge_key(v, w));
        }
        self.segs[s].pts[k].2 = NO_CELL;
        self.segs[s].pts.insert(k + 1, (t, v, NO_CELL));
        for &f in &self.seg_facets[s] {
            self.facs[f as usize].stale = true;
        }
        Ok(())
    }

    /// Where to split the missing sub-segment `u w`, as a fraction of its length from `u`: the
    /// foot of the perpendicular from the vertex that encroaches it most (the largest angle
    /// `u x w` over 90°, among the vertices next to `u` or `w`), so that one split moves both
    /// halves' diametral spheres off that vertex; `None` when no neighbour encroaches or the foot
    /// is within a fifth of an end (then the mid-point is better). Not used next to input
    /// vertices, where the concentric shells are what makes splitting terminate.
    fn projection_split(&mut self, u: VertexId, w: VertexId) -> Option<f64> {
        let (pu, pw) = (
            self.ct.triangulation().vertex(u),
            self.ct.triangulation().vertex(w),
        );
        let uw = sub(pw, pu);
        let len2 = dot(uw, uw);
        let mut best: Option<(f64, f64)> = None; // (cosine of the angle at x, fraction)
        let mut star = std::mem::take(&mut self.star);
        for end in [u, w] {
            self.stars.star(self.ct.triangulation(), end, &mut star);
            for &c in &star {
                for &x in self.ct.triangulation().cell(c) {
                    if x.is_ghost() || x == u || x == w {
                        continue;
                    }
                    let px = self.ct.triangulation().vertex(x);
                    let (xu, xw) = (sub(pu, px), sub(pw, px));
                    // (The cosine has the sign of the dot product: most vertices do not
                    // encroach, and skip the square root and the division.)
                    let d = dot(xu, xw);
                    if d >= 0.0 || d.is_nan() {
                        continue;
                    }
                    let cos = d / (dot(xu, xu) * dot(xw, xw)).sqrt();
                    if cos < 0.0 && best.is_none_or(|b| cos < b.0) {
                        best = Some((cos, dot(sub(px, pu), uw) / len2));
                    }
                }
            }
        }
        self.star = star;
        best.map(|b| b.1).filter(|f| (0.2..=0.8).contains(f))
    }

    /// The facets (positions in `facs`) having segment `s` as an edge.
    fn facets_of_segment(&self, s: usize) -> Vec<u32> {
        self.seg_facets[s].clone()
    }

    fn not_recovered(&self, facets: Vec<u32>) -> RecoveryError {
        let mut named: Vec<u64> = facets
            .iter()
            .map(|&f| u64::from(self.facs[f as usize].facet) + self.first())
            .collect();
        named.sort_unstable();
        named.dedup();
        RecoveryError::SurfaceNotRecovered {
            facets: named,
            added: self.added,
        }
    }

    /// Barycentric coordinates (in facet `f`'s corners) of each of its vertices: the boundary
    /// loop (counter-clockwise from corner 0) then the interior points.
    fn facet_vertices(&self, f: usize) -> (Vec<VertexId>, Vec<[f64; 3]>, usize) {
        let fac = &self.facs[f];
        let mut verts = Vec::new();
        let mut bary = Vec::new();
        for k in 0..3 {
            let (s, reversed) = fac.segs[k];
            let pts = &self.segs[s as usize].pts;
            let n = pts.len();
            for j in 0..n - 1 {
                let (t, v, _) = if reversed { pts[n - 1 - j] } else { pts[j] };
                let t = if reversed { 1.0 - t } else { t };
                let mut b = [0.0; 3];
                b[k] = 1.0 - t;
                b[(k + 1) % 3] = t;
                verts.push(v);
                bary.push(b);
            }
        }
        let n_boundary = verts.len();
        for &(b, v) in &fac.interior {
            verts.push(v);
            bary.push(b);
        }
        (verts, bary, n_boundary)
    }

    /// Recomputes the sub-faces of stale facets and returns the missing ones, as
    /// `(facet, sub-face index)`.
    fn check_faces(&mut self) -> Vec<(u32, [VertexId; 3])> {
        // The facets' own triangulations, in parallel (each reads only its facet).
        let stale: Vec<usize> = (0..self.facs.len())
            .filter(|&f| self.facs[f].stale)
            .collect();
        let this = &*self;
        let made: Vec<Vec<[VertexId; 3]>> = stale
            .par_iter()
            .with_min_len(64)
            .map(|&f| this.reference_subfaces(f))
            .collect();
        for (f, subfaces) in stale.into_iter().zip(made) {
            self.facs[f].subfaces = subfaces;
            self.facs[f].stale = false;
            self.facs[f].complete_at = 0;
        }
        let mut missing = Vec::new();
        let mut star = std::mem::take(&mut self.star);
        for f in 0..self.facs.len() {
            let fac = &self.facs[f];
            let since = fac.complete_at;
            if since > 0
                && fac
                    .subfaces
                    .iter()
                    .flatten()
                    .all(|v| self.touched[v.index()] <= since)
            {
                continue; // complete at its last check, and nothing near it changed
            }
            let mut subfaces = std::mem::take(&mut self.facs[f].subfaces);
            let mut absent: Vec<usize> = Vec::new();
            for (k, t) in subfaces.iter().enumerate() {
                // Present at the last check, and no insertion since has reached it.
                if since > 0 && t.iter().all(|v| self.touched[v.index()] <= since) {
                    continue;
                }
                let present = |v: &[VertexId]| v.contains(&t[1]) && v.contains(&t[2]);
                if self
                    .stars
                    .find(self.ct.triangulation(), t[0], &mut star, present)
                    .is_none()
                {
                    absent.push(k);
                }
            }
            if absent.len() >= 2 {
                self.follow_diagonals(f, &mut subfaces, &mut absent, &mut star);
            }
            for &k in &absent {
                missing.push((f as u32, subfaces[k]));
            }
            self.facs[f].subfaces = subfaces;
            self.facs[f].complete_at = if absent.is_empty() { self.changes } else { 0 };
        }
        self.star = star;
        missing
    }

    /// Every sub-segment (segment, position; sorted) whose two sub-faces (one in each facet along it) are two faces
    /// of one tetrahedron in the domain that is flat (a dihedral angle under
    /// [`FLAT_DIHEDRAL`]): two nearly coplanar surface triangles whose corners are nearly
    /// co-circular, on a flat part of the surface. A point on the edge lies inside that
    /// tetrahedron's circumsphere, so splitting the edge removes it.
    fn edges_under_flat_tetrahedra(&mut self, sides: &[f64]) -> Vec<(usize, usize)> {
        let mut todo: Vec<(usize, usize)> = Vec::new();
        let mut star = std::mem::take(&mut self.star);
        for si in 0..self.segs.len() {
            let facets = &self.seg_facets[si];
            if facets.len() != 2 {
                continue;
            }
            let side = |f: u32| sides.get(f as usize).copied().unwrap_or(0.0);
            let (s0, s1) = (side(facets[0]), side(facets[1]));
            if s0 == 0.0 || s1 == 0.0 {
                continue;
            }
            for k in 0..self.segs[si].pts.len() - 1 {
                let (u, w) = (self.segs[si].pts[k].1, self.segs[si].pts[k + 1].1);
                // The apex of the sub-face along u w in each facet, and that sub-face.
                let apex = |f: u32| {
                    self.facs[f as usize].subfaces.iter().find_map(|t| {
                        (0..3).find_map(|m| {
                            let (a, b) = (t[m], t[(m + 1) % 3]);
                            ((a == u && b == w) || (a == w && b == u))
                                .then_some((*t, t[(m + 2) % 3]))
                        })
                    })
                };
                let (Some((t0, x)), Some((t1, y))) = (apex(facets[0]), apex(facets[1])) else {
                    continue;
                };
                // Only where the surface itself is flat across the edge: the two sub-faces'
                // normals (both oriented with their facets) within the angle. This cheap test
                // comes first; the star search only where it passes.
                let normal = |t: [VertexId; 3]| {
                    let q = t.map(|v| self.ct.triangulation().vertex(v));
                    cross(sub(q[1], q[0]), sub(q[2], q[0]))
                };
                let (n0, n1) = (normal(t0), normal(t1));
                let cos = dot(n0, n1) / (dot(n0, n0) * dot(n1, n1)).sqrt();
                let pts = [u, w, x, y].map(|z| self.ct.triangulation().vertex(z));
                if cos < FLAT_SURFACE.to_radians().cos()
                    || min_dihedral(pts) >= FLAT_DIHEDRAL
                    || (self.field_points_follow && reaches_deep(pts, n0, s0))
                {
                    continue;
                }
                let on_domain_side = |t: [VertexId; 3], z: VertexId, s: f64| {
                    if s == BOTH_SIDES {
                        return true;
                    }
                    let q = [t[0], t[1], t[2], z].map(|v| self.ct.triangulation().vertex(v));
                    let above = orient3d(q[0], q[1], q[2], q[3]) == Sign::Positive;
                    if above {
                        s > 0.0
                    } else {
                        s < 0.0
                    }
                };
                // (The star search last: it costs more than the orientation tests.)
                if on_domain_side(t0, y, s0)
                    && on_domain_side(t1, x, s1)
                    && is_tetrahedron(
                        &mut self.stars,
                        self.ct.triangulation(),
                        [u, w, x, y],
                        &mut star,
                    )
                {
                    todo.push((si, k));
                }
            }
        }
        self.star = star;
        todo.sort_unstable();
        todo
    }

    /// Where the four corners of two adjacent sub-faces of a facet form a tetrahedron (a flat
    /// one: the corners are nearly co-circular in the facet's plane, so the Delaunay
    /// tetrahedralisation has both diagonals), takes as sub-faces the pair that leaves it on the
    /// side away from the domain, so it is deleted with the exterior instead of staying in the
    /// mesh as a sliver. `sides[f]` is the domain's side of facet `f` (+1 along its normal, −1
    /// against it, 0 unknown: nothing done). Returns how many were moved out.
    fn move_flat_tetrahedra_out(&mut self, sides: &[f64]) -> usize {
        let mut moved = 0;
        let mut star = std::mem::take(&mut self.star);
        for f in 0..self.facs.len() {
            let s = sides.get(f).copied().unwrap_or(0.0);
            // A wall's flat tetrahedra are in the domain on either side.
            if s == 0.0 || s == BOTH_SIDES || self.facs[f].subfaces.len() < 2 {
                continue;
            }
            let mut subfaces = std::mem::take(&mut self.facs[f].subfaces);
            let on_edges = self.boundary_edges_at(f);
            let coords = self.facet_frame_coords(f);
            // The sub-faces by their directed edges; a pair shares an edge run both ways.
            let mut by_edge: HashMap<(VertexId, VertexId), usize> = HashMap::default();
            for (k, &t) in subfaces.iter().enumerate() {
                by_edge.extend(directed_edges(t).map(|e| (e, k)));
            }
            // Each swap puts its tetrahedron outside for good, so they end; the bound only
            // guards against a bug.
            let mut stack: Vec<usize> = (0..subfaces.len()).collect();
            let mut budget = 8 * subfaces.len();
            while let Some(i) = stack.pop() {
                let t = subfaces[i];
                for e in 0..3 {
                    let (u, w, x) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
                    let Some(&j) = by_edge.get(&(w, u)) else {
                        continue;
                    };
                    // The neighbour runs w → u; its third corner y must be a fourth point.
                    let o = subfaces[j];
                    let Some(m) = (0..3).find(|&m| o[m] == w && o[(m + 1) % 3] == u) else {
                        continue;
                    };
                    let y = o[(m + 2) % 3];
                    if j == i
                        || y == x
                        || on_one_edge(&on_edges, [u, y, x])
                        || on_one_edge(&on_edges, [y, w, x])
                    {
                        continue;
                    }
                    // y is on the side of (u, w, x)'s normal (the facet's) when positive.
                    let p = [u, w, x, y].map(|z| self.ct.triangulation().vertex(z));
                    let side = orient3d(p[0], p[1], p[2], p[3]);
                    if side == Sign::Zero {
                        continue;
                    }
                    let above = side == Sign::Positive;
                    let inside = if above { s > 0.0 } else { s < 0.0 };
                    // The quadrilateral u y w x must be convex in the facet's plane, or the
                    // new sub-faces would fold over each other.
                    let convex = match (
                        coords.get(&u),
                        coords.get(&w),
                        coords.get(&x),
                        coords.get(&y),
                    ) {
                        (Some(&cu), Some(&cw), Some(&cx), Some(&cy)) => {
                            orient2d(cu, cy, cx) == Sign::Positive
                                && orient2d(cy, cw, cx) == Sign::Positive
                        }
                        _ => false,
                    };
                    // (The star search last: it costs more than the tests above.)
                    if inside
                        && convex
                        && budget > 0
                        && is_tetrahedron(
                            &mut self.stars,
                            self.ct.triangulation(),
                            [u, w, x, y],
                            &mut star,
                        )
                    {
                        budget -= 1;
                        for k in [i, j] {
                            for e in directed_edges(subfaces[k]) {
                                by_edge.remove(&e);
                            }
                        }
                        subfaces[i] = [u, y, x];
                        subfaces[j] = [y, w, x];
                        for k in [i, j] {
                            by_edge.extend(directed_edges(subfaces[k]).map(|e| (e, k)));
                        }
                        stack.extend([i, j]);
                        self.facs[f].complete_at = 0;
                        moved += 1;
                        break;
                    }
                }
            }
            self.facs[f].subfaces = subfaces;
        }
        self.star = star;
        moved
    }

    /// Where two adjacent sub-faces are both missing but the tetrahedralisation has the two
    /// triangles of the other diagonal of their quadrilateral (a co-circular choice made the
    /// other way), takes those instead (and drops them from `absent`).
    fn follow_diagonals(
        &mut self,
        f: usize,
        subfaces: &mut [[VertexId; 3]],
        absent: &mut Vec<usize>,
        star: &mut Vec<CellId>,
    ) {
        let coords = self.facet_frame_coords(f);
        let on_edges = self.boundary_edges_at(f);
        // The missing sub-faces by their directed edges: a pair shares an edge run both ways.
        let mut by_edge: HashMap<(VertexId, VertexId), usize> = HashMap::default();
        for &k in absent.iter() {
            by_edge.extend(directed_edges(subfaces[k]).map(|e| (e, k)));
        }
        let mut found = vec![false; subfaces.len()];
        for &ti in absent.iter() {
            if found[ti] {
                continue;
            }
            let t = subfaces[ti];
            for e in 0..3 {
                let (u, w, x) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
                let Some(&tj) = by_edge.get(&(w, u)) else {
                    continue;
                };
                if tj == ti || found[tj] {
                    continue;
                }
                // The neighbour runs w → u: its third corner follows u.
                let s = subfaces[tj];
                let y = s[((0..3).find(|&m| s[m] == u).unwrap_or(0) + 1) % 3];
                if on_one_edge(&on_edges, [u, y, x]) || on_one_edge(&on_edges, [y, w, x]) {
                    continue;
                }
                let (cu, cw, cx, cy) = (coords[&u], coords[&w], coords[&x], coords[&y]);
                if orient2d(cu, cy, cx) != Sign::Positive || orient2d(cy, cw, cx) != Sign::Positive
                {
                    continue;
                }
                self.stars.star(self.ct.triangulation(), x, star);
                if find_face_in(self.ct.triangulation(), star, u, y, x).is_some()
                    && find_face_in(self.ct.triangulation(), star, y, w, x).is_some()
                {
                    subfaces[ti] = [u, y, x];
                    subfaces[tj] = [y, w, x];
                    (found[ti], found[tj]) = (true, true);
                    break;
                }
            }
        }
        absent.retain(|&k| !found[k]);
    }

    /// For each vertex on facet `f`'s boundary, the facet edges (indices into its `segs`) it
    /// lies on: one, or two at a corner (more where a merged facet's loops touch).
    fn boundary_edges_at(&self, f: usize) -> HashMap<VertexId, Vec<u32>> {
        let mut on_edges: HashMap<VertexId, Vec<u32>> = HashMap::default();
        for (k, &(s, _)) in self.facs[f].segs.iter().enumerate() {
            for p in &self.segs[s as usize].pts {
                on_edges.entry(p.1).or_default().push(k as u32);
            }
        }
        on_edges
    }

    /// 2D coordinates in facet `f`'s plane of its vertices.
    fn facet_frame_coords(&self, f: usize) -> HashMap<VertexId, [f64; 2]> {
        let (verts, bary, _) = self.facet_vertices(f);
        let frame = self.frame(f);
        verts
            .iter()
            .zip(&bary)
            .map(|(&v, &b)| (v, frame_point(&frame, b)))
            .collect()
    }

    /// The facet's corners in its own plane: `(0, 0)`, `(|b - a|, 0)`, and `c` above the x axis.
    fn frame(&self, f: usize) -> [[f64; 2]; 3] {
        let c = self.facs[f].corners.map(|i| self.point(i));
        let (ab, ac) = (sub(c[1], c[0]), sub(c[2], c[0]));
        let len = dot(ab, ab).sqrt();
        let e1 = [ab[0] / len, ab[1] / len, ab[2] / len];
        let n = cross(ab, ac);
        let mut e2 = cross(n, e1);
        let l2 = dot(e2, e2).sqrt();
        e2 = [e2[0] / l2, e2[1] / l2, e2[2] / l2];
        [[0.0, 0.0], [len, 0.0], [dot(ac, e1), dot(ac, e2)]]
    }

    /// The sub-faces of facet `f`: the constrained Delaunay triangulation of its vertices in its
    /// plane, counter-clockwise like the facet.
    fn reference_subfaces(&self, f: usize) -> Vec<[VertexId; 3]> {
        let (verts, bary, n_boundary) = self.facet_vertices(f);
        if verts.len() == 3 {
            return vec![[verts[0], verts[1], verts[2]]];
        }
        let frame = self.frame(f);
        let pts: Vec<[f64; 2]> = bary.iter().map(|&b| frame_point(&frame, b)).collect();
        let Ok(tri) = Triangulation2::new(&pts) else {
            return vec![self.facs[f]
                .corners
                .map(|i| self.ct.triangulation().vertex_of_input(i as usize))];
        };
        let ids: Vec<VertexId> = (0..pts.len()).map(|i| tri.vertex_of_input(i)).collect();
        let local = |i: usize| ids[i];
        let mut cdt = ConstrainedTriangulation2::new(tri);
        for k in 0..n_boundary {
            let (a, b) = (local(k), local((k + 1) % n_boundary));
            if a != b {
                // A point exactly on a boundary sub-segment in the plane would stop the
                // constraint; the Delaunay edges are then used as they are.
                let _ = cdt.insert_segment(a, b);
            }
        }
        // Flood from the triangle left of the first boundary sub-segment, within constraints.
        let t2 = cdt.triangulation();
        let mut back = vec![VertexId::GHOST; t2.num_vertices()];
        for (i, &v) in verts.iter().enumerate() {
            back[local(i).index()] = v;
        }
        let Some((found, i)) = cdt.find_edge(local(0), local(1)) else {
            return vec![self.facs[f]
                .corners
                .map(|i| self.ct.triangulation().vertex_of_input(i as usize))];
        };
        // The cell with the edge running counter-clockwise is on its left: inside.
        let cell = t2.cell(found);
        let k = cell.iter().position(|&u| u == local(0)).unwrap_or(0);
        let start = if cell[(k + 1) % 3] == local(1) {
            found
        } else {
            t2.neighbor_facet(found, i).cell()
        };
        if t2.is_ghost(start) {
            return vec![self.facs[f]
                .corners
                .map(|i| self.ct.triangulation().vertex_of_input(i as usize))];
        }
        let mut seen = vec![false; t2.all_cells().map(|c| c.index() + 1).max().unwrap_or(0)];
        let mut stack = vec![start];
        seen[start.index()] = true;
        let mut out = Vec::new();
        while let Some(c) = stack.pop() {
            let cell = t2.cell(c);
            out.push([
                back[cell[0].index()],
                back[cell[1].index()],
                back[cell[2].index()],
            ]);
            for i in 0..3 {
                if cdt.is_constrained(c, i) {
                    continue;
                }
                let n = t2.neighbor_facet(c, i).cell();
                if !seen[n.index()] && !t2.is_ghost(n) {
                    seen[n.index()] = true;
                    stack.push(n);
                }
            }
        }
        out
    }

    /// Inserts the centroid of the missing sub-face `t` of facet `f` (true), or splits the
    /// sub-segment of the facet's boundary that `t` encroaches (false): see
    /// [`State::encroached_subsegment`].
    fn split_face(&mut self, f: u32, t: [VertexId; 3]) -> Result<bool, RecoveryError> {
        if self.added >= self.budget {
            return Err(self.not_recovered(vec![f]));
        }
        let (verts, bary, n_boundary) = self.facet_vertices(f as usize);
        if let Some((s, k)) = self.encroached_subsegment(f as usize, t, &verts, &bary, n_boundary) {
            self.split_subsegment(s, k)?;
            return Ok(false);
        }
        let mut b = [0.0; 3];
        for v in t {
            let Some(i) = verts.iter().position(|&u| u == v) else {
                return Err(self.not_recovered(vec![f]));
            };
            for k in 0..3 {
                b[k] += bary[i][k] / 3.0;
            }
        }
        let c = self.facs[f as usize].corners.map(|i| self.point(i));
        // A coordinate the three corners share (an axis-aligned facet) is kept exactly.
        let p = [0, 1, 2].map(|k| {
            if c[0][k] == c[1][k] && c[1][k] == c[2][k] {
                c[0][k]
            } else {
                b[0] * c[0][k] + b[1] * c[1][k] + b[2] * c[2][k]
            }
        });
        let s = self.facs[f as usize]
            .corners
            .map(|i| self.spacing[self.ct.triangulation().vertex_of_input(i as usize).index()]);
        let spacing = b[0] * s[0] + b[1] * s[1] + b[2] * s[2];
        let Some(v) = self.add_vertex(p, spacing, t[0])? else {
            return Err(self.not_recovered(vec![f]));
        };
        let fac = &mut self.facs[f as usize];
        fac.interior.push((b, v));
        fac.stale = true;
        Ok(true)
    }

    /// The sub-segment `(segment, position)` of facet `f`'s boundary that is an edge of the
    /// missing sub-face `t` with the angle opposite it obtuse (`t`'s third corner inside the
    /// edge's diametral circle), if any. The centroids of such sub-faces would come ever closer
    /// to that edge (a third of the way each time: a thin slot's wall next to the other wall
    /// until a centroid rounds onto an existing vertex), so the edge is split instead, which
    /// moves the sub-faces off it.
    ///
    /// `verts`, `bary` and `n_boundary` are [`State::facet_vertices`] of `f`.
    fn encroached_subsegment(
        &self,
        f: usize,
        t: [VertexId; 3],
        verts: &[VertexId],
        bary: &[[f64; 3]],
        n_boundary: usize,
    ) -> Option<(usize, usize)> {
        let frame = self.frame(f);
        let pos = t.map(|v| verts.iter().position(|&u| u == v));
        for e in 0..3 {
            let (i, j, o) = (pos[e]?, pos[(e + 1) % 3]?, pos[(e + 2) % 3]?);
            if i >= n_boundary || j >= n_boundary {
                continue;
            }
            let first = if (i + 1) % n_boundary == j {
                i
            } else if (j + 1) % n_boundary == i {
                j
            } else {
                continue;
            };
            let [a, b, c] = [i, j, o].map(|k| frame_point(&frame, bary[k]));
            if (a[0] - c[0]) * (b[0] - c[0]) + (a[1] - c[1]) * (b[1] - c[1]) < 0.0 {
                return Some(self.subsegment_at(f, first));
            }
        }
        None
    }

    /// The sub-segment `(segment, position)` from the vertex at position `at` of facet `f`'s
    /// boundary loop (as [`State::facet_vertices`] lists it) to the next one.
    fn subsegment_at(&self, f: usize, mut at: usize) -> (usize, usize) {
        for &(s, reversed) in &self.facs[f].segs {
            let n = self.segs[s as usize].pts.len();
            if at < n - 1 {
                return (s as usize, if reversed { n - 2 - at } else { at });
            }
            at -= n - 1;
        }
        unreachable!("a position on the facet's boundary loop")
    }
}

/// The directed edges of the triangle `t`, in its orientation: two triangles on one side of
/// a surface share an edge run both ways.
fn directed_edges(t: [VertexId; 3]) -> [(VertexId, VertexId); 3] {
    [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]
}

/// Whether the three corners of `t` lie on one edge of a facet (`on_edges`: its
/// [`State::boundary_edges_at`]): such a triangle has no area, though a point rounded off the edge's
/// line can make it look positive in the facet's frame.
fn on_one_edge(on_edges: &HashMap<VertexId, Vec<u32>>, t: [VertexId; 3]) -> bool {
    let edges = |v: VertexId| on_edges.get(&v).map_or(&[][..], |e| &e[..]);
    edges(t[0])
        .iter()
        .any(|k| edges(t[1]).contains(k) && edges(t[2]).contains(k))
}

/// A point of the facet frame from barycentric coordinates.
fn frame_point(frame: &[[f64; 2]; 3], b: [f64; 3]) -> [f64; 2] {
    [
        b[1] * frame[1][0] + b[2] * frame[2][0],
        b[1] * frame[1][1] + b[2] * frame[2][1],
    ]
}
