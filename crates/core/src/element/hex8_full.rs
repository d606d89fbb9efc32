//! Fully integrated trilinear hexahedron: 2×2×2 Gauss–Legendre points, weights 1.

use nalgebra::{Matrix3, Vector3};

use super::{BlockKernel, ElementError, Technology};
use crate::mesh::geometry::{hex8_gradients, jacobian};
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
) -> Result<BlockKernel, ElementError> {
    let points = gauss_points();
    let reference_gradients: Vec<[[f64; 3]; 8]> =
        points.iter().map(|&xi| hex8_gradients(xi)).collect();
    let mut gradients = Vec::with_capacity(block.len() * 64);
    let mut weights = Vec::with_capacity(block.len() * 8);
    let mut coords = [Vector3::zeros(); 8];
    for (element, ids) in block.elements().enumerate() {
        nodes.gather(ids, &mut coords);
        for (point, local) in reference_gradients.iter().enumerate() {
            let j0: Matrix3<f64> = jacobian(&coords, local);
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
            gradients.extend(local.iter().map(|g| inverse_transpose * Vector3::from(*g)));
            weights.push(det_j);
        }
    }
    Ok(BlockKernel {
        technology: Technology::Hex8Full,
        nodes_per_element: 8,
        points_per_element: 8,
        gradients,
        weights,
    })
}
