//! Wavefront `.obj` surfaces (read only): vertices and polygonal faces, with groups as markers.
//!
//! OBJ is the common denominator of graphics and many CAD and scanning tools, so it is a
//! frequent way to get a surface out of a modeller. Only geometry is read:
//! - `v x y z [w | r g b]`: a vertex (values after `z` are ignored);
//! - `f a b c ...`: a polygon of at least 3 corners, each `v`, `v/vt`, `v//vn` or `v/vt/vn`
//!   (only `v` is used). Indices are 1-based; a negative index counts back from the last vertex
//!   defined so far (`-1` is the latest). Positive indices may refer to vertices defined later
//!   in the file (they are checked at the end).
//! - markers: faces get the marker of the group (`g name...`, the whole rest of the line is the
//!   name) they are in: the k-th distinct group name, in order of first appearance, is marker
//!   k, and faces before any `g` get marker 0. A file without any `g` statement uses its
//!   materials (`usemtl name`) the same way, since many exporters write one material per part.
//!   The names become the marker names.
//! - everything else (`vt`, `vn`, `vp`, `l`, `p`, `o`, `s`, `mtllib`, curves...) is ignored, and
//!   so are `#` comments. Lines continued with a backslash are not supported.

use std::collections::HashMap;
use std::path::Path;

use crate::surface::{check_polygon_size, SurfaceFacet, SurfaceFile};
use crate::text::{data_lines, parse_point3, point_ref, read_text, shorten};
use crate::IoError;

/// Reads an `.obj` file.
pub fn read_obj(path: &Path) -> Result<SurfaceFile, IoError> {
    let text = read_text(path)?;
    parse_obj(&text, path)
}

/// Numbers the distinct names of `g` or `usemtl` statements from 1.
#[derive(Default)]
struct Names {
    ids: HashMap<String, i32>,
    list: Vec<(i32, String)>,
    current: i32,
}

impl Names {
    fn set(&mut self, name: String) {
        let next = self.list.len() as i32 + 1;
        let id = *self.ids.entry(name.clone()).or_insert(next);
        if id == next {
            self.list.push((id, name));
        }
        self.current = id;
    }
}

/// Parses the text of an `.obj` file; `file` is only used in error messages.
pub fn parse_obj(text: &str, file: &Path) -> Result<SurfaceFile, IoError> {
    let err = |line: usize, message: String| IoError::parse(file, line, message);
    let mut points = Vec::new();
    let mut facets = Vec::new();
    // Per face: (group, material); resolved to markers at the end.
    let mut tags: Vec<(i32, i32)> = Vec::new();
    let mut groups = Names::default();
    let mut materials = Names::default();
    for (line, toks) in continued(data_lines(text)) {
        match toks[0] {
            "v" => {
                if toks.len() < 4 {
                    return Err(err(
                        line,
                        format!("expected 'v x y z', found {} fields", toks.len()),
                    ));
                }
                points.push(parse_point3(&toks[1..], file, line)?);
            }
            "f" => {
                check_polygon_size(toks.len() - 1, "face", file, line)?;
                let mut polygon = Vec::with_capacity(toks.len() - 1);
                for t in &toks[1..] {
                    let v = t.split('/').next().unwrap_or("");
                    let i: i64 = v.parse().map_err(|_| {
                        err(line, format!("expected a vertex index in '{}'", shorten(t)))
                    })?;
                    // Resolve relative indices now, against the vertices defined so far.
                    let absolute = match i {
                        0 => return Err(err(line, "vertex index 0 (indices start at 1)".into())),
                        i if i < 0 => points.len() as i64 + 1 + i,
                        i => i,
                    };
                    if absolute < 1 {
                        return Err(err(
                            line,
                            format!(
                                "relative vertex index {i} goes before the first vertex \
                                 ({} defined so far)",
                                points.len()
                            ),
                        ));
                    }
                    polygon.push(absolute);
                }
                // 1-based indices, checked once all vertices are known.
                facets.push((line, polygon));
                tags.push((groups.current, materials.current));
            }
            "g" => groups.set(toks[1..].join(" ")),
            "usemtl" => materials.set(toks[1..].join(" ")),
            _ => {}
        }
    }
    let by_material = groups.list.is_empty();
    let np = points.len();
    let facets = facets
        .into_iter()
        .zip(tags)
        .map(|((line, polygon), (g, m))| {
            Ok(SurfaceFacet {
                polygons: vec![polygon
                    .into_iter()
                    .map(|v| point_ref(v, 1, np, file, line))
                    .collect::<Result<_, IoError>>()?],
                holes: Vec::new(),
                marker: if by_material { m } else { g },
                line,
            })
        })
        .collect::<Result<Vec<_>, IoError>>()?;
    Ok(SurfaceFile {
        points,
        facets,
        marker_names: if by_material {
            materials.list
        } else {
            groups.list
        },
        first_index: 1,
        ..SurfaceFile::default()
    })
}

/// Joins a line ending in a backslash with the next (the OBJ format's line continuation),
/// numbered as its first line. A lone backslash on the last line is no line at all.
fn continued<'t>(
    lines: impl Iterator<Item = (usize, Vec<&'t str>)>,
) -> impl Iterator<Item = (usize, Vec<&'t str>)> {
    let mut pending: Option<(usize, Vec<&'t str>)> = None;
    let mut lines = lines.fuse();
    std::iter::from_fn(move || loop {
        let Some((line, toks)) = lines.next() else {
            return pending.take().filter(|(_, toks)| !toks.is_empty());
        };
        let (line, mut toks) = match pending.take() {
            Some((first, mut head)) => {
                head.extend(toks);
                (first, head)
            }
            None => (line, toks),
        };
        match toks.last().and_then(|t| t.strip_suffix('\\')) {
            Some(rest) => {
                toks.pop();
                if !rest.is_empty() {
                    toks.push(rest);
                }
                pending = Some((line, toks));
            }
            None => return Some((line, toks)),
        }
    })
}
