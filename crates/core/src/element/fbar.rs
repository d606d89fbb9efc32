//! F-bar with the element's mean dilatation (the F-bar construction of de Souza Neto,
//! Perić, Dutko & Owen 1996 with the volume ratio of Nagtegaal, Parks & Rice 1974), on
//! the 2×2×2 hex8 ([`Technology::Hex8FBar`], 8 nodes, 8 points) and the 4-point tet10
//! ([`Technology::Tet10FBar`], 10 nodes, 4 points): every point's volume change is
//! replaced by the element's,
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
//!
//! The code is written once over the element's node count N and point count P (const
//! generics, so the loops have fixed bounds); the entry points pick them from the
//! kernel's technology.

use nalgebra::{Matrix3, SVector, Vector3};

use musclefem_materials::tensor::{first_piola_from_cauchy, symmetric_from_voigt};
use musclefem_materials::{Tangent, VoigtStress};

use super::{BlockKernel, Technology};
use crate::mesh::MAX_NODES_PER_ELEMENT;

/// Most degrees of freedom of an F-bar element (the tet10's 30).
const MAX_DOFS: usize = 3 * MAX_NODES_PER_ELEMENT;

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

/// J̄ = v/V of `element` at its current `positions` and its gradient
/// ∂J̄/∂x_a = (1/V) Σ_q w_q J_q F_q⁻ᵀ ∇_X N_a(q) = J̄ b̄_a [1/m], one per node (the
/// entries past the element's nodes are zero).
pub(super) fn mean_dilatation_gradient(
    kernel: &BlockKernel,
    element: usize,
    positions: &[Vector3<f64>],
) -> (f64, [Vector3<f64>; MAX_NODES_PER_ELEMENT]) {
    debug_assert!(kernel.technology().uses_mean_dilatation());
    let ppe = kernel.points_per_element();
    let mut gradient = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
    let (mut current, mut reference) = (0.0, 0.0);
    for q in 0..ppe {
        let point = element * ppe + q;
        let f = kernel.deformation_gradient(point, positions);
        let jacobian = f.determinant();
        let inverse_transpose = f
            .try_inverse()
            .map_or_else(Matrix3::zeros, |inv| inv.transpose());
        let w = kernel.weight(point);
        for (g, shape_gradient) in gradient.iter_mut().zip(kernel.gradients(point)) {
            *g += inverse_transpose * shape_gradient * (jacobian * w);
        }
        current += jacobian * w;
        reference += w;
    }
    for g in &mut gradient {
        *g /= reference;
    }
    (current / reference, gradient)
}

/// F̄ = (J̄/J)^{1/3} F for every point's F in `f` (the plain F on entry).
pub(super) fn modify(kernel: &BlockKernel, element: usize, f: &mut [Matrix3<f64>]) {
    let mean = mean_dilatation(kernel, element, f);
    for point in f {
        *point *= (mean / point.determinant()).cbrt();
    }
}

/// Add the element's F-bar internal forces (module docs) to `forces`, from its current
/// `positions` and the Cauchy stresses at F̄. Returns the current volume
/// v = Σ_q w_q J_q [m³], and writes its gradient ∂v/∂x_a = Σ_q w_q J_q F_q⁻ᵀ ∇_X N_a(q)
/// [m²] into `volume_gradient` when given (the forces need both).
pub(super) fn add_element_forces(
    kernel: &BlockKernel,
    element: usize,
    positions: &[Vector3<f64>],
    stress: &[VoigtStress],
    forces: &mut [Vector3<f64>],
    volume_gradient: Option<&mut [Vector3<f64>]>,
) -> f64 {
    let forces_of = match kernel.technology() {
        Technology::Hex8FBar => element_forces::<8, 8>,
        Technology::Tet10FBar => element_forces::<4, 10>,
        other => unreachable!("{other:?} is not an F-bar technology"),
    };
    forces_of(kernel, element, positions, stress, forces, volume_gradient)
}

/// [`add_element_forces`] for elements of N nodes and P points.
fn element_forces<const P: usize, const N: usize>(
    kernel: &BlockKernel,
    element: usize,
    positions: &[Vector3<f64>],
    stress: &[VoigtStress],
    forces: &mut [Vector3<f64>],
    volume_gradient: Option<&mut [Vector3<f64>]>,
) -> f64 {
    debug_assert_eq!(kernel.points_per_element(), P);
    debug_assert_eq!(kernel.nodes_per_element(), N);
    let mut f = [Matrix3::zeros(); P];
    let mut spatial = [[Vector3::zeros(); N]; P];
    let mut mean_gradient = [Vector3::zeros(); N];
    let mut current_volume = 0.0;
    let mut reference_volume = 0.0;
    for q in 0..P {
        let point = element * P + q;
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
    if let Some(out) = volume_gradient {
        out[..N].copy_from_slice(&mean_gradient);
    }
    for g in &mut mean_gradient {
        *g /= current_volume;
    }
    let mean = current_volume / reference_volume;
    for q in 0..P {
        let sigma = symmetric_from_voigt(&stress[q]);
        let third_trace = sigma.trace() / 3.0;
        let scale = kernel.weight(element * P + q) * mean;
        for a in 0..N {
            let g = spatial[q][a];
            forces[a] += (sigma * g + (mean_gradient[a] - g) * third_trace) * scale;
        }
    }
    current_volume
}

/// Add the consistent stiffness K_ai,bk = ∂f_a,i/∂x_b,k [N/m] of the F-bar element (dense,
/// row-major 3N × 3N, row 3a + i, column 3b + k) at its current `positions`, from the
/// Cauchy stresses `stress` and material tangents 𝔸 = ∂P/∂F `tangents` at F̄.
///
/// The forces are f_a,i = Σ_q w_q P̄_q : A^q_ai with P̄ = P(F̄) and
/// A_ai = ∂F̄/∂x_a,i = α [e_i ⊗ G_a + ⅓ c_ai F], α = (J̄/J)^{1/3},
/// c_ai = b̄_ai − g_ai, g_a = F⁻ᵀ G_a (G_a = ∇_X N_a at the point), so
///
/// K_ai,bk = Σ_q w_q [A_ai : 𝔸 : A_bk + P̄ : ∂A_ai/∂x_b,k],
/// ∂A_ai/∂x_b,k = ⅓ c_bk A_ai + ⅓ α [c_ai e_k ⊗ G_b + F ∂c_ai/∂x_b,k],
///
/// with ∂α/∂x_b,k = ⅓ α c_bk, ∂F/∂x_b,k = e_k ⊗ G_b, ∂g_ai/∂x_b,k = −g_bi g_ak and
/// ∂b̄_ai/∂x_b,k = (1/v) Σ_p w_p J_p (g^p_bk g^p_ai − g^p_bi g^p_ak) − b̄_ai b̄_bk, the last
/// term being the rank-one coupling of every point through J̄ = v/V. So
///
/// P̄ : ∂A_ai/∂x_b,k = ⅓ c_bk (P̄ : A_ai) + ⅓ α [c_ai (P̄ G_b)_k
///                     + (P̄ : F)(∂b̄_ai/∂x_b,k + g_bi g_ak)].
///
/// The forces derive from the potential Σ_q w_q Ψ(F̄_q) for a hyperelastic material, and
/// K is then symmetric; it is unsymmetric exactly when 𝔸 is (the solver then uses LU).
/// With `upper_blocks_only` (for a symmetric 𝔸) only the blocks K_ab with b ≥ a are added.
pub(super) fn add_element_stiffness(
    kernel: &BlockKernel,
    element: usize,
    positions: &[Vector3<f64>],
    stress: &[VoigtStress],
    tangents: &[Tangent],
    stiffness: &mut [f64],
    upper_blocks_only: bool,
) {
    let stiffness_of = match kernel.technology() {
        Technology::Hex8FBar => element_stiffness::<8, 8>,
        Technology::Tet10FBar => element_stiffness::<4, 10>,
        other => unreachable!("{other:?} is not an F-bar technology"),
    };
    stiffness_of(
        kernel,
        element,
        positions,
        stress,
        tangents,
        stiffness,
        upper_blocks_only,
    );
}

/// [`add_element_stiffness`] for elements of N nodes and P points.
fn element_stiffness<const P: usize, const N: usize>(
    kernel: &BlockKernel,
    element: usize,
    positions: &[Vector3<f64>],
    stress: &[VoigtStress],
    tangents: &[Tangent],
    stiffness: &mut [f64],
    upper_blocks_only: bool,
) {
    let dofs = 3 * N;
    debug_assert!(dofs <= MAX_DOFS);
    debug_assert_eq!(kernel.points_per_element(), P);
    debug_assert_eq!(kernel.nodes_per_element(), N);
    debug_assert_eq!(stiffness.len(), dofs * dofs);
    let mut f = [Matrix3::zeros(); P];
    let mut jacobian = [0.0; P];
    let mut spatial = [[Vector3::zeros(); N]; P];
    let mut mean_gradient = [Vector3::zeros(); N];
    let (mut current_volume, mut reference_volume) = (0.0, 0.0);
    for q in 0..P {
        let point = element * P + q;
        f[q] = kernel.deformation_gradient(point, positions);
        jacobian[q] = f[q].determinant();
        let inverse_transpose = f[q]
            .try_inverse()
            .map_or_else(Matrix3::zeros, |inv| inv.transpose());
        let w = kernel.weight(point);
        for (a, g) in kernel.gradients(point).iter().enumerate() {
            spatial[q][a] = inverse_transpose * g;
            mean_gradient[a] += spatial[q][a] * (jacobian[q] * w);
        }
        current_volume += jacobian[q] * w;
        reference_volume += w;
    }
    for g in &mut mean_gradient {
        *g /= current_volume;
    }
    let mean = current_volume / reference_volume;
    // ∂b̄_ai/∂x_b,k, row 3a + i, column 3b + k.
    let mut mean_derivative = [[0.0; MAX_DOFS]; MAX_DOFS];
    for q in 0..P {
        let scale = kernel.weight(element * P + q) * jacobian[q] / current_volume;
        let g = &spatial[q];
        for a in 0..N {
            let first = if upper_blocks_only { a } else { 0 };
            for i in 0..3 {
                let row = &mut mean_derivative[3 * a + i];
                for b in first..N {
                    for k in 0..3 {
                        row[3 * b + k] += scale * (g[b][k] * g[a][i] - g[b][i] * g[a][k]);
                    }
                }
            }
        }
    }
    for a in 0..N {
        let first = if upper_blocks_only { a } else { 0 };
        for i in 0..3 {
            for b in first..N {
                for k in 0..3 {
                    mean_derivative[3 * a + i][3 * b + k] -=
                        mean_gradient[a][i] * mean_gradient[b][k];
                }
            }
        }
    }
    // With A_ai = α [e_i ⊗ G_a + ⅓ c_ai F], the material term splits into the plain
    // stiffness α² (e_i ⊗ G_a) : 𝔸 : (e_k ⊗ G_b) and rank-one terms in c:
    // α² [⅓ c_bk h_ai + ⅓ c_ai h'_bk + (1/9) c_ai c_bk F : 𝔸 : F],
    // h_ai = (e_i ⊗ G_a) : 𝔸 : F, h'_bk = F : 𝔸 : (e_k ⊗ G_b). With the geometric term,
    // per point K_ai,bk += c_bk X_ai + c_ai Y_bk + Z c_ai c_bk + T g_bi g_ak, and the
    // ∂b̄/∂x term once per element with Σ_q T_q.
    let mut mean_coefficient = 0.0;
    for q in 0..P {
        let point = element * P + q;
        let w = kernel.weight(point);
        let gradients = kernel.gradients(point);
        let alpha = (mean / jacobian[q]).cbrt();
        let f_bar = f[q] * alpha;
        let piola = first_piola_from_cauchy(&f_bar, &stress[q]);
        let piola_dot_f = piola.dot(&f[q]);
        let vec_f = SVector::<f64, 9>::from_column_slice(f[q].as_slice());
        let tangent_f = tangents[q] * vec_f;
        let f_tangent = tangents[q].transpose() * vec_f;
        let f_tangent_f = vec_f.dot(&tangent_f);
        let g = &spatial[q];
        let mut c = [0.0; MAX_DOFS];
        let mut x = [0.0; MAX_DOFS];
        let mut y = [0.0; MAX_DOFS];
        for a in 0..N {
            let piola_g = piola * gradients[a];
            for i in 0..3 {
                let col = 3 * a + i;
                c[col] = mean_gradient[a][i] - g[a][i];
                let mut h = 0.0;
                let mut h_transposed = 0.0;
                for j in 0..3 {
                    h += gradients[a][j] * tangent_f[i + 3 * j];
                    h_transposed += gradients[a][j] * f_tangent[i + 3 * j];
                }
                let piola_dot_a = alpha * (piola_g[i] + c[col] / 3.0 * piola_dot_f);
                x[col] = w * (alpha * alpha / 3.0 * h + piola_dot_a / 3.0);
                y[col] = w * (alpha * alpha / 3.0 * h_transposed + alpha / 3.0 * piola_g[i]);
            }
        }
        let z = w * alpha * alpha / 9.0 * f_tangent_f;
        let t = w * alpha / 3.0 * piola_dot_f;
        mean_coefficient += t;
        super::stiffness::add_point_stiffness(
            gradients,
            w * alpha * alpha,
            &tangents[q],
            stiffness,
            upper_blocks_only,
        );
        for (row, out) in stiffness.chunks_exact_mut(dofs).enumerate() {
            let (a, i) = (row / 3, row % 3);
            let first = if upper_blocks_only { a } else { 0 };
            let (c_row, x_row) = (c[row], x[row]);
            let zc = z * c_row;
            for (b, block) in out.chunks_exact_mut(3).enumerate().skip(first) {
                let tg = t * g[b][i];
                for k in 0..3 {
                    let col = 3 * b + k;
                    block[k] += c[col] * (x_row + zc) + c_row * y[col] + tg * g[a][k];
                }
            }
        }
    }
    for (row, out) in stiffness.chunks_exact_mut(dofs).enumerate() {
        let first = if upper_blocks_only { 3 * (row / 3) } else { 0 };
        for (o, m) in out[first..]
            .iter_mut()
            .zip(&mean_derivative[row][first..dofs])
        {
            *o += mean_coefficient * m;
        }
    }
}
