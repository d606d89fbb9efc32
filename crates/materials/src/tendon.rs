//! Tendon and aponeurosis: a soft neo-Hookean matrix reinforced by collagen fibers that
//! resist extension only, through a toe region (transversely isotropic, hyperelastic, no
//! state).
//!
//! Strain energy per reference volume [J/m³ = Pa]:
//!
//! W = μ/2 (Ī₁ − 3) + W_f(e) + (J − 1)²/D,   e = (Ī₄ − 1)/2,
//!
//! with Ī₄ = |F̄ a₀|² the squared isochoric fiber stretch (a₀ the unit reference fiber
//! direction), e the fibers' Green strain, and the fibers' stress S(e) = dW_f/de [Pa]
//!
//! ```text
//! S = 0                      for e ≤ 0     (slack: no compression),
//! S = E_f e² / (2 e_t)       for 0 < e ≤ e_t (the toe region, the crimp straightening),
//! S = E_f (e − e_t/2)        for e > e_t   (linear),
//! ```
//!
//! so the fibers' stiffness dS/de rises continuously from 0 to E_f over the toe strain
//! e_t (a tangent without jumps, which Newton's method needs where a tendon goes slack).
//! E_f [Pa] is the fibers' Young's modulus beyond the toe (the tissue's is about
//! E_f + 3μ); across the fibers, in shear and in bending, only the matrix's μ acts, so the
//! tendon is stiff in tension and supple where real tendon is.
//!
//! Kirchhoff stress τ = dev(μ B̄ + S ā ⊗ ā) + J p I, with ā = F̄ a₀ and p = 2(J − 1)/D;
//! Cauchy stress σ = τ / J.
//!
//! Defaults: E_f = 1 GPa, between the 0.66 GPa measured on the human patellar tendon in
//! vitro (Johnson et al. 1994, J Orthop Res 12:796) and the 1.2 GPa of human tendon in
//! vivo (Maganaris & Paul 1999, J Physiol 521:307); e_t = 0.02, the toe region of
//! tendon's stress–strain curve ending at a few percent strain (the same shape as
//! Blankevoort & Huiskes 1991's ligament law, whose toe spans 2 ε_l = 6 % with their
//! ε_l = 0.03; a shorter one for the stiffer tendon); μ = 1 MPa, the order of ligament's shear
//! modulus (Weiss, Gardiner & Bonifasi-Lista 2002, J Biomech 35:943); D = 5e-10 1/Pa
//! (bulk modulus 4 GPa, a tenth of the muscle's D), so that the isochoric split leaves the
//! fibers their modulus: with the muscle's D = 5e-9 the tissue's small-strain modulus along
//! the fibers would be 0.78 GPa, with 5e-10 it is 0.98 GPa (ν = 0.46; see the tests).

use std::sync::Arc;

use nalgebra::{Matrix3, Vector3};

use crate::material::{PointBlock, PointResponse, StateVariable};
use crate::parameters::{Bound, ParameterSet, ParameterSpec};
use crate::registry::MaterialRegistration;
use crate::tensor::{
    IsochoricSplit, decoupled_tangent, deviatoric, symmetric_from_voigt, voigt_from_symmetric,
    volumetric_kirchhoff_slope, volumetric_pressure,
};
use crate::{Material, MaterialError};

/// Declared parameters: matrix shear modulus, fiber modulus, toe strain and
/// compressibility.
pub const TENDON_PARAMETERS: [ParameterSpec; 4] = [
    ParameterSpec::new(
        "mu",
        "Pa",
        1.0e6,
        Bound::Exclusive(0.0),
        Bound::Unbounded,
        "matrix shear modulus",
    ),
    ParameterSpec::new(
        "E_f",
        "Pa",
        1.0e9,
        Bound::Inclusive(0.0),
        Bound::Unbounded,
        "fiber Young's modulus beyond the toe region",
    ),
    ParameterSpec::new(
        "e_toe",
        "1",
        0.02,
        Bound::Inclusive(0.0),
        Bound::Exclusive(1.0),
        "fiber strain at the end of the toe region (0: linear from slack)",
    ),
    ParameterSpec::new(
        "D",
        "1/Pa",
        5.0e-10,
        Bound::Exclusive(0.0),
        Bound::Unbounded,
        "compressibility, bulk modulus = 2/D",
    ),
];

/// The fiber-reinforced tendon material (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tendon {
    /// Matrix shear modulus μ [Pa].
    pub shear_modulus: f64,
    /// Fiber Young's modulus E_f [Pa] beyond the toe region.
    pub fiber_modulus: f64,
    /// Fiber (Green) strain e_t at the end of the toe region [1].
    pub toe_strain: f64,
    /// Compressibility D [1/Pa].
    pub compressibility: f64,
}

impl Tendon {
    /// The fibers' stress S(e) [Pa] and stiffness dS/de [Pa] at Green strain `e` (see the
    /// module documentation).
    pub fn fiber_stress(&self, e: f64) -> (f64, f64) {
        let (modulus, toe) = (self.fiber_modulus, self.toe_strain);
        if e <= 0.0 {
            (0.0, 0.0)
        } else if e <= toe {
            (modulus * e * e / (2.0 * toe), modulus * e / toe)
        } else {
            (modulus * (e - 0.5 * toe), modulus)
        }
    }

    /// The Kirchhoff stress τ [Pa] at `split` with the isochoric fiber ā = F̄ a₀, and the
    /// fibers' stress and stiffness S, dS/de [Pa].
    fn kirchhoff_stress(
        &self,
        split: &IsochoricSplit,
        fiber: &Vector3<f64>,
    ) -> (Matrix3<f64>, (f64, f64)) {
        let strain = 0.5 * (fiber.norm_squared() - 1.0);
        let (stress, stiffness) = self.fiber_stress(strain);
        let m = symmetric_from_voigt(&split.b_bar) * self.shear_modulus
            + fiber * fiber.transpose() * stress;
        let jp = split.jacobian * volumetric_pressure(split.jacobian, self.compressibility);
        (
            deviatoric(&m) + Matrix3::from_diagonal_element(jp),
            (stress, stiffness),
        )
    }

    fn from_parameters(p: &ParameterSet) -> Result<Arc<dyn Material>, MaterialError> {
        Ok(Arc::new(Tendon {
            shear_modulus: p.get("mu")?,
            fiber_modulus: p.get("E_f")?,
            toe_strain: p.get("e_toe")?,
            compressibility: p.get("D")?,
        }))
    }
}

impl Material for Tendon {
    fn name(&self) -> &str {
        "tendon"
    }

    fn state_variables(&self) -> &[StateVariable] {
        &[]
    }

    fn compute(
        &self,
        block: &PointBlock,
        response: &mut PointResponse,
    ) -> Result<(), MaterialError> {
        let mut tangents = response.tangent.as_deref_mut();
        for (point, f) in block.deformation_gradient_new.iter().enumerate() {
            let split = IsochoricSplit::new(f);
            let a0 = block.fiber_direction[point].normalize();
            let fiber = split.f_bar() * a0;
            let (tau, (fiber_stress, fiber_stiffness)) = self.kirchhoff_stress(&split, &fiber);
            response.cauchy_stress[point] = voigt_from_symmetric(&(tau / split.jacobian));
            if let Some(tangents) = tangents.as_deref_mut() {
                let f_bar_t = split.f_bar().transpose();
                let d_jp_dj = volumetric_kirchhoff_slope(split.jacobian, self.compressibility);
                // dM = μ (dF̄ F̄ᵀ + F̄ dF̄ᵀ) + S' de ā⊗ā + S (dā⊗ā + ā⊗dā), dā = dF̄ a₀,
                // de = ā·dā.
                tangents[point] = decoupled_tangent(&split, &tau, d_jp_dj, |d_f_bar| {
                    let d_b_bar = d_f_bar * f_bar_t;
                    let mut d_m = (d_b_bar + d_b_bar.transpose()) * self.shear_modulus;
                    if fiber_stress > 0.0 || fiber_stiffness > 0.0 {
                        let d_fiber = d_f_bar * a0;
                        let d_strain = fiber.dot(&d_fiber);
                        let cross = d_fiber * fiber.transpose();
                        d_m += fiber * fiber.transpose() * (fiber_stiffness * d_strain)
                            + (cross + cross.transpose()) * fiber_stress;
                    }
                    d_m
                });
            }
        }
        Ok(())
    }
}

inventory::submit! {
    MaterialRegistration {
        name: "tendon",
        description: "fiber-reinforced tendon: neo-Hookean matrix mu, fibers in extension only (toe region to e_toe, then E_f), (J - 1)^2 / D",
        parameters: &TENDON_PARAMETERS,
        build: Tendon::from_parameters,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Tangent, VoigtStress, finite_difference_tangent};

    /// The default tendon, without its toe region when `linear`.
    fn tendon_with(linear: bool) -> Tendon {
        Tendon {
            shear_modulus: 1.0e6,
            fiber_modulus: 1.0e9,
            toe_strain: if linear { 0.0 } else { 0.02 },
            compressibility: 5.0e-10,
        }
    }

    fn tendon() -> Tendon {
        tendon_with(true)
    }

    /// σ of `material` at `f` with fiber along x.
    fn stress(material: &Tendon, f: &Matrix3<f64>) -> (VoigtStress, Tangent) {
        let fibers = [Vector3::x()];
        let mut stress = [VoigtStress::zeros()];
        let mut tangent = [Tangent::zeros()];
        let block = PointBlock {
            time: 0.0,
            dt: 0.0,
            deformation_gradient_old: std::slice::from_ref(f),
            deformation_gradient_new: std::slice::from_ref(f),
            fiber_direction: &fibers,
            state_old: &[],
        };
        let mut response = PointResponse {
            cauchy_stress: &mut stress,
            state_new: &mut [],
            tangent: Some(&mut tangent),
        };
        (material as &dyn Material)
            .update(&block, &mut response)
            .unwrap();
        (stress[0], tangent[0])
    }

    /// Uniaxial stress along the fibers: stretch λ, lateral stretch found so that the
    /// lateral stress vanishes (bisection).
    fn uniaxial(material: &Tendon, stretch: f64) -> f64 {
        let (mut low, mut high) = (0.5, 1.5);
        let mut axial = 0.0;
        for _ in 0..80 {
            let lateral = 0.5 * (low + high);
            let f = Matrix3::from_diagonal(&Vector3::new(stretch, lateral, lateral));
            let (s, _) = stress(material, &f);
            axial = s[0];
            if s[1] > 0.0 {
                high = lateral;
            } else {
                low = lateral;
            }
        }
        axial
    }

    /// The small-strain Young's modulus along the fibers of the linearized model:
    /// with a = 2E_f/9 + 2μ/3 and κ = 2/D, ν = (κ − a)/(a + 2κ) and E = 3a(1 + ν)
    /// (E → E_f + 3μ as κ → ∞).
    fn small_strain_modulus(material: &Tendon) -> (f64, f64) {
        let a = 2.0 * material.fiber_modulus / 9.0 + 2.0 * material.shear_modulus / 3.0;
        let kappa = 2.0 / material.compressibility;
        let poisson = (kappa - a) / (a + 2.0 * kappa);
        (3.0 * a * (1.0 + poisson), poisson)
    }

    #[test]
    fn the_fibers_give_the_modulus_in_extension_and_nothing_in_compression() {
        let strain = 1e-6;
        for compressibility in [5.0e-10, 5.0e-9, 1.0e-12] {
            let material = Tendon {
                compressibility,
                ..tendon()
            };
            let (expected, _) = small_strain_modulus(&material);
            let modulus = uniaxial(&material, 1.0 + strain) / strain;
            assert!(
                (modulus / expected - 1.0).abs() < 1e-4,
                "D {compressibility:e}: {modulus:e} vs {expected:e}"
            );
        }
        // The default: 0.98 GPa, ν = 0.46; nearly incompressible, E_f + 3μ.
        let (default, poisson) = small_strain_modulus(&tendon());
        assert!((default / 0.976e9 - 1.0).abs() < 1e-3 && (poisson - 0.459).abs() < 1e-3);
        let stiff = Tendon {
            compressibility: 1e-14,
            ..tendon()
        };
        let limit = stiff.fiber_modulus + 3.0 * stiff.shear_modulus;
        assert!((small_strain_modulus(&stiff).0 / limit - 1.0).abs() < 1e-4);
        // In compression along the fibers only the matrix resists: about 3μ.
        let material = tendon();
        let compliant = -uniaxial(&material, 1.0 - strain) / strain;
        assert!(
            (compliant / (3.0 * material.shear_modulus) - 1.0).abs() < 0.01,
            "{compliant:e}"
        );
    }

    #[test]
    fn the_toe_region_stiffens_continuously_to_the_linear_part() {
        let material = tendon_with(false);
        let (e_t, modulus) = (material.toe_strain, material.fiber_modulus);
        // Continuous stress and stiffness at both ends of the toe.
        assert_eq!(material.fiber_stress(0.0), (0.0, 0.0));
        let below = material.fiber_stress(e_t * (1.0 - 1e-12));
        let above = material.fiber_stress(e_t * (1.0 + 1e-12));
        assert!((below.0 - above.0).abs() < 1e-9 * above.0);
        assert!((below.1 - above.1).abs() < 1e-9 * modulus);
        assert!((above.0 - modulus * e_t / 2.0).abs() < 1e-6 * above.0);
        // The stiffness is the derivative of the stress inside the toe.
        let e = 0.3 * e_t;
        let h = 1e-9;
        let slope = (material.fiber_stress(e + h).0 - material.fiber_stress(e - h).0) / (2.0 * h);
        assert!((slope / material.fiber_stress(e).1 - 1.0).abs() < 1e-6);
        // Along the fibers the tissue is soft in the toe and stiff beyond: secant moduli
        // at 0.5 % and at 4 % strain.
        let soft = uniaxial(&material, 1.005) / 0.005;
        let stiff = (uniaxial(&material, 1.045) - uniaxial(&material, 1.04)) / 0.005;
        assert!(
            soft < 0.3 * modulus && stiff > 0.85 * modulus,
            "{soft:e} {stiff:e}"
        );
    }

    #[test]
    fn the_tangent_is_the_derivative_of_the_stress() {
        let fibers = [Vector3::new(1.0, 0.3, -0.2)];
        for material in [tendon_with(true), tendon_with(false)] {
            for f in [
                // In the linear part, inside the toe, and slack.
                Matrix3::new(1.05, 0.02, -0.01, 0.03, 0.97, 0.04, -0.02, 0.01, 0.99),
                Matrix3::new(
                    1.012, 0.002, -0.001, 0.003, 0.995, 0.004, -0.002, 0.001, 0.998,
                ),
                Matrix3::new(0.95, 0.02, -0.01, 0.03, 1.01, 0.04, -0.02, 0.01, 1.03),
            ] {
                let mut stress = [VoigtStress::zeros()];
                let mut analytic = [Tangent::zeros()];
                let block = PointBlock {
                    time: 0.0,
                    dt: 0.0,
                    deformation_gradient_old: std::slice::from_ref(&f),
                    deformation_gradient_new: std::slice::from_ref(&f),
                    fiber_direction: &fibers,
                    state_old: &[],
                };
                let mut response = PointResponse {
                    cauchy_stress: &mut stress,
                    state_new: &mut [],
                    tangent: Some(&mut analytic),
                };
                material.compute(&block, &mut response).unwrap();
                let mut numeric = [Tangent::zeros()];
                finite_difference_tangent(&material, &block, &mut numeric).unwrap();
                let error = (analytic[0] - numeric[0]).norm() / analytic[0].norm();
                assert!(error < 1e-6, "{error:e}");
            }
        }
    }
}
