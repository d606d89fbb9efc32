//! The linear solver: Jacobi-preconditioned conjugate gradients on the sparse symmetric
//! positive definite matrix of the orthogonal part ([`cg`]), on parallel, allocation-free
//! vector kernels with deterministic sums ([`kernels`]).

pub(crate) mod cg;
pub(crate) mod kernels;
