//! `[step.implicit] linear_solver`: AMG-preconditioned conjugate gradients reach the
//! direct solver's end force on the stretched cube, and an unknown solver is refused.

use std::path::Path;

use musclefem_core::solver::amg_cg::LinearSolver;
use musclefem_core::solver::implicit::{Factorization, run_quasi_static};
use musclefem_io::scene::{Analysis, Model, load_scene};
use musclefem_materials::MaterialLibrary;

/// The neo-Hookean cube example, 8³ F-bar hex8 (about 2 000 unknowns: a two-level
/// hierarchy), with the pulled face also held laterally (a non-uniform state), and the
/// implicit keys `implicit`.
fn load(name: &str, implicit: &str) -> Result<Model, String> {
    let example =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/neo_hookean_cube_stretch.toml");
    let text = std::fs::read_to_string(example)
        .unwrap()
        .replace("divisions = [4, 4, 4]", "divisions = [8, 8, 8]")
        .replace(
            "implicit = { increments = 10 }",
            &format!("implicit = {{ {implicit} }}"),
        )
        + "\n[[displacements]]\npart = \"cube\"\nnodes = \"x1\"\ncomponents = [\"y\", \"z\"]\n";
    let dir = std::env::temp_dir().join(format!("musclefem_solver_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    load_scene(&path, &mut MaterialLibrary::with_builtins()).map_err(|e| e.to_string())
}

fn end_force(model: &Model) -> (f64, Vec<Factorization>) {
    let Analysis::Implicit(settings) = &model.analysis else {
        panic!("implicit");
    };
    let result = run_quasi_static(&model.mesh, &model.parts, &model.loads, settings).unwrap();
    let factorizations = result.steps.iter().map(|s| s.factorization).collect();
    (result.history.last().unwrap().reactions[0], factorizations)
}

#[test]
fn amg_cg_ends_at_the_direct_solvers_force() {
    let direct = load("direct", "increments = 5").unwrap();
    let amg = load("amg", "increments = 5, linear_solver = \"amg_cg\"").unwrap();
    let Analysis::Implicit(settings) = &amg.analysis else {
        panic!("implicit");
    };
    assert_eq!(settings.linear_solver, LinearSolver::AmgCg);
    let (expected, _) = end_force(&direct);
    let (force, factorizations) = end_force(&amg);
    assert!(
        factorizations.iter().all(|f| *f == Factorization::AmgCg),
        "{factorizations:?}"
    );
    assert!(
        (force - expected).abs() <= 1e-8 * expected.abs(),
        "AMG-CG {force} N, direct {expected} N"
    );
}

#[test]
fn an_unknown_linear_solver_is_refused_with_the_choices() {
    let error = load("unknown", "linear_solver = \"amg\"").unwrap_err();
    assert!(error.contains("\"amg_cg\""), "{error}");
}
