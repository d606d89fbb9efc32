//! # musclefem-materials
//!
//! The constitutive side of musclefem, usable on its own by any finite-element code:
//!
//! - [`material`]: the batched, VUMAT-like material interface ([`Material`],
//!   [`PointBlock`], [`PointResponse`]) with input/output checks and a finite-difference
//!   tangent for materials that supply none;
//! - [`parameters`]: typed parameter declarations (unit, default, range) and their checked
//!   resolution from a name → value map;
//! - [`registry`]: built-in materials registered with `inventory` plus run-time plugins;
//! - [`neo_hookean`], [`hill`] and [`tendon`]: the built-in materials; and, for models
//!   brought from other codes (FEBio, felupe, the literature), [`neo_hookean_coupled`],
//!   [`mooney_rivlin`] and [`trans_iso_mooney_rivlin`];
//! - [`plugin`]: the C ABI (`include/musclefem_material.h`) and the plugin loader;
//! - [`hosted`]: materials defined at run time by the host program (Python);
//! - [`driver`]: a homogeneous material-point driver (uniaxial stress along the fiber).
//!
//! Units are SI throughout (Pa, s, m).

pub mod activation_history;
pub mod amplitude;
pub mod driver;
pub mod error;
pub mod hill;
pub mod hosted;
pub mod material;
pub mod mooney_rivlin;
pub mod neo_hookean;
pub mod neo_hookean_coupled;
pub mod parameters;
pub mod plugin;
pub mod registry;
pub mod tendon;
pub mod tensor;
pub mod trans_iso_mooney_rivlin;

pub use activation_history::{ActivationDynamics, ActivationHistory, ActivationHistoryError};
pub use amplitude::Amplitude;
pub use error::MaterialError;
pub use hosted::{HostedBuild, HostedMaterial};
pub use material::{Material, PointBlock, PointResponse, StateVariable, Tangent, VoigtStress};
pub use parameters::{Bound, ParameterSet, ParameterSpec};
pub use registry::{MaterialInfo, MaterialLibrary, MaterialOrigin, MaterialRegistration};

/// The README's examples, compiled and run by `cargo test --doc`.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
