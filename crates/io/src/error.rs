//! The single error type of `delmesh-io`.
//!
//! Every error names the file it is about, and parse errors also name the 1-based line, so a
//! message printed as-is (`points.node:12: expected 4 fields, found 3`) tells a user exactly
//! where to look. The type is a plain `thiserror` enum so callers can match on the kind.

use std::path::{Path, PathBuf};

/// Everything that can go wrong reading or writing a file in this crate.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The operating system refused a read, write, create, sync or rename.
    #[error("{file}: {source}", file = .file.display())]
    Io {
        /// The file being read or written (for writes: the destination, not the temp file).
        file: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A text file is malformed.
    #[error("{file}:{line}: {message}", file = .file.display())]
    Parse {
        /// The file being parsed.
        file: PathBuf,
        /// 1-based line number of the offending line.
        line: usize,
        /// What is wrong, in words.
        message: String,
    },
    /// A binary file is malformed (binary `.stl`, the binary data of a binary `.msh`); `offset`
    /// is the byte where the problem is, since such data has no lines.
    #[error("{file}: byte {offset}: {message}", file = .file.display())]
    Binary {
        /// The file being read.
        file: PathBuf,
        /// 0-based byte offset of the offending record or field.
        offset: u64,
        /// What is wrong, in words.
        message: String,
    },
    /// The data handed to a writer is inconsistent (bad dimension, index out of range, array of
    /// the wrong length, non-finite coordinate, ...). Nothing was written.
    #[error("{file}: {message}", file = .file.display())]
    InvalidInput {
        /// The file that was to be written.
        file: PathBuf,
        /// What is wrong, in words.
        message: String,
    },
    /// The VTK library failed to build or serialise the data set.
    #[error("{file}: VTK error: {message}", file = .file.display())]
    Vtk {
        /// The file being written.
        file: PathBuf,
        /// The VTK library's message.
        message: String,
    },
    /// The file's extension names a format that this reader does not handle.
    #[error("{file}: unknown or unsupported file format for this operation", file = .file.display())]
    UnknownFormat {
        /// The file.
        file: PathBuf,
    },
}

impl IoError {
    /// The file this error is about.
    pub fn file(&self) -> &Path {
        match self {
            IoError::Io { file, .. }
            | IoError::Parse { file, .. }
            | IoError::Binary { file, .. }
            | IoError::InvalidInput { file, .. }
            | IoError::Vtk { file, .. }
            | IoError::UnknownFormat { file } => file,
        }
    }

    /// The 1-based line number, for parse errors.
    pub fn line(&self) -> Option<usize> {
        match self {
            IoError::Parse { line, .. } => Some(*line),
            _ => None,
        }
    }

    pub(crate) fn io(file: &Path, source: std::io::Error) -> Self {
        IoError::Io {
            file: file.to_path_buf(),
            source,
        }
    }

    pub(crate) fn parse(file: &Path, line: usize, message: impl Into<String>) -> Self {
        IoError::Parse {
            file: file.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    pub(crate) fn binary(file: &Path, offset: u64, message: impl Into<String>) -> Self {
        IoError::Binary {
            file: file.to_path_buf(),
            offset,
            message: message.into(),
        }
    }

    pub(crate) fn invalid(file: &Path, message: impl Into<String>) -> Self {
        IoError::InvalidInput {
            file: file.to_path_buf(),
            message: message.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_and_accessors() {
        let e = IoError::parse(Path::new("points.node"), 12, "expected 4 fields, found 3");
        assert_eq!(e.to_string(), "points.node:12: expected 4 fields, found 3");
        assert_eq!(e.line(), Some(12));
        assert_eq!(e.file(), Path::new("points.node"));

        let e = IoError::io(
            Path::new("out/mesh.ele"),
            std::io::Error::new(std::io::ErrorKind::NotFound, "gone"),
        );
        assert_eq!(e.to_string(), "out/mesh.ele: gone");
        assert_eq!(e.line(), None);
        assert!(std::error::Error::source(&e).is_some());

        let e = IoError::Vtk {
            file: PathBuf::from("m.vtu"),
            message: "bad".into(),
        };
        assert_eq!(e.to_string(), "m.vtu: VTK error: bad");
        let e = IoError::UnknownFormat {
            file: PathBuf::from("m.stl"),
        };
        assert!(e.to_string().starts_with("m.stl: unknown"));
        let e = IoError::binary(Path::new("m.stl"), 84, "bad");
        assert_eq!(e.to_string(), "m.stl: byte 84: bad");
        assert_eq!(e.line(), None);
        let e = IoError::invalid(Path::new("m.node"), "dimension must be 2 or 3, found 4");
        assert_eq!(e.to_string(), "m.node: dimension must be 2 or 3, found 4");
    }

    #[test]
    fn is_send_sync_static() {
        fn check<T: Send + Sync + 'static>() {}
        check::<IoError>();
    }
}
