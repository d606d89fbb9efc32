//! F-bar on the 2×2×2 hex8 with the element's mean dilatation (the F-bar construction of
//! de Souza Neto, Perić, Dutko & Owen 1996 with the volume ratio of Nagtegaal, Parks &
//! Rice 1974): every point's volume change is replaced by the element's,
//! F̄ = (J̄/J)^{1/3} F, J = det F, J̄ = v/V = Σ_q J_q w_q / Σ_q w_q
//! (w_q = Gauss weight × det J₀, so v and V are the current and reference volumes).
//! Using the volume average rather than the centre's J keeps the constant-stress patch
//! test exact on distorted meshes.
//!
//! Internal force, from δW = ∫ P̄ : δF̄ dV₀ with det F̄ = J̄ and
//! δF̄ F̄⁻¹ = δF F⁻¹ + ⅓ (δJ̄/J̄ − δJ/J) I, δJ/J = Σ_a δu_a·∇_x N_a,
//! δJ̄/J̄ = Σ_a δu_a·b̄_a, b̄_a = (1/v) Σ_q J_q w_q ∇_x N_a(q):
//! f_a = Σ_q w_q J̄ [σ̄_q ∇_x N_a(q) + ⅓ tr σ̄_q (b̄_a − ∇_x N_a(q))],
//! ∇_x N_a = F⁻ᵀ ∇_X N_a and σ̄ the Cauchy stress at F̄. For a homogeneous deformation
//! F̄ = F, b̄_a is the mean of ∇_x N_a and this is ∫ P ∇_X N_a dV₀.

use nalgebra::{Matrix3, Vector3};

use musclefem_materials::VoigtStress;
use musclefem_materials::tensor::symmetric_from_voigt;

use super::BlockKernel;

/// Mean dilatation J̄ = Σ J_q w_q / Σ w_q of `element` from its points' plain F.
fn mean_dilatation(kernel: &BlockKernel, element: usize, f: &[Matrix3<f64>]) -> f64 {
    let ppe = kernel.points_per_element();
    let (mut current, mut reference) = (0.0, 0.0);
    for (q, fq) in f.iter().enumerate() {
        let w = kernel.weight(element * ppe + q);
        current += fq.determinant() * w;
        reference += w;
    }
    current / reference
}

/// F̄ = (J̄/J)^{1/3} F for every point's F in `f` (the plain F on entry).
pub(super) fn modify(kernel: &BlockKernel, element: usize, f: &mut [Matrix3<f64>]) {
    let mean = mean_dilatation(kernel, element, f);
    for point in f {
        *point *= (mean / point.determinant()).cbrt();
    }
}

/// Add the element's F-bar internal forces (module docs) to `forces`, from its current
/// `positions` and the Cauchy stresses at F̄.
pub(super) fn add_element_forces(
    kernel: &BlockKernel,
    element: usize,
    positions: &[Vector3<f64>],
    stress: &[VoigtStress],
    forces: &mut [Vector3<f64>],
) {
    let ppe = kernel.points_per_element();
    let npe = kernel.nodes_per_element();
    debug_assert!(ppe <= 8 && npe <= 8);
    let mut f = [Matrix3::zeros(); 8];
    let mut spatial = [[Vector3::zeros(); 8]; 8];
    let mut mean_gradient = [Vector3::zeros(); 8];
    let mut current_volume = 0.0;
    let mut reference_volume = 0.0;
    for q in 0..ppe {
        let point = element * ppe + q;
        f[q] = kernel.deformation_gradient(point, positions);
        let jacobian = f[q].determinant();
        let inverse_transpose = f[q]
            .try_inverse()
            .map_or_else(Matrix3::zeros, |inv| inv.transpose());
        let w = kernel.weight(point);
        for (a, g) in kernel.gradients(point).iter().enumerate() {
            spatial[q][a] = inverse_transpose * g;
            mean_gradient[a] += spatial[q][a] * (jacobian * w);
        }
        current_volume += jacobian * w;
        reference_volume += w;
    }
    for g in &mut mean_gradient[..npe] {
        *g /= current_volume;
    }
    let mean = current_volume / reference_volume;
    for q in 0..ppe {
        let sigma = symmetric_from_voigt(&stress[q]);
        let third_trace = sigma.trace() / 3.0;
        let scale = kernel.weight(element * ppe + q) * mean;
        for a in 0..npe {
            let g = spatial[q][a];
            forces[a] += (sigma * g + (mean_gradient[a] - g) * third_trace) * scale;
        }
    }
}
