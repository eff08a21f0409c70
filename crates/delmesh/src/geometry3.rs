//! The analytic 3D geometry of the demos: closed surface triangulations as [`Plc3`] inputs.
//!
//! The 3D pipeline (edge and face recovery R6–R8, point generation R10–R11) needs inputs whose
//! right answers are known: closed, consistently oriented surfaces of known volume, with planar
//! parts that are exactly planar. This module builds them from analytic shapes: the paper's
//! Figure 9 double ellipsoid ([`double_ellipsoid`]) and three smaller cases (a sphere, a hole,
//! two bodies), from three reusable pieces: [`box_surface`], [`icosphere`] and the ring mesher
//! of [`DoubleEllipsoid::surface`] (which also meshes plain ellipsoids, [`ellipsoid`]).
//!
//! # Conventions
//! - **Outward normals.** Every closed surface is oriented so that its triangles turn
//!   counter-clockwise seen from *outside the volume that surface encloses*: the far-field box's
//!   normals point away from the domain, a body's point into it. So the divergence-theorem volume
//!   of each closed surface ([`Surface3::signed_volume`]) is positive, and the domain's volume
//!   is the far field's minus the bodies'.
//! - **Deterministic.** No random numbers; maps are only used to share points, never iterated.
//! - **Facets.** Each plane side of a box is one input facet (a polygon triangulated in its
//!   plane); each triangle of a curved surface is its own facet. Facets are numbered in the
//!   order the surfaces are added.
//! - **Planar sides are strictly Delaunay in their plane.** A box side is triangulated by rows
//!   of points, every other row shifted by half a spacing (no four points co-circular, every
//!   angle sum across an edge below 180°), so a convex far field appears in the Delaunay
//!   tetrahedralization of its points unchanged (its hull facets are the 2D Delaunay
//!   triangulation of each side), instead of a tie-break choosing the other diagonal of a
//!   square.
//! - **Holes** come from nesting (a body's inside is not domain); [`cube_with_cubic_hole`] also
//!   gives an explicit hole seed. No point markers; regions only in [`blocks`], whose cubes
//!   share walls.
//!
//! | function | markers |
//! | --- | --- |
//! | [`double_ellipsoid`] | 1 far-field box, 2 fuselage, 3 canopy |
//! | [`sphere_in_box`] | 1 box, 2 sphere |
//! | [`cube_with_cubic_hole`] | 1 outer cube, 2 inner cube (the hole) |
//! | [`two_bodies`] | 1 box, 2 sphere, 3 ellipsoid |
//! | [`blocks`] | 1 outer surface, 2 internal walls |

use rustc_hash::FxHashMap as HashMap;
use std::f64::consts::PI;

use delmesh_boundary_recovery::{Plc3, SurfaceTriangle};

/// The default resolution of [`double_ellipsoid`]: 3,314 body points and 6,624 body
/// triangles, the size of the paper's Figure 9 surface (3309 points, 6614 faces).
pub const DOUBLE_ELLIPSOID_N: usize = 56;

/// A triangulated surface (usually one closed surface) with its markers and facets, ready to
/// be added to a [`Plc3`]: point indices and facets are local (from 0).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Surface3 {
    /// Point coordinates.
    pub points: Vec<[f64; 3]>,
    /// The triangles, with markers and local facet numbers.
    pub triangles: Vec<SurfaceTriangle>,
}

impl Surface3 {
    /// The volume enclosed, by the divergence theorem: positive for a closed surface with
    /// outward normals (taken about the first point, which keeps the sum accurate far from the
    /// origin).
    pub fn signed_volume(&self) -> f64 {
        let Some(&o) = self.points.first() else {
            return 0.0;
        };
        let rel = |v: u32| {
            let p = self.points[v as usize];
            [p[0] - o[0], p[1] - o[1], p[2] - o[2]]
        };
        self.triangles
            .iter()
            .map(|t| {
                let (a, b, c) = (rel(t.v[0]), rel(t.v[1]), rel(t.v[2]));
                dot(a, cross(b, c))
            })
            .sum::<f64>()
            / 6.0
    }

    /// Adds this surface to `plc`: its points after the PLC's, its facets after the PLC's.
    pub fn append_to(&self, plc: &mut Plc3) {
        let base = plc.points.len() as u32;
        let facet_base = plc.triangles.iter().map(|t| t.facet + 1).max().unwrap_or(0);
        plc.points.extend_from_slice(&self.points);
        plc.triangles
            .extend(self.triangles.iter().map(|t| SurfaceTriangle {
                v: t.v.map(|v| v + base),
                marker: t.marker,
                facet: t.facet + facet_base,
            }));
    }

    /// The surface moved by `by`.
    fn translated(mut self, by: [f64; 3]) -> Surface3 {
        for p in &mut self.points {
            for k in 0..3 {
                p[k] += by[k];
            }
        }
        self
    }
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

pub(crate) fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(a, b);
    dot(d, d).sqrt()
}

/// The surface of the box `[lo, hi]` with `divisions[k]` divisions along axis `k` (rounded up
/// to an even number, at least 2), outward normals, one facet per side (`x = lo`, `x = hi`,
/// `y = lo`, ... in that order), every triangle with `marker`.
///
/// Each side is triangulated by rows parallel to its axis of smaller spacing, every other row
/// shifted by half a spacing (with half-width triangles at the ends): interior triangles are
/// isosceles (angles 63°, 63°, 53° on a square lattice), the triangulation is strictly Delaunay
/// in the side's plane, and rows of points along the box edges are shared by both sides (no
/// duplicate points, no T-junctions). Points on a side have that side's coordinate exactly.
pub fn box_surface(lo: [f64; 3], hi: [f64; 3], divisions: [usize; 3], marker: i32) -> Surface3 {
    let n = divisions.map(|d| d.max(2).div_ceil(2) * 2);
    // Points are keyed by their position in half-cells along each axis.
    let coord = |k: usize, key: usize| -> f64 {
        if key == 0 {
            lo[k]
        } else if key == 2 * n[k] {
            hi[k]
        } else {
            lo[k] + (hi[k] - lo[k]) * key as f64 / (2 * n[k]) as f64
        }
    };
    let mut surface = Surface3::default();
    let mut index: HashMap<[usize; 3], u32> = HashMap::default();
    let mut facet = 0u32;
    for q in 0..3 {
        let others = [(q + 1) % 3, (q + 2) % 3];
        let width = |k: usize| (hi[k] - lo[k]) / n[k] as f64;
        // Rows run along `p`, stacked along `r`.
        let (p, r) = if width(others[1]) < width(others[0]) {
            (others[1], others[0])
        } else {
            (others[0], others[1])
        };
        for side in 0..2 {
            // Counter-clockwise in (p, r) has normal e_p × e_r = ±e_q.
            let ccw_is_outward = (r == (p + 1) % 3) == (side == 1);
            let rows: Vec<Vec<u32>> = (0..=n[r])
                .map(|j| {
                    let along: Vec<usize> = if j % 2 == 0 {
                        (0..=n[p]).map(|i| 2 * i).collect()
                    } else {
                        std::iter::once(0)
                            .chain((0..n[p]).map(|i| 2 * i + 1))
                            .chain(std::iter::once(2 * n[p]))
                            .collect()
                    };
                    along
                        .into_iter()
                        .map(|kp| {
                            let mut key = [0usize; 3];
                            key[q] = side * 2 * n[q];
                            key[r] = 2 * j;
                            key[p] = kp;
                            *index.entry(key).or_insert_with(|| {
                                surface.points.push([0, 1, 2].map(|k| coord(k, key[k])));
                                (surface.points.len() - 1) as u32
                            })
                        })
                        .collect()
                })
                .collect();
            let mut tri = |a: u32, b: u32, c: u32| {
                let v = if ccw_is_outward { [a, b, c] } else { [a, c, b] };
                surface.triangles.push(SurfaceTriangle { v, marker, facet });
            };
            for j in 0..n[r] {
                let m = n[p];
                if j % 2 == 0 {
                    // Even row e (m + 1 points) below, odd row o (m + 2 points) above.
                    let (e, o) = (&rows[j], &rows[j + 1]);
                    tri(e[0], o[1], o[0]);
                    for i in 0..m {
                        tri(e[i], e[i + 1], o[i + 1]);
                        if i > 0 {
                            tri(e[i], o[i + 1], o[i]);
                        }
                    }
                    tri(e[m], o[m + 1], o[m]);
                } else {
                    let (o, e) = (&rows[j], &rows[j + 1]);
                    tri(o[0], o[1], e[0]);
                    for i in 0..m {
                        tri(o[i + 1], e[i + 1], e[i]);
                        if i + 1 < m {
                            tri(o[i + 1], o[i + 2], e[i + 1]);
                        }
                    }
                    tri(o[m], o[m + 1], e[m]);
                }
            }
            facet += 1;
        }
    }
    surface
}

/// Divisions per axis for a box `[lo, hi]` whose spacing is at most `spacing`.
fn divisions_for(lo: [f64; 3], hi: [f64; 3], spacing: f64) -> [usize; 3] {
    [0, 1, 2].map(|k| ((hi[k] - lo[k]) / spacing).ceil().max(1.0) as usize)
}

/// A sphere of `radius` around `centre`: the icosahedron with each edge divided into
/// `frequency` parts (at least 1), projected onto the sphere. `10 f² + 2` points and `20 f²`
/// triangles, all nearly equilateral; outward normals; one facet per triangle.
pub fn icosphere(centre: [f64; 3], radius: f64, frequency: usize, marker: i32) -> Surface3 {
    let k = frequency.max(1);
    let g = 0.5 * (1.0 + 5f64.sqrt());
    let mut base = Vec::with_capacity(12);
    for s in [-1.0, 1.0] {
        for t in [-g, g] {
            base.push([0.0, s, t]);
            base.push([s, t, 0.0]);
            base.push([t, 0.0, s]);
        }
    }
    // The faces are the triples of vertices at mutual distance 2 (the edge length).
    let is_edge = |i: usize, j: usize| (dist(base[i], base[j]) - 2.0).abs() < 1e-9;
    let mut faces = Vec::with_capacity(20);
    for i in 0..12 {
        for j in i + 1..12 {
            for l in j + 1..12 {
                if is_edge(i, j) && is_edge(j, l) && is_edge(i, l) {
                    let n = cross(sub(base[j], base[i]), sub(base[l], base[i]));
                    let out = dot(n, base[i]) > 0.0;
                    faces.push(if out { [i, j, l] } else { [i, l, j] });
                }
            }
        }
    }
    debug_assert_eq!(faces.len(), 20);
    let mut surface = Surface3::default();
    // A point of the subdivision is keyed by its weights on the icosahedron's vertices, which
    // do not depend on the face it is seen from.
    let mut index: HashMap<[(usize, usize); 3], u32> = HashMap::default();
    for face in &faces {
        let mut id = |i: usize, j: usize| -> u32 {
            let w = [(face[0], k - i - j), (face[1], i), (face[2], j)];
            let mut key = w.map(|(v, wt)| if wt == 0 { (usize::MAX, 0) } else { (v, wt) });
            key.sort_unstable();
            *index.entry(key).or_insert_with(|| {
                let mut p = [0.0; 3];
                for &(v, wt) in key.iter().filter(|e| e.1 > 0) {
                    for (c, b) in p.iter_mut().zip(base[v]) {
                        *c += wt as f64 * b;
                    }
                }
                let len = dot(p, p).sqrt();
                surface
                    .points
                    .push([0, 1, 2].map(|c| centre[c] + radius * p[c] / len));
                (surface.points.len() - 1) as u32
            })
        };
        let mut tris = Vec::new();
        for i in 0..k {
            for j in 0..k - i {
                tris.push([id(i, j), id(i + 1, j), id(i, j + 1)]);
                if i + j + 1 < k {
                    tris.push([id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
                }
            }
        }
        for v in tris {
            let facet = surface.triangles.len() as u32;
            surface.triangles.push(SurfaceTriangle { v, marker, facet });
        }
    }
    surface
}

/// Where a crease tip lies between the ring ahead of it and the first ring crossing the crease,
/// as a fraction of that strip.
const TIP_FRACTION: f64 = 0.5;

/// A canopy: an ellipsoid centred on the symmetry plane `y = 0` that pokes out of the upper
/// half of a [`DoubleEllipsoid`]'s fuselage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Canopy {
    /// The centre's `x` and `z` (its `y` is 0).
    pub centre: [f64; 2],
    /// Semi-axes along `x`, `y`, `z`.
    pub semi_axes: [f64; 3],
}

/// A Hermes-like double ellipsoid (the paper's Figure 9, the hypersonic test body of the Hermes
/// project): a fuselage of two half-ellipsoids joined in the plane `z = 0`, sharing the
/// semi-axes along `x` (the length, nose at `−x`) and `y` (the span) but with different
/// heights above and below, plus an optional canopy ellipsoid on top, intersecting it.
///
/// The surface is the boundary of the union. The two halves meet with a common vertical
/// tangent plane (the surface is smooth there); the canopy meets the fuselage along a closed
/// crease whose points are mesh vertices joined by mesh edges, so the crease is modelled
/// exactly (up to its polygonal approximation). The afterbody of the wind-tunnel model is not
/// modelled: the fuselage closes into a second half-ellipsoid behind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoubleEllipsoid {
    /// Semi-axis along `x` (half the length) of both halves; centre at the origin.
    pub half_length: f64,
    /// Semi-axis along `y` (half the span) of both halves.
    pub half_span: f64,
    /// Semi-axis along `z` of the upper half (`z ≥ 0`).
    pub upper: f64,
    /// Semi-axis along `z` of the lower half (`z ≤ 0`).
    pub lower: f64,
    /// The canopy, if any.
    pub canopy: Option<Canopy>,
}

impl DoubleEllipsoid {
    /// The demo body: length 2, span 0.7, a flatter lower half (0.18) than upper (0.24), and a
    /// canopy over the front half standing about 0.09 above the fuselage.
    pub const HERMES: DoubleEllipsoid = DoubleEllipsoid {
        half_length: 1.0,
        half_span: 0.35,
        upper: 0.24,
        lower: 0.18,
        canopy: Some(Canopy {
            centre: [-0.3, 0.1],
            semi_axes: [0.45, 0.2, 0.22],
        }),
    };

    /// A plain ellipsoid centred at the origin (equal halves, no canopy).
    pub fn ellipsoid(semi_axes: [f64; 3]) -> DoubleEllipsoid {
        DoubleEllipsoid {
            half_length: semi_axes[0],
            half_span: semi_axes[1],
            upper: semi_axes[2],
            lower: semi_axes[2],
            canopy: None,
        }
    }

    /// Semi-axis along `z` on the side of `z`.
    fn height(&self, z: f64) -> f64 {
        if z >= 0.0 {
            self.upper
        } else {
            self.lower
        }
    }

    /// The fuselage's level function: negative inside, zero on its surface, positive outside.
    pub fn fuselage_level(&self, p: [f64; 3]) -> f64 {
        let (x, y, z) = (
            p[0] / self.half_length,
            p[1] / self.half_span,
            p[2] / self.height(p[2]),
        );
        x * x + y * y + z * z - 1.0
    }

    /// The canopy's level function (`+∞` without a canopy).
    pub fn canopy_level(&self, p: [f64; 3]) -> f64 {
        match self.canopy {
            None => f64::INFINITY,
            Some(c) => {
                let x = (p[0] - c.centre[0]) / c.semi_axes[0];
                let y = p[1] / c.semi_axes[1];
                let z = (p[2] - c.centre[1]) / c.semi_axes[2];
                x * x + y * y + z * z - 1.0
            }
        }
    }

    /// The perimeter of the fuselage's largest cross-section (`x = 0`).
    pub fn girth(&self) -> f64 {
        let f = |t: f64| self.fuselage_point(0.0, 1.0, t);
        arc_table(&f, 0.0, 2.0 * PI, 4096).1
    }

    /// The fuselage's cross-section point at station `x` (scale `s = √(1 − x²/a²)`) and angle
    /// `t` (the two halves are half-ellipses in `t`).
    fn fuselage_point(&self, x: f64, s: f64, t: f64) -> [f64; 3] {
        let (sin, cos) = t.sin_cos();
        let c = if sin >= 0.0 { self.upper } else { self.lower };
        [x, s * self.half_span * cos, s * c * sin]
    }

    /// The triangulated surface at `spacing` (edge length), with `markers` `[fuselage,
    /// canopy]`, outward normals, one facet per triangle.
    ///
    /// Rings of points are laid on cross-sections `x = const`, equally spaced along the
    /// meridians (by `spacing · √3/2`, the height of an equilateral triangle), with points
    /// equally spaced along each ring (every other ring shifted by half a spacing); consecutive
    /// rings are zipped by the shorter diagonal, and the nose and tail are points fanned to the
    /// first and last rings. With a canopy, the rings between the crease's front and rear tips
    /// carry its two points (computed by bisection, on both surfaces), and the canopy arcs and
    /// the fuselage arcs between them are zipped separately, so the crease is a chain of mesh
    /// edges. Its tips are vertices half-way between two rings: the canopy's cap ahead of the
    /// first crossing ring is fanned from the tip, and the tip joins that ring's fuselage arc
    /// into a closed ring zipped to the ring ahead (likewise behind).
    ///
    /// # Panics
    /// If a semi-axis or the spacing is not positive and finite, or the canopy does not cross
    /// the fuselage's upper half along one closed curve (its lowest point, front and rear ends
    /// must be inside the fuselage, its top outside it).
    pub fn surface(&self, spacing: f64, markers: [i32; 2]) -> Surface3 {
        let h = spacing;
        let a = self.half_length;
        let positive = |v: f64| v > 0.0 && v.is_finite();
        assert!(
            [h, a, self.half_span, self.upper, self.lower]
                .into_iter()
                .all(positive),
            "double ellipsoid: semi-axes and spacing must be positive and finite"
        );
        if let Some(c) = self.canopy {
            assert!(
                c.semi_axes.into_iter().all(positive),
                "double ellipsoid: canopy semi-axes must be positive and finite"
            );
        }
        // Arc length along the meridians, averaged over the angle: φ ∈ [0, π], x = −a cos φ.
        let steps = 4096;
        let thetas: Vec<f64> = (0..32).map(|i| (i as f64 + 0.5) * PI / 16.0).collect();
        let speed = |phi: f64| {
            let (s, c) = phi.sin_cos();
            thetas
                .iter()
                .map(|&t| {
                    let r = self.fuselage_point(0.0, 1.0, t);
                    (a * a * s * s + c * c * (r[1] * r[1] + r[2] * r[2])).sqrt()
                })
                .sum::<f64>()
                / thetas.len() as f64
        };
        let mut s_table = vec![0.0f64; steps + 1];
        for i in 0..steps {
            let (p0, p1) = (
                PI * i as f64 / steps as f64,
                PI * (i + 1) as f64 / steps as f64,
            );
            s_table[i + 1] = s_table[i] + 0.5 * (speed(p0) + speed(p1)) * (p1 - p0);
        }
        let s_of_x = |x: f64| {
            let phi = (-x / a).clamp(-1.0, 1.0).acos();
            let u = phi / PI * steps as f64;
            let i = (u.floor() as usize).min(steps - 1);
            s_table[i] + (u - i as f64) * (s_table[i + 1] - s_table[i])
        };
        let x_of_s = |s: f64| {
            let i = s_table.partition_point(|&v| v <= s).clamp(1, steps) - 1;
            let u = (s - s_table[i]) / (s_table[i + 1] - s_table[i]);
            -a * (PI * (i as f64 + u) / steps as f64).cos()
        };
        let total = s_table[steps];

        // Stations (x, whether the ring crosses the crease) from nose to tail, equally spaced
        // along the meridians within each stretch between the nose, the crease's tips and the
        // tail.
        let tips = self.canopy.map(|c| self.crease_tips(c));
        let delta = h * 3f64.sqrt() / 2.0;
        let mut stations: Vec<(f64, bool)> = Vec::new();
        match tips {
            None => {
                let m = ((total / delta).round() as usize).max(2);
                for i in 1..m {
                    stations.push((x_of_s(total * i as f64 / m as f64), false));
                }
            }
            Some((xf, xr)) => {
                // Each tip is `f` of a strip behind the ring ahead of it (and ahead of the ring
                // behind it), so neither the canopy's cap beyond the crossing rings nor the
                // fuselage between the tip and the next plain ring is too thin.
                let f = TIP_FRACTION;
                let (sf, sr) = (s_of_x(xf), s_of_x(xr));
                let m1 = ((sf / delta - f).round() as usize).max(1);
                let d1 = sf / (m1 as f64 + f);
                for i in 1..=m1 {
                    stations.push((x_of_s(d1 * i as f64), false));
                }
                let m2 = (((sr - sf) / delta - 1.0 + 2.0 * f).round() as usize).max(1);
                let d2 = (sr - sf) / (m2 as f64 + 1.0 - 2.0 * f);
                for i in 0..m2 {
                    stations.push((x_of_s(sf + d2 * (i as f64 + 1.0 - f)), true));
                }
                let m3 = (((total - sr) / delta - f).round() as usize).max(1);
                let d3 = (total - sr) / (m3 as f64 + f);
                for i in 0..m3 {
                    stations.push((x_of_s(sr + d3 * (i as f64 + f)), false));
                }
            }
        }

        let mut surface = Surface3::default();
        let point = |p: [f64; 3], surface: &mut Surface3| -> u32 {
            surface.points.push(p);
            (surface.points.len() - 1) as u32
        };
        let nose = Ring {
            points: vec![point([-a, 0.0, 0.0], &mut surface)],
            corners: None,
        };
        let mut rings = vec![nose];
        let [front_tip, rear_tip] = [0, 1].map(|k| {
            tips.map(|t| {
                let x = if k == 0 { t.0 } else { t.1 };
                let top = self.upper * (1.0 - (x / a) * (x / a)).max(0.0).sqrt();
                point([x, 0.0, top], &mut surface)
            })
        });
        for (k, &(x, crossed)) in stations.iter().enumerate() {
            let s = (1.0 - (x / a) * (x / a)).max(0.0).sqrt();
            let fus = |t: f64| self.fuselage_point(x, s, t);
            let ring = if !crossed {
                // Next to a crease tip, the ring straddles the top symmetrically.
                let near_tip = [k.wrapping_sub(1), k + 1]
                    .iter()
                    .any(|&j| stations.get(j).is_some_and(|s| s.1));
                let t0 = if near_tip { 0.5 * PI } else { 0.0 };
                let (table, len) = arc_table(&fus, t0, t0 + 2.0 * PI, 4096);
                let n = ((len / h).round() as usize).max(3);
                let shift = if k % 2 == 0 && !near_tip { 0.0 } else { 0.5 };
                let pts = (0..n)
                    .map(|i| fus(param_at(&table, len * (i as f64 + shift) / n as f64)))
                    .map(|p| point(p, &mut surface))
                    .collect();
                Ring {
                    points: pts,
                    corners: None,
                }
            } else {
                let c = self
                    .canopy
                    .expect("crossed stations only exist with a canopy");
                let sc = (1.0 - ((x - c.centre[0]) / c.semi_axes[0]).powi(2))
                    .max(0.0)
                    .sqrt();
                let can = |t: f64| {
                    let (sin, cos) = t.sin_cos();
                    [
                        x,
                        sc * c.semi_axes[1] * cos,
                        c.centre[1] + sc * c.semi_axes[2] * sin,
                    ]
                };
                let psi = self.crease_angle(&can);
                let right = can(psi);
                let left = [right[0], -right[1], right[2]];
                // The crease's angle on the fuselage (upper half).
                let theta = (right[2] / (s * self.upper)).atan2(right[1] / (s * self.half_span));
                let mut pts = vec![point(right, &mut surface)];
                let (table, len) = arc_table(&can, psi, PI - psi, 1024);
                let nc = ((len / h).round() as usize).max(1);
                for i in 1..nc {
                    pts.push(point(
                        can(param_at(&table, len * i as f64 / nc as f64)),
                        &mut surface,
                    ));
                }
                pts.push(point(left, &mut surface));
                let (table, len) = arc_table(&fus, PI - theta, 2.0 * PI + theta, 4096);
                let nf = ((len / h).round() as usize).max(2);
                for i in 1..nf {
                    pts.push(point(
                        fus(param_at(&table, len * i as f64 / nf as f64)),
                        &mut surface,
                    ));
                }
                Ring {
                    points: pts,
                    corners: Some((0, nc)),
                }
            };
            rings.push(ring);
        }
        rings.push(Ring {
            points: vec![point([a, 0.0, 0.0], &mut surface)],
            corners: None,
        });

        let [fuselage, canopy] = markers;
        let mut tris: Vec<([u32; 3], i32)> = Vec::new();
        for w in rings.windows(2) {
            let (r0, r1) = (&w[0], &w[1]);
            let pts = &surface.points;
            match (r0.corners, r1.corners) {
                (None, None) => zip_closed(&r0.points, &r1.points, pts, fuselage, &mut tris),
                (Some(_), Some(_)) => {
                    zip(
                        &r0.canopy_chain(),
                        &r1.canopy_chain(),
                        pts,
                        canopy,
                        &mut tris,
                    );
                    zip(
                        &r0.fuselage_chain(),
                        &r1.fuselage_chain(),
                        pts,
                        fuselage,
                        &mut tris,
                    );
                }
                (None, Some(_)) => {
                    // The crease's front tip: a cap of canopy fanned from it, and a fuselage
                    // ring through it.
                    let t = front_tip.expect("a crossed ring has a front tip before it");
                    zip(&[t], &r1.canopy_chain(), pts, canopy, &mut tris);
                    let mut ring = vec![t];
                    ring.extend(r1.fuselage_chain());
                    zip_closed(&r0.points, &ring, pts, fuselage, &mut tris);
                }
                (Some(_), None) => {
                    let t = rear_tip.expect("a crossed ring has a rear tip after it");
                    zip(&r0.canopy_chain(), &[t], pts, canopy, &mut tris);
                    let mut ring = vec![t];
                    ring.extend(r0.fuselage_chain());
                    zip_closed(&ring, &r1.points, pts, fuselage, &mut tris);
                }
            }
        }
        surface.triangles = tris
            .into_iter()
            .enumerate()
            .map(|(k, (v, marker))| SurfaceTriangle {
                v,
                marker,
                facet: k as u32,
            })
            .collect();
        surface
    }

    /// The stations `x` of the front and rear tips of the crease: where the canopy's top meets
    /// the fuselage's top.
    fn crease_tips(&self, c: Canopy) -> (f64, f64) {
        let a = self.half_length;
        let lo = (c.centre[0] - c.semi_axes[0]).max(-a);
        let hi = (c.centre[0] + c.semi_axes[0]).min(a);
        let gap = |x: f64| {
            let u = ((x - c.centre[0]) / c.semi_axes[0]).clamp(-1.0, 1.0);
            let top = c.centre[1] + c.semi_axes[2] * (1.0 - u * u).sqrt();
            top - self.upper * (1.0 - (x / a).powi(2)).max(0.0).sqrt()
        };
        let samples: Vec<(f64, f64)> = (0..=256)
            .map(|i| {
                let x = lo + (hi - lo) * i as f64 / 256.0;
                (x, gap(x))
            })
            .collect();
        let changes = samples
            .windows(2)
            .filter(|w| (w[0].1 > 0.0) != (w[1].1 > 0.0))
            .count();
        let top =
            samples.iter().copied().fold(
                (lo, f64::NEG_INFINITY),
                |b, s| if s.1 > b.1 { s } else { b },
            );
        assert!(
            top.1 > 0.0 && changes == 2 && samples[0].1 < 0.0 && samples[256].1 < 0.0,
            "double ellipsoid: the canopy must poke out of the fuselage's top along one \
             interval, with both its ends inside the fuselage"
        );
        (bisect(gap, lo, top.0), bisect(gap, hi, top.0))
    }

    /// The angle on the canopy's cross-section `can` (right half, `[−π/2, π/2]`) where it
    /// crosses the fuselage.
    fn crease_angle(&self, can: &impl Fn(f64) -> [f64; 3]) -> f64 {
        let g = |t: f64| self.fuselage_level(can(t));
        let changes = (0..64)
            .filter(|&i| {
                let t0 = -0.5 * PI + PI * i as f64 / 64.0;
                let t1 = -0.5 * PI + PI * (i + 1) as f64 / 64.0;
                (g(t0) > 0.0) != (g(t1) > 0.0)
            })
            .count();
        assert!(
            g(-0.5 * PI) < 0.0 && g(0.5 * PI) > 0.0 && changes == 1,
            "double ellipsoid: each canopy cross-section must cross the fuselage once per side"
        );
        let t = bisect(g, -0.5 * PI, 0.5 * PI);
        let p = can(t);
        assert!(
            p[2] > 0.0,
            "double ellipsoid: the canopy must cross the fuselage's upper half"
        );
        t
    }
}

/// A ring of point indices, counter-clockwise seen from `+x`, and, when it crosses the crease,
/// the positions of its right and left crease points.
struct Ring {
    points: Vec<u32>,
    corners: Option<(usize, usize)>,
}

impl Ring {
    /// The canopy arc from the right crease point to the left one.
    fn canopy_chain(&self) -> Vec<u32> {
        let (r, l) = self.corners.expect("a crease ring");
        self.points[r..=l].to_vec()
    }

    /// The fuselage arc from the left crease point around the bottom to the right one.
    fn fuselage_chain(&self) -> Vec<u32> {
        let (r, l) = self.corners.expect("a crease ring");
        let mut c = self.points[l..].to_vec();
        c.push(self.points[r]);
        c
    }
}

/// Triangulates the strip between chains `a` (at smaller `x`) and `b`, both counter-clockwise
/// seen from `+x`, whose first points are joined and whose last points are joined, advancing
/// by the shorter diagonal. Triangles `(a_i, a_i+1, b_j)` and `(a_i, b_j+1, b_j)` have outward
/// normals.
fn zip(a: &[u32], b: &[u32], pts: &[[f64; 3]], marker: i32, out: &mut Vec<([u32; 3], i32)>) {
    let (mut i, mut j) = (0, 0);
    let p = |v: u32| pts[v as usize];
    while i + 1 < a.len() || j + 1 < b.len() {
        let advance_a = if i + 1 == a.len() {
            false
        } else if j + 1 == b.len() {
            true
        } else {
            dist(p(a[i + 1]), p(b[j])) <= dist(p(a[i]), p(b[j + 1]))
        };
        if advance_a {
            out.push(([a[i], a[i + 1], b[j]], marker));
            i += 1;
        } else {
            out.push(([a[i], b[j + 1], b[j]], marker));
            j += 1;
        }
    }
}

/// [`zip`] for two closed rings (either may be a single point, a pole): `b` starts at its
/// point nearest `a`'s first.
fn zip_closed(a: &[u32], b: &[u32], pts: &[[f64; 3]], marker: i32, out: &mut Vec<([u32; 3], i32)>) {
    let close = |r: &[u32], start: usize| -> Vec<u32> {
        let mut c: Vec<u32> = r[start..].iter().chain(&r[..start]).copied().collect();
        if r.len() > 1 {
            c.push(r[start]);
        }
        c
    };
    let p0 = pts[a[0] as usize];
    let start = (0..b.len())
        .min_by(|&x, &y| dist(pts[b[x] as usize], p0).total_cmp(&dist(pts[b[y] as usize], p0)))
        .unwrap_or(0);
    zip(&close(a, 0), &close(b, start), pts, marker, out);
}

/// A table of cumulative arc length along the curve `f` over `[t0, t1]` (`n` chords), and the
/// total length.
fn arc_table(f: &impl Fn(f64) -> [f64; 3], t0: f64, t1: f64, n: usize) -> (Vec<(f64, f64)>, f64) {
    let mut table = Vec::with_capacity(n + 1);
    let mut s = 0.0;
    let mut prev = f(t0);
    table.push((t0, 0.0));
    for i in 1..=n {
        let t = t0 + (t1 - t0) * i as f64 / n as f64;
        let q = f(t);
        s += dist(prev, q);
        table.push((t, s));
        prev = q;
    }
    (table, s)
}

/// The parameter at arc length `s` in an [`arc_table`].
fn param_at(table: &[(f64, f64)], s: f64) -> f64 {
    let i = table
        .partition_point(|e| e.1 <= s)
        .clamp(1, table.len() - 1);
    let (t0, s0) = table[i - 1];
    let (t1, s1) = table[i];
    if s1 > s0 {
        t0 + (t1 - t0) * ((s - s0) / (s1 - s0)).clamp(0.0, 1.0)
    } else {
        t0
    }
}

/// The root of `f` between `lo` and `hi` (where `f` has opposite signs), by bisection to the
/// last bit.
fn bisect(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let (mut lo, mut hi) = (lo, hi);
    let lo_positive = f(lo) > 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid == lo || mid == hi {
            break;
        }
        if (f(mid) > 0.0) == lo_positive {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// An ellipsoid with `semi_axes` around `centre`, meshed by the rings of
/// [`DoubleEllipsoid::surface`] at `spacing`; outward normals, one facet per triangle.
pub fn ellipsoid(centre: [f64; 3], semi_axes: [f64; 3], spacing: f64, marker: i32) -> Surface3 {
    DoubleEllipsoid::ellipsoid(semi_axes)
        .surface(spacing, [marker, marker])
        .translated(centre)
}

/// The paper's Figure 9: the Hermes-like [`DoubleEllipsoid::HERMES`] (length 2, nose at
/// `x = −1`) meshed at spacing `girth / n`, inside the far-field box `[−5, 5] × [−3, 3]²`
/// (2 body lengths ahead and behind, 1.5 to the sides) meshed at 20 times that spacing.
/// `n` = [`DOUBLE_ELLIPSOID_N`] gives about the paper's 3309 body points; `n` below 8 is 8.
///
/// Markers: 1 far field, 2 fuselage, 3 canopy.
pub fn double_ellipsoid(n: usize) -> Plc3 {
    let body = DoubleEllipsoid::HERMES;
    let h = body.girth() / n.max(8) as f64;
    let (lo, hi) = ([-5.0, -3.0, -3.0], [5.0, 3.0, 3.0]);
    let mut plc = Plc3::default();
    box_surface(lo, hi, divisions_for(lo, hi, 20.0 * h), 1).append_to(&mut plc);
    body.surface(h, [2, 3]).append_to(&mut plc);
    plc
}

/// A unit sphere at the origin ([`icosphere`] of frequency `n`, at least 1) inside the cube
/// `[−3, 3]³` meshed at about 6 times the sphere's spacing.
///
/// Markers: 1 box, 2 sphere.
pub fn sphere_in_box(n: usize) -> Plc3 {
    let n = n.max(1);
    let h = 1.05 / n as f64;
    let (lo, hi) = ([-3.0; 3], [3.0; 3]);
    let mut plc = Plc3::default();
    box_surface(lo, hi, divisions_for(lo, hi, 6.0 * h), 1).append_to(&mut plc);
    icosphere([0.0; 3], 1.0, n, 2).append_to(&mut plc);
    plc
}

/// The cube `[−1, 1]³` with the cube `[−0.4, 0.4]³` as a hole, both with `n` divisions per
/// edge (rounded up to an even number, at least 2), so the hole's spacing is 0.4 times the
/// outer one. The hole is given by nesting and also by a hole seed at the origin.
///
/// Markers: 1 outer cube, 2 inner cube.
pub fn cube_with_cubic_hole(n: usize) -> Plc3 {
    let mut plc = Plc3::default();
    box_surface([-1.0; 3], [1.0; 3], [n; 3], 1).append_to(&mut plc);
    box_surface([-0.4; 3], [0.4; 3], [n; 3], 2).append_to(&mut plc);
    plc.holes.push([0.0; 3]);
    plc
}

/// Two separate bodies in the box `[−4, 4] × [−3, 3]²`: a sphere of radius 0.5 at
/// `(−1, 0, 0)` ([`icosphere`] of frequency `n`, at least 1) and a prolate ellipsoid of
/// semi-axes `(0.7, 0.35, 0.35)` at `(1.1, 0, 0)` at the sphere's spacing; the box at 8 times
/// it.
///
/// Markers: 1 box, 2 sphere, 3 ellipsoid.
pub fn two_bodies(n: usize) -> Plc3 {
    let n = n.max(1);
    let h = 0.5 * 1.05 / n as f64;
    let (lo, hi) = ([-4.0, -3.0, -3.0], [4.0, 3.0, 3.0]);
    let mut plc = Plc3::default();
    box_surface(lo, hi, divisions_for(lo, hi, 8.0 * h), 1).append_to(&mut plc);
    icosphere([-1.0, 0.0, 0.0], 0.5, n, 2).append_to(&mut plc);
    ellipsoid([1.1, 0.0, 0.0], [0.7, 0.35, 0.35], h, 3).append_to(&mut plc);
    plc
}

/// `count` unit cubes in a row along `x` (`[k, k + 1] × [0, 1]²`), each a region of its own
/// (a seed at its centre with attribute `k + 1`), separated by internal walls at `x = 1, 2,
/// ...` given once: where a wall meets the outer surface, three triangles share an edge. Each
/// cube is a [`box_surface`] with `n` divisions per edge; the walls are its `x = lo` sides.
/// Several materials sharing faces (a solid and the fluid around it, for conjugate heat
/// transfer) come to the mesher like this.
///
/// Markers: 1 outer surface, 2 walls.
pub fn blocks(count: usize, n: usize) -> Plc3 {
    let mut plc = Plc3::default();
    let mut index: HashMap<[u64; 3], u32> = HashMap::default();
    let count = count.max(1);
    for k in 0..count {
        let x = k as f64;
        let last = k + 1 == count;
        let cube = box_surface([x, 0.0, 0.0], [x + 1.0, 1.0, 1.0], [n; 3], 1);
        // The cube's points, shared with the previous cube's on the wall between them.
        let id: Vec<u32> = cube
            .points
            .iter()
            .map(|p| {
                *index.entry(p.map(f64::to_bits)).or_insert_with(|| {
                    plc.points.push(*p);
                    (plc.points.len() - 1) as u32
                })
            })
            .collect();
        let facet_base = 6 * k as u32;
        for t in &cube.triangles {
            // Side 1 (`x = hi`) is the next cube's wall, given by that cube as its side 0.
            if t.facet == 1 && !last {
                continue;
            }
            let wall = k > 0 && t.facet == 0;
            plc.triangles.push(SurfaceTriangle {
                v: t.v.map(|v| id[v as usize]),
                marker: if wall { 2 } else { t.marker },
                facet: facet_base + t.facet,
            });
        }
        plc.regions.push(delmesh_boundary_recovery::RegionSeed3 {
            point: [x + 0.5, 0.5, 0.5],
            attribute: (k + 1) as f64,
            max_volume: None,
        });
    }
    plc
}

/// Field points for the Table 2 demo (R9, points from an external source): seven offset
/// layers of the double ellipsoid's surface points of [`double_ellipsoid`]`(n)`, each point
/// moved along its vertex normal (area-weighted, outward) by `0.8·h·(1.5^(k+1) − 1)/0.5`,
/// `k = 0..7` for the surface spacing `h`: layers about `0.8·h` apart next to the body and
/// growing by 1.5 away from it, as the nodes of an O-mesh around it would be. About 23,000
/// points for the default `n`, inside the far field; any that a concave crease folds into the
/// body are removed with it (R9).
pub fn double_ellipsoid_shells(n: usize) -> Vec<[f64; 3]> {
    let body = DoubleEllipsoid::HERMES;
    let h = body.girth() / n.max(8) as f64;
    let surface = body.surface(h, [2, 3]);
    let mut normal = vec![[0.0f64; 3]; surface.points.len()];
    for t in &surface.triangles {
        let p = t.v.map(|i| surface.points[i as usize]);
        let u = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
        let v = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        for &i in &t.v {
            for k in 0..3 {
                normal[i as usize][k] += n[k];
            }
        }
    }
    for n in &mut normal {
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        *n = n.map(|x| x / l);
    }
    let mut points = Vec::with_capacity(7 * surface.points.len());
    let mut offset = 0.0;
    for k in 0..7 {
        offset += 0.8 * h * 1.5f64.powi(k);
        points.extend(
            surface
                .points
                .iter()
                .zip(&normal)
                .map(|(p, n)| [0, 1, 2].map(|i| p[i] + offset * n[i])),
        );
    }
    points
}
