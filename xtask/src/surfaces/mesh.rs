//! Tetrahedral meshes in TetGen's file family (`.node`, `.ele`, `.face`), as both
//! delmesh (`-o X.ele`) and TetGen write them, and what xtask measures on them: the
//! checks of a mesh of the solid bounded by a surface, and a quality summary computed
//! the same way for both tools.
//!
//! Checks ([`check_mesh_with`]), each against xtask's own reading of the input surface:
//! - orientation: every tetrahedron has positive volume, decided by the exact
//!   `orient3d` of the `robust` crate (Shewchuk's adaptive arithmetic) on the doubles
//!   read back from the file (both tools print coordinates round-trip exactly);
//! - the complex: no triangle is shared by more than two tetrahedra, and the triangles of
//!   exactly one tetrahedron are exactly the `.face` file's;
//! - volume: the tetrahedra's total volume equals the volume the input surface encloses
//!   (divergence theorem), relative 1e-9;
//! - coverage: every boundary face lies on an input triangle (its corners within 1e-9
//!   of the bounding-box diagonal), and the faces on each input triangle add up to its
//!   area, relative 1e-9; and every input vertex is an output vertex, bit for bit;
//! - topology: for a solid M bounded by closed surfaces, χ(M) = χ(∂M)/2 (the double of
//!   M along its boundary is closed, so has χ = 0, and χ(double) = 2χ(M) − χ(∂M)); so
//!   V − E + F − T of the tetrahedra must be half of V − E + F of the input surface (1
//!   for a ball, 1 − g for a handlebody of genus g, a sum over the bodies), and the
//!   boundary faces must have the input's χ.
//!
//! Quality ([`Quality`]): dihedral angles (min, max), slivers (tetrahedra whose smallest
//! dihedral angle is under 5 degrees), and the radius-edge ratio (circumradius over
//! shortest edge; TetGen's `-q` bounds it by 2 away from small input angles).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use anyhow::{ensure, Context, Result};

use crate::formats;

use super::surface::{cross, dot, norm, point_key, sorted3, sub, triangle_area, Sum, Surface};

/// Relative tolerance of the volume and area checks.
pub const RTOL: f64 = 1e-9;
/// Dihedral angle below which a tetrahedron counts as a sliver, degrees.
pub const SLIVER_DEGREES: f64 = 5.0;

/// A tetrahedral mesh read back from `X.node`, `X.ele` and `X.face`, 0-based.
#[derive(Debug, Clone, Default)]
pub struct TetMesh {
    pub points: Vec<[f64; 3]>,
    /// Corners in file order (the orientation matters).
    pub tets: Vec<[u32; 4]>,
    /// Boundary faces of the `.face` file (empty when there is none).
    pub faces: Vec<[u32; 3]>,
}

/// `X.node` next to `X.ele` (or any sibling extension).
pub fn sibling(ele: &Path, ext: &str) -> PathBuf {
    ele.with_extension(ext)
}

/// Reads `<stem>.node`, `<stem>.ele` and, if present, `<stem>.face`, where `ele` is the
/// `.ele` path.
///
/// FORMAT (TetGen 1.5, and delmesh's writer of the same family): `.node` as in
/// `formats::read_node` (the first index, 0 or 1, sets the numbering of the other two
/// files); `.ele`: `<#tets> <nodes per tet> <#attributes>` then `<idx> v1 v2 v3 v4
/// [attributes]`; `.face`: `<#faces> <#markers>` then `<idx> v1 v2 v3 [marker]`. The
/// corners of a tetrahedron are listed with `det[v2-v1, v3-v1, v4-v1] > 0` by both tools.
pub fn read_tet_mesh(ele: &Path) -> Result<TetMesh> {
    let node = formats::read_node(&sibling(ele, "node"))?;
    ensure!(node.dim == 3, "{}: not 3D", ele.display());
    let base = node.first_index;
    let points: Vec<[f64; 3]> = node
        .coords
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let n = points.len() as i64;
    let read = |path: &Path, per: usize| -> Result<Vec<Vec<u32>>> {
        let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
        let mut lines = formats::int_lines(&bytes, path);
        let (_, header) = lines
            .next()
            .with_context(|| format!("{}: empty", path.display()))??;
        let count = usize::try_from(header[0]).context("negative count")?;
        let mut out = Vec::with_capacity(count);
        for line in lines.take(count) {
            let (ln, f) = line?;
            ensure!(f.len() > per, "{}:{ln}: too few fields", path.display());
            let mut v = Vec::with_capacity(per);
            for &x in &f[1..=per] {
                ensure!(
                    (base..base + n).contains(&x),
                    "{}:{ln}: vertex {x} out of range",
                    path.display()
                );
                v.push((x - base) as u32);
            }
            out.push(v);
        }
        ensure!(
            out.len() == count,
            "{}: header says {count}, found {}",
            path.display(),
            out.len()
        );
        Ok(out)
    };
    let tets = read(ele, 4)?
        .into_iter()
        .map(|v| [v[0], v[1], v[2], v[3]])
        .collect();
    let face_path = sibling(ele, "face");
    let faces = if face_path.is_file() {
        read(&face_path, 3)?
            .into_iter()
            .map(|v| [v[0], v[1], v[2]])
            .collect()
    } else {
        Vec::new()
    };
    Ok(TetMesh {
        points,
        tets,
        faces,
    })
}

fn coord(p: [f64; 3]) -> robust::Coord3D<f64> {
    robust::Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

/// Edge index pairs of a tetrahedron, and for each the two other corners.
const EDGES: [([usize; 2], [usize; 2]); 6] = [
    ([0, 1], [2, 3]),
    ([0, 2], [1, 3]),
    ([0, 3], [1, 2]),
    ([1, 2], [0, 3]),
    ([1, 3], [0, 2]),
    ([2, 3], [0, 1]),
];

impl TetMesh {
    fn corners(&self, t: [u32; 4]) -> [[f64; 3]; 4] {
        t.map(|v| self.points[v as usize])
    }

    /// Numbers of tetrahedra with negative and with zero exact orientation, and the
    /// first bad one.
    pub fn orientation(&self) -> (usize, usize, Option<usize>) {
        let (mut neg, mut flat, mut first) = (0, 0, None);
        for (k, &t) in self.tets.iter().enumerate() {
            let [a, b, c, d] = self.corners(t).map(coord);
            // Shewchuk's orient3d is det[a-d, b-d, c-d]: negative for det[b-a, c-a,
            // d-a] > 0, the positive orientation of both tools' files.
            let o = robust::orient3d(a, b, c, d);
            if o >= 0.0 {
                if o > 0.0 {
                    neg += 1;
                } else {
                    flat += 1;
                }
                first.get_or_insert(k);
            }
        }
        (neg, flat, first)
    }

    /// Total volume (compensated sum of signed volumes).
    pub fn volume(&self) -> f64 {
        let mut s = Sum::default();
        for &t in &self.tets {
            let [a, b, c, d] = self.corners(t);
            s.add(dot(sub(b, a), cross(sub(c, a), sub(d, a))) / 6.0);
        }
        s.value()
    }

    /// The triangles of the tetrahedra with how many tetrahedra share each.
    fn tet_faces(&self) -> HashMap<[u32; 3], u8> {
        let mut m: HashMap<[u32; 3], u8> = HashMap::with_capacity(self.tets.len() * 2 + 16);
        for t in &self.tets {
            for skip in 0..4 {
                let mut f = [0u32; 3];
                let mut k = 0;
                for (j, &v) in t.iter().enumerate() {
                    if j != skip {
                        f[k] = v;
                        k += 1;
                    }
                }
                let e = m.entry(sorted3(f)).or_insert(0);
                *e = e.saturating_add(1);
            }
        }
        m
    }

    /// V − E + F − T over the vertices the tetrahedra use.
    pub fn euler_characteristic(&self) -> i64 {
        let faces = self.tet_faces().len() as i64;
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(self.tets.len() * 6);
        let mut used = vec![false; self.points.len()];
        for t in &self.tets {
            for (e, _) in EDGES {
                let (a, b) = (t[e[0]], t[e[1]]);
                edges.push((a.min(b), a.max(b)));
            }
            for &v in t {
                used[v as usize] = true;
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let v = used.iter().filter(|&&u| u).count() as i64;
        v - edges.len() as i64 + faces - self.tets.len() as i64
    }

    /// The boundary faces as a surface (for its Euler characteristic).
    fn boundary_surface(&self) -> Surface {
        Surface {
            points: self.points.clone(),
            triangles: self.faces.clone(),
        }
    }
}

/// The quality summary of a mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quality {
    pub min_dihedral: f64,
    pub max_dihedral: f64,
    /// Tetrahedra with a dihedral angle under [`SLIVER_DEGREES`].
    pub slivers: usize,
    /// Largest circumradius / shortest edge (infinite for a flat tetrahedron).
    pub max_radius_edge: f64,
    /// Tetrahedra with radius-edge ratio above 2 (TetGen's default `-q` bound).
    pub radius_edge_over_2: usize,
}

/// Interior dihedral angle, in degrees, at the edge `p q` between the faces through `r`
/// and `s`: the angle between `r` and `s` projected onto the plane normal to the edge.
fn dihedral(p: [f64; 3], q: [f64; 3], r: [f64; 3], s: [f64; 3]) -> f64 {
    let e = sub(q, p);
    let ee = dot(e, e);
    let project = |x: [f64; 3]| {
        let v = sub(x, p);
        let t = dot(v, e) / ee;
        [v[0] - t * e[0], v[1] - t * e[1], v[2] - t * e[2]]
    };
    let (u, v) = (project(r), project(s));
    norm(cross(u, v)).atan2(dot(u, v)).to_degrees()
}

/// Circumradius of the tetrahedron `a b c d` (infinite when it is flat).
fn circumradius(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    let (u, v, w) = (sub(b, a), sub(c, a), sub(d, a));
    let det = dot(u, cross(v, w));
    if det == 0.0 {
        return f64::INFINITY;
    }
    let (vw, wu, uv) = (cross(v, w), cross(w, u), cross(u, v));
    let (lu, lv, lw) = (dot(u, u), dot(v, v), dot(w, w));
    let o = [0, 1, 2].map(|k| (lu * vw[k] + lv * wu[k] + lw * uv[k]) / (2.0 * det));
    norm(o)
}

/// The quality summary of `mesh` (`None` without tetrahedra).
pub fn quality(mesh: &TetMesh) -> Option<Quality> {
    if mesh.tets.is_empty() {
        return None;
    }
    let mut q = Quality {
        min_dihedral: f64::INFINITY,
        max_dihedral: 0.0,
        slivers: 0,
        max_radius_edge: 0.0,
        radius_edge_over_2: 0,
    };
    for &t in &mesh.tets {
        let p = mesh.corners(t);
        let mut lo = f64::INFINITY;
        let mut shortest = f64::INFINITY;
        for (e, o) in EDGES {
            let a = dihedral(p[e[0]], p[e[1]], p[o[0]], p[o[1]]);
            lo = lo.min(a);
            q.max_dihedral = q.max_dihedral.max(a);
            shortest = shortest.min(norm(sub(p[e[1]], p[e[0]])));
        }
        q.min_dihedral = q.min_dihedral.min(lo);
        if lo < SLIVER_DEGREES {
            q.slivers += 1;
        }
        let ratio = circumradius(p[0], p[1], p[2], p[3]) / shortest;
        // A NaN (coincident corners) counts as the worst possible ratio.
        let ratio = if ratio.is_nan() { f64::INFINITY } else { ratio };
        q.max_radius_edge = q.max_radius_edge.max(ratio);
        if ratio > 2.0 {
            q.radius_edge_over_2 += 1;
        }
    }
    Some(q)
}

/// A uniform grid over the input triangles' bounding boxes, to find the input triangles
/// near a point.
struct TriangleGrid {
    lo: [f64; 3],
    cell: [f64; 3],
    n: [usize; 3],
    cells: Vec<Vec<u32>>,
}

impl TriangleGrid {
    fn new(s: &Surface, pad: f64) -> TriangleGrid {
        let (mut lo, mut hi) = s.bbox();
        for k in 0..3 {
            lo[k] -= pad;
            hi[k] += pad;
        }
        let side = ((s.triangles.len() as f64).cbrt().ceil() as usize).clamp(1, 200);
        let n = [side; 3];
        let cell = [0, 1, 2].map(|k| (hi[k] - lo[k]) / side as f64);
        let mut g = TriangleGrid {
            lo,
            cell,
            n,
            cells: vec![Vec::new(); side * side * side],
        };
        for (ti, t) in s.triangles.iter().enumerate() {
            let c = t.map(|v| s.points[v as usize]);
            let a = [0, 1, 2].map(|k| c[0][k].min(c[1][k]).min(c[2][k]) - pad);
            let b = [0, 1, 2].map(|k| c[0][k].max(c[1][k]).max(c[2][k]) + pad);
            let (ia, ib) = (g.index(a), g.index(b));
            for i in ia[0]..=ib[0] {
                for j in ia[1]..=ib[1] {
                    for k in ia[2]..=ib[2] {
                        let slot = (i * n[1] + j) * n[2] + k;
                        g.cells[slot].push(ti as u32);
                    }
                }
            }
        }
        g
    }

    fn index(&self, p: [f64; 3]) -> [usize; 3] {
        [0, 1, 2].map(|k| {
            let x = ((p[k] - self.lo[k]) / self.cell[k]).floor();
            (x.max(0.0) as usize).min(self.n[k] - 1)
        })
    }

    fn near(&self, p: [f64; 3]) -> &[u32] {
        let i = self.index(p);
        &self.cells[(i[0] * self.n[1] + i[1]) * self.n[2] + i[2]]
    }
}

/// The point of triangle `a b c` closest to `p` (by the Voronoi regions of its corners
/// and edges).
fn closest_on_triangle(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let along = |o: [f64; 3], d: [f64; 3], t: f64| [0, 1, 2].map(|k| o[k] + t * d[k]);
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return along(a, ab, d1 / (d1 - d3));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return along(a, ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let s = va + vb + vc;
    let (v, w) = (vb / s, vc / s);
    [0, 1, 2].map(|k| a[k] + v * ab[k] + w * ac[k])
}

fn distance_to_triangle(p: [f64; 3], t: [[f64; 3]; 3]) -> f64 {
    norm(sub(p, closest_on_triangle(p, t[0], t[1], t[2])))
}

/// The outcome of [`check_mesh_with`]: one message per failed check (empty: all passed).
#[derive(Debug, Clone, Default)]
pub struct CheckReport {
    pub failures: Vec<String>,
    /// A few words per failure, for the table's notes (`volume off by 8.2e-7`).
    pub short: Vec<String>,
    /// χ of the tetrahedra, for the table.
    pub euler: i64,
}

impl CheckReport {
    fn fail(&mut self, short: String, long: String) {
        self.short.push(short);
        self.failures.push(long);
    }
}

/// How the coverage check groups the input triangles (see [`check_mesh_with`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Patches {
    /// Each input triangle alone.
    Triangles,
    /// Neighbours that lie exactly in one plane, joined: what `--merge-coplanar`
    /// re-triangulates.
    Planar,
    /// Neighbours that lie in one plane to rounding, joined: their four corners span a volume
    /// of at most 2^-30 of the longest distance between them cubed. The full pipeline takes
    /// out the flat elements on such neighbours and swaps their diagonal
    /// (`Mesh3::remove_flat_surface_elements`).
    Flat,
}

/// [`check_mesh_with`] with coverage per input triangle.
#[cfg(test)]
pub fn check_mesh(mesh: &TetMesh, input: &Surface) -> CheckReport {
    check_mesh_with(mesh, input, Patches::Triangles)
}

/// The checks of the module docs on `mesh`, a mesh of the solid bounded by `input`
/// (xtask's reading of the input file, duplicates merged). Coverage is checked per group of
/// input triangles as `patches` says (joined across edges where both lie in one plane,
/// exactly or to rounding, consistently oriented): what re-triangulating coplanar facets
/// (`--merge-coplanar`) and taking out flat elements (the full pipeline) promise.
pub fn check_mesh_with(mesh: &TetMesh, input: &Surface, patches: Patches) -> CheckReport {
    let mut r = CheckReport::default();
    if mesh.tets.is_empty() {
        r.fail("empty".into(), "the mesh has no tetrahedra".into());
        return r;
    }
    // Orientation.
    let (neg, flat, first) = mesh.orientation();
    if neg + flat > 0 {
        let k = first.unwrap_or(0);
        r.fail(
            format!("{} inverted/flat", neg + flat),
            format!(
                "orientation: {neg} tetrahedra inverted and {flat} flat (exact orient3d); \
                 first: tetrahedron {k} {:?}",
                mesh.tets[k]
            ),
        );
    }
    // The complex and its boundary.
    let tf = mesh.tet_faces();
    let over = tf.values().filter(|&&c| c > 2).count();
    if over > 0 {
        r.fail(
            format!("{over} triangles in 3+ tetrahedra"),
            format!("complex: {over} triangles shared by more than two tetrahedra"),
        );
    }
    let mut boundary: Vec<[u32; 3]> = tf
        .iter()
        .filter(|(_, &c)| c == 1)
        .map(|(f, _)| *f)
        .collect();
    boundary.sort_unstable();
    let mut listed: Vec<[u32; 3]> = mesh.faces.iter().map(|&f| sorted3(f)).collect();
    listed.sort_unstable();
    if boundary != listed {
        let missing = boundary
            .iter()
            .filter(|f| listed.binary_search(f).is_err())
            .count();
        let extra = listed
            .iter()
            .filter(|f| boundary.binary_search(f).is_err())
            .count();
        r.fail(
            format!("{missing}/{extra} boundary faces missing/extra"),
            format!(
                "boundary: {} faces of one tetrahedron, {} in the .face file; {missing} \
                 boundary faces missing from it, {extra} listed that are not on the boundary",
                boundary.len(),
                listed.len()
            ),
        );
    }
    // Volume.
    let (want, got) = (input.signed_volume().abs(), mesh.volume());
    if (got - want).abs() > RTOL * want {
        r.fail(
            format!("volume off by {:.1e}", (got - want).abs() / want),
            format!(
                "volume: the tetrahedra hold {got:.12e}, the input surface encloses {want:.12e} \
                 (relative difference {:.1e})",
                (got - want).abs() / want
            ),
        );
    }
    // Input vertices are output vertices.
    let out_points: std::collections::HashSet<[u64; 3]> =
        mesh.points.iter().map(|&p| point_key(p)).collect();
    let lost: Vec<usize> = (0..input.points.len())
        .filter(|&i| !out_points.contains(&point_key(input.points[i])))
        .collect();
    if let Some(&i) = lost.first() {
        r.fail(
            format!("{} input vertices lost", lost.len()),
            format!(
                "vertices: {} input vertices are not output vertices, e.g. input vertex {i} {:?}",
                lost.len(),
                input.points[i]
            ),
        );
    }
    // Coverage of every input triangle (or planar patch) by boundary faces.
    let patches = match patches {
        Patches::Triangles => (0..input.triangles.len() as u32).collect(),
        Patches::Planar => planar_patches(input, false),
        Patches::Flat => planar_patches(input, true),
    };
    coverage(mesh, input, &patches, &mut r);
    // Topology.
    let euler = mesh.euler_characteristic();
    r.euler = euler;
    let chi_in = input.euler_characteristic();
    if chi_in % 2 != 0 || euler * 2 != chi_in {
        r.fail(
            format!("χ = {euler}, expected {chi_in}/2"),
            format!(
                "Euler: V - E + F - T = {euler} for the tetrahedra, the input surface has χ = \
                 {chi_in} (a solid has χ(∂M)/2)"
            ),
        );
    }
    let chi_b = mesh.boundary_surface().euler_characteristic();
    if chi_b != chi_in {
        r.fail(
            format!("boundary χ = {chi_b}, expected {chi_in}"),
            format!("Euler: the boundary faces have χ = {chi_b}, the input surface {chi_in}"),
        );
    }
    r
}

/// The planar patch of each input triangle: triangles are joined across an edge of exactly
/// two triangles that run it in opposite directions and lie exactly in one plane (robust
/// orient3d), or with `flat` in one plane to rounding ([`Patches::Flat`]), so a patch is a
/// connected (nearly) planar region. Patch ids are triangle indices.
fn planar_patches(input: &Surface, flat: bool) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..input.triangles.len() as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    let mut edges: HashMap<(u32, u32), Vec<(u32, u32)>> = HashMap::new();
    for (k, t) in input.triangles.iter().enumerate() {
        for m in 0..3 {
            let (a, b) = (t[m], t[(m + 1) % 3]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push((k as u32, t[(m + 2) % 3]));
        }
    }
    for (&(a, b), on) in &edges {
        let [(t1, c), (t2, d)] = on[..] else { continue };
        let runs = |t: u32| {
            let v = input.triangles[t as usize];
            (0..3).any(|m| v[m] == a && v[(m + 1) % 3] == b)
        };
        let p = |v: u32| coord(input.points[v as usize]);
        let in_plane = if flat {
            let q = [a, b, c, d].map(|v| input.points[v as usize]);
            let mut longest = 0.0f64;
            for i in 0..4 {
                for j in i + 1..4 {
                    longest = longest.max(norm(sub(q[i], q[j])));
                }
            }
            let volume = dot(cross(sub(q[1], q[0]), sub(q[2], q[0])), sub(q[3], q[0])).abs() / 6.0;
            volume <= longest.powi(3) * 2f64.powi(-30)
        } else {
            robust::orient3d(p(a), p(b), p(c), p(d)) == 0.0
        };
        if runs(t1) != runs(t2) && in_plane {
            let (x, y) = (find(&mut parent, t1), find(&mut parent, t2));
            parent[x as usize] = y;
        }
    }
    (0..input.triangles.len() as u32)
        .map(|t| find(&mut parent, t))
        .collect()
}

/// Maps every boundary face to the input triangle it lies on (with `patches` other than the
/// identity, to the patch all its corners and its centroid lie on) and compares areas per
/// patch.
fn coverage(mesh: &TetMesh, input: &Surface, patches: &[u32], r: &mut CheckReport) {
    let tol = RTOL * input.diagonal();
    let grid = TriangleGrid::new(input, tol);
    let corners = |t: [u32; 3]| t.map(|v| input.points[v as usize]);
    // Exact matches first: a face whose corners are an input triangle's.
    let index: HashMap<[u64; 3], u32> = input
        .points
        .iter()
        .enumerate()
        .map(|(i, &p)| (point_key(p), i as u32))
        .collect();
    let by_corners: HashMap<[u32; 3], u32> = input
        .triangles
        .iter()
        .enumerate()
        .map(|(k, &t)| (sorted3(t), k as u32))
        .collect();
    let mut covered = vec![Sum::default(); input.triangles.len()];
    let mut stray = Vec::new();
    for (fi, &f) in mesh.faces.iter().enumerate() {
        let p = f.map(|v| mesh.points[v as usize]);
        let area = triangle_area(p[0], p[1], p[2]);
        let exact = (|| {
            let v = p.map(|q| index.get(&point_key(q)).copied());
            let v = [v[0]?, v[1]?, v[2]?];
            by_corners.get(&sorted3(v)).copied()
        })();
        let centroid = [0, 1, 2].map(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0);
        let owner = exact.map(|ti| patches[ti as usize]).or_else(|| {
            grid.near(centroid)
                .iter()
                .map(|&ti| {
                    let t = corners(input.triangles[ti as usize]);
                    let d = p
                        .iter()
                        .map(|&q| distance_to_triangle(q, t))
                        .fold(0.0, f64::max);
                    (d, ti)
                })
                .filter(|&(d, _)| d <= tol)
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, ti)| patches[ti as usize])
        });
        // A face of a re-triangulated patch may straddle its input triangles: it belongs to
        // the patch when its centroid and every corner lie on triangles of that patch.
        let on_patch = |q: [f64; 3], patch: u32| {
            grid.near(q).iter().any(|&ti| {
                patches[ti as usize] == patch
                    && distance_to_triangle(q, corners(input.triangles[ti as usize])) <= tol
            })
        };
        let owner = owner.or_else(|| {
            grid.near(centroid)
                .iter()
                .map(|&ti| patches[ti as usize])
                .find(|&patch| on_patch(centroid, patch) && p.iter().all(|&q| on_patch(q, patch)))
        });
        match owner {
            Some(patch) => covered[patch as usize].add(area),
            None => stray.push(fi),
        }
    }
    if let Some(&fi) = stray.first() {
        r.fail(
            format!("{} faces off the input triangles", stray.len()),
            format!(
                "coverage: {} boundary faces lie on no input triangle, e.g. face {fi} {:?}",
                stray.len(),
                mesh.faces[fi].map(|v| mesh.points[v as usize])
            ),
        );
    }
    let mut wanted = vec![Sum::default(); input.triangles.len()];
    for (ti, &t) in input.triangles.iter().enumerate() {
        let [a, b, c] = corners(t);
        wanted[patches[ti] as usize].add(triangle_area(a, b, c));
    }
    let mut bad = 0;
    let mut worst: Option<(f64, usize, f64, f64)> = None;
    for ti in 0..input.triangles.len() {
        if patches[ti] as usize != ti {
            continue;
        }
        let want = wanted[ti].value();
        let got = covered[ti].value();
        let rel = (got - want).abs() / want;
        // NaN (a zero-area input triangle) counts as a mismatch.
        if rel.is_nan() || rel > RTOL {
            bad += 1;
            if worst.is_none_or(|w| rel > w.0) {
                worst = Some((rel, ti, got, want));
            }
        }
    }
    if let Some((rel, ti, got, want)) = worst {
        r.fail(
            format!("{bad} input triangles not covered"),
            format!(
                "coverage: on {bad} input triangles the boundary faces' area differs from the \
             triangle's; worst: input triangle {ti} {:?}, area {want:.6e}, covered {got:.6e} \
             (relative {rel:.1e})",
                input.triangles[ti]
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::super::surface::parse_off;
    use super::*;

    /// The unit cube in 6 tetrahedra around the diagonal 0-6 (Kuhn's triangulation), and
    /// its surface split along the same face diagonals.
    fn cube_mesh() -> (Surface, TetMesh) {
        let s = parse_off(
            "OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
             3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n\
             3 3 7 6\n3 3 6 2\n3 0 4 7\n3 0 7 3\n",
        )
        .unwrap();
        let mut tets = Vec::new();
        // The path 0 -> 1 -> 2 -> 6 and its five siblings (Kuhn triangulation).
        for path in [
            [0, 1, 2, 6],
            [0, 1, 5, 6],
            [0, 3, 2, 6],
            [0, 3, 7, 6],
            [0, 4, 5, 6],
            [0, 4, 7, 6],
        ] {
            let mut t: [u32; 4] = path;
            let c = t.map(|v| s.points[v as usize]);
            if dot(sub(c[1], c[0]), cross(sub(c[2], c[0]), sub(c[3], c[0]))) < 0.0 {
                t.swap(2, 3);
            }
            tets.push(t);
        }
        let mesh = TetMesh {
            points: s.points.clone(),
            tets,
            faces: s.triangles.clone(),
        };
        (s, mesh)
    }

    #[test]
    fn a_correct_cube_mesh_passes() {
        let (s, m) = cube_mesh();
        let r = check_mesh(&m, &s);
        assert!(r.failures.is_empty(), "{:?}", r.failures);
        assert_eq!(r.euler, 1);
        assert_eq!(m.volume(), 1.0);
        let q = quality(&m).unwrap();
        // Kuhn simplices: dihedral angles 45, 60 and 90 degrees; R/e = (√3/2)/1.
        assert!((q.min_dihedral - 45.0).abs() < 1e-9, "{q:?}");
        assert!((q.max_dihedral - 90.0).abs() < 1e-9, "{q:?}");
        assert!(
            (q.max_radius_edge - 3f64.sqrt() / 2.0).abs() < 1e-12,
            "{q:?}"
        );
        assert_eq!((q.slivers, q.radius_edge_over_2), (0, 0));
    }

    #[test]
    fn each_check_catches_its_defect() {
        let (s, m) = cube_mesh();
        let failures = |m: &TetMesh| check_mesh(m, &s).failures;
        // An inverted tetrahedron.
        let mut bad = m.clone();
        bad.tets[0].swap(0, 1);
        let f = failures(&bad);
        assert!(
            f[0].starts_with("orientation: 1 tetrahedra inverted and 0 flat"),
            "{f:?}"
        );
        // A missing tetrahedron: the boundary and the volume notice (a ball minus a
        // corner tetrahedron is still a ball, so χ does not).
        let mut bad = m.clone();
        bad.tets.pop();
        let f = failures(&bad).join("\n");
        for what in ["boundary:", "volume:"] {
            assert!(f.contains(what), "{what}: {f}");
        }
        // Two bodies in the input, one meshed: χ is 1, not (2 + 2) / 2.
        let mut two = s.clone();
        let n = two.points.len() as u32;
        two.points
            .extend(s.points.iter().map(|p| [p[0] + 5.0, p[1], p[2]]));
        two.triangles
            .extend(s.triangles.iter().map(|t| t.map(|v| v + n)));
        let f = check_mesh(&m, &two).failures.join("\n");
        assert!(
            f.contains("Euler: V - E + F - T = 1 for the tetrahedra, the input surface has χ = 4"),
            "{f}"
        );
        // A boundary face dropped from the .face file: one input triangle loses its area.
        let mut bad = m.clone();
        bad.faces.pop();
        let f = failures(&bad).join("\n");
        assert!(f.contains("coverage: on 1 input triangles"), "{f}");
        assert!(f.contains("missing from it"), "{f}");
        // A moved surface vertex.
        let mut bad = m.clone();
        bad.points[7][0] += 1e-3;
        let f = failures(&bad).join("\n");
        assert!(f.contains("vertices: 1 input vertices"), "{f}");
        assert!(f.contains("lie on no input triangle"), "{f}");
    }

    #[test]
    fn split_faces_are_mapped_to_their_input_triangle() {
        // The cube with a Steiner point in the middle of the bottom face (z = 0): the two
        // bottom triangles become four faces, and the tetrahedra on them become cones.
        let (s, mut m) = cube_mesh();
        m.points.push([0.5, 0.5, 0.0]);
        let c = 8;
        m.faces
            .retain(|f| f.iter().any(|&v| m.points[v as usize][2] != 0.0));
        for f in [[0, c, 1], [1, c, 2], [2, c, 3], [3, c, 0]] {
            m.faces.push(f);
        }
        // Tetrahedra: the cone of the new boundary from the centre of the cube.
        m.tets = vec![];
        m.points.push([0.5, 0.5, 0.5]);
        let centre = 9;
        for f in m.faces.clone() {
            let mut t = [f[0], f[1], f[2], centre];
            let p = t.map(|v| m.points[v as usize]);
            if dot(sub(p[1], p[0]), cross(sub(p[2], p[0]), sub(p[3], p[0]))) < 0.0 {
                t.swap(0, 1);
            }
            m.tets.push(t);
        }
        let r = check_mesh(&m, &s);
        assert!(r.failures.is_empty(), "{:?}", r.failures);
    }

    #[test]
    fn merged_coverage_is_per_planar_patch() {
        // The input's bottom square split along the other diagonal (1-3) than the mesh's
        // faces (0-2): not a union of faces per triangle, but per plane it is.
        let (mut s, m) = cube_mesh();
        s.triangles[0] = [0, 3, 1];
        s.triangles[1] = [1, 3, 2];
        let f = check_mesh_with(&m, &s, Patches::Triangles)
            .failures
            .join("\n");
        assert!(f.contains("coverage:"), "{f}");
        let r = check_mesh_with(&m, &s, Patches::Planar);
        assert!(r.failures.is_empty(), "{:?}", r.failures);
        // Planar patches: the six sides, each of two triangles.
        let patches = planar_patches(&s, false);
        let mut roots = patches.clone();
        roots.sort_unstable();
        roots.dedup();
        assert_eq!(roots.len(), 6);
        // A face off the bottom plane is still caught.
        let mut bad = m.clone();
        bad.points[1][2] += 1e-3;
        let f = check_mesh_with(&bad, &s, Patches::Planar)
            .failures
            .join("\n");
        assert!(f.contains("lie on no input triangle"), "{f}");
    }

    #[test]
    fn flat_coverage_joins_neighbours_in_one_plane_to_rounding() {
        // As above, with corner 3 of the bottom a hair (10^-13) above the other three: the
        // two bottom triangles are one patch to rounding, not exactly.
        let (mut s, mut m) = cube_mesh();
        s.triangles[0] = [0, 3, 1];
        s.triangles[1] = [1, 3, 2];
        s.points[3][2] += 1e-13;
        m.points[3][2] += 1e-13;
        let f = check_mesh_with(&m, &s, Patches::Planar).failures.join("\n");
        assert!(f.contains("coverage:"), "{f}");
        let r = check_mesh_with(&m, &s, Patches::Flat);
        assert!(r.failures.is_empty(), "{:?}", r.failures);
        // A millimetre off the plane is a different face.
        s.points[3][2] += 1e-3;
        m.points[3][2] += 1e-3;
        let f = check_mesh_with(&m, &s, Patches::Flat).failures.join("\n");
        assert!(f.contains("coverage:"), "{f}");
    }

    #[test]
    fn closest_points_and_angles() {
        let (a, b, c) = ([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let q = closest_on_triangle([0.2, 0.2, 5.0], a, b, c);
        assert!(norm(sub(q, [0.2, 0.2, 0.0])) < 1e-15, "{q:?}");
        assert_eq!(closest_on_triangle([-1.0, -1.0, 0.0], a, b, c), a);
        assert_eq!(closest_on_triangle([2.0, -1.0, 0.0], a, b, c), b);
        assert_eq!(
            closest_on_triangle([0.5, -1.0, 1.0], a, b, c),
            [0.5, 0.0, 0.0]
        );
        assert_eq!(
            closest_on_triangle([1.0, 1.0, 0.0], a, b, c),
            [0.5, 0.5, 0.0]
        );
        assert_eq!(
            closest_on_triangle([-1.0, 0.5, 0.0], a, b, c),
            [0.0, 0.5, 0.0]
        );
        // The regular tetrahedron: all dihedral angles acos(1/3), R/e = √6/4.
        let s = 1.0 / 2f64.sqrt();
        let p = [
            [1.0, 0.0, -s],
            [-1.0, 0.0, -s],
            [0.0, 1.0, s],
            [0.0, -1.0, s],
        ];
        let d = dihedral(p[0], p[1], p[2], p[3]);
        assert!(
            (d - (1.0f64 / 3.0).acos().to_degrees()).abs() < 1e-12,
            "{d}"
        );
        let r = circumradius(p[0], p[1], p[2], p[3]) / 2.0;
        assert!((r - 6f64.sqrt() / 4.0).abs() < 1e-12, "{r}");
        assert_eq!(circumradius(a, b, c, [1.0, 1.0, 0.0]), f64::INFINITY);
    }

    #[test]
    fn reads_both_numberings() {
        let dir = std::env::temp_dir().join(format!("xtask-tetmesh-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // TetGen from an .off input: 0-based, with padding spaces and markers.
        std::fs::write(
            dir.join("a.node"),
            "4  3  0  0\n   0    0 0 0\n   1    1 0 0\n   2  0 1 0\n   3  0 0 1\n",
        )
        .unwrap();
        std::fs::write(dir.join("a.ele"), "1  4  0\n    0    0 1 2 3\n").unwrap();
        std::fs::write(dir.join("a.face"), "1  1\n    0   0 2 1    1\n").unwrap();
        let m = read_tet_mesh(&dir.join("a.ele")).unwrap();
        assert_eq!(m.tets, [[0, 1, 2, 3]]);
        assert_eq!(m.faces, [[0, 2, 1]]);
        assert_eq!(m.orientation(), (0, 0, None));
        // delmesh: 1-based, with point markers and a region attribute.
        std::fs::write(
            dir.join("b.node"),
            "4 3 0 1\n1 0 0 0 0\n2 1 0 0 0\n3 0 1 0 0\n4 0 0 1 0\n",
        )
        .unwrap();
        std::fs::write(dir.join("b.ele"), "1 4 1\n1 1 2 4 3 0\n").unwrap();
        let m = read_tet_mesh(&dir.join("b.ele")).unwrap();
        assert_eq!(m.tets, [[0, 1, 3, 2]]);
        assert!(m.faces.is_empty());
        assert_eq!(m.orientation(), (1, 0, Some(0)));
        std::fs::write(dir.join("b.ele"), "1 4 1\n1 1 2 5 3 0\n").unwrap();
        let err = read_tet_mesh(&dir.join("b.ele")).unwrap_err().to_string();
        assert!(err.contains("vertex 5 out of range"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
