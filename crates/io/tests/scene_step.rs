//! The `[step.implicit]` keys a study needs (the knee's Newton and Newmark settings) and
//! the explicit step's `mass_scaling_frame`:
//! they reach the solver's settings as written, and what does not apply is refused with
//! its line.

use musclefem_io::scene::{Analysis, load_scene};
use musclefem_materials::MaterialLibrary;

/// A cube beside a moving rigid sphere, its implicit step's keys `implicit`.
fn scene(implicit: &str) -> String {
    format!(
        r#"schema_version = 1

[[materials]]
name = "rubber"
model = "neo-hookean"

[[parts]]
name = "cube"
material = "rubber"
element = "hex8-fbar"
density = 1000.0
mesh = {{ generator = "box", size = [0.01, 0.01, 0.01], divisions = [1, 1, 1] }}

[[displacements]]
part = "cube"
nodes = "x0"
components = ["x", "y", "z"]

[[rigid_bodies]]
name = "ball"
surface = {{ shape = "sphere", center = [0.02, 0.005, 0.005], radius = 0.005 }}
translation = [0.0, 0.01, 0.0]

[step]
solver = "implicit"
duration = 1.0
implicit = {{ {implicit} }}
"#
    )
}

fn load(name: &str, implicit: &str) -> Result<musclefem_io::scene::Model, String> {
    let dir = std::env::temp_dir().join(format!("musclefem_step_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene(implicit)).unwrap();
    load_scene(&path, &mut MaterialLibrary::with_builtins()).map_err(|e| e.to_string())
}

#[test]
fn the_knees_newton_and_newmark_settings_are_scene_keys() {
    let model = load(
        "keys",
        "increments = 100, dynamic = true, numerical_dissipation = 0.1, \
         residual_tolerance = 1e-6, correction_tolerance = 1e-5, line_search_cuts = 3, \
         max_iterations = 30, factor_reuse = false, inexact_newton = false, extrapolate = false, \
         predictor_frame = \"ball\"",
    )
    .unwrap();
    let Analysis::Implicit(settings) = &model.analysis else {
        panic!("implicit");
    };
    let newmark = settings.dynamics.as_ref().unwrap();
    // γ = ½ + α, β = (1 + α)²/4 with α = 0.1.
    assert!((newmark.gamma - 0.6).abs() < 1e-15);
    assert!((newmark.beta - 0.3025).abs() < 1e-15);
    assert_eq!(settings.residual_tolerance, 1e-6);
    assert_eq!(settings.correction_tolerance, 1e-5);
    assert_eq!(settings.line_search_cuts, 3);
    assert_eq!(settings.max_iterations, 30);
    assert!(settings.factor_reuse.is_none());
    assert!(settings.forcing.is_none());
    assert!(!settings.extrapolate);
    let frame = settings.predictor_frame.as_ref().unwrap();
    // The sphere's motion: 10 mm along y over the second.
    let moved = frame.isometry_at(1.0).translation.vector;
    assert!(
        (moved - nalgebra::Vector3::new(0.0, 0.01, 0.0)).norm() < 1e-15,
        "{moved}"
    );
    let defaults = load("defaults", "increments = 2").unwrap();
    let Analysis::Implicit(defaults) = &defaults.analysis else {
        panic!("implicit");
    };
    assert!(defaults.dynamics.is_none() && defaults.predictor_frame.is_none());
    assert!(defaults.factor_reuse.is_some());
    assert!(defaults.forcing.is_some() && defaults.extrapolate);
}

#[test]
fn implicit_keys_that_do_not_apply_are_refused_with_their_line() {
    let quasi_static = load("qs", "numerical_dissipation = 0.1").unwrap_err();
    assert!(
        quasi_static.contains("add `dynamic = true`"),
        "{quasi_static}"
    );
    assert!(quasi_static.contains("scene.toml:27:"), "{quasi_static}");
    let unknown = load("unknown", "predictor_frame = \"bal\"").unwrap_err();
    assert!(unknown.contains("no rigid body 'bal'"), "{unknown}");
    assert!(unknown.contains("did you mean `ball`"), "{unknown}");
    let large = load("large", "dynamic = true, numerical_dissipation = 0.7").unwrap_err();
    assert!(large.contains("must be in [0, 0.5]"), "{large}");
    let tolerance = load("tol", "correction_tolerance = 2.0").unwrap_err();
    assert!(
        tolerance.contains("correction_tolerance = 2 must be in (0, 1)"),
        "{tolerance}"
    );
}

/// The scene above with an explicit step whose keys are `explicit`.
fn load_explicit(name: &str, explicit: &str) -> Result<musclefem_io::scene::Model, String> {
    let dir = std::env::temp_dir().join(format!("musclefem_step_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    let text = scene("increments = 1")
        .replace("solver = \"implicit\"", "solver = \"explicit\"")
        .replace(
            "implicit = { increments = 1 }",
            &format!("explicit = {{ {explicit} }}"),
        );
    std::fs::write(&path, text).unwrap();
    load_scene(&path, &mut MaterialLibrary::with_builtins()).map_err(|e| e.to_string())
}

#[test]
fn the_added_mass_rides_on_the_rigid_body_the_step_names() {
    let model = load_explicit(
        "frame",
        "mass_scaling_time_step = 1e-4, mass_scaling_frame = \"ball\"",
    )
    .unwrap();
    let Analysis::Explicit(settings) = &model.analysis else {
        panic!("explicit");
    };
    let frame = settings.mass_scaling_frame.as_ref().unwrap();
    let moved = frame.isometry_at(1.0).translation.vector;
    assert!((moved - nalgebra::Vector3::new(0.0, 0.01, 0.0)).norm() < 1e-15);

    let unknown = load_explicit(
        "frame_unknown",
        "mass_scaling_time_step = 1e-4, mass_scaling_frame = \"bal\"",
    )
    .unwrap_err();
    assert!(unknown.contains("no rigid body 'bal'"), "{unknown}");
    assert!(unknown.contains("did you mean `ball`"), "{unknown}");
    assert!(unknown.contains("scene.toml:27:"), "{unknown}");
    let unscaled = load_explicit("frame_unscaled", "mass_scaling_frame = \"ball\"").unwrap_err();
    assert!(
        unscaled.contains("without mass_scaling_time_step: there is no added mass to carry"),
        "{unscaled}"
    );
}
