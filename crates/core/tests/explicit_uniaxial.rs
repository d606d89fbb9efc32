//! End-to-end checks of the explicit solver on a cube: fully integrated hex8, and a slow
//! uniaxial stretch with every element technology.

use std::collections::BTreeMap;
use std::sync::Arc;

use musclefem_core::element::Technology;
use musclefem_core::mesh::ElementShape;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::{TetOrder, box_of_hexes, box_of_tets};
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit};
use musclefem_core::solver::{Part, PrescribedDisplacement, SolverError};
use musclefem_materials::driver::{StretchHistory, run_uniaxial_stress};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

const SIDE: f64 = 0.01;

/// Compressible neo-Hookean (μ = 10 kPa, K = 2/D = 100 kPa) so that the stable step is
/// long enough for a test: c ≈ 10.6 m/s, Δt ≈ 0.4 ms on 5 mm elements.
fn neo_hookean() -> Arc<dyn Material> {
    let params = BTreeMap::from([("mu".to_string(), 1e4), ("D".to_string(), 2e-5)]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap()
}

/// Smooth ramp 0 → `value` over `duration` (3s² − 2s³, 41 knots), so that the loading
/// excites almost no waves.
fn smooth_ramp(duration: f64, value: f64) -> Amplitude {
    let knots = (0..=40)
        .map(|i| {
            let s = i as f64 / 40.0;
            (s * duration, value * s * s * (3.0 - 2.0 * s))
        })
        .collect();
    Amplitude::new(knots).unwrap()
}

/// Symmetry on x0, y0, z0 and the x1 face pulled along x by `stretch − 1` of the side.
fn uniaxial(mesh: &Mesh, stretch: f64, duration: f64) -> Vec<PrescribedDisplacement> {
    let fixed = |set: &str, dof: usize| PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("x1").unwrap().to_vec(),
            dof: 0,
            amplitude: smooth_ramp(duration, (stretch - 1.0) * SIDE),
        },
        fixed("x0", 0),
        fixed("y0", 1),
        fixed("z0", 2),
    ]
}

fn part(material: Arc<dyn Material>) -> Vec<Part> {
    part_with(material, Technology::Hex8Full)
}

fn part_with(material: Arc<dyn Material>, technology: Technology) -> Vec<Part> {
    vec![Part {
        block: 0,
        technology,
        material,
        density: 1000.0,
    }]
}

/// A cube stretched slowly to λ = 1.5 with free lateral faces: the reaction on the pulled
/// face matches P₁₁(1.5) × A₀ of the same material in homogeneous uniaxial stress (the
/// material-point driver, an independent solution path) within 1 %.
#[test]
fn slow_uniaxial_stretch_matches_the_homogeneous_solution() {
    uniaxial_stretch_matches(Technology::Hex8Full);
}

#[test]
fn slow_uniaxial_stretch_matches_the_homogeneous_solution_with_fbar() {
    uniaxial_stretch_matches(Technology::Hex8FBar);
}

#[test]
fn slow_uniaxial_stretch_matches_the_homogeneous_solution_with_one_point_hex8() {
    // μ = 10 kPa: the default hourglass modulus (homogeneous stretch: no hourglass mode).
    uniaxial_stretch_matches(Technology::hex8_one_point(1e4));
}

#[test]
fn slow_uniaxial_stretch_matches_the_homogeneous_solution_with_tet4() {
    uniaxial_stretch_matches(Technology::Tet4);
}

#[test]
fn slow_uniaxial_stretch_matches_the_homogeneous_solution_with_tet10() {
    uniaxial_stretch_matches(Technology::Tet10);
}

#[test]
fn slow_uniaxial_stretch_matches_the_homogeneous_solution_with_tet10_fbar() {
    uniaxial_stretch_matches(Technology::Tet10FBar);
}

/// 2 × 2 × 2 cells: 8 hexes, or 48 tets (Kuhn split).
fn uniaxial_stretch_matches(technology: Technology) {
    let mesh = match technology.shape() {
        ElementShape::Hex8 => box_of_hexes([SIDE; 3], [2, 2, 2]),
        ElementShape::Tet4 => box_of_tets([SIDE; 3], [2, 2, 2], TetOrder::Linear),
        ElementShape::Tet10 => box_of_tets([SIDE; 3], [2, 2, 2], TetOrder::Quadratic),
    }
    .unwrap();
    let material = neo_hookean();
    let settings = ExplicitSettings::new(2.0);
    let result = run_explicit(
        &mesh,
        &part_with(material.clone(), technology),
        &uniaxial(&mesh, 1.5, 2.0).into(),
        &settings,
    )
    .unwrap();
    let history = StretchHistory::parse("0:1,1:1.5").unwrap();
    let rows = run_uniaxial_stress(material.as_ref(), &history, 0.01).unwrap();
    let expected = rows.last().unwrap().engineering_stress * SIDE * SIDE;
    let last = result.history.last().unwrap();
    let reaction = last.reactions[0];
    println!(
        "{technology:?}: {} steps, reaction {reaction:.6} N, homogeneous {expected:.6} N, W_int {:.3e} J, \
         W_ext {:.3e} J, K {:.3e} J",
        result.steps, last.internal_energy, last.external_work, last.kinetic_energy
    );
    assert!(
        (reaction - expected).abs() < 0.01 * expected,
        "{reaction} vs {expected}"
    );
    // Free lateral faces contract: λ_t = 1 + u_y(y1)/side < 1.
    let lateral = result.displacement[mesh.node_set("y1").unwrap()[0] as usize][1] / SIDE;
    assert!(lateral < -0.1, "lateral strain {lateral}");
}

/// The same run gives bit-identical displacements on 1 and 2 threads (125 elements, two
/// chunks of elements updated in parallel).
#[test]
fn results_do_not_depend_on_the_thread_count() {
    let mesh = box_of_hexes([SIDE; 3], [5, 5, 5]).unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            run_explicit(
                &mesh,
                &part(neo_hookean()),
                &uniaxial(&mesh, 1.1, 0.05).into(),
                &ExplicitSettings::new(0.05),
            )
            .unwrap()
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(one.steps > 10);
    assert_eq!(one.displacement, two.displacement);
    assert_eq!(one.history, two.history);
}

/// A fixed step above the stable one is refused with the stable step and its element,
/// before any output.
#[test]
fn a_step_above_the_stability_limit_is_refused() {
    let mesh = box_of_hexes([SIDE; 3], [2, 2, 2]).unwrap();
    let mut settings = ExplicitSettings::new(0.1);
    settings.fixed_time_step = Some(1e-2);
    let err = run_explicit(
        &mesh,
        &part(neo_hookean()),
        &uniaxial(&mesh, 1.1, 0.1).into(),
        &settings,
    )
    .unwrap_err();
    assert!(matches!(err, SolverError::UnstableTimeStep { .. }), "{err}");
    assert!(err.to_string().contains("stable step"), "{err}");
}
