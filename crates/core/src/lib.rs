//! # musclefem-core
//!
//! The finite-element side of musclefem. What exists today:
//!
//! - [`mesh`]: the `musclefem-mesh` crate (nodes, element blocks, sets, surfaces, checks,
//!   geometry, generators), re-exported; use that crate alone to read or build meshes
//!   without the solvers.
//! - [`element`]: total-Lagrangian element kernels, each passing the patch tests on
//!   distorted meshes: the fully integrated hex8 (locks; kept as a reference), the F-bar
//!   (mean dilatation) hex8 with its consistent tangent, the one-point hex8 with the mean
//!   gradient and stiffness-type hourglass control (Flanagan–Belytschko; a batched SIMD
//!   kernel in explicit runs), the one-point tet4, the nodally averaged F-bar tet4 (no
//!   volumetric locking; explicit only) and the 4-point tet10.
//! - [`solver`]: the explicit central-difference solver (lumped mass, stable step from the
//!   current acoustic modulus, mass scaling, bulk viscosity, energy balance with hourglass
//!   and viscous energies, parallel deterministic assembly) and the implicit solver
//!   (quasi-static or Newmark dynamics, Newton with the consistent tangent, line search,
//!   step cutting, faer supernodal Cholesky in nested-dissection or AMD order and factor
//!   reuse as a CG preconditioner, LBLᵀ for indefinite and LU for unsymmetric tangents),
//!   both under the same [`solver::Loads`]: prescribed displacements, nodal forces, rigid
//!   ties.
//!
//! Not built yet: the implicit tangent of the nodally averaged tet4.
//!
//! Units are SI throughout (m, kg, s, Pa). Node, element and block ids are 0-based
//! indices; file formats with 1-based labels (Abaqus, Gmsh) are mapped on import.

pub mod element;
/// The mesh, its checks and generators: the `musclefem-mesh` crate, re-exported so that
/// `musclefem_core::mesh::...` paths work for users of the solvers.
pub use musclefem_mesh as mesh;
pub mod solver;
pub mod verification;

pub use mesh::{ElementBlock, ElementRef, ElementShape, Face, Mesh, MeshError, Nodes};

/// The README's examples, compiled and run by `cargo test --doc`.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
