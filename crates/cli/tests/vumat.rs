//! `musclefem vumat build` and `musclefem run --allow-plugins` end to end: the example
//! VUMAT (examples/vumat/neo_hookean_vumat.f) built by the command, the example scene
//! (examples/vumat/neo_hookean_cube.toml) run with it, explicitly and implicitly (the
//! host's finite-difference tangent), against the same scene with the built-in
//! `neo-hookean`: the reactions of history.csv agree to 1e-6; and the same for the paper's
//! Hill muscle (examples/vumat/hill_vumat.f and hill_block_isometric.toml against
//! examples/hill_block_isometric.toml). Skipped, saying so, when gfortran is missing, unless
//! MUSCLEFEM_REQUIRE_GFORTRAN is set (scripts/test).

mod support;

use support::fortran::{examples, gfortran_or_skip, reaction_difference, run_ok};
use support::run::{musclefem, test_dir, text};

#[test]
fn the_example_vumat_scene_matches_the_builtin_material_in_both_solvers() {
    if !gfortran_or_skip("the_example_vumat_scene_matches_the_builtin_material_in_both_solvers") {
        return;
    }
    let dir = test_dir("vumat", "cube");
    let source = examples().join("neo_hookean_vumat.f");
    let printed = run_ok(
        &dir,
        &[
            "vumat",
            "build",
            source.to_str().unwrap(),
            "--name",
            "neo-hookean-vumat",
            "--props",
            "mu=11370:Pa,D=5e-9:1/Pa",
            "--fiber",
            "none",
            "--out",
            "libneo_hookean_vumat.so",
        ],
    );
    assert!(
        printed.contains("built libneo_hookean_vumat.so: material 'neo-hookean-vumat'")
            && printed.contains("plugin = \"libneo_hookean_vumat.so\""),
        "{printed}"
    );
    let scene = std::fs::read_to_string(examples().join("neo_hookean_cube.toml")).unwrap();
    std::fs::write(dir.join("vumat.toml"), &scene).unwrap();
    let builtin = scene
        .replace("model = \"neo-hookean-vumat\"", "model = \"neo-hookean\"")
        .replace("plugin = \"libneo_hookean_vumat.so\"\n", "")
        .replace(", vumat_density = 1000.0", "");
    assert!(!builtin.contains("vumat\"") && !builtin.contains("plugin ="));
    std::fs::write(dir.join("builtin.toml"), builtin).unwrap();

    // A scene's plugin is loaded only when allowed.
    let refused = musclefem(&dir, &["run", "vumat.toml", "--out", "refused"]);
    assert!(!refused.status.success());
    assert!(
        text(&refused.stderr).contains("--allow-plugins"),
        "{}",
        text(&refused.stderr)
    );

    for solver in ["explicit", "implicit"] {
        let vumat_out = format!("vumat-{solver}");
        let builtin_out = format!("builtin-{solver}");
        let mut args = vec!["run", "vumat.toml", "--allow-plugins", "--out", &vumat_out];
        if solver == "implicit" {
            args.extend(["--solver", "implicit"]);
        }
        run_ok(&dir, &args);
        args = vec!["run", "builtin.toml", "--out", &builtin_out];
        if solver == "implicit" {
            args.extend(["--solver", "implicit"]);
        }
        run_ok(&dir, &args);
        let (difference, scale) =
            reaction_difference(&dir.join(&vumat_out), &dir.join(&builtin_out));
        eprintln!("{solver}: reactions differ by {difference:e} of the largest, {scale} N");
        // The pull's reaction: P11(1.25) A0 = 0.585 N (plus inertia when explicit).
        assert!((0.58..0.60).contains(&scale), "{solver}: {scale} N");
        assert!(difference < 1e-6, "{solver}: {difference:e}");
    }
}

/// The Hill VUMAT's props: the built-in's parameters in hill_vumat.f's order.
const HILL_PROPS: &str = "D=5e-9:1/Pa,b=15,c=379:Pa,A=4,lambda_pe=1,sigma0=7e5:Pa,alpha=10,\
                          beta=1000:Pa,lambda_opt=1.05,k=0.3,k_c=4,k_e=5,d=1.45,\
                          lambda_dot_min=-17:1/s,S=50:1/s,n1=0,n2=0,t0=0:s,t1=1e30:s";

#[test]
fn the_hill_block_through_the_hill_vumat_matches_the_builtin_hill_in_both_solvers() {
    if !gfortran_or_skip(
        "the_hill_block_through_the_hill_vumat_matches_the_builtin_hill_in_both_solvers",
    ) {
        return;
    }
    let dir = test_dir("vumat", "hill");
    let source = examples().join("hill_vumat.f");
    run_ok(
        &dir,
        &[
            "vumat",
            "build",
            source.to_str().unwrap(),
            "--name",
            "hill-vumat",
            "--props",
            HILL_PROPS,
            "--nstatev",
            "3",
            "--statev-initial",
            "1,1,0",
            "--out",
            "libhill_vumat.so",
        ],
    );
    let scene = examples().join("hill_block_isometric.toml");
    std::fs::copy(&scene, dir.join("vumat.toml")).unwrap();
    let builtin = examples().join("../hill_block_isometric.toml");
    std::fs::copy(&builtin, dir.join("builtin.toml")).unwrap();
    for solver in ["explicit", "implicit"] {
        let vumat_out = format!("vumat-{solver}");
        let builtin_out = format!("builtin-{solver}");
        run_ok(
            &dir,
            &[
                "run",
                "vumat.toml",
                "--allow-plugins",
                "--out",
                &vumat_out,
                "--solver",
                solver,
            ],
        );
        run_ok(
            &dir,
            &[
                "run",
                "builtin.toml",
                "--out",
                &builtin_out,
                "--solver",
                solver,
            ],
        );
        let (difference, scale) =
            reaction_difference(&dir.join(&vumat_out), &dir.join(&builtin_out));
        eprintln!("Hill, {solver}: reactions differ by {difference:e} of the largest, {scale} N");
        // The isometric force: 692.8 kPa x 25 mm^2 = 17.3 N.
        assert!((17.2..17.4).contains(&scale), "{solver}: {scale} N");
        assert!(difference < 1e-6, "{solver}: {difference:e}");
    }
}
