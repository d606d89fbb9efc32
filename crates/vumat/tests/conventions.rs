//! What the adapter hands the VUMAT, seen from inside: tests/fixtures/increment_probe.f
//! writes its arguments into its state variables and sums the strain increments into its
//! stress; tests/fixtures/fiber_probe.f returns a stress along the direction it takes for
//! the fiber. Checked: the times, density, charLength, temperature, lanneal, cmname,
//! nblock (blocks of at most 136), the component orders of defgradNew and stretchNew,
//! strainInc (co-rotational, summing to the logarithmic strain), relSpinInc, and the
//! three fiber conventions.

mod support {
    pub mod builds;
    pub mod points;
}

use musclefem_materials::{PointBlock, PointResponse, VoigtStress};
use musclefem_vumat::{BuiltPlugin, FiberConvention};
use nalgebra::{Matrix3, Vector3};

use support::builds::{built, fixture, gfortran_or_skip, material, options};
use support::points::{Point, deformation_gradients, matrix, polar, rotation};

/// Stiffness of the increment probe [Pa].
const E: f64 = 1e6;

fn increment_probe() -> BuiltPlugin {
    let mut build = options(
        &fixture("increment_probe.f"),
        "increment-probe",
        "E=1e6:Pa",
        30,
        FiberConvention::None,
    );
    build.cmname = Some("MUSCLE_PROBE".into());
    built(build).unwrap()
}

/// User state variable sdvK (1-based) of a point's state: after the adapter's 9.
fn sdv(state: &[f64], k: usize) -> f64 {
    state[9 + k - 1]
}

#[test]
fn times_density_and_the_other_scalars_reach_the_vumat() {
    if !gfortran_or_skip("times_density_and_the_other_scalars_reach_the_vumat") {
        return;
    }
    let probe = material(
        &increment_probe(),
        &[
            ("vumat_density", 1200.0),
            ("vumat_char_length", 0.002),
            ("vumat_temperature", 310.0),
        ],
    );
    let mut point = Point::new(&*probe, Vector3::x());
    point
        .step(Matrix3::from_diagonal(&Vector3::new(1.1, 1.0, 1.0)), 0.1)
        .unwrap();
    point
        .step(Matrix3::from_diagonal(&Vector3::new(1.2, 1.0, 1.0)), 0.05)
        .unwrap();
    let s = &point.state;
    // stepTime and totalTime: the start of the increment (0.1), dt = 0.05.
    for (value, expected) in [(sdv(s, 4), 0.1), (sdv(s, 5), 0.1), (sdv(s, 6), 0.05)] {
        assert!((value - expected).abs() < 1e-15, "{value} vs {expected}");
    }
    // density = rho_0 / det F_mid, F_mid = diag(1.15, 1, 1).
    assert!(
        (sdv(s, 7) - 1200.0 / 1.15).abs() < 1e-12 * 1200.0,
        "{}",
        sdv(s, 7)
    );
    assert_eq!([sdv(s, 8), sdv(s, 9), sdv(s, 30)], [0.002, 310.0, 310.0]);
    // lanneal = 0, nblock = 1, cmname = 'MUSCLE_PROBE' blank padded, nprops = 1.
    assert_eq!([sdv(s, 10), sdv(s, 11)], [0.0, 1.0]);
    assert_eq!([sdv(s, 12), sdv(s, 13)], [f64::from(b'M'), 12.0]);
    assert_eq!(sdv(s, 29), 1.0);
}

#[test]
fn large_blocks_reach_the_vumat_in_chunks_of_136_points() {
    if !gfortran_or_skip("large_blocks_reach_the_vumat_in_chunks_of_136_points") {
        return;
    }
    let probe = material(&increment_probe(), &[]);
    let n = 300;
    let f_old = vec![Matrix3::identity(); n];
    let f_new: Vec<Matrix3<f64>> = (0..n)
        .map(|p| Matrix3::from_diagonal(&Vector3::new(1.0 + 1e-3 * p as f64, 1.0, 1.0)))
        .collect();
    let fibers = vec![Vector3::x(); n];
    let state_old = probe.initial_state(n);
    let mut stress = vec![VoigtStress::zeros(); n];
    let mut state = vec![0.0; state_old.len()];
    let block = PointBlock {
        time: 0.1,
        dt: 0.1,
        deformation_gradient_old: &f_old,
        deformation_gradient_new: &f_new,
        fiber_direction: &fibers,
        state_old: &state_old,
    };
    probe
        .update(
            &block,
            &mut PointResponse {
                cauchy_stress: &mut stress,
                state_new: &mut state,
                tangent: None,
            },
        )
        .unwrap();
    let nstate = probe.state_count();
    for p in 0..n {
        let s = &state[p * nstate..(p + 1) * nstate];
        let expected_nblock = if p < 272 { 136.0 } else { 28.0 };
        assert_eq!(sdv(s, 11), expected_nblock, "point {p}");
        // One step from I: strainInc_11 = d lambda / lambda_mid.
        let stretch = 1e-3 * p as f64;
        let expected = E * stretch / (1.0 + 0.5 * stretch);
        assert!((stress[p][0] - expected).abs() < 1e-9 * E, "point {p}");
        assert_eq!(sdv(s, 14), 1.0 + stretch, "point {p}: defgradNew(k,1)");
    }
}

#[test]
fn defgrad_and_stretch_arrive_in_abaqus_component_order() {
    if !gfortran_or_skip("defgrad_and_stretch_arrive_in_abaqus_component_order") {
        return;
    }
    let probe = material(&increment_probe(), &[]);
    for f in deformation_gradients() {
        let mut point = Point::new(&*probe, Vector3::x());
        point.step(f, 0.1).unwrap();
        let s = &point.state;
        let order = [
            (0, 0),
            (1, 1),
            (2, 2),
            (0, 1),
            (1, 2),
            (2, 0),
            (1, 0),
            (2, 1),
            (0, 2),
        ];
        for (c, (i, j)) in order.iter().enumerate() {
            assert_eq!(sdv(s, 14 + c), f[(*i, *j)], "defgradNew(k,{})", c + 1);
        }
        let (_, u) = polar(&f);
        for (c, (i, j)) in order.iter().take(6).enumerate() {
            let value = sdv(s, 23 + c);
            assert!(
                (value - u[(*i, *j)]).abs() < 1e-12,
                "stretchNew(k,{}): {value} vs {u}",
                c + 1
            );
        }
    }
}

#[test]
fn strain_increments_are_co_rotational_and_sum_to_the_logarithmic_strain() {
    if !gfortran_or_skip("strain_increments_are_co_rotational_and_sum_to_the_logarithmic_strain") {
        return;
    }
    let probe = material(&increment_probe(), &[]);
    let mut point = Point::new(&*probe, Vector3::x());
    let steps = 100;
    let mut stress = VoigtStress::zeros();
    let mut r = Matrix3::identity();
    for step in 1..=steps {
        let t = step as f64 / steps as f64;
        let stretch = 1.0 + 0.5 * t;
        let lateral = 1.0 / stretch.sqrt();
        r = rotation([1.0, -1.0, 2.0], 1.5 * t);
        let f = r * Matrix3::from_diagonal(&Vector3::new(stretch, lateral, lateral));
        stress = point.step(f, 0.01).unwrap();
    }
    // The co-rotational stress is E times the summed strain increments: E ln U.
    let log = 1.5f64.ln();
    let expected_hat = Matrix3::from_diagonal(&Vector3::new(log, -0.5 * log, -0.5 * log)) * E;
    let hat = r.transpose() * matrix(&stress) * r;
    let error = (hat - expected_hat).norm() / expected_hat.norm();
    assert!(
        error < 1e-4,
        "co-rotational stress {hat} vs E ln U = {expected_hat} ({error:e})"
    );
    eprintln!("summed strain increments against ln U: relative difference {error:e}");
    // The spin of the material relative to the frame is zero for stretch + rotation, to
    // the midpoint rule's O(dt^2) over a rotation of 1.5 rad.
    for k in 1..=3 {
        let spin = sdv(&point.state, k);
        assert!(
            spin.abs() < 1e-5,
            "relSpinInc summed, component {k}: {spin}"
        );
        eprintln!("relSpinInc summed, component {k}: {spin:e}");
    }
}

#[test]
fn relative_spin_in_simple_shear_is_the_vorticity_minus_the_frame_spin() {
    if !gfortran_or_skip("relative_spin_in_simple_shear_is_the_vorticity_minus_the_frame_spin") {
        return;
    }
    let probe = material(&increment_probe(), &[]);
    let mut point = Point::new(&*probe, Vector3::x());
    let steps = 100;
    for step in 1..=steps {
        let gamma = step as f64 / steps as f64;
        point
            .step(
                Matrix3::new(1.0, gamma, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
                0.01,
            )
            .unwrap();
    }
    // W_21 = -gamma'/2 and the polar rotation is -atan(gamma/2) about z: the relative
    // rotation about z is atan(gamma/2) - gamma/2 at gamma = 1.
    let expected = 0.5f64.atan() - 0.5;
    let spin = sdv(&point.state, 3);
    assert!((spin - expected).abs() < 1e-5, "{spin} vs {expected}");
    assert!(sdv(&point.state, 1).abs() < 1e-14 && sdv(&point.state, 2).abs() < 1e-14);
}

/// tests/fixtures/fiber_probe.f under `fiber`, with props s = 1000 and from_state.
fn fiber_probe(fiber: FiberConvention, name: &str) -> BuiltPlugin {
    let nstatev = if fiber == FiberConvention::State {
        3
    } else {
        0
    };
    built(options(
        &fixture("fiber_probe.f"),
        name,
        "s=1000:Pa,from_state=0",
        nstatev,
        fiber,
    ))
    .unwrap()
}

#[test]
fn the_fiber_reaches_the_vumat_as_local_direction_1_or_in_state_variables_1_to_3() {
    if !gfortran_or_skip(
        "the_fiber_reaches_the_vumat_as_local_direction_1_or_in_state_variables_1_to_3",
    ) {
        return;
    }
    let fiber = Vector3::new(1.0, 2.0, 2.0);
    let a = fiber / 3.0;
    for (convention, name, from_state, direction) in [
        (FiberConvention::Orientation, "fiber-orientation", 0.0, a),
        (FiberConvention::State, "fiber-state", 1.0, a),
        (FiberConvention::None, "fiber-none", 0.0, Vector3::x()),
    ] {
        let probe = material(
            &fiber_probe(convention, name),
            &[("from_state", from_state)],
        );
        let mut point = Point::new(&*probe, fiber);
        // Before the first increment, a zero step shows the initial state variables.
        let (_, state) = point.trial(Matrix3::identity(), 0.0).unwrap();
        if convention == FiberConvention::State {
            for i in 0..3 {
                assert!((sdv(&state, i + 1) - a[i]).abs() < 1e-15, "{state:?}");
            }
        }
        for f in deformation_gradients().into_iter().take(10) {
            let stress = point.step(f, 0.1).unwrap();
            let (r, _) = polar(&f);
            let d = r * direction;
            let expected = d * d.transpose() * 1000.0;
            assert!(
                (matrix(&stress) - expected).norm() < 1e-12 * 1000.0,
                "{convention}: {stress:?} vs {expected}"
            );
        }
        if convention == FiberConvention::State {
            for i in 0..3 {
                assert!((sdv(&point.state, i + 1) - a[i]).abs() < 1e-15);
            }
        }
    }
}
