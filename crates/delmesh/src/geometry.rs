//! The analytic geometry of the demos: the paper's figures as [`Plc2`] inputs.
//!
//! Every function is deterministic (no random numbers; a small integer hash gives the coastline
//! its noise). Loops are oriented so that the domain is on their left: outer boundaries
//! counter-clockwise, bodies and islands clockwise; so the shoelace sum over all segments is the
//! domain's area.
//!
//! | function | markers |
//! | --- | --- |
//! | [`figure8`] | 1 outer square, 2 slot, 3 triangular hole |
//! | [`two_element_aerofoil`] | 1 far field, 2 main element, 3 flap |
//! | [`coastline`] | 1 coast, 2 open sea, 3 river, 4 islands |
//! | [`figure12`], [`figure13_cfd`] | 1 rectangle sides |

use std::f64::consts::PI;

use delmesh_boundary_recovery::{Plc2, Segment};
use delmesh_delaunay_core::Triangulation2;
use delmesh_point_gen::BackgroundMesh2;

/// Adds a closed loop (points in order) with one marker.
fn add_loop(plc: &mut Plc2, points: &[[f64; 2]], marker: i32) {
    let base = plc.points.len() as u32;
    let n = points.len() as u32;
    plc.points.extend_from_slice(points);
    for i in 0..n {
        plc.segments.push(Segment {
            a: base + i,
            b: base + (i + 1) % n,
            marker,
        });
    }
}

/// Adds a closed loop whose consecutive points carry the given markers: segment `i` (from
/// point `i` to point `i + 1`) gets `markers[i]`.
fn add_marked_loop(plc: &mut Plc2, points: &[[f64; 2]], markers: &[i32]) {
    let base = plc.points.len() as u32;
    let n = points.len() as u32;
    plc.points.extend_from_slice(points);
    for i in 0..n {
        plc.segments.push(Segment {
            a: base + i,
            b: base + (i + 1) % n,
            marker: markers[i as usize],
        });
    }
}

/// The Figure 5/8 input: a square with a thin slot and a small triangular hole whose tips
/// come close to the slot's long lower edge from both sides, so the Delaunay triangulation of
/// the points misses boundary edges and mid-point recovery needs several passes.
pub fn figure8() -> Plc2 {
    let mut plc = Plc2::default();
    add_loop(
        &mut plc,
        &[[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],
        1,
    );
    add_loop(
        &mut plc,
        &[[1.0, 5.0], [1.0, 5.4], [5.0, 5.03], [9.0, 5.4], [9.0, 5.0]],
        2,
    );
    add_loop(&mut plc, &[[4.8, 4.5], [5.0, 4.97], [5.2, 4.5]], 3);
    plc
}

/// A NACA 4-digit section (camber `m`, its position `p`, thickness `t`, as fractions of the
/// chord) of chord 1 with the closed trailing edge, as a counter-clockwise polygon of `2n`
/// points: the trailing edge, the upper surface to the leading edge, the lower surface back.
/// Chordwise points are spaced two thirds by cosine (fine at both edges), one third uniformly.
pub fn naca4(m: f64, p: f64, t: f64, n: usize) -> Vec<[f64; 2]> {
    let n = n.max(4);
    let surface = |x: f64, upper: bool| {
        let yt = 5.0
            * t
            * (0.2969 * x.sqrt() - 0.1260 * x - 0.3516 * x * x + 0.2843 * x.powi(3)
                - 0.1036 * x.powi(4));
        let (yc, dyc) = if m == 0.0 {
            (0.0, 0.0)
        } else if x < p {
            (
                m / (p * p) * (2.0 * p * x - x * x),
                2.0 * m / (p * p) * (p - x),
            )
        } else {
            (
                m / ((1.0 - p) * (1.0 - p)) * ((1.0 - 2.0 * p) + 2.0 * p * x - x * x),
                2.0 * m / ((1.0 - p) * (1.0 - p)) * (p - x),
            )
        };
        let th = dyc.atan();
        if upper {
            [x - yt * th.sin(), yc + yt * th.cos()]
        } else {
            [x + yt * th.sin(), yc - yt * th.cos()]
        }
    };
    // Mostly cosine spacing (fine at the leading edge's curvature), blended with a uniform
    // third so the trailing edge's spacing stays near the chord / (3n), not (π/n)².
    let xs: Vec<f64> = (0..=n)
        .map(|i| {
            let u = i as f64 / n as f64;
            2.0 / 3.0 * 0.5 * (1.0 - (PI * u).cos()) + u / 3.0
        })
        .collect();
    let mut pts = vec![[1.0, 0.0]];
    for i in (1..n).rev() {
        pts.push(surface(xs[i], true));
    }
    pts.push([0.0, 0.0]);
    for &x in &xs[1..n] {
        pts.push(surface(x, false));
    }
    pts
}

/// Scales by `chord`, rotates by `angle_deg` (positive: nose up, i.e. clockwise about the
/// leading edge turns the trailing edge down for negative values) and moves the leading edge
/// to `at`.
fn place(points: &[[f64; 2]], chord: f64, angle_deg: f64, at: [f64; 2]) -> Vec<[f64; 2]> {
    let (s, c) = angle_deg.to_radians().sin_cos();
    points
        .iter()
        .map(|p| {
            let (x, y) = (p[0] * chord, p[1] * chord);
            [at[0] + c * x - s * y, at[1] + s * x + c * y]
        })
        .collect()
}

/// The main element of the two-element aerofoil (NACA 2412, chord 1), clockwise.
fn main_element(n: usize) -> Vec<[f64; 2]> {
    let mut l = naca4(0.02, 0.4, 0.12, n);
    l.reverse();
    l
}

/// The flap (NACA 4412, chord 0.3, deflected 25° down, in the slot behind the main element's
/// trailing edge), clockwise.
fn flap(n: usize) -> Vec<[f64; 2]> {
    let mut l = place(&naca4(0.04, 0.4, 0.12, n), 0.3, -25.0, [0.96, -0.075]);
    l.reverse();
    l
}

/// Points on a circle of radius `r` around `c`, counter-clockwise.
fn circle(c: [f64; 2], r: f64, n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let a = 2.0 * PI * i as f64 / n as f64;
            [c[0] + r * a.cos(), c[1] + r * a.sin()]
        })
        .collect()
}

/// The two-element aerofoil of Figures 10 and 11: a NACA 2412 main element (`2n` points) and
/// a NACA 4412 flap (about `1.2n` points) in a circular far field of radius 10 chords.
pub fn two_element_aerofoil(n: usize) -> Plc2 {
    let mut plc = Plc2::default();
    add_loop(&mut plc, &circle([0.5, 0.0], 10.0, 64), 1);
    add_loop(&mut plc, &main_element(n), 2);
    add_loop(&mut plc, &flap((n * 6 / 10).max(8)), 3);
    plc
}

/// Points of structured O-type layer meshes around each element of
/// [`two_element_aerofoil`]`(n)`, as separate component meshes would give (Figure 10a, R9):
/// layers offset along the surface normals with growing spacing. Layers of one element may
/// overlap the other element; those points are dropped with its interior.
pub fn component_mesh_points(n: usize) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for (body, chord) in [(main_element(n), 1.0), (flap((n * 6 / 10).max(8)), 0.3)] {
        let m = body.len();
        let mut h = 0.004 * chord;
        let mut offset = 0.0;
        for _layer in 0..14 {
            offset += h;
            h *= 1.25;
            for i in 0..m {
                let (a, b) = (body[(i + m - 1) % m], body[(i + 1) % m]);
                let (tx, ty) = (b[0] - a[0], b[1] - a[1]);
                let len = tx.hypot(ty);
                // The loop is clockwise, so the outward normal is on its left.
                let nrm = [-ty / len, tx / len];
                let p = body[i];
                out.push([p[0] + offset * nrm[0], p[1] + offset * nrm[1]]);
            }
        }
    }
    out
}

/// A deterministic value in [-1, 1) from an integer (a small hash).
fn noise(k: u64) -> f64 {
    let mut z = k
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(0x632B_E59B_D9B4_E019);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Fractal refinement of the polyline `a → b`: `levels` rounds of mid-point displacement
/// along the normal by `rough` times the piece's length; returns the points after `a` up to
/// and including `b`.
fn fractal(a: [f64; 2], b: [f64; 2], levels: u32, rough: f64, seed: u64) -> Vec<[f64; 2]> {
    let mut pts = vec![a, b];
    for level in 0..levels {
        let mut next = vec![pts[0]];
        for (k, w) in pts.windows(2).enumerate() {
            let (p, q) = (w[0], w[1]);
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            let d = rough * noise(seed ^ (u64::from(level) << 32) ^ k as u64);
            next.push([0.5 * (p[0] + q[0]) - d * dy, 0.5 * (p[1] + q[1]) + d * dx]);
            next.push(q);
        }
        pts = next;
    }
    pts.remove(0);
    pts
}

/// Figure 7: an estuary. A bay open to the sea along the top (straight, coarse), a ragged
/// coastline, a river entering at the bottom (straight inlet), and three ragged islands.
pub fn coastline() -> Plc2 {
    let mut plc = Plc2::default();
    // Corners of the outer loop, counter-clockwise, with the marker of the side leaving each.
    let corners: [([f64; 2], i32, bool); 9] = [
        ([0.0, 60.0], 1, true),
        ([2.0, 20.0], 1, true),
        ([30.0, 14.0], 1, true),
        ([41.0, 0.0], 3, false), // the river inlet
        ([47.0, 0.0], 1, true),
        ([52.0, 16.0], 1, true),
        ([80.0, 24.0], 1, true),
        ([100.0, 30.0], 1, true),
        ([100.0, 60.0], 2, false), // the open sea
    ];
    let mut points = Vec::new();
    let mut markers = Vec::new();
    for (k, &(p, marker, ragged)) in corners.iter().enumerate() {
        let q = corners[(k + 1) % corners.len()].0;
        let piece = if ragged {
            fractal(p, q, 5, 0.12, 1000 + k as u64)
        } else {
            // Straight, a few points.
            let n = if marker == 2 { 12 } else { 4 };
            (1..=n)
                .map(|i| {
                    let t = i as f64 / n as f64;
                    [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
                })
                .collect()
        };
        // The loop is closed by the first corner: leave it out at the end.
        let piece_len = piece.len();
        let start_count = points.len();
        points.push(p);
        points.extend_from_slice(&piece[..piece_len - 1]);
        markers.resize(points.len(), marker);
        let _ = start_count;
    }
    add_marked_loop(&mut plc, &points, &markers);
    for (k, (c, r)) in [
        ([28.0, 40.0], 5.0),
        ([62.0, 44.0], 4.0),
        ([46.0, 26.0], 2.5),
    ]
    .into_iter()
    .enumerate()
    {
        let ring = circle(c, r, 6);
        let mut island = Vec::new();
        for i in 0..ring.len() {
            island.push(ring[i]);
            let piece = fractal(
                ring[i],
                ring[(i + 1) % ring.len()],
                3,
                0.1,
                77 + 10 * k as u64 + i as u64,
            );
            island.extend_from_slice(&piece[..piece.len() - 1]);
        }
        island.reverse();
        add_loop(&mut plc, &island, 4);
    }
    plc
}

/// Points along `a → b` whose spacing goes linearly from `ha` at `a` to `hb` at `b`; `a`
/// included, `b` not.
fn graded(a: [f64; 2], b: [f64; 2], ha: f64, hb: f64) -> Vec<[f64; 2]> {
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let mut ts = vec![0.0];
    let mut t = 0.0;
    loop {
        let h = ha + (hb - ha) * t;
        t += h / len;
        if t > 1.0 - 0.5 * (ha + (hb - ha) * t) / len {
            break;
        }
        ts.push(t);
    }
    ts.iter()
        .map(|&t| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
        .collect()
}

/// A rectangle whose sides are graded by the spacings at its corners.
fn graded_rectangle(corners: [[f64; 2]; 4], h: [f64; 4]) -> Plc2 {
    let mut pts = Vec::new();
    for k in 0..4 {
        pts.extend(graded(
            corners[k],
            corners[(k + 1) % 4],
            h[k],
            h[(k + 1) % 4],
        ));
    }
    let mut plc = Plc2::default();
    add_loop(&mut plc, &pts, 1);
    plc
}

/// Figure 12: the rectangle ABCD (2 × 1) and a background mesh of two triangles split along
/// the diagonal BD, with a small spacing at B and D and a large one at A and C, so points
/// cluster along BD.
pub fn figure12() -> (Plc2, BackgroundMesh2) {
    let corners = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
    let h = [0.2, 0.01, 0.2, 0.01];
    let plc = graded_rectangle(corners, h);
    let background = BackgroundMesh2::new(corners.to_vec(), vec![[0, 1, 3], [1, 2, 3]], h.to_vec())
        .expect("the Figure 12 background mesh is valid");
    (plc, background)
}

/// Polylines of the letters C, F and D in the box `[0.3, 2.7] × [0.25, 0.95]`.
fn letters() -> Vec<Vec<[f64; 2]>> {
    let arc = |c: [f64; 2], r: [f64; 2], from: f64, to: f64, n: usize| -> Vec<[f64; 2]> {
        (0..=n)
            .map(|i| {
                let a = (from + (to - from) * i as f64 / n as f64).to_radians();
                [c[0] + r[0] * a.cos(), c[1] + r[1] * a.sin()]
            })
            .collect()
    };
    let mut d = vec![[1.95, 0.25], [1.95, 0.95]];
    d.extend(arc([2.15, 0.6], [0.45, 0.35], 90.0, -90.0, 16));
    d.push([1.95, 0.25]);
    vec![
        arc([0.68, 0.6], [0.4, 0.35], 50.0, 310.0, 24),
        vec![[1.55, 0.95], [1.2, 0.95], [1.2, 0.25]],
        vec![[1.2, 0.62], [1.48, 0.62]],
        d,
    ]
}

/// Figure 13: a 3 × 1.2 rectangle and a background mesh whose nodes along the letters "CFD"
/// have a small spacing (0.008) and whose other nodes (corners, a coarse grid) a large one
/// (0.12), triangulated by delmesh itself.
pub fn figure13_cfd() -> (Plc2, BackgroundMesh2) {
    let (fine, coarse) = (0.008, 0.12);
    // Nodes along the letters carry the fine spacing; the nodes of a regular grid around them
    // grow from it with the distance to the letters, up to the coarse spacing.
    let mut nodes: Vec<[f64; 2]> = Vec::new();
    for line in letters() {
        for w in line.windows(2) {
            let (a, b) = (w[0], w[1]);
            let n = ((b[0] - a[0]).hypot(b[1] - a[1]) / 0.02).ceil().max(1.0) as usize;
            for k in 0..n {
                let t = k as f64 / n as f64;
                nodes.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            }
        }
    }
    let mut spacing = vec![fine; nodes.len()];
    let on_letters = nodes.clone();
    for i in 0..=24 {
        for j in 0..=10 {
            let p = [3.0 * i as f64 / 24.0, 1.2 * j as f64 / 10.0];
            let d = on_letters
                .iter()
                .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
                .fold(f64::INFINITY, f64::min);
            if d > 0.01 {
                nodes.push(p);
                spacing.push((fine + 0.3 * d).min(coarse));
            }
        }
    }
    let tri = Triangulation2::new(&nodes).expect("background nodes triangulate");
    let triangles: Vec<[u32; 3]> = tri
        .cells_in_input_numbering()
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let background = BackgroundMesh2::new(nodes, triangles, spacing)
        .expect("the Figure 13 background mesh is valid");
    let corners = [[0.0, 0.0], [3.0, 0.0], [3.0, 1.2], [0.0, 1.2]];
    (graded_rectangle(corners, [coarse / 2.0; 4]), background)
}
