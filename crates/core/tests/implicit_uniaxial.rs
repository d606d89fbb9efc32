//! End-to-end checks of the quasi-static implicit solver on a cube of fully integrated
//! hex8 in uniaxial stretch (the setup of `explicit_uniaxial.rs`, loaded quasi-statically).

use std::collections::BTreeMap;
use std::sync::Arc;

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::{TetOrder, box_of_hexes, box_of_tets, distort};
use musclefem_core::solver::implicit::{
    Factorization, ImplicitResult, ImplicitSettings, run_quasi_static,
};
use musclefem_core::solver::{Part, PrescribedDisplacement, SolverError};
use musclefem_materials::driver::{StretchHistory, run_uniaxial_stress};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

const SIDE: f64 = 0.01;

fn neo_hookean(mu: f64, d: f64) -> Arc<dyn Material> {
    let params = BTreeMap::from([("mu".to_string(), mu), ("D".to_string(), d)]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap()
}

/// Compressible neo-Hookean (μ = 10 kPa, K = 2/D = 100 kPa), as in the explicit tests.
fn compressible() -> Arc<dyn Material> {
    neo_hookean(1e4, 2e-5)
}

/// The muscle's matrix: μ = 11 370 Pa, D = 5e-9 1/Pa (K/μ ≈ 35 000).
fn nearly_incompressible() -> Arc<dyn Material> {
    neo_hookean(11_370.0, 5e-9)
}

/// Symmetry on x0, y0, z0 and the x1 face pulled along x to `stretch` linearly over 1 s.
fn uniaxial(mesh: &Mesh, stretch: f64) -> Vec<PrescribedDisplacement> {
    let fixed = |set: &str, dof: usize| PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("x1").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::ramp(1.0, (stretch - 1.0) * SIDE).unwrap(),
        },
        fixed("x0", 0),
        fixed("y0", 1),
        fixed("z0", 2),
    ]
}

fn part(material: Arc<dyn Material>, technology: Technology) -> Vec<Part> {
    vec![Part {
        block: 0,
        technology,
        material,
        density: 1000.0,
    }]
}

/// P₁₁(λ) A₀ of the material in homogeneous uniaxial stress (the material-point driver).
fn homogeneous_reaction(material: &dyn Material, stretch: f64) -> f64 {
    let history = StretchHistory::parse(&format!("0:1,1:{stretch}")).unwrap();
    let rows = run_uniaxial_stress(material, &history, 0.01).unwrap();
    rows.last().unwrap().engineering_stress * SIDE * SIDE
}

fn stretch_cube(
    material: Arc<dyn Material>,
    divisions: usize,
    stretch: f64,
    settings: &ImplicitSettings,
) -> (Mesh, Result<ImplicitResult, SolverError>) {
    let mesh = box_of_hexes([SIDE; 3], [divisions; 3]).unwrap();
    let result = run_quasi_static(
        &mesh,
        &part(material, Technology::Hex8Full),
        &uniaxial(&mesh, stretch).into(),
        settings,
    );
    (mesh, result)
}

/// Plain Newton in `increments` steps: the tangent predictor and linear solves to the
/// solver's own tolerance, so that the residuals show the consistent tangent's quadratic
/// convergence (the extrapolated first guess and the forcing term, which shorten it, are
/// checked in `implicit_first_guess.rs`).
fn plain_newton(increments: usize) -> ImplicitSettings {
    let mut settings = ImplicitSettings::new(1.0, increments);
    settings.extrapolate = false;
    settings.forcing = None;
    settings
}

/// Prints a step's relative residuals and checks that they fall quadratically: for each
/// iteration from r_k < 0.1 to r_{k+1} above the round-off `floor`, log r_{k+1} / log r_k
/// is above 1.7 (2 for quadratic convergence, 1 for linear; a linear rate of 0.1 gives
/// 1.5). Returns the number of iterations judged.
fn print_and_check_quadratic(label: &str, residuals: &[f64], floor: f64) -> usize {
    let listed: Vec<String> = residuals.iter().map(|r| format!("{r:.3e}")).collect();
    println!("{label}: relative residuals [{}]", listed.join(", "));
    let ratios: Vec<f64> = residuals
        .windows(2)
        .filter(|w| w[0] < 0.1 && w[1] > floor)
        .map(|w| w[1].log10() / w[0].log10())
        .collect();
    println!("{label}: log ratios {ratios:.2?}");
    for r in &ratios {
        assert!(
            *r > 1.7,
            "{label}: convergence is not quadratic: ratios {ratios:?}"
        );
    }
    ratios.len()
}

/// λ = 1.5 in 10 steps: the reaction on the pulled face is P₁₁(1.5) A₀ of the driver
/// within 1e-8 (the patch test makes the field homogeneous, so only the tolerances of
/// the two solves remain); every step converges quadratically in a few iterations.
#[test]
fn uniaxial_stretch_matches_the_homogeneous_solution_and_converges_quadratically() {
    let material = compressible();
    let settings = plain_newton(10);
    let (mesh, result) = stretch_cube(material.clone(), 2, 1.5, &settings);
    let result = result.unwrap();
    assert_eq!(result.steps.len(), 10);
    assert_eq!(result.cuts, 0);
    let last = result.history.last().unwrap();
    assert_eq!(last.time, 1.0);
    let expected = homogeneous_reaction(material.as_ref(), 1.5);
    let error = (last.reactions[0] - expected).abs() / expected;
    println!(
        "reaction {:.12e} N, homogeneous {expected:.12e} N, relative error {error:.2e}; \
         iterations per step {:?}",
        last.reactions[0],
        result
            .steps
            .iter()
            .map(|s| s.iterations)
            .collect::<Vec<_>>()
    );
    assert!(error < 1e-8, "{error}");
    // The symmetry faces carry the same force the other way.
    assert!((last.reactions[1] + last.reactions[0]).abs() < 1e-9 * expected);
    assert!(result.steps.iter().all(|s| s.iterations <= 6));
    assert!(
        result
            .steps
            .iter()
            .all(|s| s.factorization == Factorization::Cholesky)
    );
    // Every step has at least one iteration above the round-off floor (~1e-14).
    for (n, step) in result.steps.iter().enumerate() {
        let judged = print_and_check_quadratic(&format!("step {}", n + 1), &step.residuals, 1e-13);
        assert!(
            judged >= 1,
            "step {}: no iteration in the asymptotic range",
            n + 1
        );
    }
    // Lateral contraction of the free faces: λ_t = 1 + u_y(y1)/side.
    let lateral = 1.0 + result.displacement[mesh.node_set("y1").unwrap()[0] as usize][1] / SIDE;
    println!("lateral stretch {lateral:.6}");
    assert!(lateral < 0.9, "{lateral}");
}

/// The muscle's nearly incompressible matrix (K/μ ≈ 35 000) converges as well, with a
/// homogeneous field that keeps the volume (J = 1 within 1e-4).
#[test]
fn nearly_incompressible_stretch_converges() {
    let material = nearly_incompressible();
    let settings = plain_newton(10);
    let (mesh, result) = stretch_cube(material.clone(), 2, 1.5, &settings);
    let result = result.unwrap();
    let expected = homogeneous_reaction(material.as_ref(), 1.5);
    let reaction = result.history.last().unwrap().reactions[0];
    let error = (reaction - expected).abs() / expected;
    println!(
        "nearly incompressible: reaction {reaction:.9e} N, homogeneous {expected:.9e} N, \
         relative error {error:.2e}; iterations per step {:?}",
        result
            .steps
            .iter()
            .map(|s| s.iterations)
            .collect::<Vec<_>>()
    );
    assert!(error < 1e-7, "{error}");
    // Round-off of the pressure 2(J − 1)/D is ~ε K/μ ≈ 1e-11 of the stresses: the floor
    // is higher than in the compressible case, and fewer iterations can be judged.
    let mut judged = 0;
    for (n, step) in result.steps.iter().enumerate() {
        let label = format!("nearly incompressible, step {}", n + 1);
        judged += print_and_check_quadratic(&label, &step.residuals, 1e-10);
    }
    assert!(
        judged >= 5,
        "only {judged} iterations in the asymptotic range"
    );
    let lateral = 1.0 + result.displacement[mesh.node_set("y1").unwrap()[0] as usize][1] / SIDE;
    let jacobian = 1.5 * lateral * lateral;
    assert!((jacobian - 1.0).abs() < 1e-4, "J = {jacobian}");
}

/// Tiny stretches of the muscle's matrix (λ = 1 + 1e-3 and 1 + 1e-5 in 10 steps): the
/// residual's round-off floor (~ε K/μ of the stresses) lies above 1e-10 of the internal
/// forces, so convergence comes from the round-off criteria, in few iterations; the
/// reaction still matches the driver (1e-4; the driver's lateral stresses are solved to
/// 1e-6 Pa absolute).
#[test]
fn tiny_stretches_of_a_nearly_incompressible_cube_converge() {
    let material = nearly_incompressible();
    for stretch in [1.001, 1.00001] {
        let (_, result) = stretch_cube(
            material.clone(),
            3,
            stretch,
            &ImplicitSettings::new(1.0, 10),
        );
        let result = result.unwrap();
        let iterations: Vec<usize> = result.steps.iter().map(|s| s.iterations).collect();
        let reaction = result.history.last().unwrap().reactions[0];
        let expected = homogeneous_reaction(material.as_ref(), stretch);
        let error = (reaction - expected).abs() / expected;
        println!("λ = {stretch}: iterations {iterations:?}, reaction error {error:.2e}");
        assert!(iterations.iter().all(|&n| n <= 4), "{iterations:?}");
        assert!(error < 1e-4, "{reaction} vs {expected}");
    }
}

/// 1 and 2 threads give bit-identical displacements, reactions and residuals (1000
/// elements: 16 chunks updated in parallel; their stiffness is built in two waves of 8
/// chunks on 1 thread and in one wave of 16 on 2, `implicit_stiffness.rs`).
#[test]
fn results_do_not_depend_on_the_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            stretch_cube(compressible(), 10, 1.3, &ImplicitSettings::new(1.0, 3))
                .1
                .unwrap()
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(one.displacement.iter().any(|u| u.amax() > 0.0));
    assert_eq!(one.displacement, two.displacement);
    assert_eq!(one.history, two.history);
    assert_eq!(one.steps, two.steps);
}

/// λ = 3 of the nearly incompressible matrix in one increment: the predictor carries the
/// stretch with the linear contraction (λ_t ≈ 1 − ½ × 2 = 0) and inverts elements, so the
/// step fails; with cutting it is halved until it converges, grows back, and ends at the
/// homogeneous reaction. With fixed increments the same run is an error naming the time.
#[test]
fn a_step_too_large_is_cut_and_still_converges() {
    let material = nearly_incompressible();
    let settings = ImplicitSettings::new(1.0, 1).with_cutting();
    let (_, result) = stretch_cube(material.clone(), 2, 3.0, &settings);
    let result = result.unwrap();
    let increments: Vec<f64> = result.steps.iter().map(|s| s.increment).collect();
    println!(
        "cuts {}, increments {increments:.4?}, iterations {:?}",
        result.cuts,
        result
            .steps
            .iter()
            .map(|s| s.iterations)
            .collect::<Vec<_>>()
    );
    assert!(result.cuts >= 1);
    assert!(increments.iter().any(|&dt| dt < 1.0));
    let expected = homogeneous_reaction(material.as_ref(), 3.0);
    let reaction = result.history.last().unwrap().reactions[0];
    assert!(
        (reaction - expected).abs() < 1e-7 * expected,
        "{reaction} vs {expected}"
    );

    let fixed = ImplicitSettings::new(1.0, 1);
    let error = stretch_cube(material, 2, 3.0, &fixed).1.unwrap_err();
    println!("fixed increment: {error}");
    assert!(matches!(error, SolverError::NotConverged { .. }), "{error}");
    assert!(error.to_string().contains("t = 1.0"), "{error}");
}

/// The other technologies with an element stiffness (one-point hex8 with hourglass
/// control, linear and quadratic tets, F-bar tet10 with its mixed-pressure tangent)
/// reproduce the homogeneous stretch too (1e-8), in few iterations per step.
#[test]
fn other_technologies_match_the_homogeneous_solution() {
    let material = compressible();
    let expected = homogeneous_reaction(material.as_ref(), 1.5);
    let meshes = [
        (
            Technology::hex8_one_point(1e4),
            box_of_hexes([SIDE; 3], [2, 2, 2]),
        ),
        (
            Technology::Tet4,
            box_of_tets([SIDE; 3], [2, 2, 2], TetOrder::Linear),
        ),
        (
            Technology::Tet10,
            box_of_tets([SIDE; 3], [1, 1, 1], TetOrder::Quadratic),
        ),
        (
            Technology::Tet10FBar,
            box_of_tets([SIDE; 3], [1, 1, 1], TetOrder::Quadratic),
        ),
    ];
    for (technology, mesh) in meshes {
        let mesh = mesh.unwrap();
        let result = run_quasi_static(
            &mesh,
            &part(material.clone(), technology),
            &uniaxial(&mesh, 1.5).into(),
            &ImplicitSettings::new(1.0, 10),
        )
        .unwrap();
        let reaction = result.history.last().unwrap().reactions[0];
        let error = (reaction - expected).abs() / expected;
        let iterations: Vec<usize> = result.steps.iter().map(|s| s.iterations).collect();
        println!("{technology:?}: relative error {error:.2e}, iterations {iterations:?}");
        assert!(error < 1e-8, "{technology:?}: {reaction} vs {expected}");
        assert!(
            iterations.iter().all(|&n| n <= 6),
            "{technology:?}: {iterations:?}"
        );
    }
}

/// The active Hill muscle (n2 = 1, fibers along x) held at λ = 1 for 0.5 s, then stretched
/// to 1.2 at 2.5 s, in 50 increments of 0.05 s: the reaction follows the material-point
/// driver run with the same steps (the field is homogeneous) at every step, within 1e-7
/// of the peak force (measured: 7e-12), and the last step converges quadratically: the
/// muscle's consistent tangent and state commits work in the solver.
#[test]
fn active_muscle_follows_the_material_point_driver() {
    let material = MaterialLibrary::with_builtins()
        .create("hill", &BTreeMap::from([("n2".to_string(), 1.0)]))
        .unwrap();
    let mesh = box_of_hexes([SIDE; 3], [2, 2, 2]).unwrap();
    let mut prescribed = uniaxial(&mesh, 1.2);
    prescribed[0].amplitude =
        Amplitude::new(vec![(0.0, 0.0), (0.5, 0.0), (2.5, 0.2 * SIDE)]).unwrap();
    let result = run_quasi_static(
        &mesh,
        &part(material.clone(), Technology::Hex8Full),
        &prescribed.into(),
        &ImplicitSettings::new(2.5, 50),
    )
    .unwrap();
    let history = StretchHistory::parse("0:1,0.5:1,2.5:1.2").unwrap();
    let rows = run_uniaxial_stress(material.as_ref(), &history, 0.05).unwrap();
    assert_eq!(rows.len(), result.history.len() + 1);
    let peak = rows
        .iter()
        .map(|r| r.engineering_stress.abs() * SIDE * SIDE)
        .fold(0.0, f64::max);
    let mut largest: f64 = 0.0;
    for (row, step) in rows[1..].iter().zip(&result.history) {
        assert!((row.time - step.time).abs() < 1e-9);
        largest = largest.max((row.engineering_stress * SIDE * SIDE - step.reactions[0]).abs());
    }
    let iterations: Vec<usize> = result.steps.iter().map(|s| s.iterations).collect();
    println!(
        "active muscle: peak reaction {peak:.4e} N, largest difference {largest:.3e} N, \
         factorization {:?}, iterations {iterations:?}",
        result.steps.last().unwrap().factorization
    );
    print_and_check_quadratic(
        "active muscle, last step",
        &result.steps[49].residuals,
        1e-10,
    );
    assert!(largest < 1e-7 * peak, "{largest} vs {peak}");
}

/// F-bar with its consistent tangent on a distorted 3 × 3 × 3 cube of the muscle's nearly
/// incompressible matrix (K/μ ≈ 35 000), λ = 1.5 in 10 steps: F-bar passes the
/// constant-stress patch test on distorted meshes, so the reaction is the homogeneous one
/// (1e-7), and Newton converges quadratically (log ratio > 1.7 over at least 5 judged
/// iterations), with Cholesky since the neo-Hookean tangent is symmetric.
#[test]
fn fbar_converges_quadratically_on_a_distorted_nearly_incompressible_cube() {
    let material = nearly_incompressible();
    let mut mesh = box_of_hexes([SIDE; 3], [3; 3]).unwrap();
    assert!(distort(&mut mesh, 0.3, 7).unwrap() > 0);
    let result = run_quasi_static(
        &mesh,
        &part(material.clone(), Technology::Hex8FBar),
        &uniaxial(&mesh, 1.5).into(),
        &plain_newton(10),
    )
    .unwrap();
    let expected = homogeneous_reaction(material.as_ref(), 1.5);
    let reaction = result.history.last().unwrap().reactions[0];
    let error = (reaction - expected).abs() / expected;
    let iterations: Vec<usize> = result.steps.iter().map(|s| s.iterations).collect();
    println!("F-bar: relative error {error:.2e}, iterations {iterations:?}");
    assert!(error < 1e-7, "{reaction} vs {expected}");
    let mut judged = 0;
    for (n, step) in result.steps.iter().enumerate() {
        judged +=
            print_and_check_quadratic(&format!("F-bar, step {}", n + 1), &step.residuals, 1e-10);
        assert_eq!(step.factorization, Factorization::Cholesky);
    }
    assert!(
        judged >= 5,
        "only {judged} iterations in the asymptotic range"
    );
}
