//! [`BoundaryRecovery`]: from a [`Plc2`] to a boundary-conforming [`Mesh2`] (R4, R5, R8, R9).
//!
//! Three methods, all ending with every input segment present as a union of edges, those
//! edges constrained (later insertions never cross or remove them), and the exterior classified:
//! - [`RecoveryMethod::Stitch`], the paper's a-posteriori edge checking: triangulate the points,
//!   insert the mid-point of every missing (sub)segment, repeat until none is missing.
//!   A sub-segment with one end at an input vertex is split instead where a circle of radius
//!   2^k (the power of two nearest its middle) around that vertex cuts it: the concentric shells
//!   of Ruppert and Shewchuk. Segments meeting at a small angle are then split at equal
//!   distances from their shared vertex and stop encroaching on each other, so the loop ends.
//! - [`RecoveryMethod::APriori`], Weatherill's point per boundary edge: beside every boundary
//!   edge, an interior point on the largest empty circle through the edge that is no larger than
//!   the equilateral one, so the edge is Delaunay by construction. Edges whose circle cannot be
//!   kept empty (tight corners) are left to stitching, which also repairs anything the new
//!   points broke; the history shows how many.
//! - [`RecoveryMethod::Constrained`], beyond the paper: missing segments are inserted by edge
//!   flips, so no point is added on the boundary (a constrained Delaunay triangulation).

use crate::check::{agreed_marker, check, CheckedPlc};
use crate::classify::{classify, overridden_message, SeedName, OUTSIDE};
use crate::error::RecoveryError;
use crate::plc::{spacing_for_area, Plc2};
use delmesh_delaunay_core::{
    insertion_order, CellId, ConstrainedTriangulation2, ConstraintError, Insertion, Location,
    Triangulation2, VertexId, D2,
};
use delmesh_predicates::{orient2d, Sign};
use rustc_hash::FxHashMap as HashMap;
use std::collections::hash_map::Entry;
use std::fmt;
use std::sync::Arc;

/// How missing boundary segments are recovered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RecoveryMethod {
    /// Mid-point insertion until every segment is present (the paper's edge checking, R4).
    #[default]
    Stitch,
    /// One interior point per boundary edge, then stitching for what is left (R5).
    APriori,
    /// Edge flips, no point added (constrained Delaunay).
    Constrained,
}

/// One pass of recovery: the 2D analogue of the paper's Table 2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecoveryPass {
    /// Vertices in the triangulation at the start of the pass.
    pub points: usize,
    /// Triangles (finite cells, exterior included) at the start of the pass.
    pub triangles: usize,
    /// Boundary edges (sub-segments) to be present.
    pub boundary_edges: usize,
    /// Of those, how many were missing.
    pub missing: usize,
    /// Points inserted in the pass (mid-points, shell points or a-priori points).
    pub inserted: usize,
}

/// What recovery did: its passes, in order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RecoveryHistory {
    /// The method used.
    pub method: RecoveryMethod,
    /// The passes.
    pub passes: Vec<RecoveryPass>,
    /// A-priori points placed (APriori only).
    pub a_priori_points: usize,
    /// Boundary edges for which no empty circle was found (APriori only).
    pub a_priori_rejected: usize,
    /// Input points that repeat an earlier one exactly, merged into it: (duplicate, first),
    /// in the input's numbering.
    pub merged_points: Vec<(u64, u64)>,
    /// Merged duplicates whose boundary marker differs from the one the point they merge into
    /// keeps: (duplicate, its marker, first, the kept marker), in the input's numbering. (A
    /// duplicate's marker goes to a first point without one.)
    pub merged_markers_dropped: Vec<(u64, i32, u64, i32)>,
    /// Hole and region seeds beyond the outer boundary, which do nothing: `("hole" |
    /// "region", number)` in the input's numbering (a seed with a wrong coordinate, or in
    /// other units, would otherwise go unnoticed).
    pub seeds_outside: Vec<SeedName>,
    /// Seeds another seed overrides, as (overridden, winner): a region seed in the same
    /// region as a later one with another attribute (the last wins, as in Triangle), or in
    /// the part a hole seed removes.
    pub seeds_overridden: Vec<(SeedName, SeedName)>,
    /// Input segments with no element on either side, in the input's numbering: a wake line
    /// beyond the outer boundary or inside a hole. They bound nothing and are in no output.
    /// (A closed loop beyond the outer boundary is another body, meshed.)
    pub segments_outside: Vec<u64>,
    /// Input segments with a piece that has no element on either side (a wake line running
    /// past the far field, a boundary stretch a hole shares), in the input's numbering: that
    /// piece is in no output.
    pub segments_partly_outside: Vec<u64>,
}

impl RecoveryHistory {
    /// Points added on the boundary (by stitching) and beside it (a-priori), in total.
    pub fn points_added(&self) -> usize {
        self.passes.iter().map(|p| p.inserted).sum()
    }
}

impl fmt::Display for RecoveryHistory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:>5} {:>9} {:>10} {:>15} {:>8} {:>9}",
            "pass", "points", "triangles", "boundary edges", "missing", "inserted"
        )?;
        for (k, p) in self.passes.iter().enumerate() {
            writeln!(
                f,
                "{:>5} {:>9} {:>10} {:>15} {:>8} {:>9}",
                k + 1,
                p.points,
                p.triangles,
                p.boundary_edges,
                p.missing,
                p.inserted
            )?;
        }
        if self.method == RecoveryMethod::APriori {
            writeln!(
                f,
                "a-priori points: {} ({} edges left to stitching)",
                self.a_priori_points, self.a_priori_rejected
            )?;
        }
        if !self.merged_points.is_empty() {
            writeln!(
                f,
                "duplicates merged: {} ({})",
                self.merged_points.len(),
                merged_list(&self.merged_points)
            )?;
        }
        for &(d, dm, first, kept) in &self.merged_markers_dropped {
            writeln!(
                f,
                "warning: point {d} repeats point {first} with boundary marker {dm}, dropped \
                 (point {first} keeps {kept})"
            )?;
        }
        for (what, k) in &self.seeds_outside {
            writeln!(
                f,
                "warning: {what} seed {k} lies outside the domain (beyond its outer boundary) \
                 and does nothing"
            )?;
        }
        for &(seed, by) in &self.seeds_overridden {
            writeln!(f, "warning: {}", overridden_message(seed, by))?;
        }
        if let Some(list) = numbers(&self.segments_outside) {
            let (noun, verb) = plural(self.segments_outside.len());
            writeln!(
                f,
                "warning: {noun} {list} {verb} outside the domain (no element on either side) \
                 and in no output"
            )?;
        }
        if let Some(list) = numbers(&self.segments_partly_outside) {
            let (noun, verb) = plural(self.segments_partly_outside.len());
            writeln!(
                f,
                "warning: {noun} {list} {verb} partly outside the domain: the pieces with no \
                 element on either side are in no output"
            )?;
        }
        Ok(())
    }
}

/// The first few of `list` (see [`MERGED_SHOWN`]) as `5, 6, 9, and 4 more`, if any.
fn numbers(list: &[u64]) -> Option<String> {
    (!list.is_empty()).then(|| first_few(list, u64::to_string))
}

/// The first [`MERGED_SHOWN`] of `items`, each written by `name`, joined by commas, and how
/// many more there are (`5, 6, 9, and 4 more`).
fn first_few<T>(items: &[T], name: impl Fn(&T) -> String) -> String {
    let shown: Vec<String> = items.iter().take(MERGED_SHOWN).map(name).collect();
    match items.len().saturating_sub(MERGED_SHOWN) {
        0 => shown.join(", "),
        more => format!("{}, and {more} more", shown.join(", ")),
    }
}

/// "segment lies" or "segments lie".
fn plural(n: usize) -> (&'static str, &'static str) {
    if n == 1 {
        ("segment", "lies")
    } else {
        ("segments", "lie")
    }
}

/// How many merged duplicate points, or segments outside the domain, a recovery history lists
/// by number.
const MERGED_SHOWN: usize = 5;

/// The first merged duplicates as `points 5 into 3, 9 into 1, and 4 more`.
pub(crate) fn merged_list(merged: &[(u64, u64)]) -> String {
    format!(
        "points {}",
        first_few(merged, |(d, first)| format!("{d} into {first}"))
    )
}

/// A boundary edge of the mesh: a piece of an input segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoundaryEdge {
    /// First end.
    pub a: VertexId,
    /// Second end.
    pub b: VertexId,
    /// The input segment's boundary marker.
    pub marker: i32,
    /// The input segment (0-based) it belongs to.
    pub segment: u32,
}

/// A boundary-conforming triangulation of a [`Plc2`]: the value the later stages (point
/// generation, smoothing, output) work on.
///
/// It keeps the whole triangulation of the convex hull; cells outside the domain are tagged
/// [`OUTSIDE`] and never reported as elements, and the boundary edges are constrained, so points
/// inserted inside the domain stay inside it.
#[derive(Clone, Debug)]
pub struct Mesh2 {
    /// The triangulation with its constrained boundary edges; cell tags are region indices.
    pub cdt: ConstrainedTriangulation2,
    /// The boundary edges.
    pub edges: Vec<BoundaryEdge>,
    /// Spacing at each vertex (by vertex index), NaN where recovery knows none.
    pub spacing: Vec<f64>,
    /// Attribute of each region index (index 0: the default region, 0.0).
    pub region_attributes: Vec<f64>,
    /// Boundary marker of each input point (0 when none).
    pub point_markers: Vec<i32>,
    /// Number of input points (vertices with a smaller input index are input points).
    pub n_input_points: usize,
    /// The recovery passes.
    pub history: RecoveryHistory,
}

/// Boundary recovery of a [`Plc2`]; see the module docs.
#[derive(Clone, Debug, Default)]
pub struct BoundaryRecovery {
    method: RecoveryMethod,
    extra_points: Vec<[f64; 2]>,
    area_limits: bool,
    segment_splits: Option<SegmentSplits>,
}

/// Where to split a boundary edge, given its ends: the parameters in `(0, 1)`, increasing
/// (empty: keep it whole). See [`BoundaryRecovery::with_segment_splits`].
#[derive(Clone)]
pub struct SegmentSplits(pub Arc<SplitFn>);

/// The function of [`SegmentSplits`].
pub type SplitFn = dyn Fn([f64; 2], [f64; 2]) -> Vec<f64> + Send + Sync;

impl std::fmt::Debug for SegmentSplits {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SegmentSplits(..)")
    }
}

/// A piece of a checked segment while stitching.
#[derive(Clone, Copy, Debug)]
struct Sub {
    a: VertexId,
    b: VertexId,
    segment: u32,
}

impl BoundaryRecovery {
    /// Recovery with the given method.
    pub fn new(method: RecoveryMethod) -> Self {
        BoundaryRecovery {
            method,
            extra_points: Vec::new(),
            area_limits: false,
            segment_splits: None,
        }
    }

    /// Splits every recovered boundary edge where `splits` says (spacing sources finer than
    /// the boundary: point generation cannot fill the domain finer next to a boundary edge
    /// than the edge itself, and thin elements pile up along it), then recovers the pieces.
    pub fn with_segment_splits(mut self, splits: SegmentSplits) -> Self {
        self.segment_splits = Some(splits);
        self
    }

    /// Splits the boundary edges next to a region with an area limit
    /// ([`crate::RegionSeed::max_area`]) into equal pieces no longer than the spacing that
    /// meets the limit ([`spacing_for_area`]), as Triangle splits the segments its area
    /// refinement encroaches: point generation then fills the region from a boundary spaced
    /// like it. Off by default (a recovery alone adds only the points it needs).
    pub fn with_area_limits(mut self, on: bool) -> Self {
        self.area_limits = on;
        self
    }

    /// Adds points from an external source (R9: e.g. the nodes of separate component meshes);
    /// those that fall outside the domain are dropped with the exterior.
    pub fn with_points(mut self, points: Vec<[f64; 2]>) -> Self {
        self.extra_points = points;
        self
    }

    /// Recovers the boundary of `plc` and classifies the exterior.
    ///
    /// # Errors
    /// Invalid input (see [`RecoveryError`]), or a domain with no element inside.
    pub fn run(&self, plc: &Plc2) -> Result<Mesh2, RecoveryError> {
        let n_input = plc.points.len();
        if let Some(i) = self
            .extra_points
            .iter()
            .position(|p| !p[0].is_finite() || !p[1].is_finite())
        {
            return Err(RecoveryError::NonFinite {
                point: (n_input + i) as u64 + u64::from(plc.first_index),
            });
        }
        // Extra points are checked with the input's: one inside a segment splits it there (it
        // could never be recovered past it), one on an input point is merged with it.
        let with_extra;
        let all = if self.extra_points.is_empty() {
            plc
        } else {
            let mut p = plc.clone();
            p.points.extend_from_slice(&self.extra_points);
            with_extra = p;
            &with_extra
        };
        let checked = check(all, self.method != RecoveryMethod::Constrained)?;
        let points = checked.points.clone();
        let tri =
            Triangulation2::new(&points).map_err(|e| e.numbered_from(plc.first_index as usize))?;
        let base = u64::from(plc.first_index);
        let mut history = RecoveryHistory {
            method: self.method,
            merged_points: checked
                .merged
                .iter()
                .map(|&(d, first)| (u64::from(d) + base, u64::from(first) + base))
                .collect(),
            ..Default::default()
        };
        let mut state = State::new(tri, &checked, plc);
        let cdt = match self.method {
            RecoveryMethod::Stitch => {
                state.stitch(&mut history)?;
                state.constrain()?
            }
            RecoveryMethod::APriori => {
                state.stitch(&mut history)?;
                let mut cdt = state.constrain()?;
                classify(&mut cdt, plc)?;
                let placed = a_priori_points(&mut cdt, &state, &mut history);
                state.tri = cdt.into_triangulation();
                let before = state.pass(0);
                // In a spatially sorted, randomised order: in boundary order, each point
                // next to a finely divided circle would rebuild the cells across it.
                let at: Vec<[f64; 2]> = placed.iter().map(|p| p.point).collect();
                for i in insertion_order::<D2>(&at) {
                    let p = &placed[i as usize];
                    state.add_vertex(p.point, None, p.spacing)?;
                }
                let mut pass = before;
                pass.inserted = state.tri.num_vertices() - before.points;
                history.passes.push(pass);
                state.stitch(&mut history)?;
                state.constrain()?
            }
            RecoveryMethod::Constrained => state.constrain_by_flips(&mut history)?,
        };
        let mut cdt = cdt;
        if let Some(SegmentSplits(split_at)) = &self.segment_splits {
            let tri = cdt.triangulation();
            let splits: Vec<(usize, Vec<f64>)> = state
                .subs
                .iter()
                .enumerate()
                .filter_map(|(i, s)| {
                    let at = split_at(tri.vertex(s.a), tri.vertex(s.b));
                    (!at.is_empty()).then_some((i, at))
                })
                .collect();
            if !splits.is_empty() {
                cdt = self.split_and_recover(&mut state, cdt, &splits, &mut history)?;
            }
        }
        if self.area_limits && plc.has_area_limits() {
            classify(&mut cdt, plc)?;
            check_area_limits(&cdt, plc)?;
            let longest: Vec<f64> = plc
                .area_limits()
                .into_iter()
                .map(spacing_for_area)
                .collect();
            let splits = long_subsegments(&cdt, &state.subs, &longest);
            if !splits.is_empty() {
                cdt = self.split_and_recover(&mut state, cdt, &splits, &mut history)?;
            }
        }
        let (region_attributes, seeds) = classify(&mut cdt, plc)?;
        history.seeds_outside = seeds.outside;
        history.seeds_overridden = seeds.overridden;
        let mut point_markers = plc.point_markers.clone();
        point_markers.resize(n_input, 0);
        // A duplicate's marker goes to the point it merges into if that has none; another
        // marker there is kept, and the dropped one named in a warning.
        for &(d, first) in &checked.merged {
            let (d, first) = (d as usize, first as usize);
            if d >= n_input || first >= n_input || point_markers[d] == point_markers[first] {
                continue;
            }
            if point_markers[first] == 0 {
                point_markers[first] = point_markers[d];
            } else if point_markers[d] != 0 {
                history.merged_markers_dropped.push((
                    d as u64 + base,
                    point_markers[d],
                    first as u64 + base,
                    point_markers[first],
                ));
            }
        }
        let edges = state
            .subs
            .iter()
            .map(|s| BoundaryEdge {
                a: s.a,
                b: s.b,
                marker: checked.segments[s.segment as usize].marker,
                segment: checked.origin[s.segment as usize],
            })
            .collect();
        let mut mesh = Mesh2 {
            cdt,
            edges,
            spacing: state.spacing,
            region_attributes,
            point_markers,
            n_input_points: n_input,
            history,
        };
        let base = u64::from(plc.first_index);
        let ends: Vec<(u32, u32)> = plc.segments.iter().map(|s| (s.a, s.b)).collect();
        let (outside, partly) = mesh.segments_outside(&ends);
        let named = |list: Vec<u32>| list.into_iter().map(|k| u64::from(k) + base).collect();
        mesh.history.segments_outside = named(outside);
        mesh.history.segments_partly_outside = named(partly);
        Ok(mesh)
    }

    /// Splits the sub-segments `splits` (index, parameters) of a recovered boundary and
    /// recovers the pieces.
    fn split_and_recover(
        &self,
        state: &mut State,
        cdt: ConstrainedTriangulation2,
        splits: &[(usize, Vec<f64>)],
        history: &mut RecoveryHistory,
    ) -> Result<ConstrainedTriangulation2, RecoveryError> {
        state.tri = cdt.into_triangulation();
        state.split_subsegments(splits, history)?;
        match self.method {
            RecoveryMethod::Constrained => state.constrain_by_flips(history),
            _ => {
                state.stitch(history)?;
                state.constrain()
            }
        }
    }
}

/// Stitching stops with an error once more sub-segments have been missing in this many passes
/// in a row than in the pass before, and more than [`MISSING_GROWTH`] times the fewest of any
/// pass (plus 64): the splits are not converging (see `State::stitch`).
const GROWING_PASSES: usize = 12;

/// See [`GROWING_PASSES`].
const MISSING_GROWTH: usize = 64;

/// Recovery in progress: the unconstrained triangulation and the sub-segments to be present.
struct State<'a> {
    tri: Triangulation2,
    subs: Vec<Sub>,
    checked: &'a CheckedPlc,
    spacing: Vec<f64>,
    /// Sub-segments shorter than this are a failure (beyond double precision).
    shortest: f64,
    plc: &'a Plc2,
}

impl<'a> State<'a> {
    fn new(tri: Triangulation2, checked: &'a CheckedPlc, plc: &'a Plc2) -> Self {
        let pts = &checked.points;
        let v = |i: u32| tri.vertex_of_input(i as usize);
        let subs: Vec<Sub> = checked
            .segments
            .iter()
            .enumerate()
            .map(|(k, s)| Sub {
                a: v(s.a),
                b: v(s.b),
                segment: k as u32,
            })
            .collect();
        // The paper's dp: mean length of the boundary segments at each boundary point.
        let mut sum = vec![0.0f64; tri.num_vertices()];
        let mut count = vec![0u32; tri.num_vertices()];
        for s in &checked.segments {
            let len = dist(pts[s.a as usize], pts[s.b as usize]);
            for e in [s.a, s.b] {
                let i = v(e).index();
                sum[i] += len;
                count[i] += 1;
            }
        }
        let spacing = sum
            .iter()
            .zip(&count)
            .map(|(&s, &c)| if c > 0 { s / f64::from(c) } else { f64::NAN })
            .collect();
        let (lo, hi) = pts.iter().fold(
            ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
            |(lo, hi), p| {
                (
                    [lo[0].min(p[0]), lo[1].min(p[1])],
                    [hi[0].max(p[0]), hi[1].max(p[1])],
                )
            },
        );
        State {
            tri,
            subs,
            checked,
            spacing,
            shortest: dist(lo, hi) * 2f64.powi(-44),
            plc,
        }
    }

    fn pass_of(&self, tri: &Triangulation2, inserted: usize) -> RecoveryPass {
        RecoveryPass {
            points: tri.num_vertices(),
            triangles: tri.num_cells(),
            boundary_edges: self.subs.len(),
            missing: 0,
            inserted,
        }
    }

    fn pass(&self, inserted: usize) -> RecoveryPass {
        self.pass_of(&self.tri, inserted)
    }

    fn is_input(&self, v: VertexId) -> bool {
        self.tri.input_index(v) < self.checked.points.len()
    }

    /// Sets the spacing of vertex `v`, growing the array (NaN: none known) to hold it.
    fn set_spacing(&mut self, v: VertexId, spacing: f64) {
        if self.spacing.len() <= v.index() {
            self.spacing.resize(v.index() + 1, f64::NAN);
        }
        self.spacing[v.index()] = spacing;
    }

    /// Inserts a new vertex with a spacing value, its location walk starting next to `near`
    /// if given.
    fn add_vertex(
        &mut self,
        p: [f64; 2],
        near: Option<VertexId>,
        spacing: f64,
    ) -> Result<Option<VertexId>, RecoveryError> {
        let inserted = match near {
            Some(v) => self.tri.insert_near(p, v)?,
            None => self.tri.insert(p)?,
        };
        match inserted {
            Insertion::Inserted(v) => {
                self.set_spacing(v, spacing);
                Ok(Some(v))
            }
            Insertion::Duplicate(_) => Ok(None),
        }
    }

    /// Mid-point / shell insertion until every sub-segment is present.
    ///
    /// Splitting ends, in exact arithmetic: shells keep the pieces next to an input vertex
    /// from hiding each other. Segments that meet at an angle that double precision cannot
    /// resolve (two segments 1 ulp apart) make split points round onto the wrong side, and the
    /// missing pieces multiply with each pass (by 1.8, for 43 passes before the pieces reach
    /// the shortest length: 10^11 points). Once more have been missing in each of
    /// [`GROWING_PASSES`] passes in a row than in the one before, and more than
    /// [`MISSING_GROWTH`] times the fewest of any pass (plus 64), the segment of the first is
    /// named as an error. (A star polygon of 1000 random spikes has 38 times more missing
    /// pieces after 8 passes of growth, then fewer.)
    fn stitch(&mut self, history: &mut RecoveryHistory) -> Result<(), RecoveryError> {
        let (mut fewest, mut last, mut growing) = (usize::MAX, usize::MAX, 0);
        // A cell that had each sub-segment when last checked: most survive a pass, and are
        // then confirmed by reading that one cell.
        let mut found: Vec<Option<CellId>> = Vec::new();
        loop {
            found.resize(self.subs.len(), None);
            let mut missing = Vec::new();
            for (i, s) in self.subs.iter().enumerate() {
                found[i] = self.tri.edge_cell(s.a, s.b, found[i]);
                if found[i].is_none() {
                    missing.push(i);
                }
            }
            let mut pass = self.pass(0);
            pass.missing = missing.len();
            if missing.is_empty() {
                history.passes.push(pass);
                return Ok(());
            }
            fewest = fewest.min(missing.len());
            growing = if missing.len() > last { growing + 1 } else { 0 };
            last = missing.len();
            if growing >= GROWING_PASSES && missing.len() > MISSING_GROWTH * fewest + 64 {
                let segment = self.subs[missing[0]].segment;
                return Err(RecoveryError::NotRecovered {
                    segment: u64::from(self.checked.origin[segment as usize])
                        + u64::from(self.plc.first_index),
                    splits: self.subs.iter().filter(|t| t.segment == segment).count() - 1,
                });
            }
            for &i in &missing {
                let s = self.subs[i];
                let (pa, pb) = (self.tri.vertex(s.a), self.tri.vertex(s.b));
                let len = dist(pa, pb);
                let seg = self.checked.segments[s.segment as usize];
                if len < self.shortest {
                    return Err(self.beyond_precision(s));
                }
                let split = match (self.is_input(s.a), self.is_input(s.b)) {
                    (true, false) => shell_point(pa, pb),
                    (false, true) => shell_point(pb, pa),
                    _ => [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])],
                };
                // Spacing along the input segment, linear between its ends' values.
                let (qa, qb) = (
                    self.checked.points[seg.a as usize],
                    self.checked.points[seg.b as usize],
                );
                let t = (dist(qa, split) / dist(qa, qb)).clamp(0.0, 1.0);
                let (da, db) = (
                    self.spacing[self.tri.vertex_of_input(seg.a as usize).index()],
                    self.spacing[self.tri.vertex_of_input(seg.b as usize).index()],
                );
                let Some(v) = self.add_vertex(split, Some(s.a), da + t * (db - da))? else {
                    return Err(self.beyond_precision(s));
                };
                self.subs[i].b = v;
                self.subs.push(Sub {
                    a: v,
                    b: s.b,
                    segment: s.segment,
                });
                pass.inserted += 1;
            }
            history.passes.push(pass);
        }
    }

    /// The error for sub-segment `s`, which splitting cannot make shorter.
    fn beyond_precision(&self, s: Sub) -> RecoveryError {
        RecoveryError::BeyondPrecision {
            segment: u64::from(self.checked.origin[s.segment as usize])
                + u64::from(self.plc.first_index),
            splits: self.subs.iter().filter(|t| t.segment == s.segment).count() - 1,
        }
    }

    /// Inserts the sub-segments into the triangulation by flips, adding no point (the
    /// Steiner-free recovery); a vertex found inside a sub-segment splits it there.
    fn constrain_by_flips(
        &mut self,
        history: &mut RecoveryHistory,
    ) -> Result<ConstrainedTriangulation2, RecoveryError> {
        let mut cdt = ConstrainedTriangulation2::new(std::mem::replace(
            &mut self.tri,
            Triangulation2::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])?,
        ));
        let mut pass = self.pass_of(cdt.triangulation(), 0);
        pass.missing = self
            .subs
            .iter()
            .filter(|s| cdt.find_edge(s.a, s.b).is_none())
            .count();
        history.passes.push(pass);
        // A vertex found inside a segment splits it there (as the input checks do for
        // the other methods); pieces that overlapping collinear segments share are
        // kept once, their markers agreeing as the input checks require.
        let mut work: Vec<Sub> = std::mem::take(&mut self.subs);
        work.reverse();
        let mut present: rustc_hash::FxHashMap<(VertexId, VertexId), usize> = Default::default();
        let base = u64::from(self.plc.first_index);
        while let Some(s) = work.pop() {
            match cdt.insert_segment(s.a, s.b) {
                Ok(()) => match present.entry((s.a.min(s.b), s.a.max(s.b))) {
                    Entry::Vacant(slot) => {
                        slot.insert(self.subs.len());
                        self.subs.push(s);
                    }
                    Entry::Occupied(slot) => {
                        let kept = &mut self.subs[*slot.get()];
                        let named = |k: u32| {
                            let segment = &self.checked.segments[k as usize];
                            (
                                segment.marker,
                                u64::from(self.checked.origin[k as usize]) + base,
                            )
                        };
                        let marker = agreed_marker(named(kept.segment), named(s.segment))?;
                        if marker != named(kept.segment).0 {
                            kept.segment = s.segment;
                        }
                    }
                },
                Err(ConstraintError::VertexOnSegment { vertex, .. }) => {
                    work.push(Sub { a: vertex, ..s });
                    work.push(Sub { b: vertex, ..s });
                }
                Err(e) => return Err(self.constraint_error(e, s.segment)),
            }
        }
        history.passes.push(self.pass_of(cdt.triangulation(), 0));
        Ok(cdt)
    }

    /// Splits each listed sub-segment `(index, pieces)` into that many equal pieces, inserting
    /// the points between them into the (unconstrained) triangulation, in a spatially sorted
    /// order; the pieces keep their segment (and so its marker), the points the piece length as
    /// spacing. One recovery pass in the history.
    fn split_subsegments(
        &mut self,
        splits: &[(usize, Vec<f64>)],
        history: &mut RecoveryHistory,
    ) -> Result<(), RecoveryError> {
        let before = self.pass(0);
        let mut at = Vec::new();
        for (i, ts) in splits {
            let (pa, pb) = (
                self.tri.vertex(self.subs[*i].a),
                self.tri.vertex(self.subs[*i].b),
            );
            at.extend(ts.iter().map(|&t| lerp(pa, pb, t)));
        }
        let mut vertex = vec![VertexId(0); at.len()];
        for k in insertion_order::<D2>(&at) {
            let k = k as usize;
            vertex[k] = match self.tri.insert(at[k])? {
                Insertion::Inserted(v) | Insertion::Duplicate(v) => v,
            };
        }
        let mut next = vertex.into_iter();
        for (i, ts) in splits {
            let (i, s) = (*i, self.subs[*i]);
            let length = dist(self.tri.vertex(s.a), self.tri.vertex(s.b));
            let mut a = s.a;
            for (k, v) in next.by_ref().take(ts.len()).enumerate() {
                // (A point rounded onto an end, or onto the previous point, splits nothing.)
                if v == a || v == s.b {
                    continue;
                }
                // The spacing there: the shorter of the pieces on either side.
                let before = ts[k] - if k > 0 { ts[k - 1] } else { 0.0 };
                let after = ts.get(k + 1).copied().unwrap_or(1.0) - ts[k];
                self.set_spacing(v, length * before.min(after));
                if a == s.a {
                    self.subs[i].b = v;
                } else {
                    self.subs.push(Sub { a, b: v, ..s });
                }
                a = v;
            }
            self.subs.push(Sub { a, ..s });
        }
        let mut pass = before;
        pass.inserted = self.tri.num_vertices() - before.points;
        history.passes.push(pass);
        Ok(())
    }

    /// Wraps the triangulation (all sub-segments present) and constrains the sub-segments.
    fn constrain(&mut self) -> Result<ConstrainedTriangulation2, RecoveryError> {
        let tri = std::mem::replace(
            &mut self.tri,
            Triangulation2::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])?,
        );
        let mut cdt = ConstrainedTriangulation2::new(tri);
        for s in &self.subs {
            cdt.constrain_edge(s.a, s.b)
                .map_err(|e| self.constraint_error(e, s.segment))?;
        }
        Ok(cdt)
    }

    /// An error of the constrained triangulation, in terms of input segments.
    fn constraint_error(&self, e: ConstraintError, segment: u32) -> RecoveryError {
        let base = u64::from(self.plc.first_index);
        let name = |k: u32| u64::from(self.checked.origin[k as usize]) + base;
        match e {
            ConstraintError::CrossesConstraint { c, d, .. } => {
                let other = self
                    .subs
                    .iter()
                    .find(|s| (s.a == c && s.b == d) || (s.a == d && s.b == c))
                    .map_or(name(segment), |s| name(s.segment));
                RecoveryError::Crossing {
                    first: name(segment).min(other),
                    second: name(segment).max(other),
                }
            }
            ConstraintError::Triangulation(t) => RecoveryError::Triangulation(t),
            _ => RecoveryError::NotRecovered {
                segment: name(segment),
                splits: 0,
            },
        }
    }
}

/// Elements at most that area limits may ask for: cell ids are 32-bit, and the triangulation
/// holds the hull's cells besides the domain's.
const MAX_LIMITED_ELEMENTS: f64 = (1u64 << 30) as f64;

/// Refuses area limits that ask for more elements than [`MAX_LIMITED_ELEMENTS`] (each region's
/// area over its limit, summed), naming the region that asks for the most.
fn check_area_limits(cdt: &ConstrainedTriangulation2, plc: &Plc2) -> Result<(), RecoveryError> {
    let limits = plc.area_limits();
    let tri = cdt.triangulation();
    let mut area = vec![0.0; limits.len()];
    for c in tri.cells() {
        let tag = cdt.tag(c) as usize;
        if tag < area.len() && !tri.is_ghost(c) {
            let v = tri.cell(c);
            let p = [tri.vertex(v[0]), tri.vertex(v[1]), tri.vertex(v[2])];
            area[tag] += 0.5
                * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                    - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
        }
    }
    let need: Vec<f64> = area.iter().zip(&limits).map(|(a, l)| a / l).collect();
    if need.iter().sum::<f64>() <= MAX_LIMITED_ELEMENTS {
        return Ok(());
    }
    let tag = (0..need.len())
        .max_by(|&i, &j| need[i].total_cmp(&need[j]))
        .unwrap_or(0);
    Err(RecoveryError::AreaLimitTooSmall {
        index: (tag.max(1) - 1) as u64 + u64::from(plc.first_index),
        max_area: limits[tag],
        area: area[tag],
        elements: need[tag],
    })
}

/// The sub-segments longer than the longest edge allowed on either side (by region tag, from
/// the regions' area limits), with the number of equal pieces each is to be split into.
fn long_subsegments(
    cdt: &ConstrainedTriangulation2,
    subs: &[Sub],
    longest: &[f64],
) -> Vec<(usize, Vec<f64>)> {
    let tri = cdt.triangulation();
    let limit = |c: CellId| {
        let tag = cdt.tag(c);
        if tag == OUTSIDE || tri.is_ghost(c) {
            f64::INFINITY
        } else {
            longest.get(tag as usize).copied().unwrap_or(f64::INFINITY)
        }
    };
    let shortest = |length: f64| length / f64::from(1u32 << 20);
    subs.iter()
        .enumerate()
        .filter_map(|(i, s)| {
            let (c, e) = cdt.find_edge(s.a, s.b)?;
            let length = dist(tri.vertex(s.a), tri.vertex(s.b));
            // (At most 2^20 pieces: a limit far below the segment's length is bounded by the
            // generation's point budget, not here.)
            let h = limit(c)
                .min(limit(tri.neighbor_facet(c, e).cell()))
                .max(shortest(length));
            let pieces = (length / h).ceil() as usize;
            (pieces > 1).then(|| (i, (1..pieces).map(|j| j as f64 / pieces as f64).collect()))
        })
        .collect()
}

fn lerp(a: [f64; 2], b: [f64; 2], t: f64) -> [f64; 2] {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

/// The point of `a b` at distance 2^k from the input vertex `a`, with 2^k in [L/3, 2L/3].
fn shell_point(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let len = dist(a, b);
    let r = 2f64.powi((2.0 * len / 3.0).log2().floor() as i32);
    let t = r / len;
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// An a-priori point and its spacing.
struct Placed {
    point: [f64; 2],
    spacing: f64,
}

/// Weatherill's point per boundary edge (R5), for every side of every boundary edge that is
/// inside the domain.
fn a_priori_points(
    cdt: &mut ConstrainedTriangulation2,
    state: &State<'_>,
    history: &mut RecoveryHistory,
) -> Vec<Placed> {
    // A hash grid of the vertices and of the points placed so far, so each new circle is
    // checked against both.
    let tri = cdt.triangulation();
    let mut total = 0.0;
    for s in &state.subs {
        total += dist(tri.vertex(s.a), tri.vertex(s.b));
    }
    let cell = (total / state.subs.len().max(1) as f64).max(f64::MIN_POSITIVE);
    let key = |p: [f64; 2]| ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<[f64; 2]>> = HashMap::default();
    for v in 0..tri.num_vertices() as u32 {
        let p = tri.vertex(VertexId(v));
        grid.entry(key(p)).or_default().push(p);
    }
    let mut placed = Vec::new();
    for s in state.subs.clone() {
        let Some((c, f)) = cdt.find_edge(s.a, s.b) else {
            continue;
        };
        let tri = cdt.triangulation();
        let across = tri.neighbor_facet(c, f).cell();
        let (pa, pb) = (tri.vertex(s.a), tri.vertex(s.b));
        // Which sides are inside: the cell on the left of a → b, and the one on the right.
        let left_is_c = {
            let cv = tri.cell(c);
            let k = cv.iter().position(|&u| u == s.a).expect("edge in cell");
            cv[(k + 1) % 3] == s.b
        };
        let (left, right) = if left_is_c { (c, across) } else { (across, c) };
        let sides = [(left, 1.0), (right, -1.0)];
        let spacing = 0.5 * (state.spacing_of(s.a) + state.spacing_of(s.b));
        for (side_cell, sign) in sides {
            let tag = cdt.tag(side_cell);
            if tag == OUTSIDE {
                continue;
            }
            let len = dist(pa, pb);
            let m = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
            // Unit normal into this side (left of a → b for sign +1).
            let n = [-sign * (pb[1] - pa[1]) / len, sign * (pb[0] - pa[0]) / len];
            match empty_circle(&grid, cell, key, pa, pb, m, n, len) {
                Some(q) if lands_in_region(cdt, q, side_cell, tag) => {
                    grid.entry(key(q)).or_default().push(q);
                    placed.push(Placed {
                        point: q,
                        spacing: if spacing.is_finite() { spacing } else { len },
                    });
                    history.a_priori_points += 1;
                }
                _ => history.a_priori_rejected += 1,
            }
        }
    }
    placed
}

/// Whether `q` lies inside region `tag` and off its boundary edges (a point rounded onto a
/// thin region's boundary edge is on both sides; which cell the walk then ends in depends on
/// where it starts). The walk starts at `near`, a cell next to `q`.
fn lands_in_region(
    cdt: &mut ConstrainedTriangulation2,
    q: [f64; 2],
    near: CellId,
    tag: u32,
) -> bool {
    let Location::Cell(c) = cdt.locate_near(q, near) else {
        return false;
    };
    let t = cdt.triangulation();
    let v = t.cell(c);
    cdt.tag(c) == tag
        && (0..3).all(|i| {
            !cdt.is_constrained(c, i)
                || orient2d(t.vertex(v[(i + 1) % 3]), t.vertex(v[(i + 2) % 3]), q) != Sign::Zero
        })
}

impl State<'_> {
    fn spacing_of(&self, v: VertexId) -> f64 {
        self.spacing.get(v.index()).copied().unwrap_or(f64::NAN)
    }
}

/// The apex of the circle through `a b` whose centre is at signed distance `t` from the
/// mid-point `m` along `n`, with `t` as close to the equilateral triangle's as the points in
/// `grid` allow (none may be inside the circle); `None` if no such circle exists.
///
/// Distances are in units of `len`, so no square overflows or underflows at any coordinate
/// scale the triangulation accepts; the buckets scanned are at most the grid's occupied ones,
/// so a segment much longer than the mean (a far field) costs no more than the point count.
#[allow(clippy::too_many_arguments)]
fn empty_circle(
    grid: &HashMap<(i64, i64), Vec<[f64; 2]>>,
    cell: f64,
    key: impl Fn([f64; 2]) -> (i64, i64),
    a: [f64; 2],
    b: [f64; 2],
    m: [f64; 2],
    n: [f64; 2],
    len: f64,
) -> Option<[f64; 2]> {
    let target = 1.0 / (2.0 * 3f64.sqrt());
    // The centre's range allowed by the points seen (none: unbounded above).
    let (mut lo, mut hi) = (-1.0f64, f64::INFINITY);
    let reach = len * 1.25f64.sqrt();
    let (k0, k1) = (
        key([m[0] - reach, m[1] - reach]),
        key([m[0] + reach, m[1] + reach]),
    );
    let _ = cell;
    let mut consider = |x: [f64; 2]| {
        if x == a || x == b {
            return true;
        }
        let d = [(x[0] - m[0]) / len, (x[1] - m[1]) / len];
        let s = d[0] * n[0] + d[1] * n[1];
        let w = d[0] * d[0] + d[1] * d[1] - 0.25;
        if s > 0.0 {
            hi = hi.min(w / (2.0 * s));
        } else if s < 0.0 {
            lo = lo.max(w / (2.0 * s));
        } else if w <= 0.0 {
            return false;
        }
        true
    };
    let span = |i: i64, j: i64| (j as f64 - i as f64 + 1.0).max(0.0);
    if span(k0.0, k1.0) * span(k0.1, k1.1) > grid.len() as f64 {
        let inside = |k: &(i64, i64)| (k0.0..=k1.0).contains(&k.0) && (k0.1..=k1.1).contains(&k.1);
        for (_, bucket) in grid.iter().filter(|(k, _)| inside(k)) {
            if !bucket.iter().all(|&x| consider(x)) {
                return None;
            }
        }
    } else {
        for i in k0.0..=k1.0 {
            for j in k0.1..=k1.1 {
                if let Some(bucket) = grid.get(&(i, j)) {
                    if !bucket.iter().all(|&x| consider(x)) {
                        return None;
                    }
                }
            }
        }
    }
    if lo >= hi {
        return None;
    }
    // Keep a margin from the limiting points: they must stay strictly outside, also one on
    // (or a rounding error outside) the equilateral circle, at its apex, as a Koch curve's
    // corners are: the point went there, a rounding error from that corner.
    let t = if hi.is_finite() {
        target.min(hi - 0.1 * (hi - lo))
    } else {
        target
    };
    let h = len * (t + (0.25 + t * t).sqrt());
    Some([m[0] + h * n[0], m[1] + h * n[1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_a_priori_point_keeps_clear_of_a_corner_on_its_circle() {
        // The apex of the equilateral triangle over a b is an input corner (as a Koch curve's
        // are): the point went there, within a rounding error of it (a triangle of area 1e-33
        // beside it). It must keep clear of it, and of the edge's ends.
        let (a, b) = ([0.0, 0.0], [1.0, 0.0]);
        let key = |p: [f64; 2]| (p[0].floor() as i64, p[1].floor() as i64);
        for apex in [[0.5, 0.75f64.sqrt()], [0.5, 0.75f64.sqrt() + 1e-16]] {
            let mut grid: HashMap<(i64, i64), Vec<[f64; 2]>> = HashMap::default();
            for p in [a, b, apex] {
                grid.entry(key(p)).or_default().push(p);
            }
            let q = empty_circle(&grid, 1.0, key, a, b, [0.5, 0.0], [0.0, 1.0], 1.0).unwrap();
            assert!(dist(q, apex) > 0.05, "{q:?} beside {apex:?}");
            assert!(q[1] > 0.5, "{q:?}");
        }
        // Nothing near: the equilateral apex.
        let mut grid: HashMap<(i64, i64), Vec<[f64; 2]>> = HashMap::default();
        for p in [a, b, [0.5, 3.0]] {
            grid.entry(key(p)).or_default().push(p);
        }
        let q = empty_circle(&grid, 1.0, key, a, b, [0.5, 0.0], [0.0, 1.0], 1.0).unwrap();
        assert!((q[1] - 0.75f64.sqrt()).abs() < 1e-15, "{q:?}");
    }

    #[test]
    fn long_lists_show_the_first_few_and_count_the_rest() {
        let seven: Vec<u64> = (1..=7).collect();
        assert_eq!(numbers(&seven).unwrap(), "1, 2, 3, 4, 5, and 2 more");
        assert_eq!(numbers(&[4]).unwrap(), "4");
        assert_eq!(numbers(&[]), None);
        assert_eq!(merged_list(&[(5, 2)]), "points 5 into 2");
        let merged: Vec<(u64, u64)> = (10..16).map(|d| (d, 1)).collect();
        assert_eq!(
            merged_list(&merged),
            "points 10 into 1, 11 into 1, 12 into 1, 13 into 1, 14 into 1, and 1 more"
        );
    }
}
