//! Uncoupled Mooney–Rivlin solid (isotropic, hyperelastic, no state): FEBio's
//! "Mooney-Rivlin" (an uncoupled material, parameters c1, c2, k).
//!
//! Strain energy per reference volume [J/m³ = Pa]:
//!
//! W = c₁ (Ī₁ − 3) + c₂ (Ī₂ − 3) + k/2 (ln J)²,
//!
//! with C̄ = J^(-2/3) FᵀF, Ī₁ = tr C̄, Ī₂ = ½ (Ī₁² − tr C̄²), c₁, c₂ [Pa] (shear modulus
//! μ = 2 (c₁ + c₂)) and k the bulk modulus [Pa]. The volumetric term is FEBio's default for
//! its uncoupled materials, U = k/2 (ln J)² (FEUncoupledMaterial; FEBio offers
//! k/2 (J − 1)² only as a non-default "pressure model"), so that a FEBio model's c1, c2, k
//! mean the same here. With c₂ = 0 the isochoric part is the project's `neo-hookean` with
//! μ = 2c₁; only the volumetric terms differ (k/2 (ln J)² against (J − 1)²/D, equal to
//! second order in J − 1 for k = 2/D).
//!
//! Kirchhoff stress τ = dev(2 (c₁ + c₂ Ī₁) B̄ − 2 c₂ B̄²) + k ln J I, B̄ = J^(-2/3) F Fᵀ;
//! Cauchy stress σ = τ / J [Pa].

use std::sync::Arc;

use nalgebra::Matrix3;

use crate::material::{PointBlock, PointResponse, StateVariable};
use crate::parameters::{Bound, ParameterSet, ParameterSpec};
use crate::registry::MaterialRegistration;
use crate::tensor::{
    IsochoricSplit, decoupled_tangent, deviatoric, logarithmic_volumetric_kirchhoff,
    logarithmic_volumetric_kirchhoff_slope, symmetric_from_voigt, voigt_from_symmetric,
};
use crate::{Material, MaterialError};

/// Declared parameters: the Mooney–Rivlin constants and the bulk modulus.
pub const MOONEY_RIVLIN_PARAMETERS: [ParameterSpec; 3] = [
    ParameterSpec::new(
        "c1",
        "Pa",
        5_685.0,
        Bound::Unbounded,
        Bound::Unbounded,
        "coefficient of I1bar - 3 (default half neo-hookean's mu)",
    ),
    ParameterSpec::new(
        "c2",
        "Pa",
        0.0,
        Bound::Unbounded,
        Bound::Unbounded,
        "coefficient of I2bar - 3; shear modulus = 2 (c1 + c2) > 0",
    ),
    ParameterSpec::new(
        "k",
        "Pa",
        4.0e8,
        Bound::Exclusive(0.0),
        Bound::Unbounded,
        "bulk modulus of U = k/2 (ln J)^2 (default neo-hookean's 2/D)",
    ),
];

/// The uncoupled Mooney–Rivlin material (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MooneyRivlin {
    /// c₁ [Pa].
    pub c1: f64,
    /// c₂ [Pa].
    pub c2: f64,
    /// Bulk modulus k [Pa].
    pub bulk_modulus: f64,
}

impl MooneyRivlin {
    /// M = 2 (c₁ + c₂ Ī₁) B̄ − 2 c₂ B̄², whose deviatoric part is the isochoric Kirchhoff
    /// stress [Pa].
    #[inline]
    pub fn isochoric_stress_like(&self, b_bar: &Matrix3<f64>, i1_bar: f64) -> Matrix3<f64> {
        b_bar * (2.0 * (self.c1 + self.c2 * i1_bar)) - b_bar * b_bar * (2.0 * self.c2)
    }

    /// dM[dB̄] = 2 (c₁ + c₂ Ī₁) dB̄ + 2 c₂ tr(dB̄) B̄ − 2 c₂ (dB̄ B̄ + B̄ dB̄).
    #[inline]
    pub fn isochoric_stress_like_derivative(
        &self,
        b_bar: &Matrix3<f64>,
        i1_bar: f64,
        d_b_bar: &Matrix3<f64>,
    ) -> Matrix3<f64> {
        d_b_bar * (2.0 * (self.c1 + self.c2 * i1_bar))
            + (b_bar * d_b_bar.trace() - d_b_bar * b_bar - b_bar * d_b_bar) * (2.0 * self.c2)
    }

    /// Kirchhoff stress τ [Pa] at `split`.
    pub fn kirchhoff_stress(&self, split: &IsochoricSplit) -> Matrix3<f64> {
        let b_bar = symmetric_from_voigt(&split.b_bar);
        let jp = logarithmic_volumetric_kirchhoff(split.jacobian, self.bulk_modulus);
        deviatoric(&self.isochoric_stress_like(&b_bar, split.i1_bar))
            + Matrix3::from_diagonal_element(jp)
    }

    fn from_parameters(p: &ParameterSet) -> Result<Arc<dyn Material>, MaterialError> {
        let material = MooneyRivlin {
            c1: p.get("c1")?,
            c2: p.get("c2")?,
            bulk_modulus: p.get("k")?,
        };
        check_shear_modulus("mooney-rivlin", material.c1, material.c2)?;
        Ok(Arc::new(material))
    }
}

/// The Mooney–Rivlin shear modulus 2 (c₁ + c₂) must be positive.
pub(crate) fn check_shear_modulus(material: &str, c1: f64, c2: f64) -> Result<(), MaterialError> {
    if c1 + c2 > 0.0 {
        Ok(())
    } else {
        Err(MaterialError::InconsistentParameters {
            material: material.to_string(),
            reason: format!(
                "the shear modulus 2 (c1 + c2) = {:e} Pa must be positive",
                2.0 * (c1 + c2)
            ),
        })
    }
}

impl Material for MooneyRivlin {
    fn name(&self) -> &str {
        "mooney-rivlin"
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
            let tau = self.kirchhoff_stress(&split);
            response.cauchy_stress[point] = voigt_from_symmetric(&(tau / split.jacobian));
            if let Some(tangents) = tangents.as_deref_mut() {
                let b_bar = symmetric_from_voigt(&split.b_bar);
                let f_bar_t = split.f_bar().transpose();
                let d_jp_dj =
                    logarithmic_volumetric_kirchhoff_slope(split.jacobian, self.bulk_modulus);
                tangents[point] = decoupled_tangent(&split, &tau, d_jp_dj, |d_f_bar| {
                    let d_b_bar = d_f_bar * f_bar_t;
                    let d_b_bar = d_b_bar + d_b_bar.transpose();
                    self.isochoric_stress_like_derivative(&b_bar, split.i1_bar, &d_b_bar)
                });
            }
        }
        Ok(())
    }
}

inventory::submit! {
    MaterialRegistration {
        name: "mooney-rivlin",
        description: "uncoupled Mooney-Rivlin (FEBio's Mooney-Rivlin): W = c1 (I1bar - 3) + c2 (I2bar - 3) + k/2 (ln J)^2",
        parameters: &MOONEY_RIVLIN_PARAMETERS,
        build: MooneyRivlin::from_parameters,
    }
}
