//! examples/vumat/neo_hookean_umat.f through the UMAT adapter against the built-in
//! `neo-hookean` material: the same strain energy, so the same stress to round-off — in
//! uniaxial stress (the material-point driver), in simple shear under a rigid rotation, for
//! rotated deformations — and its DDSDDE, converted by the adapter, is the built-in's
//! analytic ∂P/∂F. A UMAT that leaves DDSDDE unset gets a finite-difference tangent from
//! the adapter, and `--tangent finite-difference` leaves it to the host.

mod support {
    pub mod builds;
    pub mod points;
}

use std::f64::consts::PI;
use std::sync::Arc;

use musclefem_materials::driver::{StretchHistory, run_uniaxial_stress};
use musclefem_materials::{Material, PointBlock, PointResponse, Tangent, VoigtStress};
use musclefem_vumat::TangentSource;
use nalgebra::{Matrix3, Vector3};

use support::builds::{
    built, builtin, fixture, gfortran_or_skip, material, neo_hookean_umat, umat_options,
};
use support::points::{Point, deformation_gradients, matrix, relative_difference, rotation};

/// Shear modulus [Pa] and compressibility [1/Pa] of the comparisons (bulk modulus 2/D =
/// 20 μ, as in tests/neo_hookean.rs).
const MU: f64 = 2.5e4;
const D: f64 = 4e-6;
const PARAMETERS: [(&str, f64); 2] = [("mu", MU), ("D", D)];

/// The example UMAT with its DDSDDE, and with the host's finite differences.
fn umat_materials() -> Vec<(TangentSource, Arc<dyn Material>)> {
    [
        (TangentSource::Ddsdde, "nh-umat"),
        (TangentSource::FiniteDifference, "nh-umat-fd"),
    ]
    .into_iter()
    .map(|(tangent, name)| {
        (
            tangent,
            material(&neo_hookean_umat(name, tangent), &PARAMETERS),
        )
    })
    .collect()
}

/// The stress and tangent ∂P/∂F of a step of `dt` from `point`'s state to `f`.
fn step_with_tangent(point: &Point, f: Matrix3<f64>, dt: f64) -> (VoigtStress, Tangent) {
    let block = PointBlock {
        time: point.time + dt,
        dt,
        deformation_gradient_old: &[point.f],
        deformation_gradient_new: &[f],
        fiber_direction: &[point.fiber],
        state_old: &point.state,
    };
    let mut stress = [VoigtStress::zeros()];
    let mut state = point.state.clone();
    let mut tangent = [Tangent::zeros()];
    point
        .material
        .update(
            &block,
            &mut PointResponse {
                cauchy_stress: &mut stress,
                state_new: &mut state,
                tangent: Some(&mut tangent),
            },
        )
        .unwrap();
    (stress[0], tangent[0])
}

fn tangent_difference(a: &Tangent, b: &Tangent) -> f64 {
    (a - b).norm() / b.norm()
}

#[test]
fn uniaxial_stress_through_the_driver_matches_the_builtin() {
    if !gfortran_or_skip("uniaxial_stress_through_the_driver_matches_the_builtin") {
        return;
    }
    let reference_material = builtin("neo-hookean", &PARAMETERS);
    let history = StretchHistory::parse("0:1,1:1.4,1.5:0.8").unwrap();
    let reference = run_uniaxial_stress(&*reference_material, &history, 0.05).unwrap();
    let scale = reference
        .iter()
        .map(|r| r.engineering_stress.abs())
        .fold(0.0, f64::max);
    assert!(scale > 0.3 * MU, "{scale}");
    for (tangent, umat) in umat_materials() {
        let rows = run_uniaxial_stress(&*umat, &history, 0.05).unwrap();
        assert_eq!(rows.len(), reference.len());
        let mut worst = 0.0_f64;
        for (row, expected) in rows.iter().zip(&reference) {
            assert_eq!(row.stretch, expected.stretch);
            for (value, wanted) in [
                (row.engineering_stress, expected.engineering_stress),
                (row.cauchy_stress, expected.cauchy_stress),
                (row.jacobian * MU, expected.jacobian * MU),
            ] {
                let relative = (value - wanted).abs() / scale;
                worst = worst.max(relative);
                assert!(relative < 1e-8, "{tangent}: {row:?} vs {expected:?}");
            }
        }
        eprintln!("UMAT uniaxial, tangent {tangent}: worst relative difference {worst:e}");
    }
}

#[test]
fn simple_shear_under_a_rigid_rotation_matches_the_builtin_stress_and_tangent() {
    if !gfortran_or_skip(
        "simple_shear_under_a_rigid_rotation_matches_the_builtin_stress_and_tangent",
    ) {
        return;
    }
    let reference = builtin("neo-hookean", &PARAMETERS);
    let steps = 40;
    let dt = 0.025;
    for (source, umat) in umat_materials() {
        let mut point = Point::new(&*umat, Vector3::new(0.6, 0.8, 0.0));
        let mut reference_point = Point::new(&*reference, Vector3::new(0.6, 0.8, 0.0));
        let (mut worst_stress, mut worst_tangent) = (0.0_f64, 0.0_f64);
        for step in 1..=steps {
            let t = step as f64 / steps as f64;
            let shear = Matrix3::new(1.0, t, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
            let f = rotation([1.0, 2.0, 3.0], 0.5 * PI * t) * shear;
            let (stress, tangent) = step_with_tangent(&point, f, dt);
            let (expected, expected_tangent) = step_with_tangent(&reference_point, f, dt);
            let relative = relative_difference(&stress, &expected);
            let relative_tangent = tangent_difference(&tangent, &expected_tangent);
            worst_stress = worst_stress.max(relative);
            worst_tangent = worst_tangent.max(relative_tangent);
            assert!(
                relative < 1e-8,
                "{source}, step {step}: {stress:?} vs {expected:?}"
            );
            // DDSDDE converted is the analytic tangent to round-off; the host's central
            // differences (h = 1e-6) to their truncation and round-off.
            let bound = match source {
                TangentSource::Ddsdde => 1e-8,
                TangentSource::FiniteDifference => 1e-6,
            };
            assert!(
                relative_tangent < bound,
                "{source}, step {step}: tangent off by {relative_tangent:e}"
            );
            assert_eq!(point.step(f, dt).unwrap(), stress);
            reference_point.step(f, dt).unwrap();
        }
        // The kept stress is the last Cauchy stress, in UMAT order (12, 13, 23 shears).
        let last = matrix(&point.trial(point.f, 0.0).unwrap().0);
        for (name, (i, j)) in [
            ("11", (0, 0)),
            ("22", (1, 1)),
            ("33", (2, 2)),
            ("12", (0, 1)),
            ("13", (0, 2)),
            ("23", (1, 2)),
        ] {
            let kept = point.state_named(&format!("umat_stress_{name}"));
            assert!((kept - last[(i, j)]).abs() < 1e-12 * last.norm(), "{name}");
        }
        assert_eq!(point.state_named("umat_increments"), steps as f64);
        eprintln!(
            "UMAT shear + rotation, tangent {source}: worst stress {worst_stress:e}, worst \
             tangent {worst_tangent:e}"
        );
    }
}

#[test]
fn a_rigidly_rotated_deformation_gives_the_rotated_stress() {
    if !gfortran_or_skip("a_rigidly_rotated_deformation_gives_the_rotated_stress") {
        return;
    }
    let q = rotation([-1.0, 0.5, 2.0], 1.1);
    for (source, umat) in umat_materials() {
        for (i, f) in deformation_gradients().into_iter().enumerate() {
            let mut point = Point::new(&*umat, Vector3::x());
            let stress = point.step(f, 0.1).unwrap();
            let rotated = point.step(q * f, 0.1).unwrap();
            let expected = q * matrix(&stress) * q.transpose();
            assert!(
                (matrix(&rotated) - expected).norm() < 1e-10 * expected.norm(),
                "{source}, F #{i}: {rotated:?} vs Q sigma Q^T = {expected}"
            );
        }
        let mut point = Point::new(&*umat, Vector3::x());
        for step in 1..=10 {
            let stress = point
                .step(rotation([0.3, -1.0, 0.2], 0.2 * step as f64), 0.1)
                .unwrap();
            assert!(stress.amax() < 1e-9 * MU, "{source}: {stress:?}");
        }
    }
}

#[test]
fn the_converted_ddsdde_is_the_builtin_analytic_tangent() {
    if !gfortran_or_skip("the_converted_ddsdde_is_the_builtin_analytic_tangent") {
        return;
    }
    let reference = builtin("neo-hookean", &PARAMETERS);
    let umat = material(
        &neo_hookean_umat("nh-umat", TangentSource::Ddsdde),
        &PARAMETERS,
    );
    assert!(umat.provides_tangent());
    let mut worst = 0.0_f64;
    // From the identity, with a step and in no time (dt = 0, the UMAT called with DTIME = 0).
    for (f, dt) in deformation_gradients()
        .into_iter()
        .zip([0.1, 0.0].repeat(12))
    {
        let (stress, tangent) = step_with_tangent(&Point::new(&*umat, Vector3::x()), f, dt);
        let (expected_stress, expected) =
            step_with_tangent(&Point::new(&*reference, Vector3::x()), f, dt);
        assert!(relative_difference(&stress, &expected_stress) < 1e-8);
        let relative = tangent_difference(&tangent, &expected);
        worst = worst.max(relative);
        assert!(
            relative < 1e-8,
            "dt {dt}: relative tangent error {relative:e}"
        );
    }
    eprintln!("DDSDDE as dP/dF against the built-in's analytic tangent: worst {worst:e}");
}

#[test]
fn a_umat_without_ddsdde_gets_a_finite_difference_tangent() {
    if !gfortran_or_skip("a_umat_without_ddsdde_gets_a_finite_difference_tangent") {
        return;
    }
    let reference = builtin("neo-hookean", &PARAMETERS);
    // faulty_umat.f with fault 0: the neo-Hookean stress, DDSDDE never set.
    let plugin = built(umat_options(
        &fixture("faulty_umat.f"),
        "faulty-umat",
        "fault=0,mu,D",
        1,
        TangentSource::Ddsdde,
    ))
    .unwrap();
    let unset = material(&plugin, &[("fault", 0.0), ("mu", MU), ("D", D)]);
    assert!(unset.provides_tangent());
    let host = material(
        &neo_hookean_umat("nh-umat-fd", TangentSource::FiniteDifference),
        &PARAMETERS,
    );
    assert!(!host.provides_tangent());
    for (i, f) in deformation_gradients().into_iter().take(8).enumerate() {
        let expected = step_with_tangent(&Point::new(&*reference, Vector3::x()), f, 0.1).1;
        for (what, umat) in [("adapter", &unset), ("host", &host)] {
            let (_, tangent) = step_with_tangent(&Point::new(&**umat, Vector3::x()), f, 0.1);
            let relative = tangent_difference(&tangent, &expected);
            assert!(relative < 1e-6, "{what}, F #{i}: {relative:e}");
        }
    }
}
