//! OpenFOAM meshes (a `constant/polyMesh` directory, ASCII), written: the input of OpenFOAM's
//! solvers (`checkMesh` reads them).
//!
//! A polyMesh is faces, not cells: `points`, `faces` (each a list of points, its normal by the
//! right-hand rule), `owner` and `neighbour` (the cell each face's normal points out of, and for
//! an internal face the cell it points into), and `boundary` (the patches: runs of boundary
//! faces). OpenFOAM wants the internal faces first, ordered by owner and then neighbour, the
//! owner the lower-numbered cell; then each patch's faces together.
//!
//! 3D ([`write_foam`]): one cell per tetrahedron (positively oriented, as VTK's); the
//! tetrahedra's faces are paired by their points. A boundary face takes the marker of the
//! boundary triangle with the same points, and the boundary is one patch per marker, in
//! increasing order, named as by [`TetMeshOut::marker_names`] (characters an OpenFOAM word
//! cannot hold, such as spaces, replaced by `_`) or `marker_<m>`, of type
//! `patch` (the case's boundary conditions say what each is); boundary faces without a
//! triangle go to a last patch, `defaultFaces`. A boundary triangle between two tetrahedra
//! (a wall between regions) is an internal face: OpenFOAM's boundary is only the domain's;
//! such marked internal faces are kept as face zones, one per marker, named as the patches.
//! Regions, when the tetrahedra have more than one, are cell zones `region_<r>`.
//!
//! 2D ([`write_foam_2d`]): OpenFOAM meshes are 3D; a 2D case is one layer of cells between two
//! planes whose patch is of type `empty`. Each triangle becomes a prism from z = 0 to z = the
//! mean edge length (cells about as deep as wide); the boundary edges become the quadrilateral
//! faces of patches `marker_<m>` (`defaultFaces` for those without a marker; a marked edge
//! between two triangles, such as a wake line, is an internal face in the face zone
//! `marker_<m>`), and the two planes the
//! patch `frontAndBack`; regions are cell zones as in 3D.

use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::atomic::{settle, stage, Staged};
use crate::tetmesh::TetMeshOut;
use crate::text::{format_f64, write_f64, write_u64};
use crate::triangle::TriangleMeshOut;
use crate::IoError;

/// The files a polyMesh directory holds (`cellZones` only with two or more regions,
/// `faceZones` only with marked internal faces).
pub const POLYMESH_FILES: [&str; 7] = [
    "points",
    "faces",
    "owner",
    "neighbour",
    "boundary",
    "cellZones",
    "faceZones",
];

/// Whether `path` names an OpenFOAM polyMesh directory (its last component is `polyMesh`): the
/// output the mesh writers choose [`write_foam`] or [`write_foam_2d`] for.
pub fn is_polymesh(path: &Path) -> bool {
    path.file_name().is_some_and(|n| n == "polyMesh")
}

/// A face: up to four points (`n` of them), normal by the right-hand rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Face {
    v: [u32; 4],
    n: u8,
}

impl Face {
    fn tri(v: [u32; 3]) -> Face {
        Face {
            v: [v[0], v[1], v[2], 0],
            n: 3,
        }
    }

    fn quad(v: [u32; 4]) -> Face {
        Face { v, n: 4 }
    }

    fn points(&self) -> &[u32] {
        &self.v[..usize::from(self.n)]
    }
}

/// A boundary patch: a name and an OpenFOAM type.
struct Patch {
    name: String,
    kind: &'static str,
}

/// A mesh as OpenFOAM stores it, faces in file order.
struct PolyMesh {
    points: Vec<[f64; 3]>,
    n_cells: usize,
    faces: Vec<Face>,
    owner: Vec<u32>,
    /// One per internal face (the first `neighbour.len()` faces).
    neighbour: Vec<u32>,
    /// Patches with their number of faces, in order after the internal faces.
    patches: Vec<(Patch, usize)>,
    /// Cell zones: a name and the cells.
    zones: Vec<(String, Vec<u32>)>,
    /// Face zones: a name and the (internal) faces.
    face_zones: Vec<(String, Vec<u32>)>,
}

/// The faces of the cells, each packed as `key << 32 | slot`: `key` the face's points, sorted
/// (the same for the two sides of an internal face), `slot` the cell times `per_cell` plus the
/// face's number in the cell. Sorting the packed faces pairs the sides of each internal face,
/// the lower cell's first.
struct FaceSet {
    packed: Vec<u128>,
    per_cell: u32,
}

/// Internal faces as their key and the slots of their two sides (the owner's first), and
/// boundary faces as key and slot.
type Paired = (Vec<(u128, u32, u32)>, Vec<(u128, u32)>);

impl FaceSet {
    /// Room for `n_cells` cells of `per_cell` faces; `None` if the slots do not fit 32 bits.
    fn new(n_cells: usize, per_cell: u32) -> Option<FaceSet> {
        (n_cells as u64 * u64::from(per_cell) <= u64::from(u32::MAX)).then(|| FaceSet {
            packed: Vec::with_capacity(n_cells * per_cell as usize),
            per_cell,
        })
    }

    fn push(&mut self, key: u128, cell: usize, face: u32) {
        self.packed
            .push(key << 32 | u128::from(cell as u32 * self.per_cell + face));
    }

    /// Pairs the two sides of each internal face; a face seen once is on the boundary.
    fn pair(mut self, file: &Path) -> Result<Paired, IoError> {
        self.packed.sort_unstable();
        let (mut internal, mut boundary) = (Vec::new(), Vec::new());
        let cell = |x: u128| x as u32 / self.per_cell;
        for group in self.packed.chunk_by(|a, b| a >> 32 == b >> 32) {
            match *group {
                [one] => boundary.push((one >> 32, one as u32)),
                [a, b] if cell(a) != cell(b) => internal.push((a >> 32, a as u32, b as u32)),
                _ => {
                    let cells: Vec<String> = group.iter().map(|&x| cell(x).to_string()).collect();
                    return Err(IoError::invalid(
                        file,
                        format!(
                            "cells {} share a face: at most two distinct cells may",
                            cells.join(", ")
                        ),
                    ));
                }
            }
        }
        Ok((internal, boundary))
    }
}

/// Faces, owners, neighbours, each patch's face count and the internal faces' keys (see
/// [`in_order`]).
type FacesInOrder = (Vec<Face>, Vec<u32>, Vec<u32>, Vec<usize>, Vec<u128>);

/// The polyMesh order: internal faces by owner and neighbour, then boundary faces by patch
/// (`patch_of` their key) and owner; `face` gives a slot's face. Faces, owners, neighbours,
/// each patch's face count, and the internal faces' keys in order.
fn in_order(
    (internal, boundary): Paired,
    per_cell: u32,
    n_patches: usize,
    patch_of: impl Fn(u128) -> usize,
    face: impl Fn(u32) -> Face,
) -> FacesInOrder {
    // Sorted by key: the pairs are not in cell order yet.
    let mut internal: Vec<(u32, u32, u32, u128)> = internal
        .into_iter()
        .map(|(k, a, b)| (a / per_cell, b / per_cell, a, k))
        .collect();
    internal.sort_unstable();
    let mut boundary: Vec<(usize, u32)> = boundary
        .into_iter()
        .map(|(k, slot)| (patch_of(k), slot))
        .collect();
    boundary.sort_unstable();
    let mut counts = vec![0; n_patches];
    let mut faces = Vec::with_capacity(internal.len() + boundary.len());
    let mut owner = Vec::with_capacity(faces.capacity());
    let mut neighbour = Vec::with_capacity(internal.len());
    let mut keys = Vec::with_capacity(internal.len());
    for (a, b, slot, k) in internal {
        faces.push(face(slot));
        owner.push(a);
        neighbour.push(b);
        keys.push(k);
    }
    for (p, slot) in boundary {
        counts[p] += 1;
        faces.push(face(slot));
        owner.push(slot / per_cell);
    }
    (faces, owner, neighbour, counts, keys)
}

/// Patches, faces, owners, neighbours, each patch's face count and the face zones (see
/// [`order_faces`]).
type Ordered = (
    Vec<Patch>,
    Vec<Face>,
    Vec<u32>,
    Vec<u32>,
    Vec<usize>,
    Vec<(String, Vec<u32>)>,
);

/// The faces of `set` in polyMesh order with their patches: one per marker of the boundary
/// faces (`marker` by key, in increasing order, named by `name`), then `defaultFaces` if some
/// boundary face has no marker. `face` gives a slot's face. Patches, faces, owners, neighbours,
/// each patch's face count, and a face zone per marker of internal faces (a wall between
/// regions, a wake), named as the patches are.
fn order_faces(
    dir: &Path,
    set: FaceSet,
    marker: &HashMap<u128, i32>,
    name: impl Fn(i32) -> String,
    face: impl Fn(u32) -> Face,
) -> Result<Ordered, IoError> {
    let per_cell = set.per_cell;
    let paired = set.pair(dir)?;
    let mut markers: Vec<i32> = paired
        .1
        .iter()
        .filter_map(|(k, _)| marker.get(k).copied())
        .collect();
    markers.sort_unstable();
    markers.dedup();
    let unmarked = paired.1.iter().any(|(k, _)| !marker.contains_key(k));
    let patches = patches(&markers, &name, unmarked);
    let patch_of = |k: u128| match marker.get(&k) {
        Some(m) => markers.binary_search(m).expect("a marker of the list"),
        None => markers.len(),
    };
    let (faces, owner, neighbour, counts, keys) =
        in_order(paired, per_cell, patches.len(), patch_of, face);
    let mut zoned: Vec<(i32, u32)> = keys
        .iter()
        .enumerate()
        .filter_map(|(f, k)| marker.get(k).map(|&m| (m, f as u32)))
        .collect();
    zoned.sort_unstable();
    let mut inner: Vec<i32> = zoned.iter().map(|z| z.0).collect();
    inner.dedup();
    // (Named as patches are, without `defaultFaces`: an unmarked internal face is no zone's.)
    let face_zones = self::patches(&inner, &name, false)
        .into_iter()
        .zip(zoned.chunk_by(|a, b| a.0 == b.0))
        .map(|(p, run)| (p.name, run.iter().map(|z| z.1).collect()))
        .collect();
    Ok((patches, faces, owner, neighbour, counts, face_zones))
}

/// The key of a face through points `v`: sorted, 32 bits each.
fn key(v: &[u32]) -> u128 {
    let mut s = [0u32; 3];
    s[..v.len()].copy_from_slice(v);
    s[..v.len()].sort_unstable();
    s[..v.len()]
        .iter()
        .fold(0u128, |k, &x| k << 32 | u128::from(x))
}

/// The error for a mesh too large for 32-bit face slots.
fn too_large(file: &Path, cells: usize) -> IoError {
    IoError::invalid(
        file,
        format!("{cells} cells are too many for an OpenFOAM mesh here"),
    )
}

/// `name` as an OpenFOAM patch or zone name (a `word`: no white space, quotes, slashes,
/// semicolons, braces or parentheses), each character it cannot hold replaced by `_`: STL
/// solid names such as gmsh's "Created by Gmsh" were refused, after all the meshing; one
/// that starts like a number gets `patch_` in front. `None` for an empty name (the patch is
/// then `marker_<m>`).
fn as_word(name: &str) -> Option<String> {
    (!name.is_empty()).then(|| {
        let word: String = name
            .chars()
            .map(|c| {
                if c.is_whitespace() || "\"'/\\;{}()".contains(c) {
                    '_'
                } else {
                    c
                }
            })
            .collect();
        // A name that starts like a number would be read back as one ("123", a gmsh
        // physical group's number used as its name).
        if word.starts_with(|c: char| c.is_ascii_digit() || "+-.".contains(c)) {
            format!("patch_{word}")
        } else {
            word
        }
    })
}

/// The boundary patches of `markers` (sorted, distinct), named as words (a name an earlier
/// patch has gets `_<m>`), then `defaultFaces` if asked.
fn patches(markers: &[i32], name: impl Fn(i32) -> String, default: bool) -> Vec<Patch> {
    let mut out: Vec<Patch> = Vec::with_capacity(markers.len() + 1);
    let names = markers
        .iter()
        .map(|&m| (m, name(m)))
        .chain(default.then(|| (0, "defaultFaces".to_string())));
    for (m, given) in names {
        let mut name = as_word(&given).unwrap_or_else(|| format!("marker_{m}"));
        // (Two markers whose names differ only by the characters replaced.)
        if out.iter().any(|p| p.name == name) {
            name = format!("{name}_{m}");
        }
        out.push(Patch {
            name,
            kind: "patch",
        });
    }
    out
}

/// Cell zones `region_<r>` of the cells' regions, if there are two or more.
fn zones(regions: Option<&[f64]>) -> Vec<(String, Vec<u32>)> {
    let Some(regions) = regions else {
        return Vec::new();
    };
    let mut values: Vec<f64> = regions.to_vec();
    values.sort_by(f64::total_cmp);
    values.dedup_by(|a, b| a.total_cmp(b).is_eq());
    if values.len() < 2 {
        return Vec::new();
    }
    let mut zones: Vec<(String, Vec<u32>)> = values
        .iter()
        .map(|&r| (format!("region_{}", format_f64(r)), Vec::new()))
        .collect();
    for (k, r) in regions.iter().enumerate() {
        let z = values
            .binary_search_by(|x| x.total_cmp(r))
            .expect("a region of the list");
        zones[z].1.push(k as u32);
    }
    zones
}

/// Writes a tetrahedral mesh as an OpenFOAM polyMesh in the directory `dir` (made if missing;
/// conventionally `case/constant/polyMesh`): `points`, `faces`, `owner`, `neighbour`,
/// `boundary`, and `cellZones` when the tetrahedra have two or more regions. Each file is
/// written atomically; zone files of an earlier mesh in `dir` are removed. Returns the files
/// written.
///
/// # Errors
/// Inconsistent arrays, a face shared by three tetrahedra, a marker name OpenFOAM cannot take,
/// or the file system's.
pub fn write_foam(dir: &Path, mesh: &TetMeshOut<'_>) -> Result<Vec<PathBuf>, IoError> {
    mesh.check(dir)?;
    // Facet `i` (opposite point `i`) of a positive tetrahedron, its normal outwards.
    const OUTWARD: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
    let face = |slot: u32| {
        let t = mesh.tets[(slot / 4) as usize];
        Face::tri(OUTWARD[(slot % 4) as usize].map(|i| t[i]))
    };
    let mut set =
        FaceSet::new(mesh.tets.len(), 4).ok_or_else(|| too_large(dir, mesh.tets.len()))?;
    for (cell, t) in mesh.tets.iter().enumerate() {
        for (i, o) in OUTWARD.iter().enumerate() {
            set.push(key(&o.map(|k| t[k])), cell, i as u32);
        }
    }
    let marker: HashMap<u128, i32> = mesh
        .faces
        .iter()
        .zip(mesh.face_markers)
        .map(|(f, &m)| (key(f), m))
        .collect();
    let (patches, faces, owner, neighbour, counts, face_zones) =
        order_faces(dir, set, &marker, |m| mesh.marker_name(m), face)?;
    write_poly_mesh(
        dir,
        &PolyMesh {
            points: mesh.coords.to_vec(),
            n_cells: mesh.tets.len(),
            faces,
            owner,
            neighbour,
            patches: patches.into_iter().zip(counts).collect(),
            zones: zones(mesh.regions),
            face_zones,
        },
    )
}

/// Writes a 2D triangle mesh as an OpenFOAM polyMesh of one layer of prisms in `dir` (see the
/// module doc): patches `marker_<m>` for the boundary edges' markers, `defaultFaces` for
/// boundary edges without one, `frontAndBack` (type `empty`) for the two planes; cell zones
/// `region_<r>` when the triangles have two or more regions. Atomic per file. Returns the
/// files written.
///
/// # Errors
/// Inconsistent arrays, an edge shared by three triangles, or the file system's.
pub fn write_foam_2d(dir: &Path, mesh: &TriangleMeshOut<'_>) -> Result<Vec<PathBuf>, IoError> {
    mesh.check(dir)?;
    let np = mesh.coords.len() / 2;
    if 2 * np as u64 > u64::from(u32::MAX) {
        return Err(IoError::invalid(
            dir,
            format!("{np} points, twice over for the two planes, do not fit 32-bit indices"),
        ));
    }
    let triangles: Vec<[u32; 3]> = mesh
        .triangles
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let xy = |v: u32| [mesh.coords[2 * v as usize], mesh.coords[2 * v as usize + 1]];
    let (mut length, mut edges) = (0.0, 0usize);
    for t in &triangles {
        for k in 0..3 {
            let (a, b) = (xy(t[k]), xy(t[(k + 1) % 3]));
            length += (a[0] - b[0]).hypot(a[1] - b[1]);
            edges += 1;
        }
    }
    let depth = if edges > 0 && length > 0.0 && length.is_finite() {
        length / edges as f64
    } else {
        1.0
    };
    let top = |v: u32| v + np as u32;
    // Side faces of the prisms: edge (a, b) of a counter-clockwise triangle has the cell on
    // its left, so (a, b, b', a') turns outwards.
    let face = |slot: u32| {
        let t = triangles[(slot / 3) as usize];
        let k = (slot % 3) as usize;
        let (a, b) = (t[k], t[(k + 1) % 3]);
        Face::quad([a, b, top(b), top(a)])
    };
    let mut set =
        FaceSet::new(triangles.len(), 3).ok_or_else(|| too_large(dir, triangles.len()))?;
    for (cell, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            set.push(key(&[t[k], t[(k + 1) % 3]]), cell, k as u32);
        }
    }
    let marker: HashMap<u128, i32> = mesh
        .edges
        .iter()
        .zip(mesh.edge_markers)
        .map(|(e, &m)| (key(e), m))
        .collect();
    let (mut patches, mut faces, mut owner, neighbour, mut counts, face_zones) =
        order_faces(dir, set, &marker, |m| format!("marker_{m}"), face)?;
    // The two planes: the bottom turned down, the top up.
    for (cell, t) in triangles.iter().enumerate() {
        faces.push(Face::tri([t[0], t[2], t[1]]));
        owner.push(cell as u32);
        faces.push(Face::tri([top(t[0]), top(t[1]), top(t[2])]));
        owner.push(cell as u32);
    }
    patches.push(Patch {
        name: "frontAndBack".into(),
        kind: "empty",
    });
    counts.push(2 * triangles.len());
    let points = (0..2 * np)
        .map(|i| {
            let p = xy((i % np) as u32);
            [p[0], p[1], if i < np { 0.0 } else { depth }]
        })
        .collect();
    write_poly_mesh(
        dir,
        &PolyMesh {
            points,
            n_cells: triangles.len(),
            faces,
            owner,
            neighbour,
            patches: patches.into_iter().zip(counts).collect(),
            zones: zones(mesh.cell_attributes),
            face_zones,
        },
    )
}

/// The `FoamFile` header of a polyMesh file.
fn header(w: &mut dyn Write, class: &str, object: &str, note: Option<&str>) -> std::io::Result<()> {
    writeln!(
        w,
        "/*--------------------------------*- C++ -*----------------------------------*\\\n\
         | Written by delmesh                                                          |\n\
         \\*---------------------------------------------------------------------------*/"
    )?;
    writeln!(
        w,
        "FoamFile\n{{\n    version     2.0;\n    format      ascii;"
    )?;
    writeln!(w, "    class       {class};")?;
    if let Some(note) = note {
        writeln!(w, "    note        \"{note}\";")?;
    }
    writeln!(
        w,
        "    location    \"constant/polyMesh\";\n    object      {object};\n}}\n"
    )
}

/// A file's contents, written to a writer.
type Body<'a> = Box<dyn Fn(&mut dyn Write) -> std::io::Result<()> + Send + Sync + 'a>;

/// Writes the files of `mesh` into `dir`, each atomically, side by side on threads (the files
/// are independent, and formatting numbers is the cost).
fn write_poly_mesh(dir: &Path, mesh: &PolyMesh) -> Result<Vec<PathBuf>, IoError> {
    if dir.exists() && !dir.is_dir() {
        return Err(IoError::invalid(
            dir,
            "an OpenFOAM mesh is written into a folder, and this is a file",
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| IoError::io(dir, e))?;
    let note = format!(
        "nPoints:{} nCells:{} nFaces:{} nInternalFaces:{}",
        mesh.points.len(),
        mesh.n_cells,
        mesh.faces.len(),
        mesh.neighbour.len()
    );
    let mut files: Vec<(&str, Body)> = vec![
        (
            "points",
            Box::new(|w: &mut dyn Write| {
                header(w, "vectorField", "points", None)?;
                writeln!(w, "{}\n(", mesh.points.len())?;
                for p in &mesh.points {
                    w.write_all(b"(")?;
                    for (k, &x) in p.iter().enumerate() {
                        if k > 0 {
                            w.write_all(b" ")?;
                        }
                        write_f64(w, x)?;
                    }
                    w.write_all(b")\n")?;
                }
                writeln!(w, ")")
            }),
        ),
        (
            "faces",
            Box::new(|w: &mut dyn Write| {
                header(w, "faceList", "faces", None)?;
                writeln!(w, "{}\n(", mesh.faces.len())?;
                for f in &mesh.faces {
                    let v = f.points();
                    write!(w, "{}(", v.len())?;
                    for (k, &x) in v.iter().enumerate() {
                        if k > 0 {
                            w.write_all(b" ")?;
                        }
                        write_u64(w, u64::from(x))?;
                    }
                    w.write_all(b")\n")?;
                }
                writeln!(w, ")")
            }),
        ),
        ("owner", label_list(&note, "owner", &mesh.owner)),
        ("neighbour", label_list(&note, "neighbour", &mesh.neighbour)),
        (
            "boundary",
            Box::new(|w: &mut dyn Write| {
                header(w, "polyBoundaryMesh", "boundary", None)?;
                writeln!(w, "{}\n(", mesh.patches.len())?;
                let mut start = mesh.neighbour.len();
                for (patch, n) in &mesh.patches {
                    writeln!(
                        w,
                        "    {}\n    {{\n        type            {};\n        nFaces          {n};\n        startFace       {start};\n    }}",
                        patch.name, patch.kind
                    )?;
                    start += n;
                }
                writeln!(w, ")")
            }),
        ),
    ];
    if !mesh.zones.is_empty() {
        files.push(("cellZones", zone_list("cell", &mesh.zones)));
    }
    if !mesh.face_zones.is_empty() {
        files.push(("faceZones", zone_list("face", &mesh.face_zones)));
    }
    let paths: Vec<PathBuf> = files.iter().map(|(name, _)| dir.join(name)).collect();
    // Written side by side (their syncs overlap), renamed together once all are on disk, with
    // the stale zones removed at the same time.
    let write =
        |path: &Path, body: &Body| stage(path, |w| body(w).map_err(|e| IoError::io(path, e)));
    let done: Vec<Result<Staged, IoError>> = std::thread::scope(|scope| {
        let threads: Vec<_> = paths[1..]
            .iter()
            .zip(&files[1..])
            .map(|(path, (_, body))| scope.spawn(move || write(path, body)))
            .collect();
        let first = write(&paths[0], &files[0].1);
        std::iter::once(first)
            .chain(threads.into_iter().map(|t| match t.join() {
                Ok(done) => done,
                Err(panic) => std::panic::resume_unwind(panic),
            }))
            .collect()
    });
    let mut staged = done.into_iter().collect::<Result<Vec<_>, _>>()?;
    // Zones number cells, faces and points: a previous mesh's in the directory would name
    // this one's wrongly, and every solver reads them. (OpenFOAM's own mesh writers remove
    // them too.)
    for stale in ["cellZones", "faceZones", "pointZones"] {
        let path = dir.join(stale);
        if !paths.contains(&path) && path.is_file() {
            staged.push(Staged::removal(path));
        }
    }
    settle(staged)?;
    Ok(paths)
}

/// The body of the `cellZones` or `faceZones` file (`kind` "cell" or "face"): each zone's
/// name and labels; face zones also have a flip map, all 0 (the faces as they are oriented,
/// owner to neighbour).
fn zone_list<'a>(kind: &'static str, zones: &'a [(String, Vec<u32>)]) -> Body<'a> {
    Box::new(move |w: &mut dyn Write| {
        header(w, "regIOobject", &format!("{kind}Zones"), None)?;
        writeln!(w, "{}\n(", zones.len())?;
        for (name, labels) in zones {
            writeln!(
                w,
                "{name}\n{{\n    type {kind}Zone;\n{kind}Labels      List<label> {}\n(",
                labels.len()
            )?;
            for &l in labels {
                write_u64(w, u64::from(l))?;
                w.write_all(b"\n")?;
            }
            if kind == "face" {
                writeln!(w, ")\n;\nflipMap         List<bool> {}\n(", labels.len())?;
                for _ in labels {
                    w.write_all(b"0\n")?;
                }
            }
            writeln!(w, ")\n;\n}}")?;
        }
        writeln!(w, ")")
    })
}

/// The body of the `owner` or `neighbour` file.
fn label_list<'a>(note: &'a str, object: &'static str, list: &'a [u32]) -> Body<'a> {
    Box::new(move |w: &mut dyn Write| {
        header(w, "labelList", object, Some(note))?;
        writeln!(w, "{}\n(", list.len())?;
        for &x in list {
            write_u64(w, u64::from(x))?;
            w.write_all(b"\n")?;
        }
        writeln!(w, ")")
    })
}
