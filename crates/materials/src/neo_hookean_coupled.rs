//! Coupled compressible neo-Hookean solid (isotropic, hyperelastic, no state): the
//! "neo-Hookean" of FEBio (which takes E and v), of felupe (`NeoHookeCompressible`, which
//! takes mu and lmbda) and of many papers and textbooks (Bonet & Wood, Holzapfel).
//!
//! Strain energy per reference volume [J/m³ = Pa]:
//!
//! W = μ/2 (I₁ − 3) − μ ln J + λ/2 (ln J)²,
//!
//! with I₁ = tr(F Fᵀ) (not the isochoric Ī₁), J = det F, μ the shear modulus and λ the
//! first Lamé constant [Pa]; at small strain it is linear elasticity with these Lamé
//! constants (bulk modulus κ = λ + 2μ/3, Young's modulus E = μ(3λ + 2μ)/(λ + μ), Poisson's
//! ratio ν = λ / (2(λ + μ))). From FEBio's E and v: μ = E / (2(1 + v)),
//! λ = E v / ((1 + v)(1 − 2v)).
//!
//! Stresses: P = μ (F − F⁻ᵀ) + λ ln J F⁻ᵀ, σ = [μ (B − I) + λ ln J I] / J [Pa].
//! Tangent: ∂P_iJ/∂F_kL = μ δ_ik δ_JL + (μ − λ ln J) F⁻¹_Jk F⁻¹_Li + λ F⁻¹_Ji F⁻¹_Lk.
//!
//! It is not the project's `neo-hookean`, which splits F into its isochoric and volumetric
//! parts (W = μ/2 (Ī₁ − 3) + (J − 1)²/D): with equal μ and bulk modulus the two agree at
//! small strain and in the incompressible limit, but not at finite strain of a compressible
//! solid (at ν = 0.3 and stretch 1.5 in uniaxial stress the coupled one carries 11.8 % more
//! force; see `tests/closed_form_uniaxial.rs`).

use std::sync::Arc;

use nalgebra::Matrix3;

use crate::material::{PointBlock, PointResponse, StateVariable, Tangent, VoigtStress};
use crate::parameters::{Bound, ParameterSet, ParameterSpec};
use crate::registry::MaterialRegistration;
use crate::tensor::left_cauchy_green_voigt;
use crate::{Material, MaterialError};

/// Declared parameters: the Lamé constants μ and λ.
pub const NEO_HOOKEAN_COUPLED_PARAMETERS: [ParameterSpec; 2] = [
    ParameterSpec::new(
        "mu",
        "Pa",
        11_370.0,
        Bound::Exclusive(0.0),
        Bound::Unbounded,
        "shear modulus (second Lame constant; default that of neo-hookean)",
    ),
    ParameterSpec::new(
        "lambda",
        "Pa",
        4.0e8,
        Bound::Inclusive(0.0),
        Bound::Unbounded,
        "first Lame constant, bulk modulus = lambda + 2 mu / 3",
    ),
];

/// The coupled compressible neo-Hookean material (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NeoHookeanCoupled {
    /// Shear modulus μ [Pa].
    pub shear_modulus: f64,
    /// First Lamé constant λ [Pa].
    pub lame_lambda: f64,
}

impl NeoHookeanCoupled {
    /// The material with Young's modulus `e` [Pa] and Poisson's ratio `nu` (FEBio's
    /// parameters).
    pub fn from_young_poisson(e: f64, nu: f64) -> Self {
        NeoHookeanCoupled {
            shear_modulus: e / (2.0 * (1.0 + nu)),
            lame_lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        }
    }

    /// Cauchy stress σ = [μ (B − I) + λ ln J I] / J (Voigt order) [Pa].
    #[inline]
    pub fn cauchy_stress(&self, f: &Matrix3<f64>) -> VoigtStress {
        let jacobian = f.determinant();
        let pressure_like = self.lame_lambda * jacobian.ln() - self.shear_modulus;
        let mut stress = left_cauchy_green_voigt(f) * self.shear_modulus;
        for i in 0..3 {
            stress[i] += pressure_like;
        }
        stress / jacobian
    }

    /// ∂P/∂F on column-major vec(F) [Pa] (see the module documentation).
    pub fn tangent(&self, f: &Matrix3<f64>) -> Tangent {
        let f_inv = f.try_inverse().unwrap_or_else(Matrix3::zeros);
        let (mu, lambda) = (self.shear_modulus, self.lame_lambda);
        let cross = mu - lambda * f.determinant().ln();
        let mut tangent = Tangent::zeros();
        for l in 0..3 {
            for k in 0..3 {
                for j in 0..3 {
                    for i in 0..3 {
                        let identity = if i == k && j == l { mu } else { 0.0 };
                        tangent[(i + 3 * j, k + 3 * l)] = identity
                            + cross * f_inv[(j, k)] * f_inv[(l, i)]
                            + lambda * f_inv[(j, i)] * f_inv[(l, k)];
                    }
                }
            }
        }
        tangent
    }

    fn from_parameters(p: &ParameterSet) -> Result<Arc<dyn Material>, MaterialError> {
        Ok(Arc::new(NeoHookeanCoupled {
            shear_modulus: p.get("mu")?,
            lame_lambda: p.get("lambda")?,
        }))
    }
}

impl Material for NeoHookeanCoupled {
    fn name(&self) -> &str {
        "neo-hookean-coupled"
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
            response.cauchy_stress[point] = self.cauchy_stress(f);
            if let Some(tangents) = tangents.as_deref_mut() {
                tangents[point] = self.tangent(f);
            }
        }
        Ok(())
    }
}

inventory::submit! {
    MaterialRegistration {
        name: "neo-hookean-coupled",
        description: "coupled compressible neo-Hookean (FEBio's neo-Hookean, felupe's NeoHookeCompressible): W = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2",
        parameters: &NEO_HOOKEAN_COUPLED_PARAMETERS,
        build: NeoHookeanCoupled::from_parameters,
    }
}
