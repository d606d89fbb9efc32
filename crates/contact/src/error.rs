//! Errors of the contact crate: they name the surface, file, line or parameter concerned.

use std::path::PathBuf;

use musclefem_core::mesh::MeshError;
use thiserror::Error;

/// Why a surface or an interaction could not be built.
#[derive(Debug, Error)]
pub enum ContactError {
    /// A mesh lookup failed (unknown surface, block or face name, a face out of range).
    #[error("surface '{surface}': {source}")]
    Mesh {
        surface: String,
        #[source]
        source: MeshError,
    },
    /// The surface has no face (or no triangle).
    #[error("surface '{0}' is empty: it has no face, so nothing can touch it")]
    EmptySurface(String),
    /// A triangle of the surface has (almost) no area.
    #[error("surface '{surface}': triangle {triangle} (nodes {nodes:?}) has no area")]
    DegenerateTriangle {
        surface: String,
        triangle: usize,
        nodes: [u32; 3],
    },
    /// A triangle names a vertex or node that does not exist.
    #[error(
        "surface '{surface}': triangle {triangle} names vertex {vertex}, but there are {count}"
    )]
    VertexOutOfRange {
        surface: String,
        triangle: usize,
        vertex: u32,
        count: usize,
    },
    /// Vertex normals given to a surface do not fit it.
    #[error("surface '{surface}': {reason}")]
    InvalidNormals { surface: String, reason: String },
    /// A parameter is out of its range.
    #[error("{what}: {value} {reason}")]
    InvalidParameter {
        what: String,
        value: f64,
        reason: String,
    },
    /// A geometry file could not be read.
    #[error("cannot read '{}': {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A geometry file is malformed.
    #[error("{}:{line}: {reason}", path.display())]
    Parse {
        path: PathBuf,
        /// 1-based line (ASCII formats) or, for binary STL, the 1-based triangle record.
        line: usize,
        reason: String,
    },
}

impl ContactError {
    /// An [`ContactError::InvalidParameter`] for `what` = `value`.
    pub(crate) fn invalid(what: &str, value: f64, reason: &str) -> Self {
        ContactError::InvalidParameter {
            what: what.to_string(),
            value,
            reason: reason.to_string(),
        }
    }
}
