//! The single error type of the `delmesh` library: [`Error`].
//!
//! A user running `delmesh` on a file needs to know which file is wrong and where, so every
//! variant names its file: reader and writer errors come from `delmesh-io` with the file and
//! line already in them; kernel errors (which know only point indices) get the input file's
//! name added here, and their point indices renumbered to the file's own numbering (a `.node`
//! file may count from 1).

use std::path::{Path, PathBuf};

use delmesh_boundary_recovery::RecoveryError;
use delmesh_delaunay_core::TriangulationError;
use delmesh_io::IoError;
use delmesh_point_gen::{PointGenError, SpacingError, SpacingError3};
use delmesh_smoothing::SmoothError;

/// Everything that can go wrong in the `delmesh` library.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading or writing a file failed, or the file is malformed (file and line in the
    /// message).
    #[error(transparent)]
    Io(#[from] IoError),
    /// The points of `file` admit no triangulation (too few, all collinear or coplanar, a
    /// coordinate out of range). Point indices in `source` are in the file's numbering.
    #[error("{file}: {source}", file = .file.display())]
    Triangulation {
        /// The input file.
        file: PathBuf,
        /// What the kernel reported.
        source: TriangulationError,
    },
    /// The output path's extension names no format this operation writes.
    #[error(
        "{file}: unsupported output format '{ext}' (supported: {supported})",
        file = .file.display()
    )]
    UnsupportedFormat {
        /// The output path.
        file: PathBuf,
        /// The extension found (with its dot), or `(none)`.
        ext: String,
        /// The supported extensions, e.g. `.vtu, .ele`.
        supported: &'static str,
    },
    /// A background or solution mesh file's extension names no format delmesh reads for it.
    #[error(
        "{file}: cannot read a background or solution mesh from a '{ext}' file (supported: \
         {supported})",
        file = .file.display()
    )]
    UnsupportedMeshInput {
        /// The input path.
        file: PathBuf,
        /// The extension found (with its dot).
        ext: String,
        /// The supported extensions, e.g. `.vtu, .vtk`.
        supported: &'static str,
    },
    /// A point set of a dimension other than 2 or 3.
    #[error("{file}: points of dimension {dim}; only 2 and 3 are supported", file = .file.display())]
    Dimension {
        /// The input file.
        file: PathBuf,
        /// The dimension found.
        dim: usize,
    },
    /// A background or adaptation mesh whose dimension is not the domain's.
    #[error(
        "{file}: a {dim}D mesh, but the domain is {expected}D (a background or adaptation mesh \
         must have the domain's dimension)",
        file = .file.display()
    )]
    MeshDimension {
        /// The mesh file.
        file: PathBuf,
        /// Its dimension.
        dim: usize,
        /// The domain's.
        expected: usize,
    },
    /// An output file would replace the input file (e.g. `pts.node -o pts.ele`, which writes
    /// `pts.node`).
    #[error(
        "{output}: writing this file would overwrite the input {input}; choose another output name",
        output = .output.display(),
        input = .input.display()
    )]
    OverwritesInput {
        /// The input file.
        input: PathBuf,
        /// The output file that is the same file.
        output: PathBuf,
    },
    /// The input domain cannot be meshed (crossing segments, bad seeds, nothing inside...);
    /// points and segments are named in the input's numbering.
    #[error(transparent)]
    Recovery(#[from] RecoveryError),
    /// The Delaunay restoration after 3D point generation and smoothing fell back on
    /// triangulating the final points again, and could not recover the refined surface there:
    /// the input was recovered, but interior points crowd the surface.
    #[error(
        "after point generation and smoothing, restoring the Delaunay property: {0} (interior \
         points crowd the surface there; --no-flips keeps the smoothed mesh, or try another \
         --recovery)"
    )]
    Restoration(RecoveryError),
    /// Automatic point generation failed (bad α or spacing).
    #[error(transparent)]
    PointGeneration(#[from] PointGenError),
    /// A background mesh or solution file does not define a valid spacing field.
    #[error("{file}: {source}", file = .file.display())]
    Spacing {
        /// The background mesh file.
        file: PathBuf,
        /// What is wrong with it.
        source: SpacingError,
    },
    /// A 3D background mesh or solution file does not define a valid spacing field.
    #[error("{file}: {source}", file = .file.display())]
    Spacing3 {
        /// The background mesh file.
        file: PathBuf,
        /// What is wrong with it.
        source: SpacingError3,
    },
    /// A background or solution file lacks the point field asked for.
    #[error("{file}: no point field '{field}' (fields: {available}; --field names the one to use)", file = .file.display())]
    MissingField {
        /// The file.
        file: PathBuf,
        /// The field asked for.
        field: String,
        /// The fields it has, comma-separated.
        available: String,
    },
    /// The spacing asked of the surface ([`crate::mesh3d::MeshOptions3::surface_spacing`]) is
    /// not a positive length, or would split the surface into more triangles than delmesh
    /// meshes.
    #[error("surface spacing {value}: {reason}")]
    SurfaceSpacing {
        /// The spacing asked.
        value: f64,
        /// Why it cannot be used.
        reason: String,
    },
    /// A conforming 3D recovery (the default, or a-priori) stopped at its bound of added
    /// points: said with the way out.
    #[error(
        "{0}; walls very close together need very many points in a conforming recovery: try \
         the constrained one (--recovery constrained, RecoveryMethod3::Constrained)"
    )]
    ConformingRecovery(RecoveryError),
    /// An option has a value it cannot take.
    #[error("{option}: {reason}")]
    BadOption {
        /// The option (its command-line name).
        option: &'static str,
        /// Why.
        reason: String,
    },
    /// A spacing source (numbered from 1 in the order given) has a bad value, or asks for
    /// more elements than delmesh can index.
    #[error("source {number}: {reason}")]
    Source {
        /// Its number, from 1.
        number: usize,
        /// What is wrong.
        reason: String,
    },
    /// Smoothing options are invalid or its input is inconsistent.
    #[error(transparent)]
    Smoothing(#[from] SmoothError),
    /// An input file's contents cannot be meshed as given (named with file and line).
    #[error("{file}: {message}", file = .file.display())]
    Input {
        /// The input file.
        file: PathBuf,
        /// What is wrong, with the line.
        message: String,
    },
    /// The domain is too large or too small for double precision meshing.
    #[error(
        "{what}: delmesh meshes coordinates up to 2^990 (about 1e298) in magnitude and domains \
         at least 2^-990 (about 1e-298) across"
    )]
    OutOfRange {
        /// What is out of range (a point and its coordinate, or the domain's extent).
        what: String,
    },
    /// A broken internal invariant (a bug in delmesh).
    #[error("internal error (a bug in delmesh): {0}")]
    Internal(String),
    /// `delmesh demo NAME` with a name that is not a demo.
    #[error("unknown demo '{name}' (available: {available})")]
    UnknownDemo {
        /// The name asked for.
        name: String,
        /// The demo names, comma-separated.
        available: String,
    },
}

impl Error {
    /// A kernel error about the points of `file`, its point indices shifted by `first_index` so
    /// they match the index column of the file.
    pub(crate) fn triangulation(file: &Path, source: TriangulationError, first_index: u32) -> Self {
        let source = source.numbered_from(first_index as usize);
        Error::Triangulation {
            file: file.to_path_buf(),
            source,
        }
    }

    /// The file the error is about, if any.
    pub fn file(&self) -> Option<&Path> {
        match self {
            Error::Io(e) => Some(e.file()),
            Error::Triangulation { file, .. }
            | Error::UnsupportedFormat { file, .. }
            | Error::UnsupportedMeshInput { file, .. }
            | Error::Dimension { file, .. }
            | Error::MeshDimension { file, .. }
            | Error::Input { file, .. } => Some(file),
            Error::OverwritesInput { output, .. } => Some(output),
            Error::Spacing { file, .. }
            | Error::Spacing3 { file, .. }
            | Error::MissingField { file, .. } => Some(file),
            Error::UnknownDemo { .. }
            | Error::Recovery(_)
            | Error::Restoration(_)
            | Error::PointGeneration(_)
            | Error::Smoothing(_)
            | Error::SurfaceSpacing { .. }
            | Error::Source { .. }
            | Error::ConformingRecovery(_)
            | Error::BadOption { .. }
            | Error::OutOfRange { .. }
            | Error::Internal(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_file_and_renumber_points() {
        let e = Error::triangulation(
            Path::new("points.node"),
            TriangulationError::NonFinite {
                index: 16,
                axis: 0,
                value: f64::NAN,
            },
            1,
        );
        assert_eq!(
            e.to_string(),
            "points.node: point 17: coordinate 0 is not finite (NaN)"
        );
        assert_eq!(e.file(), Some(Path::new("points.node")));

        let e = Error::UnsupportedFormat {
            file: PathBuf::from("mesh.stl"),
            ext: ".stl".into(),
            supported: ".vtu, .ele",
        };
        assert_eq!(
            e.to_string(),
            "mesh.stl: unsupported output format '.stl' (supported: .vtu, .ele)"
        );
    }

    #[test]
    fn is_send_sync_static() {
        fn check<T: Send + Sync + 'static>() {}
        check::<Error>();
    }
}
