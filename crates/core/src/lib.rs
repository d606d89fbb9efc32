//! # musclefem-core
//!
//! Mesh (nodes, element blocks, node/element sets, surfaces), element kernels, assembly,
//! explicit and implicit solvers, boundary conditions and rigid drivers.
//!
//! Not built yet: the elements-and-solvers issue fills this crate. It exposes no API until
//! then, so that nothing can depend on a placeholder.
