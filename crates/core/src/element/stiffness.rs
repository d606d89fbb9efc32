//! Element stiffness (the consistent tangent of the internal forces) for the technologies
//! whose forces are a plain sum over integration points, f_a = Σ_q P(F_q) ∇_X N_a(q) w_q
//! with F_q = Σ_b x_b ⊗ ∇_X N_b(q) (no modification of F): then
//!
//! K_ab,ik = ∂f_a,i/∂x_b,k = Σ_q ∇_X N_a,J(q) 𝔸_iJkL(q) ∇_X N_b,L(q) w_q,
//!
//! 𝔸 = ∂P/∂F the material's first elasticity tensor, entry (i + 3J, k + 3L) of its 9×9
//! matrix on column-major vec(F). The element matrix is dense, row a·3 + i, column b·3 + k,
//! row-major. That covers [`Technology::Hex8Full`], [`Technology::Tet4`],
//! [`Technology::Tet10`] and the point part of [`Technology::Hex8OnePoint`] (whose
//! gradients are the mean ones); the one-point hex8 adds its hourglass stiffness, the
//! derivative of the hourglass forces f_a = k Σ_α q^α γ^α_a, q^α = Σ_b x_b γ^α_b, which is
//! K_ab,ik = k Σ_α γ^α_a γ^α_b δ_ik.
//!
//! F-bar (hex8 and tet10) couples every point to the element's mean dilatation, so its tangent has extra
//! terms (through J̄ and the spatial gradients), derived and built in `fbar.rs`; it needs
//! the element's positions and stresses besides the tangents.

use nalgebra::Vector3;

use musclefem_materials::{Tangent, VoigtStress};

use super::{BlockKernel, Technology};
use crate::mesh::MAX_NODES_PER_ELEMENT;

impl BlockKernel {
    /// Whether [`Self::add_element_stiffness`] builds the consistent tangent of this
    /// kernel's internal forces (every per-element technology; not the nodally averaged
    /// tet4, whose tangent couples the 2-ring of elements).
    pub fn has_consistent_tangent(&self) -> bool {
        match self.technology {
            Technology::Hex8Full
            | Technology::Hex8OnePoint { .. }
            | Technology::Tet4
            | Technology::Tet10
            | Technology::Hex8FBar
            | Technology::Tet10FBar => true,
            Technology::Tet4NodalAverage => false,
        }
    }

    /// Size of the square element stiffness matrix: 3 × nodes per element.
    pub fn element_dofs(&self) -> usize {
        3 * self.nodes_per_element
    }

    /// Add the stiffness of `element` [N/m] to `stiffness` (dense, row-major,
    /// `element_dofs()`², row a·3 + i, column b·3 + k) at its current nodal `positions`
    /// [m], from the Cauchy stresses `stress` [Pa] and material tangents 𝔸 = ∂P/∂F [Pa] at
    /// its integration points (`points_per_element` of them, at the deformation gradients
    /// of [`Self::element_deformation_gradients`]). Positions and stresses enter F-bar's
    /// stiffness only. Returns false, adding nothing, when the technology has no
    /// consistent tangent (see [`Self::has_consistent_tangent`]).
    ///
    /// When every tangent has major symmetry ([`has_major_symmetry`]) K is symmetric: only
    /// its blocks K_ab with b ≥ a are computed, and the others mirrored (overwritten with
    /// the transposed upper blocks, so `stiffness` must then be symmetric on entry, zero as
    /// the solver passes it).
    pub fn add_element_stiffness(
        &self,
        element: usize,
        positions: &[Vector3<f64>],
        stress: &[VoigtStress],
        tangents: &[Tangent],
        stiffness: &mut [f64],
    ) -> bool {
        let symmetric = tangents.iter().all(has_major_symmetry);
        self.add_element_stiffness_with(element, positions, stress, tangents, stiffness, symmetric)
    }

    /// [`Self::add_element_stiffness`], computing only the blocks b ≥ a and mirroring them
    /// when `symmetric` (which the tangents must then have), every block otherwise.
    pub(crate) fn add_element_stiffness_with(
        &self,
        element: usize,
        positions: &[Vector3<f64>],
        stress: &[VoigtStress],
        tangents: &[Tangent],
        stiffness: &mut [f64],
        symmetric: bool,
    ) -> bool {
        if !self.has_consistent_tangent() {
            return false;
        }
        if self.technology.uses_mean_dilatation() {
            super::fbar::add_element_stiffness(
                self, element, positions, stress, tangents, stiffness, symmetric,
            );
            if symmetric {
                mirror_upper_blocks(stiffness, self.nodes_per_element);
            }
            return true;
        }
        let npe = self.nodes_per_element;
        let ppe = self.points_per_element;
        let dofs = 3 * npe;
        debug_assert_eq!(tangents.len(), ppe);
        debug_assert_eq!(stiffness.len(), dofs * dofs);
        for (q, tangent) in tangents.iter().enumerate() {
            let point = element * ppe + q;
            add_point_stiffness(
                self.gradients(point),
                self.weight(point),
                tangent,
                stiffness,
                symmetric,
            );
        }
        if symmetric {
            mirror_upper_blocks(stiffness, npe);
        }
        if let Some((gamma, k)) = self.hourglass_vectors(element) {
            for a in 0..npe {
                for b in 0..npe {
                    let kab = k * gamma.iter().map(|g| g[a] * g[b]).sum::<f64>();
                    for i in 0..3 {
                        stiffness[(3 * a + i) * dofs + 3 * b + i] += kab;
                    }
                }
            }
        }
        true
    }
}

/// Largest |𝔸 − 𝔸ᵀ| relative to the largest |𝔸| for a tangent to count as symmetric.
pub const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// Whether the tangent 𝔸 (9 × 9) has major symmetry 𝔸_iJkL = 𝔸_kLiJ, within
/// [`SYMMETRY_TOLERANCE`] of its largest entry (a hyperelastic material's has).
pub fn has_major_symmetry(tangent: &Tangent) -> bool {
    let values: &[f64; 81] = tangent.as_slice().try_into().expect("a 9 × 9 tangent");
    let largest = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut asymmetry: f64 = 0.0;
    for column in 0..9 {
        for row in column + 1..9 {
            asymmetry = asymmetry.max((values[row + 9 * column] - values[column + 9 * row]).abs());
        }
    }
    asymmetry <= SYMMETRY_TOLERANCE * largest
}

/// Copy the blocks K_ab with b > a of a square element stiffness over `nodes` nodes
/// (row-major, 3 × `nodes` square) onto the blocks K_ba = K_abᵀ.
fn mirror_upper_blocks(stiffness: &mut [f64], nodes: usize) {
    let dofs = 3 * nodes;
    for a in 0..nodes {
        for b in 0..a {
            for i in 0..3 {
                for k in 0..3 {
                    stiffness[(3 * a + i) * dofs + 3 * b + k] =
                        stiffness[(3 * b + k) * dofs + 3 * a + i];
                }
            }
        }
    }
}

/// Add one point's K_ab,ik = Σ_JL G_a,J 𝔸[(i + 3J), (k + 3L)] G_b,L w to `stiffness`
/// (row-major, 3 × `gradients.len()` square), from the point's reference gradients
/// G_a = ∇_X N_a [1/m], weight w [m³] and tangent 𝔸 [Pa]; only the blocks b ≥ a when
/// `upper_blocks_only`.
pub(super) fn add_point_stiffness(
    gradients: &[Vector3<f64>],
    weight: f64,
    tangent: &Tangent,
    stiffness: &mut [f64],
    upper_blocks_only: bool,
) {
    let dofs = 3 * gradients.len();
    // H_a[i][k + 3L] = Σ_J G_a,J 𝔸[(i + 3J), (k + 3L)] w, then K_ab,ik = Σ_L H_a G_b,L
    // (the tangent's 81 values column-major: entry (r, c) at 9c + r).
    let mut h = [[[0.0; 9]; 3]; MAX_NODES_PER_ELEMENT];
    let h = &mut h[..gradients.len()];
    let values: &[f64] = tangent.as_slice();
    for (ha, g) in h.iter_mut().zip(gradients) {
        let g = g * weight;
        for (column, c) in values.chunks_exact(9).enumerate() {
            ha[0][column] = g.x * c[0] + g.y * c[3] + g.z * c[6];
            ha[1][column] = g.x * c[1] + g.y * c[4] + g.z * c[7];
            ha[2][column] = g.x * c[2] + g.y * c[5] + g.z * c[8];
        }
    }
    for (a, (rows, ha)) in stiffness
        .chunks_exact_mut(3 * dofs)
        .zip(h.iter())
        .enumerate()
    {
        let first = if upper_blocks_only { a } else { 0 };
        for (out, hi) in rows.chunks_exact_mut(dofs).zip(ha) {
            for (o, g) in out[3 * first..]
                .chunks_exact_mut(3)
                .zip(&gradients[first..])
            {
                o[0] += hi[0] * g.x + hi[3] * g.y + hi[6] * g.z;
                o[1] += hi[1] * g.x + hi[4] * g.y + hi[7] * g.z;
                o[2] += hi[2] * g.x + hi[5] * g.y + hi[8] * g.z;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use nalgebra::Matrix3;

    use musclefem_materials::{Material, MaterialLibrary, PointBlock, PointResponse};

    use super::*;
    use crate::mesh::ElementShape;
    use crate::mesh::generate::{TetOrder, box_of_hexes, box_of_tets, distort};

    fn neo_hookean() -> Arc<dyn Material> {
        let params =
            std::collections::BTreeMap::from([("mu".to_string(), 1e4), ("D".to_string(), 1e-5)]);
        MaterialLibrary::with_builtins()
            .create("neo-hookean", &params)
            .unwrap()
    }

    /// The active Hill muscle (n2 = 1) with its fibers along x.
    fn hill() -> Arc<dyn Material> {
        let params = std::collections::BTreeMap::from([("n2".to_string(), 1.0)]);
        MaterialLibrary::with_builtins()
            .create("hill", &params)
            .unwrap()
    }

    /// The element stiffness of a distorted, deformed element equals the central finite
    /// difference of its internal forces (relative 1e-6), for every technology and the
    /// given material, and the stiffness mirrored from its blocks b ≥ a (taken when the
    /// tangent is symmetric) is the full computation's to 1e-13; returns the full
    /// computation's largest asymmetry relative to its largest entry.
    fn stiffness_is_the_derivative_of_the_forces(
        technology: Technology,
        material: Arc<dyn Material>,
    ) -> f64 {
        let size = [0.01, 0.012, 0.008];
        let mut mesh = match technology.shape() {
            ElementShape::Hex8 => box_of_hexes(size, [2, 2, 2]),
            ElementShape::Tet4 => box_of_tets(size, [2, 2, 2], TetOrder::Linear),
            ElementShape::Tet10 => box_of_tets(size, [2, 2, 2], TetOrder::Quadratic),
        }
        .unwrap();
        assert!(distort(&mut mesh, 0.3, 3).unwrap() > 0);
        let block = &mesh.blocks[0];
        let kernel = BlockKernel::new(&mesh.nodes, block, technology).unwrap();
        let a = Matrix3::new(1.2, 0.1, -0.05, 0.03, 0.9, 0.1, -0.02, 0.04, 1.05);
        let (npe, ppe) = (kernel.nodes_per_element(), kernel.points_per_element());
        let dofs = kernel.element_dofs();
        // An element with an interior node (the one the distortion moved).
        let element = block.len() / 2 + 1;
        let ids = block.element_nodes(element);
        let positions: Vec<Vector3<f64>> = ids
            .iter()
            .enumerate()
            .map(|(n, &id)| {
                let x = mesh.nodes.position(id as usize);
                a * x + Vector3::new(1e-4 * (n as f64).sin(), 2e-4 * (n as f64).cos(), 0.0)
            })
            .collect();
        let state_old = material.initial_state(ppe);
        let evaluate = |x: &[Vector3<f64>], tangents: Option<&mut [Tangent]>| {
            let mut f = vec![Matrix3::identity(); ppe];
            kernel.element_deformation_gradients(element, x, &mut f);
            let mut stress = vec![VoigtStress::zeros(); ppe];
            let mut state_new = state_old.clone();
            let points = PointBlock {
                time: 1.0,
                dt: 0.1,
                deformation_gradient_old: &vec![Matrix3::identity(); ppe],
                deformation_gradient_new: &f,
                fiber_direction: &vec![Vector3::x(); ppe],
                state_old: &state_old,
            };
            let mut response = PointResponse {
                cauchy_stress: &mut stress,
                state_new: &mut state_new,
                tangent: tangents,
            };
            material.update(&points, &mut response).unwrap();
            let mut forces = vec![Vector3::zeros(); npe];
            kernel.add_element_forces(element, x, &f, &stress, &mut forces, None);
            (forces, stress)
        };
        let mut tangents = vec![Tangent::zeros(); ppe];
        let (_, stress) = evaluate(&positions, Some(&mut tangents));
        let mut k = vec![0.0; dofs * dofs];
        assert!(kernel.add_element_stiffness(element, &positions, &stress, &tangents, &mut k));
        // The blocks b ≥ a mirrored (for a symmetric tangent) are the full computation's.
        let mut k_full = vec![0.0; dofs * dofs];
        assert!(kernel.add_element_stiffness_with(
            element,
            &positions,
            &stress,
            &tangents,
            &mut k_full,
            false
        ));
        let scale = k_full.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let mirror_error = k
            .iter()
            .zip(&k_full)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            mirror_error <= 1e-13 * scale,
            "{technology:?}: the mirrored stiffness differs by {mirror_error:e} of {scale:e}"
        );
        let h = 1e-7 * 0.005;
        let mut largest: f64 = 0.0;
        let mut error: f64 = 0.0;
        for b in 0..npe {
            for kk in 0..3 {
                let mut plus = positions.clone();
                let mut minus = positions.clone();
                plus[b][kk] += h;
                minus[b][kk] -= h;
                let (fp, fm) = (evaluate(&plus, None).0, evaluate(&minus, None).0);
                for a in 0..npe {
                    for i in 0..3 {
                        let numeric = (fp[a][i] - fm[a][i]) / (2.0 * h);
                        let analytic = k[(3 * a + i) * dofs + 3 * b + kk];
                        largest = largest.max(numeric.abs());
                        error = error.max((numeric - analytic).abs());
                    }
                }
            }
        }
        println!(
            "{technology:?}: largest stiffness entry {largest:.3e} N/m, largest error \
             {error:.3e} N/m"
        );
        assert!(
            error < 1e-6 * largest,
            "{technology:?}: {error} vs {largest}"
        );
        let mut asymmetry: f64 = 0.0;
        for r in 0..dofs {
            for c in 0..dofs {
                asymmetry = asymmetry.max((k_full[r * dofs + c] - k_full[c * dofs + r]).abs());
            }
        }
        asymmetry / largest
    }

    /// With the neo-Hookean tangent (major symmetry), the stiffness is symmetric.
    fn neo_hookean_stiffness_is_the_symmetric_derivative_of_the_forces(technology: Technology) {
        let asymmetry = stiffness_is_the_derivative_of_the_forces(technology, neo_hookean());
        assert!(asymmetry < 1e-12, "{technology:?}: asymmetry {asymmetry:e}");
    }

    #[test]
    fn hex8_full_stiffness_is_the_derivative_of_the_forces() {
        neo_hookean_stiffness_is_the_symmetric_derivative_of_the_forces(Technology::Hex8Full);
    }

    #[test]
    fn hex8_one_point_stiffness_is_the_derivative_of_the_forces() {
        neo_hookean_stiffness_is_the_symmetric_derivative_of_the_forces(
            Technology::hex8_one_point(1e4),
        );
    }

    #[test]
    fn tet4_stiffness_is_the_derivative_of_the_forces() {
        neo_hookean_stiffness_is_the_symmetric_derivative_of_the_forces(Technology::Tet4);
    }

    #[test]
    fn tet10_stiffness_is_the_derivative_of_the_forces() {
        neo_hookean_stiffness_is_the_symmetric_derivative_of_the_forces(Technology::Tet10);
    }

    #[test]
    fn fbar_stiffness_is_the_derivative_of_the_forces() {
        neo_hookean_stiffness_is_the_symmetric_derivative_of_the_forces(Technology::Hex8FBar);
    }

    /// The active Hill muscle: F-bar's stiffness matches the finite differences (1e-6).
    /// Its asymmetry is printed: F-bar's K is symmetric exactly when 𝔸 is (the forces
    /// derive from Σ w Ψ(F̄)), and Hill's tangent at this state was symmetric to round-off
    /// (3e-16), so this element does not exercise the LU path.
    #[test]
    fn fbar_stiffness_of_the_active_muscle_is_the_derivative_of_the_forces() {
        let asymmetry = stiffness_is_the_derivative_of_the_forces(Technology::Hex8FBar, hill());
        println!("Hill, F-bar: asymmetry {asymmetry:.3e} of the largest entry");
    }

    #[test]
    fn tet10_fbar_stiffness_is_the_derivative_of_the_forces() {
        neo_hookean_stiffness_is_the_symmetric_derivative_of_the_forces(Technology::Tet10FBar);
    }

    /// The active Hill muscle on the F-bar tet10, as on the F-bar hex8.
    #[test]
    fn tet10_fbar_stiffness_of_the_active_muscle_is_the_derivative_of_the_forces() {
        let asymmetry = stiffness_is_the_derivative_of_the_forces(Technology::Tet10FBar, hill());
        println!("Hill, F-bar tet10: asymmetry {asymmetry:.3e} of the largest entry");
    }

    #[test]
    fn full_hex8_stiffness_of_the_active_muscle_is_the_derivative_of_the_forces() {
        stiffness_is_the_derivative_of_the_forces(Technology::Hex8Full, hill());
    }
}
