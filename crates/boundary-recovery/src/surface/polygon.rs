//! Polygonal facets ([`PolygonFacet`]) triangulated in their plane.
//!
//! A facet is one or more polygons in one plane (TetGen `.poly` style): closed loops of three
//! or more points, segments (two points) and single points, all of which end up as edges and
//! vertices of the facet's triangles, plus hole points. Each facet is checked exactly for
//! planarity (`orient3d` of every point against three non-collinear ones), projected along the
//! axis where it is not degenerate (an affine bijection of its plane, so `orient2d` in the
//! projection decides exactly what it would in the plane), and triangulated by a
//! [`ConstrainedTriangulation2`] with every polygon edge inserted as a constraint. A facet that
//! is one loop of four points off one plane (the quadrilaterals of a curved surface's mesh, or
//! ones planar but for rounding, as OFF, OBJ, Medit and gmsh files hold them) is cut into two
//! triangles by its shorter diagonal instead; any other non-planar facet is an error.
//!
//! Which triangles belong to the facet is decided as TetGen does: every region the polygons
//! enclose is in, and the region around each hole point is removed; a polygon inside another
//! without a hole point is imprinted on the facet (its edges become edges of the facet's
//! triangles), not a hole. A facet's triangles all have one orientation: that of its first
//! loop's vertex order (the outer boundary by convention), i.e. a triangle beside that loop
//! traverses the shared edge in the loop's direction.

use super::check::scaled_points;
use super::error::SurfaceError;
use super::intersect::{collinear, orient2d, orient3d, project, projection_axis, P};
use crate::plc3::SurfaceTriangle;
use delmesh_delaunay_core::{
    CellId, ConstrainedTriangulation2, ConstraintError, Location, Triangulation2, VertexId,
};
use delmesh_predicates::{incircle_lex, Sign};
use rustc_hash::FxHashMap as HashMap;

/// A planar polygonal facet: polygons, hole points and a boundary marker.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolygonFacet {
    /// The polygons, as 0-based point indices: loops of three or more points (the first is the
    /// outer boundary and sets the orientation), segments of two, or single points.
    pub polygons: Vec<Vec<u32>>,
    /// Points in the facet's plane whose region of the facet is removed.
    pub holes: Vec<[f64; 3]>,
    /// The boundary marker of every triangle of the facet.
    pub marker: i32,
}

/// Triangulates every facet; triangles carry their facet's index and marker.
pub(crate) fn triangulate_facets(
    points: &[P],
    facets: &[PolygonFacet],
    first_index: u32,
) -> Result<Vec<SurfaceTriangle>, SurfaceError> {
    let base = u64::from(first_index);
    let (_, scaled) = scaled_points(points, base)?;
    let mut out = Vec::new();
    for (f, facet) in facets.iter().enumerate() {
        triangulate_facet(points, &scaled, facet, f as u32, base, &mut out)?;
    }
    Ok(out)
}

fn triangulate_facet(
    points: &[P],
    scaled: &[P],
    facet: &PolygonFacet,
    f: u32,
    base: u64,
    out: &mut Vec<SurfaceTriangle>,
) -> Result<(), SurfaceError> {
    let fname = u64::from(f) + base;
    let name = |v: u32| u64::from(v) + base;
    let degenerate = |why| SurfaceError::FacetDegenerate { facet: fname, why };
    // A lone triangle that is not degenerate is its own triangulation (most facets of most
    // inputs: no map, no projection). Anything else, errors included, takes the general path.
    if let ([p], true) = (&facet.polygons[..], facet.holes.is_empty()) {
        if let &[u, v, w] = &p[..] {
            let n = scaled.len();
            if [u, v, w].iter().all(|&i| (i as usize) < n)
                && !collinear(scaled[u as usize], scaled[v as usize], scaled[w as usize])
            {
                out.push(SurfaceTriangle {
                    v: [u, v, w],
                    marker: facet.marker,
                    facet: f,
                });
                return Ok(());
            }
        }
    }
    // The facet's points, each once, in order of appearance.
    let mut local: Vec<u32> = Vec::new();
    let mut local_of: HashMap<u32, u32> = HashMap::default();
    for &v in facet.polygons.iter().flatten() {
        if v as usize >= points.len() {
            return Err(SurfaceError::BadIndex {
                facet: fname,
                point: name(v),
                n_points: points.len(),
            });
        }
        local_of.entry(v).or_insert_with(|| {
            local.push(v);
            local.len() as u32 - 1
        });
    }
    if let Some(h) = facet
        .holes
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        return Err(SurfaceError::FacetBadHole {
            facet: fname,
            hole: h as u64 + base,
        });
    }
    let sp = |v: u32| scaled[v as usize];
    // Three non-collinear points span the plane.
    let Some(&a) = local.first() else {
        return Err(degenerate("it has no points"));
    };
    let Some(&b) = local.iter().find(|&&v| sp(v) != sp(a)) else {
        return Err(degenerate("fewer than three distinct points"));
    };
    let Some(&c) = local.iter().find(|&&v| !collinear(sp(a), sp(b), sp(v))) else {
        return Err(degenerate("all its points are collinear"));
    };
    if let Some(&d) = local
        .iter()
        .find(|&&d| orient3d(sp(a), sp(b), sp(c), sp(d)) != Sign::Zero)
    {
        // A quadrilateral of a surface mesh (a curved surface's, or one planar but for
        // rounding, as OFF, OBJ, Medit and gmsh files hold them) is two triangles.
        if let Some(pair) = split_quadrilateral(facet, sp) {
            out.extend(pair.map(|v| SurfaceTriangle {
                v,
                marker: facet.marker,
                facet: f,
            }));
            return Ok(());
        }
        return Err(SurfaceError::FacetNotPlanar {
            facet: fname,
            point: name(d),
            plane: [a, b, c].map(name),
        });
    }
    let axis = projection_axis(sp(a), sp(b), sp(c))
        .expect("three non-collinear points have a projection axis: a bug in delmesh");
    let loops: Vec<&Vec<u32>> = facet.polygons.iter().filter(|p| p.len() >= 3).collect();
    if loops.is_empty() {
        return Err(SurfaceError::FacetEmpty { facet: fname });
    }
    // A lone triangle is its own triangulation.
    if facet.polygons.len() == 1 && local.len() == 3 && facet.polygons[0].len() == 3 {
        let p = &facet.polygons[0];
        if facet.holes.is_empty() {
            out.push(SurfaceTriangle {
                v: [p[0], p[1], p[2]],
                marker: facet.marker,
                facet: f,
            });
            return Ok(());
        }
    }

    // A strictly convex quadrilateral is split by its Delaunay diagonal (the perturbed
    // in-circle test, the choice the constrained triangulation would make).
    if facet.polygons.len() == 1 && local.len() == 4 && facet.polygons[0].len() == 4 {
        let p = &facet.polygons[0];
        let q: [[f64; 2]; 4] = std::array::from_fn(|i| project(points[p[i] as usize], axis));
        let turn: [Sign; 4] =
            std::array::from_fn(|i| orient2d(q[i], q[(i + 1) % 4], q[(i + 2) % 4]));
        if facet.holes.is_empty() && turn[0] != Sign::Zero && turn.iter().all(|&t| t == turn[0]) {
            let circle = if turn[0] == Sign::Positive {
                [q[0], q[1], q[2], q[3]]
            } else {
                [q[0], q[2], q[1], q[3]]
            };
            let pairs = if incircle_lex(circle) == Sign::Positive {
                [[p[0], p[1], p[3]], [p[1], p[2], p[3]]]
            } else {
                [[p[0], p[1], p[2]], [p[0], p[2], p[3]]]
            };
            out.extend(pairs.map(|v| SurfaceTriangle {
                v,
                marker: facet.marker,
                facet: f,
            }));
            return Ok(());
        }
    }

    let pts2: Vec<[f64; 2]> = local
        .iter()
        .map(|&v| project(points[v as usize], axis))
        .collect();
    let kernel = |e: ConstraintError| SurfaceError::FacetTriangulation {
        facet: fname,
        source: e,
    };
    let tri = Triangulation2::new(&pts2).map_err(|e| kernel(e.into()))?;
    let vids: Vec<VertexId> = (0..local.len()).map(|i| tri.vertex_of_input(i)).collect();
    let vertex = |v: u32| vids[local_of[&v] as usize];
    let mut cdt = ConstrainedTriangulation2::new(tri);
    let global =
        |cdt: &ConstrainedTriangulation2, v: VertexId| local[cdt.triangulation().input_index(v)];
    let mut edges: Vec<(u32, u32)> = Vec::new();
    for poly in &facet.polygons {
        match poly.len() {
            0 | 1 => {}
            2 => edges.push((poly[0], poly[1])),
            n => edges.extend((0..n).map(|i| (poly[i], poly[(i + 1) % n]))),
        }
    }
    let edge_vertices: Vec<(VertexId, VertexId)> =
        edges.iter().map(|&(u, w)| (vertex(u), vertex(w))).collect();
    for (&(u, w), &(va, vb)) in edges.iter().zip(&edge_vertices) {
        if va == vb {
            return Err(SurfaceError::FacetZeroEdge {
                facet: fname,
                a: name(u),
                b: name(w),
            });
        }
        match cdt.insert_segment(va, vb) {
            Ok(()) => {}
            Err(ConstraintError::VertexOnSegment { vertex, .. }) => {
                return Err(SurfaceError::FacetPointOnEdge {
                    facet: fname,
                    point: name(global(&cdt, vertex)),
                    a: name(u),
                    b: name(w),
                })
            }
            Err(ConstraintError::CrossesConstraint { c, d, .. }) => {
                return Err(SurfaceError::FacetEdgesCross {
                    facet: fname,
                    first: [name(u), name(w)],
                    second: [name(global(&cdt, c)), name(global(&cdt, d))],
                })
            }
            Err(e) => {
                // The kernel reports a segment running along its convex hull through another
                // vertex as a missing edge: name that vertex if there is one.
                let (pu, pw) = (pts2[local_of[&u] as usize], pts2[local_of[&w] as usize]);
                let k = if pu[0] != pw[0] { 0 } else { 1 };
                let inside = |x: [f64; 2]| {
                    orient2d(pu, pw, x) == Sign::Zero
                        && pu[k].min(pw[k]) < x[k]
                        && x[k] < pu[k].max(pw[k])
                };
                return Err(
                    match local.iter().find(|&&v| inside(pts2[local_of[&v] as usize])) {
                        Some(&v) => SurfaceError::FacetPointOnEdge {
                            facet: fname,
                            point: name(v),
                            a: name(u),
                            b: name(w),
                        },
                        None => kernel(e),
                    },
                );
            }
        }
    }

    // Hole points must not sit on the facet's edges or points (which side would they mean?).
    let mut holes2 = Vec::with_capacity(facet.holes.len());
    for (h, hole) in facet.holes.iter().enumerate() {
        let p = project(*hole, axis);
        let on_boundary = match cdt.locate(p) {
            Location::Vertex(_) => true,
            Location::Cell(c) => on_constrained_edge(&cdt, c, p),
        };
        if on_boundary {
            return Err(SurfaceError::FacetHoleOnBoundary {
                facet: fname,
                hole: h as u64 + base,
            });
        }
        holes2.push(p);
    }
    let within = facet_cells(&mut cdt, &holes2);
    if !within.contains(&true) {
        return Err(SurfaceError::FacetEmpty { facet: fname });
    }
    let tri = cdt.triangulation();
    let inside = |c: CellId| within[c.index()];

    // Orientation: a triangle beside the first loop that can tell traverses its edge forward.
    let mut keep = true;
    'find: for poly in &loops {
        let n = poly.len();
        for i in 0..n {
            let (va, vb) = (vertex(poly[i]), vertex(poly[(i + 1) % n]));
            let Some((c, k)) = cdt.find_edge(va, vb) else {
                continue;
            };
            let d = tri.neighbor_facet(c, k).cell();
            let x = match (inside(c), inside(d)) {
                (true, false) => c,
                (false, true) => d,
                _ => continue,
            };
            let v = tri.cell(x);
            let at = v
                .iter()
                .position(|&u| u == va)
                .expect("a found edge is in its cell: a bug in delmesh");
            keep = v[(at + 1) % 3] == vb;
            break 'find;
        }
    }
    for c in tri.cells() {
        if !inside(c) {
            continue;
        }
        let [p, q, r] = [0, 1, 2].map(|i| global(&cdt, tri.cell(c)[i]));
        out.push(SurfaceTriangle {
            v: if keep { [p, q, r] } else { [p, r, q] },
            marker: facet.marker,
            facet: f,
        });
    }
    Ok(())
}

/// Which cells (by slot) belong to the facet, as TetGen reads a facet: every cell enclosed by
/// its polygons (one not reached from the convex hull without crossing a polygon edge), but
/// those reached from a hole point. A polygon inside another is imprinted on the facet (an
/// edge between two patches), not a hole.
fn facet_cells(cdt: &mut ConstrainedTriangulation2, holes: &[[f64; 2]]) -> Vec<bool> {
    let tri = cdt.triangulation();
    let mut within: Vec<bool> = (0..tri.num_cell_slots() as u32)
        .map(|c| tri.is_live(CellId(c)) && !tri.is_ghost(CellId(c)))
        .collect();
    let mut stack: Vec<CellId> = tri.all_cells().filter(|&c| tri.is_ghost(c)).collect();
    let mut starts: Vec<CellId> = Vec::new();
    for &h in holes {
        if let Location::Cell(c) = cdt.locate(h) {
            starts.push(c);
        }
    }
    let tri = cdt.triangulation();
    for c in starts {
        if within[c.index()] {
            within[c.index()] = false;
            stack.push(c);
        }
    }
    // Flood across edges that are not polygon edges.
    while let Some(c) = stack.pop() {
        for i in 0..3 {
            let n = tri.neighbor_facet(c, i).cell();
            if within[n.index()] && !cdt.is_constrained(c, i) {
                within[n.index()] = false;
                stack.push(n);
            }
        }
    }
    within
}

/// Whether `p`, in the closed finite cell `c`, lies on one of its constrained edges.
fn on_constrained_edge(cdt: &ConstrainedTriangulation2, c: CellId, p: [f64; 2]) -> bool {
    let tri = cdt.triangulation();
    if tri.is_ghost(c) {
        return false;
    }
    let v = tri.cell(c);
    (0..3).any(|i| {
        cdt.is_constrained(c, i)
            && orient2d(tri.vertex(v[(i + 1) % 3]), tri.vertex(v[(i + 2) % 3]), p) == Sign::Zero
    })
}

/// The two triangles of a facet that is one non-planar loop of four points and no hole: cut
/// by the shorter diagonal (the other where that one leaves a triangle with collinear
/// corners), both in the loop's order. `None` for any other facet, or if both cuts leave one.
fn split_quadrilateral(facet: &PolygonFacet, sp: impl Fn(u32) -> P) -> Option<[[u32; 3]; 2]> {
    let [p, ..] = facet.polygons.as_slice() else {
        return None;
    };
    if facet.polygons.len() != 1 || !facet.holes.is_empty() || p.len() != 4 {
        return None;
    }
    let length2 = |i: usize, j: usize| {
        let (u, w) = (sp(p[i]), sp(p[j]));
        (0..3).map(|k| (u[k] - w[k]) * (u[k] - w[k])).sum::<f64>()
    };
    let cuts = [
        [[p[0], p[1], p[2]], [p[0], p[2], p[3]]],
        [[p[0], p[1], p[3]], [p[1], p[2], p[3]]],
    ];
    let first = usize::from(length2(1, 3) < length2(0, 2));
    [first, 1 - first]
        .into_iter()
        .map(|k| cuts[k])
        .find(|pair| {
            pair.iter()
                .all(|t| !collinear(sp(t[0]), sp(t[1]), sp(t[2])))
        })
}
