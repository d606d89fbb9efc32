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

use nalgebra::Matrix3;

use crate::material::VoigtStress;
use crate::material::{PointBlock, PointResponse, StateVariable, Tangent};
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

    /// Cauchy stress at the split F, and with `tangent` the consistent tangent ∂P/∂F there.
    #[inline]
    fn point_response(&self, split: &IsochoricSplit, tangent: Option<&mut Tangent>) -> VoigtStress {
        let stress = self.cauchy_stress(split);
        if let Some(tangent) = tangent {
            let tau = symmetric_from_voigt(&stress) * split.jacobian;
            let f_bar_t = split.f_bar().transpose();
            let d_jp_dj = volumetric_kirchhoff_slope(split.jacobian, self.compressibility);
            // τ = dev(μ B̄) + J p I: dM = μ (dF̄ F̄ᵀ + F̄ dF̄ᵀ).
            *tangent = decoupled_tangent(split, &tau, d_jp_dj, |d_f_bar| {
                let d_b_bar = d_f_bar * f_bar_t;
                (d_b_bar + d_b_bar.transpose()) * self.shear_modulus
            });
        }
        stress
    }

    /// Cauchy stresses (and with `tangents` the tangents) of a block of points, as
    /// `<dyn Material>::update` gives them, with only the checks of what this material
    /// reads: each F_new finite with det F_new > 0, and each result finite (same errors
    /// as `update`). The explicit solver's one-point hexahedra call it on every step:
    /// their F at the start of the step was checked as the previous step's F_new, and the
    /// fiber direction, time and step, which `update` also checks, play no part in this
    /// material. A `stresses` or `tangents` of another length than the block is an error.
    pub fn accepted_block_stresses(
        &self,
        deformation_gradients: &[Matrix3<f64>],
        stresses: &mut [VoigtStress],
        mut tangents: Option<&mut [Tangent]>,
    ) -> Result<(), MaterialError> {
        let points = deformation_gradients.len();
        let shapes = [("cauchy_stress", stresses.len())]
            .into_iter()
            .chain(tangents.as_deref().map(|t| ("tangent", t.len())));
        for (what, found) in shapes {
            if found != points {
                return Err(MaterialError::BlockShape {
                    what,
                    expected: points,
                    found,
                });
            }
        }
        let non_finite = |point, what| MaterialError::NonFiniteResult {
            material: self.name().to_string(),
            point,
            what,
        };
        for (point, (f, out)) in deformation_gradients
            .iter()
            .zip(stresses.iter_mut())
            .enumerate()
        {
            if !f.sum().is_finite() {
                return Err(MaterialError::InvalidPoint {
                    point,
                    reason: format!("F_new has a non-finite entry: {f:?}"),
                });
            }
            let split = IsochoricSplit::new(f);
            if split.jacobian <= 0.0 {
                return Err(MaterialError::InvalidPoint {
                    point,
                    reason: format!(
                        "det F_new = {:e} <= 0 (inverted or collapsed element)",
                        split.jacobian
                    ),
                });
            }
            let tangent = tangents.as_deref_mut().map(|t| &mut t[point]);
            *out = self.point_response(&split, tangent);
        }
        // The results checked after the whole block, as `update` does.
        if let Some(point) = stresses.iter().position(|s| !s.sum().is_finite()) {
            return Err(non_finite(point, "Cauchy stress"));
        }
        if let Some(tangents) = tangents
            && let Some(point) = tangents.iter().position(|t| !t.sum().is_finite())
        {
            return Err(non_finite(point, "tangent"));
        }
        Ok(())
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

    fn as_neo_hookean(&self) -> Option<&NeoHookean> {
        Some(self)
    }

    fn compute(
        &self,
        block: &PointBlock,
        response: &mut PointResponse,
    ) -> Result<(), MaterialError> {
        let mut tangents = response.tangent.as_deref_mut();
        for (point, f) in block.deformation_gradient_new.iter().enumerate() {
            let tangent = tangents.as_deref_mut().map(|t| &mut t[point]);
            response.cauchy_stress[point] = self.point_response(&IsochoricSplit::new(f), tangent);
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

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;

    fn material() -> NeoHookean {
        NeoHookean {
            shear_modulus: 11_370.0,
            compressibility: 5.0e-9,
        }
    }

    type Responses = (Vec<VoigtStress>, Vec<Tangent>);

    /// Stresses, tangents and errors of `update` on the block of deformation gradients
    /// `f_new` (F_old = I, fibers along x).
    fn through_update(f_new: &[Matrix3<f64>]) -> Result<Responses, String> {
        let f_old = vec![Matrix3::identity(); f_new.len()];
        let fibers = vec![Vector3::x(); f_new.len()];
        let block = PointBlock {
            time: 0.1,
            dt: 1e-4,
            deformation_gradient_old: &f_old,
            deformation_gradient_new: f_new,
            fiber_direction: &fibers,
            state_old: &[],
        };
        let mut stresses = vec![VoigtStress::zeros(); f_new.len()];
        let mut tangents = vec![Tangent::zeros(); f_new.len()];
        let mut response = PointResponse {
            cauchy_stress: &mut stresses,
            state_new: &mut [],
            tangent: Some(&mut tangents),
        };
        let material: &dyn Material = &material();
        material
            .update(&block, &mut response)
            .map_err(|e| e.to_string())?;
        Ok((stresses, tangents))
    }

    fn fused(f_new: &[Matrix3<f64>]) -> Result<Responses, String> {
        let mut stresses = vec![VoigtStress::zeros(); f_new.len()];
        let mut tangents = vec![Tangent::zeros(); f_new.len()];
        material()
            .accepted_block_stresses(f_new, &mut stresses, Some(&mut tangents))
            .map_err(|e| e.to_string())?;
        let mut alone = vec![VoigtStress::zeros(); f_new.len()];
        material()
            .accepted_block_stresses(f_new, &mut alone, None)
            .map_err(|e| e.to_string())?;
        assert_eq!(
            alone, stresses,
            "the stresses do not depend on the tangents"
        );
        Ok((stresses, tangents))
    }

    #[test]
    fn the_fused_block_gives_updates_stresses_and_errors() {
        // Deformations from near-identity to large stretch and shear, J from 0.6 to 1.9.
        let f: Vec<Matrix3<f64>> = (0..40)
            .map(|k| {
                let s = k as f64 / 40.0;
                Matrix3::new(
                    0.8 + s,
                    0.3 * s,
                    -0.1 * s,
                    0.05,
                    1.0 - 0.2 * s,
                    0.2 * s * s,
                    -0.02 * s,
                    0.1,
                    0.9 + 0.1 * s,
                )
            })
            .collect();
        let (ours, reference) = (fused(&f).unwrap(), through_update(&f).unwrap());
        for (a, b) in ours.0.iter().zip(&reference.0) {
            assert_eq!(a.as_slice(), b.as_slice());
        }
        for (a, b) in ours.1.iter().zip(&reference.1) {
            assert_eq!(a.as_slice(), b.as_slice());
        }
        let mut inverted = f.clone();
        inverted[7] = Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -0.5);
        let error = fused(&inverted).unwrap_err();
        assert_eq!(error, through_update(&inverted).unwrap_err());
        assert!(
            error.contains("point 7") && error.contains("det F_new"),
            "{error}"
        );
        let mut not_finite = f;
        not_finite[3][(1, 2)] = f64::NAN;
        let error = fused(&not_finite).unwrap_err();
        assert_eq!(error, through_update(&not_finite).unwrap_err());
        assert!(
            error.contains("point 3") && error.contains("non-finite"),
            "{error}"
        );
    }
}
