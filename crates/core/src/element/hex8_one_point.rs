//! One-point hexahedron with the uniform (mean) gradient and stiffness-type hourglass
//! control (Flanagan & Belytschko 1981, "A uniform strain hexahedron and quadrilateral
//! with orthogonal hourglass control", IJNME 17:679–706), total Lagrangian.
//!
//! **Mean gradient.** The one point at the centre uses
//! B̄_a = (1/V) ∫_V ∇_X N_a dV [1/m], V = ∫_V dV [m³] the reference volume. The integrand
//! J₀⁻ᵀ ∇_ξ N_a det J₀ = cof(J₀) ∇_ξ N_a is a polynomial of degree ≤ 2 in each of ξ, η,
//! ζ, so the 2×2×2 Gauss rule integrates it exactly. Then Σ_a X_a ⊗ B̄_a = I and
//! Σ_a B̄_a = 0 on any (distorted) element, so F = Σ_a x_a ⊗ B̄_a reproduces every linear
//! field x = A X + b exactly (F = A), and the forces f_a = V P B̄_a = ∫ P ∇_X N_a dV of a
//! constant first Piola–Kirchhoff stress P [Pa] are those of full integration: the
//! constant-stress patch test holds. One volume constraint per element: no volumetric
//! locking.
//!
//! **Hourglass modes.** With the hourglass base vectors over the 8 nodes (C3D8 order,
//! (ξ_a, η_a, ζ_a) the corners of [−1, 1]³) h¹_a = η_a ζ_a, h² = ζ_a ξ_a, h³ = ξ_a η_a,
//! h⁴ = ξ_a η_a ζ_a, the Flanagan–Belytschko hourglass vectors are
//! γ^α_a = h^α_a − (Σ_b h^α_b X_b) · B̄_a (dimensionless). They are orthogonal to every
//! linear field: Σ_a γ^α_a = 0 and Σ_a X_a γ^α_a = 0. The generalized hourglass
//! displacements q^α = Σ_a x_a γ^α_a = Σ_a u_a γ^α_a [m] (u = x − X; the X part vanishes)
//! therefore vanish for every linear field, rigid rotations included, and pick up exactly
//! the nodal motions the centre point does not see: the displacement modes
//! Γ^α_a = h^α_a − Σ_i (h^α · B̄_i) X_ia leave F = I but give q ≠ 0.
//!
//! **Stiffness-type control** in the reference configuration: the hourglass energy and
//! the internal hourglass forces (added to the element's internal forces, f = ∂E/∂x) are
//! E_hg = ½ k Σ_α |q^α|² [J], f_a = k Σ_α q^α γ^α_a [N],
//! k = G_hg V Σ_a |B̄_a|² / 24 [N/m],
//! with G_hg the technology's `hourglass_modulus` [Pa]. E_hg is invariant under a rigid
//! rotation of the current configuration (q → R q), so the forces are objective; it
//! uses no material tangent and no rate, so it is conservative and its work shows up in
//! the solver's internal energy. The scaling: on a cube of side h, Σ_a |B̄_a|² = 3/(2h²)
//! and γ = h, so the mode u_x = s ξη (nodal values s h³) has q = 8 s and
//! E_hg = 2 G_hg h s², which is the shear part 2 μ h s² of the energy the fully
//! integrated hex8 gives the same mode in linear elasticity (its volumetric part is
//! (2/3) λ h s²): G_hg = μ would make the three ξη-type modes as stiff as full
//! integration's deviatoric response (the ξηζ mode gets 2 G_hg h s² against
//! (8/9) μ h s²). [`DEFAULT_HOURGLASS_FACTOR`] × μ, 5 % of that, is the default of
//! [`super::Technology::hex8_one_point`]. Use the shear modulus, not the P-wave modulus
//! λ + 2μ of Flanagan–Belytschko: for nearly incompressible tissue λ ≫ μ and an
//! hourglass stiffness scaled with λ would bring back the locking the one point removes.
//! Since G_hg ≤ μ the hourglass stiffness does not shorten the stable explicit step,
//! which is set by the dilatational modulus.

use nalgebra::Vector3;

use super::{BlockKernel, ElementError, Technology, hex8_full};
use crate::mesh::{ElementBlock, ElementShape, Nodes};

/// Default ratio of the hourglass modulus G_hg to the material's shear modulus.
pub const DEFAULT_HOURGLASS_FACTOR: f64 = 0.05;

/// Hourglass data of every element of a block.
#[derive(Debug, Clone)]
pub(super) struct Hourglass {
    /// γ^α_a: 4 modes × 8 nodes per element.
    vectors: Vec<[[f64; 8]; 4]>,
    /// k per element [N/m].
    stiffness: Vec<f64>,
}

/// h^α_a = η_a ζ_a, ζ_a ξ_a, ξ_a η_a, ξ_a η_a ζ_a over the reference corners.
pub(super) fn hourglass_base() -> [[f64; 8]; 4] {
    let mut h = [[0.0; 8]; 4];
    for (a, c) in ElementShape::Hex8.reference_nodes().iter().enumerate() {
        h[0][a] = c[1] * c[2];
        h[1][a] = c[2] * c[0];
        h[2][a] = c[0] * c[1];
        h[3][a] = c[0] * c[1] * c[2];
    }
    h
}

/// Mean gradients B̄_a, V, γ^α_a and k of every element of `block`.
pub(super) fn reference_data(
    nodes: &Nodes,
    block: &ElementBlock,
    hourglass_modulus: f64,
) -> Result<BlockKernel, ElementError> {
    let technology = Technology::Hex8OnePoint { hourglass_modulus };
    if !(hourglass_modulus.is_finite() && hourglass_modulus >= 0.0) {
        return Err(ElementError::InvalidParameter {
            block: block.name.clone(),
            technology,
            reason: format!("hourglass modulus {hourglass_modulus} Pa must be finite and >= 0"),
        });
    }
    let full = hex8_full::reference_data(nodes, block, technology)?;
    let base = hourglass_base();
    let count = block.len();
    let mut gradients = Vec::with_capacity(count * 8);
    let mut weights = Vec::with_capacity(count);
    let mut vectors = Vec::with_capacity(count);
    let mut stiffness = Vec::with_capacity(count);
    let mut coords = [Vector3::zeros(); 8];
    for (element, ids) in block.elements().enumerate() {
        let volume = full.reference_volume(element);
        let mut mean = [Vector3::zeros(); 8];
        for q in 0..8 {
            let point = element * 8 + q;
            let w = full.weight(point);
            for (m, g) in mean.iter_mut().zip(full.gradients(point)) {
                *m += g * w;
            }
        }
        mean.iter_mut().for_each(|m| *m /= volume);
        // Positions from the element's centroid: Σ_b h_b = 0, so h·X does not change,
        // and the round-off does not grow with the distance from the origin.
        nodes.gather(ids, &mut coords);
        let centroid = coords.iter().sum::<Vector3<f64>>() / 8.0;
        let mut gamma = [[0.0; 8]; 4];
        for (g, h) in gamma.iter_mut().zip(&base) {
            let hx: Vector3<f64> = h
                .iter()
                .zip(&coords)
                .map(|(hb, x)| (x - centroid) * *hb)
                .sum();
            for a in 0..8 {
                g[a] = h[a] - hx.dot(&mean[a]);
            }
        }
        let sum_squares: f64 = mean.iter().map(|m| m.norm_squared()).sum();
        gradients.extend_from_slice(&mean);
        weights.push(volume);
        vectors.push(gamma);
        stiffness.push(hourglass_modulus * volume * sum_squares / 24.0);
    }
    Ok(BlockKernel {
        technology,
        nodes_per_element: 8,
        points_per_element: 1,
        gradients,
        weights,
        hourglass: Some(Hourglass { vectors, stiffness }),
    })
}

impl Hourglass {
    /// γ^α_a and k of `element`.
    pub fn of(&self, element: usize) -> (&[[f64; 8]; 4], f64) {
        (&self.vectors[element], self.stiffness[element])
    }

    /// q^α = Σ_a x_a γ^α_a [m] of `element` at its current `positions` (taken from the
    /// first node, which Σ_a γ^α_a = 0 allows, for round-off).
    pub fn modes(&self, element: usize, positions: &[Vector3<f64>]) -> [Vector3<f64>; 4] {
        let gamma = &self.vectors[element];
        let origin = positions[0];
        let mut q = [Vector3::zeros(); 4];
        for (qa, g) in q.iter_mut().zip(gamma) {
            for (x, ga) in positions.iter().zip(g) {
                *qa += (x - origin) * *ga;
            }
        }
        q
    }

    /// E_hg = ½ k Σ_α |q^α|² [J].
    pub fn energy(&self, element: usize, positions: &[Vector3<f64>]) -> f64 {
        let q = self.modes(element, positions);
        0.5 * self.stiffness[element] * q.iter().map(|v| v.norm_squared()).sum::<f64>()
    }

    /// Add f_a = k Σ_α q^α γ^α_a [N] to `forces`.
    pub fn add_forces(
        &self,
        element: usize,
        positions: &[Vector3<f64>],
        forces: &mut [Vector3<f64>],
    ) {
        let q = self.modes(element, positions);
        let (gamma, k) = self.of(element);
        for (a, f) in forces.iter_mut().enumerate().take(8) {
            for (qa, g) in q.iter().zip(gamma) {
                *f += qa * (k * g[a]);
            }
        }
    }
}
