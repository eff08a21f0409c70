//! SVG pictures of 2D meshes: for 2D meshes people would rather look than read.
//!
//! Each mesh edge is drawn once, all in one `<path>`; boundary edges are drawn over them,
//! thicker and coloured by marker; triangles can be filled by a per-cell value (region,
//! quality). Coordinates are in pixels rounded to 0.01, the y axis points up as in the mesh,
//! and stroke widths do not depend on the mesh's size, so a 100,000-triangle mesh gives a file
//! of a few megabytes that any browser shows.

use std::fmt::Write as _;
use std::path::Path;

use crate::atomic::write_atomic;
use crate::model::check_points;
use crate::IoError;

/// A 2D mesh to draw.
#[derive(Clone, Copy, Debug)]
pub struct SvgMesh<'a> {
    /// `2 * n_points` coordinates.
    pub coords: &'a [f64],
    /// `3 * n_triangles` 0-based point indices.
    pub triangles: &'a [u32],
    /// Boundary edges, drawn thicker.
    pub segments: &'a [[u32; 2]],
    /// One marker per boundary edge (its colour).
    pub segment_markers: &'a [i32],
    /// A value per triangle to colour it by (none: white).
    pub cell_values: Option<&'a [f64]>,
}

/// Picture size and styling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SvgOptions {
    /// Width of the picture in pixels (the height follows the mesh's aspect ratio).
    pub width_px: f64,
    /// Width of mesh edges in pixels.
    pub edge_px: f64,
    /// Width of boundary edges in pixels.
    pub boundary_px: f64,
}

impl Default for SvgOptions {
    fn default() -> Self {
        SvgOptions {
            width_px: 1000.0,
            edge_px: 0.4,
            boundary_px: 1.5,
        }
    }
}

const PALETTE: [&str; 8] = [
    "#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];
const FILLS: [&str; 8] = [
    "#fde0dd", "#deebf7", "#e5f5e0", "#fee6ce", "#efedf5", "#f6e8c3", "#fbe2ee", "#d9f0f3",
];

/// Writes `mesh` as an SVG picture. Atomic.
pub fn write_svg(path: &Path, mesh: &SvgMesh<'_>, options: &SvgOptions) -> Result<(), IoError> {
    check_points(path, 2, mesh.coords)?;
    let np = mesh.coords.len() / 2;
    if mesh.triangles.len() % 3 != 0 || mesh.triangles.iter().any(|&v| v as usize >= np) {
        return Err(IoError::invalid(
            path,
            "triangles must index the points, 3 per triangle",
        ));
    }
    if mesh.segments.len() != mesh.segment_markers.len()
        || mesh.segments.iter().flatten().any(|&v| v as usize >= np)
    {
        return Err(IoError::invalid(
            path,
            "segments must index the points, one marker each",
        ));
    }
    if mesh
        .cell_values
        .is_some_and(|v| v.len() * 3 != mesh.triangles.len())
    {
        return Err(IoError::invalid(
            path,
            "one cell value per triangle is needed",
        ));
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in mesh.coords.chunks_exact(2) {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if np == 0 {
        (lo, hi) = ([0.0; 2], [1.0; 2]);
    }
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    let margin = 10.0;
    let scale = (options.width_px - 2.0 * margin) / (hi[0] - lo[0]).max(span * 1e-3);
    let height = (hi[1] - lo[1]) * scale + 2.0 * margin;
    let xy = |v: u32| {
        let p = &mesh.coords[2 * v as usize..2 * v as usize + 2];
        (
            (p[0] - lo[0]) * scale + margin,
            (hi[1] - p[1]) * scale + margin,
        )
    };
    let mut body = String::new();
    let _ = writeln!(
        body,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0}\" height=\"{:.0}\" viewBox=\"0 0 {:.2} {:.2}\">",
        options.width_px, height, options.width_px, height
    );
    let _ = writeln!(
        body,
        "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>"
    );
    if let Some(values) = mesh.cell_values {
        // One path per distinct value (regions), colours cycling through a light palette.
        let mut distinct: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        distinct.sort_by(f64::total_cmp);
        distinct.dedup();
        for (k, &value) in distinct.iter().enumerate() {
            let mut d = String::new();
            for (t, &v) in mesh.triangles.chunks_exact(3).zip(values) {
                if v == value {
                    let [(x0, y0), (x1, y1), (x2, y2)] = [xy(t[0]), xy(t[1]), xy(t[2])];
                    let _ = write!(d, "M{x0:.2} {y0:.2}L{x1:.2} {y1:.2}L{x2:.2} {y2:.2}Z");
                }
            }
            let _ = writeln!(
                body,
                "<path fill=\"{}\" stroke=\"none\" d=\"{d}\"/>",
                FILLS[k % FILLS.len()]
            );
        }
    }
    // Unique edges.
    let mut edges: Vec<(u32, u32)> = mesh
        .triangles
        .chunks_exact(3)
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let mut d = String::with_capacity(edges.len() * 28);
    for (a, b) in edges {
        let ((x0, y0), (x1, y1)) = (xy(a), xy(b));
        let _ = write!(d, "M{x0:.2} {y0:.2}L{x1:.2} {y1:.2}");
    }
    let _ = writeln!(
        body,
        "<path fill=\"none\" stroke=\"#404040\" stroke-width=\"{}\" d=\"{d}\"/>",
        options.edge_px
    );
    let mut markers: Vec<i32> = mesh.segment_markers.to_vec();
    markers.sort_unstable();
    markers.dedup();
    for (k, &m) in markers.iter().enumerate() {
        let mut d = String::new();
        for (s, _) in mesh
            .segments
            .iter()
            .zip(mesh.segment_markers)
            .filter(|(_, &x)| x == m)
        {
            let ((x0, y0), (x1, y1)) = (xy(s[0]), xy(s[1]));
            let _ = write!(d, "M{x0:.2} {y0:.2}L{x1:.2} {y1:.2}");
        }
        let _ = writeln!(
            body,
            "<path fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" stroke-linecap=\"round\" d=\"{d}\"><title>marker {m}</title></path>",
            PALETTE[k % PALETTE.len()],
            options.boundary_px
        );
    }
    body.push_str("</svg>\n");
    write_atomic(path, |w| {
        w.write_all(body.as_bytes())
            .map_err(|e| IoError::io(path, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_two_triangle_square() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sq.svg");
        let coords = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0];
        let mesh = SvgMesh {
            coords: &coords,
            triangles: &[0, 1, 2, 0, 2, 3],
            segments: &[[0, 1], [1, 2], [2, 3], [3, 0]],
            segment_markers: &[1, 1, 2, 2],
            cell_values: Some(&[0.0, 1.0]),
        };
        let options = SvgOptions {
            width_px: 120.0,
            ..SvgOptions::default()
        };
        write_svg(&path, &mesh, &options).unwrap();
        insta::assert_snapshot!(std::fs::read_to_string(&path).unwrap());
        let bad = SvgMesh {
            triangles: &[0, 1, 9],
            ..mesh
        };
        assert!(write_svg(&path, &bad, &options).is_err());
    }
}
