//! Reference data shared by the isoparametric kernels: at every integration point ξ_q of
//! a rule with reference weights w_q, the Jacobian J₀ = Σ_a X_a ⊗ ∇_ξ N_a(ξ_q) of the
//! reference configuration, the reference gradients ∇_X N_a = J₀⁻ᵀ ∇_ξ N_a [1/m] and the
//! weight w_q det J₀ [m³]. An element with det J₀ ≤ 0 at a point is refused.

use nalgebra::{Matrix3, Vector3};

use super::{BlockKernel, ElementError, Technology};
use crate::mesh::geometry::jacobian;
use crate::mesh::{ElementBlock, MAX_NODES_PER_ELEMENT, Nodes};

/// One integration point of a rule: ∇_ξ N_a of every node there, and its weight in the
/// reference element.
pub(super) struct RulePoint {
    pub gradients: Vec<[f64; 3]>,
    pub weight: f64,
}

/// The kernel data of `block` for `technology`, integrated with `rule` at every element.
pub(super) fn reference_data(
    nodes: &Nodes,
    block: &ElementBlock,
    technology: Technology,
    rule: &[RulePoint],
) -> Result<BlockKernel, ElementError> {
    let npe = block.shape.nodes_per_element();
    debug_assert!(rule.iter().all(|p| p.gradients.len() == npe));
    let mut gradients = Vec::with_capacity(block.len() * rule.len() * npe);
    let mut weights = Vec::with_capacity(block.len() * rule.len());
    let mut coords = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
    for (element, ids) in block.elements().enumerate() {
        nodes.gather(ids, &mut coords);
        for (point, local) in rule.iter().enumerate() {
            let j0: Matrix3<f64> = jacobian(&coords[..npe], &local.gradients);
            let det_j = j0.determinant();
            let inverse_transpose = j0.try_inverse().map(|inv| inv.transpose());
            let Some(inverse_transpose) = inverse_transpose.filter(|_| det_j > 0.0) else {
                return Err(ElementError::InvertedReference {
                    block: block.name.clone(),
                    element,
                    point,
                    det_j,
                });
            };
            gradients.extend(
                local
                    .gradients
                    .iter()
                    .map(|g| inverse_transpose * Vector3::from(*g)),
            );
            weights.push(local.weight * det_j);
        }
    }
    Ok(BlockKernel {
        technology,
        nodes_per_element: npe,
        points_per_element: rule.len(),
        gradients,
        weights,
        hourglass: None,
    })
}
