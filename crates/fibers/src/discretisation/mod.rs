//! The cell-centred finite-volume discretisation of ∇²φ = 0.
//!
//! Integrating over cell P and applying the divergence theorem, the net flux of ∇φ out of
//! every cell vanishes: Σ_f (∇φ)_f · S_f = 0, S_f the area vector of face f out of P.
//!
//! - Interior face, d = x_N − x_P between the cell centroids: the over-relaxed split
//!   S = Δ + k, Δ = (|S|²/(S·d)) d, gives
//!   (∇φ)_f·S ≈ a_f (φ_N − φ_P) + k·(∇φ)_f with a_f = |S|²/(S·d) [m]: the first term is
//!   implicit (the symmetric positive definite matrix), the second, the non-orthogonal
//!   correction, is explicit, with (∇φ)_f = w ∇φ_P + (1 − w) ∇φ_N interpolated from the
//!   cell gradients ([`coefficients`]).
//! - Inlet or outlet face (fixed potential φ_b), d = x_b − x_P to the face centre: the same
//!   split, (∇φ)_b·S ≈ a_b (φ_b − φ_P) + k_b·∇φ_P.
//! - Wall face: zero flux.
//!
//! The cell gradients are weighted least squares ([`gradient`]). The orthogonal part is the
//! matrix A and right-hand side b of [`matrix`]; the correction c(φ) of
//! [`correction`] is updated between solves (deferred correction) until
//! A φ = b + c(φ) holds to the tolerance (see [`crate::solve`]).
//!
//! Every term is exact for a linear potential whose gradient is parallel to the walls, so
//! such a field is reproduced to the solver tolerance on any mesh.

pub(crate) mod coefficients;
pub(crate) mod correction;
pub(crate) mod gradient;
pub(crate) mod matrix;
