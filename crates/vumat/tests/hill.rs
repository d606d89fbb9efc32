//! examples/vumat/hill_vumat.f, the paper's Hill muscle written as a VUMAT (fiber as local
//! direction 1, state λ_m, λ_s, σ_SEE), against the built-in `hill` material: uniaxial
//! stress along the fiber through the material-point driver, passive and active, and an
//! active point sheared under a rigid rotation with an oblique fiber, step by step, stress
//! and state.

mod support {
    pub mod builds;
    pub mod points;
}

use std::f64::consts::PI;

use musclefem_materials::driver::{StretchHistory, run_uniaxial_stress};
use musclefem_vumat::{BuiltPlugin, FiberConvention};
use nalgebra::{Matrix3, Vector3};

use support::builds::{built, builtin, example, gfortran_or_skip, material, options};
use support::points::{Point, relative_difference, rotation};

/// The built-in's parameters (names, defaults and units, Table 1) as the VUMAT's props,
/// in hill_vumat.f's order; t1 = 1e30 s stands for the built-in's "never" (infinity).
const PROPS: &str = "D=5e-9:1/Pa,b=15,c=379:Pa,A=4,lambda_pe=1,sigma0=7e5:Pa,alpha=10,\
                     beta=1000:Pa,lambda_opt=1.05,k=0.3,k_c=4,k_e=5,d=1.45,\
                     lambda_dot_min=-17:1/s,S=50:1/s,n1=0,n2=0,t0=0:s,t1=1e30:s";

fn hill_vumat() -> BuiltPlugin {
    let mut build = options(
        &example("hill_vumat.f"),
        "hill-vumat",
        PROPS,
        3,
        FiberConvention::Orientation,
    );
    build.statev_initial = vec![1.0, 1.0, 0.0];
    built(build).unwrap()
}

#[test]
fn uniaxial_stress_passive_and_active_matches_the_builtin_hill_muscle() {
    if !gfortran_or_skip("uniaxial_stress_passive_and_active_matches_the_builtin_hill_muscle") {
        return;
    }
    let plugin = hill_vumat();
    for (n2, history) in [(0.0, "0:1,1:1.2"), (1.0, "0:1,0.5:1,1.5:1.2,2:1.1")] {
        let vumat = material(&plugin, &[("n2", n2)]);
        let reference_material = builtin("hill", &[("n2", n2)]);
        let history = StretchHistory::parse(history).unwrap();
        let reference = run_uniaxial_stress(&*reference_material, &history, 2e-3).unwrap();
        let rows = run_uniaxial_stress(&*vumat, &history, 2e-3).unwrap();
        let scale = reference
            .iter()
            .map(|r| r.engineering_stress.abs())
            .fold(0.0, f64::max);
        assert!(scale > 1e4, "n2 = {n2}: {scale}");
        let mut worst = 0.0_f64;
        for (row, expected) in rows.iter().zip(&reference) {
            let relative = (row.engineering_stress - expected.engineering_stress).abs() / scale;
            worst = worst.max(relative);
            assert!(relative < 1e-8, "n2 = {n2}: {row:?} vs {expected:?}");
        }
        eprintln!("uniaxial, n2 = {n2}: worst relative difference {worst:e} of {scale} Pa");
    }
}

#[test]
fn an_active_point_sheared_under_rotation_matches_the_builtin_stress_and_state() {
    if !gfortran_or_skip(
        "an_active_point_sheared_under_rotation_matches_the_builtin_stress_and_state",
    ) {
        return;
    }
    let vumat = material(&hill_vumat(), &[("n2", 1.0)]);
    let reference = builtin("hill", &[("n2", 1.0)]);
    let fiber = Vector3::new(0.6, 0.8, 0.0);
    let mut point = Point::new(&*vumat, fiber);
    let mut reference_point = Point::new(&*reference, fiber);
    let steps = 200;
    let mut worst = 0.0_f64;
    for step in 1..=steps {
        let t = step as f64 / steps as f64;
        let stretch = 1.0 + 0.15 * (PI * t).sin();
        let lateral = 1.0 / stretch.sqrt();
        let deformation = Matrix3::new(stretch, 0.3 * t, 0.0, 0.0, lateral, 0.0, 0.0, 0.0, lateral);
        let f = rotation([1.0, 2.0, 3.0], 0.5 * PI * t) * deformation;
        let stress = point.step(f, 1e-3).unwrap();
        let expected = reference_point.step(f, 1e-3).unwrap();
        let relative = relative_difference(&stress, &expected);
        worst = worst.max(relative);
        assert!(relative < 1e-8, "step {step}: {stress:?} vs {expected:?}");
        for (i, name) in ["lambda_m", "lambda_s", "sigma_see"].iter().enumerate() {
            let value = point.state_named(&format!("sdv{}", i + 1));
            let wanted = reference_point.state_named(name);
            let scale = if i == 2 { 1e3 + wanted.abs() } else { 1.0 };
            assert!(
                (value - wanted).abs() < 1e-9 * scale,
                "step {step}, {name}: {value} vs {wanted}"
            );
        }
    }
    assert!(reference_point.state_named("sigma_see") > 1e5);
    eprintln!("active shear + rotation: worst relative stress difference {worst:e}");
}
