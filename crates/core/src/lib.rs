//! # musclefem-core
//!
//! The finite-element side of musclefem. What exists today:
//!
//! - [`mesh`]: nodes (structure of arrays), element blocks of hex8, tet4 and tet10 with a
//!   fiber direction per element, node sets, element sets, surfaces made of element faces,
//!   checks ([`Mesh::validate`]), volumes and face area vectors, and structured box
//!   generators (hexes, linear or quadratic tets) with a random interior distortion for
//!   patch tests.
//!
//! - [`element`]: total-Lagrangian element kernels, each passing the patch tests on
//!   distorted meshes: the fully integrated hex8, the F-bar (mean dilatation) hex8 that
//!   does not lock, the one-point hex8 with the mean gradient and stiffness-type hourglass
//!   control (Flanagan–Belytschko), the one-point tet4 and the 4-point tet10.
//! - [`solver`]: the explicit central-difference solver with lumped mass, a stable step
//!   from the current acoustic modulus, prescribed displacements, reactions, an energy
//!   balance check, parallel element updates and a deterministic force assembly; and the
//!   quasi-static implicit solver (Newton with the consistent tangent, line search, step
//!   cutting, faer sparse Cholesky/LU with the symbolic factorization reused).
//!
//! Not built yet (the rest of the elements-and-solvers issue): a locking-free tet, the
//! F-bar tangent, implicit dynamics and the trait through which contact
//! forces enter a solve.
//!
//! Units are SI throughout (m, kg, s, Pa). Node, element and block ids are 0-based
//! indices; file formats with 1-based labels (Abaqus, Gmsh) are mapped on import.

pub mod element;
pub mod mesh;
pub mod solver;

pub use mesh::{ElementBlock, ElementRef, ElementShape, Face, Mesh, MeshError, Nodes};
