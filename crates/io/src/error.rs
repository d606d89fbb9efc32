//! Errors of the output functions. Every variant names the file it concerns.

use std::path::PathBuf;

/// Why an output file could not be written (or read back).
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// An operating-system call on `path` failed; `action` says which ("create", "rename
    /// ... to", "sync", ...).
    #[error("cannot {action} '{}'", path.display())]
    Io {
        action: &'static str,
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The path cannot name an output file (no file name, e.g. `dir/..` or `/`).
    #[error("'{}' does not name a file", path.display())]
    NotAFile { path: PathBuf },
    /// Drawing a chart failed.
    #[error("cannot draw the chart '{}': {message}", path.display())]
    Plot { path: PathBuf, message: String },
    /// A CSV file does not hold what was expected.
    #[error("'{}' line {line}: {message}", path.display())]
    Parse {
        path: PathBuf,
        line: usize,
        message: String,
    },
    /// What was to be written to `path` is inconsistent (e.g. a field with one value
    /// per element that has the wrong length, a repeated name, a time going backwards).
    #[error("cannot write '{}': {message}", path.display())]
    Data { path: PathBuf, message: String },
    /// A stopped run cannot be resumed from the checkpoint `path`.
    #[error("cannot resume from '{}': {message}", path.display())]
    Resume { path: PathBuf, message: String },
    /// A file read back (e.g. a frame) lacks what was asked for or is inconsistent.
    #[error("cannot read '{}': {message}", path.display())]
    Read { path: PathBuf, message: String },
    /// The VTK library failed to encode or decode `path`.
    #[error("VTK error on '{}': {message}", path.display())]
    Vtk { path: PathBuf, message: String },
}

impl OutputError {
    pub(crate) fn io(
        action: &'static str,
        path: impl Into<PathBuf>,
        source: std::io::Error,
    ) -> Self {
        OutputError::Io {
            action,
            path: path.into(),
            source,
        }
    }
}
