//! Linear tetrahedron with nodally averaged F-bar ([`Technology::Tet4NodalAverage`]), the
//! average-nodal-volume tet of Bonet & Burton (1998) written as an F-bar so that it works
//! with any material through the `Material` interface (Cauchy stress at a given F).
//!
//! Per block, with V_e and v_e = V_e J_e the reference and current volumes of tet e
//! [m³], J_e = det F_e, and V_a = Σ_{e∋a} V_e the reference volume around node a:
//!
//! - nodal Jacobian J_a = Σ_{e∋a} v_e / V_a ([`NodalAveraging::nodal_jacobians`]);
//! - element averaged Jacobian J̄_e = ¼ Σ_{a∈e} J_a;
//! - F̄_e = α F_e with α = (J̄_e/J_e)^{1/3}, so det F̄_e = J̄_e; the material sees F̄_e and
//!   returns the Cauchy stress σ̄_e.
//!
//! Internal forces: the derivative of W = Σ_e V_e Ψ(F̄_e) (for a hyperelastic material;
//! the same expression is used for any material). With P̄ = ∂Ψ/∂F̄ and the Kirchhoff stress
//! τ̄ = P̄ F̄ᵀ = J̄ σ̄, δF̄ = α δF + ⅓ α (δJ̄/J̄ − δJ/J) F gives
//!
//! P̄ : δF̄ = α P̄ : δF + ⅓ tr τ̄ (δJ̄/J̄ − δJ/J).
//!
//! With ∇_x N_a = F⁻ᵀ ∇_X N_a [1/m], δJ/J = Σ_a δx_a · ∇_x N_a and α P̄ ∇_X N_a = J̄ σ̄ ∇_x N_a,
//! the local part is deviatoric:
//!
//! f_a^dev = V_e J̄_e dev(σ̄_e) ∇_x N_a  [N]  ([`add_deviatoric_forces`]).
//!
//! The δJ̄ part couples neighbours: δJ̄_e = ¼ Σ_{a∈e} δJ_a, δJ_a = Σ_{e'∋a} δv_{e'} / V_a,
//! δv_{e'} = v_{e'} Σ_{b∈e'} δx_b · ∇_x N_b. Collecting terms, with
//!
//! s_e = V_e tr τ̄_e / (3·4·J̄_e) = V_e tr σ̄_e / 12  [J]  ([`pressure_work`]),
//! S_a = Σ_{e∋a} s_e / V_a  [Pa]  ([`NodalAveraging::nodal_pressures`]),
//!
//! node b of tet e' receives f_b^vol = (Σ_{a∈e'} S_a) v_{e'} ∇_x N_b  [N]
//! ([`add_pressure_forces`]). Under a homogeneous deformation all J_a = J, F̄ = F,
//! S_a = tr σ/12, and f^dev + f^vol = v σ ∇_x N_b, the plain tet4 forces: the patch tests
//! hold. v_{e'} ∇_x N_b = V_{e'} cof(F) ∇_X N_b, cof F = J F⁻ᵀ, so no inverse is needed.
//!
//! Stable step: with a volumetric/deviatoric energy the averaging changes only the
//! volumetric part, and Σ_e V_e (J̄_e − 1)² ≤ Σ_e V_e (J_e − 1)² (Jensen twice), so the
//! highest frequency is at most the plain tet4's; the solvers use the plain tet4 bound.
//!
//! The element-level path of [`super::BlockKernel`] ([`super::BlockKernel::add_element_forces`])
//! cannot see the neighbours: for this technology it gives the plain tet4 forces, and the
//! solvers use the block-level passes instead (`solver/nodal_average.rs`).

use nalgebra::{Matrix3, Vector3};

use super::isoparametric::{RulePoint, reference_data as isoparametric};
use super::{BlockKernel, ElementError, Technology};
use crate::mesh::ElementBlock;
use crate::mesh::Nodes;
use crate::mesh::geometry::TET4_GRADIENTS;

/// Volume of the reference (unit) tetrahedron.
const TET_REFERENCE_VOLUME: f64 = 1.0 / 6.0;

/// ∇_X N_a and V of every element (as the plain tet4).
pub(super) fn reference_data(
    nodes: &Nodes,
    block: &ElementBlock,
) -> Result<BlockKernel, ElementError> {
    let rule = [RulePoint {
        gradients: TET4_GRADIENTS.to_vec(),
        weight: TET_REFERENCE_VOLUME,
    }];
    isoparametric(nodes, block, Technology::Tet4NodalAverage, &rule)
}

/// The node patches of a tet4 block: which block-local node each corner is, and the
/// reference volume V_a = Σ_{e∋a} V_e around each node [m³].
#[derive(Debug, Clone)]
pub struct NodalAveraging {
    /// Block-local node of each corner, 4 per element.
    corners: Vec<u32>,
    /// Mesh node id of each block-local node.
    node_ids: Vec<u32>,
    /// V_a [m³] of each block-local node.
    reference_nodal_volume: Vec<f64>,
}

impl NodalAveraging {
    /// The patches of `block`, whose reference volumes `kernel` holds.
    pub fn new(kernel: &BlockKernel, block: &ElementBlock) -> Self {
        let mut local = std::collections::HashMap::new();
        let mut node_ids = Vec::new();
        let corners: Vec<u32> = block
            .connectivity
            .iter()
            .map(|&id| {
                *local.entry(id).or_insert_with(|| {
                    node_ids.push(id);
                    (node_ids.len() - 1) as u32
                })
            })
            .collect();
        let mut reference_nodal_volume = vec![0.0; node_ids.len()];
        for (element, ids) in corners.chunks_exact(4).enumerate() {
            for &a in ids {
                reference_nodal_volume[a as usize] += kernel.reference_volume(element);
            }
        }
        NodalAveraging {
            corners,
            node_ids,
            reference_nodal_volume,
        }
    }

    /// Number of nodes of the block.
    pub fn node_count(&self) -> usize {
        self.node_ids.len()
    }

    /// Block-local nodes of `element`.
    #[inline]
    pub fn corners(&self, element: usize) -> &[u32] {
        &self.corners[4 * element..4 * element + 4]
    }

    /// J_a = Σ_{e∋a} v_e / V_a of every block-local node, from the current volumes
    /// `current_volume` of all elements [m³], summed in element order.
    pub fn nodal_jacobians(&self, current_volume: &[f64], nodal_jacobian: &mut [f64]) {
        self.nodal_average(current_volume, nodal_jacobian);
    }

    /// S_a = Σ_{e∋a} s_e / V_a [Pa] of every block-local node, from every element's
    /// [`pressure_work`] s_e [J], summed in element order.
    pub fn nodal_pressures(&self, pressure_work: &[f64], nodal_pressure: &mut [f64]) {
        self.nodal_average(pressure_work, nodal_pressure);
    }

    /// out_a = Σ_{e∋a} q_e / V_a, serially in element order (deterministic).
    fn nodal_average(&self, per_element: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for (ids, q) in self.corners.chunks_exact(4).zip(per_element) {
            for &a in ids {
                out[a as usize] += q;
            }
        }
        for (o, v) in out.iter_mut().zip(&self.reference_nodal_volume) {
            *o /= v;
        }
    }

    /// J̄_e = ¼ Σ_{a∈e} J_a of `element` (or ¼ Σ S_a for nodal pressures: the element sum
    /// of [`add_pressure_forces`] is 4 times this mean).
    #[inline]
    pub fn element_mean(&self, element: usize, nodal: &[f64]) -> f64 {
        0.25 * self
            .corners(element)
            .iter()
            .map(|&a| nodal[a as usize])
            .sum::<f64>()
    }

    /// Add the element forces `forces` (4 per element, for the elements from
    /// `first_element` on, in block order) to the nodal forces `out` of the whole mesh,
    /// serially in element order.
    pub fn scatter(&self, first_element: usize, forces: &[Vector3<f64>], out: &mut [Vector3<f64>]) {
        let corners = &self.corners[4 * first_element..4 * first_element + forces.len()];
        for (ids, f) in corners.chunks_exact(4).zip(forces.chunks_exact(4)) {
            for (&a, fa) in ids.iter().zip(f) {
                out[self.node_ids[a as usize] as usize] += fa;
            }
        }
    }
}

/// F̄ = (J̄/J)^{1/3} F.
#[inline]
pub fn averaged_deformation_gradient(f: &Matrix3<f64>, averaged_jacobian: f64) -> Matrix3<f64> {
    f * (averaged_jacobian / f.determinant()).cbrt()
}

/// Local (deviatoric) forces f_a = V J̄ dev(σ̄) ∇_x N_a [N] of `element` with plain
/// deformation gradient `f`, averaged Jacobian J̄ and Cauchy stress `sigma` at F̄ [Pa],
/// added to `forces` (4 nodes).
pub fn add_deviatoric_forces(
    kernel: &BlockKernel,
    element: usize,
    f: &Matrix3<f64>,
    averaged_jacobian: f64,
    sigma: &Matrix3<f64>,
    forces: &mut [Vector3<f64>],
) {
    let deviator = sigma - Matrix3::identity() * (sigma.trace() / 3.0);
    // V J̄ dev σ̄ F⁻ᵀ = (J̄/J) dev σ̄ V cof F.
    let cofactor = cofactor(f);
    let scale = kernel.weight(element) * averaged_jacobian / f.determinant();
    let m = deviator * cofactor * scale;
    for (fa, g) in forces.iter_mut().zip(kernel.gradients(element)) {
        *fa += m * g;
    }
}

/// s_e = V_e tr σ̄_e / 12 [J] of `element` (module docs).
#[inline]
pub fn pressure_work(kernel: &BlockKernel, element: usize, sigma: &Matrix3<f64>) -> f64 {
    kernel.weight(element) * sigma.trace() / 12.0
}

/// Coupling forces f_b = p v_e ∇_x N_b = p V_e cof(F) ∇_X N_b [N] of `element`, with
/// p = Σ_{a∈e} S_a [Pa], added to `forces` (4 nodes).
pub fn add_pressure_forces(
    kernel: &BlockKernel,
    element: usize,
    f: &Matrix3<f64>,
    pressure: f64,
    forces: &mut [Vector3<f64>],
) {
    let m = cofactor(f) * (pressure * kernel.weight(element));
    for (fa, g) in forces.iter_mut().zip(kernel.gradients(element)) {
        *fa += m * g;
    }
}

/// cof F = J F⁻ᵀ, entry by entry (defined for any F).
#[inline]
pub fn cofactor(f: &Matrix3<f64>) -> Matrix3<f64> {
    let c0 = f.column(1).cross(&f.column(2));
    let c1 = f.column(2).cross(&f.column(0));
    let c2 = f.column(0).cross(&f.column(1));
    // The rows of F⁻¹ are (f₁×f₂, f₂×f₀, f₀×f₁)/J for the columns f_K of F.
    Matrix3::from_columns(&[c0, c1, c2])
}
