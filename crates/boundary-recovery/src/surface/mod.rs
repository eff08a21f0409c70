//! Surface checks for 3D meshing: is a [`Plc3`] a set of closed, orientable, non-intersecting
//! triangle surfaces, and which of them lie inside which?
//!
//! 3D boundary recovery needs every surface triangle to end up as a face of the tetrahedral
//! mesh, and the flood fill that deletes the exterior needs the surfaces to separate space into
//! clean insides and outsides. Both fail in confusing ways, deep inside the mesher, on a surface
//! that is open, folded or self-intersecting, so [`check_surface`] rejects those first, with
//! errors naming the facets and points in the user's numbering ([`SurfaceError`]).
//!
//! [`check_surface`]'s documentation lists the stages and why each decision is exact; the
//! predicates are in `intersect.rs` (triangle pairs) and `volume.rs` (volumes, the ray).
//!
//! [`Plc3::from_polygon_facets`] builds a [`Plc3`] from planar polygonal facets (TetGen
//! `.poly`), triangulating each in its plane.

mod bvh;
mod check;
mod error;
mod intersect;
mod polygon;
mod volume;

pub use check::{check_surface, first_occurrences};
pub use error::{
    EdgeName, Listed, PointOnTriangle, SurfaceError, TJunctions, TriangleName, TrianglePair,
};
pub use polygon::PolygonFacet;

use crate::plc3::{Plc3, SurfaceTriangle};
use bvh::Boxes;
use intersect::point_on_triangle;
use volume::{wind, Surface, Winding};

/// An edge of a checked surface and its two triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SurfaceEdge {
    /// The end points (indices into [`CheckedSurface::points`]), `v[0] < v[1]`.
    pub v: [u32; 2],
    /// The triangle traversing the edge from `v[0]` to `v[1]`, then the one traversing it
    /// from `v[1]` to `v[0]` (indices into [`CheckedSurface::triangles`]).
    pub triangles: [u32; 2],
}

/// An edge where three or more surface triangles meet: internal walls between regions of the
/// domain join each other or the outer surface there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Junction {
    /// The end points (indices into [`CheckedSurface::points`]), `v[0] < v[1]`.
    pub v: [u32; 2],
    /// The triangles on it (indices into [`CheckedSurface::triangles`]), in input order.
    pub triangles: Vec<u32>,
}

/// One closed surface (a connected component of the triangles, joined across edges).
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceComponent {
    /// Its triangles (indices into [`CheckedSurface::triangles`]), in input order.
    pub triangles: Vec<u32>,
    /// The enclosed volume, positive when the triangles are oriented outward (counter-clockwise
    /// seen from outside), negative when inward; 0 for a component with walls.
    pub volume: f64,
    /// Whether the triangles face outward (the sign of `volume`, certified exactly).
    pub outward: bool,
    /// How many other components enclose this one (0 for all when the surface has walls).
    pub depth: u32,
    /// The innermost component enclosing this one (`None` for all when the surface has walls).
    pub parent: Option<u32>,
    /// Whether it has [`Junction`]s: internal walls split what it encloses into several
    /// regions, so it has no one volume, orientation or inside.
    pub walls: bool,
}

/// Where a point lies relative to a checked surface ([`CheckedSurface::locate`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PointLocation {
    /// On the closed triangle with this index.
    OnSurface {
        /// The triangle (index into [`CheckedSurface::triangles`]).
        triangle: u32,
    },
    /// Off the surface, inside these components (sorted; empty: outside all). Components
    /// with walls have no inside and are never listed.
    Enclosed {
        /// The enclosing components.
        components: Vec<u32>,
    },
}

/// A surface that passed [`check_surface`]: closed, consistently oriented (triangles reversed
/// where needed), free of self-intersections, with internal walls allowed (edges of three or
/// more triangles: [`Junction`]s); with its edges, closed components, and, when it has no
/// walls, their volumes and nesting.
#[derive(Clone, Debug)]
pub struct CheckedSurface {
    /// The distinct input points (duplicates merged), in the order of their first occurrence.
    pub points: Vec<[f64; 3]>,
    /// For each point, its input index (0-based; the first occurrence).
    pub input_index: Vec<u32>,
    /// For each input point, its index in [`CheckedSurface::points`].
    pub vertex_of_input: Vec<u32>,
    /// Merged duplicates: `(duplicate, first occurrence)` input indices (0-based), sorted.
    pub merged: Vec<(u32, u32)>,
    /// Triangles whose corners were reversed to orient their closed surface consistently
    /// (indices into [`CheckedSurface::triangles`]), sorted.
    pub reoriented: Vec<u32>,
    /// The triangles, in input order, with corners indexing [`CheckedSurface::points`]
    /// (reversed for those in [`CheckedSurface::reoriented`]).
    pub triangles: Vec<SurfaceTriangle>,
    /// Every edge of two triangles once, sorted by its end points.
    pub edges: Vec<SurfaceEdge>,
    /// Every edge of three or more triangles once, sorted by its end points.
    pub junctions: Vec<Junction>,
    /// The component of each triangle.
    pub triangle_component: Vec<u32>,
    /// The closed surfaces, numbered in the order of their first triangle.
    pub components: Vec<SurfaceComponent>,
    /// The input's numbering base (0 or 1), for messages.
    pub first_index: u32,
    /// The power of two that scaled the coordinates for the predicates.
    scale: f64,
    /// Scaled points (what the predicates see).
    scaled: Vec<[f64; 3]>,
    /// Triangle corners (as in `triangles`).
    corners: Vec<[u32; 3]>,
    /// Triangle boxes and their hierarchy, for ray queries.
    boxes: Boxes,
}

impl CheckedSurface {
    /// The volume of the domain by nesting parity, without hole seeds: the space inside an odd
    /// number of surfaces. Components at even depth (the far field, a cavity inside a body)
    /// add their volume, those at odd depth (bodies, the material of a hollow body) subtract
    /// theirs: `Σ ±|volume|`. With hole seeds (or region seeds that should keep a body's
    /// inside) the caller decides which nested regions to keep, with
    /// [`CheckedSurface::locate`] telling which surfaces enclose each seed. `None` for a
    /// surface with walls, which has no nesting parity (the volume is then the mesh's).
    pub fn domain_volume(&self) -> Option<f64> {
        if self.has_walls() {
            return None;
        }
        let volume = self
            .components
            .iter()
            .map(|c| {
                if c.depth % 2 == 0 {
                    c.volume.abs()
                } else {
                    -c.volume.abs()
                }
            })
            .sum();
        Some(volume)
    }

    /// Whether the surface has internal walls ([`Junction`]s): regions of the domain meet
    /// there, and nesting parity does not say which side of a triangle is inside.
    pub fn has_walls(&self) -> bool {
        !self.junctions.is_empty()
    }

    /// Where the point lies: on the surface (which triangle), or which components enclose it;
    /// decided exactly by the perturbed ray of [`check_surface`]'s nesting. `None` if a
    /// coordinate is not finite or, scaled as the surface was, outside the exact predicates'
    /// range (a non-zero magnitude below 2^-142 or above 2^201 times the surface's largest).
    pub fn locate(&self, p: [f64; 3]) -> Option<PointLocation> {
        if p.iter().any(|x| !x.is_finite()) {
            return None;
        }
        let q = p.map(|x| x * self.scale);
        let (tiny, huge) = delmesh_predicates::COORDINATE_RANGE;
        if q.iter()
            .zip(p)
            .any(|(x, x0)| x.abs() > huge || (x0 != 0.0 && x.abs() < tiny))
        {
            return None;
        }
        let surface = Surface {
            pts: &self.scaled,
            tris: &self.corners,
            component: &self.triangle_component,
        };
        let mut winding = Winding::new(self.components.len());
        if let Some(t) = wind(surface, &self.boxes, u32::MAX, q, true, &mut winding) {
            return Some(PointLocation::OnSurface { triangle: t });
        }
        let mut components = winding.take_nonzero();
        components.retain(|&c| !self.components[c as usize].walls);
        Some(PointLocation::Enclosed { components })
    }

    /// Whether the point lies on the surface (exactly; a box query, cheaper than
    /// [`CheckedSurface::locate`]'s ray). False for a point `locate` cannot take.
    pub fn touches(&self, p: [f64; 3]) -> bool {
        let q = p.map(|x| x * self.scale);
        let (tiny, huge) = delmesh_predicates::COORDINATE_RANGE;
        if q.iter()
            .zip(p)
            .any(|(x, x0)| !x.is_finite() || x.abs() > huge || (x0 != 0.0 && x.abs() < tiny))
        {
            return false;
        }
        let mut on = false;
        self.boxes.overlapping(&(q, q), &mut Vec::new(), |t| {
            on = on
                || point_on_triangle(self.corners[t as usize].map(|v| self.scaled[v as usize]), q);
        });
        on
    }

    /// Whether some surface triangle comes closer to `p` than `d` (floating-point distances:
    /// for placing optional points away from the surface, not for any decision the mesh's
    /// validity rests on). False for a point [`CheckedSurface::touches`] cannot take.
    pub fn within(&self, p: [f64; 3], d: f64) -> bool {
        let (q, r) = (p.map(|x| x * self.scale), d * self.scale);
        if !(q.iter().all(|x| x.is_finite()) && r.is_finite()) {
            return false;
        }
        let reach = (q.map(|x| x - r), q.map(|x| x + r));
        let mut near = false;
        self.boxes.overlapping(&reach, &mut Vec::new(), |t| {
            near = near
                || distance2_to_triangle(
                    self.corners[t as usize].map(|v| self.scaled[v as usize]),
                    q,
                ) < r * r;
        });
        near
    }

    /// Whether the point is in the domain by nesting parity (inside an odd number of
    /// surfaces, as [`CheckedSurface::domain_volume`] counts); `None` on the surface, for a
    /// point [`CheckedSurface::locate`] cannot take, or on a surface with walls.
    pub fn in_domain(&self, p: [f64; 3]) -> Option<bool> {
        if self.has_walls() {
            return None;
        }
        match self.locate(p)? {
            PointLocation::OnSurface { .. } => None,
            PointLocation::Enclosed { components } => Some(components.len() % 2 == 1),
        }
    }
}

impl Plc3 {
    /// A PLC from planar polygonal facets (TetGen `.poly` style), each triangulated in its
    /// plane: see [`PolygonFacet`]. Triangle `k` of the result carries the number and marker
    /// of the facet it came from; `first_index` is the input's numbering base, used in errors
    /// and kept in the result.
    ///
    /// # Errors
    /// A bad point index or coordinate, a non-planar or degenerate facet, crossing polygon
    /// edges, a point inside a polygon edge, a hole point on a polygon, or a facet that
    /// encloses nothing.
    pub fn from_polygon_facets(
        points: Vec<[f64; 3]>,
        facets: &[PolygonFacet],
        first_index: u32,
    ) -> Result<Plc3, SurfaceError> {
        let triangles = polygon::triangulate_facets(&points, facets, first_index)?;
        Ok(Plc3 {
            points,
            triangles,
            first_index,
            ..Default::default()
        })
    }
}

/// The squared distance from `q` to triangle `t`: to its plane where `q` projects inside it,
/// else to the nearest edge.
fn distance2_to_triangle(t: [[f64; 3]; 3], q: [f64; 3]) -> f64 {
    use crate::recovery3::{cross, dot, sub};
    let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
    let nn = dot(n, n);
    let inside = nn > 0.0
        && (0..3).all(|k| {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            dot(n, cross(sub(b, a), sub(q, a))) >= 0.0
        });
    if inside {
        let h = dot(sub(q, t[0]), n);
        return h * h / nn;
    }
    (0..3)
        .map(|k| {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let (ab, aq) = (sub(b, a), sub(q, a));
            let len2 = dot(ab, ab);
            let s = if len2 > 0.0 {
                (dot(aq, ab) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let foot = sub(aq, ab.map(|x| x * s));
            dot(foot, foot)
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::distance2_to_triangle;

    #[test]
    fn distance_to_a_triangle_from_above_beside_an_edge_and_a_corner() {
        let t = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        // Above the inside: the height; on it: 0.
        assert_eq!(distance2_to_triangle(t, [0.5, 0.5, 3.0]), 9.0);
        assert_eq!(distance2_to_triangle(t, [0.5, 0.5, 0.0]), 0.0);
        // Beside the edge y = 0, and beyond the corner (2, 0, 0).
        assert_eq!(distance2_to_triangle(t, [1.0, -1.0, 1.0]), 2.0);
        assert_eq!(distance2_to_triangle(t, [3.0, -1.0, 0.0]), 2.0);
        // Flat triangle (collinear corners): the distance to its segments.
        let flat = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        assert_eq!(distance2_to_triangle(flat, [1.0, 1.0, 0.0]), 1.0);
    }
}
