//! Fully integrated trilinear hexahedron: 2×2×2 Gauss–Legendre points, weights 1.
//! N_a = (1 + ξ_a ξ)(1 + η_a η)(1 + ζ_a ζ)/8; F = Σ_a x_a ⊗ ∇_X N_a at each point;
//! f_a = Σ_q P_q ∇_X N_a(q) det J₀(q) [N]. Locks when nearly incompressible (8 points
//! each constrained to J ≈ 1); kept as the reference for the other hex8 technologies.

use super::isoparametric::{RulePoint, reference_data as isoparametric};
use super::{BlockKernel, ElementError, Technology};
use crate::mesh::geometry::hex8_gradients;
use crate::mesh::{ElementBlock, Nodes};

/// 1/√3, the 2-point Gauss–Legendre abscissa on [−1, 1].
const GAUSS_2: f64 = 0.577_350_269_189_625_8;

/// The 8 Gauss points (ξ, η, ζ) = (±1/√3, ±1/√3, ±1/√3), weight 1 each.
pub(super) fn gauss_points() -> [[f64; 3]; 8] {
    let mut points = [[0.0; 3]; 8];
    for (q, point) in points.iter_mut().enumerate() {
        let sign = |bit: usize| if q >> bit & 1 == 0 { -GAUSS_2 } else { GAUSS_2 };
        *point = [sign(0), sign(1), sign(2)];
    }
    points
}

/// ∇_X N_a = J₀⁻ᵀ ∇_ξ N_a and w det J₀ at every Gauss point of every element.
pub(super) fn reference_data(
    nodes: &Nodes,
    block: &ElementBlock,
    technology: Technology,
) -> Result<BlockKernel, ElementError> {
    let rule: Vec<RulePoint> = gauss_points()
        .iter()
        .map(|&xi| RulePoint {
            gradients: hex8_gradients(xi).to_vec(),
            weight: 1.0,
        })
        .collect();
    isoparametric(nodes, block, technology, &rule)
}
