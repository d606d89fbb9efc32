//! Volumetric locking: linear tets (one point) and fully integrated hex8 cannot deform at
//! constant volume in most modes, so a nearly incompressible material (bulk modulus K
//! large against the shear modulus μ) makes them far too stiff. The F-bar hex8, the
//! nodally averaged tet4, the tet10 and the F-bar tet10 do not lock in the end force
//! (docs/stability.md has the measured stiffening; plain tet10's pressure does oscillate
//! from point to point at K/μ = 10⁴, which the F-bar tet10 removes).

use nalgebra::Vector3;

use musclefem_core::element::Technology;
use musclefem_materials::{Material, PointBlock, PointResponse, Tangent, VoigtStress};

/// K/μ from which a locking element gets a warning (ν = (3K/μ − 2)/(6K/μ + 2) ≥ 0.476).
/// Measured on the clamped cube at 3 elements per edge (`tests/stability.rs`): tet4 pulls
/// back 1.3× as hard as the F-bar hex8 at K/μ = 10, 3.0× at 100, 15× at 1000, 132× at 10⁴.
pub const LOCKING_BULK_TO_SHEAR: f64 = 20.0;

/// The small-strain bulk modulus K [Pa] of `material`: from the tangent at F = I,
/// ∂P₁₁/∂F₁₁ = K + 4μ/3 (the smallest over the three axes, so an anisotropic material's
/// stiff fiber direction does not count).
pub fn small_strain_bulk_modulus(material: &dyn Material) -> Option<f64> {
    let mu = small_strain_shear_modulus(material)?;
    let tangent = small_strain_tangent(material)?;
    // F_ii sits at 4 i.
    let longitudinal = (0..3)
        .map(|i| tangent[(4 * i, 4 * i)])
        .fold(f64::INFINITY, f64::min);
    let bulk = longitudinal - 4.0 * mu / 3.0;
    (bulk.is_finite() && bulk > 0.0).then_some(bulk)
}

/// A warning when `technology` locks with `material` (K/μ ≥ [`LOCKING_BULK_TO_SHEAR`]).
pub fn locking_warning(technology: Technology, material: &dyn Material) -> Option<String> {
    let name = match technology {
        Technology::Tet4 => "tet4",
        Technology::Hex8Full => "hex8-full",
        _ => return None,
    };
    let mu = small_strain_shear_modulus(material)?;
    let ratio = small_strain_bulk_modulus(material)? / mu;
    let poisson = (3.0 * ratio - 2.0) / (6.0 * ratio + 2.0);
    (ratio >= LOCKING_BULK_TO_SHEAR).then(|| {
        format!(
            "{name} locks with this nearly incompressible material (K/mu = {ratio:.3e}, \
             nu = {poisson:.4}): its response is too stiff; use hex8-fbar, tet10-fbar, tet10 \
             or tet4-nodal-average (explicit)"
        )
    })
}

/// The material tangent ∂P/∂F at F = I, t = 0 (vec(F) column-major: F_ij sits at i + 3 j),
/// or `None` when the material refuses the point.
pub(super) fn small_strain_tangent(material: &dyn Material) -> Option<Tangent> {
    let identity = [nalgebra::Matrix3::identity()];
    let state = material.initial_state(1);
    let points = PointBlock {
        time: 0.0,
        dt: 1e-3,
        deformation_gradient_old: &identity,
        deformation_gradient_new: &identity,
        fiber_direction: &[Vector3::x()],
        state_old: &state,
    };
    let mut stress = [VoigtStress::zeros()];
    let mut state_new = state.clone();
    let mut tangent = [Tangent::zeros()];
    let mut response = PointResponse {
        cauchy_stress: &mut stress,
        state_new: &mut state_new,
        tangent: Some(&mut tangent),
    };
    material.update(&points, &mut response).ok()?;
    Some(tangent[0])
}

/// The smallest of ∂P_ij/∂F_ij (i ≠ j) at F = I, t = 0, from the material's tangent: the
/// shear modulus μ of an isotropic material at small strain [Pa].
pub fn small_strain_shear_modulus(material: &dyn Material) -> Option<f64> {
    let tangent = small_strain_tangent(material)?;
    let shear = [(0, 1), (1, 0), (1, 2), (2, 1), (0, 2), (2, 0)]
        .iter()
        .map(|&(i, j)| tangent[(i + 3 * j, i + 3 * j)])
        .fold(f64::INFINITY, f64::min);
    (shear.is_finite() && shear > 0.0).then_some(shear)
}

#[cfg(test)]
mod tests {
    use super::*;
    use musclefem_materials::MaterialLibrary;
    use std::collections::BTreeMap;

    fn neo_hookean(d: f64) -> std::sync::Arc<dyn Material> {
        let parameters = BTreeMap::from([("mu".to_string(), 1e4), ("D".to_string(), d)]);
        MaterialLibrary::with_builtins()
            .create("neo-hookean", &parameters)
            .unwrap()
    }

    #[test]
    fn the_bulk_modulus_is_two_over_d() {
        let k = small_strain_bulk_modulus(neo_hookean(2e-5).as_ref()).unwrap();
        assert!((k - 1e5).abs() < 1e-6 * 1e5, "{k}");
    }

    #[test]
    fn only_locking_elements_with_a_nearly_incompressible_material_are_warned() {
        let soft = neo_hookean(2e-5); // K/μ = 10
        let stiff = neo_hookean(2e-7); // K/μ = 1000
        assert!(locking_warning(Technology::Tet4, soft.as_ref()).is_none());
        let warning = locking_warning(Technology::Tet4, stiff.as_ref()).unwrap();
        assert!(warning.contains("tet4 locks") && warning.contains("K/mu = 1.000e3"));
        assert!(locking_warning(Technology::Hex8Full, stiff.as_ref()).is_some());
        for free in [
            Technology::Hex8FBar,
            Technology::Tet10,
            Technology::Tet10FBar,
            Technology::Tet4NodalAverage,
        ] {
            assert!(locking_warning(free, stiff.as_ref()).is_none(), "{free:?}");
        }
    }
}
