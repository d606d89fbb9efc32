//! Scene files: the examples build and run to the results their comments promise.

use std::path::{Path, PathBuf};

use musclefem_core::solver::explicit::run_explicit;
use musclefem_core::solver::implicit::run_quasi_static;
use musclefem_io::scene::{Analysis, load_scene};
use musclefem_materials::MaterialLibrary;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// Every example in examples/ parses and builds.
#[test]
fn every_example_builds() {
    let directory = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut count = 0;
    for entry in std::fs::read_dir(&directory).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let model = load_scene(&path, &mut MaterialLibrary::with_builtins())
                .unwrap_or_else(|e| panic!("{e}"));
            assert!(!model.parts.is_empty());
            count += 1;
        }
    }
    assert!(count >= 2, "{count} examples");
}

/// The neo-Hookean cube: the reaction on x1 at λ = 1.5 is the material-point driver's
/// 10.0257 kPa × 1 cm² (its comment says 1.00 N).
#[test]
fn the_neo_hookean_cube_example_reaches_the_promised_reaction() {
    let model = load_scene(
        &example("neo_hookean_cube_stretch.toml"),
        &mut MaterialLibrary::with_builtins(),
    )
    .unwrap();
    let Analysis::Implicit(settings) = &model.analysis else {
        panic!("the example is implicit");
    };
    let result = run_quasi_static(&model.mesh, &model.parts, &model.loads, settings).unwrap();
    assert_eq!(model.displacement_names[0], "cube.x1.x");
    let reaction = result.history.last().unwrap().reactions[0];
    let expected = 10_025.68 * 1e-4;
    assert!(
        (reaction - expected).abs() < 1e-6 * expected,
        "reaction {reaction} N, expected {expected} N"
    );
}

/// The coupled neo-Hookean cube (issue #34): the reaction on x1 at λ = 1.5 is the closed
/// form P₁₁ = [μ (λ² − 1) + λ_L ln J] / λ × 1 cm², the lateral stretch t solving
/// μ (t² − 1) + λ_L ln(λ t²) = 0 by bisection here (its comment says 0.984 N).
#[test]
fn the_coupled_neo_hookean_cube_example_reaches_the_closed_form_reaction() {
    let model = load_scene(
        &example("neo_hookean_coupled_cube_stretch.toml"),
        &mut MaterialLibrary::with_builtins(),
    )
    .unwrap();
    let Analysis::Implicit(settings) = &model.analysis else {
        panic!("the example is implicit");
    };
    let result = run_quasi_static(&model.mesh, &model.parts, &model.loads, settings).unwrap();
    assert_eq!(model.displacement_names[0], "cube.x1.x");
    let reaction = result.history.last().unwrap().reactions[0];
    let (mu, lame, stretch) = (1.0e4, 1.5e4, 1.5);
    let lateral_stress = |t: f64| mu * (t * t - 1.0) + lame * (stretch * t * t).ln();
    let (mut low, mut high) = (0.5, 1.0);
    assert!(lateral_stress(low) < 0.0 && lateral_stress(high) > 0.0);
    for _ in 0..100 {
        let mid = 0.5 * (low + high);
        if lateral_stress(mid) < 0.0 {
            low = mid;
        } else {
            high = mid;
        }
    }
    let jacobian = stretch * low * low;
    let expected = (mu * (stretch * stretch - 1.0) + lame * jacobian.ln()) / stretch * 1e-4;
    eprintln!(
        "reaction {reaction} N, closed form {expected} N: relative difference {:.1e}",
        (reaction / expected - 1.0).abs()
    );
    assert!(
        (reaction - expected).abs() < 1e-6 * expected,
        "reaction {reaction} N, expected {expected} N"
    );
    assert!(
        (expected - 0.9835).abs() < 5e-5,
        "the comment's 0.984 N: {expected}"
    );
}

/// The Hill block held isometrically: the reaction at 0.15 s is the driver's isometric
/// 692.76 kPa × 25 mm² (its comment says 17.3 N), within 1 %.
#[test]
fn the_isometric_hill_example_reaches_the_promised_force() {
    let model = load_scene(
        &example("hill_block_isometric.toml"),
        &mut MaterialLibrary::with_builtins(),
    )
    .unwrap();
    let Analysis::Explicit(settings) = &model.analysis else {
        panic!("the example is explicit");
    };
    let result = run_explicit(&model.mesh, &model.parts, &model.loads, settings).unwrap();
    let reaction = result.history.last().unwrap().reactions[1];
    let expected = 692_757.25 * 25e-6;
    assert!(
        (reaction - expected).abs() < 0.01 * expected,
        "reaction {reaction} N, expected {expected} N"
    );
}
