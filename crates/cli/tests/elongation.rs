//! Verification of the elongation tests (issue: single-muscle validation):
//! - a cylinder with sliding grips deforms homogeneously, so its curve is the material
//!   point's (`musclefem point`) with the same stretch history;
//! - the fusiform curve converges with the mesh (observed order printed);
//! - explicit (mass-scaled) and implicit fusiform curves agree;
//! - active stress exceeds passive stress at every strain, and the deformed shapes differ.

use std::ops::ControlFlow;

use nalgebra::Vector3;

use musclefem::elongation::setup::muscle_material;
use musclefem::elongation::{
    CurvePoint, ElementChoice, ElongationRun, ElongationTest, ElongationWatcher, Grips, Mode,
    Shape, Solver, Unwatched, run_elongation,
};
use musclefem_core::solver::observer::Snapshot;
use musclefem_materials::driver::{StretchHistory, run_uniaxial_stress};

fn test(mode: Mode, shape: Shape, mesh_size_mm: f64) -> ElongationTest {
    ElongationTest {
        shape,
        mesh_size: 1e-3 * mesh_size_mm,
        ..ElongationTest::recommended(mode)
    }
}

fn run(test: &ElongationTest) -> ElongationRun {
    run_elongation(test, &mut Unwatched).unwrap_or_else(|e| panic!("{e:#}"))
}

/// The largest relative difference of two curves' stresses over the stretching phase,
/// relative to the largest stress of `reference`, sampling `curve` at `reference`'s strains.
fn curve_difference(curve: &ElongationRun, reference: &[(f64, f64)]) -> f64 {
    let scale = reference.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    reference
        .iter()
        .filter_map(|&(strain, stress)| {
            curve
                .curve
                .stress_at_strain(strain)
                .map(|s| (s - stress).abs() / scale)
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_cylinder_with_sliding_grips_follows_the_material_point() {
    for (mode, history) in [
        (Mode::Passive, "0:1,2:1.2"),
        (Mode::Active, "0:1,0.5:1,2.5:1.2"),
    ] {
        let mut cylinder = test(mode, Shape::Cylinder, 4.0);
        cylinder.grips = Grips::Sliding;
        let run = run(&cylinder);
        let material = muscle_material(&cylinder).unwrap();
        let increment = musclefem::elongation::setup::DEFAULT_IMPLICIT_INCREMENT;
        let rows = run_uniaxial_stress(
            material.as_ref(),
            &StretchHistory::parse(history).unwrap(),
            increment,
        )
        .unwrap();
        let hold = mode.hold();
        let reference: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.time >= hold)
            .map(|r| (r.stretch - 1.0, r.engineering_stress))
            .collect();
        let difference = curve_difference(&run, &reference);
        println!(
            "{} cylinder vs material point: largest difference {:.3e} of the peak stress \
             ({} elements)",
            mode.name(),
            difference,
            run.elements
        );
        assert!(difference < 0.005, "{}: {difference}", mode.name());
    }
}

/// Keeps the displacement of the last curve point.
#[derive(Default)]
struct LastDisplacement(Vec<Vector3<f64>>);

impl ElongationWatcher for LastDisplacement {
    fn point(&mut self, _point: &CurvePoint, snapshot: &Snapshot) -> ControlFlow<()> {
        self.0 = snapshot.displacement.to_vec();
        ControlFlow::Continue(())
    }
}

#[test]
fn active_stress_exceeds_passive_and_the_shapes_differ() {
    let mut shapes = Vec::new();
    let mut curves = Vec::new();
    for mode in [Mode::Passive, Mode::Active] {
        let mut last = LastDisplacement::default();
        let run = run_elongation(&test(mode, Shape::Fusiform, 4.0), &mut last).unwrap();
        shapes.push(last.0);
        curves.push(run.curve);
    }
    let (passive, active) = (&curves[0], &curves[1]);
    for point in passive.stretching().iter().skip(1) {
        let active_stress = active.stress_at_strain(point.strain).unwrap();
        assert!(
            active_stress > point.stress,
            "at strain {}: active {active_stress} Pa, passive {} Pa",
            point.strain,
            point.stress
        );
    }
    // The active muscle contracts more laterally: compare the largest lateral
    // displacement.
    let lateral = |u: &[Vector3<f64>]| u.iter().map(|u| u.x.hypot(u.y)).fold(0.0, f64::max);
    let (passive_lateral, active_lateral) = (lateral(&shapes[0]), lateral(&shapes[1]));
    println!(
        "largest lateral displacement: passive {passive_lateral:.4e} m, active {active_lateral:.4e} m"
    );
    assert!(
        (active_lateral - passive_lateral).abs() > 0.05 * passive_lateral,
        "passive {passive_lateral} m, active {active_lateral} m"
    );
}

#[test]
fn the_fusiform_curve_converges_with_the_mesh() {
    let sizes = [6.0, 3.0, 1.5];
    let mut stresses = Vec::new();
    for size in sizes {
        let run = run(&test(Mode::Passive, Shape::Fusiform, size));
        let stress = run.curve.stress_at_strain(0.2).unwrap();
        println!(
            "mesh {size} mm: {} elements, stress at 20 % strain {:.4} kPa, {:.2?}",
            run.elements,
            1e-3 * stress,
            run.solve_time
        );
        stresses.push(stress);
    }
    let (d1, d2) = (
        (stresses[0] - stresses[1]).abs(),
        (stresses[1] - stresses[2]).abs(),
    );
    let order = (d1 / d2).ln() / 2f64.ln();
    println!(
        "observed order {order:.2}; change from the middle to the finest mesh {:.3e} of the stress",
        d2 / stresses[2]
    );
    assert!(d2 < d1, "the differences shrink: {d1} then {d2}");
    assert!(
        d2 < 0.02 * stresses[2],
        "the two finest meshes agree within 2 %"
    );
}

#[test]
fn explicit_and_implicit_fusiform_curves_agree() {
    for mode in [Mode::Passive, Mode::Active] {
        let implicit = run(&test(mode, Shape::Fusiform, 4.0));
        let mut explicit_test = test(mode, Shape::Fusiform, 4.0);
        explicit_test.solver = Solver::Explicit;
        explicit_test.element = ElementChoice::Hex8Fbar;
        let explicit = run(&explicit_test);
        let reference: Vec<(f64, f64)> = implicit
            .curve
            .stretching()
            .iter()
            .map(|p| (p.strain, p.stress))
            .collect();
        let difference = curve_difference(&explicit, &reference);
        println!(
            "{}: explicit vs implicit largest difference {:.3e} of the peak; mass scaling \
             added {:.3e} of the mass, kinetic/internal energy up to {:.2e}",
            mode.name(),
            difference,
            explicit.added_mass_fraction.unwrap(),
            explicit.kinetic_to_internal.unwrap()
        );
        assert!(difference < 0.02, "{}: {difference}", mode.name());
    }
}
