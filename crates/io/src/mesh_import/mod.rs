//! Mesh import: Abaqus `.inp` and Gmsh `.msh` (4.1 ASCII or binary, 2.2 ASCII) into a
//! [`Mesh`].
//!
//! [`read_mesh`] picks the reader by the file extension (`.inp` → [`read_abaqus`],
//! `.msh` → [`read_gmsh`]); [`parse_abaqus`] and [`parse_gmsh`] read text already in
//! memory. Both return an [`ImportedMesh`]: the mesh with 0-based ids, plus the file label
//! of every node and element and the file's element type of every block, so that results
//! can be reported in the labels the user knows and a solver can pick an element
//! technology (e.g. one-point hex8 for `C3D8R`).
//!
//! Conventions of the result (both formats):
//!
//! - node ids follow the order in which nodes appear in the file(s); element ids the order
//!   within their block;
//! - local node order is Abaqus's (see [`musclefem_mesh::ElementShape`]); Gmsh's
//!   10-node tetrahedron is reordered (its last two mid-edge nodes are swapped);
//! - node sets, element sets and surfaces are sorted by id and free of duplicates;
//! - every fiber direction is e_x, except where an Abaqus `*ORIENTATION` gives one
//!   ([`ImportedMesh::fiber_sources`] says which blocks);
//! - the mesh has passed [`Mesh::validate`] (no inverted or degenerate element).
//!
//! Errors ([`ImportError`]) never panic and read `FILE:LINE: message`, naming the keyword
//! or section, the label and the cause. See [`abaqus`] and [`gmsh`] for what each reader
//! supports and deliberately leaves out.

pub mod abaqus;
mod abaqus_keywords;
mod build;
mod error;
mod face_match;
pub mod gmsh;

use std::path::{Path, PathBuf};

use musclefem_mesh::Mesh;

pub use abaqus::{parse_abaqus, read_abaqus, read_abaqus_with};
pub use error::ImportError;
pub use gmsh::{parse_gmsh, parse_gmsh_bytes, read_gmsh};

/// A mesh read from a file, with the file's labels.
#[derive(Clone, Debug)]
pub struct ImportedMesh {
    /// The mesh (0-based ids, validated).
    pub mesh: Mesh,
    /// File label of each node: `node_labels[id]`.
    pub node_labels: Vec<i64>,
    /// File label of each element, per block: `element_labels[block][element]`.
    pub element_labels: Vec<Vec<i64>>,
    /// The file's element type of each block: Abaqus names (`"C3D8R"`, `"C3D10"`, ...) or
    /// Gmsh's (`"tet4"`, `"hex8"`, `"tet10"`).
    pub element_types: Vec<String>,
    /// Keywords the reader skipped because they do not describe the mesh (materials,
    /// steps, loads, ...), in file order. Always empty for Gmsh.
    pub skipped_keywords: Vec<SkippedKeyword>,
    /// What the reader read over or could not place, in file order: every skipped keyword
    /// with the reason, surface elements on no volume face, partly oriented blocks, ...
    /// [`summarize_warnings`] groups them for a terminal.
    pub warnings: Vec<ImportWarning>,
    /// Where the fibers of each block come from: `Some("*ORIENTATION ORI (file:line)")`
    /// when every element of the block got its fiber from the file (Abaqus
    /// `*ORIENTATION`, local 1-axis), `None` when they are the default e_x.
    pub fiber_sources: Vec<Option<String>>,
}

/// Something the reader read over without failing, and where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImportWarning {
    /// The file, as given or as named by `*INCLUDE`.
    pub file: PathBuf,
    /// 1-based line.
    pub line: usize,
    /// The keyword (Abaqus, upper case without the star) or section (Gmsh) concerned.
    pub keyword: String,
    /// What was ignored and why.
    pub message: String,
}

/// The warnings as lines, one per (keyword, message): the first place, and how many
/// more times it occurs, e.g. `deck.inp:812: *STEP ignored: ... (and 3 more)`.
pub fn summarize_warnings(warnings: &[ImportWarning]) -> Vec<String> {
    let mut lines: Vec<(&ImportWarning, usize)> = Vec::new();
    for w in warnings {
        match lines
            .iter_mut()
            .find(|(first, _)| first.keyword == w.keyword && first.message == w.message)
        {
            Some((_, count)) => *count += 1,
            None => lines.push((w, 1)),
        }
    }
    lines
        .into_iter()
        .map(|(w, count)| {
            let more = match count {
                1 => String::new(),
                n => format!(" (and {} more)", n - 1),
            };
            format!("{}:{}: {}{more}", w.file.display(), w.line, w.message)
        })
        .collect()
}

/// A keyword that was read over (Abaqus), and where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SkippedKeyword {
    /// The file, as given or as named by `*INCLUDE`.
    pub file: PathBuf,
    /// 1-based line of the keyword line.
    pub line: usize,
    /// The keyword in upper case without the star, e.g. `"MATERIAL"`.
    pub keyword: String,
}

/// Reads a mesh, choosing the reader by extension: `.inp` (Abaqus) or `.msh` (Gmsh),
/// in any letter case.
pub fn read_mesh(path: impl AsRef<Path>) -> Result<ImportedMesh, ImportError> {
    read_mesh_with(path, false)
}

/// [`read_mesh`], with Abaqus `*INCLUDE`s from outside the file's folder when
/// `outside_includes` ([`read_abaqus_with`]).
pub fn read_mesh_with(
    path: impl AsRef<Path>,
    outside_includes: bool,
) -> Result<ImportedMesh, ImportError> {
    let path = path.as_ref();
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("inp") => read_abaqus_with(path, outside_includes),
        Some("msh") => read_gmsh(path),
        _ => Err(ImportError::Mesh {
            file: path.to_path_buf(),
            message: "unknown mesh format: the extension must be .inp (Abaqus) or .msh (Gmsh)"
                .into(),
        }),
    }
}

/// Reads a whole file as bytes, naming it in the error.
fn read_bytes(path: &Path) -> Result<Vec<u8>, ImportError> {
    std::fs::read(path).map_err(|source| ImportError::Io {
        file: path.to_path_buf(),
        source,
    })
}

/// The bytes as UTF-8 text, or an error at the line of the first invalid byte.
fn utf8(bytes: Vec<u8>, path: &Path) -> Result<String, ImportError> {
    String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..valid]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        ImportError::Parse {
            file: path.to_path_buf(),
            line,
            message: format!("not a text file: invalid UTF-8 at byte {valid} (binary data?)"),
        }
    })
}
