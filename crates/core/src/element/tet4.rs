//! Linear tetrahedron (C3D4 node order), one integration point.
//!
//! N_a = L_a, the barycentric coordinates; their reference gradients are constant, so
//! ∇_X N_a = J₀⁻ᵀ ∇_ξ L_a [1/m] with J₀ = Σ_a X_a ⊗ ∇_ξ L_a, and the one point has the
//! weight V = det J₀ / 6 [m³], the element's volume. F = Σ_a x_a ⊗ ∇_X N_a is constant in
//! the element, and the internal forces f_a = V P ∇_X N_a [N] (P = J σ F⁻ᵀ [Pa]) are
//! exact. Constant strain: it locks in bending and when nearly incompressible (one
//! volume constraint per element against about one free node per 5–6 elements); kept for
//! meshes that come only as linear tets and as a reference.

use super::isoparametric::{RulePoint, reference_data as isoparametric};
use super::{BlockKernel, ElementError, Technology};
use crate::mesh::geometry::TET4_GRADIENTS;
use crate::mesh::{ElementBlock, Nodes};

/// Volume of the reference (unit) tetrahedron.
const TET_REFERENCE_VOLUME: f64 = 1.0 / 6.0;

/// ∇_X N_a and V of every element.
pub(super) fn reference_data(
    nodes: &Nodes,
    block: &ElementBlock,
) -> Result<BlockKernel, ElementError> {
    let rule = [RulePoint {
        gradients: TET4_GRADIENTS.to_vec(),
        weight: TET_REFERENCE_VOLUME,
    }];
    isoparametric(nodes, block, Technology::Tet4, &rule)
}
