//! `musclefem umat build` and `musclefem run --allow-plugins` end to end: the example UMAT
//! (examples/vumat/neo_hookean_umat.f) built by the command, with its DDSDDE and with
//! `--tangent finite-difference`, the example scene (examples/vumat/neo_hookean_umat_cube.toml)
//! run with it implicitly and explicitly against the same scene with the built-in
//! `neo-hookean` (examples/neo_hookean_cube_stretch.toml): the reactions of history.csv agree
//! to 1e-6 of the largest, and implicitly every increment takes the built-in's number of
//! Newton iterations — the converted DDSDDE is the built-in's consistent tangent (a wrong
//! tangent converges more slowly). Skipped, saying so, when gfortran is missing, unless
//! MUSCLEFEM_REQUIRE_GFORTRAN is set (scripts/test).

mod support;

use std::path::Path;

use support::fortran::{examples, gfortran_or_skip, history, reaction_difference, run_ok};
use support::run::{example, test_dir};

/// The newton_iterations column of a run's history.
fn newton_iterations(dir: &Path) -> Vec<f64> {
    let (header, rows) = history(dir);
    let column = header
        .iter()
        .position(|h| h == "newton_iterations")
        .unwrap();
    rows.iter().map(|r| r[column]).collect()
}

#[test]
fn the_example_umat_scene_matches_the_builtin_material_in_both_solvers() {
    if !gfortran_or_skip("the_example_umat_scene_matches_the_builtin_material_in_both_solvers") {
        return;
    }
    let dir = test_dir("umat", "cube");
    let source = examples().join("neo_hookean_umat.f");
    let source = source.to_str().unwrap();
    let props = "mu=11370:Pa,D=5e-9:1/Pa";
    let printed = run_ok(
        &dir,
        &[
            "umat",
            "build",
            source,
            "--name",
            "neo-hookean-umat",
            "--props",
            props,
            "--out",
            "libneo_hookean_umat.so",
        ],
    );
    assert!(
        printed.contains("built libneo_hookean_umat.so: material 'neo-hookean-umat'")
            && printed.contains(
                "(UMAT, cmname NEO-HOOKEAN-UMAT, 2 props, nstatev 0, fiber \
                                 convention none, tangent ddsdde)"
            ),
        "{printed}"
    );
    // The same UMAT with the host's finite differences, under the same material name.
    std::fs::create_dir_all(dir.join("fd")).unwrap();
    run_ok(
        &dir,
        &[
            "umat",
            "build",
            source,
            "--name",
            "neo-hookean-umat",
            "--props",
            props,
            "--tangent",
            "finite-difference",
            "--out",
            "fd/libneo_hookean_umat.so",
        ],
    );
    let scene = std::fs::read_to_string(examples().join("neo_hookean_umat_cube.toml")).unwrap();
    std::fs::write(dir.join("umat.toml"), &scene).unwrap();
    std::fs::write(dir.join("fd/umat.toml"), &scene).unwrap();
    let builtin = example("neo_hookean_cube_stretch.toml");

    for solver in ["implicit", "explicit"] {
        let builtin_out = format!("builtin-{solver}");
        run_ok(
            &dir,
            &["run", &builtin, "--out", &builtin_out, "--solver", solver],
        );
        for (scene, tangent) in [
            ("umat.toml", "ddsdde"),
            ("fd/umat.toml", "finite-difference"),
        ] {
            let out = format!("umat-{tangent}-{solver}");
            run_ok(
                &dir,
                &[
                    "run",
                    scene,
                    "--allow-plugins",
                    "--out",
                    &out,
                    "--solver",
                    solver,
                ],
            );
            let (difference, scale) = reaction_difference(&dir.join(&out), &dir.join(&builtin_out));
            eprintln!(
                "UMAT ({tangent} tangent), {solver}: reactions differ by {difference:e} of the \
                 largest, {scale} N"
            );
            // P11 at stretch 1.5 over 1 cm^2: about 1.0 N.
            assert!((0.95..1.1).contains(&scale), "{solver}: {scale} N");
            assert!(difference < 1e-6, "{tangent}, {solver}: {difference:e}");
        }
    }
    // Plain Newton (tangent predictor, every solve to the solver's own tolerance), where
    // the iterations show the tangent's quality alone: the UMAT's, analytic or by finite
    // differences, takes those of the built-in material. (With the default extrapolated
    // first guess the finite-difference tangent, accurate to ~1e-7, takes 4 iterations in
    // two increments where the others take 3: its error then decides the last one.)
    let plain = |text: &str| {
        assert!(text.contains("implicit = { increments = 10 }"));
        text.replace(
            "implicit = { increments = 10 }",
            "implicit = { increments = 10, extrapolate = false, inexact_newton = false }",
        )
    };
    let builtin_text = std::fs::read_to_string(&builtin).unwrap();
    std::fs::write(dir.join("plain_builtin.toml"), plain(&builtin_text)).unwrap();
    std::fs::write(dir.join("plain_umat.toml"), plain(&scene)).unwrap();
    std::fs::write(dir.join("fd/plain_umat.toml"), plain(&scene)).unwrap();
    run_ok(
        &dir,
        &["run", "plain_builtin.toml", "--out", "plain-builtin"],
    );
    let expected = newton_iterations(&dir.join("plain-builtin"));
    for (scene, tangent) in [
        ("plain_umat.toml", "ddsdde"),
        ("fd/plain_umat.toml", "finite-difference"),
    ] {
        let out = format!("plain-umat-{tangent}");
        run_ok(&dir, &["run", scene, "--allow-plugins", "--out", &out]);
        let iterations = newton_iterations(&dir.join(&out));
        eprintln!(
            "plain Newton iterations: UMAT ({tangent}) {iterations:?}, built-in {expected:?}"
        );
        assert_eq!(iterations, expected, "{tangent}");
    }
}
