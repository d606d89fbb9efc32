//! Compressible neo-Hookean solid (isotropic, hyperelastic, no state).
//!
//! Strain energy per reference volume [J/m³ = Pa]:
//!
//! W = μ/2 (Ī₁ − 3) + (J − 1)²/D,
//!
//! with Ī₁ = tr(J^(-2/3) F Fᵀ), μ the shear modulus [Pa] and D the compressibility
//! [1/Pa] (bulk modulus κ = 2/D), the same volumetric term as the Hill muscle model.
//! Cauchy stress: σ = (μ/J) dev(B̄) + p I, p = 2(J − 1)/D.

use std::sync::Arc;

use crate::material::VoigtStress;
use crate::material::{PointBlock, PointResponse, StateVariable};
use crate::parameters::{Bound, ParameterSet, ParameterSpec};
use crate::registry::MaterialRegistration;
use crate::tensor::{
    IsochoricSplit, decoupled_tangent, deviatoric_voigt, symmetric_from_voigt,
    volumetric_kirchhoff_slope, volumetric_pressure,
};
use crate::{Material, MaterialError};

/// Declared parameters: shear modulus and compressibility.
pub const NEO_HOOKEAN_PARAMETERS: [ParameterSpec; 2] = [
    ParameterSpec::new(
        "mu",
        "Pa",
        11_370.0,
        Bound::Exclusive(0.0),
        Bound::Unbounded,
        "shear modulus (default 2bc of the Hill matrix, Table 1)",
    ),
    ParameterSpec::new(
        "D",
        "1/Pa",
        5.0e-9,
        Bound::Exclusive(0.0),
        Bound::Unbounded,
        "compressibility, bulk modulus = 2/D",
    ),
];

/// The compressible neo-Hookean material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NeoHookean {
    /// Shear modulus μ [Pa].
    pub shear_modulus: f64,
    /// Compressibility D [1/Pa].
    pub compressibility: f64,
}

impl NeoHookean {
    /// Cauchy stress σ = (μ/J) dev(B̄) + 2(J − 1)/D I (Voigt order).
    #[inline]
    pub fn cauchy_stress(&self, split: &IsochoricSplit) -> VoigtStress {
        let pressure = volumetric_pressure(split.jacobian, self.compressibility);
        let mut stress = deviatoric_voigt(&split.b_bar) * (self.shear_modulus / split.jacobian);
        for i in 0..3 {
            stress[i] += pressure;
        }
        stress
    }

    fn from_parameters(p: &ParameterSet) -> Result<Arc<dyn Material>, MaterialError> {
        Ok(Arc::new(NeoHookean {
            shear_modulus: p.get("mu")?,
            compressibility: p.get("D")?,
        }))
    }
}

impl Material for NeoHookean {
    fn name(&self) -> &str {
        "neo-hookean"
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
            let stress = self.cauchy_stress(&split);
            response.cauchy_stress[point] = stress;
            if let Some(tangents) = tangents.as_deref_mut() {
                let tau = symmetric_from_voigt(&stress) * split.jacobian;
                let f_bar_t = split.f_bar().transpose();
                let d_jp_dj = volumetric_kirchhoff_slope(split.jacobian, self.compressibility);
                // τ = dev(μ B̄) + J p I: dM = μ (dF̄ F̄ᵀ + F̄ dF̄ᵀ).
                tangents[point] = decoupled_tangent(&split, &tau, d_jp_dj, |d_f_bar| {
                    let d_b_bar = d_f_bar * f_bar_t;
                    (d_b_bar + d_b_bar.transpose()) * self.shear_modulus
                });
            }
        }
        Ok(())
    }
}

inventory::submit! {
    MaterialRegistration {
        name: "neo-hookean",
        description: "compressible neo-Hookean solid: W = mu/2 (I1bar - 3) + (J - 1)^2 / D",
        parameters: &NEO_HOOKEAN_PARAMETERS,
        build: NeoHookean::from_parameters,
    }
}
