//! # musclefem-io
//!
//! Input and output of musclefem:
//!
//! - [`atomic`]: files that appear complete or not at all (temporary file in the same
//!   directory, fsync, rename), so an interrupted run never leaves a half-written output;
//! - [`csv`]: CSV tables at full `f64` precision, among them the material-point driver's
//!   history ([`csv::write_uniaxial_csv`]);
//! - [`plot`]: PNG charts (several named series per panel, panels side by side, axis
//!   labels with units, legend) drawn with a bundled font, so no system font is needed;
//! - [`mesh_import`]: meshes from Abaqus `.inp` and Gmsh `.msh` 4.1 files, with file and
//!   line in every error.
//!
//! Scene files come with a later issue.

pub mod atomic;
pub mod csv;
pub mod error;
pub mod mesh_import;
pub mod plot;

pub use atomic::{PendingFile, write_atomically};
pub use error::OutputError;
