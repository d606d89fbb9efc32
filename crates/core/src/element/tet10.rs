//! Quadratic tetrahedron (C3D10 node order), 4 integration points: the reference data
//! of [`Technology::Tet10`] and of [`Technology::Tet10FBar`] (which modifies F at the same
//! points, `fbar.rs`).
//!
//! Shape functions (L_i the barycentric coordinates, L₁ = 1 − ξ − η − ζ, L₂ = ξ, L₃ = η,
//! L₄ = ζ): corners N_i = L_i (2L_i − 1), mid-edge nodes N = 4 L_a L_b
//! ([`crate::mesh::geometry::tet10_gradients`]). At each point,
//! ∇_X N_a = J₀⁻ᵀ ∇_ξ N_a [1/m], F = Σ_a x_a ⊗ ∇_X N_a, and
//! f_a = Σ_q w_q det J₀(q) P_q ∇_X N_a(q) [N] with P = J σ F⁻ᵀ [Pa].
//!
//! Rule: the symmetric 4-point rule of degree 2 (Keast 1986; Hammer, Marlowe & Stroud
//! 1956): barycentric points (α, β, β, β) and permutations, α = (5 + 3√5)/20,
//! β = (5 − √5)/20, weights 1/24 each (sum 1/6, the unit tet's volume). For a
//! straight-sided tet10 (mid-edge nodes at the midpoints, as the box generators and
//! `distort` make them) det J₀ is constant and ∇_X N_a linear, so the volume and the
//! constant-stress forces ∫ P ∇_X N_a dV are integrated exactly, and the stiffness
//! (quadratic integrand) too. For curved elements det J₀ is cubic and the rule is not
//! exact: the kernel's reference volume is then an approximation (the mesh's
//! [`crate::mesh::ElementShape::volume`] uses a degree-3 rule).

use super::isoparametric::{RulePoint, reference_data as isoparametric};
use super::{BlockKernel, ElementError, Technology};
use crate::mesh::geometry::tet10_gradients;
use crate::mesh::{ElementBlock, Nodes};

/// α = (5 + 3√5)/20 of the degree-2 rule.
const ALPHA: f64 = 0.585_410_196_624_968_5;
/// β = (5 − √5)/20 of the degree-2 rule.
const BETA: f64 = 0.138_196_601_125_010_5;
/// Weight of each point (the reference tet has volume 1/6).
const WEIGHT: f64 = 1.0 / 24.0;

/// The 4 points in reference coordinates (ξ, η, ζ) = (L₂, L₃, L₄).
pub(super) const POINTS: [[f64; 3]; 4] = [
    [BETA, BETA, BETA],
    [ALPHA, BETA, BETA],
    [BETA, ALPHA, BETA],
    [BETA, BETA, ALPHA],
];

/// ∇_X N_a and w det J₀ at every point of every element, for `technology` (Tet10 or
/// Tet10FBar).
pub(super) fn reference_data(
    nodes: &Nodes,
    block: &ElementBlock,
    technology: Technology,
) -> Result<BlockKernel, ElementError> {
    let rule: Vec<RulePoint> = POINTS
        .iter()
        .map(|&xi| RulePoint {
            gradients: tet10_gradients(xi).to_vec(),
            weight: WEIGHT,
        })
        .collect();
    isoparametric(nodes, block, technology, &rule)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule integrates every monomial of degree ≤ 2 over the unit tet exactly:
    /// ∫ ξ^i η^j ζ^k = i! j! k! / (i + j + k + 3)!.
    #[test]
    fn the_rule_has_degree_two() {
        let factorial = |n: u32| (1..=n).product::<u32>() as f64;
        for i in 0..=2u32 {
            for j in 0..=(2 - i) {
                for k in 0..=(2 - i - j) {
                    let rule: f64 = POINTS
                        .iter()
                        .map(|p| {
                            WEIGHT * p[0].powi(i as i32) * p[1].powi(j as i32) * p[2].powi(k as i32)
                        })
                        .sum();
                    let exact =
                        factorial(i) * factorial(j) * factorial(k) / factorial(i + j + k + 3);
                    assert!(
                        (rule - exact).abs() < 1e-15,
                        "ξ^{i} η^{j} ζ^{k}: {rule} vs {exact}"
                    );
                }
            }
        }
        assert!((ALPHA - (5.0 + 3.0 * 5f64.sqrt()) / 20.0).abs() < 1e-16);
        assert!((BETA - (5.0 - 5f64.sqrt()) / 20.0).abs() < 1e-16);
    }
}
