//! examples/vumat/neo_hookean_vumat.f through the VUMAT adapter against the built-in
//! `neo-hookean` material: the same strain energy, so the same stress to round-off — in
//! uniaxial stress (the material-point driver), in simple shear under a rigid rotation, for
//! rotated deformations, in the finite-difference tangent — and the adapter's kept state
//! (co-rotational stress, internal energy) carried from step to step.

mod support {
    pub mod builds;
    pub mod points;
}

use std::f64::consts::PI;

use musclefem_materials::driver::{StretchHistory, run_uniaxial_stress};
use musclefem_materials::{Material, PointBlock, PointResponse, Tangent, VoigtStress};
use musclefem_vumat::FiberConvention;
use nalgebra::{Matrix3, Vector3};

use support::builds::{builtin, gfortran_or_skip, material, neo_hookean_vumat};
use support::points::{Point, deformation_gradients, matrix, polar, relative_difference, rotation};

/// Shear modulus [Pa] and compressibility [1/Pa] of the comparisons: bulk modulus 2/D =
/// 20 μ, so that the volumetric and deviatoric stresses are of similar size.
const MU: f64 = 2.5e4;
const D: f64 = 4e-6;
const PARAMETERS: [(&str, f64); 2] = [("mu", MU), ("D", D)];

/// The VUMAT's material under the two conventions that give it other bases: the fiber's
/// (orientation) and the global one (none).
fn vumat_materials() -> Vec<(FiberConvention, std::sync::Arc<dyn Material>)> {
    [
        (FiberConvention::Orientation, "nh-vumat-orientation"),
        (FiberConvention::None, "nh-vumat-global"),
    ]
    .into_iter()
    .map(|(fiber, name)| {
        (
            fiber,
            material(&neo_hookean_vumat(name, fiber), &PARAMETERS),
        )
    })
    .collect()
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
    for (fiber, vumat) in vumat_materials() {
        let rows = run_uniaxial_stress(&*vumat, &history, 0.05).unwrap();
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
                assert!(relative < 1e-8, "{fiber}: {row:?} vs {expected:?}");
            }
        }
        eprintln!("uniaxial, fiber convention {fiber}: worst relative difference {worst:e}");
    }
}

#[test]
fn simple_shear_under_a_rigid_rotation_matches_the_builtin_step_by_step() {
    if !gfortran_or_skip("simple_shear_under_a_rigid_rotation_matches_the_builtin_step_by_step") {
        return;
    }
    let reference = builtin("neo-hookean", &PARAMETERS);
    let steps = 40;
    let dt = 0.025;
    for (fiber, vumat) in vumat_materials() {
        let mut point = Point::new(&*vumat, Vector3::new(0.6, 0.8, 0.0));
        let mut reference_point = Point::new(&*reference, Vector3::new(0.6, 0.8, 0.0));
        let mut worst = 0.0_f64;
        for step in 1..=steps {
            let t = step as f64 / steps as f64;
            let shear = Matrix3::new(1.0, t, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
            let f = rotation([1.0, 2.0, 3.0], 0.5 * PI * t) * shear;
            let stress = point.step(f, dt).unwrap();
            let expected = reference_point.step(f, dt).unwrap();
            let relative = relative_difference(&stress, &expected);
            worst = worst.max(relative);
            assert!(
                relative < 1e-8,
                "{fiber}, step {step}: {stress:?} vs {expected:?}"
            );
        }
        // The kept co-rotational stress is R^T sigma R of the last step.
        let f = point.f;
        let (r, _) = polar(&f);
        let kept = Matrix3::from_fn(|i, j| {
            let name = ["11", "22", "33"];
            let key = match (i.min(j), i.max(j)) {
                (a, b) if a == b => name[a].to_string(),
                (0, 1) => "12".into(),
                (1, 2) => "23".into(),
                _ => "31".into(),
            };
            point.state_named(&format!("vumat_stress_{key}"))
        });
        let last = reference_point.trial(f, 0.0).unwrap().0;
        let basis = if fiber == FiberConvention::Orientation {
            // (a, b, c) of the fiber (0.6, 0.8, 0): b from the z axis, c = a x b.
            let a = Vector3::new(0.6, 0.8, 0.0);
            let b = Vector3::z();
            Matrix3::from_columns(&[a, b, a.cross(&b)])
        } else {
            Matrix3::identity()
        };
        let expected_kept = basis.transpose() * r.transpose() * matrix(&last) * r * basis;
        assert!(
            (kept - expected_kept).norm() < 1e-8 * expected_kept.norm(),
            "{fiber}: kept {kept} vs {expected_kept}"
        );
        // Specific internal energy: the stress power summed over the steps is W / rho_0
        // (simple shear is isochoric: W = mu gamma^2 / 2), to the midpoint rule's O(dt^2).
        let energy = point.state_named("vumat_ener_intern");
        let expected_energy = 0.5 * MU / 1000.0;
        assert!(
            (energy - expected_energy).abs() < 1e-3 * expected_energy,
            "{fiber}: internal energy {energy} J/kg vs {expected_energy}"
        );
        eprintln!("shear + rotation, fiber convention {fiber}: worst {worst:e}, energy {energy}");
    }
}

#[test]
fn a_rigidly_rotated_deformation_gives_the_rotated_stress() {
    if !gfortran_or_skip("a_rigidly_rotated_deformation_gives_the_rotated_stress") {
        return;
    }
    let q = rotation([-1.0, 0.5, 2.0], 1.1);
    for (fiber, vumat) in vumat_materials() {
        for (i, f) in deformation_gradients().into_iter().enumerate() {
            let fiber_direction = Vector3::new(1.0, 2.0, 2.0);
            // Deformed, then rotated rigidly in a second step.
            let mut point = Point::new(&*vumat, fiber_direction);
            let stress = point.step(f, 0.1).unwrap();
            let rotated = point.step(q * f, 0.1).unwrap();
            let expected = q * matrix(&stress) * q.transpose();
            assert!(
                (matrix(&rotated) - expected).norm() < 1e-10 * expected.norm(),
                "{fiber}, F #{i}: {rotated:?} vs Q sigma Q^T = {expected}"
            );
            // Rotated in the same step as deformed.
            let at_once = Point::new(&*vumat, fiber_direction)
                .step(q * f, 0.1)
                .unwrap();
            assert!(
                relative_difference(&at_once, &rotated) < 1e-10,
                "{fiber}, F #{i}"
            );
        }
        // A rigid rotation alone stresses nothing.
        let mut point = Point::new(&*vumat, Vector3::x());
        for step in 1..=10 {
            let stress = point
                .step(rotation([0.3, -1.0, 0.2], 0.2 * step as f64), 0.1)
                .unwrap();
            assert!(stress.amax() < 1e-9 * MU, "{fiber}: {stress:?}");
        }
    }
}

#[test]
fn a_zero_step_returns_the_kept_stress_or_the_stress_at_a_new_f_and_keeps_the_state() {
    if !gfortran_or_skip(
        "a_zero_step_returns_the_kept_stress_or_the_stress_at_a_new_f_and_keeps_the_state",
    ) {
        return;
    }
    let reference = builtin("neo-hookean", &PARAMETERS);
    for (fiber, vumat) in vumat_materials() {
        let mut point = Point::new(&*vumat, Vector3::new(0.0, 1.0, 1.0));
        let f = deformation_gradients()[5];
        let stress = point.step(f, 0.1).unwrap();
        let (again, state) = point.trial(f, 0.0).unwrap();
        assert!(relative_difference(&again, &stress) < 1e-14, "{fiber}");
        assert_eq!(state, point.state, "{fiber}");
        // A deformation in no time (the host differentiating the stress at t = 0): the
        // VUMAT's stress at the new F, the state unchanged.
        let g = deformation_gradients()[9];
        let (moved, state) = point.trial(g, 0.0).unwrap();
        let expected = Point::new(&*reference, Vector3::x()).step(g, 0.1).unwrap();
        assert!(relative_difference(&moved, &expected) < 1e-8, "{fiber}");
        assert_eq!(state, point.state, "{fiber}");
    }
}

/// The tangent dP/dF of `material` at `f` after a step of `dt` from the identity.
fn tangent(material: &dyn Material, f: Matrix3<f64>, dt: f64) -> Tangent {
    let state = material.initial_state(1);
    let block = PointBlock {
        time: 0.1,
        dt,
        deformation_gradient_old: &[Matrix3::identity()],
        deformation_gradient_new: &[f],
        fiber_direction: &[Vector3::x()],
        state_old: &state,
    };
    let mut stress = [VoigtStress::zeros()];
    let mut state_new = state.clone();
    let mut tangent = [Tangent::zeros()];
    material
        .update(
            &block,
            &mut PointResponse {
                cauchy_stress: &mut stress,
                state_new: &mut state_new,
                tangent: Some(&mut tangent),
            },
        )
        .unwrap();
    tangent[0]
}

#[test]
fn the_finite_difference_tangent_matches_the_builtin_analytic_one() {
    if !gfortran_or_skip("the_finite_difference_tangent_matches_the_builtin_analytic_one") {
        return;
    }
    let reference = builtin("neo-hookean", &PARAMETERS);
    for (fiber, vumat) in vumat_materials() {
        assert!(!vumat.provides_tangent());
        // dt = 0: the explicit solver's stable step at t = 0 differentiates in no time.
        for (f, dt) in deformation_gradients()
            .into_iter()
            .take(8)
            .zip([0.1, 0.0].repeat(4))
        {
            let expected = tangent(&*reference, f, dt);
            let relative = (tangent(&*vumat, f, dt) - expected).norm() / expected.norm();
            assert!(
                relative < 1e-6,
                "{fiber}, dt {dt}: relative tangent error {relative:e}"
            );
        }
    }
}

/// One step of `fs` from the identity as one block: the stresses.
fn block_stress(material: &dyn Material, fs: &[Matrix3<f64>]) -> Vec<VoigtStress> {
    let n = fs.len();
    let f_old = vec![Matrix3::identity(); n];
    let fibers = vec![Vector3::new(0.0, 0.6, 0.8); n];
    let state = material.initial_state(n);
    let mut stress = vec![VoigtStress::zeros(); n];
    let mut state_new = state.clone();
    let block = PointBlock {
        time: 0.1,
        dt: 0.1,
        deformation_gradient_old: &f_old,
        deformation_gradient_new: fs,
        fiber_direction: &fibers,
        state_old: &state,
    };
    material
        .update(
            &block,
            &mut PointResponse {
                cauchy_stress: &mut stress,
                state_new: &mut state_new,
                tangent: None,
            },
        )
        .unwrap();
    stress
}

#[test]
fn blocks_on_several_threads_give_the_serial_result() {
    if !gfortran_or_skip("blocks_on_several_threads_give_the_serial_result") {
        return;
    }
    for (fiber, vumat) in vumat_materials() {
        let fs: Vec<Matrix3<f64>> = deformation_gradients().repeat(20);
        let serial = block_stress(&*vumat, &fs);
        let parallel: Vec<VoigtStress> = std::thread::scope(|scope| {
            let handles: Vec<_> = fs
                .chunks(40)
                .map(|chunk| {
                    let vumat = &vumat;
                    scope.spawn(move || {
                        // Each thread repeats its block, so that the calls overlap.
                        let first = block_stress(&**vumat, chunk);
                        for _ in 0..20 {
                            assert_eq!(block_stress(&**vumat, chunk), first);
                        }
                        first
                    })
                })
                .collect();
            handles
                .into_iter()
                .flat_map(|h| h.join().unwrap())
                .collect()
        });
        assert_eq!(parallel, serial, "{fiber}");
    }
}
