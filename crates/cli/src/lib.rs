//! The `musclefem` program's library: the scenarios behind its subcommands, usable from
//! tests, benchmarks and the parametric studies.
//!
//! - [`elongation`]: the single-muscle uniaxial elongation tests (`musclefem elongate`).

pub mod elongation;
