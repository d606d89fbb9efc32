//! # musclefem-io
//!
//! Input and output of musclefem:
//!
//! - [`atomic`]: files that appear complete or not at all (temporary file in the same
//!   directory, fsync, rename), so an interrupted run never leaves a half-written output;
//! - [`csv`]: CSV tables at full `f64` precision, among them the material-point driver's
//!   history ([`csv::write_uniaxial_csv`]);
//! - [`fiber_csv`]: fiber fields as CSV (element id, centroid, unit direction);
//! - [`strand_csv`]: tendon strands as CSV (end nodes' labels, slack length, law);
//! - [`output`]: VTU frames and a PVD time series for ParaView, CSV histories, the scene
//!   copy and the run log, laid out in a run directory;
//! - [`plot`]: PNG charts (several named series per panel, panels side by side, axis
//!   labels with units, legend) drawn with a bundled font, so no system font is needed;
//! - [`mesh_export`]: meshes as Abaqus `.inp` text that [`mesh_import`] reads back
//!   unchanged (a study's generated mesh handed to a scene file), and rigid surfaces
//!   with their vertex normals as OBJ text that a scene's rigid body reads back unchanged;
//! - [`mesh_import`]: meshes from Abaqus `.inp` and Gmsh `.msh` (4.1, 2.2) files, with
//!   file and line in every error;
//! - [`scene`]: scene files (TOML): parts, materials, loads and the step, checked and built
//!   into what the solvers take, with errors that name the line and key.
//!
//! Features (all on by default): `results` (the [`output`] module: frames and histories
//! of a solver run, with musclefem-core and vtkio), `plot` ([`plot`], with plotters) and
//! `scene` ([`scene`]: also contact and fibers). Without them the crate reads meshes
//! and writes CSV over musclefem-mesh and musclefem-materials alone:
//! `cargo tree -p musclefem-io --no-default-features -e normal`.

pub mod atomic;
pub mod csv;
pub mod delimited;
pub mod error;
pub mod fiber_csv;
pub mod fingerprint;
pub mod mesh_export;
pub mod mesh_import;
pub mod opensim_storage;
#[cfg(feature = "results")]
pub mod output;
pub mod paths;
#[cfg(feature = "plot")]
pub mod plot;
#[cfg(feature = "scene")]
pub mod scene;
pub mod strand_csv;

pub use atomic::{PendingFile, write_atomically};
pub use error::OutputError;

/// The README's examples, compiled and run by `cargo test --doc`.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
