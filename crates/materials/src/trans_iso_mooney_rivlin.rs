//! Transversely isotropic Mooney–Rivlin solid for ligament and tendon (hyperelastic, no
//! state): Weiss, Maker & Govindjee 1996 (Comput Methods Appl Mech Eng 135:107), FEBio's
//! "trans iso Mooney-Rivlin" (an uncoupled material, parameters c1, c2, c3, c4, c5,
//! lam_max, k, with the fiber along the element's fiber direction).
//!
//! Strain energy per reference volume [J/m³ = Pa]:
//!
//! W = c₁ (Ī₁ − 3) + c₂ (Ī₂ − 3) + F₂(λ̃) + k/2 (ln J)²,
//!
//! the matrix and volume as in [`crate::mooney_rivlin`], λ̃ = |F̄ a₀| = √Ī₄ the isochoric
//! fiber stretch (a₀ the unit reference fiber direction) and the fibers' energy given by
//! their stress-like function g(λ̃) = λ̃ dF₂/dλ̃ [Pa]:
//!
//! ```text
//! g = 0                            for λ̃ < 1          (slack: no compression),
//! g = c₃ (exp(c₄ (λ̃ − 1)) − 1)      for 1 ≤ λ̃ < λ_max  (the toe: crimped collagen
//!                                                      straightening),
//! g = c₅ λ̃ + c₆                     for λ̃ ≥ λ_max      (straight fibers, linear),
//! ```
//!
//! with c₆ = c₃ (exp(c₄ (λ_max − 1)) − 1) − c₅ λ_max so that g is continuous at λ_max
//! (its slope is continuous only if c₃ c₄ exp(c₄ (λ_max − 1)) = c₅, as with the defaults).
//!
//! Kirchhoff stress τ = dev(2 (c₁ + c₂ Ī₁) B̄ − 2 c₂ B̄² + g(λ̃)/Ī₄ ā ⊗ ā) + k ln J I,
//! ā = F̄ a₀; Cauchy stress σ = τ / J [Pa]. In uniaxial stress along the fibers the fibers
//! add g to the axial Kirchhoff stress (less its deviatoric share).
//!
//! This differs from the project's `tendon` (a neo-Hookean matrix, fibers quadratic in
//! their Green strain through the toe then linear, (J − 1)²/D): a FEBio or literature
//! ligament model (Weiss 1996; Gardiner & Weiss 2003 for the human MCL) is given in these
//! parameters. FEBio (since 3.x) reads c3 = 0 as "derive c3 from c5 for a smooth
//! transition"; here c3 must be given (> 0).
//!
//! Defaults: a tendon of the same stiffness as the built-in `tendon`: matrix μ = 2c₁ =
//! 1 MPa, c₂ = 0; fibers straight at λ_max = 1.02 (2 % stretch) and of modulus c₅ = 1 GPa
//! beyond; c₄ = 100 and c₃ = c₅ / (c₄ exp(c₄ (λ_max − 1))) = 1.3534 MPa, so that the
//! fibers' stiffness is continuous; k = 4 GPa (the `tendon`'s 2/D).

use std::sync::Arc;

use nalgebra::{Matrix3, Vector3};

use crate::material::{PointBlock, PointResponse, StateVariable};
use crate::mooney_rivlin::{MooneyRivlin, check_shear_modulus};
use crate::parameters::{Bound, ParameterSet, ParameterSpec};
use crate::registry::MaterialRegistration;
use crate::tensor::{
    IsochoricSplit, decoupled_tangent, deviatoric, logarithmic_volumetric_kirchhoff,
    logarithmic_volumetric_kirchhoff_slope, symmetric_from_voigt, voigt_from_symmetric,
};
use crate::{Material, MaterialError};

/// Declared parameters, named as in FEBio.
pub const TRANS_ISO_MOONEY_RIVLIN_PARAMETERS: [ParameterSpec; 7] = [
    ParameterSpec::new(
        "c1",
        "Pa",
        0.5e6,
        Bound::Unbounded,
        Bound::Unbounded,
        "matrix coefficient of I1bar - 3",
    ),
    ParameterSpec::new(
        "c2",
        "Pa",
        0.0,
        Bound::Unbounded,
        Bound::Unbounded,
        "matrix coefficient of I2bar - 3; 2 (c1 + c2) > 0",
    ),
    ParameterSpec::new(
        "c3",
        "Pa",
        1.353_352_832_366_127e6,
        Bound::Exclusive(0.0),
        Bound::Unbounded,
        "fiber toe: stress scale of c3 (exp(c4 (lam - 1)) - 1)",
    ),
    ParameterSpec::new(
        "c4",
        "1",
        100.0,
        Bound::Exclusive(0.0),
        Bound::Unbounded,
        "fiber toe: exponential rate",
    ),
    ParameterSpec::new(
        "c5",
        "Pa",
        1.0e9,
        Bound::Inclusive(0.0),
        Bound::Unbounded,
        "fiber modulus of the linear region (lam >= lam_max)",
    ),
    ParameterSpec::new(
        "lam_max",
        "1",
        1.02,
        Bound::Inclusive(1.0),
        Bound::Unbounded,
        "fiber stretch at which the fibers are straight (end of the toe)",
    ),
    ParameterSpec::new(
        "k",
        "Pa",
        4.0e9,
        Bound::Exclusive(0.0),
        Bound::Unbounded,
        "bulk modulus of U = k/2 (ln J)^2",
    ),
];

/// The transversely isotropic Mooney–Rivlin material (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TransIsoMooneyRivlin {
    /// Matrix and volume: c₁, c₂, k.
    pub matrix: MooneyRivlin,
    /// Toe stress scale c₃ [Pa].
    pub c3: f64,
    /// Toe exponential rate c₄ [1].
    pub c4: f64,
    /// Linear-region fiber modulus c₅ [Pa].
    pub c5: f64,
    /// Fiber stretch λ_max at the end of the toe [1].
    pub lam_max: f64,
}

impl TransIsoMooneyRivlin {
    /// The fibers' g(λ̃) = λ̃ dF₂/dλ̃ and its derivative dg/dλ̃ [Pa] at isochoric fiber
    /// stretch `stretch` (see the module documentation).
    pub fn fiber_stress(&self, stretch: f64) -> (f64, f64) {
        if stretch < 1.0 {
            (0.0, 0.0)
        } else if stretch < self.lam_max {
            let e = (self.c4 * (stretch - 1.0)).exp();
            (self.c3 * (e - 1.0), self.c3 * self.c4 * e)
        } else {
            let c6 =
                self.c3 * ((self.c4 * (self.lam_max - 1.0)).exp() - 1.0) - self.c5 * self.lam_max;
            (self.c5 * stretch + c6, self.c5)
        }
    }

    /// Kirchhoff stress τ [Pa] at `split` with the isochoric fiber ā = F̄ a₀, and the
    /// fibers' h = g/Ī₄ and dh/dĪ₄ [Pa].
    fn kirchhoff_stress(
        &self,
        split: &IsochoricSplit,
        fiber: &Vector3<f64>,
    ) -> (Matrix3<f64>, (f64, f64)) {
        let i4_bar = fiber.norm_squared();
        let stretch = i4_bar.sqrt();
        let (g, dg) = self.fiber_stress(stretch);
        let h = g / i4_bar;
        let dh = dg / (2.0 * stretch * i4_bar) - g / (i4_bar * i4_bar);
        let b_bar = symmetric_from_voigt(&split.b_bar);
        let m =
            self.matrix.isochoric_stress_like(&b_bar, split.i1_bar) + fiber * fiber.transpose() * h;
        let jp = logarithmic_volumetric_kirchhoff(split.jacobian, self.matrix.bulk_modulus);
        (deviatoric(&m) + Matrix3::from_diagonal_element(jp), (h, dh))
    }

    fn from_parameters(p: &ParameterSet) -> Result<Arc<dyn Material>, MaterialError> {
        let material = TransIsoMooneyRivlin {
            matrix: MooneyRivlin {
                c1: p.get("c1")?,
                c2: p.get("c2")?,
                bulk_modulus: p.get("k")?,
            },
            c3: p.get("c3")?,
            c4: p.get("c4")?,
            c5: p.get("c5")?,
            lam_max: p.get("lam_max")?,
        };
        check_shear_modulus(
            "trans-iso-mooney-rivlin",
            material.matrix.c1,
            material.matrix.c2,
        )?;
        Ok(Arc::new(material))
    }
}

impl Material for TransIsoMooneyRivlin {
    fn name(&self) -> &str {
        "trans-iso-mooney-rivlin"
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
            let (tau, (h, dh)) = self.kirchhoff_stress(&split, &fiber);
            response.cauchy_stress[point] = voigt_from_symmetric(&(tau / split.jacobian));
            if let Some(tangents) = tangents.as_deref_mut() {
                let b_bar = symmetric_from_voigt(&split.b_bar);
                let f_bar_t = split.f_bar().transpose();
                let d_jp_dj = logarithmic_volumetric_kirchhoff_slope(
                    split.jacobian,
                    self.matrix.bulk_modulus,
                );
                // dM = dM_matrix + dh ā⊗ā + h (dā⊗ā + ā⊗dā), dā = dF̄ a₀,
                // dh = h'(Ī₄) 2 ā·dā.
                tangents[point] = decoupled_tangent(&split, &tau, d_jp_dj, |d_f_bar| {
                    let d_b_bar = d_f_bar * f_bar_t;
                    let d_b_bar = d_b_bar + d_b_bar.transpose();
                    let mut d_m = self.matrix.isochoric_stress_like_derivative(
                        &b_bar,
                        split.i1_bar,
                        &d_b_bar,
                    );
                    if h != 0.0 || dh != 0.0 {
                        let d_fiber = d_f_bar * a0;
                        let cross = d_fiber * fiber.transpose();
                        d_m += fiber * fiber.transpose() * (2.0 * dh * fiber.dot(&d_fiber))
                            + (cross + cross.transpose()) * h;
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
        name: "trans-iso-mooney-rivlin",
        description: "transversely isotropic Mooney-Rivlin for ligament and tendon (Weiss 1996; FEBio's trans iso Mooney-Rivlin): c1, c2 matrix, fibers exponential toe c3, c4 to lam_max then linear c5, k/2 (ln J)^2",
        parameters: &TRANS_ISO_MOONEY_RIVLIN_PARAMETERS,
        build: TransIsoMooneyRivlin::from_parameters,
    }
}
