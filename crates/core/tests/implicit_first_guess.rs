//! The implicit solver's cheaper Newton on the uniaxial cube of issue #36
//! (`verification::uniaxial_cube`, F-bar hex8, neo-Hookean): each increment starts from
//! the last one extrapolated, the iterative solves stop at Newton's forcing term, and the
//! stiffness of a converged state is never built. The answer must be that of the plain
//! Newton (tangent predictor, every solve to its own tolerance) within the tolerances.

use musclefem_core::solver::amg_cg::LinearSolver;
use musclefem_core::solver::implicit::{ImplicitResult, ImplicitSettings, run_quasi_static};
use musclefem_core::verification::uniaxial_cube::UniaxialCube;

fn run(cube: &UniaxialCube, settings: &ImplicitSettings) -> ImplicitResult {
    let model = cube.model();
    run_quasi_static(&model.mesh, &model.parts, &model.loads, settings).unwrap()
}

fn newton_iterations(result: &ImplicitResult) -> usize {
    result.steps.iter().map(|s| s.iterations).sum()
}

fn end_force(result: &ImplicitResult) -> f64 {
    result.history.last().unwrap().reactions[0]
}

fn same_force_in_fewer_iterations(poisson: f64, linear_solver: LinearSolver) {
    let cube = UniaxialCube::with_poisson(6, poisson);
    let mut plain = cube.settings();
    plain.extrapolate = false;
    plain.forcing = None;
    plain.linear_solver = linear_solver;
    let mut settings = cube.settings();
    settings.linear_solver = linear_solver;
    let (reference, result) = (run(&cube, &plain), run(&cube, &settings));
    let (f0, f) = (end_force(&reference), end_force(&result));
    println!(
        "ν = {poisson}, {linear_solver:?}: plain {} Newton iterations, {} stiffness builds \
         of {} evaluations; now {}, {} of {}; end force {f0:.15e} against {f:.15e} N",
        newton_iterations(&reference),
        reference.evaluation_times.stiffness_builds,
        reference.evaluation_times.evaluations,
        newton_iterations(&result),
        result.evaluation_times.stiffness_builds,
        result.evaluation_times.evaluations,
    );
    // Both converged to a relative residual of 1e-10: the forces agree far below 1e-8.
    assert!((f - f0).abs() <= 1e-10 * f0.abs(), "{f} against {f0}");
    // The first increment has nothing to extrapolate; every later one keeps the guess.
    assert!(!result.steps[0].extrapolated);
    assert!(result.steps[1..].iter().all(|s| s.extrapolated));
    assert!(
        newton_iterations(&result) < newton_iterations(&reference),
        "{} against {}",
        newton_iterations(&result),
        newton_iterations(&reference)
    );
    // No stiffness where Newton converged: at most one build per solve.
    let solves = result.linear_solves.solves;
    assert!(result.evaluation_times.stiffness_builds <= solves);
    assert!(result.evaluation_times.stiffness_builds < result.evaluation_times.evaluations);
}

#[test]
fn the_compressible_cube_reaches_the_same_force_in_fewer_iterations() {
    same_force_in_fewer_iterations(0.3, LinearSolver::Direct);
}

#[test]
fn the_nearly_incompressible_cube_reaches_the_same_force_in_fewer_iterations() {
    same_force_in_fewer_iterations(0.49, LinearSolver::Direct);
}

#[test]
fn amg_cg_reaches_the_same_force_in_fewer_iterations() {
    same_force_in_fewer_iterations(0.3, LinearSolver::AmgCg);
}
