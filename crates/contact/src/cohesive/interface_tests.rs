//! The interface's forces, stiffness, commit and report on single bonds.

use musclefem_core::solver::{Interaction, RigidMotion, RigidRotation};
use musclefem_materials::Amplitude;
use nalgebra::{DMatrix, Matrix3, Unit, Vector3};

use super::*;

fn settings(tangential: TangentialMode) -> CohesiveSettings {
    CohesiveSettings {
        normal_stiffness: 1e3,
        shear_stiffness: 1e3,
        tangential_stiffness: 1e3,
        initiation_separation: 0.01,
        failure_separation: 0.03,
        tangential,
        bond_tolerance: 1e-6,
    }
}

/// Main triangle nodes 0, 1, 2 on z = 0, secondary node 3 on it at (0.3, 0.2, 0).
fn reference() -> Vec<Vector3<f64>> {
    vec![
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.3, 0.2, 0.0),
    ]
}

fn deformable(settings: &CohesiveSettings) -> CohesiveInterface {
    let main = MainSide::Deformable {
        triangles: vec![[0, 1, 2]],
    };
    CohesiveInterface::build(
        "glue",
        ("top", &[3], &[0.5]),
        ("bottom", main),
        &reference(),
        settings,
    )
    .unwrap()
}

fn all_forces(interface: &mut CohesiveInterface, time: f64, x: &[Vector3<f64>]) -> Vec<f64> {
    let mut force = vec![Vector3::zeros(); x.len()];
    interface.search(time, x).unwrap();
    interface.forces(time, x, true, &mut force).unwrap();
    force.iter().flat_map(|f| f.iter().copied()).collect()
}

/// The assembled stiffness against central differences of the forces.
fn check_stiffness(interface: &mut CohesiveInterface, time: f64, x: &[Vector3<f64>]) {
    let n = 3 * x.len();
    all_forces(interface, time, x);
    let mut k = DMatrix::<f64>::zeros(n, n);
    interface.stiffness(&mut |a, b, block: &Matrix3<f64>| {
        for i in 0..3 {
            for j in 0..3 {
                k[(3 * a as usize + i, 3 * b as usize + j)] += block[(i, j)];
            }
        }
    });
    let h = 1e-7;
    let scale = k.amax();
    for column in 0..n {
        let mut plus = x.to_vec();
        let mut minus = x.to_vec();
        plus[column / 3][column % 3] += h;
        minus[column / 3][column % 3] -= h;
        let fp = all_forces(interface, time, &plus);
        let fm = all_forces(interface, time, &minus);
        for row in 0..n {
            let fd = (fp[row] - fm[row]) / (2.0 * h);
            assert!(
                (fd - k[(row, column)]).abs() <= 1e-6 * scale,
                "K[{row}][{column}] = {} vs {fd}",
                k[(row, column)]
            );
        }
    }
}

#[test]
fn an_opened_bond_pulls_its_node_back_and_the_main_nodes_take_the_reaction() {
    let mut interface = deformable(&settings(TangentialMode::Elastic));
    let mut x = reference();
    x[3].z += 0.004;
    let f = all_forces(&mut interface, 0.0, &x);
    // f_s = A K δ n = 0.5 × 1e3 × 0.004 along +z (it enters like an internal force).
    assert!((f[11] - 2.0).abs() < 1e-12);
    // Reactions −ξ f_s, ξ = (0.5, 0.3, 0.2).
    assert!((f[2] + 1.0).abs() < 1e-12 && (f[5] + 0.6).abs() < 1e-12);
    assert!((f[8] + 0.4).abs() < 1e-12);
    let report = interface.report();
    assert!((report.force - Vector3::new(0.0, 0.0, -2.0)).norm() < 1e-12);
    assert_eq!((report.active_points, report.active_area), (1, 0.5));
    assert!((report.stored_energy - 0.5 * 0.5 * 1e3 * 0.004 * 0.004).abs() < 1e-15);
    let fields = interface.nodal_fields(4);
    assert_eq!(fields[0].name, "cohesive_traction");
    let traction = Vector3::from_column_slice(&fields[0].values[9..12]);
    assert!((traction - Vector3::new(0.0, 0.0, -4.0)).norm() < 1e-12);
    assert!(fields[0].values[..9].iter().all(|&v| v == 0.0));
}

#[test]
fn damage_waits_for_commit_and_never_heals() {
    let mut interface = deformable(&settings(TangentialMode::Elastic));
    let mut x = reference();
    x[3].z += 0.02;
    all_forces(&mut interface, 0.0, &x);
    // D(0.02) = 0.03 × 0.01 / (0.02 × 0.02) = 0.75; a trial is not committed.
    assert!((interface.bond_states().next().unwrap().2 - 0.75).abs() < 1e-14);
    x[3].z = 0.005;
    all_forces(&mut interface, 0.0, &x);
    assert_eq!(interface.bond_states().next().unwrap().2, 0.0);
    x[3].z = 0.02;
    all_forces(&mut interface, 0.0, &x);
    interface.commit();
    x[3].z = 0.005;
    let f = all_forces(&mut interface, 0.0, &x);
    assert!((f[11] - 0.25 * 0.5 * 1e3 * 0.005).abs() < 1e-12);
    assert!((interface.report().bonded_area - 0.5).abs() < 1e-15);
    x[3].z = 0.04;
    all_forces(&mut interface, 0.0, &x);
    interface.commit();
    assert_eq!(interface.report().bonded_area, 0.0);
    // Failed, pressed: the normal stiffness still resists.
    x[3].z = -0.001;
    let f = all_forces(&mut interface, 0.0, &x);
    assert!((f[11] + 0.5 * 1e3 * 0.001).abs() < 1e-12);
}

#[test]
fn the_stiffness_is_consistent_with_a_deformable_main_in_elastic_opening() {
    let mut interface = deformable(&settings(TangentialMode::Elastic));
    let mut x = reference();
    // The main triangle moved, tilted and stretched; the node opened into softening.
    x[0] += Vector3::new(0.01, -0.02, 0.005);
    x[1] += Vector3::new(0.03, 0.01, 0.1);
    x[2] += Vector3::new(-0.02, 0.04, -0.05);
    x[3] += Vector3::new(0.008, -0.006, 0.012);
    check_stiffness(&mut interface, 0.0, &x);
    // Unloading after damage (secant).
    all_forces(&mut interface, 0.0, &x);
    interface.commit();
    x[3] -= Vector3::new(0.002, 0.0, 0.006);
    check_stiffness(&mut interface, 0.0, &x);
}

fn rigid(tangential: TangentialMode, stiffness: [f64; 3]) -> CohesiveInterface {
    let ramp = |v| Some(Amplitude::ramp(1.0, v).unwrap());
    let main = MainSide::Rigid {
        vertices: reference()[..3].to_vec(),
        triangles: vec![[0, 1, 2]],
        motion: RigidMotion {
            translation: [ramp(0.01), None, ramp(-0.02)],
            rotation: Some(RigidRotation {
                center: Vector3::new(0.2, 0.1, 0.0),
                axis: Unit::new_normalize(Vector3::new(1.0, 1.0, 0.3)),
                angle: Amplitude::ramp(1.0, 0.4).unwrap(),
            }),
        },
    };
    let [kn, ks, kt] = stiffness;
    let s = CohesiveSettings {
        normal_stiffness: kn,
        shear_stiffness: ks,
        tangential_stiffness: kt,
        ..settings(tangential)
    };
    let nodes = vec![Vector3::new(0.3, 0.2, 0.0)];
    CohesiveInterface::build("bone", ("muscle", &[0], &[0.7]), ("femur", main), &nodes, &s)
        .unwrap()
}

#[test]
fn the_stiffness_is_consistent_with_a_rigid_main_in_every_mode() {
    for (mode, k) in [
        (TangentialMode::Elastic, [1e3, 1e3, 1e3]),
        (TangentialMode::Elastic, [1e3, 4e2, 7e2]),
        (TangentialMode::FreeSlide, [1e3, 4e2, 7e2]),
    ] {
        let mut interface = rigid(mode, k);
        assert_eq!(
            interface.symmetric_stiffness(),
            mode == TangentialMode::FreeSlide || k[0] == k[1]
        );
        // Where the bonded point goes at t = 0.6, plus a separation in softening.
        let placement = interface.main.placement(0.6);
        let point = placement * nalgebra::Point3::new(0.3, 0.2, 0.0);
        let x = vec![point.coords + Vector3::new(0.006, 0.009, 0.011)];
        check_stiffness(&mut interface, 0.6, &x);
    }
}

#[test]
fn a_rigid_main_follows_its_motion() {
    let mut interface = rigid(TangentialMode::Elastic, [1e3; 3]);
    let placement = interface.main.placement(1.0);
    let point = placement * nalgebra::Point3::new(0.3, 0.2, 0.0);
    let normal = placement * Vector3::z();
    let x = vec![point.coords + 0.004 * normal];
    let f = all_forces(&mut interface, 1.0, &x);
    let expected = 0.7 * 1e3 * 0.004 * normal;
    assert!((Vector3::from_column_slice(&f) - expected).norm() < 1e-12);
    let (_, separation, _) = interface.bond_states().next().unwrap();
    assert!((separation - Vector3::new(0.004, 0.0, 0.0)).norm() < 1e-15);
}

#[test]
fn nothing_within_the_tolerance_is_an_error_naming_the_interface_and_surfaces() {
    let mut x = reference();
    x[3].z = 0.01;
    let main = MainSide::Deformable {
        triangles: vec![[0, 1, 2]],
    };
    let error = CohesiveInterface::build(
        "glue",
        ("top", &[3], &[0.5]),
        ("bottom", main),
        &x,
        &settings(TangentialMode::Elastic),
    )
    .unwrap_err()
    .to_string();
    for part in ["'glue'", "'top'", "'bottom'", "1.000e-6 m", "1.000e-2 m"] {
        assert!(error.contains(part), "{error}");
    }
}
