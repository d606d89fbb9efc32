//! The paper's elongation test through a VUMAT: `musclefem elongate` writes the passive and
//! the active test as scenes with the built-in `hill` (a coarse cylinder with sliding grips,
//! implicit); the same scenes with the material swapped for examples/vumat/hill_vumat.f,
//! built by `musclefem vumat build`, run by `musclefem run`, give the built-in's curve: the
//! reactions (the force of curve.csv) to 1e-6 of the largest, every increment. Skipped,
//! saying so, when gfortran is missing, unless MUSCLEFEM_REQUIRE_GFORTRAN is set.

mod support;

use support::fortran::{
    column_difference, examples, gfortran_or_skip, reaction_difference, run_ok,
};
use support::run::{CHEAP_ELONGATION, test_dir};

/// The Hill VUMAT's props: the built-in's parameters in hill_vumat.f's order.
const HILL_PROPS: &str = "D=5e-9:1/Pa,b=15,c=379:Pa,A=4,lambda_pe=1,sigma0=7e5:Pa,alpha=10,\
                          beta=1000:Pa,lambda_opt=1.05,k=0.3,k_c=4,k_e=5,d=1.45,\
                          lambda_dot_min=-17:1/s,S=50:1/s,n1=0,n2=0,t0=0:s,t1=1e30:s";

#[test]
fn the_elongation_test_through_the_hill_vumat_gives_the_builtin_curve() {
    if !gfortran_or_skip("the_elongation_test_through_the_hill_vumat_gives_the_builtin_curve") {
        return;
    }
    let dir = test_dir("vumat", "elongation");
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
    let mut args = vec!["elongate", "--mode", "both", "--frame-interval", "0"];
    args.extend_from_slice(&CHEAP_ELONGATION);
    args.extend_from_slice(&["--out", "builtin"]);
    run_ok(&dir, &args);

    for mode in ["passive", "active"] {
        let builtin = dir.join("builtin").join(mode);
        let scene = std::fs::read_to_string(builtin.join("scene.toml")).unwrap();
        assert_eq!(scene.matches("model = \"hill\"\n").count(), 1, "{scene}");
        let parameters = if mode == "passive" {
            "parameters = { n2 = 0.0, t0 = 0.0 }"
        } else {
            "parameters = { n2 = 1.0, t0 = 0.0 }"
        };
        assert!(scene.contains(parameters), "{scene}");
        let swapped = scene
            .replace(
                "model = \"hill\"\n",
                "model = \"hill-vumat\"\nplugin = \"libhill_vumat.so\"\n",
            )
            .replace(
                parameters,
                &parameters.replace(" }", ", vumat_density = 1060.0 }"),
            );
        let vumat = dir.join(format!("vumat-{mode}"));
        std::fs::create_dir_all(&vumat).unwrap();
        std::fs::write(vumat.join("scene.toml"), swapped).unwrap();
        std::fs::copy(builtin.join("specimen.inp"), vumat.join("specimen.inp")).unwrap();
        std::fs::copy(dir.join("libhill_vumat.so"), vumat.join("libhill_vumat.so")).unwrap();
        let scene_path = format!("vumat-{mode}/scene.toml");
        let out = format!("vumat-{mode}/run");
        run_ok(
            &dir,
            &["run", &scene_path, "--allow-plugins", "--out", &out],
        );

        let (difference, scale) = reaction_difference(&dir.join(&out), &builtin);
        let (energy, _) = column_difference(&dir.join(&out), &builtin, "internal_energy");
        eprintln!(
            "elongation, {mode}: reactions differ by {difference:e} of the largest ({scale} N), \
             internal energy by {energy:e}"
        );
        // The force at 20 % strain: 126 kPa passive, 755 kPa active (elongate's printed
        // engineering stresses) over the specimen's 2.4 cm^2.
        let expected = if mode == "passive" {
            25.0..35.0
        } else {
            160.0..200.0
        };
        assert!(expected.contains(&scale), "{mode}: {scale} N");
        assert!(difference < 1e-6, "{mode}: {difference:e}");
        assert!(energy < 1e-6, "{mode}: internal energy {energy:e}");
    }
}
