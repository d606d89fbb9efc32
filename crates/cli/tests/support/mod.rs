//! Helpers shared by the CLI tests (a folder, so cargo does not take it for a test).

pub mod csv;
pub mod fortran;
pub mod mesh_files;
pub mod run;
