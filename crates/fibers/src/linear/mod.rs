//! The linear solver: preconditioned conjugate gradients on the sparse symmetric positive
//! definite matrix of the orthogonal part ([`cg`]), with a Jacobi or an aggregation
//! multigrid ([`amg`]) preconditioner, on parallel, allocation-free vector kernels with
//! deterministic sums ([`kernels`]).

pub(crate) mod amg;
pub(crate) mod cg;
pub(crate) mod kernels;
