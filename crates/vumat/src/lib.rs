//! # musclefem-vumat
//!
//! Run an existing Abaqus/Explicit VUMAT or Abaqus/Standard UMAT, unchanged, as a musclefem
//! material: [`build_plugin`] compiles the user's Fortran `SUBROUTINE VUMAT` (or `UMAT`,
//! [`Subroutine`]) with gfortran and links it with its adapter of `plugins/abaqus_vumat`
//! into a plugin of musclefem's material ABI
//! (`crates/materials/include/musclefem_material.h`), which scenes load like any other
//! (`[[materials]] plugin = "libmy_vumat.so"`, `musclefem run --allow-plugins`).
//!
//! - [`options`]: the build's options ([`VumatBuild`]): the material name, the props as
//!   named parameters ([`Prop`]), nstatev, the fiber-direction convention
//!   ([`FiberConvention`]);
//! - [`kind`]: VUMAT or UMAT ([`Subroutine`]) and the UMAT's tangent ([`TangentSource`]);
//! - [`compile`]: the compilers' runs and the check that the library loads;
//! - `config_header`: the generated `vumat_config.h`;
//! - [`error`]: what went wrong, with the compilers' messages passed through.
//!
//! The adapter's conventions (co-rotational stress, U from F = R U, the midpoint strain
//! increment, Abaqus's component orders, the state the adapter keeps) are documented in
//! `docs/vumat.md` and in the adapter's sources.

pub mod compile;
mod config_header;
pub mod error;
pub mod kind;
pub mod options;
mod sources;
pub mod toolchain;

pub use compile::{BuiltPlugin, build_plugin};
pub use error::VumatError;
pub use kind::{Subroutine, TangentSource};
pub use options::{FiberConvention, Prop, VumatBuild};
