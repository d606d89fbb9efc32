//! Errors of the mesh readers: every one names the file, and the line when there is one.

use std::path::{Path, PathBuf};

/// Why a mesh file could not be imported.
///
/// The `Display` text starts with `FILE:LINE: ` (the path as given to the reader, or as
/// an `*INCLUDE` named it), so that editors and terminals can jump to the place.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// The file could not be read at all.
    #[error("cannot read '{}': {source}", file.display())]
    Io {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Something is wrong at a line of the file: `message` names the keyword or section,
    /// the label and the cause.
    #[error("{}:{line}: {message}", file.display())]
    Parse {
        file: PathBuf,
        /// 1-based line number.
        line: usize,
        message: String,
    },
    /// The mesh as a whole is wrong (e.g. it has no element); no single line is to blame.
    #[error("{}: {message}", file.display())]
    Mesh { file: PathBuf, message: String },
}

impl ImportError {
    /// The file the error concerns.
    pub fn file(&self) -> &Path {
        match self {
            ImportError::Io { file, .. }
            | ImportError::Parse { file, .. }
            | ImportError::Mesh { file, .. } => file,
        }
    }

    /// The 1-based line the error concerns, if there is one.
    pub fn line(&self) -> Option<usize> {
        match self {
            ImportError::Parse { line, .. } => Some(*line),
            _ => None,
        }
    }
}
